//! NC programs: FANUC (Macro A/B), GSK 980TDC, Siemens 802D/840D and LinuxCNC lathe dialects
//! interpreted into a toolpath whose thread moves become passes.
//!
//! The interpreter reads text given by the caller (no IO here): the main program, and a
//! loader for subprograms found beside it. Every error names the file, line and column and
//! the call stack. Layout:
//!
//! - `program`: splitting a file into programs and blocks (comments, N numbers, labels,
//!   FANUC `;` end of block and `%` tape marks);
//! - `lex`: the one lexer (a cursor with spans mapped to columns) of every dialect, for the
//!   static check and both expression readers;
//! - `expr`: the expression evaluators (FANUC `[ ]`/`#`, Siemens `( )`/`R`);
//! - `fanuc`: FANUC/GSK blocks, Macro A/B, G76, G92, GSK G34;
//! - `siemens`: Siemens 802D blocks, labels and jumps; `siemens_840d`, `siemens_vars` and
//!   `siemens_flow`: the 840D's statements, user variables and control structures;
//!   `siemens_cycles`: the thread cycles CYCLE97/CYCLE99 as their moves;
//! - `okuma`: Okuma OSP-P lathe programs, a reader of their own (`okuma_expr` the
//!   expressions, `okuma_cycles` the thread cycles G33/G34/G71 as moves);
//! - `linuxcnc`: LinuxCNC blocks, O-word subroutines and control flow; `lcnc_g76`: G76;
//!   `lcnc_modes`: M70..M73; `lcnc_g7x` and `lcnc_contour`: the lathe cycles G70/G71/G72
//!   (the block and contour, the geometry);
//! - `lcnc_expr`: LinuxCNC expressions and numbered/named parameters;
//! - `motion`: modal state, motion words, and recording moves;
//! - `codes`: which G/M codes and words each dialect runs, refuses or does not know, and
//!   FANUC G-code systems B and C read as system A;
//! - `settings`: what the job says of the machine (`Settings`, `G76Params`);
//! - `state`: the interpreter's state (`Interp`), grouped: run settings, programs, modal
//!   state, frames, threading state, FANUC/Siemens variables, output;
//! - `check`: the static check of every block before anything runs (all problems at once);
//! - `error`: the error that stops a run (`NcError`), with the diagnostics found before it;
//! - `mill/`: FANUC machining-centre programs (`Settings::mill`): the public milling nouns
//!   (`mill/mod.rs`), the blocks into programmed moves (`mill/blocks.rs`) and cutter radius
//!   compensation of the programmed moves as a pure pass (`mill/comp.rs`);
//! - `chain`: continuous threading (thread blocks that follow each other without a re-sync)
//!   and the GSK thread run-out J/K;
//! - `units`: what a program leaves to the machine: FANUC/GSK decimal-point input and the
//!   least input increment (how every word becomes mm), the modes at power-on, the main
//!   program of a file with several, and the warnings when numbers look read wrong.

mod chain;
mod check;
mod codes;
#[cfg(test)]
mod cycle_tests;
mod cycles;
mod detect;
mod error;
mod expr;
mod fanuc;
mod lcnc_contour;
mod lcnc_expr;
mod lcnc_g76;
mod lcnc_g7x;
mod lcnc_modes;
mod lex;
mod linuxcnc;
#[cfg(test)]
mod machine_tests;
mod mill;
mod motion;
#[cfg(test)]
mod mrc_tests;
mod nose;
#[cfg(test)]
mod nose_tests;
mod okuma;
mod okuma_cycles;
mod okuma_expr;
mod okuma_parse;
#[cfg(test)]
mod okuma_tests;
mod program;
#[cfg(test)]
mod real_tests;
mod settings;
mod siemens;
mod siemens_840d;
mod siemens_cycles;
mod siemens_defs;
mod siemens_flow;
#[cfg(test)]
mod siemens_tests;
mod siemens_vars;
#[cfg(test)]
mod spindle_tests;
mod state;
#[cfg(test)]
mod tests;
mod troughs;
mod units;
#[cfg(test)]
mod units_tests;

pub use error::NcError;
pub use mill::{CompSide, MillArc, MillKind, MillMove, MillSettings, Plane};
pub use nose::{Nose, NoseData, NoseOffset, NoseRule};
pub use settings::{G76Params, Settings, ToolOffsets};

use expr::Fail;
pub use program::decode_program;
use program::{load_programs, Program};
use state::Interp;
pub use units::{DecimalPoint, InputIncrement, PowerOn};

pub use crate::diag::{Diagnostic, Severity};
use crate::model::helix::Spindle;
use std::collections::HashMap;

/// Controller dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// FANUC lathe, G-code system A, Custom Macro B (and Macro A `G65 H..`).
    Fanuc,
    /// LinuxCNC (rs274ngc) lathe: O-word subroutines and control flow, numbered and named
    /// parameters, `G33 Z K`, `G76 P Z I J K R Q H E L`, radius mode G8 by default,
    /// diameter mode G7.
    Linuxcnc,
    /// GSK 980TDC: FANUC syntax; `G34 F J K R` with R the lead change per revolution and
    /// J/K the thread run-out.
    Gsk980,
    /// Siemens SINUMERIK 802D.
    Siemens802d,
    /// Siemens SINUMERIK 840D (sl): 802D and user variables (`DEF`), structured control
    /// flow, `PROC` parameters, the thread cycles CYCLE97/CYCLE99 and G331/G332.
    Siemens840d,
    /// Okuma OSP-P lathe (`.MIN`/`.SSB`): G33/G34 thread cycles, the G71 compound thread
    /// cutting cycle, `CALL`/`RTS`, common and local variables (`okuma`).
    Okuma,
}

impl Dialect {
    /// Parse the name used in jobs and on the command line.
    pub fn from_name(s: &str) -> Option<Dialect> {
        match s {
            "fanuc" => Some(Dialect::Fanuc),
            "gsk980" => Some(Dialect::Gsk980),
            "linuxcnc" => Some(Dialect::Linuxcnc),
            "siemens-802d" => Some(Dialect::Siemens802d),
            "siemens-840d" => Some(Dialect::Siemens840d),
            "okuma" => Some(Dialect::Okuma),
            _ => None,
        }
    }
}

impl Dialect {
    /// The syntax family: GSK writes programs as FANUC does.
    fn syntax(self) -> Dialect {
        match self {
            Dialect::Gsk980 => Dialect::Fanuc,
            Dialect::Siemens840d => Dialect::Siemens802d,
            d => d,
        }
    }
}

/// FANUC lathe G-code system (FANUC 0i-TF/30i-B lathe manuals, "G code list": parameter
/// GSB/GSC). System A writes U/W for incremental moves; B and C have G90/G91.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GcodeSystem {
    /// System A (vpcut's FANUC/GSK lathe codes are written in it).
    #[default]
    A,
    /// System B.
    B,
    /// System C.
    C,
}

impl GcodeSystem {
    /// Parse `"A"`, `"B"` or `"C"`.
    pub fn from_name(s: &str) -> Option<GcodeSystem> {
        match s {
            "A" | "a" => Some(GcodeSystem::A),
            "B" | "b" => Some(GcodeSystem::B),
            "C" | "c" => Some(GcodeSystem::C),
            _ => None,
        }
    }
}

/// A program's text and the name it is known by.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Source {
    /// File name (for messages and subprogram lookup).
    pub name: String,
    /// The text.
    pub text: String,
}

/// What a move does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKind {
    /// G0.
    Rapid,
    /// G1.
    Feed,
    /// A spindle-synchronised threading move.
    Thread,
    /// A circular move G02/G03 in the XZ plane (not a thread move; see [`Move::arc`]).
    Arc,
}

impl MoveKind {
    /// Name used in CSV/JSON.
    pub fn name(self) -> &'static str {
        match self {
            MoveKind::Rapid => "rapid",
            MoveKind::Feed => "feed",
            MoveKind::Thread => "thread",
            MoveKind::Arc => "arc",
        }
    }
}

/// One interpreted move, in mm, end point in work coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Move {
    /// File of the block.
    pub file: String,
    /// 1-based line of the block.
    pub line: usize,
    /// Kind.
    pub kind: MoveKind,
    /// Start diameter.
    pub x_start: f64,
    /// Start z.
    pub z_start: f64,
    /// End diameter.
    pub x_dia: f64,
    /// End z.
    pub z: f64,
    /// Lead at the start (thread moves).
    pub lead: Option<f64>,
    /// Lead change per revolution (thread moves).
    pub lead_change: Option<f64>,
    /// Spindle angle at the sync point (deg, thread moves). For a chained move, the spindle
    /// angle where the previous thread move ended (its Q/SF start angle is ignored).
    pub sync_angle_deg: Option<f64>,
    /// A thread move that continues the previous one without waiting for the spindle's
    /// one-rev signal (continuous threading: a thread block right after a thread block, or
    /// the GSK run-out segment of its own block). Its phase continues; its lead is what its
    /// block programs.
    pub chained: bool,
    /// Active tool number (T0101 and T1 are tool 1).
    pub tool: Option<u32>,
    /// The active tool as the program wrote it, for messages: the T word that selected it
    /// (`T0202`, GSK `T0101`, Okuma `T030303`, LinuxCNC `T3`, Siemens `T="GEW_AUSSEN_3.0"`
    /// or `T3`, with the D word in force: `T3 D1`); `None` before any T word.
    pub tool_word: Option<std::sync::Arc<str>>,
    /// Spindle direction.
    pub spindle: Spindle,
    /// Centre and sense of an arc move (`MoveKind::Arc`).
    pub arc: Option<ArcGeometry>,
    /// The spindle speed as the program set it when the move was made.
    pub speed: SpindleSpeed,
    /// The feed of a feed or arc move (the modal F, in mm), `None` before any F.
    pub feed: Option<Feed>,
    /// A thread move of a threading cycle's pass (FANUC/GSK G76 and G92, Siemens
    /// CYCLE97/CYCLE99, LinuxCNC G76): its infeed is the cycle's.
    pub cycle: bool,
    /// The tool nose radius compensation (G41/G42) the move's path was made with (`nose`).
    pub nose: Option<Nose>,
}

/// The spindle speed as a program sets it: G97 `S` (rev/min), or G96 `S` (constant
/// surface speed) with its clamp (FANUC/GSK `G50 S`, Siemens `LIMS=`, LinuxCNC `G96 D`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpindleSpeed {
    /// G97: the programmed speed (rev/min), if any S was given.
    pub rpm: Option<f64>,
    /// G96: the surface speed (m/min; an inch program's ft/min converted).
    pub surface: Option<f64>,
    /// The clamp on G96's speed (rev/min), if set.
    pub max: Option<f64>,
}

impl SpindleSpeed {
    /// The speed (rev/min) with the tool at diameter `x` (mm): G97's S, or G96's surface
    /// speed `1000 v / (pi x)` clamped (unbounded on the axis without a clamp); `None` when
    /// the program set no speed.
    pub fn at(&self, x: f64) -> Option<f64> {
        match self.surface {
            Some(v) => {
                let n = 1000.0 * v / (std::f64::consts::PI * x.abs());
                Some(self.max.map_or(n, |m| n.min(m)))
            }
            None => self.rpm,
        }
    }
}

/// A feed move's programmed feed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feed {
    /// mm per revolution (`per_rev`) or mm per minute.
    pub value: f64,
    /// Feed per revolution (FANUC G99, Siemens/LinuxCNC G95), else per minute.
    pub per_rev: bool,
}

/// A dwell (FANUC/GSK `G04 X/U/P`, Siemens `G4 F/S`, LinuxCNC `G4 P`): the spindle turns
/// while the axes wait.
#[derive(Clone, Debug, PartialEq)]
pub struct Dwell {
    /// How many moves were made before it.
    pub after: usize,
    /// Seconds, or spindle revolutions (Siemens `G4 S`).
    pub time: DwellTime,
    /// The spindle speed then, and the tool's diameter (for revolutions under G96).
    pub speed: SpindleSpeed,
    /// The tool's diameter then (mm).
    pub x: f64,
    /// The program file and 1-based line of the block.
    pub file: String,
    /// 1-based line.
    pub line: usize,
}

/// How long a dwell lasts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DwellTime {
    /// Seconds.
    Seconds(f64),
    /// Spindle revolutions.
    Revolutions(f64),
}

/// The circle of an arc move, in the XZ plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcGeometry {
    /// Centre, as a diameter (twice the centre's distance from the axis, signed).
    pub x_centre_dia: f64,
    /// Centre z.
    pub z_centre: f64,
    /// G02: clockwise seen from +Y with Z to the right and X up (the textbook lathe view).
    pub clockwise: bool,
}

/// Limits that turn runaway programs into errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Executed blocks.
    pub max_blocks: u64,
    /// Subprogram nesting.
    pub max_depth: usize,
    /// Moves recorded (every rapid, feed, arc and thread move, cycle passes included;
    /// milling moves too). Checked as they are made, so that a runaway loop stops with an
    /// error long before its moves fill the memory: a move takes about 200 bytes, so the
    /// default of a million stays near 200 MB, and the largest seed scene makes a few
    /// thousand (a G76 of 10,000 passes makes 40,000).
    pub max_moves: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_blocks: 10_000_000,
            max_depth: 8,
            max_moves: 1_000_000,
        }
    }
}

/// How to interpret.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    /// Limits on executed blocks and nesting.
    pub limits: Limits,
    /// Unknown words and codes are errors instead of warnings.
    pub strict: bool,
    /// The machine's settings that the program cannot say.
    pub settings: Settings,
}

/// An interpreted program: its moves and the warnings found on the way.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Toolpath {
    /// The moves in execution order.
    pub moves: Vec<Move>,
    /// A milling program's moves (with [`Settings::mill`]), in execution order.
    pub mill: Vec<MillMove>,
    /// Warnings (skipped unknown words and codes), each once, in the order found.
    pub warnings: Vec<Diagnostic>,
    /// The dwells, in execution order.
    pub dwells: Vec<Dwell>,
    /// A thread move was made in inch units (G20/G70, or inch at power-on): the program
    /// is an inch program, and its thread is reported in inches beside mm.
    pub inch: bool,
}

/// Degrees (as the programs write angles) to radians.
pub(super) fn to_rad(x: f64) -> f64 {
    x.to_radians()
}

/// Interpret a program into moves with the default options; warnings are dropped (see
/// [`interpret_with`]).
pub fn interpret(
    main: &Source,
    dialect: Dialect,
    loader: &dyn Fn(&str) -> Option<Source>,
    limits: Limits,
) -> Result<Vec<Move>, NcError> {
    let opts = Options {
        limits,
        ..Options::default()
    };
    interpret_with(main, dialect, loader, &opts).map(|t| t.moves)
}

/// Interpret a program: first a static check of every block of every program that can be
/// found (all problems are reported at once, errors stop here), then the run (which stops
/// at the first run-time error: a computed jump to nowhere, a division by zero, a limit).
pub fn interpret_with(
    main: &Source,
    dialect: Dialect,
    loader: &dyn Fn(&str) -> Option<Source>,
    opts: &Options,
) -> Result<Toolpath, NcError> {
    run_program(main, dialect, loader, opts, None)
}

/// The moves a program makes before the error that stops it, as a control makes them before
/// its alarm (for showing the toolpath of a program [`interpret_with`] refuses): the static
/// check's errors do not stop this run, its first run-time error does. Empty for Okuma
/// programs and where the program cannot start (a file that cannot be read, no main
/// program).
pub fn interpret_partial(
    main: &Source,
    dialect: Dialect,
    loader: &dyn Fn(&str) -> Option<Source>,
    opts: &Options,
) -> Vec<Move> {
    let mut made = Vec::new();
    match run_program(main, dialect, loader, opts, Some(&mut made)) {
        Ok(t) => t.moves,
        Err(_) => made,
    }
}

/// `interpret_with`; with `partial`, the static check's errors do not stop the run, and the
/// moves made before a run-time error are left in `partial`.
fn run_program(
    main: &Source,
    dialect: Dialect,
    loader: &dyn Fn(&str) -> Option<Source>,
    opts: &Options,
    partial: Option<&mut Vec<Move>>,
) -> Result<Toolpath, NcError> {
    if dialect == Dialect::Okuma {
        return okuma::interpret(main, loader, opts);
    }
    let real = dialect;
    let gsk = dialect == Dialect::Gsk980;
    let dialect = dialect.syntax();
    let detected = detect::detected_system(main, real, opts);
    let with_system;
    let opts = match &detected {
        Some(d) => {
            with_system = Options {
                settings: Settings {
                    gcode_system: d.0,
                    ..opts.settings.clone()
                },
                ..opts.clone()
            };
            &with_system
        }
        None => opts,
    };
    let mut m = Interp::new(dialect, gsk, loader, opts);
    m.cfg.s840 = real == Dialect::Siemens840d;
    m.lc.st.home28 = m.frames.reference;
    m.lc.st.home30 = m.frames.reference2;
    if m.cfg.milling && real != Dialect::Fanuc {
        return Err(NcError {
            file: main.name.clone(),
            line: 1,
            col: 0,
            message: "milling programs (a job with mill settings) are FANUC only for now".into(),
            snippet: main.text.lines().next().unwrap_or("").to_string(),
            stack: Vec::new(),
            hint: Some("write the milling program in the FANUC dialect".into()),
            others: Vec::new(),
        });
    }
    let def_warnings = m.load_definitions(&opts.settings.definitions, &main.name)?;
    let skip = opts.settings.block_skip;
    let all: Vec<std::rc::Rc<Program>> = load_programs(main, dialect, skip)
        .into_iter()
        .map(|mut p| {
            siemens_defs::expand_program(&mut p, &m.vars.s840.macros);
            std::rc::Rc::new(p)
        })
        .collect();
    // The main program: the one the job names, else the one the control would run (the
    // first that ends in M30/M02 and that no other calls).
    let first = if dialect == Dialect::Fanuc && (all.len() > 1 || opts.settings.main.is_some()) {
        let names: Vec<Vec<String>> = all.iter().map(|p| units::names_of(p)).collect();
        let facts: Vec<(Vec<String>, bool)> = all
            .iter()
            .map(|p| check::program_facts(p, opts.settings.gcode_system))
            .collect();
        units::main_program(&names, &facts, opts.settings.main.as_deref()).map_err(|message| {
            NcError {
                file: main.name.clone(),
                line: 1,
                col: 0,
                message,
                snippet: main.text.lines().next().unwrap_or("").to_string(),
                stack: Vec::new(),
                hint: Some(
                    "the main program is named by its O number, e.g. main = \"O1000\"".into(),
                ),
                others: Vec::new(),
            }
        })?
    } else {
        0
    };
    let prog = all[first].clone();
    let mut to_check = Vec::new();
    for p in &all {
        m.register(p.clone());
        to_check.push(p.clone());
    }
    // The static check, program by program; called programs are loaded as they are named.
    let mut diagnostics: Vec<Diagnostic> = def_warnings;
    let milling = m.cfg.milling;
    let macros = m.vars.s840.macros.clone();
    let mut checked: Vec<String> = Vec::new();
    while let Some(p) = to_check.pop() {
        if checked.contains(&p.name) {
            continue;
        }
        checked.push(p.name.clone());
        let mut found = |name: &str| match m.find_program(name) {
            Some(q) => {
                to_check.push(q);
                true
            }
            None => false,
        };
        diagnostics.extend(check::check_program(
            &p,
            real,
            milling,
            opts.settings.gcode_system,
            opts.strict,
            &macros,
            &mut found,
        ));
    }
    diagnostics.sort_by(|a, b| (&a.file, a.line, a.col).cmp(&(&b.file, b.line, b.col)));
    if partial.is_none() && diagnostics.iter().any(|d| d.severity == Severity::Error) {
        return Err(NcError::from_diagnostics(diagnostics));
    }
    m.cfg.stop_at = diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| (d.file.clone(), d.line))
        .collect();
    diagnostics.retain(|d| d.severity != Severity::Error);
    let mut warnings = diagnostics;
    if let Some((system, line, why)) = detected {
        warnings.insert(0, detect::system_warning(main, system, line, &why));
    }
    let moves = m.run(prog, &mut warnings).map_err(|mut e| {
        if let Some(made) = partial {
            let before = std::mem::take(&mut m.out.moves);
            *made = nose::apply(&m, before.clone(), &warnings).unwrap_or(before);
        }
        e.others = warnings.clone();
        e
    })?;
    let moves = nose::apply(&m, moves, &warnings)?;
    let mill = match m.mill.take() {
        Some(st) => mill::compensate(&st.path).map_err(|(k, message)| {
            let site = &st.path[k].site;
            NcError {
                file: site.file.clone(),
                line: site.line,
                col: 0,
                message,
                snippet: site.snippet.clone(),
                stack: site.stack.clone(),
                hint: None,
                others: warnings.clone(),
            }
        })?,
        None => Vec::new(),
    };
    Ok(Toolpath {
        moves,
        mill,
        warnings,
        dwells: std::mem::take(&mut m.out.dwells),
        inch: m.out.inch_threads,
    })
}

impl Interp<'_> {
    /// A program by the name it is called by: already known, or loaded beside the main
    /// file (FANUC `O0002`, `O0002.NC`; Siemens `NAME.SPF`, `NAME.MPF`).
    fn find_program(&mut self, name: &str) -> Option<std::rc::Rc<Program>> {
        if let Some(p) = self.progs.by_name.get(name) {
            return Some(p.clone());
        }
        let candidates: Vec<String> =
            match name.strip_prefix('O').and_then(|n| n.parse::<u32>().ok()) {
                Some(n) if self.cfg.dialect == Dialect::Fanuc => vec![
                    format!("O{n:04}"),
                    format!("O{n:04}.NC"),
                    format!("O{n:04}.nc"),
                    format!("O{n}"),
                ],
                _ => vec![
                    format!("{name}.SPF"),
                    format!("{name}.spf"),
                    format!("{name}.MPF"),
                    name.to_string(),
                ],
            };
        let src = candidates.iter().find_map(|c| (self.progs.loader)(c))?;
        let macros = &self.vars.s840.macros;
        let loaded: Vec<_> = load_programs(&src, self.cfg.dialect, self.cfg.block_skip)
            .into_iter()
            .map(|mut p| {
                siemens_defs::expand_program(&mut p, macros);
                std::rc::Rc::new(p)
            })
            .collect();
        let mut loaded = loaded.into_iter();
        let first = loaded.next().expect("one program");
        self.register(first.clone());
        self.progs.by_name.insert(name.to_string(), first.clone());
        for other in loaded {
            self.register(other);
        }
        Some(first)
    }

    /// The dialect as the user named it (GSK shares FANUC's syntax).
    fn real_dialect(&self) -> Dialect {
        if self.cfg.gsk {
            Dialect::Gsk980
        } else if self.cfg.s840 {
            Dialect::Siemens840d
        } else {
            self.cfg.dialect
        }
    }

    /// A word or code vpcut does not know: a warning (skipped), or an error in strict mode.
    fn unknown(&mut self, col: usize, message: String) -> Result<(), Fail> {
        if self.cfg.strict {
            return Err((col, message));
        }
        self.out.pending.push((col, message));
        Ok(())
    }

    /// Run from the first block of `prog`; warnings of the run are added to `warnings`
    /// (each once).
    fn run(
        &mut self,
        prog: std::rc::Rc<Program>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Vec<Move>, NcError> {
        let m = self;
        let dialect = m.cfg.dialect;
        let mut stack: Vec<Frame> = Vec::new();
        let mut loops: Vec<(u32, usize)> = Vec::new();
        let mut cur = prog;
        let mut pc = 0usize;
        // Leave the current (sub)program: run it again while repeats are left, else go back to
        // the caller. Returns false at the end of the main program.
        let leave = |stack: &mut Vec<Frame>,
                     cur: &mut std::rc::Rc<Program>,
                     pc: &mut usize,
                     loops: &mut Vec<(u32, usize)>| {
            match stack.last_mut() {
                Some(top) if top.repeats_left > 1 => {
                    top.repeats_left -= 1;
                    *pc = 0;
                    loops.clear();
                    Some(false)
                }
                Some(_) => {
                    let f = stack.pop().expect("checked");
                    *cur = f.caller;
                    *pc = f.ret;
                    *loops = f.caller_loops;
                    Some(f.macro_level)
                }
                None => None,
            }
        };
        loop {
            if pc >= cur.blocks.len() {
                match leave(&mut stack, &mut cur, &mut pc, &mut loops) {
                    Some(popped_macro) => {
                        if popped_macro {
                            m.vars.locals.pop();
                        }
                        continue;
                    }
                    None => break,
                }
            }
            m.out.blocks += 1;
            let (line, orig, text) = &cur.blocks[pc];
            let fail = |stack: &[Frame], col: usize, message: String| NcError {
                file: cur.name.clone(),
                line: *line,
                col: lex::char_col(orig, col),
                message,
                hint: None,
                others: Vec::new(),
                snippet: orig.clone(),
                stack: callers(stack),
            };
            if !m.cfg.stop_at.is_empty() && m.cfg.stop_at.contains(&(cur.name.clone(), *line)) {
                // A partial run stops at a block the check refused.
                return Err(fail(&stack, 0, "a block the check refused".into()));
            }
            if m.out.blocks > m.cfg.limits.max_blocks {
                return Err(fail(
                    &stack,
                    0,
                    format!(
                        "more than {} blocks executed: a loop that never ends?",
                        m.cfg.limits.max_blocks
                    ),
                ));
            }
            let before = m.out.moves.len();
            if let Some(st) = m.mill.as_mut() {
                st.stack = callers(&stack);
            }
            let step = match dialect {
                Dialect::Siemens802d | Dialect::Siemens840d => m.siemens_block(&cur, pc, text),
                Dialect::Linuxcnc => m.lcnc_block(&cur, pc, text),
                Dialect::Fanuc | Dialect::Gsk980 | Dialect::Okuma => {
                    m.fanuc_block(&cur, pc, text, &mut loops)
                }
            };
            m.check_inch_lead(before);
            // Columns are in the comment-stripped text; map back roughly to the line.
            let offset = || orig.to_ascii_uppercase().find(text.as_str()).unwrap_or(0);
            if !m.out.pending.is_empty() || !m.out.notes.is_empty() {
                let offset = offset();
                let skipped = "skipped: vpcut does not simulate it (an error with --strict)";
                let pending = std::mem::take(&mut m.out.pending)
                    .into_iter()
                    .map(|(col, message)| (col, message, skipped.to_string()));
                let notes = std::mem::take(&mut m.out.notes);
                for (col, message, hint) in pending.chain(notes) {
                    let e = fail(&stack, col + offset, message);
                    let mut d = e.diagnostic();
                    d.severity = Severity::Warning;
                    d.hint = Some(hint);
                    // Once a line: the check's warning (at its word) and the run's (at
                    // the block) are one.
                    let seen = warnings
                        .iter()
                        .any(|w| (&w.file, w.line, &w.message) == (&d.file, d.line, &d.message));
                    if !seen {
                        warnings.push(d);
                    }
                }
            }
            if !m.out.notes.is_empty() {
                let offset = offset();
                for (col, message, hint) in std::mem::take(&mut m.out.notes) {
                    let mut d = fail(&stack, col + offset, message).diagnostic();
                    d.severity = Severity::Warning;
                    d.hint = Some(hint);
                    // Once a line: the check's warning (at its word) and the run's (at
                    // the block) are one.
                    let seen = warnings
                        .iter()
                        .any(|w| (&w.file, w.line, &w.message) == (&d.file, d.line, &d.message));
                    if !seen {
                        warnings.push(d);
                    }
                }
            }
            let step = match step {
                Ok(s) => s,
                Err((col, msg)) => return Err(fail(&stack, col + offset(), msg)),
            };
            let made = m.out.moves.len() + m.mill.as_ref().map_or(0, |st| st.path.len());
            if m.out.too_many_moves || made > m.cfg.limits.max_moves {
                return Err(fail(
                    &stack,
                    0,
                    format!(
                        "more than {} moves (the limit on moves a program may make): a loop that never ends?",
                        m.cfg.limits.max_moves
                    ),
                ));
            }
            if face_threads(&mut m.out.moves[before..]) {
                face_thread_warning(warnings, fail(&stack, 0, String::new()));
            }
            for mv in &m.out.moves[before..] {
                if let Some(msg) = lead_problem(mv) {
                    return Err(fail(&stack, 0, msg));
                }
            }
            match step {
                Step::Next => pc += 1,
                Step::Jump(to) => pc = to,
                Step::End => break,
                Step::Return => {
                    if stack.is_empty() && dialect == Dialect::Fanuc {
                        main_m99(warnings, fail(&stack, 0, String::new()));
                    }
                    match leave(&mut stack, &mut cur, &mut pc, &mut loops) {
                        Some(popped_macro) => {
                            if popped_macro {
                                m.vars.locals.pop();
                            }
                        }
                        None => break,
                    }
                }
                Step::ReturnTo(n) => {
                    // M99 P<n>: back to the caller's block N<n> once the last repetition ends;
                    // in the main program it ends the run, as M99 does (see `Step::ReturnTo`).
                    if stack.is_empty() && dialect == Dialect::Fanuc {
                        main_m99(warnings, fail(&stack, 0, String::new()));
                    }
                    let target = match stack.last() {
                        Some(top) if top.repeats_left <= 1 => match top.caller.numbers.get(&n) {
                            Some(&k) => Some(k),
                            None => {
                                return Err(fail(
                                    &stack,
                                    1,
                                    format!("M99 P{n}: the calling program has no block N{n}"),
                                ))
                            }
                        },
                        _ => None,
                    };
                    match leave(&mut stack, &mut cur, &mut pc, &mut loops) {
                        Some(popped_macro) => {
                            if popped_macro {
                                m.vars.locals.pop();
                            }
                            if let Some(k) = target {
                                pc = k;
                            }
                        }
                        None => break,
                    }
                }
                Step::Call(name, times, args) => {
                    if stack.len() + 1 > m.cfg.limits.max_depth {
                        return Err(fail(
                            &stack,
                            0,
                            format!("subprogram nesting deeper than {}", m.cfg.limits.max_depth),
                        ));
                    }
                    let Some(p) = m.find_program(&name) else {
                        let file = codes::fanuc_file_name(&name);
                        let beside = if dialect == Dialect::Fanuc {
                            file
                        } else {
                            format!("{name}.SPF")
                        };
                        return Err(fail(
                        &stack,
                        1,
                        format!("subprogram `{name}` not found (in this file or as {beside} beside it)"),
                    ));
                    };
                    stack.push(Frame {
                        caller: cur.clone(),
                        ret: pc + 1,
                        repeats_left: times.max(1),
                        caller_loops: std::mem::take(&mut loops),
                        macro_level: args.is_some(),
                    });
                    if let Some(args) = args {
                        // A new level: all locals vacant but the arguments (set once, kept
                        // over the repetitions).
                        m.vars
                            .locals
                            .push(args.into_iter().filter(|a| !a.1.is_nan()).collect());
                    }
                    cur = p;
                    pc = 0;
                }
            }
        }
        Ok(std::mem::take(&mut m.out.moves))
    }
}

/// The warning at an M99 that ends the main program (`at`: its block, as an error without a
/// message): a FANUC goes back to the program's start (or to `N` of `M99 P`) and runs it
/// again until the operator stops it; vpcut runs it once.
fn main_m99(warnings: &mut Vec<Diagnostic>, at: NcError) {
    let mut d = at.diagnostic();
    d.severity = Severity::Warning;
    d.message = "M99 ends the main program: a FANUC-style control goes back to its start and runs it again, without end; vpcut runs it once".into();
    d.hint = Some("end the main program with M30 (or M02); if this is a subprogram, the file's main program is chosen by `main` in [program] (the one that ends in M30 and is called by no other, by default)".into());
    warnings.push(d);
}

/// Thread moves along X only (a face thread or scroll: FANUC/GSK G32 and LinuxCNC/Siemens
/// G33 without Z travel, which the controls run) become feed moves at their lead per
/// revolution: vpcut's threads run along Z, so the face is cut as a facing move cuts it
/// (the spiral's own groove is not modelled). Returns whether there was one.
fn face_threads(moves: &mut [Move]) -> bool {
    let mut any = false;
    for mv in moves.iter_mut() {
        let lead = mv.lead.filter(|f| *f > 0.0 && f.is_finite());
        if mv.kind == MoveKind::Thread && mv.z == mv.z_start && mv.x_dia != mv.x_start {
            if let Some(f) = lead {
                mv.kind = MoveKind::Feed;
                mv.lead = None;
                mv.lead_change = None;
                mv.sync_angle_deg = None;
                mv.chained = false;
                mv.feed = Some(Feed {
                    value: f,
                    per_rev: true,
                });
                any = true;
            }
        }
    }
    any
}

/// The warning at a block whose thread moves run along X only (`face_threads`).
fn face_thread_warning(warnings: &mut Vec<Diagnostic>, at: NcError) {
    let mut d = at.diagnostic();
    d.severity = Severity::Warning;
    d.message = "a thread move along X only (a face thread or scroll): run as a feed move at its lead per revolution; vpcut simulates threads along Z, so the face is cut as a facing move would cut it (the spiral groove is not modelled)".into();
    d.hint =
        Some("a thread on a face is not compared with the drawing; the threads along Z are".into());
    let seen = warnings
        .iter()
        .any(|w| (&w.file, w.line, &w.message) == (&d.file, d.line, &d.message));
    if !seen {
        warnings.push(d);
    }
}

/// Why a thread move cannot be cut as programmed, if it cannot: a lead that is not positive
/// at the start or that reaches zero before the end (`L^2 = F^2 + 2 K s` along z: a real
/// control alarms), or a move without axial travel.
pub(super) fn lead_problem(mv: &Move) -> Option<String> {
    let (f, k) = (mv.lead?, mv.lead_change.unwrap_or(0.0));
    let s = (mv.z - mv.z_start).abs();
    if s == 0.0 && mv.x_dia == mv.x_start {
        // A thread move that goes nowhere (a repeated block): nothing to cut.
        return None;
    }
    if !(f > 0.0 && f.is_finite() && k.is_finite()) {
        return Some(format!(
            "a thread move needs a positive lead, got {f} mm/rev"
        ));
    }
    if s == 0.0 {
        return Some(
            "a thread move without travel along Z (a face thread) is not simulated".into(),
        );
    }
    if f * f + 2.0 * k * s <= 0.0 {
        return Some(format!(
            "the lead {f} mm/rev changing by {k} mm/rev^2 reaches zero after {:.4} mm of this {s:.4} mm thread move (a real control alarms)",
            f * f / (2.0 * k.abs())
        ));
    }
    None
}

/// The callers of the running block, innermost first ("O0002:14").
fn callers(stack: &[Frame]) -> Vec<String> {
    stack
        .iter()
        .rev()
        .map(|f| {
            let l = f
                .caller
                .blocks
                .get(f.ret.saturating_sub(1))
                .map_or(0, |b| b.0);
            format!("{}:{l}", f.caller.name)
        })
        .collect()
}

/// A subprogram call in progress: where to return, how many more runs of the callee, and
/// the caller's open WHILE loops (loops belong to one program).
struct Frame {
    caller: std::rc::Rc<Program>,
    ret: usize,
    repeats_left: u32,
    caller_loops: Vec<(u32, usize)>,
    /// A G65 call: leaving it drops its level of local variables.
    macro_level: bool,
}

enum Step {
    Next,
    Jump(usize),
    End,
    Return,
    /// `M99 P<n>`: return to the block N<n> of the caller. FANUC loops a main program
    /// from its start (or from N<n>) on M99; vpcut ends the run there instead, as on M30.
    ReturnTo(u32),
    /// A subprogram call: name, runs, and for a G65 macro call its arguments (a new level
    /// of local variables).
    Call(String, u32, Option<Vec<(u32, f64)>>),
}

/// Words of one block.
#[derive(Default)]
struct Words {
    g: Vec<u32>,
    m: Vec<u32>,
    vals: HashMap<String, (f64, usize)>,
    /// Letters whose value was written with a decimal point.
    points: Vec<String>,
    /// Letters whose value was a number written without a decimal point (not a variable or
    /// an expression; FANUC syntax only): what standard decimal-point input reads in the
    /// least input increment (`units`).
    plain: Vec<String>,
    /// The T word as written, where it is a plain number or a Siemens tool name (`T0202`,
    /// `T="NAME"`); else the tool is spelled from its value ([`tool_word`]).
    t_text: Option<String>,
}

/// A tool word spelled from its value, as the dialect writes it: FANUC and GSK codes with
/// an offset in four digits (`T0202`), Okuma's in four or six (`T0101`, `T030303`), a
/// number alone otherwise (`T3`).
pub(super) fn tool_word(dialect: Dialect, t: f64) -> String {
    let n = t.round().max(0.0) as u64;
    match dialect {
        Dialect::Fanuc if n >= 100 => format!("T{n:04}"),
        Dialect::Okuma if n >= 10_000 => format!("T{n:06}"),
        Dialect::Okuma => format!("T{n:04}"),
        _ => format!("T{n}"),
    }
}

/// A move's tool for a message: as the program wrote it, else `T<n>`, else "no tool".
impl Move {
    /// The tool as the program wrote it (`T0202`, `T="GEW_AUSSEN_3.0"`), else its number
    /// as `T<n>`; "no tool" before any T word.
    pub fn tool_name(&self) -> String {
        match (&self.tool_word, self.tool) {
            (Some(w), _) => w.to_string(),
            (None, Some(t)) => format!("T{t}"),
            (None, None) => "no tool".into(),
        }
    }
}

/// What synchronises a thread move to the spindle.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sync {
    /// Lead at the start (mm/rev).
    lead: f64,
    /// Lead change per revolution (mm/rev^2).
    change: f64,
    /// Spindle angle at the start (deg).
    angle: f64,
}

/// The lead along the path of a thread move (mm per revolution along the move: its Z lead
/// times path length over Z travel; equal to the Z lead on a straight thread).
pub fn path_lead(m: &Move) -> Option<f64> {
    let lead = m.lead?;
    let dz = (m.z - m.z_start).abs();
    if dz == 0.0 {
        return Some(lead);
    }
    let path = ((m.x_dia - m.x_start) / 2.0).hypot(m.z - m.z_start);
    Some(lead * path / dz)
}

/// The moves as CSV, one row per move the control makes (rapids and feeds of cycles
/// included): `file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg,x_start_dia,
/// z_start,path_lead`. `x_dia`/`z` are the end point, `x_start_dia`/`z_start` the start;
/// `lead` is the Z lead (mm of Z per spindle revolution), `path_lead` the distance per
/// revolution along the move (LinuxCNC's K on a taper; the same as `lead` on a straight
/// thread).
pub fn to_csv(moves: &[Move]) -> String {
    let mut s = String::from(
        "file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg,x_start_dia,z_start,path_lead\n",
    );
    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
    for m in moves {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{}\n",
            m.file,
            m.line,
            m.kind.name(),
            m.x_dia,
            m.x_dia / 2.0,
            m.z,
            o(m.lead),
            o(m.lead_change),
            o(m.sync_angle_deg),
            m.x_start,
            m.z_start,
            o(path_lead(m)),
        ));
    }
    s
}
