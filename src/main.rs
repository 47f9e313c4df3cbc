//! The `vpcut` command line: `vpcut simulate job.toml [--report report.json] [--check]`.
//!
//! Exit codes: 0 success, 1 only with `--check` when the verdict is fail, 2 bad input or
//! an output that cannot be written.

use anyhow::Context as _;
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Simulates CNC thread machining and reports gouges and leftover stock per turn.
#[derive(Parser)]
#[command(name = "vpcut", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a job: sweep every pass through the stock, compare with the ideal thread,
    /// print a summary and optionally write the JSON report.
    Simulate(SimulateArgs),
}

#[derive(clap::Args)]
struct SimulateArgs {
    /// The job file (TOML); see docs/job-format.md.
    job: PathBuf,
    /// Write the full report as JSON here (vpcut.report/1, see docs/report-format.md).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Exit with code 1 when the verdict is fail (for CI).
    #[arg(long)]
    check: bool,
    /// Dexel budget (both surfaces); the job is refused before allocating when its grid
    /// needs more. Default: the job's [simulation] max_dexels, else 2e8 (about 0.8 GB).
    #[arg(long, value_name = "N")]
    max_dexels: Option<u64>,
    /// Number of worker threads (default: all cores). Results do not depend on it.
    #[arg(long, short = 'j', value_name = "N")]
    threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    quiet: bool,
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Simulate(args) => simulate(args),
    }
}

fn simulate(args: SimulateArgs) -> anyhow::Result<ExitCode> {
    if let Some(n) = args.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build_global()
            .context("cannot set up the worker threads")?;
    }
    let src = std::fs::read_to_string(&args.job)
        .with_context(|| format!("cannot read the job file {}", args.job.display()))?;
    let job = vpcut::Job::from_toml(&src, &args.job.display().to_string())?;
    let opts = vpcut::Options {
        max_dexels: args.max_dexels,
    };
    let out =
        vpcut::simulate(&job, &opts).map_err(|e| anyhow::anyhow!("{}: {e}", args.job.display()))?;
    if let Some(path) = &args.report {
        write_atomic(path, out.report.to_json().as_bytes())?;
    }
    if !args.quiet {
        print!("{}", out.report.summary());
        if let Some(path) = &args.report {
            println!("  report written to {}", path.display());
        }
    }
    Ok(
        if args.check && out.report.verdict == vpcut::Verdict::Fail {
            ExitCode::from(1)
        } else {
            ExitCode::SUCCESS
        },
    )
}

/// Write a file through a temporary file in the same folder and a rename, so that a failed
/// run never leaves half a file.
fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        anyhow::anyhow!("cannot write {}: {e}", path.display())
    })
}
