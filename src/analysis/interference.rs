//! Tool body interference: what the body behind the edge cut beyond the edge's own swept
//! groove, and the effective side clearance that predicts it.
//!
//! - **Measured**: the stock is cut twice, with the edges alone (planar profiles) and with
//!   the bodies too. Every dexel the bodies cut deeper is body interference; its size is the
//!   distance in the axial plane from the body-cut point to the edge-cut profile of the same
//!   generator (how far the body reached past the edge's surface), its volume the annular
//!   sector between the two radii. Each is assigned to the turn and flank of the ideal
//!   profile it lies on, as `compare` does. The radial dexels hold one surface per ray, so a
//!   body that rubs a flank only below some radius (an undercut) is recorded as cut up to
//!   the surface: the size and place are right, the volume is an upper bound.
//! - **Predicted**: at depth `Y` behind the rake face the -z flank of the body is set back
//!   by `Y (tan a_l + tan l)` and the section has travelled `dir L / (2 pi r)` per mm of
//!   depth along the axis (the helix, `tan psi` at radius `r`), so it stays clear of the
//!   groove wall while `tan a_l + tan l + dir tan psi > 0`; likewise the +z flank while
//!   `tan a_r - tan l - dir tan psi > 0`. The effective clearances `atan` of these, at the
//!   crest and root radii, per turn, are `alpha -/+ (psi - lambda)` of `domain.md` §4 in
//!   tangent form.

use crate::kernel::body;
use crate::model::geom::segment_distance2;
use crate::model::pass::Pass;
use crate::model::stock::{Grid, Surface};
use crate::model::thread::{Flank, ThreadSpec};
use crate::model::tool::Tool;
use glam::DVec2;
use std::collections::BTreeMap;
use std::f64::consts::TAU;

/// Smallest body cut counted (mm): below it, rounding of the `f32` dexels.
const EPS_MM: f64 = 1e-4;

/// The worst body cut of a turn and flank.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Hit {
    /// How far past the edge's surface (mm, axial plane).
    pub(crate) depth: f64,
    /// Where (rad, mm).
    pub(crate) theta: f64,
    pub(crate) z: f64,
    /// Volume cut by the body (mm^3, an upper bound for undercuts).
    pub(crate) volume: f64,
}

impl Hit {
    fn merge(&mut self, o: &Hit) {
        if o.depth > self.depth {
            (self.depth, self.theta, self.z) = (o.depth, o.theta, o.z);
        }
        self.volume += o.volume;
    }
}

/// Body interference per `(start, turn)` and flank ([`Flank::ALL`] order).
pub(crate) type Interference = BTreeMap<(u32, i64), [Option<Hit>; 4]>;

/// What the tool bodies did: the measured interference, the predicted clearances, and the
/// passes whose bodies were swept (their section count and sampling bound).
pub(crate) type Bodies = (
    Interference,
    BTreeMap<(u32, i64), Clearance>,
    Vec<(usize, f64)>,
);

/// The section count and sampling bound of each pass whose body is swept (not skipped as
/// unable to reach past its edge), for the blank's signed radius `q_blank`.
pub(crate) fn swept_bodies(
    passes: &[Pass],
    tools: &[Tool],
    q_blank: f64,
    surface: Surface,
) -> Vec<(usize, f64)> {
    passes
        .iter()
        .filter_map(|p| {
            let tool = tools.get(p.tool)?;
            let zone = body::zone(p, q_blank, surface);
            let s = body::sections(p, tool, zone, surface.sense())?;
            Some((s.samples.len(), s.bound))
        })
        .collect()
}

/// Add one column's interference to `total` (in column order).
pub(crate) fn add_column(total: &mut Interference, c: &Interference) {
    for (k, flanks) in c {
        let slot = total.entry(*k).or_default();
        for (s, f) in slot.iter_mut().zip(flanks) {
            if let Some(f) = f {
                s.get_or_insert_with(Hit::default).merge(f);
            }
        }
    }
}

/// The body interference of one grid's columns, one column at a time (the streaming
/// pipeline runs it on each column of a tile while both cuts are in cache).
pub(crate) struct Measurer<'a> {
    grid: Grid,
    q_blank: f64,
    surface: Surface,
    thread: &'a ThreadSpec,
}

impl<'a> Measurer<'a> {
    /// The measurement of `surface` (blank signed radius `q_blank`) on `grid`.
    pub(crate) fn new(
        grid: Grid,
        q_blank: f64,
        surface: Surface,
        thread: &'a ThreadSpec,
    ) -> Measurer<'a> {
        Measurer {
            grid,
            q_blank,
            surface,
            thread,
        }
    }

    /// Column `i`: `p` cut by the edges alone, `c` with the bodies.
    pub(crate) fn column(&self, i: usize, p: &[f32], c: &[f32]) -> Interference {
        let (grid, q_blank, thread) = (&self.grid, self.q_blank, self.thread);
        let sense = self.surface.sense();
        let cell = grid.dtheta() * grid.dz;
        let (z_first, z_last) = (grid.z(0), grid.z(grid.n_z.saturating_sub(1)));
        let mut out = Interference::new();
        // Cells the body cut deeper (a few per flank and turn, if any).
        let hits: Vec<usize> = (0..grid.n_z)
            .filter(|&j| sense * (p[j] as f64 - c[j] as f64) > EPS_MM)
            .collect();
        if hits.is_empty() {
            return out;
        }
        let theta = grid.theta(i);
        let ideal = thread.column(theta, z_first, z_last);
        let r = |q: &[f32], j: usize| sense * (q[j] as f64 + q_blank);
        // The edge-cut profile as points (z, r); the distance to it is searched outward
        // from the cell, a segment on each side per step, until the segments' nearer
        // ends lie farther along the axis than the best distance so far (no farther
        // segment can be closer). It starts at the radial gap and shrinks at the first
        // wall met on either side.
        let seg = |k: usize| ((grid.z(k), r(p, k)), (grid.z(k + 1), r(p, k + 1)));
        for &j in &hits {
            let (z, rc, rp) = (grid.z(j), r(c, j), r(p, j));
            let radial = (rp - rc).abs();
            let mut d2 = radial * radial;
            for step in 0.. {
                // Segment [k, k+1] towards -z (k = j - 1 - step) and towards +z (k = j + step).
                let below = (step < j).then(|| j - 1 - step);
                let above = (j + step + 1 < grid.n_z).then_some(j + step);
                let mut any = false;
                for k in below.into_iter().chain(above) {
                    let gap = if k < j {
                        z - grid.z(k + 1)
                    } else {
                        grid.z(k) - z
                    };
                    if gap * gap <= d2 {
                        any = true;
                        let (a, b) = seg(k);
                        d2 = d2.min(segment_distance2(
                            DVec2::new(z, rc),
                            DVec2::from(a),
                            DVec2::from(b),
                        ));
                    }
                }
                if !any {
                    break;
                }
            }
            // Inside the thread the turns are the comparison's (the groove whose region
            // holds the point); outside, in the run-in and run-out, the turn of the feature
            // above it (0 before the first, past the last turn after it).
            let inside = ideal.span.is_some_and(|(a, b)| z >= a && z <= b);
            let key = match ideal.groove_at(0, z).filter(|_| inside) {
                Some(g) => (ideal.grooves[g].start, ideal.grooves[g].turn),
                None => {
                    let feature = ideal.features.partition_point(|f| f.z < z);
                    ideal
                        .features
                        .get(feature)
                        .map_or((0, 0), |f| (f.start, f.turn()))
                }
            };
            let (_, flank) = ideal.distance(z, thread.height(rc), f64::INFINITY);
            let hit = Hit {
                depth: d2.sqrt(),
                theta,
                z,
                volume: (rp * rp - rc * rc).abs() * 0.5 * cell,
            };
            out.entry(key).or_default()[flank.index()]
                .get_or_insert_with(Hit::default)
                .merge(&hit);
        }
        out
    }
}

/// Effective side clearances (deg) of one turn: -z and +z flank at crest and root, each the
/// smallest over the passes whose tool has a body; `pass` has the smallest of all.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Clearance {
    pub(crate) left_crest: f64,
    pub(crate) left_root: f64,
    pub(crate) right_crest: f64,
    pub(crate) right_root: f64,
    /// The pass (index) with the smallest of the four.
    pub(crate) pass: usize,
}

/// The effective clearances of the bodies per `(start, turn)`, from each pass's lead where
/// it crosses the middle of the turn (`None` for turns no bodied pass reaches).
pub(crate) fn clearances(
    thread: &ThreadSpec,
    passes: &[Pass],
    tools: &[Tool],
) -> BTreeMap<(u32, i64), Clearance> {
    let mut out: BTreeMap<(u32, i64), Clearance> = BTreeMap::new();
    for (i, p) in passes.iter().enumerate() {
        let Some(body) = tools.get(p.tool).and_then(|t| t.body) else {
            continue;
        };
        let (Some(t_end), h) = (p.revolutions(), p.helix()) else {
            continue;
        };
        let (sl, sr) = (body.slope_left(), body.slope_right());
        for s in 0..thread.starts {
            let sh = thread.start_helix(s);
            for n in 1..=thread.whole_turns() {
                let z = sh.z(n as f64 - 0.5);
                let Some(t) = h.revs_at_z(z).filter(|t| *t <= t_end) else {
                    continue;
                };
                let lead = h.law.lead(t).abs();
                let eff = |r: f64| {
                    let tan_psi = lead / (TAU * r);
                    (
                        (sl + h.dir * tan_psi).atan().to_degrees(),
                        (sr - h.dir * tan_psi).atan().to_degrees(),
                    )
                };
                let (lc, rc) = eff(thread.crest_radius);
                let (lr, rr) = eff(thread.root_radius);
                let c = Clearance {
                    left_crest: lc,
                    left_root: lr,
                    right_crest: rc,
                    right_root: rr,
                    pass: i,
                };
                let worst = |c: &Clearance| {
                    c.left_crest
                        .min(c.left_root)
                        .min(c.right_crest)
                        .min(c.right_root)
                };
                let slot = out.entry((s, n)).or_insert(c);
                let pass = if worst(&c) < worst(slot) {
                    i
                } else {
                    slot.pass
                };
                *slot = Clearance {
                    left_crest: slot.left_crest.min(c.left_crest),
                    left_root: slot.left_root.min(c.left_root),
                    right_crest: slot.right_crest.min(c.right_crest),
                    right_root: slot.right_root.min(c.right_root),
                    pass,
                };
            }
        }
    }
    out
}

/// Whether any pass of the job has a tool body whose sections are swept.
pub(crate) fn has_bodies(passes: &[Pass], tools: &[Tool]) -> bool {
    passes
        .iter()
        .any(|p| tools.get(p.tool).is_some_and(Tool::has_body))
}

/// Flank names for the findings.
pub(crate) fn flank_name(k: usize) -> &'static str {
    Flank::ALL[k].name()
}
