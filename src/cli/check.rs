//! `vpcut check`: many jobs in one call, in parallel; the table of verdicts; `--shard I/N`
//! (`cli::shard`); `--report-dir DIR`, a record of each job (`cli::record`), and
//! `--changed-since DIR`, the jobs whose inputs are unchanged since such records carried
//! (their earlier outcome in the table, JUnit and SARIF, marked) and the others run.

use crate::cli::ci::{Case, Checked, Failed};
use crate::cli::count::parse_dexels;
use crate::cli::inputs::Inputs;
use crate::cli::output::{Allow, Outputs};
use crate::cli::record::{self, Carried, Options, Outcome, Record};
use crate::cli::term::{self, Progress, Stream};
use crate::{complete_report, error_place, error_text, load_job, parse_threads, places};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub(crate) struct CheckArgs {
    /// The job files (TOML).
    #[arg(required = true, value_name = "JOB")]
    jobs: Vec<PathBuf>,
    /// Memory budget per job, in dexels of 4 bytes (see `simulate --max-dexels`).
    #[arg(long, value_name = "N", value_parser = parse_dexels)]
    max_dexels: Option<u64>,
    /// Number of worker threads (default: all cores; at most 4 x the cores).
    #[arg(long, short = 'j', value_name = "N", value_parser = parse_threads)]
    threads: Option<usize>,
    /// Unknown words and codes in the jobs' NC programs are errors, not warnings.
    #[arg(long)]
    strict: bool,
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    quiet: bool,
    /// Check only shard I of N (`2/4`), for a CI matrix: the jobs sorted by path and dealt
    /// round robin, so the N shards together check every job once whatever order the
    /// shell lists them in (see docs/ci-formats.md).
    #[arg(long, value_name = "I/N", value_parser = crate::cli::shard::parse_shard)]
    shard: Option<crate::cli::shard::Shard>,
    /// Write a record of each job into this folder (made if missing): `<job path,
    /// percent-encoded>.json` with the SHA-256 of every file the job read, its outcome and
    /// its whole JSON report (see docs/ci-formats.md). The folder `--changed-since` reads.
    #[arg(long, value_name = "DIR")]
    report_dir: Option<PathBuf>,
    /// Run only the jobs that changed since the records in DIR (an earlier run's
    /// `--report-dir`): a job whose record has this vpcut's version and options and whose
    /// every input file has the recorded SHA-256 is not run; its recorded verdict and
    /// findings stand, marked `unchanged` in the table, JUnit and SARIF.
    #[arg(long, value_name = "DIR")]
    changed_since: Option<PathBuf>,
    #[command(flatten)]
    ci: crate::CiArgs,
}

/// What became of one job: run (and the record to write), or carried from its record.
enum Done {
    /// It ran (or could not be read).
    Ran {
        case: Case,
        /// The files it read, for `Outputs::protect`.
        read: Vec<PathBuf>,
        /// Its record, when it ran to a report.
        record: Option<String>,
    },
    /// Unchanged since its record.
    Carried { case: Case, text: String },
}

impl Done {
    fn case(&self) -> &Case {
        match self {
            Done::Ran { case, .. } | Done::Carried { case, .. } => case,
        }
    }
}

pub(crate) fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    use rayon::prelude::*;
    let clock = Instant::now();
    let mut jobs: Vec<&Path> = args.jobs.iter().map(PathBuf::as_path).collect();
    if let Some(shard) = args.shard {
        jobs = crate::cli::shard::select(&jobs, shard);
    }
    if let Some(dir) = &args.changed_since {
        record::check_dir(dir)?;
    }
    let mut outs = Outputs::new(&jobs);
    let slots = args.ci.slots(&mut outs)?;
    if let Some(dir) = &args.report_dir {
        outs.folder(dir, "--report-dir")?;
    }
    crate::set_threads(args.threads)?;
    let say = if outs.uses_stdout() {
        Stream::Stderr
    } else {
        Stream::Stdout
    };
    let progress = Progress::new(args.quiet);
    let opts = vpcut::SimOptions {
        max_dexels: args.max_dexels,
    };
    let options = Options {
        strict: args.strict,
        max_dexels: args.max_dexels,
    };
    // The records first (an unreadable one stops the run before any work), in job order.
    let carried: Vec<Option<Carried>> = match &args.changed_since {
        Some(dir) => jobs
            .iter()
            .map(|j| record::unchanged(dir, j, options))
            .collect::<anyhow::Result<_>>()?,
        None => jobs.iter().map(|_| None).collect(),
    };
    let torun = carried.iter().filter(|c| c.is_none()).count();
    let what = match carried.len() - torun {
        0 => format!("checking {} jobs", jobs.len()),
        n => format!("checking {torun} jobs ({n} unchanged)"),
    };
    let done: Vec<Done> = progress.stage(&what, || {
        jobs.par_iter()
            .zip(carried)
            .map(|(p, earlier)| match earlier {
                Some(c) => Done::Carried {
                    case: Case {
                        job: p.to_path_buf(),
                        seconds: 0.0,
                        result: Ok(Checked {
                            outcome: c.outcome,
                            unchanged_since: Some(c.file),
                        }),
                    },
                    text: c.text,
                },
                None => check_one(p, options, &opts, args.report_dir.is_some()),
            })
            .collect()
    });
    let read: Vec<PathBuf> = done
        .iter()
        .flat_map(|d| match d {
            Done::Ran { read, .. } => read.clone(),
            Done::Carried { .. } => Vec::new(),
        })
        .collect();
    outs.protect(&read)?;
    if let Some(dir) = &args.report_dir {
        for d in &done {
            let (case, text) = match d {
                Done::Ran {
                    case,
                    record: Some(text),
                    ..
                } => (case, text),
                Done::Carried { case, text } => (case, text),
                Done::Ran { record: None, .. } => continue,
            };
            let slot = outs.file(
                &dir.join(record::file_name(&case.job)),
                "--report-dir",
                Allow::File,
            )?;
            outs.put(slot, text.as_bytes())?;
        }
    }
    let cases: Vec<&Case> = done.iter().map(Done::case).collect();
    crate::CiArgs::write(slots, &cases, &mut outs)?;
    let written = progress.stage("writing", || outs.commit())?;
    if !args.quiet {
        say.write(&check_table(&cases, say, clock.elapsed().as_secs_f64()));
        let records = args.report_dir.as_ref().map(|d| (d, cases.len()));
        for p in written {
            if records.is_some_and(|(d, _)| p.starts_with(d)) {
                continue;
            }
            say.write(&format!("  wrote {}\n", p.display()));
        }
        if let Some((d, n)) = records {
            say.write(&format!(
                "  wrote the records of {n} jobs into {}\n",
                d.display()
            ));
        }
    }
    // The jobs that could not be checked, whatever -q says.
    for c in &cases {
        if let Err(e) = &c.result {
            term::err(&term::diagnostics(&format!("{}\n", e.message)));
        }
    }
    let bad = cases.iter().any(|c| c.result.is_err());
    let failed = cases
        .iter()
        .any(|c| matches!(&c.result, Ok(k) if k.outcome.fail));
    Ok(if bad {
        ExitCode::from(2)
    } else if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Read and simulate one job of `vpcut check`; whatever goes wrong is its outcome. Also
/// the files it read, and its record (`--report-dir`) when it ran to a report.
fn check_one(path: &Path, options: Options, opts: &vpcut::SimOptions, keep: bool) -> Done {
    let start = Instant::now();
    let inputs = Inputs::default();
    let run = || -> anyhow::Result<(Checked, String)> {
        let (job, text) = load_job(path, options.strict, &inputs)?;
        let mut report = vpcut::simulate_report(&job, opts)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        complete_report(&mut report, &inputs);
        let outcome = Outcome::of(&report, places(&report, path, &text, &job, &inputs));
        let json = if keep {
            report.to_json()
        } else {
            String::new()
        };
        Ok((
            Checked {
                outcome,
                unchanged_since: None,
            },
            json,
        ))
    };
    let (result, report) = match run() {
        Ok((c, json)) => (Ok(c), Some(json)),
        Err(e) => (
            Err(Failed {
                message: error_text(&e),
                place: error_place(&e, path),
            }),
            None,
        ),
    };
    let record = match (&result, report) {
        (Ok(c), Some(json)) if keep => Some(
            Record {
                job: path,
                options,
                inputs: inputs.hashed(),
                absent: inputs.absent(),
                outcome: &c.outcome,
                report: &json,
            }
            .to_json(),
        ),
        _ => None,
    };
    let case = Case {
        job: path.to_path_buf(),
        seconds: start.elapsed().as_secs_f64(),
        result,
    };
    Done::Ran {
        case,
        read: inputs.paths(),
        record,
    }
}

/// The table of `vpcut check`: one line per job, then the totals. A job carried from an
/// earlier record says `unchanged` where the others give their time.
fn check_table(cases: &[&Case], stream: Stream, wall_s: f64) -> String {
    use std::fmt::Write as _;
    let on = stream.colour();
    let width = cases
        .iter()
        .map(|c| c.job.display().to_string().chars().count())
        .max()
        .unwrap_or(3)
        .max(3);
    let mut s = format!(
        "{:<width$}  verdict  worst gouge mm  worst leftover mm  errors  warnings     time s\n",
        "job"
    );
    let (mut pass, mut fail, mut bad, mut same) = (0, 0, 0, 0);
    for c in cases {
        let job = c.job.display().to_string();
        let pad = " ".repeat(width - job.chars().count());
        match &c.result {
            Ok(k) => {
                let r = &k.outcome;
                let tol = r.tolerance_mm;
                let (word, style) = if r.fail {
                    fail += 1;
                    ("FAIL", term::RED)
                } else {
                    pass += 1;
                    ("PASS", term::GREEN)
                };
                let cell = |x: f64, w: usize| {
                    let text = format!("{:>w$}", readable_mm(x));
                    if x > tol {
                        term::paint(on, term::RED, &text)
                    } else {
                        text
                    }
                };
                let time = if k.unchanged_since.is_some() {
                    same += 1;
                    "unchanged".to_string()
                } else {
                    format!("{:.2}", c.seconds)
                };
                let _ = writeln!(
                    s,
                    "{job}{pad}  {}     {}  {}  {:>6}  {:>8}  {:>9}",
                    term::paint(on, style, word),
                    cell(r.max_gouge_mm, 14),
                    cell(r.max_leftover_mm, 17),
                    r.errors,
                    r.warnings,
                    time
                );
            }
            Err(_) => {
                bad += 1;
                let _ = writeln!(
                    s,
                    "{job}{pad}  {}    {:>14}  {:>17}  {:>6}  {:>8}  {:>9.2}",
                    term::paint(on, term::RED, "ERROR"),
                    "-",
                    "-",
                    "-",
                    "-",
                    c.seconds
                );
            }
        }
    }
    let unchanged = if same > 0 {
        format!(" ({same} unchanged since their records, not run)")
    } else {
        String::new()
    };
    let _ = writeln!(
        s,
        "{} job{}: {pass} pass, {fail} fail, {bad} cannot be checked{unchanged}; {:.2} s in all",
        cases.len(),
        if cases.len() == 1 { "" } else { "s" },
        wall_s
    );
    s
}

/// A length in mm with 4 decimals, or scientific when huge.
fn readable_mm(x: f64) -> String {
    if x.abs() >= 1e7 {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}
