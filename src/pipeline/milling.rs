//! What a milling run adds to the report: the moves' figures (removed volume, radial
//! depth, feed at the edge, feed per tooth, engagement, chip thickness), rapids that cut,
//! feeds over the machine's limit, and the pitch diameter against the drawing's limits.

use crate::analysis::findings::{Finding, FindingKind};
use crate::analysis::measure::TurnMeasure;
use crate::job::{Job, MillJob};
use crate::kernel::mill::{self, MillStats};
use crate::model::stock::Surface;
use crate::nc::{self, Severity};
use crate::report::{self, r4, r6, Report};
use std::collections::BTreeMap;

/// Add the milling job `mj`'s figures and findings to `report`.
pub(super) fn add_mill(
    report: &mut Report,
    job: &Job,
    mj: &MillJob,
    stats: &MillStats,
    measures: &[Vec<TurnMeasure>],
    surface: Surface,
) {
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
                pass: Some(i + 1),
                angle_deg: Some(r4(cut.at.0.to_degrees().rem_euclid(360.0))),
                z_mm: Some(r6(cut.at.1)),
                file: Some(m.file.clone()),
                line: Some(m.line),
                value: Some(r6(cut.depth)),
                unit: Some("mm"),
                ..Finding::new(FindingKind::RapidCut, Severity::Error, format!(
                    "{}:{}: a rapid (G00) move cuts {:.4} mm deep ({:.3} mm3) at {:.1} deg, z {:.3}",
                    m.file,
                    m.line,
                    cut.depth,
                    cut.volume,
                    cut.at.0.to_degrees().rem_euclid(360.0),
                    cut.at.1
                ))
            });
        }
        if let (Some(f), Some(max)) = (m.feed.filter(|_| cutting), job.machine.max_feed) {
            if f > max {
                report.findings.push(Finding {
                    pass: Some(i + 1),
                    z_mm: Some(r6(m.end[2])),
                    file: Some(m.file.clone()),
                    line: Some(m.line),
                    value: Some(r6(f)),
                    unit: Some("mm/min"),
                    ..Finding::new(
                        FindingKind::FeedLimit,
                        Severity::Error,
                        format!(
                            "{}:{}: feed {f} mm/min over the machine's {max} mm/min",
                            m.file, m.line
                        ),
                    )
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
            .retain(|f| f.kind != FindingKind::GrooveWidth && f.kind != FindingKind::ToothWidth);
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
                turn: Some(turn),
                start: Some(start),
                value: Some(r6(off)),
                unit: Some("mm"),
                ..Finding::new(FindingKind::PitchDiameter, Severity::Error, format!(
                    "turn {turn}: pitch diameter {a:.4} to {b:.4} mm, outside the drawing's {lo} to {hi} mm"
                ))
            });
        }
    }
}
