//! Unit tests of the FANUC milling interpreter and of cutter radius compensation.

use super::comp::{compensate, Comp, Programmed, Site};
use crate::nc::*;
use std::f64::consts::{PI, TAU};

/// G57's work zero at the job's origin, G54's at (100, 50, -10); H10 a length offset,
/// D60 = 5 mm, D61 = 9 mm; the tool comes from z = 100.
fn settings() -> MillSettings {
    let mut work_offsets = [[0.0; 3]; 6];
    work_offsets[0] = [100.0, 50.0, -10.0];
    MillSettings {
        work_offsets,
        radius_offsets: vec![(60, 5.0), (61, 9.0)],
        length_offsets: vec![10],
        home_z: 100.0,
    }
}

fn mill(text: &str) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "M.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        settings: Settings {
            mill: Some(settings()),
            ..Settings::in_mm()
        },
        ..Options::default()
    };
    interpret_with(&src, Dialect::Fanuc, &|_| None, &opts)
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
}

#[track_caller]
fn assert_pt(got: [f64; 3], want: [f64; 3]) {
    assert!(close(got, want, 1e-9), "got {got:?}, want {want:?}");
}

#[track_caller]
fn assert_near(got: f64, want: f64) {
    assert!((got - want).abs() <= 1e-9, "got {got}, want {want}");
}

const SEED: &str = "%
N10 G90 G00 G57 X0. Y0.
N20 G43 H10 Z0. M3 S1592
N30 G91 G00 X0. Y0. Z-25.375
N40 G41 D60 X0. Y-8.68 Z0.
N50 G03 X10. Y8.68 Z0.375 R8.78 F79.6
N60 G03 X0. Y0. Z1.5 I-10. J0.
N70 G03 X-10. Y8.68 Z0.375 R8.78
N80 G00 G40 X0. Y-8.68 Z0.
N90 G49 G57 G00 Z200. M5
N100 M30
%
";

/// Seed 001 by hand. The programmed contour: (0, 0, -25.375) -> start-up to (0, -8.68) ->
/// R8.78 CCW to (10, 0, -25) -> full circle I-10 about (0, 0) rising to -23.5 -> R8.78 CCW
/// to (0, 8.68, -23.125) -> G40 to (0, 0).
///
/// Entry arc centre: the chord (0, -8.68) -> (10, 0) is c = sqrt(10^2 + 8.68^2) =
/// 13.241692 long; the centre lies h = sqrt(8.78^2 - (c/2)^2) = 5.766524 from its middle
/// (5, -4.34), on its left (a CCW arc of at most 180 deg): C1 = (5, -4.34) + h (-8.68, 10)/c
/// = (1.220013, 0.014824). (Not quite on the X axis: the entry arc is not exactly tangent
/// to the R10 circle, it meets it at a 0.0969 deg inner corner.) The exit arc's centre is
/// C1 mirrored in X: C3 = (1.220013, -0.014824).
///
/// Start-up (G41, r = 5): the arc's start tangent is CCW, its left points to C1, so the
/// tool centre goes to S = (0, -8.68) + 5 (C1 - (0, -8.68)) / 8.78 = (0.694768, -3.728506).
/// The entry arc's tool circle: centre C1, radius 8.78 - 5 = 3.78. The full circle's: the
/// origin, radius 10 - 5 = 5. Their joint (an inner corner) is the intersection of the two
/// circles nearest (5, 0): J1 = (4.999998, 0.004379), at 0.050178 deg; the joint of the full
/// circle and the exit arc is J1 mirrored, J2 = (4.999998, -0.004379). So the full circle's
/// tool centre runs at radius 5 about the origin from J1 to J2: sweep 2 pi - 2 atan2(J1),
/// 0.00175 rad short of 2 pi, z from -25 to -23.5. The exit arc ends perpendicular to its end
/// tangent (the next in-plane block cancels): E = (0, 8.68) + 5 (C3 - (0, 8.68)) / 8.78 =
/// (0.694768, 3.728506); the cancel rapid runs from E to the programmed (0, 0, -23.125).
#[test]
fn seed_001_internal_thread_with_g41() {
    let t = mill(SEED).unwrap();
    assert!(t.moves.is_empty());
    let m = &t.mill;
    assert_eq!(
        m.iter().map(|m| m.line).collect::<Vec<_>>(),
        [3, 4, 5, 6, 7, 8, 9]
    );
    // N20: from above (home_z) down to Z0 under G43; N30 down to -25.375. No compensation.
    assert_eq!(m[0].kind, MillKind::Rapid);
    assert_pt(m[0].start, [0.0, 0.0, 100.0]);
    assert_pt(m[0].end, [0.0, 0.0, 0.0]);
    assert_eq!(
        (m[0].spindle, m[0].spindle_rpm),
        (Some(Spindle::Cw), Some(1592.0))
    );
    assert_pt(m[1].end, [0.0, 0.0, -25.375]);
    assert_eq!(m[1].comp, None);

    let c = (10f64 * 10.0 + 8.68 * 8.68).sqrt();
    let h = (8.78f64 * 8.78 - c * c / 4.0).sqrt();
    let c1 = [5.0 - h * 8.68 / c, -4.34 + h * 10.0 / c];
    assert!((c1[0] - 1.220013).abs() < 1e-6 && (c1[1] - 0.014824).abs() < 1e-6);
    let s = [5.0 * c1[0] / 8.78, -8.68 + 5.0 * (c1[1] + 8.68) / 8.78];
    // J1: |p| = 5 and |p - C1| = 3.78, so p . C1 = k = (25 + |C1|^2 - 3.78^2) / 2; p is k/|C1|
    // along C1 and sqrt(25 - (k/|C1|)^2) across it, on the side of (5, 0).
    let d = c1[0].hypot(c1[1]);
    let k = (25.0 + d * d - 3.78 * 3.78) / 2.0;
    let across = (25.0 - (k / d).powi(2)).sqrt();
    let j1 = [
        k / d * c1[0] / d + across * c1[1] / d,
        k / d * c1[1] / d - across * c1[0] / d,
    ];
    assert!((j1[0] - 4.999998).abs() < 1e-6 && (j1[1] - 0.004379).abs() < 1e-6);
    let e = [s[0], -s[1]];

    // N40: start-up, rapid, from the uncompensated point to S.
    let su = &m[2];
    assert_eq!(
        (su.kind, su.comp),
        (MillKind::Rapid, Some((CompSide::Left, 5.0)))
    );
    assert_pt(su.start, [0.0, 0.0, -25.375]);
    assert_pt(su.end, [s[0], s[1], -25.375]);
    assert_pt(su.programmed_end, [0.0, -8.68, -25.375]);

    // N50: entry arc, tool circle about C1 of radius 3.78 from S to J1.
    let entry = &m[3];
    let arc = entry.arc.unwrap();
    assert_eq!((entry.kind, entry.feed), (MillKind::Arc, Some(79.6)));
    assert_pt(arc.centre, [c1[0], c1[1], -25.375]);
    assert_near(arc.radius, 3.78);
    assert_pt(entry.start, [s[0], s[1], -25.375]);
    assert_pt(entry.end, [j1[0], j1[1], -25.0]);
    let ang = |p: [f64; 2], o: [f64; 2]| (p[1] - o[1]).atan2(p[0] - o[0]);
    assert_near(arc.sweep, ang(j1, c1) - ang([0.0, -8.68], c1));
    assert_eq!(arc.plane, Plane::Xy);

    // N60: the full circle, radius 5 about the origin, J1 -> J2, z -25 -> -23.5.
    let full = &m[4];
    let arc = full.arc.unwrap();
    assert_pt(arc.centre, [0.0, 0.0, -25.0]);
    assert_near(arc.radius, 5.0);
    assert_pt(full.start, [j1[0], j1[1], -25.0]);
    assert_pt(full.end, [j1[0], -j1[1], -23.5]);
    assert_near(arc.sweep, TAU - 2.0 * j1[1].atan2(j1[0]));
    assert!((arc.sweep - TAU).abs() < 2e-3);
    assert_pt(full.programmed_end, [10.0, 0.0, -23.5]);

    // N70: exit arc about C3, radius 3.78, J2 -> E.
    let exit = &m[5];
    let arc = exit.arc.unwrap();
    assert_pt(arc.centre, [c1[0], -c1[1], -23.5]);
    assert_near(arc.radius, 3.78);
    assert_pt(exit.end, [e[0], e[1], -23.125]);

    // N80: the cancel rapid from E to the programmed end.
    let cancel = &m[6];
    assert_eq!(
        (cancel.kind, cancel.comp),
        (MillKind::Rapid, Some((CompSide::Left, 5.0)))
    );
    assert_pt(cancel.start, [e[0], e[1], -23.125]);
    assert_pt(cancel.end, [0.0, 0.0, -23.125]);
}

/// G42 on the seed: the tool runs outside, at 8.78 + 5 on the R8.78 arcs and 15 on the
/// full circle (about the origin, nearly a full turn, z -25 -> -23.5). The joints are now
/// outer corners of 0.0969 deg, met where the offset circles cross.
#[test]
fn seed_001_with_g42_runs_outside() {
    let t = mill(&SEED.replace("G41", "G42")).unwrap();
    let m = &t.mill;
    assert_eq!(m.len(), 7);
    assert_near(m[3].arc.unwrap().radius, 13.78);
    let full = m[4].arc.unwrap();
    assert_near(full.radius, 15.0);
    assert_pt(full.centre, [0.0, 0.0, -25.0]);
    assert!((full.sweep - TAU).abs() < 5e-3, "{}", full.sweep);
    assert!((m[4].start[0] - 15.0).abs() < 1e-3 && (m[4].start[2] + 25.0).abs() < 1e-12);
    assert!((m[4].end[2] + 23.5).abs() < 1e-12);
    // Start-up: 5 mm to the right of the entry arc's start tangent, away from its centre.
    assert!(m[2].end[1] < -8.68 - 4.9, "{:?}", m[2].end);
    assert_eq!(m[6].comp, Some((CompSide::Right, 5.0)));
}

#[test]
fn line_corners_inner_and_outer() {
    // A 20 mm square CCW about (10, 10) with the tool (r 5) on the left: inside, inner
    // corners; the tool centre runs the 10 mm square (5, 5)..(15, 15).
    let t = mill(
        "G90 G57 G0 X0 Y-10\nG43 H10 Z-5\nG41 D60 G1 X0 Y0 F100\nX20\nY20\nX0\nY0\nG40 G0 X0 Y-10\nM30\n",
    )
    .unwrap();
    let ends: Vec<[f64; 3]> = t.mill.iter().map(|m| m.end).collect();
    // Start-up: perpendicular to X+ (the next block), left: (0, 5).
    assert_pt(ends[1], [0.0, 5.0, -5.0]);
    assert_pt(ends[2], [15.0, 5.0, -5.0]);
    assert_pt(ends[3], [15.0, 15.0, -5.0]);
    assert_pt(ends[4], [5.0, 15.0, -5.0]);
    // The last side ends perpendicular to its own direction (the next block cancels).
    assert_pt(ends[5], [5.0, 0.0, -5.0]);
    assert_pt(ends[6], [0.0, -10.0, -5.0]);
    // The same square clockwise with G41: the tool outside; 90 deg corners are extended.
    let t = mill(
        "G90 G57 G0 X0 Y-10\nG43 H10 Z-5\nG41 D60 G1 X0 Y0 F100\nY20\nX20\nY0\nX0\nG40 G0 X0 Y-10\nM30\n",
    )
    .unwrap();
    let ends: Vec<[f64; 3]> = t.mill.iter().map(|m| m.end).collect();
    assert_pt(ends[1], [-5.0, 0.0, -5.0]);
    assert_pt(ends[2], [-5.0, 25.0, -5.0]);
    assert_pt(ends[3], [25.0, 25.0, -5.0]);
    assert_pt(ends[4], [25.0, -5.0, -5.0]);
    // An acute outer corner (a 135 deg turn) is refused.
    let e = mill(
        "G90 G57 G0 X0 Y-10\nG43 H10 Z-5\nG41 D60 G1 X0 Y0 F100\nY20\nX20 Y0\nG40 G0 X30 Y-10\nM30\n",
    )
    .unwrap_err();
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("does not model that corner"), "{e}");
}

#[test]
fn compensation_errors() {
    let e = mill("G90 G57 G0 X0 Y0\nG43 H10 Z-5\nG41 D60 G3 X10 Y0 R5 F100\nM30\n").unwrap_err();
    assert_eq!(e.line, 3);
    assert!(
        e.message.contains("G02/G03") && e.message.contains("PS0034"),
        "{e}"
    );
    let e = mill("G90 G57 G0 X0 Y0\nG43 H10 Z-5\nG41 D7 G1 X10 F100\nM30\n").unwrap_err();
    assert!(e.message.contains("D7 is not a radius offset"), "{e}");
    let e = mill("G90 G57 G0 X0 Y0\nG43 H10 Z-5\nG41 D-60 G1 X10 F100\nM30\n").unwrap_err();
    assert!(e.message.contains("D-60 is not a radius offset"), "{e}");
    // The tool (r 9) does not fit in an R5 arc.
    let e = mill(
        "G90 G57 G0 X0 Y-5\nG43 H10 Z-5\nG41 D61 G1 X0 Y0 F100\nG3 X0 Y10 R5\nG40 G1 X0 Y0\nM30\n",
    )
    .unwrap_err();
    assert_eq!(e.line, 4);
    assert!(e.message.contains("R - r <= 0"), "{e}");
    let e = mill("G90 G57 G0 X0 Y-5\nG43 H10 Z-5\nG41 D60 G1 X0 Y0 F100\nG40 G3 X0 Y10 R5\nM30\n")
        .unwrap_err();
    assert!(e.message.contains("G40"), "{e}");
}

#[test]
fn tool_length_and_unknown_positions() {
    let e = mill("G90 G57 G0 X0 Y0\nG43 H11 Z5\nM30\n").unwrap_err();
    assert_eq!((e.line, e.col), (2, 5));
    assert!(
        e.message
            .contains("H11 is not a length offset of the job's tools"),
        "{e}"
    );
    // A plunge without G43.
    let e = mill("G90 G57 G0 X0 Y0\nG91 G0 Z-5\nM30\n").unwrap_err();
    assert!(e.message.contains("no tool length compensation"), "{e}");
    let e = mill("G90 G57 G0 X0 Y0 Z5\nG1 Z-5 F100\nM30\n").unwrap_err();
    assert!(e.message.contains("G43"), "{e}");
    // A feed move from an unknown X.
    let e = mill("G43 H10 Z5\nG1 X5 F100\nM30\n").unwrap_err();
    assert!(e.message.contains("unknown position"), "{e}");
    // No F yet.
    let e = mill("G90 G57 G0 X0 Y0\nG43 H10 Z5\nG1 X5\nM30\n").unwrap_err();
    assert!(e.message.contains("needs F"), "{e}");
    // Unknown X/Y: nothing recorded until both are known; G49 leaves upward unrecorded.
    let t = mill("G90 G57 G0 X1\nG43 H10 Z5\nY2\nZ1\nG49 G0 Z50\nX30\nM30\n").unwrap();
    assert_eq!(t.mill.len(), 1);
    assert_pt(t.mill[0].start, [1.0, 2.0, 5.0]);
    assert_pt(t.mill[0].end, [1.0, 2.0, 1.0]);
}

#[test]
fn arcs_r_negative_full_circles_and_g18() {
    // R-5 from (5, 0) to (-5, 0)... a half circle either way; use a quarter: (5, 0) to
    // (0, 5) about the origin is 90 deg CCW with R5, 270 deg CCW with R-5 (centre (5, 5)).
    let head = "G90 G57 G0 X5 Y0\nG43 H10 Z0\n";
    let t = mill(&format!("{head}G3 X0 Y5 R5 F100\nM30\n")).unwrap();
    let a = t.mill[1].arc.unwrap();
    assert_pt(a.centre, [0.0, 0.0, 0.0]);
    assert_near(a.sweep, PI / 2.0);
    let t = mill(&format!("{head}G3 X0 Y5 R-5 F100\nM30\n")).unwrap();
    let a = t.mill[1].arc.unwrap();
    assert_pt(a.centre, [5.0, 5.0, 0.0]);
    assert_near(a.sweep, 1.5 * PI);
    // A G02 full circle with I: sweep -2 pi, helical by Z-2.
    let t = mill(&format!("{head}G2 X5 Y0 Z-2 I-5 F100\nM30\n")).unwrap();
    let m = &t.mill[1];
    assert_near(m.arc.unwrap().sweep, -TAU);
    assert_pt(m.end, [5.0, 0.0, -2.0]);
    // R with end == start, and an end off the circle.
    let e = mill(&format!("{head}G2 X5 Y0 R5 F100\nM30\n")).unwrap_err();
    assert!(e.message.contains("full circle needs I/J"), "{e}");
    let e = mill(&format!("{head}G3 X0 Y5.01 I-5 F100\nM30\n")).unwrap_err();
    assert!(e.message.contains("off the circle by 0.0100 mm"), "{e}");
    // G18: the plane seen from +Y with Z right and X up. From (x 5, z 0) G02 to (x 0, z 5)
    // with K5 (centre at z 5, x 5)... take the centre at the origin: I-5 (x offset).
    // In (Z, X) the start is (0, 5), the end (5, 0): clockwise about the origin, -90 deg.
    let t = mill(&format!("{head}G18 G2 X0 Z5 I-5 K0 F100\nM30\n")).unwrap();
    let a = t.mill[1].arc.unwrap();
    assert_eq!(a.plane, Plane::Zx);
    assert_pt(a.centre, [0.0, 0.0, 0.0]);
    assert_near(a.sweep, -PI / 2.0);
    // G03 the other way round is the long way: 270 deg.
    let t = mill(&format!("{head}G18 G3 X0 Z5 I-5 F100\nM30\n")).unwrap();
    assert_near(t.mill[1].arc.unwrap().sweep, 1.5 * PI);
}

#[test]
fn static_check_in_mill_mode() {
    // Y, D, H, G43, G41 pass the check; G81 and G32 are refused with a message.
    let e =
        mill("G90 G57 G0 X0 Y0\nG43 H10 Z5\nG81 X0 Y0 Z-5 R1 F100\nG32 Z-5 F1\nM30\n").unwrap_err();
    let all = e.all();
    assert_eq!(all.len(), 2, "{e}");
    assert!(all
        .iter()
        .any(|d| d.line == 3 && d.message.contains("G81 (canned drilling cycle)")));
    assert!(all
        .iter()
        .any(|d| d.line == 4 && d.message.contains("lathe threading")));
    assert!(mill(SEED).unwrap().warnings.is_empty());
    // On a lathe Y and D are unknown addresses (warnings).
    let src = Source {
        name: "L.NC".into(),
        text: "G0 X10 Y5 D3 Z2\nM30\n".into(),
    };
    let t = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(t.warnings.len(), 2);
    // Other dialects are not milled.
    let src = Source {
        name: "L.NC".into(),
        text: "G0 X10\n".into(),
    };
    let opts = Options {
        settings: Settings {
            mill: Some(settings()),
            ..Settings::in_mm()
        },
        ..Options::default()
    };
    let e = interpret_with(&src, Dialect::Gsk980, &|_| None, &opts).unwrap_err();
    assert!(e.message.contains("FANUC only"), "{e}");
}

#[test]
fn subprograms_run_in_mill_mode() {
    let t =
        mill("O0001\nG90 G57 G0 X0 Y0\nG43 H10 Z1\nM98 P20002\nM30\nO0002\nG91 G1 Z-1 F50\nM99\n")
            .unwrap();
    assert_eq!(t.mill.len(), 3);
    assert_pt(t.mill[2].end, [0.0, 0.0, -1.0]);
}

/// The compensation pass alone: a line then a tangent arc, then a Z-only block, cancel.
#[test]
fn compensate_pure_pass_tangent_and_z_only() {
    let mv = |start: [f64; 3], end: [f64; 3], arc: Option<MillArc>, comp: Comp| Programmed {
        site: Site {
            file: "P".into(),
            line: 1,
            snippet: String::new(),
            stack: Vec::new(),
        },
        kind: if arc.is_some() {
            MillKind::Arc
        } else {
            MillKind::Feed
        },
        plane: Plane::Xy,
        start,
        end,
        arc,
        comp,
        feed: Some(100.0),
        spindle_rpm: None,
        spindle: None,
        tool: None,
        tool_word: None,
    };
    let on = Comp::On(CompSide::Right, 2.0);
    let arc = MillArc {
        centre: [10.0, 10.0, 0.0],
        radius: 10.0,
        sweep: PI / 2.0,
        plane: Plane::Xy,
    };
    let path = [
        mv(
            [0.0, -5.0, 0.0],
            [0.0, 0.0, 0.0],
            None,
            Comp::Start(CompSide::Right, 2.0),
        ),
        mv([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], None, on),
        mv([10.0, 0.0, 0.0], [10.0, 0.0, -1.0], None, on),
        mv([10.0, 0.0, -1.0], [20.0, 10.0, -1.0], Some(arc), on),
        mv(
            [20.0, 10.0, -1.0],
            [30.0, 10.0, -1.0],
            None,
            Comp::Cancel(CompSide::Right, 2.0),
        ),
    ];
    let out = compensate(&path).unwrap();
    assert_pt(out[0].end, [0.0, -2.0, 0.0]);
    assert_pt(out[1].end, [10.0, -2.0, 0.0]);
    assert_pt(out[2].start, [10.0, -2.0, 0.0]);
    assert_pt(out[2].end, [10.0, -2.0, -1.0]);
    let a = out[3].arc.unwrap();
    assert_near(a.radius, 12.0);
    assert_near(a.sweep, PI / 2.0);
    assert_pt(out[3].end, [22.0, 10.0, -1.0]);
    assert_pt(out[4].end, [30.0, 10.0, -1.0]);
}

/// A line into a clockwise arc with G41 (D60, r 5): the path turns left, an inner corner.
/// The offset line is y = 5; the offset circle is the arc's (centre (13, -4), R 5) grown
/// to 10 (the left of a clockwise arc is its outside): they meet at x = 13 - sqrt(100 - 81)
/// (the root nearer the joint). The arc ends perpendicular to its end direction -Y, on its
/// left: (18 + 5, -4), and the cancel runs from there to (25, -4).
#[test]
fn line_to_arc_inner_corner() {
    let m = mill(
        "G90 G57 G0 X0 Y-5\nG43 H10 Z-1\nG41 D60 G1 X0 Y0 F100\nX10\nG2 X18 Y-4 I3 J-4\nG40 G1 X25\nM30\n",
    )
    .unwrap()
    .mill;
    let j = 13.0 - 19f64.sqrt();
    assert_pt(m[2].end, [j, 5.0, -1.0]);
    assert_pt(m[3].start, [j, 5.0, -1.0]);
    let a = m[3].arc.unwrap();
    assert_near(a.radius, 10.0);
    assert_pt(m[3].end, [23.0, -4.0, -1.0]);
    // Sweep: clockwise from the joint's angle about the centre to 0.
    assert_near(a.sweep, -(9f64).atan2(j - 13.0));
    assert_pt(m[4].end, [25.0, -4.0, -1.0]);
}
