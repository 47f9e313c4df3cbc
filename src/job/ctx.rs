//! The job text parsed once: the TOML document that serde deserializes and whose spans
//! locate every key, and the context that turns a bad value into a [`JobError`] naming
//! the file, the key, its line and column.

use super::schema::RawJob;
use super::{keys, JobError};
use serde::Deserialize;
use std::fmt;
use toml_edit::ImDocument;

/// Byte offset to 1-based line and column.
pub(super) fn line_col(src: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(src.len());
    let before = &src[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

pub(super) fn source_line(src: &str, line: usize) -> String {
    src.lines()
        .nth(line.saturating_sub(1))
        .unwrap_or("")
        .to_string()
}

/// Find the span of a dotted key path (`tool[1].width`, `thread.pitch.first`) in `src`.
/// Falls back to the nearest existing parent.
fn locate(doc: &ImDocument<&str>, key: &str) -> Option<std::ops::Range<usize>> {
    let mut item: &toml_edit::Item = doc.as_item();
    let mut best = None;
    for part in key.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (n, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (part, None),
        };
        if let Some(s) = key_span(item, name) {
            best = Some(s);
        }
        let Some(mut next) = item.get(name) else {
            break;
        };
        if let Some(i) = index {
            let Some(n) = next.get(i) else {
                break;
            };
            next = n;
        }
        if let Some(s) = next.span() {
            best = Some(s);
        }
        item = next;
    }
    best
}

fn key_span(item: &toml_edit::Item, name: &str) -> Option<std::ops::Range<usize>> {
    match item {
        toml_edit::Item::Table(t) => t.key(name).and_then(|k| k.span()),
        toml_edit::Item::Value(toml_edit::Value::InlineTable(t)) => {
            t.key(name).and_then(|k| k.span())
        }
        _ => None,
    }
}

/// The job's text, its document and its name: the context of validation errors.
pub(super) struct Ctx<'a> {
    src: &'a str,
    file: &'a str,
    /// The one parse of `src` (`None` without a job text: [`Ctx::empty`]).
    doc: Option<ImDocument<&'a str>>,
}

impl<'a> Ctx<'a> {
    /// Parse the job text `src` of `file` into a TOML document: the one parse of the job.
    pub(super) fn parse(src: &'a str, file: &'a str) -> Result<Ctx<'a>, JobError> {
        let doc =
            ImDocument::parse(src).map_err(|e| keys::schema_error(src, file, None, &e.into()))?;
        Ok(Ctx {
            src,
            file,
            doc: Some(doc),
        })
    }

    /// A context without a job text (errors name `file` without a line).
    pub(super) fn empty(file: &'a str) -> Ctx<'a> {
        Ctx {
            src: "",
            file,
            doc: None,
        }
    }

    /// The document deserialized into the raw schema (serde's errors in the job file's
    /// words), then every number checked against its key's range.
    pub(super) fn raw(&self) -> Result<RawJob, JobError> {
        let doc = self.doc.as_ref().expect("a parsed job text");
        let raw = RawJob::deserialize(toml_edit::de::Deserializer::from(doc.clone()))
            .map_err(|e| keys::schema_error(self.src, self.file, Some(doc), &e))?;
        keys::check_numbers(self.src, self.file, doc)?;
        Ok(raw)
    }

    pub(super) fn err(&self, key: &str, message: impl fmt::Display) -> JobError {
        let (line, col) = self
            .doc
            .as_ref()
            .and_then(|doc| locate(doc, key))
            .map(|r| line_col(self.src, r.start))
            .unwrap_or((0, 0));
        JobError::Invalid {
            file: self.file.to_string(),
            key: key.to_string(),
            line,
            col,
            message: message.to_string(),
            snippet: source_line(self.src, line),
        }
    }

    pub(super) fn finite(&self, key: &str, v: f64) -> Result<f64, JobError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a finite number, got {v}")))
        }
    }

    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a number > 0, got {v}")))
        }
    }

    pub(super) fn non_negative(&self, key: &str, v: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("expected a number >= 0, got {v}")))
        }
    }

    pub(super) fn angle(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, JobError> {
        self.finite(key, v)?;
        if v >= lo && v < hi {
            Ok(v.to_radians())
        } else {
            Err(self.err(
                key,
                format!("expected an angle in [{lo}, {hi}) degrees, got {v}"),
            ))
        }
    }
}
