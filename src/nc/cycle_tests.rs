//! Unit tests of the threading-cycle tapers and chamfers (G92, G76), arcs, work offsets,
//! `M99 P`, G65 argument specification II and block skip. Every expected number is derived
//! by hand in the comments, not by the code under test.

use super::*;

fn run_with(text: &str, dialect: Dialect, settings: &Settings) -> Result<Vec<Move>, NcError> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        settings: settings.clone(),
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts).map(|t| t.moves)
}

fn run(text: &str, dialect: Dialect) -> Result<Vec<Move>, NcError> {
    run_with(text, dialect, &Settings::in_mm())
}

fn chamfer(leads: f64) -> Settings {
    Settings {
        thread_chamfer: leads,
        ..Settings::in_mm()
    }
}

/// (kind, x_start, z_start, x_end, z_end) of every move.
fn path(moves: &[Move]) -> Vec<(MoveKind, f64, f64, f64, f64)> {
    moves
        .iter()
        .map(|m| (m.kind, m.x_start, m.z_start, m.x_dia, m.z))
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

fn assert_path(got: &[(MoveKind, f64, f64, f64, f64)], want: &[(MoveKind, f64, f64, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.0 == w.0 && close(g.1, w.1) && close(g.2, w.2) && close(g.3, w.3) && close(g.4, w.4),
            "move {i}: got {g:?}, want {w:?}"
        );
    }
}

use MoveKind::{Arc as A, Rapid as R, Thread as T};

/// G92 taper: R = radius at the start minus radius at the end, so the cycle from (X30, Z3)
/// with X24 rapids to X24 + 2(-0.5) = X23, threads to (X24, Z-20), rapids out to
/// X30 and back to Z3. R, Z and F are modal: `X23.5` starts at X22.5.
#[test]
fn g92_taper_r_is_start_minus_end_radius_and_modal() {
    let moves = run(
        "G0 X30 Z3\nG92 X24 Z-20 R-0.5 F2\nX23.5\nG0 X40\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    assert_path(
        &path(&moves)[1..],
        &[
            (R, 30.0, 3.0, 23.0, 3.0),
            (T, 23.0, 3.0, 24.0, -20.0),
            (R, 24.0, -20.0, 30.0, -20.0),
            (R, 30.0, -20.0, 30.0, 3.0),
            (R, 30.0, 3.0, 22.5, 3.0),
            (T, 22.5, 3.0, 23.5, -20.0),
            (R, 23.5, -20.0, 30.0, -20.0),
            (R, 30.0, -20.0, 30.0, 3.0),
            (R, 30.0, 3.0, 40.0, 3.0),
        ],
    );
    assert_eq!(moves[2].lead, Some(2.0));
    // With U/W (incremental from the start point): U-6 W-23 is the same cycle.
    let inc = run("G0 X30 Z3\nG92 U-6 W-23 R-0.5 F2\nM30\n", Dialect::Fanuc).unwrap();
    assert_path(&path(&inc), &path(&moves)[..5]);
}

/// G92 chamfer of 1 lead (F2: 2 mm): the thread from (X24, Z3) stops 2 mm before Z-20, at
/// Z-18, and the pull-out goes 2 mm out in radius (45 deg) to (X28, Z-20). It continues the
/// spindle phase: 21 mm at 2 mm/rev is 10.5 rev after the start at Q90000 (90 deg), so it
/// starts at 90 + 10.5 x 360 = 3870 = 270 deg (mod 360). M24 turns it off, M23 on again
/// (10.5 rev after 0 deg: 180 deg).
#[test]
fn g92_chamfer_is_a_chained_45_degree_thread_move() {
    let moves = run_with(
        "G0 X30 Z3\nG92 X24 Z-20 F2 Q90000\nM24\nX23.5\nM23\nX23\nM30\n",
        Dialect::Fanuc,
        &chamfer(1.0),
    )
    .unwrap();
    let moves = &moves[1..];
    assert_path(
        &path(moves),
        &[
            (R, 30.0, 3.0, 24.0, 3.0),
            (T, 24.0, 3.0, 24.0, -18.0),
            (T, 24.0, -18.0, 28.0, -20.0),
            (R, 28.0, -20.0, 30.0, -20.0),
            (R, 30.0, -20.0, 30.0, 3.0),
            (R, 30.0, 3.0, 23.5, 3.0),
            (T, 23.5, 3.0, 23.5, -20.0),
            (R, 23.5, -20.0, 30.0, -20.0),
            (R, 30.0, -20.0, 30.0, 3.0),
            (R, 30.0, 3.0, 23.0, 3.0),
            (T, 23.0, 3.0, 23.0, -18.0),
            (T, 23.0, -18.0, 27.0, -20.0),
            (R, 27.0, -20.0, 30.0, -20.0),
            (R, 30.0, -20.0, 30.0, 3.0),
        ],
    );
    let angle = |i: usize| moves[i].sync_angle_deg.unwrap();
    assert!(close(angle(1), 90.0) && close(angle(2), 270.0));
    // Only the pull-outs continue a thread without a re-sync.
    let chained: Vec<usize> = (0..moves.len()).filter(|&i| moves[i].chained).collect();
    assert_eq!(chained, vec![2, 11]);
    assert!(close(angle(10), 0.0) && close(angle(11), 180.0));
    assert_eq!(
        (moves[2].lead, moves[2].lead_change),
        (Some(2.0), Some(0.0))
    );
    // Without a chamfer setting there is none, M23 or not.
    let plain = run("G0 X30 Z3\nM23\nG92 X24 Z-20 F2\nM30\n", Dialect::Fanuc).unwrap();
    assert_eq!(plain.len(), 5);
    // A chamfer as long as the thread is an error naming the Z word: Z1 to Z-1 is 2 mm.
    let e = run_with("G0 X30 Z1\nG92 X24 Z-1 F2\n", Dialect::Fanuc, &chamfer(1.0)).unwrap_err();
    assert_eq!((e.line, e.col), (2, 9), "{e}");
    assert!(e.message.contains("chamfer"), "{e}");
}

/// G76 taper and chamfer. Block 1 P011060: m = 1, rr = 10 (1.0 lead = 2 mm), a = 60;
/// Q100: dmin = 0.1; R0.1: d = 0.1. Block 2: root X24 at Z-20, i = R-0.5, k = 1.0,
/// dd = 0.6, F2, from (X30, Z5).
/// Depths: 0.6; max(0.6 sqrt2 = 0.848528, 0.7) = 0.848528; n = 3 gives
/// max(1.039230, 0.948528) >= k - d = 0.9, so 0.9; then m = 1 pass at 1.0.
/// Pass end X = 24 + 2(k - d_n): 24.8, 24.302944, 24.2, 24.0; start X = end X + 2i = end - 1.
/// Flank infeed toward the chuck: both ends shift by +(k - d_n) tan30.
/// Chamfer: the Z travel is 25, so the thread splits 2 mm before the end, 23/25 of the way:
/// X = (x - 1) + 0.92 = x - 0.08; the pull-out ends at (x - 0.08 + 4, ze); 23 mm = 11.5 rev,
/// so its spindle angle is 180 deg.
#[test]
fn g76_taper_and_chamfer_passes_by_hand() {
    let moves = run(
        "G0 X30 Z5\nG76 P011060 Q100 R0.1\nG76 X24 Z-20 R-0.5 P1000 Q600 F2\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    let t: Vec<&Move> = moves.iter().filter(|m| m.kind == T).collect();
    let tan30 = 30f64.to_radians().tan();
    let depths = [0.6, 0.6 * 2f64.sqrt(), 0.9, 1.0];
    assert_eq!(t.len(), 2 * depths.len());
    for (n, d) in depths.iter().enumerate() {
        let back = 1.0 - d;
        let x = 24.0 + 2.0 * back;
        let shift = back * tan30;
        let (zs, ze) = (5.0 + shift, -20.0 + shift);
        let (main, out) = (t[2 * n], t[2 * n + 1]);
        let got = [
            (main.x_start, main.z_start, main.x_dia, main.z),
            (out.x_start, out.z_start, out.x_dia, out.z),
        ];
        let want = [
            (x - 1.0, zs, x - 0.08, ze + 2.0),
            (x - 0.08, ze + 2.0, x + 3.92, ze),
        ];
        for (g, w) in got.iter().zip(&want) {
            assert!(
                close(g.0, w.0) && close(g.1, w.1) && close(g.2, w.2) && close(g.3, w.3),
                "pass {n}: {g:?} vs {w:?}"
            );
        }
        assert!(close(main.sync_angle_deg.unwrap(), 0.0));
        assert!(close(out.sync_angle_deg.unwrap(), 180.0));
    }
    // Every pass returns to the start point before the next.
    let last = moves.last().unwrap();
    assert_eq!((last.kind, last.x_dia, last.z), (R, 30.0, 5.0));
    // rr = 00 clears the chamfer that the job set (parameter 5130 is overwritten).
    let none = run_with(
        "G0 X30 Z5\nG76 P010060 Q100 R0.1\nG76 X24 Z-20 P1000 Q600 F2\nM30\n",
        Dialect::Fanuc,
        &chamfer(1.0),
    )
    .unwrap();
    assert_eq!(none.iter().filter(|m| m.kind == T).count(), 4);
    // ... and G76's rr = 05 (0.5 lead = 1 mm) is used by a following G92: thread to Z-19,
    // pull-out to (X26, Z-20).
    let g92 = run(
        "G76 P010560 Q100 R0.1\nG0 X30 Z3\nG92 X24 Z-20 F2\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    assert_path(
        &path(&g92)[2..4],
        &[(T, 24.0, 3.0, 24.0, -19.0), (T, 24.0, -19.0, 26.0, -20.0)],
    );
}

/// The textbook convex quarter round from the face centre: G03 X20 Z-10 R10 from (X0, Z0)
/// has its centre on the axis at Z-10 (start vector (z, r) = (10, 0) at 0 deg, end (0, 10)
/// at 90 deg: counter-clockwise). I0 K-10 names the same centre. The concave fillet G02 X40
/// Z-20 R10 from (X20, Z-10) has its centre at (r 20, z -10) (start at -90 deg, end at
/// 180 deg, going down: clockwise), I10 K0; R-10 takes the other centre (r 10, z -20).
#[test]
fn arcs_by_radius_and_by_centre_agree() {
    let moves = run(
        "G0 X0 Z0 F0.2\nG03 X20 Z-10 R10\nG0 X0 Z0\nG03 X20 Z-10 I0 K-10\n\
         G02 X40 Z-20 R10\nG0 X20 Z-10\nG02 X40 Z-20 I10 K0\nG0 X20 Z-10\nG2 X40 Z-20 R-10\n\
         G1 W-5\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    let arcs: Vec<(f64, f64, f64, f64, bool)> = moves
        .iter()
        .filter(|m| m.kind == A)
        .map(|m| {
            let a = m.arc.unwrap();
            (m.x_dia, m.z, a.x_centre_dia, a.z_centre, a.clockwise)
        })
        .collect();
    let want = [
        (20.0, -10.0, 0.0, -10.0, false),
        (20.0, -10.0, 0.0, -10.0, false),
        (40.0, -20.0, 40.0, -10.0, true),
        (40.0, -20.0, 40.0, -10.0, true),
        (40.0, -20.0, 20.0, -20.0, true),
    ];
    assert_eq!(arcs.len(), want.len());
    for (g, w) in arcs.iter().zip(&want) {
        assert!(
            close(g.0, w.0) && close(g.1, w.1) && close(g.2, w.2) && close(g.3, w.3) && g.4 == w.4,
            "{g:?} vs {w:?}"
        );
    }
    // The position after an arc is its end: W-5 runs from (X40, Z-20) to Z-25.
    let last = moves.last().unwrap();
    assert_eq!(
        (last.kind, last.x_start, last.z_start, last.z),
        (MoveKind::Feed, 40.0, -20.0, -25.0)
    );
    assert_eq!(
        to_csv(&moves).lines().nth(2).unwrap().split(',').nth(2),
        Some("arc")
    );
}

/// An end point off the circle: centre (z -10.01, r 0) is 10.01 from the start but
/// hypot(0.01, 10) = 10.000005 from the end, 0.01 > 0.002 apart: an error at the I word
/// (column 14). 0.001 off is accepted. A chord of hypot(30, 20) = 36.06 with R10 is
/// longer than the diameter 20: an error at R (column 14).
#[test]
fn arc_end_off_the_circle_is_an_error_at_line_and_column() {
    let e = run("G0 X0 Z0 F0.2\nG03 X20 Z-10 I0 K-10.01\n", Dialect::Fanuc).unwrap_err();
    assert_eq!((e.line, e.col), (2, 14), "{e}");
    assert!(e.message.contains("off the circle"), "{e}");
    assert!(e.to_string().contains("\n  --> T.NC:2:14\n"), "{e}");
    run("G0 X0 Z0 F0.2\nG03 X20 Z-10 I0 K-10.001\n", Dialect::Fanuc).unwrap();
    let e = run("G0 X0 Z0 F0.2\nG02 X40 Z-30 R10\n", Dialect::Fanuc).unwrap_err();
    assert_eq!((e.line, e.col), (2, 14), "{e}");
    let e = run("G0 X0 Z0 F0.2\nG02 X40 Z-30\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("needs R"), "{e}");
}

/// G55 with the offset (X 1 as a diameter, Z -12.5): absolute X/Z shift by exactly the
/// offset; incremental W does not. G76's X/Z shift the same way.
#[test]
fn work_offsets_shift_absolute_coordinates() {
    let mut s = Settings::in_mm();
    s.work_offsets[1] = (1.0, -12.5);
    let g32 = "G0 X24 Z5\nG32 Z-20 F2\nG0 W-1\nM30\n";
    let base = path(&run_with(g32, Dialect::Fanuc, &s).unwrap());
    let g55 = path(&run_with(&format!("G55\n{g32}"), Dialect::Fanuc, &s).unwrap());
    assert_path(
        &base,
        &[
            (R, 0.0, 0.0, 24.0, 5.0),
            (T, 24.0, 5.0, 24.0, -20.0),
            (R, 24.0, -20.0, 24.0, -21.0),
        ],
    );
    assert_path(
        &g55,
        &[
            (R, 0.0, 0.0, 25.0, -7.5),
            (T, 25.0, -7.5, 25.0, -32.5),
            (R, 25.0, -32.5, 25.0, -33.5),
        ],
    );
    let g76 = "G0 X30 Z5\nG76 P010060 Q100 R0.1\nG76 X24 Z-20 P1000 Q600 F2\nM30\n";
    let a = run_with(g76, Dialect::Fanuc, &s).unwrap();
    // The start point shifts with the offset too: every pass shifts by (1, -12.5).
    let b = run_with(&format!("G55\n{g76}"), Dialect::Fanuc, &s).unwrap();
    let ta: Vec<&Move> = a.iter().filter(|m| m.kind == T).collect();
    let tb: Vec<&Move> = b.iter().filter(|m| m.kind == T).collect();
    assert_eq!(ta.len(), tb.len());
    for (p, q) in ta.iter().zip(&tb) {
        assert!(
            close(q.x_dia, p.x_dia + 1.0) && close(q.z, p.z - 12.5),
            "{p:?} {q:?}"
        );
        assert!(close(q.x_start, p.x_start + 1.0) && close(q.z_start, p.z_start - 12.5));
    }
}

/// `M99 P20` returns to the caller's N20, past `G0 X1 Z1`; a missing N is an error at the
/// M99 block; in the main program M99 (with or without P) ends the run.
#[test]
fn m99_p_returns_to_a_sequence_number() {
    let text = "M98 P1000\nG0 X1 Z1\nN20 G0 X2 Z2\nM30\nO1000\nG0 X9 Z9\nM99 P20\n";
    let moves = run(text, Dialect::Fanuc).unwrap();
    let ends: Vec<(f64, f64)> = moves.iter().map(|m| (m.x_dia, m.z)).collect();
    assert_eq!(ends, vec![(9.0, 9.0), (2.0, 2.0)]);
    // Two runs of the subprogram, then the jump.
    let moves = run(&text.replace("P1000", "P21000"), Dialect::Fanuc).unwrap();
    assert_eq!(moves.len(), 3);
    let e = run(&text.replace("M99 P20", "M99 P30"), Dialect::Fanuc).unwrap_err();
    assert_eq!((e.file.as_str(), e.line), ("O1000", 7), "{e}");
    assert!(e.message.contains("no block N30"), "{e}");
    let moves = run("G0 X1 Z1\nM99 P1\nN1 G0 X2 Z2\n", Dialect::Fanuc).unwrap();
    assert_eq!(moves.len(), 1);
}

/// Specification II: the n-th I, J, K set #(3n+1), #(3n+2), #(3n+3). FANUC's example
/// `A1 B2 I-3 I4 D5`: #1 = 1, #2 = 2, #4 = -3, the second I is #7 = 4, then D (#7 in
/// specification I) overwrites it with 5. Ten full sets fill #4..#33 with 1..30, so #16 =
/// 13 and #17 = 14. The fifth J is #17 like Q: the later word wins.
#[test]
fn g65_argument_specification_ii() {
    let text = "G65 P9000 A1 B2 I-3 I4 D5\nM30\nO9000\nG0 X#1 Z#2\nG0 X#4 Z#7\nM99\n";
    let ends: Vec<(f64, f64)> = run(text, Dialect::Fanuc)
        .unwrap()
        .iter()
        .map(|m| (m.x_dia, m.z))
        .collect();
    assert_eq!(ends, vec![(1.0, 2.0), (-3.0, 5.0)]);
    let sets: String = (0..10)
        .map(|n| format!(" I{} J{} K{}", 3 * n + 1, 3 * n + 2, 3 * n + 3))
        .collect();
    let text = format!("G65 P9001{sets}\nM30\nO9001\nG0 X#4 Z#33\nG0 X#16 Z#17\nM99\n");
    let ends: Vec<(f64, f64)> = run(&text, Dialect::Fanuc)
        .unwrap()
        .iter()
        .map(|m| (m.x_dia, m.z))
        .collect();
    assert_eq!(ends, vec![(1.0, 30.0), (13.0, 14.0)]);
    let e = run(
        &format!("G65 P9001{sets} I31\nM30\nO9001\nM99\n"),
        Dialect::Fanuc,
    )
    .unwrap_err();
    assert!(e.message.contains("more than 10 `I`"), "{e}");
    let q = |args: &str| {
        run(
            &format!("G65 P9002 {args}\nM30\nO9002\nG0 X#17 Z0\nM99\n"),
            Dialect::Fanuc,
        )
        .unwrap()[0]
            .x_dia
    };
    assert_eq!(q("Q1 J0 J0 J0 J0 J9"), 9.0);
    assert_eq!(q("J0 J0 J0 J0 J9 Q1"), 1.0);
    assert_eq!(q("Q0"), 0.0);
}

/// `G65 P L3 A10`: the arguments are set once, so the macro's `#1=#1+1` counts on over the
/// repetitions: X11, X12, X13.
#[test]
fn g65_l_repeats_keep_the_level() {
    let text = "G65 P9003 L3 A10\nM30\nO9003\n#1=#1+1\nG0 X#1 Z0\nM99\n";
    let x: Vec<f64> = run(text, Dialect::Fanuc)
        .unwrap()
        .iter()
        .map(|m| m.x_dia)
        .collect();
    assert_eq!(x, vec![11.0, 12.0, 13.0]);
}

/// Block skip on (default) leaves out `/` blocks; off runs them, `/1` too.
#[test]
fn block_skip_switch() {
    let text = "G0 X1 Z1\n/G0 X2 Z2\n/1 G0 X3 Z3\nM30\n";
    assert_eq!(run(text, Dialect::Fanuc).unwrap().len(), 1);
    let off = Settings {
        block_skip: false,
        ..Settings::in_mm()
    };
    let x: Vec<f64> = run_with(text, Dialect::Fanuc, &off)
        .unwrap()
        .iter()
        .map(|m| m.x_dia)
        .collect();
    assert_eq!(x, vec![1.0, 2.0, 3.0]);
}

/// G96/G97 and G98/G99 are accepted; thread leads stay per revolution under G98.
#[test]
fn lathe_modes_are_accepted() {
    let moves = run(
        "G96 S200\nG97 S800\nG98\nG0 X20 Z2\nG32 Z-10 F1.5\nG99\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    assert_eq!(moves[1].lead, Some(1.5));
}

/// G28 U0 W0 from (X30, Z5) with the reference point at (X200, Z150): the intermediate
/// point is the current one, then one rapid home. `G28 X40` goes via X40 (same Z) and homes
/// X only: (X40, Z5) then (X200, Z5). Without a reference point G28 goes to the machine zero.
#[test]
fn g28_returns_via_the_intermediate_point() {
    let s = Settings {
        reference_point: Some((200.0, 150.0)),
        ..Settings::in_mm()
    };
    let moves = run_with(
        "G0 X30 Z5\nG28 U0 W0\nG0 X30 Z5\nG28 X40\nG0 W-1\n",
        Dialect::Fanuc,
        &s,
    )
    .unwrap();
    assert_path(
        &path(&moves)[1..],
        &[
            (R, 30.0, 5.0, 200.0, 150.0),
            (R, 200.0, 150.0, 30.0, 5.0),
            (R, 30.0, 5.0, 40.0, 5.0),
            (R, 40.0, 5.0, 200.0, 5.0),
            (R, 200.0, 5.0, 200.0, 4.0),
        ],
    );
    // Without a reference point in the job: the machine zero.
    let moves = run("G0 X30 Z5\nG28 U0 W0\n", Dialect::Fanuc).unwrap();
    assert_eq!((moves[1].x_dia, moves[1].z), (0.0, 0.0));
}

/// The one-block G74/G75 of FANUC 0T and Haas (`G75 X Z I K D F`; Haas lathe manual "G75
/// O.D./I.D. grooving cycle", "G74 end face grooving cycle"): I is the X amount and K the Z
/// amount, as the two-block form's P and Q (G75: I the peck, K the step; G74: K the peck, I
/// the step), in program units with a point. The oracle is the two-block form with the same
/// amounts in the least increment (0.001 mm), tested against the manual's figure above:
/// the same moves, over a table of blocks. Without a peck word the plunge is one feed to
/// the bottom (`G75 X0. I..` a cut-off in pecks, Haas shop programs).
#[test]
fn one_block_g74_g75_are_the_two_block_cycles() {
    let standard = Settings::default();
    let cases = [
        (
            "G0 X52. Z-10.\n",
            "G75 X30. Z-20. I1.5 K3. F0.1",
            "G75 X30. Z-20. P1500 Q3000 F0.1",
        ),
        (
            "G0 X52. Z-10.\n",
            "G75 X30. I2. F0.1",
            "G75 X30. P2000 F0.1",
        ),
        (
            "G0 X1.5 Z-2.\n",
            "G75 X0. I0.127 F0.05",
            "G75 X0. P127 F0.05",
        ),
        ("G0 X0. Z2.\n", "G74 Z-20. K5. F0.1", "G74 Z-20. Q5000 F0.1"),
        (
            "G0 X40. Z2.\n",
            "G74 X20. Z-8. I2.5 K1. F0.1",
            "G74 X20. Z-8. P2500 Q1000 F0.1",
        ),
        (
            "G0 X40. Z2.\n",
            "G74 X20. Z-8. I2500 K1000 F0.1",
            "G74 X20. Z-8. P2500 Q1000 F0.1",
        ),
    ];
    for (head, one, two) in cases {
        let a = run_with(&format!("{head}{one}\nM30\n"), Dialect::Fanuc, &standard)
            .unwrap_or_else(|e| panic!("{one}: {e}"));
        let b = run_with(
            &format!("{head}G7{} R0\n{two}\nM30\n", &two[2..3]),
            Dialect::Fanuc,
            &standard,
        )
        .unwrap_or_else(|e| panic!("{two}: {e}"));
        assert_eq!(path(&a), path(&b), "{one}");
        assert!(a.len() > 2, "{one}");
    }
    // A G75 without I: one plunge to X0 (a cut-off), then back.
    let t = run_with(
        "G0 X20. Z-5.\nG75 X0. F0.05\nM30\n",
        Dialect::Fanuc,
        &standard,
    )
    .unwrap();
    let feeds: Vec<_> = t.iter().filter(|m| m.kind == MoveKind::Feed).collect();
    assert_eq!(feeds.len(), 1);
    assert!(close(feeds[0].x_dia, 0.0));
    // Both forms in one block: an error.
    let e = run_with(
        "G0 X20. Z-5.\nG75 X0. I1. P500 F0.05\n",
        Dialect::Fanuc,
        &standard,
    )
    .unwrap_err();
    assert!(e.message.contains("one block"), "{e}");
}

/// GSK G92 and G76 run-out J/K (980TDi manual, G92 and G76: "J: the movement in the short
/// axis in thread run-out ... K: the length in the long axis"; K omitted or 0 with J: K =
/// J; J0: none; modal): over the last K of Z the thread also rises |J| in radius towards the
/// start point, in one chained thread move, for external and internal threads, towards -Z
/// and +Z. By hand for each random case: the split at `z_end - dir K`, the end at
/// `x_end + side 2 |J|` (side: towards the start X), then the rapids home. The modal J/K
/// carry to the next X-only block; J0 cancels; G76's passes end alike.
#[test]
fn gsk_cycle_runout_j_k_rises_over_the_last_k() {
    let mut seed = 0x9e37_79b9_u64;
    let mut rnd = |lo: f64, hi: f64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        lo + (hi - lo) * (seed % 10_000) as f64 / 10_000.0
    };
    for case in 0..40 {
        let external = case % 2 == 0;
        let toward_minus = case % 4 < 2;
        let x_end = (rnd(20.0, 60.0) * 10.0).round() / 10.0;
        let x0 = if external { x_end + 6.0 } else { x_end - 6.0 };
        let z0: f64 = if toward_minus { 5.0 } else { -45.0 };
        let z_end: f64 = if toward_minus { -30.0 } else { -5.0 };
        let j = (rnd(0.5, 3.0) * 10.0).round() / 10.0;
        let k = if case % 3 == 0 {
            None
        } else {
            Some((rnd(1.0, 6.0) * 10.0).round() / 10.0)
        };
        let words = match k {
            Some(k) => format!("J{j:.1} K{k:.1}"),
            None => format!("J{j:.1}"),
        };
        let text = format!(
            "G0 X{x0:.1} Z{z0:.1}\nG92 X{x_end:.1} Z{z_end:.1} F2.0 {words}\nX{:.1}\nJ0 X{x_end:.1}\nG0 X{x0:.1}\nM30\n",
            if external { x_end + 0.4 } else { x_end - 0.4 }
        );
        let moves = run(&text, Dialect::Gsk980).unwrap_or_else(|e| panic!("{text}: {e}"));
        let kk = k.unwrap_or(j);
        let dir = (z_end - z0).signum();
        let side = if external { 1.0 } else { -1.0 };
        let split = z_end - dir * kk;
        for (pass, x) in [(0usize, x_end), (1, x_end + side * 0.4)] {
            let threads: Vec<&Move> = moves
                .iter()
                .filter(|m| m.kind == MoveKind::Thread && m.line == 2 + pass)
                .collect();
            assert_eq!(
                threads.len(),
                2,
                "case {case} pass {pass}: {text}\n{threads:?}"
            );
            assert!(
                close(threads[0].z, split) && close(threads[0].x_dia, x),
                "case {case}: {threads:?}"
            );
            assert!(
                close(threads[1].z, z_end) && close(threads[1].x_dia, x + side * 2.0 * j),
                "case {case}: {threads:?}"
            );
            assert!(
                threads[1].chained,
                "case {case}: the run-out continues the thread"
            );
        }
        // J0: the third pass runs straight to the end.
        let last: Vec<&Move> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread && m.line == 4)
            .collect();
        assert_eq!(last.len(), 1, "case {case}: {last:?}");
        assert!(close(last[0].z, z_end) && close(last[0].x_dia, x_end));
    }
    // G76 (two blocks): J/K in either block; every pass ends in the run-out. X80 Z10 to
    // X60.64 Z-62, J2 K3: each pass splits at Z-59 + its flank shift and rises 4 in diameter.
    for text in [
        "G0 X80 Z10\nG76 P020060 Q0.15 R0.1 J2 K3\nG76 X60.64 Z-62 P3.68 Q1.8 F6\nM30\n",
        "G0 X80 Z10\nG76 P020060 Q0.15 R0.1\nG76 X60.64 Z-62 P3.68 Q1.8 F6 J2 K3\nM30\n",
    ] {
        let moves = run(text, Dialect::Gsk980).unwrap();
        let threads: Vec<&Move> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect();
        assert!(
            threads.len() >= 8 && threads.len() % 2 == 0,
            "{text}: {threads:?}"
        );
        for p in threads.chunks(2) {
            assert!(close(p[0].z - p[1].z, 3.0), "{text}: {p:?}");
            assert!(close(p[1].x_dia - p[0].x_dia, 4.0), "{text}: {p:?}");
        }
        // The first pass at x_end + 2 (k - d1) = 60.64 + 2 (3.68 - 1.8) = 64.4.
        assert!(close(threads[0].x_dia, 64.4), "{:?}", threads[0]);
    }
    // FANUC's G76 reads K as the one-block form's thread height, as before.
    assert!(run(
        "G0 X80 Z10\nG76 X60.64 Z-62 K3.68 D1.8 F6\nM30\n",
        Dialect::Fanuc
    )
    .is_ok());
}
