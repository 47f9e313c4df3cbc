//! Turning: the stock a lathe's turning, facing and boring moves remove, axisymmetric.
//!
//! While the spindle turns, a feed or arc move of a turning tool removes its 2-D shape
//! swept along the move's (z, x) path at every angle of the part. The shape is a round nose
//! (radius `r_n`) with two straight edges tangent to it ([`TurningTool`]); the program
//! drives its *imaginary tip* (the corner of the nose's tangents along z and x, tool tip
//! direction 3 of the controls by default, [`TurningTool::with_tip`] for the others; the
//! moves come here already compensated where the program used G41/G42, `nc::nose`), so the
//! nose centre runs `r_n` above and `r_n` to the +z side of the programmed point. The same
//! shape with a flat bottom between two noses is a grooving or threading insert's edge
//! ([`TurningTool::insert`]: a trapezoid, a V, a round-nose V), driven by its reference
//! point; their feed moves and rapids are swept the same way.
//!
//! Everything here works in the axial half-plane `(z, h)` with `h = q = sense * r` (`q` of
//! [`crate::model::stock`]): the tool's body lies towards `+h` (outwards for an external
//! tool, towards the axis for a boring bar), and a cut lowers `q`. The shape's lower
//! boundary `g(u)` at axial offset `u` from the (left) nose centre is convex (the nose's
//! lower arc between the edges' tangent points, the flat, the edges beyond, `+inf` outside
//! the shape), so the
//! swept envelope `e(z) = min over the path of [h_c + g(z - z_c)]` is exact in closed form:
//! a function of the path parameter whose minimum is at an end of the move, at an end of
//! the shape's span, at a corner of the boundary, or where the path's slope equals the
//! boundary's slope (on a nose that is the path offset by `r_n` along its normal: a
//! parallel line, or the concentric circle of radius `R -+ r_n` for an arc; on the flat,
//! the path's highest or lowest point; on an edge, the path point whose tangent is
//! parallel to it). Every candidate is a point of the swept shape, and the minimum is
//! among them, so the envelope is exact at every z it is evaluated at ([`Turned`]). Feed
//! marks (the nose's cusps between revolutions, `f^2 / (8 r_n)` high) are neglected.
//!
//! Material removal is a union of swept volumes, so the order of cuts does not matter:
//! the turned profile is a per-z clamp `q = min(q, e(z))` applied to every column with the
//! thread sweeps. Only what needs the time order (a rapid that meets material that was
//! still there) walks the moves in order ([`Turned::rapid_depth`]).

use crate::model::part::{Approach, PartProfile};
use crate::model::tool::{Edge, Tool};
use std::f64::consts::TAU;

/// A tool's axial shape as a lathe move sweeps it: a round nose (or, with a flat, two noses
/// `flat` apart joined by a flat bottom) with two straight edges tangent to it. A turning
/// or boring insert (`flat` 0), or a grooving or threading insert's edge
/// ([`TurningTool::insert`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TurningTool {
    /// The id the program's T word selects.
    pub(crate) id: u32,
    /// Nose radius (mm, at least 0: 0 is a sharp corner).
    pub(crate) nose_radius: f64,
    /// Width of the flat bottom between the two noses (mm, at least 0): a grooving
    /// insert's width, a threading insert's tip flat; 0 for a turning insert.
    pub(crate) flat: f64,
    /// The leading (-z side) edge's angle from the radial direction (rad), positive when
    /// it leans towards -z away from the nose (a 95 deg approach angle is -5 deg).
    pub(crate) lead_angle: f64,
    /// The trailing (+z side) edge's angle from the radial direction (rad), positive when
    /// it leans towards +z (a 5 deg end cutting edge angle is 85 deg).
    pub(crate) trail_angle: f64,
    /// A boring bar (cuts the bore) rather than an external tool.
    pub(crate) internal: bool,
    /// Where the (left) nose centre is from the point the program drives, `(dz, dh)`:
    /// `(r_n, r_n)` for a turning insert's imaginary tip; for an insert driven by its
    /// reference point on the tip, the tip's left corner (`dh` = the nose radius).
    pub(crate) anchor: (f64, f64),
}

impl TurningTool {
    /// A turning or boring insert driven by its imaginary tip (tool tip orientation 3, or 2
    /// in a bore): the nose centre `r_n` to the +z side of and above the programmed point.
    pub(crate) fn turning(
        id: u32,
        nose_radius: f64,
        (lead_angle, trail_angle): (f64, f64),
        internal: bool,
    ) -> TurningTool {
        TurningTool {
            id,
            nose_radius,
            flat: 0.0,
            lead_angle,
            trail_angle,
            internal,
            anchor: (nose_radius, nose_radius),
        }
    }

    /// This insert driven by the imaginary tip of direction `tip` (FANUC numbering,
    /// [`crate::model::tool::tip_direction`]): the nose centre lies `-r_n` times the tip's
    /// direction from the driven point (3 outside and 2 in a bore: `(r_n, r_n)` in `(z,
    /// h)`, as [`TurningTool::turning`]; 0 and 9 drive the centre). `None` past 9.
    pub(crate) fn with_tip(self, tip: u8) -> Option<TurningTool> {
        let (dz, dx) = crate::model::tool::tip_direction(tip)?;
        let sense = if self.internal { -1.0 } else { 1.0 };
        let r = self.nose_radius;
        Some(TurningTool {
            anchor: (-r * dz, -r * dx * sense),
            ..self
        })
    }

    /// The tip direction (FANUC numbering) of a turning insert whose nose centre sits at
    /// `anchor` from the driven point: the inverse of [`TurningTool::with_tip`]; the
    /// default (3 outside, 2 in a bore) for a sharp corner, where it does not matter.
    pub(crate) fn tip(&self) -> u8 {
        let r = self.nose_radius;
        let default = if self.internal { 2 } else { 3 };
        if r <= 0.0 {
            return default;
        }
        let sense = if self.internal { -1.0 } else { 1.0 };
        let q = (-self.anchor.0 / r, -self.anchor.1 * sense / r);
        (0..=8)
            .find(|&t| {
                crate::model::tool::tip_direction(t)
                    .is_some_and(|d| (d.0 - q.0).abs() < 1e-9 && (d.1 - q.1).abs() < 1e-9)
            })
            .unwrap_or(default)
    }

    /// The edge of a grooving or threading insert as the shape its feed moves and rapids
    /// sweep, driven by its reference point ([`Tool::reference_offset`] from the tip centre,
    /// at the tip's height): a trapezoid is a flat with two straight flanks (vertical for a
    /// grooving insert), a round-nose V a nose with two flanks. A mesh insert's section is
    /// taken as the trapezoid of its flat and the flanks' mean slopes over the first mm
    /// above it (exact for a section with one facet on each side, as a prismatic insert's).
    /// `internal`: the insert cuts the bore (an internal thread's tools).
    pub(crate) fn insert(tool: &Tool, internal: bool) -> TurningTool {
        let off = tool.reference_offset();
        let (r, flat, lead, trail, left) = match &tool.edge {
            Edge::Trapezoid {
                tip,
                left_angle,
                right_angle,
            } => (0.0, *tip, *left_angle, *right_angle, -tip / 2.0 - off),
            Edge::RoundV { radius, half_angle } => (*radius, 0.0, *half_angle, *half_angle, -off),
            Edge::Mesh { .. } => {
                let (a, b) = tool.span(1e-9);
                let (a1, b1) = tool.span(1.0);
                let angle = |run: f64| run.max(0.0).atan();
                (0.0, (b - a).max(0.0), angle(a - a1), angle(b1 - b), a)
            }
        };
        TurningTool {
            id: tool.id,
            nose_radius: r,
            flat,
            lead_angle: lead,
            trail_angle: trail,
            internal,
            anchor: (left, r),
        }
    }

    /// The `v` span of a nose's lower arc, relative to its centre: between the edges'
    /// tangent points, or to the nose's side where an edge leans back over it.
    fn arc_span(&self) -> (f64, f64) {
        let r = self.nose_radius;
        let a = if self.lead_angle > 0.0 {
            -r * self.lead_angle.cos()
        } else {
            -r
        };
        let b = if self.trail_angle > 0.0 {
            r * self.trail_angle.cos()
        } else {
            r
        };
        (a, b)
    }

    /// The `u` span of the shape (infinite on a side whose edge leans out).
    fn domain(&self) -> (f64, f64) {
        let r = self.nose_radius;
        (
            if self.lead_angle > 0.0 {
                f64::NEG_INFINITY
            } else {
                -r
            },
            if self.trail_angle > 0.0 {
                f64::INFINITY
            } else {
                self.flat + r
            },
        )
    }

    /// The lowest point of the shape at axial offset `u` from the (left) nose centre,
    /// relative to the nose centre's height; `+inf` outside the shape.
    pub(crate) fn lower(&self, u: f64) -> f64 {
        let r = self.nose_radius;
        // Offsets past the flat are measured from the right nose's centre.
        let v = if u <= 0.0 {
            u
        } else if u >= self.flat {
            u - self.flat
        } else {
            return -r;
        };
        let (a, b) = self.arc_span();
        if v < a {
            if self.lead_angle > 0.0 {
                -r * self.lead_angle.sin() + (a - v) / self.lead_angle.tan()
            } else {
                f64::INFINITY
            }
        } else if v > b {
            if self.trail_angle > 0.0 {
                -r * self.trail_angle.sin() + (v - b) / self.trail_angle.tan()
            } else {
                f64::INFINITY
            }
        } else {
            -(r * r - v * v).max(0.0).sqrt()
        }
    }

    /// The slopes `dg/du` of the edges that are part of the lower boundary.
    fn edge_slopes(&self) -> impl Iterator<Item = f64> {
        let lead = (self.lead_angle > 0.0).then(|| -1.0 / self.lead_angle.tan());
        let trail = (self.trail_angle > 0.0).then(|| 1.0 / self.trail_angle.tan());
        lead.into_iter().chain(trail)
    }

    /// How far the shape reaches to each side of the left nose's centre at height `dh`
    /// above its lowest point (an upper bound): where it can reach below a surface `dh`
    /// above the nose's bottom.
    fn reach(&self, dh: f64) -> (f64, f64) {
        let r = self.nose_radius;
        let dh = dh.max(0.0);
        let side = |angle: f64| {
            if angle > 0.0 {
                r + dh * angle.tan()
            } else {
                r
            }
        };
        (side(self.lead_angle), self.flat + side(self.trail_angle))
    }
}

/// The path of the nose centre in the axial half-plane `(z, h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum TurnPath {
    /// A straight move.
    Line {
        /// Start `(z, h)`.
        from: (f64, f64),
        /// End `(z, h)`.
        to: (f64, f64),
    },
    /// A circular move.
    Arc {
        /// Centre `(z, h)`.
        centre: (f64, f64),
        /// Radius (mm).
        radius: f64,
        /// Angle of the start from the centre (rad, from +z towards +h).
        start: f64,
        /// Signed sweep (rad): positive counter-clockwise in `(z, h)`; a full circle is
        /// `+-TAU`.
        sweep: f64,
    },
}

impl TurnPath {
    /// The (left) nose centre's path of a move of the driven point (a turning insert's
    /// imaginary tip, an insert's reference point) from `(z0, x0)` to `(z1, x1)` (`x`
    /// diameters) on the surface of `sense` (1 outside, -1 in the bore), straight or about
    /// the centre `(zc, xc)` (clockwise as G02 in the (z, radius) plane).
    pub(crate) fn of_move(
        tool: &TurningTool,
        sense: f64,
        from: (f64, f64),
        to: (f64, f64),
        arc: Option<((f64, f64), bool)>,
    ) -> TurnPath {
        let (dz, dh) = tool.anchor;
        let at = |(z, x): (f64, f64)| (z + dz, sense * x / 2.0 + dh);
        let (a, b) = (at(from), at(to));
        match arc {
            None => TurnPath::Line { from: a, to: b },
            Some((centre, clockwise)) => {
                let c = at(centre);
                let radius = (a.0 - c.0).hypot(a.1 - c.1);
                let start = (a.1 - c.1).atan2(a.0 - c.0);
                let end = (b.1 - c.1).atan2(b.0 - c.0);
                // Mirrored (h = -r in a bore), a clockwise arc turns the other way.
                let ccw = clockwise == (sense < 0.0);
                let mut sweep = if ccw {
                    (end - start).rem_euclid(TAU)
                } else {
                    -(start - end).rem_euclid(TAU)
                };
                if a == b {
                    sweep = if ccw { TAU } else { -TAU };
                }
                TurnPath::Arc {
                    centre: c,
                    radius,
                    start,
                    sweep,
                }
            }
        }
    }

    /// The path's axial and height extent.
    fn bounds(&self) -> ((f64, f64), (f64, f64)) {
        match *self {
            TurnPath::Line { from, to } => (
                (from.0.min(to.0), from.0.max(to.0)),
                (from.1.min(to.1), from.1.max(to.1)),
            ),
            TurnPath::Arc { centre, radius, .. } => (
                (centre.0 - radius, centre.0 + radius),
                (centre.1 - radius, centre.1 + radius),
            ),
        }
    }
}

/// The swept shape's lowest point at `z`: `+inf` where the move does not reach.
pub(crate) fn envelope(tool: &TurningTool, path: &TurnPath, z: f64) -> f64 {
    let r = tool.nose_radius;
    let flat = tool.flat;
    let (umin, umax) = tool.domain();
    // The corners of the flat (kinks of the boundary when the noses are sharp) and the
    // shape's span's ends.
    let ends = [0.0, flat, umin, umax];
    match *path {
        TurnPath::Line { from, to } => {
            let at = |t: f64| (from.0 + t * (to.0 - from.0), from.1 + t * (to.1 - from.1));
            let eval = |t: f64| {
                let c = at(t);
                c.1 + tool.lower(z - c.0)
            };
            let mut best = eval(0.0).min(eval(1.0));
            let dz = to.0 - from.0;
            if dz != 0.0 {
                let m = (to.1 - from.1) / dz;
                // Where a nose's boundary is parallel to the move: the left nose's lower
                // arc has the slopes up to 0, the right one's from 0.
                let contact = m * r / (1.0 + m * m).sqrt();
                let u_nose = if m <= 0.0 { contact } else { flat + contact };
                for u in std::iter::once(u_nose).chain(ends) {
                    if !u.is_finite() {
                        continue;
                    }
                    let t = (z - from.0 - u) / dz;
                    if (0.0..=1.0).contains(&t) {
                        let c = at(t);
                        let v = c.1 + tool.lower(u.clamp(umin, umax));
                        best = best.min(v);
                    }
                }
            }
            best
        }
        TurnPath::Arc {
            centre,
            radius,
            start,
            sweep,
        } => {
            let at = |th: f64| (centre.0 + radius * th.cos(), centre.1 + radius * th.sin());
            let inside = |th: f64| {
                let d = if sweep >= 0.0 {
                    (th - start).rem_euclid(TAU)
                } else {
                    (start - th).rem_euclid(TAU)
                };
                d <= sweep.abs() + 1e-12 || d >= TAU - 1e-12
            };
            let eval = |th: f64| {
                let c = at(th);
                c.1 + tool.lower(z - c.0)
            };
            let mut best = eval(start).min(eval(start + sweep));
            let mut try_angle = |th: f64, u: Option<f64>| {
                if th.is_finite() && inside(th) {
                    let c = at(th);
                    let v = match u {
                        Some(u) => c.1 + tool.lower(u),
                        None => c.1 + tool.lower(z - c.0),
                    };
                    best = best.min(v);
                }
            };
            // On a nose: the contact point is on the concentric circle of radius R - r_n
            // (upper half, sin > 0) or R + r_n (lower half) about the centre, shifted by
            // the nose's offset (0 or the flat).
            let noses: &[f64] = if flat > 0.0 { &[0.0, flat] } else { &[0.0] };
            for &off in noses {
                for s in [1.0f64, -1.0] {
                    let rho = radius - s * r;
                    if rho != 0.0 {
                        let c = (z - off - centre.0) / rho;
                        if c.abs() <= 1.0 {
                            let th = s * c.acos();
                            try_angle(th, Some(off - s * r * th.cos()));
                        }
                    }
                }
            }
            // On the flat: the path's highest or lowest point.
            if flat > 0.0 {
                let u = z - centre.0;
                if (0.0..=flat).contains(&u) {
                    for th in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2] {
                        try_angle(th, Some(u));
                    }
                }
            }
            // On an edge: the path's tangent parallel to it (slope -cot th = m).
            for m in tool.edge_slopes() {
                let th = 1.0f64.atan2(-m);
                try_angle(th, None);
                try_angle(th + std::f64::consts::PI, None);
            }
            // The flat's corners and the shape's span's ends: z - z_c(th) = u.
            for u in ends {
                if u.is_finite() && radius > 0.0 {
                    let c = (z - u - centre.0) / radius;
                    if c.abs() <= 1.0 {
                        let th = c.acos();
                        try_angle(th, Some(u));
                        try_angle(-th, Some(u));
                    }
                }
            }
            best
        }
    }
}

/// One turning move: its tool and the nose centre's path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TurnCut {
    /// The tool.
    pub(crate) tool: TurningTool,
    /// The nose centre's path.
    pub(crate) path: TurnPath,
}

impl TurnCut {
    /// The z span where the swept shape may reach below `q_top` (a bound); `None` when it
    /// does not.
    pub(crate) fn span(&self, q_top: f64) -> Option<(f64, f64)> {
        let ((z0, z1), (h0, _)) = self.path.bounds();
        let bottom = h0 - self.tool.nose_radius;
        if bottom >= q_top {
            return None;
        }
        let (l, r) = self.tool.reach(q_top - bottom);
        Some((z0 - l, z1 + r))
    }
}

/// The turning moves of one surface, in program order: the turned profile.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Turned {
    /// The moves.
    pub(crate) cuts: Vec<TurnCut>,
}

impl Turned {
    /// Clamp a column of cells `z0 + j dz` holding `q - q_blank` to the turned profile,
    /// never below `q_floor` (no material left: the axis, or the other surface).
    pub(crate) fn clamp(&self, q: &mut [f32], z0: f64, dz: f64, q_blank: f64, q_floor: f64) {
        for cut in &self.cuts {
            let Some((lo, hi)) = cut.span(q_blank) else {
                continue;
            };
            let j0 = ((lo - z0) / dz).floor().max(0.0) as usize;
            let j1 = (((hi - z0) / dz).ceil() + 1.0).clamp(0.0, q.len() as f64) as usize;
            let j0 = j0.min(j1);
            for (j, v) in q[j0..j1].iter_mut().enumerate() {
                let e = envelope(&cut.tool, &cut.path, z0 + dz * (j0 + j) as f64);
                if e < q_blank + *v as f64 {
                    *v = v.min((e.max(q_floor) - q_blank) as f32);
                }
            }
        }
    }

    /// The turned profile over `n` cells `z0 + j dz`, as `q - q_blank` (zero where nothing
    /// was turned).
    pub(crate) fn profile(
        &self,
        n: usize,
        z0: f64,
        dz: f64,
        q_blank: f64,
        q_floor: f64,
    ) -> Vec<f32> {
        let mut q = vec![0f32; n];
        self.clamp(&mut q, z0, dz, q_blank, q_floor);
        q
    }
}

/// The stock of one surface along z as the moves so far left it, sampled every `dz` from
/// the blank's start: what a rapid is checked against, in program order (each cut and each
/// check costs the cells it spans, so a long program stays linear in its moves).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Profile {
    z_lo: f64,
    z_hi: f64,
    dz: f64,
    q_blank: f64,
    q_floor: f64,
    q: Vec<f64>,
}

impl Profile {
    /// The blank: `q_blank` over `[z_lo, z_hi]`, no cut going below `q_floor`.
    pub(crate) fn new((z_lo, z_hi): (f64, f64), dz: f64, q_blank: f64, q_floor: f64) -> Profile {
        let n = ((z_hi - z_lo) / dz).ceil().max(0.0) as usize + 1;
        Profile {
            z_lo,
            z_hi,
            dz,
            q_blank,
            q_floor,
            q: vec![q_blank; n],
        }
    }

    /// A contour that is not cut (the chuck and its jaws, turning with the part): its
    /// radius at every cell of its span within `within` (the larger side at a step), every
    /// `dz`; `None` where they do not meet.
    pub(crate) fn outline(contour: &PartProfile, within: (f64, f64), dz: f64) -> Option<Profile> {
        let (z_lo, z_hi) = contour.z_span();
        let (z_lo, z_hi) = (z_lo.max(within.0), z_hi.min(within.1));
        if z_lo > z_hi {
            return None;
        }
        let mut p = Profile::new((z_lo, z_hi), dz, 0.0, 0.0);
        for j in 0..p.q.len() {
            let z = p.z(j);
            let r = [Approach::FromBelow, Approach::FromAbove]
                .iter()
                .filter_map(|&a| contour.radius(z, a))
                .fold(0.0, f64::max);
            p.q[j] = r;
        }
        p.q_blank = p.q.iter().copied().fold(0.0, f64::max);
        Some(p)
    }

    /// The cells a swept shape reaches below the blank in.
    fn cells(&self, cut: &TurnCut) -> Option<std::ops::Range<usize>> {
        let (lo, hi) = cut.span(self.q_blank)?;
        let (lo, hi) = (lo.max(self.z_lo), hi.min(self.z_hi));
        if lo > hi {
            return None;
        }
        let j0 = ((lo - self.z_lo) / self.dz).floor().max(0.0) as usize;
        let j1 = (((hi - self.z_lo) / self.dz).ceil() as usize + 1).min(self.q.len());
        Some(j0.min(j1)..j1)
    }

    fn z(&self, j: usize) -> f64 {
        (self.z_lo + self.dz * j as f64).min(self.z_hi)
    }

    /// Remove what `cut` sweeps.
    pub(crate) fn cut(&mut self, cut: &TurnCut) {
        let Some(cells) = self.cells(cut) else {
            return;
        };
        for j in cells {
            let e = envelope(&cut.tool, &cut.path, self.z(j)).max(self.q_floor);
            self.q[j] = self.q[j].min(e);
        }
    }

    /// How deep the shape of `tool` swept along `path` (a rapid) goes into the stock: the
    /// deepest radial depth and its z, or `None` when it meets no material.
    pub(crate) fn rapid_depth(&self, tool: &TurningTool, path: &TurnPath) -> Option<(f64, f64)> {
        let rapid = TurnCut {
            tool: *tool,
            path: *path,
        };
        let mut worst: Option<(f64, f64)> = None;
        for j in self.cells(&rapid)? {
            let z = self.z(j);
            let depth = self.q[j] - envelope(tool, path, z).max(self.q_floor);
            if depth > 0.0 && worst.is_none_or(|(d, _)| depth > d) {
                worst = Some((depth, z));
            }
        }
        worst
    }
}

#[cfg(test)]
mod tests;
