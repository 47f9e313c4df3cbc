//! Where each located finding is on the cut surface: the point the page's 3D view flies
//! to. A gouge or leftover's is the dexel of the exact extreme of its turn and flank (the
//! report rounds the angle to 0.1 deg). Which pass and NC block made a finding is the
//! report's own (`report::blame`): the page shows those fields, it does not work them out
//! again.

use crate::analysis::findings::FindingKind;
use crate::job::Job;
use crate::model::stock::{Stock, Surface};
use crate::model::thread::{Flank, Side};
use crate::pipeline::Outcome;
use crate::report::Finding;
use std::f64::consts::TAU;

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
