//! The CI formats: JUnit XML (one `testsuite` per job, one `testcase` per turn and per
//! check, a `failure` for every error finding, an `error` for a job that could not be read)
//! and SARIF 2.1.0 (a `result` for every finding, located in the NC program's line where
//! the finding comes from one, else in the job file at the table it concerns).

use crate::cli::record::{Outcome, Row};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A place in a file: 1-based line and column.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Place {
    /// The file, as the user would write its path.
    #[serde(serialize_with = "path_text")]
    pub(crate) file: PathBuf,
    /// 1-based line.
    pub(crate) line: usize,
    /// 1-based column.
    pub(crate) column: usize,
}

/// A path as text (bytes that are not UTF-8 replaced), for a record.
fn path_text<S: serde::Serializer>(p: &Path, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&p.to_string_lossy())
}

/// A job that ran, or whose earlier outcome stands (`--changed-since`).
#[derive(Debug)]
pub(crate) struct Checked {
    /// Its outcome: the verdict and the findings with their places.
    pub(crate) outcome: Outcome,
    /// The earlier run's record it was carried from, when the job did not run because
    /// nothing it reads changed since.
    pub(crate) unchanged_since: Option<PathBuf>,
}

/// A job that could not be read or simulated.
#[derive(Debug)]
pub(crate) struct Failed {
    /// What went wrong, as printed.
    pub(crate) message: String,
    /// Where.
    pub(crate) place: Place,
}

/// One job of a run.
#[derive(Debug)]
pub(crate) struct Case {
    /// The job file as given.
    pub(crate) job: PathBuf,
    /// Wall time (s).
    pub(crate) seconds: f64,
    /// The outcome.
    pub(crate) result: Result<Checked, Failed>,
}

impl Case {
    /// The name a person knows the job by: its name, else its file.
    fn name(&self) -> String {
        match &self.result {
            Ok(c) if !c.outcome.name.is_empty() => c.outcome.name.clone(),
            _ => self.job.display().to_string(),
        }
    }
}

/// Escape text for XML attribute values and content.
fn xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // XML 1.0 allows tab, newline and carriage return of the control characters.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// A `testcase` of a suite: a name, its error findings and its warnings.
struct TestCase<'a> {
    name: String,
    failures: Vec<&'a Row>,
    warnings: Vec<&'a Row>,
}

/// The test cases of a report: one per turn (the turn's deviation and measurement
/// findings), then one per kind of finding that belongs to no turn (machine, program and
/// milling checks).
fn test_cases(outcome: &Outcome) -> Vec<TestCase<'_>> {
    let multi = outcome.starts > 1;
    let mut cases: Vec<TestCase<'_>> = outcome
        .turns
        .iter()
        .map(|&(turn, start)| TestCase {
            name: if multi {
                format!("start {start} turn {turn}")
            } else {
                format!("turn {turn}")
            },
            failures: Vec::new(),
            warnings: Vec::new(),
        })
        .collect();
    for f in &outcome.findings {
        let turn = f.turn.and_then(|n| {
            outcome
                .turns
                .iter()
                .position(|&(turn, start)| turn == n && f.start.unwrap_or(start) == start)
        });
        let i = match turn {
            Some(i) => i,
            None => {
                let name = format!("check {}", f.kind);
                match cases.iter().position(|c| c.name == name) {
                    Some(i) => i,
                    None => {
                        cases.push(TestCase {
                            name,
                            failures: Vec::new(),
                            warnings: Vec::new(),
                        });
                        cases.len() - 1
                    }
                }
            }
        };
        if f.error {
            cases[i].failures.push(f);
        } else {
            cases[i].warnings.push(f);
        }
    }
    cases
}

/// JUnit XML for the jobs of a run.
pub(crate) fn junit(cases: &[&Case]) -> String {
    let mut suites = String::new();
    let (mut tests, mut failures, mut errors, mut time) = (0, 0, 0, 0.0);
    for case in cases {
        let name = xml(&case.name());
        let file = xml(&case.job.display().to_string());
        time += case.seconds;
        match &case.result {
            Ok(c) => {
                let tcs = test_cases(&c.outcome);
                let failed = tcs.iter().filter(|t| !t.failures.is_empty()).count();
                tests += tcs.len();
                failures += failed;
                let _ = writeln!(
                    suites,
                    "  <testsuite name=\"{name}\" file=\"{file}\" tests=\"{}\" failures=\"{failed}\" errors=\"0\" skipped=\"0\" time=\"{:.3}\">",
                    tcs.len(),
                    case.seconds
                );
                let _ = write!(
                    suites,
                    "    <properties>\n      <property name=\"verdict\" value=\"{}\"/>\n      <property name=\"tolerance_mm\" value=\"{}\"/>\n      <property name=\"vpcut_version\" value=\"{}\"/>\n",
                    if c.outcome.fail { "fail" } else { "pass" },
                    c.outcome.tolerance_mm,
                    xml(vpcut::VERSION)
                );
                if let Some(since) = &c.unchanged_since {
                    let _ = writeln!(
                        suites,
                        "      <property name=\"unchanged_since\" value=\"{}\"/>",
                        xml(&since.display().to_string())
                    );
                }
                suites.push_str("    </properties>\n");
                for t in &tcs {
                    let _ = write!(
                        suites,
                        "    <testcase classname=\"{name}\" name=\"{}\" file=\"{file}\" time=\"0\"",
                        xml(&t.name)
                    );
                    if t.failures.is_empty() && t.warnings.is_empty() {
                        suites.push_str("/>\n");
                        continue;
                    }
                    suites.push_str(">\n");
                    // Where a finding is: its place, as SARIF gives it.
                    let at = |f: &Row| {
                        let p = &f.place;
                        format!("{}:{}:{}: ", p.file.display(), p.line, p.column)
                    };
                    for f in &t.failures {
                        let _ = writeln!(
                            suites,
                            "      <failure type=\"{}\" message=\"{}\">{}{}</failure>",
                            xml(&f.kind),
                            xml(&f.message),
                            xml(&at(f)),
                            xml(&f.message)
                        );
                    }
                    if !t.warnings.is_empty() {
                        let text: Vec<String> = t
                            .warnings
                            .iter()
                            .map(|f| format!("{}warning {}: {}", at(f), f.kind, f.message))
                            .collect();
                        let _ = writeln!(
                            suites,
                            "      <system-out>{}</system-out>",
                            xml(&text.join("\n"))
                        );
                    }
                    suites.push_str("    </testcase>\n");
                }
            }
            Err(e) => {
                tests += 1;
                errors += 1;
                let _ = writeln!(
                    suites,
                    "  <testsuite name=\"{name}\" file=\"{file}\" tests=\"1\" failures=\"0\" errors=\"1\" skipped=\"0\" time=\"{:.3}\">",
                    case.seconds
                );
                let first = e.message.lines().next().unwrap_or("");
                let _ = writeln!(
                    suites,
                    "    <testcase classname=\"{name}\" name=\"read and simulate\" file=\"{file}\" time=\"0\">\n      <error type=\"input\" message=\"{}\">{}</error>\n    </testcase>",
                    xml(first),
                    xml(&e.message)
                );
            }
        }
        suites.push_str("  </testsuite>\n");
    }
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"vpcut\" tests=\"{tests}\" failures=\"{failures}\" errors=\"{errors}\" time=\"{time:.3}\">\n{suites}</testsuites>\n"
    )
}

/// SARIF's rules: one per kind of finding (`FindingKind::description`), and one for a job
/// that cannot be read or simulated.
fn rules() -> Vec<(&'static str, &'static str)> {
    let mut r: Vec<_> = vpcut::FindingKind::ALL
        .iter()
        .map(|k| (k.name(), k.description()))
        .collect();
    r.push((
        "input",
        "The job or its program cannot be read or simulated.",
    ));
    r
}

/// A path as a URI reference: relative paths stay relative (to the directory the run
/// started in), absolute ones become `file://` URIs; reserved characters are
/// percent-encoded.
pub(crate) fn uri(path: &Path) -> String {
    let s = path.to_string_lossy().replace('\\', "/");
    let mut out = String::new();
    if path.is_absolute() {
        out.push_str("file://");
        if !s.starts_with('/') {
            out.push('/');
        }
    }
    for b in s.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

/// SARIF 2.1.0 for the jobs of a run: one run, a result per finding (and per job that
/// could not be read).
pub(crate) fn sarif(cases: &[&Case]) -> String {
    use serde_json::json;
    let rules = rules();
    let rule_index = |kind: &str| {
        rules
            .iter()
            .position(|r| r.0 == kind)
            .expect("every finding kind has a rule")
    };
    let physical = |p: &Place| {
        json!({
            "physicalLocation": {
                "artifactLocation": { "uri": uri(&p.file) },
                "region": { "startLine": p.line.max(1), "startColumn": p.column.max(1) }
            }
        })
    };
    let location = |p: &Place| json!([physical(p)]);
    let mut results = Vec::new();
    for case in cases {
        let job = case.job.display().to_string();
        match &case.result {
            Ok(c) => {
                for f in &c.outcome.findings {
                    let i = rule_index(&f.kind);
                    let mut props = serde_json::Map::new();
                    props.insert("job".into(), json!(job));
                    for (k, v) in [
                        ("turn", json!(f.turn)),
                        ("start", json!(f.start)),
                        ("flank", json!(f.flank)),
                        ("pass", json!(f.pass)),
                        ("angle_deg", json!(f.angle_deg)),
                        ("z_mm", json!(f.z_mm)),
                        ("value", json!(f.value)),
                        ("unit", json!(f.unit)),
                    ] {
                        if !v.is_null() {
                            props.insert(k.into(), v);
                        }
                    }
                    if let Some(k) = &f.key {
                        props.insert("job_key".into(), json!(k));
                    }
                    if let Some(since) = &c.unchanged_since {
                        props.insert("unchanged_since".into(), json!(since.display().to_string()));
                    }
                    let mut result = json!({
                        "ruleId": rules[i].0,
                        "ruleIndex": i,
                        "level": if f.error { "error" } else { "warning" },
                        "message": { "text": format!("{}: {}", case.name(), f.message) },
                        "locations": location(&f.place),
                        "properties": props,
                    });
                    if let Some(j) = &f.job_place {
                        let mut related = physical(j);
                        related["id"] = json!(0);
                        related["message"] = json!({ "text": "the job" });
                        result["relatedLocations"] = json!([related]);
                    }
                    results.push(result);
                }
            }
            Err(e) => {
                let i = rule_index("input");
                results.push(json!({
                    "ruleId": "input",
                    "ruleIndex": i,
                    "level": "error",
                    "message": { "text": e.message },
                    "locations": location(&e.place),
                    "properties": { "job": job },
                }));
            }
        }
    }
    let rules: Vec<_> = rules
        .iter()
        .map(|(id, text)| json!({ "id": id, "shortDescription": { "text": text } }))
        .collect();
    let doc = json!({
        "$schema": "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": { "driver": {
                "name": "vpcut",
                "version": vpcut::VERSION,
                "rules": rules,
            }},
            "columnKind": "unicodeCodePoints",
            "results": results,
        }]
    });
    let mut s = serde_json::to_string_pretty(&doc).expect("SARIF serializes");
    s.push('\n');
    s
}

/// Where a finding is, and where in the job file it belongs: its NC block when it has one
/// (a program diagnostic, a milling move, the block whose pass or move cut it), with the
/// job file at its key or table as the related place; else the job file at the finding's
/// key (`pass[2]` is the third `[[pass]]`, `thread.z_start` the line of `z_start` in
/// `[thread]`), else at the table the kind concerns (`[thread]` for deviations and
/// measurements, `[machine]` for machine checks, the pass's `[[pass]]`, else `[program]`
/// or `[process]`), else the job file's first line.
pub(crate) fn place(
    f: &vpcut::Finding,
    job_path: &Path,
    job_text: &str,
    program_file: &dyn Fn(&str) -> Option<PathBuf>,
    pass_blocks: &[(usize, String, usize)],
) -> (Place, Option<Place>) {
    let in_program = |file: &str, line: usize, column: usize| Place {
        file: program_file(file).unwrap_or_else(|| {
            job_path
                .parent()
                .map(|d| d.join(file))
                .unwrap_or_else(|| PathBuf::from(file))
        }),
        line,
        column: column.max(1),
    };
    let (line, column) = job_line(f, job_text).unwrap_or((1, 1));
    let in_job = Place {
        file: job_path.to_path_buf(),
        line,
        column,
    };
    if let (Some(file), Some(line)) = (&f.file, f.line) {
        return (in_program(file, line, f.column.unwrap_or(1)), Some(in_job));
    }
    // A pass check of a pass from the program: its thread block.
    if let Some(b) = pass_blocks.iter().find(|b| Some(b.0 + 1) == f.pass) {
        return (in_program(&b.1, b.2, 1), Some(in_job));
    }
    (in_job, None)
}

/// The line (1-based) and column of a table's header in a job's text: the `nth` (0-based)
/// `[name]` or `[[name]]` header.
fn header(job_text: &str, name: &str, nth: usize) -> Option<(usize, usize)> {
    job_text
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            let t = l.trim_start();
            let inner = t.trim_start_matches('[');
            t.starts_with('[')
                && inner.starts_with(name)
                && inner[name.len()..].trim_start().starts_with(']')
        })
        .nth(nth)
        .map(|(i, l)| (i + 1, l.len() - l.trim_start().len() + 1))
}

/// The line of `key = ...` inside the table whose header is at `from` (1-based), before the
/// next header.
fn key_line(job_text: &str, from: usize, key: &str) -> Option<(usize, usize)> {
    job_text
        .lines()
        .enumerate()
        .skip(from)
        .take_while(|(_, l)| !l.trim_start().starts_with('['))
        .find(|(_, l)| {
            let t = l.trim_start();
            t.strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map(|(i, l)| (i + 1, l.len() - l.trim_start().len() + 1))
}

/// Where a finding belongs in the job file: its key (`table.key`, `table[n].key`, `table`),
/// else the table its kind concerns, else the pass's `[[pass]]`, `[program]` or
/// `[process]`.
fn job_line(f: &vpcut::Finding, job_text: &str) -> Option<(usize, usize)> {
    let by_key = f.key.as_deref().and_then(|k| {
        let (table, rest) = k.split_once('.').unwrap_or((k, ""));
        let (table, nth) = match table.split_once('[') {
            Some((t, n)) => (t, n.trim_end_matches(']').parse().ok()?),
            None => (table, 0),
        };
        let at = header(job_text, table, nth)?;
        Some(if rest.is_empty() {
            at
        } else {
            key_line(job_text, at.0, rest).unwrap_or(at)
        })
    });
    use vpcut::FindingKind as K;
    let by_kind = || match f.kind {
        K::Gouge
        | K::Leftover
        | K::MissingFeature
        | K::Lead
        | K::GrooveWidth
        | K::ToothWidth
        | K::SplitFeature
        | K::PitchDiameter => header(job_text, "thread", 0),
        K::FeedLimit | K::RunIn | K::AxisAcceleration => header(job_text, "machine", 0),
        K::FlankInterference => header(job_text, "tool", 0),
        _ => None,
    };
    by_key
        .or_else(by_kind)
        .or_else(|| {
            f.pass
                .and_then(|p| header(job_text, "pass", p.saturating_sub(1)))
        })
        .or_else(|| header(job_text, "program", 0))
        .or_else(|| header(job_text, "process", 0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_are_percent_encoded_and_absolute_paths_are_file_uris() {
        assert_eq!(
            uri(Path::new("scenes/a b/job.toml")),
            "scenes/a%20b/job.toml"
        );
        assert_eq!(uri(Path::new("O0001.NC")), "O0001.NC");
        assert_eq!(uri(Path::new("/tmp/x#1.toml")), "file:///tmp/x%231.toml");
        assert_eq!(uri(Path::new("caf\u{e9}.nc")), "caf%C3%A9.nc");
    }

    #[test]
    fn xml_escapes_markup_and_control_characters() {
        assert_eq!(
            xml("a<b & \"c\" 'd'>"),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;"
        );
        assert_eq!(xml("x\u{1}y\tz"), "x\\u{1}y\tz");
    }

    #[test]
    fn findings_without_a_program_line_point_at_the_job_table() {
        let job =
            "name = \"x\"\n\n[blank]\ndiameter = 1\n\n  [thread]\nform = \"square\"\n[machine]\n";
        let f = |kind| vpcut::Finding::new(kind, vpcut::Severity::Error, String::new());
        let none = |_: &str| None;
        let at = |kind| place(&f(kind), Path::new("j.toml"), job, &none, &[]).0;
        assert_eq!(
            (
                at(vpcut::FindingKind::Gouge).line,
                at(vpcut::FindingKind::Gouge).column
            ),
            (6, 3)
        );
        assert_eq!(at(vpcut::FindingKind::RunIn).line, 8);
        assert_eq!(
            (
                at(vpcut::FindingKind::Hand).line,
                at(vpcut::FindingKind::Hand).column
            ),
            (1, 1)
        );
        let program = vpcut::Finding {
            file: Some("O1.NC".into()),
            line: Some(12),
            column: Some(4),
            ..f(vpcut::FindingKind::Program)
        };
        let (p, related) = place(&program, Path::new("jobs/j.toml"), job, &none, &[]);
        assert_eq!(related.map(|r| r.line), Some(1));
        assert_eq!(
            p,
            Place {
                file: PathBuf::from("jobs/O1.NC"),
                line: 12,
                column: 4
            }
        );
    }
}
