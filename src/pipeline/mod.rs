//! The pipeline: a job's passes cut into the stock, compared, measured, checked and
//! reported, column by column.

use crate::analysis::{checks as machine, compare, interference, measure};
use crate::kernel::{mill, sweep};
use crate::report::{self, r4, r6};
use crate::*;
use std::collections::BTreeMap;
use std::time::Instant;

/// Tool placements (pass crossings of a column) a simulation may do: 1000 times the seed
/// 004 scene (195 passes, 3600 columns), about ten minutes of sweep on two cores.
const MAX_PLACEMENTS: f64 = 5e9;

/// Run-time options that are not part of the job.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Options {
    /// Overrides the job's dexel budget.
    pub max_dexels: Option<u64>,
}

/// A simulation that could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The run would hold more dexels in memory at once than allowed.
    #[error("the run would hold {} dexels ({} MB) at once: {held_as}; over the budget of {}; coarsen [simulation] axial_spacing or angular_cells, narrow z_range, or raise --max-dexels", readable(*held), readable(held.saturating_mul(4) / 1_000_000), readable(*limit))]
    DexelBudget {
        /// Dexels held at once (4 bytes each).
        held: u64,
        /// The budget.
        limit: u64,
        /// What they are: the whole grid (its size and why) or the tiles in flight.
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
}

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
fn blank_stock(job: &Job, grid: Grid) -> Result<Stock, SimError> {
    Stock::try_blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0).ok_or_else(|| {
        let surfaces: u128 = if job.blank.bore > 0.0 { 2 } else { 1 };
        SimError::OutOfMemory {
            bytes: grid.n_theta as u128 * grid.n_z as u128 * surfaces * 4,
            angular: grid.n_theta,
            axial: grid.n_z,
        }
    })
}

/// Simulate a job: sweep, compare, measure, check, report. The whole grid is kept and
/// returned (the model, the pictures and the plots need it); [`simulate_report`] streams
/// the columns instead and returns the same report holding only a column per thread.
pub fn simulate(job: &Job, opts: &Options) -> Result<Outcome, SimError> {
    let (report, stock, edge_stock) = run(job, opts, true)?;
    Ok(Outcome {
        report,
        stock: stock.expect("a full-grid run keeps its stock"),
        edge_stock,
    })
}

/// Simulate a job as [`simulate`] does, for its report only: the columns are swept,
/// compared and checked for body interference one at a time, each while it is in cache,
/// in buffers of one column per thread, and their results merged in column order. The
/// report is byte for byte the one [`simulate`] gives, for any thread count; the memory
/// held no longer grows with the number of angular cells, and the dexel budget applies to
/// what is held. Milling jobs still build their whole grid.
pub fn simulate_report(job: &Job, opts: &Options) -> Result<Report, SimError> {
    run(job, opts, false).map(|r| r.0)
}

/// Dexels a run sweeps and compares at most (a 1 m screw at 0.01 mm x 3600 has 3.6e8; this
/// is about a minute of work on two cores).
const MAX_GRID_DEXELS: u64 = 20_000_000_000;

/// One column's results: what the sweep did, the comparison, the body interference, and
/// the seconds spent sweeping and comparing (to split the fused pipeline's wall time).
struct ColumnOut {
    stats: SweepStats,
    dev: Deviation,
    hits: Option<interference::Interference>,
    seconds: (f64, f64),
}

/// The per-column pipeline: sweep (and the edges alone, with swept bodies), compare, body
/// interference.
struct Pipeline<'a> {
    sweep: sweep::GridSweep<'a>,
    edges: Option<sweep::GridSweep<'a>>,
    cmp: compare::Comparer<'a>,
    bodies: interference::Measurer<'a>,
    n_z: usize,
}

impl Pipeline<'_> {
    /// Column `i`, held in `col` (and `edge`, the edges' cut): both are cut in place.
    fn column(
        &self,
        i: usize,
        col: &mut [f32],
        edge: Option<&mut [f32]>,
        prior: &mut compare::Prior,
    ) -> ColumnOut {
        let t0 = Instant::now();
        let stats = self.sweep.column(i, col);
        let edge = match (edge, &self.edges) {
            (Some(e), Some(s)) => {
                s.column(i, e);
                Some(e)
            }
            _ => None,
        };
        let t1 = Instant::now();
        let dev = self.cmp.column(i, col, prior);
        prior.add(&dev);
        let hits = edge.map(|e| self.bodies.column(i, e, col));
        let t2 = Instant::now();
        ColumnOut {
            stats,
            dev,
            hits,
            seconds: ((t1 - t0).as_secs_f64(), (t2 - t1).as_secs_f64()),
        }
    }

    /// The columns from `first` on, held contiguously in `cols` (and `edges`).
    fn tile(&self, first: usize, cols: &mut [f32], edges: Option<&mut [f32]>) -> Vec<ColumnOut> {
        let n_z = self.n_z;
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
}

/// A zeroed column buffer, or `None` when the memory cannot be had.
fn column_buffer(n: usize) -> Option<Vec<f32>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).ok()?;
    v.resize(n, 0.0);
    Some(v)
}

/// The run behind [`simulate`] (`keep`: the whole grid, returned) and
/// [`simulate_report`] (streamed).
#[allow(clippy::type_complexity)]
fn run(
    job: &Job,
    opts: &Options,
    keep: bool,
) -> Result<(Report, Option<Stock>, Option<Stock>), SimError> {
    let t_start = Instant::now();
    let (grid, requested) = plan_grid(job)?;
    let limit = opts.max_dexels.unwrap_or(job.sim.max_dexels);
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
    let swept = if job.mill.is_some() {
        Vec::new()
    } else {
        interference::swept_bodies(job, q_blank, surface)
    };
    let twice = !swept.is_empty() && has_surface;
    let whole = keep || job.mill.is_some();
    let threads = rayon::current_num_threads().max(1);
    let tile = compare::tile_columns(grid.n_theta);
    // The memory held at once: the whole grid (twice with swept bodies), or a column per
    // thread (two with swept bodies).
    let (held, held_as) = if whole {
        let held = requested.saturating_add(if twice { grid.dexels() as u64 } else { 0 });
        let why = if job.mill.is_some() {
            "a milling job keeps it"
        } else {
            "the model, pictures and plots need it"
        };
        (
            held,
            format!(
                "the whole grid, {} angular x {} axial x {surfaces} surface(s){}, as {why}",
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
        let per = if twice { 2 } else { 1 };
        let in_flight = threads.min(grid.n_theta.max(1));
        (
            (in_flight as u64)
                .saturating_mul(per)
                .saturating_mul(grid.n_z as u64),
            format!(
                "{} column(s) of {} axial cells, {per} per thread on {in_flight} thread(s); the {} angular columns are streamed",
                in_flight as u64 * per,
                readable(grid.n_z as u64),
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
    if let Some(mill) = &job.mill {
        let out = simulate_mill(job, mill, grid, t_start)?;
        return Ok((out.report, keep.then_some(out.stock), None));
    }
    if requested > MAX_GRID_DEXELS {
        return Err(SimError::TooManyDexels {
            dexels: requested,
            limit: MAX_GRID_DEXELS,
            angular: grid.n_theta,
            axial: grid.n_z,
        });
    }
    // Each pass crosses every column once per revolution: bound the work before doing it.
    let revs: f64 = job
        .passes
        .iter()
        .map(|p| p.revolutions().unwrap_or(0.0) + 1.0)
        .sum();
    let placements = revs * grid.n_theta as f64;
    if placements > MAX_PLACEMENTS {
        return Err(SimError::TooManyPlacements {
            placements,
            limit: MAX_PLACEMENTS,
            columns: grid.n_theta,
        });
    }
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
    let window = grid_window(&grid);
    let edges: Vec<Tool> = job.tools.iter().map(Tool::edge_only).collect();
    let pipe = Pipeline {
        sweep: sweep::GridSweep::new(grid, q_blank, surface, &job.passes, &job.tools),
        edges: twice.then(|| sweep::GridSweep::new(grid, q_blank, surface, &job.passes, &edges)),
        cmp: compare::Comparer::new(grid, q_blank, surface, thread, window),
        bodies: interference::Measurer::new(grid, q_blank, surface, thread),
        n_z: grid.n_z,
    };
    let n_z = grid.n_z;
    let columns: Vec<ColumnOut> = if !has_surface || n_z == 0 {
        Vec::new()
    } else if let Some(stock) = &mut stock {
        use rayon::prelude::*;
        let q = stock.surface_mut(surface).expect("the thread's surface");
        let tiles: Vec<Vec<ColumnOut>> = match &mut edge_stock {
            Some(e) => {
                let qe = e.surface_mut(surface).expect("the thread's surface");
                q.par_chunks_mut(tile * n_z)
                    .zip(qe.par_chunks_mut(tile * n_z))
                    .enumerate()
                    .map(|(t, (c, e))| pipe.tile(t * tile, c, Some(e)))
                    .collect()
            }
            None => q
                .par_chunks_mut(tile * n_z)
                .enumerate()
                .map(|(t, c)| pipe.tile(t * tile, c, None))
                .collect(),
        };
        tiles.into_iter().flatten().collect()
    } else {
        use rayon::prelude::*;
        let n_tiles = grid.n_theta.div_ceil(tile);
        let tiles: Vec<Option<Vec<ColumnOut>>> = (0..n_tiles)
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
                            pipe.column(i, main, edge.as_deref_mut(), &mut prior)
                        })
                        .collect(),
                    )
                },
            )
            .collect();
        let mut out = Vec::with_capacity(grid.n_theta);
        for t in tiles {
            out.extend(t.ok_or(SimError::OutOfMemory {
                bytes: n_z as u128 * 4 * if twice { 2 } else { 1 },
                angular: grid.n_theta,
                axial: grid.n_z,
            })?);
        }
        out
    };
    // Merge in column order.
    let mut stats = SweepStats::default();
    let mut dev = Deviation::default();
    let mut hits = interference::Interference::new();
    let (mut s_sweep, mut s_compare) = (0.0, 0.0);
    for c in &columns {
        stats = stats + c.stats;
        dev.add_column(&c.dev);
        if let Some(h) = &c.hits {
            interference::add_column(&mut hits, h);
        }
        s_sweep += c.seconds.0;
        s_compare += c.seconds.1;
    }
    drop(columns);
    let bodies =
        interference::has_bodies(job).then(|| (hits, interference::clearances(job), swept));
    // Sweep and compare run fused: their wall time is split in proportion to their CPU
    // time.
    let fused = t0.elapsed().as_secs_f64();
    let share = if s_sweep + s_compare > 0.0 {
        s_sweep / (s_sweep + s_compare)
    } else {
        1.0
    };
    let (t_sweep, t_compare) = (fused * share, fused * (1.0 - share));

    let t0 = Instant::now();
    let ((m_lo, m_hi), spacing) = measure_window(job, window);
    let measures = if m_hi > m_lo {
        measure(
            thread,
            &job.passes,
            &job.tools,
            q_blank,
            (m_lo, m_hi),
            MeasureConfig {
                spacing,
                generators: job.sim.measure_generators,
                pitch_diameter: false,
            },
        )
    } else {
        Vec::new()
    };
    let t_measure = t0.elapsed().as_secs_f64();

    let mut machine_issues = machine::check(&job.passes, &job.machine, &job.blank);
    // A chained pass (continuous threading, a GSK run-out) is already at speed: it needs
    // no run-in of its own.
    machine_issues.retain(|i| i.kind != "run_in" || job.chains.iter().all(|c| c.pass != i.pass));
    machine_issues.extend(machine::chain_check(
        &job.chains,
        &job.machine,
        job.sim.tolerance,
    ));
    machine_issues.extend(machine::head_check(
        &job.passes,
        &job.tools,
        &job.blank,
        job.thread.side,
    ));
    let mut report = build_report(
        job,
        grid,
        stats,
        &dev,
        &measures,
        spacing,
        &machine_issues,
        bodies.as_ref(),
    );
    report.timing_s = report::Timing {
        setup: t_setup,
        sweep: t_sweep,
        compare: t_compare,
        measure: t_measure,
        total: t_start.elapsed().as_secs_f64(),
    };
    Ok((report, stock, edge_stock))
}

/// A milling job: the cutters swept along the program's path, then the same comparison
/// and measurement as a turned thread, and the moves' figures.
fn simulate_mill(
    job: &Job,
    mj: &MillJob,
    grid: Grid,
    t_start: Instant,
) -> Result<Outcome, SimError> {
    let placements = mj.path.len() as f64 * grid.n_theta as f64;
    if placements > MAX_PLACEMENTS {
        return Err(SimError::TooManyPlacements {
            placements,
            limit: MAX_PLACEMENTS,
            columns: grid.n_theta,
        });
    }
    let thread = &job.thread;
    let surface = thread_surface(thread);
    let mut stock = blank_stock(job, grid)?;
    let t_setup = t_start.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let stats = sweep_mill(&mut stock, surface, &mj.path, &mj.cutters);
    let t_sweep = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let window = grid_window(&grid);
    let dev = compare(&stock, thread, window);
    let t_compare = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let ((m_lo, m_hi), spacing) = measure_window(job, window);
    let cut = |q: &mut [f32], c: Column| mill_column(q, c, &mj.path, &mj.cutters);
    let measures = if m_hi > m_lo {
        measure::measure_by(
            thread,
            &cut,
            stock.blank_q(surface),
            (m_lo, m_hi),
            MeasureConfig {
                spacing,
                generators: job.sim.measure_generators,
                pitch_diameter: true,
            },
        )
    } else {
        Vec::new()
    };
    let t_measure = t0.elapsed().as_secs_f64();
    let sweep_stats = SweepStats {
        placements: stats.placements,
        dexel_updates: stats.dexel_updates,
    };
    let mut report = build_report(
        job,
        stock.grid,
        sweep_stats,
        &dev,
        &measures,
        spacing,
        &[],
        None,
    );
    report.passes = mj.path.moves.len();
    let ring = (job.blank.bore / 2.0, job.blank.diameter / 2.0);
    let tips: Vec<f64> = mj.cutters.iter().map(|c| c.radius).collect();
    let engaged = mill::engagement(&mj.path, &tips, ring);
    let mut moves = Vec::with_capacity(mj.moves.len());
    for (i, (m, pm)) in mj.moves.iter().zip(&mj.path.moves).enumerate() {
        let cutter = &mj.cutters[pm.cutter];
        let cut = stats.moves[i];
        let rpm = mj.rpm[i];
        let cutting = m.kind != nc::MillKind::Rapid;
        // The edge that makes the thread's root runs on the far side of the centre's
        // circle from its centre (a bore) or on the near side (an external thread).
        let edge_ratio = match &m.arc {
            Some(a) if a.radius > 0.0 => {
                let r = a.radius + surface.sense() * -cutter.radius;
                r.abs() / a.radius
            }
            _ => 1.0,
        };
        let feed_edge = m.feed.filter(|_| cutting).map(|f| f * edge_ratio);
        let fz = feed_edge.map(|f| f / (rpm * cutter.flutes as f64));
        let eng = (cutting && cut.volume > 0.0).then_some(engaged[i]);
        let chip = match (fz, eng) {
            (Some(fz), Some(e)) => Some(fz * e.min(std::f64::consts::FRAC_PI_2).sin()),
            _ => None,
        };
        let tool = mj.cutter_ids[pm.cutter];
        if m.kind == nc::MillKind::Rapid && r6(cut.depth) > 0.0 {
            report.findings.push(Finding {
                kind: "rapid_cut",
                severity: "error",
                turn: None,
                start: None,
                flank: None,
                pass: Some(i + 1),
                angle_deg: Some(r4(cut.at.0.to_degrees().rem_euclid(360.0))),
                z_mm: Some(r6(cut.at.1)),
                file: Some(m.file.clone()),
                line: Some(m.line),
                column: None,
                value: Some(r6(cut.depth)),
                unit: Some("mm"),
                message: format!(
                    "{}:{}: a rapid (G00) move cuts {:.4} mm deep ({:.3} mm3) at {:.1} deg, z {:.3}",
                    m.file,
                    m.line,
                    cut.depth,
                    cut.volume,
                    cut.at.0.to_degrees().rem_euclid(360.0),
                    cut.at.1
                ),
            });
        }
        if let (Some(f), Some(max)) = (m.feed.filter(|_| cutting), job.machine.max_feed) {
            if f > max {
                report.findings.push(Finding {
                    kind: "feed_limit",
                    severity: "error",
                    turn: None,
                    start: None,
                    flank: None,
                    pass: Some(i + 1),
                    angle_deg: None,
                    z_mm: Some(r6(m.end[2])),
                    file: Some(m.file.clone()),
                    line: Some(m.line),
                    column: None,
                    value: Some(r6(f)),
                    unit: Some("mm/min"),
                    message: format!(
                        "{}:{}: feed {f} mm/min over the machine's {max} mm/min",
                        m.file, m.line
                    ),
                });
            }
        }
        moves.push(report::MillMoveRow {
            index: i + 1,
            file: m.file.clone(),
            line: m.line,
            kind: match m.kind {
                nc::MillKind::Rapid => "rapid",
                nc::MillKind::Feed => "feed",
                nc::MillKind::Arc => "arc",
            },
            tool,
            comp: m.comp.map(|(side, _)| match side {
                nc::CompSide::Left => "left",
                nc::CompSide::Right => "right",
            }),
            comp_radius_mm: m.comp.map(|c| r6(c.1)),
            end_mm: [r6(m.end[0]), r6(m.end[1]), r6(m.end[2])],
            feed_centre_mm_min: m.feed.filter(|_| cutting).map(r4),
            feed_edge_mm_min: feed_edge.map(r4),
            feed_per_tooth_mm: fz.map(r6),
            spindle_rpm: r4(rpm),
            removed_volume_mm3: r6(cut.volume),
            radial_depth_mm: r6(cut.depth),
            engagement_deg: eng.map(|e| r4(e.to_degrees())),
            chip_thickness_mm: chip.map(r6),
        });
    }
    let fold = |f: fn(&TurnMeasure) -> Option<f64>| {
        measures
            .iter()
            .flatten()
            .filter_map(f)
            .fold(None, |acc: Option<(f64, f64)>, x| {
                Some(acc.map_or((x, x), |(a, b)| (a.min(x), b.max(x))))
            })
    };
    let d2 = fold(|m| m.pitch_diameter);
    let d2_ideal = fold(|m| m.ideal_pitch_diameter);
    report.mill = Some(report::MillInfo {
        sampling_bound_mm: r6(mill::SAMPLING_BOUND_MM),
        samples: mj.path.len(),
        cutters: mj
            .cutters
            .iter()
            .zip(&mj.cutter_ids)
            .map(|(c, &id)| report::CutterRow {
                id,
                diameter_mm: r6(2.0 * c.radius),
                flutes: c.flutes,
                length_mm: r6(c.length()),
            })
            .collect(),
        pitch_diameter_min_mm: d2.map(|d| r6(d.0)),
        pitch_diameter_max_mm: d2.map(|d| r6(d.1)),
        ideal_pitch_diameter_mm: d2_ideal.map(|d| r6(0.5 * (d.0 + d.1))),
        moves,
    });
    if let Some((lo, hi)) = job.pitch_diameter_limits {
        // The drawing's tolerance class bounds the widths through the pitch diameter:
        // its limits replace the basic profile's widths +- the tolerance.
        report
            .findings
            .retain(|f| f.kind != "groove_width" && f.kind != "tooth_width");
        let mut per_turn: BTreeMap<(u32, i64), (f64, f64)> = BTreeMap::new();
        for m in measures.iter().flatten() {
            if let Some(d) = m.pitch_diameter {
                let e = per_turn.entry((m.start, m.turn)).or_insert((d, d));
                *e = (e.0.min(d), e.1.max(d));
            }
        }
        for (&(start, turn), &(a, b)) in &per_turn {
            let off = if a < lo {
                a - lo
            } else if b > hi {
                b - hi
            } else {
                continue;
            };
            report.findings.push(Finding {
                kind: "pitch_diameter",
                severity: "error",
                turn: Some(turn),
                start: Some(start),
                flank: None,
                pass: None,
                angle_deg: None,
                z_mm: None,
                file: None,
                line: None,
                column: None,
                value: Some(r6(off)),
                unit: Some("mm"),
                message: format!(
                    "turn {turn}: pitch diameter {a:.4} to {b:.4} mm, outside the drawing's {lo} to {hi} mm"
                ),
            });
        }
    }
    report.verdict = rank_findings(&mut report.findings);
    report.finding_counts = report::FindingCounts::of(&report.findings);
    report.timing_s = report::Timing {
        setup: t_setup,
        sweep: t_sweep,
        compare: t_compare,
        measure: t_measure,
        total: t_start.elapsed().as_secs_f64(),
    };
    Ok(Outcome {
        report,
        stock,
        edge_stock: None,
    })
}

/// The stock surface a thread is cut on.
fn thread_surface(thread: &ThreadSpec) -> Surface {
    match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    }
}

/// The axial span of the grid's cells (the comparison's window).
fn grid_window(grid: &Grid) -> (f64, f64) {
    (
        grid.z(0) - 0.5 * grid.dz,
        grid.z(grid.n_z - 1) + 0.5 * grid.dz,
    )
}

/// Where the measurement columns run (the thread and two leads and its depth beyond, inside
/// the window) and their spacing, kept under 8M cells a column.
fn measure_window(job: &Job, window: (f64, f64)) -> ((f64, f64), f64) {
    let thread = &job.thread;
    let law = thread.helix.law;
    let reach = 2.0 * law.lead(0.0).max(law.lead(thread.turns)) + thread.depth();
    let (z_a, z_b) = (thread.helix.z(thread.turns), thread.helix.z0);
    let lo = window.0.max(z_a.min(z_b) - reach);
    let hi = window.1.min(z_a.max(z_b) + reach);
    ((lo, hi), job.sim.measure_spacing.max((hi - lo) / 8.0e6))
}

/// Sort findings, errors first and then by [`KINDS`]; the verdict they give.
fn rank_findings(findings: &mut [Finding]) -> Verdict {
    findings.sort_by_key(|f| {
        (
            (f.severity != "error") as u8,
            KINDS
                .iter()
                .position(|k| *k == f.kind)
                .unwrap_or(KINDS.len()),
        )
    });
    if findings.iter().any(|f| f.severity == "error") {
        Verdict::Fail
    } else {
        Verdict::Pass
    }
}

fn location(e: &Extreme) -> report::Location {
    report::Location {
        turn: e.turn,
        start: e.start,
        flank: e.flank.name(),
        angle_deg: r4(e.theta.to_degrees().rem_euclid(360.0)),
        z_mm: r6(e.z),
    }
}

#[allow(clippy::too_many_arguments)]
fn build_report(
    job: &Job,
    grid: Grid,
    stats: SweepStats,
    dev: &Deviation,
    measures: &[Vec<TurnMeasure>],
    spacing: f64,
    machine_issues: &[machine::MachineIssue],
    bodies: Option<&interference::Bodies>,
) -> Report {
    let thread = &job.thread;
    let tol = job.sim.tolerance;
    let (major, minor) = match thread.side {
        Side::External => (2.0 * thread.crest_radius, 2.0 * thread.root_radius),
        Side::Internal => (2.0 * thread.root_radius, 2.0 * thread.crest_radius),
    };
    let mut findings: Vec<Finding> = Vec::new();
    let mut turns = Vec::new();
    // Index the measurements by (start, turn): the reference generator, and all of them.
    let mut reference: BTreeMap<(u32, i64), &TurnMeasure> = BTreeMap::new();
    let mut by_turn: BTreeMap<(u32, i64), Vec<&TurnMeasure>> = BTreeMap::new();
    for (g, list) in measures.iter().enumerate() {
        for m in list {
            if g == 0 {
                reference.entry((m.start, m.turn)).or_insert(m);
            }
            by_turn.entry((m.start, m.turn)).or_default().push(m);
        }
    }
    for s in 0..thread.starts {
        for n in 1..=thread.whole_turns() {
            let m = reference.get(&(s, n)).copied();
            let all: &[&TurnMeasure] = by_turn.get(&(s, n)).map_or(&[], Vec::as_slice);
            let td = dev.turns.get(&(s, n)).cloned().unwrap_or_default();
            let flank = |f: Flank| report::FlankRow {
                max_gouge_mm: r6(td.gouge[f.index()].map_or(0.0, |e| e.value)),
                max_leftover_mm: r6(td.leftover[f.index()].map_or(0.0, |e| e.value)),
            };
            let fold = |v: &mut Option<(f64, f64)>, x: f64| {
                *v = Some(v.map_or((x, x), |(a, b)| (a.min(x), b.max(x))));
            };
            let (mut ideal_rng, mut meas_rng, mut max_err) = (None, None, None::<f64>);
            for g in all {
                if let Some(i) = g.ideal_lead {
                    fold(&mut ideal_rng, i);
                }
                if let Some(x) = g.lead {
                    fold(&mut meas_rng, x);
                }
                if let (Some(i), Some(x)) = (g.ideal_lead, g.lead) {
                    max_err = Some(max_err.map_or((x - i).abs(), |e: f64| e.max((x - i).abs())));
                }
            }
            let diam = m.and_then(|m| m.cut_heights).map(|(a, b)| {
                let (ra, rb) = (thread.radius(a), thread.radius(b));
                (2.0 * ra.min(rb), 2.0 * ra.max(rb))
            });
            let lead_mid = thread.helix.law.lead(n as f64 - 0.5);
            let psi = (lead_mid / (std::f64::consts::PI * 2.0 * thread.pitch_radius)).atan();
            let row = TurnRow {
                turn: n,
                start: s,
                pitch_diameter_mm: m.and_then(|m| m.pitch_diameter).map(r6),
                ideal_pitch_diameter_mm: m.and_then(|m| m.ideal_pitch_diameter).map(r6),
                ideal_lead_mm: m.and_then(|m| m.ideal_lead).map(r6),
                measured_lead_mm: m.and_then(|m| m.lead).map(r6),
                lead_spread: report::LeadSpread {
                    ideal_min_mm: r6(ideal_rng.map_or(0.0, |r| r.0)),
                    ideal_max_mm: r6(ideal_rng.map_or(0.0, |r| r.1)),
                    measured_min_mm: meas_rng.map(|r| r6(r.0)),
                    measured_max_mm: meas_rng.map(|r| r6(r.1)),
                    max_error_mm: max_err.map(r6),
                },
                ideal_groove_width_mm: m.and_then(|m| m.ideal_groove).map(r6),
                groove_width_mm: m.and_then(|m| m.groove).map(r6),
                ideal_tooth_width_mm: m.and_then(|m| m.ideal_tooth).map(r6),
                tooth_width_mm: m.and_then(|m| m.tooth).map(r6),
                min_diameter_mm: diam.map(|d| r6(d.0)),
                max_diameter_mm: diam.map(|d| r6(d.1)),
                helix_angle_deg: r4(psi.to_degrees()),
                max_gouge_mm: r6(td.max_gouge().map_or(0.0, |e| e.value)),
                max_leftover_mm: r6(td.max_leftover().map_or(0.0, |e| e.value)),
                gouge_volume_mm3: r6(td.gouge_volume),
                leftover_volume_mm3: r6(td.leftover_volume),
                flanks: report::Flanks {
                    left: flank(Flank::Left),
                    right: flank(Flank::Right),
                    root: flank(Flank::Root),
                    crest: flank(Flank::Crest),
                },
                clearance_deg: bodies.and_then(|b| b.1.get(&(s, n))).map(|c| {
                    report::ClearanceRow {
                        left_crest: r4(c.left_crest),
                        left_root: r4(c.left_root),
                        right_crest: r4(c.right_crest),
                        right_root: r4(c.right_root),
                        pass: c.pass + 1,
                    }
                }),
            };
            if td.compared == 0 && dev.compared_dexels > 0 {
                findings.push(Finding {
                    turn: Some(n),
                    start: Some(s),
                    ..Finding::new(
                        "not_compared",
                        "warning",
                        format!(
                            "turn {n}: no dexel of it lies on the simulated stock ([simulation] z_range): it is not checked"
                        ),
                    )
                });
            }
            turn_findings(&row, &td, all, tol, &mut findings);
            turns.push(row);
        }
    }
    for (i, p) in job.passes.iter().enumerate() {
        let hand = p.helix().hand();
        if hand != thread.hand() {
            let name = |h: Hand| if h == Hand::Right { "right" } else { "left" };
            findings.push(Finding {
                kind: "hand",
                severity: "error",
                turn: None,
                start: None,
                flank: None,
                pass: Some(i + 1),
                angle_deg: None,
                z_mm: Some(r6(p.z_start)),
                file: None,
                line: None,
                column: None,
                value: None,
                unit: None,
                message: format!(
                    "pass {}: spindle {} feeding toward {}z cuts a {}-hand helix; the drawing's thread is {}-hand",
                    i + 1,
                    if p.spindle == Spindle::Cw { "cw (M03)" } else { "ccw (M04)" },
                    if p.z_end < p.z_start { "-" } else { "+" },
                    name(hand),
                    name(thread.hand())
                ),
            });
        }
    }
    let mut interference_rows = bodies.map(|_| Vec::new());
    if let (Some((hits, _, _)), Some(rows)) = (bodies, interference_rows.as_mut()) {
        for (&(start, turn), flanks) in hits {
            for (k, h) in flanks.iter().enumerate() {
                let Some(h) = h.filter(|h| r6(h.depth) > 0.0) else {
                    continue;
                };
                let flank = interference::flank_name(k);
                let angle = r4(h.theta.to_degrees().rem_euclid(360.0));
                rows.push(report::InterferenceRow {
                    turn,
                    start,
                    flank,
                    max_mm: r6(h.depth),
                    angle_deg: angle,
                    z_mm: r6(h.z),
                    volume_mm3: r6(h.volume),
                });
                findings.push(Finding {
                    kind: "flank_interference",
                    severity: if h.depth > tol { "error" } else { "warning" },
                    turn: Some(turn),
                    start: Some(start),
                    flank: Some(flank),
                    pass: None,
                    angle_deg: Some(angle),
                    z_mm: Some(r6(h.z)),
                    file: None,
                    line: None,
                    column: None,
                    value: Some(r6(h.depth)),
                    unit: Some("mm"),
                    message: format!(
                        "turn {turn} {flank} flank: the tool body cut {:.4} mm past its edge's surface at {angle:.1} deg, z {:.3} ({:.3} mm3): the side clearance is smaller than the helix angle there",
                        h.depth, h.z, h.volume
                    ),
                });
            }
        }
    }
    for mi in machine_issues {
        findings.push(Finding {
            kind: mi.kind,
            severity: if mi.error { "error" } else { "warning" },
            turn: None,
            start: None,
            flank: None,
            pass: Some(mi.pass + 1),
            angle_deg: None,
            z_mm: Some(r6(mi.z)),
            file: None,
            line: None,
            column: None,
            value: Some(r6(mi.value)),
            unit: Some(match mi.kind {
                "feed_limit" => "mm/min",
                "axis_acceleration" => "mm/s^2",
                "thread_chain" => "mm/rev",
                _ => "mm",
            }),
            message: mi.message.clone(),
        });
    }
    for w in &job.program_warnings {
        findings.push(Finding {
            kind: "program",
            severity: "warning",
            turn: None,
            start: None,
            flank: None,
            pass: None,
            angle_deg: None,
            z_mm: None,
            file: Some(w.file.clone()),
            line: Some(w.line),
            column: Some(w.col.max(1)),
            value: None,
            unit: None,
            message: format!("{}:{}:{}: {}", w.file, w.line, w.col.max(1), w.message),
        });
    }
    if dev.compared_dexels == 0 {
        findings.push(Finding::new(
            "not_compared",
            "error",
            "no dexel of the thread lies on the simulated stock: nothing was compared, so nothing is verified (check thread.z_start against the blank and [simulation] z_range)".to_string(),
        ));
    }
    let verdict = rank_findings(&mut findings);
    let gouge = dev.max_gouge();
    let leftover = dev.max_leftover();
    Report {
        schema: SCHEMA,
        vpcut_version: report::VERSION,
        job: job.name.clone(),
        inputs: Vec::new(),
        verdict,
        finding_counts: report::FindingCounts::of(&findings),
        tolerance_mm: r6(tol),
        thread: report::ThreadInfo {
            side: match thread.side {
                Side::External => "external",
                Side::Internal => "internal",
            },
            form: job.form.name(),
            hand: match thread.hand() {
                Hand::Right => "right",
                Hand::Left => "left",
            },
            starts: thread.starts,
            major_diameter_mm: r6(major),
            minor_diameter_mm: r6(minor),
            pitch_diameter_mm: r6(2.0 * thread.pitch_radius),
            constant_width: match thread.width {
                WidthRule::Groove(_) => "groove",
                WidthRule::Tooth(_) => "tooth",
            },
            width_mm: r6(match thread.width {
                WidthRule::Groove(w) | WidthRule::Tooth(w) => w,
            }),
            lead_at_start_mm: r6(thread.helix.law.f),
            lead_change_mm: r6(thread.helix.law.k),
            turns: r6(thread.turns),
        },
        stock: report::StockInfo {
            angular_cells: grid.n_theta,
            axial_cells: grid.n_z,
            axial_spacing_mm: r6(grid.dz),
            dexels: grid.dexels() as u64 * if job.blank.bore > 0.0 { 2 } else { 1 },
            surfaces: if job.blank.bore > 0.0 {
                vec!["outer", "inner"]
            } else {
                vec!["outer"]
            },
            bytes_per_dexel: 4,
            z_min_mm: r6(grid.z(0)),
            z_max_mm: r6(grid.z(grid.n_z - 1)),
        },
        passes: job.passes.len(),
        kernel: {
            // The swept bodies' sections (the same the sweep used).
            let swept = bodies.map_or(&[][..], |b| &b.2[..]);
            report::KernelInfo {
                placements: stats.placements,
                dexel_updates: stats.dexel_updates,
                body_sections: swept.iter().map(|s| s.0).max(),
                body_sampling_bound_mm: swept
                    .iter()
                    .map(|s| s.1)
                    .reduce(f64::max)
                    .map(|b| r6(b.max(1e-6))),
            }
        },
        measurement: report::MeasurementInfo {
            axial_spacing_mm: r6(spacing),
            generators: measures.len(),
            reference_angle_deg: r4(thread.helix.theta0.to_degrees()),
        },
        deviation: report::DeviationInfo {
            max_gouge_mm: r6(gouge.map_or(0.0, |e| e.value)),
            max_gouge_at: gouge.filter(|e| r6(e.value) > 0.0).as_ref().map(location),
            max_leftover_mm: r6(leftover.map_or(0.0, |e| e.value)),
            max_leftover_at: leftover
                .filter(|e| r6(e.value) > 0.0)
                .as_ref()
                .map(location),
            gouge_volume_mm3: r6(dev.gouge_volume()),
            leftover_volume_mm3: r6(dev.leftover_volume()),
            removed_volume_mm3: r6(dev.removed_volume),
            ideal_removed_volume_mm3: r6(dev.ideal_removed_volume),
            total_removed_volume_mm3: r6(dev.total_removed_volume),
            compared_dexels: dev.compared_dexels,
            compared_z_mm: dev
                .compared_z
                .map(|(a, b)| [r6(a - 0.5 * grid.dz), r6(b + 0.5 * grid.dz)]),
            uncompared_removed_volume_mm3: r6(
                (dev.total_removed_volume - dev.removed_volume).max(0.0)
            ),
        },
        turns,
        interference: interference_rows,
        mill: None,
        findings,
        timing_s: report::Timing::default(),
    }
}

/// Finding kinds in report order.
const KINDS: [&str; 18] = [
    "not_compared",
    "hand",
    "rapid_cut",
    "head_length",
    "gouge",
    "leftover",
    "flank_interference",
    "missing_feature",
    "lead",
    "pitch_diameter",
    "groove_width",
    "tooth_width",
    "feed_limit",
    "split_feature",
    "run_in",
    "axis_acceleration",
    "program",
    "thread_chain",
];

fn turn_findings(
    row: &TurnRow,
    td: &TurnDeviation,
    all: &[&TurnMeasure],
    tol: f64,
    out: &mut Vec<Finding>,
) {
    let base = |kind, severity, value: f64, message: String| Finding {
        kind,
        severity,
        turn: Some(row.turn),
        start: Some(row.start),
        flank: None,
        pass: None,
        angle_deg: None,
        z_mm: None,
        file: None,
        line: None,
        column: None,
        value: Some(r6(value)),
        unit: Some("mm"),
        message,
    };
    for (kind, slots) in [("gouge", &td.gouge), ("leftover", &td.leftover)] {
        for f in Flank::ALL {
            let Some(e) = slots[f.index()] else { continue };
            if e.value <= tol {
                continue;
            }
            let l = location(&e);
            out.push(Finding {
                flank: Some(f.name()),
                angle_deg: Some(l.angle_deg),
                z_mm: Some(l.z_mm),
                ..base(
                    kind,
                    "error",
                    e.value,
                    format!(
                        "turn {} {}: {kind} {:.4} mm at {:.1} deg, z {:.3}",
                        row.turn,
                        f.label(),
                        e.value,
                        l.angle_deg,
                        l.z_mm
                    ),
                )
            });
        }
    }
    if all.iter().any(|m| {
        (m.ideal_groove.is_some() && m.groove.is_none())
            || (m.ideal_tooth.is_some() && m.tooth.is_none())
    }) {
        out.push(base(
            "missing_feature",
            "error",
            0.0,
            format!(
                "turn {}: a groove or tooth the drawing has is not found at the pitch diameter on some generator",
                row.turn
            ),
        ));
    }
    if let Some(err) = row.lead_spread.max_error_mm {
        if err > tol {
            out.push(base(
                "lead",
                "error",
                err,
                format!(
                    "turn {}: lead off by up to {:.4} mm (reference generator: measured {} vs ideal {})",
                    row.turn,
                    err,
                    fmt_opt(row.measured_lead_mm),
                    fmt_opt(row.ideal_lead_mm)
                ),
            ));
        }
    }
    // Widths on every generator: the worst difference from the ideal (the row shows the
    // reference generator's).
    for (kind, what, pick) in [
        (
            "groove_width",
            "groove",
            (|m: &TurnMeasure| m.ideal_groove.zip(m.groove)) as fn(&TurnMeasure) -> _,
        ),
        ("tooth_width", "tooth", |m: &TurnMeasure| {
            m.ideal_tooth.zip(m.tooth)
        }),
    ] {
        let worst = all
            .iter()
            .filter_map(|m| pick(m))
            .fold(None::<(f64, f64)>, |acc, (i, g)| match acc {
                Some((ai, ag)) if (ag - ai).abs() >= (g - i).abs() => Some((ai, ag)),
                _ => Some((i, g)),
            });
        if let Some((i, g)) = worst {
            if (g - i).abs() > tol {
                out.push(base(
                    kind,
                    "error",
                    g - i,
                    format!(
                        "turn {}: {what} width {g:.4} mm, drawing {i:.4} mm",
                        row.turn
                    ),
                ));
            }
        }
    }
    if all.iter().any(|m| m.split) {
        out.push(base(
            "split_feature",
            "warning",
            0.0,
            format!(
                "turn {}: a ridge or notch crosses the pitch diameter inside one feature",
                row.turn
            ),
        ));
    }
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.4}"))
}
