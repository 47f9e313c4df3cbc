//! LinuxCNC (rs274ngc): blocks, O-word subroutines and control flow, and the G76 threading
//! cycle (`lcnc_g76`) as `Interp::convert_threading_cycle` computes it.
//!
//! A file is split when loaded: each `oN sub` .. `oN endsub` (numbered or `o<name>`) becomes
//! a program of its own, registered as `ON` / `O<NAME>`, and the main program keeps the
//! other lines (a definition is skipped where it stands and runs when called). `o<name>
//! call` of a subroutine not in the file loads `name.ngc` beside it, as rs274 does. Every
//! call is a new level of `#1..#30` (the arguments) and of named locals; `endsub`/`return`
//! with a value sets `#<_value>` and `#<_value_returned>` (else both 0). Loops and `if`
//! chains are matched by their O-word within one program (labels local to it, as rs274's:
//! `o100 if` inside `o100 sub` is another label than the sub's, and `o100 return` there
//! returns from the sub whether or not an `if` or loop of that number encloses it):
//! `while`/`endwhile`, `do`/`while`, `repeat`/`endrepeat` (count rounded half to even, one
//! count per repeat for the run as rs274 keeps it, so a repeat left by `return` resumes
//! with what was left on the next call), `if`/`elseif`/
//! `else`/`endif`, `break` and `continue` (of `while` and `do` loops only, as in rs274; in a `do` loop, as rs274 2.9.0~pre1 does,
//! `continue` runs the next line of the loop's O-word: the closing `while`, which tests, or
//! a later `break` of that loop, which leaves it; and after a `break` out of a `while` loop
//! the next closing `while` of a `do` loop does not loop). Parameter assignments of a line take effect after the whole line is read.

use super::expr::Fail;
use super::lcnc_expr::{Param, Params};
use super::lex::Cursor;
use super::{Interp, Program, Source, Step, Words};
use std::collections::HashMap;
use std::rc::Rc;

#[cfg(test)]
#[path = "lcnc_tests.rs"]
mod tests;

/// A block as `Program` keeps it: (1-based line, the line, the text parsed).
type Block = (usize, String, String);

/// O-word keywords.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kw {
    Sub,
    Endsub,
    Call,
    Return,
    Do,
    While,
    Endwhile,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
    Repeat,
    Endrepeat,
}

impl Kw {
    fn from_name(s: &str) -> Option<Kw> {
        Some(match s {
            "SUB" => Kw::Sub,
            "ENDSUB" => Kw::Endsub,
            "CALL" => Kw::Call,
            "RETURN" => Kw::Return,
            "DO" => Kw::Do,
            "WHILE" => Kw::While,
            "ENDWHILE" => Kw::Endwhile,
            "IF" => Kw::If,
            "ELSEIF" => Kw::Elseif,
            "ELSE" => Kw::Else,
            "ENDIF" => Kw::Endif,
            "BREAK" => Kw::Break,
            "CONTINUE" => Kw::Continue,
            "REPEAT" => Kw::Repeat,
            "ENDREPEAT" => Kw::Endrepeat,
            _ => return None,
        })
    }
    /// `sub`, `endsub`, `call` and `return` name a subroutine (rs274's "global" O-words);
    /// the others are labels of the program (or subroutine) they stand in, so `o100 if`
    /// inside `o100 sub` is another label than the sub's and `o100 return` is no line of
    /// that `if` (`Interp::read_o`: the local names are prefixed with the sub's name).
    fn local(self) -> bool {
        !matches!(self, Kw::Sub | Kw::Endsub | Kw::Call | Kw::Return)
    }
    fn name(self) -> &'static str {
        match self {
            Kw::Sub => "sub",
            Kw::Endsub => "endsub",
            Kw::Call => "call",
            Kw::Return => "return",
            Kw::Do => "do",
            Kw::While => "while",
            Kw::Endwhile => "endwhile",
            Kw::If => "if",
            Kw::Elseif => "elseif",
            Kw::Else => "else",
            Kw::Endif => "endif",
            Kw::Break => "break",
            Kw::Continue => "continue",
            Kw::Repeat => "repeat",
            Kw::Endrepeat => "endrepeat",
        }
    }
}

/// The O-words of a program's blocks: (key such as `O100` or `O<NAME>`, keyword), and for
/// a block opening an `if`, loop or `repeat` whose O-word already opened one earlier in the
/// program, that earlier block (rs274: "duplicate O-word label").
struct Flow {
    words: Vec<Option<(String, Kw)>>,
    dup_of: Vec<Option<usize>>,
    /// For a block that opens an `if`, loop or `repeat`: the first later block that opens
    /// another one with its label (rs274 errors there, whatever runs between).
    first_dup: Vec<Option<usize>>,
}

impl Flow {
    /// rs274 (`convert_control_functions`) keeps one table of the labels opened so far: a
    /// `while` whose label opened a `do` closes it; any other opening of a label in the
    /// table is a duplicate. The scan here is that table, read once in file order.
    fn new(prog: &Program) -> Flow {
        let words: Vec<Option<(String, Kw)>> = prog.blocks.iter().map(|b| oword_of(&b.2)).collect();
        let mut dup_of = vec![None; words.len()];
        let mut first_dup = vec![None; words.len()];
        // Each label's first opening block, and whether a line closing it came since.
        let mut opened: HashMap<&str, (usize, Kw, bool)> = HashMap::new();
        for (i, w) in words.iter().enumerate() {
            let Some((key, kw)) = w else { continue };
            let entry = opened.get_mut(key.as_str());
            if matches!(kw, Kw::Endif | Kw::Endwhile | Kw::Endrepeat) {
                if let Some(e) = entry {
                    e.2 = true;
                }
                continue;
            }
            if !matches!(kw, Kw::If | Kw::Do | Kw::Repeat | Kw::While) {
                continue;
            }
            match entry {
                Some(e) if e.1 == Kw::Do && *kw == Kw::While => e.2 = true,
                Some(&mut (j, _, closed)) => {
                    dup_of[i] = Some(j);
                    // Inside the block it opens: the block cannot be matched.
                    if !closed {
                        first_dup[j].get_or_insert(i);
                    }
                }
                None => {
                    opened.insert(key, (i, *kw, false));
                }
            }
        }
        Flow {
            words,
            dup_of,
            first_dup,
        }
    }
}

/// LinuxCNC interpreter state kept beside the shared `Interp` fields.
#[derive(Default)]
pub(super) struct Lcnc {
    pub(super) params: Params,
    /// O-word tables by program (its address: programs live as long as the run).
    flow: HashMap<usize, Rc<Flow>>,
    /// The block an `if` chain jumped to (an `elseif`/`else` reached this way is taken).
    jumped: Option<(usize, usize)>,
    /// rs274 2.9.0~pre1: after a `break` out of a while loop, the next closing `while` of a
    /// do loop does not loop (whatever its test); a `break` out of a do loop clears this.
    broke_while: bool,
    /// What is left of each `repeat`'s count, by (program, block): one table for the run,
    /// as rs274's.
    repeats: HashMap<(usize, usize), i64>,
    /// Machine state that only the predefined parameters read (`lcnc_expr::lc_predefined`).
    pub(super) st: LcState,
    /// A G70/G71/G72 whose contour subroutine is being read (`lcnc_g7x`).
    pub(super) g7x: Option<Box<super::lcnc_g7x::G7xRead>>,
    /// The state M70/M73 saved, by call level (`lcnc_modes`).
    pub(super) contexts: HashMap<usize, super::lcnc_modes::Context>,
}

/// LinuxCNC modal and machine state beside `Interp`'s shared fields: what `#<_..>` and
/// `#5161..` read, and the homes of G28/G30 (machine coordinates, X as a diameter, mm).
pub(super) struct LcState {
    /// The 1-based line of the block being run (`#<_line>`).
    pub(super) line: usize,
    pub(super) plane: u32,
    pub(super) ccomp: u32,
    /// G93, G94 or G95 (rs274 starts in G94).
    pub(super) feed_mode: u32,
    /// G43 on.
    pub(super) tool_offset: bool,
    /// G99 (R plane, rs274's start) or G98 (old Z) canned-cycle return.
    pub(super) retract_r: bool,
    /// G90.1 (else G91.1, rs274's start).
    pub(super) ijk_absolute: bool,
    pub(super) spindle_on: bool,
    pub(super) mist: bool,
    pub(super) flood: bool,
    /// M48/M49 (and M50/M51 P): overrides enabled (rs274's start: on).
    pub(super) speed_override: bool,
    pub(super) feed_override: bool,
    pub(super) adaptive_feed: bool,
    pub(super) feed_hold: bool,
    /// The last T word (-1 before any: rs274's `#<_selected_tool>`).
    pub(super) selected_tool: i64,
    /// G96 D: the maximum spindle speed under constant surface speed.
    pub(super) max_rpm: Option<f64>,
    /// G28 and G30 positions (#5161.. and #5181..).
    pub(super) home28: (f64, f64),
    pub(super) home30: (f64, f64),
    /// G92 offsets as stored in #5211.. (kept by G92.2, restored by G92.3), and whether
    /// they are applied (#5210).
    pub(super) g92_params: (f64, f64),
    pub(super) g92_on: bool,
}

impl Default for LcState {
    fn default() -> LcState {
        LcState {
            line: 0,
            plane: 180,
            ccomp: 400,
            feed_mode: 94,
            tool_offset: false,
            retract_r: true,
            ijk_absolute: false,
            spindle_on: false,
            mist: false,
            flood: false,
            speed_override: true,
            feed_override: true,
            adaptive_feed: false,
            feed_hold: false,
            selected_tool: -1,
            max_rpm: None,
            home28: (0.0, 0.0),
            home30: (0.0, 0.0),
            g92_params: (0.0, 0.0),
            g92_on: false,
        }
    }
}

/// A line upper-cased with comments (`( .. )`, `;` to the end) blanked, so columns stay.
fn blank_comments(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut depth = 0;
    let mut rest_blank = false;
    for ch in line.chars() {
        if rest_blank {
            break;
        }
        match ch {
            ';' if depth == 0 => rest_blank = true,
            '(' => {
                depth += 1;
                out.push(' ');
            }
            ')' if depth > 0 => {
                depth -= 1;
                out.push(' ');
            }
            _ if depth > 0 => out.extend(std::iter::repeat_n(' ', ch.len_utf8())),
            _ => out.push(ch.to_ascii_uppercase()),
        }
    }
    out.trim_end().to_string()
}

/// rs274's comment errors: a `(` inside a comment, or one not closed on its line (column of
/// the `(`).
fn comment_error(line: &str) -> Option<Fail> {
    let mut open = None;
    for (k, b) in line.bytes().enumerate() {
        match (b, open) {
            (b';', None) => return None,
            (b'(', None) => open = Some(k + 1),
            (b'(', Some(_)) => return Some((k + 1, "nested comment: `(` inside a comment".into())),
            (b')', Some(_)) => open = None,
            _ => {}
        }
    }
    open.map(|col| {
        (
            col,
            "unclosed comment: expected `)` on this line".to_string(),
        )
    })
}

/// The O-word at the start of a line (after an optional N number): key and keyword; the
/// cursor is left after the keyword. `Ok(None)` when the line does not start with `O`.
fn oword(c: &mut Cursor) -> Result<Option<(String, Kw)>, Fail> {
    if c.peek() == Some(b'N') && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.i += 1;
        let _ = c.number();
    }
    if !c.eat("O") {
        return Ok(None);
    }
    let key = if c.eat("<") {
        format!("O<{}>", c.angle_name()?)
    } else if c.peek() == Some(b'[') {
        // `o[expression]`: rs274 computes the number. A plain number is read here (so a
        // `o[101] sub` is found when the file loads); any other expression is kept as
        // `O[..]` and computed when the line runs (`lc_indirect`).
        let start = c.i;
        let mut depth = 0usize;
        while let Some(b) = c.peek() {
            c.i += 1;
            match b {
                b'[' => depth += 1,
                b']' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
        }
        if depth != 0 {
            return Err((
                c.col_at(start),
                "expected `]` closing the O-word's expression".into(),
            ));
        }
        let inner = String::from_utf8_lossy(&c.s[start + 1..c.i - 1]).to_string();
        match inner.parse::<f64>() {
            Ok(n) => match integer_value(n) {
                Some(n) => format!("O{n}"),
                None => {
                    return Err((
                        c.col_at(start),
                        format!("Non integer value for integer: o[{inner}]"),
                    ))
                }
            },
            Err(_) => format!("O[{inner}]"),
        }
    } else {
        let at = c.col();
        match c.number() {
            // Integer formatting: the same text as `{n}` for whole numbers, and cheap (this
            // runs for every executed O-word line).
            Some(n) if n.fract() == 0.0 && n.abs() < 1e15 => format!("O{}", n as i64),
            Some(n) if n.fract() == 0.0 => format!("O{n}"),
            _ => return Err((at, "expected an O-word number or <name>".into())),
        }
    };
    let at = c.col();
    let kw = c.ident();
    match Kw::from_name(&kw) {
        Some(k) => Ok(Some((key, k))),
        None => Err((
            at,
            format!("expected sub, endsub, call, return, do, while, endwhile, if, elseif, else, endif, break, continue, repeat or endrepeat after {}, found `{}`", key.to_lowercase(), kw.to_lowercase()),
        )),
    }
}

/// rs274's `read_integer_value`: a value within 1e-4 of a whole number is that number.
pub(super) fn integer_value(v: f64) -> Option<i64> {
    if !v.is_finite() || v.abs() > 2e9 {
        return None;
    }
    let floor = v.floor();
    if v - floor > 0.9999 {
        Some(v.ceil() as i64)
    } else if v - floor > 0.0001 {
        None
    } else {
        Some(floor as i64)
    }
}

fn oword_of(text: &str) -> Option<(String, Kw)> {
    oword(&mut Cursor::squeezed(text)).ok().flatten()
}

/// Split a LinuxCNC file into its main program and its subroutines (see the module docs).
/// A `sub` without its `endsub` stays in the main program, where running it is an error.
pub(super) fn load(src: &Source) -> Vec<Program> {
    let block = |i: usize, line: &str| -> Option<Block> {
        let text = blank_comments(line);
        let t = text.trim_start();
        // `(abort, ..)` is a comment that stops the program, and a bad comment an error:
        // keep their lines.
        let keep = line.to_ascii_uppercase().contains("(ABORT,") || comment_error(line).is_some();
        ((!t.is_empty() || keep) && t != "%" && !t.starts_with('/'))
            .then(|| (i + 1, line.to_string(), text))
    };
    let mut main = Vec::new();
    let mut subs: Vec<(String, Vec<Block>)> = Vec::new();
    let mut open: Option<(String, Vec<Block>)> = None;
    for (i, line) in src.text.lines().enumerate() {
        let Some(b) = block(i, line) else { continue };
        let ow = oword_of(&b.2);
        match (&mut open, ow) {
            (None, Some((key, Kw::Sub))) => open = Some((key, vec![b])),
            (Some((key, body)), Some((k, Kw::Endsub))) if *key == k => {
                body.push(b);
                let (key, mut body) = open.take().expect("open");
                body.remove(0);
                subs.push((key, body));
            }
            (Some((_, body)), _) => body.push(b),
            (None, _) => main.push(b),
        }
    }
    if let Some((_, body)) = open {
        main.extend(body);
    }
    let program = |alias: Option<String>, blocks| Program {
        name: src.name.clone(),
        alias,
        blocks,
        labels: HashMap::new(),
        numbers: HashMap::new(),
    };
    let mut out = vec![program(None, main)];
    out.extend(subs.into_iter().map(|(k, b)| program(Some(k), b)));
    out
}

impl Interp<'_> {
    /// One LinuxCNC block: an O-word line, or words and parameter assignments.
    pub(super) fn lcnc_block(
        &mut self,
        prog: &Program,
        pc: usize,
        text: &str,
    ) -> Result<Step, Fail> {
        let id = prog as *const Program as usize;
        self.lc.st.line = prog.blocks[pc].0;
        let jumped = self.lc.jumped.take() == Some((id, pc));
        let orig = &prog.blocks[pc].1;
        let has_comment = orig.as_bytes().iter().any(|&b| b == b'(' || b == b')');
        if let Some(e) = has_comment.then(|| comment_error(orig)).flatten() {
            return Err(e);
        }
        let abort = if has_comment {
            orig.as_bytes()
                .windows(7)
                .position(|w| w.eq_ignore_ascii_case(b"(ABORT,"))
        } else {
            None
        };
        if let Some(k) = abort {
            return Err((
                k + 1,
                format!(
                    "program aborted: {}",
                    orig[k + 7..].trim_end_matches(')').trim()
                ),
            ));
        }
        let mut c = Cursor::squeezed(text);
        if let Some((key, kw)) = oword(&mut c)? {
            let key = match key.strip_prefix("O[") {
                Some(expr) => self.lc_indirect(expr, kw)?,
                None => key,
            };
            return self.lcnc_oword(prog, pc, id, key, kw, &mut c, jumped);
        }
        let mut w = Words::default();
        let mut sets: Vec<(Param, f64)> = Vec::new();
        while !c.done() {
            let at = c.col();
            if c.eat("#") {
                let p = self.lc_param(&mut c)?;
                if let Param::Named(n) = &p {
                    if super::lcnc_expr::predefined(n) {
                        return Err((
                            at,
                            format!(
                                "cannot assign to read-only parameter #<{}>",
                                n.to_lowercase()
                            ),
                        ));
                    }
                }
                if let Param::Num(n) = p {
                    if let Some(why) = super::lcnc_expr::system_write_refused(n) {
                        return Err((at, why));
                    }
                }
                if !c.eat("=") {
                    return c.err("expected `=` after the parameter");
                }
                if let Param::Named(n) = &p {
                    self.lc_declare(n);
                }
                let v = self.lc_value(&mut c)?;
                sets.push((p, v));
                continue;
            }
            let letter = c.peek().expect("not done");
            if !letter.is_ascii_alphabetic() {
                return Err((at, format!("expected a word, found {}", c.here())));
            }
            c.i += 1;
            let st = c.i;
            let v = self.lc_value(&mut c)?;
            if !v.is_finite() {
                return Err((at, format!("the {} word's value is {v}", letter as char)));
            }
            // The tool as written (`T0505` is tool 505 to rs274, written with its zeros).
            let written = &c.s[st..c.i];
            if letter == b'T' && !written.is_empty() && written.iter().all(u8::is_ascii_digit) {
                w.t_text = Some(format!("T{}", String::from_utf8_lossy(written)));
            }
            let code = |v: f64| -> Result<u32, Fail> {
                let tenth = (v * 10.0).round();
                if v < 0.0 || (v * 10.0 - tenth).abs() > 1e-6 || tenth % 10.0 != 0.0 {
                    return Err((at, format!("{}{v} is not supported", letter as char)));
                }
                Ok((tenth / 10.0) as u32)
            };
            // G codes with a decimal that vpcut knows (G28.1, G30.1, G59.1..G59.3, G61.1,
            // G90.1, G91.1, G92.1..G92.3, G33.1, and G38.n to refuse it by name) come as
            // `DECIMAL_G + tenths` (see `motion::decimal_g`).
            let g_code = |v: f64| -> Result<u32, Fail> {
                let tenth = (v * 10.0).round();
                if v >= 0.0 && (v * 10.0 - tenth).abs() <= 1e-6 && tenth % 10.0 != 0.0 {
                    let t = tenth as u32;
                    if matches!(
                        t,
                        281 | 301
                            | 331
                            | 382..=385
                            | 411
                            | 421
                            | 431
                            | 432
                            | 591..=593
                            | 611
                            | 711
                            | 712
                            | 721
                            | 722
                            | 901
                            | 911
                            | 921..=923
                    ) {
                        return Ok(super::motion::DECIMAL_G + t);
                    }
                }
                code(v)
            };
            match letter {
                b'G' => w.g.push(g_code(v)?),
                b'M' => {
                    let m = code(v)?;
                    if m == 98 || m == 99 {
                        return Err((
                            at,
                            format!("M{m} (FANUC-style subprograms) is not supported: use o-word subroutines"),
                        ));
                    }
                    w.m.push(m)
                }
                b'N' => {}
                // U, W (increments), A and C (fillet, chamfer): words of a G7x contour
                // subroutine only (refused elsewhere below).
                b'X' | b'Z' | b'F' | b'K' | b'Q' | b'S' | b'T' | b'R' | b'P' | b'L' | b'J'
                | b'I' | b'H' | b'E' | b'D' | b'U' | b'W' | b'A' | b'C' => {
                    let k = (letter as char).to_string();
                    if w.vals.contains_key(&k) {
                        return Err((at, format!("more than one {k} word on the line")));
                    }
                    w.vals.insert(k, (v, at));
                }
                b'O' => return Err((at, "an O-word must start the line".into())),
                other => {
                    return Err((
                        at,
                        format!(
                            "the word `{}` is not supported on a LinuxCNC lathe (X Z axes)",
                            other as char
                        ),
                    ))
                }
            }
        }
        // rs274: the line's parameter settings take effect after the whole line is read.
        for (p, v) in sets {
            self.lc_set(p, v);
        }
        if self.lc.g7x.is_some() {
            // A line of a G7x contour: only its motion words count (rs274 runs nothing else).
            self.lc_g7x_block(&w)?;
            return Ok(Step::Next);
        }
        for k in ["U", "W", "A", "C"] {
            if let Some(&(_, at)) = w.vals.get(k) {
                return Err((
                    at,
                    format!(
                        "Bad character '{}' used (a LinuxCNC lathe has X and Z; U, W, A and C are words of a G70/G71/G72 contour only)",
                        k.to_lowercase()
                    ),
                ));
            }
        }
        self.lc_modal(&w);
        let dyn_offset = [431, 432].map(|c| super::motion::DECIMAL_G + c);
        if w.g.iter().any(|g| dyn_offset.contains(g)) {
            // G43.1 X Z / G43.2: the words are tool length offsets, no move; the tool's
            // tip follows the program whatever the offsets (rs274's canon points are the
            // tip's), so nothing else changes.
            w.vals.retain(|k, _| !matches!(k.as_str(), "X" | "Z" | "H"));
        }
        if let Some(&m) = w.m.iter().find(|&&m| (70..=73).contains(&m)) {
            // rs274 sets F and S before it saves or restores the state, and runs the
            // block's G codes after.
            if let Some(&(f, _)) = w.vals.get("F") {
                self.modal.feed = Some(f);
            }
            if let Some(&(s, _)) = w.vals.get("S") {
                self.modal.speed = Some(s);
            }
            self.lc_m7x(m)?;
        }
        if let Some(code) = w.g.iter().find_map(|&g| super::lcnc_g7x::g7x_code(g)) {
            return self.lc_g7x_start(&w, code, prog, pc);
        }
        if w.g.contains(&76) {
            return self.in_cycle(|m| m.lcnc_g76(&w, prog, pc));
        }
        self.apply(&w, prog, pc)
    }

    /// `o[expression] call`: the subroutine whose number the expression gives (rs274: a
    /// whole number within 1e-4). `expr` is the text after `O[`. Other O-words with a
    /// computed number are refused: vpcut matches `if`/loop labels and finds subroutine
    /// definitions when the file loads.
    fn lc_indirect(&mut self, expr: &str, kw: Kw) -> Result<String, Fail> {
        if kw != Kw::Call {
            return Err((
                1,
                format!(
                    "o[{} {}: an O-word number computed from parameters is simulated for call only (a constant such as o[101] works everywhere)",
                    expr.to_lowercase(),
                    kw.name()
                ),
            ));
        }
        let text = format!("[{expr}");
        let v = self.lc_bracket(&mut Cursor::squeezed(&text))?;
        match integer_value(v) {
            Some(n) => Ok(format!("O{n}")),
            None => Err((
                1,
                format!(
                    "Non integer value for integer: o[{} is {v}",
                    expr.to_lowercase()
                ),
            )),
        }
    }

    /// The modal state only LinuxCNC's predefined parameters read (the rest is `apply`'s).
    fn lc_modal(&mut self, w: &Words) {
        let st = &mut self.lc.st;
        for &g in &w.g {
            match g {
                17..=19 => st.plane = g * 10,
                40..=42 => st.ccomp = g * 10,
                g if g == super::motion::DECIMAL_G + 411 => st.ccomp = 411,
                g if g == super::motion::DECIMAL_G + 421 => st.ccomp = 421,
                43 => st.tool_offset = true,
                49 => st.tool_offset = false,
                93..=95 => st.feed_mode = g,
                98 => st.retract_r = false,
                99 => st.retract_r = true,
                g if g == super::motion::DECIMAL_G + 901 => st.ijk_absolute = true,
                g if g == super::motion::DECIMAL_G + 911 => st.ijk_absolute = false,
                _ => {}
            }
        }
        if w.g.contains(&96) {
            if let Some(&(d, _)) = w.vals.get("D") {
                st.max_rpm = Some(d);
            }
        }
        let p = w.vals.get("P").map(|v| v.0);
        // rs274 changes the tool (M6 stops the spindle: `STOP_SPINDLE_TURNING` before
        // `CHANGE_TOOL`) before it starts the spindle of the same block.
        if w.m.contains(&6) {
            st.spindle_on = false;
        }
        for &m in &w.m {
            match m {
                3 | 4 => st.spindle_on = true,
                5 => st.spindle_on = false,
                7 => st.mist = true,
                8 => st.flood = true,
                9 => (st.mist, st.flood) = (false, false),
                48 => (st.speed_override, st.feed_override) = (true, true),
                49 => (st.speed_override, st.feed_override) = (false, false),
                50 => st.feed_override = p.is_none_or(|p| p != 0.0),
                51 => st.speed_override = p.is_none_or(|p| p != 0.0),
                52 => st.adaptive_feed = p.is_none_or(|p| p != 0.0),
                53 => st.feed_hold = p.is_none_or(|p| p != 0.0),
                _ => {}
            }
        }
        if let Some(&(t, _)) = w.vals.get("T") {
            st.selected_tool = t.round() as i64;
        }
    }

    /// G10 L2 (set a work offset to X/Z) and G10 L20 (set it so that the current point reads
    /// X/Z), `P0` the active system, `P1..P9` G54..G59.3; axes not named keep their offset.
    /// `xs` turns an X word into a diameter, `scale` program units into mm. G10 L1/L10/L11
    /// (tool table entries) set the tool's nose radius and orientation (`nose::lc_g10_tool`):
    /// the tool's tip follows the program whatever its length offsets (rs274 sends them to
    /// the machine with `USE_TOOL_LENGTH_OFFSET`; its canon's points are the tip's).
    pub(super) fn lc_g10(&mut self, w: &Words, xs: f64, scale: f64) -> Result<(), Fail> {
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let l = val("L").ok_or((1, "G10 needs L (L2 or L20 set work offsets)".to_string()))?;
        if l == 1.0 || l == 10.0 || l == 11.0 {
            // The tool table's entry: its nose radius and orientation (`nose`); its
            // offsets go to the machine and the tip follows the program.
            return self.lc_g10_tool(w, l, scale);
        }
        if l != 2.0 && l != 20.0 {
            return Err((
                w.vals.get("L").map_or(1, |v| v.1),
                format!("G10 L{l} (other data) is not simulated: vpcut runs G10 L1, L10, L11 (tool table: a tool's radius and orientation) and L2, L20 (work offsets)"),
            ));
        }
        let p = val("P").ok_or((1, format!("G10 L{l} needs P (0 active, 1..9 G54..G59.3)")))?;
        if !(0.0..=9.0).contains(&p) || p.fract() != 0.0 {
            return Err((
                w.vals.get("P").map_or(1, |v| v.1),
                format!("G10 L{l} P{p}: expected P0..P9"),
            ));
        }
        if val("R").is_some_and(|r| r != 0.0) {
            return Err((
                w.vals.get("R").map_or(1, |v| v.1),
                "G10 R (a rotation of the XY plane) is not simulated on a lathe".into(),
            ));
        }
        let k = if p == 0.0 {
            self.frames.work
        } else {
            p as usize - 1
        };
        let g92 = self.frames.g92_off;
        let o = &mut self.frames.offsets[k];
        if let Some(v) = val("X") {
            let v = v * xs * scale;
            o.0 = if l == 2.0 { v } else { self.x - g92.0 - v };
        }
        if let Some(v) = val("Z") {
            let v = v * scale;
            o.1 = if l == 2.0 { v } else { self.z - g92.1 - v };
        }
        Ok(())
    }

    fn lc_flow(&mut self, prog: &Program, id: usize) -> Rc<Flow> {
        self.lc
            .flow
            .entry(id)
            .or_insert_with(|| Rc::new(Flow::new(prog)))
            .clone()
    }

    #[allow(clippy::too_many_arguments)]
    fn lcnc_oword(
        &mut self,
        prog: &Program,
        pc: usize,
        id: usize,
        key: String,
        kw: Kw,
        c: &mut Cursor,
        jumped: bool,
    ) -> Result<Step, Fail> {
        let flow = self.lc_flow(prog, id);
        let lname = key.to_lowercase();
        // The next (or previous) line of this O-word, break and continue left out.
        let is = |k: usize| -> Option<Kw> {
            match &flow.words[k] {
                Some((kk, w))
                    if *kk == key && w.local() && !matches!(w, Kw::Break | Kw::Continue) =>
                {
                    Some(*w)
                }
                _ => None,
            }
        };
        let next = || (pc + 1..flow.words.len()).find_map(|k| is(k).map(|w| (k, w)));
        let prev = |want: Kw| (0..pc).rev().find(|&k| is(k) == Some(want));
        let missing = |what: &str| -> Fail {
            (
                1,
                format!("{lname} {}: no matching {lname} {what}", kw.name()),
            )
        };
        // rs274 looks a closing line's label up among the blocks opened before it
        // (`control_find_oword`): none is "undefined O-word label".
        let closes = matches!(
            kw,
            Kw::Elseif
                | Kw::Else
                | Kw::Endif
                | Kw::Endwhile
                | Kw::Endrepeat
                | Kw::Break
                | Kw::Continue
        );
        let opened =
            (0..pc).any(|k| matches!(is(k), Some(Kw::If | Kw::While | Kw::Do | Kw::Repeat)));
        if closes && !opened {
            return Err((
                1,
                format!(
                    "undefined O-word label: {lname} {} (no {lname} if, while, do or repeat before it)",
                    kw.name()
                ),
            ));
        }
        if let Some(k) = flow.first_dup[pc] {
            return Err((
                1,
                format!(
                    "duplicate O-word label: the {lname} {} at line {} is already defined here (use another number)",
                    flow.words[k].as_ref().map_or("", |w| w.1.name()),
                    prog.blocks[k].0
                ),
            ));
        }
        if let Some(j) = flow.dup_of[pc] {
            return Err((
                1,
                format!(
                    "duplicate O-word label: {lname} already opened a block at line {} (use another number)",
                    prog.blocks[j].0
                ),
            ));
        }
        let cond = |m: &Self, c: &mut Cursor| -> Result<bool, Fail> {
            let v = m.lc_bracket(c)?;
            Ok(v != 0.0)
        };
        let step = match kw {
            Kw::Sub => {
                return Err((
                    1,
                    format!("{lname} sub: no matching {lname} endsub, or inside another sub"),
                ))
            }
            Kw::Endsub | Kw::Return => {
                if self.lc_depth() == 0 {
                    return Err((
                        1,
                        format!("not in a subroutine definition: {lname} {}", kw.name()),
                    ));
                }
                let value = if c.done() {
                    None
                } else {
                    Some(self.lc_bracket(c)?)
                };
                let g = &mut self.lc.params.globals;
                g.insert("_VALUE".into(), value.unwrap_or(0.0));
                g.insert("_VALUE_RETURNED".into(), f64::from(value.is_some()));
                // The end of a G7x contour subroutine runs the cycle; an M73 state comes
                // back.
                self.lc_g7x_end()?;
                self.lc_context_leave();
                Step::Return
            }
            Kw::Call => {
                let mut args = Vec::new();
                while !c.done() {
                    if args.len() == 30 {
                        return c.err("more than 30 call arguments");
                    }
                    args.push((args.len() as u32 + 1, self.lc_bracket(c)?));
                }
                if !self.progs.by_name.contains_key(&key) {
                    self.lc_load_sub(&key)?;
                }
                self.lc_push_level();
                return Ok(Step::Call(key, 1, Some(args)));
            }
            Kw::Do | Kw::Endif => Step::Next,
            Kw::While => match next() {
                // A loop head: its endwhile follows.
                Some((end, Kw::Endwhile)) => {
                    if cond(self, c)? {
                        Step::Next
                    } else {
                        Step::Jump(end + 1)
                    }
                }
                // The end of a do loop.
                _ => {
                    let start =
                        prev(Kw::Do).ok_or_else(|| missing("endwhile (or do before it)"))?;
                    let test = cond(self, c)?;
                    if std::mem::take(&mut self.lc.broke_while) {
                        Step::Next
                    } else if test {
                        Step::Jump(start + 1)
                    } else {
                        Step::Next
                    }
                }
            },
            Kw::Endwhile => Step::Jump(prev(Kw::While).ok_or_else(|| missing("while"))?),
            Kw::Break | Kw::Continue => {
                let (end, w) = next().ok_or_else(|| missing("endwhile, endrepeat or while"))?;
                if w == Kw::Endrepeat {
                    // rs274 2.9.0~pre1: "no matching while/do label .. (found 'repeat')".
                    return Err((
                        1,
                        format!("{lname} {}: only while and do loops can be left or continued, not repeat", kw.name()),
                    ));
                }
                if !matches!(w, Kw::Endwhile | Kw::While) {
                    return Err(missing("endwhile or while"));
                }
                if kw == Kw::Break {
                    self.lc.broke_while = w == Kw::Endwhile;
                    Step::Jump(end + 1)
                } else if w == Kw::While {
                    // A do loop: rs274 (2.9.0~pre1) skips to the next line of this O-word
                    // and runs it: the closing while (which tests), or a later break or
                    // continue of the same loop.
                    let k = (pc + 1..flow.words.len())
                        .find(
                            |&k| matches!(&flow.words[k], Some((kk, w)) if *kk == key && w.local()),
                        )
                        .unwrap_or(end);
                    Step::Jump(k)
                } else {
                    // The endwhile, which goes back to the test.
                    Step::Jump(end)
                }
            }
            Kw::Repeat => {
                let n = self.lc_bracket(c)?.round_ties_even();
                let end = match next() {
                    Some((k, Kw::Endrepeat)) => k,
                    _ => return Err(missing("endrepeat")),
                };
                // rs274 2.9.0~pre1 refuses these when it reads them, run or skipped, even in
                // a repeat [0]; vpcut refuses the repeat (a program that leaves the repeat by
                // another loop's break before rs274 reads the line is refused too).
                let exit = (pc + 1..end).find(|&k| {
                    matches!(&flow.words[k], Some((kk, Kw::Break | Kw::Continue)) if *kk == key)
                });
                if let Some(k) = exit {
                    return Err((
                        1,
                        format!("{lname} repeat: the break or continue at line {} cannot leave a repeat (only while and do loops)", prog.blocks[k].0),
                    ));
                }
                // rs274 keeps one count per repeat for the whole run (`offset_map`): set
                // when the count is unset, one less each time the repeat line runs the
                // body, unset when it skips it. A repeat left by `return` keeps what is
                // left, so the next call runs the body only that many times.
                let slot = self.lc.repeats.entry((id, pc));
                let left = *slot.or_insert(n.clamp(-1.0, 1e15) as i64);
                if left > 0 {
                    self.lc.repeats.insert((id, pc), left - 1);
                    Step::Next
                } else {
                    self.lc.repeats.remove(&(id, pc));
                    Step::Jump(end + 1)
                }
            }
            Kw::Endrepeat => Step::Jump(prev(Kw::Repeat).ok_or_else(|| missing("repeat"))?),
            Kw::If | Kw::Elseif | Kw::Else => {
                let test = match kw {
                    Kw::If => true,
                    _ if !jumped => {
                        // The branch before was taken: leave the chain.
                        let end = (pc + 1..flow.words.len())
                            .find(|&k| is(k) == Some(Kw::Endif))
                            .ok_or_else(|| missing("endif"))?;
                        return Ok(Step::Jump(end + 1));
                    }
                    Kw::Elseif => true,
                    _ => false,
                };
                if !test || cond(self, c)? {
                    Step::Next
                } else {
                    match next() {
                        Some((k, Kw::Elseif | Kw::Else)) => {
                            self.lc.jumped = Some((id, k));
                            Step::Jump(k)
                        }
                        Some((k, Kw::Endif)) => Step::Jump(k + 1),
                        _ => return Err(missing("endif")),
                    }
                }
            }
        };
        if !c.done() {
            return c.err(format!("unexpected text after {lname} {}", kw.name()));
        }
        Ok(step)
    }

    /// `o<name> call` of a subroutine not in this file: `name.ngc` beside it, else in the
    /// folders of `Settings::subroutine_path`.
    fn lc_load_sub(&mut self, key: &str) -> Result<(), Fail> {
        let lname = key.to_lowercase();
        let Some(name) = lname.strip_prefix("o<").and_then(|n| n.strip_suffix('>')) else {
            return Err((
                1,
                format!("{lname} is not defined: no {lname} sub in this file"),
            ));
        };
        let file = format!("{name}.ngc");
        // rs274 (`find_ngc_file`): the working folder (beside the program), then each
        // folder of SUBROUTINE_PATH in turn; the first file found is the one.
        let found = std::iter::once(file.clone())
            .chain(self.cfg.subroutine_path.iter().map(|d| {
                let d = d.trim_end_matches('/');
                if d.is_empty() {
                    file.clone()
                } else {
                    format!("{d}/{file}")
                }
            }))
            .find_map(|f| (self.progs.loader)(&f));
        let Some(src) = found else {
            let searched = if self.cfg.subroutine_path.is_empty() {
                String::new()
            } else {
                format!(" or in {}", self.cfg.subroutine_path.join(", "))
            };
            return Err((
                1,
                format!(
                    "subroutine {lname} not found (in this file, as {file} beside it{searched})"
                ),
            ));
        };
        for p in load(&src).into_iter().skip(1) {
            if let Some(a) = p.alias.clone() {
                self.progs.by_name.entry(a).or_insert_with(|| Rc::new(p));
            }
        }
        if !self.progs.by_name.contains_key(key) {
            return Err((1, format!("{file} does not define {lname} sub")));
        }
        Ok(())
    }
}

/// rs274's error for a spindle-synchronised move while the spindle stands, with why it
/// stands.
pub(super) fn spindle_stopped(rs274: &str) -> String {
    format!("{rs274} (the spindle stands: never started, or stopped by M5 or by a tool change M6, which rs274 runs with the spindle stopped; start it with M3 or M4)")
}
