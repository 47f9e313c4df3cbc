//! The gauges' part of the report: the tolerance class, each gauge element's value, limit
//! and call, the over-wire prediction, and where the thread was placed on the cut.
//!
//! With a class the gauges decide the thread: the findings the nominal comparison gives
//! per dexel and per turn (gouge, leftover, lead, widths, missing or split features) stay
//! in the turn rows and the deviation totals, but are not findings: a thread anywhere in
//! its zone differs from any one nominal profile, and a gauge would pass it. Every failed
//! element is one error finding; an undecided one a warning.

use super::{r6, Report};
use crate::analysis::findings::{Finding, FindingKind};
use crate::analysis::gauge::{Call, Gauge};
use crate::analysis::measure::TurnMeasure;
use crate::analysis::place::Placement;
use crate::diag::Severity;
use crate::model::tolerance::{SizeLimits, ThreadClass, UnitSystem};
use serde::Serialize;

/// The least and greatest of a value (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Range {
    /// Least (mm).
    pub min: f64,
    /// Greatest (mm).
    pub max: f64,
}

impl Range {
    fn of((a, b): (f64, f64)) -> Range {
        Range {
            min: r6(a),
            max: r6(b),
        }
    }
}

/// A limit pair as the report writes it: an open end is absent (`null`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LimitPair {
    /// Least size (mm), if the class sets one.
    pub min: Option<f64>,
    /// Greatest size (mm), if the class sets one.
    pub max: Option<f64>,
}

impl LimitPair {
    fn of(l: SizeLimits) -> LimitPair {
        let f = |x: f64| x.is_finite().then(|| r6(x));
        LimitPair {
            min: f(l.min),
            max: f(l.max),
        }
    }
}

/// One gauge element in the report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GaugeElementInfo {
    /// What is checked.
    pub element: &'static str,
    /// `max` or `min`: the limit's end.
    pub limit: &'static str,
    /// The limit (mm).
    pub limit_mm: f64,
    /// The measured value (mm).
    pub value_mm: Option<f64>,
    /// The resolution its call used (mm).
    pub resolution_mm: f64,
    /// `pass`, `fail`, `undecided` or `not_measured`.
    pub verdict: &'static str,
    /// A recommendation, not a limit (ISO 965-1's least root radius): a failure is a
    /// warning and does not decide the gauges' verdict.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub advisory: bool,
}

/// The three-wire measurement a shop can check the part with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OverWires {
    /// Best-size wire diameter (mm).
    pub wire_mm: f64,
    /// Predicted measurement over the wires for the smallest and largest simple pitch
    /// diameter (mm).
    pub measurement_mm: Range,
}

/// The thread against its tolerance class.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GaugeInfo {
    /// The designation as the drawing names it.
    pub designation: String,
    /// The tolerance class.
    pub class: String,
    /// `pass`, `fail` or `undecided` (`not_measured` when nothing could be gauged).
    pub verdict: &'static str,
    /// The simulation's resolution on a diameter (mm): values within it of a limit are
    /// undecided.
    pub resolution_mm: f64,
    /// Functional (virtual) pitch diameter: the GO gauge's size over the worst window of
    /// the length of engagement (mm).
    pub functional_diameter_mm: Option<f64>,
    /// That window's z range (mm).
    pub functional_window_z_mm: Option<[f64; 2]>,
    /// The length of engagement the GO gauge checks (mm).
    pub engagement_length_mm: f64,
    /// Simple pitch diameter of the complete turns on every generator (mm).
    pub pitch_diameter_mm: Option<Range>,
    /// The NOT GO gauge's size in its worst window of `not_go_turns` turns: the virtual
    /// truncated-profile gauge (flank contact within `not_go_band_mm` of its pitch line)
    /// that just assembles with them (mm).
    pub not_go_diameter_mm: Option<f64>,
    /// The first turn of that window.
    pub not_go_turn: Option<i64>,
    /// Turns the NOT GO gauge engages at once.
    pub not_go_turns: f64,
    /// The truncated NOT GO profile's contact band: half its height either side of the
    /// pitch line (mm, radial).
    pub not_go_band_mm: f64,
    /// The NOT GO as single elements: the largest (external) or smallest (internal)
    /// simple pitch diameter of the turns of its worst window (mm), and that window's
    /// first turn.
    pub not_go_simple_diameter_mm: Option<f64>,
    /// See `not_go_simple_diameter_mm`.
    pub not_go_simple_turn: Option<i64>,
    /// Crest diameter of the complete turns: major (external) or minor (internal) (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub major_diameter_mm: Option<Range>,
    /// See `major_diameter_mm`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minor_diameter_mm: Option<Range>,
    /// Root diameter of the complete turns (mm).
    pub root_diameter_mm: Option<Range>,
    /// External threads whose class has a root zone (ISO 965-1): the least effective root
    /// radius of the complete turns (the largest disk that fills the root), measured up
    /// to twice the recommended least (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub root_radius_mm: Option<f64>,
    /// The turn of that root.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub root_radius_turn: Option<i64>,
    /// The class's limits (mm).
    pub limits: GaugeLimits,
    /// Every element checked.
    pub elements: Vec<GaugeElementInfo>,
    /// A taper thread (NPT, R, Rc): its gauge's stand-off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub taper: Option<TaperInfo>,
    /// Three wires of best size (external threads).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub over_wires: Option<OverWires>,
    /// Inch designations: the same values in inches and the threads per inch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inch: Option<InchView>,
    /// Where the limits come from.
    pub source: String,
}

/// A taper thread's gauge (ASME B1.20.1's L1 ring or plug, ISO 7-2's taper gauges): a
/// perfect taper gauge of the basic profile fitted to the cut over its length.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TaperInfo {
    /// `ring` (external) or `plug` (internal).
    pub gauge: &'static str,
    /// How far the gauge's plane stops from the part's nominal gauge plane (turns, signed:
    /// positive where it stops short of it: more material, an external thread large or an
    /// internal one small).
    pub stand_off_turns: f64,
    /// The same along z (mm).
    pub stand_off_mm: f64,
    /// The stand-off allowed either way (turns).
    pub tolerance_turns: f64,
    /// z of the gauge's plane where it stopped, and of the part's nominal gauge plane (mm).
    pub gauge_plane_z_mm: f64,
    /// See `gauge_plane_z_mm`.
    pub nominal_gauge_plane_z_mm: f64,
    /// The cut's pitch cone at the nominal gauge plane as the gauge sees it (mm), and the
    /// basic pitch diameter there (E1).
    pub pitch_diameter_at_gauge_plane_mm: f64,
    /// See `pitch_diameter_at_gauge_plane_mm`.
    pub basic_pitch_diameter_mm: f64,
    /// The resolution of the stand-off (turns).
    pub resolution_turns: f64,
}

/// The class's limits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GaugeLimits {
    /// Pitch diameter.
    pub pitch_diameter_mm: LimitPair,
    /// Major diameter.
    pub major_diameter_mm: LimitPair,
    /// Minor diameter.
    pub minor_diameter_mm: LimitPair,
}

/// An inch thread's figures in inches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct InchView {
    /// Threads per inch.
    pub tpi: f64,
    /// Functional pitch diameter (in).
    pub functional_diameter_in: Option<f64>,
    /// Simple pitch diameter, least and greatest (in).
    pub pitch_diameter_in: Option<Range>,
    /// Pitch diameter limits (in).
    pub pitch_diameter_limits_in: LimitPair,
}

/// Where the thread was placed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PlacementInfo {
    /// `fitted` (placed on the cut) or `given` (`thread.z_start`).
    pub how: &'static str,
    /// The thread's first feature at its start angle (mm).
    pub z_start_mm: f64,
    /// Features (grooves or teeth) the fit used.
    pub features: usize,
    /// Their root mean square offset from one helix (mm).
    pub spread_mm: f64,
    /// With a given `z_start`: the cut's offset from it (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset_mm: Option<f64>,
}

impl PlacementInfo {
    pub(crate) fn of(p: &Placement, fitted: bool) -> PlacementInfo {
        PlacementInfo {
            how: if fitted { "fitted" } else { "given" },
            z_start_mm: r6(p.z_start),
            features: p.features,
            spread_mm: r6(p.spread),
            offset_mm: p.offset.map(r6),
        }
    }
}

/// Kinds a class's gauges decide instead of the nominal comparison.
const NOMINAL: [FindingKind; 8] = [
    FindingKind::Gouge,
    FindingKind::Leftover,
    FindingKind::MissingFeature,
    FindingKind::Lead,
    FindingKind::GrooveWidth,
    FindingKind::ToothWidth,
    FindingKind::SplitFeature,
    FindingKind::PitchDiameter,
];

/// A diameter for a message: mm, and inches for an inch class.
fn dia(v: f64, class: &ThreadClass) -> String {
    match class.units {
        UnitSystem::Metric => format!("{v:.4} mm"),
        UnitSystem::Inch => format!("{v:.4} mm ({:.5} in)", v / 25.4),
    }
}

/// A small length as a person reads it: four decimals, or two significant digits below
/// 0.001 mm (a resolution of 0.000017 mm is not "0.0000").
fn small(v: f64) -> String {
    if v >= 0.001 || v == 0.0 {
        format!("{v:.4}")
    } else {
        format!("{v:.2e}")
    }
}

fn element_words(name: &str) -> &'static str {
    match name {
        "go_functional_pitch_diameter" => "GO gauge: functional pitch diameter",
        "not_go_pitch_diameter" => "NOT GO gauge (truncated profile): pitch diameter",
        "major_diameter" => "major diameter",
        "minor_diameter" => "minor diameter",
        "root_diameter" => "root diameter",
        "root_radius" => "root radius",
        "gauge_plane_stand_off" => "taper gauge: its plane's stand-off",
        _ => "gauge element",
    }
}

/// Put the gauges' results into the report: the section, the per-turn pitch diameters,
/// and the findings (replacing the nominal comparison's).
pub(crate) fn add_gauge(
    report: &mut Report,
    class: &ThreadClass,
    g: &Gauge,
    measures: &[Vec<TurnMeasure>],
) {
    report.findings.retain(|f| !NOMINAL.contains(&f.kind));
    for e in &g.elements {
        let severity = match e.call {
            // A recommendation is said only where the cut is clearly short of it.
            Call::Undecided | Call::NotMeasured if e.advisory => continue,
            Call::Fail if e.advisory => Severity::Warning,
            Call::Fail => Severity::Error,
            Call::Undecided | Call::NotMeasured => Severity::Warning,
            Call::Pass => continue,
        };
        let (end, side) = if e.upper {
            ("maximum", "over")
        } else {
            ("minimum", "under")
        };
        let what = element_words(e.name);
        let message = match (e.call, e.value) {
            (Call::NotMeasured, _) | (_, None) => format!(
                "{what}: not measured (no complete turn of the thread was found on the cut), so the {} {end} {} is not checked",
                class.designation,
                dia(e.limit, class)
            ),
            (Call::Undecided, Some(v)) => format!(
                "{what} {} is within the simulation's resolution ({} mm) of the {} {end} {}: undecided",
                dia(v, class),
                small(e.resolution),
                class.designation,
                dia(e.limit, class)
            ),
            (_, Some(v)) => format!(
                "{what} {} is {side} the {} {end} {} by {}",
                dia(v, class),
                class.designation,
                dia(e.limit, class),
                dia((v - e.limit).abs(), class)
            ),
        };
        let message = match (e.name, e.value) {
            ("gauge_plane_stand_off", Some(v)) => {
                let gauge = if class.internal { "plug" } else { "ring" };
                let turns = v / class.pitch;
                let allowed = e.limit.abs() / class.pitch;
                let how = if v > 0.0 {
                    format!(
                        "stops {:.2} turns short of the gauge plane (the thread is {})",
                        turns,
                        if class.internal { "small" } else { "large" }
                    )
                } else {
                    format!(
                        "goes {:.2} turns past the gauge plane (the thread is {})",
                        -turns,
                        if class.internal { "large" } else { "small" }
                    )
                };
                match e.call {
                    Call::Undecided => format!(
                        "the {} taper {gauge} gauge {how}, within the simulation's resolution ({:.3} turns) of the ±{allowed} turns allowed: undecided",
                        class.designation,
                        e.resolution / class.pitch
                    ),
                    _ => format!(
                        "the {} taper {gauge} gauge {how}: over the ±{allowed} turns allowed by {:.2} turns ({:.4} mm along the axis)",
                        class.designation,
                        turns.abs() - allowed,
                        (v.abs() - e.limit.abs()).abs()
                    ),
                }
            }
            _ => message,
        };
        let message = if e.advisory {
            format!(
                "{message} (ISO 965-1 recommends a root radius of at least 0.125P for external threads; a recommendation, not part of the gauges' verdict)"
            )
        } else {
            message
        };
        let mut f = Finding::new(FindingKind::Gauge, severity, message);
        f.value = e.value.map(r6);
        f.unit = Some("mm");
        report.findings.push(f);
    }
    // The turn rows: the simple pitch diameter of each turn on the reference generator.
    if let Some(reference) = measures.first() {
        for row in &mut report.turns {
            if let Some(m) = reference
                .iter()
                .find(|m| m.turn == row.turn && m.start == row.start)
            {
                row.pitch_diameter_mm = m.pitch_diameter.map(r6);
            }
        }
    }
    let external = !class.internal;
    let crest = g.crest.map(Range::of);
    let inch = (class.units == UnitSystem::Inch).then(|| {
        let i = |v: f64| (v / 25.4 * 1e6).round() / 1e6;
        InchView {
            tpi: r6(25.4 / class.pitch),
            functional_diameter_in: g.functional.map(|f| i(f.0)),
            pitch_diameter_in: g.simple.map(|(a, b)| Range {
                min: i(a),
                max: i(b),
            }),
            pitch_diameter_limits_in: LimitPair {
                min: class
                    .pitch_diameter
                    .min
                    .is_finite()
                    .then(|| i(class.pitch_diameter.min)),
                max: class
                    .pitch_diameter
                    .max
                    .is_finite()
                    .then(|| i(class.pitch_diameter.max)),
            },
        }
    });
    report.gauge = Some(GaugeInfo {
        designation: class.designation.clone(),
        class: class.class.clone(),
        verdict: g.verdict.name(),
        resolution_mm: r6(g.resolution),
        functional_diameter_mm: g.functional.map(|f| r6(f.0)),
        functional_window_z_mm: g.functional.map(|f| [r6(f.1 .0), r6(f.1 .1)]),
        engagement_length_mm: r6(class.engagement_length),
        pitch_diameter_mm: g.simple.map(Range::of),
        not_go_diameter_mm: g.not_go.map(|n| r6(n.0)),
        not_go_turn: g.not_go.map(|n| n.1),
        not_go_turns: class.not_go_turns,
        not_go_band_mm: r6(crate::analysis::gauge::not_go_band(class)),
        not_go_simple_diameter_mm: g.not_go_simple.map(|n| r6(n.0)),
        not_go_simple_turn: g.not_go_simple.map(|n| n.1),
        major_diameter_mm: if external { crest } else { None },
        minor_diameter_mm: if external { None } else { crest },
        root_diameter_mm: g.root.map(Range::of),
        root_radius_mm: g.root_radius.map(|r| r6(r.0)),
        root_radius_turn: g.root_radius.map(|r| r.1),
        limits: GaugeLimits {
            pitch_diameter_mm: LimitPair::of(class.pitch_diameter),
            major_diameter_mm: LimitPair::of(class.major_diameter),
            minor_diameter_mm: LimitPair::of(class.minor_diameter),
        },
        elements: g
            .elements
            .iter()
            .map(|e| GaugeElementInfo {
                element: e.name,
                limit: if e.upper { "max" } else { "min" },
                limit_mm: r6(e.limit),
                value_mm: e.value.map(r6),
                resolution_mm: r6(e.resolution),
                verdict: e.call.name(),
                advisory: e.advisory,
            })
            .collect(),
        taper: g.stand_off.map(|so| TaperInfo {
            gauge: if class.internal { "plug" } else { "ring" },
            stand_off_turns: r6(so.turns),
            stand_off_mm: r6(so.mm),
            tolerance_turns: so.tolerance_turns,
            gauge_plane_z_mm: r6(so.plane_z),
            nominal_gauge_plane_z_mm: r6(so.nominal_z),
            pitch_diameter_at_gauge_plane_mm: r6(so.diameter),
            basic_pitch_diameter_mm: r6(class.basic_pitch_diameter),
            resolution_turns: r6(so.resolution / class.pitch),
        }),
        over_wires: g.over_wires.map(|(w, lo, hi)| OverWires {
            wire_mm: r6(w),
            measurement_mm: Range::of((lo, hi)),
        }),
        inch,
        source: class.source.clone(),
    });
}

/// The summary's lines for the gauges.
pub(crate) fn summary(g: &GaugeInfo) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let o = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.4}"));
    let _ = writeln!(
        s,
        "  gauges ({}): {}, resolution {} mm",
        g.designation,
        g.verdict,
        small(g.resolution_mm)
    );
    for e in &g.elements {
        let _ = writeln!(
            s,
            "    {:<40} {:>9} mm  {} {:.4}  {}",
            format!("{} ({})", element_words(e.element), e.limit),
            o(e.value_mm),
            e.limit,
            e.limit_mm,
            if e.advisory {
                format!("{} (recommended)", e.verdict)
            } else {
                e.verdict.to_string()
            }
        );
    }
    if let Some(t) = g.taper {
        let _ = writeln!(
            s,
            "    taper {} gauge stands {:+.3} turns off the gauge plane (allowed ±{}; resolution {} turns): the cut's pitch cone {:.4} mm there, basic {:.4} mm",
            t.gauge,
            t.stand_off_turns,
            t.tolerance_turns,
            small(t.resolution_turns),
            t.pitch_diameter_at_gauge_plane_mm,
            t.basic_pitch_diameter_mm
        );
    }
    if let (Some(v), Some(t)) = (g.not_go_simple_diameter_mm, g.not_go_simple_turn) {
        let _ = writeln!(
            s,
            "    NOT GO as single elements: simple pitch diameter {v:.4} mm (turns from {t})"
        );
    }
    if let Some(w) = g.over_wires {
        let _ = writeln!(
            s,
            "    over three {:.4} mm wires: {:.4} .. {:.4} mm",
            w.wire_mm, w.measurement_mm.min, w.measurement_mm.max
        );
    }
    s
}
