//! NC programs: FANUC (Macro A/B), GSK 980TDC, Siemens 802D and LinuxCNC lathe dialects
//! interpreted into a toolpath whose thread moves become passes.
//!
//! The interpreter reads text given by the caller (no IO here): the main program, and a
//! loader for subprograms found beside it. Every error names the file, line and column and
//! the call stack. Layout:
//!
//! - `program`: splitting a file into programs and blocks (comments, N numbers, labels);
//! - `expr`: the block cursor and the expression evaluators (FANUC `[ ]`/`#`, Siemens `( )`/`R`);
//! - `fanuc`: FANUC/GSK blocks, Macro A/B, G76, G92, GSK G34;
//! - `siemens`: Siemens 802D blocks, labels and jumps;
//! - `linuxcnc`: LinuxCNC blocks, O-word subroutines and control flow, G76;
//! - `lcnc_expr`: LinuxCNC expressions and numbered/named parameters;
//! - `motion`: modal state, motion words, and recording moves.

mod expr;
mod fanuc;
mod lcnc_expr;
mod linuxcnc;
mod motion;
mod program;
mod siemens;
#[cfg(test)]
mod tests;

use program::{load_programs, Program};

use crate::helix::Spindle;
use std::collections::HashMap;
use std::fmt;

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
}

impl Dialect {
    /// Parse the name used in jobs and on the command line.
    pub fn from_name(s: &str) -> Option<Dialect> {
        match s {
            "fanuc" => Some(Dialect::Fanuc),
            "gsk980" => Some(Dialect::Gsk980),
            "linuxcnc" => Some(Dialect::Linuxcnc),
            "siemens-802d" => Some(Dialect::Siemens802d),
            _ => None,
        }
    }
}

impl Dialect {
    /// The syntax family: GSK writes programs as FANUC does.
    fn syntax(self) -> Dialect {
        match self {
            Dialect::Gsk980 => Dialect::Fanuc,
            d => d,
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
    /// G1 (and arcs, later).
    Feed,
    /// A spindle-synchronised threading move.
    Thread,
}

impl MoveKind {
    /// Name used in CSV/JSON.
    pub fn name(self) -> &'static str {
        match self {
            MoveKind::Rapid => "rapid",
            MoveKind::Feed => "feed",
            MoveKind::Thread => "thread",
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
    /// Spindle angle at the sync point (deg, thread moves).
    pub sync_angle_deg: Option<f64>,
    /// Active tool number (T0101 and T1 are tool 1).
    pub tool: Option<u32>,
    /// Spindle direction.
    pub spindle: Spindle,
}

/// An error while interpreting.
#[derive(Clone, Debug, PartialEq)]
pub struct NcError {
    /// File.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (0 = the whole block).
    pub col: usize,
    /// What is wrong.
    pub message: String,
    /// The block's text.
    pub snippet: String,
    /// Callers, innermost first ("MYAAA.MPF:14").
    pub stack: Vec<String>,
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file,
            self.line,
            self.col.max(1),
            self.message
        )?;
        let num = self.line.to_string();
        let pad = " ".repeat(num.len());
        write!(f, "\n{pad} |\n{num} | {}", self.snippet)?;
        if self.col > 0 {
            write!(f, "\n{pad} | {}^", " ".repeat(self.col - 1))?;
        }
        for s in &self.stack {
            write!(f, "\n  called from {s}")?;
        }
        Ok(())
    }
}

impl std::error::Error for NcError {}

/// Limits that turn runaway programs into errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Executed blocks.
    pub max_blocks: u64,
    /// Subprogram nesting.
    pub max_depth: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_blocks: 10_000_000,
            max_depth: 8,
        }
    }
}

/// Interpreter state.
struct Machine<'l> {
    /// Syntax family (FANUC for GSK too).
    dialect: Dialect,
    /// GSK 980TDC semantics for G34.
    gsk: bool,
    /// LinuxCNC semantics (G33 K, G76 P..L, G7/G8).
    lcnc: bool,
    /// X words are diameters (G7; always on FANUC/GSK/Siemens lathes), else radii (G8).
    diameter_mode: bool,
    loader: &'l dyn Fn(&str) -> Option<Source>,
    limits: Limits,
    programs: HashMap<String, std::rc::Rc<Program>>,
    r: HashMap<u32, f64>,
    /// FANUC common variables (#100.., #500..); a missing entry is null (vacant).
    vars: HashMap<u32, f64>,
    /// FANUC local variables #1..#33, one level per G65 macro call; missing = null.
    locals: Vec<HashMap<u32, f64>>,
    x: f64,
    z: f64,
    motion: u32,
    incremental: bool,
    inch: bool,
    tool: Option<u32>,
    spindle: Spindle,
    moves: Vec<Move>,
    blocks: u64,
    g76: G76Setup,
    /// Modal G92 target z and lead.
    g92: Option<(f64, f64)>,
    /// LinuxCNC named parameters, call levels and O-word tables.
    lc: linuxcnc::Lcnc,
}

pub(super) fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// Interpret a program into moves.
pub fn interpret(
    main: &Source,
    dialect: Dialect,
    loader: &dyn Fn(&str) -> Option<Source>,
    limits: Limits,
) -> Result<Vec<Move>, NcError> {
    let gsk = dialect == Dialect::Gsk980;
    let lcnc = dialect == Dialect::Linuxcnc;
    let dialect = dialect.syntax();
    let mut m = Machine {
        dialect,
        gsk,
        lcnc,
        diameter_mode: !lcnc,
        loader,
        limits,
        programs: HashMap::new(),
        r: HashMap::new(),
        vars: HashMap::new(),
        locals: vec![HashMap::new()],
        x: 0.0,
        z: 0.0,
        motion: 0,
        incremental: false,
        inch: false,
        tool: None,
        spindle: Spindle::Cw,
        moves: Vec::new(),
        blocks: 0,
        g76: G76Setup {
            m: 1,
            r: 0,
            a: 60.0,
            dmin: 0.0,
            d: 0.0,
        },
        g92: None,
        lc: Default::default(),
    };
    let mut all = load_programs(main, dialect).into_iter();
    let prog = std::rc::Rc::new(all.next().expect("a file gives at least one program"));
    m.register(prog.clone());
    for p in all {
        m.register(std::rc::Rc::new(p));
    }
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
                        m.locals.pop();
                    }
                    continue;
                }
                None => break,
            }
        }
        m.blocks += 1;
        let (line, orig, text) = &cur.blocks[pc];
        let fail = |stack: &[Frame], col: usize, message: String| NcError {
            file: cur.name.clone(),
            line: *line,
            col,
            message,
            snippet: orig.clone(),
            stack: stack
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
                .collect(),
        };
        if m.blocks > m.limits.max_blocks {
            return Err(fail(
                &stack,
                0,
                format!(
                    "more than {} blocks executed: a loop that never ends?",
                    m.limits.max_blocks
                ),
            ));
        }
        let step = match dialect {
            Dialect::Siemens802d => m.siemens_block(&cur, pc, text),
            Dialect::Linuxcnc => m.lcnc_block(&cur, pc, text),
            Dialect::Fanuc | Dialect::Gsk980 => m.fanuc_block(&cur, pc, text, &mut loops),
        };
        let step = match step {
            Ok(s) => s,
            Err((col, msg)) => {
                // Columns are in the comment-stripped text; map back roughly to the line.
                let offset = orig.to_ascii_uppercase().find(text.as_str()).unwrap_or(0);
                return Err(fail(&stack, col + offset, msg));
            }
        };
        match step {
            Step::Next => pc += 1,
            Step::Jump(to) => pc = to,
            Step::End => break,
            Step::Return => match leave(&mut stack, &mut cur, &mut pc, &mut loops) {
                Some(popped_macro) => {
                    if popped_macro {
                        m.locals.pop();
                    }
                }
                None => break,
            },
            Step::Call(name, times, args) => {
                if stack.len() + 1 > m.limits.max_depth {
                    return Err(fail(
                        &stack,
                        0,
                        format!("subprogram nesting deeper than {}", m.limits.max_depth),
                    ));
                }
                let p = match m.programs.get(&name) {
                    Some(p) => p.clone(),
                    None => {
                        let candidates: Vec<String> =
                            match name.strip_prefix('O').and_then(|n| n.parse::<u32>().ok()) {
                                Some(n) if dialect == Dialect::Fanuc => vec![
                                    format!("O{n:04}"),
                                    format!("O{n:04}.NC"),
                                    format!("O{n:04}.nc"),
                                    format!("O{n}"),
                                ],
                                _ => vec![
                                    format!("{name}.SPF"),
                                    format!("{name}.spf"),
                                    format!("{name}.MPF"),
                                    name.clone(),
                                ],
                            };
                        let Some(src) = candidates.iter().find_map(|c| (m.loader)(c)) else {
                            return Err(fail(&stack, 1, format!("subprogram `{name}` not found (in this file or as {} beside it)", candidates[0])));
                        };
                        let mut loaded = load_programs(&src, dialect).into_iter();
                        let first = std::rc::Rc::new(loaded.next().expect("one program"));
                        m.register(first.clone());
                        m.programs.insert(name.clone(), first);
                        for other in loaded {
                            m.register(std::rc::Rc::new(other));
                        }
                        m.programs[&name].clone()
                    }
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
                    m.locals
                        .push(args.into_iter().filter(|a| !a.1.is_nan()).collect());
                }
                cur = p;
                pc = 0;
            }
        }
    }
    Ok(m.moves)
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
}

/// FANUC G76 first-block data (modal): finishing count, chamfer, tool angle (deg),
/// minimum cut and finishing allowance (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
struct G76Setup {
    m: u32,
    r: u32,
    a: f64,
    dmin: f64,
    d: f64,
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

/// The moves as CSV: `line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg`.
pub fn to_csv(moves: &[Move]) -> String {
    let mut s = String::from("file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg\n");
    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
    for m in moves {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            m.file,
            m.line,
            m.kind.name(),
            m.x_dia,
            m.x_dia / 2.0,
            m.z,
            o(m.lead),
            o(m.lead_change),
            o(m.sync_angle_deg)
        ));
    }
    s
}
