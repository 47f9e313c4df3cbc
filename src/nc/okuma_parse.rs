//! Okuma OSP-P program text into blocks (5238-E section 2, "Program format"): the `$NAME.MIN%`
//! header line and `%` skipped, `O` names starting programs, `( )` comments, `/` block skip,
//! `N` sequence names, address words with numbers or `=` expressions, assignments
//! `NAME=expr`, and the statements `IF [..] N..`, `GOTO N..`, `CALL O.. Q.. NAME=..`, `RTS`.
//! Columns are 0-based character positions of the line (comments are blanked, not removed).

use super::okuma_expr::{var_of, Var};
use super::{Diagnostic, Severity, Source};
use std::collections::HashMap;

type Fail = super::expr::Fail;

/// A value written in a word: a number, or `=` and an expression evaluated when the block
/// runs.
#[derive(Clone, Debug)]
pub(super) enum Val {
    Num(f64),
    Expr(String, usize),
}

/// One item of a block.
#[derive(Clone, Debug)]
pub(super) enum Item {
    /// An address word: letter, value, column of the letter.
    Word(char, Val, usize),
    /// `NAME=expr`.
    Assign(Var, String, usize),
    /// `IF [cond] N..` (or `IF [cond] GOTO N..`): condition, its column, the target.
    If(String, usize, String),
    /// `GOTO N..`.
    Goto(String),
    /// `CALL O.. [Q..] [NAME=..]`: program, repeats, arguments.
    Call(String, Option<Val>, Vec<(Var, String, usize)>),
    /// `RTS`.
    Rts,
}

/// A block: its line, the original text, the items and whether it starts with `/`.
#[derive(Clone, Debug)]
pub(super) struct Block {
    pub(super) line: usize,
    pub(super) orig: String,
    pub(super) items: Vec<Item>,
    pub(super) skip: bool,
}

/// A program: name, file, blocks, sequence names to block indices.
#[derive(Debug)]
pub(super) struct Prog {
    pub(super) name: String,
    pub(super) file: String,
    pub(super) blocks: Vec<Block>,
    pub(super) labels: HashMap<String, usize>,
}

/// Blank `( .. )` comments (keeping columns) and upper-case the rest.
fn clean(line: &str) -> String {
    let mut depth = 0;
    line.chars()
        .map(|c| match c {
            '(' => {
                depth += 1;
                ' '
            }
            ')' if depth > 0 => {
                depth -= 1;
                ' '
            }
            _ if depth > 0 => ' ',
            c => c.to_ascii_uppercase(),
        })
        .collect()
}

/// A run of letters and digits from `i`.
fn alnum(s: &[char], i: usize) -> String {
    s[i..]
        .iter()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect()
}

/// An expression's text from `i` (up to white space outside brackets), or the column where
/// a bracket is left open.
fn expr_at(s: &[char], i: usize) -> Result<String, Fail> {
    let e = expr_text(s, i);
    let open = e.chars().filter(|c| *c == '[').count();
    let close = e.chars().filter(|c| *c == ']').count();
    if open > close {
        return Err((
            i + e.chars().count(),
            "expected `]` closing the bracket".into(),
        ));
    }
    Ok(e)
}

/// An expression's text from `i`: up to white space outside brackets.
fn expr_text(s: &[char], i: usize) -> String {
    let mut depth = 0i32;
    let mut out = String::new();
    for &c in &s[i..] {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            ' ' | '\t' if depth <= 0 => break,
            _ => {}
        }
        out.push(c);
    }
    out
}

/// A plain number from `i` (`-1.5`, `.5`, `100`): its text, or `None`.
fn number_text(s: &[char], i: usize) -> Option<String> {
    let mut j = i;
    if s.get(j).is_some_and(|c| *c == '+' || *c == '-') {
        j += 1;
    }
    let digits_from = j;
    while s.get(j).is_some_and(|c| c.is_ascii_digit() || *c == '.') {
        j += 1;
    }
    let t: String = s[i..j].iter().collect();
    (s[digits_from..j].iter().any(|c| c.is_ascii_digit())).then_some(t)
}

/// The `N` label after `IF [..]` / `GOTO` at `i` (white space skipped): `(label, next i)`.
fn label_at(s: &[char], mut i: usize) -> Result<(String, usize), Fail> {
    while s.get(i).is_some_and(|c| *c == ' ' || *c == '\t') {
        i += 1;
    }
    if s.get(i) != Some(&'N') || alnum(s, i + 1).is_empty() {
        return Err((i, "expected a sequence name such as `N100`".into()));
    }
    let l = alnum(s, i);
    Ok((l.clone(), i + l.len()))
}

/// Parse one block's cleaned text into its label and items.
fn parse_block(text: &str) -> Result<(Option<String>, bool, Vec<Item>), Fail> {
    let s: Vec<char> = text.chars().collect();
    let mut i = 0;
    let ws = |i: &mut usize| {
        while s.get(*i).is_some_and(|c| *c == ' ' || *c == '\t') {
            *i += 1;
        }
    };
    ws(&mut i);
    let mut skip = false;
    if s.get(i) == Some(&'/') {
        skip = true;
        i += 1;
        ws(&mut i);
    }
    let mut label = None;
    if s.get(i) == Some(&'N') && s.get(i + 1).is_some_and(|c| c.is_ascii_alphanumeric()) {
        let l = alnum(&s, i);
        if s.get(i + l.len()) != Some(&'=') {
            i += l.len();
            label = Some(l);
        }
    }
    let mut items = Vec::new();
    loop {
        ws(&mut i);
        let Some(&c) = s.get(i) else { break };
        if !c.is_ascii_alphabetic() {
            return Err((
                i,
                format!("unexpected `{c}`: expected an address letter, a variable or a statement"),
            ));
        }
        let letters: String = s[i..]
            .iter()
            .take_while(|c| c.is_ascii_alphabetic())
            .collect();
        if letters.len() == 1 {
            let j = i + 1;
            if s.get(j) == Some(&'=') {
                let e = expr_at(&s, j + 1)?;
                if e.is_empty() {
                    return Err((j + 1, format!("expected an expression after `{c}=`")));
                }
                items.push(Item::Word(c, Val::Expr(e.clone(), j + 1), i));
                i = j + 1 + e.len();
            } else {
                let t = number_text(&s, j).ok_or((
                    j,
                    format!("expected a number after `{c}` (or `{c}=` and an expression)"),
                ))?;
                let v = t
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && v.abs() < 1e9)
                    .ok_or((j, format!("`{t}` is not a number vpcut can use (at most 9 digits before the point)")))?;
                items.push(Item::Word(c, Val::Num(v), i));
                i = j + t.len();
            }
            continue;
        }
        match letters.as_str() {
            "IF" => {
                let mut j = i + 2;
                ws(&mut j);
                if s.get(j) != Some(&'[') {
                    return Err((j, "expected `[` and a condition after IF".into()));
                }
                let e = expr_at(&s, j)?;
                if !e.ends_with(']') {
                    return Err((j, "expected `]` closing the IF condition".into()));
                }
                let cond_col = j;
                j += e.len();
                let mut k = j;
                ws(&mut k);
                if alnum(&s, k) == "GOTO" {
                    j = k + 4;
                }
                let (l, next) = label_at(&s, j)?;
                items.push(Item::If(e, cond_col, l));
                i = next;
            }
            "GOTO" => {
                let (l, next) = label_at(&s, i + 4)?;
                items.push(Item::Goto(l));
                i = next;
            }
            "RTS" => {
                items.push(Item::Rts);
                i += 3;
            }
            "CALL" => {
                let mut j = i + 4;
                ws(&mut j);
                let name = alnum(&s, j);
                if !name.starts_with('O') || name.len() < 2 {
                    return Err((
                        j,
                        "expected a program name such as `OSUB1` after CALL".into(),
                    ));
                }
                j += name.len();
                let mut q = None;
                let mut args = Vec::new();
                loop {
                    ws(&mut j);
                    if j >= s.len() {
                        break;
                    }
                    let n = alnum(&s, j);
                    if n.is_empty() {
                        return Err((
                            j,
                            "expected `Q` (repeats) or an argument `NAME=value`".into(),
                        ));
                    }
                    if n == "Q"
                        || (n.starts_with('Q') && n[1..].chars().all(|c| c.is_ascii_digit()))
                            && s.get(j + n.len()) != Some(&'=')
                    {
                        let t = number_text(&s, j + 1)
                            .ok_or((j + 1, "expected a count after Q".to_string()))?;
                        q = Some(Val::Num(
                            t.parse()
                                .map_err(|_| (j + 1, format!("`{t}` is not a number")))?,
                        ));
                        j += 1 + t.len();
                        continue;
                    }
                    if s.get(j + n.len()) != Some(&'=') {
                        return Err((
                            j,
                            format!("expected `{n}=` and a value: an argument of the call"),
                        ));
                    }
                    let var = var_of(&n).ok_or((j, format!("`{n}` is not a variable name")))?;
                    let e = expr_at(&s, j + n.len() + 1)?;
                    args.push((var, e.clone(), j + n.len() + 1));
                    j += n.len() + 1 + e.len();
                }
                items.push(Item::Call(name, q, args));
                i = j;
            }
            _ => {
                let name = alnum(&s, i);
                let mut j = i + name.len();
                ws(&mut j);
                if s.get(j) != Some(&'=') {
                    return Err((i, format!("unknown word `{name}`: expected an address letter, `NAME=` (a variable), IF, GOTO, CALL or RTS")));
                }
                let var = var_of(&name).ok_or((i, format!("`{name}` is not a variable name")))?;
                j += 1;
                ws(&mut j);
                let e = expr_at(&s, j)?;
                if e.is_empty() {
                    return Err((j, format!("expected an expression after `{name}=`")));
                }
                items.push(Item::Assign(var, e.clone(), j));
                i = j + e.len();
            }
        }
    }
    Ok((label, skip, items))
}

/// Split a file into programs: the `$NAME.MIN%` header line and `%` are skipped, an `O`
/// name at the start of a line starts a program (the text before the first is a program
/// named after the file). Parse errors are collected, not fatal here.
pub(super) fn load(src: &Source, errors: &mut Vec<Diagnostic>) -> Vec<Prog> {
    let mut progs: Vec<Prog> = Vec::new();
    let stem = src
        .name
        .rsplit('/')
        .next()
        .unwrap_or(&src.name)
        .split('.')
        .next()
        .unwrap_or("")
        .to_ascii_uppercase();
    let mut cur = Prog {
        name: stem,
        file: src.name.clone(),
        blocks: Vec::new(),
        labels: HashMap::new(),
    };
    for (n, raw) in src.text.lines().enumerate() {
        let line = n + 1;
        let trimmed = raw.trim();
        if trimmed.starts_with('$') || trimmed.is_empty() {
            continue;
        }
        let mut text = clean(raw);
        if let Some(k) = text.find('%') {
            text.truncate(k);
        }
        if text.trim().is_empty() {
            continue;
        }
        let t = text.trim_start();
        if t.starts_with('O') && t[1..].starts_with(|c: char| c.is_ascii_alphanumeric()) {
            let name: String = t
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric())
                .collect();
            let rest = &t[name.len()..];
            if !rest.trim().is_empty() && !rest.starts_with(' ') {
                // `OSUB=..` is not a program name; let the block parser say why.
            } else {
                if !cur.blocks.is_empty() || !progs.is_empty() || cur.name != name {
                    let done = std::mem::replace(
                        &mut cur,
                        Prog {
                            name: name.clone(),
                            file: src.name.clone(),
                            blocks: Vec::new(),
                            labels: HashMap::new(),
                        },
                    );
                    if !done.blocks.is_empty() {
                        progs.push(done);
                    }
                }
                if rest.trim().is_empty() {
                    continue;
                }
                let pad = text.len() - rest.len();
                text = format!("{}{}", " ".repeat(pad), rest);
            }
        }
        match parse_block(&text) {
            Ok((label, skip, items)) => {
                if let Some(l) = label {
                    cur.labels.entry(l).or_insert(cur.blocks.len());
                }
                cur.blocks.push(Block {
                    line,
                    orig: raw.to_string(),
                    items,
                    skip,
                });
            }
            Err((col, message)) => errors.push(diag(
                Severity::Error,
                &src.name,
                line,
                col + 1,
                message,
                raw,
                None,
            )),
        }
    }
    if !cur.blocks.is_empty() || progs.is_empty() {
        progs.push(cur);
    }
    progs
}

pub(super) fn diag(
    severity: Severity,
    file: &str,
    line: usize,
    col: usize,
    message: String,
    snippet: &str,
    hint: Option<String>,
) -> Diagnostic {
    Diagnostic {
        severity,
        file: file.to_string(),
        line,
        col,
        message,
        hint,
        snippet: snippet.to_string(),
        stack: Vec::new(),
    }
}
