//! The root radius of an external thread, measured on the cut as ISO 965-1 states it: the
//! root contour has no part with a radius under `R_min` (0.125P). A contour has that
//! radius everywhere when a disk of radius `R` rolled along it from the air side reaches
//! every point of it (the surface equals its opening by the disk); at a corner sharper
//! than `R` the disk stays off by the *gap*, `(R - rho)(1/sin(b/2) - 1)` for an arc of
//! radius `rho` joining two straight sides at an angle `b` (the flanks of a V root: b = the
//! flank angle; a flat root's corners: b = 90 deg + a/2). The effective root radius of a
//! turn is the largest `R` whose disk fills the turn's root (below the pitch line) to the
//! stored radii's rounding: the arc's radius for a round root, 0 for a sharp corner.
//!
//! Computed on the measurement generators' cuts, every complete turn, thinned to about a
//! hundredth of `R_min` along z: the resolution is that step times the flank's slope.
//! Pure.

use super::GaugeColumn;
use crate::analysis::measure::TurnMeasure;
use crate::model::thread::ThreadSpec;

/// Centres per sample step: the disks' centres lie on a grid four times finer than the
/// samples (on a grid as coarse as the samples a disk cannot follow a root arc of nearly
/// its own radius: its centres' path is then a small circle).
const SUB: usize = 4;

/// The disk's gap on one sampled profile: heights `h` (above the root, increasing towards
/// the air) at spacing `step`, the largest `E - h` over the cells `eval` (indices) where
/// `E` is the lower boundary of the union of every disk of radius `r` centred on the
/// sub-grid ([`SUB`]) that lies above the samples.
pub(super) fn gap(h: &[f64], step: f64, r: f64, eval: (usize, usize)) -> f64 {
    let n = h.len();
    let (e0, e1) = (eval.0.min(n), eval.1.min(n));
    if e0 >= e1 || r <= 0.0 {
        return 0.0;
    }
    let m = (r / step).floor() as usize + 1;
    let width = 2 * m + 1;
    // w[k][d]: the disk's half-height at sample offset `d - m` from a centre `k/SUB` of a
    // step past its grid sample; negative where the sample is beyond the disk.
    let w: Vec<Vec<f64>> = (0..SUB)
        .map(|k| {
            (0..width)
                .map(|d| {
                    let off = (d as f64 - m as f64 - k as f64 / SUB as f64) * step;
                    let q = r * r - off * off;
                    if q >= 0.0 {
                        q.sqrt()
                    } else {
                        -1.0
                    }
                })
                .collect()
        })
        .collect();
    // Centres that can reach an evaluated cell, and the lowest each can sit.
    let c0 = e0.saturating_sub(m);
    let c1 = (e1 + m).min(n);
    let centre: Vec<[f64; SUB]> = (c0..c1)
        .map(|j| {
            let mut c = [f64::NEG_INFINITY; SUB];
            let (a, b) = (j.saturating_sub(m), (j + m + 1).min(n));
            for (k, ck) in c.iter_mut().enumerate() {
                for i in a..b {
                    let wk = w[k][i + m - j];
                    if wk >= 0.0 {
                        *ck = ck.max(h[i] + wk);
                    }
                }
            }
            c
        })
        .collect();
    let mut worst = 0.0f64;
    for i in e0..e1 {
        let (a, b) = (i.saturating_sub(m).max(c0), (i + m + 1).min(c1));
        let mut e = f64::INFINITY;
        for j in a..b {
            for k in 0..SUB {
                let wk = w[k][i + m - j];
                if wk >= 0.0 {
                    e = e.min(centre[j - c0][k] - wk);
                }
            }
        }
        worst = worst.max(e - h[i]);
    }
    worst
}

/// One turn's root: its heights thinned to `step`, and the cells to evaluate (below the
/// pitch line within half a pitch of the groove's centre).
struct Root {
    h: Vec<f64>,
    step: f64,
    eval: (usize, usize),
    turn: i64,
}

/// The least effective root radius over the complete turns of every generator (mm), capped
/// at `cap`, the turn it was found on, and the resolution (mm): `(rho, turn, resolution)`.
/// `None` without a complete turn.
pub(super) fn root_radius(
    thread: &ThreadSpec,
    columns: &[GaugeColumn],
    turns: &[Vec<TurnMeasure>],
    r_min: f64,
    cap: f64,
    rounding: f64,
) -> Option<(f64, i64, f64)> {
    let pitch = thread.pitch_of_turn(1);
    let level = thread.pitch_height();
    let mut roots = Vec::new();
    let mut step_used = 0.0f64;
    for (c, measured) in columns.iter().zip(turns) {
        let s = ((r_min / 100.0) / c.dz).round().max(1.0) as usize;
        let step = s as f64 * c.dz;
        step_used = step_used.max(step);
        for m in measured.iter().filter(|m| m.pitch_diameter.is_some()) {
            let zc = thread.helix.z(m.t);
            // The groove and a disk's reach beyond it on either side.
            let reach = 0.5 * pitch + 2.0 * cap;
            let j0 = ((zc - reach - c.z0) / c.dz).ceil().max(0.0) as usize;
            let j1 = (((zc + reach - c.z0) / c.dz).floor().max(0.0) as usize).min(c.h.len());
            if j1 <= j0 + 2 {
                continue;
            }
            let h: Vec<f64> = (j0..j1).step_by(s).map(|j| c.h[j] as f64).collect();
            let z_of = |i: usize| c.z0 + (j0 + i * s) as f64 * c.dz;
            let inside = |i: usize| (z_of(i) - zc).abs() <= 0.5 * pitch && h[i] < level;
            let Some(first) = (0..h.len()).find(|&i| inside(i)) else {
                continue;
            };
            let last = (0..h.len()).rev().find(|&i| inside(i)).unwrap_or(first);
            roots.push(Root {
                h,
                step,
                eval: (first, last + 1),
                turn: m.turn,
            });
        }
    }
    if roots.is_empty() {
        return None;
    }
    // The thinning's error: a corner between two samples may lie a step's slope beyond
    // them (the flank's slope, cot of its angle from the radial; at least 1).
    let cot = 1.0 / thread.left_angle.min(thread.right_angle).tan().max(1e-9);
    let resolution = step_used * (cot.max(1.0) + 0.05) + rounding;
    // A disk fits where its gap is within the rounding and the centres' grid's own
    // shortfall (a twentieth of the step: measured on sampled arcs, below 0.04 steps).
    let fits =
        |root: &Root, r: f64| gap(&root.h, root.step, r, root.eval) <= rounding + 0.05 * root.step;
    // The least radius over the turns: each turn is bisected only below the least so far.
    let mut best = (cap, roots[0].turn);
    for root in &roots {
        if fits(root, best.0) {
            continue;
        }
        let (mut lo, mut hi) = (0.0, best.0);
        while hi - lo > 1e-5 {
            let mid = 0.5 * (lo + hi);
            if fits(root, mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        best = (lo, root.turn);
    }
    Some((best.0, best.1, resolution))
}
