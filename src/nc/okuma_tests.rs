//! Okuma OSP-P programs against hand derivations from the OSP-P200L programming manual
//! 5238-E (each test says which section and how its numbers were worked).

use super::*;
use crate::model::helix::LeadLaw;

fn run_with(text: &str, files: &[(&str, &str)]) -> Result<Toolpath, NcError> {
    let main = Source {
        name: "TEST.MIN".into(),
        text: text.into(),
    };
    let files: Vec<(String, String)> = files
        .iter()
        .map(|(n, t)| (n.to_string(), t.to_string()))
        .collect();
    let loader = move |n: &str| {
        files.iter().find(|f| f.0 == n).map(|f| Source {
            name: f.0.clone(),
            text: f.1.clone(),
        })
    };
    interpret_with(&main, Dialect::Okuma, &loader, &Options::default())
}

fn run(text: &str) -> Toolpath {
    run_with(text, &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// (kind, start, end, lead) of every move.
type Row = (MoveKind, (f64, f64), (f64, f64), Option<f64>);

fn rows(t: &Toolpath) -> Vec<Row> {
    t.moves
        .iter()
        .map(|m| (m.kind, (m.x_start, m.z_start), (m.x_dia, m.z), m.lead))
        .collect()
}

fn close(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9
}

/// The moves of one fixed-cycle pass from `s` at diameter `x` to `z` (5238-E P-97's figure:
/// in at rapid, the thread, out in X, back in Z), written out by hand.
fn g33_pass(s: (f64, f64), x: f64, z: f64, lead: f64) -> Vec<Row> {
    vec![
        (MoveKind::Rapid, s, (x, s.1), None),
        (MoveKind::Thread, (x, s.1), (x, z), Some(lead)),
        (MoveKind::Rapid, (x, z), (s.0, z), None),
        (MoveKind::Rapid, (s.0, z), s, None),
    ]
}

fn same(got: &[Row], want: &[Row]) {
    assert_eq!(got.len(), want.len(), "{got:?}\n{want:?}");
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.0, w.0, "{g:?} {w:?}");
        assert!(close(g.1, w.1) && close(g.2, w.2), "{g:?} {w:?}");
        match (g.3, w.3) {
            (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "{g:?} {w:?}"),
            (None, None) => {}
            _ => panic!("{g:?} {w:?}"),
        }
    }
}

#[test]
fn g33_passes_repeat_modally_from_the_start_point() {
    // Each block with X is one more pass of the same cycle from the start point (34, 5).
    let t = run("$THRD.MIN%\nO1000\nG00 X34 Z5 S500 M03\nG33 X29.4 Z-30 F2\nX28.9\nX28.5\nG00 X100 Z100\nM02\n%\n");
    let s = (34.0, 5.0);
    let mut want = vec![(MoveKind::Rapid, (0.0, 0.0), s, None)];
    for x in [29.4, 28.9, 28.5] {
        want.extend(g33_pass(s, x, -30.0, 2.0));
    }
    want.push((MoveKind::Rapid, s, (100.0, 100.0), None));
    same(&rows(&t), &want);
    // The passes are a cycle's, synchronised at angle 0 (no C).
    assert!(t
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .all(|m| m.cycle && m.sync_angle_deg == Some(0.0)));
}

#[test]
fn g33_words_j_k_c_i_and_a_change_the_pass_as_the_manual_says() {
    // Cases: (words, pass start, pass end, lead, sync angle), each derived from P-97:
    // F/J is the lead; K shifts the start in Z (the tool goes to Z first); C the phase; I the
    // radius at the start minus at the end; A the taper angle (I = -L tan A over the length).
    let t30 = 30f64.to_radians().tan() * 35.0;
    type Case<'a> = (&'a str, (f64, f64), (f64, f64), f64, f64);
    let cases: [Case; 5] = [
        ("G33 X29 Z-30 F6 J3", (29.0, 5.0), (29.0, -30.0), 2.0, 0.0),
        ("G33 X29 Z-30 F2 K-1", (29.0, 4.0), (29.0, -30.0), 2.0, 0.0),
        (
            "G33 X29 Z-30 F2 C180",
            (29.0, 5.0),
            (29.0, -30.0),
            2.0,
            180.0,
        ),
        (
            "G33 X29 Z-30 F2 I-1.5",
            (26.0, 5.0),
            (29.0, -30.0),
            2.0,
            0.0,
        ),
        (
            "G33 X29 Z-30 F2 A30",
            (29.0 - 2.0 * t30, 5.0),
            (29.0, -30.0),
            2.0,
            0.0,
        ),
    ];
    for (words, a, b, lead, angle) in cases {
        let t = run(&format!("G00 X34 Z5\n{words}\nM02\n"));
        let th: Vec<&Move> = t
            .moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect();
        assert_eq!(th.len(), 1, "{words}");
        let m = th[0];
        assert!(
            close((m.x_start, m.z_start), a) && close((m.x_dia, m.z), b),
            "{words}: {m:?}"
        );
        assert_eq!(m.lead, Some(lead), "{words}");
        assert_eq!(m.sync_angle_deg, Some(angle), "{words}");
        assert!(
            close(
                (t.moves.last().unwrap().x_dia, t.moves.last().unwrap().z),
                (34.0, 5.0)
            ),
            "{words}"
        );
    }
}

#[test]
fn g34_reproduces_the_manuals_variable_lead_example() {
    // 5238-E (controllers.md 1.1): D = n (F0 + n E / 2); the example 42 = 7 (F0 + 7 x 1/2)
    // gives F0 = 2.5 with E = 1: 42 mm of travel take 7 revolutions and end at lead 9.5.
    let t = run("G00 X40 Z0\nG34 X36 Z-42 F2.5 E1\nM02\n");
    let m = t.moves.iter().find(|m| m.kind == MoveKind::Thread).unwrap();
    assert_eq!((m.lead, m.lead_change), (Some(2.5), Some(1.0)));
    let law = LeadLaw { f: 2.5, k: 1.0 };
    let revs = law.revs_at(42.0).unwrap();
    assert!((revs - 7.0).abs() < 1e-12, "{revs}");
    assert!((law.lead(revs) - 9.5).abs() < 1e-12);
    // A decreasing lead that reaches zero inside the move is the control's alarm.
    let e = run_with("G00 X40 Z0\nG34 X36 Z-42 F2 E-0.1\nM02\n", &[]).unwrap_err();
    assert!(e.message.contains("reaches zero"), "{e}");
    assert_eq!(e.line, 2);
    // E on G33 is G34's word.
    let e = run_with("G00 X40 Z0\nG33 X36 Z-42 F2 E1\nM02\n", &[]).unwrap_err();
    assert!(e.message.contains("G34"), "{e}");
}

#[test]
fn g71_compound_cycle_cuts_the_manuals_depth_schedules() {
    // M30x2 external from the start (34, 5): root X27.54 (H = 2.46 on the diameter),
    // 60 deg tool (B60) along the flank (M32). Cutting points c (diameters below the crest
    // X30), each pass at X = 30 - c, shifted +c/2 tan 30 deg in Z (towards the start).
    // Pattern 3 (M75), D0.8 U0.1: D^2 = 0.64 >= 2.46^2 - 2.36^2 = 0.482: sqrt(n) 0.8 =
    // 0.8, 1.131371, 1.385641, 1.6, 1.788854, 1.959592, 2.116601, 2.262742, n = 9: 2.4 ->
    // 2.36 (H - U), then the finish at 2.46.
    // Pattern 1 (M73), D0.5 no U: 0.5, 1.0, 1.5, 2.0, then 2.46.
    let t30 = 30f64.to_radians().tan();
    let cases: [(&str, Vec<f64>); 2] = [
        (
            "M32 M75\nG71 X27.54 Z-30 B60 D0.8 U0.1 H2.46 F2",
            vec![
                0.8, 1.131371, 1.385641, 1.6, 1.788854, 1.959592, 2.116601, 2.262742, 2.36, 2.46,
            ],
        ),
        (
            "G71 X27.54 Z-30 B60 D0.5 H2.46 F2 M32 M73",
            vec![0.5, 1.0, 1.5, 2.0, 2.46],
        ),
    ];
    for (block, cuts) in cases {
        let t = run(&format!("G00 X34 Z5\n{block}\nM02\n"));
        let th: Vec<&Move> = t
            .moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect();
        assert_eq!(th.len(), cuts.len(), "{block}");
        for (m, c) in th.iter().zip(&cuts) {
            let dz = c / 2.0 * t30;
            assert!((m.x_start - (30.0 - c)).abs() < 5e-7, "{block}: {m:?} {c}");
            assert!((m.z_start - (5.0 + dz)).abs() < 5e-7, "{block}: {m:?}");
            assert!((m.z - (-30.0 + dz)).abs() < 5e-7, "{block}: {m:?}");
            assert_eq!(m.lead, Some(2.0));
            assert!(m.cycle);
        }
        let last = t.moves.last().unwrap();
        assert!(close((last.x_dia, last.z), (34.0, 5.0)));
    }
    // Q2: each cutting point twice, at 0 and 180 deg.
    let t = run("G00 X34 Z5\nG71 X27.54 Z-30 B0 D0.5 H2.46 F4 Q2 M73\nM02\n");
    let angles: Vec<f64> = t.moves.iter().filter_map(|m| m.sync_angle_deg).collect();
    assert_eq!(angles.len(), 10);
    assert!(angles.chunks(2).all(|p| p == [0.0, 180.0]), "{angles:?}");
}

#[test]
fn variables_if_goto_and_calls_run_as_written() {
    // A loop over VC1 (P-? user task: IF [..] N.. jumps when the condition holds): passes at
    // 29.4, 29.0, 28.6, 28.2 (the loop stops when VC1 = 27.8 < 28.2).
    let t = run(
        "VC1=29.4\nG00 X34 Z5\nN10 G33 X=VC1 Z-30 F2\nVC1=VC1-0.4\nIF [VC1 GE 28.2] N10\nGOTO NEND\nG00 X0 Z0\nNEND M02\n",
    );
    let xs: Vec<f64> = t
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .map(|m| m.x_dia)
        .collect();
    let want = [29.4, 29.0, 28.6, 28.2];
    assert_eq!(xs.len(), 4, "{xs:?}");
    assert!(
        xs.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-9),
        "{xs:?}"
    );
    // CALL with Q repeats and a local argument; RTS returns; a subprogram in its .SSB file.
    let sub = "$SUBS.SSB%\nOPASS\nG33 X=DIA Z-20 F1.5\nDIA=DIA-0.3\nVC2=VC2+1\nRTS\n%\n";
    let t = run_with(
        "$MAIN.MIN%\nO1\nG00 X24 Z3\nCALL OPASS Q3 DIA=21.6\nG00 X=VC2*10 Z50\nM02\n",
        &[("OPASS.SSB", sub)],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let xs: Vec<f64> = t
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .map(|m| m.x_dia)
        .collect();
    // The argument is set once; each repeat continues with the sub's own DIA.
    assert_eq!(xs.len(), 3);
    assert!(
        xs.iter()
            .zip([21.6, 21.3, 21.0])
            .all(|(a, b)| (a - b).abs() < 1e-9),
        "{xs:?}"
    );
    let last = t.moves.last().unwrap();
    assert!(close((last.x_dia, last.z), (30.0, 50.0)), "{last:?}");
    assert_eq!(t.moves[1].file, "OPASS.SSB");
}

#[test]
fn arcs_by_radius_l_and_centre_ik() {
    // A quarter circle of radius 5 from (20, 0) to (30, -5): in the (z, radius) plane from
    // (0, 10) to (-5, 15). Clockwise seen with Z right and X up, the minor arc's centre is
    // (0, 15): the start straight below it (-90 deg), the end left of it (-180 deg), a
    // quarter turn clockwise. So the centre is at z 0, diameter 30; as I/K from the start:
    // I5 (radius) K0 -- worked by hand.
    for block in ["G02 X30 Z-5 L5 F0.2", "G02 X30 Z-5 I5 K0 F0.2"] {
        let t = run(&format!("G00 X20 Z0\nG01 Z0 F0.2\n{block}\nM02\n"));
        let a = t.moves.last().unwrap();
        assert_eq!(a.kind, MoveKind::Arc, "{block}");
        let g = a.arc.unwrap();
        assert!(
            (g.x_centre_dia - 30.0).abs() < 1e-9 && g.z_centre.abs() < 1e-9,
            "{block}: {g:?}"
        );
        assert!(g.clockwise);
    }
}

#[test]
fn bad_programs_stop_at_their_line_and_column() {
    // (program, line, column, words of the message)
    let cases: [(&str, usize, usize, &str); 10] = [
        ("G00 X10\nG99 Z5\n", 2, 1, "G99 is not a G code"),
        ("G00 X10\n  G32 X10 Z5 F2\n", 2, 3, "face threads"),
        ("G00 X10\nG01 X5 Z0 F0.1 G85\n", 2, 16, "LAP"),
        ("G00 X10\nX\n", 2, 2, "expected a number after `X`"),
        ("G00 X10\nG00 X=[1+ Z5\n", 2, 13, "expected `]`"),
        ("G00 X=FOO\n", 1, 7, "local variable `FOO`"),
        ("GOTO N99\n", 1, 6, "no block N99"),
        ("G00 X30 Z5\nM23\nG33 X29 Z-30 F2 L2\n", 3, 17, "M23"),
        ("G00 X30 Z5\nCALL ONOPE\n", 2, 6, "ONOPE"),
        ("G00 X30 Z5\nG71 X27 Z-30 D0.2 H2.4 F2 M74\n", 2, 1, "M74"),
    ];
    for (text, line, col, msg) in cases {
        let e = run_with(text, &[]).expect_err(text);
        assert_eq!((e.line, e.col), (line, col), "{text}: {e}");
        assert!(e.message.contains(msg), "{text}: {e}");
        assert!(
            !e.message.contains("Some(") && !e.message.contains("None"),
            "{e}"
        );
    }
    // Every static problem of the file at once.
    let e = run_with("G99\nG00 X1\nG98\n", &[]).unwrap_err();
    assert_eq!(e.all().len(), 2);
    // An unknown M code is a warning (skipped) naming it, at its column.
    let t = run("G00 X30 Z5 M123\nM02\n");
    assert_eq!(t.warnings.len(), 1);
    assert_eq!((t.warnings[0].line, t.warnings[0].col), (1, 12));
    assert!(t.warnings[0].message.contains("M123"));
    // A word the block does not read is a warning at its column; U/W outside G71 an error.
    let t = run("G00 X30 Z5 P3\nM02\n");
    assert_eq!((t.warnings[0].line, t.warnings[0].col), (1, 12));
    let e = run_with("G00 X30 Z5\nG01 U-2 F0.1\n", &[]).unwrap_err();
    assert_eq!((e.line, e.col), (2, 5));
    assert!(e.message.contains("G91"), "{e}");
}

/// Driven-tool functions (M option, 5238-E section 9 "contour generation" and the M-tool
/// spindle fixed cycles G181-G189): no turning move is made of their blocks, the modal
/// cycle's later hole positions (`C90`) and its cancel G180 included; the threading after
/// them runs. A warning names the code.
#[test]
fn driven_tool_functions_make_no_turning_move() {
    let text = "$T.MIN%\nG00 X84 Z5\nM110\nG94\nG00 X50 Z5 C0\nG181 X50 Z-8 C0 K3 F100 E0.3\nC90\nC180\nG180\nG101 X40 Z-5 C30 F200\nG95 G00 X30 Z5\nG33 X28.5 Z-20 F1.5\nG00 X100 Z50\nM02\n";
    let t = run(text);
    let xz: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
    // X84 Z5, X50 Z5, then the G33 pass from (30, 5) (in to X28.5, the thread to Z-20, out
    // to X30, back to Z5) and the last rapid: nothing of G181 (Z-8) or G101 (X40 Z-5).
    let want = [
        (84.0, 5.0),
        (50.0, 5.0),
        (30.0, 5.0),
        (28.5, 5.0),
        (28.5, -20.0),
        (30.0, -20.0),
        (30.0, 5.0),
        (100.0, 50.0),
    ];
    assert_eq!(xz, want);
    assert_eq!(
        t.moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .count(),
        1
    );
    let w: Vec<&str> = t.warnings.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(
        w.iter().filter(|m| m.contains("driven tool")).count(),
        3,
        "{w:?}"
    );
    // Strict, each is an error.
    let strict = Options {
        strict: true,
        ..Options::default()
    };
    let main = Source {
        name: "T.MIN".into(),
        text: text.into(),
    };
    assert!(interpret_with(&main, Dialect::Okuma, &|_| None, &strict).is_err());
}
