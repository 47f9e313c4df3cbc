//! Where a key stands in the job file and what its value must be, for every key at once:
//! the range of every number (finite, and within what a lathe can mean), and serde's
//! errors (wrong type, missing or unknown key) said in the job file's words, with the
//! dotted key (`tool[0].width`, `thread.pitch.first`) and its line and column.
//!
//! serde names Rust types (`expected u32`, `struct RawWidth`, `untagged enum RawPitch`);
//! the job file knows whole numbers, numbers, strings, arrays and tables. The key comes from
//! the span toml gives with every error: the deepest key or value of the document that
//! holds it.

use super::ctx::{line_col, source_line};
use super::JobError;
use serde::Deserialize;
use std::ops::Range;
use toml_edit::{ImDocument, Item, Value};

/// The largest magnitude of a number in a job (mm, degrees, mm/rev, counts), unless the
/// key has its own range in [`range_of`]: 100 m is beyond any lathe or mill.
const MAX_NUMBER: f64 = 1e5;

/// One key or value of the document: its dotted path, the span of its key and of its value.
struct Node<'a> {
    path: String,
    key: Option<Range<usize>>,
    span: Option<Range<usize>>,
    value: Option<&'a Value>,
}

fn push_item<'a>(out: &mut Vec<Node<'a>>, path: String, key: Option<Range<usize>>, item: &'a Item) {
    match item {
        Item::None => {}
        Item::Value(v) => push_value(out, path, key, v),
        Item::Table(t) => {
            out.push(Node {
                path: path.clone(),
                key,
                span: t.span(),
                value: None,
            });
            for (k, it) in t.iter() {
                let ks = t.key(k).and_then(|k| k.span());
                push_item(out, join(&path, k), ks, it);
            }
        }
        Item::ArrayOfTables(a) => {
            out.push(Node {
                path: path.clone(),
                key,
                span: a.span(),
                value: None,
            });
            for (i, t) in a.iter().enumerate() {
                let p = format!("{path}[{i}]");
                out.push(Node {
                    path: p.clone(),
                    key: None,
                    span: t.span(),
                    value: None,
                });
                for (k, it) in t.iter() {
                    let ks = t.key(k).and_then(|k| k.span());
                    push_item(out, join(&p, k), ks, it);
                }
            }
        }
    }
}

fn push_value<'a>(out: &mut Vec<Node<'a>>, path: String, key: Option<Range<usize>>, v: &'a Value) {
    out.push(Node {
        path: path.clone(),
        key,
        span: v.span(),
        value: Some(v),
    });
    match v {
        Value::Array(a) => {
            for (i, e) in a.iter().enumerate() {
                push_value(out, format!("{path}[{i}]"), None, e);
            }
        }
        Value::InlineTable(t) => {
            for (k, e) in t.iter() {
                let ks = t.key(k).and_then(|k| k.span());
                push_value(out, join(&path, k), ks, e);
            }
        }
        _ => {}
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// Every key and value of a job text (empty when it is not valid TOML).
fn nodes<'a>(doc: &'a ImDocument<&str>) -> Vec<Node<'a>> {
    let mut out = Vec::new();
    push_item(&mut out, String::new(), None, doc.as_item());
    out
}

/// The dotted key whose key or value holds byte `at` (the deepest one).
fn key_at(doc: &ImDocument<&str>, at: usize) -> Option<String> {
    let holds =
        |r: &Option<Range<usize>>| r.as_ref().is_some_and(|r| r.contains(&at) || r.start == at);
    nodes(doc)
        .into_iter()
        .filter(|n| !n.path.is_empty() && (holds(&n.key) || holds(&n.span)))
        .max_by_key(|n| n.path.len())
        .map(|n| n.path)
}

/// The range of the numbers of a key (its path without array indices): (lowest, highest).
fn range_of(key: &str) -> (f64, f64) {
    match key {
        // Counts and budgets that are no lengths: what keeps memory and time bounded is
        // checked where they are used (the dexel budget, the placements).
        "simulation.max_dexels" => (0.0, 1e15),
        "simulation.angular_cells" => (0.0, 1e7),
        // Rates: rev/min, mm/min, mm/s^2.
        "machine.spindle_rpm"
        | "machine.max_feed"
        | "machine.acceleration"
        | "machine.rapid_rate" => (-1e6, 1e6),
        _ => (-MAX_NUMBER, MAX_NUMBER),
    }
}

/// The key without array indices (`tool[1].width` -> `tool.width`).
fn plain_key(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    let mut depth = 0;
    for c in path.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// An error about the value at `span` of `key`.
fn invalid(
    src: &str,
    file: &str,
    key: &str,
    span: Option<Range<usize>>,
    message: String,
) -> JobError {
    let (line, col) = span.map_or((0, 0), |r| line_col(src, r.start));
    JobError::Invalid {
        file: file.to_string(),
        key: key.to_string(),
        line,
        col,
        message,
        snippet: source_line(src, line),
    }
}

/// Every number of the job is finite and within its key's range ([`range_of`]): nothing
/// downstream meets `nan`, `inf` or a length of 1e300 mm.
pub(super) fn check_numbers(src: &str, file: &str, doc: &ImDocument<&str>) -> Result<(), JobError> {
    for n in nodes(doc) {
        let v = match n.value {
            Some(Value::Float(f)) => *f.value(),
            Some(Value::Integer(i)) => *i.value() as f64,
            _ => continue,
        };
        let (lo, hi) = range_of(&plain_key(&n.path));
        if !v.is_finite() {
            return Err(invalid(
                src,
                file,
                &n.path,
                n.span,
                format!("expected a finite number, got {}", shown(v)),
            ));
        }
        if v < lo || v > hi {
            return Err(invalid(
                src,
                file,
                &n.path,
                n.span,
                format!(
                    "expected a number from {} to {}, got {}",
                    shown(lo),
                    shown(hi),
                    shown(v)
                ),
            ));
        }
    }
    Ok(())
}

/// A number as the job file would write it (`nan`, `inf`, `1e300`).
fn shown(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else if v.abs() >= 1e9 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// serde's error about a job text in the job file's words, with the key it is about.
pub(super) fn schema_error(
    src: &str,
    file: &str,
    doc: Option<&ImDocument<&str>>,
    e: &toml_edit::de::Error,
) -> JobError {
    let span = e.span();
    let message = e.message().trim().to_string();
    let key = match (doc, &span) {
        (Some(doc), Some(r)) => key_at(doc, r.start),
        _ => None,
    };
    let (line, col) = span.clone().map_or((0, 0), |r| line_col(src, r.start));
    let Some(key) = key else {
        return JobError::Syntax {
            file: file.to_string(),
            line,
            col,
            message: in_words(&message),
            snippet: source_line(src, line),
        };
    };
    let got = span
        .clone()
        .and_then(|r| src.get(r))
        .map(|t| {
            let t = t.trim();
            match t.char_indices().nth(30) {
                Some((k, _)) => format!("{}..", &t[..k]),
                None => t.to_string(),
            }
        })
        .unwrap_or_default();
    let message = if message == "wanted string or table" {
        // An enum given something else than its name: ask serde for the names.
        format!(
            "expected {}, got {got}",
            names_at(src, span.clone()).unwrap_or_else(|| "a name in quotes".into())
        )
    } else {
        in_words(&message)
    };
    invalid(src, file, &key, span, message)
}

/// The names an enum key takes: the job parsed again with a string that no enum knows at
/// `span`, whose error lists them (`one of `a`, `b``).
fn names_at(src: &str, span: Option<Range<usize>>) -> Option<String> {
    let span = span?;
    let text = format!("{}\"?\"{}", src.get(..span.start)?, src.get(span.end..)?);
    let e = toml_edit::de::from_str::<super::schema::RawJob>(&text).err()?;
    let (_, names) = e.message().split_once("expected ")?;
    names
        .starts_with("one of")
        .then(|| names.trim().to_string())
}

/// A serde message with Rust's type names put in the job file's words.
fn in_words(message: &str) -> String {
    let typed = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "));
    if let Some((got, exp)) = typed.and_then(|r| r.split_once(", expected ")) {
        let value = message.starts_with("invalid value");
        return format!("expected {}, got {}", expected(exp, value), got_words(got));
    }
    if let Some((n, exp)) = message
        .strip_prefix("invalid length ")
        .and_then(|r| r.split_once(", expected "))
    {
        return format!("expected {}, got {n} values", expected(exp, false));
    }
    if message.starts_with("data did not match any variant") {
        return "a value of the wrong type".into();
    }
    message.to_string()
}

/// What serde expected, in the job file's words (`value`: the type was right but the value
/// out of its range).
fn expected(e: &str, value: bool) -> String {
    let whole = |max: &str| {
        if value {
            format!("a whole number from 0 to {max}")
        } else {
            "a whole number".to_string()
        }
    };
    match e.trim() {
        "u8" => whole("255"),
        "u16" => whole("65535"),
        "u32" => whole("4294967295"),
        "u64" | "usize" => whole("18446744073709551615"),
        "i8" | "i16" | "i32" | "i64" | "isize" => "a whole number".into(),
        "f32" | "f64" => "a number".into(),
        "a boolean" => "true or false".into(),
        "a string" | "a borrowed string" => "a string in quotes".into(),
        "a sequence" => "an array [ .. ] (or [[ .. ]] tables)".into(),
        "a map" => "a table".into(),
        s if s.starts_with("struct ") => "a table `{ .. }`".into(),
        s if s.starts_with("enum ") => "a name in quotes".into(),
        s => s.to_string(),
    }
}

/// What the job file gave, from serde's description of it.
fn got_words(g: &str) -> String {
    let ticked = |p: &str| g.strip_prefix(p).map(|r| r.trim_matches('`').to_string());
    if let Some(v) = ticked("floating point ").or_else(|| ticked("integer ")) {
        return v;
    }
    if let Some(v) = ticked("boolean ") {
        return v;
    }
    if let Some(s) = g.strip_prefix("string ") {
        return format!("the string {s}");
    }
    match g {
        "map" => "a table".into(),
        "sequence" => "an array".into(),
        other => other.to_string(),
    }
}

/// A fixed-size array key (`z_range = [lo, hi]`): exactly `N` values, no more (serde's
/// arrays stop reading after `N` and would take `[1, 2, 3]`).
pub(super) fn fixed<'de, D, T, const N: usize>(d: D) -> Result<Option<[T; N]>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let v: Option<Vec<T>> = Option::deserialize(d)?;
    match v {
        None => Ok(None),
        Some(v) => {
            let n = v.len();
            v.try_into().map(Some).map_err(|_| {
                serde::de::Error::invalid_length(n, &format!("an array of {N} values").as_str())
            })
        }
    }
}

/// The dexel budget, a count a person may write as an integer (`400000000`,
/// `400_000_000`) or in scientific notation, which TOML reads as a float (`4e8`, `4.0e8`):
/// a float is taken when it is a whole number. Fractions (`1.5`), `nan`, `inf`, and
/// numbers outside the key's range ([`range_of`]: negatives) are refused.
pub(super) fn count<'de, D>(d: D) -> Result<Option<u64>, D::Error>
where
    D: serde::Deserializer<'de>,
{
    struct Count;
    impl serde::de::Visitor<'_> for Count {
        type Value = u64;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a whole number (400000000, 400_000_000 or 4e8)")
        }
        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<u64, E> {
            self.visit_f64(v as f64).map(|_| v)
        }
        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<u64, E> {
            self.visit_f64(v as f64)
        }
        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<u64, E> {
            let (lo, hi) = range_of("simulation.max_dexels");
            if !v.is_finite() || v.fract() != 0.0 {
                Err(E::custom(format!(
                    "expected a whole number (400000000, 400_000_000 or 4e8), got {}",
                    shown(v)
                )))
            } else if v < lo || v > hi {
                Err(E::custom(format!(
                    "expected a whole number from {} to {}, got {}",
                    shown(lo),
                    shown(hi),
                    shown(v)
                )))
            } else {
                // Whole and at most 1e15 (below 2^53): exact.
                Ok(v as u64)
            }
        }
    }
    d.deserialize_any(Count).map(Some)
}
