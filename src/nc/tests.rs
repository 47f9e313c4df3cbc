//! Unit tests of the interpreter.

use super::*;

fn threads(moves: &[Move]) -> Vec<&Move> {
    moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect()
}

/// The toolpath of `text` (as `T.NC`) in `dialect`, numbers in mm.
fn toolpath(text: &str, dialect: Dialect) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    interpret_with(
        &src,
        dialect,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
}

fn run(text: &str, dialect: Dialect) -> Result<Vec<Move>, NcError> {
    toolpath(text, dialect).map(|t| t.moves)
}

/// `controllers.md` 2.3's worked schedule: k = 1.30, dd = 0.45, dmin = 0.10, d = 0.05
/// gives 0.450, 0.636, 0.779, 0.900, 1.006, 1.106, 1.206, 1.250, then m x 1.300, each
/// pass shifted by (k - d_n) tan30 against the feed (flank infeed).
#[test]
fn fanuc_g76_depth_schedule_and_flank_infeed() {
    let moves = run(
        "G0 X30 Z5\nG76 P020060 Q100 R0.05\nG76 X24 Z-20 P1300 Q450 F2\nM30\n",
        Dialect::Fanuc,
    )
    .unwrap();
    let t: Vec<&Move> = threads(&moves);
    let want = [
        0.45,
        0.45 * 2f64.sqrt(),
        0.45 * 3f64.sqrt(),
        0.9,
        0.45 * 5f64.sqrt(),
        0.0,
        0.0,
        1.25,
        1.3,
        1.3,
    ];
    assert_eq!(t.len(), want.len());
    let mut prev = 0.0;
    for (i, (m, &w)) in t.iter().zip(&want).enumerate() {
        let depth = 1.3 - (m.x_dia - 24.0) / 2.0;
        let w = if w == 0.0 { prev + 0.1 } else { w };
        assert!((depth - w).abs() < 1e-9, "pass {i}: depth {depth} vs {w}");
        let shift = (1.3 - depth) * (30f64.to_radians()).tan();
        assert!((m.z_start - (5.0 + shift)).abs() < 1e-9 && (m.z - (-20.0 + shift)).abs() < 1e-9);
        assert_eq!(m.lead, Some(2.0));
        prev = depth;
    }
    // Q with a point: 0.1 mm with a warning (Haas; a FANUC 0i alarms PS0007), the same
    // passes as Q100.
    let full = |text: &str| {
        let src = Source {
            name: "T.NC".into(),
            text: text.into(),
        };
        let opts = Options {
            settings: Settings::in_mm(),
            ..Options::default()
        };
        interpret_with(&src, Dialect::Fanuc, &|_| None, &opts).unwrap()
    };
    let plain = full("G0 X30 Z5\nG76 P020060 Q100 R0.05\nG76 X24 Z-20 P1300 Q450 F2\nM30\n");
    let pointed = full("G0 X30 Z5\nG76 P020060 Q0.1 R0.05\nG76 X24 Z-20 P1.3 Q0.45 F2\nM30\n");
    assert_eq!(plain.moves, pointed.moves);
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    let said: Vec<&str> = pointed
        .warnings
        .iter()
        .map(|w| w.message.as_str())
        .collect();
    assert_eq!(said.len(), 3, "{said:?}");
    assert!(
        said.iter().all(|m| m.contains("has a decimal point")),
        "{said:?}"
    );
}

/// Seed 000's first program (GSK 980TDC, OCR-corrected: `00001` -> `O0001`,
/// `M98 P25 0002` -> `M98 P250002`, `GOO` -> `G00`), its run-out words dropped: O0002 runs
/// 25 times, each 0.2 mm deeper (U-10.2, then U10 out).
#[test]
fn m98_repeats_an_o_program_of_the_same_file() {
    let text = "O0001\nN10 G00 X120 Z80\nN20 M03 M08 G97 S800\nN30 T0101\nN40 G00 X60 Z8\n\
                N50 M98 P250002\nN60 G00 X120\nN70 Z80\nN80 T0100\nN90 M30\n\
                O0002\nN10 G00 U-10.2\nN20 G34 Z-70 F4 R1\nN30 G0 U10\nN40 G00 Z8\nN50 M99\n";
    let moves = run(text, Dialect::Gsk980).unwrap();
    let t: Vec<&Move> = threads(&moves);
    assert_eq!(t.len(), 25);
    for (k, m) in t.iter().enumerate() {
        assert!(
            (m.x_dia - (49.8 - 0.2 * k as f64)).abs() < 1e-9,
            "{k}: {}",
            m.x_dia
        );
        assert_eq!(
            (m.z_start, m.z, m.lead, m.lead_change),
            (8.0, -70.0, Some(4.0), Some(1.0))
        );
        assert_eq!(m.tool, Some(1));
    }
    let e = run("M98 P0003\nM30\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("subprogram `O3` not found"), "{e}");
}

#[test]
fn g50_sets_the_position_and_g70_is_not_inch_on_fanuc() {
    let moves = run("G50 X100 Z50\nG0 X60 Z8\nM30\n", Dialect::Gsk980).unwrap();
    assert_eq!(moves.len(), 1);
    assert_eq!((moves[0].x_start, moves[0].z_start), (100.0, 50.0));
    // G70 is the finishing cycle (not inch input): it needs its shape's blocks.
    let e = run("G70 P10 Q20\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("G70 P10: no block N10"), "{e}");
    let e = run("G52 X10\n", Dialect::Linuxcnc).unwrap_err();
    assert!(
        e.message
            .contains("G52 (local coordinate system offset) is not simulated"),
        "{e}"
    );
}

/// Repeats do not count as nesting, and WHILE loops belong to their own program.
#[test]
fn repeated_calls_nest_and_keep_their_loops() {
    let text = "O0001\n#1=0\nWHILE[#1LT2]DO1\n#1=#1+1\nM98 P30002\nEND1\nM30\n\
                O0002\nM98 P20003\nM99\n\
                O0003\n#2=0\nWHILE[#2LT1]DO1\n#2=#2+1\nG0 X1\nG32 Z-1 F1\nG0 Z0\nEND1\nM99\n";
    let moves = run(text, Dialect::Fanuc).unwrap();
    // 2 outer iterations x 3 calls of O0002 x 2 calls of O0003 x 1 inner iteration.
    assert_eq!(
        moves.iter().filter(|m| m.kind == MoveKind::Thread).count(),
        12
    );
    let deep = "O0001\nM98 P2\nM30\nO0002\nM98 P3\nM99\nO0003\nM98 P2\nM99\n";
    let e = run(deep, Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("nesting deeper than 8"), "{e}");
    assert!(e.stack.len() == 8, "{:?}", e.stack);
}

#[test]
fn macro_a_arithmetic_and_jumps() {
    let text = "G0 X60 Z4\nG65 H01 P#102 Q0.5\nG65 H01 P#103 Q0\n\
                N10 G65 H02 P#104 Q#103 R1\nG65 H01 P#103 Q#104\nG65 H81 P30 Q#104 R6\n\
                G65 H01 P#100 Q#102\nG00 U-#100\nG32 W-20 F3\nG00 X60\nZ4\n\
                G65 H03 P#101 Q#100 R0.2\nG65 H01 P#102 Q#101\nG65 H86 P20 Q#102 R0.2\n\
                G65 H80 P10\nN20 G65 H01 P#102 Q0.2\nG65 H80 P10\nN30 M30\n";
    let moves = run(text, Dialect::Gsk980).unwrap();
    let x: Vec<f64> = moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .map(|m| m.x_dia)
        .collect();
    // Infeeds 0.5, 0.3, then the 0.2 floor: X = 60 - infeed (U is a diameter change).
    assert_eq!(x.len(), 5);
    for (got, want) in x.iter().zip([59.5, 59.7, 59.8, 59.8, 59.8]) {
        assert!((got - want).abs() < 1e-9, "{x:?}");
    }
    let e = run("G65 H05 P#1 Q1 R0\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("division by zero"), "{e}");
}

#[test]
fn errors_name_line_and_column() {
    let e = run("R1=1\nR2=R1/0\n", Dialect::Siemens802d).unwrap_err();
    assert_eq!((e.line, e.message.as_str()), (2, "division by zero"));
    let e = run("GOTOF NOWHERE\n", Dialect::Siemens802d).unwrap_err();
    assert!(e.message.contains("label `NOWHERE` not found"), "{e}");
    let e = run("AA: GOTOB AA\n", Dialect::Siemens802d).unwrap_err();
    assert!(e.message.contains("blocks executed"), "{e}");
    let e = run("END1\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("END1 without DO1"), "{e}");
}

fn run_opts(text: &str, dialect: Dialect, strict: bool) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        strict,
        settings: Settings::in_mm(),
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts)
}

/// The static check reports every problem of the program at once, with exact columns,
/// including those in blocks that would never run.
#[test]
fn all_problems_are_reported_at_once_with_line_and_column() {
    let text = "G0 X60 Z8\n#1=[2+3\nG1 X1..5\nIF [#1 GT 2] GOTO 99\nG0 X#1 Z=3\nM30\n";
    let e = run_opts(text, Dialect::Fanuc, false).unwrap_err();
    let all = e.all();
    let at: Vec<(usize, usize)> = all.iter().map(|d| (d.line, d.col)).collect();
    // Line 2: `]` missing at the end (column 8, after `3`); line 3: `1..5` at column 5;
    // line 4: GOTO 99 has no N99 (column 19, the 99); line 5: `=` where Z's value belongs
    // (column 9).
    assert_eq!(at, vec![(2, 8), (3, 5), (4, 19), (5, 9)], "{e}");
    let sev: Vec<Severity> = all.iter().map(|d| d.severity).collect();
    use Severity::{Error, Warning};
    // A missing jump target is a warning: a control alarms only when the jump is taken.
    assert_eq!(sev, vec![Error, Error, Warning, Error], "{e}");
    assert!(all[1].message.contains("`1..5` is not a number"), "{e}");
    assert!(all[2].message.contains("no block N99"), "{e}");
    let shown = e.to_string();
    // Each diagnostic: `severity: message`, then `--> file:line:col`.
    let lines: Vec<&str> = shown.lines().collect();
    let at = |head: &str, place: &str| {
        let place = format!("--> {place}");
        lines
            .windows(2)
            .any(|w| w[0].starts_with(head) && w[1].trim_start() == place)
    };
    assert!(at("error: ", "T.NC:3:5"), "{shown}");
    assert!(at("warning: no block N99", "T.NC:4:19"), "{shown}");
    assert!(shown.ends_with("3 errors, 1 warning"), "{shown}");
    // The caret stands under the column.
    assert!(shown.contains("3 | G1 X1..5\n  |     ^"), "{shown}");
}

/// Unknown words and codes are warnings that are skipped, or errors in strict mode; known
/// codes that would falsify the toolpath are always errors.
#[test]
fn unknown_codes_warn_or_fail_in_strict_mode() {
    let text = "G0 X60 Z8\nM123\nG123 X50\nY5 G0 Z4\nG32 Z-20 F2\nM30\n";
    let t = run_opts(text, Dialect::Fanuc, false).unwrap();
    let w: Vec<(usize, usize)> = t.warnings.iter().map(|d| (d.line, d.col)).collect();
    assert_eq!(w, vec![(2, 1), (3, 1), (4, 1)], "{:?}", t.warnings);
    assert!(t.warnings.iter().all(|d| d.severity == Severity::Warning));
    // The skipped words do not stop the rest of their blocks: X50 and Z4 still move.
    let ends: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
    assert_eq!(
        ends,
        vec![(60.0, 8.0), (50.0, 8.0), (50.0, 4.0), (50.0, -20.0)]
    );
    let e = run_opts(text, Dialect::Fanuc, true).unwrap_err();
    assert_eq!(e.all().len(), 3, "{e}");
    assert!(e.all().iter().all(|d| d.severity == Severity::Error));
    // A code that would leave the tool somewhere vpcut cannot know: refused even without
    // --strict (G30 goes to the second reference point since issue 17).
    let e = run_opts("G52 U0 W0\n", Dialect::Fanuc, false).unwrap_err();
    assert!(e.message.contains("G52 (coordinate system setting"), "{e}");
    // A warning of a block inside a loop is reported once.
    let t = run_opts(
        "#1=0\nWHILE [#1 LT 3] DO1\nM123\n#1=#1+1\nEND1\n",
        Dialect::Fanuc,
        false,
    )
    .unwrap();
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
}

#[test]
fn siemens_labels_loops_and_calls_are_checked_before_running() {
    // A backward GOTOF, a missing label, and a missing subprogram in a branch never run.
    let text = "R1=1\nTOP: G0 X10\nIF R1==2 GOTOF TOP\nIF R1==3 GOTOB NOWHERE\nIF R1==1 GOTOF END\nNOPROG\nEND: M30\n";
    let e = run_opts(text, Dialect::Siemens802d, false).unwrap_err();
    let msgs: Vec<(usize, String)> = e
        .all()
        .iter()
        .map(|d| (d.line, d.message.clone()))
        .collect();
    assert_eq!(msgs.len(), 3, "{e}");
    assert!(
        msgs[0]
            .1
            .contains("GOTOF jumps forward, but `TOP` is above"),
        "{e}"
    );
    assert!(msgs[1].1.contains("label `NOWHERE` not found"), "{e}");
    assert!(msgs[2].1.contains("subprogram `NOPROG` not found"), "{e}");
    let sev: Vec<Severity> = e.all().iter().map(|d| d.severity).collect();
    assert_eq!(
        sev,
        vec![Severity::Error, Severity::Warning, Severity::Warning]
    );
    // Without the backward GOTOF the program runs: the missing label and subprogram sit in
    // branches that are never taken (R1 is 1), as on a control, and stay warnings.
    let ok = text.replace("IF R1==2 GOTOF TOP\n", "");
    let t = run_opts(&ok, Dialect::Siemens802d, false).unwrap();
    assert_eq!((t.moves.len(), t.warnings.len()), (1, 2));
    // Taken, the jump to nowhere stops the run.
    let e = run_opts(
        "R1=3\nIF R1==3 GOTOB NOWHERE\n",
        Dialect::Siemens802d,
        false,
    )
    .unwrap_err();
    assert!(e.message.contains("label `NOWHERE` not found"), "{e}");
    // Statements vpcut does not simulate are skipped with a warning; a message to the
    // operator moves nothing and is no warning.
    let t = run_opts(
        "MSG(\"ROUGHING\")\nROT Z45\nG0 X10 Z5\nM30\n",
        Dialect::Siemens802d,
        false,
    )
    .unwrap();
    assert_eq!(t.warnings.len(), 1);
    assert!(t.warnings[0].message.contains("`ROT`"), "{:?}", t.warnings);
    assert_eq!(t.moves.len(), 1);
}

#[test]
fn fanuc_loops_are_matched_statically() {
    let e = run_opts(
        "WHILE [1 EQ 1] DO1\nWHILE [1 EQ 1] DO2\nEND1\nEND2\n",
        Dialect::Fanuc,
        false,
    )
    .unwrap_err();
    assert!(
        e.message
            .contains("END1 closes DO1 while an inner loop is still open"),
        "{e}"
    );
    let e = run_opts(
        "#1=1\nWHILE [#1 LT 3] DO1\n#1=#1+1\n",
        Dialect::Fanuc,
        false,
    )
    .unwrap_err();
    assert_eq!(
        (e.line, e.message.as_str()),
        (2, "WHILE .. DO1 without END1")
    );
    let e = run_opts("G0 X10 (no end\n", Dialect::Fanuc, false).unwrap_err();
    assert_eq!((e.line, e.col), (1, 8), "{e}");
    // Arguments of a G65 macro call are letters of every kind: no warning about A, B, D;
    // the only diagnostic is the missing program, a warning, then the error when called.
    let e = run_opts("G65 P9010 A1 B2 D3\n", Dialect::Fanuc, false).unwrap_err();
    assert!(e.message.contains("subprogram `O9010` not found"), "{e}");
    assert_eq!(e.others.len(), 1, "{e}");
    assert!(
        e.others[0].message.contains("subprogram O9010 not found"),
        "{e}"
    );
    assert_eq!(e.others[0].severity, Severity::Warning);
}

#[test]
fn operators_and_inverse_functions() {
    // FANUC: 7 MOD 3 = 1; ASIN[0.5] = 30 deg; ACOS[0] = 90; 1 XOR 1 = 0.
    let t = "#1=[7 MOD 3]\n#2=ASIN[0.5]\n#3=ACOS[0]\n#4=[1 XOR 1]\nG0 X[#1*10+#4] Z[#2+#3]\n";
    let m = run(t, Dialect::Fanuc).unwrap();
    assert_eq!((m[0].x_dia, m[0].z), (10.0, 120.0));
    let e = run("#1=ASIN[2]\n", Dialect::Fanuc).unwrap_err();
    assert!(e.message.contains("must lie in -1..1"), "{e}");
    // Siemens: 7 DIV 2 = 3 (integer division), 7 MOD 2 = 1, NOT 0 = 1.
    let m = run(
        "R1=7 DIV 2\nR2=7 MOD 2\nR3=NOT 0\nG0 X=R1*10+R2 Z=R3\n",
        Dialect::Siemens802d,
    )
    .unwrap();
    assert_eq!((m[0].x_dia, m[0].z), (31.0, 1.0));
}

/// A decreasing lead that would reach zero inside the block is an alarm with the block's
/// line: `F^2 + 2 K s = 16 - 2 * 0.5 * 20 = -4 < 0`; it reaches zero after 16 mm.
#[test]
fn a_lead_reaching_zero_is_an_error_at_its_block() {
    let e = run("G0 X30 Z0\nG34 Z-20 F4 K-0.5\n", Dialect::Fanuc).unwrap_err();
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("reaches zero after 16.0000 mm"), "{e}");
    // 18 mm would leave sqrt(16 - 18) = imaginary as well; 15 mm leaves lead 1.
    let m = run("G0 X30 Z0\nG34 Z-15 F4 K-0.5\n", Dialect::Fanuc).unwrap();
    assert_eq!(m.len(), 2);
    // A thread move along X only (a face thread, which the controls cut) runs as a feed
    // move at its lead per revolution, with a warning at its block.
    for (text, d) in [
        ("G0 X30 Z0\nG33 X40 Z0 K2\n", Dialect::Siemens802d),
        ("G0 X30 Z0\nG32 X40 F2.\n", Dialect::Fanuc),
        (
            "G18 G7 G21\nG0 X30 Z0 M3 S100\nG33 X40 K2\n",
            Dialect::Linuxcnc,
        ),
    ] {
        let t = toolpath(text, d).unwrap_or_else(|e| panic!("{text}: {e}"));
        let last = t.moves.last().unwrap();
        assert_eq!(last.kind, MoveKind::Feed, "{text}: {last:?}");
        assert_eq!((last.x_dia, last.z, last.lead), (40.0, 0.0, None), "{text}");
        let f = last.feed.unwrap();
        assert!(f.per_rev && f.value == 2.0, "{text}: {f:?}");
        assert!(
            t.warnings
                .iter()
                .any(|w| w.message.contains("face thread") && w.line == text.lines().count()),
            "{text}: {:?}",
            t.warnings
        );
    }
}

/// The fast number reader gives the same f64 as `str::parse` (correct rounding).
#[test]
fn numbers_read_as_str_parse_reads_them() {
    let cases = [
        "0",
        "12",
        "12.",
        ".5",
        "1.5",
        "0.1",
        "0.3",
        "2.1166666666666667",
        "25.4",
        "123456789012345",
        "1234567890123456789",
        "0.0000000000000000000000001",
        "99999.99999",
        "3.14159265358979",
        "0.083333",
        "1.8978",
        "100000000000000000000000000",
    ];
    for s in cases {
        assert_eq!(
            lex::ascii_number(s.as_bytes()),
            s.parse::<f64>().ok(),
            "{s}"
        );
    }
    // 200,000 pseudo-random decimals of 1..18 digits with the point anywhere.
    let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
    for _ in 0..200_000 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let len = 1 + (seed % 18) as usize;
        let point = (seed >> 8) as usize % (len + 2);
        let mut s: String = (0..len)
            .map(|i| char::from(b'0' + ((seed >> (i % 50)) % 10) as u8))
            .collect();
        if point <= len {
            s.insert(point, '.');
        }
        assert_eq!(
            lex::ascii_number(s.as_bytes()),
            s.parse::<f64>().ok(),
            "{s}"
        );
    }
    assert_eq!(lex::ascii_number(b"1..5"), None);
    assert_eq!(lex::ascii_number(b"."), None);
}

/// FANUC's two-argument arc tangent `ATAN[y]/[x]` is atan2, not atan(y) divided by x.
#[test]
fn atan_of_two_brackets_is_atan2() {
    let moves = run("#1=ATAN[1]/[2]\nG0 X#1 Z0\n", Dialect::Fanuc).unwrap();
    assert!((moves[0].x_dia - 1f64.atan2(2.0).to_degrees()).abs() < 1e-12);
}

/// GSK statement macros compare with symbols as well as words (980TDi manual 3.28:
/// `IF[#100<100]GOTO10`, `IF[#100==100]THEN`, `IF[3<>2]GOTO2`): for every pair of values
/// and operator the jump is taken exactly when the comparison holds (Rust's own `<`, `==`,
/// ... the oracle), and the word form (LT, EQ, ...) agrees. FANUC alarms on the symbols.
#[test]
fn gsk_macros_compare_with_symbols() {
    type Cmp = fn(f64, f64) -> bool;
    let ops: [(&str, &str, Cmp); 6] = [
        ("==", "EQ", |a, b| a == b),
        ("<>", "NE", |a, b| a != b),
        ("<=", "LE", |a, b| a <= b),
        (">=", "GE", |a, b| a >= b),
        ("<", "LT", |a, b| a < b),
        (">", "GT", |a, b| a > b),
    ];
    for (a, b) in [(1.0, 2.0), (2.0, 2.0), (3.0, -1.5), (-0.5, 0.25)] {
        for (sym, word, f) in ops {
            for op in [sym, word] {
                let text = format!("#1={a}\n#2={b}\nIF[#1{op}#2]GOTO10\nG0 X1.\nN10 G0 X2.\nM30\n");
                let m = run(&text, Dialect::Gsk980).unwrap_or_else(|e| panic!("{text}: {e}"));
                let jumped = m.len() == 1;
                assert_eq!(jumped, f(a, b), "{text}");
            }
        }
    }
    let e = run("#1=1\nIF[#1<2]GOTO10\nN10 M30\n", Dialect::Fanuc).unwrap_err();
    assert_eq!(e.line, 2, "{e}");
}

/// An unknown M code is one warning at its word, not a second one at its block from the
/// run: every dialect, every line with one.
#[test]
fn an_unknown_code_is_warned_once() {
    for (d, text) in [
        (Dialect::Fanuc, "G0 X30. Z5.\nN100 M77\nG0 X40. M78\nM30\n"),
        (Dialect::Gsk980, "G0 X30. Z5.\nN100 M77\nG0 X40. M78\nM30\n"),
        (
            Dialect::Siemens802d,
            "G0 X30 Z5\nN100 M77\nG0 X40 M78\nM30\n",
        ),
    ] {
        let t = toolpath(text, d).unwrap_or_else(|e| panic!("{d:?}: {e}"));
        for (line, code) in [(2, "M77"), (3, "M78")] {
            let n = t
                .warnings
                .iter()
                .filter(|w| w.line == line && w.message.contains(code))
                .count();
            assert_eq!(n, 1, "{d:?} line {line}: {:#?}", t.warnings);
        }
    }
}
