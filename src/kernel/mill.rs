//! Thread milling: cutters as solids of revolution, swept along the tool-centre path of a
//! milling program through the radial dexels of the part.
//!
//! The part is static, its axis along z at the origin of the path's xy. A thread mill
//! spins far faster than it feeds, so what cuts is the envelope of its teeth: the solid of
//! revolution of its axial profile ([`Cutter`]: `R(u)` from the tip up). At one position
//! (centre `c` in xy, tip at `z_tip`) the disc of radius `R(z - z_tip)` meets the radial ray
//! of column `theta` (direction `d`, normal `n`) between `s = d.c -+ sqrt(R^2 - (n.c)^2)`;
//! an outer surface keeps what lies inside the near end, a bore what lies outside the far
//! end, so in signed radii (`q = sense r`, see [`crate::model::stock`]) every dexel is cut by
//! `q = min(q, sense (d.c) - sqrt(R^2 - (n.c)^2))`. Each profile segment is linear in `z`,
//! so the cells it covers are walked as a ramp, clipped to where the disc can reach past
//! the blank, without branches (vectorised; AVX2 when the CPU has it, with the same bits).
//!
//! The path is sampled ([`MillPath`]): each move at steps of at most [`DZ_STEP`] along the
//! axis and [`xy_step`] across it. A step's axial part shifts the profile by at most half a
//! step (an error of `DZ_STEP / 2` in the report's axial-plane distance), its part across
//! the ray misses the top of a disc by at most `dxy^2 / (8 R)`; the two halves of
//! [`SAMPLING_BOUND_MM`]. Columns run in parallel with rayon; the order of the `min`s does
//! not matter and the per-move figures are merged in column order, so the result does not
//! depend on the thread count.

use crate::model::stock::{Grid, Stock, Surface};
use rayon::prelude::*;

/// The stated bound of the path sampling on the cut surface (mm, axial-plane distance).
pub const SAMPLING_BOUND_MM: f64 = 0.002;
/// Largest axial step between samples (mm): shifts the profile by at most half of it.
pub(crate) const DZ_STEP: f64 = SAMPLING_BOUND_MM;
/// At most this many samples in one simulation (memory and time guard).
pub(crate) const MAX_SAMPLES: usize = 20_000_000;

/// Largest step across the ray (mm) for discs of radius `r_min` and up: the sampled disc
/// tops miss the true envelope by at most `dxy^2 / (8 r_min) = SAMPLING_BOUND_MM / 2`.
pub(crate) fn xy_step(r_min: f64) -> f64 {
    (4.0 * SAMPLING_BOUND_MM * r_min.max(1e-3)).sqrt()
}

/// A thread mill (or any milling cutter) as a solid of revolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Cutter {
    /// The axial profile: `(u, R)` vertices from the tip (`u = 0`) up, `u` non-decreasing;
    /// equal `u` with different `R` is a step (a shoulder).
    pub profile: Vec<[f64; 2]>,
    /// Number of flutes (teeth around the circumference) for the feed per tooth.
    pub flutes: u32,
    /// The cutting radius (largest radius of the teeth), what the D register should hold.
    pub radius: f64,
}

/// The shape of a thread mill, as the job gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutterSpec {
    /// Tooth tip diameter (mm).
    pub diameter: f64,
    /// Flank angles from the radial plane (rad), lower and upper flank of each tooth.
    pub half_angles: [f64; 2],
    /// Axial width of the tooth tip (mm).
    pub tip_flat: f64,
    /// Number of teeth (1: a single-profile mill).
    pub teeth: u32,
    /// Tooth spacing (mm).
    pub pitch: f64,
    /// Radial height of a tooth (mm).
    pub tooth_depth: f64,
    /// Height of the first tooth's tip centre above the cutter's end (mm).
    pub first_tooth: f64,
    /// Shank (and neck) diameter above the teeth (mm).
    pub shank_diameter: f64,
    /// Length of the neck (core diameter) between the last tooth and the shank (mm).
    pub neck: f64,
    /// Overall length from the tip (mm).
    pub length: f64,
    /// Flutes.
    pub flutes: u32,
    /// A drill point below the teeth: (drill diameter, included point angle in rad).
    pub drill: Option<(f64, f64)>,
    /// A 90-degree chamfer (countersink) above the teeth up to this diameter (mm).
    pub chamfer: Option<f64>,
}

impl CutterSpec {
    /// Half the axial base width of a tooth: where its flanks meet the core.
    pub fn half_base(&self) -> [f64; 2] {
        [
            0.5 * self.tip_flat + self.tooth_depth * self.half_angles[0].tan(),
            0.5 * self.tip_flat + self.tooth_depth * self.half_angles[1].tan(),
        ]
    }
}

/// A thread mill whose profile does not fit together ([`Cutter::from_spec`]).
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CutterError {
    /// The teeth are deeper than the cutter's radius.
    #[error("the teeth ({depth} mm deep) reach the axis of a {diameter} mm cutter")]
    TeethReachAxis {
        /// Tooth depth (mm).
        depth: f64,
        /// Diameter at the tooth tips (mm).
        diameter: f64,
    },
    /// Neighbouring teeth overlap at the core.
    #[error("teeth {width:.4} mm wide at the core overlap at a pitch of {pitch} mm: make them shallower or the tip flat narrower")]
    TeethOverlap {
        /// Width of a tooth at the core (mm).
        width: f64,
        /// Tooth pitch (mm).
        pitch: f64,
    },
    /// The drill point runs into the first tooth.
    #[error("the drill point ({length:.3} mm long) runs into the first tooth, which starts {first_base:.3} mm above the tip")]
    DrillPointTooLong {
        /// Length of the drill point (mm).
        length: f64,
        /// Height of the first tooth's lower base above the tip (mm).
        first_base: f64,
    },
    /// The first tooth reaches below the cutter's tip.
    #[error("the first tooth ({half_base:.3} mm from its centre to its lower base) does not fit above the tip at {first_tooth} mm")]
    FirstToothLow {
        /// Half the tooth's base, below its centre (mm).
        half_base: f64,
        /// Height of the first tooth's centre above the tip (mm).
        first_tooth: f64,
    },
    /// The chamfer is no wider than the core.
    #[error("the chamfer diameter {chamfer} is not larger than the core ({core:.3})")]
    ChamferInsideCore {
        /// Chamfer diameter (mm).
        chamfer: f64,
        /// Core diameter (mm).
        core: f64,
    },
    /// The cutter ends below its teeth.
    #[error("the cutter is {length} mm long but its teeth end {teeth_end:.3} mm above the tip")]
    TooShort {
        /// Length (mm).
        length: f64,
        /// Height of the teeth's end above the tip (mm).
        teeth_end: f64,
    },
}

impl Cutter {
    /// Build the profile of a thread mill; the error says what does not fit.
    pub fn from_spec(s: &CutterSpec) -> Result<Cutter, CutterError> {
        let rt = 0.5 * s.diameter;
        let rc = rt - s.tooth_depth;
        if rc <= 0.0 {
            return Err(CutterError::TeethReachAxis {
                depth: s.tooth_depth,
                diameter: s.diameter,
            });
        }
        let [hb_lo, hb_hi] = s.half_base();
        if s.teeth > 1 && hb_lo + hb_hi > s.pitch + 1e-9 {
            return Err(CutterError::TeethOverlap {
                width: hb_lo + hb_hi,
                pitch: s.pitch,
            });
        }
        let mut p: Vec<[f64; 2]> = vec![[0.0, 0.0]];
        let first_base = s.first_tooth - hb_lo;
        match s.drill {
            Some((dd, point)) => {
                let rd = 0.5 * dd;
                let h = rd / (0.5 * point).tan();
                if h > first_base + 1e-9 {
                    return Err(CutterError::DrillPointTooLong {
                        length: h,
                        first_base,
                    });
                }
                p.push([h, rd]);
                p.push([first_base, rd]);
            }
            None => {
                if first_base < -1e-9 {
                    return Err(CutterError::FirstToothLow {
                        half_base: hb_lo,
                        first_tooth: s.first_tooth,
                    });
                }
            }
        }
        p.push([first_base.max(0.0), rc]);
        for k in 0..s.teeth {
            let uc = s.first_tooth + k as f64 * s.pitch;
            p.push([uc - hb_lo, rc]);
            p.push([uc - 0.5 * s.tip_flat, rt]);
            if s.tip_flat > 0.0 {
                p.push([uc + 0.5 * s.tip_flat, rt]);
            }
            p.push([uc + hb_hi, rc]);
        }
        let mut u = s.first_tooth + (s.teeth.max(1) - 1) as f64 * s.pitch + hb_hi + s.neck;
        p.push([u, rc]);
        if let Some(dc) = s.chamfer {
            let rch = 0.5 * dc;
            if rch <= rc {
                return Err(CutterError::ChamferInsideCore {
                    chamfer: dc,
                    core: 2.0 * rc,
                });
            }
            u += rch - rc;
            p.push([u, rch]);
        }
        let rs = 0.5 * s.shank_diameter;
        p.push([u, rs]);
        if s.length <= u {
            return Err(CutterError::TooShort {
                length: s.length,
                teeth_end: u,
            });
        }
        p.push([s.length, rs]);
        p.push([s.length, 0.0]);
        p.dedup();
        Ok(Cutter {
            radius: p.iter().map(|v| v[1]).fold(0.0, f64::max).max(rt),
            profile: p,
            flutes: s.flutes.max(1),
        })
    }

    /// The radius at height `u` above the tip (the largest, on a shoulder); 0 outside.
    pub fn radius_at(&self, u: f64) -> f64 {
        let mut best: f64 = 0.0;
        for w in self.profile.windows(2) {
            let ([ua, ra], [ub, rb]) = (w[0], w[1]);
            if u < ua || u > ub {
                continue;
            }
            let r = if ub > ua {
                ra + (rb - ra) * (u - ua) / (ub - ua)
            } else {
                ra.max(rb)
            };
            best = best.max(r);
        }
        best
    }

    /// Length from the tip to the top of the profile.
    pub fn length(&self) -> f64 {
        self.profile.last().map_or(0.0, |v| v[0])
    }

    /// The smallest radius of the cutting part (for the sampling step): the core between
    /// the teeth, or a quarter of the cutting radius if the profile narrows further.
    pub fn core_radius(&self) -> f64 {
        let inner = self
            .profile
            .iter()
            .map(|v| v[1])
            .filter(|&r| r > 0.0)
            .fold(f64::INFINITY, f64::min);
        inner.max(0.25 * self.radius)
    }

    /// Non-vertical profile segments.
    fn segments(&self) -> Vec<Seg> {
        self.profile
            .windows(2)
            .filter(|w| w[1][0] > w[0][0])
            .map(|w| Seg {
                ua: w[0][0],
                ub: w[1][0],
                ra: w[0][1],
                slope: (w[1][1] - w[0][1]) / (w[1][0] - w[0][0]),
                r_hi: w[0][1].max(w[1][1]),
            })
            .collect()
    }
}

#[derive(Clone, Copy, Debug)]
struct Seg {
    ua: f64,
    ub: f64,
    ra: f64,
    slope: f64,
    r_hi: f64,
}

/// One path move for the kernel: the tool centre from `start` to `end`, straight or on a
/// circle about a z-parallel axis (helical when z changes), in the part frame (the part
/// axis is x = y = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Straight.
    Line,
    /// Circular in xy about `centre` by `sweep` rad (positive counter-clockwise seen from
    /// +z), z linear in the angle.
    Arc {
        /// Centre (x, y).
        centre: [f64; 2],
        /// Signed sweep (rad).
        sweep: f64,
    },
}

/// A move of the tool centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathMove {
    /// Tool tip centre at the start (part frame).
    pub start: [f64; 3],
    /// At the end.
    pub end: [f64; 3],
    /// Straight or circular.
    pub motion: Motion,
    /// Index of the cutter.
    pub cutter: usize,
}

impl PathMove {
    /// The position at `tau` in [0, 1].
    pub fn at(&self, tau: f64) -> [f64; 3] {
        let z = self.start[2] + (self.end[2] - self.start[2]) * tau;
        match self.motion {
            Motion::Line => [
                self.start[0] + (self.end[0] - self.start[0]) * tau,
                self.start[1] + (self.end[1] - self.start[1]) * tau,
                z,
            ],
            Motion::Arc { centre, sweep } => {
                let (dx, dy) = (self.start[0] - centre[0], self.start[1] - centre[1]);
                let (s, c) = (sweep * tau).sin_cos();
                [centre[0] + c * dx - s * dy, centre[1] + s * dx + c * dy, z]
            }
        }
    }

    /// Length of the move in xy and along z.
    pub fn lengths(&self) -> (f64, f64) {
        let dz = (self.end[2] - self.start[2]).abs();
        let xy = match self.motion {
            Motion::Line => (self.end[0] - self.start[0]).hypot(self.end[1] - self.start[1]),
            Motion::Arc { centre, sweep } => {
                (self.start[0] - centre[0]).hypot(self.start[1] - centre[1]) * sweep.abs()
            }
        };
        (xy, dz)
    }
}

/// The sampled path: every move's positions, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct MillPath {
    /// The moves.
    pub moves: Vec<PathMove>,
    /// Samples `(x, y, z_tip)` of all moves, move after move (each move's both ends).
    samples: Vec<[f64; 3]>,
    /// Each move's range in `samples`.
    ranges: Vec<std::ops::Range<usize>>,
    /// Each move's samples' bounds: smallest and largest distance from the axis, lowest
    /// tip z (a move that cannot reach the stock is skipped whole).
    bounds: Vec<(f64, f64, f64)>,
}

/// The path would need more samples than [`MAX_SAMPLES`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TooManySamples(pub usize);

impl MillPath {
    /// Sample `moves` for `cutters` at the steps of the stated bound.
    pub fn new(moves: Vec<PathMove>, cutters: &[Cutter]) -> Result<MillPath, TooManySamples> {
        MillPath::refined(moves, cutters, 1)
    }

    /// As [`MillPath::new`] with `refine` times as many samples (to check the bound
    /// against a finer sampling).
    pub fn refined(
        moves: Vec<PathMove>,
        cutters: &[Cutter],
        refine: u32,
    ) -> Result<MillPath, TooManySamples> {
        let mut counts = Vec::with_capacity(moves.len());
        let mut total = 0usize;
        for m in &moves {
            let (xy, dz) = m.lengths();
            let r = cutters.get(m.cutter).map_or(1.0, Cutter::core_radius);
            let n = (dz / DZ_STEP).max(xy / xy_step(r)).ceil().max(1.0) * refine.max(1) as f64;
            if !n.is_finite() || n > MAX_SAMPLES as f64 {
                return Err(TooManySamples(usize::MAX));
            }
            let n = n as usize;
            total += n + 1;
            if total > MAX_SAMPLES {
                return Err(TooManySamples(total));
            }
            counts.push(n);
        }
        let mut samples = Vec::with_capacity(total);
        let mut ranges = Vec::with_capacity(moves.len());
        let mut bounds = Vec::with_capacity(moves.len());
        for (m, &n) in moves.iter().zip(&counts) {
            let a = samples.len();
            samples.extend((0..=n).map(|i| m.at(i as f64 / n as f64)));
            let b = samples[a..].iter().fold(
                (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY),
                |(lo, hi, z), s| {
                    let r = s[0].hypot(s[1]);
                    (lo.min(r), hi.max(r), z.min(s[2]))
                },
            );
            bounds.push(b);
            ranges.push(a..samples.len());
        }
        Ok(MillPath {
            moves,
            samples,
            ranges,
            bounds,
        })
    }

    /// Whether move `m` cannot cut a stock of signed blank radius `q_blank` (an outer
    /// surface `q = r`, a bore `q = -r`) between `z0` and `z1` with discs up to `r_max`.
    fn misses(&self, m: usize, q_blank: f64, z1: f64, r_max: f64) -> bool {
        let (lo, hi, z) = self.bounds[m];
        z > z1
            || (q_blank < 0.0 && hi + r_max <= -q_blank)
            || (q_blank > 0.0 && lo - r_max >= q_blank)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }
}

/// What one move did to the stock (merged over the columns).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MoveCut {
    /// Volume removed (mm^3).
    pub volume: f64,
    /// Largest radial depth removed from one dexel (mm).
    pub depth: f64,
    /// Where: angle (rad) and z (mm).
    pub at: (f64, f64),
    /// Dexels it changed.
    pub dexels: u64,
}

impl MoveCut {
    fn merge(&mut self, o: &MoveCut) {
        self.volume += o.volume;
        self.dexels += o.dexels;
        if o.depth > self.depth {
            self.depth = o.depth;
            self.at = o.at;
        }
    }
}

/// What a milling sweep did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MillStats {
    /// Per move.
    pub moves: Vec<MoveCut>,
    /// Samples that reached a column (placements).
    pub placements: u64,
    /// Dexel updates.
    pub dexel_updates: u64,
}

/// Cut `surface` of the stock along the path: every column by `GridMill::column` on
/// rayon, the per-move figures merged in column order.
pub fn sweep_mill(
    stock: &mut Stock,
    surface: Surface,
    path: &MillPath,
    cutters: &[Cutter],
) -> MillStats {
    let grid = stock.grid;
    let mill = GridMill::new(grid, stock.blank_q(surface), surface, path, cutters);
    let Some(q) = stock.surface_mut(surface) else {
        return MillStats::default();
    };
    let per_column: Vec<MillColumn> = q
        .par_chunks_mut(grid.n_z)
        .enumerate()
        .map(|(i, col)| mill.column(i, col))
        .collect();
    let mut stats = mill.stats();
    for c in &per_column {
        stats.add_column(c);
    }
    stats
}

/// What the path did to one column: per move that changed it (the others add nothing),
/// and the placements and dexel updates.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MillColumn {
    /// The moves that changed the column, in path order: (move index, what it did).
    pub(crate) cuts: Vec<(usize, MoveCut)>,
    /// Samples that reached the column.
    pub(crate) placements: u64,
    /// Dexel updates.
    pub(crate) updates: u64,
}

impl MillStats {
    /// Add one column's figures (in column order, so that sums do not depend on the
    /// thread count).
    pub(crate) fn add_column(&mut self, c: &MillColumn) {
        // A move that did not change the column adds nothing (+0 volume, no dexel, no
        // depth): leaving it out gives the same sums.
        for (m, b) in &c.cuts {
            self.moves[*m].merge(b);
        }
        self.placements += c.placements;
        self.dexel_updates += c.updates;
    }
}

/// The path cutting the columns of a grid one at a time, each in a buffer of its own (the
/// whole grid's column or a streamed one: `q - q_blank`, cut in place).
pub(crate) struct GridMill<'a> {
    grid: Grid,
    q_blank: f64,
    surface: Surface,
    path: &'a MillPath,
    cutters: &'a [Cutter],
    segs: Vec<Vec<Seg>>,
}

impl<'a> GridMill<'a> {
    /// The path's cutters on `grid`'s `surface` of a blank at `q_blank`.
    pub(crate) fn new(
        grid: Grid,
        q_blank: f64,
        surface: Surface,
        path: &'a MillPath,
        cutters: &'a [Cutter],
    ) -> GridMill<'a> {
        GridMill {
            grid,
            q_blank,
            surface,
            path,
            cutters,
            segs: cutters.iter().map(Cutter::segments).collect(),
        }
    }

    /// Empty figures with a slot per move.
    pub(crate) fn stats(&self) -> MillStats {
        MillStats {
            moves: vec![MoveCut::default(); self.path.moves.len()],
            ..MillStats::default()
        }
    }

    /// Cut column `i`, held in `col`.
    pub(crate) fn column(&self, i: usize, col: &mut [f32]) -> MillColumn {
        let (grid, path, q_blank) = (self.grid, self.path, self.q_blank);
        let cell_area = grid.dtheta() * 0.5 * grid.dz;
        let theta = grid.theta(i);
        let ray = MillRay::new(theta, grid.z0, grid.dz, col.len(), q_blank, self.surface);
        let mut cuts = Vec::new();
        let (mut hits, mut snapshot) = (Vec::new(), Vec::new());
        let (mut placements, mut updates) = (0u64, 0u64);
        for (m, mv) in path.moves.iter().enumerate() {
            let segs = &self.segs[mv.cutter];
            ray.hits(path, m, segs, &mut hits);
            // The cells the move may change: from its lowest placed tip up the cutter.
            let len = self.cutters[mv.cutter].length();
            let (lo, hi) = hits
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
                    (lo.min(h.z_tip), hi.max(h.z_tip + len))
                });
            let j0 = ((lo - grid.z0) / grid.dz).ceil().max(0.0);
            let j1 = ((hi - grid.z0) / grid.dz)
                .floor()
                .min(col.len() as f64 - 1.0);
            if j1 < j0 {
                continue;
            }
            let range = j0 as usize..j1 as usize + 1;
            snapshot.clear();
            snapshot.extend_from_slice(&col[range.clone()]);
            placements += hits.len() as u64;
            updates += ray.apply(col, &hits, segs);
            let mut c = MoveCut::default();
            for (k, (&old, &new)) in snapshot.iter().zip(&col[range.clone()]).enumerate() {
                if new < old {
                    let (ro, rn) = (old as f64 + q_blank, new as f64 + q_blank);
                    c.volume += (ro * ro - rn * rn).abs() * cell_area;
                    c.dexels += 1;
                    let d = (old - new) as f64;
                    if d > c.depth {
                        c.depth = d;
                        c.at = (theta, grid.z(range.start + k));
                    }
                }
            }
            if c.dexels > 0 {
                cuts.push((m, c));
            }
        }
        MillColumn {
            cuts,
            placements,
            updates,
        }
    }
}

/// Cut one free-standing column (the fine measurement generators). `q` holds
/// `q - q_blank` and is cut in place.
pub fn mill_column(
    q: &mut [f32],
    c: crate::kernel::sweep::Column,
    path: &MillPath,
    cutters: &[Cutter],
) {
    let segs: Vec<Vec<Seg>> = cutters.iter().map(Cutter::segments).collect();
    let ray = MillRay::new(c.theta, c.z0, c.dz, q.len(), c.q_blank, c.surface);
    let mut hits = Vec::new();
    for (m, mv) in path.moves.iter().enumerate() {
        ray.hits(path, m, &segs[mv.cutter], &mut hits);
        ray.apply(q, &hits, &segs[mv.cutter]);
    }
}

/// Cut one free-standing column by move `m` of `path` alone (which move made a dexel:
/// `report::blame`). `q` holds `q - q_blank` and is cut in place.
pub(crate) fn mill_column_by(
    q: &mut [f32],
    c: crate::kernel::sweep::Column,
    path: &MillPath,
    m: usize,
    cutters: &[Cutter],
) {
    let Some(cutter) = path.moves.get(m).and_then(|mv| cutters.get(mv.cutter)) else {
        return;
    };
    let segs = cutter.segments();
    let ray = MillRay::new(c.theta, c.z0, c.dz, q.len(), c.q_blank, c.surface);
    let mut hits = Vec::new();
    ray.hits(path, m, &segs, &mut hits);
    ray.apply(q, &hits, &segs);
}

/// A column's ray: its direction, cells and surface.
struct MillRay {
    sin: f64,
    cos: f64,
    z0: f64,
    dz: f64,
    /// Cells.
    n: f64,
    q_blank: f64,
    sense: f64,
}

/// A sample that can cut past the blank on a ray: a cut value is `c - sqrt(R^2 - b2)` for
/// discs with `R^2 > need2`.
struct Hit {
    z_tip: f64,
    c: f64,
    b2: f64,
    need2: f64,
}

impl MillRay {
    fn new(theta: f64, z0: f64, dz: f64, n: usize, q_blank: f64, surface: Surface) -> MillRay {
        let (sin, cos) = theta.sin_cos();
        MillRay {
            sin,
            cos,
            z0,
            dz,
            n: n as f64,
            q_blank,
            sense: surface.sense(),
        }
    }

    /// The samples of move `m` that can cut past the blank on this ray (none when the
    /// move's bounds keep it away), into `out`. With `C = sense (d.c) - q_blank` and
    /// `B = n.c` the cut is below the blank only where `sqrt(R^2 - B^2) > C`; an outer
    /// surface also needs the disc on the ray's side of the axis (`d.c + sqrt(..) > 0`).
    fn hits(&self, path: &MillPath, m: usize, segs: &[Seg], out: &mut Vec<Hit>) {
        out.clear();
        let r_max = segs.iter().map(|s| s.r_hi).fold(0.0, f64::max);
        if path.misses(m, self.q_blank, self.z0 + self.n * self.dz, r_max) {
            return;
        }
        for s in &path.samples[path.ranges[m].clone()] {
            let a = self.cos * s[0] + self.sin * s[1];
            let b = -self.sin * s[0] + self.cos * s[1];
            if b.abs() >= r_max {
                continue;
            }
            let c = self.sense * a - self.q_blank;
            let mut extra = c.max(0.0);
            if self.sense > 0.0 && a < 0.0 {
                extra = extra.max(-a);
            }
            let need2 = b * b + extra * extra;
            if r_max * r_max > need2 {
                out.push(Hit {
                    z_tip: s[2],
                    c,
                    b2: b * b,
                    need2,
                });
            }
        }
    }

    /// Apply the hits to the column; returns the dexel updates.
    fn apply(&self, col: &mut [f32], hits: &[Hit], segs: &[Seg]) -> u64 {
        let (z0, dz, n) = (self.z0, self.dz, self.n);
        let mut updates = 0u64;
        for h in hits {
            let need = h.need2.sqrt();
            for g in segs {
                if g.r_hi * g.r_hi <= h.need2 {
                    continue;
                }
                // Cells whose centre lies in [ua, ub) above the tip.
                let base = h.z_tip + g.ua - z0;
                let mut j0 = (base / dz).ceil().max(0.0);
                let mut j1 = ((h.z_tip + g.ub - z0) / dz).ceil().min(n) - 1.0;
                // Clip to where R(u) > need: R is linear in j.
                if g.slope != 0.0 {
                    let jn = ((need - g.ra) / g.slope + base) / dz;
                    if g.slope > 0.0 {
                        j0 = j0.max(jn.floor());
                    } else {
                        j1 = j1.min(jn.ceil());
                    }
                }
                if j1 < j0 {
                    continue;
                }
                let r0 = g.ra + g.slope * (j0 * dz - base);
                let (j0, j1) = (j0 as usize, j1 as usize);
                updates += (j1 + 1 - j0) as u64;
                ramp(
                    &mut col[j0..=j1],
                    r0 as f32,
                    (g.slope * dz) as f32,
                    h.b2 as f32,
                    h.c as f32,
                );
            }
        }
        updates
    }
}

/// `q_j = min(q_j, c - sqrt(max(R_j^2 - b2, 0)))` with `R_j = r0 + j step`; cells whose disc
/// misses the ray (`R_j^2 <= b2`) or does not reach below the blank are left as they are.
fn ramp(q: &mut [f32], r0: f32, step: f32, b2: f32, c: f32) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked above); the function is the same code.
            unsafe { ramp_avx2(q, r0, step, b2, c) };
            return;
        }
    }
    ramp_generic(q, r0, step, b2, c);
}

#[inline(always)]
fn ramp_generic(q: &mut [f32], r0: f32, step: f32, b2: f32, c: f32) {
    for (j, v) in q.iter_mut().enumerate() {
        let r = r0 + step * j as f32;
        let t = r * r - b2;
        let cand = if t > 0.0 { c - t.sqrt() } else { f32::INFINITY };
        *v = if cand < *v { cand } else { *v };
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn ramp_avx2(q: &mut [f32], r0: f32, step: f32, b2: f32, c: f32) {
    ramp_generic(q, r0, step, b2, c)
}

/// The largest arc of the tooth-tip circle (radius `r_tip`) in uncut material over each
/// move, in rad (0 for moves that cut nothing of the blank ring `r_lo < r < r_hi`): the
/// material is the ring less what the tip circle swept during the last turn about the part
/// axis (a comb's higher teeth have cut it there). Seen in xy at 0.5 deg on the circle and
/// at most 720 positions per move.
pub(crate) fn engagement(path: &MillPath, r_tip: &[f64], ring: (f64, f64)) -> Vec<f64> {
    const POINTS: usize = 720;
    let (r_lo, r_hi) = ring;
    // Visited positions (x, y, cumulative angle about the axis).
    let mut seen: Vec<(f64, f64, f64)> = Vec::new();
    let mut phi_prev: Option<f64> = None;
    let mut cum = 0.0;
    let mut out = Vec::with_capacity(path.moves.len());
    for (m, mv) in path.moves.iter().enumerate() {
        let rt = r_tip[mv.cutter];
        let range = path.ranges[m].clone();
        let every = range.len().div_ceil(720).max(1);
        let mut best: f64 = 0.0;
        for s in path.samples[range].iter().step_by(every) {
            let phi = s[1].atan2(s[0]);
            if s[0].hypot(s[1]) > 1e-9 {
                if let Some(p) = phi_prev {
                    let mut d = phi - p;
                    d -= std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
                    cum += d;
                }
                phi_prev = Some(phi);
            }
            let recent: Vec<&(f64, f64, f64)> = seen
                .iter()
                .rev()
                .take_while(|q| (cum - q.2).abs() < std::f64::consts::TAU - 1e-9)
                .filter(|q| (q.0 - s[0]).hypot(q.1 - s[1]) < 2.0 * rt)
                .collect();
            let mut inside = 0usize;
            for k in 0..POINTS {
                let b = std::f64::consts::TAU * (k as f64 + 0.5) / POINTS as f64;
                let (px, py) = (s[0] + rt * b.cos(), s[1] + rt * b.sin());
                let r = px.hypot(py);
                if r <= r_lo || r >= r_hi {
                    continue;
                }
                let cut = recent
                    .iter()
                    .any(|q| (px - q.0).powi(2) + (py - q.1).powi(2) < rt * rt);
                if !cut {
                    inside += 1;
                }
            }
            best = best.max(std::f64::consts::TAU * inside as f64 / POINTS as f64);
            seen.push((s[0], s[1], cum));
        }
        out.push(best);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::stock::Grid;

    fn comb(teeth: u32) -> CutterSpec {
        CutterSpec {
            diameter: 10.0,
            half_angles: [30f64.to_radians(); 2],
            tip_flat: 0.1875,
            teeth,
            pitch: 1.5,
            tooth_depth: 0.92,
            first_tooth: 0.75,
            shank_diameter: 8.0,
            neck: 1.0,
            length: 40.0,
            flutes: 1,
            drill: None,
            chamfer: None,
        }
    }

    #[test]
    fn comb_profile_has_its_teeth_at_the_pitch() {
        let c = Cutter::from_spec(&comb(3)).unwrap();
        for k in 0..3 {
            let u = 0.75 + 1.5 * k as f64;
            assert!((c.radius_at(u) - 5.0).abs() < 1e-12);
            // On the flank, 0.3 mm from the tip centre: R = 5 - (0.3 - f/2) / tan 30.
            let r = 5.0 - (0.3 - 0.09375) / 30f64.to_radians().tan();
            assert!((c.radius_at(u + 0.3) - r).abs() < 1e-12);
            assert!((c.radius_at(u - 0.3) - r).abs() < 1e-12);
        }
        assert!((c.radius_at(20.0) - 4.0).abs() < 1e-12);
        assert_eq!(c.radius, 5.0);
        let e = Cutter::from_spec(&CutterSpec {
            tooth_depth: 1.3,
            ..comb(3)
        })
        .unwrap_err();
        assert!(matches!(e, CutterError::TeethOverlap { .. }), "{e}");
        assert!(e.to_string().contains("overlap"), "{e}");
    }

    /// A straight plunge of a disc cutter into a bar along z cuts the bar to the exact
    /// radius where the ray meets the disc: closed form for every column.
    #[test]
    fn plunge_cuts_the_disc_exactly() {
        let grid = Grid {
            n_theta: 72,
            n_z: 100,
            theta0: 0.0,
            z0: -0.995,
            dz: 0.01,
        };
        let mut stock = Stock::blank(grid, 10.0, 0.0);
        // A plain cylinder of radius 4 (teeth of zero width, shank of radius 4).
        let cutter = Cutter {
            profile: vec![[0.0, 0.0], [0.0, 4.0], [5.0, 4.0], [5.0, 0.0]],
            flutes: 2,
            radius: 4.0,
        };
        let m = PathMove {
            start: [11.0, 0.0, 2.0],
            end: [11.0, 0.0, -0.5],
            motion: Motion::Line,
            cutter: 0,
        };
        let path = MillPath::new(vec![m], std::slice::from_ref(&cutter)).unwrap();
        let stats = sweep_mill(&mut stock, Surface::Outer, &path, &[cutter]);
        for i in 0..grid.n_theta {
            let th = grid.theta(i);
            let (a, b) = (11.0 * th.cos(), -11.0 * th.sin());
            // Behind the axis (a < 0) the disc misses the ray's half.
            let expect = if b.abs() < 4.0 && a > 0.0 {
                (a - (16.0 - b * b).sqrt()).min(10.0)
            } else {
                10.0
            };
            for j in [0usize, 40, 60, 99] {
                let got = stock.radius(Surface::Outer, i, j).unwrap();
                let z = grid.z(j);
                let e = if z >= -0.5 { expect } else { 10.0 };
                assert!((got - e).abs() < 2e-6, "col {i} cell {j}: {got} vs {e}");
            }
        }
        assert!(stats.moves[0].volume > 0.0);
    }
}
