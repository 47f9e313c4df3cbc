//! The pipeline: one run of a job over its operation (a lathe's passes or a thread mill's
//! path). In order: the grid and the memory the run may hold ([`grid`]); every column cut,
//! compared and checked for body interference while it is in cache ([`columns`]); the
//! measurement generators; the machine checks; the report and its findings
//! ([`crate::report`]), with what milling adds ([`milling`]).

mod columns;
mod grid;
mod milling;

pub(crate) use columns::{Held, Sink};
pub use grid::plan_grid;

use crate::analysis::compare::{Comparer, Deviation};
use crate::analysis::findings::{rank, FindingCounts, FindingKind};
use crate::analysis::gauge;
use crate::analysis::interference::{self, Measurer};
use crate::analysis::measure::{generator_cells, measure_kept, MeasureConfig};
use crate::analysis::{checks, chips, contour};
use crate::job::{Job, MillJob};
use crate::kernel::mill::{mill_column, GridMill};
use crate::kernel::sweep::{sweep_column, Column, GridSweep};
use crate::model::pass::Pass;
use crate::model::stock::{Stock, Surface};
use crate::model::tool::Tool;
use crate::report::{self, build_report, Report};
use columns::{Cutting, NoSink, Pipeline};
use grid::{blank_stock, grid_window, measure_window, thread_surface};
use std::time::Instant;

/// Tool placements (pass crossings of a column) a simulation may do: 1000 times the seed
/// 004 scene (195 passes, 3600 columns), about ten minutes of sweep on two cores.
const MAX_PLACEMENTS: f64 = 5e9;

/// Run-time options that are not part of the job.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimOptions {
    /// Overrides the job's dexel budget.
    pub max_dexels: Option<u64>,
}

/// A simulation that could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The run would hold more memory at once than the budget allows.
    #[error("the run would hold {} at once: {held_as}; over the budget of {} ({} dexels of 4 bytes); coarsen [simulation] axial_spacing or angular_cells, narrow z_range, or raise --max-dexels", grid::bytes_readable(*bytes), grid::bytes_readable(limit.saturating_mul(grid::DEXEL_BYTES)), readable(*limit))]
    DexelBudget {
        /// Bytes held at once at the run's peak.
        bytes: u64,
        /// The budget, in dexels of 4 bytes (`max_dexels`).
        limit: u64,
        /// What they are, term by term, with their sizes.
        held_as: String,
        /// Dexels the whole grid has (all surfaces).
        requested: u64,
        /// Angular cells.
        angular: usize,
        /// Axial cells.
        axial: usize,
        /// Surfaces.
        surfaces: u32,
    },
    /// A streaming run would sweep and compare more dexels than any sensible job does.
    #[error("the grid has {} dexels ({angular} angular x {} axial), over the limit of {} a run sweeps and compares: coarsen [simulation] axial_spacing or angular_cells, or narrow z_range", readable(*dexels), readable(*axial as u64), readable(*limit))]
    TooManyDexels {
        /// Dexels of the grid.
        dexels: u64,
        /// The limit.
        limit: u64,
        /// Angular cells.
        angular: usize,
        /// Axial cells.
        axial: usize,
    },
    /// The passes would place the tool more often than any sensible job does.
    #[error("the passes cross the {columns} angular columns about {placements:.2e} times, over the limit of {limit:.0e}: check the leads and the number of passes, or use fewer angular cells")]
    TooManyPlacements {
        /// Estimated placements.
        placements: f64,
        /// The limit.
        limit: f64,
        /// Angular columns.
        columns: usize,
    },
    /// The memory for the stock grid could not be allocated.
    #[error("cannot allocate {bytes} bytes for the stock ({angular} angular x {axial} axial cells): coarsen [simulation] axial_spacing or angular_cells, narrow z_range, or lower --max-dexels")]
    OutOfMemory {
        /// Bytes asked for.
        bytes: u128,
        /// Angular cells.
        angular: usize,
        /// Axial cells.
        axial: usize,
    },
    /// The axial window holds no cell.
    #[error("the axial window [{lo}, {hi}] mm holds no cell of the blank")]
    EmptyWindow {
        /// Low end.
        lo: f64,
        /// High end.
        hi: f64,
    },
}

/// A count as a person reads it: whole below ten million, else scientific, and a count that
/// was capped at the integer's limit as "more than" it (never 20 digits of a cap).
fn readable(n: u64) -> String {
    if n == u64::MAX {
        format!("more than {:.1e}", u64::MAX as f64)
    } else if n >= 10_000_000 {
        format!("{:.2e}", n as f64)
    } else {
        n.to_string()
    }
}

/// The class the gauges judge the job's thread by: a thread with a class, of constant
/// lead and equal groove width (the gauges' perfect thread).
fn gauge_class(job: &Job) -> Option<&crate::model::tolerance::ThreadClass> {
    use crate::model::thread::WidthRule;
    job.thread_class.as_ref().filter(|_| {
        job.thread.helix.law.k == 0.0 && matches!(job.thread.width, WidthRule::Groove(_))
    })
}

/// The result of a simulation.
#[derive(Debug)]
pub struct Outcome {
    /// The report.
    pub report: Report,
    /// The cut stock.
    pub stock: Stock,
    /// With tool bodies: the stock as the edges alone cut it (where it differs from
    /// `stock`, a body cut past its edge).
    pub edge_stock: Option<Stock>,
    /// The deviation from the ideal thread, exact (the report rounds it).
    pub deviation: Deviation,
}

/// What cuts the stock in a job.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Operation<'a> {
    /// A lathe's threading passes and the tools they name.
    Turning {
        passes: &'a [Pass],
        tools: &'a [Tool],
    },
    /// A thread mill's path.
    Milling(&'a MillJob),
}

impl<'a> Operation<'a> {
    /// The job's operation.
    pub(crate) fn of(job: &'a Job) -> Operation<'a> {
        match &job.mill {
            Some(mj) => Operation::Milling(mj),
            None => Operation::Turning {
                passes: &job.passes,
                tools: &job.tools,
            },
        }
    }
}

/// Simulate a job: cut, compare, measure, check, report. The whole grid is kept and
/// returned (the pictures, the plots and the page read any dexel; the model alone is
/// meshed while the columns stream, `output::stream`); [`simulate_report`] streams the
/// columns instead and returns the same report holding only a column per thread.
pub fn simulate(job: &Job, opts: &SimOptions) -> Result<Outcome, SimError> {
    let run = run::<NoSink>(job, opts, true, None)?;
    Ok(Outcome {
        report: run.report,
        stock: run.stock.expect("a full-grid run keeps its stock"),
        edge_stock: run.edge_stock,
        deviation: run.deviation,
    })
}

/// Simulate a job as [`simulate`] does, for its report only: the columns are cut,
/// compared and checked for body interference one at a time, each while it is in cache,
/// in buffers of one column per thread, and their results merged in column order. The
/// report is byte for byte the one [`simulate`] gives, for any thread count; the memory
/// held does not grow with the number of angular cells, and the dexel budget applies to
/// what is held.
pub fn simulate_report(job: &Job, opts: &SimOptions) -> Result<Report, SimError> {
    run::<NoSink>(job, opts, false, None).map(|r| r.report)
}

/// A streamed run whose raw columns also went to a [`Sink`].
pub(crate) struct Streamed<P> {
    /// The report, byte for byte [`simulate`]'s.
    pub(crate) report: Report,
    /// The exact deviation.
    pub(crate) deviation: Deviation,
    /// The sink's parts, in interval order.
    pub(crate) parts: Vec<P>,
    /// The column the sink asked for after the run, cut again (relative to the blank).
    pub(crate) probe: Option<(usize, Vec<f32>)>,
}

/// Simulate a job streamed as [`simulate_report`] does, handing the thread's surface to
/// `sink` an interval of columns at a time while they are held (the model's mesh). The
/// dexel budget counts a buffer of the widest interval per thread.
pub(crate) fn simulate_with<S: Sink>(
    job: &Job,
    opts: &SimOptions,
    sink: &S,
) -> Result<Streamed<S::Part>, SimError> {
    let run = run(job, opts, false, Some(sink))?;
    Ok(Streamed {
        report: run.report,
        deviation: run.deviation,
        parts: run.parts,
        probe: run.probe,
    })
}

/// The insert's limits pass by pass (`analysis::chips`): the chips against each tool's
/// `depth_per_pass` (worked out only when a tool has one), and the threading cycles'
/// infeeds against the flanks.
fn insert_limits(
    job: &Job,
    passes: &[Pass],
    tools: &[Tool],
    turned: &crate::kernel::turn::Turned,
    q_blank: f64,
    q_floor: f64,
) -> Vec<checks::MachineIssue> {
    let sense = match job.thread.side {
        crate::model::thread::Side::External => 1.0,
        crate::model::thread::Side::Internal => -1.0,
    };
    let mut out = Vec::new();
    let limited = tools
        .iter()
        .any(|t| t.depth_per_pass.max.is_some() || t.depth_per_pass.min.is_some());
    if limited {
        let b = &job.blank;
        let surface = chips::Surface {
            sense,
            q_blank,
            q_floor,
            z_span: (b.z_front - b.length, b.z_front),
            turned,
        };
        let found = chips::pass_chips(passes, tools, surface);
        let names = |i: usize| job.pass_tool_name(i);
        out.extend(chips::depth_issues(passes, tools, &found, &names));
    }
    let rubs = chips::infeed_rubs(passes, tools, &job.pass_blocks, &job.pass_cycle, sense);
    out.extend(chips::rub_issues(passes, &rubs));
    out
}

/// The finished part's contour (`[part] profile`, or `bore_profile` for `bore`) against
/// every cut on that surface (`analysis::contour`); `None` without that contour.
fn part_check(
    job: &Job,
    passes: &[Pass],
    tools: &[Tool],
    bore: bool,
    compared: Option<(f64, f64)>,
) -> Option<(Vec<contour::PartGouge>, Vec<contour::PartLeftover>)> {
    let b = &job.blank;
    let (profile, sense, q_blank, q_floor, turned) = if bore {
        (
            job.bore_profile.as_ref()?,
            -1.0,
            -b.bore / 2.0,
            -b.diameter / 2.0,
            &job.turning.inner,
        )
    } else {
        (
            job.part_profile.as_ref()?,
            1.0,
            b.diameter / 2.0,
            b.bore / 2.0,
            &job.turning.outer,
        )
    };
    let on_this = (job.thread.side == crate::model::thread::Side::Internal) == bore;
    Some(contour::check(&contour::Surface {
        profile,
        sense,
        q_blank,
        q_floor,
        turned,
        thread: on_this.then_some((&job.thread, compared)),
        passes: if on_this { passes } else { &[] },
        tools,
        dz: job.sim.axial_spacing,
        z_span: (b.z_front - b.length, b.z_front),
        tolerance: job.sim.tolerance,
    }))
}

/// What [`run`] gives: the report, the exact deviation, the stocks when kept, and a
/// sink's parts and probe.
struct Run<P> {
    report: Report,
    deviation: Deviation,
    stock: Option<Stock>,
    edge_stock: Option<Stock>,
    parts: Vec<P>,
    probe: Option<(usize, Vec<f32>)>,
}

/// The run behind [`simulate`] (`keep`: the whole grid, returned), [`simulate_report`]
/// (streamed) and [`simulate_with`] (streamed through a sink's intervals).
fn run<S: Sink>(
    job: &Job,
    opts: &SimOptions,
    keep: bool,
    sink: Option<&S>,
) -> Result<Run<S::Part>, SimError> {
    let t_start = Instant::now();
    let op = Operation::of(job);
    let (grid, requested) = plan_grid(job)?;
    let surfaces: u32 = if job.blank.bore > 0.0 { 2 } else { 1 };
    let thread = &job.thread;
    let surface = thread_surface(thread);
    let q_blank = match surface {
        Surface::Outer => job.blank.diameter / 2.0,
        Surface::Inner => -job.blank.bore / 2.0,
    };
    let has_surface = surface == Surface::Outer || job.blank.bore > 0.0;
    // With tool bodies whose sections are swept, the edges alone cut a second stock: the
    // difference is what the bodies cut beyond their edges. Bodies that are all skipped
    // (they cannot reach past their edges) cut exactly the edges' stock: no second sweep.
    let swept = match op {
        Operation::Turning { passes, tools } => {
            interference::swept_bodies(passes, tools, q_blank, surface)
        }
        Operation::Milling(_) => Vec::new(),
    };
    let twice = !swept.is_empty() && has_surface;
    let limit = opts.max_dexels.unwrap_or(job.sim.max_dexels);
    let window = grid_window(&grid);
    let ((m_lo, m_hi), spacing) = measure_window(job, window);
    let (turned, q_floor) = match surface {
        Surface::Outer => (&job.turning.outer, job.blank.bore / 2.0),
        Surface::Inner => (&job.turning.inner, -job.blank.diameter / 2.0),
    };
    let mut shape = grid::RunShape {
        grid,
        requested,
        surfaces,
        keep,
        twice,
        columns: sink.map_or(1, |s| columns::widest(s.bounds(), grid.n_theta) + 1),
        has_surface,
        threads: rayon::current_num_threads(),
        turned: !turned.cuts.is_empty(),
        prepared: (0, 0),
        mill_moves: match op {
            Operation::Milling(mj) => Some(mj.path.moves.len()),
            Operation::Turning { .. } => None,
        },
        ideal: grid::ideal_size(thread, &grid),
        measure: (m_hi > m_lo).then(|| {
            (
                generator_cells((m_lo, m_hi), spacing),
                job.sim.measure_generators.max(1),
            )
        }),
        gauge: gauge_class(job).is_some(),
    };
    // Each pass crosses every column once per revolution, each mill sample reaches every
    // column at most once: bound the work before doing it.
    let placements = match op {
        Operation::Turning { passes, .. } => passes
            .iter()
            .map(|p| p.revolutions().unwrap_or(0.0) + 1.0)
            .sum::<f64>(),
        Operation::Milling(mj) => mj.path.len() as f64,
    } * grid.n_theta as f64;
    if placements > MAX_PLACEMENTS {
        return Err(SimError::TooManyPlacements {
            placements,
            limit: MAX_PLACEMENTS,
            columns: grid.n_theta,
        });
    }
    // The passes prepared (the bodies' tables built: at most 64 MB a pass), then the
    // budget on everything the run will hold, before the grid is allocated.
    let edges: Vec<Tool> = job.tools.iter().map(Tool::edge_only).collect();
    let cut = match op {
        Operation::Turning { passes, tools } => Cutting::Turning {
            sweep: GridSweep::new(grid, q_blank, surface, passes, tools),
            edges: twice.then(|| GridSweep::new(grid, q_blank, surface, passes, &edges)),
        },
        Operation::Milling(mj) => {
            Cutting::Milling(GridMill::new(grid, q_blank, surface, &mj.path, &mj.cutters))
        }
    };
    if let Cutting::Turning { sweep, edges } = &cut {
        let (a, b) = sweep.heap_bytes();
        let e = edges.as_ref().map_or(0, |e| e.heap_bytes().0);
        shape.prepared = (a + e, b);
    }
    grid::check_budget(grid, requested, limit, surfaces, &grid::footprint(&shape))?;
    let mut stock = if keep {
        Some(blank_stock(job, grid)?)
    } else {
        None
    };
    let mut edge_stock = if keep && twice {
        Some(blank_stock(job, grid)?)
    } else {
        None
    };
    let t_setup = t_start.elapsed().as_secs_f64();

    let t0 = Instant::now();
    let mill_stats = match &cut {
        Cutting::Milling(m) => Some(m.stats()),
        Cutting::Turning { .. } => None,
    };
    // The program's turning moves on the thread's surface: one profile along z, clamped
    // into every column and every measurement generator (kernel::turn).
    let turned_profile = (!turned.cuts.is_empty())
        .then(|| turned.profile(grid.n_z, grid.z0, grid.dz, q_blank, q_floor));
    let pipe = Pipeline {
        cut,
        cmp: Comparer::new(grid, q_blank, surface, thread, window),
        bodies: Measurer::new(grid, q_blank, surface, thread),
        grid,
        turned: turned_profile.as_deref(),
    };
    let (merged, parts) = match sink {
        Some(s) if has_surface => pipe.run_intervals(s, mill_stats)?,
        _ if has_surface => (
            pipe.run(surface, stock.as_mut(), edge_stock.as_mut(), mill_stats)?,
            Vec::new(),
        ),
        _ => (
            columns::Merged {
                mill: mill_stats,
                ..columns::Merged::default()
            },
            Vec::new(),
        ),
    };
    let probe = match sink.and_then(|s| s.probe(&merged.dev)) {
        Some(i) if has_surface && i < grid.n_theta => Some((
            i,
            pipe.cut_alone(i).ok_or(SimError::OutOfMemory {
                bytes: grid.n_z as u128 * 4,
                angular: grid.n_theta,
                axial: grid.n_z,
            })?,
        )),
        _ => None,
    };
    // Cutting and comparing run fused: their wall time is split in proportion to their
    // CPU time.
    let fused = t0.elapsed().as_secs_f64();
    let (s_cut, s_compare) = merged.seconds;
    let share = if s_cut + s_compare > 0.0 {
        s_cut / (s_cut + s_compare)
    } else {
        1.0
    };
    let (t_sweep, t_compare) = (fused * share, fused * (1.0 - share));

    let t0 = Instant::now();
    let gauged = gauge_class(job);
    let (measures, kept) = if m_hi > m_lo {
        let cfg = MeasureConfig {
            spacing,
            generators: job.sim.measure_generators,
            pitch_diameter: matches!(op, Operation::Milling(_)) || gauged.is_some(),
            keep_columns: gauged.is_some(),
        };
        match op {
            Operation::Turning { passes, tools } => {
                let cut = |q: &mut [f32], c: Column| {
                    sweep_column(q, c, passes, tools);
                    turned.clamp(q, c.z0, c.dz, c.q_blank, q_floor);
                };
                measure_kept(thread, &cut, q_blank, (m_lo, m_hi), cfg)
            }
            Operation::Milling(mj) => {
                let cut = |q: &mut [f32], c: Column| mill_column(q, c, &mj.path, &mj.cutters);
                measure_kept(thread, &cut, q_blank, (m_lo, m_hi), cfg)
            }
        }
    } else {
        (Vec::new(), Vec::new())
    };
    let gauge = gauged.map(|class| gauge::judge(thread, class, &kept, &measures, spacing));
    drop(kept);
    let t_measure = t0.elapsed().as_secs_f64();

    let (machine_issues, bodies) = match op {
        Operation::Turning { passes, tools } => {
            let mut issues = checks::check(passes, &job.pass_rpm, &job.machine, &job.blank);
            // A chained pass (continuous threading, a GSK run-out) is already at speed: it
            // needs no run-in of its own.
            issues.retain(|i| {
                i.kind != FindingKind::RunIn || job.chains.iter().all(|c| c.pass != i.pass)
            });
            issues.extend(checks::chain_check(
                &job.chains,
                &job.pass_rpm,
                &job.machine,
                job.sim.tolerance,
            ));
            issues.extend(checks::head_check(passes, tools, &job.blank, thread.side));
            issues.extend(insert_limits(job, passes, tools, turned, q_blank, q_floor));
            let bodies = interference::has_bodies(passes, tools).then(|| {
                (
                    merged.hits,
                    interference::clearances(thread, passes, tools),
                    swept,
                )
            });
            (issues, bodies)
        }
        Operation::Milling(_) => (Vec::new(), None),
    };
    let mut report = build_report(
        job,
        grid,
        merged.stats,
        &merged.dev,
        &measures,
        spacing,
        &machine_issues,
        bodies.as_ref(),
    );
    if let (Operation::Milling(mj), Some(stats)) = (op, &merged.mill) {
        milling::add_mill(&mut report, job, mj, stats, &measures, surface);
        report.verdict = rank(&mut report.findings);
        report.finding_counts = FindingCounts::of(&report.findings);
    }
    if let (Some(class), Some(g)) = (gauged, &gauge) {
        report::add_gauge(&mut report, class, g, &measures);
        report.verdict = rank(&mut report.findings);
        report.finding_counts = FindingCounts::of(&report.findings);
    }
    if let Operation::Turning { passes, tools } = op {
        let compared = merged
            .dev
            .compared_z
            .map(|(a, b)| (a - 0.5 * grid.dz, b + 0.5 * grid.dz));
        for bore in [false, true] {
            if let Some(found) = part_check(job, passes, tools, bore, compared) {
                report::add_part(&mut report, job, bore, &found);
                report.verdict = rank(&mut report.findings);
                report.finding_counts = FindingCounts::of(&report.findings);
            }
        }
    }
    report::locate(job, &merged.dev, &mut report.findings);
    let units = report.units();
    report.findings = report::group(std::mem::take(&mut report.findings), units);
    report.verdict = rank(&mut report.findings);
    report.finding_counts = FindingCounts::of(&report.findings);
    report.timing_s = report::Timing {
        setup: t_setup,
        sweep: t_sweep,
        compare: t_compare,
        measure: t_measure,
        total: t_start.elapsed().as_secs_f64(),
    };
    Ok(Run {
        report,
        deviation: merged.dev,
        stock,
        edge_stock,
        parts,
        probe,
    })
}
