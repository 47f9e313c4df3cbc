//! The job file: TOML schema, validation, and the resolved [`Job`].
//!
//! This is the input serialization boundary. [`Job::from_toml`] takes the file's text and
//! its name (no IO here), checks every key, and returns either a [`Job`] in mm and radians
//! or a [`JobError`] that names the file, the key, its line and column, and what was
//! expected. Unknown keys are errors. The format is documented in `docs/job-format.md`.

use crate::gen::process::{self, Process};
use crate::model::helix::{Hand, Helix, LeadLaw, Spindle};
use crate::model::pass::Pass;
pub(crate) use crate::model::setup::{Blank, ChainLink, Machine};
use crate::model::solid::Solid;
use crate::model::thread::{Side, ThreadSpec, WidthRule};
use crate::model::tool::{Body, Edge, Reference, Tool};
use serde::Deserialize;
use std::fmt;

mod keys;
mod mill;
pub use mill::MillJob;

/// A job that could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JobError {
    /// The text is not valid TOML or does not fit the schema (unknown or missing key,
    /// wrong type).
    #[error("{}", render(file, *line, *col, "", message, snippet))]
    Syntax {
        /// File name as given.
        file: String,
        /// 1-based line (0 when unknown).
        line: usize,
        /// 1-based column.
        col: usize,
        /// What is wrong.
        message: String,
        /// The offending source line.
        snippet: String,
    },
    /// The job's NC program could not be interpreted.
    #[error("{0}")]
    Program(Box<crate::nc::NcError>),
    /// A key has a value that makes no sense (negative lead, tooth wider than the pitch...).
    #[error("{}", render(file, *line, *col, key, message, snippet))]
    Invalid {
        /// File name as given.
        file: String,
        /// Dotted key path, e.g. `thread.pitch.first` or `tool[1].width`.
        key: String,
        /// 1-based line (0 when unknown).
        line: usize,
        /// 1-based column.
        col: usize,
        /// What was expected.
        message: String,
        /// The offending source line.
        snippet: String,
    },
}

fn render(file: &str, line: usize, col: usize, key: &str, message: &str, snippet: &str) -> String {
    let mut s = String::new();
    if line > 0 {
        s.push_str(&format!("{file}:{line}:{col}: "));
    } else {
        s.push_str(&format!("{file}: "));
    }
    if !key.is_empty() {
        s.push_str(&format!("`{key}`: "));
    }
    s.push_str(message);
    if line > 0 && !snippet.is_empty() {
        let num = line.to_string();
        let pad = " ".repeat(num.len());
        let (snippet, col) = crate::nc::clip_line(snippet, col);
        s.push_str(&format!(
            "\n{pad} |\n{num} | {snippet}\n{pad} | {}^",
            " ".repeat(col.saturating_sub(1))
        ));
    }
    s
}

/// Simulation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Axial dexel spacing (mm).
    pub axial_spacing: f64,
    /// Number of angular columns.
    pub angular_cells: usize,
    /// Deviation tolerance (mm).
    pub tolerance: f64,
    /// Axial window of interest; the grid covers the blank clipped to it.
    pub z_range: Option<(f64, f64)>,
    /// Dexel budget (both surfaces).
    pub max_dexels: u64,
    /// Axial spacing of the measurement generators (mm).
    pub measure_spacing: f64,
    /// Number of measurement generators.
    pub measure_generators: usize,
}

/// Default dexel budget: about 0.8 GB of f32 radii.
pub const DEFAULT_MAX_DEXELS: u64 = 200_000_000;

/// The thread form's name, as written in the job.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FormName {
    /// Rectangular / square thread.
    Square,
    /// ISO 2904 trapezoidal, 30 degrees.
    Trapezoidal,
    /// ISO 68-1 metric, 60 degrees.
    IsoMetric,
    /// Unified (UN), 60 degrees.
    Unified,
    /// ACME, 29 degrees.
    Acme,
    /// Buttress (sawtooth): asymmetric flanks.
    Buttress,
    /// Any V or trapezoid with explicit flank angles.
    V,
}

impl FormName {
    /// The name as written in a job.
    pub fn name(self) -> &'static str {
        match self {
            FormName::Square => "square",
            FormName::Trapezoidal => "trapezoidal",
            FormName::IsoMetric => "iso-metric",
            FormName::Unified => "unified",
            FormName::Acme => "acme",
            FormName::Buttress => "buttress",
            FormName::V => "v",
        }
    }
}

/// A resolved job.
#[derive(Clone, Debug)]
pub struct Job {
    /// Name (from the file, or empty).
    pub name: String,
    /// The blank.
    pub blank: Blank,
    /// The form's name.
    pub form: FormName,
    /// The thread wanted.
    pub thread: ThreadSpec,
    /// Tools; passes refer to them by index.
    pub tools: Vec<Tool>,
    /// Threading passes, explicit ones first, then generated ones.
    pub passes: Vec<Pass>,
    /// Machine data.
    pub machine: Machine,
    /// Simulation settings.
    pub sim: SimConfig,
    /// Warnings from interpreting the `[program]` (skipped unknown words and codes).
    pub program_warnings: Vec<crate::nc::Diagnostic>,
    /// Joints of continuous thread chains in the program (see [`ChainLink`]).
    pub chains: Vec<ChainLink>,
    /// Where the passes that come from the `[program]` are in it: (pass index, file as the
    /// job names the program, 1-based line of the thread block). Empty without a program.
    pub pass_blocks: Vec<(usize, String, usize)>,
    /// A milling job (`[machine] kind = "mill"`): its cutters and path. Its `tools` and
    /// `passes` are empty.
    pub mill: Option<MillJob>,
    /// The drawing's limits of the pitch diameter (a tolerance class such as ISO 965 6H):
    /// checked on the measured simple pitch diameter of every turn (milling jobs).
    pub pitch_diameter_limits: Option<(f64, f64)>,
    /// The plan of `[process] kind = "plan"`, whose passes are [`Job::passes`].
    pub plan: Option<crate::gen::plan::Plan>,
}

// ---------------------------------------------------------------------------------------
// Raw schema.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawJob {
    name: Option<String>,
    blank: RawBlank,
    thread: RawThread,
    #[serde(default)]
    tool: Vec<RawTool>,
    #[serde(default)]
    pass: Vec<RawPass>,
    process: Option<RawProcess>,
    program: Option<RawProgram>,
    #[serde(default)]
    machine: RawMachine,
    #[serde(default)]
    simulation: RawSimulation,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProgram {
    file: String,
    dialect: String,
    /// Unknown words and codes are errors, not warnings.
    #[serde(default)]
    strict: bool,
    /// Thread chamfer (pull-out) of G92/G76 in leads (FANUC parameter 5130 / 10).
    #[serde(default)]
    thread_chamfer: f64,
    /// Work offsets `G54`..`G59` = { x = diameter, z }.
    #[serde(default)]
    work_offsets: std::collections::BTreeMap<String, RawOffset>,
    /// Skip blocks that start with `/` (the operator's block-skip switch).
    #[serde(default = "yes")]
    block_skip: bool,
    /// Where G28 goes: { x = diameter, z } in the job's frame.
    reference_point: Option<RawPoint>,
    /// FANUC/GSK lathe G-code system: "A" (default), "B" or "C".
    gcode_system: Option<String>,
    /// Where FANUC/GSK G30 (and LinuxCNC's G30 at the start) goes: { x = diameter, z }.
    second_reference_point: Option<RawPoint>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPoint {
    x: f64,
    z: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawOffset {
    #[serde(default)]
    x: f64,
    y: Option<f64>,
    #[serde(default)]
    z: f64,
}

fn yes() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBlank {
    diameter: f64,
    #[serde(default)]
    bore: f64,
    length: f64,
    #[serde(default)]
    z_front: f64,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum SideName {
    #[default]
    External,
    Internal,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum HandName {
    #[default]
    Right,
    Left,
}

/// `pitch = 6.0` or `pitch = { first, increment, last | turns }`.
enum RawPitch {
    Constant(f64),
    Series(RawSeries),
}

impl<'de> Deserialize<'de> for RawPitch {
    /// A number or a table, told apart by what the file holds; any other value is an error
    /// that says both forms (an untagged enum would only say that nothing matched).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Pitch;
        impl<'de> serde::de::Visitor<'de> for Pitch {
            type Value = RawPitch;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a pitch in mm or a table { first = .., increment = .., last = .. or turns = .. }")
            }
            fn visit_f64<E>(self, v: f64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<RawPitch, A::Error> {
                RawSeries::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(RawPitch::Series)
            }
        }
        d.deserialize_any(Pitch)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSeries {
    first: f64,
    increment: f64,
    last: Option<f64>,
    turns: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWidth {
    groove: Option<f64>,
    tooth: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawThread {
    #[serde(default)]
    side: SideName,
    form: FormName,
    flank_angle: Option<f64>,
    #[serde(default, deserialize_with = "keys::fixed")]
    flank_angles: Option<[f64; 2]>,
    major_diameter: f64,
    minor_diameter: Option<f64>,
    pitch_diameter: Option<f64>,
    #[serde(default)]
    hand: HandName,
    #[serde(default = "one")]
    starts: u32,
    #[serde(default)]
    z_start: f64,
    #[serde(default)]
    start_angle: f64,
    pitch: RawPitch,
    length: Option<f64>,
    turns: Option<f64>,
    width: Option<RawWidth>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pitch_diameter_limits: Option<[f64; 2]>,
}

fn one() -> u32 {
    1
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum ToolKind {
    Grooving,
    Threading,
    Trapezoidal,
    Mesh,
    ThreadMill,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum RefName {
    #[default]
    Center,
    Left,
    Right,
    Tip,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTool {
    id: u32,
    kind: ToolKind,
    width: Option<f64>,
    angle: Option<f64>,
    tip_flat: Option<f64>,
    nose_radius: Option<f64>,
    tip_width: Option<f64>,
    flank_angle: Option<f64>,
    #[serde(default, deserialize_with = "keys::fixed")]
    flank_angles: Option<[f64; 2]>,
    reference: Option<RefName>,
    length: Option<f64>,
    file: Option<String>,
    #[serde(default, deserialize_with = "keys::fixed")]
    mesh_origin: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "keys::fixed")]
    mesh_axes: Option<[String; 3]>,
    mesh_units: Option<String>,
    mesh_body: Option<bool>,
    cutter: Option<mill::CutterName>,
    diameter: Option<f64>,
    pitch: Option<f64>,
    teeth: Option<u32>,
    tooth_depth: Option<f64>,
    first_tooth: Option<f64>,
    shank_diameter: Option<f64>,
    neck: Option<f64>,
    flutes: Option<u32>,
    drill_diameter: Option<f64>,
    point_angle: Option<f64>,
    chamfer_diameter: Option<f64>,
    h: Option<u32>,
    d: Option<u32>,
    d_value: Option<f64>,
    thickness: Option<f64>,
    side_clearance_left: Option<f64>,
    side_clearance_right: Option<f64>,
    front_clearance: Option<f64>,
    inclination: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPass {
    tool: u32,
    x: f64,
    x_end: Option<f64>,
    z_start: f64,
    z_end: f64,
    lead: f64,
    #[serde(default)]
    lead_change: f64,
    #[serde(default)]
    start_angle: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProcess {
    kind: process::Kind,
    tool: u32,
    layers: Option<u32>,
    depths: Option<Vec<f64>>,
    #[serde(default)]
    schedule: process::Schedule,
    layer_depth: Option<f64>,
    #[serde(default)]
    method: process::AxialMethod,
    z_from: Option<f64>,
    z_to: Option<f64>,
    origin_z: Option<f64>,
    root_width: Option<f64>,
    max_depth: Option<f64>,
    min_depth: Option<f64>,
    infeed: Option<crate::gen::plan::Infeed>,
    finish_passes: Option<u32>,
    spring_passes: Option<u32>,
    finish_allowance: Option<f64>,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum SpindleName {
    #[default]
    Cw,
    Ccw,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMachine {
    #[serde(default)]
    kind: mill::MachineKind,
    #[serde(default, deserialize_with = "keys::fixed")]
    axis: Option<[f64; 2]>,
    home_z: Option<f64>,
    #[serde(default = "default_rpm")]
    spindle_rpm: f64,
    max_feed: Option<f64>,
    acceleration: Option<f64>,
    #[serde(default)]
    spindle: SpindleName,
}

fn default_rpm() -> f64 {
    200.0
}

impl Default for RawMachine {
    fn default() -> Self {
        RawMachine {
            kind: mill::MachineKind::Lathe,
            axis: None,
            home_z: None,
            spindle_rpm: default_rpm(),
            max_feed: None,
            acceleration: None,
            spindle: SpindleName::Cw,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSimulation {
    #[serde(default = "default_spacing")]
    axial_spacing: f64,
    #[serde(default = "default_cells")]
    angular_cells: usize,
    #[serde(default = "default_tolerance")]
    tolerance: f64,
    #[serde(default, deserialize_with = "keys::fixed")]
    z_range: Option<[f64; 2]>,
    max_dexels: Option<u64>,
    #[serde(default = "default_measure_spacing")]
    measure_spacing: f64,
    #[serde(default = "default_generators")]
    measure_generators: usize,
}

fn default_spacing() -> f64 {
    0.01
}
fn default_cells() -> usize {
    3600
}
fn default_tolerance() -> f64 {
    0.01
}
fn default_measure_spacing() -> f64 {
    0.0005
}
fn default_generators() -> usize {
    12
}

impl Default for RawSimulation {
    fn default() -> Self {
        RawSimulation {
            axial_spacing: default_spacing(),
            angular_cells: default_cells(),
            tolerance: default_tolerance(),
            z_range: None,
            max_dexels: None,
            measure_spacing: default_measure_spacing(),
            measure_generators: default_generators(),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Locating keys in the source.

/// Byte offset to 1-based line and column.
fn line_col(src: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(src.len());
    let before = &src[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn source_line(src: &str, line: usize) -> String {
    src.lines()
        .nth(line.saturating_sub(1))
        .unwrap_or("")
        .to_string()
}

/// Find the span of a dotted key path (`tool[1].width`, `thread.pitch.first`) in `src`.
/// Falls back to the nearest existing parent.
fn locate(src: &str, key: &str) -> Option<std::ops::Range<usize>> {
    let doc = toml_edit::ImDocument::parse(src).ok()?;
    let mut item: &toml_edit::Item = doc.as_item();
    let mut best = None;
    for part in key.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (n, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (part, None),
        };
        if let Some(s) = key_span(item, name) {
            best = Some(s);
        }
        let Some(mut next) = item.get(name) else {
            break;
        };
        if let Some(i) = index {
            let Some(n) = next.get(i) else {
                break;
            };
            next = n;
        }
        if let Some(s) = next.span() {
            best = Some(s);
        }
        item = next;
    }
    best
}

fn key_span(item: &toml_edit::Item, name: &str) -> Option<std::ops::Range<usize>> {
    match item {
        toml_edit::Item::Table(t) => t.key(name).and_then(|k| k.span()),
        toml_edit::Item::Value(toml_edit::Value::InlineTable(t)) => {
            t.key(name).and_then(|k| k.span())
        }
        _ => None,
    }
}

/// Collects the context for validation errors.
struct Ctx<'a> {
    src: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, key: &str, message: impl fmt::Display) -> JobError {
        let (line, col) = locate(self.src, key)
            .map(|r| line_col(self.src, r.start))
            .unwrap_or((0, 0));
        JobError::Invalid {
            file: self.file.to_string(),
            key: key.to_string(),
            line,
            col,
            message: message.to_string(),
            snippet: source_line(self.src, line),
        }
    }

    fn finite(&self, key: &str, v: f64) -> Result<f64, JobError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a finite number, got {v}")))
        }
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a number > 0, got {v}")))
        }
    }

    fn non_negative(&self, key: &str, v: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a number >= 0, got {v}")))
        }
    }

    fn angle(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v >= lo && v < hi {
            Ok(v.to_radians())
        } else {
            Err(self.err(
                key,
                format!("expected an angle in [{lo}, {hi}) degrees, got {v}"),
            ))
        }
    }
}

// ---------------------------------------------------------------------------------------
// Resolution.

impl Job {
    /// Parse and validate a job. `file` is only used in messages. A job with a `[program]`
    /// needs [`Job::from_toml_with`].
    pub fn from_toml(src: &str, file: &str) -> Result<Job, JobError> {
        Job::from_toml_with(src, file, &|_| None)
    }

    /// Parse and validate a job whose `[program]` (and its subprograms) `load` returns by
    /// name, relative to the job file. The library itself reads no files.
    pub fn from_toml_with(
        src: &str,
        file: &str,
        load: &dyn Fn(&str) -> Option<String>,
    ) -> Result<Job, JobError> {
        Job::from_toml_opts(src, file, load, false)
    }

    /// As [`Job::from_toml_with`]; `strict` makes unknown words and codes in the program
    /// errors (as `[program] strict = true` does).
    pub fn from_toml_opts(
        src: &str,
        file: &str,
        load: &dyn Fn(&str) -> Option<String>,
        strict: bool,
    ) -> Result<Job, JobError> {
        let raw: RawJob = toml::from_str(src).map_err(|e| keys::schema_error(src, file, &e))?;
        keys::check_numbers(src, file)?;
        let cx = Ctx { src, file };
        resolve(raw, &cx, load, strict)
    }
}

fn resolve(
    raw: RawJob,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
    strict: bool,
) -> Result<Job, JobError> {
    let b = &raw.blank;
    let blank = Blank {
        diameter: cx.positive("blank.diameter", b.diameter)?,
        bore: cx.non_negative("blank.bore", b.bore)?,
        length: cx.positive("blank.length", b.length)?,
        z_front: cx.finite("blank.z_front", b.z_front)?,
    };
    if blank.bore >= blank.diameter {
        return Err(cx.err("blank.bore", "expected a bore smaller than the diameter"));
    }
    let machine = Machine {
        spindle_rpm: cx.positive("machine.spindle_rpm", raw.machine.spindle_rpm)?,
        max_feed: raw
            .machine
            .max_feed
            .map(|v| cx.positive("machine.max_feed", v))
            .transpose()?,
        acceleration: raw
            .machine
            .acceleration
            .map(|v| cx.positive("machine.acceleration", v))
            .transpose()?,
        spindle: match raw.machine.spindle {
            SpindleName::Cw => Spindle::Cw,
            SpindleName::Ccw => Spindle::Ccw,
        },
    };
    let s = &raw.simulation;
    let sim = SimConfig {
        axial_spacing: cx.positive("simulation.axial_spacing", s.axial_spacing)?,
        angular_cells: if s.angular_cells >= 4 {
            s.angular_cells
        } else {
            return Err(cx.err("simulation.angular_cells", "expected at least 4 cells"));
        },
        tolerance: cx.positive("simulation.tolerance", s.tolerance)?,
        z_range: match s.z_range {
            None => None,
            Some([a, b]) => {
                cx.finite("simulation.z_range", a)?;
                cx.finite("simulation.z_range", b)?;
                if a >= b {
                    return Err(cx.err(
                        "simulation.z_range",
                        "expected [z_min, z_max] with z_min < z_max",
                    ));
                }
                Some((a, b))
            }
        },
        max_dexels: s.max_dexels.unwrap_or(DEFAULT_MAX_DEXELS),
        measure_spacing: cx.positive("simulation.measure_spacing", s.measure_spacing)?,
        measure_generators: if (1..=3600).contains(&s.measure_generators) {
            s.measure_generators
        } else {
            return Err(cx.err(
                "simulation.measure_generators",
                "expected 1 to 3600 generators",
            ));
        },
    };
    let (thread, form) = resolve_thread(&raw.thread, &blank, cx)?;
    // The grid must resolve the thread (and a pitch far below the spacing would make the
    // ideal profile of each column enormous).
    let p_min = thread
        .pitch_of_turn(1)
        .min(thread.pitch_of_turn(thread.turns.ceil().max(1.0) as i64));
    if sim.axial_spacing * 4.0 > p_min {
        return Err(cx.err(
            "simulation.axial_spacing",
            format!(
                "expected at most a quarter of the smallest pitch ({p_min:.4} mm), got {}",
                sim.axial_spacing
            ),
        ));
    }
    for (i, t) in raw.tool.iter().enumerate() {
        if raw.tool[..i].iter().any(|o| o.id == t.id) {
            return Err(cx.err(
                &format!("tool[{i}].id"),
                format!("tool id {} is used twice", t.id),
            ));
        }
        check_tool_keys(t, i, cx)?;
    }
    if raw.machine.kind == mill::MachineKind::Mill {
        if raw.machine.spindle != SpindleName::Cw {
            return Err(cx.err(
                "machine.spindle",
                "a mill's spindle direction comes from the program (M03/M04)",
            ));
        }
        let (mill, program_warnings) =
            mill::resolve_mill(&raw, blank.z_front, machine.spindle_rpm, cx, load, strict)?;
        let pitch_diameter_limits = match raw.thread.pitch_diameter_limits {
            Some([a, b]) => {
                let key = "thread.pitch_diameter_limits";
                if cx.positive(key, a)? >= cx.positive(key, b)? {
                    return Err(cx.err(key, "expected [smallest, largest] pitch diameter (mm)"));
                }
                Some((a, b))
            }
            None => None,
        };
        return Ok(Job {
            name: raw.name.unwrap_or_default(),
            blank,
            form,
            thread,
            tools: Vec::new(),
            passes: Vec::new(),
            machine,
            sim,
            program_warnings,
            chains: Vec::new(),
            pass_blocks: Vec::new(),
            mill: Some(mill),
            pitch_diameter_limits,
            plan: None,
        });
    }
    if raw.thread.pitch_diameter_limits.is_some() {
        return Err(cx.err(
            "thread.pitch_diameter_limits",
            "the pitch diameter is measured on milling jobs only, for now",
        ));
    }
    if raw.machine.axis.is_some() || raw.machine.home_z.is_some() {
        return Err(cx.err(
            if raw.machine.axis.is_some() {
                "machine.axis"
            } else {
                "machine.home_z"
            },
            "this key is for milling jobs ([machine] kind = \"mill\")",
        ));
    }
    let mut tools = Vec::with_capacity(raw.tool.len());
    for (i, t) in raw.tool.iter().enumerate() {
        tools.push(resolve_tool(t, i, cx, load)?);
    }
    let tool_index = |id: u32, key: &str| -> Result<usize, JobError> {
        tools.iter().position(|t| t.id == id).ok_or_else(|| {
            let ids: Vec<String> = tools.iter().map(|t| t.id.to_string()).collect();
            cx.err(
                key,
                format!(
                    "no [[tool]] with id {id} (defined: {})",
                    if ids.is_empty() {
                        "none".into()
                    } else {
                        ids.join(", ")
                    }
                ),
            )
        })
    };
    let mut passes = Vec::new();
    for (i, p) in raw.pass.iter().enumerate() {
        let key = |k: &str| format!("pass[{i}].{k}");
        let pass = Pass {
            tool: tool_index(p.tool, &key("tool"))?,
            x_start: cx.positive(&key("x"), p.x)?,
            x_end: cx.positive(&key("x_end"), p.x_end.unwrap_or(p.x))?,
            z_start: cx.finite(&key("z_start"), p.z_start)?,
            z_end: cx.finite(&key("z_end"), p.z_end)?,
            lead: cx.positive(&key("lead"), p.lead)?,
            lead_change: cx.finite(&key("lead_change"), p.lead_change)?,
            start_angle: cx.finite(&key("start_angle"), p.start_angle)?.to_radians(),
            spindle: machine.spindle,
        };
        check_pass(&pass, &key, cx)?;
        passes.push(pass);
    }
    let mut plan = None;
    if let Some(pr) = raw
        .process
        .as_ref()
        .filter(|p| p.kind == process::Kind::Plan)
    {
        let p = plan_process(pr, &thread, &tools, &blank, &machine, &sim, &tool_index, cx)?;
        passes.extend(p.passes());
        plan = Some(p);
    } else if let Some(pr) = &raw.process {
        if let Some(key) = pr.plan_key() {
            return Err(cx.err(
                &format!("process.{key}"),
                "this key belongs to the planner (`kind = \"plan\"`)",
            ));
        }
        let process = Process {
            kind: pr.kind,
            tool: tool_index(pr.tool, "process.tool")?,
            layers: pr.layers,
            depths: pr.depths.clone(),
            schedule: pr.schedule,
            layer_depth: pr.layer_depth,
            method: pr.method,
            z_from: pr.z_from,
            z_to: pr.z_to,
            origin_z: pr.origin_z,
            root_width: pr.root_width,
        };
        let generated = process::generate(&process, &thread, &tools, &blank, machine.spindle)
            .map_err(|e| cx.err(&format!("process.{}", e.key), e.message))?;
        for (i, p) in generated.iter().enumerate() {
            check_pass(
                p,
                &|k: &str| format!("process (generated pass {i}, {k})"),
                cx,
            )?;
        }
        passes.extend(generated);
    }
    let mut program_warnings = Vec::new();
    let mut chains = Vec::new();
    let mut pass_blocks = Vec::new();
    if let Some(pr) = &raw.program {
        let ProgramPasses {
            passes: more,
            links,
            warnings: w,
            blocks,
        } = program_passes(pr, &tools, cx, load, strict)?;
        let offset = passes.len();
        chains.extend(links.into_iter().map(|mut l| {
            l.pass += offset;
            l
        }));
        pass_blocks.extend(
            blocks
                .into_iter()
                .enumerate()
                .map(|(i, (file, line))| (offset + i, file, line)),
        );
        passes.extend(more);
        program_warnings = w;
    }
    if passes.is_empty() {
        return Err(cx.err(
            "pass",
            "expected at least one [[pass]], a [process] or a [program] with threading moves",
        ));
    }
    Ok(Job {
        name: raw.name.unwrap_or_default(),
        blank,
        form,
        thread,
        tools,
        passes,
        machine,
        sim,
        program_warnings,
        chains,
        pass_blocks,
        mill: None,
        pitch_diameter_limits: None,
        plan,
    })
}

impl Job {
    /// This job with its passes replaced by those of an NC program: `text`, read as
    /// `file` in `dialect` (`fanuc`, `gsk980`, `siemens-802d`, `linuxcnc`), strictly (every
    /// word must be understood). The round trip of `vpcut plan`.
    pub fn with_program(&self, file: &str, text: &str, dialect: &str) -> Result<Job, JobError> {
        let pr = RawProgram {
            file: file.to_string(),
            dialect: dialect.to_string(),
            strict: true,
            thread_chamfer: 0.0,
            work_offsets: Default::default(),
            block_skip: true,
            reference_point: None,
            gcode_system: None,
            second_reference_point: None,
        };
        let cx = Ctx { src: "", file };
        let load = |name: &str| (name == file).then(|| text.to_string());
        let ProgramPasses {
            passes,
            links,
            warnings,
            blocks,
        } = program_passes(&pr, &self.tools, &cx, &load, true)?;
        Ok(Job {
            passes,
            chains: links,
            program_warnings: warnings,
            pass_blocks: blocks
                .into_iter()
                .enumerate()
                .map(|(i, (file, line))| (i, file, line))
                .collect(),
            plan: None,
            ..self.clone()
        })
    }
}

impl RawProcess {
    /// The first planner key given to another generator.
    fn plan_key(&self) -> Option<&'static str> {
        [
            ("max_depth", self.max_depth.is_some()),
            ("min_depth", self.min_depth.is_some()),
            ("infeed", self.infeed.is_some()),
            ("finish_passes", self.finish_passes.is_some()),
            ("spring_passes", self.spring_passes.is_some()),
            ("finish_allowance", self.finish_allowance.is_some()),
        ]
        .into_iter()
        .find(|k| k.1)
        .map(|k| k.0)
    }
}

/// `[process] kind = "plan"`: the planner's limits, and the plan.
#[allow(clippy::too_many_arguments)]
fn plan_process(
    pr: &RawProcess,
    thread: &ThreadSpec,
    tools: &[Tool],
    blank: &Blank,
    machine: &Machine,
    sim: &SimConfig,
    tool_index: &dyn Fn(u32, &str) -> Result<usize, JobError>,
    cx: &Ctx,
) -> Result<crate::gen::plan::Plan, JobError> {
    for (key, given) in [
        ("layers", pr.layers.is_some()),
        ("depths", pr.depths.is_some()),
        ("layer_depth", pr.layer_depth.is_some()),
        ("origin_z", pr.origin_z.is_some()),
        ("root_width", pr.root_width.is_some()),
        ("z_from", pr.z_from.is_some()),
        ("z_to", pr.z_to.is_some()),
    ] {
        if given {
            return Err(cx.err(
                &format!("process.{key}"),
                "the planner chooses its layers and runs itself: give max_depth, min_depth, schedule, infeed, finish_allowance, finish_passes, spring_passes",
            ));
        }
    }
    let max_depth = pr.max_depth.ok_or_else(|| {
        cx.err(
            "process.max_depth",
            "the planner needs max_depth (mm per pass)",
        )
    })?;
    let allowance = pr.finish_allowance.unwrap_or(0.0);
    let limits = crate::gen::plan::Limits {
        max_depth,
        min_depth: pr.min_depth.unwrap_or(0.0),
        schedule: pr.schedule,
        infeed: pr.infeed.unwrap_or_default(),
        finish_passes: pr
            .finish_passes
            .unwrap_or(if allowance > 0.0 { 1 } else { 0 }),
        spring_passes: pr.spring_passes.unwrap_or(0),
        finish_allowance: allowance,
    };
    let tool = tool_index(pr.tool, "process.tool")?;
    crate::gen::plan::plan(&limits, tool, thread, tools, blank, machine, sim.tolerance)
        .map_err(|e| cx.err(&format!("process.{}", e.key), e.message))
}

/// What a job's program gives: its passes, the joints of its thread chains and the
/// interpreter's warnings.
struct ProgramPasses {
    passes: Vec<Pass>,
    links: Vec<ChainLink>,
    warnings: Vec<crate::nc::Diagnostic>,
    /// Each pass's thread block: file and line.
    blocks: Vec<(String, usize)>,
}

/// Interpret the job's program and turn its threading moves into passes, with the joints
/// of its thread chains (pass indices counted from the program's first pass). A chained
/// move's sync angle already continues the previous move's phase (`nc::chain`), so every
/// pass is built the same way.
fn program_passes(
    pr: &RawProgram,
    tools: &[Tool],
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
    strict: bool,
) -> Result<ProgramPasses, JobError> {
    use crate::nc::{MoveKind, Settings};
    let mut settings = Settings {
        thread_chamfer: cx.non_negative("program.thread_chamfer", pr.thread_chamfer)?,
        block_skip: pr.block_skip,
        ..Settings::default()
    };
    if settings.thread_chamfer > 9.9 {
        return Err(cx.err(
            "program.thread_chamfer",
            format!(
                "expected at most 9.9 leads (FANUC's 99 x 0.1 L), got {}",
                settings.thread_chamfer
            ),
        ));
    }
    if let Some(g) = &pr.gcode_system {
        settings.gcode_system = crate::nc::GcodeSystem::from_name(g).ok_or_else(|| {
            cx.err(
                "program.gcode_system",
                format!("expected \"A\", \"B\" or \"C\" (FANUC lathe G-code system), got `{g}`"),
            )
        })?;
    }
    if let Some(p) = &pr.second_reference_point {
        settings.second_reference_point = Some((
            cx.finite("program.second_reference_point.x", p.x)?,
            cx.finite("program.second_reference_point.z", p.z)?,
        ));
    }
    if let Some(p) = &pr.reference_point {
        settings.reference_point = Some((
            cx.finite("program.reference_point.x", p.x)?,
            cx.finite("program.reference_point.z", p.z)?,
        ));
    }
    for (name, off) in &pr.work_offsets {
        let key = format!("program.work_offsets.{name}");
        let i = work_index(name)
            .ok_or_else(|| cx.err(&key, format!("expected one of G54..G59, got `{name}`")))?;
        if off.y.is_some() {
            return Err(cx.err(
                &format!("{key}.y"),
                "a lathe's work offsets have x (a diameter) and z; y is for milling jobs",
            ));
        }
        settings.work_offsets[i] = (
            cx.finite(&format!("{key}.x"), off.x)?,
            cx.finite(&format!("{key}.z"), off.z)?,
        );
    }
    let toolpath = run_program(pr, settings, cx, load, strict)?;
    let moves = toolpath.moves;
    let fail = |m: &crate::nc::Move, message: String| move_error(&m.file, m.line, message);
    let mut out: Vec<Pass> = Vec::new();
    let mut links = Vec::new();
    let mut blocks = Vec::new();
    // A thread move that goes nowhere (a repeated block) cuts nothing.
    let goes = |m: &&crate::nc::Move| m.z != m.z_start || m.x_dia != m.x_start;
    for m in moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .filter(goes)
    {
        let tool = match m.tool {
            Some(id) => tools.iter().position(|t| t.id == id),
            None if tools.len() == 1 => Some(0),
            None => None,
        }
        .ok_or_else(|| {
            fail(
                m,
                format!(
                    "threading with tool {:?}, which the job's [[tool]] list does not define",
                    m.tool
                ),
            )
        })?;
        let angle = m.sync_angle_deg.unwrap_or(0.0).to_radians();
        let pass = Pass {
            tool,
            x_start: m.x_start,
            x_end: m.x_dia,
            z_start: m.z_start,
            z_end: m.z,
            lead: m.lead.unwrap_or(0.0),
            lead_change: m.lead_change.unwrap_or(0.0),
            // The thread starts `angle` past the index pulse; the part turns under the
            // tool, so the part angle under it is -angle with M03 and +angle with M04.
            start_angle: -m.spindle.sign() * angle,
            spindle: m.spindle,
        };
        if pass.lead <= 0.0 || pass.z_start == pass.z_end || pass.revolutions().is_none() {
            return Err(fail(m, format!("threading move to z = {}: the lead is not positive all the way (a real control alarms)", m.z)));
        }
        if m.chained {
            if let Some(prev) = out.last() {
                links.push(ChainLink {
                    pass: out.len(),
                    file: m.file.clone(),
                    line: m.line,
                    z: pass.z_start,
                    lead_before: prev.end_lead().unwrap_or(prev.lead),
                    change_before: prev.lead_change,
                    lead_after: pass.lead,
                    change_after: pass.lead_change,
                });
            }
        }
        blocks.push((m.file.clone(), m.line));
        out.push(pass);
    }
    Ok(ProgramPasses {
        passes: out,
        links,
        warnings: toolpath.warnings,
        blocks,
    })
}

/// An error about a program's move (its block, as a whole).
fn move_error(file: &str, line: usize, message: String) -> JobError {
    JobError::Program(Box::new(crate::nc::NcError {
        file: file.to_string(),
        line,
        col: 0,
        message,
        snippet: String::new(),
        stack: Vec::new(),
        hint: None,
        others: Vec::new(),
    }))
}

/// G54..G59 as an index.
fn work_index(name: &str) -> Option<usize> {
    ["G54", "G55", "G56", "G57", "G58", "G59"]
        .iter()
        .position(|g| *g == name)
}

/// Read the job's program (and its subprograms, through `load`) and interpret it with
/// `settings`.
fn run_program(
    pr: &RawProgram,
    settings: crate::nc::Settings,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
    strict: bool,
) -> Result<crate::nc::Toolpath, JobError> {
    use crate::nc::{interpret_with, Dialect, Options, Source};
    let dialect = Dialect::from_name(&pr.dialect).ok_or_else(|| {
        cx.err(
            "program.dialect",
            format!(
                "expected `fanuc`, `gsk980`, `linuxcnc` or `siemens-802d`, got `{}`",
                pr.dialect
            ),
        )
    })?;
    let text = load(&pr.file).ok_or_else(|| {
        cx.err(
            "program.file",
            format!("cannot read `{}` (relative to the job file)", pr.file),
        )
    })?;
    let main = Source {
        name: pr.file.clone(),
        text,
    };
    let loader = |name: &str| {
        load(name).map(|text| Source {
            name: name.to_string(),
            text,
        })
    };
    let opts = Options {
        strict: strict || pr.strict,
        settings,
        ..Options::default()
    };
    interpret_with(&main, dialect, &loader, &opts).map_err(|e| JobError::Program(Box::new(e)))
}

fn check_pass(p: &Pass, key: &dyn Fn(&str) -> String, cx: &Ctx) -> Result<(), JobError> {
    if p.z_start == p.z_end {
        return Err(cx.err(&key("z_end"), "expected z_end different from z_start"));
    }
    if p.revolutions().is_none() {
        let law = p.helix().law;
        let at = law
            .zero_lead_revs()
            .map(|t| {
                format!(
                    " after {t:.3} revolutions ({:.3} mm of travel)",
                    law.travel(t)
                )
            })
            .unwrap_or_default();
        return Err(cx.err(
            &key("lead_change"),
            format!(
                "the lead would reach zero{at} before z_end = {}; a real control alarms here",
                p.z_end
            ),
        ));
    }
    Ok(())
}

/// Standard depth data of a form for a constant pitch `p`: (included angle, minor
/// diameter from major `d`, pitch diameter from `d`).
fn form_defaults(
    form: FormName,
    side: Side,
    d: f64,
    p: Option<f64>,
) -> (Option<f64>, Option<f64>, Option<f64>) {
    match (form, p) {
        (FormName::Square, _) => (Some(0.0), None, None),
        (FormName::Trapezoidal, Some(p)) => {
            // ISO 2904: h3 = 0.5P + ac, d2 = d - 0.5P.
            let ac = if p <= 1.5 {
                0.15
            } else if p <= 5.0 {
                0.25
            } else if p <= 12.0 {
                0.5
            } else {
                1.0
            };
            (
                Some(30.0),
                Some(d - 2.0 * (0.5 * p + ac)),
                Some(d - 0.5 * p),
            )
        }
        (FormName::Trapezoidal, None) => (Some(30.0), None, None),
        (FormName::IsoMetric | FormName::Unified, Some(p)) => {
            // ISO 68-1: d2 = d - 0.649519P; external design root d3 = d - 1.226869P,
            // internal minor D1 = D - 1.082532P.
            let minor = match side {
                Side::External => d - 1.226_869 * p,
                Side::Internal => d - 1.082_532 * p,
            };
            (Some(60.0), Some(minor), Some(d - 0.649_519 * p))
        }
        (FormName::IsoMetric | FormName::Unified, None) => (Some(60.0), None, None),
        (FormName::Acme, Some(p)) => (
            Some(29.0),
            Some(d - 2.0 * (0.5 * p + 0.254)),
            Some(d - 0.5 * p),
        ),
        (FormName::Acme, None) => (Some(29.0), None, None),
        (FormName::Buttress | FormName::V, _) => (None, None, None),
    }
}

/// A length for a message: at most 4 decimals, no trailing zeros, no 300-digit values.
fn fmt_mm(v: f64) -> String {
    if !v.is_finite() || v.abs() >= 1e9 {
        return format!("{v:.3e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn resolve_thread(
    t: &RawThread,
    blank: &Blank,
    cx: &Ctx,
) -> Result<(ThreadSpec, FormName), JobError> {
    let side = match t.side {
        SideName::External => Side::External,
        SideName::Internal => Side::Internal,
    };
    let major = cx.positive("thread.major_diameter", t.major_diameter)?;
    let starts = t.starts;
    if starts == 0 || starts > 64 {
        return Err(cx.err("thread.starts", "expected 1 to 64 starts"));
    }
    // Pitch law: F = P1 - dP/2, K = dP gives P_n = P1 + (n-1) dP between whole turns.
    let (p1, dp, series_turns, constant) = match &t.pitch {
        RawPitch::Constant(p) => (cx.positive("thread.pitch", *p)?, 0.0, None, Some(*p)),
        RawPitch::Series(s) => {
            let p1 = cx.positive("thread.pitch.first", s.first)?;
            let dp = cx.finite("thread.pitch.increment", s.increment)?;
            let turns = match (s.last, s.turns) {
                (Some(last), None) => {
                    cx.positive("thread.pitch.last", last)?;
                    if dp == 0.0 {
                        return Err(cx.err("thread.pitch.increment", "expected a non-zero increment with `last` (use a number for constant pitch)"));
                    }
                    let n = (last - p1) / dp + 1.0;
                    if n < 1.0 - 1e-9 || (n - n.round()).abs() > 1e-6 {
                        return Err(cx.err("thread.pitch.last", format!("expected first + (n-1)*increment for a whole number of turns n; (last - first)/increment + 1 = {n}")));
                    }
                    n.round()
                }
                (None, Some(n)) => cx.positive("thread.pitch.turns", n)?,
                _ => {
                    return Err(cx.err("thread.pitch", "expected exactly one of `last` or `turns`"))
                }
            };
            (p1, dp, Some(turns), None)
        }
    };
    let turns = match (series_turns, t.length, t.turns) {
        (Some(n), None, None) => n,
        (Some(_), _, _) => {
            return Err(cx.err(
                "thread.turns",
                "the pitch series already gives the number of turns",
            ))
        }
        // Turns are revolutions of the pitch helix: a multi-start thread advances a lead
        // (starts x pitch) per turn.
        (None, Some(len), None) => cx.positive("thread.length", len)? / (p1 * starts as f64),
        (None, None, Some(n)) => cx.positive("thread.turns", n)?,
        (None, Some(_), Some(_)) => {
            return Err(cx.err("thread.turns", "expected `length` or `turns`, not both"))
        }
        (None, None, None) => {
            return Err(cx.err(
                "thread",
                "expected `length` (mm) or `turns` for a constant pitch",
            ))
        }
    };
    if turns > 100_000.0 {
        return Err(cx.err("thread", format!("{turns} turns: at most 100000")));
    }
    if turns < 1.0 {
        // A pitch far longer than the thread (`pitch = 1e4` over 72 mm) leaves nothing to
        // measure: no turn, no flank pair, an empty report.
        let key = match (series_turns, t.length) {
            (Some(_), _) => "thread.pitch",
            (None, Some(_)) => "thread.length",
            (None, None) => "thread.turns",
        };
        return Err(cx.err(
            key,
            format!("the thread has {turns:.4} turns (its length over the pitch {p1} mm): expected at least one"),
        ));
    }
    let law = LeadLaw {
        f: starts as f64 * (p1 - dp / 2.0),
        k: starts as f64 * dp,
    };
    for (n, key) in [
        (0.0, "thread.pitch.first"),
        (turns, "thread.pitch.increment"),
    ] {
        if law.lead(n) <= 0.0 {
            return Err(cx.err(
                key,
                format!(
                    "the lead law F + K*t = {} + {}*t is not positive at t = {n}",
                    law.f, law.k
                ),
            ));
        }
    }
    let (std_angle, std_minor, std_pitch) = form_defaults(t.form, side, major, constant);
    let (left, right) = match (t.flank_angles, t.flank_angle, std_angle, t.form) {
        (Some([l, r]), None, _, FormName::V | FormName::Buttress) => (l, r),
        (Some(_), _, _, _) => return Err(cx.err("thread.flank_angles", "`flank_angles` is for the `v` and `buttress` forms; use `flank_angle` (included) for symmetric forms")),
        (None, Some(a), _, FormName::Trapezoidal | FormName::V | FormName::Acme) => (a / 2.0, a / 2.0),
        (None, Some(_), _, _) => return Err(cx.err("thread.flank_angle", "this form has a fixed flank angle")),
        (None, None, Some(a), _) => (a / 2.0, a / 2.0),
        (None, None, None, FormName::Buttress) => (3.0, 30.0),
        (None, None, None, _) => return Err(cx.err("thread.flank_angles", "expected [left, right] flank angles in degrees from the radial direction")),
    };
    let left_angle = cx.angle("thread.flank_angles", left, 0.0, 80.0)?;
    let right_angle = cx.angle("thread.flank_angles", right, 0.0, 80.0)?;
    let minor = match (t.minor_diameter, std_minor) {
        (Some(m), _) => cx.positive("thread.minor_diameter", m)?,
        (None, Some(m)) => m,
        (None, None) => {
            return Err(cx.err(
                "thread.minor_diameter",
                "expected a minor diameter (no standard depth for this form and pitch)",
            ))
        }
    };
    if minor >= major {
        return Err(cx.err(
            "thread.minor_diameter",
            format!("expected less than major_diameter = {major}"),
        ));
    }
    let pitch_d = match (t.pitch_diameter, std_pitch) {
        (Some(p), _) => cx.positive("thread.pitch_diameter", p)?,
        (None, Some(p)) => p,
        (None, None) => 0.5 * (major + minor),
    };
    if pitch_d <= minor || pitch_d >= major {
        return Err(cx.err(
            "thread.pitch_diameter",
            format!("expected between the minor ({minor}) and major ({major}) diameters"),
        ));
    }
    match side {
        Side::External if major > blank.diameter + 1e-9 => {
            return Err(cx.err(
                "thread.major_diameter",
                format!(
                    "an external thread must fit the blank: major {major} > blank diameter {}",
                    blank.diameter
                ),
            ));
        }
        Side::Internal if minor < blank.bore - 1e-9 || blank.bore == 0.0 => {
            return Err(cx.err("thread.minor_diameter", format!("an internal thread needs a bore no larger than its minor diameter (blank.bore = {})", blank.bore)));
        }
        Side::Internal if major >= blank.diameter => {
            return Err(cx.err(
                "thread.major_diameter",
                "an internal thread must stay inside the blank's outer diameter",
            ));
        }
        _ => {}
    }
    let (root_radius, crest_radius) = match side {
        Side::External => (minor / 2.0, major / 2.0),
        Side::Internal => (major / 2.0, minor / 2.0),
    };
    let width = match (&t.width, constant) {
        (
            Some(RawWidth {
                groove: Some(w),
                tooth: None,
            }),
            _,
        ) => WidthRule::Groove(cx.positive("thread.width.groove", *w)?),
        (
            Some(RawWidth {
                groove: None,
                tooth: Some(w),
            }),
            _,
        ) => WidthRule::Tooth(cx.positive("thread.width.tooth", *w)?),
        (Some(_), _) => {
            return Err(cx.err(
                "thread.width",
                "expected exactly one of { groove = .. } or { tooth = .. }",
            ))
        }
        (None, Some(p)) => WidthRule::Groove(p / 2.0),
        (None, None) => {
            return Err(cx.err(
                "thread.width",
                "a variable pitch needs `width = { groove = .. }` or `{ tooth = .. }`",
            ))
        }
    };
    let helix = Helix {
        z0: cx.finite("thread.z_start", t.z_start)?,
        dir: -1.0,
        law,
        theta0: cx.finite("thread.start_angle", t.start_angle)?.to_radians(),
        spin: match t.hand {
            HandName::Right => 1.0,
            HandName::Left => -1.0,
        },
    };
    let spec = ThreadSpec {
        side,
        root_radius,
        crest_radius,
        pitch_radius: pitch_d / 2.0,
        left_angle,
        right_angle,
        width,
        starts,
        helix,
        turns,
    };
    debug_assert_eq!(
        spec.hand(),
        if t.hand == HandName::Right {
            Hand::Right
        } else {
            Hand::Left
        }
    );
    // The drawing's thread must lie on the blank: its pitch helix, from the first feature
    // to the last, may reach past a face by half a lead at most (a groove cut through
    // the face); a thread off the stock could never be cut, and would compare nothing.
    {
        let (z_first, z_last) = (spec.helix.z0, spec.helix.z(turns));
        let (b_lo, b_hi) = (blank.z_front - blank.length, blank.z_front);
        let slack = 0.5 * law.lead(0.0).max(law.lead(turns));
        let (t_lo, t_hi) = (z_first.min(z_last), z_first.max(z_last));
        if t_hi > b_hi + slack || t_lo < b_lo - slack {
            let start_off = z_first < b_lo - slack || z_first > b_hi + slack;
            let key = if start_off {
                "thread.z_start"
            } else if t.length.is_some() {
                "thread.length"
            } else if t.turns.is_some() {
                "thread.turns"
            } else {
                "thread.pitch"
            };
            return Err(cx.err(
                key,
                format!(
                    "the thread runs from z {} to z {} (its first to its last turn), off the blank (z {} to {}): the stock cannot hold it; expected a thread on the blank, reaching past a face by at most half a lead ({} mm)",
                    fmt_mm(z_first),
                    fmt_mm(z_last),
                    fmt_mm(b_lo),
                    fmt_mm(b_hi),
                    fmt_mm(slack)
                ),
            ));
        }
    }
    // Shapes that cannot exist.
    let hp = spec.pitch_height();
    let widen = spec.widening();
    let depth = spec.depth();
    let pitches = [
        spec.pitch_of_turn(1),
        spec.pitch_of_turn(turns.ceil().max(1.0) as i64),
    ];
    let (p_min, p_max) = (pitches[0].min(pitches[1]), pitches[0].max(pitches[1]));
    match width {
        WidthRule::Groove(w) => {
            if w - hp * widen < -1e-9 {
                return Err(cx.err("thread.width.groove", format!("the groove closes before the root: width {w} at the pitch line leaves {:.4} mm at the root", w - hp * widen)));
            }
            if w - hp * widen >= p_min {
                return Err(cx.err("thread.width.groove", format!("the groove's root ({:.4} mm) is wider than the smallest pitch ({p_min:.4} mm): no tooth is left", w - hp * widen)));
            }
        }
        WidthRule::Tooth(tw) => {
            if tw >= p_min {
                return Err(cx.err(
                    "thread.width.tooth",
                    format!(
                        "expected a tooth narrower than the first pitch ({p_min:.4} mm), got {tw}"
                    ),
                ));
            }
            if tw - (depth - hp) * widen < -1e-9 {
                return Err(cx.err("thread.width.tooth", "the tooth comes to a point below the crest: widen it or use a smaller flank angle"));
            }
            if p_min - tw - hp * widen < -1e-9 {
                return Err(cx.err(
                    "thread.width.tooth",
                    "the groove between the first teeth closes before the root",
                ));
            }
        }
    }
    let _ = p_max;
    Ok((spec, t.form))
}

fn resolve_tool(
    t: &RawTool,
    i: usize,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
) -> Result<Tool, JobError> {
    let key = |k: &str| format!("tool[{i}].{k}");
    let reference = match t.reference.unwrap_or_default() {
        RefName::Center => Reference::Center,
        RefName::Left => Reference::Left,
        RefName::Right => Reference::Right,
        RefName::Tip => Reference::Tip,
    };
    let edge = match t.kind {
        ToolKind::Grooving => Edge::Trapezoid {
            tip: cx.positive(
                &key("width"),
                t.width
                    .ok_or_else(|| cx.err(&key("kind"), "a grooving tool needs `width` (mm)"))?,
            )?,
            left_angle: 0.0,
            right_angle: 0.0,
        },
        ToolKind::Threading => {
            let angle = t.angle.ok_or_else(|| {
                cx.err(
                    &key("kind"),
                    "a threading tool needs `angle` (included, degrees)",
                )
            })?;
            let half = cx.angle(&key("angle"), angle, 1.0, 160.0)? / 2.0;
            match (t.tip_flat, t.nose_radius) {
                (Some(_), Some(_)) => {
                    return Err(cx.err(
                        &key("nose_radius"),
                        "give `tip_flat` or `nose_radius`, not both",
                    ))
                }
                (None, Some(r)) => Edge::RoundV {
                    radius: cx.positive(&key("nose_radius"), r)?,
                    half_angle: half,
                },
                (flat, None) => Edge::Trapezoid {
                    tip: cx.non_negative(&key("tip_flat"), flat.unwrap_or(0.0))?,
                    left_angle: half,
                    right_angle: half,
                },
            }
        }
        ToolKind::Trapezoidal => {
            let tip = cx.positive(
                &key("tip_width"),
                t.tip_width.ok_or_else(|| {
                    cx.err(&key("kind"), "a trapezoidal tool needs `tip_width` (mm)")
                })?,
            )?;
            let (l, r) =
                match (t.flank_angles, t.flank_angle) {
                    (Some([l, r]), None) => (l, r),
                    (None, Some(a)) => (a / 2.0, a / 2.0),
                    (None, None) => (15.0, 15.0),
                    (Some(_), Some(_)) => return Err(cx.err(
                        &key("flank_angle"),
                        "give `flank_angle` (included) or `flank_angles` ([left, right]), not both",
                    )),
                };
            Edge::Trapezoid {
                tip,
                left_angle: cx.angle(&key("flank_angles"), l, 0.0, 80.0)?,
                right_angle: cx.angle(&key("flank_angles"), r, 0.0, 80.0)?,
            }
        }
        ToolKind::Mesh => resolve_mesh(t, &key, cx, load)?,
        ToolKind::ThreadMill => {
            return Err(cx.err(
                &key("kind"),
                "a thread mill needs a milling job: set [machine] kind = \"mill\"",
            ))
        }
    };
    if t.kind == ToolKind::Mesh {
        return Ok(Tool {
            id: t.id,
            edge,
            reference,
            body: None,
            length: None,
        });
    }
    let body = resolve_body(t, &edge, &key, cx)?;
    let length = t
        .length
        .map(|l| cx.positive(&key("length"), l))
        .transpose()?;
    Ok(Tool {
        id: t.id,
        edge,
        reference,
        body,
        length,
    })
}

/// Every optional `[[tool]]` key and the kinds of tool it applies to: a key set on a tool
/// of another kind is an error that says so.
fn check_tool_keys(t: &RawTool, i: usize, cx: &Ctx) -> Result<(), JobError> {
    use ToolKind::{Grooving, Mesh, ThreadMill, Threading, Trapezoidal};
    const INSERTS: &[ToolKind] = &[Grooving, Threading, Trapezoidal];
    const MILL: &[ToolKind] = &[ThreadMill];
    let keys: [(&str, bool, &[ToolKind]); 34] = [
        ("width", t.width.is_some(), &[Grooving]),
        ("angle", t.angle.is_some(), &[Threading, ThreadMill]),
        ("tip_flat", t.tip_flat.is_some(), &[Threading, ThreadMill]),
        ("nose_radius", t.nose_radius.is_some(), &[Threading]),
        ("tip_width", t.tip_width.is_some(), &[Trapezoidal]),
        ("flank_angle", t.flank_angle.is_some(), &[Trapezoidal]),
        (
            "flank_angles",
            t.flank_angles.is_some(),
            &[Trapezoidal, ThreadMill],
        ),
        ("reference", t.reference.is_some(), INSERTS),
        (
            "length",
            t.length.is_some(),
            &[Grooving, Threading, Trapezoidal, ThreadMill],
        ),
        ("thickness", t.thickness.is_some(), INSERTS),
        (
            "side_clearance_left",
            t.side_clearance_left.is_some(),
            INSERTS,
        ),
        (
            "side_clearance_right",
            t.side_clearance_right.is_some(),
            INSERTS,
        ),
        ("front_clearance", t.front_clearance.is_some(), INSERTS),
        ("inclination", t.inclination.is_some(), INSERTS),
        ("file", t.file.is_some(), &[Mesh]),
        ("mesh_origin", t.mesh_origin.is_some(), &[Mesh]),
        ("mesh_axes", t.mesh_axes.is_some(), &[Mesh]),
        ("mesh_units", t.mesh_units.is_some(), &[Mesh]),
        ("mesh_body", t.mesh_body.is_some(), &[Mesh]),
        ("cutter", t.cutter.is_some(), MILL),
        ("diameter", t.diameter.is_some(), MILL),
        ("pitch", t.pitch.is_some(), MILL),
        ("teeth", t.teeth.is_some(), MILL),
        ("tooth_depth", t.tooth_depth.is_some(), MILL),
        ("first_tooth", t.first_tooth.is_some(), MILL),
        ("shank_diameter", t.shank_diameter.is_some(), MILL),
        ("neck", t.neck.is_some(), MILL),
        ("flutes", t.flutes.is_some(), MILL),
        ("drill_diameter", t.drill_diameter.is_some(), MILL),
        ("point_angle", t.point_angle.is_some(), MILL),
        ("chamfer_diameter", t.chamfer_diameter.is_some(), MILL),
        ("h", t.h.is_some(), MILL),
        ("d", t.d.is_some(), MILL),
        ("d_value", t.d_value.is_some(), MILL),
    ];
    if let Some((k, _, kinds)) = keys
        .iter()
        .find(|(_, set, kinds)| *set && !kinds.contains(&t.kind))
    {
        let why = if t.kind == Mesh {
            "this key does not apply to a mesh tool: the mesh gives its shape and body, `mesh_origin` its reference point"
        } else if *kinds == [Mesh] {
            "this key applies to `kind = \"mesh\"` tools only"
        } else if *kinds == MILL {
            "this key applies to `kind = \"thread-mill\"` tools only"
        } else {
            "this key does not apply to this kind of tool"
        };
        return Err(cx.err(&format!("tool[{i}].{k}"), why));
    }
    Ok(())
}

/// A mesh tool: the OBJ `file` (read through `load`, relative to the job file), placed by
/// `mesh_origin` (the reference point: on the tip, in the rake face; OBJ units) and
/// `mesh_axes` (the OBJ axes along the part's axis, the height above the tip away from the
/// material, and the depth behind the rake face), in `mesh_units`.
fn resolve_mesh(
    t: &RawTool,
    key: &dyn Fn(&str) -> String,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
) -> Result<Edge, JobError> {
    let file = t.file.as_deref().ok_or_else(|| {
        cx.err(
            &key("kind"),
            "a mesh tool needs `file` (an OBJ file, relative to the job file)",
        )
    })?;
    let text = load(file).ok_or_else(|| {
        cx.err(
            &key("file"),
            format!("cannot read `{file}` (relative to the job file)"),
        )
    })?;
    let scale = match t.mesh_units.as_deref().unwrap_or("mm") {
        "mm" => 1.0,
        "inch" => 25.4,
        "m" => 1000.0,
        other => {
            return Err(cx.err(
                &key("mesh_units"),
                format!("expected \"mm\", \"inch\" or \"m\", got \"{other}\""),
            ))
        }
    };
    let origin = t.mesh_origin.unwrap_or([0.0; 3]);
    for v in origin {
        cx.finite(&key("mesh_origin"), v)?;
    }
    let names = t
        .mesh_axes
        .clone()
        .unwrap_or_else(|| ["+x".into(), "+y".into(), "+z".into()]);
    // (OBJ axis, sign) for the part's axis, the height and the depth.
    let mut axes = [(0usize, 1.0f64); 3];
    for (k, name) in names.iter().enumerate() {
        let (sign, axis) = match name.as_str() {
            "+x" | "x" => (1.0, 0),
            "-x" => (-1.0, 0),
            "+y" | "y" => (1.0, 1),
            "-y" => (-1.0, 1),
            "+z" | "z" => (1.0, 2),
            "-z" => (-1.0, 2),
            other => {
                return Err(cx.err(
                    &key("mesh_axes"),
                    format!("expected three of \"+x\", \"-x\", \"+y\", \"-y\", \"+z\", \"-z\" (the part's axis, the height above the tip, the depth behind the rake face), got \"{other}\""),
                ))
            }
        };
        axes[k] = (axis, sign);
    }
    if axes[0].0 == axes[1].0 || axes[0].0 == axes[2].0 || axes[1].0 == axes[2].0 {
        return Err(cx.err(
            &key("mesh_axes"),
            "expected each OBJ axis once (the part's axis, the height, the depth)",
        ));
    }
    let opts = tobj::LoadOptions {
        triangulate: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| {
        cx.err(
            &key("file"),
            format!("{file}: not a readable OBJ mesh: {e}"),
        )
    })?;
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    for m in &models {
        let base = vertices.len();
        for p in m.mesh.positions.chunks_exact(3) {
            let tool = axes.map(|(axis, sign)| sign * (p[axis] - origin[axis]) * scale);
            // [V, H, Y] -> the solid's [H, Y, V].
            vertices.push([tool[1], tool[2], tool[0]]);
        }
        for t in m.mesh.indices.chunks_exact(3) {
            triangles.push([
                base + t[0] as usize,
                base + t[1] as usize,
                base + t[2] as usize,
            ]);
        }
    }
    if vertices.iter().flatten().any(|v| !v.is_finite()) {
        return Err(cx.err(
            &key("file"),
            format!("{file}: a vertex is not a finite number"),
        ));
    }
    let solid = Solid::from_mesh(&vertices, &triangles)
        .map_err(|e| cx.err(&key("file"), format!("{file}: {e}")))?;
    Ok(Edge::Mesh {
        solid: std::sync::Arc::new(solid),
        body: t.mesh_body.unwrap_or(true),
    })
}

/// The insert behind the edge: present with `thickness`, which then needs both side
/// clearances (no default: a clearance is what the check is about).
fn resolve_body(
    t: &RawTool,
    edge: &Edge,
    key: &dyn Fn(&str) -> String,
    cx: &Ctx,
) -> Result<Option<Body>, JobError> {
    let Some(thickness) = t.thickness else {
        let stray = [
            ("side_clearance_left", t.side_clearance_left.is_some()),
            ("side_clearance_right", t.side_clearance_right.is_some()),
            ("front_clearance", t.front_clearance.is_some()),
            ("inclination", t.inclination.is_some()),
        ];
        if let Some((k, _)) = stray.iter().find(|(_, set)| *set) {
            return Err(cx.err(
                &key(k),
                "a tool body needs `thickness` (mm behind the rake face) too",
            ));
        }
        return Ok(None);
    };
    if matches!(edge, Edge::RoundV { .. }) {
        return Err(cx.err(
            &key("thickness"),
            "a tool body is modelled for flat-tipped edges only (grooving, trapezoidal, threading with `tip_flat`)",
        ));
    }
    let thickness = cx.positive(&key("thickness"), thickness)?;
    if thickness > 50.0 {
        return Err(cx.err(
            &key("thickness"),
            format!("expected at most 50 mm, got {thickness}"),
        ));
    }
    let side = |k: &str, v: Option<f64>| -> Result<f64, JobError> {
        let v = v.ok_or_else(|| {
            cx.err(
                &key("thickness"),
                format!("a tool body needs `{k}` (degrees; negative when ground to stand out)"),
            )
        })?;
        cx.angle(&key(k), v, -30.0, 45.0)
    };
    Ok(Some(Body {
        thickness,
        clearance_left: side("side_clearance_left", t.side_clearance_left)?,
        clearance_right: side("side_clearance_right", t.side_clearance_right)?,
        clearance_front: cx.angle(
            &key("front_clearance"),
            t.front_clearance.unwrap_or(0.0),
            0.0,
            45.0,
        )?,
        inclination: cx.angle(
            &key("inclination"),
            t.inclination.unwrap_or(0.0),
            -30.0,
            30.0,
        )?,
    }))
}
