//! The one lexer of every dialect: a cursor over one block's text with byte spans mapped
//! back to the columns of the line, used by the static check (`check`), the FANUC/Siemens
//! expression reader (`expr`) and the LinuxCNC one (`lcnc_expr`).
//!
//! The dialects differ in what the cursor skips between tokens ([`Blanks`]): the
//! interpreters of FANUC and Siemens blocks skip white space (comments are already gone);
//! the static check sees the original line (upper-cased) and skips blanks, FANUC-syntax
//! `( )` comments and what follows `;`; LinuxCNC lines are read as rs274 reads them, with
//! their white space removed up front, the columns kept in a span map. Brackets (`[ ]` or
//! `( )`) and variables (`#`, `R`, `#<name>`) are the readers' business: they ask the
//! cursor for the next character, number or name.

use super::Dialect;
use std::borrow::Cow;

/// How deep expressions may nest (brackets, signs, functions) in every dialect's reader.
pub(super) const MAX_NEST: usize = 100;

/// What the cursor skips between tokens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Blanks {
    /// ASCII white space (a block whose comments are already removed).
    White,
    /// Blanks and tabs; `( )` comments when `comments` (FANUC syntax); `;` and `\r` end the
    /// line. An unclosed comment is recorded in [`Cursor::unclosed`].
    Line {
        /// `( )` are comments (FANUC, GSK, LinuxCNC), not brackets (Siemens).
        comments: bool,
    },
    /// Nothing: the white space was removed when the cursor was made (LinuxCNC).
    Removed,
}

/// A byte range `start..end` of the cursor's text.
pub(super) type Span = (usize, usize);

/// A cursor over one block's text.
pub(super) struct Cursor<'a> {
    /// The text (upper-cased or with white space removed where the mode says so).
    pub(super) s: Cow<'a, [u8]>,
    /// 1-based column in the line of each byte of `s`; empty when byte `i` is column
    /// `i + 1`.
    cols: Vec<usize>,
    /// The position.
    pub(super) i: usize,
    /// The dialect being read.
    pub(super) dialect: Dialect,
    /// What is skipped between tokens.
    blanks: Blanks,
    /// Values being read inside each other (bounded: no block can exhaust the stack).
    pub(super) nest: usize,
    /// Byte offsets of comments opened and not closed (`Blanks::Line`), in the order met.
    pub(super) unclosed: Vec<usize>,
}

impl<'a> Cursor<'a> {
    /// A block as the FANUC/Siemens interpreters read it: white space between tokens.
    pub(super) fn new(s: &'a str, dialect: Dialect) -> Cursor<'a> {
        Cursor {
            s: Cow::Borrowed(s.as_bytes()),
            cols: Vec::new(),
            i: 0,
            dialect,
            blanks: Blanks::White,
            nest: 0,
            unclosed: Vec::new(),
        }
    }

    /// The original line as the static check reads it: upper-cased, comments skipped.
    pub(super) fn line(orig: &str, dialect: Dialect) -> Cursor<'static> {
        Cursor {
            s: Cow::Owned(orig.to_ascii_uppercase().into_bytes()),
            cols: Vec::new(),
            i: 0,
            dialect,
            blanks: Blanks::Line {
                comments: !matches!(dialect, Dialect::Siemens802d | Dialect::Siemens840d),
            },
            nest: 0,
            unclosed: Vec::new(),
        }
    }

    /// A LinuxCNC line (upper-cased, comments blanked, columns as in the file) with its
    /// white space removed.
    pub(super) fn squeezed(text: &str) -> Cursor<'static> {
        let mut s = Vec::with_capacity(text.len());
        let mut cols = Vec::with_capacity(text.len());
        for (k, b) in text.bytes().enumerate() {
            if !b.is_ascii_whitespace() {
                s.push(b);
                cols.push(k + 1);
            }
        }
        Cursor {
            s: Cow::Owned(s),
            cols,
            i: 0,
            dialect: Dialect::Linuxcnc,
            blanks: Blanks::Removed,
            nest: 0,
            unclosed: Vec::new(),
        }
    }

    /// The dialect's expression brackets: `( )` on Siemens, `[ ]` elsewhere.
    pub(super) fn brackets(&self) -> (&'static str, &'static str) {
        match self.dialect {
            Dialect::Siemens802d | Dialect::Siemens840d => ("(", ")"),
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc | Dialect::Okuma => ("[", "]"),
        }
    }

    /// Skip what lies between tokens.
    pub(super) fn ws(&mut self) {
        match self.blanks {
            Blanks::Removed => {}
            Blanks::White => {
                while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
                    self.i += 1;
                }
            }
            Blanks::Line { comments } => loop {
                while self.i < self.s.len() && (self.s[self.i] == b' ' || self.s[self.i] == b'\t') {
                    self.i += 1;
                }
                // Comments are skipped here so that columns stay those of the original line.
                match self.s.get(self.i) {
                    Some(b'(') if comments => {
                        let start = self.i;
                        let mut depth = 0;
                        while self.i < self.s.len() {
                            match self.s[self.i] {
                                b'(' => depth += 1,
                                b')' => depth -= 1,
                                _ => {}
                            }
                            self.i += 1;
                            if depth == 0 {
                                break;
                            }
                        }
                        if depth != 0 {
                            self.unclosed.push(start);
                        }
                    }
                    Some(b';') | Some(b'\r') => self.i = self.s.len(),
                    _ => return,
                }
            },
        }
    }

    /// The next byte after what is skipped.
    pub(super) fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }

    /// The byte `k` places ahead (nothing skipped).
    pub(super) fn peek_at(&self, k: usize) -> Option<u8> {
        self.s.get(self.i + k).copied()
    }

    /// Nothing but what is skipped is left.
    pub(super) fn done(&mut self) -> bool {
        self.peek().is_none()
    }

    /// Read `t` if it comes next.
    pub(super) fn eat(&mut self, t: &str) -> bool {
        self.ws();
        if self.s[self.i..].starts_with(t.as_bytes()) {
            self.i += t.len();
            true
        } else {
            false
        }
    }

    /// What stands at the cursor, for a message.
    pub(super) fn here(&self) -> String {
        if self.i >= self.s.len() {
            return match self.blanks {
                Blanks::Removed => "the end of the line".into(),
                _ => "the end of the block".into(),
            };
        }
        describe_char(char_at(&self.s, self.i))
    }

    /// The 1-based column of the cursor.
    pub(super) fn col(&self) -> usize {
        self.col_at(self.i)
    }

    /// The 1-based column of byte `i` (one past the last character at the end).
    pub(super) fn col_at(&self, i: usize) -> usize {
        if self.cols.is_empty() {
            return match self.blanks {
                Blanks::Removed => 1,
                _ => i + 1,
            };
        }
        match self.cols.get(i) {
            Some(&c) => c,
            None => self.cols.last().map_or(1, |c| c + 1),
        }
    }

    /// An error at the cursor.
    pub(super) fn err<T>(&self, msg: impl Into<String>) -> Result<T, (usize, String)> {
        Err((self.col(), msg.into()))
    }

    /// The text of a span.
    pub(super) fn text(&self, (start, end): Span) -> String {
        String::from_utf8_lossy(&self.s[start..end]).into_owned()
    }

    /// Read while `f` holds; the span read.
    fn take_while(&mut self, f: impl Fn(u8) -> bool) -> Span {
        let st = self.i;
        while self.i < self.s.len() && f(self.s[self.i]) {
            self.i += 1;
        }
        (st, self.i)
    }

    /// Letters and `_` (a keyword, function or address name).
    pub(super) fn ident(&mut self) -> String {
        self.ws();
        let span = self.take_while(|b| b.is_ascii_alphabetic() || b == b'_');
        self.text(span)
    }

    /// Letters, digits and `_` (a Siemens label or program name).
    pub(super) fn name_with_digits(&mut self) -> String {
        self.ws();
        let span = self.take_while(|b| b.is_ascii_alphanumeric() || b == b'_');
        self.text(span)
    }

    /// The digits and points of a number, unread; `None` when none come next.
    pub(super) fn number_span(&mut self) -> Option<Span> {
        self.ws();
        let span = self.take_while(|b| b.is_ascii_digit() || b == b'.');
        (span.0 != span.1).then_some(span)
    }

    /// An unsigned decimal number (`12`, `12.`, `.5`, `1.5`); nothing read when malformed.
    pub(super) fn number(&mut self) -> Option<f64> {
        let (st, end) = self.number_span()?;
        match ascii_number(&self.s[st..end]) {
            Some(v) => Some(v),
            None => {
                self.i = st;
                None
            }
        }
    }

    /// The name inside `<..>` after `#` or `O` (the `<` already read).
    pub(super) fn angle_name(&mut self) -> Result<String, (usize, String)> {
        let st = self.i;
        while self.peek().is_some_and(|b| b != b'>') {
            self.i += 1;
        }
        if !self.eat(">") {
            return Err((self.col_at(st), "expected `>` closing the name".into()));
        }
        let name = self.text((st, self.i - 1));
        if name.is_empty() {
            return Err((
                self.col_at(st),
                "expected a name between `<` and `>`".into(),
            ));
        }
        Ok(name)
    }
}

/// How a character reads in a message: itself in backquotes, or its code for a NUL,
/// another control character or a character that is not ASCII.
pub(super) fn describe_char(c: char) -> String {
    match c {
        '\0' => "a NUL byte (0x00)".to_string(),
        c if c.is_ascii_control() => format!("a control character (0x{:02X})", c as u32),
        c if !c.is_ascii() => {
            let latin1 = if (c as u32) < 0x100 {
                format!("; the byte 0x{:02X} in a Latin-1 file", c as u32)
            } else {
                String::new()
            };
            format!(
                "a character that is not ASCII, `{c}` (U+{:04X}{latin1})",
                c as u32
            )
        }
        c => format!("`{c}`"),
    }
}

/// A 1-based column counted in bytes of `line` as one counted in characters (0 stays 0:
/// the whole block).
pub(super) fn char_col(line: &str, col: usize) -> usize {
    if col <= 1 {
        return col;
    }
    match line.get(..(col - 1).min(line.len())) {
        Some(before) => before.chars().count() + 1,
        None => col,
    }
}

/// The character starting at byte `i` of `s` (valid UTF-8 from a char boundary).
pub(super) fn char_at(s: &[u8], i: usize) -> char {
    let end = (i + 4).min(s.len());
    let bytes = &s[i.min(end)..end];
    match std::str::from_utf8(bytes) {
        Ok(t) => t.chars().next(),
        Err(e) => std::str::from_utf8(&bytes[..e.valid_up_to()])
            .ok()
            .and_then(|t| t.chars().next()),
    }
    .unwrap_or(char::from(bytes.first().copied().unwrap_or(b' ')))
}

/// An unsigned decimal of ASCII digits and at most one point (`12`, `12.`, `.5`, `1.5`).
/// Up to 15 digits and 22 decimals it is the integer of all digits divided by a power of
/// ten: one division of two exact values, so correctly rounded, as `str::parse` is (which
/// takes the rest). The interpreters read numbers in every executed block: this is their
/// hot path.
pub(super) fn ascii_number(b: &[u8]) -> Option<f64> {
    let mut int: u64 = 0;
    let mut digits = 0;
    let mut decimals = None;
    for &c in b {
        match c {
            b'0'..=b'9' => {
                int = int.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                digits += 1;
                if let Some(d) = decimals.as_mut() {
                    *d += 1;
                }
            }
            b'.' if decimals.is_none() => decimals = Some(0),
            _ => return None,
        }
    }
    if digits == 0 {
        return None;
    }
    let k: i32 = decimals.unwrap_or(0);
    if digits <= 15 && k <= 22 {
        return Some(int as f64 / 10f64.powi(k));
    }
    std::str::from_utf8(b).ok()?.parse().ok()
}
