//! The per-column pipeline: each angular column is cut (the passes' sweep, with the edges
//! alone beside it where tool bodies are swept, or the mill's path), compared with the
//! ideal thread and checked for body interference while it is in cache; tiles of columns
//! run in order on one thread, and their results are merged in column order, so the
//! figures do not depend on the thread count. The columns live in the whole grid (kept for
//! the outputs that need it) or in a zeroed buffer of one column per thread (streamed).

use crate::analysis::compare::{self, Deviation};
use crate::analysis::interference::{self, Interference};
use crate::kernel::mill::{GridMill, MillColumn, MillStats};
use crate::kernel::sweep::{GridSweep, SweepStats};
use crate::model::stock::{Grid, Stock, Surface};
use std::time::Instant;

use super::grid::column_buffer;
use super::SimError;

/// What cuts the columns.
pub(super) enum Cutting<'a> {
    /// A lathe's passes; with swept tool bodies, also the edges alone (their difference is
    /// what the bodies cut past their edges).
    Turning {
        sweep: GridSweep<'a>,
        edges: Option<GridSweep<'a>>,
    },
    /// A thread mill's path.
    Milling(GridMill<'a>),
}

/// One column's results: what the cut did, the comparison, the body interference, and the
/// seconds spent cutting and comparing (to split the fused pipeline's wall time).
struct ColumnOut {
    stats: SweepStats,
    mill: Option<MillColumn>,
    dev: Deviation,
    hits: Option<Interference>,
    seconds: (f64, f64),
}

/// What cutting a column gave: the sweep's counts, a milling column's figures, seconds.
struct Cut {
    stats: SweepStats,
    mill: Option<MillColumn>,
    seconds: f64,
}

/// The columns' results merged in column order.
#[derive(Default)]
pub(super) struct Merged {
    /// Placements and dexel updates.
    pub(super) stats: SweepStats,
    /// The deviation from the ideal thread.
    pub(super) dev: Deviation,
    /// What the bodies cut past their edges.
    pub(super) hits: Interference,
    /// A milling run's per-move figures.
    pub(super) mill: Option<MillStats>,
    /// CPU seconds cutting and comparing.
    pub(super) seconds: (f64, f64),
}

/// The raw columns of one interval as a streamed run holds them for a [`Sink`]: the
/// thread's surface at the unwrapped columns `first..=last` (`last` may be `n_theta`:
/// column 0 again), relative to the blank, and with swept tool bodies the edges' cut
/// beside them.
pub(crate) struct Held<'a> {
    /// The first (unwrapped) column.
    pub(crate) first: usize,
    n_z: usize,
    cols: &'a [f32],
    edges: Option<&'a [f32]>,
}

impl<'a> Held<'a> {
    /// The last (unwrapped) column held.
    pub(crate) fn last(&self) -> usize {
        self.first + self.cols.len() / self.n_z.max(1) - 1
    }

    /// The dexels of unwrapped column `u` (`first <= u <= last`).
    pub(crate) fn column(&self, u: usize) -> &'a [f32] {
        let k = u - self.first;
        &self.cols[k * self.n_z..(k + 1) * self.n_z]
    }

    /// The edges' cut of unwrapped column `u`, with swept tool bodies.
    pub(crate) fn edge(&self, u: usize) -> Option<&'a [f32]> {
        let k = u - self.first;
        self.edges.map(|e| &e[k * self.n_z..(k + 1) * self.n_z])
    }
}

/// What a streamed run hands its raw columns to, an interval at a time, besides comparing
/// them (the model's mesh: `output::mesh`). The intervals depend only on the grid, so the
/// parts, returned in interval order, do not depend on the thread count.
pub(crate) trait Sink: Sync {
    /// What one interval gives.
    type Part: Send;
    /// What one interval leaves for the next one on the same thread (fresh for each run
    /// of consecutive intervals).
    type Carry: Default;

    /// The first column of every interval: 0 first, increasing, each below `n_theta`.
    /// Interval `k` holds the columns from `bounds[k]` to `bounds[k + 1]` inclusive (the
    /// last interval to `n_theta`: column 0 again).
    fn bounds(&self) -> &[usize];

    /// Interval `k`'s part, from its raw columns; `carry` is what the interval before it
    /// left when it ran just before on this thread (else the default).
    fn interval(&self, k: usize, held: &Held<'_>, carry: &mut Self::Carry) -> Self::Part;

    /// After the run, from its exact deviation: a column to cut once more and return
    /// (the model's focus reads a dexel of it).
    fn probe(&self, dev: &Deviation) -> Option<usize>;
}

/// A run without a sink.
pub(crate) enum NoSink {}

impl Sink for NoSink {
    type Part = ();
    type Carry = ();
    fn bounds(&self) -> &[usize] {
        match *self {}
    }
    fn interval(&self, _: usize, _: &Held<'_>, _: &mut ()) {
        match *self {}
    }
    fn probe(&self, _: &Deviation) -> Option<usize> {
        match *self {}
    }
}

/// Tiles per thread in a wave (see [`Pipeline::run`]).
const WAVE_TILES: usize = 4;

/// The columns whose results a wave holds at once, on `threads` threads, each unit of the
/// wave running up to `extra` columns past its tile (0; a sink's units end with an
/// interval: [`Pipeline::run_intervals`]).
pub(super) fn wave_columns(grid: &Grid, threads: usize, extra: usize) -> usize {
    let tile = compare::tile_columns(grid.n_theta);
    (WAVE_TILES * threads.max(1) * (tile + extra)).min(grid.n_theta)
}

/// The heap memory of a B-tree map of `entries` entries of `entry` bytes, built in key
/// order (bytes): leaves of 11 slots, at least 5 of them full (a split in key order leaves
/// the left node with 5), an internal node per 6 leaves or fewer, each with 12 edges.
pub(super) fn btree_bytes(entries: u64, entry: usize) -> u64 {
    if entries == 0 {
        return 0;
    }
    let node = 11 * entry as u64 + 16;
    let leaves = entries / 5 + 1;
    let internal = leaves / 5 + 1;
    leaves * node + internal * (node + 12 * 8)
}

/// The most heap memory one column's results hold (bytes): the comparison's extremes per
/// turn (`keys` turns), the body interference's (`bodies`: its turns, the grooves' and the
/// run-in's and run-out's features), a milling column's figures per move that changed it
/// (`mill_moves`: at most every move, doubled for the vector's growth).
pub(super) fn column_out_bytes(keys: u64, bodies: Option<u64>, mill_moves: Option<usize>) -> u64 {
    use std::mem::size_of;
    let dev = btree_bytes(keys, size_of::<((u32, i64), compare::TurnDeviation)>());
    let hits = bodies.map_or(0, |k| {
        btree_bytes(k, size_of::<((u32, i64), [Option<interference::Hit>; 4])>())
    });
    let mill = mill_moves.map_or(0, |m| {
        2 * m as u64 * size_of::<(usize, crate::kernel::mill::MoveCut)>() as u64
    });
    size_of::<ColumnOut>() as u64 + dev + hits + mill
}

/// Merge columns' results, in column order, into `m`.
fn merge(m: &mut Merged, columns: impl IntoIterator<Item = ColumnOut>) {
    for c in columns {
        m.stats = m.stats + c.stats;
        m.dev.add_column(&c.dev);
        if let Some(h) = &c.hits {
            interference::add_column(&mut m.hits, h);
        }
        if let (Some(total), Some(c)) = (m.mill.as_mut(), &c.mill) {
            total.add_column(c);
        }
        m.seconds.0 += c.seconds.0;
        m.seconds.1 += c.seconds.1;
    }
}

/// The per-column pipeline: cut, compare, body interference.
pub(super) struct Pipeline<'a> {
    pub(super) cut: Cutting<'a>,
    pub(super) cmp: compare::Comparer<'a>,
    pub(super) bodies: interference::Measurer<'a>,
    pub(super) grid: Grid,
    /// The program's turning moves as a per-cell bound on `q - q_blank` (the same for every
    /// column: the cut is axisymmetric), or `None` without turning moves.
    pub(super) turned: Option<&'a [f32]>,
}

/// Clamp a column to the turned profile. Removal is a minimum, so it commutes with the
/// sweep: the result does not depend on when the turning moves ran.
fn clamp_turned(col: &mut [f32], turned: &[f32]) {
    for (q, t) in col.iter_mut().zip(turned) {
        *q = q.min(*t);
    }
}

impl Pipeline<'_> {
    /// Whether the edges alone cut a second column beside each.
    fn twice(&self) -> bool {
        matches!(&self.cut, Cutting::Turning { edges: Some(_), .. })
    }

    /// Column `i`, held in `col` (and `edge`, the edges' cut): both are cut in place,
    /// then compared.
    fn column(
        &self,
        i: usize,
        col: &mut [f32],
        edge: Option<&mut [f32]>,
        prior: &mut compare::Prior,
    ) -> ColumnOut {
        let mut edge = edge;
        let cut = self.cut(i, col, edge.as_deref_mut());
        self.compare(i, col, edge.as_deref(), cut, prior)
    }

    /// Cut column `i` in place in `col` (and `edge`, the edges' cut, beside it), clamped
    /// to the turned profile.
    fn cut(&self, i: usize, col: &mut [f32], edge: Option<&mut [f32]>) -> Cut {
        let t0 = Instant::now();
        let (stats, mill, edge) = match &self.cut {
            Cutting::Turning { sweep, edges } => {
                let stats = sweep.column(i, col);
                let edge = match (edge, edges) {
                    (Some(e), Some(s)) => {
                        s.column(i, e);
                        Some(e)
                    }
                    _ => None,
                };
                (stats, None, edge)
            }
            Cutting::Milling(m) => {
                let c = m.column(i, col);
                let stats = SweepStats {
                    placements: c.placements,
                    dexel_updates: c.updates,
                };
                (stats, Some(c), None)
            }
        };
        if let Some(t) = self.turned {
            clamp_turned(col, t);
            if let Some(e) = edge {
                clamp_turned(e, t);
            }
        }
        Cut {
            stats,
            mill,
            seconds: t0.elapsed().as_secs_f64(),
        }
    }

    /// Compare cut column `i` (and measure its body interference from `edge`).
    fn compare(
        &self,
        i: usize,
        col: &[f32],
        edge: Option<&[f32]>,
        cut: Cut,
        prior: &mut compare::Prior,
    ) -> ColumnOut {
        let t1 = Instant::now();
        let dev = self.cmp.column(i, col, prior);
        prior.add(&dev);
        let hits = edge.map(|e| self.bodies.column(i, e, col));
        ColumnOut {
            stats: cut.stats,
            mill: cut.mill,
            dev,
            hits,
            seconds: (cut.seconds, t1.elapsed().as_secs_f64()),
        }
    }

    /// Column `i` cut alone (no comparison) in a zeroed buffer, or `None` when its memory
    /// cannot be had.
    pub(super) fn cut_alone(&self, i: usize) -> Option<Vec<f32>> {
        let mut col = column_buffer(self.grid.n_z)?;
        self.cut(i, &mut col, None);
        Some(col)
    }

    /// The columns from `first` on, held contiguously in `cols` (and `edges`).
    fn tile(&self, first: usize, cols: &mut [f32], edges: Option<&mut [f32]>) -> Vec<ColumnOut> {
        let n_z = self.grid.n_z;
        let mut edges = edges;
        let mut prior = compare::Prior::default();
        cols.chunks_mut(n_z)
            .enumerate()
            .map(|(k, col)| {
                let e = edges.as_deref_mut().map(|e| &mut e[k * n_z..(k + 1) * n_z]);
                self.column(first + k, col, e, &mut prior)
            })
            .collect()
    }

    /// Run every column of `surface`: in `stock` (and `edge_stock`) when the whole grid is
    /// kept, else streamed through column buffers; merged in column order.
    pub(super) fn run(
        &self,
        surface: Surface,
        stock: Option<&mut Stock>,
        edge_stock: Option<&mut Stock>,
        mill: Option<MillStats>,
    ) -> Result<Merged, SimError> {
        use rayon::prelude::*;
        let (grid, n_z) = (self.grid, self.grid.n_z);
        let tile = compare::tile_columns(grid.n_theta);
        let twice = self.twice();
        let mut m = Merged {
            mill,
            ..Merged::default()
        };
        if n_z == 0 {
            return Ok(m);
        }
        // Tiles run in waves of a few per thread, each wave merged in column order before
        // the next starts: the columns' results held at once (a milling column's per-move
        // figures among them) do not grow with the number of columns.
        let wave = WAVE_TILES * rayon::current_num_threads().max(1);
        let n_tiles = grid.n_theta.div_ceil(tile);
        if let Some(stock) = stock {
            let Some(q) = stock.surface_mut(surface) else {
                return Ok(Merged::default());
            };
            let mut edges = edge_stock.and_then(|e| e.surface_mut(surface));
            let span = wave * tile * n_z;
            for (w, q) in q.chunks_mut(span).enumerate() {
                let first = w * wave * tile;
                let here = w * span..w * span + q.len();
                let tiles: Vec<Vec<ColumnOut>> = match edges.as_deref_mut() {
                    Some(qe) => q
                        .par_chunks_mut(tile * n_z)
                        .zip(qe[here].par_chunks_mut(tile * n_z))
                        .enumerate()
                        .map(|(t, (c, e))| self.tile(first + t * tile, c, Some(e)))
                        .collect(),
                    None => q
                        .par_chunks_mut(tile * n_z)
                        .enumerate()
                        .map(|(t, c)| self.tile(first + t * tile, c, None))
                        .collect(),
                };
                merge(&mut m, tiles.into_iter().flatten());
            }
        } else {
            for w0 in (0..n_tiles).step_by(wave) {
                let tiles: Vec<Option<Vec<ColumnOut>>> = (w0..(w0 + wave).min(n_tiles))
                    .into_par_iter()
                    .map_init(
                        || {
                            let main = column_buffer(n_z)?;
                            let edge = if twice {
                                Some(column_buffer(n_z)?)
                            } else {
                                None
                            };
                            Some((main, edge))
                        },
                        |bufs, t| {
                            let (main, edge) = bufs.as_mut()?;
                            let cols = t * tile..((t + 1) * tile).min(grid.n_theta);
                            let mut prior = compare::Prior::default();
                            Some(
                                cols.map(|i| {
                                    main.fill(0.0);
                                    if let Some(e) = edge.as_mut() {
                                        e.fill(0.0);
                                    }
                                    self.column(i, main, edge.as_deref_mut(), &mut prior)
                                })
                                .collect(),
                            )
                        },
                    )
                    .collect();
                for t in tiles {
                    let t = t.ok_or(SimError::OutOfMemory {
                        bytes: n_z as u128 * 4 * if twice { 2 } else { 1 },
                        angular: grid.n_theta,
                        axial: grid.n_z,
                    })?;
                    merge(&mut m, t);
                }
            }
        }
        Ok(m)
    }

    /// Run every column of `surface` streamed, an interval of `sink`'s at a time: each
    /// thread takes units of consecutive intervals (at least a tile of columns, so the
    /// units depend only on the grid) into a buffer of the widest interval's columns, cuts
    /// and compares each column once in column order, and hands each interval's columns
    /// to the sink; the interval's last column stays in the buffer as the next one's first
    /// (a unit's very last column is cut twice: once more, uncompared, for its sink).
    /// Results merged in column order, the parts returned in interval order.
    pub(super) fn run_intervals<S: Sink>(
        &self,
        sink: &S,
        mill: Option<MillStats>,
    ) -> Result<(Merged, Vec<S::Part>), SimError> {
        use rayon::prelude::*;
        let (n, n_z) = (self.grid.n_theta, self.grid.n_z);
        let twice = self.twice();
        let mut m = Merged {
            mill,
            ..Merged::default()
        };
        let units = units(sink.bounds(), n);
        let width = widest(sink.bounds(), n) + 1;
        let wave = WAVE_TILES * rayon::current_num_threads().max(1);
        let mut parts = Vec::with_capacity(sink.bounds().len());
        for w in units.chunks(wave) {
            let done: Vec<Option<UnitOut<S>>> = w
                .par_iter()
                .map_init(
                    || {
                        let main = column_buffer(width * n_z)?;
                        let edge = if twice {
                            Some(column_buffer(width * n_z)?)
                        } else {
                            None
                        };
                        Some((main, edge))
                    },
                    |bufs, unit| {
                        let (main, edge) = bufs.as_mut()?;
                        Some(self.unit(sink, unit.clone(), main, edge.as_deref_mut()))
                    },
                )
                .collect();
            for d in done {
                let (cols, ps) = d.ok_or(SimError::OutOfMemory {
                    bytes: (width * n_z) as u128 * 4 * if twice { 2 } else { 1 },
                    angular: n,
                    axial: n_z,
                })?;
                merge(&mut m, cols);
                parts.extend(ps);
            }
        }
        Ok((m, parts))
    }

    /// The intervals `ks` of `sink`, in order on one thread, in `main` (and `edge`).
    fn unit<S: Sink>(
        &self,
        sink: &S,
        ks: std::ops::Range<usize>,
        main: &mut [f32],
        mut edge: Option<&mut [f32]>,
    ) -> UnitOut<S> {
        let (n, n_z) = (self.grid.n_theta, self.grid.n_z);
        let bounds = sink.bounds();
        let mut prior = compare::Prior::default();
        let mut carry = S::Carry::default();
        let mut outs = Vec::new();
        let mut parts = Vec::with_capacity(ks.len());
        for k in ks.clone() {
            let (a, b) = (bounds[k], end(bounds, k, n));
            // The first interval of the unit cuts its first column; the others have it.
            let from = if k == ks.start { a } else { a + 1 };
            for u in from..=b {
                let s = (u - a) * n_z..(u - a + 1) * n_z;
                let col = &mut main[s.clone()];
                col.fill(0.0);
                let mut e = edge.as_deref_mut().map(|e| &mut e[s]);
                if let Some(e) = e.as_deref_mut() {
                    e.fill(0.0);
                }
                let cut = self.cut(u % n, col, e.as_deref_mut());
                // Every column is compared once, in the unit that starts at or before it:
                // the unit's last column is the next unit's first.
                if u < b || k + 1 < ks.end {
                    outs.push(self.compare(u % n, col, e.as_deref(), cut, &mut prior));
                }
            }
            let held = (b - a + 1) * n_z;
            parts.push(sink.interval(
                k,
                &Held {
                    first: a,
                    n_z,
                    cols: &main[..held],
                    edges: edge.as_deref().map(|e| &e[..held]),
                },
                &mut carry,
            ));
            let last = (b - a) * n_z..held;
            main.copy_within(last.clone(), 0);
            if let Some(e) = edge.as_deref_mut() {
                e.copy_within(last, 0);
            }
        }
        (outs, parts)
    }
}

/// A unit's results: its columns' (in column order) and its intervals' parts.
type UnitOut<S> = (Vec<ColumnOut>, Vec<<S as Sink>::Part>);

/// The end of interval `k` (the next one's first column, or `n` for the last).
fn end(bounds: &[usize], k: usize, n: usize) -> usize {
    bounds.get(k + 1).copied().unwrap_or(n)
}

/// The most columns an interval spans past its first.
pub(crate) fn widest(bounds: &[usize], n: usize) -> usize {
    (0..bounds.len())
        .map(|k| end(bounds, k, n) - bounds[k])
        .max()
        .unwrap_or(0)
}

/// Consecutive intervals grouped into units of at least a tile of columns (the last may
/// be shorter): they depend only on the intervals and the grid.
fn units(bounds: &[usize], n: usize) -> Vec<std::ops::Range<usize>> {
    let tile = compare::tile_columns(n);
    let mut out = Vec::new();
    let mut k0 = 0;
    for k in 0..bounds.len() {
        if end(bounds, k, n) - bounds[k0] >= tile || k + 1 == bounds.len() {
            out.push(k0..k + 1);
            k0 = k + 1;
        }
    }
    out
}
