//! The report: what `report.json` holds, and the short summary for a person.
//!
//! This is the output serialization boundary (`docs/report-format.md`). Every length is in
//! mm rounded to 1e-6 mm (volumes to 1e-6 mm^3), angles in degrees rounded to 1e-4, so the
//! file is byte-identical between runs and thread counts; only `timing_s` changes.

pub use crate::analysis::findings::{Extent, Finding, FindingCounts, FindingKind, Verdict};
use crate::diag::Severity;
use serde::Serialize;
use std::fmt::Write as _;

mod blame;
mod build;
mod gauge;
mod group;
mod units;
pub(crate) use blame::locate;
pub(crate) use build::{add_part, build_report};
pub(crate) use gauge::add_gauge;
pub use gauge::{
    GaugeElementInfo, GaugeInfo, GaugeLimits, InchView, LimitPair, OverWires, PlacementInfo, Range,
    TaperInfo,
};
pub(crate) use group::group;
pub use units::InchThread;
pub(crate) use units::Units;

/// The schema tag.
pub const SCHEMA: &str = "vpcut.report/1";

/// Round to 1e-6 (and turn -0 into 0).
pub(crate) fn r6(x: f64) -> f64 {
    let v = (x * 1e6).round() / 1e6;
    if v == 0.0 {
        0.0
    } else {
        v
    }
}

/// Round to 1e-4.
pub(crate) fn r4(x: f64) -> f64 {
    let v = (x * 1e4).round() / 1e4;
    if v == 0.0 {
        0.0
    } else {
        v
    }
}

/// The version of vpcut, as the report records it.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// An input file of a job.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct InputFile {
    /// `job`, `program` (an NC program or subprogram) or `tool` (a tool mesh).
    pub role: &'static str,
    /// The path as it was given (the job's) or as the job names it (the files it reads).
    pub path: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
}

impl InputFile {
    /// Record a file with the hash of its bytes.
    pub fn new(role: &'static str, path: impl Into<String>, bytes: &[u8]) -> InputFile {
        use sha2::Digest as _;
        let digest = sha2::Sha256::digest(bytes);
        let mut sha256 = String::with_capacity(64);
        for b in digest {
            let _ = write!(sha256, "{b:02x}");
        }
        InputFile {
            role,
            path: path.into(),
            sha256,
        }
    }
}

/// The whole report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// Always [`SCHEMA`].
    pub schema: &'static str,
    /// The version of vpcut that wrote it ([`VERSION`]).
    pub vpcut_version: &'static str,
    /// The job's name.
    pub job: String,
    /// The files the job was read from, with their SHA-256 (the caller that read them
    /// fills this in; empty when the job did not come from files).
    pub inputs: Vec<InputFile>,
    /// pass / fail.
    pub verdict: Verdict,
    /// How many findings are errors and how many warnings.
    pub finding_counts: FindingCounts,
    /// Deviation tolerance (mm).
    pub tolerance_mm: f64,
    /// The thread wanted.
    pub thread: ThreadInfo,
    /// The dexel grid.
    pub stock: StockInfo,
    /// Number of threading passes.
    pub passes: usize,
    /// What the sweep kernel did.
    pub kernel: KernelInfo,
    /// How leads and widths were measured.
    pub measurement: MeasurementInfo,
    /// Deviation totals.
    pub deviation: DeviationInfo,
    /// The thread against its tolerance class (a job with `designation` or `class`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gauge: Option<GaugeInfo>,
    /// Per turn (and start).
    pub turns: Vec<TurnRow>,
    /// Where a tool body cut beyond its edge's swept groove: present (maybe empty) for
    /// jobs with tool bodies, absent without.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interference: Option<Vec<InterferenceRow>>,
    /// Milling jobs: the cutters, the sampling and every move's cut.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mill: Option<MillInfo>,
    /// A lathe program's cycle time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycle_time_s: Option<CycleTimeInfo>,
    /// Findings, errors first.
    pub findings: Vec<Finding>,
    /// Wall-clock times (s): the one part that changes between runs.
    pub timing_s: Timing,
}

/// The thread wanted, as resolved.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThreadInfo {
    /// `external` / `internal`.
    pub side: &'static str,
    /// Form name.
    pub form: &'static str,
    /// `right` / `left`.
    pub hand: &'static str,
    /// Number of starts.
    pub starts: u32,
    /// Major diameter (mm).
    pub major_diameter_mm: f64,
    /// Minor diameter (mm).
    pub minor_diameter_mm: f64,
    /// Pitch diameter where widths and leads are measured (mm).
    pub pitch_diameter_mm: f64,
    /// `groove` or `tooth`: which width is constant.
    pub constant_width: &'static str,
    /// That width at the pitch line (mm).
    pub width_mm: f64,
    /// Lead law of start 0: lead at t = 0 (mm/rev).
    pub lead_at_start_mm: f64,
    /// Lead change per revolution (mm/rev^2).
    pub lead_change_mm: f64,
    /// Number of turns.
    pub turns: f64,
    /// Where the thread was placed on the cut, or the cut's offset from the given place.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub placement: Option<PlacementInfo>,
    /// An inch job ([`crate::Job::inch`]): the thread's figures in inches and threads per
    /// inch; the messages and the summary give inches beside mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inch: Option<InchThread>,
}

/// The stock grid.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StockInfo {
    /// Angular columns.
    pub angular_cells: usize,
    /// Axial cells per column.
    pub axial_cells: usize,
    /// Axial spacing (mm).
    pub axial_spacing_mm: f64,
    /// Stored dexels (all surfaces).
    pub dexels: u64,
    /// Surfaces stored (`outer`, `inner`).
    pub surfaces: Vec<&'static str>,
    /// Bytes per stored dexel.
    pub bytes_per_dexel: u32,
    /// z of the first cell centre (mm).
    pub z_min_mm: f64,
    /// z of the last cell centre (mm).
    pub z_max_mm: f64,
}

/// Sweep counters.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KernelInfo {
    /// Tool placements (pass crossings of a column).
    pub placements: u64,
    /// Dexel updates.
    pub dexel_updates: u64,
    /// Tool bodies swept: the most sections behind one edge, and the bound on how far the
    /// sampled body's cut can be from the continuous body's (mm). Absent without bodies, or
    /// when no body can reach beyond its edge (then nothing is sampled).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body_sections: Option<usize>,
    /// See `body_sections`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body_sampling_bound_mm: Option<f64>,
}

/// Measurement settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasurementInfo {
    /// Axial spacing of the measurement columns (mm).
    pub axial_spacing_mm: f64,
    /// Number of generators (the first is the reference one at the thread's start angle).
    pub generators: usize,
    /// Angle of the reference generator (deg).
    pub reference_angle_deg: f64,
}

/// Deviation totals.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeviationInfo {
    /// Worst gouge (mm, normal distance).
    pub max_gouge_mm: f64,
    /// Where it is.
    pub max_gouge_at: Option<Location>,
    /// Worst leftover (mm).
    pub max_leftover_mm: f64,
    /// Where it is.
    pub max_leftover_at: Option<Location>,
    /// Volume cut inside the ideal part (mm^3).
    pub gouge_volume_mm3: f64,
    /// Volume left outside the ideal part (mm^3).
    pub leftover_volume_mm3: f64,
    /// Volume removed in the compared region (mm^3).
    pub removed_volume_mm3: f64,
    /// Volume the ideal thread removes there (mm^3).
    pub ideal_removed_volume_mm3: f64,
    /// Volume removed anywhere on the grid (mm^3).
    pub total_removed_volume_mm3: f64,
    /// Dexels compared.
    pub compared_dexels: u64,
    /// The z range the drawing defines and the comparison covered (mm): from the first
    /// thread groove's -z wall to the last one's +z wall at the crest, over all generators,
    /// clipped to the stock; `null` when no dexel was compared.
    pub compared_z_mm: Option<[f64; 2]>,
    /// Volume removed outside that range, where the drawing does not define the thread
    /// (run-in, run-out, chamfers) and nothing is compared (mm^3).
    pub uncompared_removed_volume_mm3: f64,
}

/// A place on the part.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Location {
    /// Turn (1-based).
    pub turn: i64,
    /// Start.
    pub start: u32,
    /// `left`, `right`, `root` or `crest`.
    pub flank: &'static str,
    /// Angle on the part (deg, in [0, 360)).
    pub angle_deg: f64,
    /// Axial position (mm).
    pub z_mm: f64,
}

/// Extremes of one flank.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FlankRow {
    /// Worst gouge (mm).
    pub max_gouge_mm: f64,
    /// Worst leftover (mm).
    pub max_leftover_mm: f64,
}

/// Per-flank extremes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Flanks {
    /// Left wall of the groove (-z side).
    pub left: FlankRow,
    /// Right wall (+z side).
    pub right: FlankRow,
    /// Groove bottom.
    pub root: FlankRow,
    /// Tooth top.
    pub crest: FlankRow,
}

/// Lead over all generators.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LeadSpread {
    /// Smallest ideal lead over the generators (mm).
    pub ideal_min_mm: f64,
    /// Largest ideal lead (mm).
    pub ideal_max_mm: f64,
    /// Smallest measured lead (mm).
    pub measured_min_mm: Option<f64>,
    /// Largest measured lead (mm).
    pub measured_max_mm: Option<f64>,
    /// Largest |measured - ideal| on any generator (mm).
    pub max_error_mm: Option<f64>,
}

/// One turn.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TurnRow {
    /// Turn (1-based).
    pub turn: i64,
    /// Milling jobs: the measured simple pitch diameter (groove width = half the pitch,
    /// `docs/report-format.md`) on the reference generator, and the ideal's (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pitch_diameter_mm: Option<f64>,
    /// See `pitch_diameter_mm`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ideal_pitch_diameter_mm: Option<f64>,
    /// Start.
    pub start: u32,
    /// Ideal lead (pitch for one start) on the reference generator (mm).
    pub ideal_lead_mm: Option<f64>,
    /// Measured lead there (mm).
    pub measured_lead_mm: Option<f64>,
    /// Lead over all generators.
    pub lead_spread: LeadSpread,
    /// Ideal groove width at the pitch line (mm).
    pub ideal_groove_width_mm: Option<f64>,
    /// Measured groove width (mm).
    pub groove_width_mm: Option<f64>,
    /// Ideal tooth width at the pitch line (mm).
    pub ideal_tooth_width_mm: Option<f64>,
    /// Measured tooth width (mm).
    pub tooth_width_mm: Option<f64>,
    /// Deepest cut diameter in the turn on the reference generator (mm): the root for an
    /// external thread, the crest for an internal one.
    pub min_diameter_mm: Option<f64>,
    /// Largest diameter there (mm).
    pub max_diameter_mm: Option<f64>,
    /// Helix angle of the ideal pitch helix at the pitch diameter, mid-turn (deg).
    pub helix_angle_deg: f64,
    /// Worst gouge in the turn (mm).
    pub max_gouge_mm: f64,
    /// Worst leftover in the turn (mm).
    pub max_leftover_mm: f64,
    /// Gouge volume (mm^3).
    pub gouge_volume_mm3: f64,
    /// Leftover volume (mm^3).
    pub leftover_volume_mm3: f64,
    /// Per flank.
    pub flanks: Flanks,
    /// Effective side clearance of the tool bodies in this turn (jobs with tool bodies).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_deg: Option<ClearanceRow>,
}

/// Effective side clearance (deg) of the tool body in a turn: `atan(tan a + tan l +/- tan
/// psi)` on each flank at the crest and root radii, the smallest over the passes; zero or
/// less means the body reaches the groove wall.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClearanceRow {
    /// -z flank at the crest radius.
    pub left_crest: f64,
    /// -z flank at the root radius.
    pub left_root: f64,
    /// +z flank at the crest radius.
    pub right_crest: f64,
    /// +z flank at the root radius.
    pub right_root: f64,
    /// The pass (1-based) with the smallest value.
    pub pass: usize,
}

/// A turn and flank where a tool body cut past the surface its edge cut.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InterferenceRow {
    /// Turn (1-based).
    pub turn: i64,
    /// Start.
    pub start: u32,
    /// Flank (`left`, `right`, `root`, `crest`).
    pub flank: &'static str,
    /// How far past the edge's surface (mm, axial plane).
    pub max_mm: f64,
    /// Where (deg, mm).
    pub angle_deg: f64,
    /// Axial position (mm).
    pub z_mm: f64,
    /// Volume the body cut (mm^3; an upper bound where it undercuts a flank).
    pub volume_mm3: f64,
}

/// Wall-clock times.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Timing {
    /// Building the passes and the blank.
    pub setup: f64,
    /// The sweep.
    pub sweep: f64,
    /// Deviation and volumes.
    pub compare: f64,
    /// Measurement generators.
    pub measure: f64,
    /// Everything.
    pub total: f64,
}

impl Report {
    /// The report as pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("report serializes");
        s.push('\n');
        s
    }

    /// The summary a 3D model carries (glTF `extras`): schema, job, verdict, tolerance, the
    /// thread, the deviation totals with the worst places, the findings counted by kind, and
    /// the colour scale (`scale_mm`: deviations of this size get the full colour). No timing,
    /// so the model's bytes do not change between runs.
    pub fn summary_json(&self, scale_mm: f64) -> String {
        let mut kinds = std::collections::BTreeMap::<&str, usize>::new();
        for f in &self.findings {
            *kinds.entry(f.kind.name()).or_default() += 1;
        }
        serde_json::json!({
            "schema": self.schema,
            "job": self.job,
            "verdict": self.verdict,
            "tolerance_mm": self.tolerance_mm,
            "thread": self.thread,
            "deviation": self.deviation,
            "findings": kinds,
            "colour_scale_mm": r6(scale_mm),
        })
        .to_string()
    }

    /// How lengths read for a person: inches beside mm for an inch job.
    pub(crate) fn units(&self) -> Units {
        Units {
            inch: self.thread.inch.is_some(),
        }
    }

    /// A short summary for a terminal, plain.
    pub fn summary(&self) -> String {
        self.summary_with(&SummaryStyle::default())
    }

    /// The summary dressed as `style` says: the verdict, errors and the cells of the
    /// per-turn table that are out of tolerance painted, findings grouped by kind with their
    /// counts, and the run's wall time.
    pub fn summary_with(&self, style: &SummaryStyle<'_>) -> String {
        let paint = |tone: Tone, text: &str| match style.paint {
            Some(p) => p(tone, text),
            None => text.to_string(),
        };
        let tol = self.tolerance_mm;
        let mut s = String::new();
        let name = if self.job.is_empty() {
            "job"
        } else {
            &self.job
        };
        let verdict = match self.verdict {
            Verdict::Pass => paint(Tone::Pass, "PASS"),
            Verdict::Fail => paint(Tone::Fail, "FAIL"),
        };
        let _ = writeln!(
            s,
            "{name}: {verdict} at tolerance {} mm ({} {} thread, {} turns)",
            num(tol, 4),
            self.thread.form,
            self.thread.side,
            num(self.thread.turns, 2)
        );
        let (time, what) = match style.wall_s {
            Some(t) => (t, "in all"),
            None => (self.timing_s.total, "simulating"),
        };
        let t = &self.thread;
        let _ = writeln!(
            s,
            "  thread: major diameter {} mm, pitch diameter {} mm, minor diameter {} mm, depth {} mm",
            num(t.major_diameter_mm, 4),
            num(t.pitch_diameter_mm, 4),
            num(t.minor_diameter_mm, 4),
            num((t.major_diameter_mm - t.minor_diameter_mm) / 2.0, 4)
        );
        if let Some(i) = &t.inch {
            let lead = if t.starts > 1 {
                format!("lead {} in", num(i.lead_in, 5))
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "          major diameter {} in, pitch diameter {} in, minor diameter {} in, depth {} in, {} TPI{}{lead}",
                num(i.major_diameter_in, 5),
                num(i.pitch_diameter_in, 5),
                num(i.minor_diameter_in, 5),
                num(i.depth_in, 5),
                num(i.tpi, 3),
                if lead.is_empty() { "" } else { ", " }
            );
        }
        let units = self.units();
        let _ = writeln!(
            s,
            "  simulated every {} deg and {} mm along z ({} x {} points), {} passes, {} s {what}",
            num(360.0 / self.stock.angular_cells.max(1) as f64, 4),
            num(self.stock.axial_spacing_mm, 4),
            count(self.stock.angular_cells as f64),
            count(self.stock.axial_cells as f64),
            count(self.passes as f64),
            num(time, 3)
        );
        let loc = |l: &Option<Location>| match l {
            Some(l) => format!(
                "turn {} {}{}, {} deg, {}",
                l.turn,
                l.flank,
                if matches!(l.flank, "left" | "right") {
                    " flank"
                } else {
                    ""
                },
                num(l.angle_deg, 1),
                units.z(l.z_mm)
            ),
            None => "-".to_string(),
        };
        let d = &self.deviation;
        let worst = |x: f64| {
            let cell = format!("{:>9}", num(x, 4));
            if x > tol {
                paint(Tone::Bad, &cell)
            } else {
                cell
            }
        };
        let inches = |x: f64| {
            if units.inch {
                format!(" ({} in)", num(x / units::MM_PER_INCH, 5))
            } else {
                String::new()
            }
        };
        let _ = writeln!(
            s,
            "  worst gouge    {} mm{}  {}",
            worst(d.max_gouge_mm),
            inches(d.max_gouge_mm),
            loc(&d.max_gouge_at)
        );
        let _ = writeln!(
            s,
            "  worst leftover {} mm{}  {}",
            worst(d.max_leftover_mm),
            inches(d.max_leftover_mm),
            loc(&d.max_leftover_at)
        );
        let _ = writeln!(
            s,
            "  volume removed {} mm3 (ideal {}), gouge {} mm3, leftover {} mm3",
            num(d.removed_volume_mm3, 2),
            num(d.ideal_removed_volume_mm3, 2),
            num(d.gouge_volume_mm3, 3),
            num(d.leftover_volume_mm3, 3)
        );
        if let Some(c) = &self.cycle_time_s {
            let tools: Vec<String> = c
                .tools
                .iter()
                .map(|t| {
                    let name = match (&t.name, t.tool) {
                        (Some(w), _) => w.clone(),
                        (None, Some(n)) => format!("T{n}"),
                        (None, None) => "no tool".to_string(),
                    };
                    format!("{name} {}", duration(t.seconds))
                })
                .collect();
            let _ = writeln!(
                s,
                "  cycle time {} (rapids {} at {} mm/min{}, feeds {}, threading {}, waits {}; {})",
                duration(c.total),
                duration(c.rapid),
                num(c.rapid_rate_mm_min, 0),
                if c.rapid_rate_default {
                    ", the default: [machine] rapid_rate"
                } else {
                    ""
                },
                duration(c.feed),
                duration(c.thread),
                duration(c.wait),
                tools.join(", ")
            );
        }
        match d.compared_z_mm {
            Some([lo, hi]) => {
                let _ = writeln!(
                    s,
                    "  compared z {} to {}{} (the drawing's thread); outside it (run-in, run-out) {} mm3 removed, not compared",
                    num(lo, 3),
                    num(hi, 3),
                    if units.inch {
                        format!(
                            " ({} to {} in)",
                            num(lo / units::MM_PER_INCH, 4),
                            num(hi / units::MM_PER_INCH, 4)
                        )
                    } else {
                        String::new()
                    },
                    num(d.uncompared_removed_volume_mm3, 2)
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "  nothing compared: the thread is not on the simulated stock"
                );
            }
        }
        if let Some(g) = &self.gauge {
            s.push_str(&gauge::summary(g));
        }
        let o = |v: Option<f64>| v.map_or("      -".to_string(), |x| format!("{:>7}", num(x, 3)));
        // A measured cell, painted when it misses its ideal by more than the tolerance (or
        // is missing where there is an ideal).
        let m = |ideal: Option<f64>, got: Option<f64>| {
            let cell = o(got);
            let bad = match (ideal, got) {
                (Some(i), Some(g)) => (g - i).abs() > tol,
                (Some(_), None) => true,
                _ => false,
            };
            if bad {
                paint(Tone::Bad, &cell)
            } else {
                cell
            }
        };
        let dev = |x: f64| {
            let cell = format!("{:>7}", num(x, 3));
            if x > tol {
                paint(Tone::Bad, &cell)
            } else {
                cell
            }
        };
        // An inch job's leads also as threads per inch (of the pitch: starts / lead).
        let starts = f64::from(self.thread.starts.max(1));
        let tpi = |lead: Option<f64>| {
            lead.filter(|&l| l > 0.0)
                .map_or("      -".to_string(), |l| {
                    format!("{:>7}", num(starts * units::MM_PER_INCH / l, 3))
                })
        };
        let _ = writeln!(
            s,
            "\n  turn  lead: ideal measured  groove: ideal measured  tooth: ideal measured   gouge leftover{}",
            if units.inch {
                "    TPI: ideal measured (lengths in mm)"
            } else {
                ""
            }
        );
        for t in &self.turns {
            let start = if self.thread.starts > 1 {
                format!("{}.{}", t.start + 1, t.turn)
            } else {
                t.turn.to_string()
            };
            let tpis = if units.inch {
                format!(
                    "         {} {}",
                    tpi(t.ideal_lead_mm),
                    tpi(t.measured_lead_mm)
                )
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "  {start:>4}      {} {}         {} {}        {} {}  {} {}{tpis}",
                o(t.ideal_lead_mm),
                m(t.ideal_lead_mm, t.measured_lead_mm),
                o(t.ideal_groove_width_mm),
                m(t.ideal_groove_width_mm, t.groove_width_mm),
                o(t.ideal_tooth_width_mm),
                m(t.ideal_tooth_width_mm, t.tooth_width_mm),
                dev(t.max_gouge_mm),
                dev(t.max_leftover_mm)
            );
        }
        let FindingCounts { errors, warnings } = FindingCounts::of(&self.findings);
        let _ = writeln!(s, "\n  findings: {errors} errors, {warnings} warnings");
        // Grouped by severity and kind, in report order, with the first few messages.
        let mut groups: Vec<(Severity, FindingKind, Vec<String>)> = Vec::new();
        for f in &self.findings {
            let m = located(f);
            match groups
                .iter_mut()
                .find(|g| (g.0, g.1) == (f.severity, f.kind))
            {
                Some(g) => g.2.push(m),
                None => groups.push((f.severity, f.kind, vec![m])),
            }
        }
        const SHOWN: usize = 3;
        for (severity, kind, messages) in groups {
            let tone = match severity {
                Severity::Error => Tone::Fail,
                Severity::Warning => Tone::Warning,
            };
            let head = format!("{:<7}", crate::analysis::findings::severity_name(severity));
            let _ = writeln!(s, "    {} {kind} x{}", paint(tone, &head), messages.len());
            for m in messages.iter().take(SHOWN) {
                let _ = writeln!(s, "        {m}");
            }
            if messages.len() > SHOWN {
                let _ = writeln!(
                    s,
                    "        ... {} more {kind} findings in the report",
                    messages.len() - SHOWN
                );
            }
        }
        s
    }
}

/// A finding's message led by its source (`file:line:col: ` of its NC block, or `job key
/// K: `), unless the message already names its block.
fn located(f: &Finding) -> String {
    let named = match (&f.file, f.line) {
        (Some(file), Some(line)) => f.message.starts_with(&format!("{file}:{line}:")),
        _ => false,
    };
    match f.source() {
        Some(src) if !named => format!("{src}: {}", f.message),
        _ => f.message.clone(),
    }
}

/// What a piece of the terminal summary says, for colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Tone {
    /// A pass verdict.
    Pass,
    /// A fail verdict, an error.
    Fail,
    /// A value out of tolerance.
    Bad,
    /// A warning.
    Warning,
}

/// Paints a piece of the summary for its [`Tone`] (colour on a terminal).
pub type Painter<'a> = &'a dyn Fn(Tone, &str) -> String;

/// How [`Report::summary_with`] dresses the summary.
#[derive(Clone, Copy, Default)]
pub struct SummaryStyle<'a> {
    /// Paints a piece of text (colour on a terminal); `None`: plain text.
    pub paint: Option<Painter<'a>>,
    /// The whole run's wall time (s), shown instead of the simulation's own.
    pub wall_s: Option<f64>,
}

impl std::fmt::Debug for SummaryStyle<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SummaryStyle")
            .field("paint", &self.paint.is_some())
            .field("wall_s", &self.wall_s)
            .finish()
    }
}

/// A value with `decimals` decimals, or in scientific form from ten million up (never 300
/// digits).
fn num(x: f64, decimals: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x.abs() >= 1e7 {
        format!("{x:.3e}")
    } else {
        format!("{x:.decimals$}")
    }
}

/// A count: whole below ten million, else scientific.
fn count(x: f64) -> String {
    if x.abs() < 1e7 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

/// A lathe program's cycle time (s), rounded to 0.1 ms: the parts, and per tool.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CycleTimeInfo {
    /// The whole cycle.
    pub total: f64,
    /// Rapids.
    pub rapid: f64,
    /// Feed and arc moves.
    pub feed: f64,
    /// Threading moves.
    pub thread: f64,
    /// The thread moves' waits for the one-rev signal and the dwells.
    pub wait: f64,
    /// The rapid rate used (mm/min).
    pub rapid_rate_mm_min: f64,
    /// Whether that rate is vpcut's default (the job gives no `[machine] rapid_rate`).
    pub rapid_rate_default: bool,
    /// Per tool, in the order of first use.
    pub tools: Vec<ToolTime>,
}

/// One tool's share of the cycle time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolTime {
    /// Its T number (`null` for the moves before any T word).
    pub tool: Option<u32>,
    /// The tool as the program first wrote it (`T0606`, `T="GEW_AUSSEN_3.0"`), `null` for
    /// the moves before any T word.
    pub name: Option<String>,
    /// Seconds.
    pub seconds: f64,
}

impl CycleTimeInfo {
    /// The report's rounded copy of a cycle time.
    pub(crate) fn of(c: &crate::model::setup::CycleTime) -> CycleTimeInfo {
        CycleTimeInfo {
            total: r4(c.total()),
            rapid: r4(c.rapid),
            feed: r4(c.feed),
            thread: r4(c.thread),
            wait: r4(c.wait),
            rapid_rate_mm_min: r4(c.rapid_rate),
            rapid_rate_default: !c.rapid_rate_given,
            tools: c
                .by_tool
                .iter()
                .zip(&c.tool_words)
                .map(|(&(tool, s), name)| ToolTime {
                    tool,
                    name: name.clone(),
                    seconds: r4(s),
                })
                .collect(),
        }
    }
}

/// A time in seconds as a person reads it: `12.3 s`, `2 min 05.4 s`.
fn duration(s: f64) -> String {
    if s < 60.0 {
        format!("{s:.1} s")
    } else {
        let m = (s / 60.0).floor();
        format!("{m} min {:04.1} s", s - 60.0 * m)
    }
}

/// A milling job's kernel and moves.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MillInfo {
    /// Stated bound of the path sampling on the cut surface (mm).
    pub sampling_bound_mm: f64,
    /// Path samples.
    pub samples: usize,
    /// The cutters.
    pub cutters: Vec<CutterRow>,
    /// Simple pitch diameter over all turns and generators: smallest and largest (mm).
    pub pitch_diameter_min_mm: Option<f64>,
    /// See `pitch_diameter_min_mm`.
    pub pitch_diameter_max_mm: Option<f64>,
    /// The ideal's (mm).
    pub ideal_pitch_diameter_mm: Option<f64>,
    /// Every move of the program, in order.
    pub moves: Vec<MillMoveRow>,
}

/// One cutter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CutterRow {
    /// Tool id.
    pub id: u32,
    /// Cutting diameter (mm).
    pub diameter_mm: f64,
    /// Flutes.
    pub flutes: u32,
    /// Length (mm).
    pub length_mm: f64,
}

/// One milling move and what it cut.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MillMoveRow {
    /// 1-based move number.
    #[serde(rename = "move")]
    pub index: usize,
    /// Program file and line.
    pub file: String,
    /// See `file`.
    pub line: usize,
    /// `rapid`, `feed` or `arc`.
    pub kind: &'static str,
    /// Tool id.
    pub tool: u32,
    /// Cutter radius compensation: `left` (G41), `right` (G42), absent when off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comp: Option<&'static str>,
    /// The D value in force (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comp_radius_mm: Option<f64>,
    /// Tool centre at the end (job frame, mm).
    pub end_mm: [f64; 3],
    /// Programmed feed, along the tool centre's path (mm/min).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feed_centre_mm_min: Option<f64>,
    /// The feed at the cutting edge where it makes the thread's root (mm/min): seed 001's
    /// `v1 = v2 D0 / (D0 - D2)` on an arc about the part axis.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feed_edge_mm_min: Option<f64>,
    /// Feed per tooth at the edge (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feed_per_tooth_mm: Option<f64>,
    /// Spindle speed (rev/min).
    pub spindle_rpm: f64,
    /// Volume the move removed (mm^3), from the stock.
    pub removed_volume_mm3: f64,
    /// Largest radial depth it removed at one dexel (mm): the radial engagement.
    pub radial_depth_mm: f64,
    /// Largest arc of the cutter's tooth-tip circle in uncut material (deg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub engagement_deg: Option<f64>,
    /// Largest chip thickness at the tooth tip, `fz sin(min(engagement, 90 deg))` (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chip_thickness_mm: Option<f64>,
}
