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

/// Tiles per thread in a wave (see [`Pipeline::run`]).
const WAVE_TILES: usize = 4;

/// The columns whose results a wave holds at once, on `threads` threads.
pub(super) fn wave_columns(grid: &Grid, threads: usize) -> usize {
    let tile = compare::tile_columns(grid.n_theta);
    (WAVE_TILES * threads.max(1) * tile).min(grid.n_theta)
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

    /// Column `i`, held in `col` (and `edge`, the edges' cut): both are cut in place.
    fn column(
        &self,
        i: usize,
        col: &mut [f32],
        edge: Option<&mut [f32]>,
        prior: &mut compare::Prior,
    ) -> ColumnOut {
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
        let mut edge = edge;
        if let Some(t) = self.turned {
            clamp_turned(col, t);
            if let Some(e) = edge.as_deref_mut() {
                clamp_turned(e, t);
            }
        }
        let t1 = Instant::now();
        let dev = self.cmp.column(i, col, prior);
        prior.add(&dev);
        let hits = edge.map(|e| self.bodies.column(i, e, col));
        let t2 = Instant::now();
        ColumnOut {
            stats,
            mill,
            dev,
            hits,
            seconds: ((t1 - t0).as_secs_f64(), (t2 - t1).as_secs_f64()),
        }
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
}
