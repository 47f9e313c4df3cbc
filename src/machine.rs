//! Machine checks: feed limit, run-in length and axial acceleration of each pass.
//!
//! - **Feed**: the axis feed is lead x rpm; with a variable lead the worst case is at the
//!   end with the larger lead (`domain.md` §5).
//! - **Run-in**: the axis needs `v^2 / (2a)` to reach the synchronous speed `v = L * rpm/60`
//!   from rest; a pass that starts closer to the material than that cuts its first turn
//!   with a lagging lead.
//! - **Acceleration**: a variable lead needs a constant axial acceleration `K * (rpm/60)^2`
//!   during the cut; more than the axis can give and it falls behind.
//! - **Thread chains**: a thread block that continues the previous one without waiting for
//!   the one-rev signal (continuous threading, `nc::chain`) but programs another lead law
//!   (a different start lead or lead change): the lead jumps at the joint, which no axis
//!   can follow (a velocity step of `dL x rpm`); Rockwell 9/Series: "Do not re-program the
//!   G34 command in consecutive threading blocks. Doing so will cause the control to pause
//!   axis motion ... while the axis re-synchronizes with the spindle." A warning: vpcut
//!   cuts the programmed laws with the phase running on, and what the real axis does at the
//!   joint (lag, or a pause and re-sync) is control-specific, so the cut shown there may
//!   not be the machine's.

use crate::job::{Blank, ChainLink, Machine};
use crate::pass::Pass;

/// A machine check that failed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MachineIssue {
    /// `feed_limit`, `run_in` or `axis_acceleration`.
    pub kind: &'static str,
    /// Whether it makes the job fail.
    pub error: bool,
    /// Pass index.
    pub pass: usize,
    /// Where (mm).
    pub z: f64,
    /// The value that broke the limit (mm/min, mm, mm/s^2).
    pub value: f64,
    /// The limit.
    pub limit: f64,
    /// One line for a person.
    pub message: String,
}

/// Check every pass against the machine.
pub(crate) fn check(passes: &[Pass], machine: &Machine, blank: &Blank) -> Vec<MachineIssue> {
    let mut out = Vec::new();
    let rps = machine.spindle_rpm / 60.0;
    let z_back = blank.z_front - blank.length;
    for (i, p) in passes.iter().enumerate() {
        let Some(end_lead) = p.end_lead() else {
            continue;
        };
        let (lead_max, z_at) = if end_lead > p.lead {
            (end_lead, p.z_end)
        } else {
            (p.lead, p.z_start)
        };
        if let Some(max_feed) = machine.max_feed {
            let feed = lead_max * machine.spindle_rpm;
            if feed > max_feed {
                out.push(MachineIssue {
                    kind: "feed_limit",
                    error: true,
                    pass: i,
                    z: z_at,
                    value: feed,
                    limit: max_feed,
                    message: format!(
                        "pass {}: lead {:.4} mm/rev x {} rpm = {:.1} mm/min exceeds max_feed {} mm/min",
                        i + 1,
                        lead_max,
                        machine.spindle_rpm,
                        feed,
                        max_feed
                    ),
                });
            }
        }
        if let Some(a) = machine.acceleration {
            let v = p.lead * rps;
            let needed = v * v / (2.0 * a);
            let available = if p.z_end < p.z_start {
                p.z_start - blank.z_front
            } else {
                z_back - p.z_start
            }
            .max(0.0);
            if available < needed {
                out.push(MachineIssue {
                    kind: "run_in",
                    error: false,
                    pass: i,
                    z: p.z_start,
                    value: available,
                    limit: needed,
                    message: format!(
                        "pass {}: {:.3} mm of run-in before the blank, the axis needs {:.3} mm to reach {:.2} mm/s at {} mm/s^2",
                        i + 1,
                        available,
                        needed,
                        v,
                        a
                    ),
                });
            }
            let acc = p.lead_change.abs() * rps * rps;
            if acc > a {
                out.push(MachineIssue {
                    kind: "axis_acceleration",
                    error: false,
                    pass: i,
                    z: p.z_start,
                    value: acc,
                    limit: a,
                    message: format!(
                        "pass {}: a lead change of {} mm/rev^2 at {} rpm needs {:.1} mm/s^2 of axial acceleration, more than {} mm/s^2",
                        i + 1,
                        p.lead_change,
                        machine.spindle_rpm,
                        acc,
                        a
                    ),
                });
            }
        }
    }
    out
}

/// A chained block may program its start lead rounded to the least input increment
/// (0.001 mm) and still continue the previous law: half of it is the tolerance.
pub(crate) const CHAIN_LEAD_TOL: f64 = 0.0005;

/// The `thread_chain` check: every chain joint whose lead law jumps.
pub(crate) fn chain_check(links: &[ChainLink]) -> Vec<MachineIssue> {
    links
        .iter()
        .filter(|l| {
            (l.lead_after - l.lead_before).abs() > CHAIN_LEAD_TOL
                || (l.change_after - l.change_before).abs() > 1e-9
        })
        .map(|l| MachineIssue {
            kind: "thread_chain",
            error: false,
            pass: l.pass,
            z: l.z,
            value: l.lead_after - l.lead_before,
            limit: CHAIN_LEAD_TOL,
            message: format!(
                "pass {} ({}:{}, z = {:.4}): a continuous thread block re-programs the lead law without a re-sync: lead {:.4} -> {:.4} mm/rev, change {} -> {} mm/rev^2; the axis cannot follow the jump (some controls pause and re-sync)",
                l.pass + 1,
                l.file,
                l.line,
                l.z,
                l.lead_before,
                l.lead_after,
                l.change_before,
                l.change_after
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::helix::Spindle;

    #[test]
    fn feed_worst_case_is_the_larger_end() {
        let p = Pass {
            tool: 0,
            x_start: 26.0,
            x_end: 26.0,
            z_start: 5.5,
            z_end: -80.5,
            lead: 4.0,
            lead_change: 1.5,
            start_angle: 0.0,
            spindle: Spindle::Cw,
        };
        let m = Machine {
            spindle_rpm: 200.0,
            max_feed: Some(3000.0),
            acceleration: Some(1000.0),
            spindle: Spindle::Cw,
        };
        let blank = Blank {
            diameter: 28.0,
            bore: 0.0,
            length: 120.0,
            z_front: 0.0,
        };
        let issues = check(std::slice::from_ref(&p), &m, &blank);
        // End lead: sqrt(16 + 2*1.5*86) = 16.565 mm/rev -> 3313 mm/min.
        let feed = issues.iter().find(|i| i.kind == "feed_limit").unwrap();
        assert!((feed.value - (16.0f64 + 3.0 * 86.0).sqrt() * 200.0).abs() < 1e-9);
        assert!(feed.error);
        // Run-in: v = 4*200/60 = 13.33 mm/s, needs 0.0889 mm; 5.5 available.
        assert!(issues.iter().all(|i| i.kind != "run_in"));
    }
}
