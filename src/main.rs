//! The `vpcut` command line: `vpcut simulate job.toml [--report report.json] [--check]
//! [--gltf out.glb] [--png out.png] [--html report.html]`, `vpcut render model.glb --png view.png`,
//! `vpcut toolpath program --dialect D`, `vpcut plan job.toml --dialect D`.
//!
//! Every option and output path is checked before any work starts; outputs are written to
//! temporaries and put in place only when all of them succeeded (`cli::output`), so a run
//! that fails leaves existing files as they were. `-` is standard output for `--report`,
//! `--gltf` and `plan -o`. Nothing prints with `println!`: a closed pipe ends the output
//! quietly (`cli::term`).
//!
//! Exit codes: 0 success, 1 only with `--check` when the verdict is fail, 2 bad input or
//! an output that cannot be written.

mod cli;

use anyhow::Context as _;
use clap::{Parser, Subcommand};
use cli::ci::{self, Case, Checked, Place};
use cli::count::parse_dexels;
use cli::html::Html;
use cli::inputs::{self, Inputs};
use cli::output::{Allow, Outputs, Slot};
use cli::term::{self, Progress, Stream};
use cli::toolpath::{toolpath, ToolpathArgs};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

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
    Simulate(Box<SimulateArgs>),
    /// Verify many jobs in one call (in parallel): one line per job with its verdict, worst
    /// gouge and leftover and time; exit 1 if any fails, 2 if any cannot be read.
    Check(cli::check::CheckArgs),
    /// Render a model written by `simulate --gltf` (headless, wgpu) to PNG pictures.
    Render(RenderArgs),
    /// Interpret an NC program and print its moves (CSV by default), as the control would
    /// run them: end points in mm, leads for thread moves.
    Toolpath(ToolpathArgs),
    /// Plan the passes of a job's `[process] kind = "plan"` and write them as an NC
    /// program; `--check` reads it back and simulates it.
    Plan(PlanArgs),
}

#[derive(clap::Args)]
struct RenderArgs {
    /// The model (`.glb` written by `vpcut simulate --gltf`).
    model: PathBuf,
    #[command(flatten)]
    picture: PictureArgs,
}

/// Headless pictures of the cut part (wgpu: a GPU, or Mesa's software Vulkan).
#[derive(clap::Args)]
struct PictureArgs {
    /// Render the cut part to this PNG (the camera is `--view`).
    #[arg(long, value_name = "FILE")]
    png: Option<PathBuf>,
    /// Render every view into this folder as `iso.png`, `front.png`, `section.png` and
    /// `closeup.png`.
    #[arg(long, value_name = "DIR")]
    renders: Option<PathBuf>,
    /// Camera of `--png`: `iso` (the default), `front`, `section` (the near half cut away
    /// along the axis: the machined profile as a solid cut face with the ideal profile over
    /// it) or `closeup` (a section through the worst finding).
    #[arg(long, value_parser = parse_view)]
    view: Option<vpcut::View>,
    /// Picture size `WIDTHxHEIGHT` in pixels (default 1024x768): the width a multiple of 64
    /// from 256, the height from 192, both at most 8192 and the adapter's limit.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Multisampling (anti-aliasing): 4 (the default) or 1 samples per pixel.
    #[arg(long, value_name = "N", value_parser = parse_msaa)]
    msaa: Option<u32>,
    /// Draw feature edges (crests, roots, flank corners) as dark lines.
    #[arg(long)]
    edges: bool,
    /// The toolpath in the whole-part views: `auto` (the default: in full while its lines
    /// cross at most 12 % of the part's pixels, translucent up to 30 %, left out beyond, as
    /// the caption says), `full` or `off`.
    #[arg(long, value_name = "MODE", value_parser = parse_toolpath)]
    toolpath: Option<vpcut::ToolpathMode>,
    /// Leave the toolpath out of the whole-part views (`--toolpath off`).
    #[arg(long, conflicts_with = "toolpath")]
    no_toolpath: bool,
}

fn parse_toolpath(s: &str) -> Result<vpcut::ToolpathMode, String> {
    vpcut::ToolpathMode::from_name(s)
        .ok_or_else(|| format!("expected one of auto, full, off, not `{s}`"))
}

fn parse_view(s: &str) -> Result<vpcut::View, String> {
    vpcut::View::from_name(s)
        .ok_or_else(|| format!("expected one of iso, front, section, closeup, not `{s}`"))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 1024x768, not `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let size = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    vpcut::RenderOptions {
        width: size.0,
        height: size.1,
        ..Default::default()
    }
    .validate()
    .map_err(|e| e.to_string())?;
    Ok(size)
}

fn parse_plot_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 1600x900, not `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(320..=8192).contains(&w) || !(320..=8192).contains(&h) {
        return Err(format!(
            "plot size {w}x{h}: each side from 320 to 8192 pixels"
        ));
    }
    Ok((w, h))
}

fn parse_msaa(s: &str) -> Result<u32, String> {
    match s {
        "1" => Ok(1),
        "4" => Ok(4),
        _ => Err(format!("expected 1 or 4 samples per pixel, not `{s}`")),
    }
}

/// `-j N`: at least 1, at most four times the cores there are (and 1024): more threads
/// only cost memory and time, and a typo like `-j 100000` is refused at once.
fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s
        .parse()
        .map_err(|_| format!("expected a number of threads, not `{s}`"))?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let max = (4 * cores).min(1024);
    if n == 0 {
        return Err("expected at least 1 thread".into());
    }
    if n > max {
        return Err(format!(
            "at most {max} threads (4 x the {cores} cores here; more only cost memory)"
        ));
    }
    Ok(n)
}

fn parse_finite(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite number, not `{s}`")),
    }
}

fn parse_tolerance(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!(
            "expected a finite number of mm, 0 or more, not `{s}`"
        )),
    }
}

/// The pictures asked for, checked against the adapter before any work.
struct Pictures {
    renderer: vpcut::Renderer,
    /// `--png`: its slot and options.
    png: Option<(Slot, vpcut::RenderOptions)>,
    /// `--renders`: every view's slot and options.
    renders: Vec<(Slot, vpcut::RenderOptions)>,
}

impl PictureArgs {
    fn wanted(&self) -> bool {
        self.png.is_some() || self.renders.is_some()
    }

    /// Check the options (the ones that only make sense with a picture need one), start the
    /// renderer and check the size against the adapter, and reserve the output files.
    fn prepare(&self, outs: &mut Outputs, progress: &Progress) -> anyhow::Result<Option<Pictures>> {
        if self.png.is_none() && self.view.is_some() {
            anyhow::bail!(
                "--view chooses the camera of --png: give --png FILE (--renders DIR draws every view)"
            );
        }
        if !self.wanted() {
            let given = [
                (self.size.is_some(), "--size"),
                (self.msaa.is_some(), "--msaa"),
                (self.edges, "--edges"),
                (self.no_toolpath, "--no-toolpath"),
                (self.toolpath.is_some(), "--toolpath"),
            ];
            if let Some((_, flag)) = given.iter().find(|g| g.0) {
                anyhow::bail!("{flag} is for pictures: give --png FILE or --renders DIR");
            }
            return Ok(None);
        }
        let (width, height) = self.size.unwrap_or((1024, 768));
        let opts = |view| vpcut::RenderOptions {
            view,
            width,
            height,
            edges: self.edges,
            toolpath: if self.no_toolpath {
                vpcut::ToolpathMode::Off
            } else {
                self.toolpath.unwrap_or_default()
            },
        };
        let base = opts(self.view.unwrap_or(vpcut::View::Iso));
        base.validate()?;
        let png = match &self.png {
            Some(p) => Some((outs.file(p, "--png", Allow::File)?, base)),
            None => None,
        };
        let mut renders = Vec::new();
        if let Some(dir) = &self.renders {
            outs.folder(dir, "--renders")?;
            for view in vpcut::View::ALL {
                let path = dir.join(format!("{}.png", view.name()));
                renders.push((outs.file(&path, "--renders", Allow::File)?, opts(view)));
            }
        }
        let renderer = progress.stage("starting the renderer", || {
            cli::quiet::gpu_quiet(|| vpcut::Renderer::new(self.msaa.unwrap_or(4)))
        })?;
        renderer.check(&base)?;
        Ok(Some(Pictures {
            renderer,
            png,
            renders,
        }))
    }
}

impl Pictures {
    /// Draw every picture into its slot.
    fn draw(
        &self,
        scene: &vpcut::Scene,
        outs: &mut Outputs,
        progress: &Progress,
    ) -> anyhow::Result<()> {
        for (slot, opts) in self.png.iter().chain(&self.renders) {
            let bytes = progress
                .stage(&format!("rendering the {} view", opts.view.name()), || {
                    self.renderer.png(scene, opts)
                })?;
            outs.put(*slot, &bytes)?;
        }
        Ok(())
    }
}

#[derive(clap::Args)]
struct PlanArgs {
    /// The job file (TOML) with `[process] kind = "plan"`; see docs/job-format.md.
    job: PathBuf,
    /// The controller: `fanuc`, `gsk980`, `siemens-802d`, `siemens-840d` (the 802D program,
    /// which the 840D runs unchanged) or `linuxcnc`.
    #[arg(long)]
    dialect: String,
    /// FANUC: the compact Custom Macro B version (layer tables and WHILE loops).
    #[arg(long = "macro")]
    macro_b: bool,
    /// Write the program here (atomically); `-` or none: standard output (the summary then
    /// goes to standard error).
    #[arg(long, short = 'o', value_name = "FILE")]
    output: Option<PathBuf>,
    /// Read the program back, check it gives exactly the planned passes, simulate it and
    /// exit with 1 unless it passes.
    #[arg(long)]
    check: bool,
    /// Print nothing but the program and errors.
    #[arg(long, short = 'q')]
    quiet: bool,
}

#[derive(clap::Args)]
struct SimulateArgs {
    /// The job file (TOML); see docs/job-format.md.
    job: PathBuf,
    /// Write the full report as JSON here (vpcut.report/1, see docs/report-format.md);
    /// `-`: standard output (the summary then goes to standard error).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Exit with code 1 when the verdict is fail (for CI).
    #[arg(long)]
    check: bool,
    /// Memory budget, in dexels of 4 bytes (2e8 is 800 MB): the run is refused before it
    /// allocates the stock when what it would hold at once is more, and the error says
    /// what that is, term by term. Counted: the stock (the whole grid, both surfaces, and
    /// the edges' cut with rubbing tool bodies, when --png/--renders, --plots or --html
    /// need it; else a column per thread, two with rubbing bodies, and with --gltf the
    /// columns from one of the model's kept columns to the next), each thread's
    /// comparison, the results of a wave of columns, the bodies' tables, the turned
    /// profile, the measurement generators. Written 400000000, 400_000_000, 4e8 or 4.0e8.
    /// Default: the job's [simulation] max_dexels, else 2e8.
    #[arg(long, value_name = "N", value_parser = parse_dexels)]
    max_dexels: Option<u64>,
    /// Number of worker threads (default: all cores; at most 4 x the cores). Results do
    /// not depend on it.
    #[arg(long, short = 'j', value_name = "N", value_parser = parse_threads)]
    threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long, short = 'q')]
    quiet: bool,
    /// Unknown words and codes in the job's NC program are errors, not warnings.
    #[arg(long)]
    strict: bool,
    /// Write the pictures that need no GPU here: `developed.png` (the deviation field
    /// unrolled, angle x z) and `section.png` (machined vs ideal profile along a generator).
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
    /// Angle of the generator in `section.png` and the first of `trace.png` (deg on the
    /// part; default: the angle of the report's worst deviation beyond the tolerance, so
    /// both run through it; 0 when the cut is within it).
    #[arg(long, value_name = "DEG", requires = "plots", value_parser = parse_finite)]
    section_angle: Option<f64>,
    /// Size of `developed.png` as `WIDTHxHEIGHT` pixels (default 1600x900; each side 320
    /// to 8192); `section.png` and `trace.png` take its width and 2/3 and 5/9 of its
    /// height. Text sizes follow the picture.
    #[arg(long, value_name = "WxH", value_parser = parse_plot_size)]
    plot_size: Option<(u32, u32)>,
    /// Write the cut part as binary glTF (`.glb`): the stock coloured by deviation, the
    /// toolpath, the tool, and the report summary in `extras`; positions in metres. `-`:
    /// standard output.
    #[arg(long, value_name = "FILE")]
    gltf: Option<PathBuf>,
    /// Also put the ideal thread surface (translucent) into the glTF.
    #[arg(long, requires = "gltf")]
    gltf_ideal: bool,
    /// Largest distance (mm) the exported surface may stray from the dexel data
    /// (default: the job's tolerance; the mesh is simplified to it).
    #[arg(long, value_name = "MM", conflicts_with = "gltf_full", requires = "gltf", value_parser = parse_tolerance)]
    gltf_tolerance: Option<f64>,
    /// Export every dexel as a vertex (no simplification; large files).
    #[arg(long, requires = "gltf")]
    gltf_full: bool,
    /// Write a self-contained HTML report here: the verdict, the job, the per-turn table,
    /// the findings with the pass (and NC block) that made them, the plots, the renders
    /// where there is a GPU adapter, and an interactive 3D view of the cut part (WebGL2).
    /// `-`: standard output.
    #[arg(long, value_name = "FILE")]
    html: Option<PathBuf>,
    #[command(flatten)]
    picture: PictureArgs,
    #[command(flatten)]
    ci: CiArgs,
}

/// Reports for CI systems.
#[derive(clap::Args)]
struct CiArgs {
    /// Write JUnit XML here: a testsuite per job, a testcase per turn and per check, a
    /// failure per error finding. `-`: standard output.
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    /// Write SARIF 2.1.0 here: a result per finding, located at the NC program's line where
    /// it has one, else in the job file. `-`: standard output.
    #[arg(long, value_name = "FILE")]
    sarif: Option<PathBuf>,
}

impl CiArgs {
    /// Reserve the outputs.
    fn slots(&self, outs: &mut Outputs) -> anyhow::Result<(Option<Slot>, Option<Slot>)> {
        let junit = match &self.junit {
            Some(p) => Some(outs.file(p, "--junit", Allow::FileOrStdout)?),
            None => None,
        };
        let sarif = match &self.sarif {
            Some(p) => Some(outs.file(p, "--sarif", Allow::FileOrStdout)?),
            None => None,
        };
        Ok((junit, sarif))
    }

    /// Write them.
    fn write(
        slots: (Option<Slot>, Option<Slot>),
        cases: &[&Case],
        outs: &mut Outputs,
    ) -> anyhow::Result<()> {
        if let Some(slot) = slots.0 {
            outs.put(slot, ci::junit(cases).as_bytes())?;
        }
        if let Some(slot) = slots.1 {
            outs.put(slot, ci::sarif(cases).as_bytes())?;
        }
        Ok(())
    }
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
            report_error(&e);
            ExitCode::from(2)
        }
    }
}

/// An error on standard error: job and program diagnostics as they render themselves
/// (they say `error:` themselves), everything else as `error: ...` with its causes.
fn report_error(e: &anyhow::Error) {
    match diagnostic_text(e) {
        Some(text) => term::err(&term::diagnostics(&format!("{text}\n"))),
        None => term::error(&format!("{e:#}")),
    }
}

/// The NC program error inside an error, if that is what it is.
fn program_error(e: &anyhow::Error) -> Option<&vpcut::NcError> {
    e.downcast_ref::<vpcut::NcError>()
        .or_else(|| match e.downcast_ref() {
            Some(vpcut::JobError::Program(nc)) => Some(nc.as_ref()),
            _ => None,
        })
}

/// A job or program error as its diagnostics render it (without colour).
fn diagnostic_text(e: &anyhow::Error) -> Option<String> {
    match program_error(e) {
        Some(nc) => Some(nc.to_string()),
        None => e.downcast_ref::<vpcut::JobError>().map(|j| j.to_string()),
    }
}

/// An error as text, the way `report_error` prints it (without colour).
fn error_text(e: &anyhow::Error) -> String {
    diagnostic_text(e).unwrap_or_else(|| format!("error: {e:#}"))
}

/// Where an error is: the file, line and column it names, else the job file.
fn error_place(e: &anyhow::Error, job: &Path) -> Place {
    let at = |file: &str, line: usize, column: usize| Place {
        file: PathBuf::from(file),
        line: line.max(1),
        column: column.max(1),
    };
    if let Some(nc) = program_error(e) {
        return at(&nc.file, nc.line, nc.col);
    }
    match e.downcast_ref::<vpcut::JobError>() {
        Some(vpcut::JobError::Syntax {
            file, line, col, ..
        })
        | Some(vpcut::JobError::Invalid {
            file, line, col, ..
        }) => at(file, *line, *col),
        _ => at(&job.display().to_string(), 1, 1),
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Simulate(args) => simulate(*args),
        Command::Check(args) => cli::check::check(args),
        Command::Render(args) => render(args),
        Command::Toolpath(args) => toolpath(args),
        Command::Plan(args) => plan(args),
    }
}

/// Read a job and the files it names beside it (recorded in `inputs`); program diagnostics
/// name the files that hold the programs.
fn load_job(path: &Path, strict: bool, inputs: &Inputs) -> anyhow::Result<(vpcut::Job, String)> {
    let (src, bytes) = inputs::read_text(path, "the job file")?;
    inputs.add("job", path.to_path_buf(), path.display().to_string(), bytes);
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let load = inputs.loader(&dir);
    let job = vpcut::Job::from_toml_opts(&src, &path.display().to_string(), &load, strict)
        .map_err(|e| match e {
            vpcut::JobError::Program(mut nc) => {
                name_files(&mut nc, inputs);
                anyhow::Error::from(vpcut::JobError::Program(nc))
            }
            e => e.into(),
        })?;
    Ok((job, src))
}

/// Where each finding of a report is (for SARIF).
fn places(
    report: &vpcut::Report,
    job_path: &Path,
    job_text: &str,
    job: &vpcut::Job,
    inputs: &Inputs,
) -> Vec<(Place, Option<Place>)> {
    let program_file = |name: &str| inputs.program_file(name);
    report
        .findings
        .iter()
        .map(|f| ci::place(f, job_path, job_text, &program_file, &job.pass_blocks))
        .collect()
}

/// Diagnostics name programs (`O2`, `MYBBB.SPF`); say the file's path instead.
fn name_files(nc: &mut vpcut::NcError, inputs: &Inputs) {
    if let Some(p) = inputs.program_file(&nc.file) {
        nc.file = p.display().to_string();
    }
    for d in &mut nc.others {
        name_file(d, inputs);
    }
}

fn name_file(d: &mut vpcut::Diagnostic, inputs: &Inputs) {
    if let Some(p) = inputs.program_file(&d.file) {
        d.file = p.display().to_string();
    }
}

/// What the library cannot know: the input files with their hashes, and program findings
/// naming the file that holds the program (as the job names it), not the program (`O2`).
fn complete_report(report: &mut vpcut::Report, inputs: &Inputs) {
    report.inputs = inputs.report();
    for f in &mut report.findings {
        if let Some(name) = f.file.as_deref().and_then(|n| inputs.program_name(n)) {
            f.file = Some(name);
        }
    }
}

/// Set up the worker threads (`-j`; already range-checked).
fn set_threads(n: Option<usize>) -> anyhow::Result<()> {
    if let Some(n) = n {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("cannot set up the worker threads")?;
    }
    Ok(())
}

/// A count or size as a person reads it: whole up to a million, else in scientific form
/// (never a 20-digit number).
fn readable(x: f64) -> String {
    if x.abs() < 1e6 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

fn plan(args: PlanArgs) -> anyhow::Result<ExitCode> {
    let post = vpcut::post::Post::from_name(&args.dialect, args.macro_b).with_context(|| {
        format!(
            "unknown dialect `{}`{}: expected `fanuc`, `gsk980`, `linuxcnc`, `siemens-802d` or `siemens-840d` (--macro: fanuc only)",
            args.dialect,
            if args.macro_b { " with --macro" } else { "" }
        )
    })?;
    let mut outs = Outputs::new(&[&args.job]);
    let dash = PathBuf::from("-");
    let slot = outs.file(
        args.output.as_ref().unwrap_or(&dash),
        "-o",
        Allow::FileOrStdout,
    )?;
    // The summary goes where the program does not.
    let say = if outs.uses_stdout() {
        Stream::Stderr
    } else {
        Stream::Stdout
    };
    let inputs = Inputs::default();
    let (job, _) = load_job(&args.job, false, &inputs)?;
    outs.protect(&inputs.paths())?;
    let plan = job.plan.as_ref().with_context(|| {
        format!(
            "{}: nothing to plan: give the job a [process] with kind = \"plan\" and its limits (docs/job-format.md)",
            args.job.display()
        )
    })?;
    let tool_id = job.tools[plan.tool].id;
    let name = if job.name.is_empty() {
        args.job.display().to_string()
    } else {
        job.name.clone()
    };
    let text = vpcut::post::post(plan, tool_id, &name, post)?;
    let summary = vpcut::post::summary(plan, post);
    outs.put(slot, text.as_bytes())?;
    let written = outs.commit()?;
    if !args.quiet {
        say.write(&summary);
        for p in written {
            say.write(&format!("  program written to {}\n", p.display()));
        }
    }
    if !args.check {
        return Ok(ExitCode::SUCCESS);
    }
    // The round trip: read the program back and simulate what it cuts.
    let file = args
        .output
        .as_ref()
        .filter(|p| p.as_os_str() != "-")
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "plan.nc".into());
    let back = job.with_program(&file, &text, &args.dialect)?;
    if let Some(why) = vpcut::post::differ(&vpcut::post::toolpath(plan, post), &back.passes) {
        term::error(&format!(
            "the program does not read back to the plan: {why}"
        ));
        return Ok(ExitCode::from(1));
    }
    let progress = Progress::new(args.quiet);
    let out = progress
        .stage("simulating the program", || {
            vpcut::simulate(&back, &vpcut::SimOptions::default())
        })
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.job.display()))?;
    if !args.quiet {
        say.write(&format!(
            "  read back: {} passes, the planned ones; simulated:\n",
            back.passes.len()
        ));
        say.write(&term::summary(&out.report, say, None));
    }
    Ok(if out.report.verdict == vpcut::Verdict::Fail {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn render(args: RenderArgs) -> anyhow::Result<ExitCode> {
    if !args.picture.wanted() {
        anyhow::bail!("nothing to do: give --png FILE or --renders DIR");
    }
    let progress = Progress::new(false);
    let mut outs = Outputs::new(&[&args.model]);
    let pictures = args
        .picture
        .prepare(&mut outs, &progress)?
        .expect("pictures are wanted");
    let bytes = inputs::read_bytes(&args.model, "the model")?;
    let scene = vpcut::from_glb(&bytes).with_context(|| format!("{}", args.model.display()))?;
    pictures.draw(&scene, &mut outs, &progress)?;
    outs.commit()?;
    Ok(ExitCode::SUCCESS)
}

fn simulate(args: SimulateArgs) -> anyhow::Result<ExitCode> {
    let clock = Instant::now();
    let progress = Progress::new(args.quiet);
    // Every option and output first: nothing is simulated for a run that cannot finish.
    let mut outs = Outputs::new(&[&args.job]);
    let report_slot = match &args.report {
        Some(p) => Some(outs.file(p, "--report", Allow::FileOrStdout)?),
        None => None,
    };
    let gltf_slot = match &args.gltf {
        Some(p) => Some(outs.file(p, "--gltf", Allow::FileOrStdout)?),
        None => None,
    };
    let plot_slots = match &args.plots {
        Some(dir) => {
            outs.folder(dir, "--plots")?;
            Some((
                outs.file(&dir.join("developed.png"), "--plots", Allow::File)?,
                outs.file(&dir.join("section.png"), "--plots", Allow::File)?,
                outs.file(&dir.join("trace.png"), "--plots", Allow::File)?,
            ))
        }
        None => None,
    };
    if args.plot_size.is_some() && args.plots.is_none() && args.html.is_none() {
        anyhow::bail!("--plot-size is the size of the plots: give --plots DIR or --html FILE");
    }
    let ci_slots = args.ci.slots(&mut outs)?;
    let pictures = args.picture.prepare(&mut outs, &progress)?;
    let html = match &args.html {
        Some(p) => Some(Html::prepare(p, &mut outs, &progress, pictures.is_some())?),
        None => None,
    };
    set_threads(args.threads)?;
    let inputs = Inputs::default();
    let (job, job_text) = progress.stage("reading the job", || {
        load_job(&args.job, args.strict, &inputs)
    })?;
    outs.protect(&inputs.paths())?;
    // The summary goes where no output does.
    let say = if outs.uses_stdout() {
        Stream::Stderr
    } else {
        Stream::Stdout
    };
    if !args.quiet {
        for w in &job.program_warnings {
            let mut w = w.clone();
            name_file(&mut w, &inputs);
            term::err(&term::diagnostics(&format!("{w}\n")));
        }
    }
    let opts = vpcut::SimOptions {
        max_dexels: args.max_dexels,
    };
    let e = if args.gltf_full {
        Some(0.0)
    } else {
        args.gltf_tolerance
    };
    // Only the pictures, the plots and the page need the whole grid: without them the
    // columns stream (the same report; the model alone meshed as they stream, same bytes).
    let pictured = pictures.is_some() || plot_slots.is_some() || html.is_some();
    let model = vpcut::SceneOptions {
        mesh_tolerance: e,
        ideal: args.gltf_ideal,
    };
    let (mut report, mut grids, mut meshed) = progress
        .stage("simulating: sweep, compare, measure", || {
            if gltf_slot.is_some() && !pictured {
                vpcut::simulate_meshed(&job, &opts, &model)
                    .map(|m| (m.report.clone(), None, Some(m)))
            } else if pictured {
                vpcut::simulate(&job, &opts).map(|o| (o.report.clone(), Some(o), None))
            } else {
                vpcut::simulate_report(&job, &opts).map(|r| (r, None, None))
            }
        })
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.job.display()))?;
    complete_report(&mut report, &inputs);
    if let Some(o) = &mut grids {
        o.report = report.clone();
    }
    meshed.iter_mut().for_each(|m| m.report = report.clone());
    if let Some(slot) = report_slot {
        outs.put(slot, report.to_json().as_bytes())?;
    }
    // Pictures use the default mesh and the ideal (drawn on section planes); the model
    // shares that mesh unless it asks for another tolerance.
    let picture_scene = (pictures.is_some() || html.is_some()).then(|| {
        progress.stage("meshing the part", || {
            vpcut::build_scene(
                &job,
                grids.as_ref().expect("the grid was kept"),
                &vpcut::SceneOptions {
                    mesh_tolerance: None,
                    ideal: true,
                },
            )
        })
    });
    if let Some(slot) = gltf_slot {
        if args.gltf_full && !args.quiet {
            let bytes = GLB_BYTES_PER_DEXEL * report.stock.dexels as f64;
            if bytes > 50e6 {
                term::err(&format!(
                    "--gltf-full: every one of the {} dexels is a vertex: about {} MB to write\n",
                    readable(report.stock.dexels as f64),
                    readable(bytes / 1e6)
                ));
            }
        }
        let scene = match (meshed.take(), &picture_scene, e) {
            (Some(m), _, _) => m.into_scene(),
            (None, Some(s), None) => vpcut::Scene {
                ideal: if args.gltf_ideal {
                    s.ideal.clone()
                } else {
                    None
                },
                ..s.clone()
            },
            _ => progress.stage("meshing the part for the model", || {
                vpcut::build_scene(&job, grids.as_ref().expect("the grid was kept"), &model)
            }),
        };
        let glb = progress.stage("encoding the model", || vpcut::to_glb(&scene))?;
        outs.put(slot, &glb)?;
    }
    if let (Some(p), Some(scene)) = (&pictures, &picture_scene) {
        p.draw(scene, &mut outs, &progress)?;
    }
    let mut plots = None;
    if plot_slots.is_some() || html.is_some() {
        let tol = job.sim.tolerance;
        let stock = &grids.as_ref().expect("the grid was kept").stock;
        let name = args
            .job
            .parent()
            .and_then(|p| p.file_name())
            .or(args.job.file_stem())
            .map_or_else(|| "job".into(), |n| n.to_string_lossy().into_owned());
        let verdict = match report.verdict {
            vpcut::Verdict::Pass => "PASS",
            vpcut::Verdict::Fail => "FAIL",
        };
        let title = format!("{name}: {verdict}");
        let angle = args.section_angle.map_or_else(
            || {
                let out = grids.as_ref().expect("the grid was kept");
                vpcut::section_angle(&out.deviation, &stock.grid, tol)
            },
            f64::to_radians,
        );
        // The page alone shows them at most 720 pixels wide: smaller ones cost less.
        let (dw, dh, sw, sh, tw, th) = if let Some((w, h)) = args.plot_size {
            (w, h, w, (h * 2).div_ceil(3), w, (h * 5).div_ceil(9))
        } else if plot_slots.is_some() {
            (1600, 900, 1600, 600, 1600, 500)
        } else {
            (1024, 576, 1200, 450, 1200, 375)
        };
        let (dev, sec, tr) = progress.stage("drawing the plots", || {
            let deviation = &grids.as_ref().expect("the grid was kept").deviation;
            let dev = vpcut::developed_view(stock, &job.thread, deviation, tol, dw, dh, &title);
            let sec = vpcut::section_view(stock, &job.thread, angle, tol, sw, sh, &title);
            let tr = vpcut::trace_view(stock, &job.thread, deviation, angle, tol, tw, th, &title);
            (png(&dev), png(&sec), png(&tr))
        });
        plots = Some(([dev?, sec?, tr?], angle));
    }
    if let (Some((developed, section, trace)), Some(([dev, sec, tr], _))) = (plot_slots, &plots) {
        outs.put(developed, dev)?;
        outs.put(section, sec)?;
        outs.put(trace, tr)?;
    }
    if let (Some(h), Some(o), Some(scene), Some((plots, angle))) =
        (&html, &grids, &picture_scene, plots)
    {
        let renderer = pictures.as_ref().map(|p| &p.renderer);
        h.write(&job, o, scene, plots, angle, renderer, &mut outs, &progress)?;
    }
    if ci_slots.0.is_some() || ci_slots.1.is_some() {
        let case = Case {
            job: args.job.clone(),
            seconds: clock.elapsed().as_secs_f64(),
            result: Ok(Checked {
                outcome: cli::record::Outcome::of(
                    &report,
                    places(&report, &args.job, &job_text, &job, &inputs),
                ),
                unchanged_since: None,
            }),
        };
        CiArgs::write(ci_slots, &[&case], &mut outs)?;
    }
    let written = progress.stage("writing", || outs.commit())?;
    if !args.quiet {
        let wall = clock.elapsed().as_secs_f64();
        say.write(&term::summary(&report, say, Some(wall)));
        for p in written {
            say.write(&format!("  wrote {}\n", p.display()));
        }
    }
    Ok(if args.check && report.verdict == vpcut::Verdict::Fail {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// About how many bytes a `--gltf-full` model takes per dexel: a vertex (12 bytes of
/// position, 8 of colour) and two triangles (24 bytes of indices).
const GLB_BYTES_PER_DEXEL: f64 = 44.0;

/// An image as PNG bytes (the renders' encoder, without text chunks).
fn png(img: &image::RgbImage) -> anyhow::Result<Vec<u8>> {
    vpcut::encode_png(img, &[]).context("cannot encode a PNG")
}
