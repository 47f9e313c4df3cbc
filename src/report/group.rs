//! One cause, one finding: the per-turn findings of the thread (deviations, leads, widths,
//! missing and split features, body rubs) and the per-pass findings (a pass of the other
//! hand) that one NC block or one job key made are one finding: the worst of them, with the
//! extent of all (turns, flanks, z range, how many of each kind, and each kind's largest
//! size: two mistakes in one block, a G76 too shallow and of the wrong lead, are one
//! finding whose message names both with their sizes). The per-turn detail stays in the
//! report's turn rows. Findings of different blocks, or of none, stay apart.

use crate::analysis::findings::{Extent, Finding, FindingKind};
use crate::report::{r6, Units};

/// Whether a finding is one of a block's many per-turn or per-pass findings.
fn groupable(f: &Finding) -> bool {
    use FindingKind as K;
    let per_turn = matches!(
        f.kind,
        K::Gouge
            | K::Leftover
            | K::Lead
            | K::GrooveWidth
            | K::ToothWidth
            | K::MissingFeature
            | K::SplitFeature
            | K::PitchDiameter
            | K::FlankInterference
    ) && f.turn.is_some();
    let has_source = (f.file.is_some() && f.line.is_some()) || f.key.is_some();
    (per_turn || f.kind == K::Hand) && has_source
}

/// How a finding ranks as the one a group shows: deviations by size first (gouge, leftover,
/// body rub), then the measurements, in report order.
fn weight(f: &Finding) -> (u8, f64) {
    use FindingKind as K;
    match f.kind {
        K::Hand => (3, 0.0),
        K::Gouge | K::Leftover | K::FlankInterference => (2, f.value.unwrap_or(0.0)),
        _ => (1, 0.0),
    }
}

/// Group `findings` by severity and source; groups of one finding stay as they were.
/// `units`: how the sizes in a group's message read.
pub(crate) fn group(findings: Vec<Finding>, units: Units) -> Vec<Finding> {
    let mut out: Vec<Finding> = Vec::new();
    let mut groups: Vec<Vec<Finding>> = Vec::new();
    for f in findings {
        if !groupable(&f) {
            out.push(f);
            continue;
        }
        let same = |g: &Vec<Finding>| {
            let h = &g[0];
            (h.severity, &h.file, h.line, &h.key) == (f.severity, &f.file, f.line, &f.key)
        };
        match groups.iter_mut().find(|g| same(g)) {
            Some(g) => g.push(f),
            None => groups.push(vec![f]),
        }
    }
    for g in groups {
        out.push(merge(g, units));
    }
    out
}

/// One finding for a group: its worst member, its extent and a message that says both.
fn merge(mut g: Vec<Finding>, units: Units) -> Finding {
    if g.len() == 1 {
        return g.pop().expect("one finding");
    }
    let mut lead = 0;
    for (i, f) in g.iter().enumerate() {
        let (a, b) = (weight(f), weight(&g[lead]));
        if a.0 > b.0 || (a.0 == b.0 && a.1 > b.1) {
            lead = i;
        }
    }
    let turns: Vec<i64> = g.iter().filter_map(|f| f.turn).collect();
    let zs: Vec<f64> = g.iter().filter_map(|f| f.z_mm).collect();
    let mut flanks: Vec<&'static str> = Vec::new();
    for f in g.iter().filter_map(|f| f.flank) {
        if !flanks.contains(&f.name()) {
            flanks.push(f.name());
        }
    }
    let mut kinds: Vec<(FindingKind, usize)> = Vec::new();
    for f in &g {
        match kinds.iter_mut().find(|k| k.0 == f.kind) {
            Some(k) => k.1 += 1,
            None => kinds.push((f.kind, 1)),
        }
    }
    kinds.sort();
    let extent = Extent {
        findings: g.len(),
        turns: (!turns.is_empty()).then(|| {
            [
                *turns.iter().min().expect("a turn"),
                *turns.iter().max().expect("a turn"),
            ]
        }),
        flanks: flanks.clone(),
        z_mm: (!zs.is_empty()).then(|| {
            [
                r6(zs.iter().copied().fold(f64::INFINITY, f64::min)),
                r6(zs.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
            ]
        }),
        kinds: kinds.iter().map(|k| (k.0.name(), k.1)).collect(),
    };
    let mut f = g.swap_remove(lead);
    let mut what = Vec::new();
    if let Some([a, b]) = extent.turns {
        what.push(if a == b {
            format!("turn {a}")
        } else {
            format!("turns {a} to {b}")
        });
    }
    if !flanks.is_empty() {
        what.push(format!("{} ", flanks.join(", ")));
        if let Some(last) = what.last_mut() {
            *last = last.trim_end().to_string();
        }
    }
    if let Some([lo, hi]) = extent.z_mm {
        what.push(format!("z {lo:.3} to {hi:.3}"));
    }
    // Each kind with its largest size (the lead's error, the width's difference from the
    // drawing, the deviation), where it has one.
    let counts: Vec<String> = kinds
        .iter()
        .map(|(k, n)| {
            let largest = g
                .iter()
                .chain(std::iter::once(&f))
                .filter(|x| x.kind == *k && x.unit == Some("mm"))
                .filter_map(|x| x.value)
                .map(f64::abs)
                .fold(0.0, f64::max);
            if largest > 0.0 {
                format!("{n} {} up to {}", k.name(), units.len(largest, 4))
            } else {
                format!("{n} {}", k.name())
            }
        })
        .collect();
    f.message = format!(
        "{} (the worst of {} findings with this source: {}; over {})",
        f.message,
        extent.findings,
        counts.join(", "),
        what.join(", ")
    );
    f.extent = Some(extent);
    f
}
