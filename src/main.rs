//! The `vpcut` command line: `vpcut simulate job.toml [--report report.json] [--check]
//! [--gltf out.glb] [--png out.png]`, `vpcut render model.glb --png view.png`,
//! `vpcut toolpath program --dialect D`.
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
struct ToolpathArgs {
    /// The main program; subprograms are looked up beside it.
    program: PathBuf,
    /// Controller dialect: `fanuc`, `gsk980`, `linuxcnc` or `siemens-802d`.
    #[arg(long)]
    dialect: String,
    /// Print JSON instead of CSV.
    #[arg(long)]
    json: bool,
    /// Print CSV (the default): file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
    /// Unknown words and codes are errors, not warnings.
    #[arg(long)]
    strict: bool,
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
    /// Camera of `--png`: `iso`, `front`, `section` (the near half cut away along the axis:
    /// the machined profile as a solid cut face with the ideal profile over it) or `closeup`
    /// (a section through the worst finding).
    #[arg(long, default_value = "iso", value_parser = parse_view)]
    view: vpcut::View,
    /// Picture size `WIDTHxHEIGHT` in pixels; the width a multiple of 64.
    #[arg(long, default_value = "1024x768", value_name = "WxH", value_parser = parse_size)]
    size: (u32, u32),
    /// Multisampling (anti-aliasing): 4 or 1 samples per pixel.
    #[arg(long, default_value_t = 4, value_name = "N")]
    msaa: u32,
    /// Draw feature edges (crests, roots, flank corners) as dark lines.
    #[arg(long)]
    edges: bool,
    /// Leave the toolpath out of the whole-part views (programs with many passes hide the
    /// part behind their lines).
    #[arg(long)]
    no_toolpath: bool,
}

fn parse_view(s: &str) -> Result<vpcut::View, String> {
    vpcut::View::from_name(s)
        .ok_or_else(|| format!("expected one of iso, front, section, closeup, not `{s}`"))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 1024x768, not `{s}`");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?))
}

impl PictureArgs {
    fn wanted(&self) -> bool {
        self.png.is_some() || self.renders.is_some()
    }

    /// Draw what was asked for and write it atomically.
    fn write(&self, scene: &vpcut::Scene) -> anyhow::Result<()> {
        if !self.wanted() {
            return Ok(());
        }
        let renderer = vpcut::Renderer::new(self.msaa)?;
        let opts = |view| vpcut::RenderOptions {
            view,
            width: self.size.0,
            height: self.size.1,
            edges: self.edges,
            toolpath: !self.no_toolpath,
        };
        if let Some(path) = &self.png {
            write_atomic(path, &renderer.png(scene, &opts(self.view))?)?;
        }
        if let Some(dir) = &self.renders {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create the folder {}", dir.display()))?;
            for view in vpcut::View::ALL {
                let path = dir.join(format!("{}.png", view.name()));
                write_atomic(&path, &renderer.png(scene, &opts(view))?)?;
            }
        }
        Ok(())
    }
}

#[derive(clap::Args)]
struct PlanArgs {
    /// The job file (TOML) with `[process] kind = "plan"`; see docs/job-format.md.
    job: PathBuf,
    /// The controller: `fanuc`, `gsk980`, `siemens-802d` or `linuxcnc`.
    #[arg(long)]
    dialect: String,
    /// FANUC: the compact Custom Macro B version (layer tables and WHILE loops).
    #[arg(long = "macro")]
    macro_b: bool,
    /// Write the program here (atomically); without it, to standard output.
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
    /// Unknown words and codes in the job's NC program are errors, not warnings.
    #[arg(long)]
    strict: bool,
    /// Write the pictures that need no GPU here: `developed.png` (the deviation field
    /// unrolled, angle x z) and `section.png` (machined vs ideal profile along a generator).
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
    /// Angle of the generator in `section.png` (deg on the part).
    #[arg(long, value_name = "DEG", default_value_t = 0.0)]
    section_angle: f64,
    /// Write the cut part as binary glTF (`.glb`): the stock coloured by deviation, the
    /// toolpath, the tool, and the report summary in `extras`; positions in metres.
    #[arg(long, value_name = "FILE")]
    gltf: Option<PathBuf>,
    /// Also put the ideal thread surface (translucent) into the glTF.
    #[arg(long)]
    gltf_ideal: bool,
    /// Largest distance (mm) the exported surface may stray from the dexel data
    /// (default: the job's tolerance; the mesh is simplified to it).
    #[arg(long, value_name = "MM", conflicts_with = "gltf_full")]
    gltf_tolerance: Option<f64>,
    /// Export every dexel as a vertex (no simplification; large files).
    #[arg(long)]
    gltf_full: bool,
    #[command(flatten)]
    picture: PictureArgs,
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
            // Program diagnostics say `error:` themselves, compiler style.
            let program = e
                .downcast_ref::<vpcut::NcError>()
                .or_else(|| match e.downcast_ref() {
                    Some(vpcut::JobError::Program(nc)) => Some(nc.as_ref()),
                    _ => None,
                });
            match program {
                Some(nc) => eprintln!("{nc}"),
                None => eprintln!("error: {e:#}"),
            }
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Simulate(args) => simulate(args),
        Command::Render(args) => render(args),
        Command::Toolpath(args) => toolpath(args),
        Command::Plan(args) => plan(args),
    }
}

fn plan(args: PlanArgs) -> anyhow::Result<ExitCode> {
    let post = vpcut::post::Post::from_name(&args.dialect, args.macro_b).with_context(|| {
        format!(
            "unknown dialect `{}`{}: expected `fanuc`, `gsk980`, `linuxcnc` or `siemens-802d` (--macro: fanuc only)",
            args.dialect,
            if args.macro_b { " with --macro" } else { "" }
        )
    })?;
    let src = std::fs::read_to_string(&args.job)
        .with_context(|| format!("cannot read the job file {}", args.job.display()))?;
    let dir = args.job.parent().map(Path::to_path_buf).unwrap_or_default();
    let load = |name: &str| {
        std::fs::read(dir.join(name))
            .ok()
            .map(vpcut::decode_program)
    };
    let job = vpcut::Job::from_toml_with(&src, &args.job.display().to_string(), &load)?;
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
    match &args.output {
        Some(path) => {
            write_atomic(path, text.as_bytes())?;
            if !args.quiet {
                print!("{summary}");
                println!("  program written to {}", path.display());
            }
        }
        None => {
            print!("{text}");
            if !args.quiet {
                eprint!("{summary}");
            }
        }
    }
    if !args.check {
        return Ok(ExitCode::SUCCESS);
    }
    // The round trip: read the program back and simulate what it cuts.
    let file = args
        .output
        .as_ref()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "plan.nc".into());
    let back = job.with_program(&file, &text, &args.dialect)?;
    if let Some(why) = vpcut::post::differ(&vpcut::post::toolpath(plan, post), &back.passes) {
        eprintln!("error: the program does not read back to the plan: {why}");
        return Ok(ExitCode::from(1));
    }
    let out = vpcut::simulate(&back, &vpcut::Options::default())
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.job.display()))?;
    let say = |s: String| {
        if args.output.is_some() {
            print!("{s}")
        } else {
            eprint!("{s}")
        }
    };
    if !args.quiet {
        say(format!(
            "  read back: {} passes, the planned ones; simulated:\n",
            back.passes.len()
        ));
        say(out.report.summary());
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
    let bytes = std::fs::read(&args.model)
        .with_context(|| format!("cannot read the model {}", args.model.display()))?;
    let scene = vpcut::from_glb(&bytes).with_context(|| format!("{}", args.model.display()))?;
    args.picture.write(&scene)?;
    Ok(ExitCode::SUCCESS)
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
    let dir = args.job.parent().map(Path::to_path_buf).unwrap_or_default();
    let load = |name: &str| {
        std::fs::read(dir.join(name))
            .ok()
            .map(vpcut::decode_program)
    };
    let job =
        vpcut::Job::from_toml_opts(&src, &args.job.display().to_string(), &load, args.strict)?;
    let opts = vpcut::Options {
        max_dexels: args.max_dexels,
    };
    let out =
        vpcut::simulate(&job, &opts).map_err(|e| anyhow::anyhow!("{}: {e}", args.job.display()))?;
    if let Some(path) = &args.report {
        write_atomic(path, out.report.to_json().as_bytes())?;
    }
    let e = if args.gltf_full {
        Some(0.0)
    } else {
        args.gltf_tolerance
    };
    if e.is_some_and(|e| !e.is_finite() || e < 0.0) {
        anyhow::bail!("--gltf-tolerance must be a finite number of mm, 0 or more");
    }
    // Pictures use the default mesh and the ideal (drawn on section planes); the model
    // shares that mesh unless it asks for another tolerance.
    let picture_scene = args.picture.wanted().then(|| {
        vpcut::build_scene(
            &job,
            &out,
            &vpcut::SceneOptions {
                mesh_tolerance: None,
                ideal: true,
            },
        )
    });
    if let Some(path) = &args.gltf {
        let scene = match (&picture_scene, e) {
            (Some(s), None) => vpcut::Scene {
                ideal: if args.gltf_ideal {
                    s.ideal.clone()
                } else {
                    None
                },
                ..s.clone()
            },
            _ => vpcut::build_scene(
                &job,
                &out,
                &vpcut::SceneOptions {
                    mesh_tolerance: e,
                    ideal: args.gltf_ideal,
                },
            ),
        };
        write_atomic(path, &vpcut::to_glb(&scene)?)?;
    }
    if let Some(scene) = &picture_scene {
        args.picture.write(scene)?;
    }
    if let Some(dir) = &args.plots {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the folder {}", dir.display()))?;
        let tol = job.sim.tolerance;
        let dev = vpcut::developed_view(&out.stock, &job.thread, tol, 1440, 900);
        write_atomic(&dir.join("developed.png"), &png(&dev)?)?;
        let angle = args.section_angle.to_radians();
        let sec = vpcut::section_view(&out.stock, &job.thread, angle, tol, 1600, 600);
        write_atomic(&dir.join("section.png"), &png(&sec)?)?;
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

fn toolpath(args: ToolpathArgs) -> anyhow::Result<ExitCode> {
    let dialect = vpcut::Dialect::from_name(&args.dialect).with_context(|| {
        format!(
            "unknown dialect `{}`: expected `fanuc`, `gsk980`, `linuxcnc` or `siemens-802d`",
            args.dialect
        )
    })?;
    let text = std::fs::read(&args.program)
        .map(vpcut::decode_program)
        .with_context(|| format!("cannot read {}", args.program.display()))?;
    let dir = args
        .program
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let name = args
        .program
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let main = vpcut::Source { name, text };
    let load = |n: &str| {
        std::fs::read(dir.join(n))
            .ok()
            .map(vpcut::decode_program)
            .map(|text| vpcut::Source {
                name: n.to_string(),
                text,
            })
    };
    let opts = vpcut::NcOptions {
        strict: args.strict,
        ..vpcut::NcOptions::default()
    };
    let toolpath = vpcut::interpret_with(&main, dialect, &load, &opts)?;
    for w in &toolpath.warnings {
        eprintln!("{w}");
    }
    let moves = toolpath.moves;
    let _ = args.csv;
    if args.json {
        let rows: Vec<serde_json::Value> = moves
            .iter()
            .map(|m| {
                serde_json::json!({
                    "file": m.file, "line": m.line, "kind": m.kind.name(),
                    "x_dia": m.x_dia, "x_radius": m.x_dia / 2.0, "z": m.z,
                    "lead": m.lead, "lead_change": m.lead_change,
                    "sync_angle_deg": m.sync_angle_deg, "tool": m.tool,
                    "arc": m.arc.map(|a| serde_json::json!({
                        "x_centre_dia": a.x_centre_dia, "z_centre": a.z_centre,
                        "clockwise": a.clockwise,
                    })),
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        print!("{}", vpcut::to_csv(&moves));
    }
    Ok(ExitCode::SUCCESS)
}

/// An image as PNG bytes.
fn png(img: &image::RgbImage) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    img.write_with_encoder(image::codecs::png::PngEncoder::new(&mut bytes))
        .context("cannot encode a PNG")?;
    Ok(bytes)
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
