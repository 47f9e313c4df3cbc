//! The program's turning moves cut the stock: the turned scene's profile against its hand
//! derivation (README of `scenes/turned-m20x2.5-fanuc`), a finer grid, rapids into
//! material, and the job's errors for turning tools.

use crate::support::{root, scene_text, with};
use vpcut::{simulate, Job, SimOptions, Surface};

const SCENE: &str = "turned-m20x2.5-fanuc";

fn program() -> String {
    std::fs::read_to_string(root().join("scenes").join(SCENE).join("O0017.NC")).unwrap()
}

/// The scene's job with `program` as its NC program and `edits` applied.
fn job_with(program: &str, edits: &[(&str, &str, &str)]) -> Result<Job, vpcut::JobError> {
    let text = with(&scene_text(SCENE), edits);
    let prog = program.to_string();
    let load = move |f: &str| (f == "O0017.NC").then(|| prog.clone());
    Job::from_toml_with(&text, "job.toml", &load)
}

/// The hand-derived turned radius at `z` (README): faced at Z0 past the centre, a 45 deg
/// chamfer X17 Z0 -> X19.8 Z-1.4 whose uncompensated 0.4 nose leaves the line
/// r_n (2 - sqrt 2) = 0.234315 mm high radially, the major diameter 19.8 to the nose
/// centre's end at Z-29.6, the nose's arc down to Z-30, the bar's 12.5 beyond.
fn turned_radius(z: f64) -> f64 {
    let rn = 0.4;
    if z >= 0.0 {
        0.0
    } else if z >= -29.6 {
        let chamfer = 9.9 - (z + 1.4) + rn * (2.0 - std::f64::consts::SQRT_2);
        chamfer.min(9.9)
    } else if z >= -30.0 {
        9.9 + rn - (rn * rn - (z + 29.6).powi(2)).sqrt()
    } else {
        12.5
    }
}

#[test]
fn the_crest_is_the_turned_profile_derived_by_hand() {
    // Every angle's radius is at most the turned one; the thread's grooves leave some
    // angle of every z untouched (the groove is narrower than the pitch at every depth
    // here), so the largest radius over the columns is the turned profile itself.
    let job = job_with(&program(), &[("simulation", "angular_cells", "720")]).unwrap();
    let out = simulate(&job, &SimOptions::default()).unwrap();
    let s = &out.stock;
    let g = s.grid;
    let mut checked = 0;
    for j in 0..g.n_z {
        let z = g.z(j);
        let top = (0..g.n_theta)
            .map(|i| s.radius(Surface::Outer, i, j).unwrap())
            .fold(f64::NEG_INFINITY, f64::max);
        let want = turned_radius(z);
        assert!(
            (top - want).abs() < 2e-6,
            "z {z}: turned to {top}, derived {want}"
        );
        checked += 1;
    }
    assert_eq!(checked, 4000);
    // The crest of every turn is gouged by 0.1 mm: 19.8 against the basic 20.0.
    let r = &out.report;
    assert!((r.deviation.max_gouge_mm - 0.1).abs() < 2e-6);
    for t in &r.turns {
        assert!(
            (t.max_diameter_mm.unwrap() - 19.8).abs() < 4e-6,
            "turn {}",
            t.turn
        );
    }
}

#[test]
fn a_finer_grid_gives_the_same_crest_and_root() {
    let job = job_with(
        &program(),
        &[
            ("simulation", "angular_cells", "1440"),
            ("simulation", "axial_spacing", "0.004"),
        ],
    )
    .unwrap();
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    assert!((r.deviation.max_gouge_mm - 0.1).abs() < 2e-6);
    // The root: X16.933 against d3 = 16.932828, 0.000086 mm proud.
    assert!((r.deviation.max_leftover_mm - 0.000086).abs() < 2e-6);
}

#[test]
fn a_rapid_into_the_turned_part_is_a_finding_at_its_block() {
    // After the shoulder (X26 Z-30) a rapid to X18 Z-10: its nose bottom ends at r = 9.0
    // at z = -9.6, 0.9 mm under the turned 9.9 (the deepest point of the move).
    let prog = program().replace(
        "N120 G00 X100.0 Z100.0",
        "N120 G00 X18.0 Z-10.0\nN125 X100.0 Z100.0",
    );
    let line = prog.lines().position(|l| l.starts_with("N120")).unwrap() + 1;
    let job = job_with(&prog, &[("simulation", "angular_cells", "72")]).unwrap();
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let hits: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == vpcut::FindingKind::RapidCut)
        .collect();
    // The rapid out of it (N125) starts 0.9 deep too: a rapid is checked against what the
    // feeds left, and removes nothing itself (a crash is not a cut).
    assert_eq!(hits.len(), 2, "{hits:?}");
    for (f, line) in hits.iter().zip([line, line + 1]) {
        assert_eq!(f.line, Some(line));
        assert!((f.value.unwrap() - 0.9).abs() < 1e-6, "{f:?}");
        assert!((f.z_mm.unwrap() + 9.6).abs() < 0.011, "{f:?}");
    }
    assert_eq!(r.verdict, vpcut::Verdict::Fail);
    // Down to the turned surface exactly (X19.8): it touches, and cuts nothing.
    let prog = program().replace(
        "N120 G00 X100.0 Z100.0",
        "N120 G00 X19.8 Z-20.0\nN125 X100.0 Z100.0",
    );
    let job = job_with(&prog, &[("simulation", "angular_cells", "72")]).unwrap();
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    assert!(r
        .findings
        .iter()
        .all(|f| f.kind != vpcut::FindingKind::RapidCut));
    // The same plunge (X18 at Z-10, from X27) before the part is turned meets the bar's
    // 12.5: 3.5 mm deep, on the way in and on the way out.
    let prog = program().replace(
        "N80 X17.0",
        "N71 X27.0\nN72 Z-10.0\nN73 X18.0\nN74 X27.0\nN75 Z2.0\nN80 X17.0",
    );
    let job = job_with(&prog, &[("simulation", "angular_cells", "72")]).unwrap();
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let hits: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == vpcut::FindingKind::RapidCut)
        .collect();
    assert_eq!(hits.len(), 2, "{hits:?}");
    for f in hits {
        assert!((f.value.unwrap() - 3.5).abs() < 1e-6, "{f:?}");
        assert!((f.z_mm.unwrap() + 9.6).abs() < 0.011, "{f:?}");
    }
}

#[test]
fn turning_tools_are_checked_key_by_key() {
    let text = scene_text(SCENE);
    let bad = [
        (
            "nose_radius = 0.4",
            "nose_radius = -0.4",
            "tool[0].nose_radius",
        ),
        (
            "edge_angles = [-5.0, 85.0]",
            "edge_angles = [-5.0, 95.0]",
            "tool[0].edge_angles",
        ),
        (
            "edge_angles = [-5.0, 85.0]",
            "edge_angles = [-50.0, 40.0]",
            "tool[0].edge_angles",
        ),
        (
            "edge_angles = [-5.0, 85.0]",
            "edge_angles = [-5.0, 85.0]\nwidth = 3.0",
            "tool[0].width",
        ),
        (
            "edge_angles = [-5.0, 85.0]",
            "edge_angles = [-5.0, 85.0]\nside = \"inside\"",
            "tool[0]",
        ),
    ];
    let prog = program();
    for (from, to, key) in bad {
        let t = text.replace(from, to);
        let p = prog.clone();
        let load = move |f: &str| (f == "O0017.NC").then(|| p.clone());
        let e = Job::from_toml_with(&t, "job.toml", &load).unwrap_err();
        let d = e.diagnostic();
        assert!(d.message.contains(key) || d.line > 0, "{to}: {d:?}");
        assert!(d.line > 0, "{to}: no line: {d:?}");
    }
    // A thread block under a turning tool's T number says so, at its line.
    let bad = program().replace("N130 T0303", "N130 T0101");
    let e = job_with(&bad, &[]).unwrap_err().diagnostic();
    assert!(e.message.contains("a turning tool"), "{e:?}");
    assert!(e.line > 0, "{e:?}");
    // A turning tool needs a program; a pass cannot use it.
    let t = text.replace(
        "[program]\nfile = \"O0017.NC\"\ndialect = \"fanuc\"\n",
        "[[pass]]\ntool = 1\nx = 17.0\nz_start = 5.0\nz_end = -25.0\nlead = 2.5\n",
    );
    let e = Job::from_toml(&t, "job.toml").unwrap_err();
    assert!(
        e.diagnostic().message.contains("tool[0].kind"),
        "{:?}",
        e.diagnostic()
    );
}

#[test]
fn a_boring_bar_in_g90_cycles_turns_the_bore_by_hand() {
    // A tube (40 x 16 bore), bored by two FANUC G90 cycles with a boring bar (T0202,
    // `side = "internal"`, 0.4 nose) to X17.6 from Z2 to Z-25, then threaded M20x2.5
    // inside. The bar's imaginary tip is on the material's side (+r) and the -z side: its
    // nose centre runs at r - 0.4, z + 0.4. Derived: r = 8.8 from the face to z = -24.6,
    // the nose's arc 8.4 + sqrt(0.16 - (z + 24.6)^2) to z = -25, the blank's 8 beyond.
    // The grooves leave the bore's radius at some angle of every z: the smallest radius
    // over the columns is the bored profile.
    let text = r#"
        [blank]
        diameter = 40.0
        bore = 16.0
        length = 30.0
        [thread]
        side = "internal"
        form = "iso-metric"
        major_diameter = 20.0
        pitch = 2.5
        length = 20.0
        [[tool]]
        id = 1
        kind = "threading"
        angle = 60.0
        tip_flat = 0.3125
        reference = "tip"
        [[tool]]
        id = 2
        kind = "turning"
        side = "internal"
        edge_angles = [-3.0, 58.0]
        [program]
        file = "bore.nc"
        dialect = "fanuc"
        [simulation]
        angular_cells = 360
        axial_spacing = 0.01
        measure_generators = 2
    "#;
    let prog = "O1\nT0202\nG00 X15.0 Z2.0\nG90 X17.0 Z-25.0 F0.2\nX17.6\nG00 X15.0 Z50.0\nT0101\nG00 X16.0 Z5.0\nG92 X18.0 Z-22.5 F2.5\nX19.0\nX19.7\nX20.0\nG00 X16.0 Z50.0\nM30\n";
    let load = |f: &str| (f == "bore.nc").then(|| prog.to_string());
    let job = Job::from_toml_with(text, "job.toml", &load).unwrap();
    let out = simulate(&job, &SimOptions::default()).unwrap();
    let s = &out.stock;
    let g = s.grid;
    for j in 0..g.n_z {
        let z = g.z(j);
        let low = (0..g.n_theta)
            .map(|i| s.radius(Surface::Inner, i, j).unwrap())
            .fold(f64::INFINITY, f64::min);
        let want = if z >= -24.6 {
            8.8
        } else if z >= -25.0 {
            8.4 + (0.16 - (z + 24.6).powi(2)).sqrt()
        } else {
            8.0
        };
        assert!(
            (low - want).abs() < 2e-6,
            "z {z}: bored to {low}, derived {want}"
        );
    }
    // The outside is untouched.
    assert!(s.outer.iter().all(|&v| v == 0.0));
    assert!(out
        .report
        .findings
        .iter()
        .all(|f| f.kind != vpcut::FindingKind::RapidCut));
}
