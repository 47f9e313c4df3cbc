//! Taps (`[[tool]] kind = "tap"`, issue 27): a program's tapping strokes cut the internal
//! thread. Oracles: the internal thread's closed form (the tooth's root flat at the major
//! diameter, at every groove's centre, where the full teeth reached), the chamfer's cone
//! worked by hand in the chamfer zone, and the feed against the tap's pitch.

use vpcut::{simulate, FindingKind, Job, SimOptions, Surface};

/// An M10x1.5 thread tapped into an 8.5 mm bore of a 20 mm tube (z 0 to -30) by tool 5:
/// a plug tap, chamfer 3 threads (4.5 mm) from the basic minor 8.376 at its tip.
fn job(program: &str, dialect: &str) -> Job {
    let toml = format!(
        "name = \"m10-tap\"\n\
         [blank]\ndiameter = 20.0\nbore = 8.5\nlength = 30.0\nz_front = 0.0\n\
         [thread]\nside = \"internal\"\nform = \"iso-metric\"\nmajor_diameter = 10.0\n\
         pitch = 1.5\nminor_diameter = 8.5\nlength = 12.0\n\
         [[tool]]\nid = 5\nkind = \"tap\"\ndiameter = 10.0\npitch = 1.5\nchamfer_threads = 3\n\
         [program]\nfile = \"T.NC\"\ndialect = \"{dialect}\"\n\
         [machine]\nspindle_rpm = 300\n\
         [simulation]\naxial_spacing = 0.01\nangular_cells = 72\ntolerance = 0.01\n"
    );
    let load = |f: &str| (f == "T.NC").then(|| program.to_string());
    Job::from_toml_with(&toml, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"))
}

/// FANUC rigid tapping from the R point Z3 to Z-20 at 1.5 mm/rev (M03, sync 0).
const FANUC: &str = "G18 G21 G99\nT0505\nG97 S300 M03\nG0 X0 Z10.\nM29 S300\nG84 Z-20. R-7. F1.5\nG80\nG0 Z50.\nM30\n";

#[test]
fn a_tap_cuts_the_internal_thread_and_its_chamfer_cone() {
    let job = job(FANUC, "fanuc");
    // The inward stroke gives two passes (full depth, chamfer); the way back none.
    assert_eq!(job.passes.len(), 2, "{:?}", job.passes);
    assert!(job
        .program_warnings
        .iter()
        .all(|w| !w.message.contains("tapping")));
    let out = simulate(&job, &SimOptions::default()).unwrap();
    let r = &out.report;
    assert!(
        r.findings.iter().all(|f| f.kind != FindingKind::TapFeed),
        "{:?}",
        r.findings
    );
    // The thread (z 0 to -12) lies where the full teeth reached (behind -15.5): the cut is
    // the closed form, no gouge or leftover beyond the tolerance.
    assert_eq!(r.verdict, vpcut::Verdict::Pass, "{:?}", r.findings);
    // Groove centres, by hand: the tip's helix from Z3 at sync 0, M03 (the part angle under
    // the tool falls 2 pi a revolution), lead 1.5: at column angle th the tip passed at
    // revolutions t = frac(-th / 2 pi) + n, z = 3 - 1.5 t. Where the tap ended (tip at -20)
    // a groove centre s = z + 20 behind the tip is cut to the cone's diameter
    // 8.376 + (10 - 8.376) s / 4.5 (s < 4.5), to the major diameter 10 beyond.
    let st = &out.stock;
    let g = st.grid;
    let mut checked = (0, 0);
    for i in (0..g.n_theta).step_by(9) {
        let th = g.theta(i);
        let frac = (-th / std::f64::consts::TAU).rem_euclid(1.0);
        for n in 0..20 {
            let z = 3.0 - 1.5 * (frac + n as f64);
            if !(-19.8..=-1.0).contains(&z) {
                continue;
            }
            let s = z + 20.0;
            let want = if s < 4.5 {
                (8.376 + (10.0 - 8.376) * s / 4.5) / 2.0
            } else {
                5.0
            };
            if want <= 4.25 + 1e-3 {
                continue; // the cone inside the bore cuts nothing
            }
            let j = ((z - g.z0) / g.dz).round() as usize;
            let got = st.radius(Surface::Inner, i, j).unwrap();
            assert!(
                (got - want).abs() < 2e-4,
                "column {i} z {z}: radius {got}, the closed form {want}"
            );
            if s < 4.5 {
                checked.0 += 1;
            } else {
                checked.1 += 1;
            }
        }
    }
    assert!(checked.0 >= 16 && checked.1 >= 60, "{checked:?}");
}

#[test]
fn a_tap_fed_off_its_pitch_is_one_finding_at_its_block() {
    // F1.55 for a 1.5 pitch tap: 0.05 mm/rev off, one finding at the G84 block (line 6),
    // for the stroke in and out alike.
    let job = job(&FANUC.replace("F1.5", "F1.55"), "fanuc");
    let r = vpcut::simulate_report(&job, &SimOptions::default()).unwrap();
    let f: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::TapFeed)
        .collect();
    assert_eq!(f.len(), 1, "{:?}", r.findings);
    assert_eq!((f[0].file.as_deref(), f[0].line), (Some("T.NC"), Some(6)));
    assert!((f[0].value.unwrap() - 0.05).abs() < 1e-9);
    assert!(f[0].is_error());
    assert!(!f[0].message.contains("Some("), "{}", f[0].message);
    assert_eq!(r.verdict, vpcut::Verdict::Fail);
}

#[test]
fn every_dialects_tapping_cuts_with_the_tap() {
    // The same stroke (R point Z3 to Z-20, 1.5 mm/rev) written in each dialect's tapping
    // code gives the same two passes as FANUC's G84.
    let fanuc = job(FANUC, "fanuc").passes;
    let cases = [
        (
            "fanuc",
            "T0505\nG97 S300 M03\nG0 X0 Z3.\nG32 Z-20. F1.5\nG0 Z50.\nM30\n",
        ),
        (
            "linuxcnc",
            "G7 G18 G21\nT5 M6\nS300 M3\nG0 X0 Z3\nG33.1 Z-20 K1.5\nG0 Z50\nM2\n",
        ),
        (
            "siemens-840d",
            "T5 D1\nS300 M3\nG0 X0 Z3\nSPOS=0\nG331 Z-20 K1.5 S300\nG332 Z3 K1.5\nG0 Z50\nM30\n",
        ),
    ];
    for (dialect, prog) in cases {
        let got = job(prog, dialect).passes;
        assert_eq!(got.len(), 2, "{dialect}: {got:?}");
        for (a, b) in got.iter().zip(&fanuc) {
            assert_eq!(
                (a.x_start, a.x_end, a.z_start, a.z_end, a.lead),
                (b.x_start, b.x_end, b.z_start, b.z_end, b.lead),
                "{dialect}"
            );
            let d = (a.start_angle - b.start_angle).rem_euclid(std::f64::consts::TAU);
            assert!(
                d < 1e-9 || std::f64::consts::TAU - d < 1e-9,
                "{dialect}: {a:?} {b:?}"
            );
        }
    }
}

#[test]
fn bad_tap_keys_name_their_key() {
    // (the tool table's keys, the key the error names, words of the message)
    let cases = [
        (
            "diameter = 10.0\nchamfer_threads = 3",
            "tool[0].kind",
            "`pitch`",
        ),
        (
            "pitch = 1.5\nchamfer_threads = 3",
            "tool[0].kind",
            "`diameter`",
        ),
        (
            "diameter = 10.0\npitch = 1.5",
            "tool[0].kind",
            "chamfer_length",
        ),
        (
            "diameter = 10.0\npitch = 1.5\nchamfer_threads = 3\nchamfer_length = 4",
            "tool[0].chamfer_threads",
            "not both",
        ),
        (
            "diameter = 10.0\npitch = 1.5\nchamfer_threads = 3\nchamfer_diameter = 11",
            "tool[0].chamfer_diameter",
            "at most the major diameter",
        ),
        (
            "diameter = 10.0\npitch = 12\nchamfer_threads = 3",
            "tool[0].pitch",
            "below the diameter",
        ),
        (
            "diameter = 10.0\npitch = 1.5\nchamfer_threads = 3\nangle = 60",
            "tool[0].angle",
            "does not apply",
        ),
    ];
    for (keys, key, words) in cases {
        let toml = format!(
            "[blank]\ndiameter = 20.0\nbore = 8.5\nlength = 30.0\n\
             [thread]\nside = \"internal\"\nform = \"iso-metric\"\nmajor_diameter = 10.0\npitch = 1.5\nminor_diameter = 8.5\nlength = 12.0\n\
             [[tool]]\nid = 5\nkind = \"tap\"\n{keys}\n\
             [program]\nfile = \"T.NC\"\ndialect = \"fanuc\"\n"
        );
        let load = |f: &str| (f == "T.NC").then(|| FANUC.to_string());
        let e = Job::from_toml_with(&toml, "job.toml", &load).expect_err(keys);
        let text = e.to_string();
        assert!(text.contains(key) && text.contains(words), "{keys}: {text}");
    }
}
