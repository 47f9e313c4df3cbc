//! Siemens 840D structured control flow (`controllers.md` 6; SINUMERIK 840D sl Programming
//! Manual, "Program sequence control", "Control structures"): `IF/ELSE/ENDIF`,
//! `WHILE/ENDWHILE`, `FOR/ENDFOR`, `REPEAT/UNTIL` and `LOOP/ENDLOOP`, each keyword first in
//! its block (after the block number and a label).
//!
//! The run keeps no loop stack: each keyword finds its partner by scanning the program's
//! blocks with the nesting counted, so that a `GOTOF` out of a loop leaves nothing behind
//! (as on the control, where the structure is fixed when the program is loaded). `check`
//! reports unmatched keywords of every program before anything runs.

use super::{Diagnostic, Program, Severity};

/// A structure keyword that opens, continues or closes a block structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kw {
    If,
    Else,
    EndIf,
    While,
    EndWhile,
    For,
    EndFor,
    Repeat,
    Until,
    Loop,
    EndLoop,
}

impl Kw {
    fn name(self) -> &'static str {
        match self {
            Kw::If => "IF",
            Kw::Else => "ELSE",
            Kw::EndIf => "ENDIF",
            Kw::While => "WHILE",
            Kw::EndWhile => "ENDWHILE",
            Kw::For => "FOR",
            Kw::EndFor => "ENDFOR",
            Kw::Repeat => "REPEAT",
            Kw::Until => "UNTIL",
            Kw::Loop => "LOOP",
            Kw::EndLoop => "ENDLOOP",
        }
    }
    /// The keyword that closes the structure this one opens.
    fn closer(self) -> Option<Kw> {
        match self {
            Kw::If => Some(Kw::EndIf),
            Kw::While => Some(Kw::EndWhile),
            Kw::For => Some(Kw::EndFor),
            Kw::Repeat => Some(Kw::Until),
            Kw::Loop => Some(Kw::EndLoop),
            _ => None,
        }
    }
    fn opener(self) -> Option<Kw> {
        match self {
            Kw::EndIf | Kw::Else => Some(Kw::If),
            Kw::EndWhile => Some(Kw::While),
            Kw::EndFor => Some(Kw::For),
            Kw::Until => Some(Kw::Repeat),
            Kw::EndLoop => Some(Kw::Loop),
            _ => None,
        }
    }
}

/// The words of a block's text (letters, digits, `_`), upper case as the blocks are.
fn words(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
}

/// The byte offset of the block's first word after its block number and label.
pub(super) fn head_offset(text: &str) -> usize {
    let b = text.as_bytes();
    let mut i = 0;
    let skip_ws = |i: &mut usize| {
        while *i < b.len() && b[*i].is_ascii_whitespace() {
            *i += 1;
        }
    };
    skip_ws(&mut i);
    if b.get(i) == Some(&b'N') && b.get(i + 1).is_some_and(u8::is_ascii_digit) {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        skip_ws(&mut i);
    }
    let st = i;
    let mut j = i;
    while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
        j += 1;
    }
    if j > st && b.get(j) == Some(&b':') {
        i = j + 1;
        skip_ws(&mut i);
    }
    i
}

/// The structure keyword a block starts with (an `IF` with a `GOTO..` in its block is the
/// 802D conditional jump, not a structure).
pub(super) fn keyword(text: &str) -> Option<Kw> {
    let rest = &text[head_offset(text)..];
    let first = words(rest).next()?;
    // The keyword must be the whole first word (`IFX` is not `IF`).
    if !rest.starts_with(first) {
        return None;
    }
    Some(match first {
        "IF" => {
            if words(rest).any(|w| matches!(w, "GOTOF" | "GOTOB" | "GOTO" | "GOTOC")) {
                return None;
            }
            Kw::If
        }
        "ELSE" => Kw::Else,
        "ENDIF" => Kw::EndIf,
        "WHILE" => Kw::While,
        "ENDWHILE" => Kw::EndWhile,
        "FOR" => Kw::For,
        "ENDFOR" => Kw::EndFor,
        "REPEAT" => Kw::Repeat,
        "UNTIL" => Kw::Until,
        "LOOP" => Kw::Loop,
        "ENDLOOP" => Kw::EndLoop,
        _ => return None,
    })
}

/// The block of the keyword that answers the one at `pc`: forward for an opener (to its
/// closer, or for `IF` to its `ELSE` when `else_too`), backward for a closer (to its
/// opener). `None` when it is missing (the static check reports it first).
pub(super) fn partner(prog: &Program, pc: usize, else_too: bool) -> Option<usize> {
    let kw = keyword(&prog.blocks[pc].2)?;
    if let Some(close) = kw.closer() {
        let mut depth = 0usize;
        for k in pc + 1..prog.blocks.len() {
            match keyword(&prog.blocks[k].2) {
                Some(o) if o == kw => depth += 1,
                Some(Kw::Else) if kw == Kw::If && depth == 0 && else_too => return Some(k),
                Some(c) if c == close => {
                    if depth == 0 {
                        return Some(k);
                    }
                    depth -= 1;
                }
                _ => {}
            }
        }
        return None;
    }
    if kw == Kw::Else {
        // ELSE reached from its IF branch: on to the ENDIF.
        let mut depth = 0usize;
        for k in pc + 1..prog.blocks.len() {
            match keyword(&prog.blocks[k].2) {
                Some(Kw::If) => depth += 1,
                Some(Kw::EndIf) => {
                    if depth == 0 {
                        return Some(k);
                    }
                    depth -= 1;
                }
                _ => {}
            }
        }
        return None;
    }
    let open = kw.opener()?;
    let mut depth = 0usize;
    for k in (0..pc).rev() {
        match keyword(&prog.blocks[k].2) {
            Some(c) if c == kw => depth += 1,
            Some(o) if o == open => {
                if depth == 0 {
                    return Some(k);
                }
                depth -= 1;
            }
            _ => {}
        }
    }
    None
}

/// Every structure keyword of `prog` without its partner, or closing across another
/// structure: errors, found before anything runs.
pub(super) fn check(prog: &Program) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut open: Vec<(Kw, usize)> = Vec::new();
    let diag = |k: usize, message: String, hint: &str| {
        let (line, orig, text) = &prog.blocks[k];
        let at = head_offset(text);
        let col = orig
            .to_ascii_uppercase()
            .find(text.as_str())
            .map_or(1, |o| o + at + 1);
        Diagnostic {
            severity: Severity::Error,
            file: prog.name.clone(),
            line: *line,
            col,
            message,
            hint: Some(hint.to_string()),
            snippet: orig.clone(),
            stack: Vec::new(),
        }
    };
    for (k, (_, _, text)) in prog.blocks.iter().enumerate() {
        let Some(kw) = keyword(text) else { continue };
        if kw.closer().is_some() {
            open.push((kw, k));
            continue;
        }
        let want = kw.opener().expect("a closer or ELSE");
        match open.last() {
            Some(&(o, _)) if o == want => {
                if kw != Kw::Else {
                    open.pop();
                }
            }
            Some(&(o, _)) => out.push(diag(
                k,
                format!(
                    "{} closes {} while {} is still open",
                    kw.name(),
                    want.name(),
                    o.name()
                ),
                "structures nest and never cross: close the inner one first",
            )),
            None => out.push(diag(
                k,
                format!("{} without {}", kw.name(), want.name()),
                "control structures stay within one program",
            )),
        }
    }
    for (kw, k) in open {
        let close = kw.closer().expect("an opener");
        out.push(diag(
            k,
            format!("{} without {}", kw.name(), close.name()),
            &format!("close it with {}", close.name()),
        ));
    }
    out
}
