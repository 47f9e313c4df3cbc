//! Compare the cut stock with the ideal thread: signed deviation per dexel, volumes, and
//! the worst gouge and leftover per turn and flank.
//!
//! The deviation of a dexel is the distance, in the axial plane, from the cut surface point
//! `(z, h_cut)` to the exact ideal profile polyline of its generator, signed by the side:
//! **gouge** when the cut lies inside the ideal part (material removed that should stay),
//! **leftover** when it lies outside (stock that should be gone). The true distance is used
//! rather than the radial gap scaled by the local slope: on a square groove a wall moved
//! 0.1 mm axially leaves dexels whose radial gap is the full thread depth, and only the
//! distance to the wall gives 0.1 mm. Distances ignore the helix angle (a tilt of a few
//! degrees, cos 5 deg = 0.996).
//!
//! Volumes are exact per dexel in cylindrical coordinates, `|r1^2 - r2^2|/2 * dtheta * dz`,
//! summed in a fixed order (columns, then cells) so they do not depend on the thread count.

use super::runs;
use crate::model::stock::{Grid, Stock, Surface};
use crate::model::thread::{Flank, ThreadGroove, ThreadSpec, WidthRule};
use glam::DVec2;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Where an extreme value was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extreme {
    /// Normal distance (mm), >= 0.
    pub value: f64,
    /// Angle on the part (rad).
    pub theta: f64,
    /// Axial position (mm).
    pub z: f64,
    /// Turn (1-based; 0 = before the first feature).
    pub turn: i64,
    /// Start.
    pub start: u32,
    /// Part of the profile nearest to the point.
    pub flank: Flank,
    /// Where the point's groove crossing lies in its turn: the helix parameter past the
    /// turn's first (0 at the turn's start angle, 1 at its end). Among values the report
    /// writes alike, the extreme is the one nearest the middle of its turn.
    pub turn_fraction: f64,
}

/// Values that differ by less than this (mm) may be written alike by the report (it
/// rounds to 1e-6 mm): a point below an extreme by at least this cannot replace it.
pub(crate) const TIE_MARGIN: f64 = 2e-6;

impl Extreme {
    /// The value as the report writes it, in units of its last digit (1e-6 mm).
    fn written(&self) -> f64 {
        (self.value * 1e6).round()
    }

    /// How far the point lies from the middle of its turn, in turns.
    fn off_middle(&self) -> f64 {
        (self.turn_fraction.clamp(0.0, 1.0) - 0.5).abs()
    }

    /// Whether `self` replaces `other` as an extreme: a larger value as the report writes
    /// it, or the same written value nearer the middle of its turn. A defect that runs
    /// evenly along the thread so has its place half a turn from each turn's start, not at
    /// the columns met first (the start angle), where the end of one turn and the start
    /// of the next are one spot reported twice. A total order on `(written value, off
    /// middle)`: the merged extremes do not depend on the order points are met in, but
    /// among exact equals the first wins.
    pub(crate) fn beats(&self, other: &Extreme) -> bool {
        let (a, b) = (self.written(), other.written());
        a > b || (a == b && self.off_middle() < other.off_middle())
    }

    fn keep_max(slot: &mut Option<Extreme>, e: Extreme) {
        if slot.is_none_or(|s| e.beats(&s)) {
            *slot = Some(e);
        }
    }
}

/// The helix parameter of a groove past its turn's first (see [`Extreme::turn_fraction`]).
fn turn_fraction(g: &ThreadGroove) -> f64 {
    (g.g - (g.turn - 1) as f64).clamp(0.0, 1.0)
}

/// Deviation statistics of one turn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TurnDeviation {
    /// Worst gouge per flank ([`Flank::ALL`] order).
    pub gouge: [Option<Extreme>; 4],
    /// Worst leftover per flank.
    pub leftover: [Option<Extreme>; 4],
    /// Gouge volume (mm^3).
    pub gouge_volume: f64,
    /// Leftover volume (mm^3).
    pub leftover_volume: f64,
    /// Dexels compared.
    pub compared: u64,
}

impl TurnDeviation {
    /// Worst gouge over all flanks.
    pub fn max_gouge(&self) -> Option<Extreme> {
        worst(&self.gouge)
    }

    /// Worst leftover over all flanks.
    pub fn max_leftover(&self) -> Option<Extreme> {
        worst(&self.leftover)
    }

    fn merge(&mut self, o: &TurnDeviation) {
        for f in 0..4 {
            if let Some(e) = o.gouge[f] {
                Extreme::keep_max(&mut self.gouge[f], e);
            }
            if let Some(e) = o.leftover[f] {
                Extreme::keep_max(&mut self.leftover[f], e);
            }
        }
        self.gouge_volume += o.gouge_volume;
        self.leftover_volume += o.leftover_volume;
        self.compared += o.compared;
    }
}

fn worst(v: &[Option<Extreme>; 4]) -> Option<Extreme> {
    let mut best = None;
    for e in v.iter().flatten() {
        Extreme::keep_max(&mut best, *e);
    }
    best
}

/// The least deviation over the dexels of one root or crest flat of one crossing: a root
/// that is too shallow all across (leftover) or a crest that is too low all across (gouge)
/// is reported at the root (crest) with its radial size, even where a flank is nearer to
/// every dexel (a narrow root under a shallow cut). A deviation over part of a flat only
/// (a ridge, a notch, a wall moved sideways) is the normal distance of its dexels.
struct Flat<'a> {
    /// The column's angle.
    theta: f64,
    /// The column's thread grooves.
    grooves: &'a [ThreadGroove],
    /// Equal groove width (else equal tooth width).
    equal_groove: bool,
    /// The flat the walk is on.
    open: Option<OpenFlat>,
    /// Flats found deviating all across.
    found: Vec<FoundFlat>,
}

/// A flat found deviating all across: its turn `(start, turn)`, its extreme, and the z of
/// its first and last dexel.
type FoundFlat = ((u32, i64), Extreme, (f64, f64));

/// A root or crest flat being walked.
struct OpenFlat {
    /// Its segment of the ideal polyline.
    seg: usize,
    /// A root (else a crest).
    root: bool,
    /// The compared range holds all of it.
    whole: bool,
    /// The least deviation so far (into the material for a crest).
    least: f64,
    /// z of its first and last dexel.
    z: (f64, f64),
    /// The groove region of its first dexel and of its last.
    grooves: (usize, usize),
}

impl Flat<'_> {
    #[inline]
    fn add(&mut self, seg: usize, root: bool, whole: bool, v: f64, z: f64, groove: usize) {
        match &mut self.open {
            Some(o) if o.seg == seg => {
                o.least = o.least.min(v);
                o.z.1 = z;
                o.grooves.1 = groove;
            }
            _ => {
                self.close();
                self.open = Some(OpenFlat {
                    seg,
                    root,
                    whole,
                    least: v,
                    z: (z, z),
                    grooves: (groove, groove),
                });
            }
        }
    }

    /// Close the open flat: it deviates all across when its least value is positive and
    /// the compared range holds all of it. It is placed at the middle of its dexels.
    fn close(&mut self) {
        let Some(o) = self.open.take() else {
            return;
        };
        let z = 0.5 * (o.z.0 + o.z.1);
        // A crest lies between two grooves, centred where their regions meet: it goes
        // with the turn whose measurement takes that tooth, the groove before it along
        // the helix for equal groove width, the one after it for equal tooth width (see
        // `measure`). A root lies in one groove.
        let (a, b) = o.grooves;
        let pick = match (self.grooves.get(a), self.grooves.get(b)) {
            (Some(ga), Some(gb)) if a != b => {
                if (ga.g < gb.g) == self.equal_groove {
                    a
                } else {
                    b
                }
            }
            _ => a,
        };
        let key = self.grooves.get(pick).map_or((0, 0), |g| (g.start, g.turn));
        if o.least > 0.0 && o.whole {
            self.found.push((
                key,
                Extreme {
                    value: o.least,
                    theta: self.theta,
                    z,
                    turn: key.1,
                    start: key.0,
                    flank: if o.root { Flank::Root } else { Flank::Crest },
                    turn_fraction: self.grooves.get(pick).map_or(0.5, turn_fraction),
                },
                o.z,
            ));
        }
    }
}

/// A per-turn extreme as the report's findings give it ([`Deviation::places`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    /// A gouge (else a leftover).
    pub gouge: bool,
    /// The extreme: its value, place, turn and flank.
    pub extreme: Extreme,
    /// The adjacent turn whose extreme lies on the same spot, given here once.
    pub also: Option<i64>,
}

/// Whether two extremes lie on one spot of the part: on columns at most one and a half
/// columns apart (across the 0/360 deg join too) and within two cells along the axis.
fn same_spot(a: &Extreme, b: &Extreme, grid: &Grid) -> bool {
    let d = (a.theta - b.theta).rem_euclid(std::f64::consts::TAU);
    let gap = d.min(std::f64::consts::TAU - d);
    gap <= 1.5 * grid.dtheta() + 1e-12 && (a.z - b.z).abs() <= 2.0 * grid.dz + 1e-12
}

/// The comparison of a whole stock.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Per (start, turn).
    pub turns: BTreeMap<(u32, i64), TurnDeviation>,
    /// Volume removed from the blank inside the compared region (mm^3).
    pub removed_volume: f64,
    /// Volume the ideal thread removes from the blank in the same region (mm^3).
    pub ideal_removed_volume: f64,
    /// Volume removed anywhere on the grid (mm^3).
    pub total_removed_volume: f64,
    /// Dexels compared.
    pub compared_dexels: u64,
    /// The z range of the compared dexels over all columns (mm, cell centres).
    pub compared_z: Option<(f64, f64)>,
}

impl Deviation {
    /// Worst gouge anywhere.
    pub fn max_gouge(&self) -> Option<Extreme> {
        let mut best = None;
        for t in self.turns.values() {
            if let Some(e) = t.max_gouge() {
                Extreme::keep_max(&mut best, e);
            }
        }
        best
    }

    /// Worst leftover anywhere.
    pub fn max_leftover(&self) -> Option<Extreme> {
        let mut best = None;
        for t in self.turns.values() {
            if let Some(e) = t.max_leftover() {
                Extreme::keep_max(&mut best, e);
            }
        }
        best
    }

    /// The per-turn extremes beyond `tol` that the report gives as findings, one per place:
    /// where the extremes of two adjacent turns (same start and kind) lie on one spot of
    /// the part (the end of one turn meets the start of the next at the start angle, so a
    /// defect there can be the worst of both), the spot is given once, as the larger of the
    /// two (the earlier turn's on a tie), naming the other turn (`also`). Every other
    /// extreme is given as it is. Turn order, then gouge before leftover, then flank order.
    pub fn places(&self, tol: f64, grid: &Grid) -> Vec<Place> {
        let mut all: Vec<Place> = Vec::new();
        for td in self.turns.values() {
            for (gouge, slots) in [(true, &td.gouge), (false, &td.leftover)] {
                for e in slots.iter().flatten().filter(|e| e.value > tol) {
                    all.push(Place {
                        gouge,
                        extreme: *e,
                        also: None,
                    });
                }
            }
        }
        let same = |a: &Place, b: &Place| {
            let (x, y) = (&a.extreme, &b.extreme);
            a.gouge == b.gouge
                && x.start == y.start
                && x.turn.abs_diff(y.turn) == 1
                && same_spot(x, y, grid)
        };
        // Which of two at one spot is given: the larger, the earlier turn's on a tie.
        let wins = |a: &Place, b: &Place| {
            let (x, y) = (&a.extreme, &b.extreme);
            x.value > y.value || (x.value == y.value && x.turn < y.turn)
        };
        let mut out = Vec::with_capacity(all.len());
        for (i, p) in all.iter().enumerate() {
            if all
                .iter()
                .enumerate()
                .any(|(k, q)| k != i && same(p, q) && wins(q, p))
            {
                continue;
            }
            let also = all
                .iter()
                .enumerate()
                .find(|(k, q)| *k != i && same(p, q))
                .map(|(_, q)| q.extreme.turn);
            out.push(Place { also, ..*p });
        }
        out
    }

    /// Total gouge volume.
    pub fn gouge_volume(&self) -> f64 {
        self.turns.values().map(|t| t.gouge_volume).sum()
    }

    /// Total leftover volume.
    pub fn leftover_volume(&self) -> f64 {
        self.turns.values().map(|t| t.leftover_volume).sum()
    }
}

/// Compare the thread's surface of `stock` with the ideal, inside the axial window
/// `[z_lo, z_hi]` intersected with each generator's thread span.
pub fn compare(stock: &Stock, thread: &ThreadSpec, window: (f64, f64)) -> Deviation {
    let surface = match thread.side {
        crate::model::thread::Side::External => Surface::Outer,
        crate::model::thread::Side::Internal => Surface::Inner,
    };
    let Some(q) = stock.surface(surface) else {
        return Deviation::default();
    };
    let grid = stock.grid;
    let cmp = Comparer::new(grid, stock.blank_q(surface), surface, thread, window);
    let tile = tile_columns(grid.n_theta);
    let tiles: Vec<Vec<Deviation>> = q
        .par_chunks(tile * grid.n_z.max(1))
        .enumerate()
        .map(|(t, cols)| {
            let mut prior = Prior::default();
            cols.chunks(grid.n_z.max(1))
                .enumerate()
                .map(|(k, col)| {
                    let d = cmp.column(t * tile + k, col, &prior);
                    prior.add(&d);
                    d
                })
                .collect()
        })
        .collect();
    let mut total = Deviation::default();
    for c in tiles.iter().flatten() {
        total.add_column(c);
    }
    total
}

/// The signed deviation of every cell of column `i` of `stock`'s thread surface, as the
/// report's comparison counts it (window: the grid's span, as the pipeline compares):
/// the values the report's extremes are the largest of ([`Comparer::signed`]). Empty
/// without the thread's surface.
pub fn column_deviation(stock: &Stock, thread: &ThreadSpec, i: usize) -> Vec<Option<f64>> {
    let surface = match thread.side {
        crate::model::thread::Side::External => Surface::Outer,
        crate::model::thread::Side::Internal => Surface::Inner,
    };
    let grid = stock.grid;
    let Some(q) = stock.surface(surface) else {
        return Vec::new();
    };
    let Some(col) = q.get(i * grid.n_z..(i + 1) * grid.n_z) else {
        return Vec::new();
    };
    Comparer::new(grid, stock.blank_q(surface), surface, thread, grid.window()).signed(i, col)
}

/// Columns per tile of a grid of `n_theta` columns: 64 tiles (or one column each), so
/// that the tiles do not depend on the thread count.
pub(crate) fn tile_columns(n_theta: usize) -> usize {
    n_theta.div_ceil(64).max(1)
}

/// The largest gouge and leftover per turn and flank of the columns compared before, in
/// one tile (compared in column order on one thread). A point whose radial gap is at most
/// the smallest of them over the four flanks, less [`TIE_MARGIN`], cannot beat the earlier
/// column's extreme on whichever flank it lies (its normal distance is at most its gap,
/// and only a value the report writes alike could win by its place in the turn), so its
/// normal distance is not computed: the merged extremes are exactly those of comparing
/// every point, whatever the tiles.
#[derive(Default)]
pub(crate) struct Prior {
    turns: BTreeMap<(u32, i64), ([f64; 4], [f64; 4])>,
}

impl Prior {
    /// Take in a column's extremes.
    pub(crate) fn add(&mut self, d: &Deviation) {
        for (k, t) in &d.turns {
            let e = self.turns.entry(*k).or_insert(([0.0; 4], [0.0; 4]));
            for f in 0..4 {
                if let Some(x) = t.gouge[f] {
                    e.0[f] = e.0[f].max(x.value);
                }
                if let Some(x) = t.leftover[f] {
                    e.1[f] = e.1[f].max(x.value);
                }
            }
        }
    }

    /// The largest gouge and leftover per flank of turn `key` so far (0 for none).
    fn floors(&self, key: (u32, i64)) -> ([f64; 4], [f64; 4]) {
        self.turns
            .get(&key)
            .copied()
            .unwrap_or(([0.0; 4], [0.0; 4]))
    }
}

impl Deviation {
    /// Add one column's comparison (columns are added in column order, so that the sums
    /// do not depend on how the columns were split between threads or tiles).
    pub(crate) fn add_column(&mut self, c: &Deviation) {
        for (k, t) in &c.turns {
            self.turns.entry(*k).or_default().merge(t);
        }
        self.removed_volume += c.removed_volume;
        self.ideal_removed_volume += c.ideal_removed_volume;
        self.total_removed_volume += c.total_removed_volume;
        self.compared_dexels += c.compared_dexels;
        if let Some((a, b)) = c.compared_z {
            self.compared_z = Some(
                self.compared_z
                    .map_or((a, b), |(x, y)| (x.min(a), y.max(b))),
            );
        }
    }
}

thread_local! {
    /// [`Comparer::column`]'s ideal heights, reused from column to column.
    static IDEAL_HEIGHTS: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The comparison of one grid's columns, one column at a time: [`compare`] runs it over a
/// whole stock, the streaming pipeline on each column of a tile while it is in cache.
pub(crate) struct Comparer<'a> {
    grid: Grid,
    thread: &'a ThreadSpec,
    window: (f64, f64),
    surface: Surface,
    q_blank: f64,
    /// Compute every point's distance (no pruning): the oracle of the pruning's tests.
    #[cfg(test)]
    exhaustive: bool,
}

impl<'a> Comparer<'a> {
    /// The comparison of `surface` (blank signed radius `q_blank`) on `grid`.
    pub(crate) fn new(
        grid: Grid,
        q_blank: f64,
        surface: Surface,
        thread: &'a ThreadSpec,
        window: (f64, f64),
    ) -> Comparer<'a> {
        Comparer {
            grid,
            thread,
            window,
            surface,
            q_blank,
            #[cfg(test)]
            exhaustive: false,
        }
    }

    /// Whether points that cannot beat the extremes are skipped (always, but in the
    /// pruning's tests).
    #[inline]
    fn prunes(&self) -> bool {
        #[cfg(test)]
        return !self.exhaustive;
        #[cfg(not(test))]
        true
    }

    /// Compare column `i` of the grid, its stored values `col`.
    /// `prior`: the extremes of the columns before it in its tile.
    pub(crate) fn column(&self, i: usize, col: &[f32], prior: &Prior) -> Deviation {
        self.column_with(i, col, prior, None)
    }

    /// The signed deviation of every cell of column `i` (stored values `col`) as the
    /// comparison counts it (negative: gouge; `None`: not compared): the normal distance,
    /// or on a root (crest) that deviates all across, the larger of it and the flat's
    /// radial size. The extremes the report gives are the largest of these values; the
    /// pictures draw them ([`column_deviation`]).
    pub(crate) fn signed(&self, i: usize, col: &[f32]) -> Vec<Option<f64>> {
        let mut cells = vec![None; col.len()];
        self.column_with(i, col, &Prior::default(), Some(&mut cells));
        cells
    }

    /// [`Comparer::column`], and with `cells` every cell's signed deviation (every distance
    /// computed).
    fn column_with(
        &self,
        i: usize,
        col: &[f32],
        prior: &Prior,
        mut cells: Option<&mut [Option<f64>]>,
    ) -> Deviation {
        let prunes = self.prunes() && cells.is_none();
        let (grid, thread, window, surface, q_blank) = (
            &self.grid,
            self.thread,
            self.window,
            self.surface,
            self.q_blank,
        );
        let r_blank = surface.sense() * q_blank;
        let cell = grid.dtheta() * grid.dz;
        let z_first = grid.z(0);
        let z_last = grid.z(grid.n_z.saturating_sub(1));
        let theta = grid.theta(i);
        let ideal = thread.column(theta, z_first, z_last);
        let mut out = Deviation::default();
        let sense = surface.sense();
        // The volume a cell's cut removes from the blank (summed over every cell, and over
        // the compared ones), in cell order: a sum's order is part of the report.
        let removed = |qj: f32| {
            let r = sense * (qj as f64 + q_blank);
            (r_blank * r_blank - r * r).abs() * 0.5 * cell
        };
        // The compared cells [j0, j1), if any.
        let range = ideal.span.and_then(|(a, b)| {
            let lo = a.max(window.0);
            let hi = b.min(window.1);
            if hi < lo {
                return None;
            }
            let j0 = ((lo - grid.z0) / grid.dz).ceil().max(0.0) as usize;
            let j1 = (((hi - grid.z0) / grid.dz).floor().max(-1.0) + 1.0) as usize;
            let j1 = j1.min(grid.n_z);
            (j1 > j0).then_some((lo, hi, j0, j1))
        });
        let Some((lo, hi, j0, j1)) = range else {
            out.total_removed_volume = sum_removed(out.total_removed_volume, col, &removed);
            return out;
        };
        out.total_removed_volume = sum_removed(out.total_removed_volume, &col[..j0], &removed);
        out.compared_z = Some((grid.z(j0), grid.z(j1 - 1)));
        // The ideal heights of the compared cells, in a buffer kept per thread (a fresh
        // one per column costs its pages' first touch every time).
        let mut ideal_h = IDEAL_HEIGHTS.with(|b| std::mem::take(&mut *b.borrow_mut()));
        ideal_h.clear();
        ideal_h.resize(j1 - j0, 0.0);
        ideal.fill_heights(grid.z0, grid.dz, j0, &mut ideal_h);
        let depth = thread.depth() as f32;
        let kinds: Vec<Flank> = (0..ideal.verts.len() - 1)
            .map(|i| ideal.segment_flank(i))
            .collect();
        let flats: Vec<Option<bool>> = (0..kinds.len()).map(|i| ideal.flat(i)).collect();
        let whole: Vec<bool> = (0..kinds.len())
            .map(|i| ideal.verts[i].z >= lo && ideal.verts[i + 1].z <= hi)
            .collect();
        // The groove and the segment of the ideal walked along z, each with the z where
        // it next changes (as `groove_at` and `advance` decide it).
        let grooves = &ideal.grooves;
        let groove_end = |g: usize| {
            if g + 1 < grooves.len() {
                0.5 * (grooves[g].z_hi + grooves[g + 1].z_lo)
            } else {
                f64::INFINITY
            }
        };
        let key_of = |g: usize| grooves.get(g).map_or((0, 0), |g| (g.start, g.turn));
        let fraction_of = |g: usize| grooves.get(g).map_or(0.5, turn_fraction);
        let mut groove = 0usize;
        let mut next_groove = groove_end(groove);
        let nv = ideal.verts.len();
        let seg_end = |s: usize| {
            if s + 2 < nv {
                ideal.verts[s + 1].z
            } else {
                f64::INFINITY
            }
        };
        let mut seg = ideal.advance(0, grid.z(j0));
        let mut next_seg = seg_end(seg);
        let mut key = key_of(groove);
        let mut td = TurnDeviation::default();
        let mut started = false;
        // The last ideal height's bits, its radius and removed volume; the last cut's bits
        // and removed volume (both start with the values of 0).
        let ideal_of = |hi32: f32| {
            let r_ideal = thread.radius(hi32 as f64);
            let ideal_removed = if sense * (r_blank - r_ideal) > 0.0 {
                (r_blank * r_blank - r_ideal * r_ideal).abs() * 0.5 * cell
            } else {
                0.0
            };
            (hi32.to_bits(), r_ideal, ideal_removed)
        };
        let mut last_ideal = ideal_of(0.0);
        let mut last_cut = (0f32.to_bits(), removed(0.0));
        let mut floors = ([0.0; 4], [0.0; 4]);
        let mut flat = Flat {
            theta,
            grooves,
            equal_groove: matches!(thread.width, WidthRule::Groove(_)),
            open: None,
            found: Vec::new(),
        };
        // Runs of cells with the same cut, the same ideal height, one segment and one
        // groove: their volumes are the same values summed in cell order, and the middle
        // of a run over a flat is decided at once (`runs::danger`).
        let n_cmp = ideal_h.len();
        let mut danger: Vec<(usize, usize)> = Vec::new();
        let mut k = 0;
        while k < n_cmp {
            let j = j0 + k;
            let z = grid.z(j);
            if !started || z >= next_groove {
                while z >= next_groove {
                    groove += 1;
                    next_groove = groove_end(groove);
                }
                let now = key_of(groove);
                if !started || now != key {
                    if started {
                        out.turns
                            .entry(key)
                            .or_default()
                            .merge(&std::mem::take(&mut td));
                    }
                    started = true;
                    key = now;
                    floors = prior.floors(key);
                }
            }
            while next_seg <= z {
                seg += 1;
                next_seg = seg_end(seg);
            }
            let qj = col[j];
            let hi32 = ideal_h[k];
            // The run ends before the first cell at or past the next groove or segment
            // change (as the walk above decides it), or where the cut or ideal changes.
            let (qb, hb) = (qj.to_bits(), hi32.to_bits());
            // (Most runs on a slanted flank are one cell long: known without the limit.)
            let e = if k + 1 < n_cmp && col[j + 1].to_bits() == qb && ideal_h[k + 1].to_bits() == hb
            {
                let limit = first_at_or_past(grid, j, j1, next_groove.min(next_seg)) - j0;
                k + 1 + same_run(&col[j + 1..j0 + limit], &ideal_h[k + 1..limit], qb, hb)
            } else {
                k + 1
            };
            let m = e - k;
            let r_cut = sense * (qj as f64 + q_blank);
            let h_cut = thread.height(r_cut);
            let h_ideal = hi32 as f64;
            // Runs of cells share their ideal height (flats, walls) and often their cut:
            // the same bits give the same values, computed once per run.
            if hi32.to_bits() != last_ideal.0 {
                last_ideal = ideal_of(hi32);
            }
            let (_, r_ideal, ideal_removed) = last_ideal;
            if qj.to_bits() != last_cut.0 {
                last_cut = (qj.to_bits(), removed(qj));
            }
            out.compared_dexels += m as u64;
            td.compared += m as u64;
            let v = last_cut.1;
            // Adding +0 leaves a sum of non-negative terms unchanged.
            if v != 0.0 {
                out.total_removed_volume = runs::add_repeated(out.total_removed_volume, v, m);
                out.removed_volume = runs::add_repeated(out.removed_volume, v, m);
            }
            if ideal_removed != 0.0 {
                out.ideal_removed_volume =
                    runs::add_repeated(out.ideal_removed_volume, ideal_removed, m);
            }
            let gap = h_cut - h_ideal;
            // Flats: how far the whole root (crest) of this crossing stays above (below)
            // its ideal height, measured radially (the run's first and last cells).
            match flats[seg] {
                Some(true) if hi32 == 0.0 => {
                    flat.add(seg, true, whole[seg], gap, z, groove);
                    if m > 1 {
                        flat.add(seg, true, whole[seg], gap, grid.z(j0 + e - 1), groove);
                    }
                }
                Some(false) if hi32 == depth => {
                    flat.add(seg, false, whole[seg], -gap, z, groove);
                    if m > 1 {
                        flat.add(seg, false, whole[seg], -gap, grid.z(j0 + e - 1), groove);
                    }
                }
                _ => flat.close(),
            }
            if gap == 0.0 {
                if let Some(c) = cells.as_deref_mut() {
                    c[j..j0 + e].fill(Some(0.0));
                }
                k = e;
                continue;
            }
            let vol = (r_ideal * r_ideal - r_cut * r_cut).abs() * 0.5 * cell;
            let (slots, before) = if gap < 0.0 {
                td.gouge_volume = runs::add_repeated(td.gouge_volume, vol, m);
                (&mut td.gouge, &floors.0)
            } else {
                td.leftover_volume = runs::add_repeated(td.leftover_volume, vol, m);
                (&mut td.leftover, &floors.1)
            };
            // The points of the run that may beat the extremes so far; the others are
            // proven unable to (`runs::danger`).
            let whole = [(0, m)];
            let ranges: &[(usize, usize)] = if prunes && m > 2 {
                let mut floor = [f64::NEG_INFINITY; 4];
                for f in 0..4 {
                    floor[f] = slots[f]
                        .map_or(f64::NEG_INFINITY, |e| e.value)
                        .max(before[f])
                        - TIE_MARGIN;
                }
                let run = runs::Run {
                    z_of: |i: usize| grid.z(j + i),
                    m,
                    dz: grid.dz,
                    h: h_cut,
                    ideal_h: h_ideal,
                    seg,
                };
                runs::danger(&ideal, &kinds, &run, &floor, &mut danger);
                &danger
            } else {
                &whole
            };
            for &(ra, rb) in ranges {
                for i in ra..rb {
                    let z = grid.z(j + i);
                    // The normal distance never exceeds the radial gap: skip points that
                    // cannot beat the maximum seen so far, in this column or in those before
                    // it in the tile ([`Prior`]), on any flank they can be nearest to.
                    let mut floor = [0.0; 4];
                    for f in 0..4 {
                        floor[f] = slots[f].map_or(0.0, |e| e.value).max(before[f]) - TIE_MARGIN;
                    }
                    if prunes && cannot_win(&ideal, &kinds, seg, (z, h_cut), gap.abs(), &floor) {
                        continue;
                    }
                    let (d, flank) = ideal.distance_near(seg, z, h_cut, gap.abs());
                    if let Some(c) = cells.as_deref_mut() {
                        c[j + i] = Some(gap.signum() * d);
                    }
                    Extreme::keep_max(
                        &mut slots[flank.index()],
                        Extreme {
                            value: d,
                            theta,
                            z,
                            turn: key.1,
                            start: key.0,
                            flank,
                            turn_fraction: fraction_of(groove),
                        },
                    );
                }
            }
            k = e;
        }
        out.total_removed_volume = sum_removed(out.total_removed_volume, &col[j1..], &removed);
        if started {
            out.turns.entry(key).or_default().merge(&td);
        }
        IDEAL_HEIGHTS.with(|b| *b.borrow_mut() = ideal_h);
        flat.close();
        for (k0, e, (za, zb)) in flat.found {
            if let Some(c) = cells.as_deref_mut() {
                // Every dexel of the flat deviates by at least its least radial gap.
                let v = if e.flank == Flank::Root {
                    e.value
                } else {
                    -e.value
                };
                let ja = ((za - grid.z0) / grid.dz).round().max(0.0) as usize;
                let jb = (((zb - grid.z0) / grid.dz).round().max(0.0) as usize).min(c.len() - 1);
                for x in c[ja..=jb].iter_mut().flatten() {
                    if x.abs() < v.abs() {
                        *x = v;
                    }
                }
            }
            let td = out.turns.entry(k0).or_default();
            let slots = if e.flank == Flank::Root {
                &mut td.leftover
            } else {
                &mut td.gouge
            };
            Extreme::keep_max(&mut slots[e.flank.index()], e);
        }
        out
    }
}

/// `sum` plus the volume `removed` of each cell of `col`, in cell order (runs of equal
/// cells at once, [`runs::add_repeated`]; uncut cells add +0 and are skipped).
fn sum_removed(mut sum: f64, col: &[f32], removed: &impl Fn(f32) -> f64) -> f64 {
    let mut k = 0;
    while k < col.len() {
        let b = col[k].to_bits();
        let m = 1 + col[k + 1..]
            .iter()
            .position(|c| c.to_bits() != b)
            .unwrap_or(col.len() - k - 1);
        let v = removed(col[k]);
        if v != 0.0 {
            sum = runs::add_repeated(sum, v, m);
        }
        k += m;
    }
    sum
}

/// How many leading cells of `cut` and `ideal` (as long as each other) hold the bits
/// `qb` and `hb`: sixteen cells compared at a time (vectorized), then one by one.
fn same_run(cut: &[f32], ideal: &[f32], qb: u32, hb: u32) -> usize {
    let n = cut.len().min(ideal.len());
    let mut i = 0;
    while i + 16 <= n {
        let mut differ = false;
        for t in 0..16 {
            differ |= (cut[i + t].to_bits() != qb) | (ideal[i + t].to_bits() != hb);
        }
        if differ {
            break;
        }
        i += 16;
    }
    while i < n && cut[i].to_bits() == qb && ideal[i].to_bits() == hb {
        i += 1;
    }
    i
}

/// The first cell index in `(j, end]` whose z is at or past `limit` (`end` if none), as a
/// cell-by-cell walk comparing `grid.z` with `limit` finds it (`grid.z` increases with
/// the index).
fn first_at_or_past(grid: &Grid, j: usize, end: usize, limit: f64) -> usize {
    let lo = j + 1;
    // Past the last cell (an infinite limit among them): none.
    if lo >= end || grid.z(end - 1) < limit {
        return end.max(lo);
    }
    // An estimate (truncated: no libm call), corrected by the walks below.
    let est = (limit - grid.z0) / grid.dz;
    let mut e = if est >= lo as f64 {
        (est as usize).clamp(lo, end)
    } else {
        lo
    };
    while e > lo && grid.z(e - 1) >= limit {
        e -= 1;
    }
    while e < end && grid.z(e) < limit {
        e += 1;
    }
    e
}

/// Whether a point at `z` in segment `seg` with radial gap `g` to the ideal cannot beat the
/// maxima `floor` (per flank) on whichever flank it is nearest to: its normal distance is
/// at most `g`, so the flank is that of a segment within `g` of it along the axis (or the
/// crest, the distance's fallback), and it cannot win where `g` is at most that flank's
/// maximum (an earlier point wins a tie).
fn cannot_win(
    ideal: &crate::model::thread::ColumnIdeal,
    kinds: &[Flank],
    seg: usize,
    (z, h): (f64, f64),
    g: f64,
    floor: &[f64; 4],
) -> bool {
    if floor.iter().all(|&v| g <= v) {
        return true;
    }
    let v = &ideal.verts;
    let n = kinds.len();
    // The distance falls back to the crest only when no segment lies within `g`: the
    // one it starts from (the distance's first segment) settles that.
    let first = seg.min(n - 1);
    if g > floor[Flank::Crest.index()]
        && crate::model::geom::segment_distance2(
            DVec2::new(z, h),
            v[first].vec(),
            v[first + 1].vec(),
        ) > g * g
    {
        return false;
    }
    // A margin over `g`: candidates are a superset of the segments the distance can pick.
    let reach = g * (1.0 + 1e-9) + 1e-12;
    let mut i = first;
    while i < n {
        if v[i].z - z > reach {
            break;
        }
        if g > floor[kinds[i].index()] {
            return false;
        }
        i += 1;
    }
    let mut i = first;
    while i > 0 {
        i -= 1;
        if z - v[i + 1].z > reach {
            break;
        }
        if g > floor[kinds[i].index()] {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Lcg;
    use crate::model::thread::Side;

    /// Seed 002's square (or trapezoid) equal-tooth screw.
    fn screw(side: Side, angles: f64) -> ThreadSpec {
        crate::model::thread::seed002_screw(side, angles)
    }

    /// Cuts a column: `(column index, its ideal, the thread, its stored values)`.
    type Cutter<'a> =
        dyn FnMut(usize, &crate::model::thread::ColumnIdeal, &ThreadSpec, &mut [f32]) + 'a;

    /// Compare `n_theta` columns cut by `cut(column index, ideal, column)` both pruned (as a
    /// tile runs, against the extremes of the columns before it) and with every distance
    /// computed, merged in column order, on square and trapezoid, external and internal
    /// threads; the two must be equal, extremes (values, places, flanks), volumes and flats.
    fn check_pruning(n_theta: usize, dz: f64, cut: &mut Cutter<'_>) {
        for (side, angles) in [
            (Side::External, 0.0),
            (Side::External, 15.0),
            (Side::Internal, 0.0),
            (Side::Internal, 30.0),
        ] {
            let thread = screw(side, angles);
            let n_z = (96.0 / dz).round() as usize;
            let grid = Grid {
                n_theta,
                n_z,
                theta0: 0.0,
                z0: -92.0 + 0.5 * dz,
                dz,
            };
            let surface = match side {
                Side::External => Surface::Outer,
                Side::Internal => Surface::Inner,
            };
            let q_blank = match side {
                Side::External => 14.0,
                Side::Internal => -11.0,
            };
            let window = (-92.0, 4.0);
            let mut cmp = Comparer::new(grid, q_blank, surface, &thread, window);
            let (mut prior, mut pruned, mut every) =
                (Prior::default(), Deviation::default(), Deviation::default());
            for i in 0..grid.n_theta {
                let ideal = thread.column(grid.theta(i), grid.z(0), grid.z(grid.n_z - 1));
                let mut col = vec![0f32; grid.n_z];
                cut(i, &ideal, &thread, &mut col);
                for c in col.iter_mut() {
                    // Stored values are signed radii from the blank, never beyond it.
                    *c = c.min(0.0);
                }
                cmp.exhaustive = false;
                let d = cmp.column(i, &col, &prior);
                prior.add(&d);
                pruned.add_column(&d);
                cmp.exhaustive = true;
                every.add_column(&cmp.column(i, &col, &Prior::default()));
            }
            assert_eq!(pruned, every, "{side:?} {angles}");
            assert!(every.max_gouge().is_some() && every.max_leftover().is_some());
            assert!(every.turns.len() >= 7, "{}", every.turns.len());
        }
    }

    /// The stored value of height `h` above the root, for the fixture's blank.
    fn stored(thread: &ThreadSpec, h: f64) -> f32 {
        let (sense, q_blank) = match thread.side {
            Side::External => (1.0, 14.0),
            Side::Internal => (-1.0, -11.0),
        };
        (sense * thread.radius(h) - q_blank) as f32
    }

    /// Level cuts, the runs the comparison decides a whole run at a time
    /// (`runs::danger`): runs of random length at one height, either a random one or
    /// exactly a root, a crest, half the depth or the blank (an uncut groove: level with the
    /// crest corners, where the vertex rule decides), with some columns repeating the one
    /// before so that extremes tie across columns and the first must keep them; and at
    /// 0.01 and 0.013 mm spacings (cells on and off the walls).
    #[test]
    fn run_decisions_change_nothing() {
        for (seed, dz) in [(31u64, 0.02), (32, 0.013), (33, 0.01)] {
            let mut rng = Lcg(seed);
            let mut last: Vec<f32> = Vec::new();
            let mut cut = |_: usize,
                           _: &crate::model::thread::ColumnIdeal,
                           thread: &ThreadSpec,
                           col: &mut [f32]| {
                if !last.is_empty() && rng.next() < 0.4 {
                    col.copy_from_slice(&last);
                    return;
                }
                let depth = thread.depth();
                let mut j = 0;
                while j < col.len() {
                    let len = 1 + (rng.next() * 1500.0) as usize;
                    let pick = rng.next();
                    let h = if pick < 0.2 {
                        0.0
                    } else if pick < 0.4 {
                        depth
                    } else if pick < 0.5 {
                        0.5 * depth
                    } else if pick < 0.6 {
                        f64::NAN
                    } else {
                        (rng.next() * 1.4 - 0.2) * depth
                    };
                    for c in col.iter_mut().skip(j).take(len) {
                        *c = if h.is_nan() { 0.0 } else { stored(thread, h) };
                    }
                    j += len;
                }
                last = col.to_vec();
            };
            check_pruning(16, dz, &mut cut);
        }
    }

    /// The pruned comparison (points that cannot beat the extremes by their radial gap, in
    /// this column or in those before it in the tile, are skipped) gives exactly the extremes,
    /// volumes and flats of computing every point's distance, on cuts of every kind: runs
    /// of random length at random offsets from the ideal (gouges and leftovers, deep and
    /// shallow, walls moved), on square and trapezoid, external and internal threads.
    #[test]
    fn pruning_changes_nothing() {
        let mut rng = Lcg(20);
        let mut cut = |_: usize,
                       ideal: &crate::model::thread::ColumnIdeal,
                       thread: &ThreadSpec,
                       col: &mut [f32]| {
            // Runs of cells: the ideal shifted along z by up to 1 mm and offset in height
            // by up to 2 mm (clamped to the blank and one depth below the root), or left
            // uncut.
            let mut j = 0;
            while j < col.len() {
                let len = 1 + (rng.next() * 400.0) as usize;
                let (shift, off) = ((rng.next() - 0.5) * 2.0, (rng.next() - 0.5) * 4.0);
                let uncut = rng.next() < 0.1;
                for c in col.iter_mut().skip(j).take(len) {
                    if !uncut {
                        let z = -92.0 + 0.01 + 0.02 * j as f64 + shift;
                        *c = stored(thread, (ideal.height_at(z) + off).clamp(-3.0, 3.0));
                    }
                    j += 1;
                }
            }
        };
        check_pruning(24, 0.02, &mut cut);
    }
}
