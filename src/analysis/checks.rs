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

use crate::analysis::findings::FindingKind;
use crate::model::pass::Pass;
use crate::model::setup::{Blank, ChainLink, Machine};
use crate::model::thread::Side;
use crate::model::tool::Tool;

/// A machine check that failed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MachineIssue {
    /// `feed_limit`, `run_in` or `axis_acceleration`.
    pub kind: FindingKind,
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

/// Check every pass's tool head against the depth it cuts: a head (`length` above the tip,
/// or a mesh's height) shorter than the distance from the tip to the blank's surface puts
/// the holder into the part. Seed 000 asks for a head 2 to 3 mm longer than the tooth.
pub(crate) fn head_check(
    passes: &[Pass],
    tools: &[Tool],
    blank: &Blank,
    side: Side,
) -> Vec<MachineIssue> {
    let mut out = Vec::new();
    for (i, p) in passes.iter().enumerate() {
        let Some(length) = tools.get(p.tool).and_then(Tool::head_length) else {
            continue;
        };
        // The deepest point of the pass and how far below the blank's surface it is.
        let (x, z) = match side {
            Side::External if p.x_end < p.x_start => (p.x_end, p.z_end),
            Side::External => (p.x_start, p.z_start),
            Side::Internal if p.x_end > p.x_start => (p.x_end, p.z_end),
            Side::Internal => (p.x_start, p.z_start),
        };
        let depth = match side {
            Side::External => (blank.diameter - x) / 2.0,
            Side::Internal => (x - blank.bore) / 2.0,
        };
        if depth > length + 1e-9 {
            out.push(MachineIssue {
                kind: FindingKind::HeadLength,
                error: true,
                pass: i,
                z,
                value: depth,
                limit: length,
                message: format!(
                    "pass {}: the tool's head reaches {length:.3} mm above its tip, but the tip runs {depth:.3} mm below the blank's surface: the holder would hit the part",
                    i + 1
                ),
            });
        }
    }
    out
}

/// A spindle speed as the messages write it: whole as programmed, else to 0.1 rev/min (a
/// G96 speed at a diameter).
pub(crate) fn rpm_text(rpm: f64) -> String {
    if rpm.fract() == 0.0 {
        format!("{rpm}")
    } else {
        format!("{rpm:.1}")
    }
}

/// The spindle speed of pass `i`: the program's (`rpm[i]`), else the machine's.
fn pass_rpm(rpm: &[f64], i: usize, machine: &Machine) -> f64 {
    rpm.get(i).copied().unwrap_or(machine.spindle_rpm)
}

/// Check every pass against the machine, pass `i` at the spindle speed `rpm[i]` (the
/// program's; the machine's `spindle_rpm` where `rpm` has none).
pub(crate) fn check(
    passes: &[Pass],
    rpm: &[f64],
    machine: &Machine,
    blank: &Blank,
) -> Vec<MachineIssue> {
    let mut out = Vec::new();
    let z_back = blank.z_front - blank.length;
    for (i, p) in passes.iter().enumerate() {
        let n = pass_rpm(rpm, i, machine);
        let rps = n / 60.0;
        let Some(end_lead) = p.end_lead() else {
            continue;
        };
        let (lead_max, z_at) = if end_lead > p.lead {
            (end_lead, p.z_end)
        } else {
            (p.lead, p.z_start)
        };
        if let Some(max_feed) = machine.max_feed {
            let feed = lead_max * n;
            if feed > max_feed {
                out.push(MachineIssue {
                    kind: FindingKind::FeedLimit,
                    error: true,
                    pass: i,
                    z: z_at,
                    value: feed,
                    limit: max_feed,
                    message: format!(
                        "pass {}: lead {:.4} mm/rev x {} rpm = {:.1} mm/min exceeds max_feed {} mm/min",
                        i + 1,
                        lead_max,
                        rpm_text(n),
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
                    kind: FindingKind::RunIn,
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
                    kind: FindingKind::AxisAcceleration,
                    error: false,
                    pass: i,
                    z: p.z_start,
                    value: acc,
                    limit: a,
                    message: format!(
                        "pass {}: a lead change of {} mm/rev^2 at {} rpm needs {:.1} mm/s^2 of axial acceleration, more than {} mm/s^2",
                        i + 1,
                        p.lead_change,
                        rpm_text(n),
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

/// The `thread_chain` check: every chain joint whose lead law jumps. With a known
/// acceleration a lead step `dL` is a feed step `dv = dL rpm/60` that the axis makes up
/// with a lag of `dv^2/(2a)`: a step whose lag stays under a tenth of the tolerance (a
/// variable lead written as chained G33 blocks, `crate::gen::post`) is no finding.
pub(crate) fn chain_check(
    links: &[ChainLink],
    rpm: &[f64],
    machine: &Machine,
    tolerance: f64,
) -> Vec<MachineIssue> {
    links
        .iter()
        .filter(|l| {
            let rps = pass_rpm(rpm, l.pass, machine) / 60.0;
            let step = (l.lead_after - l.lead_before).abs();
            let felt = match machine.acceleration {
                Some(a) => (step * rps).powi(2) / (2.0 * a) > 0.1 * tolerance,
                None => true,
            };
            (step > CHAIN_LEAD_TOL && felt) || (l.change_after - l.change_before).abs() > 1e-9
        })
        .map(|l| MachineIssue {
            kind: FindingKind::ThreadChain,
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
    use crate::model::helix::Spindle;

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
            rapid_rate: None,
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
        let issues = check(std::slice::from_ref(&p), &[], &m, &blank);
        // End lead: sqrt(16 + 2*1.5*86) = 16.565 mm/rev -> 3313 mm/min.
        let feed = issues
            .iter()
            .find(|i| i.kind == FindingKind::FeedLimit)
            .unwrap();
        assert!((feed.value - (16.0f64 + 3.0 * 86.0).sqrt() * 200.0).abs() < 1e-9);
        assert!(feed.error);
        // Run-in: v = 4*200/60 = 13.33 mm/s, needs 0.0889 mm; 5.5 available.
        assert!(issues.iter().all(|i| i.kind != FindingKind::RunIn));
    }

    /// A job whose `[program]` is `text` (dialect `dialect`), one 2 mm grooving tool. The
    /// programs write plain numbers in mm (`G0 X28 Z5`): on a FANUC/GSK the job says the
    /// machine reads them so (calculator-type decimal-point input).
    fn program_job(text: &str, dialect: &str, spindle: &str) -> crate::job::Job {
        let input = if matches!(dialect, "fanuc" | "gsk980") {
            "decimal_point = \"calculator\"\n"
        } else {
            ""
        };
        let toml = format!(
            "[blank]\ndiameter = 30.0\nlength = 60.0\n\
             [thread]\nform = \"square\"\nmajor_diameter = 30.0\nminor_diameter = 28.0\n\
             pitch = 2.0\nturns = 5\nwidth = {{ groove = 1.0 }}\n\
             [[tool]]\nid = 1\nkind = \"grooving\"\nwidth = 1.0\n\
             [program]\nfile = \"P.NC\"\ndialect = \"{dialect}\"\n{input}\
             [machine]\nspindle = \"{spindle}\"\n"
        );
        let load = |f: &str| (f == "P.NC").then(|| text.to_string());
        crate::job::Job::from_toml_with(&toml, "t.toml", &load).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Two chained G32 blocks of one lead cut exactly the helix of one block: at every
    /// revolution of the second pass its point (angle on the part, z) is the single block's
    /// at `t + 3.5` (F2 over the first 7 mm), in both spindle directions; closed form
    /// `theta(t) = theta0 - spin 2 pi t`, `z(t) = z0 - 2t`.
    #[test]
    fn chained_g32_blocks_cut_one_helix() {
        for (m, spindle) in [("M03", "cw"), ("M04", "ccw")] {
            let one = program_job(
                &format!("{m}\nG0 X28 Z5\nG32 Z-15 F2\nM30\n"),
                "fanuc",
                spindle,
            );
            let two = program_job(
                &format!("{m}\nG0 X28 Z5\nG32 Z-2 F2 Q45000\nG32 Z-15 F2 Q90000\nM30\n"),
                "fanuc",
                spindle,
            );
            assert_eq!((one.passes.len(), two.passes.len()), (1, 2));
            let single = one.passes[0].helix();
            let spin = if spindle == "cw" { 1.0 } else { -1.0 };
            // The first block's Q45000 is a real start angle: the whole chain is turned
            // by it against the single block (Q0).
            let q = -spin * 45f64.to_radians();
            for (i, p) in two.passes.iter().enumerate() {
                let t0 = if i == 0 { 0.0 } else { 3.5 };
                let h = p.helix();
                for k in 0..5 {
                    let t = k as f64 * 0.7;
                    let want_theta = single.theta0 + q - spin * std::f64::consts::TAU * (t + t0);
                    let d = (h.theta0 - spin * std::f64::consts::TAU * t - want_theta)
                        .rem_euclid(std::f64::consts::TAU);
                    assert!(
                        d < 1e-9 || std::f64::consts::TAU - d < 1e-9,
                        "{m} pass {i} t {t}: {d}"
                    );
                    assert!((h.z(t) - single.z(t + t0)).abs() < 1e-9);
                }
            }
            // A pure continuation: no thread_chain finding.
            assert!(
                chain_check(&two.chains, &two.pass_rpm, &two.machine, two.sim.tolerance).is_empty()
            );
            assert_eq!(two.chains.len(), 1);
        }
    }

    /// The thread_chain check fires where a chained block re-programs the lead (F) or the
    /// lead change (K), and stays silent for a continuation whose F is the previous end
    /// lead rounded to 0.001 (sqrt(16 + 2 x 12) = 6.32456 -> F6.325).
    #[test]
    fn thread_chain_fires_for_a_reprogrammed_law() {
        let base = "M03\nG0 X28 Z5\nG34 Z-7 F4 K1\n";
        let job = |second: &str| program_job(&format!("{base}{second}\nM30\n"), "fanuc", "cw");
        let j = job("G34 Z-20 F6.325 K1");
        assert_eq!(j.chains.len(), 1);
        assert!(chain_check(&j.chains, &j.pass_rpm, &j.machine, j.sim.tolerance).is_empty());
        let j = job("G34 Z-20 F7 K1");
        let issues = chain_check(&j.chains, &j.pass_rpm, &j.machine, j.sim.tolerance);
        assert_eq!(issues.len(), 1);
        let i = &issues[0];
        assert_eq!(
            (i.kind, i.error, i.pass, i.z),
            (FindingKind::ThreadChain, false, 1, -7.0)
        );
        assert!((i.value - (7.0 - 40f64.sqrt())).abs() < 1e-12, "{i:?}");
        assert!(i.message.contains("P.NC:4"), "{}", i.message);
        assert_eq!(
            {
                let j = job("G34 Z-20 F6.325 K2");
                chain_check(&j.chains, &j.pass_rpm, &j.machine, j.sim.tolerance)
            }
            .len(),
            1
        );
        assert_eq!(
            {
                let j = job("G32 Z-20 F6.325");
                chain_check(&j.chains, &j.pass_rpm, &j.machine, j.sim.tolerance)
            }
            .len(),
            1
        );
        // Not chained: a rapid between the blocks re-syncs, nothing to report.
        assert!(job("G0 X29\nG34 Z-20 F7 K1").chains.is_empty());
        // GSK: the run-out segment continues its block's law exactly.
        let gsk = program_job(
            "M03\nG0 X28 Z5\nG34 Z-20 F4 J1 K2 R0.5\nM30\n",
            "gsk980",
            "cw",
        );
        assert_eq!((gsk.passes.len(), gsk.chains.len()), (2, 1));
        assert!(
            chain_check(&gsk.chains, &gsk.pass_rpm, &gsk.machine, gsk.sim.tolerance).is_empty()
        );
    }
}
