//! The one diagnostic type ([`Diagnostic`], with its [`Severity`]) and its one renderer:
//! job errors ([`crate::JobError`]) and NC program errors and warnings are all shown by
//! [`render`], through `codespan-reporting`, as plain text without colour:
//!
//! ```text
//! error: `blank.diameter`: expected a number > 0, got -20
//!   --> job.toml:3:12
//!   |
//! 3 | diameter = -20.0
//!   |            ^
//!   |
//!   = hint: ...
//! ```
//!
//! The severity and the message, the file, line and column, the source line with a caret
//! under the column (the whole line underlined for a diagnostic about a block as a whole),
//! then the hint and the call stack as notes. A diagnostic without a line names its file
//! in a note.

use codespan_reporting::diagnostic::{self as cs, Label};
use codespan_reporting::files::{Error, Files};
use codespan_reporting::term::{self, Chars, Config};
use std::fmt;
use std::ops::Range;

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// The program cannot be run.
    Error,
    /// The program runs, but something was skipped or looks wrong.
    Warning,
}

/// One problem found in a program, with where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// File.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (0 = the whole block).
    pub col: usize,
    /// What is wrong.
    pub message: String,
    /// What to do about it, when there is something to say.
    pub hint: Option<String>,
    /// The block's text.
    pub snippet: String,
    /// Callers, innermost first ("MYAAA.MPF:14").
    pub stack: Vec<String>,
}

impl fmt::Display for Diagnostic {
    /// Rendered as a compiler does (this module): `error: message`, `--> file:line:col`,
    /// the source line with a caret under the column, the hint and the call stack.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        render(self, f)
    }
}

/// Write `d` as the module documentation shows, without a trailing newline.
pub(crate) fn render(d: &Diagnostic, f: &mut dyn fmt::Write) -> fmt::Result {
    let severity = match d.severity {
        Severity::Error => cs::Severity::Error,
        Severity::Warning => cs::Severity::Warning,
    };
    let mut notes = Vec::new();
    if let Some(h) = &d.hint {
        notes.push(format!("hint: {h}"));
    }
    notes.extend(d.stack.iter().map(|s| format!("called from {s}")));
    let mut out = cs::Diagnostic::new(severity).with_message(&d.message);
    let (shown, col) = clip_line(d.snippet.trim_end(), d.col);
    let file = OneLine {
        name: &d.file,
        text: &shown,
        line: d.line,
        col: d.col.max(1),
    };
    if d.line > 0 {
        out = out.with_labels(vec![Label::primary((), marked(&shown, col))]);
    } else {
        notes.insert(0, format!("in {}", d.file));
    }
    let config = Config {
        chars: Chars::ascii(),
        ..Config::default()
    };
    let mut text = String::new();
    term::emit(&mut text, &config, &file, &out.with_notes(notes)).map_err(|_| fmt::Error)?;
    f.write_str(text.trim_end())
}

/// The bytes of `line` under the marker: the character at the 1-based column `col`, the
/// end of the line past its last character, the whole line for column 0.
fn marked(line: &str, col: usize) -> Range<usize> {
    if col == 0 {
        return 0..line.len();
    }
    match line.char_indices().nth(col - 1) {
        Some((at, c)) => at..at + c.len_utf8(),
        None => line.len()..line.len(),
    }
}

/// The one source line a diagnostic shows, as codespan's file: its line number and the
/// column the diagnostic names (a clipped line's columns are not the file's).
struct OneLine<'a> {
    name: &'a str,
    text: &'a str,
    line: usize,
    col: usize,
}

impl<'a> Files<'a> for OneLine<'a> {
    type FileId = ();
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, (): ()) -> Result<&'a str, Error> {
        Ok(self.name)
    }

    fn source(&'a self, (): ()) -> Result<&'a str, Error> {
        Ok(self.text)
    }

    fn line_index(&'a self, (): (), _byte_index: usize) -> Result<usize, Error> {
        Ok(self.line.saturating_sub(1))
    }

    fn line_number(&'a self, (): (), line_index: usize) -> Result<usize, Error> {
        Ok(line_index + 1)
    }

    fn column_number(&'a self, (): (), _line: usize, _byte_index: usize) -> Result<usize, Error> {
        Ok(self.col)
    }

    fn line_range(&'a self, (): (), line_index: usize) -> Result<Range<usize>, Error> {
        if line_index == self.line.saturating_sub(1) {
            Ok(0..self.text.len())
        } else {
            Err(Error::LineTooLarge {
                given: line_index,
                max: self.line.saturating_sub(1),
            })
        }
    }
}

/// A source line as a message shows it: a long one (a hostile program's 100,000 brackets)
/// cut to a window of about 100 characters around the 1-based character column `col` (0:
/// no column), with `...` where it was cut; and the column in what is shown.
pub(crate) fn clip_line(line: &str, col: usize) -> (String, usize) {
    const WIDTH: usize = 100;
    let n = line.chars().count();
    if n <= WIDTH {
        return (line.to_string(), col);
    }
    let at = col.saturating_sub(1).min(n);
    let start = at.saturating_sub(WIDTH / 2).min(n - WIDTH);
    let end = start + WIDTH;
    let mut out = String::new();
    if start > 0 {
        out.push_str("...");
    }
    out.extend(line.chars().skip(start).take(WIDTH));
    if end < n {
        out.push_str("...");
    }
    let col = if col == 0 {
        0
    } else {
        col - start + if start > 0 { 3 } else { 0 }
    };
    (out, col)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(line: usize, col: usize, snippet: &str) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            file: "P.NC".into(),
            line,
            col,
            message: "something is wrong".into(),
            hint: Some("do this".into()),
            snippet: snippet.into(),
            stack: vec!["MAIN.NC:4".into()],
        }
    }

    fn shown(d: &Diagnostic) -> String {
        let mut s = String::new();
        render(d, &mut s).unwrap();
        s
    }

    #[test]
    fn caret_under_the_column() {
        let s = shown(&diag(12, 4, "G1 X1..5"));
        assert_eq!(
            s,
            "error: something is wrong\n   --> P.NC:12:4\n   |\n12 | G1 X1..5\n   |    ^\n   |\n   = hint: do this\n   = called from MAIN.NC:4"
        );
    }

    #[test]
    fn whole_block_and_no_line() {
        let s = shown(&diag(3, 0, "G1 X5"));
        assert!(s.contains("--> P.NC:3:1\n  |\n3 | G1 X5\n  | ^^^^^"), "{s}");
        // A move's error names its block without its text.
        let s = shown(&diag(12, 0, ""));
        assert!(s.contains("--> P.NC:12:1\n"), "{s}");
        let s = shown(&diag(0, 0, ""));
        assert!(
            s.starts_with("error: something is wrong\n = in P.NC\n"),
            "{s}"
        );
    }

    #[test]
    fn long_lines_are_clipped_and_keep_their_column() {
        let line = format!("{}X{}", "[".repeat(5000), "]".repeat(5000));
        let s = shown(&diag(1, 5001, &line));
        assert!(s.contains("--> P.NC:1:5001"), "{s}");
        assert!(s.len() < 1000, "{s}");
        let src = s.lines().find(|l| l.starts_with("1 |")).unwrap();
        let caret = s.lines().find(|l| l.ends_with('^')).unwrap();
        assert_eq!(src.chars().nth(caret.len() - 1), Some('X'), "{s}");
    }
}
