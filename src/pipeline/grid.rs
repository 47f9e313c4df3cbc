//! The grid a run uses and what it holds: cells that cover the blank (or the job's
//! window) exactly, the stock's memory, the column buffers of a streamed run, and the
//! windows the comparison and the measurement generators look at.

use crate::job::Job;
use crate::model::stock::{Grid, Stock, Surface};
use crate::model::thread::{Side, ThreadSpec};

use super::{readable, SimError};

/// The grid a job will use, and the number of dexels it stores.
pub fn plan_grid(job: &Job) -> Result<(Grid, u64), SimError> {
    let b = &job.blank;
    let (mut lo, mut hi) = (b.z_front - b.length, b.z_front);
    if let Some((a, c)) = job.sim.z_range {
        lo = lo.max(a);
        hi = hi.min(c);
    }
    // The cells cover the window exactly: a length that is a whole number of cells (up to
    // rounding: 40 / 0.02 = 1999.9999999999998) keeps `axial_spacing`; any other length
    // gets one more cell and the spacing shrinks to fit (80.5 mm at 0.04: 2013 cells of
    // 0.039990 mm), so no part of the blank is left out at a face.
    let asked = job.sim.axial_spacing;
    let cells = if hi > lo { (hi - lo) / asked } else { 0.0 };
    let (n_z, dz) = if (cells - cells.round()).abs() <= 1e-9 * cells.max(1.0) {
        (cells.round(), asked)
    } else {
        let n = cells.ceil();
        (n, (hi - lo) / n)
    };
    if n_z.is_nan() || n_z < 1.0 {
        return Err(SimError::EmptyWindow { lo, hi });
    }
    let surfaces: u32 = if b.bore > 0.0 { 2 } else { 1 };
    let requested =
        (job.sim.angular_cells as f64 * n_z * surfaces as f64).min(u64::MAX as f64) as u64;
    let grid = Grid {
        n_theta: job.sim.angular_cells,
        n_z: n_z.min(usize::MAX as f64) as usize,
        theta0: job.thread.helix.theta0,
        z0: lo + 0.5 * dz,
        dz,
    };
    Ok((grid, requested))
}

/// The job's blank on `grid`, or the error that its memory cannot be had.
pub(super) fn blank_stock(job: &Job, grid: Grid) -> Result<Stock, SimError> {
    Stock::try_blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0).ok_or_else(|| {
        let surfaces: u128 = if job.blank.bore > 0.0 { 2 } else { 1 };
        SimError::OutOfMemory {
            bytes: grid.n_theta as u128 * grid.n_z as u128 * surfaces * 4,
            angular: grid.n_theta,
            axial: grid.n_z,
        }
    })
}

/// A zeroed column buffer, or `None` when the memory cannot be had.
pub(super) fn column_buffer(n: usize) -> Option<Vec<f32>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).ok()?;
    v.resize(n, 0.0);
    Some(v)
}

/// The stock surface a thread is cut on.
pub(super) fn thread_surface(thread: &ThreadSpec) -> Surface {
    match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    }
}

/// The axial span of the grid's cells (the comparison's window).
pub(super) fn grid_window(grid: &Grid) -> (f64, f64) {
    grid.window()
}

/// Where the measurement columns run (the thread and two leads and its depth beyond, inside
/// the window) and their spacing, kept under 8M cells a column.
pub(super) fn measure_window(job: &Job, window: (f64, f64)) -> ((f64, f64), f64) {
    let thread = &job.thread;
    let law = thread.helix.law;
    let reach = 2.0 * law.lead(0.0).max(law.lead(thread.turns)) + thread.depth();
    let (z_a, z_b) = (thread.helix.z(thread.turns), thread.helix.z0);
    let lo = window.0.max(z_a.min(z_b) - reach);
    let hi = window.1.min(z_a.max(z_b) + reach);
    ((lo, hi), job.sim.measure_spacing.max((hi - lo) / 8.0e6))
}

/// Dexels a run sweeps and compares at most (a 1 m screw at 0.01 mm x 3600 has 3.6e8; this
/// is about a minute of work on two cores).
const MAX_GRID_DEXELS: u64 = 20_000_000_000;

/// Bytes of a dexel: the unit of the budget (`max_dexels` dexels are `4 max_dexels` bytes).
pub(super) const DEXEL_BYTES: u64 = 4;

/// When a run holds a [`Term`]: all along, while the columns are cut and compared, or
/// while the measurement generators run (after the columns: the two never overlap).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    Run,
    Columns,
    Measure,
}

/// One thing a run holds: its bytes, what it is, and when.
#[derive(Clone, Debug)]
pub(super) struct Term {
    pub(super) bytes: u64,
    pub(super) what: String,
    pub(super) phase: Phase,
}

/// What a run holds that grows with the part (cells, columns, turns, passes, moves), term
/// by term: the budget is on its peak, `Run` terms plus the larger of the two phases.
/// What does not grow with the part (the job, the report's fixed fields) is left out.
#[derive(Clone, Debug, Default)]
pub(super) struct Footprint {
    pub(super) terms: Vec<Term>,
}

impl Footprint {
    /// Add a term (none of zero bytes).
    pub(super) fn add(&mut self, phase: Phase, bytes: u64, what: impl Into<String>) {
        if bytes > 0 {
            self.terms.push(Term {
                bytes,
                what: what.into(),
                phase,
            });
        }
    }

    fn sum(&self, phase: Phase) -> u64 {
        self.terms
            .iter()
            .filter(|t| t.phase == phase)
            .fold(0u64, |a, t| a.saturating_add(t.bytes))
    }

    /// The larger of the two phases.
    fn peak_phase(&self) -> Phase {
        if self.sum(Phase::Measure) > self.sum(Phase::Columns) {
            Phase::Measure
        } else {
            Phase::Columns
        }
    }

    /// The bytes held at once at the peak.
    pub(super) fn held(&self) -> u64 {
        self.sum(Phase::Run)
            .saturating_add(self.sum(self.peak_phase()))
    }

    /// The terms in words, each with its size: the whole run's, then each phase's, the
    /// peak's named.
    pub(super) fn describe(&self) -> String {
        let peak = self.peak_phase();
        let list = |phase: Phase| {
            self.terms
                .iter()
                .filter(|t| t.phase == phase)
                .map(|t| format!("{} ({})", t.what, bytes_readable(t.bytes)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut parts = vec![list(Phase::Run)];
        for (phase, during) in [
            (Phase::Columns, "while the columns are cut"),
            (Phase::Measure, "then while the generators are measured"),
        ] {
            let terms = list(phase);
            if !terms.is_empty() {
                let mark = if phase == peak { ", the peak" } else { "" };
                parts.push(format!("{during}{mark}: {terms}"));
            }
        }
        parts.retain(|p| !p.is_empty());
        if parts.is_empty() {
            "nothing".to_string()
        } else {
            parts.join("; ")
        }
    }
}

/// Bytes as a person reads them: three significant digits in B, kB, MB, GB or TB
/// (1000s), beyond that in scientific notation, and a count capped at the integer's limit
/// as "more than" it.
pub(super) fn bytes_readable(b: u64) -> String {
    if b == u64::MAX {
        return format!("more than {:.1e} bytes", u64::MAX as f64);
    }
    let (v, unit) = match b {
        0..=999 => return format!("{b} bytes"),
        1_000..=999_999 => (b as f64 / 1e3, "kB"),
        1_000_000..=999_999_999 => (b as f64 / 1e6, "MB"),
        1_000_000_000..=999_999_999_999 => (b as f64 / 1e9, "GB"),
        1_000_000_000_000..=999_999_999_999_999 => (b as f64 / 1e12, "TB"),
        _ => return format!("{:.2e} bytes", b as f64),
    };
    if v >= 100.0 {
        format!("{v:.0} {unit}")
    } else if v >= 10.0 {
        format!("{v:.1} {unit}")
    } else {
        format!("{v:.2} {unit}")
    }
}

/// What a run is, as far as its memory goes.
pub(super) struct RunShape {
    pub(super) grid: Grid,
    /// Dexels of the whole grid (all surfaces).
    pub(super) requested: u64,
    pub(super) surfaces: u32,
    /// The whole grid is kept (else streamed).
    pub(super) keep: bool,
    /// Swept bodies: the edges alone cut a second stock.
    pub(super) twice: bool,
    /// Columns each thread holds when streamed: 1, or (the model meshed as the columns
    /// stream) the widest interval from one kept column to the next, both ends.
    pub(super) columns: usize,
    /// The thread's surface exists (else no column is cut).
    pub(super) has_surface: bool,
    /// Threads the columns and generators run on.
    pub(super) threads: usize,
    /// The program turned the thread's surface: a profile along z.
    pub(super) turned: bool,
    /// The passes prepared for the sweep (with the bodies' tables, and without them, as
    /// each measurement generator prepares them), bytes; 0 before they are built.
    pub(super) prepared: (u64, u64),
    /// A milling path's moves.
    pub(super) mill_moves: Option<usize>,
    /// A column's ideal over the grid.
    pub(super) ideal: IdealSize,
    /// Measurement cells per generator and generators, if any.
    pub(super) measure: Option<(usize, usize)>,
    /// A tolerance class is gauged: the generators' cuts are kept for the gauges.
    pub(super) gauge: bool,
}

/// What a run of `shape` holds that grows with the part.
pub(super) fn footprint(s: &RunShape) -> Footprint {
    use std::mem::size_of;
    // In u128: a grid of `usize::MAX` cells (a 1e-300 mm spacing) times a few bytes does
    // not wrap; each term is capped at `u64::MAX` ("more than 1.8e19 bytes").
    let cap = |x: u128| x.min(u64::MAX as u128) as u64;
    let grid = &s.grid;
    let n_z = grid.n_z as u128;
    let f32s = size_of::<f32>() as u128;
    let threads = s.threads.max(1) as u128;
    let mut f = Footprint::default();
    let IdealSize {
        bytes: ideal_bytes,
        verts,
        grooves,
        features,
    } = s.ideal;
    let keys = grooves + 1;
    if s.keep {
        let grid_bytes = cap(s.requested as u128 * DEXEL_BYTES as u128);
        f.add(
            Phase::Run,
            grid_bytes,
            format!(
                "the whole grid, {} angular x {} axial x {} surface(s), as the model, pictures and plots need it",
                grid.n_theta,
                readable(grid.n_z as u64),
                s.surfaces
            ),
        );
        if s.twice {
            f.add(Phase::Run, grid_bytes, "its cut by the edges alone");
        }
    }
    if s.turned {
        f.add(Phase::Run, cap(n_z * f32s), "the turned profile");
    }
    f.add(Phase::Run, s.prepared.0, "the passes' bodies prepared");
    if let Some(m) = s.mill_moves {
        f.add(
            Phase::Run,
            cap(m as u128 * size_of::<crate::kernel::mill::MoveCut>() as u128),
            "the figures per move",
        );
    }
    if s.has_surface && n_z > 0 {
        let in_flight = threads.min(grid.n_theta.max(1) as u128);
        if !s.keep {
            let per = s.columns.max(1) as u128 * if s.twice { 2 } else { 1 };
            f.add(
                Phase::Columns,
                cap(in_flight * per * n_z * DEXEL_BYTES as u128),
                format!(
                    "{} column(s) of {} axial cells, {per} per thread on {in_flight} thread(s){}; the {} angular columns are streamed",
                    in_flight * per,
                    readable(grid.n_z as u64),
                    if s.columns > 1 {
                        format!(
                            " (the model is meshed as they stream: the columns from one of its kept columns to the next, at most {}{}; the mesh's profiles come on top)",
                            s.columns,
                            if s.twice { ", and the edges' cut of each" } else { "" }
                        )
                    } else {
                        String::new()
                    },
                    grid.n_theta
                ),
            );
        }
        // Per thread: the comparison's ideal (its polyline, per-vertex tables, heights per
        // cell, the extremes so far per turn); with bodies, the cells they cut deeper (a
        // vector that may double past every cell) and a mesh body's section bounds; a
        // milling column's snapshot of the cells a move may change (doubled: it grows).
        let mut per_thread = ideal_bytes as u128
            + verts as u128 * 8
            + n_z * f32s
            + super::columns::btree_bytes(keys, size_of::<((u32, i64), [f64; 8])>()) as u128;
        if s.twice {
            per_thread += 2 * n_z * size_of::<usize>() as u128 + 2 * n_z * f32s;
        }
        if s.mill_moves.is_some() {
            per_thread += 2 * n_z * f32s;
        }
        f.add(
            Phase::Columns,
            cap(in_flight * per_thread),
            format!("each thread's comparison of a column with the ideal, {grooves} turn(s)"),
        );
        let wave = super::columns::wave_columns(grid, s.threads, s.columns.max(1) - 1) as u128;
        let out = super::columns::column_out_bytes(
            keys,
            s.twice.then_some(keys + features),
            s.mill_moves,
        );
        f.add(
            Phase::Columns,
            cap(wave * out as u128),
            format!("the results of a wave of {wave} column(s)"),
        );
    }
    if let Some((cells, generators)) = s.measure {
        let in_flight = threads.min(generators.max(1) as u128);
        let one = crate::analysis::measure::generator_bytes(cells, features as usize) as u128
            + ideal_bytes as u128
            + s.prepared.1 as u128;
        f.add(
            Phase::Measure,
            cap(in_flight * one),
            format!(
                "{in_flight} measurement generator(s) of {} cells at a time",
                readable(cells as u64)
            ),
        );
        if s.gauge {
            // Every generator's heights (f32), and the gauges' points ((f64, f64)) of
            // the whole span and of one window.
            let all = cells as u128 * generators.max(1) as u128;
            f.add(
                Phase::Measure,
                cap(all * (f32s + 2 * 16)),
                format!(
                    "the gauges' {} generator cut(s) of {} cells and their points",
                    generators.max(1),
                    readable(cells as u64)
                ),
            );
        }
    }
    f
}

/// A column's ideal over the grid (at the thread's start angle; another angle's differs by
/// at most a groove and a feature per start): its heap bytes, vertices, grooves and
/// features, each with a margin of those.
pub(super) fn ideal_size(thread: &ThreadSpec, grid: &Grid) -> IdealSize {
    use crate::model::thread::{Feature, ThreadGroove, Vertex};
    use std::mem::size_of;
    if grid.n_z == 0 {
        return IdealSize::default();
    }
    let ideal = thread.column(thread.helix.theta0, grid.z(0), grid.z(grid.n_z - 1));
    let margin = 2 * (thread.starts as usize + 1);
    let verts = ideal.verts.capacity() + 2 * margin;
    let bytes = verts * size_of::<Vertex>()
        + (ideal.features.capacity() + margin) * size_of::<Feature>()
        + (ideal.grooves.capacity() + margin) * size_of::<ThreadGroove>();
    IdealSize {
        bytes: bytes as u64,
        verts: verts as u64,
        grooves: (ideal.grooves.len() + margin) as u64,
        features: (ideal.features.len() + margin) as u64,
    }
}

/// A column's ideal as far as memory goes (see [`ideal_size`]).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct IdealSize {
    /// Heap bytes of its polyline, features and grooves.
    pub(super) bytes: u64,
    /// Vertices.
    pub(super) verts: u64,
    /// Grooves: the turns a column's comparison has (one more for the points before).
    pub(super) grooves: u64,
    /// Features: with the grooves, the turns of the body interference.
    pub(super) features: u64,
}

/// Check what a run holds at once (`footprint`) against the budget of `limit` dexels of
/// [`DEXEL_BYTES`] each; then the grid's own size (`requested` dexels on `surfaces`
/// surfaces) against [`MAX_GRID_DEXELS`].
pub(super) fn check_budget(
    grid: Grid,
    requested: u64,
    limit: u64,
    surfaces: u32,
    footprint: &Footprint,
) -> Result<(), SimError> {
    let held = footprint.held();
    if held > limit.saturating_mul(DEXEL_BYTES) {
        return Err(SimError::DexelBudget {
            bytes: held,
            limit,
            held_as: footprint.describe(),
            requested,
            angular: grid.n_theta,
            axial: grid.n_z,
            surfaces,
        });
    }
    if requested > MAX_GRID_DEXELS {
        return Err(SimError::TooManyDexels {
            dexels: requested,
            limit: MAX_GRID_DEXELS,
            angular: grid.n_theta,
            axial: grid.n_z,
        });
    }
    Ok(())
}
