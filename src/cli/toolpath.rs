//! `vpcut toolpath`: a program's moves as the control makes them, as CSV or JSON, with the
//! machine settings a program cannot say given on the command line.

use super::inputs::{self, Inputs};
use super::term;
use crate::{name_file, name_files};
use anyhow::Context as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct ToolpathArgs {
    /// The main program; subprograms are looked up beside it.
    pub(crate) program: PathBuf,
    /// Controller dialect: `fanuc`, `gsk980`, `linuxcnc`, `siemens-802d`, `siemens-840d` or `okuma`.
    /// FANUC/GSK cycles take their variant from the block's words: a G76 with K or D is the
    /// one-block G76 of Haas and FANUC 0T (else FANUC 0i's two blocks); G71/G72 with D (G73
    /// with I, K or D) the one-block 0T/Haas form; G70..G75 list every move they make
    /// (docs/job-format.md, "Multiple repetitive cycles").
    #[arg(long)]
    pub(crate) dialect: String,
    /// Print JSON instead of CSV.
    #[arg(long)]
    pub(crate) json: bool,
    /// Print CSV (the default): file,line,kind,x_dia,x_radius,z,lead,lead_change,
    /// sync_angle_deg,x_start_dia,z_start,path_lead: every move the control makes (cycle
    /// rapids included), its end and start; `lead` is the Z lead, `path_lead` the lead
    /// along the move.
    #[arg(long, conflicts_with = "json")]
    pub(crate) csv: bool,
    /// Unknown words and codes are errors, not warnings.
    #[arg(long)]
    pub(crate) strict: bool,
    /// Where G28 goes (and LinuxCNC's #5161/#5163): `X,Z`, X as a diameter, in mm in
    /// machine coordinates (the job's `[program] reference_point`; default 0,0).
    #[arg(long, value_name = "X,Z", value_parser = parse_point, allow_hyphen_values = true)]
    pub(crate) reference_point: Option<(f64, f64)>,
    /// Where FANUC/GSK G30 goes (and LinuxCNC's #5181/#5183 at the start): `X,Z` as
    /// `--reference-point` (the job's `[program] second_reference_point`; default 0,0).
    #[arg(long, value_name = "X,Z", value_parser = parse_point, allow_hyphen_values = true)]
    pub(crate) second_reference_point: Option<(f64, f64)>,
    /// FANUC/GSK lathe G-code system: A (the default), B or C (the job's
    /// `[program] gcode_system`).
    #[arg(long, value_name = "A|B|C", value_parser = parse_gcode_system)]
    pub(crate) gcode_system: Option<vpcut::GcodeSystem>,
    /// FANUC/GSK decimal-point input: `standard` (the default: `X30` is 0.030 mm) or
    /// `calculator` (`X30` is 30 mm) (the job's `[program] decimal_point`).
    #[arg(long, value_name = "standard|calculator", value_parser = parse_decimal_point)]
    pub(crate) decimal_point: Option<vpcut::DecimalPoint>,
    /// The least input increment in mm: 0.001 (the default) or 0.0001 (the job's
    /// `[program] input_increment`).
    #[arg(long, value_name = "MM", value_parser = parse_increment)]
    pub(crate) input_increment: Option<vpcut::InputIncrement>,
    /// The units at power-on: `mm` (the default) or `inch` (the job's `[program] units`).
    #[arg(long, value_name = "mm|inch", value_parser = ["mm", "inch"])]
    pub(crate) units: Option<String>,
    /// The main program of a file that holds several, e.g. `O1000` (the job's `[program]
    /// main`; default: the one that ends in M30 and that no other calls).
    #[arg(long, value_name = "ONNNN")]
    pub(crate) main: Option<String>,
    /// LinuxCNC: a folder searched for the file of an `o<name> call` that the program does
    /// not define, after the program's own folder (the INI's SUBROUTINE_PATH; repeat the
    /// option for several, searched in order; relative to the program's folder).
    #[arg(long, value_name = "DIR")]
    pub(crate) subroutine_path: Vec<String>,
    /// A turning tool's nose for tool nose radius compensation (G41/G42): `T:R:TIP`, the
    /// tool number, its nose radius (mm) and imaginary tip direction (FANUC numbering 0..9,
    /// 3 an external tool turning towards the chuck), e.g. `--nose 1:0.8:3` (a job's
    /// `kind = "turning"` tool's `nose_radius` and `tip_direction`; repeat for several).
    /// Without it G41/G42 compensate with radius 0: the programmed path.
    #[arg(long, value_name = "T:R:TIP", value_parser = parse_nose)]
    pub(crate) nose: Vec<(u32, (f64, u8))>,
    /// Siemens: a definition file of the machine read before the program (GUD `DEF` lines,
    /// macro `DEFINE .. AS` lines, or a cycle `.SPF` that starts with `PROC NAME`); repeat
    /// the option for several; relative to the program's folder (the job's `[program]
    /// definitions`)
    #[arg(long, value_name = "FILE")]
    pub(crate) definitions: Vec<String>,
}

/// `T:R:TIP` of `--nose`.
fn parse_nose(s: &str) -> Result<(u32, (f64, u8)), String> {
    let bad = || format!("expected TOOL:RADIUS:TIP (e.g. 1:0.8:3; the tip 0 to 9), got `{s}`");
    let f: Vec<&str> = s.split(':').collect();
    let [t, r, tip] = f[..] else {
        return Err(bad());
    };
    let t: u32 = t.trim().parse().map_err(|_| bad())?;
    let r: f64 = r.trim().parse().map_err(|_| bad())?;
    let tip: u8 = tip.trim().parse().map_err(|_| bad())?;
    if !(0.0..=25.0).contains(&r) || tip > 9 {
        return Err(bad());
    }
    Ok((t, (r, tip)))
}

/// `standard` or `calculator` of `--decimal-point`.
fn parse_decimal_point(s: &str) -> Result<vpcut::DecimalPoint, String> {
    vpcut::DecimalPoint::from_name(s)
        .ok_or_else(|| format!("expected standard or calculator, got `{s}`"))
}

/// `0.001` or `0.0001` of `--input-increment`.
fn parse_increment(s: &str) -> Result<vpcut::InputIncrement, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .and_then(vpcut::InputIncrement::from_mm)
        .ok_or_else(|| format!("expected 0.001 or 0.0001 (mm), got `{s}`"))
}

/// `X,Z` of `--reference-point`.
fn parse_point(s: &str) -> Result<(f64, f64), String> {
    let bad = || format!("expected X,Z (two numbers, X a diameter), got `{s}`");
    let (x, z) = s.split_once(',').ok_or_else(bad)?;
    let x: f64 = x.trim().parse().map_err(|_| bad())?;
    let z: f64 = z.trim().parse().map_err(|_| bad())?;
    if !(x.is_finite() && z.is_finite()) {
        return Err(bad());
    }
    Ok((x, z))
}

/// `A`, `B` or `C` of `--gcode-system`.
fn parse_gcode_system(s: &str) -> Result<vpcut::GcodeSystem, String> {
    vpcut::GcodeSystem::from_name(s).ok_or_else(|| format!("expected A, B or C, got `{s}`"))
}

pub(crate) fn toolpath(args: ToolpathArgs) -> anyhow::Result<ExitCode> {
    let dialect = vpcut::Dialect::from_name(&args.dialect).with_context(|| {
        format!(
            "unknown dialect `{}`: expected `fanuc`, `gsk980`, `linuxcnc`, `siemens-802d`, `siemens-840d` or `okuma`",
            args.dialect
        )
    })?;
    let bytes = inputs::read_bytes(&args.program, "the program")?;
    let inputs = Inputs::default();
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
    let text = inputs::decode_program(&bytes);
    inputs.add("program", args.program.clone(), name.clone(), bytes);
    let main = vpcut::Source { name, text };
    let read = inputs.loader(&dir);
    let load = |n: &str| {
        read(n).map(|text| vpcut::Source {
            name: n.to_string(),
            text,
        })
    };
    let mut opts = vpcut::NcOptions {
        strict: args.strict,
        ..vpcut::NcOptions::default()
    };
    opts.settings.reference_point = args.reference_point;
    opts.settings.second_reference_point = args.second_reference_point;
    opts.settings.gcode_system = args.gcode_system.unwrap_or_default();
    opts.settings.gcode_system_named = args.gcode_system.is_some();
    opts.settings.decimal_point = args.decimal_point.unwrap_or_default();
    opts.settings.input_increment = args.input_increment.unwrap_or_default();
    opts.settings.power_on.inch = args.units.as_deref() == Some("inch");
    opts.settings.main = args.main.clone();
    opts.settings.noses.tool = args.nose.iter().copied().collect();
    opts.settings.subroutine_path = args.subroutine_path.clone();
    opts.settings.definitions = args.definitions.clone();
    let toolpath = match vpcut::interpret_with(&main, dialect, &load, &opts) {
        Ok(t) => t,
        Err(mut e) => {
            // The moves the control makes before its alarm are printed all the same, then
            // the error (exit code 2).
            let mut moves = vpcut::interpret_partial(&main, dialect, &load, &opts);
            if !moves.is_empty() {
                inputs.name_move_files(&mut moves);
                print_moves(&moves, args.json)?;
            }
            name_files(&mut e, &inputs);
            return Err(e.into());
        }
    };
    for w in &toolpath.warnings {
        let mut w = w.clone();
        name_file(&mut w, &inputs);
        term::err(&term::diagnostics(&format!("{w}\n")));
    }
    let mut moves = toolpath.moves;
    // Moves name their program (`O2`); rows name the file that holds it.
    inputs.name_move_files(&mut moves);
    let _ = args.csv;
    print_moves(&moves, args.json)?;
    Ok(ExitCode::SUCCESS)
}

/// The moves on standard output: CSV, or JSON with `json`.
fn print_moves(moves: &[vpcut::Move], json: bool) -> anyhow::Result<()> {
    if json {
        let rows: Vec<serde_json::Value> = moves
            .iter()
            .map(|m| {
                serde_json::json!({
                    "file": m.file, "line": m.line, "kind": m.kind.name(),
                    "x_dia": m.x_dia, "x_radius": m.x_dia / 2.0, "z": m.z,
                    "lead": m.lead, "lead_change": m.lead_change,
                    "sync_angle_deg": m.sync_angle_deg, "tool": m.tool,
                    "x_start_dia": m.x_start, "z_start": m.z_start,
                    "lead_axis": m.lead.map(|_| "z"), "path_lead": vpcut::path_lead(m),
                    "arc": m.arc.map(|a| serde_json::json!({
                        "x_centre_dia": a.x_centre_dia, "z_centre": a.z_centre,
                        "clockwise": a.clockwise,
                    })),
                })
            })
            .collect();
        let mut s = serde_json::to_string_pretty(&rows)?;
        s.push('\n');
        term::out(&s);
    } else {
        term::out(&vpcut::to_csv(moves));
    }
    Ok(())
}
