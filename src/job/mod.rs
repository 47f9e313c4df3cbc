//! The job file: TOML schema, validation, and the resolved [`Job`].
//!
//! This is the input serialization boundary. [`Job::from_toml`] takes the file's text and
//! its name (no IO here), checks every key, and returns either a [`Job`] in mm and radians
//! or a [`JobError`] that names the file, the key, its line and column, and what was
//! expected. Unknown keys are errors. The format is documented in `docs/job-format.md`.
//!
//! Loading a job is two steps:
//!
//! 1. parse: the text, read once into a TOML document (whose spans locate every key), is
//!    deserialized into the raw schema (`schema`) and checked key by key (`parse`, with
//!    `forms` for the thread, `tools`, `process` for `[[pass]]` and `[process]`, `mill`
//!    for milling jobs and `program` for the `[program]` table), giving a [`Job`] whose
//!    program has not run;
//! 2. the program stage ([`crate::toolpath`]): the program, read through the caller's
//!    loader, interpreted, and its moves made into passes (lathe) or the path (mill).
//!
//! Layout: `ctx` (locating keys, the errors' context), `keys` (serde's errors and every
//! number's range), `schema`, `parse`, `forms`, `standard` (the drawing's designation and
//! tolerance class), `tools`, `process`, `program`, `mill`.

use crate::kernel::turn::TurningTool;
use crate::model::part::PartProfile;
use crate::model::pass::Pass;
pub(crate) use crate::model::setup::{Blank, ChainLink, CycleTime, Machine};
use crate::model::thread::ThreadSpec;
use crate::model::tolerance::ThreadClass;
use crate::model::tool::{Holder, Tap, Tool};
use crate::nc::{Diagnostic, NcError, Severity};
use crate::toolpath::{self, LatheTool, LatheTurning, ProgramError, Role, TurnStock};

mod ctx;
mod forms;
mod keys;
mod mill;
mod parse;
mod place;
mod process;
mod program;
mod schema;
mod standard;
mod tools;

use ctx::Ctx;
pub use forms::FormName;
pub use mill::MillJob;
use parse::{Parsed, Pending};

/// A job that could not be read. Shown as its [`JobError::diagnostic`] (the program's
/// errors as all of theirs): the message, file, line and column, the source line with a
/// caret (see [`Diagnostic`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JobError {
    /// The text is not valid TOML or does not fit the schema (unknown or missing key,
    /// wrong type).
    #[error("{}", self.diagnostic())]
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
    Program(Box<NcError>),
    /// A key has a value that makes no sense (negative lead, tooth wider than the pitch...).
    #[error("{}", self.diagnostic())]
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

impl JobError {
    /// This error as a diagnostic (a program's: the error that stopped it); the key of an
    /// invalid value leads its message (`` `blank.diameter`: expected ...``).
    pub fn diagnostic(&self) -> Diagnostic {
        let (file, line, col, message, snippet) = match self {
            JobError::Program(nc) => return nc.diagnostic(),
            JobError::Syntax {
                file,
                line,
                col,
                message,
                snippet,
            } => (file, line, col, message.clone(), snippet),
            JobError::Invalid {
                file,
                key,
                line,
                col,
                message,
                snippet,
            } => (file, line, col, format!("`{key}`: {message}"), snippet),
        };
        Diagnostic {
            severity: Severity::Error,
            file: file.clone(),
            line: *line,
            col: *col,
            message,
            hint: None,
            snippet: snippet.clone(),
            stack: Vec::new(),
        }
    }
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
    pub program_warnings: Vec<Diagnostic>,
    /// Joints of continuous thread chains in the program (see [`ChainLink`]).
    pub chains: Vec<ChainLink>,
    /// Where the passes that come from the `[program]` are in it: (pass index, file as the
    /// job names the program, 1-based line of the thread block). Empty without a program.
    pub pass_blocks: Vec<(usize, String, usize)>,
    /// How many of the passes are the job's own `[[pass]]` tables (the first ones); the
    /// rest come from the `[process]` or the program.
    pub(crate) explicit_passes: usize,
    /// The spindle speed of each pass (rev/min): the program's (`G97 S`, or `G96 S` at the
    /// pass's diameter within its clamp), else `[machine] spindle_rpm`.
    pub pass_rpm: Vec<f64>,
    /// Whether each pass is a threading cycle's (G76, G92, CYCLE97/99, LinuxCNC G76).
    pub(crate) pass_cycle: Vec<bool>,
    /// The program cut its thread in inches (`nc::Toolpath::inch`).
    pub(crate) program_inch: bool,
    /// Each program pass's tool as the program wrote it (`T0202`); `None` for the job's
    /// own passes ([`Job::pass_tool_name`]).
    pub(crate) pass_tool_words: Vec<Option<String>>,
    /// A milling job (`[machine] kind = "mill"`): its cutters and path. Its `tools` and
    /// `passes` are empty.
    pub mill: Option<MillJob>,
    /// The drawing's limits of the pitch diameter (a tolerance class such as ISO 965 6H):
    /// checked on the measured simple pitch diameter of every turn (milling jobs).
    pub pitch_diameter_limits: Option<(f64, f64)>,
    /// The drawing's tolerance class, from `[thread] designation` (`M30x2-6g`) or `class`
    /// (`6g` with the explicit form, major diameter and pitch): the limits of size the
    /// virtual gauges judge the cut thread against. Its length of engagement is at most
    /// the thread's length. `None` when the job names no class.
    pub thread_class: Option<ThreadClass>,
    /// The plan of `[process] kind = "plan"`, whose passes are [`Job::passes`].
    pub plan: Option<crate::gen::plan::Plan>,
    /// Where the thread was placed on the cut (no `thread.z_start`), or how far the cut
    /// lies from the given one (constant lead); `None` where nothing was fitted.
    pub placement: Option<crate::analysis::place::Placement>,
    /// Whether the thread's position comes from the cut: no `thread.z_start`, and passes
    /// that the thread does not generate.
    pub(crate) fit_thread: bool,
    /// The finished part's outer contour as drawn (`[part] profile`), if given.
    pub part_profile: Option<PartProfile>,
    /// Its bore's contour (`[part] bore_profile`), if given.
    pub bore_profile: Option<PartProfile>,
    /// The tools' holders (`[[tool]] holder`), by tool id.
    pub holders: Vec<(u32, Holder)>,
    /// The chuck and its jaws (`[machine] chuck`), a contour turning with the part.
    pub chuck: Option<PartProfile>,
    /// A lathe program's cycle time (rapids, feeds, threading, waits; by tool).
    pub cycle_time: Option<CycleTime>,
    /// The turning tools (`kind = "turning"`) the program's T words select.
    pub(crate) turning_tools: Vec<TurningTool>,
    /// What the program's turning moves cut, and its rapids that meet material.
    pub(crate) turning: LatheTurning,
    /// The taps (`kind = "tap"`); each one's tooth is in `tools` under its id.
    pub(crate) taps: Vec<Tap>,
    /// The program's tap strokes whose feed is not the tap's pitch.
    pub(crate) tap_feeds: Vec<toolpath::TapFeed>,
}

impl Job {
    /// Whether the job is an inch job, reported in inches (and threads per inch) beside
    /// mm: its tolerance class or designation is in inches (`1/2-13 UNC-2A`), its form is
    /// an inch standard's (`unified`, `acme`), or its program cuts the thread in inches
    /// (G20/G70, or inch at power-on).
    pub fn inch(&self) -> bool {
        use crate::model::tolerance::UnitSystem;
        self.thread_class
            .as_ref()
            .is_some_and(|c| c.units == UnitSystem::Inch)
            || matches!(self.form, FormName::Unified | FormName::Acme)
            || self.program_inch
    }

    /// The tool of pass `i` (0-based) for a message: as the program wrote it (`T0202`,
    /// `T="GEW_AUSSEN_3.0"`), else the job's `[[tool]]` id as `T<id>`.
    pub fn pass_tool_name(&self, i: usize) -> String {
        match self.pass_tool_words.get(i) {
            Some(Some(w)) => w.clone(),
            _ => self
                .passes
                .get(i)
                .and_then(|p| self.tools.get(p.tool))
                .map_or_else(|| "no tool".into(), |t| format!("T{}", t.id)),
        }
    }

    /// Parse and validate a job. `file` is only used in messages. A job with a `[program]`
    /// needs [`Job::from_toml_with`].
    pub fn from_toml(src: &str, file: &str) -> Result<Job, JobError> {
        Job::from_toml_with(src, file, &|_| None)
    }

    /// Parse and validate a job whose `[program]` (and its subprograms) `load` returns by
    /// name, relative to the job file: parse, then the program stage. The library itself
    /// reads no files.
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
        // Step 1: parse the text into a job whose program has not run.
        let cx = Ctx::parse(src, file)?;
        let Parsed { job, program } = parse::resolve(cx.raw()?, &cx, load, strict)?;
        // Step 2: the program stage.
        let mut job = match program {
            Some(pending) => job.run_program(pending, load, &cx)?,
            None => job,
        };
        let fit_it = job.fit_thread;
        job.place(fit_it);
        if job.mill.is_none() && job.passes.is_empty() {
            return Err(cx.err(
                "pass",
                "expected at least one [[pass]], a [process] or a [program] with threading moves",
            ));
        }
        Ok(job)
    }

    /// The program stage on a parsed job: its program interpreted, and its moves made into
    /// passes after the job's own (lathe) or into its path (mill).
    fn run_program(
        mut self,
        pending: Pending,
        load: &dyn Fn(&str) -> Option<String>,
        cx: &Ctx,
    ) -> Result<Job, JobError> {
        let fail = |e: ProgramError| program_error(e, cx, load);
        match pending {
            Pending::Lathe(mut program) => {
                // Tool nose radius compensation's radius and tip: the turning tools'.
                program.options.settings.noses.tool = self
                    .turning_tools
                    .iter()
                    .map(|t| (t.id, (t.nose_radius, t.tip())))
                    .collect();
                let path = toolpath::interpret(&program, load).map_err(fail)?;
                self.program_inch = path.inch;
                let lathe = toolpath::lathe_passes(
                    &path.moves,
                    &self.tools,
                    &self.turning_tools,
                    &self.taps,
                )
                .map_err(fail)?;
                self.tap_feeds = lathe.tap_feeds;
                let offset = self.passes.len();
                self.chains.extend(lathe.links.into_iter().map(|mut l| {
                    l.pass += offset;
                    l
                }));
                self.pass_blocks.extend(
                    lathe
                        .blocks
                        .into_iter()
                        .enumerate()
                        .map(|(i, (file, line))| (offset + i, file, line)),
                );
                self.pass_cycle.resize(offset, false);
                self.pass_cycle.extend(lathe.cycle);
                self.pass_tool_words.resize(offset, None);
                self.pass_tool_words.extend(lathe.tool_words);
                let rpm = self.machine.spindle_rpm;
                self.pass_rpm
                    .extend(lathe.rpm.into_iter().map(|r| r.unwrap_or(rpm)));
                self.passes.extend(lathe.passes);
                let b = &self.blank;
                let outer = TurnStock {
                    q_blank: b.diameter / 2.0,
                    q_floor: b.bore / 2.0,
                };
                let inner = (b.bore > 0.0).then_some(TurnStock {
                    q_blank: -b.bore / 2.0,
                    q_floor: -b.diameter / 2.0,
                });
                self.turning = toolpath::lathe_turning(
                    &path.moves,
                    &self.lathe_tools(),
                    outer,
                    inner,
                    (b.z_front - b.length, b.z_front),
                    self.sim.axial_spacing,
                    self.chuck.as_ref(),
                );
                self.cycle_time = Some(toolpath::cycle_time(
                    &path.moves,
                    &path.dwells,
                    &self.machine,
                ));
                let mut warnings = path.warnings;
                let stage = lathe.warnings.into_iter().chain(toolpath::scale_warnings(
                    &path.moves,
                    b.diameter,
                    (b.z_front - b.length, b.z_front),
                ));
                warnings.extend(stage.map(|w| stage_warning(w, load)));
                self.program_warnings = warnings;
            }
            Pending::Mill(parts) => {
                let path = toolpath::interpret(&parts.program, load).map_err(fail)?;
                let setup = toolpath::MillSetup {
                    cutters: &parts.cutters,
                    ids: &parts.ids,
                    axis: parts.axis,
                    rpm: self.machine.spindle_rpm,
                };
                let (mill_path, rpm) = toolpath::mill_path(&path.mill, &setup).map_err(fail)?;
                self.mill = Some(MillJob {
                    cutters: parts.cutters,
                    cutter_ids: parts.ids,
                    moves: path.mill,
                    axis: parts.axis,
                    path: mill_path,
                    rpm,
                });
                self.program_warnings = path.warnings;
            }
        }
        Ok(self)
    }

    /// Every tool of a lathe program as its moves sweep it: the turning tools, and the
    /// grooving and threading inserts (on the thread's side: in the bore for an internal
    /// thread).
    fn lathe_tools(&self) -> Vec<LatheTool> {
        let internal = self.thread.side == crate::model::thread::Side::Internal;
        let holder = |id: u32| self.holders.iter().find(|h| h.0 == id).map(|h| h.1);
        let turning = self.turning_tools.iter().map(|&shape| LatheTool {
            shape,
            role: Role::Turning,
            holder: holder(shape.id),
        });
        let inserts = self.tools.iter().map(|t| LatheTool {
            shape: TurningTool::insert(t, internal),
            holder: holder(t.id),
            role: match t.edge {
                crate::model::tool::Edge::Trapezoid {
                    left_angle,
                    right_angle,
                    ..
                } if left_angle == 0.0 && right_angle == 0.0 => Role::Grooving,
                _ => Role::Threading,
            },
        });
        turning.chain(inserts).collect()
    }

    /// This job with its passes replaced by those of an NC program: `text`, read as
    /// `file` in `dialect` (`fanuc`, `gsk980`, `siemens-802d`, `linuxcnc`), strictly (every
    /// word must be understood). The round trip of `vpcut plan`.
    pub fn with_program(&self, file: &str, text: &str, dialect: &str) -> Result<Job, JobError> {
        let pr = schema::RawProgram {
            file: file.to_string(),
            dialect: dialect.to_string(),
            strict: true,
            thread_chamfer: 0.0,
            work_offsets: Default::default(),
            block_skip: true,
            reference_point: None,
            gcode_system: None,
            second_reference_point: None,
            decimal_point: None,
            input_increment: None,
            units: None,
            feed_mode: None,
            x_mode: None,
            main: None,
            subroutine_path: Vec::new(),
            definitions: Vec::new(),
        };
        let cx = Ctx::empty(file);
        let program = program::lathe_program(&pr, None, &self.blank, &cx, true)?;
        let load = |name: &str| (name == file).then(|| text.to_string());
        let job = Job {
            passes: Vec::new(),
            chains: Vec::new(),
            pass_blocks: Vec::new(),
            explicit_passes: 0,
            pass_rpm: Vec::new(),
            pass_cycle: Vec::new(),
            pass_tool_words: Vec::new(),
            program_inch: false,
            program_warnings: Vec::new(),
            plan: None,
            ..self.clone()
        };
        let mut job = job.run_program(Pending::Lathe(program), &load, &cx)?;
        let fit_it = job.fit_thread;
        job.place(fit_it);
        Ok(job)
    }
}

/// A warning of the program stage as a diagnostic of its block (the block's line read
/// again through `load`).
fn stage_warning(w: toolpath::StageWarning, load: &dyn Fn(&str) -> Option<String>) -> Diagnostic {
    Diagnostic {
        severity: crate::nc::Severity::Warning,
        snippet: load(&w.file)
            .and_then(|t| t.lines().nth(w.line.wrapping_sub(1)).map(str::to_string))
            .unwrap_or_default(),
        file: w.file,
        line: w.line,
        col: 0,
        message: w.message,
        hint: Some(w.hint),
        stack: Vec::new(),
    }
}

/// An error of the program stage as a job error: the interpreter's errors and those about a
/// move as the program's (a move's about its block as a whole: column 0), the others at the
/// job's keys. A move's error shows its block's line, read again through `load`.
fn program_error(e: ProgramError, cx: &Ctx, load: &dyn Fn(&str) -> Option<String>) -> JobError {
    match e {
        ProgramError::Nc(nc) => JobError::Program(nc),
        ProgramError::Move {
            file,
            line,
            message,
        } => JobError::Program(Box::new(NcError {
            snippet: load(&file)
                .and_then(|t| t.lines().nth(line.wrapping_sub(1)).map(str::to_string))
                .unwrap_or_default(),
            file,
            line,
            col: 0,
            message,
            stack: Vec::new(),
            hint: None,
            others: Vec::new(),
        })),
        ProgramError::Unreadable(file) => cx.err(
            "program.file",
            format!("cannot read `{file}` (relative to the job file)"),
        ),
        ProgramError::Samples(n) => cx.err(
            "program",
            format!(
                "the path needs {n} samples at the stated sampling bound, over the limit of {}: a shorter program or fewer moves",
                crate::kernel::mill::MAX_SAMPLES
            ),
        ),
    }
}
