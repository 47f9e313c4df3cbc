//! Findings: what the user must know about a run, typed. A [`Finding`] has a
//! [`FindingKind`] (its declaration order is the report's order), a [`Severity`] (an error
//! fails the job) and, where it has one, the [`Flank`] it is on; the report writes their
//! snake-case names. [`rank`] sorts findings and gives the [`Verdict`].

use crate::diag::Severity;
use crate::model::thread::Flank;
use serde::{Serialize, Serializer};
use std::fmt;

/// What a finding is about. The order of the variants is the order of the report's
/// findings within a severity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum FindingKind {
    /// A turn (or the whole thread) has no dexel on the simulated stock: it is not checked.
    NotCompared,
    /// A gauge element of the thread's tolerance class (GO, NOT GO, major, minor, root
    /// diameter) fails or cannot be decided.
    Gauge,
    /// The cut lies off the thread's given position (`thread.z_start`).
    Placement,
    /// A pass cuts a helix of the other hand than the drawing's.
    Hand,
    /// A rapid move cuts material (or a threading insert's feed move or radial entry).
    RapidCut,
    /// A tool's holder, or a tool, meets the part or the chuck.
    Collision,
    /// The tool's head is too short for the thread's depth.
    HeadLength,
    /// A pass's radial chip outside the insert's depth per pass.
    DepthPerPass,
    /// Material removed beyond the ideal surface, beyond the tolerance.
    Gouge,
    /// Material left above the ideal surface, beyond the tolerance.
    Leftover,
    /// A tool body cut past its edge's surface.
    FlankInterference,
    /// A threading cycle's infeed runs an edge along (or into) the flank cut before.
    InfeedAngle,
    /// A groove or tooth the drawing has is not found at the pitch diameter.
    MissingFeature,
    /// A turn's measured lead is off.
    Lead,
    /// A turn's pitch diameter is outside the drawing's limits (milling jobs).
    PitchDiameter,
    /// A groove's width at the pitch diameter is off.
    GrooveWidth,
    /// A tooth's width at the pitch diameter is off.
    ToothWidth,
    /// A feed over the machine's limit.
    FeedLimit,
    /// A ridge or notch crosses the pitch diameter inside one feature.
    SplitFeature,
    /// A pass starts too close to the part to reach its speed.
    RunIn,
    /// A lead change the axis cannot follow.
    AxisAcceleration,
    /// A warning from interpreting the NC program: a skipped unknown word or code.
    Program,
    /// A continuous thread chain changes the lead at a joint.
    ThreadChain,
    /// A tap's feed per revolution is not its pitch.
    TapFeed,
}

impl FindingKind {
    /// Every kind, in report order.
    pub const ALL: [FindingKind; 24] = [
        FindingKind::NotCompared,
        FindingKind::Gauge,
        FindingKind::Placement,
        FindingKind::Hand,
        FindingKind::RapidCut,
        FindingKind::Collision,
        FindingKind::HeadLength,
        FindingKind::DepthPerPass,
        FindingKind::Gouge,
        FindingKind::Leftover,
        FindingKind::FlankInterference,
        FindingKind::InfeedAngle,
        FindingKind::MissingFeature,
        FindingKind::Lead,
        FindingKind::PitchDiameter,
        FindingKind::GrooveWidth,
        FindingKind::ToothWidth,
        FindingKind::FeedLimit,
        FindingKind::SplitFeature,
        FindingKind::RunIn,
        FindingKind::AxisAcceleration,
        FindingKind::Program,
        FindingKind::ThreadChain,
        FindingKind::TapFeed,
    ];

    /// The name the report uses (`not_compared`, `gouge`, ...).
    pub fn name(self) -> &'static str {
        match self {
            FindingKind::NotCompared => "not_compared",
            FindingKind::Gauge => "gauge",
            FindingKind::Placement => "placement",
            FindingKind::Hand => "hand",
            FindingKind::RapidCut => "rapid_cut",
            FindingKind::Collision => "collision",
            FindingKind::HeadLength => "head_length",
            FindingKind::DepthPerPass => "depth_per_pass",
            FindingKind::InfeedAngle => "infeed_angle",
            FindingKind::Gouge => "gouge",
            FindingKind::Leftover => "leftover",
            FindingKind::FlankInterference => "flank_interference",
            FindingKind::MissingFeature => "missing_feature",
            FindingKind::Lead => "lead",
            FindingKind::PitchDiameter => "pitch_diameter",
            FindingKind::GrooveWidth => "groove_width",
            FindingKind::ToothWidth => "tooth_width",
            FindingKind::FeedLimit => "feed_limit",
            FindingKind::SplitFeature => "split_feature",
            FindingKind::RunIn => "run_in",
            FindingKind::AxisAcceleration => "axis_acceleration",
            FindingKind::Program => "program",
            FindingKind::ThreadChain => "thread_chain",
            FindingKind::TapFeed => "tap_feed",
        }
    }
}

impl FindingKind {
    /// One sentence on what it means (SARIF's rule text).
    pub fn description(self) -> &'static str {
        match self {
            FindingKind::NotCompared => {
                "Part of the thread lies on no simulated dexel: it is not checked."
            }
            FindingKind::Gauge => {
                "A GO/NOT GO gauge or a diameter of the thread's tolerance class rejects the thread, or the simulation cannot decide it."
            }
            FindingKind::Placement => {
                "The cut thread lies off the position the job gives it (thread.z_start)."
            }
            FindingKind::Hand => "A pass cuts the other hand than the drawing's thread.",
            FindingKind::RapidCut => {
                "A rapid (G00) move, or a threading insert's move off the thread, removes material."
            }
            FindingKind::Collision => {
                "A tool's holder or boring bar meets the part, or a tool or its holder meets the chuck."
            }
            FindingKind::HeadLength => {
                "A pass runs deeper than the tool's head reaches: the holder hits the part."
            }
            FindingKind::Gouge => {
                "Material removed that the ideal thread keeps, beyond the tolerance."
            }
            FindingKind::Leftover => {
                "Material left that the ideal thread removes, beyond the tolerance."
            }
            FindingKind::FlankInterference => "A tool body cuts past the surface its edge cut.",
            FindingKind::DepthPerPass => {
                "A pass's radial chip is over (or under) the insert's depth per pass."
            }
            FindingKind::InfeedAngle => {
                "A threading cycle's infeed runs an edge along or into the flank cut before: it rubs."
            }
            FindingKind::MissingFeature => {
                "A groove or tooth of the drawing is not formed at the pitch diameter."
            }
            FindingKind::Lead => "A turn's lead is off by more than the tolerance.",
            FindingKind::PitchDiameter => {
                "A turn's simple pitch diameter is outside the drawing's limits."
            }
            FindingKind::GrooveWidth => "A groove's width is off by more than the tolerance.",
            FindingKind::ToothWidth => "A tooth's width is off by more than the tolerance.",
            FindingKind::FeedLimit => "The axis feed exceeds the machine's maximum.",
            FindingKind::SplitFeature => {
                "A ridge or notch crosses the pitch diameter inside one feature."
            }
            FindingKind::RunIn => "Less run-in than the axis needs to reach speed.",
            FindingKind::AxisAcceleration => {
                "A lead change needs more axial acceleration than the machine has."
            }
            FindingKind::Program => {
                "A diagnostic of the NC program (a skipped word or code, a missing subprogram)."
            }
            FindingKind::ThreadChain => {
                "A chained thread block re-programs the lead law without a re-sync."
            }
            FindingKind::TapFeed => {
                "A tap is fed at another feed per revolution than its pitch: it strips the thread."
            }
        }
    }
}

impl fmt::Display for FindingKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The severity's report name: `error` or `warning`.
pub(crate) fn severity_name(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

fn ser_severity<S: Serializer>(s: &Severity, ser: S) -> Result<S::Ok, S::Error> {
    ser.serialize_str(severity_name(*s))
}

fn ser_flank<S: Serializer>(f: &Option<Flank>, ser: S) -> Result<S::Ok, S::Error> {
    match f {
        Some(f) => ser.serialize_some(f.name()),
        None => ser.serialize_none(),
    }
}

/// Something the user must know.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    /// What it is about.
    pub kind: FindingKind,
    /// An error fails the job.
    #[serde(serialize_with = "ser_severity")]
    pub severity: Severity,
    /// Turn, if it belongs to one.
    pub turn: Option<i64>,
    /// Start.
    pub start: Option<u32>,
    /// Flank, for deviations and body interference.
    #[serde(serialize_with = "ser_flank")]
    pub flank: Option<Flank>,
    /// Pass (1-based), for machine checks.
    pub pass: Option<usize>,
    /// Angle on the part (deg).
    pub angle_deg: Option<f64>,
    /// Axial position (mm).
    pub z_mm: Option<f64>,
    /// The program file the finding is in (program findings): as the job names it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// 1-based line in `file`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<usize>,
    /// 1-based column in `file`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub column: Option<usize>,
    /// The job file's key the finding is about, where no NC block made it (a pass of
    /// `[[pass]]` as `pass[2]`, `thread.z_start`, `machine`): the job's own source.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub key: Option<String>,
    /// The value (unit in `unit`); absent where a finding has none (program findings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// `mm`, `mm/min`, `mm/s^2`, `mm/rev`, `deg`; absent with `value`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<&'static str>,
    /// One line for a person.
    pub message: String,
    /// Where a finding stands for many (one block's deviations on many turns): what they
    /// cover. The finding's own fields are the worst one's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extent: Option<Extent>,
}

/// What the findings a finding stands for cover.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Extent {
    /// How many findings it stands for.
    pub findings: usize,
    /// The first and last turn.
    pub turns: Option<[i64; 2]>,
    /// The flanks (`left`, `right`, `root`, `crest`), in order of appearance.
    pub flanks: Vec<&'static str>,
    /// The lowest and highest axial position (mm).
    pub z_mm: Option<[f64; 2]>,
    /// How many of each kind, in report order.
    pub kinds: Vec<(&'static str, usize)>,
}

impl Finding {
    /// A finding with a kind, a severity and a message and no location or value; the
    /// fields that apply are set with struct update syntax (`..Finding::new(..)`).
    pub fn new(kind: FindingKind, severity: Severity, message: String) -> Finding {
        Finding {
            kind,
            severity,
            turn: None,
            start: None,
            flank: None,
            pass: None,
            angle_deg: None,
            z_mm: None,
            file: None,
            line: None,
            column: None,
            key: None,
            value: None,
            unit: None,
            message,
            extent: None,
        }
    }

    /// Whether it fails the job.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// Where it is, for a person: `file:line:col` of its NC block, else `job key K`;
    /// `None` where it has neither.
    pub fn source(&self) -> Option<String> {
        match (&self.file, self.line, &self.key) {
            (Some(f), Some(l), _) => Some(format!("{f}:{l}:{}", self.column.unwrap_or(1))),
            (_, _, Some(k)) => Some(format!("job key {k}")),
            _ => None,
        }
    }
}

/// How many findings of each severity a report has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FindingCounts {
    /// Findings that fail the job.
    pub errors: usize,
    /// The others.
    pub warnings: usize,
}

impl FindingCounts {
    /// Count `findings`.
    pub fn of(findings: &[Finding]) -> FindingCounts {
        let errors = findings.iter().filter(|f| f.is_error()).count();
        FindingCounts {
            errors,
            warnings: findings.len() - errors,
        }
    }
}

/// pass / fail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Within tolerance, no error findings.
    Pass,
    /// At least one error finding.
    Fail,
}

/// Sort findings, errors first and then by kind (a stable sort: findings of one kind keep
/// their order); the verdict they give.
pub(crate) fn rank(findings: &mut [Finding]) -> Verdict {
    findings.sort_by_key(|f| (!f.is_error(), f.kind));
    if findings.iter().any(Finding::is_error) {
        Verdict::Fail
    } else {
        Verdict::Pass
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_listed_once_in_declaration_order_with_their_serde_names() {
        for w in FindingKind::ALL.windows(2) {
            assert!(w[0] < w[1], "{:?} before {:?}", w[0], w[1]);
        }
        for k in FindingKind::ALL {
            let json = serde_json::to_string(&k).unwrap();
            assert_eq!(json, format!("\"{}\"", k.name()));
        }
    }

    #[test]
    fn errors_come_first_then_kinds_in_order() {
        let f = |k, s| Finding::new(k, s, String::new());
        let mut v = vec![
            f(FindingKind::Program, Severity::Warning),
            f(FindingKind::Lead, Severity::Error),
            f(FindingKind::Gouge, Severity::Error),
            f(FindingKind::NotCompared, Severity::Warning),
        ];
        assert_eq!(rank(&mut v), Verdict::Fail);
        let kinds: Vec<_> = v.iter().map(|f| f.kind).collect();
        assert_eq!(
            kinds,
            [
                FindingKind::Gouge,
                FindingKind::Lead,
                FindingKind::NotCompared,
                FindingKind::Program
            ]
        );
        v.retain(|f| !f.is_error());
        assert_eq!(rank(&mut v), Verdict::Pass);
    }
}
