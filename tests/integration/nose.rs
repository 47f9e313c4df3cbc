//! Lathe tool nose radius compensation (G41/G42/G40) against LinuxCNC's own interpreter:
//! seeded random contours (`tests/data/linuxcnc/nose/gen.py`, rs274's canon by `regen.sh`
//! with the tool table `tool.tbl`: every orientation, radii 0.2 to 1.6 mm, `D` naming
//! another entry) must give rs274's moves one for one: rapids, feeds and arcs (the arcs
//! rs274 inserts round outer corners among them), every end and arc centre to rs274's 4
//! printed decimals (1e-7 mm, the programs being in mm x 1000); where rs274 stops, vpcut
//! refuses the program with rs274's words at the block rs274 names.

use crate::support::root;
use vpcut::{
    interpret_with, linuxcnc_orientation, Dialect, MoveKind, NcOptions, NoseData, Settings, Source,
};

/// One motion of rs274's canon: kind, end (radius, z) and for an arc its centre (radius,
/// z) and counter-clockwise (seen from +Y, Z right, X up).
#[derive(Debug)]
struct Canon {
    kind: MoveKind,
    from: [f64; 2],
    to: [f64; 2],
    arc: Option<([f64; 2], bool)>,
}

fn canon(text: &str) -> Vec<Canon> {
    let mut out = Vec::new();
    let mut at = [0.0, 0.0];
    for line in text.lines() {
        let args = || -> Vec<f64> {
            let inner = &line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()];
            inner
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect()
        };
        let (kind, to, arc) =
            if line.contains("STRAIGHT_TRAVERSE(") || line.contains("STRAIGHT_FEED(") {
                let v = args();
                let kind = if line.contains("TRAVERSE") {
                    MoveKind::Rapid
                } else {
                    MoveKind::Feed
                };
                (kind, [v[0], v[2]], None)
            } else if line.contains("ARC_FEED(") {
                // In the XZ plane: first end Z, second end X, first axis centre Z, second X,
                // rotation (1 counter-clockwise in (Z, X)).
                let v = args();
                (
                    MoveKind::Arc,
                    [v[1], v[0]],
                    Some(([v[3], v[2]], v[4] > 0.0)),
                )
            } else {
                continue;
            };
        // rs274 makes moves of no length (a lathe tool's origin moved before an arc), where
        // vpcut leaves out what does not move.
        if (to[0] - at[0]).hypot(to[1] - at[1]) > 0.6e-4 || arc.is_some() {
            out.push(Canon {
                kind,
                from: at,
                to,
                arc,
            });
        }
        at = to;
    }
    out
}

/// `tool.tbl`: each tool's nose radius (its diameter `D` in inches, the programs' mm x
/// 1000) and tip direction (its orientation `Q` in FANUC's numbering).
fn tool_table(text: &str) -> NoseData {
    let mut noses = NoseData::default();
    for line in text.lines() {
        let word = |c: char| -> f64 {
            line.split_whitespace()
                .find_map(|w| w.strip_prefix(c))
                .unwrap()
                .parse()
                .unwrap()
        };
        let id = word('T') as u32;
        let radius = word('D') * 25.4 / 2.0;
        let q = word('Q') as u8;
        noses.tool.insert(id, (radius, linuxcnc_orientation(q)));
    }
    noses
}

#[test]
fn random_contours_match_linuxcnc_move_for_move() {
    let dir = root().join("tests/data/linuxcnc/nose");
    let noses = tool_table(&std::fs::read_to_string(dir.join("tool.tbl")).unwrap());
    let opts = NcOptions {
        settings: Settings {
            noses,
            ..Settings::default()
        },
        ..NcOptions::default()
    };
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let n = e.unwrap().file_name().into_string().unwrap();
            n.strip_suffix(".ngc").map(str::to_string)
        })
        .collect();
    names.sort();
    assert!(names.len() >= 40, "{} programs", names.len());
    let (mut n_errors, mut n_moves, mut n_arcs) = (0, 0, 0);
    let mut failures = Vec::new();
    for name in &names {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let src = Source {
            name: format!("{name}.ngc"),
            text: text.clone(),
        };
        let got = interpret_with(&src, Dialect::Linuxcnc, &|_| None, &opts);
        if let Ok(err) = std::fs::read_to_string(dir.join(format!("{name}.err"))) {
            n_errors += 1;
            let mut lines = err.lines();
            let words = lines.next().unwrap();
            let block = lines.next().unwrap().trim();
            let line = text.lines().position(|l| l.trim() == block).unwrap() + 1;
            match got {
                Ok(_) => failures.push(format!("{name}: runs, rs274 stops: {words} at {line}")),
                Err(e) if e.line != line || !e.message.contains(words) => {
                    failures.push(format!("{name}: {e}\n   vs rs274 at line {line}: {words}"))
                }
                Err(_) => {}
            }
            continue;
        }
        let moves = match got {
            Ok(t) => t.moves,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let want = canon(&std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap());
        let moves: Vec<&vpcut::Move> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Arc || m.x_dia != m.x_start || m.z != m.z_start)
            .collect();
        if moves.len() != want.len() {
            failures.push(format!(
                "{name}: {} moves, rs274 {}",
                moves.len(),
                want.len()
            ));
            continue;
        }
        for (k, (m, w)) in moves.iter().zip(&want).enumerate() {
            n_moves += 1;
            let got = [m.x_start / 2.0, m.z_start, m.x_dia / 2.0, m.z];
            let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
            let mut bad = m.kind != w.kind || (0..4).any(|c| (got[c] - exp[c]).abs() > 0.51e-4);
            if let (Some(g), Some((c, ccw))) = (m.arc, w.arc) {
                n_arcs += 1;
                bad |= (g.x_centre_dia / 2.0 - c[0]).abs() > 0.51e-4
                    || (g.z_centre - c[1]).abs() > 0.51e-4
                    || g.clockwise == ccw;
            }
            if bad {
                failures.push(format!("{name} move {k}: {m:?}\n   vs rs274 {w:?}"));
                break;
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} programs differ from rs274:\n{}",
        failures.len(),
        names.len(),
        failures.join("\n")
    );
    // 96 programs: 20 refused as rs274 refuses them, 809 moves (316 arcs, those rs274
    // inserts round outer corners among them) equal to rs274's.
    assert!(
        n_errors >= 15 && n_moves > 700 && n_arcs > 250,
        "{n_errors} {n_moves} {n_arcs}"
    );
}

/// The finished part (issue 26) turned with a nose radius: an M30x2 (basic size) on a 34 mm
/// bar whose drawing has a lead-in chamfer of angle `phi` to the axis (radial height `a`,
/// axial length `c`, `tan phi = a / c`) and the 30 mm major diameter to the bar's end. The
/// program faces, turns the chamfer and the diameter with a turning tool of nose radius
/// `rn` (tip direction 3, the default), then cuts the thread with a G76. With G42 on the
/// contour (type A start-up on the chamfer's extension, G40 off the bar's end) the nose
/// runs tangent to the drawn chamfer: the part is the drawing, no finding. Without, the
/// imaginary tip runs on the chamfer and the nose centre `rn (1, 1)` from it lies
/// `rn (sin phi + cos phi)` from the chamfer's line: a band of stock `s = rn (sin phi +
/// cos phi - 1)` thick on the chamfer (`rn (2 - sqrt 2)` in radius at 45 deg), which the
/// thread's flanks cut through; its worst point is at a tooth's corner where the band meets
/// a flank at `beta = 120 deg - phi`: `s / sin(beta)` when `beta < 90 deg`, else `s`
/// (`tests/integration/part_outline.rs` derives the same for a band made by moving the
/// chamfer).
fn part_job(a: f64, c: f64, rn: f64, comp: bool) -> vpcut::Job {
    let (g42, g40) = if comp { ("G42 ", "G40 ") } else { ("", "") };
    // The start-up ends on the chamfer's line 0.5 mm in front of the face.
    let e = 0.5;
    let rs = 15.0 - a - e * a / c;
    let prog = format!(
        "%\nO2701\nN10 G21 G18 G40 G99\nN20 T0101\nN30 G97 S800 M03\n\
         N40 G00 X36.0 Z0.0\nN50 G01 X-1.0 F0.1\nN60 G00 X{xs:.6} Z2.0\n\
         N70 {g42}G01 X{x0:.6} Z{e:.6} F0.1\nN80 X30.0 Z{z1:.6}\nN90 Z-60.0\n\
         N100 {g40}G00 X40.0\nN110 G00 X100.0 Z100.0\nN120 T0303\nN130 G97 S600 M03\n\
         N140 G00 X32.0 Z5.0\nN150 G76 P010060 Q100 R0.05\n\
         N160 G76 X27.546 Z-36.0 P1227 Q400 F2.0\nN170 G00 X100.0 Z100.0\nN180 M30\n%\n",
        xs = 2.0 * rs - 4.0,
        x0 = 2.0 * rs,
        z1 = -c,
    );
    let text = format!(
        r#"
name = "nose"
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
nose_radius = {rn}
[[tool]]
id = 3
kind = "threading"
angle = 60.0
tip_flat = 0.3333333333
reference = "tip"
[program]
file = "O2701.NC"
dialect = "fanuc"
[machine]
spindle_rpm = 600
max_feed = 5000
[simulation]
axial_spacing = 0.02
angular_cells = 180
measure_generators = 4
tolerance = 0.01
[part]
profile = [[0.0, {d0:.6}], [{zc:.6}, 30.0], [-59.0, 30.0]]
"#,
        d0 = 30.0 - 2.0 * a,
        zc = -c,
    );
    vpcut::Job::from_toml_with(&text, "nose.toml", &move |f: &str| {
        (f == "O2701.NC").then(|| prog.clone())
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_compensated_chamfer_is_the_drawing_and_an_uncompensated_one_leaves_the_closed_form() {
    let mut rng = crate::support::Rng(2726);
    for case in 0..5 {
        let phi = rng.range(20.0, 70.0).to_radians();
        let rn = rng.range(0.2, 1.2);
        let c = rng.range(1.0, 2.0).min(2.5 / phi.tan());
        let a = c * phi.tan();
        let run = |comp| {
            vpcut::simulate_report(&part_job(a, c, rn, comp), &vpcut::SimOptions::default())
                .unwrap()
        };
        let exact = run(true);
        let d = &exact.deviation;
        assert!(
            d.max_leftover_mm < 1e-3 && d.max_gouge_mm < 1e-3,
            "case {case} (phi {:.1} deg, rn {rn:.3}): compensated, leftover {} gouge {}: {:#?}",
            phi.to_degrees(),
            d.max_leftover_mm,
            d.max_gouge_mm,
            exact.findings
        );
        assert_eq!(exact.verdict, vpcut::Verdict::Pass, "{:#?}", exact.findings);
        let plain = run(false);
        let s = rn * (phi.sin() + phi.cos() - 1.0);
        let beta = 120f64.to_radians() - phi;
        let want = if beta < 90f64.to_radians() {
            s / beta.sin()
        } else {
            s
        };
        let d = &plain.deviation;
        assert!(
            (d.max_leftover_mm - want).abs() < 1e-3 && d.max_gouge_mm < 1e-3,
            "case {case} (phi {:.1} deg, rn {rn:.3}): leftover {} vs {want}, gouge {}",
            phi.to_degrees(),
            d.max_leftover_mm,
            d.max_gouge_mm
        );
        let z = d.max_leftover_at.as_ref().unwrap().z_mm;
        assert!((-c - 0.05..=0.05).contains(&z), "case {case}: at z {z}");
        assert_eq!(plain.verdict, vpcut::Verdict::Fail);
        eprintln!(
            "phi {:.1} rn {rn:.3}: compensated leftover {:.2e} gouge {:.2e}; plain {:.5} vs {want:.5}",
            phi.to_degrees(),
            exact.deviation.max_leftover_mm,
            exact.deviation.max_gouge_mm,
            d.max_leftover_mm
        );
    }
}

/// The job's keys: `tip_direction` moves the point the program drives (the kernel's anchor:
/// a tip 8 tool's driven point is the nose's lowest point, so an uncompensated program
/// turns the same diameter, shifted by `r_n` along z at a face); out-of-range values are
/// errors at their key.
#[test]
fn tip_direction_and_offset_keys() {
    let job = |tool: &str, machine: &str| {
        let text = format!(
            r#"
[blank]
diameter = 34.0
length = 60.0
z_front = 1.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 20.0
[[tool]]
id = 1
kind = "turning"
{tool}
[[tool]]
id = 3
kind = "threading"
angle = 60.0
[program]
file = "P.NC"
dialect = "fanuc"
[machine]
spindle_rpm = 600
{machine}
"#
        );
        vpcut::Job::from_toml_with(&text, "j.toml", &|_| {
            Some("O1\nT0101\nG00 X36.0 Z2.0\nG01 X30.0 F0.1\nZ-30.0\nT0303\nG00 X32.0 Z5.0\nG76 P010060 Q100 R0.05\nG76 X27.546 Z-25.0 P1227 Q400 F2.0\nM30\n".into())
        })
    };
    let e = job("tip_direction = 10", "").unwrap_err().to_string();
    assert!(
        e.contains("tool[0].tip_direction") && e.contains("0 to 9"),
        "{e}"
    );
    let e = job("", "offsets.1 = { t = 12 }").unwrap_err().to_string();
    assert!(e.contains("machine.offsets.1.t"), "{e}");
    let e = job("", "offsets.1 = { r = -0.4 }").unwrap_err().to_string();
    assert!(e.contains("machine.offsets.1.r"), "{e}");
    let e = job("tip_direction = 3", "").err();
    assert!(e.is_none(), "{e:?}");
    let e = job("", "offsets.1 = { r = 0.8, wear_r = -0.01, t = 3 }").err();
    assert!(e.is_none(), "{e:?}");
}

/// `vpcut toolpath --nose T:R:TIP` compensates as a job's turning tool does (the bore of the
/// FANUC corpus, its header's hand-checked start-up end X31.634315 Z0.882843); without it
/// G41 compensates nothing; a malformed value is a usage error.
#[test]
fn the_toolpath_command_takes_the_nose() {
    let prog = root().join("tests/data/nc/fanuc/corpus-0i-tnr-g41-bore-m30.nc");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .arg("toolpath")
            .arg(&prog)
            .args(["--dialect", "fanuc"])
            .args(extra)
            .output()
            .unwrap()
    };
    let line9 = |out: &std::process::Output| -> Vec<f64> {
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let row = text
            .lines()
            .find(|l| l.contains(",9,feed,"))
            .unwrap()
            .to_string();
        row.split(',')
            .skip(3)
            .take(3)
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let comp = run(&["--nose", "2:0.4:2"]);
    assert!(comp.status.success());
    let v = line9(&comp);
    assert!(
        (v[0] - 31.634315).abs() < 1e-6 && (v[2] - 0.882843).abs() < 1e-6,
        "{v:?}"
    );
    let plain = run(&[]);
    let v = line9(&plain);
    assert!(
        (v[0] - 31.4).abs() < 1e-12 && (v[2] - 1.0).abs() < 1e-12,
        "{v:?}"
    );
    assert_eq!(run(&["--nose", "2:0.4"]).status.code(), Some(2));
}
