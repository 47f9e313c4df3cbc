//! Issue 30: what a program relies on the machine for. The manuals' own G76 examples in
//! standard input and in the other increment system; the modes at power-on (inch, feed per
//! minute, radius or diameter X); the main program of a file with several; the warnings
//! when a program's numbers look read in the wrong units. Every expected number is derived
//! by hand in the comments.

use super::*;

fn run_with(text: &str, dialect: Dialect, settings: Settings) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "M.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        settings,
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts)
}

fn threads(t: &Toolpath) -> Vec<&Move> {
    t.moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-6
}

/// The G76 example of FANUC's 0i lathe operator's manual, written as the manual writes it,
/// for standard decimal-point input (the manual itself is not in the page store;
/// `controllers.md` 2.3 has its word list, issue 30 quotes the first block):
/// `G00 X80.0 Z130.0; G76 P011060 Q100 R200; G76 X60640 Z25000 P3680 Q1800 F6.0;`.
///
/// By hand: m = 1, r = 10 (a pull-out of 1.0 lead = 6 mm), a = 60; dmin = Q100 = 0.100,
/// d = R200 = 0.200 mm (it used to be read as 200 mm: one pass at full depth); X 60.640,
/// Z 25.000, k = P3680 = 3.680, dd = Q1800 = 1.800. Rough passes `max(1.8 sqrt n, prev +
/// 0.1)` while below k - d = 3.48: 1.8, 2.545584, 3.117691 (3.6 would pass 3.48), then
/// 3.48, then k once. X = 60.64 + 2 (3.68 - d_n): 64.4, 62.908831, 61.764617, 61.04,
/// 60.64; each pass starts (3.68 - d_n) tan 30 deg back towards +Z (flank infeed) and its
/// thread runs to Z 25 + 6 (the pull-out takes the last 6 mm) from Z 130 plus that.
#[test]
fn fanuc_manual_g76_example_in_standard_input() {
    let text = "G00 X80.0 Z130.0\nG76 P011060 Q100 R200\nG76 X60640 Z25000 P3680 Q1800 F6.0\n";
    let t = run_with(text, Dialect::Fanuc, Settings::default()).unwrap();
    let th = threads(&t);
    // Each pass: the thread and its chained 45 deg pull-out.
    assert_eq!(th.len(), 10);
    let tan30 = 30f64.to_radians().tan();
    let depths = [1.8, 1.8 * 2f64.sqrt(), 1.8 * 3f64.sqrt(), 3.48, 3.68];
    for (n, d) in depths.iter().enumerate() {
        let (main, out) = (th[2 * n], th[2 * n + 1]);
        let x = 60.64 + 2.0 * (3.68 - d);
        let shift = (3.68 - d) * tan30;
        assert!(
            close(main.x_start, x) && close(main.x_dia, x),
            "pass {n}: {main:?}"
        );
        assert!(close(main.z_start, 130.0 + shift), "pass {n}: {main:?}");
        assert!(close(main.z, 31.0 + shift), "pass {n}: {main:?}");
        assert_eq!(main.lead, Some(6.0));
        assert!(out.chained && close(out.x_dia, x + 12.0) && close(out.z, 25.0 + shift));
    }
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    // Read as calculator-type input the manual's X60640 is 60640 mm: said, with the
    // setting that reads it as written.
    let calc = Settings {
        decimal_point: DecimalPoint::Calculator,
        ..Settings::default()
    };
    let t = run_with(text, Dialect::Fanuc, calc).unwrap();
    let w = &t.warnings[0];
    assert_eq!((w.line, w.col), (3, 5), "{w}");
    assert!(
        w.message.contains("X60640") && w.message.contains("60640 mm"),
        "{w}"
    );
    assert!(w
        .hint
        .as_deref()
        .unwrap()
        .contains("decimal_point = \"standard\""));
}

/// The same thread written for a GSK 980TDc whose least input increment is 0.0001 mm (IS-C,
/// the 980TDc's finer setting), in the style of GSK's manual (plain axis words in mm, as
/// those machines read them: calculator-type input): P36800 is 3.68 mm there; the passes are
/// the FANUC example's (derived above). Read in 0.001 mm it is a thread 36.8 mm deep on a
/// 60.64 mm root: the warning names `input_increment`.
#[test]
fn gsk_g76_written_for_tenth_micrometres() {
    let text = "G00 X80 Z130\nG76 P011060 Q1000 R0.2\nG76 X60.64 Z25 P36800 Q18000 F6\n";
    let settings = |increment| Settings {
        decimal_point: DecimalPoint::Calculator,
        input_increment: increment,
        ..Settings::default()
    };
    let fine = run_with(
        text,
        Dialect::Gsk980,
        settings(InputIncrement::TenthMicrometre),
    )
    .unwrap();
    let x: Vec<f64> = threads(&fine).iter().step_by(2).map(|m| m.x_dia).collect();
    let want = [64.4, 62.908831, 61.764617, 61.04, 60.64];
    assert_eq!(x.len(), 5);
    assert!(x.iter().zip(want).all(|(a, b)| close(*a, b)), "{x:?}");
    assert!(fine.warnings.is_empty(), "{:?}", fine.warnings);
    // In 0.001 mm: k = 36.8, dd = 18, dmin = 1: the first pass 2 (36.8 - 18) above X60.64.
    let coarse = run_with(text, Dialect::Gsk980, settings(InputIncrement::Micrometre)).unwrap();
    assert!(close(threads(&coarse)[0].x_dia, 60.64 + 2.0 * 18.8));
    let w = &coarse.warnings[0];
    assert_eq!((w.line, w.col), (3, 16), "{w}");
    assert!(w.message.contains("36.8 mm deep"), "{w}");
    let hint = w.hint.as_deref().unwrap();
    assert!(
        hint.contains("input_increment = 0.0001") && hint.contains("3.68 mm"),
        "{hint}"
    );
}

/// Plain axis words in standard input: `X60` is 0.060 mm; the first such word of a run is
/// warned (once) with the setting that reads it as 60 mm, and the run goes on.
#[test]
fn plain_axis_words_that_look_like_millimetres_are_warned_once() {
    let text = "G0 X60 Z8\nG0 X61 Z9\nG0 X60. Z8.\n";
    let t = run_with(text, Dialect::Fanuc, Settings::default()).unwrap();
    assert!(close(t.moves[0].x_dia, 0.06) && close(t.moves[0].z, 0.008));
    assert!(close(t.moves[2].x_dia, 60.0) && close(t.moves[2].z, 8.0));
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    let w = &t.warnings[0];
    assert_eq!((w.line, w.col), (1, 4));
    assert!(
        w.message.contains("X60") && w.message.contains("0.06 mm"),
        "{w}"
    );
    assert!(w
        .hint
        .as_deref()
        .unwrap()
        .contains("decimal_point = \"calculator\""));
    // Siemens and LinuxCNC have no decimal-point input: nothing to warn.
    let s = run_with(text, Dialect::Siemens802d, Settings::default()).unwrap();
    assert!(close(s.moves[0].x_dia, 60.0) && s.warnings.is_empty());
}

/// An inch program on a machine in inch at power-on has no G20: its `F.0625` (16 threads per
/// inch) read in mm is a 0.0625 mm lead, warned at the block with the setting; with
/// `units = "inch"` it is 1.5875 mm and X.74 is 18.796 mm. A program that says G21 (or G20)
/// itself gets no warning.
#[test]
fn inch_at_power_on() {
    let text = "G0 X.8 Z.2\nG92 X.74 Z-1. F.0625\nX.73\nM30\n";
    let t = run_with(text, Dialect::Fanuc, Settings::default()).unwrap();
    assert_eq!(threads(&t)[0].lead, Some(0.0625));
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    let w = &t.warnings[0];
    assert_eq!(w.line, 2);
    assert!(w.message.contains("16 threads per inch"), "{w}");
    assert!(w.hint.as_deref().unwrap().contains("units = \"inch\""));
    let inch = Settings {
        power_on: PowerOn {
            inch: true,
            ..PowerOn::default()
        },
        ..Settings::default()
    };
    let t = run_with(text, Dialect::Fanuc, inch.clone()).unwrap();
    let th = threads(&t);
    assert!(close(th[0].lead.unwrap(), 1.5875) && close(th[0].x_dia, 18.796));
    assert!(close(th[1].x_dia, 0.73 * 25.4));
    assert!(t.warnings.is_empty());
    let said = run_with(&format!("G21\n{text}"), Dialect::Fanuc, Settings::default()).unwrap();
    assert!(said.warnings.is_empty());
    // G21 in the program wins over the power-on inch; G70 (Siemens) likewise.
    let t = run_with(&format!("G21\n{text}"), Dialect::Fanuc, inch.clone()).unwrap();
    assert_eq!(threads(&t)[0].lead, Some(0.0625));
    let s = run_with("G0 X1 Z0.2\nG33 Z-1 K0.0625\n", Dialect::Siemens802d, inch).unwrap();
    assert!(close(threads(&s)[0].lead.unwrap(), 1.5875));
}

/// Feed per minute at power-on (G98 on a FANUC lathe): a rigid tap's pitch is F / S =
/// 750 / 500 = 1.5 mm; per revolution (the default) F is the pitch. G99 in the program
/// wins over the power-on mode.
#[test]
fn feed_per_minute_at_power_on() {
    let text = "G0 X0. Z10.\nM3 S500\nM29 S500\nG84 Z-20. R-7. F750.\nG80\n";
    let per_minute = Settings {
        power_on: PowerOn {
            per_minute: true,
            ..PowerOn::default()
        },
        ..Settings::default()
    };
    let t = run_with(text, Dialect::Fanuc, per_minute.clone()).unwrap();
    assert_eq!(threads(&t)[0].lead, Some(1.5));
    let t = run_with(&format!("G99\n{text}"), Dialect::Fanuc, per_minute).unwrap();
    assert_eq!(threads(&t)[0].lead, Some(750.0));
}

/// Radius programming: X15 is a radius of 15 (diameter 30), U2 moves the radius by 2 and
/// G76's X is the root radius; LinuxCNC in diameter mode at power-on (its G7) reads X30 as a
/// diameter.
#[test]
fn radius_or_diameter_x_at_power_on() {
    let radius = Settings {
        power_on: PowerOn {
            diameter: Some(false),
            ..PowerOn::default()
        },
        ..Settings::default()
    };
    let t = run_with(
        "G0 X15. Z5.\nG32 Z-20. F2.\nG0 U2.\nG0 X15. Z5.\nG76 P010060 Q0 R0.\nG76 X9. Z-20. P1000 Q100000 F2.\n",
        Dialect::Fanuc,
        radius,
    )
    .unwrap();
    assert_eq!(t.moves[0].x_dia, 30.0);
    assert_eq!(t.moves[2].x_dia, 34.0);
    let th = threads(&t);
    // G76 k = 1: the passes at k - d = k (d = 0) and k, both on the root diameter 18.
    assert_eq!(th.last().unwrap().x_dia, 18.0);
    let diameter = Settings {
        power_on: PowerOn {
            diameter: Some(true),
            ..PowerOn::default()
        },
        ..Settings::default()
    };
    let l = run_with("G0 X30 Z5 M3\nG33 Z-20 K2\n", Dialect::Linuxcnc, diameter).unwrap();
    assert_eq!(l.moves[0].x_dia, 30.0);
    let l = run_with("G0 X30 Z5\n", Dialect::Linuxcnc, Settings::default()).unwrap();
    assert_eq!(l.moves[0].x_dia, 60.0);
}

/// A file whose first program is a subprogram: the control runs the program that ends the
/// run (M30) and that no other calls (O1000); its `M98 P30100` runs O0100 three times, one
/// thread pass each. It used to run O0100 alone (one pass, then its M99 ended the run).
const SUB_FIRST: &str = "O0100 (ONE PASS)\nG32 W-20. F2.\nG0 U2.\nW20.\nU-2.\nM99\n\
                         O1000 (MAIN)\nG0 X30. Z5.\nM98 P30100\nG0 X60.\nM30\n";

#[test]
fn the_main_program_is_the_one_that_ends_the_run() {
    let t = run_with(SUB_FIRST, Dialect::Fanuc, Settings::default()).unwrap();
    let th = threads(&t);
    assert_eq!(th.len(), 3);
    assert!(th
        .iter()
        .all(|m| m.x_dia == 30.0 && m.z_start == 5.0 && m.z == -15.0));
    assert_eq!(t.moves.last().unwrap().x_dia, 60.0);
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    // `main` names it; naming the subprogram runs it alone, and its M99 is warned.
    let named = |main: &str| Settings {
        main: Some(main.into()),
        ..Settings::default()
    };
    let t = run_with(SUB_FIRST, Dialect::Fanuc, named("O1000")).unwrap();
    assert_eq!(threads(&t).len(), 3);
    let t = run_with(SUB_FIRST, Dialect::Fanuc, named("O100")).unwrap();
    assert_eq!(threads(&t).len(), 1);
    let w = &t.warnings[0];
    assert_eq!((w.line, w.severity), (6, Severity::Warning));
    assert!(w.message.contains("M99 ends the main program"), "{w}");
    let e = run_with(SUB_FIRST, Dialect::Fanuc, named("O2000")).unwrap_err();
    assert!(
        e.message.contains("no program O2000") && e.message.contains("O1000"),
        "{e}"
    );
    // Two programs that end in M30, neither called: the first, as before.
    let two = "O0001\nG0 X10. Z1.\nM30\nO0002\nG0 X20. Z2.\nM30\n";
    let t = run_with(two, Dialect::Fanuc, Settings::default()).unwrap();
    assert_eq!(t.moves[0].x_dia, 10.0);
}

/// A main program that ends in M99 (or `M99 P..`) loops on a FANUC: warned at that block,
/// run once (GSK alike).
#[test]
fn a_main_program_ending_in_m99_is_warned() {
    for (text, line) in [
        ("G0 X30. Z5.\nG32 Z-20. F2.\nG0 X40.\nZ5.\nM99\n", 5),
        ("N10 G0 X30. Z5.\nG32 Z-20. F2.\nG0 X40.\nZ5.\nM99 P10\n", 5),
    ] {
        for dialect in [Dialect::Fanuc, Dialect::Gsk980] {
            let t = run_with(text, dialect, Settings::default()).unwrap();
            assert_eq!(threads(&t).len(), 1);
            assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
            assert_eq!(t.warnings[0].line, line);
            assert!(t.warnings[0].message.contains("M99 ends the main program"));
        }
    }
}

/// Words that never take a decimal point refuse one, at the word: G76's first-block P
/// (`mmrraa`) and a threading Q (0.001 deg).
#[test]
fn points_on_count_words_are_refused() {
    for (text, col, want) in [
        (
            "G0 X30. Z5.\nG76 P010060. Q50 R0.\n",
            5,
            "takes no decimal point",
        ),
        (
            "G0 X30. Z5.\nG32 Z-20. F2. Q90.\n",
            15,
            "Q90 is written Q90000",
        ),
    ] {
        let e = run_with(text, Dialect::Fanuc, Settings::default()).unwrap_err();
        assert_eq!((e.line, e.col), (2, col), "{e}");
        assert!(e.message.contains(want), "{e}");
    }
}

/// G65 arguments without a decimal point (FANUC Custom Macro B, "Decimal point position of
/// argument": they count in the least input increment of their address): in standard input
/// `X50` passes 0.050 and `A30` 0.030 deg, `Z-20.` passes -20 and `F2` 2 (F's increment is a
/// machine matter: as written); in calculator-type input all as written.
#[test]
fn g65_arguments_without_a_point() {
    let text = "G65 P9010 X50 Z-20. A30 F2\nM30\nO9010\nG0 X#24 Z#26\nG0 X#1 Z#9\nM99\n";
    let t = run_with(text, Dialect::Fanuc, Settings::default()).unwrap();
    let ends: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
    assert!(
        close(ends[0].0, 0.05) && close(ends[0].1, -20.0),
        "{ends:?}"
    );
    assert!(close(ends[1].0, 0.03) && close(ends[1].1, 2.0), "{ends:?}");
    let calc = Settings {
        decimal_point: DecimalPoint::Calculator,
        ..Settings::default()
    };
    let t = run_with(text, Dialect::Fanuc, calc).unwrap();
    let ends: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
    assert_eq!(ends, [(50.0, -20.0), (30.0, 2.0)]);
}

/// G04 is a dwell: its X, U or P is the time, and the block moves nothing (FANUC 0i-TF
/// "Dwell (G04)", GSK 980TDc "Dwell G04"). It used to move the tool to X1 (a grooving
/// tool's plunge to the axis).
#[test]
fn g04_dwells_in_place() {
    for dialect in [Dialect::Fanuc, Dialect::Gsk980] {
        let t = run_with(
            "G0 X30. Z-30.\nG1 X23.5 F.05\nG4 X1.\nG04 U0.5\nG4 P500\nG0 X30.\n",
            dialect,
            Settings::default(),
        )
        .unwrap();
        let ends: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
        assert_eq!(ends, [(30.0, -30.0), (23.5, -30.0), (30.0, -30.0)]);
    }
}
