//! A lathe program's cycle time from its moves: rapids at the machine's rapid rate along
//! their path (interpolated), feed and arc moves at their feed (per minute, or per
//! revolution at the spindle speed there: under G96 it changes with the diameter, and
//! the time is the exact integral along the move), thread moves at the lead times the
//! speed (their spindle revolutions from the lead law), each unchained thread move's wait
//! for the one-rev signal (half a revolution, the mean over where the spindle happens to
//! be), and the dwells. Not modelled: acceleration, tool changes, spindle run-up. The
//! program's first move starts where the machine happens to be (the interpreter starts at
//! the work zero): it is not counted.

use crate::kernel::turn::{TurnPath, TurningTool};
use crate::model::helix::LeadLaw;
use crate::model::setup::{CycleTime, Machine, DEFAULT_RAPID_RATE};
use crate::nc::{self, DwellTime, MoveKind, SpindleSpeed};

/// Minutes per revolution `1/n` with the tool at diameter `x`: G97's speed (or the
/// machine's where the program set none), G96's `pi |x| / (1000 v)` held up by its clamp.
fn min_per_rev(speed: &SpindleSpeed, x: f64, default_rpm: f64) -> f64 {
    match speed.surface {
        Some(v) => {
            let n = std::f64::consts::PI * x.abs() / (1000.0 * v);
            speed.max.map_or(n, |m| n.max(1.0 / m))
        }
        None => 1.0 / speed.rpm.unwrap_or(default_rpm),
    }
}

/// The mean of `max(c, k |x0 + (x1 - x0) t|)` over `t` in `[0, 1]`, exactly: G96's minutes
/// per revolution along a straight move (`c` the clamp's, `k = pi / (1000 v)`).
fn mean_clamped_abs(c: f64, k: f64, x0: f64, x1: f64) -> f64 {
    // Break [0, 1] where |x| crosses 0 and where k |x| crosses c; on each piece the
    // integrand is linear: the trapezoid rule is exact.
    let f = |t: f64| c.max(k * (x0 + (x1 - x0) * t).abs());
    let mut cuts = vec![0.0, 1.0];
    if x1 != x0 {
        for target in [0.0, c / k, -c / k] {
            if target.is_finite() {
                let t = (target - x0) / (x1 - x0);
                if t > 0.0 && t < 1.0 {
                    cuts.push(t);
                }
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2)
        .map(|w| 0.5 * (f(w[0]) + f(w[1])) * (w[1] - w[0]))
        .sum()
}

/// The mean minutes per revolution along a straight move from diameter `x0` to `x1`.
fn mean_min_per_rev(speed: &SpindleSpeed, x0: f64, x1: f64, default_rpm: f64) -> f64 {
    match speed.surface {
        Some(v) => {
            let c = speed.max.map_or(0.0, |m| 1.0 / m);
            mean_clamped_abs(c, std::f64::consts::PI / (1000.0 * v), x0, x1)
        }
        None => min_per_rev(speed, x0, default_rpm),
    }
}

/// The cycle time of `moves` and `dwells` on `machine`.
pub(crate) fn cycle_time(moves: &[nc::Move], dwells: &[nc::Dwell], machine: &Machine) -> CycleTime {
    let rate = machine.rapid_rate.unwrap_or(DEFAULT_RAPID_RATE);
    let rpm = machine.spindle_rpm;
    let mut out = CycleTime {
        rapid_rate: rate,
        rapid_rate_given: machine.rapid_rate.is_some(),
        ..CycleTime::default()
    };
    let add = |out: &mut CycleTime, m: Option<&nc::Move>, s: f64| {
        let tool = m.and_then(|m| m.tool);
        match out.by_tool.iter_mut().find(|t| t.0 == tool) {
            Some(t) => t.1 += s,
            None => {
                out.by_tool.push((tool, s));
                out.tool_words
                    .push(m.and_then(|m| m.tool_word.as_deref()).map(str::to_string));
            }
        }
    };
    for m in moves.iter().skip(1) {
        let (dr, dz) = ((m.x_dia - m.x_start) / 2.0, m.z - m.z_start);
        let len = dr.hypot(dz);
        let minutes = |out: &mut CycleTime| -> f64 {
            match m.kind {
                MoveKind::Rapid => {
                    let t = len / rate;
                    out.rapid += 60.0 * t;
                    t
                }
                MoveKind::Feed | MoveKind::Arc => {
                    let (len, per_rev) = match (m.kind, m.arc) {
                        (MoveKind::Arc, Some(a)) => arc_length_and_mean(m, &a, rpm),
                        _ => (len, mean_min_per_rev(&m.speed, m.x_start, m.x_dia, rpm)),
                    };
                    let t = match m.feed {
                        Some(f) if f.per_rev => len / f.value * per_rev,
                        Some(f) => len / f.value,
                        None => 0.0,
                    };
                    out.feed += 60.0 * t;
                    t
                }
                MoveKind::Thread => {
                    let law = LeadLaw {
                        f: m.lead.unwrap_or(0.0),
                        k: m.lead_change.unwrap_or(0.0),
                    };
                    let revs = law.revs_at(dz.abs()).unwrap_or(0.0);
                    let t = revs * mean_min_per_rev(&m.speed, m.x_start, m.x_dia, rpm);
                    out.thread += 60.0 * t;
                    // A thread move that is not chained waits for the one-rev signal.
                    let wait = if m.chained {
                        0.0
                    } else {
                        0.5 * min_per_rev(&m.speed, m.x_start, rpm)
                    };
                    out.wait += 60.0 * wait;
                    t + wait
                }
            }
        };
        let t = minutes(&mut out);
        add(&mut out, Some(m), 60.0 * t);
    }
    for d in dwells {
        let s = match d.time {
            DwellTime::Seconds(s) => s,
            DwellTime::Revolutions(r) => 60.0 * r * min_per_rev(&d.speed, d.x, rpm),
        };
        out.wait += s;
        let m = d.after.checked_sub(1).and_then(|i| moves.get(i));
        add(&mut out, m, s);
    }
    out
}

/// An arc move's length and its mean minutes per revolution (under G96 the diameter
/// changes along it: the mean over 256 equal steps of its angle, Simpson's rule).
fn arc_length_and_mean(m: &nc::Move, a: &nc::ArcGeometry, rpm: f64) -> (f64, f64) {
    let needle = TurningTool::turning(0, 0.0, (0.0, 0.0), false);
    let path = TurnPath::of_move(
        &needle,
        1.0,
        (m.z_start, m.x_start),
        (m.z, m.x_dia),
        Some(((a.z_centre, a.x_centre_dia), a.clockwise)),
    );
    let TurnPath::Arc {
        centre,
        radius,
        start,
        sweep,
    } = path
    else {
        return (0.0, min_per_rev(&m.speed, m.x_start, rpm));
    };
    const N: usize = 256;
    let x = |k: usize| 2.0 * (centre.1 + radius * (start + sweep * k as f64 / N as f64).sin());
    let sum: f64 = (0..=N)
        .map(|k| {
            let w = if k == 0 || k == N {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * min_per_rev(&m.speed, x(k), rpm)
        })
        .sum();
    (radius * sweep.abs(), sum / (3.0 * N as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clamped_mean_is_the_integral() {
        // max(c, k|x|) over x from -10 to 30 (t: x = -10 + 40 t) with c = 1, k = 0.1: |x|
        // below 10 is clamped. By hand: over x in [-10, 10] the value is 1 (half the t
        // range); over [10, 30] it rises 1 -> 3, mean 2; total 0.5 x 1 + 0.5 x 2 = 1.5.
        assert!((mean_clamped_abs(1.0, 0.1, -10.0, 30.0) - 1.5).abs() < 1e-12);
        // Unclamped, k |x| from 20 to 40: 0.1 x 30 = 3.
        assert!((mean_clamped_abs(0.0, 0.1, 20.0, 40.0) - 3.0).abs() < 1e-12);
        // Through the axis unclamped: |x| from 10 down to 0 and up to 10, mean 5 k.
        assert!((mean_clamped_abs(0.0, 0.1, 10.0, -10.0) - 0.5).abs() < 1e-12);
    }
}
