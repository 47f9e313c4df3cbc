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
    (
        grid.z(0) - 0.5 * grid.dz,
        grid.z(grid.n_z - 1) + 0.5 * grid.dz,
    )
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

/// Check what a run on `grid` (`requested` dexels on `surfaces` surfaces) would hold at
/// once against the budget `limit`: the whole grid when it is kept (`keep`; twice with
/// swept bodies, `twice`), else `columns` columns per thread (1; a mesh interval's when
/// the model is meshed streamed), twice with swept bodies. Then the grid's own size
/// against [`MAX_GRID_DEXELS`].
pub(super) fn check_budget(
    grid: Grid,
    requested: u64,
    limit: u64,
    surfaces: u32,
    keep: bool,
    columns: usize,
    twice: bool,
) -> Result<(), SimError> {
    let (held, held_as) = if keep {
        let held = requested.saturating_add(if twice { grid.dexels() as u64 } else { 0 });
        (
            held,
            format!(
                "the whole grid, {} angular x {} axial x {surfaces} surface(s){}, as the model, pictures and plots need it",
                grid.n_theta,
                readable(grid.n_z as u64),
                if twice {
                    " and its cut by the edges alone"
                } else {
                    ""
                }
            ),
        )
    } else {
        let per = columns.max(1) as u64 * if twice { 2 } else { 1 };
        let in_flight = rayon::current_num_threads().max(1).min(grid.n_theta.max(1));
        (
            (in_flight as u64)
                .saturating_mul(per)
                .saturating_mul(grid.n_z as u64),
            format!(
                "{} column(s) of {} axial cells, {per} per thread on {in_flight} thread(s){}; the {} angular columns are streamed",
                in_flight as u64 * per,
                readable(grid.n_z as u64),
                if columns > 1 {
                    format!(
                        " (the model is meshed as they stream: the columns from one of its kept columns to the next, at most {columns}{}; the mesh's profiles come on top)",
                        if twice { ", and the edges' cut of each" } else { "" }
                    )
                } else {
                    String::new()
                },
                grid.n_theta
            ),
        )
    };
    if held > limit {
        return Err(SimError::DexelBudget {
            held,
            limit,
            held_as,
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
