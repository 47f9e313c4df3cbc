//! Issue 26, the finished part: a thread's lead-in chamfer (and any contour below the
//! thread) drawn in `[part]` is part of the ideal, without a tolerance class too.
//!
//! An M30x2 (basic size, no class) on a 34 mm bar: a program faces, turns a chamfer of
//! axial length `c` and radial height `a` into the 30 mm major diameter with a sharp
//! turning tool (nose radius 0: its cut is the programmed line exactly, its edges lean
//! away from a chamfer of up to 85 deg), then cuts the thread with a G76 to the basic root
//! (X27.546, a 60 deg insert with the P/6 flat of the d3 profile). The part drawn with that
//! chamfer: the cut is the drawing, no finding. The chamfer programmed `dz` further into
//! +z leaves a band of stock whose normal thickness is `s = dz sin(phi)` (`phi` the
//! chamfer's angle to the axis, `tan phi = a / c`: the distance between two parallel lines
//! `dz` apart along z), and no gouge. The worst leftover is at a tooth's corner where the
//! band meets a flank at `beta = 120 deg - phi` (the 60 deg thread's flank lies at 60 deg
//! to the axis): the cut's corner lies `s / sin(beta)` out along the flank from the
//! drawing's, which is its nearest point of the drawing when `beta < 90 deg`; else the band
//! itself, `s`. Without `[part]` the same exact chamfer is a gouge of the crest of turn 1 (the
//! old verdict the issue reports).

use vpcut::{simulate_report, Job, Report, SimOptions};

/// The program: face, chamfer from (X30-2a, Z`dz`) to (X30, Z-c+`dz`), the major
/// diameter to Z-40 and the shoulder, then the two-block G76 of the M30x2 basic size.
fn program(a: f64, c: f64, dz: f64) -> String {
    format!(
        "%\nO2601\nN10 G21 G18 G40 G99\nN20 T0101\nN30 G97 S800 M03\n\
         N40 G00 X36.0 Z0.0\nN50 G01 X-1.0 F0.1\nN60 G00 X{x0:.4} Z1.0\n\
         N70 G01 Z{z0:.4} F0.1\nN80 X30.0 Z{z1:.4}\nN90 Z-40.0\nN100 X36.0\n\
         N110 G00 X100.0 Z100.0\nN120 T0303\nN130 G97 S600 M03\nN140 G00 X32.0 Z5.0\n\
         N150 G76 P010060 Q100 R0.05\nN160 G76 X27.546 Z-36.0 P1227 Q400 F2.0\n\
         N170 G00 X100.0 Z100.0\nN180 M30\n%\n",
        x0 = 30.0 - 2.0 * a,
        z0 = dz,
        z1 = -c + dz,
    )
}

/// The job; `part` is the `[part]` table's body, or empty for none.
fn job(a: f64, c: f64, dz: f64, part: &str) -> Job {
    let text = format!(
        r#"
name = "chamfer"
[blank]
diameter = 34.0
length = 60.0
z_front = 1.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 32.0
[[tool]]
id = 1
kind = "turning"
nose_radius = 0.0
edge_angles = [-5.0, 85.0]
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.3333333333
reference = "tip"
[program]
file = "O2601.NC"
dialect = "fanuc"
[machine]
spindle_rpm = 600
max_feed = 5000
[simulation]
axial_spacing = 0.02
angular_cells = 180
measure_generators = 4
tolerance = 0.01
{part}
"#
    );
    let prog = program(a, c, dz);
    Job::from_toml_with(&text, "chamfer.toml", &move |f: &str| {
        (f == "O2601.NC").then(|| prog.clone())
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

fn part(a: f64, c: f64) -> String {
    format!(
        "[part]\nprofile = [[0.0, {d0:.4}], [{zc:.4}, 30.0], [-40.0, 30.0], [-40.0, 34.0], [-59.0, 34.0]]",
        d0 = 30.0 - 2.0 * a,
        zc = -c,
    )
}

fn run(job: &Job) -> Report {
    simulate_report(job, &SimOptions::default()).unwrap()
}

#[test]
fn a_drawn_chamfer_is_part_of_the_ideal_thread() {
    // (radial height a, axial length c): 45, 60 and 30 deg chamfers, small and large.
    for (a, c) in [(2.0, 2.0), (1.0, 1.0), (1.5, 0.866), (0.8, 1.4), (2.5, 2.5)] {
        let exact = run(&job(a, c, 0.0, &part(a, c)));
        assert_eq!(
            exact.verdict,
            vpcut::Verdict::Pass,
            "chamfer {a} x {c}: {:#?}",
            exact.findings
        );
        assert!(exact.findings.is_empty(), "{:#?}", exact.findings);
        assert!(
            exact.deviation.max_leftover_mm < 1e-3 && exact.deviation.max_gouge_mm < 1e-3,
            "chamfer {a} x {c}: gouge {} leftover {}",
            exact.deviation.max_gouge_mm,
            exact.deviation.max_leftover_mm
        );
        for dz in [0.05, 0.12] {
            let short = run(&job(a, c, dz, &part(a, c)));
            let phi = (a / c).atan();
            let beta = 120f64.to_radians() - phi;
            let s = dz * phi.sin();
            let want = if beta < 90f64.to_radians() {
                s / beta.sin()
            } else {
                s
            };
            let d = &short.deviation;
            assert!(
                (d.max_leftover_mm - want).abs() < 1e-3,
                "chamfer {a} x {c} moved {dz}: leftover {} vs {want}",
                d.max_leftover_mm
            );
            assert!(d.max_gouge_mm < 1e-3, "gouge {}", d.max_gouge_mm);
            // Only on the chamfer's turns: it reaches z -c + dz.
            let z = d.max_leftover_at.as_ref().unwrap().z_mm;
            assert!((-c + dz - 0.05..=dz).contains(&z), "at z {z}");
            assert_eq!(short.verdict, vpcut::Verdict::Fail);
        }
    }
    // Without the drawing's part the exact chamfer is a gouge of turn 1, deeper than the
    // tolerance by far (the chamfer's radial height at the face, less what the groove takes).
    let bare = run(&job(2.0, 2.0, 0.0, ""));
    assert!(
        bare.deviation.max_gouge_mm > 0.5,
        "{}",
        bare.deviation.max_gouge_mm
    );
    assert_eq!(bare.verdict, vpcut::Verdict::Fail);
}
