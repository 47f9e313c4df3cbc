//! NC programs against a second method: the seed programs, run by the interpreter, must
//! cut what the pass generators that transcribe the same method cut.

use crate::support::{scene_job, with};
use vpcut::{simulate, SimOptions};

/// Seed 002's MYAAA.MPF/MYBBB.SPF through the Siemens interpreter give exactly the passes of
/// the `seed002` generator (the same arithmetic written in Rust).
#[test]
fn seed002_siemens_program_equals_its_generator() {
    let program = scene_job("seed002-siemens-equal-tooth");
    let generator = scene_job("seed002-equal-tooth");
    assert_eq!(program.passes.len(), 15);
    assert_eq!(program.passes.len(), generator.passes.len());
    for (a, b) in program.passes.iter().zip(&generator.passes) {
        for (x, y) in [
            (a.x_start, b.x_start),
            (a.x_end, b.x_end),
            (a.z_start, b.z_start),
            (a.z_end, b.z_end),
            (a.lead, b.lead),
            (a.lead_change, b.lead_change),
            (a.start_angle, b.start_angle),
        ] {
            assert!((x - y).abs() < 1e-12, "{a:?} vs {b:?}");
        }
        assert_eq!(a.tool, b.tool);
    }
}

/// Seed 004's Macro B program cuts the stock the `flank-borrow` generator cuts: the same
/// helices, started at different points in front of the face. (The program runs 66 layers,
/// not 65: 6.5 - 65 x 0.1 is 6.4e-15 in binary floating point, so `WHILE[#2GT0]` runs once
/// more and repeats the finishing depth.)
#[test]
fn seed004_macro_b_program_cuts_what_its_generator_cuts() {
    let small = |name: &str| {
        let mut j = scene_job(name);
        j.sim.angular_cells = 360;
        j.sim.axial_spacing = 0.02;
        j.sim.measure_generators = 2;
        j
    };
    let program = small("seed004-tr100x12-macro-b");
    let generator = small("seed004-tr100x12");
    assert_eq!(program.passes.len(), 198);
    assert_eq!(generator.passes.len(), 195);
    let a = simulate(&program, &SimOptions::default()).unwrap();
    let b = simulate(&generator, &SimOptions::default()).unwrap();
    let worst = a
        .stock
        .outer
        .iter()
        .zip(&b.stock.outer)
        .map(|(x, y)| (x - y).abs())
        .fold(0f32, f32::max);
    assert!(worst < 1e-5, "stocks differ by {worst} mm");
}

/// `vpcut toolpath` prints the moves as the control runs them.
#[test]
fn toolpath_csv_of_the_siemens_program() {
    let dir = crate::support::root().join("scenes/seed002-siemens-equal-tooth");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args([
            "toolpath",
            dir.join("MYAAA.MPF").to_str().unwrap(),
            "--dialect",
            "siemens-802d",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let csv = String::from_utf8(out.stdout).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg,x_start_dia,z_start,path_lead")
    );
    let threads: Vec<&str> = csv.lines().filter(|l| l.contains(",thread,")).collect();
    assert_eq!(threads.len(), 15);
    // Pass 2 of layer 1: start lead K = 4 - 0.25, end z = R0 - R22 = -80.5, diameter 26.
    assert!(
        threads[1].starts_with("MYBBB.SPF,35,thread,26,13,-80.5,3.75,1.5,0,26,"),
        "{}",
        threads[1]
    );
}

/// A program error names the program file, line and column, and the caller.
#[test]
fn program_errors_name_file_line_and_caller() {
    let dir = std::env::temp_dir().join(format!("vpcut-nc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("MAIN.MPF"), "R1=0\nSUBA\nM02\n").unwrap();
    std::fs::write(dir.join("SUBA.SPF"), "; sub\nR2=5/R1\nRET\n").unwrap();
    let job = with(
        &crate::support::scene_text("seed002-siemens-equal-tooth"),
        &[("program", "file", "\"MAIN.MPF\"")],
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args(["simulate", dir.join("job.toml").to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        crate::support::has_diagnostic(&err, "error: division by zero", "SUBA.SPF:2:6"),
        "{err}"
    );
    assert!(err.contains("called from MAIN.MPF:2"), "{err}");
}

/// The seed003 job with its program replaced by `program` and `[program]` keys added. The
/// programs of these tests write plain numbers in mm (`G0 X60 Z3`, `F2`): for FANUC/GSK the
/// job says the machine reads them so (`decimal_point = "calculator"`, unless the keys say
/// otherwise; `units_tests` and `machine_settings_*` test standard input).
fn program_job(program: &str, keys: &[(&str, &str)]) -> Result<vpcut::Job, vpcut::JobError> {
    let fanuc = keys
        .iter()
        .all(|(k, v)| *k != "dialect" || v.contains("fanuc") || v.contains("gsk"));
    let mut edits = vec![("program", "file", "\"T.NC\"")];
    if fanuc {
        edits.push(("program", "decimal_point", "\"calculator\""));
    }
    edits.extend(keys.iter().map(|(k, v)| ("program", *k, *v)));
    let text = with(&crate::support::scene_text("seed003-g76-2in-12tpi"), &edits);
    let program = program.to_string();
    vpcut::Job::from_toml_with(&text, "job.toml", &move |f: &str| {
        (f == "T.NC").then(|| program.clone())
    })
}

/// `thread_chamfer = 1.0` turns a G92 pass into a main pass and a chained 45 deg pull-out
/// pass. Oracle: the pass module's own helix. The pull-out starts where the main pass ends
/// (Z-18, 2 mm = 1 lead before Z-20), on the main helix's angle there (theta0 - spin 2pi t
/// at t = its revolutions, mod 2 pi), and leaves by its own Z travel (2 mm) in radius.
#[test]
fn g92_chamfer_pass_continues_the_main_helix() {
    let prog = "G0 X60 Z3\nM03\nG92 X48 Z-20 F2 Q30000\nM30\n";
    let job = program_job(prog, &[("thread_chamfer", "1.0")]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(job.passes.len(), 2);
    let (a, b) = (&job.passes[0], &job.passes[1]);
    assert_eq!(
        (a.z_start, a.z_end, b.z_start, b.z_end),
        (3.0, -18.0, -18.0, -20.0)
    );
    assert_eq!((a.x_end, b.x_start, b.x_end), (48.0, 48.0, 52.0));
    assert_eq!((b.lead, b.lead_change), (2.0, 0.0));
    let h = a.helix();
    let end = h.theta0 - h.spin * std::f64::consts::TAU * a.revolutions().unwrap();
    let diff = (end - b.start_angle).rem_euclid(std::f64::consts::TAU);
    assert!(
        diff < 1e-9 || std::f64::consts::TAU - diff < 1e-9,
        "{end} vs {}",
        b.start_angle
    );
    // Without the key: one pass, as before.
    assert_eq!(program_job(prog, &[]).unwrap().passes.len(), 1);
    // The cut: the pull-out tip runs r(z) = 24 + (-18 - z) over [-20, -18]; the tip flat
    // (half width w = P/12 = 0.176389) reaches lowest at a slice z when centred at z + w, so
    // the deepest cut there is r = 6 - z - w (25 - w at z = -19). At z = -10 it is the
    // root, 24.
    let mut job = job;
    job.sim.angular_cells = 360;
    job.sim.axial_spacing = 0.02;
    job.sim.measure_generators = 2;
    let out = simulate(&job, &SimOptions::default()).unwrap();
    let st = &out.stock;
    let deepest = |z: f64| {
        let j = ((z - st.grid.z0) / st.grid.dz).round() as usize;
        let r = (0..st.grid.n_theta)
            .map(|i| st.radius(vpcut::Surface::Outer, i, j).unwrap())
            .fold(f64::INFINITY, f64::min);
        (st.grid.z(j), r)
    };
    let w = 2.1166666666666667 / 12.0;
    let (z, r) = deepest(-19.0);
    assert!(
        (r - (6.0 - z - w)).abs() < 0.01,
        "z {z}: {r} vs {}",
        6.0 - z - w
    );
    let (_, r) = deepest(-10.0);
    assert!((r - 24.0).abs() < 1e-3, "{r}");
}

/// `work_offsets`: the G32 pass under G55 = { x = 1, z = -12.5 } is the G54 pass shifted by
/// exactly 1 in diameter and -12.5 in z.
#[test]
fn g55_work_offset_shifts_a_g32_pass() {
    let prog = "G0 X48 Z3\nG32 Z-20 F2\nM30\n";
    let off = [("work_offsets", "{ G55 = { x = 1, z = -12.5 } }")];
    let base = program_job(prog, &off).unwrap();
    let g55 = program_job(&format!("G55\n{prog}"), &off).unwrap();
    let (p, q) = (&base.passes[0], &g55.passes[0]);
    assert_eq!((p.x_start, p.z_start, p.z_end), (48.0, 3.0, -20.0));
    assert_eq!(
        (q.x_start, q.x_end, q.z_start, q.z_end),
        (49.0, 49.0, -9.5, -32.5)
    );
}

/// Rigid tapping runs in the interpreter (its moves are thread moves along the axis); a job
/// whose program also taps (with another tool) simulates its thread and leaves the tapping
/// block out with a warning at that block, whatever the code, when the job has no tap tool
/// of that T number (a threading tool's pass at X0 would cut the whole part away; with a
/// `kind = "tap"` tool the strokes cut, `taps.rs`). Issue 30: it used to stop
/// the whole job. Oracle: the same program without its tapping blocks gives the same pass.
#[test]
fn tapping_blocks_are_warned_and_the_thread_is_simulated() {
    let cases = [
        (
            "fanuc",
            "G0 X60 Z3\nG32 Z-20 F2\nG0 X0 Z5\nM29 S300\nG84 Z-10 R-2 F1.5\nG80\nM30\n",
            &[5][..],
        ),
        (
            "fanuc",
            "G0 X60 Z3\nG32 Z-20 F2\nG0 X0 Z5\nG32 Z-10 F1.5\nM30\n",
            &[4],
        ),
        (
            "linuxcnc",
            "G7 G0 X60 Z3 M3\nG33 Z-20 K2\nG0 X0 Z5\nG33.1 Z-10 K1.5\nM2\n",
            &[4],
        ),
        (
            "siemens-840d",
            "G0 X60 Z3\nG33 Z-20 K2\nG0 X0 Z5\nSPOS=0\nG331 Z-10 K1.5 S300\nG332 Z5 K1.5\nM30\n",
            // G331 in and G332 out: two blocks, each warned.
            &[5, 6],
        ),
    ];
    for (dialect, prog, lines) in cases {
        let d = format!("\"{dialect}\"");
        let job = program_job(prog, &[("dialect", &d)]).unwrap_or_else(|e| panic!("{e}"));
        let taps: Vec<_> = job
            .program_warnings
            .iter()
            .filter(|w| w.message.contains("tapping"))
            .collect();
        let at: Vec<(&str, usize, vpcut::Severity)> = taps
            .iter()
            .map(|w| (w.file.as_str(), w.line, w.severity))
            .collect();
        let want: Vec<(&str, usize, vpcut::Severity)> = lines
            .iter()
            .map(|&l| ("T.NC", l, vpcut::Severity::Warning))
            .collect();
        assert_eq!(at, want, "{dialect}: {:?}", job.program_warnings);
        assert!(
            taps.iter().all(|w| w.message.contains("not simulated")),
            "{dialect}"
        );
        // Without the tapping blocks the same program simulates the same thread.
        let cut: String = prog.lines().take(2).map(|l| format!("{l}\n")).collect();
        let alone = program_job(&cut, &[("dialect", &d)]).unwrap();
        assert_eq!(job.passes, alone.passes, "{dialect}");
        assert_eq!(job.passes.len(), 1, "{dialect}");
    }
}

/// `block_skip = false` runs the `/` blocks; bad `[program]` values name their key.
#[test]
fn program_settings_block_skip_and_errors() {
    let prog = "G0 X48 Z3\nG32 Z-20 F2\n/G0 X48 Z3\n/G32 Z-20 F2\nM30\n";
    assert_eq!(program_job(prog, &[]).unwrap().passes.len(), 1);
    let run = program_job(prog, &[("block_skip", "false")]).unwrap();
    assert_eq!(run.passes.len(), 2);
    let e = program_job(prog, &[("thread_chamfer", "-1")])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("program.thread_chamfer") && e.contains(">= 0"),
        "{e}"
    );
    let e = program_job(prog, &[("work_offsets", "{ G60 = { x = 1 } }")])
        .unwrap_err()
        .to_string();
    assert!(e.contains("G54..G59"), "{e}");
    let e = program_job(prog, &[("work_offsets", "{ G55 = { y = 1 } }")])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("program.work_offsets.G55.y") && e.contains("milling"),
        "{e}"
    );
}

/// `vpcut toolpath --json` names arcs `arc` and gives their centre: G03 X20 Z-10 R10 from
/// (X0, Z0) turns about (X0, Z-10) counter-clockwise (the convex quarter round).
#[test]
fn toolpath_json_names_arcs_with_their_centre() {
    let dir = std::env::temp_dir().join(format!("vpcut-arc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ARC.NC");
    std::fs::write(&file, "G0 X0 Z0 F0.2\nG03 X20. Z-10. R10.\nM30\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args([
            "toolpath",
            file.to_str().unwrap(),
            "--dialect",
            "fanuc",
            "--json",
        ])
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let arc = &v[1];
    assert_eq!(arc["kind"], "arc");
    assert_eq!(
        (arc["x_dia"].as_f64(), arc["z"].as_f64()),
        (Some(20.0), Some(-10.0))
    );
    let c = (
        arc["arc"]["x_centre_dia"].as_f64().unwrap(),
        arc["arc"]["z_centre"].as_f64().unwrap(),
    );
    assert!(c.0.abs() < 1e-9 && (c.1 + 10.0).abs() < 1e-9, "{c:?}");
    assert_eq!(arc["arc"]["clockwise"], false);
    assert!(v[0]["arc"].is_null());
}

/// A chained FANUC G32 that re-programs the lead shows in the report as a `thread_chain`
/// warning on the chained pass (2), at the joint z = -7, with the jump 3 - 2 = 1 mm/rev;
/// the same program with a rapid between the blocks (a re-sync) has none. The chained pass
/// starts inside the blank but is already at speed: no `run_in` warning for it (the
/// re-synced one gets one: 0 mm of run-in for v = 3 x 200/60 = 10 mm/s at 1000 mm/s^2).
#[test]
fn thread_chain_finding_in_the_report() {
    let toml = "[blank]\ndiameter = 30.0\nlength = 40.0\n\
                [thread]\nform = \"square\"\nmajor_diameter = 30.0\nminor_diameter = 29.0\n\
                pitch = 2.0\nturns = 3\nz_start = -2.0\nwidth = { groove = 1.0 }\n\
                [[tool]]\nid = 1\nkind = \"grooving\"\nwidth = 1.0\n\
                [program]\nfile = \"P.NC\"\ndialect = \"fanuc\"\n\
                [machine]\nacceleration = 1000.0\n\
                [simulation]\naxial_spacing = 0.05\nangular_cells = 90\nmeasure_generators = 1\n";
    let report = |program: &'static str| {
        let load = |f: &str| (f == "P.NC").then(|| program.to_string());
        let job = vpcut::Job::from_toml_with(toml, "t.toml", &load).unwrap();
        simulate(&job, &SimOptions::default()).unwrap().report
    };
    let r = report("M03\nG0 X29. Z5.\nG32 Z-7. F2.\nG32 Z-20. F3.\nM30\n");
    let chain: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == vpcut::FindingKind::ThreadChain)
        .collect();
    assert_eq!(chain.len(), 1, "{:?}", r.findings);
    let f = chain[0];
    assert_eq!(
        (f.severity, f.pass, f.z_mm, f.value, f.unit),
        (
            vpcut::Severity::Warning,
            Some(2),
            Some(-7.0),
            Some(1.0),
            Some("mm/rev")
        )
    );
    assert!(f.message.contains("P.NC:4"), "{}", f.message);
    assert!(
        r.findings
            .iter()
            .all(|f| f.kind != vpcut::FindingKind::RunIn),
        "{:?}",
        r.findings
    );
    let r = report("M03\nG0 X29. Z5.\nG32 Z-7. F2.\nG0 X31.\nG0 X29.\nG32 Z-20. F3.\nM30\n");
    assert!(r
        .findings
        .iter()
        .all(|f| f.kind != vpcut::FindingKind::ThreadChain));
    let run_in: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == vpcut::FindingKind::RunIn)
        .collect();
    assert_eq!(run_in.len(), 1, "{:?}", r.findings);
    assert_eq!((run_in[0].pass, run_in[0].value), (Some(2), Some(0.0)));
}

/// Issue 30: the machine settings a program relies on come from `[program]`. Oracle: the
/// seed003 scene, whose program says G20 itself, cut by the same program without G20 on a
/// machine in inch at power-on (`units = "inch"`): the same passes. Without the setting its
/// 0.083333 lead reads as millimetres and is warned (12 threads per inch).
#[test]
fn machine_settings_of_the_program_table() {
    let scene = crate::support::scene_job("seed003-g76-2in-12tpi");
    let text = std::fs::read_to_string(
        crate::support::root().join("scenes/seed003-g76-2in-12tpi/G76-2IN-12TPI.NC"),
    )
    .unwrap();
    let no_g20: String = text
        .lines()
        .filter(|l| l.trim() != "G20")
        .map(|l| format!("{l}\n"))
        .collect();
    let standard = ("decimal_point", "\"standard\"");
    let inch = program_job(&no_g20, &[standard, ("units", "\"inch\"")]).unwrap();
    assert_eq!(inch.passes, scene.passes);
    assert!(
        inch.program_warnings.is_empty(),
        "{:?}",
        inch.program_warnings
    );
    let mm = program_job(&no_g20, &[standard]).unwrap();
    let w: Vec<&str> = mm
        .program_warnings
        .iter()
        .map(|w| w.message.as_str())
        .collect();
    assert!(w.iter().any(|m| m.contains("12 threads per inch")), "{w:?}");
}

/// Numbers orders of magnitude off the blank (2 in, 50.8 mm): plain `X49` read in standard
/// input is 0.049 mm, so every thread move lies within a hundredth of the blank's diameter of
/// the axis; the FANUC manual's `X60640` read as calculator-type input is 60640 mm, more than
/// 100 times the blank away. Both are warned at the block with the settings to check; the
/// job still loads (the report shows what it cuts).
#[test]
fn numbers_orders_of_magnitude_off_the_blank_are_warned() {
    let standard = ("decimal_point", "\"standard\"");
    let job = program_job("G0 X55 Z5\nG92 X49 Z-20 F2.\nM30\n", &[standard]).unwrap();
    let near: Vec<_> = job
        .program_warnings
        .iter()
        .filter(|w| w.message.contains("of the axis"))
        .collect();
    assert_eq!(near.len(), 1, "{:?}", job.program_warnings);
    assert_eq!((near[0].line, near[0].col), (2, 0));
    assert!(near[0].message.contains("0.049 mm"), "{}", near[0]);
    assert!(near[0].hint.as_deref().unwrap().contains("decimal_point"));
    // The interpreter's own warning at the first plain axis word.
    assert!(job
        .program_warnings
        .iter()
        .any(|w| w.line == 1 && w.message.contains("X55 has no decimal point")));
    let manual = "G00 X80.0 Z130.0\nG76 P011060 Q100 R200\nG76 X60640 Z25000 P3680 Q1800 F6.0\n";
    let job = program_job(manual, &[("decimal_point", "\"calculator\"")]).unwrap();
    let far: Vec<_> = job
        .program_warnings
        .iter()
        .filter(|w| w.message.contains("times the blank's size"))
        .collect();
    assert_eq!(far.len(), 1, "{:?}", job.program_warnings);
    assert_eq!(far[0].line, 3);
    // Read as the manual means it (standard input): no such warning.
    let job = program_job(manual, &[standard]).unwrap();
    assert!(
        !job.program_warnings
            .iter()
            .any(|w| w.message.contains("blank")),
        "{:?}",
        job.program_warnings
    );
}

/// `main` picks the main program of a file with several; without it the one that ends in
/// M30 and that no other calls runs (here O1000, stored after its subprogram: three passes).
/// Bad values of the new keys name their key and what is expected.
#[test]
fn main_program_and_setting_errors() {
    let file = "O0100\nG0 X48. Z3.\nG32 Z-17. F2.\nG0 X50.\nZ3.\nM99\nO1000\nM98 P30100\nM30\n";
    assert_eq!(program_job(file, &[]).unwrap().passes.len(), 3);
    let job = program_job(file, &[("main", "\"O100\"")]).unwrap();
    assert_eq!(job.passes.len(), 1);
    assert!(job
        .program_warnings
        .iter()
        .any(|w| w.message.contains("M99 ends the main program")));
    for (key, value, want) in [
        ("decimal_point", "\"dpi\"", "\"standard\""),
        ("input_increment", "0.01", "0.0001"),
        ("units", "\"cm\"", "\"inch\""),
        ("feed_mode", "\"per-second\"", "\"per-minute\""),
        ("x_mode", "\"chord\"", "\"radius\""),
        ("main", "\"MAIN\"", "O1000"),
    ] {
        let e = program_job(file, &[(key, value)]).unwrap_err().to_string();
        assert!(
            e.contains(&format!("program.{key}")) && e.contains(want),
            "{key}: {e}"
        );
    }
    let e = program_job(file, &[("main", "\"O2000\"")])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no program O2000"), "{e}");
    // Siemens and LinuxCNC have neither decimal-point input nor O programs.
    for dialect in ["\"siemens-802d\"", "\"linuxcnc\""] {
        for (key, value) in [
            ("decimal_point", "\"calculator\""),
            ("input_increment", "0.0001"),
            ("main", "\"O1000\""),
        ] {
            let e = program_job("G0 X30 Z5\n", &[("dialect", dialect), (key, value)])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("program.{key}")) && e.contains("FANUC/GSK setting"),
                "{dialect} {key}: {e}"
            );
        }
    }
}

/// `vpcut toolpath` takes the machine settings as flags: the FANUC manual's G76 first pass is
/// at X64.4 in standard input (the default); `--decimal-point calculator` reads its X60640
/// as 60640 mm (warned); `--input-increment 0.0001` reads X60640, P3680 and Q1800 as 6.064,
/// 0.368 and 0.18 mm (first pass 6.064 + 2 (0.368 - 0.18) = 6.44); `--units inch` makes the lead 6 in =
/// 152.4 mm; `--main` picks the program; bad values exit 2 naming the flag.
#[test]
fn toolpath_machine_setting_flags() {
    let dir = std::env::temp_dir().join(format!("vpcut-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("M68.NC");
    std::fs::write(
        &file,
        "O0100\nG00 X80.0 Z130.0\nG76 P011060 Q100 R200\nG76 X60640 Z25000 P3680 Q1800 F6.0\nM99\nO0200\nG00 X80.0 Z130.0\nG92 X70. Z25. F6.\nM30\n",
    )
    .unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["toolpath", file.to_str().unwrap(), "--dialect", "fanuc"];
        args.extend_from_slice(extra);
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(&args)
            .output()
            .unwrap()
    };
    let first_thread = |out: &std::process::Output| -> Vec<String> {
        let csv = String::from_utf8_lossy(&out.stdout).into_owned();
        let row = csv
            .lines()
            .find(|l| l.contains(",thread,"))
            .unwrap()
            .to_string();
        row.split(',').map(str::to_string).collect()
    };
    // Without --main the main program is O0200 (it ends in M30): the G92 at X70.
    let out = run(&[]);
    assert!(out.status.success());
    assert_eq!(first_thread(&out)[3], "70");
    let out = run(&["--main", "O100"]);
    assert!(out.status.success());
    assert_eq!(first_thread(&out)[3], "64.4");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(err.contains("M99 ends the main program"), "{err}");
    let out = run(&["--main", "O100", "--input-increment", "0.0001"]);
    let x: f64 = first_thread(&out)[3].parse().unwrap();
    assert!((x - 6.44).abs() < 1e-9, "{x}");
    let out = run(&["--main", "O100", "--units", "inch"]);
    let lead: f64 = first_thread(&out)[6].parse().unwrap();
    assert!((lead - 152.4).abs() < 1e-9, "{lead}");
    let out = run(&["--main", "O100", "--decimal-point", "calculator"]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(err.contains("X60640") && err.contains("60640 mm"), "{err}");
    for bad in [
        &["--decimal-point", "dpi"][..],
        &["--input-increment", "0.01"],
        &["--units", "cm"],
    ] {
        let out = run(bad);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(bad[0]),
            "{bad:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A program that stops with an error after its thread (a run-time alarm, or a block the
/// static check refuses): `vpcut toolpath` still prints the moves made before it, as the
/// control makes them before its alarm, then the error at its block, exit code 2. Oracle:
/// the same program without the faulty block, whose whole toolpath the partial one equals.
#[test]
fn toolpath_prints_the_moves_before_an_error() {
    let dir = std::env::temp_dir().join(format!("vpcut-partial-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fanuc =
        "O0001\nG0 X32. Z5.\nG97 S500 M03\nG92 X29.2 Z-20. F2.\nX28.6\nX28.2\nG0 X40. Z40.\n";
    let lcnc = "G18 G7 G21\nG0 X32 Z5 M3 S500\nG33 Z-20 K2\nG0 X34\nZ5\n";
    let siemens = "G0 X32 Z5\nM3 S500\nG33 Z-20 K2\nG0 X34\nZ5\n";
    // (dialect, the program's good part, the faulty block, the end, what the error says)
    let cases = [
        ("fanuc", fanuc, "G70 P3 Q9", "M30", "no block N3"),
        ("fanuc", fanuc, "#1=1/0", "M30", "division by zero"),
        ("fanuc", fanuc, "G0 X#3000", "M30", ""),
        ("linuxcnc", lcnc, "G0 X[1/0]", "M2", ""),
        ("linuxcnc", lcnc, "o100 call", "M2", ""),
        ("siemens-802d", siemens, "R1=1/0", "M30", ""),
        ("siemens-802d", siemens, "GOTOF NOWHERE", "M30", "NOWHERE"),
        // Refused by the check before anything runs: the run stops there too.
        ("fanuc", fanuc, "MO1", "M30", "unknown word"),
        ("fanuc", fanuc, "G52 X10. Z5.", "M30", "G52"),
        ("linuxcnc", lcnc, "G38.2 Z-5 F10", "M2", "G38.2"),
    ];
    let run = |name: &str, text: &str, dialect: &str| {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(["toolpath", file.to_str().unwrap(), "--dialect", dialect])
            .current_dir(&dir)
            .output()
            .unwrap()
    };
    for (k, (dialect, good, bad, end, says)) in cases.iter().enumerate() {
        let whole = run(&format!("P{k}.NC"), &format!("{good}{end}\n"), dialect);
        assert!(
            whole.status.success(),
            "{dialect} {bad}: the good part runs"
        );
        // A move after the faulty block, which the control never makes.
        let faulty = run(
            &format!("P{k}.NC"),
            &format!("{good}{bad}\nG0 X50 Z50\n{end}\n"),
            dialect,
        );
        let err = String::from_utf8_lossy(&faulty.stderr);
        assert_eq!(faulty.status.code(), Some(2), "{dialect} {bad}: {err}");
        let line = good.lines().count() + 1;
        assert!(
            err.contains(&format!("P{k}.NC:{line}:")) && err.contains(says),
            "{dialect} {bad}: the error at line {line}: {err}"
        );
        let got = String::from_utf8_lossy(&faulty.stdout);
        let want = String::from_utf8_lossy(&whole.stdout);
        assert!(got.contains(",thread,"), "{dialect} {bad}: {got}");
        assert_eq!(got, want, "{dialect} {bad}: the moves before the error");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
