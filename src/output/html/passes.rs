//! Which pass made a deviation finding: the dexel of a gouge or leftover finding is re-cut
//! pass by pass with the kernel's free-standing column ([`sweep_column`]), and the first
//! pass whose own cut reaches the dexel's final value is the one that left it there (with
//! tool bodies, whose grid sweep is tabulated, the pass that cut it deepest). For a
//! job with an NC program the pass's thread block (file and line) comes with it.
//!
//! The dexel is the exact place of the turn and flank's extreme the finding reports (the
//! report rounds the angle to 0.1 deg). Also where each located finding is on the cut
//! surface (the point the 3D view flies to).

use crate::analysis::findings::FindingKind;
use crate::job::Job;
use crate::kernel::sweep::{sweep_column, Column};
use crate::model::stock::{Stock, Surface};
use crate::model::thread::{Flank, Side};
use crate::pipeline::Outcome;
use crate::report::Finding;
use std::f64::consts::TAU;

/// The pass that cut a finding's dexel deepest.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FindingPass {
    /// The pass (1-based, as the report counts them).
    pub pass: usize,
    /// Its thread block in the NC program, for program jobs: the file as the job names it
    /// and the 1-based line.
    pub block: Option<(String, usize)>,
}

/// How close a pass's own cut must come to the dexel's final value (mm): the stock holds
/// `f32`, the re-cut the same `f32` arithmetic, so they agree far closer than this.
const SAME_CUT_MM: f64 = 1e-5;

/// The surface the thread is on.
fn thread_surface(job: &Job) -> Surface {
    match job.thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    }
}

/// Where a finding is: the angle (rad) and axial position (mm). A gouge or leftover's are
/// the exact ones of its turn and flank's extreme (the report rounds them); the others',
/// the report's.
fn place(out: &Outcome, f: &Finding) -> Option<(f64, f64)> {
    let exact = || {
        let t = out.deviation.turns.get(&(f.start?, f.turn?))?;
        let k = Flank::ALL.iter().position(|&x| Some(x) == f.flank)?;
        let e = match f.kind {
            FindingKind::Gouge => t.gouge[k],
            FindingKind::Leftover => t.leftover[k],
            _ => None,
        }?;
        Some((e.theta, e.z))
    };
    exact().or_else(|| Some((f.angle_deg?.to_radians(), f.z_mm?)))
}

/// The dexel (column, cell) nearest to an angle (rad) and an axial position (mm).
fn dexel(stock: &Stock, theta: f64, z: f64) -> Option<(usize, usize)> {
    let g = &stock.grid;
    if g.n_theta == 0 || g.n_z == 0 || !theta.is_finite() || !z.is_finite() {
        return None;
    }
    let turns = (theta - g.theta0) / TAU;
    let i = ((turns - turns.floor()) * g.n_theta as f64).round() as usize % g.n_theta;
    let j = ((z - g.z0) / g.dz).round();
    if j < 0.0 || j >= g.n_z as f64 {
        return None;
    }
    Some((i, j as usize))
}

/// Where a finding with an angle and an axial position is on the cut surface (mm, part
/// frame), if the stock has that dexel.
pub fn finding_point(out: &Outcome, job: &Job, f: &Finding) -> Option<[f32; 3]> {
    let stock = &out.stock;
    let (theta, z) = place(out, f)?;
    let s = thread_surface(job);
    let (i, j) = dexel(stock, theta, z)?;
    let r = stock.radius(s, i, j)?;
    let t = stock.grid.theta(i);
    Some([(r * t.cos()) as f32, (r * t.sin()) as f32, z as f32])
}

/// For every finding of `findings` (in order): the pass that cut its dexel, for gouge and
/// leftover findings on a turning job's stock; `None` for the others, for milling jobs and
/// where no pass cut the dexel at all.
pub fn finding_passes(job: &Job, out: &Outcome, findings: &[Finding]) -> Vec<Option<FindingPass>> {
    findings
        .iter()
        .map(|f| match f.kind {
            FindingKind::Gouge | FindingKind::Leftover if job.mill.is_none() => {
                let (theta, z) = place(out, f)?;
                pass_of(job, &out.stock, theta, z)
            }
            _ => None,
        })
        .collect()
}

/// The first pass whose own cut reaches the final value of the dexel at `theta`, `z`
/// (else the one that cut it deepest).
fn pass_of(job: &Job, stock: &Stock, theta: f64, z: f64) -> Option<FindingPass> {
    let s = thread_surface(job);
    let (i, j) = dexel(stock, theta, z)?;
    let g = &stock.grid;
    let fin = f64::from(*stock.surface(s)?.get(i * g.n_z + j)?);
    if fin >= 0.0 {
        // Blank: nothing cut this dexel.
        return None;
    }
    let c = Column {
        theta: g.theta(i),
        z0: g.z0,
        dz: g.dz,
        q_blank: stock.blank_q(s),
        surface: s,
    };
    let mut col = vec![0f32; g.n_z];
    // Each pass's own cut of the dexel; the grid's sweep tabulates tool bodies where this
    // samples them, so a body's cut may differ a little: the deepest cut wins, the first
    // pass among equals.
    let cuts: Vec<f64> = job
        .passes
        .iter()
        .map(|p| {
            col.fill(0.0);
            sweep_column(&mut col, c, std::slice::from_ref(p), &job.tools);
            f64::from(col[j])
        })
        .collect();
    let deepest = cuts.iter().copied().fold(f64::INFINITY, f64::min);
    if deepest >= 0.0 {
        return None;
    }
    let k = cuts
        .iter()
        .position(|&v| v <= deepest.max(fin) + SAME_CUT_MM)?;
    let block = job
        .pass_blocks
        .iter()
        .find(|b| b.0 == k)
        .map(|b| (b.1.clone(), b.2));
    Some(FindingPass { pass: k + 1, block })
}
