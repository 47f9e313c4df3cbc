//! The error that stops a program's run ([`NcError`]): the block's place, what is wrong, the
//! callers, a hint, and the other diagnostics found before it.

use crate::diag::{Diagnostic, Severity};
use std::fmt;

/// A program that cannot be run: the error that stopped it (its fields), and every other
/// diagnostic found before stopping (`others`: the static check reports all the problems
/// of all programs at once; a run-time error comes alone, with the warnings before it).
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
    /// What to do about it.
    pub hint: Option<String>,
    /// The other errors and the warnings, in file and line order.
    pub others: Vec<Diagnostic>,
}

impl NcError {
    /// This error as a diagnostic.
    pub fn diagnostic(&self) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            file: self.file.clone(),
            line: self.line,
            col: self.col,
            message: self.message.clone(),
            hint: self.hint.clone(),
            snippet: self.snippet.clone(),
            stack: self.stack.clone(),
        }
    }

    /// Every diagnostic, this error first.
    pub fn all(&self) -> Vec<Diagnostic> {
        let mut v = vec![self.diagnostic()];
        v.extend(self.others.iter().cloned());
        v
    }

    pub(super) fn from_diagnostics(mut all: Vec<Diagnostic>) -> NcError {
        let k = all
            .iter()
            .position(|d| d.severity == Severity::Error)
            .expect("called with at least one error");
        let d = all.remove(k);
        NcError {
            file: d.file,
            line: d.line,
            col: d.col,
            message: d.message,
            snippet: d.snippet,
            stack: d.stack,
            hint: d.hint,
            others: all,
        }
    }
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut all = self.all();
        all.sort_by(|a, b| (&a.file, a.line, a.col).cmp(&(&b.file, b.line, b.col)));
        for (i, d) in all.iter().enumerate() {
            if i > 0 {
                write!(f, "\n\n")?;
            }
            write!(f, "{d}")?;
        }
        let errors = all.iter().filter(|d| d.severity == Severity::Error).count();
        let warnings = all.len() - errors;
        if all.len() > 1 {
            write!(
                f,
                "\n\n{errors} error{}, {warnings} warning{}",
                if errors == 1 { "" } else { "s" },
                if warnings == 1 { "" } else { "s" }
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for NcError {}
