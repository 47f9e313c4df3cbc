//! Static checks of a program before it runs: every block of every program that can be
//! found is read once, and every problem is reported with its line and column, not just the
//! first one (a compiler's diagnostics, not an interpreter's first alarm).
//!
//! What is checked without running anything:
//! - syntax: malformed numbers, words without a value, unbalanced `[ ]`/`( )`, unclosed
//!   comments, characters that are no part of the language, assignments without `=`,
//!   unknown functions in expressions;
//! - words and codes: address letters, G and M codes that vpcut does not know are warnings
//!   (errors in strict mode); at run time they are skipped ([`super::codes`]);
//! - control flow that is written out: `WHILE .. DOn`/`ENDn` pairs and their numbers and
//!   Siemens `GOTOF`/`GOTOB` directions (errors); `GOTO n`/`IF .. GOTO n`/Macro A jump
//!   targets, Siemens labels and subprograms called by a literal name or number that cannot
//!   be found (warnings: a control alarms only when it reaches them, so a program whose
//!   dead branch calls a missing program still runs; the run stops if one is reached).
//!
//! What needs the values of variables (a computed jump, a division by zero, a lead that
//! reaches zero) is found at run time, where the interpreter stops at the first such error.
//! LinuxCNC programs are checked for their comments and characters only: their O-word
//! language is read by the interpreter itself.

use super::codes::{self, Verdict};
use super::expr::{FANUC_MAX_VALUE, SIEMENS_MAX_VALUE};
use super::lex::{char_at, char_col, describe_char, Cursor, MAX_NEST};
use super::program::Program;
use super::{Diagnostic, Dialect, Severity};

/// The checker's view of one block: the original line, upper-cased, in the lexer's cursor
/// (which skips comments), with where its findings go.
struct Line<'a> {
    c: Cursor<'static>,
    /// A FANUC milling program (its G/M codes and addresses).
    mill: bool,
    /// The FANUC lathe G-code system.
    system: codes::GcodeSystem,
    out: &'a mut Vec<(usize, Severity, String, Option<String>)>,
}

type Stop = ();

impl std::ops::Deref for Line<'_> {
    type Target = Cursor<'static>;
    fn deref(&self) -> &Cursor<'static> {
        &self.c
    }
}

impl std::ops::DerefMut for Line<'_> {
    fn deref_mut(&mut self) -> &mut Cursor<'static> {
        &mut self.c
    }
}

impl Line<'_> {
    /// Skip blanks and comments, reporting a comment left open.
    fn ws(&mut self) {
        self.c.ws();
        for start in std::mem::take(&mut self.c.unclosed) {
            self.out.push((
                start + 1,
                Severity::Error,
                "unclosed comment: `(` without `)`".into(),
                Some("add `)` at the end of the comment".into()),
            ));
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.c.peek()
    }
    fn at_end(&mut self) -> bool {
        self.peek().is_none()
    }
    fn eat(&mut self, t: &str) -> bool {
        self.ws();
        self.c.eat(t)
    }
    fn error(
        &mut self,
        col: usize,
        msg: impl Into<String>,
        hint: Option<&str>,
    ) -> Result<(), Stop> {
        self.out
            .push((col, Severity::Error, msg.into(), hint.map(str::to_string)));
        Err(())
    }
    fn unknown(&mut self, col: usize, msg: String, strict: bool) {
        let severity = if strict {
            Severity::Error
        } else {
            Severity::Warning
        };
        let hint = if strict {
            "vpcut does not simulate it; without --strict it is skipped with a warning"
        } else {
            "skipped: vpcut does not simulate it (an error with --strict)"
        };
        self.out.push((col, severity, msg, Some(hint.into())));
    }
    fn letters(&mut self) -> String {
        self.ws();
        self.c.ident()
    }
    /// An unsigned number; `Some(None)` when malformed (reported), `None` when absent.
    fn number(&mut self) -> Option<Option<f64>> {
        self.ws();
        let (st, end) = self.c.number_span()?;
        let t = self.c.text((st, end));
        let max = match self.dialect {
            Dialect::Siemens802d | Dialect::Siemens840d => SIEMENS_MAX_VALUE,
            _ => FANUC_MAX_VALUE,
        };
        match t.parse::<f64>() {
            Ok(v) if v > max => {
                let shown = if t.len() > 20 {
                    format!("{}.. ({} characters)", &t[..12], t.len())
                } else {
                    t
                };
                self.out.push((
                    st + 1,
                    Severity::Error,
                    format!("the number {shown} is too large (at most ±{max:e})"),
                    None,
                ));
                Some(None)
            }
            Ok(v) => Some(Some(v)),
            Err(_) => {
                self.out.push((
                    st + 1,
                    Severity::Error,
                    format!("`{t}` is not a number"),
                    None,
                ));
                Some(None)
            }
        }
    }
    fn unexpected(&mut self, what: &str) -> Result<(), Stop> {
        let col = self.i + 1;
        if self.i >= self.s.len() {
            return self.error(col, format!("the block ends here: expected {what}"), None);
        }
        let c = describe_char(char_at(&self.s, self.i));
        self.error(col, format!("unexpected {c}: expected {what}"), None)
    }
    /// Enter one more level of an expression; an error past `MAX_NEST`.
    fn enter(&mut self) -> Result<(), Stop> {
        if self.nest >= MAX_NEST {
            let col = self.i + 1;
            return self.error(
                col,
                format!("the expression nests more than {MAX_NEST} levels deep"),
                Some("split it over several assignments"),
            );
        }
        self.nest += 1;
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------
// FANUC / GSK (Macro A and B).

const FANUC_FUNCTIONS: &[&str] = &[
    "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN", "EXP",
];
const FANUC_OPS: &[&str] = &[
    "AND", "OR", "XOR", "MOD", "EQ", "NE", "GT", "GE", "LT", "LE",
];

impl Line<'_> {
    /// `[ expr ]`, the cursor on `[`.
    fn f_bracket(&mut self) -> Result<(), Stop> {
        if !self.eat("[") {
            return self.unexpected("`[`");
        }
        self.f_expr()?;
        if !self.eat("]") {
            return self.unexpected("an operator or `]`");
        }
        Ok(())
    }
    fn f_expr(&mut self) -> Result<(), Stop> {
        loop {
            while self.eat("-") || self.eat("+") {}
            self.f_primary()?;
            match self.peek() {
                Some(b'+' | b'-' | b'*' | b'/') => self.i += 1,
                // GSK's statement macros compare with symbols too (`IF[#1<10]`, `==`, `<>`).
                Some(b'<' | b'>' | b'=') if self.c.dialect == Dialect::Gsk980 => {
                    if !["==", "<>", "<=", ">=", "<", ">"]
                        .iter()
                        .any(|op| self.eat(op))
                    {
                        return self.unexpected("an operator or `]`");
                    }
                }
                Some(c) if c.is_ascii_alphabetic() => {
                    let at = self.i;
                    let w = self.letters();
                    if !FANUC_OPS.contains(&w.as_str()) {
                        return self.error(
                            at + 1,
                            format!("`{w}` is not an operator"),
                            Some("operators: + - * / MOD AND OR XOR EQ NE GT GE LT LE"),
                        );
                    }
                }
                _ => return Ok(()),
            }
        }
    }
    fn f_primary(&mut self) -> Result<(), Stop> {
        self.enter()?;
        let r = self.f_primary_inner();
        self.nest -= 1;
        r
    }
    fn f_primary_inner(&mut self) -> Result<(), Stop> {
        match self.peek() {
            Some(b'[') => self.f_bracket(),
            Some(b'#') => {
                self.i += 1;
                self.f_var_index()
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                self.number();
                Ok(())
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let at = self.i;
                let f = self.letters();
                if !FANUC_FUNCTIONS.contains(&f.as_str()) {
                    return self.error(
                        at + 1,
                        format!("unknown function `{f}`"),
                        Some("functions: SIN COS TAN ASIN ACOS ATAN SQRT ABS ROUND FIX FUP LN EXP"),
                    );
                }
                if !self.eat("[") {
                    return self.unexpected(&format!("`[` after {f}"));
                }
                self.f_expr()?;
                if f == "ATAN" && self.eat(",") {
                    self.f_expr()?;
                }
                if !self.eat("]") {
                    return self.unexpected("an operator or `]`");
                }
                if f == "ATAN" && self.peek() == Some(b'/') {
                    let save = self.i;
                    self.i += 1;
                    if self.peek() == Some(b'[') {
                        self.f_bracket()?;
                    } else {
                        self.i = save;
                    }
                }
                Ok(())
            }
            _ => self.unexpected("a number, a #variable, a function or `[`"),
        }
    }
    fn f_var_index(&mut self) -> Result<(), Stop> {
        if self.peek() == Some(b'[') {
            return self.f_bracket();
        }
        match self.number() {
            Some(_) => Ok(()),
            None => self.unexpected("a variable number after `#`"),
        }
    }
    /// A word's value: a number, `#n`, `-#n` or `[expr]`.
    fn f_value(&mut self, letter: char) -> Result<Option<f64>, Stop> {
        let neg = self.eat("-");
        let _ = self.eat("+");
        match self.peek() {
            Some(b'#') => {
                self.i += 1;
                self.f_var_index()?;
                Ok(None)
            }
            Some(b'[') => {
                self.f_bracket()?;
                Ok(None)
            }
            _ => match self.number() {
                Some(v) => Ok(v.map(|v| if neg { -v } else { v })),
                None => {
                    self.unexpected(&format!("a value after `{letter}`"))?;
                    Ok(None)
                }
            },
        }
    }
}

/// Per-block facts the program-level checks need.
#[derive(Default)]
struct BlockFacts {
    /// `GOTO n` targets with their columns.
    gotos: Vec<(u32, usize)>,
    /// `WHILE .. DOn` with column.
    whiles: Vec<(u32, usize)>,
    /// `ENDn` with column.
    ends: Vec<(u32, usize)>,
    /// Programs called by a literal number or name, with column.
    calls: Vec<(String, usize)>,
    /// An M02 or M30 (the end of the run).
    stops: bool,
}

fn fanuc_block(l: &mut Line, strict: bool, facts: &mut BlockFacts) -> Result<(), Stop> {
    l.ws();
    if l.eat("/") && l.s.get(l.i).is_some_and(u8::is_ascii_digit) {
        l.i += 1; // a block-skip level, /1../9
    }
    let mut g65 = false;
    let mut g76 = false;
    let mut mrc = false;
    let mut m98 = false;
    let mut m99 = false;
    let mut p_word: Option<(f64, usize)> = None;
    let mut h_word: Option<Option<f64>> = None;
    let mut l_word = false;
    let mut strange: Vec<(usize, char)> = Vec::new();
    while !l.at_end() {
        let at = l.i;
        if l.eat("#") {
            l.f_var_index()?;
            if !l.eat("=") {
                return l.error(
                    l.i + 1,
                    "expected `=` after a variable",
                    Some("a variable is set with #n = expression"),
                );
            }
            l.f_expr()?;
            continue;
        }
        let Some(c) = l.peek() else { break };
        if !c.is_ascii_alphabetic() {
            return l.unexpected("a word (letter and value) or #variable");
        }
        // A keyword or a one-letter address.
        let save = l.i;
        let w = l.letters();
        match w.as_str() {
            "WHILE" => {
                l.f_bracket()?;
                if !l.eat("DO") {
                    return l.error(l.i + 1, "expected DOn after WHILE [..]", None);
                }
                match l.number() {
                    Some(Some(n)) if (1.0..=3.0).contains(&n) && n.fract() == 0.0 => {
                        facts.whiles.push((n as u32, at + 1))
                    }
                    _ => return l.error(at + 1, "WHILE needs DO1, DO2 or DO3", None),
                }
                continue;
            }
            "END" => {
                match l.number() {
                    Some(Some(n)) if (1.0..=3.0).contains(&n) && n.fract() == 0.0 => {
                        facts.ends.push((n as u32, at + 1))
                    }
                    _ => return l.error(at + 1, "expected END1, END2 or END3", None),
                }
                continue;
            }
            "IF" => {
                l.f_bracket()?;
                if l.eat("GOTO") {
                    l.ws();
                    let col = l.i + 1;
                    if let Some(n) = l.f_value('N')? {
                        facts.gotos.push((n as u32, col));
                    }
                    continue;
                }
                if l.eat("THEN") {
                    continue;
                }
                return l.error(l.i + 1, "expected GOTO or THEN after IF [..]", None);
            }
            "GOTO" => {
                l.ws();
                let col = l.i + 1;
                if let Some(n) = l.f_value('N')? {
                    facts.gotos.push((n as u32, col));
                }
                continue;
            }
            _ => {}
        }
        if w.len() > 1 {
            // Letters glued together: the first is an address without a value, or a typo.
            l.i = save + 1;
            return l.error(
                at + 1,
                format!("unknown word `{w}`"),
                Some("an address letter is followed by its value, e.g. X10.5 or Z#1"),
            );
        }
        let letter = w.as_bytes()[0] as char;
        let v = l.f_value(letter)?;
        match letter {
            'N' | 'O' => {}
            'G' | 'M' => {
                if let Some(code) = v {
                    let verdict = if letter == 'G' && !l.mill && code.fract() == 0.0 && code >= 0.0
                    {
                        match codes::in_system_a(l.system, code as u32) {
                            codes::InA::Code(c) => {
                                codes::g_verdict(l.dialect, l.mill, f64::from(c))
                            }
                            _ => Verdict::Run,
                        }
                    } else if letter == 'G' {
                        codes::g_verdict(l.dialect, l.mill, code)
                    } else {
                        codes::m_verdict(l.dialect, l.mill, code)
                    };
                    match verdict {
                        Verdict::Run => {}
                        Verdict::Unknown(msg) => l.unknown(at + 1, msg, strict),
                        Verdict::Refused(msg) => {
                            l.out.push((at + 1, Severity::Error, msg, None));
                        }
                    }
                    g65 |= letter == 'G' && code == 65.0;
                    g76 |= letter == 'G'
                        && !l.mill
                        && code.fract() == 0.0
                        && code >= 0.0
                        && codes::in_system_a(l.system, code as u32) == codes::InA::Code(76);
                    mrc |= letter == 'G'
                        && !l.mill
                        && code.fract() == 0.0
                        && code >= 0.0
                        && matches!(
                            codes::in_system_a(l.system, code as u32),
                            codes::InA::Code(71..=74)
                        );
                    m98 |= letter == 'M' && code == 98.0;
                    facts.stops |= letter == 'M' && (code == 2.0 || code == 30.0);
                    m99 |= letter == 'M' && code == 99.0;
                }
            }
            'P' => {
                if let Some(p) = v {
                    p_word = Some((p, at + 1));
                }
            }
            'H' => h_word = Some(v),
            'L' => l_word = true,
            other if codes::address(l.mill, other) => {}
            other => strange.push((at + 1, other)),
        }
    }
    // Every letter passes an argument in a G65 macro call.
    if !g65 {
        // The one-block G76 (Haas, FANUC 0T) reads A (tool angle) and D (first depth).
        strange.retain(|&(_, c)| !(g76 && matches!(c, 'A' | 'D')));
        // The one-block G71..G73 (0T, Haas) read D (depth, divisions); G74 D is refused
        // by name when it runs.
        strange.retain(|&(_, c)| !(mrc && c == 'D'));
        for (col, letter) in strange {
            l.unknown(col, format!("unknown address `{letter}`"), strict);
        }
    }
    if let Some((p, col)) = p_word {
        let p = p.round() as u64;
        match h_word {
            // Macro A jumps: H80 (always) .. H86 jump to block N<P>.
            Some(Some(h)) if g65 && (80.0..=86.0).contains(&h) => facts.gotos.push((p as u32, col)),
            Some(_) => {}
            None if g65 => facts.calls.push((format!("O{p}"), col)),
            None if m98 => {
                let prog = if l_word { p } else { p % 10_000 };
                facts.calls.push((format!("O{prog}"), col));
            }
            None => {}
        }
        // M99 P n returns to block n of the caller: checked at run time.
        let _ = m99;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Siemens 802D.

const SIEMENS_FUNCTIONS: &[&str] = &[
    "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN2", "SQRT", "ABS", "POT", "TRUNC", "ROUND", "LN",
    "EXP",
];
const SIEMENS_WORD_OPS: &[&str] = &["AND", "OR", "XOR", "NOT", "DIV", "MOD"];

impl Line<'_> {
    fn s_expr(&mut self) -> Result<(), Stop> {
        loop {
            while self.eat("-") || self.eat("+") || self.eat("NOT") {}
            self.s_primary()?;
            self.ws();
            let rest = &self.s[self.i..];
            let op2 = ["==", "<>", "<=", ">="]
                .iter()
                .find(|o| rest.starts_with(o.as_bytes()));
            if let Some(o) = op2 {
                self.i += o.len();
                continue;
            }
            match self.peek() {
                Some(b'+' | b'-' | b'*' | b'/' | b'<' | b'>') => self.i += 1,
                Some(c) if c.is_ascii_alphabetic() => {
                    let save = self.i;
                    let w = self.letters();
                    if SIEMENS_WORD_OPS.contains(&w.as_str()) {
                        continue;
                    }
                    // The next word of the block (`X=R1 Z=R2`, `IF R1>2 GOTOF L`).
                    self.i = save;
                    return Ok(());
                }
                _ => return Ok(()),
            }
        }
    }
    fn s_primary(&mut self) -> Result<(), Stop> {
        self.enter()?;
        let r = self.s_primary_inner();
        self.nest -= 1;
        r
    }
    fn s_primary_inner(&mut self) -> Result<(), Stop> {
        match self.peek() {
            Some(b'(') => {
                self.i += 1;
                self.s_expr()?;
                if !self.eat(")") {
                    return self.unexpected("an operator or `)`");
                }
                Ok(())
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                self.number();
                // 802 exponent: 1.5EX-5.
                if self.eat("EX") {
                    let _ = self.eat("-") || self.eat("+");
                    if self.number().is_none() {
                        return self.unexpected("an exponent after EX");
                    }
                }
                Ok(())
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let at = self.i;
                let w = self.letters();
                if w == "R" {
                    if self.number().is_none() {
                        if self.peek() == Some(b'[') {
                            self.i += 1;
                            self.s_expr()?;
                            if !self.eat("]") {
                                return self.unexpected("`]`");
                            }
                            return Ok(());
                        }
                        return self.unexpected("an R parameter number");
                    }
                    return Ok(());
                }
                if !SIEMENS_FUNCTIONS.contains(&w.as_str()) {
                    while self
                        .s
                        .get(self.i)
                        .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_')
                    {
                        self.i += 1;
                    }
                    let save = self.i;
                    if self.peek() != Some(b'(') {
                        // A global user variable of the machine or a cycle's parameter
                        // (`TEST`, `DIA[2]`): the run knows them, or stops at the block.
                        self.i = save;
                        if self.eat("[") {
                            self.s_expr()?;
                            while self.eat(",") {
                                self.s_expr()?;
                            }
                            if !self.eat("]") {
                                return self.unexpected("`]`");
                            }
                        }
                        return Ok(());
                    }
                    return self.error(at + 1, format!("unknown name `{w}` in an expression"), Some("R parameters are R<n>; functions: SIN COS TAN ASIN ACOS ATAN2 SQRT ABS POT TRUNC ROUND LN EXP"));
                }
                if !self.eat("(") {
                    return self.unexpected(&format!("`(` after {w}"));
                }
                self.s_expr()?;
                while self.eat(",") {
                    self.s_expr()?;
                }
                if !self.eat(")") {
                    return self.unexpected("an operator or `)`");
                }
                Ok(())
            }
            _ => self.unexpected("a number, an R parameter, a function or `(`"),
        }
    }
}

/// Siemens facts: `(keyword, label, column)` jumps and called names.
fn siemens_block(
    l: &mut Line,
    strict: bool,
    jumps: &mut Vec<(String, String, usize)>,
    calls: &mut Vec<(String, usize)>,
    find: &mut dyn FnMut(&str) -> bool,
) -> Result<(), Stop> {
    l.ws();
    if l.peek() == Some(b'%') {
        // `%_N_NAME_MPF`: the transfer format's header (the run skips it).
        l.i = l.s.len();
        return Ok(());
    }
    if l.eat("/") && l.s.get(l.i).is_some_and(u8::is_ascii_digit) {
        l.i += 1; // a block-skip level, /1../9
    }
    l.ws();
    if l.s.get(l.i) == Some(&b'N') && l.s.get(l.i + 1).is_some_and(u8::is_ascii_digit) {
        l.i += 1;
        l.number();
    }
    // A label `NAME:`.
    let save = l.i;
    let w = l.letters();
    let mut rest = w.clone();
    while l.i < l.s.len() && (l.s[l.i].is_ascii_alphanumeric() || l.s[l.i] == b'_') {
        rest.push(l.s[l.i] as char);
        l.i += 1;
    }
    if rest.is_empty() || !l.eat(":") {
        l.i = save;
    }
    // `PROC NAME(params)`: a cycle's first block (its parameters are bound by the run).
    {
        let save = l.i;
        if l.letters() == "PROC" {
            l.i = l.s.len();
            return Ok(());
        }
        l.i = save;
    }
    // G74/G75 (reference and fixed point approach): the axes named with any value
    // (`G75 X1=0 Z1=0`, `FP=1`); the run reads the block (`siemens::fixed_point`).
    l.ws();
    let head = &l.s[l.i..];
    if (head.starts_with(b"G74") || head.starts_with(b"G75"))
        && !head
            .get(3)
            .is_some_and(|b| b.is_ascii_digit() || *b == b'.')
    {
        l.i = l.s.len();
        return Ok(());
    }
    while !l.at_end() {
        let at = l.i;
        let Some(c) = l.peek() else { break };
        if !c.is_ascii_alphabetic() && c != b'_' {
            return l.unexpected("a word");
        }
        let mut name = l.letters();
        // A name that goes on with digits and opens an argument list (`MS100("zond", 1)`):
        // a cycle call.
        {
            let mut k = l.i;
            while l
                .s
                .get(k)
                .is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_')
            {
                k += 1;
            }
            let known = name == "CYCLE" && matches!(&l.s[l.i..k], b"97" | b"99" | b"84");
            if k > l.i && name.len() > 1 && l.s.get(k) == Some(&b'(') && !known {
                name.push_str(&String::from_utf8_lossy(&l.s[l.i..k]));
                l.i = k;
                skip_arguments(l)?;
                let _ = find(&name);
                continue;
            }
        }
        match name.as_str() {
            // A tool by name: the 840D's tool management.
            "T" if {
                l.ws();
                l.s[l.i..].starts_with(b"=\"")
            } =>
            {
                return l.error(
                    at + 1,
                    "a tool by name (`T=\"name\"`) is the 840D's tool management, not the 802D's",
                    Some("run the program with --dialect siemens-840d (dialect = \"siemens-840d\" in the job)"),
                );
            }
            // `M3=4`, `S3=1500`: the function or speed of spindle 3 (the run reads it).
            "M" | "S"
                if {
                    let mut k = l.i;
                    while l.s.get(k).is_some_and(u8::is_ascii_digit) {
                        k += 1;
                    }
                    k > l.i && l.s.get(k) == Some(&b'=')
                } =>
            {
                l.number();
                let _ = l.eat("=");
                l.s_expr()?;
            }
            "IF" => {
                l.s_expr()?;
                let kw = l.letters();
                if !matches!(kw.as_str(), "GOTOF" | "GOTOB" | "GOTO") {
                    return l.error(
                        l.i + 1,
                        "expected GOTOF, GOTOB or GOTO after IF condition",
                        None,
                    );
                }
                let target = label_name(l);
                jumps.push((kw, target, at + 1));
                return Ok(());
            }
            "GOTOF" | "GOTOB" | "GOTO" => {
                let target = label_name(l);
                jumps.push((name, target, at + 1));
                return Ok(());
            }
            "RET" => {}
            "R" if l.s.get(l.i).is_some_and(u8::is_ascii_digit) => {
                l.number();
                if !l.eat("=") {
                    return l.error(
                        l.i + 1,
                        "expected `=` after an R parameter",
                        Some("R parameters are set with Rn = expression"),
                    );
                }
                l.s_expr()?;
            }
            addr if codes::siemens_address(addr) => {
                if l.eat("=") {
                    l.s_expr()?;
                } else {
                    let _ = l.eat("-");
                    let v = match l.number() {
                        Some(v) => v,
                        None => return l.unexpected(&format!("a value after `{addr}`")),
                    };
                    if let (Some(code), "G" | "M") = (v, addr) {
                        let verdict = if addr == "G" {
                            codes::g_code(l.dialect, code)
                        } else {
                            codes::m_code(l.dialect, code)
                        };
                        match verdict {
                            Verdict::Run => {}
                            Verdict::Unknown(msg) => l.unknown(at + 1, msg, strict),
                            Verdict::Refused(msg) => {
                                l.out.push((at + 1, Severity::Error, msg, None))
                            }
                        }
                    }
                }
            }
            "CYCLE"
                if l.s[l.i..].starts_with(b"97(")
                    || l.s[l.i..].starts_with(b"99(")
                    || l.s[l.i..].starts_with(b"84(") =>
            {
                // The thread cycles (`siemens_cycles`): their arguments are expressions,
                // any may be left empty.
                l.i += 3;
                loop {
                    l.ws();
                    if !matches!(l.peek(), Some(b',') | Some(b')')) {
                        l.s_expr()?;
                    }
                    if l.eat(")") {
                        break;
                    }
                    if !l.eat(",") {
                        return l.unexpected("`,` or `)`");
                    }
                }
            }
            // Tool radius compensation's approach and retraction (`nose`; KONTC/KONTT are
            // refused by the run).
            "NORM" | "KONT" | "KONTC" | "KONTT" => {}
            // Diameter and radius programming (802D sl and 840D), run.
            "DIAMON" | "DIAMOF" => {}
            // A message to the operator, a preprocessing stop: no motion.
            "MSG" | "STOPRE" => l.i = l.s.len(),
            // G96's spindle speed limit (rev/min), read by the run.
            "LIMS" => {
                l.ws();
                let _ = l.eat("=");
                l.s_expr()?;
            }
            kw if codes::siemens_keyword(kw) => {
                l.unknown(at + 1, format!("`{kw}` is not simulated"), strict);
                // Skip its arguments: `=value`, `(...)` or the rest of the block.
                l.i = l.s.len();
            }
            call if call.len() > 2 => {
                let mut full = call.to_string();
                while l.i < l.s.len() && (l.s[l.i].is_ascii_alphanumeric() || l.s[l.i] == b'_') {
                    full.push(l.s[l.i] as char);
                    l.i += 1;
                }
                l.ws();
                if l.s.get(l.i) == Some(&b'=') && l.s.get(l.i + 1) != Some(&b'=') {
                    // `NAME = value`: a global user variable (GUD) of the machine; the run
                    // warns that the program does not define it.
                    l.i += 1;
                    l.ws();
                    if l.peek() == Some(b'"') {
                        skip_quoted(l);
                    } else {
                        l.s_expr()?;
                    }
                    continue;
                }
                if l.peek() == Some(b'(') {
                    // `NAME(a, "b", ..)`: a cycle called with arguments (strings among
                    // them); the run binds them, or warns when the cycle is not found.
                    skip_arguments(l)?;
                    // Found, it is checked too; not found, the run warns when it reaches it.
                    let _ = find(&full);
                    continue;
                }
                calls.push((full, at + 1));
                if l.eat("P") && l.number().is_none() {
                    return l.unexpected("a repeat count after P");
                }
            }
            // `NAME = value` with a two-letter name: a global user variable (the run warns
            // when no definition file defines it).
            other
                if other.len() > 1 && {
                    l.ws();
                    l.s.get(l.i) == Some(&b'=') && l.s.get(l.i + 1) != Some(&b'=')
                } =>
            {
                l.i += 1;
                l.s_expr()?;
            }
            other => {
                l.unknown(at + 1, format!("unknown address `{other}`"), strict);
                if l.eat("=") {
                    l.s_expr()?;
                } else {
                    let _ = l.eat("-");
                    let _ = l.number();
                }
            }
        }
    }
    Ok(())
}

/// Past a string literal `"..."` (the cursor on its opening quote).
fn skip_quoted(l: &mut Line) {
    l.i += 1;
    while l.i < l.s.len() && l.s[l.i] != b'"' {
        l.i += 1;
    }
    l.i = (l.i + 1).min(l.s.len());
}

/// Past a call's argument list `( .. )` (the cursor on `(`): expressions, strings and empty
/// places, nested brackets.
fn skip_arguments(l: &mut Line) -> Result<(), Stop> {
    let mut depth = 0usize;
    while l.i < l.s.len() {
        match l.s[l.i] {
            b'"' => {
                skip_quoted(l);
                continue;
            }
            b'(' => depth += 1,
            b')' => {
                depth -= 1;
                if depth == 0 {
                    l.i += 1;
                    return Ok(());
                }
            }
            _ => {}
        }
        l.i += 1;
    }
    l.unexpected("`)` closing the call's arguments")
}

fn label_name(l: &mut Line) -> String {
    l.ws();
    let st = l.i;
    while l.i < l.s.len() && (l.s[l.i].is_ascii_alphanumeric() || l.s[l.i] == b'_') {
        l.i += 1;
    }
    String::from_utf8_lossy(&l.s[st..l.i]).into_owned()
}

// ---------------------------------------------------------------------------------------
// Whole programs.

/// What a FANUC/GSK program says of its place in a file (for choosing the main program):
/// the programs it calls by a literal number (`M98 P..`, `G65 P..`) and whether it has an
/// M02 or M30. Blocks that do not read are left out (the check reports them).
pub(super) fn program_facts(prog: &Program, system: codes::GcodeSystem) -> (Vec<String>, bool) {
    let mut calls = Vec::new();
    let mut stops = false;
    for (_, orig, _) in &prog.blocks {
        let mut found = Vec::new();
        let mut l = Line {
            c: Cursor::line(orig, Dialect::Fanuc),
            mill: false,
            system,
            out: &mut found,
        };
        let mut facts = BlockFacts::default();
        let _ = fanuc_block(&mut l, false, &mut facts);
        calls.extend(facts.calls.into_iter().map(|c| c.0));
        stops |= facts.stops;
    }
    (calls, stops)
}

/// Check every block of `prog` and its written-out control flow (`mill`: a FANUC milling
/// program's codes and addresses). `find` says whether a called program exists (in the
/// file or beside it). Diagnostics come in line order.
#[allow(clippy::too_many_arguments)]
pub(super) fn check_program(
    prog: &Program,
    dialect: Dialect,
    mill: bool,
    system: codes::GcodeSystem,
    strict: bool,
    macros: &std::collections::HashMap<String, String>,
    find: &mut dyn FnMut(&str) -> bool,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut loops: Vec<(u32, usize, usize)> = Vec::new(); // (n, line, col) of open WHILEs
    for (idx, (line, orig, _)) in prog.blocks.iter().enumerate() {
        let mut found = Vec::new();
        // Siemens macros of the definition files are read as the run reads them.
        let text = super::siemens_defs::expand(orig, macros);
        let mut l = Line {
            c: Cursor::line(&text, dialect),
            mill,
            system,
            out: &mut found,
        };
        let diag =
            |col: usize, severity: Severity, message: String, hint: Option<String>| Diagnostic {
                severity,
                file: prog.name.clone(),
                line: *line,
                col: char_col(orig, col),
                message,
                hint,
                snippet: orig.clone(),
                stack: Vec::new(),
            };
        match dialect {
            // 840D blocks are checked by `siemens_flow::check` below and as they run.
            Dialect::Siemens840d => {}
            Dialect::Siemens802d => {
                let mut jumps = Vec::new();
                let mut calls = Vec::new();
                let _ = siemens_block(&mut l, strict, &mut jumps, &mut calls, find);
                for (kw, target, col) in jumps {
                    match prog.labels.get(&target) {
                        None => found.push((
                            col,
                            Severity::Warning,
                            format!("label `{target}` not found in {}", prog.name),
                            Some("a label is written `NAME:` at the start of a block; the run stops here if the jump is taken".into()),
                        )),
                        Some(&to) if kw == "GOTOF" && to <= idx => found.push((
                            col,
                            Severity::Error,
                            format!("GOTOF jumps forward, but `{target}` is above"),
                            Some("use GOTOB (or GOTO)".into()),
                        )),
                        Some(&to) if kw == "GOTOB" && to > idx => found.push((
                            col,
                            Severity::Error,
                            format!("GOTOB jumps back, but `{target}` is below"),
                            Some("use GOTOF (or GOTO)".into()),
                        )),
                        Some(_) => {}
                    }
                }
                for (name, col) in calls {
                    if !find(&name) {
                        found.push((
                            col,
                            Severity::Warning,
                            format!("subprogram `{name}` not found (in this file or as {name}.SPF beside it)"),
                            Some("a control alarms only when the call or jump is reached, and so does vpcut".into()),
                        ));
                    }
                }
            }
            Dialect::Linuxcnc => {
                // Comments and characters only (the O-word language is the interpreter's).
                while !l.at_end() {
                    l.i += 1;
                }
            }
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Okuma => {
                let mut facts = BlockFacts::default();
                let _ = fanuc_block(&mut l, strict, &mut facts);
                for (n, col) in facts.gotos {
                    if !prog.numbers.contains_key(&n) {
                        found.push((
                            col,
                            Severity::Warning,
                            format!("no block N{n} in {}", prog.name),
                            Some("a control alarms only when the call or jump is reached, and so does vpcut".into()),
                        ));
                    }
                }
                for (n, col) in facts.whiles {
                    loops.push((n, *line, col));
                }
                for (n, col) in facts.ends {
                    match loops.iter().rposition(|o| o.0 == n) {
                        Some(k) => {
                            if k + 1 != loops.len() {
                                found.push((
                                    col,
                                    Severity::Error,
                                    format!(
                                        "END{n} closes DO{n} while an inner loop is still open"
                                    ),
                                    Some("WHILE loops nest and never cross".into()),
                                ));
                            }
                            loops.truncate(k);
                        }
                        None => found.push((
                            col,
                            Severity::Error,
                            format!("END{n} without DO{n}"),
                            None,
                        )),
                    }
                }
                for (name, col) in facts.calls {
                    if !find(&name) {
                        found.push((
                            col,
                            Severity::Warning,
                            format!(
                                "subprogram {} not found (in this file or as {0} beside it)",
                                codes::fanuc_file_name(&name)
                            ),
                            Some("a control alarms only when the call or jump is reached, and so does vpcut".into()),
                        ));
                    }
                }
            }
        }
        out.extend(
            found
                .into_iter()
                .map(|(col, sev, msg, hint)| diag(col, sev, msg, hint)),
        );
    }
    if dialect == Dialect::Siemens840d {
        out.extend(super::siemens_flow::check(prog));
    }
    for (n, line, col) in loops {
        let orig = prog
            .blocks
            .iter()
            .find(|b| b.0 == line)
            .map_or(String::new(), |b| b.1.clone());
        out.push(Diagnostic {
            severity: Severity::Error,
            file: prog.name.clone(),
            line,
            col,
            message: format!("WHILE .. DO{n} without END{n}"),
            hint: Some(format!("close the loop with END{n}")),
            snippet: orig,
            stack: Vec::new(),
        });
    }
    out
}
