//! The report assembled from a run's results: the thread and stock, the per-turn rows
//! (deviation per flank, measured leads and widths, clearances), the body interference, and
//! the findings each of them gives, ranked into the verdict.

use crate::analysis::checks::MachineIssue;
use crate::analysis::compare::{Deviation, Extreme, TurnDeviation};
use crate::analysis::contour::{Cutter, PartGouge, PartLeftover};
use crate::analysis::findings::{rank, Finding, FindingKind};
use crate::analysis::interference;
use crate::analysis::measure::TurnMeasure;
use crate::diag::Severity;
use crate::job::Job;
use crate::kernel::sweep::SweepStats;
use crate::model::helix::{Hand, Spindle};
use crate::model::stock::Grid;
use crate::model::thread::{Flank, Side, WidthRule};
use crate::report::{self, r4, r6, InchThread, Report, TurnRow, Units, SCHEMA};
use crate::toolpath::{HitKind, RapidHit, Role};
use std::collections::BTreeMap;

pub(crate) fn location(e: &Extreme) -> report::Location {
    report::Location {
        turn: e.turn,
        start: e.start,
        flank: e.flank.name(),
        angle_deg: r4(e.theta.to_degrees().rem_euclid(360.0)),
        z_mm: r6(e.z),
    }
}

/// The report of a run.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_report(
    job: &Job,
    grid: Grid,
    stats: SweepStats,
    dev: &Deviation,
    measures: &[Vec<TurnMeasure>],
    spacing: f64,
    machine_issues: &[MachineIssue],
    bodies: Option<&interference::Bodies>,
) -> Report {
    let thread = &job.thread;
    let tol = job.sim.tolerance;
    let units = Units { inch: job.inch() };
    let (major, minor) = match thread.side {
        Side::External => (2.0 * thread.crest_radius, 2.0 * thread.root_radius),
        Side::Internal => (2.0 * thread.root_radius, 2.0 * thread.crest_radius),
    };
    let mut findings: Vec<Finding> = Vec::new();
    let mut turns = Vec::new();
    // The deviation findings, one per place of the part.
    let places: BTreeMap<(u32, i64, bool, usize), Option<i64>> = dev
        .places(tol, &grid)
        .iter()
        .map(|p| {
            let e = &p.extreme;
            ((e.start, e.turn, p.gouge, e.flank.index()), p.also)
        })
        .collect();
    // Index the measurements by (start, turn): the reference generator, and all of them
    // with their generator's angle (equally spaced from the thread's start angle, as
    // `measure` places them).
    let mut reference: BTreeMap<(u32, i64), &TurnMeasure> = BTreeMap::new();
    let mut by_turn: BTreeMap<(u32, i64), Vec<(f64, &TurnMeasure)>> = BTreeMap::new();
    for (g, list) in measures.iter().enumerate() {
        let angle =
            thread.helix.theta0 + std::f64::consts::TAU * g as f64 / measures.len().max(1) as f64;
        for m in list {
            if g == 0 {
                reference.entry((m.start, m.turn)).or_insert(m);
            }
            by_turn
                .entry((m.start, m.turn))
                .or_default()
                .push((angle, m));
        }
    }
    for s in 0..thread.starts {
        for n in 1..=thread.whole_turns() {
            let m = reference.get(&(s, n)).copied();
            let all: &[(f64, &TurnMeasure)] = by_turn.get(&(s, n)).map_or(&[], Vec::as_slice);
            let td = dev.turns.get(&(s, n)).cloned().unwrap_or_default();
            let flank = |f: Flank| report::FlankRow {
                max_gouge_mm: r6(td.gouge[f.index()].map_or(0.0, |e| e.value)),
                max_leftover_mm: r6(td.leftover[f.index()].map_or(0.0, |e| e.value)),
            };
            let fold = |v: &mut Option<(f64, f64)>, x: f64| {
                *v = Some(v.map_or((x, x), |(a, b)| (a.min(x), b.max(x))));
            };
            let (mut ideal_rng, mut meas_rng, mut max_err) = (None, None, None::<f64>);
            for (_, g) in all {
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
            let diam = m
                .and_then(|m| m.cut_heights.map(|c| (c, m.t)))
                .map(|((a, b), t)| {
                    // Heights above the local root: at the turn's middle for a taper thread.
                    let z = thread.helix.z(t + 0.5);
                    let (ra, rb) = (thread.local_radius(z, a), thread.local_radius(z, b));
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
                        FindingKind::NotCompared,
                        Severity::Warning,
                        format!(
                            "turn {n}: no part of it lies on the simulated stock ([simulation] z_range): it is not checked"
                        ),
                    )
                });
            }
            let starts = thread.starts;
            turn_findings(
                &row,
                &td,
                &places,
                all,
                thread.helix.theta0,
                (tol, units, starts),
                &mut findings,
            );
            turns.push(row);
        }
    }
    for (i, p) in job.passes.iter().enumerate() {
        let hand = p.helix().hand();
        if hand != thread.hand() {
            let name = |h: Hand| if h == Hand::Right { "right" } else { "left" };
            findings.push(Finding {
                pass: Some(i + 1),
                z_mm: Some(r6(p.z_start)),
                ..Finding::new(FindingKind::Hand, Severity::Error, format!(
                    "pass {}: spindle {} feeding toward {}z cuts a {}-hand helix; the drawing's thread is {}-hand",
                    i + 1,
                    if p.spindle == Spindle::Cw { "cw (M03)" } else { "ccw (M04)" },
                    if p.z_end < p.z_start { "-" } else { "+" },
                    name(hand),
                    name(thread.hand())
                ))
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
                let severity = if h.depth > tol {
                    Severity::Error
                } else {
                    Severity::Warning
                };
                let message = format!(
                    "turn {turn} {flank} flank: the tool body cut {} past its edge's surface at {angle:.1} deg, {} ({:.3} mm3): the side clearance is smaller than the helix angle there",
                    units.len(h.depth, 4),
                    units.z(h.z),
                    h.volume
                );
                findings.push(Finding {
                    turn: Some(turn),
                    start: Some(start),
                    flank: Some(Flank::ALL[k]),
                    angle_deg: Some(angle),
                    z_mm: Some(r6(h.z)),
                    value: Some(r6(h.depth)),
                    unit: Some("mm"),
                    ..Finding::new(FindingKind::FlankInterference, severity, message)
                });
            }
        }
    }
    for mi in machine_issues {
        // The insert's checks are about a program's block: where it is.
        let block = matches!(
            mi.kind,
            FindingKind::DepthPerPass | FindingKind::InfeedAngle
        )
        .then(|| job.pass_blocks.iter().find(|b| b.0 == mi.pass))
        .flatten();
        let message = match block {
            Some((_, file, line)) => format!("{file}:{line}: {}", mi.message),
            None => mi.message.clone(),
        };
        findings.push(Finding {
            file: block.map(|b| b.1.clone()),
            line: block.map(|b| b.2),
            pass: Some(mi.pass + 1),
            z_mm: Some(r6(mi.z)),
            value: Some(r6(mi.value)),
            unit: Some(match mi.kind {
                FindingKind::FeedLimit => "mm/min",
                FindingKind::AxisAcceleration => "mm/s^2",
                FindingKind::InfeedAngle => "deg",
                FindingKind::ThreadChain => "mm/rev",
                _ => "mm",
            }),
            ..Finding::new(
                mi.kind,
                if mi.error {
                    Severity::Error
                } else {
                    Severity::Warning
                },
                message,
            )
        });
    }
    for w in &job.program_warnings {
        findings.push(Finding {
            file: Some(w.file.clone()),
            line: Some(w.line),
            column: Some(w.col.max(1)),
            ..Finding::new(
                FindingKind::Program,
                Severity::Warning,
                format!("{}:{}:{}: {}", w.file, w.line, w.col.max(1), w.message),
            )
        });
    }
    for t in &job.tap_feeds {
        findings.push(Finding {
            file: Some(t.file.clone()),
            line: Some(t.line),
            value: Some(r6(t.feed - t.pitch)),
            unit: Some("mm/rev"),
            ..Finding::new(
                FindingKind::TapFeed,
                Severity::Error,
                format!(
                    "{}:{}: the tap is fed {} mm/rev, its pitch is {} mm: every tooth cuts {} mm/rev off the groove the one before it cut, and the thread is stripped",
                    t.file,
                    t.line,
                    r6(t.feed),
                    r6(t.pitch),
                    r6((t.feed - t.pitch).abs())
                ),
            )
        });
    }
    for h in &job.turning.rapids {
        findings.push(Finding {
            z_mm: Some(r6(h.z)),
            file: Some(h.file.clone()),
            line: Some(h.line),
            value: Some(r6(h.depth)),
            unit: Some("mm"),
            ..Finding::new(
                match h.kind {
                    HitKind::Holder | HitKind::Chuck => FindingKind::Collision,
                    _ => FindingKind::RapidCut,
                },
                Severity::Error,
                rapid_message(h, units),
            )
        });
    }
    if dev.compared_dexels == 0 {
        findings.push(Finding::new(
            FindingKind::NotCompared,
            Severity::Error,
            "no part of the thread lies on the simulated stock: nothing was compared, so nothing is verified (check thread.z_start against the blank and [simulation] z_range)".to_string(),
        ));
    }
    // A given z_start the cut does not follow: the ideal is kept where the job puts it.
    if let Some(off) = job.placement.and_then(|p| p.offset) {
        if off.abs() > tol {
            let mut f = Finding::new(
                FindingKind::Placement,
                Severity::Warning,
                format!(
                    "the cut thread lies {} {} of thread.z_start = {} (the nearest equivalent position): the comparison keeps the given position; leave z_start out to place the thread on the cut",
                    units.len(off.abs(), 4),
                    if off > 0.0 { "in front (+z)" } else { "behind (-z)" },
                    r6(thread.helix.z0)
                ),
            );
            f.value = Some(r6(off));
            f.unit = Some("mm");
            findings.push(f);
        }
    }
    let verdict = rank(&mut findings);
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
            placement: job
                .placement
                .as_ref()
                .map(|p| report::PlacementInfo::of(p, job.fit_thread)),
            inch: units.inch.then(|| {
                let lead = thread.helix.law.f;
                InchThread::of(
                    major,
                    2.0 * thread.pitch_radius,
                    minor,
                    lead / f64::from(thread.starts.max(1)),
                    lead,
                )
            }),
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
        gauge: None,
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
        cycle_time_s: job.cycle_time.as_ref().map(report::CycleTimeInfo::of),
        findings,
        timing_s: report::Timing::default(),
    }
}

/// The findings of one turn: its deviations beyond the tolerance that `places` gives (one
/// per place of the part, [`Deviation::places`]), missing features, its lead, its widths
/// (`all`: the turn's measurement on every generator, with the generator's angle; the
/// reference generator's angle `reference`), split features; `(tol, units, starts)`: the
/// tolerance, how lengths read, the thread's starts (a single start's lead is also given in
/// threads per inch).
fn turn_findings(
    row: &TurnRow,
    td: &TurnDeviation,
    places: &BTreeMap<(u32, i64, bool, usize), Option<i64>>,
    all: &[(f64, &TurnMeasure)],
    reference: f64,
    (tol, units, starts): (f64, Units, u32),
    out: &mut Vec<Finding>,
) {
    let base = |kind, severity, value: f64, message: String| Finding {
        turn: Some(row.turn),
        start: Some(row.start),
        value: Some(r6(value)),
        unit: Some("mm"),
        ..Finding::new(kind, severity, message)
    };
    for (kind, slots) in [
        (FindingKind::Gouge, &td.gouge),
        (FindingKind::Leftover, &td.leftover),
    ] {
        for f in Flank::ALL {
            let Some(e) = slots[f.index()] else { continue };
            if e.value <= tol {
                continue;
            }
            let key = (e.start, e.turn, kind == FindingKind::Gouge, f.index());
            // Given with the adjacent turn's at the same place, or here naming it.
            let Some(also) = places.get(&key) else {
                continue;
            };
            let also = also.map_or(String::new(), |t| {
                format!(" (also turn {t}'s worst there: the turns meet at this place)")
            });
            let l = location(&e);
            out.push(Finding {
                flank: Some(f),
                angle_deg: Some(l.angle_deg),
                z_mm: Some(l.z_mm),
                ..base(
                    kind,
                    Severity::Error,
                    e.value,
                    format!(
                        "turn {} {}: {kind} {} at {:.1} deg, {}{also}",
                        row.turn,
                        f.label(),
                        units.len(e.value, 4),
                        l.angle_deg,
                        units.z(l.z_mm)
                    ),
                )
            });
        }
    }
    if all.iter().any(|(_, m)| {
        (m.ideal_groove.is_some() && m.groove.is_none())
            || (m.ideal_tooth.is_some() && m.tooth.is_none())
    }) {
        out.push(base(
            FindingKind::MissingFeature,
            Severity::Error,
            0.0,
            format!(
                "turn {}: a groove or tooth the drawing has is not formed at the pitch diameter at one or more of the measured angles",
                row.turn
            ),
        ));
    }
    if let Some(err) = row.lead_spread.max_error_mm {
        if err > tol {
            out.push(base(
                FindingKind::Lead,
                Severity::Error,
                err,
                format!(
                    "turn {}: lead off by up to {} (at the reference angle: measured {} vs ideal {})",
                    row.turn,
                    units.len(err, 4),
                    fmt_lead(row.measured_lead_mm, units, starts),
                    fmt_lead(row.ideal_lead_mm, units, starts)
                ),
            ));
        }
    }
    // Widths on every generator: the worst difference from the ideal, at its generator's
    // angle, with the drawing's width there. On a variable lead the drawing's width changes
    // along the turn, so where that is not the reference angle the message also gives the
    // reference angle's, which the turn row shows.
    for (kind, what, pick) in [
        (
            FindingKind::GrooveWidth,
            "groove",
            (|m: &TurnMeasure| m.ideal_groove.zip(m.groove)) as fn(&TurnMeasure) -> _,
        ),
        (FindingKind::ToothWidth, "tooth", |m: &TurnMeasure| {
            m.ideal_tooth.zip(m.tooth)
        }),
    ] {
        let worst = all
            .iter()
            .filter_map(|(a, m)| pick(m).map(|v| (*a, v)))
            .fold(None::<(f64, (f64, f64))>, |acc, (a, (i, g))| match acc {
                Some((aa, (ai, ag))) if (ag - ai).abs() >= (g - i).abs() => Some((aa, (ai, ag))),
                _ => Some((a, (i, g))),
            });
        if let Some((angle, (i, g))) = worst {
            if (g - i).abs() > tol {
                let angle_deg = r4(angle.to_degrees().rem_euclid(360.0));
                let at_reference = match all
                    .iter()
                    .find(|(a, _)| *a == reference)
                    .and_then(|(_, m)| pick(m))
                {
                    Some((ri, _)) if angle != reference => format!(
                        " ({} at the reference angle {:.1} deg, as the turn row gives it)",
                        units.len(ri, 4),
                        reference.to_degrees().rem_euclid(360.0)
                    ),
                    _ => String::new(),
                };
                out.push(Finding {
                    angle_deg: Some(angle_deg),
                    ..base(
                        kind,
                        Severity::Error,
                        g - i,
                        format!(
                            "turn {}: {what} width {} at {angle_deg:.1} deg, where the drawing's is {}{at_reference}",
                            row.turn,
                            units.len(g, 4),
                            units.len(i, 4)
                        ),
                    )
                });
            }
        }
    }
    if all.iter().any(|(_, m)| m.split) {
        out.push(base(
            FindingKind::SplitFeature,
            Severity::Warning,
            0.0,
            format!(
                "turn {}: a ridge or notch crosses the pitch diameter inside one feature",
                row.turn
            ),
        ));
    }
}

/// A move into material, in the user's words: what moved, which tool, how deep, where.
fn rapid_message(h: &RapidHit, units: Units) -> String {
    let tool = match h.role {
        Role::Turning if h.internal => "boring bar",
        Role::Turning => "turning tool",
        Role::Grooving => "grooving insert",
        Role::Threading => "threading insert",
    };
    let more = match h.moves {
        1 => String::new(),
        n => format!("; {n} such moves of this block, the deepest"),
    };
    let place = if h.internal { "bore's wall" } else { "part" };
    match h.kind {
        HitKind::Holder => {
            return format!(
                "{}:{}: the {} of the {tool} {} meets the {place} {} deep at {} (the stock as the move leaves it{more})",
                h.file,
                h.line,
                if h.internal { "boring bar" } else { "holder" },
                h.tool_name,
                units.len(h.depth, 4),
                units.z(h.z)
            )
        }
        HitKind::Chuck => {
            return format!(
                "{}:{}: the {tool} {} (its tip or its holder) runs {} into the chuck or its jaws at {} ([machine] chuck{more})",
                h.file,
                h.line,
                h.tool_name,
                units.len(h.depth, 4),
                units.z(h.z)
            )
        }
        _ => {}
    }
    let what = match h.kind {
        HitKind::Rapid => "a rapid (G00) move",
        HitKind::Feed => "a feed move",
        _ => "a synchronised entry (a thread move more radial than axial)",
    };
    let why = match h.kind {
        HitKind::Rapid => "",
        _ => ": a threading insert cuts only along the thread",
    };
    format!(
        "{}:{}: {what} of the {tool} {} runs {} into the {place} at {} (the stock the moves before it left{more}){why}",
        h.file,
        h.line,
        h.tool_name,
        units.len(h.depth, 4),
        units.z(h.z)
    )
}

/// A measured or ideal lead for a message: mm, with inches and (one start) threads per
/// inch for an inch job; `-` where there is none.
fn fmt_lead(v: Option<f64>, units: Units, starts: u32) -> String {
    v.map_or("-".to_string(), |x| units.pitch(x, 4, starts == 1))
}

/// One surface's contour check as the report's findings: each NC block whose moves or
/// passes cut into the part (its deepest, with how many of them), each stretch of stock
/// left outside it; `bore` for the bore's contour. The verdict is ranked again by the
/// caller.
pub(crate) fn add_part(
    report: &mut Report,
    job: &Job,
    bore: bool,
    (gouges, leftovers): &(Vec<PartGouge>, Vec<PartLeftover>),
) {
    let moves = if bore {
        &job.turning.inner_blocks
    } else {
        &job.turning.outer_blocks
    };
    let surface = if bore { "bore's contour" } else { "contour" };
    let units = report.units();
    let part_key = if bore {
        "part.bore_profile"
    } else {
        "part.profile"
    };
    /// The deepest gouge of one NC block, what made it (in words) and how many did.
    struct Block<'a> {
        file: Option<String>,
        line: Option<usize>,
        worst: &'a PartGouge,
        who: String,
        count: usize,
    }
    let mut blocks: Vec<Block> = Vec::new();
    for g in gouges {
        let (block, who) = match g.by {
            Cutter::Pass(i) => (
                job.pass_blocks
                    .iter()
                    .find(|b| b.0 == i)
                    .map(|b| (b.1.clone(), b.2)),
                format!("pass {}", i + 1),
            ),
            Cutter::Move(i) => (moves.get(i).cloned(), "a feed move".to_string()),
        };
        let (file, line) = block.map_or((None, None), |(f, l)| (Some(f), Some(l)));
        match blocks
            .iter_mut()
            .find(|b| (&b.file, b.line) == (&file, line))
        {
            Some(b) => {
                b.count += 1;
                if g.depth > b.worst.depth {
                    (b.worst, b.who) = (g, who);
                }
            }
            None => blocks.push(Block {
                file,
                line,
                worst: g,
                who,
                count: 1,
            }),
        }
    }
    for b in blocks {
        let g = b.worst;
        let at = match (&b.file, b.line) {
            (Some(f), Some(l)) => format!("{f}:{l}: "),
            _ => String::new(),
        };
        let more = if b.count > 1 {
            format!(
                " ({} of this block's moves cut into it, this one deepest)",
                b.count
            )
        } else {
            String::new()
        };
        report.findings.push(Finding {
            pass: match g.by {
                Cutter::Pass(i) => Some(i + 1),
                Cutter::Move(_) => None,
            },
            z_mm: Some(r6(g.z)),
            key: b.file.is_none().then(|| part_key.to_string()),
            file: b.file,
            line: b.line,
            value: Some(r6(g.depth)),
            unit: Some("mm"),
            ..Finding::new(
                FindingKind::Gouge,
                Severity::Error,
                format!(
                    "{at}the part: {} cuts {} under its {surface} (d {}) at {}{more}",
                    b.who,
                    units.len(g.depth, 4),
                    units.len(2.0 * g.floor, 3),
                    units.z(g.z)
                ),
            )
        });
    }
    for l in leftovers {
        report.findings.push(Finding {
            z_mm: Some(r6(l.z)),
            key: Some(part_key.to_string()),
            value: Some(r6(l.height)),
            unit: Some("mm"),
            ..Finding::new(
                FindingKind::Leftover,
                Severity::Error,
                format!(
                    "the part: the turned stock stands {} over its {surface} from {} to {}, the most at {}",
                    units.len(l.height, 4),
                    units.z(l.span.0),
                    units.z(l.span.1),
                    units.z(l.z)
                ),
            )
        });
    }
}
