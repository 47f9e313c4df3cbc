//! The thread the drawing asks for, and its ideal surface in closed form.
//!
//! A thread is a pitch helix (per start) plus a groove shape. Along any generator (a line
//! of the part at a fixed angle) the pitch helix crosses at known z. For **equal groove
//! width** every crossing is the centre of a groove of constant width at the pitch
//! diameter; for **equal tooth width** every crossing is the centre of a tooth and the
//! groove between two teeth is as wide as their gap less the tooth. Constant pitch is
//! equal groove width with the width of the standard form.
//!
//! Radial positions are handled as *height above the root* `h` (0 at the root, `depth` at
//! the crest) so external and internal threads share every formula: `h` grows into the
//! material's free side. In `(z, h)` the ideal axial profile of one generator is an exact
//! polyline ([`ColumnIdeal`]): crest flats, groove walls and root flats, with the walls of
//! neighbouring grooves intersected where they overlap (sharp crests).

use crate::model::clip;
use crate::model::geom;
use crate::model::helix::{Hand, Helix};
use crate::model::part::PartProfile;
use crate::model::stock::first_cell;
use glam::DVec2;
use std::f64::consts::TAU;

/// Which surface of the part carries the thread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// On the outside of a bar (a screw).
    External,
    /// On the inside of a bore (a nut).
    Internal,
}

/// Which width stays constant along a variable-pitch thread (measured at the pitch line).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WidthRule {
    /// Equal groove width: the groove is this wide at the pitch diameter.
    Groove(f64),
    /// Equal tooth width: the tooth is this wide at the pitch diameter.
    Tooth(f64),
}

/// The part of a profile a point of the surface lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Flank {
    /// The wall of a groove on its -z side (toward the chuck).
    Left,
    /// The wall of a groove on its +z side (toward the part's front face).
    Right,
    /// The bottom of a groove.
    Root,
    /// The top of a tooth.
    Crest,
}

impl Flank {
    /// All flanks, in report order.
    pub const ALL: [Flank; 4] = [Flank::Left, Flank::Right, Flank::Root, Flank::Crest];

    /// Lower-case name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Flank::Left => "left",
            Flank::Right => "right",
            Flank::Root => "root",
            Flank::Crest => "crest",
        }
    }

    /// The part's name in a sentence: "left flank", "right flank", "root", "crest".
    pub fn label(self) -> &'static str {
        match self {
            Flank::Left => "left flank",
            Flank::Right => "right flank",
            Flank::Root => "root",
            Flank::Crest => "crest",
        }
    }

    /// Index into [`Flank::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// The thread wanted, resolved into geometry (mm, radians).
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadSpec {
    /// External or internal.
    pub side: Side,
    /// Radius at the root (minor radius outside, major radius inside).
    pub root_radius: f64,
    /// Radius at the crest (major radius outside, minor radius inside).
    pub crest_radius: f64,
    /// Radius of the pitch line where widths and leads are measured.
    pub pitch_radius: f64,
    /// Inclination of the groove's left wall from the radial direction (rad).
    pub left_angle: f64,
    /// Inclination of the groove's right wall from the radial direction (rad).
    pub right_angle: f64,
    /// The width kept constant.
    pub width: WidthRule,
    /// Number of starts, spaced by 360/starts degrees.
    pub starts: u32,
    /// The pitch helix of start 0: `t = 0` is the first feature (groove or tooth centre).
    pub helix: Helix,
    /// Number of turns: features sit at `t = 0, 1, ..` up to `turns`.
    pub turns: f64,
    /// The finished part's contour on the thread's surface (`[part] profile` outside,
    /// `bore_profile` inside), as drawn: where it lies below the thread (a lead-in
    /// chamfer, a run-out relief) the ideal follows it (see [`ThreadSpec::column`]).
    pub outline: Option<std::sync::Arc<PartProfile>>,
    /// A taper thread (NPT, ISO 7-1's R and Rc): its root, pitch and crest are cones of one
    /// slope, the radii above being theirs at `Taper::z_ref`. `None` for a parallel thread.
    pub taper: Option<Taper>,
}

/// The cones of a taper thread: every radius of the thread changes by `slope` per mm of
/// z (1:16 on the diameter: a slope of 1/32, negative where the diameter grows towards
/// -z, as an external pipe thread's from its small end at the part's face). The flanks
/// keep their angles to the radial (the bisector of the thread's angle perpendicular to
/// the axis, ASME B1.20.1 and ISO 7-1): the ideal profile is exact, a parallel profile with
/// the walls' tangents adjusted for the slope and sheared onto the cones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Taper {
    /// Radius change per mm of z (signed).
    pub slope: f64,
    /// The z where the thread's radii are the ones `ThreadSpec` states (mm).
    pub z_ref: f64,
}

/// A groove of the ideal profile on one generator, by its four corners' z.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Groove {
    left_top: f64,
    left_root: f64,
    right_root: f64,
    right_top: f64,
}

/// A pitch-helix crossing on one generator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feature {
    /// Which start.
    pub start: u32,
    /// Revolutions of that start's pitch helix.
    pub t: f64,
    /// Axial position (mm).
    pub z: f64,
}

impl Feature {
    /// The turn the material just below this feature (toward -z) belongs to: turn n spans
    /// the pitch helix from `t = n-1` to `t = n`.
    pub fn turn(&self) -> i64 {
        self.t.floor() as i64 + 1
    }
}

/// A vertex of the ideal profile polyline in `(z, h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Axial position (mm).
    pub z: f64,
    /// Height above the root (mm).
    pub h: f64,
}

/// A groove of the thread (one the drawing defines) where it crosses one generator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadGroove {
    /// Which start.
    pub start: u32,
    /// The turn it belongs to (1-based; see [`ThreadSpec::turn_of`]).
    pub turn: i64,
    /// The groove's helix parameter at this crossing (revolutions of its start's helix).
    pub g: f64,
    /// Its -z end at the crest (where its -z wall reaches the crest height).
    pub z_lo: f64,
    /// Its +z end at the crest.
    pub z_hi: f64,
}

/// The exact ideal axial profile along one generator.
#[derive(Clone, Debug)]
pub struct ColumnIdeal {
    /// Polyline vertices, z non-decreasing; vertical walls give two vertices at one z.
    pub verts: Vec<Vertex>,
    /// Pitch-helix crossings, z increasing.
    pub features: Vec<Feature>,
    /// The grooves of the thread the drawing defines on this generator, z increasing:
    /// those whose helix parameter lies in the thread (see [`ThreadSpec::groove_range`]).
    pub grooves: Vec<ThreadGroove>,
    /// The z span the drawing defines on this generator, from the middle of the tooth
    /// before the first thread groove to the middle of the tooth after the last: the part
    /// compared with the cut. Beyond it lie the run-in and run-out, which the drawing
    /// does not define.
    pub span: Option<(f64, f64)>,
    depth: f64,
    /// A taper thread's cones: their slope in height per mm of z and the z where they
    /// pass through heights 0 (the root) and `depth` (the crest); `(0, 0)` for a parallel
    /// thread.
    cone: (f64, f64),
}

impl ThreadSpec {
    /// Sign that turns a radius difference into a height difference.
    pub fn sense(&self) -> f64 {
        match self.side {
            Side::External => 1.0,
            Side::Internal => -1.0,
        }
    }

    /// Height above the root of a radius.
    pub fn height(&self, r: f64) -> f64 {
        self.sense() * (r - self.root_radius)
    }

    /// Radius of a height above the root.
    pub fn radius(&self, h: f64) -> f64 {
        self.root_radius + self.sense() * h
    }

    /// Thread depth, root to crest.
    pub fn depth(&self) -> f64 {
        (self.crest_radius - self.root_radius).abs()
    }

    /// Height of the pitch line above the root.
    pub fn pitch_height(&self) -> f64 {
        self.height(self.pitch_radius)
    }

    /// The taper's cone in height at `z`: how far the root (and every cone of the thread)
    /// lies above its height at the reference plane (0 for a parallel thread).
    pub fn cone_height(&self, z: f64) -> f64 {
        self.taper
            .map_or(0.0, |t| self.sense() * t.slope * (z - t.z_ref))
    }

    /// Height of a radius above the thread's local root at `z` (its root cone's there):
    /// the profile as a parallel thread's, whatever the taper.
    pub fn local_height(&self, z: f64, r: f64) -> f64 {
        self.height(r) - self.cone_height(z)
    }

    /// The radius at `z` of a height above the local root ([`ThreadSpec::local_height`]'s
    /// inverse).
    pub fn local_radius(&self, z: f64, h: f64) -> f64 {
        self.radius(h + self.cone_height(z))
    }

    /// The walls' tangents (left, right: axial run per unit of height) of the parallel
    /// profile that, sheared onto a taper's cones, has the flank angles: a right wall's
    /// `T/(1 - s T)`, a left wall's `T/(1 + s T)` (`s` the cones' slope in height, `T` the
    /// flank's tangent); the flanks' own for a parallel thread.
    pub(crate) fn wall_tangents(&self) -> (f64, f64) {
        let (tl, tr) = (self.left_angle.tan(), self.right_angle.tan());
        match self.taper {
            None => (tl, tr),
            Some(t) => {
                let s = self.sense() * t.slope;
                (tl / (1.0 + s * tl), tr / (1.0 - s * tr))
            }
        }
    }

    /// Hand of the thread.
    pub fn hand(&self) -> Hand {
        self.helix.hand()
    }

    /// Sum of the wall tangents: how fast a groove widens per mm of height.
    pub fn widening(&self) -> f64 {
        self.left_angle.tan() + self.right_angle.tan()
    }

    /// The pitch helix of start `s`.
    pub fn start_helix(&self, s: u32) -> Helix {
        let mut h = self.helix;
        h.theta0 += TAU * s as f64 / self.starts as f64;
        h
    }

    /// Ideal groove width at height `h` above the root for a groove that is `w_pitch` wide
    /// at the pitch line.
    pub fn groove_width_at(&self, w_pitch: f64, h: f64) -> f64 {
        w_pitch + (h - self.pitch_height()) * self.widening()
    }

    /// The pitch (crest-to-crest spacing along the generator) of turn `n` (1-based) at the
    /// reference generator: `z(n-1) - z(n)`.
    pub fn pitch_of_turn(&self, n: i64) -> f64 {
        let law = self.helix.law;
        (law.travel(n as f64) - law.travel(n as f64 - 1.0)) / self.starts as f64
    }

    /// How much wider than a groove a tool may be and still count as fitting it: 1e-6 of
    /// the largest lead (at least 1e-9 mm). The standard forms' constants are given to
    /// six digits (ISO 68-1's 0.649519 P, 1.226869 P), so the root flat of a standard
    /// form and a tool ground to the same standard's exact value differ by that much.
    pub fn fit_tolerance(&self) -> f64 {
        let law = self.helix.law;
        (1e-6 * law.lead(0.0).abs().max(law.lead(self.turns).abs())).max(1e-9)
    }

    /// Number of turns reported: every whole turn, and a last partial one.
    pub fn whole_turns(&self) -> i64 {
        ((self.turns - 1e-9).ceil() as i64).max(1)
    }

    /// The helix parameters of the grooves the drawing defines: the thread runs from the
    /// first feature (`t = 0`) to the last (`t = turns`). With equal groove width the
    /// features are the grooves themselves; with equal tooth width they are teeth, and a
    /// groove (halfway between two teeth, half a pitch on) exists only between two teeth
    /// of the thread.
    pub fn groove_range(&self) -> (f64, f64) {
        match self.width {
            WidthRule::Groove(_) => (0.0, self.turns),
            WidthRule::Tooth(_) => {
                let half = 0.5 / self.starts as f64;
                (half, self.turns - half)
            }
        }
    }

    /// The turn of a groove with helix parameter `g`: turn `n` is the thread from
    /// `g = n - 1` (inclusive) to `g = n`; the thread's last feature closes its last turn.
    pub fn turn_of(&self, g: f64) -> i64 {
        ((g + 1e-9).floor() as i64 + 1).clamp(1, self.whole_turns())
    }

    /// The range of revolutions worth of features that covers `[z_lo, z_hi]` with a margin,
    /// clipped where the lead law would make the lead vanish.
    fn t_range(&self, z_lo: f64, z_hi: f64) -> (f64, f64) {
        let law = self.helix.law;
        let margin = 2.0 * law.f.abs().max(law.lead(self.turns).abs()) + self.depth() * 4.0;
        let z0 = self.helix.z0;
        let dir = self.helix.dir;
        // Travel needed to reach each end of the window.
        let (s_a, s_b) = {
            let a = dir * (z_lo - margin - z0);
            let b = dir * (z_hi + margin - z0);
            (a.min(b), a.max(b))
        };
        let limit = law.zero_lead_revs();
        let lo = law.revs_at(s_a).unwrap_or(match limit {
            Some(t0) if t0 < 0.0 => t0 + 1e-6,
            _ => -1e6,
        });
        let hi = law.revs_at(s_b).unwrap_or(match limit {
            Some(t0) if t0 > 0.0 => t0 - 1e-6,
            _ => 1e6,
        });
        (lo.min(hi) - 1.0, lo.max(hi) + 1.0)
    }

    /// The pitch-helix crossings (all starts) on the generator at `theta` that matter for
    /// `[z_lo, z_hi]`, sorted by z.
    pub fn features(&self, theta: f64, z_lo: f64, z_hi: f64) -> Vec<Feature> {
        let (t_lo, t_hi) = self.t_range(z_lo, z_hi);
        let mut out = Vec::new();
        for s in 0..self.starts {
            let h = self.start_helix(s);
            out.extend(h.crossings(theta, t_lo, t_hi).filter_map(|t| {
                let lead = h.law.lead(t);
                (lead > 0.0).then(|| Feature {
                    start: s,
                    t,
                    z: h.z(t),
                })
            }));
        }
        out.sort_by(|a, b| a.z.total_cmp(&b.z).then(a.start.cmp(&b.start)));
        out
    }

    fn groove(&self, centre: f64, w_pitch: f64) -> Groove {
        let hp = self.pitch_height();
        let depth = self.depth();
        let (tl, tr) = self.wall_tangents();
        Groove {
            left_top: centre - w_pitch / 2.0 - (depth - hp) * tl,
            left_root: centre - w_pitch / 2.0 + hp * tl,
            right_root: centre + w_pitch / 2.0 - hp * tr,
            right_top: centre + w_pitch / 2.0 + (depth - hp) * tr,
        }
    }

    /// The ideal profile on the generator at `theta` for the window `[z_lo, z_hi]`: the
    /// thread's grooves, and where the part's [`ThreadSpec::outline`] lies below them (its
    /// chamfers, reliefs), the outline: the drawing's part, thread and contour together.
    pub fn column(&self, theta: f64, z_lo: f64, z_hi: f64) -> ColumnIdeal {
        let features = self.features(theta, z_lo, z_hi);
        let grooves: Vec<Groove> = match self.width {
            WidthRule::Groove(w) => features.iter().map(|f| self.groove(f.z, w)).collect(),
            WidthRule::Tooth(tw) => features
                .windows(2)
                .filter_map(|p| {
                    let gap = p[1].z - p[0].z - tw;
                    (gap > 0.0).then(|| self.groove(0.5 * (p[0].z + p[1].z), gap))
                })
                .collect(),
        };
        let depth = self.depth();
        let (tl, tr) = self.wall_tangents();
        let mut verts = envelope(&grooves, depth, tl + tr, z_lo - 1.0, z_hi + 1.0);
        // A taper: the parallel profile sheared onto the cones (exact: a shear keeps
        // segments straight; the walls' tangents were adjusted for it).
        if self.taper.is_some() {
            for v in &mut verts {
                v.h += self.cone_height(v.z);
            }
        }
        let (thread, mut span) = self.thread_grooves(&features);
        if let Some(part) = &self.outline {
            let mut contour: Vec<Vertex> = part
                .points()
                .iter()
                .map(|&(z, r)| Vertex {
                    z,
                    h: self.height(r),
                })
                .collect();
            // Past the part's +z end (its free end, the bar's face) the part is gone: a
            // thread depth below the root stands for "no material" (measurements see an
            // open groove there, as on the cut). Its -z end (the chuck's side) bounds
            // nothing. The drawing defines the thread only on the part.
            let end = part.z_span().1;
            contour.push(Vertex { z: end, h: -depth });
            contour.push(Vertex {
                z: end.max(z_hi + 1.0) + 1.0,
                h: -depth,
            });
            verts = clip::lower(&verts, &contour);
            span = span.and_then(|(a, b)| (a < end).then_some((a, b.min(end))));
        }
        ColumnIdeal {
            verts,
            features,
            grooves: thread,
            span,
            depth,
            cone: self
                .taper
                .map_or((0.0, 0.0), |t| (self.sense() * t.slope, t.z_ref)),
        }
    }

    /// The grooves of the thread among the crossings `features` (sorted by z), z
    /// increasing, and the span they define: it reaches from the middle of the tooth
    /// before the first to the middle of the tooth after the last, so that the walls of
    /// the end grooves are compared on both sides (a cut past the last wall is a gouge
    /// of the thread). An equal-width groove is centred on its feature; an equal-tooth
    /// groove lies between two neighbouring teeth and takes the start of the tooth on its
    /// +z side, its helix parameter half a pitch from that tooth's toward the other.
    fn thread_grooves(&self, features: &[Feature]) -> (Vec<ThreadGroove>, Option<(f64, f64)>) {
        let (g_lo, g_hi) = self.groove_range();
        let inside = |g: f64| g >= g_lo - 1e-9 && g <= g_hi + 1e-9;
        let hp = self.pitch_height();
        let over = self.depth() - hp;
        let (tl, tr) = self.wall_tangents();
        let make = |start: u32, g: f64, centre: f64, w: f64| ThreadGroove {
            start,
            turn: self.turn_of(g),
            g,
            z_lo: centre - w / 2.0 - over * tl,
            z_hi: centre + w / 2.0 + over * tr,
        };
        // Every groove on the generator (thread or not), z increasing.
        let all: Vec<ThreadGroove> = match self.width {
            WidthRule::Groove(w) => features
                .iter()
                .map(|f| make(f.start, f.t, f.z, w))
                .collect(),
            WidthRule::Tooth(tw) => {
                // Moving toward -z along a generator is moving along the helix against
                // the direction of its axial travel.
                let step = -self.helix.dir * 0.5 / self.starts as f64;
                features
                    .windows(2)
                    .map(|p| {
                        let g = p[1].t + step;
                        make(p[1].start, g, 0.5 * (p[0].z + p[1].z), p[1].z - p[0].z - tw)
                    })
                    .collect()
            }
        };
        let first = all.iter().position(|g| inside(g.g));
        let last = all.iter().rposition(|g| inside(g.g));
        let (Some(i0), Some(i1)) = (first, last) else {
            return (Vec::new(), None);
        };
        let lo = if i0 > 0 {
            0.5 * (all[i0 - 1].z_hi + all[i0].z_lo)
        } else {
            all[i0].z_lo
        };
        let hi = if i1 + 1 < all.len() {
            0.5 * (all[i1].z_hi + all[i1 + 1].z_lo)
        } else {
            all[i1].z_hi
        };
        let thread = all[i0..=i1]
            .iter()
            .filter(|g| inside(g.g))
            .copied()
            .collect();
        (thread, Some((lo, hi)))
    }
}

/// Lower envelope (in height) of the grooves: the exact ideal profile polyline.
fn envelope(grooves: &[Groove], depth: f64, widening: f64, z_lo: f64, z_hi: f64) -> Vec<Vertex> {
    let mut v: Vec<Vertex> = Vec::with_capacity(grooves.len() * 4 + 2);
    v.push(Vertex {
        z: z_lo.min(grooves.first().map_or(z_lo, |g| g.left_top)),
        h: depth,
    });
    let mut prev: Option<Groove> = None;
    for g in grooves {
        match prev {
            Some(p) if p.right_top > g.left_top => {
                // The walls of neighbouring grooves meet below the crest.
                v.pop(); // p.right_top
                let hs = if widening > 0.0 {
                    (g.left_root - p.right_root) / widening
                } else {
                    0.0
                };
                if hs > 0.0 {
                    let z = p.right_root + hs * (p.right_top - p.right_root) / depth;
                    v.push(Vertex { z, h: hs });
                    v.push(Vertex {
                        z: g.left_root,
                        h: 0.0,
                    });
                } else {
                    // Roots overlap: one merged root flat.
                    v.pop(); // p.right_root
                }
            }
            _ => {
                v.push(Vertex {
                    z: g.left_top,
                    h: depth,
                });
                v.push(Vertex {
                    z: g.left_root,
                    h: 0.0,
                });
            }
        }
        v.push(Vertex {
            z: g.right_root,
            h: 0.0,
        });
        v.push(Vertex {
            z: g.right_top,
            h: depth,
        });
        prev = Some(*g);
    }
    let last = v.last().map_or(z_hi, |p| p.z);
    v.push(Vertex {
        z: z_hi.max(last),
        h: depth,
    });
    v
}

/// [`geom::segment_foot`] in `(z, h)` for the profile's vertices.
#[inline]
fn segment_foot(p: (f64, f64), a: Vertex, b: Vertex) -> (f64, i8) {
    geom::segment_foot(DVec2::from(p), a.vec(), b.vec())
}

impl Vertex {
    /// The vertex as `(z, h)`.
    #[inline]
    pub(crate) fn vec(self) -> DVec2 {
        DVec2::new(self.z, self.h)
    }
}

impl ColumnIdeal {
    /// Index of the segment `[verts[i], verts[i+1]]` containing `z` (the first such one).
    fn segment_at(&self, z: f64) -> usize {
        let i = self.verts.partition_point(|v| v.z <= z);
        i.clamp(1, self.verts.len() - 1) - 1
    }

    /// Ideal height above the root at `z`.
    pub fn height_at(&self, z: f64) -> f64 {
        let i = self.segment_at(z);
        let (a, b) = (self.verts[i], self.verts[i + 1]);
        if b.z <= a.z {
            return a.h.min(b.h);
        }
        let u = ((z - a.z) / (b.z - a.z)).clamp(0.0, 1.0);
        a.h + u * (b.h - a.h)
    }

    /// Fill `out[k]` with the ideal height of cell `j0 + k` of a column whose cell `j` lies
    /// at `z0 + j*dz`, walking the polyline once. A wall is placed on the cells by the
    /// stock's tie rule (`stock::first_cell`, computed from `z0` as the sweep
    /// does): a cell on a vertical wall takes the wall's +z side.
    pub fn fill_heights(&self, z0: f64, dz: f64, j0: usize, out: &mut [f32]) {
        let cell_of = |z: f64| first_cell((z - z0) / dz);
        let mut i = self.segment_at(z0 + j0 as f64 * dz);
        // Step back over vertices the cell rule puts after the first cell.
        while i > 0 && cell_of(self.verts[i].z) > j0 as f64 {
            i -= 1;
        }
        // The cell the next vertex falls on, computed once per vertex.
        let n = self.verts.len();
        let next_of = |i: usize| {
            if i + 2 < n {
                cell_of(self.verts[i + 1].z)
            } else {
                f64::INFINITY
            }
        };
        let mut next = next_of(i);
        // Runs of cells on one segment: a wall or a flat is one value.
        let len = out.len();
        let mut k = 0;
        while k < len {
            let j = (j0 + k) as f64;
            while next <= j {
                i += 1;
                next = next_of(i);
            }
            // The cells before the next vertex's (`next` is a whole cell number > j).
            let end = if next.is_finite() {
                ((next - j0 as f64) as usize).min(len)
            } else {
                len
            };
            let (a, b) = (self.verts[i], self.verts[i + 1]);
            let run = &mut out[k..end];
            if b.z <= a.z {
                run.fill(a.h.min(b.h) as f32);
            } else if a.h == b.h {
                // A flat: `u * (b.h - a.h)` is +0 whatever `u` (in [0, 1]).
                run.fill((a.h + 0.0) as f32);
            } else {
                for (m, o) in run.iter_mut().enumerate() {
                    let z = z0 + (j0 + k + m) as f64 * dz;
                    let u = ((z - a.z) / (b.z - a.z)).clamp(0.0, 1.0);
                    *o = (a.h + u * (b.h - a.h)) as f32;
                }
            }
            k = end;
        }
    }

    /// Distance in the axial plane from `(z, h)` to the ideal profile, and the part of the
    /// profile nearest to it. `bound` must be at least the distance (the vertical gap to
    /// the profile always is).
    pub fn distance(&self, z: f64, h: f64, bound: f64) -> (f64, Flank) {
        self.distance_near(self.segment_at(z), z, h, bound)
    }

    /// [`ColumnIdeal::distance`] starting from `hint`, the index of the segment containing
    /// `z` (callers walking along z keep it and skip the search). Segments are visited
    /// outward from the hint and the scan stops on each side once the axial gap alone
    /// exceeds the best distance so far; ties go to the lowest segment index.
    pub fn distance_near(&self, hint: usize, z: f64, h: f64, bound: f64) -> (f64, Flank) {
        match self.nearest(hint, z, h, bound) {
            Some((d, i, end)) => (d, self.flank_of(i, end, z, h)),
            None => (bound, Flank::Crest),
        }
    }

    /// The distance as [`ColumnIdeal::distance_near`], with the part left to decide:
    /// `(distance, segment, end)`, `end` -1 or 1 where the nearest point is that
    /// segment's first or last vertex (the part is then decided by
    /// [`ColumnIdeal::flank_of`]), else 0. `None` when nothing lies within `bound`.
    pub(crate) fn nearest(
        &self,
        hint: usize,
        z: f64,
        h: f64,
        bound: f64,
    ) -> Option<(f64, usize, i8)> {
        let last = self.verts.len() - 2;
        let i0 = hint.min(last);
        let mut best = bound * bound;
        let mut best_i = usize::MAX;
        let mut best_end = 0i8;
        let mut i = i0;
        while i <= last {
            let (a, b) = (self.verts[i], self.verts[i + 1]);
            let gap = a.z - z;
            if gap > 0.0 && gap * gap > best {
                break;
            }
            let (d2, end) = segment_foot((z, h), a, b);
            if d2 < best || (best_i == usize::MAX && d2 <= best) {
                best = d2;
                best_i = i;
                best_end = end;
            }
            i += 1;
        }
        let mut i = i0;
        while i > 0 {
            i -= 1;
            let (a, b) = (self.verts[i], self.verts[i + 1]);
            let gap = z - b.z;
            if gap > 0.0 && gap * gap > best {
                break;
            }
            let (d2, end) = segment_foot((z, h), a, b);
            if d2 <= best {
                best = d2;
                best_i = i;
                best_end = end;
            }
        }
        (best_i != usize::MAX).then(|| (best.sqrt(), best_i, best_end))
    }

    /// The part a point nearest to segment `i` (at its end `end`, see
    /// [`ColumnIdeal::nearest`]) belongs to.
    pub(crate) fn flank_of(&self, i: usize, end: i8, z: f64, h: f64) -> Flank {
        // Only a nearest point at a vertex has two candidate segments.
        let i = if end != 0 {
            self.at_vertex(i, end, z, h)
        } else {
            i
        };
        let (a, b) = (self.verts[i], self.verts[i + 1]);
        self.segment_kind(a, b)
    }

    /// The segment a point nearest to the end `end` (-1: its first vertex, 1: its last) of
    /// segment `i` belongs to. Both segments meeting at that vertex are equally near: the
    /// point belongs to the one whose normal is closer to the direction from the vertex
    /// to the point (the wedge between the two normals is split at its bisector). This
    /// makes the flank names symmetric under mirroring, where a tie broken by index would
    /// not be.
    #[inline]
    fn at_vertex(&self, i: usize, end: i8, z: f64, h: f64) -> usize {
        let last = self.verts.len() - 2;
        let proper = |k: usize| {
            let (a, b) = (self.verts[k], self.verts[k + 1]);
            a.z != b.z || a.h != b.h
        };
        let (vertex, other) = if end < 0 {
            let mut k = i;
            while k > 0 && !proper(k - 1) {
                k -= 1;
            }
            (self.verts[i], (k > 0).then(|| k - 1))
        } else {
            let mut k = i + 1;
            while k <= last && !proper(k) {
                k += 1;
            }
            (self.verts[i + 1], (k <= last).then_some(k))
        };
        let Some(o) = other else { return i };
        let (vz, vh) = (z - vertex.z, h - vertex.h);
        // |v . n| / |n| for the normal n = (-sh, sz) of each segment, compared squared.
        let align = |k: usize| {
            let (p, q) = (self.verts[k], self.verts[k + 1]);
            let (sz, sh) = (q.z - p.z, q.h - p.h);
            let dot = -sh * vz + sz * vh;
            (dot * dot, sz * sz + sh * sh)
        };
        let ((no, lo), (ni, li)) = (align(o), align(i));
        if no * li > ni * lo {
            o
        } else {
            i
        }
    }

    /// Index of the segment containing `z`, moving forward from `hint` (for callers
    /// walking along increasing z).
    pub fn advance(&self, mut hint: usize, z: f64) -> usize {
        while hint + 2 < self.verts.len() && self.verts[hint + 1].z <= z {
            hint += 1;
        }
        hint
    }

    /// The part of the profile segment `i` belongs to (as [`ColumnIdeal::distance`] names
    /// the segments).
    pub(crate) fn segment_flank(&self, i: usize) -> Flank {
        self.segment_kind(self.verts[i], self.verts[i + 1])
    }

    fn segment_kind(&self, a: Vertex, b: Vertex) -> Flank {
        // Heights above the cone of a taper's root (the heights themselves for a parallel
        // thread): a root or crest runs along the cone.
        let (slope, z_ref) = self.cone;
        let local = |v: Vertex| v.h - slope * (v.z - z_ref);
        let (ha, hb) = (local(a), local(b));
        let eps = 1e-12 * (1.0 + self.depth + slope.abs() * (a.z - z_ref).abs());
        if (ha - hb).abs() <= eps {
            if ha <= eps {
                Flank::Root
            } else {
                Flank::Crest
            }
        } else if hb < ha {
            Flank::Left
        } else {
            Flank::Right
        }
    }

    /// A taper's cone in height at `z` (0 for a parallel thread): the ideal's height less
    /// this is its height above the local root.
    pub fn cone_height(&self, z: f64) -> f64 {
        self.cone.0 * (z - self.cone.1)
    }

    /// The thread groove a point at `z` belongs to, moving forward from `hint` (for callers
    /// walking along increasing z): the region of a groove reaches halfway across the
    /// tooth to each neighbour (the middle of the two crest ends). `None` without grooves.
    pub fn groove_at(&self, mut hint: usize, z: f64) -> Option<usize> {
        let g = &self.grooves;
        if g.is_empty() {
            return None;
        }
        while hint + 1 < g.len() && z >= 0.5 * (g[hint].z_hi + g[hint + 1].z_lo) {
            hint += 1;
        }
        Some(hint)
    }

    /// The index of the segment holding `z` (as [`ColumnIdeal::advance`]) when it is a
    /// root flat (`Some(true)`), a crest flat (`Some(false)`), else `None`.
    pub fn flat(&self, seg: usize) -> Option<bool> {
        let (a, b) = (self.verts[seg], self.verts[seg + 1]);
        if b.z <= a.z {
            return None;
        }
        match self.segment_kind(a, b) {
            Flank::Root => Some(true),
            Flank::Crest => Some(false),
            _ => None,
        }
    }
}

/// Seed 002's square equal-tooth screw (major 28, minor 22, pitch 7 + 1.5 t, tooth 3,
/// 7 turns), or with flank angles (`angles` deg) a trapezoid of the same pitches: a fixture
/// for the tests of the thread and of the comparison.
#[cfg(test)]
pub(crate) fn seed002_screw(side: Side, angles: f64) -> ThreadSpec {
    let (root, crest) = match side {
        Side::External => (11.0, 14.0),
        Side::Internal => (14.0, 11.0),
    };
    ThreadSpec {
        side,
        root_radius: root,
        crest_radius: crest,
        pitch_radius: 12.5,
        left_angle: angles.to_radians(),
        right_angle: angles.to_radians(),
        width: WidthRule::Tooth(3.0),
        starts: 1,
        helix: Helix {
            z0: 0.0,
            dir: -1.0,
            law: crate::model::helix::LeadLaw {
                f: 7.0 - 0.75,
                k: 1.5,
            },
            theta0: 0.0,
            spin: 1.0,
        },
        turns: 7.0,
        outline: None,
        taper: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::LeadLaw;

    fn square_equal_tooth() -> ThreadSpec {
        seed002_screw(Side::External, 0.0)
    }

    #[test]
    fn equal_tooth_profile_on_reference_generator() {
        let th = square_equal_tooth();
        let col = th.column(0.0, -90.0, 5.0);
        // Teeth centred at 0, -7, -15.5, ...: crest at the centre, root halfway between.
        assert_eq!(col.height_at(0.0), 3.0);
        assert_eq!(col.height_at(-7.0 + 1.49), 3.0);
        assert_eq!(col.height_at(-7.0 + 1.51), 0.0);
        assert_eq!(col.height_at(-3.5), 0.0);
        assert_eq!(col.height_at(-15.5 + 1.49), 3.0);
        let (a, b) = col.span.unwrap();
        assert!((a + 80.5).abs() < 1e-12 && b.abs() < 1e-12);
        // A point 0.2 mm into the groove [-5.5, -1.5] below the tooth at 0, at mid height:
        // nearest is the groove's +z wall (the tooth's lower flank).
        let (d, f) = col.distance(-1.5 - 0.2, 1.5, 2.0);
        assert!((d - 0.2).abs() < 1e-12);
        assert_eq!(f, Flank::Right);
        // A point 0.3 mm inside the tooth from its upper flank (z = 1.5), near the root of
        // the groove above: nearest is that groove's -z wall.
        let (d, f) = col.distance(1.5 - 0.3, 0.5, 3.0);
        assert!((d - 0.3).abs() < 1e-12);
        assert_eq!(f, Flank::Left);
    }

    #[test]
    fn sharp_v_crest_is_intersected() {
        // 60 deg sharp V: grooves of width P at the crest meet in a point.
        let p = 2.0;
        let depth = p * 0.866_025_403_784_438_6;
        let th = ThreadSpec {
            side: Side::External,
            root_radius: 10.0,
            crest_radius: 10.0 + depth,
            pitch_radius: 10.0 + depth / 2.0,
            left_angle: 30f64.to_radians(),
            right_angle: 30f64.to_radians(),
            width: WidthRule::Groove(p / 2.0 + 0.2),
            starts: 1,
            helix: Helix {
                z0: 0.0,
                dir: -1.0,
                law: LeadLaw::constant(p),
                theta0: 0.0,
                spin: 1.0,
            },
            turns: 5.0,
            outline: None,
            taper: None,
        };
        let col = th.column(0.0, -10.0, 1.0);
        // The crest between grooves at 0 and -2 is at -1, lowered by 0.1/tan30 ... in h.
        let crest = col.height_at(-1.0);
        let expect = depth - 0.1 / 30f64.to_radians().tan();
        assert!((crest - expect).abs() < 1e-9, "{crest} vs {expect}");
        // Heights never exceed the depth and the polyline is monotone in z.
        assert!(col.verts.windows(2).all(|w| w[0].z <= w[1].z));
    }
}

#[cfg(test)]
mod taper_tests {
    use super::*;
    use crate::model::helix::LeadLaw;

    /// An NPT-like 60 deg thread of pitch 1.814 on a 1:16 taper, external (diameter growing
    /// towards -z, slope -1/32) or internal (shrinking, +1/32), its radii at z = 0.
    fn tapered(side: Side) -> ThreadSpec {
        let p = 1.814;
        let depth = 0.8 * p;
        let (root, crest, slope) = match side {
            Side::External => (10.0, 10.0 + depth, -1.0 / 32.0),
            Side::Internal => (10.0 + depth, 10.0, 1.0 / 32.0),
        };
        ThreadSpec {
            side,
            root_radius: root,
            crest_radius: crest,
            pitch_radius: 10.0 + 0.5 * depth,
            left_angle: 30f64.to_radians(),
            right_angle: 30f64.to_radians(),
            width: WidthRule::Groove(p / 2.0),
            starts: 1,
            helix: Helix {
                z0: -0.3,
                dir: -1.0,
                law: LeadLaw::constant(p),
                theta0: 0.0,
                spin: 1.0,
            },
            turns: 8.0,
            outline: None,
            taper: Some(Taper { slope, z_ref: 0.0 }),
        }
    }

    /// The tapered ideal against its closed form: roots and crests on the cones (their
    /// radius `r_ref + slope (z - z_ref)`), every wall at its flank angle from the radial in
    /// the axial plane, each groove `w` wide along the pitch cone and centred on its
    /// feature, the parts named as a parallel thread's.
    #[test]
    fn the_tapered_ideal_has_its_cones_and_flank_angles() {
        for side in [Side::External, Side::Internal] {
            let t = tapered(side);
            let slope = t.taper.unwrap().slope;
            let col = t.column(0.7, -16.0, 1.0);
            let r_of = |v: &Vertex| t.radius(v.h);
            let cone = |r_ref: f64, z: f64| r_ref + slope * z;
            let mut walls = 0;
            for w in col.verts.windows(2) {
                let (a, b) = (w[0], w[1]);
                if a.z < -15.0 || b.z > 0.5 || (a.z == b.z && a.h == b.h) {
                    continue;
                }
                let (ra, rb) = (r_of(&a), r_of(&b));
                match col.segment_kind(a, b) {
                    Flank::Root => {
                        assert!(
                            (ra - cone(t.root_radius, a.z)).abs() < 1e-12,
                            "{side:?} root"
                        );
                        assert!(
                            (rb - cone(t.root_radius, b.z)).abs() < 1e-12,
                            "{side:?} root"
                        );
                    }
                    Flank::Crest => {
                        assert!(
                            (ra - cone(t.crest_radius, a.z)).abs() < 1e-12,
                            "{side:?} crest"
                        );
                        assert!(
                            (rb - cone(t.crest_radius, b.z)).abs() < 1e-12,
                            "{side:?} crest"
                        );
                    }
                    _ => {
                        let angle = ((b.z - a.z) / (rb - ra)).abs().atan();
                        assert!(
                            (angle - 30f64.to_radians()).abs() < 1e-12,
                            "{side:?}: wall at {} deg",
                            angle.to_degrees()
                        );
                        walls += 1;
                    }
                }
            }
            assert!(walls >= 14, "{side:?}: {walls} walls");
            // The pitch cone crosses each groove's walls w/2 either side of its feature.
            let hp = t.pitch_height();
            for f in col.features.iter().filter(|f| f.z > -14.0 && f.z < -1.0) {
                for z in [f.z - 1.814 / 4.0, f.z + 1.814 / 4.0] {
                    let local = col.height_at(z) - t.cone_height(z);
                    assert!(
                        (local - hp).abs() < 1e-12,
                        "{side:?} z {z}: {local} vs {hp}"
                    );
                }
                // The groove's centre is below the pitch cone (external: the root side).
                assert!(col.height_at(f.z) - t.cone_height(f.z) < hp);
            }
        }
    }
}
