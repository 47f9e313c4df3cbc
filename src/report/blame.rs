//! Every finding at its source: the NC block whose pass or turning move made a deviation
//! (the dexel of the extreme re-cut by each pass alone and by each turning move alone: the
//! deepest cut is the one that left the surface there, turning moves first among equals as
//! a lathe program turns before it threads; a thread-milling job's dexel re-cut by each
//! mill move alone), the thread block of a machine check's pass, and for what no block
//! made, the job file's key (`pass[2]`, `thread.z_start`).
//!
//! The report's per-turn measurement findings (lead, widths, missing and split features)
//! are blamed at their turn's worst deviation: the place the turn is most off; where the
//! turn's own surface is within the tolerance, its width is off because a neighbour's
//! groove is (another start's, one turn on either side), and it goes to that worst
//! deviation.

use crate::analysis::compare::{Deviation, Extreme, TurnDeviation};
use crate::analysis::findings::{Finding, FindingKind};
use crate::job::Job;
use crate::kernel::mill::mill_column_by;
use crate::kernel::sweep::{sweep_column, Column};
use crate::kernel::turn::envelope;
use crate::model::stock::Surface;
use crate::model::thread::{Flank, Side};
use std::fmt::Write as _;

/// What cut a dexel last to its final depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Maker {
    /// A threading pass (0-based index into `Job::passes`).
    Pass(usize),
    /// A turning (feed or arc) move of the program, 0-based in its surface's moves.
    Move(usize),
    /// A milling move (0-based in `MillJob::moves`, the path's moves).
    Mill(usize),
}

/// How close a cut must come to the deepest to count as reaching it (mm): the stock holds
/// `f32`, the re-cut the same arithmetic, so equal cuts agree far closer than this.
const SAME_CUT_MM: f64 = 1e-5;

/// The thread's surface, its blank radius (signed: negative inside) and its floor.
fn surface(job: &Job) -> (Surface, f64, f64) {
    let b = &job.blank;
    match job.thread.side {
        Side::External => (Surface::Outer, b.diameter / 2.0, b.bore / 2.0),
        Side::Internal => (Surface::Inner, -b.bore / 2.0, -b.diameter / 2.0),
    }
}

/// What made the dexel at `theta`, `z` of the thread's surface: the deepest of every pass's
/// and every turning move's own cut (turning first, then passes in order, among equals), or
/// of a milling job's every move's; where nothing cut it, the pass (move) whose cut comes
/// nearest within `reach` mm along the axis; `None` where there is none.
pub(crate) fn maker_at(job: &Job, theta: f64, z: f64, dz: f64, reach: f64) -> Option<Maker> {
    if !theta.is_finite() || !z.is_finite() {
        return None;
    }
    let (s, q_blank, q_floor) = surface(job);
    let c = Column {
        theta,
        z0: z,
        dz: dz.max(1e-9),
        q_blank,
        surface: s,
    };
    if job.mill.is_some() {
        return mill_maker(job, c, reach);
    }
    let mut cuts: Vec<(Maker, f64)> = Vec::new();
    let turned = match s {
        Surface::Outer => &job.turning.outer,
        Surface::Inner => &job.turning.inner,
    };
    for (i, cut) in turned.cuts.iter().enumerate() {
        let Some((lo, hi)) = cut.span(q_blank) else {
            continue;
        };
        if z < lo || z > hi {
            continue;
        }
        let e = envelope(&cut.tool, &cut.path, z);
        let v = e.max(q_floor) - q_blank;
        if v < 0.0 {
            cuts.push((Maker::Move(i), v));
        }
    }
    let mut col = [0f32; 1];
    for (k, p) in job.passes.iter().enumerate() {
        col[0] = 0.0;
        sweep_column(&mut col, c, std::slice::from_ref(p), &job.tools);
        let v = f64::from(col[0]);
        if v < 0.0 {
            cuts.push((Maker::Pass(k), v));
        }
    }
    deepest(&cuts).or_else(|| nearest_pass(job, c, reach))
}

/// Of the cuts `(maker, signed depth)`, in order, the first within [`SAME_CUT_MM`] of the
/// deepest.
fn deepest(cuts: &[(Maker, f64)]) -> Option<Maker> {
    let deepest = cuts.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    cuts.iter()
        .find(|c| c.1 <= deepest + SAME_CUT_MM)
        .map(|c| c.0)
}

/// A milling job's move that made the dexel of column `c` (one cell): the deepest of each
/// move's own cut, the first among equals; where none cut it, the move whose cut comes
/// nearest within `reach` mm along the axis.
fn mill_maker(job: &Job, c: Column, reach: f64) -> Option<Maker> {
    let mj = job.mill.as_ref()?;
    let n_moves = mj.path.moves.len();
    let cut =
        |q: &mut [f32], col: Column, m: usize| mill_column_by(q, col, &mj.path, m, &mj.cutters);
    let mut cuts: Vec<(Maker, f64)> = Vec::new();
    let mut col = [0f32; 1];
    for m in 0..n_moves {
        col[0] = 0.0;
        cut(&mut col, c, m);
        let v = f64::from(col[0]);
        if v < 0.0 {
            cuts.push((Maker::Mill(m), v));
        }
    }
    deepest(&cuts).or_else(|| nearest(c, reach, n_moves, &cut).map(Maker::Mill))
}

/// The pass whose cut comes nearest along the axis to a dexel no pass cut (within `reach`
/// mm either side: the thread's length): the one that left it standing. The first pass
/// among equals.
fn nearest_pass(job: &Job, c: Column, reach: f64) -> Option<Maker> {
    let cut = |q: &mut [f32], col: Column, k: usize| {
        sweep_column(q, col, std::slice::from_ref(&job.passes[k]), &job.tools);
    };
    nearest(c, reach, job.passes.len(), &cut).map(Maker::Pass)
}

/// Of `count` cutters (`cut(q, column, k)` cuts with the k-th alone), the one whose cut
/// comes nearest along the axis to the cell of `c`, within `reach` mm either side; the
/// first among equals.
fn nearest(
    c: Column,
    reach: f64,
    count: usize,
    cut: &dyn Fn(&mut [f32], Column, usize),
) -> Option<usize> {
    let n = ((reach / c.dz).ceil() as usize).clamp(1, 100_000);
    let col = Column {
        z0: c.z0 - n as f64 * c.dz,
        ..c
    };
    let mut q = vec![0f32; 2 * n + 1];
    let mut best: Option<(usize, usize)> = None;
    for k in 0..count {
        q.fill(0.0);
        cut(&mut q, col, k);
        let near = q
            .iter()
            .enumerate()
            .filter(|(_, v)| **v < 0.0)
            .map(|(j, _)| j.abs_diff(n))
            .min();
        if let Some(d) = near {
            if best.is_none_or(|b| d < b.1) {
                best = Some((k, d));
            }
        }
    }
    best.map(|b| b.0)
}

/// The program block (file, 1-based line) of what made a dexel; or the job key of a pass
/// that does not come from the program.
fn source_of(job: &Job, m: Maker) -> (Option<(String, usize)>, Option<String>) {
    let (s, _, _) = surface(job);
    match m {
        Maker::Pass(k) => match job.pass_blocks.iter().find(|b| b.0 == k) {
            Some(b) => (Some((b.1.clone(), b.2)), None),
            None => (None, Some(pass_key(job, k))),
        },
        Maker::Move(i) => {
            let blocks = match s {
                Surface::Outer => &job.turning.outer_blocks,
                Surface::Inner => &job.turning.inner_blocks,
            };
            (blocks.get(i).cloned(), None)
        }
        Maker::Mill(i) => (
            job.mill
                .as_ref()
                .and_then(|mj| mj.moves.get(i))
                .map(|m| (m.file.clone(), m.line)),
            None,
        ),
    }
}

/// The job key of a pass that no program block made: its `[[pass]]` table, else the
/// `[process]` that generated it.
fn pass_key(job: &Job, k: usize) -> String {
    if k < job.explicit_passes {
        format!("pass[{k}]")
    } else {
        "process".to_string()
    }
}

/// The turn's worst deviation (gouge or leftover, any flank).
fn worst(td: &TurnDeviation) -> Option<Extreme> {
    match (td.max_gouge(), td.max_leftover()) {
        (Some(g), Some(l)) => Some(if l.value > g.value { l } else { g }),
        (g, l) => g.or(l),
    }
}

/// The exact extreme a deviation finding reports (its turn and flank's), or the turn's
/// worst for the turn's measurement findings: where that is within `tol`, the worst of
/// the turns of every start within one turn of it beyond `tol` (the first among equals).
fn extreme_of(dev: &Deviation, f: &Finding, tol: f64) -> Option<Extreme> {
    let (start, turn) = (f.start?, f.turn?);
    let td = dev.turns.get(&(start, turn))?;
    let near = || {
        let own = worst(td);
        if own.is_some_and(|e| e.value > tol) {
            return own;
        }
        let mut best: Option<Extreme> = None;
        for e in dev
            .turns
            .iter()
            .filter(|((_, n), _)| n.abs_diff(turn) <= 1)
            .filter_map(|(_, t)| worst(t))
        {
            if e.value > tol && best.is_none_or(|b| e.value > b.value) {
                best = Some(e);
            }
        }
        best.or(own)
    };
    match f.kind {
        FindingKind::Gouge | FindingKind::Leftover => {
            let k = Flank::ALL.iter().position(|&x| Some(x) == f.flank)?;
            if f.kind == FindingKind::Gouge {
                td.gouge[k]
            } else {
                td.leftover[k]
            }
        }
        FindingKind::Lead
        | FindingKind::GrooveWidth
        | FindingKind::ToothWidth
        | FindingKind::MissingFeature
        | FindingKind::SplitFeature
        | FindingKind::PitchDiameter => near(),
        _ => None,
    }
}

/// The key of the job's table a finding that no block made is about: for a deviation or a
/// measurement no pass reached, what should have cut it (the program, the process, the
/// passes).
fn table_key(job: &Job, f: &Finding) -> &'static str {
    use FindingKind as K;
    match f.kind {
        K::Placement => "thread.z_start",
        K::NotCompared => "simulation.z_range",
        K::Gauge => "thread.designation",
        K::FeedLimit | K::RunIn | K::AxisAcceleration => "machine",
        K::FlankInterference | K::HeadLength | K::DepthPerPass | K::InfeedAngle => "tool",
        K::Program | K::RapidCut => "program",
        _ if job.mill.is_some() || !job.pass_blocks.is_empty() => "program",
        _ if job.explicit_passes < job.passes.len() => "process",
        _ if job.explicit_passes > 0 => "pass",
        _ => "thread",
    }
}

/// Give every finding of `findings` its source: an NC block (file, line, column 1) where a
/// pass or a move of the program made it, else the job key. Findings that have a place
/// keep it.
pub(crate) fn locate(job: &Job, dev: &Deviation, findings: &mut [Finding]) {
    // The thread's length and a lead either side: a block that stops short leaves the
    // turns after it uncut, and it is the nearest pass's.
    let law = job.thread.helix.law;
    let lead = law.f.abs().max(law.lead(job.thread.turns).abs());
    let reach = lead * (job.thread.turns.abs() + 1.0);
    for f in findings.iter_mut() {
        if f.file.is_some() && f.line.is_some() {
            continue;
        }
        // What made it: the pass a check is about, else the dexel's cutter.
        let check = f
            .pass
            .filter(|&p| p >= 1 && !matches!(f.kind, FindingKind::Gouge | FindingKind::Leftover));
        let maker = match check {
            Some(p) => Some(Maker::Pass(p - 1)),
            None => {
                let at = extreme_of(dev, f, job.sim.tolerance)
                    .map(|e| (e.theta, e.z))
                    .or_else(|| match f.kind {
                        FindingKind::FlankInterference => {
                            Some((f.angle_deg?.to_radians(), f.z_mm?))
                        }
                        _ => None,
                    });
                at.and_then(|(theta, z)| maker_at(job, theta, z, dev_dz(job), reach))
            }
        };
        if let Some(m) = maker {
            if let Maker::Pass(k) = m {
                f.pass.get_or_insert(k + 1);
                // The pass that cut (or left) the dexel, and its tool as written.
                if check.is_none() {
                    let _ = write!(f.message, ", pass {} with {}", k + 1, job.pass_tool_name(k));
                }
            }
            let (block, key) = source_of(job, m);
            if let Some((file, line)) = block {
                f.file = Some(file);
                f.line = Some(line);
                f.column.get_or_insert(1);
                continue;
            }
            if key.is_some() {
                f.key = key;
                continue;
            }
        }
        if f.key.is_none() {
            f.key = Some(table_key(job, f).to_string());
        }
    }
}

/// The axial spacing of the cells the job is simulated on (only the width of the one cell
/// re-cut: the cut at a cell's centre does not depend on it).
fn dev_dz(job: &Job) -> f64 {
    job.sim.axial_spacing
}
