//! Okuma OSP-P lathe programs (`[program] dialect = "okuma"`, `.MIN` main programs and
//! `.SSB` subprograms): program structure (`$NAME.MIN%` header line, `O` names, `N`
//! sequence names, `( )` comments, `/` block skip), G00/G01/G02/G03 with diameter X, the
//! thread cutting cycles G31/G33 and G34 and the compound thread cutting cycle G71
//! (`okuma_cycles`), subprograms (`CALL O.. Q.. NAME=..`, `RTS`), common variables `VC<n>`
//! and local variables with expressions (`okuma_expr`), `IF [..] N..` and `GOTO N..`.
//!
//! Sources (OSP-P200L programming manual 5238-E; see `docs/coverage/okuma.md` for every code
//! with its status and page): section 2 (program format, sequence names), section 7 (fixed
//! cycles), the user-task chapter (variables, IF/GOTO, CALL/RTS). A G code the manual lists
//! but vpcut does not simulate is an error naming it; an unknown G code is an error; an
//! unknown M code is a warning (an error with `--strict`): M codes are machine functions the
//! control passes on.
//!
//! Numbers are millimetres as written (OSP reads `X100` as 100 mm); X is a diameter.

use super::okuma_cycles::{self as cyc, CycleMove, Infeed, Pattern, Sync3, G71};
use super::okuma_expr::{Parser, Var, Vars};
use super::okuma_parse::{diag, load, Block, Item, Prog, Val};
use super::{
    ArcGeometry, Diagnostic, Feed, Move, MoveKind, NcError, Options, Severity, Source,
    SpindleSpeed, Toolpath,
};
use crate::model::helix::Spindle;
use std::collections::HashMap;
use std::rc::Rc;

type Fail = super::expr::Fail;

/// What vpcut does with a G code of the OSP-P lathe manual.
enum GCode {
    /// Simulated.
    Run,
    /// Listed by the manual but refused (the reason).
    Refused(&'static str),
    /// Skipped with a warning (an error with `--strict`): its block makes no move.
    Skipped(&'static str),
}

/// The driven-tool functions of a lathe with the M option (milling, drilling and tapping
/// on the face or side with the C axis: G100-G199, their fixed cycles G180-G189): none moves
/// the turning or threading tool through the part, and their X/Z name a hole or a path of
/// the driven tool, so their blocks make no move here (a warning names them).
const DRIVEN_TOOL: &str = "a function of the driven tool and the C axis (M option, G100-G199): skipped, its block makes no turning move";

/// The G codes (5238-E, "G code table"); `None` for a code the manual does not list.
fn g_code(g: u32) -> Option<GCode> {
    use GCode::*;
    Some(match g {
        0..=4 | 20 | 21 | 31 | 33 | 34 | 40..=42 | 50 | 71 | 90 | 91 | 94..=97 | 13 | 14 => Run,
        32 => Refused("G32 (end face thread cutting cycle): face threads are not simulated"),
        35 => Refused("G35 (variable lead, transverse) is not simulated"),
        72 => Refused("G72 (compound thread cutting cycle on an end face): face threads are not simulated"),
        73..=79 => Refused("the fixed cycles G73-G79 (grooving, drilling, tapping on the face) are not simulated yet"),
        80..=88 => Refused("the LAP cycles (G80-G88: contour definition G81/G82/G83, roughing G85/G86, finishing G87) are not simulated yet"),
        100..=199 => Skipped(DRIVEN_TOOL),
        _ => return None,
    })
}

/// The M codes vpcut knows: run (machine functions with no effect on the path, or modes the
/// thread cycles read).
fn m_known(m: u32) -> bool {
    // The M option's driven-tool functions move nothing of the turning tool: M12/M13/M14
    // the M-tool spindle (stop, forward, reverse), M109/M110 the C-axis connection,
    // M146/M147 its clamp (5238-E, M code table of the M option).
    matches!(
        m,
        0..=5 | 8 | 9 | 12..=14 | 22 | 23 | 30 | 32..=34 | 40..=44 | 73..=75 | 109 | 110 | 146 | 147
    )
}

/// The static check: every block's G and M codes (all programs of the file).
fn check(progs: &[Prog], strict: bool, out: &mut Vec<Diagnostic>) {
    for p in progs {
        for b in &p.blocks {
            for it in &b.items {
                let Item::Word(letter @ ('G' | 'M'), Val::Num(v), col) = it else {
                    continue;
                };
                let code = *v as u32;
                let at = |sev, msg: String, hint: Option<String>| {
                    diag(sev, &p.file, b.line, col + 1, msg, &b.orig, hint)
                };
                if v.fract() != 0.0 || *v < 0.0 {
                    out.push(at(
                        Severity::Error,
                        format!("{letter}{v}: expected a whole code number"),
                        None,
                    ));
                    continue;
                }
                if *letter == 'G' {
                    match g_code(code) {
                        Some(GCode::Run) => {}
                        Some(GCode::Skipped(why)) => out.push(at(
                            if strict {
                                Severity::Error
                            } else {
                                Severity::Warning
                            },
                            format!("G{code}: {why}"),
                            Some(
                                "docs/coverage/okuma.md lists what the okuma dialect simulates"
                                    .into(),
                            ),
                        )),
                        Some(GCode::Refused(why)) => out.push(at(
                            Severity::Error,
                            why.to_string(),
                            Some(
                                "docs/coverage/okuma.md lists what the okuma dialect simulates"
                                    .into(),
                            ),
                        )),
                        None => out.push(at(
                            Severity::Error,
                            format!("G{code:02} is not a G code of the OSP-P lathe"),
                            Some("docs/coverage/okuma.md lists the OSP-P codes".into()),
                        )),
                    }
                } else if !m_known(code) {
                    out.push(at(
                        if strict {
                            Severity::Error
                        } else {
                            Severity::Warning
                        },
                        format!("M{code:02} is not an M code vpcut knows"),
                        Some("skipped: vpcut does not simulate it (an error with --strict)".into()),
                    ));
                }
            }
        }
    }
}

/// The modal state of a run.
struct State {
    x: f64,
    z: f64,
    motion: u32,
    incremental: bool,
    inch: bool,
    per_rev: bool,
    feed: Option<f64>,
    speed: Option<f64>,
    css: bool,
    speed_max: Option<f64>,
    spindle: Spindle,
    tool: Option<u32>,
    /// The T code as written (`T030303`), `Move::tool_word`.
    tool_word: Option<std::sync::Arc<str>>,
    infeed: Infeed,
    pattern: Pattern,
    chamfer: bool,
    /// The start point of the active fixed thread cycle (G31/G33/G34), and its last words.
    cycle: Option<ThreadModal>,
    /// Tool nose radius compensation: G41/G42 (`None`: G40), and the nose radius
    /// compensation number (the T code's third pair).
    nose: Option<super::CompSide>,
    nose_no: Option<u32>,
    /// A driven-tool fixed cycle (G181-G189) is active until G180: its blocks (a hole's
    /// X, Z, C) make no turning move.
    driven: bool,
}

#[derive(Clone, Copy)]
struct ThreadModal {
    start: (f64, f64),
    x: f64,
    z: f64,
    lead: f64,
    change: f64,
    i: f64,
    k: f64,
    c: f64,
}

/// A subprogram call in progress.
struct Frame {
    prog: Rc<Prog>,
    ret: usize,
    repeats_left: u32,
    locals: HashMap<String, f64>,
}

struct Run<'a> {
    progs: HashMap<String, Rc<Prog>>,
    loader: &'a dyn Fn(&str) -> Option<Source>,
    opts: &'a Options,
    st: State,
    common: HashMap<u32, f64>,
    moves: Vec<Move>,
    warnings: Vec<Diagnostic>,
    /// A thread move was made in inch units (`Toolpath::inch`).
    inch_threads: bool,
}

/// Interpret an Okuma OSP-P program: the static check of every block of every program the
/// file holds (all problems at once), then the run.
pub(super) fn interpret(
    main: &Source,
    loader: &dyn Fn(&str) -> Option<Source>,
    opts: &Options,
) -> Result<Toolpath, NcError> {
    let mut diags = Vec::new();
    let progs = load(main, &mut diags);
    check(&progs, opts.strict, &mut diags);
    diags.sort_by(|a, b| (&a.file, a.line, a.col).cmp(&(&b.file, b.line, b.col)));
    if diags.iter().any(|d| d.severity == Severity::Error) {
        return Err(NcError::from_diagnostics(diags));
    }
    let first = progs[0].name.clone();
    let reference = opts.settings.reference_point.unwrap_or((0.0, 0.0));
    let mut run = Run {
        progs: progs
            .into_iter()
            .map(|p| (p.name.clone(), Rc::new(p)))
            .collect(),
        loader,
        opts,
        st: State {
            x: reference.0,
            z: reference.1,
            motion: 0,
            incremental: false,
            inch: opts.settings.power_on.inch,
            per_rev: !opts.settings.power_on.per_minute,
            feed: None,
            speed: None,
            css: false,
            speed_max: None,
            spindle: Spindle::Cw,
            tool: None,
            tool_word: None,
            infeed: Infeed::Single,
            pattern: Pattern::One,
            chamfer: false,
            cycle: None,
            nose: None,
            nose_no: None,
            driven: false,
        },
        common: HashMap::new(),
        moves: Vec::new(),
        warnings: diags,
        inch_threads: false,
    };
    let prog = run.progs[&first].clone();
    run.run(prog)?;
    // Tool nose radius compensation, as FANUC's (the OSP-P200L manual, "Tool nose radius
    // compensation": the intersections of the offset paths).
    let moves = super::nose::compensate(&run.moves).map_err(|(k, message)| {
        let mv = &run.moves[k];
        let snippet = run
            .progs
            .values()
            .filter(|p| p.file == mv.file)
            .flat_map(|p| p.blocks.iter())
            .find(|b| b.line == mv.line)
            .map_or_else(String::new, |b| b.orig.clone());
        NcError {
            file: mv.file.clone(),
            line: mv.line,
            col: 0,
            message,
            snippet,
            stack: Vec::new(),
            hint: None,
            others: run.warnings.clone(),
        }
    })?;
    Ok(Toolpath {
        moves,
        mill: Vec::new(),
        warnings: run.warnings,
        dwells: Vec::new(),
        inch: run.inch_threads,
    })
}

/// What a block asks of the run loop.
enum Step {
    Next,
    Jump(usize),
    Call(String, u32, HashMap<String, f64>),
    Return,
    End,
}

impl Run<'_> {
    /// A program by name: known, or loaded from `NAME.SSB` beside the main file (also
    /// without the `O`, and lower case).
    fn find(&mut self, name: &str) -> Option<Rc<Prog>> {
        if let Some(p) = self.progs.get(name) {
            return Some(p.clone());
        }
        let bare = name.strip_prefix('O').unwrap_or(name);
        let candidates = [
            format!("{name}.SSB"),
            format!("{bare}.SSB"),
            format!("{}.ssb", name.to_ascii_lowercase()),
            format!("{}.ssb", bare.to_ascii_lowercase()),
            format!("{name}.MIN"),
        ];
        let src = candidates.iter().find_map(|c| (self.loader)(c))?;
        let mut errs = Vec::new();
        let loaded = load(&src, &mut errs);
        check(&loaded, self.opts.strict, &mut errs);
        self.warnings.extend(
            errs.iter()
                .filter(|d| d.severity == Severity::Warning)
                .cloned(),
        );
        if let Some(e) = errs.into_iter().find(|d| d.severity == Severity::Error) {
            // Reported when the call is made (`run`): the first error of the file.
            self.warnings.push(e);
            return None;
        }
        let mut found = None;
        for (k, p) in loaded.into_iter().enumerate() {
            let p = Rc::new(p);
            if k == 0 {
                // The file's first program answers to the called name too.
                self.progs.insert(name.to_string(), p.clone());
                found = Some(p.clone());
            }
            self.progs.entry(p.name.clone()).or_insert(p);
        }
        self.progs.get(name).cloned().or(found)
    }

    fn run(&mut self, main: Rc<Prog>) -> Result<(), NcError> {
        let mut stack: Vec<Frame> = Vec::new();
        let mut cur = main;
        let mut locals: HashMap<String, f64> = HashMap::new();
        let mut pc = 0usize;
        let mut executed: u64 = 0;
        let limits = self.opts.limits;
        loop {
            if pc >= cur.blocks.len() {
                // The end of a subprogram without RTS returns; of the main program ends.
                match stack.pop() {
                    Some(f) => {
                        cur = f.prog;
                        pc = f.ret;
                        locals = f.locals;
                        continue;
                    }
                    None => break,
                }
            }
            let b = cur.blocks[pc].clone();
            executed += 1;
            let fail = |stack: &[Frame], col: usize, message: String| NcError {
                file: cur.file.clone(),
                line: b.line,
                col,
                message,
                snippet: b.orig.clone(),
                stack: stack
                    .iter()
                    .rev()
                    .map(|f| {
                        format!(
                            "{}:{}",
                            f.prog.file,
                            f.prog.blocks.get(f.ret - 1).map_or(0, |b| b.line)
                        )
                    })
                    .collect(),
                hint: None,
                others: Vec::new(),
            };
            if executed > limits.max_blocks {
                return Err(fail(
                    &stack,
                    0,
                    format!(
                        "more than {} blocks executed: a loop that never ends?",
                        limits.max_blocks
                    ),
                ));
            }
            if b.skip && self.opts.settings.block_skip {
                pc += 1;
                continue;
            }
            let before = self.moves.len();
            let step = self
                .block(&cur, &b, &mut locals)
                .map_err(|(col, m)| fail(&stack, col + 1, m))?;
            if self.moves.len() > limits.max_moves {
                return Err(fail(
                    &stack,
                    0,
                    format!("more than {} moves (the limit on moves a program may make): a loop that never ends?", limits.max_moves),
                ));
            }
            for mv in &self.moves[before..] {
                if let Some(msg) = super::lead_problem(mv) {
                    return Err(fail(&stack, 0, msg));
                }
            }
            match step {
                Step::Next => pc += 1,
                Step::Jump(k) => pc = k,
                Step::End => break,
                Step::Return => match stack.last_mut() {
                    Some(top) if top.repeats_left > 1 => {
                        top.repeats_left -= 1;
                        pc = 0;
                    }
                    Some(_) => {
                        let f = stack.pop().expect("checked");
                        cur = f.prog;
                        pc = f.ret;
                        locals = f.locals;
                    }
                    None => {
                        return Err(fail(&stack, 0, "RTS in the main program: RTS ends a subprogram (end the main program with M02 or M30)".into()))
                    }
                },
                Step::Call(name, times, args) => {
                    if stack.len() + 1 > limits.max_depth {
                        return Err(fail(&stack, 0, format!("subprogram nesting deeper than {}", limits.max_depth)));
                    }
                    let Some(p) = self.find(&name) else {
                        let col = b.orig.to_ascii_uppercase().find(&name).map_or(1, |k| k + 1);
                        return Err(fail(
                            &stack,
                            col,
                            format!("subprogram `{name}` not found (in this file or as {name}.SSB beside it)"),
                        ));
                    };
                    stack.push(Frame {
                        prog: cur.clone(),
                        ret: pc + 1,
                        repeats_left: times,
                        locals: std::mem::replace(&mut locals, args),
                    });
                    cur = p;
                    pc = 0;
                }
            }
        }
        Ok(())
    }

    fn eval(&self, locals: &HashMap<String, f64>, text: &str, col: usize) -> Result<f64, Fail> {
        let vars = Vars {
            common: &self.common,
            local: locals,
        };
        Parser::new(text, col, &vars).whole()
    }

    fn value(&self, locals: &HashMap<String, f64>, v: &Val) -> Result<f64, Fail> {
        match v {
            Val::Num(x) => Ok(*x),
            Val::Expr(t, col) => self.eval(locals, t, *col),
        }
    }

    fn set(&mut self, locals: &mut HashMap<String, f64>, var: &Var, v: f64) {
        match var {
            Var::Common(n) => {
                self.common.insert(*n, v);
            }
            Var::Local(l) => {
                locals.insert(l.clone(), v);
            }
        }
    }

    /// One block: statements first (assignments, IF, GOTO, CALL, RTS), then the words.
    fn block(
        &mut self,
        prog: &Prog,
        b: &Block,
        locals: &mut HashMap<String, f64>,
    ) -> Result<Step, Fail> {
        let mut words: Vec<(char, f64, usize)> = Vec::new();
        let jump = |l: &str, col: usize| {
            prog.labels
                .get(l)
                .copied()
                .ok_or((col, format!("no block {l} in program {}", prog.name)))
        };
        let col_of = |needle: &str| b.orig.to_ascii_uppercase().find(needle).unwrap_or(0);
        for it in &b.items {
            match it {
                Item::Assign(var, e, col) => {
                    let v = self.eval(locals, e, *col)?;
                    self.set(locals, var, v);
                }
                Item::If(cond, col, l) => {
                    let inner = &cond[1..cond.len() - 1];
                    if self.eval(locals, inner, col + 1)? != 0.0 {
                        return jump(l, col_of(l)).map(Step::Jump);
                    }
                }
                Item::Goto(l) => return jump(l, col_of(l)).map(Step::Jump),
                Item::Rts => return Ok(Step::Return),
                Item::Call(name, q, args) => {
                    let times = match q {
                        Some(v) => {
                            let n = self.value(locals, v)?;
                            if !(n >= 1.0 && n.fract() == 0.0 && n < 1e6) {
                                return Err((
                                    col_of("Q"),
                                    format!(
                                        "CALL Q{n}: expected a whole number of repeats, 1 or more"
                                    ),
                                ));
                            }
                            n as u32
                        }
                        None => 1,
                    };
                    let mut callee = HashMap::new();
                    for (var, e, col) in args {
                        let v = self.eval(locals, e, *col)?;
                        match var {
                            Var::Local(l) => {
                                callee.insert(l.clone(), v);
                            }
                            Var::Common(n) => {
                                self.common.insert(*n, v);
                            }
                        }
                    }
                    self.words(prog, b, &words)?;
                    return Ok(Step::Call(name.clone(), times, callee));
                }
                Item::Word(c, v, col) => {
                    let x = self.value(locals, v)?;
                    words.push((*c, x, *col));
                }
            }
        }
        self.words(prog, b, &words)
    }

    /// The words of a block: modes, then the motion.
    fn words(&mut self, prog: &Prog, b: &Block, w: &[(char, f64, usize)]) -> Result<Step, Fail> {
        let get = |c: char| w.iter().rev().find(|t| t.0 == c).map(|t| (t.1, t.2));
        let mut end = false;
        let mut g71 = false;
        let mut thread_g = None;
        for &(c, v, col) in w {
            match c {
                'G' => {
                    let g = v as u32;
                    match g {
                        0..=3 => {
                            self.st.motion = g;
                            self.st.cycle = None;
                        }
                        31 | 33 | 34 => {
                            thread_g = Some(g);
                        }
                        4 => {}
                        40 => self.st.nose = None,
                        41 => self.st.nose = Some(super::CompSide::Left),
                        42 => self.st.nose = Some(super::CompSide::Right),
                        20 => self.st.inch = true,
                        21 => self.st.inch = false,
                        71 => g71 = true,
                        90 => self.st.incremental = false,
                        91 => self.st.incremental = true,
                        94 => self.st.per_rev = false,
                        95 => self.st.per_rev = true,
                        96 => self.st.css = true,
                        97 => self.st.css = false,
                        50 => {
                            if get('X').is_some() || get('Z').is_some() {
                                return Err((col, "G50 with X/Z (zero shift) is not simulated: set the work zero in the job".into()));
                            }
                            if let Some((s, _)) = get('S') {
                                self.st.speed_max = Some(s);
                            }
                        }
                        _ => {}
                    }
                }
                'M' => match v as u32 {
                    2 | 30 => end = true,
                    3 => self.st.spindle = Spindle::Cw,
                    4 => self.st.spindle = Spindle::Ccw,
                    22 => self.st.chamfer = false,
                    23 => self.st.chamfer = true,
                    32 => self.st.infeed = Infeed::Single,
                    33 => self.st.infeed = Infeed::Zigzag,
                    34 => self.st.infeed = Infeed::Reverse,
                    73 => self.st.pattern = Pattern::One,
                    74 => self.st.pattern = Pattern::Two,
                    75 => self.st.pattern = Pattern::Three,
                    _ => {}
                },
                'S' if !w.iter().any(|t| t.0 == 'G' && t.1 == 50.0) => self.st.speed = Some(v),
                'F' => self.st.feed = Some(v),
                'T' => self.tool(v, col, &b.orig)?,
                _ => {}
            }
        }
        // Driven-tool functions (G100-G199, warned by the check) and the blocks of their
        // modal fixed cycles make no turning move.
        if let Some(g) = w
            .iter()
            .filter(|t| t.0 == 'G')
            .map(|t| t.1 as u32)
            .find(|g| (100..=199).contains(g))
        {
            self.st.driven = (181..=189).contains(&g);
            return Ok(if end { Step::End } else { Step::Next });
        }
        if self.st.driven && !w.iter().any(|t| t.0 == 'G') {
            return Ok(if end { Step::End } else { Step::Next });
        }
        self.st.driven = false;
        let cycle_block = g71 || thread_g.is_some() || self.st.cycle.is_some();
        for &(c, _, col) in w {
            let known = match c {
                'G' | 'M' | 'S' | 'F' | 'T' | 'X' | 'Z' | 'N' => true,
                'I' | 'K' | 'L' => true,
                'A' | 'C' | 'E' | 'J' => cycle_block,
                'B' | 'D' | 'H' | 'Q' | 'U' => g71,
                _ => false,
            };
            if known {
                continue;
            }
            if c == 'U' || c == 'W' {
                return Err((col, format!("{c}: incremental moves are written with G91 on the OSP-P lathe (U and W are cycle words); vpcut does not read {c} here")));
            }
            let message = format!("the word `{c}` is not read in this block");
            if self.opts.strict {
                return Err((col, message));
            }
            let d = diag(
                Severity::Warning,
                &prog.file,
                b.line,
                col + 1,
                message,
                &b.orig,
                Some("skipped: vpcut does not simulate it (an error with --strict)".into()),
            );
            if !self.warnings.iter().any(|x| {
                (&x.file, x.line, x.col, &x.message) == (&d.file, d.line, d.col, &d.message)
            }) {
                self.warnings.push(d);
            }
        }
        if g71 {
            self.g71(prog, b, w)?;
        } else if let Some(g) = thread_g {
            self.thread_cycle(prog, b, w, g, true)?;
        } else if self.st.cycle.is_some() && (get('X').is_some() || get('Z').is_some()) {
            self.thread_cycle(prog, b, w, 0, false)?;
        } else if get('X').is_some() || get('Z').is_some() {
            self.motion(prog, b, w)?;
        } else if let Some((_, col)) = get('I').or(get('K')).or(get('L')) {
            if self.st.motion >= 2 {
                return Err((
                    col,
                    format!(
                        "G{:02} without X or Z: a full circle is not a lathe move",
                        self.st.motion
                    ),
                ));
            }
        }
        Ok(if end { Step::End } else { Step::Next })
    }

    /// `T`: four digits (offset number, tool number) or six (offset, tool, nose radius
    /// number), 5238-E "T code"; `line` the block as written, whose T word at `col` (from
    /// 0) names the tool in messages (`T001111`, not `T1111`).
    fn tool(&mut self, v: f64, col: usize, line: &str) -> Result<(), Fail> {
        if v < 0.0 || v.fract() != 0.0 {
            return Err((
                col,
                format!("T{v}: expected a tool code such as T0101 or T010101"),
            ));
        }
        let n = v as u64;
        let (offset, tool) = if n >= 10_000 {
            (n / 10_000, (n / 100) % 100)
        } else {
            (n / 100, n % 100)
        };
        self.st.nose_no = (n >= 10_000 && n % 100 > 0).then_some((n % 100) as u32);
        if offset > 0 && self.opts.settings.tool_offsets.is_some() {
            return Err((col, "the job's tool offsets are not applied to Okuma programs yet: leave [machine] offsets out and program the tool's point".into()));
        }
        self.st.tool = Some(tool as u32);
        let written: String = line
            .chars()
            .skip(col)
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        let word = match written.strip_prefix(['T', 't']) {
            Some(d) if !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()) => {
                format!("T{d}")
            }
            _ => super::tool_word(super::Dialect::Okuma, v),
        };
        self.st.tool_word = Some(std::sync::Arc::from(word));
        Ok(())
    }

    fn length(&self, w: &[(char, f64, usize)], c: char) -> Option<f64> {
        let s = if self.st.inch { 25.4 } else { 1.0 };
        w.iter().rev().find(|t| t.0 == c).map(|t| t.1 * s)
    }

    /// The end point of a move: X (diameter) and Z, absolute or G91 incremental.
    fn target(&self, w: &[(char, f64, usize)]) -> (f64, f64) {
        let inc = self.st.incremental;
        let x = self
            .length(w, 'X')
            .map_or(self.st.x, |v| if inc { self.st.x + v } else { v });
        let z = self
            .length(w, 'Z')
            .map_or(self.st.z, |v| if inc { self.st.z + v } else { v });
        (x, z)
    }

    fn emit(
        &mut self,
        (file, line): (&str, usize),
        kind: MoveKind,
        a: (f64, f64),
        e: (f64, f64),
        sync: Option<Sync3>,
        cycle: bool,
    ) {
        let speed = SpindleSpeed {
            rpm: (!self.st.css).then_some(self.st.speed).flatten(),
            surface: self.st.css.then_some(self.st.speed).flatten(),
            max: self.st.speed_max,
        };
        let unit = if self.st.inch { 25.4 } else { 1.0 };
        self.inch_threads |= kind == MoveKind::Thread && self.st.inch;
        self.moves.push(Move {
            file: file.to_string(),
            line,
            kind,
            x_start: a.0,
            z_start: a.1,
            x_dia: e.0,
            z: e.1,
            lead: sync.map(|s| s.lead),
            lead_change: sync.map(|s| s.change),
            sync_angle_deg: sync.map(|s| s.angle),
            chained: false,
            tool: self.st.tool,
            tool_word: self.st.tool_word.clone(),
            spindle: self.st.spindle,
            arc: None,
            speed,
            feed: self.st.feed.map(|f| Feed {
                value: f * unit,
                per_rev: self.st.per_rev,
            }),
            cycle,
            nose: self.st.nose.map(|side| {
                let (radius, tip) = self.opts.settings.noses.of(self.st.tool, self.st.nose_no);
                super::Nose {
                    side,
                    radius,
                    tip,
                    rule: super::NoseRule::Fanuc,
                    held: cycle || kind == MoveKind::Thread,
                }
            }),
        });
    }

    /// G00/G01/G02/G03.
    fn motion(&mut self, prog: &Prog, b: &Block, w: &[(char, f64, usize)]) -> Result<(), Fail> {
        let a = (self.st.x, self.st.z);
        let e = self.target(w);
        match self.st.motion {
            0 => self.emit((&prog.file, b.line), MoveKind::Rapid, a, e, None, false),
            1 => {
                if self.st.feed.is_none() {
                    return Err((0, "G01 before any F: the feed is not set".into()));
                }
                self.emit((&prog.file, b.line), MoveKind::Feed, a, e, None, false)
            }
            g => {
                let cw = g == 2;
                // (z, radius): the plane seen from +Y, Z to the right, X up.
                let (pa, pb) = ((a.1, a.0 / 2.0), (e.1, e.0 / 2.0));
                let centre = if let Some(r) = self.length(w, 'L') {
                    let chord = (pb.0 - pa.0).hypot(pb.1 - pa.1);
                    if chord == 0.0
                        || r == 0.0
                        || chord / 2.0 > r.abs() + super::motion::ARC_TOLERANCE
                    {
                        let col = w.iter().find(|t| t.0 == 'L').map_or(0, |t| t.2);
                        return Err((col, format!("G{g:02} L{r}: the radius does not reach from the start to the end ({chord:.4} mm apart)")));
                    }
                    super::motion::radius_centre(pa, pb, r, cw)
                } else if w.iter().any(|t| t.0 == 'I' || t.0 == 'K') {
                    let i = self.length(w, 'I').unwrap_or(0.0);
                    let k = self.length(w, 'K').unwrap_or(0.0);
                    let c = (pa.0 + k, pa.1 + i);
                    let (ra, rb) = (
                        (pa.0 - c.0).hypot(pa.1 - c.1),
                        (pb.0 - c.0).hypot(pb.1 - c.1),
                    );
                    if (ra - rb).abs() > super::motion::ARC_TOLERANCE {
                        let col = w
                            .iter()
                            .find(|t| t.0 == 'I' || t.0 == 'K')
                            .map_or(0, |t| t.2);
                        return Err((col, format!("G{g:02}: the end point is off the circle: {rb:.4} mm from the centre, the start {ra:.4} mm")));
                    }
                    c
                } else {
                    return Err((
                        0,
                        format!("G{g:02} needs L (the radius) or I/K (the centre)"),
                    ));
                };
                if self.st.feed.is_none() {
                    return Err((0, format!("G{g:02} before any F: the feed is not set")));
                }
                self.emit((&prog.file, b.line), MoveKind::Arc, a, e, None, false);
                if let Some(last) = self.moves.last_mut() {
                    last.arc = Some(ArcGeometry {
                        x_centre_dia: 2.0 * centre.1,
                        z_centre: centre.0,
                        clockwise: cw,
                    });
                }
            }
        }
        self.st.x = e.0;
        self.st.z = e.1;
        Ok(())
    }

    /// The lead of a thread block: F, or F/J (J threads in F), 5238-E P-97.
    fn lead(&self, w: &[(char, f64, usize)], modal: Option<f64>) -> Result<f64, Fail> {
        let f = match self.length(w, 'F') {
            Some(f) => f,
            None => modal.ok_or((0, "a thread cycle needs F (the lead)".to_string()))?,
        };
        match w.iter().rev().find(|t| t.0 == 'J') {
            Some(&(_, j, col)) => {
                if !(j >= 1.0 && j.fract() == 0.0) {
                    return Err((
                        col,
                        format!("J{j}: expected a whole number of threads in F, 1 or more"),
                    ));
                }
                Ok(f / j)
            }
            None => Ok(f),
        }
    }

    fn no_chamfer(&self, w: &[(char, f64, usize)]) -> Result<(), Fail> {
        if self.st.chamfer {
            let col = w.iter().find(|t| t.0 == 'L').map_or(0, |t| t.2);
            return Err((col, "thread chamfering (M23) is not simulated: program M22 (chamfering off) before the thread cycle".into()));
        }
        Ok(())
    }

    /// G31/G33 (constant lead) and G34 (variable lead, E the change per revolution): one
    /// pass from the start point; a later block with X or Z repeats the cycle (modal) from
    /// the same start point.
    fn thread_cycle(
        &mut self,
        prog: &Prog,
        b: &Block,
        w: &[(char, f64, usize)],
        g: u32,
        new: bool,
    ) -> Result<(), Fail> {
        self.no_chamfer(w)?;
        let prev = self.st.cycle;
        let start = match (new, prev) {
            (false, Some(p)) => p.start,
            _ => (self.st.x, self.st.z),
        };
        let modal_lead = prev.map(|p| p.lead);
        let lead = if new && g != 0 {
            self.lead(w, if prev.is_some() { modal_lead } else { None })?
        } else {
            match self.length(w, 'F') {
                Some(_) => self.lead(w, None)?,
                None => modal_lead.expect("a modal cycle"),
            }
        };
        let change = if g == 34 {
            self.length(w, 'E').ok_or((
                0,
                "G34 needs E (the lead change per revolution)".to_string(),
            ))?
        } else if g == 0 {
            prev.map_or(0.0, |p| p.change)
        } else {
            if let Some(&(_, _, col)) = w.iter().find(|t| t.0 == 'E') {
                return Err((
                    col,
                    format!("G{g}: E (a lead change) belongs to G34, the variable lead cycle"),
                ));
            }
            0.0
        };
        let x = self.length(w, 'X').or(prev.map(|p| p.x)).ok_or((
            0,
            "a thread cycle needs X (the thread diameter of the pass)".to_string(),
        ))?;
        let z = self
            .length(w, 'Z')
            .or(prev.map(|p| p.z))
            .ok_or((0, "a thread cycle needs Z (the thread's end)".to_string()))?;
        let i = match (self.length(w, 'I'), w.iter().rev().find(|t| t.0 == 'A')) {
            (Some(i), _) => i,
            (None, Some(&(_, a, _))) => -(z - start.1).abs() * a.to_radians().tan(),
            (None, None) => prev.map_or(0.0, |p| p.i),
        };
        let k = self
            .length(w, 'K')
            .unwrap_or(if new { 0.0 } else { prev.map_or(0.0, |p| p.k) });
        let c = w
            .iter()
            .rev()
            .find(|t| t.0 == 'C')
            .map_or(prev.map_or(0.0, |p| p.c), |t| t.1);
        let sync = Sync3 {
            lead,
            change,
            angle: c.rem_euclid(360.0),
        };
        let moves = cyc::pass(start, x, z, i, k, 0.0, sync);
        self.cycle_moves(prog, b, &moves);
        self.st.cycle = Some(ThreadModal {
            start,
            x,
            z,
            lead,
            change,
            i,
            k,
            c,
        });
        Ok(())
    }

    fn cycle_moves(&mut self, prog: &Prog, b: &Block, moves: &[CycleMove]) {
        for m in moves {
            self.emit(
                (&prog.file, b.line),
                m.kind,
                m.a,
                m.b,
                m.sync,
                m.kind == MoveKind::Thread,
            );
            if self.moves.len() > self.opts.limits.max_moves {
                return;
            }
        }
        if let Some(m) = moves.last() {
            self.st.x = m.b.0;
            self.st.z = m.b.1;
        }
    }

    /// G71: the compound fixed thread cutting cycle (longitudinal), all its passes.
    fn g71(&mut self, prog: &Prog, b: &Block, w: &[(char, f64, usize)]) -> Result<(), Fail> {
        self.no_chamfer(w)?;
        let gcol = w
            .iter()
            .find(|t| t.0 == 'G' && t.1 == 71.0)
            .map_or(0, |t| t.2);
        let need = |c: char, what: &str| {
            self.length(w, c)
                .ok_or((gcol, format!("G71 needs {c} ({what})")))
        };
        let x = need('X', "the thread's root diameter")?;
        let z = need('Z', "the thread's end")?;
        let d = need('D', "the first cutting point, a diameter")?;
        let h = need('H', "the thread height, a diameter")?;
        let u = self.length(w, 'U').unwrap_or(0.0);
        let b_angle = w.iter().rev().find(|t| t.0 == 'B').map_or(0.0, |t| t.1);
        if !(0.0..180.0).contains(&b_angle) {
            let col = w.iter().find(|t| t.0 == 'B').map_or(0, |t| t.2);
            return Err((
                col,
                format!("G71 B{b_angle}: expected a tool angle from 0 to less than 180 deg"),
            ));
        }
        let start = (self.st.x, self.st.z);
        let i = match (self.length(w, 'I'), w.iter().rev().find(|t| t.0 == 'A')) {
            (Some(i), _) => i,
            (None, Some(&(_, a, _))) => -(z - start.1).abs() * a.to_radians().tan(),
            (None, None) => 0.0,
        };
        let starts = match w.iter().rev().find(|t| t.0 == 'Q') {
            Some(&(_, q, col)) => {
                if !(q >= 1.0 && q.fract() == 0.0 && q <= 360.0) {
                    return Err((
                        col,
                        format!("G71 Q{q}: expected a whole number of threads, 1 to 360"),
                    ));
                }
                q as u32
            }
            None => 1,
        };
        let g = G71 {
            x,
            z,
            i,
            b: b_angle,
            d,
            h,
            u,
            lead: self.lead(w, None)?,
            change: self.length(w, 'E').unwrap_or(0.0),
            starts,
            infeed: self.st.infeed,
            pattern: self.st.pattern,
        };
        let gcol = w
            .iter()
            .find(|t| t.0 == 'G' && t.1 == 71.0)
            .map_or(0, |t| t.2);
        let moves = cyc::compound(start, &g).map_err(|(_, m)| (gcol, m))?;
        self.cycle_moves(prog, b, &moves);
        Ok(())
    }
}
