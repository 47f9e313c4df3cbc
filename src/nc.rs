//! NC programs: FANUC (Macro B subset) and Siemens 802D (R parameters, labels, subprograms)
//! lathe dialects interpreted into a toolpath whose thread moves become passes.
//!
//! This is the first part of the NC-program issue: enough of both languages to run the seed
//! programs (seed 002's `MYAAA.MPF`/`MYBBB.SPF`, seed 004's Macro B Tr program). It reads
//! text given by the caller (no IO here): the main program, and a loader for subprograms
//! found beside it. Every error names the file, line and column and the call stack.
//! FANUC G92 and the two-block G76 expand into passes here; M98/M99 subprograms, Macro A
//! (`G65 H..`), the GSK 980TDC `G34 F R` and LinuxCNC `G33`/`G76` (G7/G8) run too. Not yet:
//! taper cycles, run-out, G65 P calls with arguments, LinuxCNC O-words, Siemens CYCLE97,
//! diagnostics that go on after the first error.

use crate::helix::Spindle;
use std::collections::HashMap;
use std::fmt;

/// Controller dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// FANUC lathe, G-code system A, Custom Macro B (and Macro A `G65 H..`).
    Fanuc,
    /// LinuxCNC (rs274ngc) lathe: FANUC-like syntax, `G33 Z K`, `G76 P Z I J K R Q H`,
    /// radius mode G8 by default, diameter mode G7.
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
            Dialect::Gsk980 | Dialect::Linuxcnc => Dialect::Fanuc,
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

/// A program split into blocks.
#[derive(Debug)]
struct Program {
    name: String,
    /// Another name it is called by (`O0001` for the first program of `MAIN.NC`).
    alias: Option<String>,
    /// (1-based line, original text, text without comments, upper-cased).
    blocks: Vec<(usize, String, String)>,
    labels: HashMap<String, usize>,
    numbers: HashMap<u32, usize>,
}

fn strip_comment(line: &str, dialect: Dialect) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match (dialect, c) {
            (Dialect::Siemens802d, ';') => break,
            (Dialect::Fanuc, ';') if depth == 0 => break,
            (Dialect::Fanuc, '(') => depth += 1,
            (Dialect::Fanuc, ')') if depth > 0 => depth -= 1,
            _ if depth > 0 => {}
            _ => out.push(c.to_ascii_uppercase()),
        }
    }
    out.trim().to_string()
}

/// The programs of a file: for FANUC syntax each `O<number>` line starts a new program
/// (named `O<number>`, the first one also by the file's name); Siemens files hold one.
fn load_programs(src: &Source, dialect: Dialect) -> Vec<Program> {
    let mut out = Vec::new();
    let mut name = src.name.clone();
    let mut alias: Option<String> = None;
    let mut lines: Vec<(usize, &str)> = Vec::new();
    for (i, line) in src.text.lines().enumerate() {
        let text = strip_comment(line, dialect);
        let onum = text
            .strip_prefix('O')
            .filter(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
            .and_then(|r| r.parse::<u32>().ok());
        if dialect == Dialect::Fanuc {
            if let Some(n) = onum {
                let real = |l: &str| {
                    let t = strip_comment(l, dialect);
                    !t.is_empty() && t != "%"
                };
                if lines.iter().any(|(_, l)| real(l)) {
                    let mut p = load_program(&name, &lines, dialect);
                    p.alias = alias.take();
                    out.push(p);
                    lines.clear();
                    name = format!("O{n}");
                } else {
                    alias = Some(format!("O{n}"));
                }
                continue;
            }
        }
        lines.push((i, line));
    }
    let mut p = load_program(&name, &lines, dialect);
    p.alias = alias;
    out.push(p);
    out
}

fn load_program(name: &str, lines: &[(usize, &str)], dialect: Dialect) -> Program {
    let mut blocks = Vec::new();
    let mut labels = HashMap::new();
    let mut numbers = HashMap::new();
    for &(i, line) in lines {
        let text = strip_comment(line, dialect);
        if text.is_empty() || text == "%" || text.starts_with('/') {
            continue;
        }
        let idx = blocks.len();
        let mut rest = text.as_str();
        // N number.
        if let Some(r) = rest.strip_prefix('N') {
            let digits: String = r.chars().take_while(|c| c.is_ascii_digit()).collect();
            if !digits.is_empty() {
                if let Ok(n) = digits.parse() {
                    numbers.insert(n, idx);
                }
                rest = r[digits.len()..].trim_start();
            }
        }
        if dialect == Dialect::Siemens802d {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && rest[name.len()..].starts_with(':') {
                labels.insert(name, idx);
            }
        }
        blocks.push((i + 1, line.to_string(), text));
    }
    Program {
        name: name.to_string(),
        alias: None,
        blocks,
        labels,
        numbers,
    }
}

/// A cursor over one block's text.
struct Cur<'a> {
    s: &'a [u8],
    i: usize,
    dialect: Dialect,
}

type Fail = (usize, String);

impl<'a> Cur<'a> {
    fn new(s: &'a str, dialect: Dialect) -> Cur<'a> {
        Cur {
            s: s.as_bytes(),
            i: 0,
            dialect,
        }
    }
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }
    fn eat(&mut self, t: &str) -> bool {
        self.ws();
        if self.s[self.i..].starts_with(t.as_bytes()) {
            self.i += t.len();
            true
        } else {
            false
        }
    }
    fn done(&mut self) -> bool {
        self.peek().is_none()
    }
    fn err<T>(&self, msg: impl Into<String>) -> Result<T, Fail> {
        Err((self.i + 1, msg.into()))
    }
    fn ident(&mut self) -> String {
        self.ws();
        let st = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphabetic() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[st..self.i]).into_owned()
    }
    fn name_with_digits(&mut self) -> String {
        self.ws();
        let st = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[st..self.i]).into_owned()
    }
    /// An unsigned decimal number (`12`, `12.`, `.5`, `1.5`).
    fn number(&mut self) -> Option<f64> {
        self.ws();
        let st = self.i;
        while self.i < self.s.len() && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.') {
            self.i += 1;
        }
        if st == self.i {
            return None;
        }
        let t = String::from_utf8_lossy(&self.s[st..self.i]);
        match t.parse::<f64>() {
            Ok(v) => Some(v),
            Err(_) => {
                self.i = st;
                None
            }
        }
    }
}

/// Null (NaN) as 0, for arithmetic.
fn z(v: f64) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        v
    }
}

/// A comparison operator.
type Compare = fn(f64, f64) -> bool;

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
}

fn deg(x: f64) -> f64 {
    x.to_radians()
}

impl Machine<'_> {
    fn register(&mut self, p: std::rc::Rc<Program>) {
        if let Some(a) = &p.alias {
            self.programs.insert(a.clone(), p.clone());
        }
        self.programs.insert(p.name.clone(), p);
    }

    fn get(&self, c: &mut Cur, idx: u32) -> Result<f64, Fail> {
        match c.dialect {
            Dialect::Siemens802d => Ok(*self.r.get(&idx).unwrap_or(&0.0)),
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => {
                // Null (vacant, and #0) is carried as NaN: 0 in arithmetic, but not equal
                // to 0 under EQ/NE (controllers.md 4.1).
                let v = if idx == 0 {
                    None
                } else if (1..=33).contains(&idx) {
                    self.locals.last().and_then(|l| l.get(&idx))
                } else {
                    self.vars.get(&idx)
                };
                Ok(v.copied().unwrap_or(f64::NAN))
            }
        }
    }

    fn expr(&self, c: &mut Cur) -> Result<f64, Fail> {
        self.or(c)
    }

    /// Store a FANUC variable; null (NaN) makes it vacant.
    fn set_var(&mut self, idx: u32, v: f64) {
        let map = if (1..=33).contains(&idx) {
            self.locals.last_mut().expect("level 0 always exists")
        } else {
            &mut self.vars
        };
        if v.is_nan() {
            map.remove(&idx);
        } else {
            map.insert(idx, v);
        }
    }
    fn or(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.and(c)?;
        while c.eat("OR") {
            let w = self.and(c)?;
            v = f64::from(z(v) != 0.0 || z(w) != 0.0);
        }
        Ok(v)
    }
    fn and(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.cmp(c)?;
        while c.eat("AND") {
            let w = self.cmp(c)?;
            v = f64::from(z(v) != 0.0 && z(w) != 0.0);
        }
        Ok(v)
    }
    fn cmp(&self, c: &mut Cur) -> Result<f64, Fail> {
        let v = self.add(c)?;
        let ops: &[(&str, Compare)] = match c.dialect {
            Dialect::Siemens802d => &[
                ("==", |a, b| a == b),
                ("<>", |a, b| a != b),
                ("<=", |a, b| a <= b),
                (">=", |a, b| a >= b),
                ("<", |a, b| a < b),
                (">", |a, b| a > b),
            ],
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => &[
                ("EQ", |a, b| a == b),
                ("NE", |a, b| a != b),
                ("LE", |a, b| a <= b),
                ("GE", |a, b| a >= b),
                ("LT", |a, b| a < b),
                ("GT", |a, b| a > b),
            ],
        };
        for (op, f) in ops {
            if c.eat(op) {
                let w = self.add(c)?;
                // Null equals only null under EQ/NE; elsewhere it is 0.
                let result = match *op {
                    "EQ" | "NE" if v.is_nan() || w.is_nan() => {
                        (v.is_nan() && w.is_nan()) == (*op == "EQ")
                    }
                    _ => f(z(v), z(w)),
                };
                return Ok(f64::from(result));
            }
        }
        Ok(v)
    }
    fn add(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.mul(c)?;
        loop {
            if c.eat("+") {
                v = z(v) + z(self.mul(c)?);
            } else if c.peek() == Some(b'-') {
                c.i += 1;
                v = z(v) - z(self.mul(c)?);
            } else {
                return Ok(v);
            }
        }
    }
    fn mul(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.unary(c)?;
        loop {
            if c.eat("*") {
                v = z(v) * z(self.unary(c)?);
            } else if c.eat("/") {
                let at = c.i;
                let w = z(self.unary(c)?);
                if w == 0.0 {
                    return Err((at + 1, "division by zero".into()));
                }
                v = z(v) / w;
            } else {
                return Ok(v);
            }
        }
    }
    fn unary(&self, c: &mut Cur) -> Result<f64, Fail> {
        if c.eat("-") {
            return Ok(-z(self.unary(c)?));
        }
        if c.eat("+") {
            return self.unary(c);
        }
        self.primary(c)
    }
    fn primary(&self, c: &mut Cur) -> Result<f64, Fail> {
        let (open, close) = match c.dialect {
            Dialect::Siemens802d => ("(", ")"),
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => ("[", "]"),
        };
        if c.eat(open) {
            let v = self.expr(c)?;
            if !c.eat(close) {
                return c.err(format!("expected `{close}`"));
            }
            return Ok(v);
        }
        if c.dialect == Dialect::Fanuc && c.eat("#") {
            return self.var_ref(c);
        }
        if let Some(v) = c.number() {
            return Ok(v);
        }
        let at = c.i;
        let name = c.ident();
        if name.is_empty() {
            return c.err("expected a number, a parameter or a function");
        }
        if c.dialect == Dialect::Siemens802d && name == "R" {
            let Some(n) = c.number() else {
                return c.err("expected an R parameter number");
            };
            return self.get(c, n as u32);
        }
        if !c.eat(open) {
            return Err((at + 1, format!("unknown name `{name}`")));
        }
        let a = z(self.expr(c)?);
        let b = if c.eat(",") {
            Some(z(self.expr(c)?))
        } else {
            None
        };
        if !c.eat(close) {
            return c.err(format!("expected `{close}`"));
        }
        let v = match (name.as_str(), b) {
            ("ABS", None) => a.abs(),
            ("SQRT", None) if a >= 0.0 => a.sqrt(),
            ("SQRT", None) => return Err((at + 1, "square root of a negative number".into())),
            ("SIN", None) => deg(a).sin(),
            ("COS", None) => deg(a).cos(),
            ("TAN", None) => deg(a).tan(),
            ("ATAN2", Some(b)) => a.atan2(b).to_degrees(),
            ("ATAN", Some(b)) => a.atan2(b).to_degrees(),
            ("ATAN", None) => a.atan().to_degrees(),
            ("TRUNC", None) | ("FIX", None) => a.trunc(),
            ("FUP", None) => {
                if a >= 0.0 {
                    a.ceil()
                } else {
                    a.floor()
                }
            }
            ("ROUND", None) => a.round(),
            ("POT", None) => a * a,
            ("LN", None) if a > 0.0 => a.ln(),
            ("EXP", None) => a.exp(),
            _ => {
                return Err((
                    at + 1,
                    format!("unknown function `{name}` with these arguments"),
                ))
            }
        };
        Ok(v)
    }
    fn var_ref(&self, c: &mut Cur) -> Result<f64, Fail> {
        let idx = if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            v
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        self.get(c, idx.round() as u32)
    }

    /// A FANUC word value: a number, `#n`, `-#n` or `[expr]`.
    fn fanuc_value(&self, c: &mut Cur) -> Result<f64, Fail> {
        let neg = c.eat("-");
        let _ = c.eat("+");
        let v = if c.eat("#") {
            self.var_ref(c)?
        } else if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            v
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a number".to_string()))?
        };
        Ok(if neg { -v } else { v })
    }
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
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => {
                m.fanuc_block(&cur, pc, text, &mut loops)
            }
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

impl Machine<'_> {
    fn siemens_block(&mut self, prog: &Program, pc: usize, text: &str) -> Result<Step, Fail> {
        let mut c = Cur::new(text, self.dialect);
        // Skip N and a label.
        if c.eat("N") {
            let _ = c.number();
        }
        let save = c.i;
        let name = c.name_with_digits();
        if name.is_empty() || !c.eat(":") {
            // Not a label: read the block from the start.
            c.i = save;
        }
        let mut w = Words::default();
        while !c.done() {
            let at = c.i;
            let name = c.ident();
            match name.as_str() {
                "IF" => {
                    let v = self.expr(&mut c)?;
                    let kw = c.ident();
                    let target = c.name_with_digits();
                    let to = self.label(prog, pc, &kw, &target, at)?;
                    return Ok(if v != 0.0 { Step::Jump(to) } else { Step::Next });
                }
                "GOTOF" | "GOTOB" | "GOTO" => {
                    let target = c.name_with_digits();
                    return Ok(Step::Jump(self.label(prog, pc, &name, &target, at)?));
                }
                "RET" => return Ok(Step::Return),
                "R" if c.s.get(c.i).is_some_and(|b| b.is_ascii_digit()) => {
                    let n = c.number().unwrap_or(0.0) as u32;
                    if !c.eat("=") {
                        return c.err("expected `=` after an R parameter");
                    }
                    let v = self.expr(&mut c)?;
                    self.r.insert(n, v);
                }
                "" => return Err((at + 1, format!("unexpected `{}`", c.s[c.i] as char))),
                addr if addr.len() <= 2
                    && matches!(
                        addr,
                        "G" | "M" | "S" | "T" | "X" | "Z" | "F" | "K" | "I" | "SF" | "D" | "P"
                    ) =>
                {
                    let v = if c.eat("=") {
                        self.expr(&mut c)?
                    } else {
                        let neg = c.eat("-");
                        let v = c
                            .number()
                            .ok_or((c.i + 1, format!("expected a value after `{addr}`")))?;
                        if neg {
                            -v
                        } else {
                            v
                        }
                    };
                    match addr {
                        "G" => w.g.push(v as u32),
                        "M" => w.m.push(v as u32),
                        _ => {
                            w.vals.insert(addr.to_string(), (v, at + 1));
                        }
                    }
                }
                call if call.len() > 2 => {
                    // A subprogram called by name, with an optional repeat `P n`.
                    let mut times = 1;
                    if c.eat("P") {
                        times = c.number().unwrap_or(1.0).max(1.0) as u32;
                    }
                    self.apply(&w, prog, pc)?;
                    return Ok(Step::Call(call.to_string(), times, None));
                }
                other => return Err((at + 1, format!("unknown word `{other}`"))),
            }
        }
        self.apply(&w, prog, pc)
    }

    fn label(
        &self,
        prog: &Program,
        pc: usize,
        kw: &str,
        target: &str,
        at: usize,
    ) -> Result<usize, Fail> {
        let Some(&to) = prog.labels.get(target) else {
            return Err((
                at + 1,
                format!("label `{target}` not found in {}", prog.name),
            ));
        };
        match kw {
            "GOTOF" if to <= pc => Err((
                at + 1,
                format!("GOTOF jumps forward, but `{target}` is above"),
            )),
            "GOTOB" if to > pc => {
                Err((at + 1, format!("GOTOB jumps back, but `{target}` is below")))
            }
            "GOTOF" | "GOTOB" | "GOTO" => Ok(to),
            _ => Err((at + 1, format!("expected GOTOF, GOTOB or GOTO, got `{kw}`"))),
        }
    }

    fn fanuc_block(
        &mut self,
        prog: &Program,
        pc: usize,
        text: &str,
        loops: &mut Vec<(u32, usize)>,
    ) -> Result<Step, Fail> {
        let mut c = Cur::new(text, self.dialect);
        if text.starts_with('O') && text[1..].chars().all(|ch| ch.is_ascii_digit()) {
            return Ok(Step::Next);
        }
        let mut w = Words::default();
        while !c.done() {
            let at = c.i;
            if c.eat("#") {
                let idx = self.var_index(&mut c)?;
                if !c.eat("=") {
                    return c.err("expected `=` after a variable");
                }
                let v = self.expr(&mut c)?;
                self.set_var(idx, v);
                continue;
            }
            if c.eat("WHILE") {
                let v = self.bracket(&mut c)?;
                if !c.eat("DO") {
                    return c.err("expected DOn after WHILE [..]");
                }
                let n = c.number().unwrap_or(0.0) as u32;
                if v != 0.0 {
                    loops.retain(|l| l.1 != pc);
                    loops.push((n, pc));
                    return Ok(Step::Next);
                }
                // Skip to the block after the matching ENDn.
                for (k, b) in prog.blocks.iter().enumerate().skip(pc + 1) {
                    if b.2.replace(' ', "") == format!("END{n}") {
                        loops.retain(|l| l.1 != pc);
                        return Ok(Step::Jump(k + 1));
                    }
                }
                return Err((at + 1, format!("WHILE .. DO{n} without END{n}")));
            }
            if c.eat("END") {
                let n = c.number().unwrap_or(0.0) as u32;
                let Some(&(_, start)) = loops.iter().rev().find(|l| l.0 == n) else {
                    return Err((at + 1, format!("END{n} without DO{n}")));
                };
                return Ok(Step::Jump(start));
            }
            if c.eat("IF") {
                let v = self.bracket(&mut c)?;
                if c.eat("GOTO") {
                    let n = c.number().unwrap_or(0.0) as u32;
                    if v == 0.0 {
                        return Ok(Step::Next);
                    }
                    return prog
                        .numbers
                        .get(&n)
                        .map(|&k| Step::Jump(k))
                        .ok_or((at + 1, format!("no block N{n}")));
                }
                if c.eat("THEN") {
                    if v == 0.0 {
                        return Ok(Step::Next);
                    }
                    continue;
                }
                return c.err("expected GOTO or THEN after IF [..]");
            }
            if c.eat("GOTO") {
                let n = c.number().unwrap_or(0.0) as u32;
                return prog
                    .numbers
                    .get(&n)
                    .map(|&k| Step::Jump(k))
                    .ok_or((at + 1, format!("no block N{n}")));
            }
            if c.eat("G65") {
                return self.macro_a(&mut c, prog);
            }
            let Some(letter) = c.peek().filter(u8::is_ascii_alphabetic) else {
                return Err((at + 1, format!("unexpected `{}`", c.s[c.i] as char)));
            };
            c.i += 1;
            let st = c.i;
            let v = self.fanuc_value(&mut c)?;
            if v.is_nan() {
                // An address whose value is a vacant variable is left out (FANUC).
                continue;
            }
            if text[st..c.i].contains('.') {
                w.points.push((letter as char).to_string());
            }
            match letter {
                b'G' => w.g.push(v.round() as u32),
                b'M' => w.m.push(v.round() as u32),
                b'N' | b'O' => {}
                b'X' | b'Z' | b'U' | b'W' | b'F' | b'K' | b'Q' | b'S' | b'T' | b'R' | b'P'
                | b'L' | b'J' | b'I' | b'H' | b'E' => {
                    w.vals.insert((letter as char).to_string(), (v, at + 1));
                }
                other => {
                    return Err((
                        at + 1,
                        format!("the word `{}` is not supported yet", other as char),
                    ))
                }
            }
        }
        if w.g.contains(&76) {
            return if self.lcnc {
                self.lcnc_g76(&w, prog, pc)
            } else {
                self.g76(&w, prog, pc)
            };
        }
        self.apply(&w, prog, pc)
    }

    /// FANUC/GSK Custom Macro A: `G65 Hnn P#i Q#j R#k` (`controllers.md` 5). P names the
    /// result variable (or the block number of a jump); Q and R are variables or constants.
    fn macro_a(&mut self, c: &mut Cur, prog: &Program) -> Result<Step, Fail> {
        let mut h = None;
        let mut p: Option<(f64, bool)> = None; // (value, written as #n)
        let (mut q, mut r) = (0.0, 0.0);
        let mut repeats = 1.0;
        // Macro call arguments (specification I): letter -> local variable.
        let mut args: Vec<(u32, f64)> = Vec::new();
        while !c.done() {
            let at = c.i;
            let Some(letter) = c.peek().filter(u8::is_ascii_alphabetic) else {
                return Err((at + 1, format!("unexpected `{}` in G65", c.s[c.i] as char)));
            };
            c.i += 1;
            match letter {
                b'H' => {
                    h = Some(
                        c.number()
                            .ok_or((c.i + 1, "expected the H code".to_string()))?
                            as u32,
                    )
                }
                b'P' => {
                    let var = c.eat("#");
                    let v = c
                        .number()
                        .ok_or((c.i + 1, "expected a number".to_string()))?;
                    p = Some((v, var));
                }
                b'Q' => q = z(self.fanuc_value(c)?),
                b'R' => r = z(self.fanuc_value(c)?),
                b'L' => repeats = z(self.fanuc_value(c)?),
                other => {
                    let var = match other {
                        b'A' => 1,
                        b'B' => 2,
                        b'C' => 3,
                        b'I' => 4,
                        b'J' => 5,
                        b'K' => 6,
                        b'D' => 7,
                        b'E' => 8,
                        b'F' => 9,
                        b'M' => 13,
                        b'S' => 19,
                        b'T' => 20,
                        b'U' => 21,
                        b'V' => 22,
                        b'W' => 23,
                        b'X' => 24,
                        b'Y' => 25,
                        b'Z' => 26,
                        _ => {
                            return Err((
                                at + 1,
                                format!("`{}` cannot pass a G65 argument", other as char),
                            ))
                        }
                    };
                    args.push((var, self.fanuc_value(c)?));
                }
            }
        }
        let Some(h) = h else {
            // G65 P<program> L<repeats> <arguments>: a macro call with its own locals. Q and
            // R were read as Macro A operands above; as arguments they are #17 and #18.
            let (pv, _) = p.ok_or((1, "G65 needs P (the macro program) or H".to_string()))?;
            if q != 0.0 {
                args.push((17, q));
            }
            if r != 0.0 {
                args.push((18, r));
            }
            let times = repeats.round().clamp(1.0, 9999.0) as u32;
            return Ok(Step::Call(
                format!("O{}", pv.round() as u64),
                times,
                Some(args),
            ));
        };
        let (pv, pvar) = p.ok_or((1, format!("G65 H{h:02} needs P")))?;
        let jump = |cond: bool| -> Result<Step, Fail> {
            if !cond {
                return Ok(Step::Next);
            }
            let n = pv.round() as u32;
            prog.numbers
                .get(&n)
                .map(|&k| Step::Jump(k))
                .ok_or((1, format!("no block N{n}")))
        };
        let set = |m: &mut Self, v: f64| -> Result<Step, Fail> {
            if !pvar {
                return Err((1, format!("G65 H{h:02}: P must name a variable (#n)")));
            }
            m.set_var(pv.round() as u32, v);
            Ok(Step::Next)
        };
        let nonzero = |v: f64| {
            if v == 0.0 {
                Err((1, "division by zero".to_string()))
            } else {
                Ok(v)
            }
        };
        match h {
            1 => set(self, q),
            2 => set(self, q + r),
            3 => set(self, q - r),
            4 => set(self, q * r),
            5 => set(self, q / nonzero(r)?),
            21 if q >= 0.0 => set(self, q.sqrt()),
            22 => set(self, q.abs()),
            23 => set(self, q % nonzero(r)?),
            27 => set(self, q.hypot(r)),
            31 => set(self, q * r.to_radians().sin()),
            32 => set(self, q * r.to_radians().cos()),
            33 => set(self, q * r.to_radians().tan()),
            34 => set(self, q.atan2(r).to_degrees()),
            80 => jump(true),
            81 => jump(q == r),
            82 => jump(q != r),
            83 => jump(q > r),
            84 => jump(q < r),
            85 => jump(q >= r),
            86 => jump(q <= r),
            99 => Err((
                1,
                format!(
                    "alarm {} raised by the program (G65 H99)",
                    500 + pv.round() as i64
                ),
            )),
            _ => Err((1, format!("G65 H{h:02} is not supported yet"))),
        }
    }

    /// LinuxCNC G76 (`controllers.md` 2.5, from `Interp::convert_threading_cycle`): the
    /// drive line is the current X; pass n is cut `|I| + J n^(1/R)` from it while that is
    /// less than `|I| + K`, then at `|I| + K` once plus H spring passes; each pass is shifted
    /// by `(depth - |I|) tan Q` in z and ends at `Z + K tan Q` less that shift. In G7, I, J
    /// and K are diameters. Reproduced against rs274's output in the tests.
    fn lcnc_g76(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.inch { 25.4 } else { 1.0 };
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let half = if self.diameter_mode { 0.5 } else { 1.0 };
        let pitch = val("P").ok_or((1, "G76 needs P (the pitch)".to_string()))? * scale;
        let end_z = val("Z").ok_or((1, "G76 needs Z".to_string()))? * scale;
        let i = val("I").ok_or((
            1,
            "G76 needs I (crest offset from the drive line)".to_string(),
        ))? * scale
            * half;
        let j = val("J").unwrap_or(0.0) * scale * half;
        let k = val("K").unwrap_or(0.0) * scale * half;
        if i == 0.0 || j <= 0.0 || k <= j || pitch <= 0.0 {
            return Err((1, "G76 needs I != 0, J > 0, K > J and P > 0".into()));
        }
        let taper_len = val("E").unwrap_or(0.0) * scale;
        let tapers = match val("L").unwrap_or(0.0).round() as i64 {
            0 => false,
            3 if taper_len > 0.0 => true,
            3 => return Err((1, "G76 L3 needs a taper length E > 0".into())),
            _ => {
                return Err((
                    1,
                    "G76 entry-only or exit-only tapers (L1, L2) are not supported yet".into(),
                ))
            }
        };
        let mut degression = val("R").unwrap_or(1.0);
        if degression < 1.0 {
            degression = 1.0;
        }
        let (x0, start_z) = (self.x / 2.0, self.z); // drive line, radius
        let mut angle = val("Q").unwrap_or(0.0).to_radians();
        if end_z > start_z {
            angle = -angle;
        }
        let springs = val("H").unwrap_or(0.0).max(0.0) as u32;
        let full = i.abs();
        let end_depth = k.abs() + full;
        let target_z = end_z + k.abs() * angle.tan();
        // External (I < 0): passes below the drive line; internal: above.
        let side = if i < 0.0 { -1.0 } else { 1.0 };
        let mut depths = Vec::new();
        let mut depth = full + j.abs();
        let mut n = 1.0f64;
        while depth < end_depth {
            depths.push(depth);
            if depths.len() > 100_000 {
                return Err((1, "G76 would cut more than 100000 passes".into()));
            }
            n += 1.0;
            depth = full + j.abs() * n.powf(1.0 / degression);
        }
        for _ in 0..=springs {
            depths.push(end_depth);
        }
        let dir = if end_z < start_z { -1.0 } else { 1.0 };
        if tapers && 2.0 * taper_len > (target_z - start_z).abs() {
            return Err((1, "G76 E is greater than half the drive line length".into()));
        }
        for d in depths {
            let zoff = (d - full) * angle.tan();
            let x = 2.0 * (x0 + side * d);
            let (zs, ze) = (start_z - zoff, target_z - zoff);
            if tapers {
                // rs274: from the retract line, a synchronised radial move (|I| long) to the
                // taper start K above the pass, the entry taper over E, the pass, and the
                // exit taper back up by K. Feeds are per path length (P hypot(E,K)/E on the
                // tapers), so the axial lead is P throughout; the radial move uses up
                // |I| / (P hypot(E,K)/E) revolutions before the entry taper starts.
                let kx = 2.0 * (x0 + side * (d - k.abs()));
                let p_taper = pitch * taper_len.hypot(k.abs()) / taper_len;
                let mut revs = full / p_taper;
                let (z1, z2) = (zs + dir * taper_len, ze - dir * taper_len);
                let segments = [(kx, zs, x, z1), (x, z1, x, z2), (x, z2, kx, ze)];
                for (xa, za, xb, zb) in segments {
                    let sync = Sync {
                        lead: pitch,
                        change: 0.0,
                        angle: (revs * 360.0).rem_euclid(360.0),
                    };
                    self.emit(prog, pc, MoveKind::Thread, (xa, za), (xb, zb), Some(sync));
                    revs += (zb - za).abs() / pitch;
                }
                continue;
            }
            let sync = Sync {
                lead: pitch,
                change: 0.0,
                angle: 0.0,
            };
            self.cycle_pass(prog, pc, (2.0 * x0, start_z), (x, zs), (x, ze), sync);
        }
        Ok(Step::Next)
    }

    /// A word in the least input increment (0.001 mm, 0.0001 in), as G76 P/Q are written.
    fn increment_word(&self, w: &Words, k: &str) -> Result<Option<f64>, Fail> {
        let Some(&(v, col)) = w.vals.get(k) else {
            return Ok(None);
        };
        if w.points.iter().any(|p| p == k) {
            return Err((
                col,
                format!("G76 {k} counts in the least input increment and takes no decimal point"),
            ));
        }
        Ok(Some(if self.inch {
            v * 0.0001 * 25.4
        } else {
            v * 0.001
        }))
    }

    /// FANUC G76, two-block form (`domain.md` section 3, `controllers.md` 2.3): block 1
    /// sets `P(mmrraa) Q(dmin) R(d)`; block 2 `X(U) Z(W) R(i) P(k) Q(dd) F(L)` cuts rough
    /// passes at `d_n = max(dd*sqrt(n), d_(n-1) + dmin)` until `k - d`, one at `k - d`, then
    /// `m` at `k`, each on single-flank infeed: shifted against the cutting direction by
    /// `(k - d_n) tan(a/2)` so the trailing flank follows the final groove's wall.
    fn g76(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.inch { 25.4 } else { 1.0 };
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let is_second = ["X", "Z", "U", "W"].iter().any(|k| w.vals.contains_key(*k));
        if !is_second {
            if let Some(p) = val("P") {
                let p = p.round() as u32;
                self.g76.m = (p / 10000).max(1);
                self.g76.r = (p / 100) % 100;
                self.g76.a = (p % 100) as f64;
            }
            if let Some(q) = self.increment_word(w, "Q")? {
                self.g76.dmin = q;
            }
            if let Some(r) = val("R") {
                self.g76.d = r * scale;
            }
            return Ok(Step::Next);
        }
        let (x0, z0) = (self.x, self.z);
        let x_end = match (val("X"), val("U")) {
            (Some(x), _) => x * scale,
            (None, Some(u)) => x0 + u * scale,
            _ => x0,
        };
        let z_end = match (val("Z"), val("W")) {
            (Some(z), _) => z * scale,
            (None, Some(wv)) => z0 + wv * scale,
            _ => z0,
        };
        if val("R").is_some_and(|r| r != 0.0) {
            return Err((
                1,
                "taper G76 (R in the second block) is not supported yet".into(),
            ));
        }
        let k = self
            .increment_word(w, "P")?
            .ok_or((1, "G76 needs P (thread height)".to_string()))?;
        let dd = self
            .increment_word(w, "Q")?
            .ok_or((1, "G76 needs Q (first cut depth)".to_string()))?;
        let lead = val("F").ok_or((1, "G76 needs F (the lead)".to_string()))? * scale;
        if k <= 0.0 || dd <= 0.0 || lead <= 0.0 || z_end == z0 {
            return Err((
                1,
                "G76 needs a positive height, first cut, lead and a Z move".into(),
            ));
        }
        let s = self.g76;
        let stop = (k - s.d).max(0.0);
        let mut depths = Vec::new();
        let mut prev = 0.0;
        for n in 1..=100_000 {
            let dn = (dd * (n as f64).sqrt()).max(prev + s.dmin);
            if dn >= stop {
                break;
            }
            depths.push(dn);
            prev = dn;
        }
        if depths.len() >= 100_000 {
            return Err((1, "G76 would cut more than 100000 rough passes".into()));
        }
        if stop > 0.0 && depths.last().is_none_or(|&l| l < stop) {
            depths.push(stop);
        }
        for _ in 0..s.m {
            depths.push(k);
        }
        // The root diameter is X; passes stand back from it by (k - d_n), on the side
        // of the start point (outside for external threads, inside for internal).
        let side = if x0 >= x_end { 1.0 } else { -1.0 };
        let dir = if z_end < z0 { -1.0 } else { 1.0 };
        let tan = (s.a.to_radians() / 2.0).tan();
        for dn in depths {
            let back = k - dn;
            let x = x_end + side * 2.0 * back;
            let shift = -dir * back * tan;
            let (zs, ze) = (z0 + shift, z_end + shift);
            let sync = Sync {
                lead,
                change: 0.0,
                angle: 0.0,
            };
            self.cycle_pass(prog, pc, (x0, z0), (x, zs), (x, ze), sync);
        }
        Ok(Step::Next)
    }

    fn var_index(&self, c: &mut Cur) -> Result<u32, Fail> {
        let v = if c.peek() == Some(b'[') {
            self.bracket(c)?
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        if !(1.0..=9999.0).contains(&v) {
            return c.err(format!("variable #{v} cannot be set"));
        }
        Ok(v.round() as u32)
    }

    fn bracket(&self, c: &mut Cur) -> Result<f64, Fail> {
        if !c.eat("[") {
            return c.err("expected `[`");
        }
        let v = self.expr(c)?;
        if !c.eat("]") {
            return c.err("expected `]`");
        }
        Ok(z(v))
    }

    /// Modal state and motion of one block's words.
    fn apply(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.inch { 25.4 } else { 1.0 };
        let mut set_position = false;
        for &g in &w.g {
            match g {
                0 | 1 | 32 | 33 | 34 | 35 => self.motion = g,
                // G92 is the threading cycle on FANUC/GSK lathes, an offset on LinuxCNC.
                92 if self.dialect == Dialect::Fanuc && !self.lcnc => self.motion = 92,
                90 => self.incremental = false,
                91 => self.incremental = true,
                20 => self.inch = true,
                21 => self.inch = false,
                70 if self.dialect == Dialect::Siemens802d => self.inch = true,
                71 if self.dialect == Dialect::Siemens802d => self.inch = false,
                7 if self.lcnc => self.diameter_mode = true,
                8 if self.lcnc => self.diameter_mode = false,
                // FANUC/GSK G50 with X/Z sets the coordinates of the current position.
                50 if self.dialect == Dialect::Fanuc && !self.lcnc => set_position = true,
                17 | 18 | 40 | 54..=59 | 64 | 94 | 95 | 96 | 97 | 98 | 99 => {}
                other => return Err((1, format!("G{other} is not supported yet"))),
            }
        }
        let mut end = false;
        for &mc in &w.m {
            match mc {
                3 | 13 => self.spindle = Spindle::Cw,
                4 | 14 => self.spindle = Spindle::Ccw,
                5 | 8 | 9 | 0 | 1 => {}
                2 | 30 => end = true,
                17 if self.dialect == Dialect::Siemens802d => return Ok(Step::Return),
                98 if self.dialect == Dialect::Fanuc => {
                    // `M98 P<count><prog>` (the last four digits name O<prog>) or `P<prog> L<n>`.
                    let p = w
                        .vals
                        .get("P")
                        .map(|v| v.0.round() as u64)
                        .ok_or((1, "M98 needs P".to_string()))?;
                    let (times, prog) = match w.vals.get("L") {
                        Some(l) => (l.0.round().max(1.0) as u32, p),
                        None => (((p / 10_000).max(1)) as u32, p % 10_000),
                    };
                    if times > 9999 {
                        return Err((1, format!("M98 repeat count {times} is over 9999")));
                    }
                    return Ok(Step::Call(format!("O{prog}"), times, None));
                }
                99 if self.dialect == Dialect::Fanuc => {
                    if w.vals.contains_key("P") {
                        return Err((
                            1,
                            "M99 P (return to a sequence number) is not supported yet".into(),
                        ));
                    }
                    return Ok(Step::Return);
                }
                98 | 99 => {
                    return Err((
                        1,
                        format!("M{mc} is not a Siemens word: call subprograms by name"),
                    ))
                }
                other => return Err((1, format!("M{other} is not supported yet"))),
            }
        }
        if let Some(&(t, _)) = w.vals.get("T") {
            let t = t.round() as u32;
            self.tool = Some(if self.dialect == Dialect::Fanuc && t >= 100 {
                t / 100
            } else {
                t
            });
        }
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let scale = if self.inch { 25.4 } else { scale };
        let mut x = self.x;
        let mut z = self.z;
        let mut moved = false;
        let xs = if self.diameter_mode { 1.0 } else { 2.0 };
        if let Some(v) = val("X").map(|v| v * xs) {
            x = if self.incremental {
                self.x + v * scale
            } else {
                v * scale
            };
            moved = true;
        }
        if let Some(v) = val("Z") {
            z = if self.incremental {
                self.z + v * scale
            } else {
                v * scale
            };
            moved = true;
        }
        if self.dialect == Dialect::Fanuc {
            if let Some(v) = val("U") {
                x = self.x + v * scale;
                moved = true;
            }
            if let Some(v) = val("W") {
                z = self.z + v * scale;
                moved = true;
            }
        }
        if set_position {
            self.x = x;
            self.z = z;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if moved && self.dialect == Dialect::Fanuc && self.motion == 92 && !self.lcnc {
            return self.g92(w, prog, pc, x, z, scale);
        }
        if moved {
            let (kind, lead, change, angle) = match (self.dialect, self.motion) {
                (_, 0) => (MoveKind::Rapid, None, None, None),
                (_, 1) => (MoveKind::Feed, None, None, None),
                (Dialect::Fanuc, 33) if self.lcnc => {
                    let k = val("K").ok_or((1, "G33 needs K (the pitch)".to_string()))? * scale;
                    (MoveKind::Thread, Some(k), Some(0.0), Some(0.0))
                }
                (Dialect::Fanuc, 34) if self.gsk => {
                    return self.gsk_g34(w, prog, pc, x, z, scale);
                }
                (Dialect::Fanuc, 32) | (Dialect::Fanuc, 34) => {
                    let f = val("F").ok_or((1, format!("G{} needs F (the lead)", self.motion)))?
                        * scale;
                    let k = if self.motion == 34 {
                        val("K").unwrap_or(0.0) * scale
                    } else {
                        0.0
                    };
                    let q = val("Q").unwrap_or(0.0) / 1000.0;
                    (MoveKind::Thread, Some(f), Some(k), Some(q))
                }
                (Dialect::Siemens802d, 33..=35) => {
                    let k = val("K")
                        .or(val("I"))
                        .ok_or((1, format!("G{} needs K (the lead)", self.motion)))?
                        * scale;
                    let f = if self.motion == 33 {
                        0.0
                    } else {
                        val("F").unwrap_or(0.0).abs() * scale
                    };
                    let f = if self.motion == 35 { -f } else { f };
                    (
                        MoveKind::Thread,
                        Some(k),
                        Some(f),
                        Some(val("SF").unwrap_or(0.0)),
                    )
                }
                (_, g) => {
                    return Err((
                        1,
                        format!("G{g} moves are not supported in this dialect yet"),
                    ))
                }
            };
            let sync = lead.map(|lead| Sync {
                lead,
                change: change.unwrap_or(0.0),
                angle: angle.unwrap_or(0.0),
            });
            self.emit(prog, pc, kind, (self.x, self.z), (x, z), sync);
            self.x = x;
            self.z = z;
        }
        Ok(if end { Step::End } else { Step::Next })
    }
}

impl Machine<'_> {
    /// GSK 980TDC `G34 X(U) Z(W) F(I) J K R` (`domain.md` section 3, seed 000): F start
    /// lead (or I threads per inch), R lead change per revolution. The run-out words J/K
    /// are refused for now: where the tool ends after a run-out (and so what the next
    /// incremental move starts from) is not documented in our sources, and seed 000's
    /// `U-10.2 ... U10` cycle only makes sense for one of the readings.
    fn gsk_g34(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        x: f64,
        z: f64,
        scale: f64,
    ) -> Result<Step, Fail> {
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let lead = match (val("F"), val("I")) {
            (Some(f), _) => f * scale,
            (None, Some(tpi)) if tpi > 0.0 => 25.4 / tpi,
            _ => return Err((1, "G34 needs F (lead) or I (threads per inch)".into())),
        };
        for k in ["J", "K"] {
            if let Some(&(v, col)) = w.vals.get(k) {
                if v != 0.0 {
                    return Err((
                        col,
                        format!("G34 thread run-out ({k}) is not supported yet"),
                    ));
                }
            }
        }
        let change = val("R").unwrap_or(0.0) * scale;
        let sync = Sync {
            lead,
            change,
            angle: 0.0,
        };
        self.emit(
            prog,
            pc,
            MoveKind::Thread,
            (self.x, self.z),
            (x, z),
            Some(sync),
        );
        self.x = x;
        self.z = z;
        Ok(Step::Next)
    }

    /// FANUC G92 (modal): rapid to the X of the block, thread to its Z, rapid back out in
    /// X and back in Z to the start point. Later X-only blocks repeat it at a new depth.
    fn g92(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        x: f64,
        z: f64,
        scale: f64,
    ) -> Result<Step, Fail> {
        let (x0, z0) = (self.x, self.z);
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let z_target = if w.vals.contains_key("Z") || w.vals.contains_key("W") {
            z
        } else {
            self.g92
                .map(|g| g.0)
                .ok_or((1, "G92 needs Z (or W) the first time".to_string()))?
        };
        let lead = match val("F") {
            Some(f) => f * scale,
            None => self
                .g92
                .map(|g| g.1)
                .ok_or((1, "G92 needs F (the lead)".to_string()))?,
        };
        if val("R").is_some_and(|r| r != 0.0) {
            return Err((1, "taper G92 (R) is not supported yet".into()));
        }
        self.g92 = Some((z_target, lead));
        let q = val("Q").unwrap_or(0.0) / 1000.0;
        let sync = Sync {
            lead,
            change: 0.0,
            angle: q,
        };
        self.cycle_pass(prog, pc, (x0, z0), (x, z0), (x, z_target), sync);
        Ok(Step::Next)
    }

    /// Record a move of the block at `pc` from `a` to `b` (diameter, z); `sync` makes it a
    /// thread move.
    fn emit(
        &mut self,
        prog: &Program,
        pc: usize,
        kind: MoveKind,
        a: (f64, f64),
        b: (f64, f64),
        sync: Option<Sync>,
    ) {
        self.moves.push(Move {
            file: prog.name.clone(),
            line: prog.blocks[pc].0,
            kind,
            x_start: a.0,
            z_start: a.1,
            x_dia: b.0,
            z: b.1,
            lead: sync.map(|s| s.lead),
            lead_change: sync.map(|s| s.change),
            sync_angle_deg: sync.map(|s| s.angle),
            tool: self.tool,
            spindle: self.spindle,
        });
    }

    /// One pass of a threading cycle: rapid from `home` to the start (Z first, then X),
    /// thread to `end`, rapid out to home's X and back to home's Z. Zero-length rapids are
    /// left out.
    fn cycle_pass(
        &mut self,
        prog: &Program,
        pc: usize,
        home: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        sync: Sync,
    ) {
        let path = [home, (home.0, start.1), start];
        for w in path.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
        }
        self.emit(prog, pc, MoveKind::Thread, start, end, Some(sync));
        let back = [end, (home.0, end.1), home];
        for w in back.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn threads(moves: &[Move]) -> Vec<&Move> {
        moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect()
    }

    fn run(text: &str, dialect: Dialect) -> Result<Vec<Move>, NcError> {
        let src = Source {
            name: "T.NC".into(),
            text: text.into(),
        };
        interpret(&src, dialect, &|_| None, Limits::default())
    }

    #[test]
    fn siemens_r_parameters_labels_and_g34() {
        let moves = run(
            "R1=2 R2=3\nIF R1<R2 GOTOF AA\nR3=99\nAA: R4=ABS(R1-R2)*2+TRUNC(2.7) ; comment\nG0 X=R4*10 Z=5\nG35 Z=-20 K=R2 F=0.1\nM30\n",
            Dialect::Siemens802d,
        )
        .unwrap();
        assert_eq!(moves.len(), 2);
        assert_eq!(moves[0].x_dia, 40.0);
        let t = &moves[1];
        assert_eq!(
            (t.kind, t.lead, t.lead_change),
            (MoveKind::Thread, Some(3.0), Some(-0.1))
        );
        assert_eq!((t.x_start, t.z_start, t.z), (40.0, 5.0, -20.0));
    }

    #[test]
    fn fanuc_macro_b_loop_and_g32() {
        let moves = run(
            "#1=0\nWHILE[#1LT3]DO1\n#1=#1+1\nG0X[20-#1]Z2.\nG32Z-10.F1.5\nEND1\nM30\n",
            Dialect::Fanuc,
        )
        .unwrap();
        let threads: Vec<&Move> = threads(&moves);
        assert_eq!(threads.len(), 3);
        assert_eq!(threads[2].x_dia, 17.0);
        assert_eq!(threads[0].lead, Some(1.5));
    }

    /// `controllers.md` 2.3's worked schedule: k = 1.30, dd = 0.45, dmin = 0.10, d = 0.05
    /// gives 0.450, 0.636, 0.779, 0.900, 1.006, 1.106, 1.206, 1.250, then m x 1.300, each
    /// pass shifted by (k - d_n) tan30 against the feed (flank infeed).
    #[test]
    fn fanuc_g76_depth_schedule_and_flank_infeed() {
        let moves = run(
            "G0 X30 Z5\nG76 P020060 Q100 R0.05\nG76 X24 Z-20 P1300 Q450 F2\nM30\n",
            Dialect::Fanuc,
        )
        .unwrap();
        let t: Vec<&Move> = threads(&moves);
        let want = [
            0.45,
            0.45 * 2f64.sqrt(),
            0.45 * 3f64.sqrt(),
            0.9,
            0.45 * 5f64.sqrt(),
            0.0,
            0.0,
            1.25,
            1.3,
            1.3,
        ];
        assert_eq!(t.len(), want.len());
        let mut prev = 0.0;
        for (i, (m, &w)) in t.iter().zip(&want).enumerate() {
            let depth = 1.3 - (m.x_dia - 24.0) / 2.0;
            let w = if w == 0.0 { prev + 0.1 } else { w };
            assert!((depth - w).abs() < 1e-9, "pass {i}: depth {depth} vs {w}");
            let shift = (1.3 - depth) * (30f64.to_radians()).tan();
            assert!(
                (m.z_start - (5.0 + shift)).abs() < 1e-9 && (m.z - (-20.0 + shift)).abs() < 1e-9
            );
            assert_eq!(m.lead, Some(2.0));
            prev = depth;
        }
        let e = run("G76 P010060 Q0.1 R0\n", Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("no decimal point"), "{e}");
    }

    #[test]
    fn fanuc_g92_is_modal() {
        let moves = run(
            "G0 X30 Z3\nG92 X19.2 Z-20 F1.5\nX18.6\nX18.38\nG0 X40\nM30\n",
            Dialect::Fanuc,
        )
        .unwrap();
        let t: Vec<&Move> = threads(&moves);
        assert_eq!(t.len(), 3);
        assert_eq!(
            (t[2].x_dia, t[2].z_start, t[2].z, t[2].lead),
            (18.38, 3.0, -20.0, Some(1.5))
        );
        // Each cycle returns to the start point.
        assert_eq!((moves[4].x_dia, moves[4].z), (30.0, 3.0));
    }

    /// Seed 000's first program (GSK 980TDC, OCR-corrected: `00001` -> `O0001`,
    /// `M98 P25 0002` -> `M98 P250002`, `GOO` -> `G00`), its run-out words dropped: O0002 runs
    /// 25 times, each 0.2 mm deeper (U-10.2, then U10 out).
    #[test]
    fn m98_repeats_an_o_program_of_the_same_file() {
        let text = "O0001\nN10 G00 X120 Z80\nN20 M03 M08 G97 S800\nN30 T0101\nN40 G00 X60 Z8\n\
                    N50 M98 P250002\nN60 G00 X120\nN70 Z80\nN80 T0100\nN90 M30\n\
                    O0002\nN10 G00 U-10.2\nN20 G34 Z-70 F4 R1\nN30 G0 U10\nN40 G00 Z8\nN50 M99\n";
        let moves = run(text, Dialect::Gsk980).unwrap();
        let t: Vec<&Move> = threads(&moves);
        assert_eq!(t.len(), 25);
        for (k, m) in t.iter().enumerate() {
            assert!(
                (m.x_dia - (49.8 - 0.2 * k as f64)).abs() < 1e-9,
                "{k}: {}",
                m.x_dia
            );
            assert_eq!(
                (m.z_start, m.z, m.lead, m.lead_change),
                (8.0, -70.0, Some(4.0), Some(1.0))
            );
            assert_eq!(m.tool, Some(1));
        }
        let e = run("G0 X50 Z5\nG34 Z-70 F4 J1 K2 R1\n", Dialect::Gsk980).unwrap_err();
        assert!(e.message.contains("run-out"), "{e}");
        let e = run("M98 P0003\nM30\n", Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("subprogram `O3` not found"), "{e}");
    }

    /// Seed 000's Macro A loop shape: `G65 H01/H02/H03/H81/H86/H80` on #100.. variables.
    #[test]
    fn percent_line_before_the_o_number_keeps_one_program() {
        let moves = run(
            "%\nO0004 (MAIN)\nG0 X20 Z2\nG32 Z-10 F1\nM30\n%\n",
            Dialect::Fanuc,
        )
        .unwrap();
        assert_eq!(
            moves.iter().filter(|m| m.kind == MoveKind::Thread).count(),
            1
        );
    }

    #[test]
    fn g50_sets_the_position_and_g70_is_not_inch_on_fanuc() {
        let moves = run("G50 X100 Z50\nG0 X60 Z8\nM30\n", Dialect::Gsk980).unwrap();
        assert_eq!(moves.len(), 1);
        assert_eq!((moves[0].x_start, moves[0].z_start), (100.0, 50.0));
        let e = run("G70 P10 Q20\n", Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("G70 is not supported"), "{e}");
        let e = run("G92 X10\n", Dialect::Linuxcnc).unwrap_err();
        assert!(e.message.contains("G92 is not supported"), "{e}");
    }

    /// Repeats do not count as nesting, and WHILE loops belong to their own program.
    #[test]
    fn repeated_calls_nest_and_keep_their_loops() {
        let text = "O0001\n#1=0\nWHILE[#1LT2]DO1\n#1=#1+1\nM98 P30002\nEND1\nM30\n\
                    O0002\nM98 P20003\nM99\n\
                    O0003\n#2=0\nWHILE[#2LT1]DO1\n#2=#2+1\nG0 X1\nG32 Z-1 F1\nG0 Z0\nEND1\nM99\n";
        let moves = run(text, Dialect::Fanuc).unwrap();
        // 2 outer iterations x 3 calls of O0002 x 2 calls of O0003 x 1 inner iteration.
        assert_eq!(
            moves.iter().filter(|m| m.kind == MoveKind::Thread).count(),
            12
        );
        let deep = "O0001\nM98 P2\nM30\nO0002\nM98 P3\nM99\nO0003\nM98 P2\nM99\n";
        let e = run(deep, Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("nesting deeper than 8"), "{e}");
        assert!(e.stack.len() == 8, "{:?}", e.stack);
    }

    /// G65 P calls: arguments land in #1.. of a new level, the caller's locals come back,
    /// and a vacant variable is 0 in arithmetic but not EQ 0; an address with a vacant
    /// variable is left out.
    #[test]
    fn g65_macro_call_locals_and_null() {
        let text = "O0001\n#1=7\nG0 X20 Z2\nG65 P9010 A1.5 B3 Z-12\nG65 P9010 A2 Z-6\n\
                    G0 X#1\nM30\n\
                    O9010\nIF[#2EQ#0]THEN#2=4\nIF[#3EQ0]GOTO9\nG32 X[20-#2] Z#26 F#1 Q#33\nN9 M99\n";
        let moves = run(text, Dialect::Fanuc).unwrap();
        let t: Vec<&Move> = threads(&moves);
        assert_eq!(t.len(), 2);
        assert_eq!((t[0].x_dia, t[0].z, t[0].lead), (17.0, -12.0, Some(1.5)));
        // B absent: #2 vacant, so EQ #0 holds and #2 becomes 4; #3 vacant is not EQ 0, so
        // no jump to N9.
        assert_eq!((t[1].x_dia, t[1].z, t[1].lead), (16.0, -6.0, Some(2.0)));
        // Q#33 (vacant) was left out: sync angle 0.
        assert_eq!(t[1].sync_angle_deg, Some(0.0));
        // The caller's #1 = 7 is back after the calls.
        assert_eq!(moves.last().unwrap().x_dia, 7.0);
        let null = "#1=#0\n#2=#1+1\nIF[#1EQ0]GOTO5\nG0 X#2\nN5 M30\n";
        let moves = run(null, Dialect::Fanuc).unwrap();
        assert_eq!(moves.len(), 1, "vacant is not EQ 0, and #1 + 1 = 1");
        assert_eq!(moves[0].x_dia, 1.0);
    }

    #[test]
    fn macro_a_arithmetic_and_jumps() {
        let text = "G0 X60 Z4\nG65 H01 P#102 Q0.5\nG65 H01 P#103 Q0\n\
                    N10 G65 H02 P#104 Q#103 R1\nG65 H01 P#103 Q#104\nG65 H81 P30 Q#104 R6\n\
                    G65 H01 P#100 Q#102\nG00 U-#100\nG32 W-20 F3\nG00 X60\nZ4\n\
                    G65 H03 P#101 Q#100 R0.2\nG65 H01 P#102 Q#101\nG65 H86 P20 Q#102 R0.2\n\
                    G65 H80 P10\nN20 G65 H01 P#102 Q0.2\nG65 H80 P10\nN30 M30\n";
        let moves = run(text, Dialect::Gsk980).unwrap();
        let x: Vec<f64> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .map(|m| m.x_dia)
            .collect();
        // Infeeds 0.5, 0.3, then the 0.2 floor: X = 60 - infeed (U is a diameter change).
        assert_eq!(x.len(), 5);
        for (got, want) in x.iter().zip([59.5, 59.7, 59.8, 59.8, 59.8]) {
            assert!((got - want).abs() < 1e-9, "{x:?}");
        }
        let e = run("G65 H05 P#1 Q1 R0\n", Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("division by zero"), "{e}");
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = run("R1=1\nR2=R1/0\n", Dialect::Siemens802d).unwrap_err();
        assert_eq!((e.line, e.message.as_str()), (2, "division by zero"));
        let e = run("GOTOF NOWHERE\n", Dialect::Siemens802d).unwrap_err();
        assert!(e.message.contains("label `NOWHERE` not found"), "{e}");
        let e = run("AA: GOTOB AA\n", Dialect::Siemens802d).unwrap_err();
        assert!(e.message.contains("blocks executed"), "{e}");
        let e = run("END1\n", Dialect::Fanuc).unwrap_err();
        assert!(e.message.contains("END1 without DO1"), "{e}");
    }
}
