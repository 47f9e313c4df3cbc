//! `vpcut check --report-dir DIR` and `--changed-since DIR`: one record a job, and the
//! jobs whose inputs have not changed since an earlier run's records.
//!
//! A record is `DIR/<key>.json` (`vpcut.check/1`), the key the job's path as given on the
//! command line with every byte but `A-Z a-z 0-9 - _ .` written `%XX` (`jobs/a.toml` is
//! `jobs%2Fa.toml.json`; a key over [`MAX_KEY`] bytes keeps its first bytes and ends in
//! `~` and 16 hex digits of the path's SHA-256). It holds what decides the job's outcome
//! (vpcut's version, `--strict` and `--max-dexels`, the SHA-256 of every file the job
//! read: the job file, its programs and subprograms, its tool meshes; the files it looked
//! for and did not find), the outcome the CI formats and the table are written from (the
//! verdict, the worst values, every finding with its places), and the whole
//! `vpcut.report/1` report.
//!
//! A job is unchanged when its record has this vpcut's version and the run's options, its
//! path, every file it read still has the recorded SHA-256, and none of those it did not
//! find has appeared: its outcome is the record's (the simulation is deterministic, and
//! these are everything it reads). A job that could not be read is never carried: it runs
//! again.

use crate::cli::ci::Place;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The schema of a record.
pub(crate) const SCHEMA: &str = "vpcut.check/1";

/// The longest key a record's file name takes whole (bytes).
pub(crate) const MAX_KEY: usize = 200;

/// A job's outcome as the CI formats and the table need it: from a fresh report, or
/// carried from an earlier run's record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Outcome {
    /// The job's name (`name = ...`; empty when it has none).
    pub(crate) name: String,
    /// Whether the verdict is fail.
    pub(crate) fail: bool,
    /// The job's tolerance (mm).
    pub(crate) tolerance_mm: f64,
    /// Starts of the thread.
    pub(crate) starts: u32,
    /// The report's turn rows: (turn, start).
    pub(crate) turns: Vec<(i64, u32)>,
    /// Worst gouge and leftover (mm).
    pub(crate) max_gouge_mm: f64,
    /// See `max_gouge_mm`.
    pub(crate) max_leftover_mm: f64,
    /// Error findings.
    pub(crate) errors: usize,
    /// Warning findings.
    pub(crate) warnings: usize,
    /// The findings, in the report's order.
    pub(crate) findings: Vec<Row>,
}

/// One finding of an [`Outcome`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Row {
    /// The kind's name (`gouge`, `program`, ...).
    pub(crate) kind: String,
    /// An error (else a warning).
    pub(crate) error: bool,
    /// The message.
    pub(crate) message: String,
    /// Turn, start, flank, pass, angle, z, value and unit, key: as the report's.
    pub(crate) turn: Option<i64>,
    /// See `turn`.
    pub(crate) start: Option<u32>,
    /// See `turn`.
    pub(crate) flank: Option<String>,
    /// See `turn`.
    pub(crate) pass: Option<usize>,
    /// See `turn`.
    pub(crate) angle_deg: Option<f64>,
    /// See `turn`.
    pub(crate) z_mm: Option<f64>,
    /// See `turn`.
    pub(crate) value: Option<f64>,
    /// See `turn`.
    pub(crate) unit: Option<String>,
    /// See `turn`.
    pub(crate) key: Option<String>,
    /// Where it is (its NC block, or the job file).
    pub(crate) place: Place,
    /// The job file's place when `place` is in an NC program.
    pub(crate) job_place: Option<Place>,
}

impl Outcome {
    /// The outcome of a report whose findings are at `places` (in the report's order).
    pub(crate) fn of(report: &vpcut::Report, places: Vec<(Place, Option<Place>)>) -> Outcome {
        Outcome {
            name: report.job.clone(),
            fail: report.verdict == vpcut::Verdict::Fail,
            tolerance_mm: report.tolerance_mm,
            starts: report.thread.starts,
            turns: report.turns.iter().map(|t| (t.turn, t.start)).collect(),
            max_gouge_mm: report.deviation.max_gouge_mm,
            max_leftover_mm: report.deviation.max_leftover_mm,
            errors: report.finding_counts.errors,
            warnings: report.finding_counts.warnings,
            findings: report
                .findings
                .iter()
                .zip(places)
                .map(|(f, (place, job_place))| Row {
                    kind: f.kind.name().to_string(),
                    error: f.is_error(),
                    message: f.message.clone(),
                    turn: f.turn,
                    start: f.start,
                    flank: f.flank.map(|x| x.name().to_string()),
                    pass: f.pass,
                    angle_deg: f.angle_deg,
                    z_mm: f.z_mm,
                    value: f.value,
                    unit: f.unit.map(str::to_string),
                    key: f.key.clone(),
                    place,
                    job_place,
                })
                .collect(),
        }
    }
}

/// A file a job read, with its hash; or looked for and did not find.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Hashed {
    /// `job`, `program` or `tool`.
    pub(crate) role: String,
    /// Its path as this run read it (relative to the folder vpcut ran in, or absolute).
    pub(crate) path: String,
    /// SHA-256 of its bytes, lower-case hex.
    pub(crate) sha256: String,
}

/// What decides a job's outcome besides its files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct Options {
    /// `--strict`.
    pub(crate) strict: bool,
    /// `--max-dexels`.
    pub(crate) max_dexels: Option<u64>,
}

/// A record as read back: everything but the report.
#[derive(Debug, Deserialize)]
struct Read {
    schema: String,
    vpcut_version: String,
    job: String,
    options: Options,
    inputs: Vec<Hashed>,
    absent: Vec<String>,
    outcome: Outcome,
}

/// A record's first fields, read before the rest: another schema or version is no error.
#[derive(Debug, Deserialize)]
struct Head {
    schema: Option<String>,
    vpcut_version: Option<String>,
}

/// The record a run writes for one job.
pub(crate) struct Record<'a> {
    /// The job's path as given.
    pub(crate) job: &'a Path,
    /// The run's options.
    pub(crate) options: Options,
    /// The files the job read (path, role, bytes' hash).
    pub(crate) inputs: Vec<Hashed>,
    /// The files it looked for and did not find.
    pub(crate) absent: Vec<PathBuf>,
    /// Its outcome.
    pub(crate) outcome: &'a Outcome,
    /// Its report as JSON (`Report::to_json`).
    pub(crate) report: &'a str,
}

impl Record<'_> {
    /// The record as JSON text with a final newline.
    pub(crate) fn to_json(&self) -> String {
        #[derive(Serialize)]
        struct Write<'b> {
            schema: &'static str,
            vpcut_version: &'static str,
            job: String,
            options: Options,
            inputs: &'b [Hashed],
            absent: Vec<String>,
            outcome: &'b Outcome,
            report: &'b serde_json::value::RawValue,
        }
        let report: Box<serde_json::value::RawValue> =
            serde_json::from_str(self.report).expect("a report is JSON");
        let mut s = serde_json::to_string_pretty(&Write {
            schema: SCHEMA,
            vpcut_version: vpcut::VERSION,
            job: lossy(self.job),
            options: self.options,
            inputs: &self.inputs,
            absent: self.absent.iter().map(|p| lossy(p)).collect(),
            outcome: self.outcome,
            report: &report,
        })
        .expect("a record serializes");
        s.push('\n');
        s
    }
}

/// A path as text (its bytes that are not UTF-8 replaced).
fn lossy(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// The file name of the record of the job at `job` (as given).
pub(crate) fn file_name(job: &Path) -> String {
    use std::fmt::Write as _;
    let raw = job.as_os_str().as_encoded_bytes();
    let mut key = String::new();
    let mut cut = None;
    for &b in raw {
        if key.len() > MAX_KEY / 2 && cut.is_none() {
            cut = Some(key.len());
        }
        if b.is_ascii_alphanumeric() || b"-_.".contains(&b) {
            key.push(b as char);
        } else {
            let _ = write!(key, "%{b:02X}");
        }
    }
    if key.len() > MAX_KEY {
        use sha2::Digest as _;
        let digest = sha2::Sha256::digest(raw);
        key.truncate(cut.unwrap_or(key.len()));
        key.push('~');
        for b in &digest[..8] {
            let _ = write!(key, "{b:02x}");
        }
    }
    key.push_str(".json");
    key
}

/// SHA-256 of bytes, lower-case hex.
pub(crate) fn sha256(bytes: &[u8]) -> String {
    vpcut::InputFile::new("job", "", bytes).sha256
}

/// An earlier run's record of a job, when the job is unchanged since.
#[derive(Debug)]
pub(crate) struct Carried {
    /// The record's file.
    pub(crate) file: PathBuf,
    /// Its text (written again unchanged by `--report-dir`).
    pub(crate) text: String,
    /// The outcome it recorded.
    pub(crate) outcome: Outcome,
}

/// Check `--changed-since DIR` before any work: a folder that exists.
pub(crate) fn check_dir(dir: &Path) -> anyhow::Result<()> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(_) => anyhow::bail!(
            "--changed-since {}: not a folder: give the --report-dir of an earlier `vpcut check`",
            dir.display()
        ),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => anyhow::bail!(
            "--changed-since {}: no such folder: give the --report-dir of an earlier `vpcut check` (an empty folder checks every job)",
            dir.display()
        ),
        Err(e) => anyhow::bail!("--changed-since {}: {e}", dir.display()),
    }
}

/// The earlier record of the job at `job` in `dir`, when the job has not changed since it
/// (`None`: run it). A record that is not a record of this schema and version, of another
/// job (path) or other options is a changed job; a record of this version that cannot be
/// read is an error that names it.
pub(crate) fn unchanged(
    dir: &Path,
    job: &Path,
    options: Options,
) -> anyhow::Result<Option<Carried>> {
    let file = dir.join(file_name(job));
    let text = match std::fs::read(&file) {
        Ok(bytes) => String::from_utf8(bytes).map_err(|_| {
            anyhow::anyhow!(
                "--changed-since: {}: not UTF-8 text, not a record of `vpcut check --report-dir`",
                file.display()
            )
        })?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => anyhow::bail!("--changed-since: cannot read {}: {e}", file.display()),
    };
    let bad = |e: serde_json::Error| {
        anyhow::anyhow!(
            "--changed-since: {}:{}:{}: not a record of `vpcut check --report-dir` ({SCHEMA}): {e}",
            file.display(),
            e.line(),
            e.column()
        )
    };
    let head: Head = serde_json::from_str(&text).map_err(bad)?;
    if head.schema.as_deref() != Some(SCHEMA)
        || head.vpcut_version.as_deref() != Some(vpcut::VERSION)
    {
        return Ok(None);
    }
    let read: Read = serde_json::from_str(&text).map_err(bad)?;
    debug_assert_eq!(read.schema, SCHEMA);
    debug_assert_eq!(read.vpcut_version, vpcut::VERSION);
    if read.job != lossy(job) || read.options != options {
        return Ok(None);
    }
    let same = |h: &Hashed| std::fs::read(&h.path).is_ok_and(|b| sha256(&b) == h.sha256);
    let job_hashed = read
        .inputs
        .iter()
        .any(|h| h.role == "job" && h.path == read.job);
    if !job_hashed || !read.inputs.iter().all(same) {
        return Ok(None);
    }
    if read
        .absent
        .iter()
        .any(|p| std::fs::symlink_metadata(p).is_ok())
    {
        return Ok(None);
    }
    Ok(Some(Carried {
        file,
        text,
        outcome: read.outcome,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_are_the_path_percent_encoded_and_bounded() {
        assert_eq!(file_name(Path::new("jobs/a.toml")), "jobs%2Fa.toml.json");
        assert_eq!(
            file_name(Path::new("/t/a b%.toml")),
            "%2Ft%2Fa%20b%25.toml.json"
        );
        assert_ne!(file_name(Path::new("a/b")), file_name(Path::new("a%2Fb")));
        let long = "d/".repeat(150) + "j.toml";
        let a = file_name(Path::new(&long));
        let b = file_name(Path::new(&(long.clone() + "x")));
        assert!(a.len() <= MAX_KEY + 30, "{}", a.len());
        assert_ne!(a, b);
        assert!(a.starts_with("d%2Fd%2F") && a.ends_with(".json"), "{a}");
    }
}
