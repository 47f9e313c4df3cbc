//! NC programs against a second method: the seed programs, run by the interpreter, must
//! cut what the pass generators that transcribe the same method cut.

use crate::support::{scene_job, with};
use vpcut::{simulate, Options};

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
    let a = simulate(&program, &Options::default()).unwrap();
    let b = simulate(&generator, &Options::default()).unwrap();
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
        Some("file,line,kind,x_dia,x_radius,z,lead,lead_change,sync_angle_deg")
    );
    let threads: Vec<&str> = csv.lines().filter(|l| l.contains(",thread,")).collect();
    assert_eq!(threads.len(), 15);
    // Pass 2 of layer 1: start lead K = 4 - 0.25, end z = R0 - R22 = -80.5, diameter 26.
    assert_eq!(threads[1], "MYBBB.SPF,35,thread,26,13,-80.5,3.75,1.5,0");
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
    assert!(err.contains("SUBA.SPF:2:6: division by zero"), "{err}");
    assert!(err.contains("called from MAIN.MPF:2"), "{err}");
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
        simulate(&job, &Options::default()).unwrap().report
    };
    let r = report("M03\nG0 X29 Z5\nG32 Z-7 F2\nG32 Z-20 F3\nM30\n");
    let chain: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == "thread_chain")
        .collect();
    assert_eq!(chain.len(), 1, "{:?}", r.findings);
    let f = chain[0];
    assert_eq!(
        (f.severity, f.pass, f.z_mm, f.value, f.unit),
        ("warning", Some(2), Some(-7.0), 1.0, "mm/rev")
    );
    assert!(f.message.contains("P.NC:4"), "{}", f.message);
    assert!(
        r.findings.iter().all(|f| f.kind != "run_in"),
        "{:?}",
        r.findings
    );
    let r = report("M03\nG0 X29 Z5\nG32 Z-7 F2\nG0 X31\nG0 X29\nG32 Z-20 F3\nM30\n");
    assert!(r.findings.iter().all(|f| f.kind != "thread_chain"));
    let run_in: Vec<_> = r.findings.iter().filter(|f| f.kind == "run_in").collect();
    assert_eq!(run_in.len(), 1, "{:?}", r.findings);
    assert_eq!((run_in[0].pass, run_in[0].value), (Some(2), 0.0));
}
