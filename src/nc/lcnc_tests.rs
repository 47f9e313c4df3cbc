//! Unit tests of the LinuxCNC path: O-words, parameters, expressions, G76 tapers.
//!
//! The expected values come from LinuxCNC's own interpreter (`rs274 -g`, Debian
//! `linuxcnc-uspace` 2.9.0~pre1+git20230208) run on the same lines with `(debug, ..)`
//! messages, quoted beside each test, or are derived by hand in the comments. Values are
//! read back here as the X of G0 moves in G7 (diameter) mode, where X is the move's `x_dia`.

use crate::nc::{interpret, Dialect, Limits, Move, MoveKind, NcError, Source};

fn run_with(
    text: &str,
    loader: &dyn Fn(&str) -> Option<Source>,
    limits: Limits,
) -> Result<Vec<Move>, NcError> {
    let src = Source {
        name: "t.ngc".into(),
        text: text.into(),
    };
    interpret(&src, Dialect::Linuxcnc, loader, limits)
}

fn run(text: &str) -> Result<Vec<Move>, NcError> {
    run_with(text, &|_| None, Limits::default())
}

/// The X (diameter, G7) of every move.
fn xs(text: &str) -> Vec<f64> {
    let text = format!("G7\n{text}");
    run(&text)
        .unwrap_or_else(|e| panic!("{e}"))
        .iter()
        .map(|m| m.x_dia)
        .collect()
}

fn close(got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{got:?} vs {want:?}");
    }
}

/// rs274 (b.ngc): caller `#<a>=7 #1=9`; the sub sets `#<a>=3 #1=4 #31=31`; after the call
/// the caller reads 7, 9 and 31. The sub cannot read the caller's `#<a>` (rs274: "Named
/// parameter #<a> not defined" when read in an expression).
#[test]
fn named_locals_and_numbered_locals_are_scoped_to_the_call() {
    let text = "#<a>=7\n#1=9\no10 sub\n#<a>=3\n#1=4\n#31=31\nG0 X[#<a>+#1]\no10 endsub\n\
                o10 call [1]\nG0 X#<a>\nG0 X#1\nG0 X#31\no10 call [2]\n";
    close(&xs(text), &[7.0, 7.0, 9.0, 31.0, 7.0]);
    // Each call starts with its own named locals: the second call does not see the first's.
    close(
        &xs(
            "o1 sub\nG0 X[EXISTS[#<b>]]\n#<b>=1\nG0 X[EXISTS[#<b>]]\no1 endsub\no1 call\no1 call\n",
        ),
        &[0.0, 1.0, 0.0, 1.0],
    );
    let e = run("#<a>=7\no1 sub\nG0 X#<a>\no1 endsub\no1 call\n").unwrap_err();
    assert_eq!((e.line, e.col), (3, 5), "{e}");
    // Globals `#<_name>` are shared.
    close(
        &xs("o1 sub\n#<_g>=[#<_g>+#1]\no1 endsub\n#<_g>=1\no1 call [2]\no1 call [3]\nG0 X#<_g>\n"),
        &[6.0],
    );
}

/// rs274: `#1=#<undefinedname>` fails with "Named parameter #<undefinedname> not defined";
/// numbered parameters read 0 until set.
#[test]
fn an_unset_named_parameter_is_an_error() {
    let e = run("G0 X1\n  #1 = [2 + #<UndefinedName>]\n").unwrap_err();
    assert_eq!((e.file.as_str(), e.line, e.col), ("t.ngc", 2, 13), "{e}");
    assert!(e.message.contains("#<undefinedname> is not defined"), "{e}");
    close(
        &xs("G0 X[#77+1]\nG0 X[EXISTS[#<q>]]\n#<q>=1\nG0 X[EXISTS[#<Q>]]\n"),
        &[1.0, 0.0, 1.0],
    );
}

/// rs274 (e.ngc, f.ngc): a while loop with `continue` on even counts and `break` at 5 runs
/// its top 1..5 and leaves with 5; the body after the continue runs for 1, 3 only.
/// In a do loop, rs274's continue runs the next line of the loop's O-word: the closing
/// while (tests, loops: f.ngc o500 runs its body for 3..9), or a later break (leaves:
/// e.ngc printed top 1, top 2, after 2).
#[test]
fn break_and_continue() {
    let w = "#10=0\no400 while [#10 LT 9]\n#10=[#10+1]\nG0 X#10\no401 if [[#10 MOD 2] EQ 0]\n\
             o400 continue\no401 endif\no402 if [#10 GE 5]\no400 break\no402 endif\nG0 X[100+#10]\n\
             o400 endwhile\nG0 X[1000+#10]\n";
    close(&xs(w), &[1.0, 101.0, 2.0, 3.0, 103.0, 4.0, 5.0, 1005.0]);
    let d = "#10=0\no300 do\n#10=[#10+1]\nG0 X#10\no301 if [[#10 MOD 2] EQ 0]\no300 continue\n\
             o301 endif\no302 if [#10 GE 5]\no300 break\no302 endif\no300 while [#10 LT 9]\nG0 X[1000+#10]\n";
    close(&xs(d), &[1.0, 2.0, 1002.0]);
    let f = "#20=0\no500 do\n#20=[#20+1]\no501 if [#20 LT 3]\no500 continue\no501 endif\n\
             G0 X#20\no500 while [#20 LT 9]\nG0 X[100+#20]\n";
    close(&xs(f), &[3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 109.0]);
    // rs274 2.9.0~pre1: after a break out of a while loop (even in a sub) the next do loop's
    // closing while falls through once ("t 1; a 1; u 1; u 2; u 3; b 3"); a break out of a
    // do loop in between clears that ("t 1; t 2; t 3; a 3").
    let dos = "o138 do\n#1=[#1+1]\nG0 X#1\no138 while [#1 LT 3]\nG0 X[10+#1]\n\
               #1=0\no139 do\n#1=[#1+1]\nG0 X[20+#1]\no139 while [#1 LT 3]\nG0 X[30+#1]\n";
    close(
        &xs(&format!(
            "#1=0\no1 sub\no133 while [1]\no133 break\no133 endwhile\no1 endsub\no1 call\n{dos}"
        )),
        &[1.0, 11.0, 21.0, 22.0, 23.0, 33.0],
    );
    close(
        &xs(&format!("#1=0\no133 while [1]\no133 break\no133 endwhile\no135 do\no135 break\no135 while [1]\n{dos}")),
        &[1.0, 2.0, 3.0, 13.0, 21.0, 22.0, 23.0, 33.0],
    );
    // A do loop runs its body once even when the test is false.
    close(&xs("o3 do\nG0 X7\no3 while [0]\n"), &[7.0]);
    // rs274 2.9.0~pre1 refuses break and continue in a repeat, even not run: "no matching
    // while/do label: 'o1 break' (found 'repeat' in line 2)"; vpcut says so at the repeat.
    for word in ["break", "continue"] {
        let e = run(&format!(
            "#1=0\no1 repeat [10]\n#1=[#1+1]\no2 if [#1 EQ 3]\no1 {word}\no2 endif\no1 endrepeat\n"
        ))
        .unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("at line 5 cannot leave a repeat"), "{e}");
    }
    // Even in a repeat that does not run (rs274: "no matching while/do label", random
    // seed 87).
    let e = run("o1 repeat [0]\no1 break\no1 endrepeat\nG0 X4\n").unwrap_err();
    assert!(e.message.contains("at line 2 cannot leave a repeat"), "{e}");
}

/// rs274 (b.ngc): a chain if/elseif/else inside a while, an `if` nested in the elseif
/// branch: count 1 takes the if, 2 the elseif (and continues), 3 the else (and breaks).
#[test]
fn nested_if_elseif_else() {
    let text = "#40=0\no20 while [1]\n#40=[#40+1]\no21 if [#40 EQ 1]\nG0 X1\n\
                o21 elseif [#40 EQ 2]\nG0 X2\no22 if [1]\no20 continue\no22 endif\nG0 X99\n\
                o21 else\no20 break\no21 endif\nG0 X[10+#40]\no20 endwhile\nG0 X[100+#40]\n";
    close(&xs(text), &[1.0, 11.0, 2.0, 103.0]);
    // The first true branch only; else when none is; nested chains with other numbers.
    let chain = |v: f64| {
        xs(&format!(
            "#1={v}\no1 if [#1 LT 0]\nG0 X1\no1 elseif [#1 LT 10]\no2 if [#1 LT 5]\nG0 X2\no2 else\nG0 X3\no2 endif\n\
             o1 elseif [#1 LT 20]\nG0 X4\no1 else\nG0 X5\no1 endif\nG0 X6\n"
        ))
    };
    close(&chain(-1.0), &[1.0, 6.0]);
    close(&chain(1.0), &[2.0, 6.0]);
    close(&chain(7.0), &[3.0, 6.0]);
    close(&chain(15.0), &[4.0, 6.0]);
    close(&chain(25.0), &[5.0, 6.0]);
}

#[test]
fn recursion_deeper_than_the_limit_is_an_error() {
    let e = run("o1 sub\no1 call [#1+1]\no1 endsub\no1 call [0]\nM2\n").unwrap_err();
    assert!(e.message.contains("nesting deeper than 8"), "{e}");
    assert_eq!((e.line, e.file.as_str()), (2, "t.ngc"), "{e}");
    assert_eq!(e.stack.len(), 8, "{e}");
    // Bounded recursion works: o2 counts down from 5 and sums into a global.
    close(
        &xs("o2 sub\no3 if [#1 GT 0]\n#<_s>=[#<_s>+#1]\no2 call [#1-1]\no3 endif\no2 endsub\n#<_s>=0\no2 call [5]\nG0 X#<_s>\n"),
        &[15.0],
    );
}

#[test]
fn an_endless_loop_hits_the_block_limit() {
    let limits = Limits {
        max_blocks: 1000,
        max_depth: 8,

        ..Limits::default()
    };
    let e = run_with(
        "G7\n#1=0\no101 while [1]\n  #1=[#1+1]\no101 endwhile\n",
        &|_| None,
        limits,
    )
    .unwrap_err();
    assert!(e.message.contains("more than 1000 blocks"), "{e}");
    assert!((3..=5).contains(&e.line) && e.file == "t.ngc", "{e}");
    assert!(
        e.to_string()
            .contains(&format!("\n  --> t.ngc:{}:1\n", e.line)),
        "{e}"
    );
    let e = run_with("o1 do\no1 while [1]\n", &|_| None, limits).unwrap_err();
    assert!(e.message.contains("more than 1000 blocks"), "{e}");
}

/// rs274 2.9.0~pre1 (a.ngc, b.ngc, c.ngc), printed with `(debug, ..)`.
#[test]
fn expressions_as_rs274() {
    let cases: [(&str, f64); 28] = [
        ("[1 EQ 1.00005]", 1.0),
        ("[1 NE 1.00005]", 0.0),
        ("[1 LT 1.00005]", 1.0),
        ("[1.00005 LE 1]", 0.0),
        ("[1.00005 GT 1]", 1.0),
        ("[1 GE 1.00005]", 0.0),
        ("[-7 MOD 3]", 2.0),
        ("[7 MOD -3]", 1.0),
        ("[2**3**2]", 64.0),
        ("[-2**2]", 4.0),
        ("[1 LT 2 LT 3]", 1.0),
        ("[ROUND[-2.5]]", -3.0),
        ("[FIX[-2.5]]", -3.0),
        ("[FUP[-2.5]]", -2.0),
        ("[1+2*3 EQ 7 AND 1]", 1.0),
        ("[ATAN[1]/[1]]", 45.0),
        ("[1 OR 0 XOR 1]", 0.0),
        // By hand: functions in degrees, precedence of + over comparisons.
        ("[SIN[30]*2]", 1.0),
        ("[ACOS[0]+ASIN[1]]", 180.0),
        ("[SQRT[16]+ABS[-2]-LN[EXP[3]]]", 3.0),
        ("[10-2-3]", 5.0),
        ("[12/3/2]", 2.0),
        ("-[1+2]", -3.0),
        ("[cos[60] + tan[45]]", 1.5),
        // rs274: fmod by 0 is not a number, which comparisons make 0 and OR 1 before the
        // bracket closes (rs274 printed ne=0 eq=0 lt=0 or=1).
        ("[1 NE 1 MOD 0]", 0.0),
        ("[1 EQ 1 MOD 0]", 0.0),
        ("[1 LT 1 MOD 0]", 0.0),
        ("[1 OR 1 MOD 0]", 1.0),
    ];
    for (e, want) in cases {
        let got = xs(&format!("g0 x{e}\n"));
        assert!((got[0] - want).abs() < 1e-9, "{e}: {got:?} vs {want}");
    }
    // rs274: repeat [2.3] runs 2 times, [2.5] 2, [2.7] 3, [3.5] 4, [-1] none.
    for (n, times) in [(2.3, 2), (2.5, 2), (2.7, 3), (3.5, 4), (-1.0, 0)] {
        let got = xs(&format!("o1 repeat [{n}]\nG0 X1\no1 endrepeat\n"));
        assert_eq!(got.len(), times, "repeat [{n}]");
    }
    // Comments, `;` and case: `(debug, ..)` and `(print, ..)` are comments.
    close(
        &xs("(print, [x)\ng0 X 1 0 (debug, #1) Z1 ; G0 X99\n#<My_Var> = 3\nG0 X#<my_var>\n"),
        &[10.0, 3.0],
    );
}

#[test]
fn bad_lines_are_errors_with_columns() {
    let cases: [(&str, usize, usize, &str); 22] = [
        ("#1=1+2\n", 1, 5, "expected a word"),
        ("G0 X[1+]\n", 1, 8, "expected a value"),
        ("G0 X[1/0]\n", 1, 7, "division by zero"),
        ("G0 X[SQRT[-1]]\n", 1, 6, "SQRT of -1"),
        ("o1 endwhile\n", 1, 1, "undefined O-word label"),
        ("o1 while [1]\nG0 X1\n", 1, 1, "no matching o1 endwhile"),
        ("o1 frob\n", 1, 4, "expected sub, endsub"),
        (
            "G0 X#5399\n",
            1,
            6,
            "system parameter #5399 is not modelled",
        ),
        ("M98 P100\n", 1, 1, "use o-word subroutines"),
        // rs274: "K word missing with g33/g33.1" (and a G33.1 block repeats it).
        ("G33.1 Z-10\n", 1, 1, "G33.1 needs K"),
        ("G0 U5\n", 1, 4, "Bad character 'u' used"),
        ("o9 call\n", 1, 1, "o9 is not defined"),
        ("G0 X1 X2\n", 1, 7, "more than one X word"),
        // rs274: "Calculation resulted in 'not a number'".
        ("G0 X[[1 MOD 0] NE 0]\n", 1, 6, "not a number"),
        // rs274: "Cannot assign to read-only parameter #<_x>", "Nested comment found",
        // "Unclosed comment found", "duplicate O-word label - already defined in line 2".
        ("G0 X1 #<_x>=1\n", 1, 7, "read-only parameter #<_x>"),
        ("#<_value>=3\n", 1, 1, "read-only parameter #<_value>"),
        ("G0 X1 (a (b) c)\n", 1, 10, "nested comment"),
        ("G0 X1 (abc\n", 1, 7, "unclosed comment"),
        (
            "G0 X1\no1 if [1]\no1 endif\no1 if [1]\no1 endif\n",
            4,
            1,
            "already opened a block at line 2",
        ),
        ("G0 X#<_ini[a]b>\n", 1, 5, "(machine state) is not modelled"),
        // rs274 draws these arcs in XY and YZ (its canon: ARC_FEED in the selected plane).
        (
            "G19\nG2 X10 Z-5 R5 F100\n",
            2,
            1,
            "G2 in the G19 plane (YZ) is not simulated",
        ),
        (
            "G17 G3 X10 Z-5 R5 F100\n",
            1,
            1,
            "G3 in the G17 plane (XY) is not simulated",
        ),
    ];
    for (text, line, col, msg) in cases {
        let e = run(text).unwrap_err();
        assert_eq!((e.line, e.col), (line, col), "{text}: {e}");
        assert!(e.message.contains(msg), "{text}: {e}");
    }
    let e = run("o1 return\n").unwrap_err();
    assert!(e.message.contains("not in a subroutine definition"), "{e}");
    let e = run("o1 sub\nG0 X1\n").unwrap_err();
    assert!(e.message.contains("no matching o1 endsub"), "{e}");
    // No line can exhaust the stack: nesting, signs and parameters of parameters.
    for deep in [
        "[".repeat(100_000),
        "-".repeat(100_000) + "1",
        "#".repeat(100_000) + "1",
    ] {
        let e = run(&format!("G0 X{deep}\n")).unwrap_err();
        assert_eq!(e.line, 1, "{e}");
    }
    let e = run("(abort, tool not set)\n").unwrap_err();
    assert!(e.message.contains("aborted: tool not set"), "{e}");
}

/// `o<name> call` of a sub not in the file loads `name.ngc` (lower case, as rs274 folds the
/// line); the error names that file when it is missing or does not define the sub.
#[test]
fn external_subroutines_load_beside_the_file() {
    let loader = |name: &str| -> Option<Source> {
        (name == "cut.ngc").then(|| Source {
            name: "cut.ngc".into(),
            text: "(a sub file)\no<cut> sub\nG0 X#1\nG33 Z-10 K#2\no<cut> endsub\nM2\n".into(),
        })
    };
    let m = run_with(
        "G7 M3\nG0 X20 Z2\no<Cut> call [19] [1.5]\no<cut> call [18.5] [1.5]\n",
        &loader,
        Limits::default(),
    )
    .unwrap();
    let t: Vec<&Move> = m.iter().filter(|m| m.kind == MoveKind::Thread).collect();
    assert_eq!(t.len(), 2);
    assert_eq!(
        (t[1].x_dia, t[1].lead, t[1].file.as_str()),
        (18.5, Some(1.5), "cut.ngc")
    );
    assert_eq!(t[0].line, 4);
    let e = run_with("o<nope> call\n", &loader, Limits::default()).unwrap_err();
    assert!(e.message.contains("nope.ngc"), "{e}");
    let other = |_: &str| -> Option<Source> {
        Some(Source {
            name: "x.ngc".into(),
            text: "G0 X1\n".into(),
        })
    };
    let e = run_with("o<x> call\n", &other, Limits::default()).unwrap_err();
    assert!(e.message.contains("x.ngc does not define o<x> sub"), "{e}");
}

/// G76 tapers: rs274 2.9.0~pre1 cuts L1, L2 and L3 with E0 as L0 (the same 32
/// synchronisation calls); vpcut refuses L4 and a negative E, which rs274 ignores.
#[test]
fn g76_taper_words() {
    let g76 = |tail: &str| {
        run(&format!(
            "G18 G7 G21 M3\nG0 X20 Z5\nG76 P2 Z-20 I-1 J0.4 K1.5 R2 Q29.5 H1 {tail}\nM2\n"
        ))
    };
    let plain = g76("").unwrap();
    for tail in ["L1 E0", "L2 E0", "L3 E0", "L0 E2"] {
        assert_eq!(g76(tail).unwrap(), plain, "{tail}");
    }
    for (tail, msg) in [
        ("L4 E1", "expected L0, L1, L2 or L3"),
        ("L1 E-1", "must not be negative"),
        ("L3 E13", "longer than the drive line"),
        ("L1 E26", "longer than the drive line"),
    ] {
        let e = g76(tail).unwrap_err();
        assert!(e.message.contains(msg), "{tail}: {e}");
    }
    // L1 E20 fits (one taper of a ~25.4 mm drive line); the entry taper of every pass ends
    // E beyond its start and the pass runs to the end.
    let t = g76("L1 E20").unwrap();
    let th: Vec<&Move> = t.iter().filter(|m| m.kind == MoveKind::Thread).collect();
    assert_eq!(th.len(), 2 * 16);
    assert!((th[0].z_start - th[0].z - 20.0).abs() < 1e-9);
}

/// G33.1's refusals: K not positive (rs274 passes it to motion: vpcut refuses it at K's
/// column), a tap along X only (no travel on the spindle axis); a block of no length runs
/// and moves nothing (rs274 prints its RIGID_TAP).
#[test]
fn rigid_tap_refusals() {
    for (text, col, want) in [
        ("G0 X0 Z5\nM3\nG33.1 Z-10 K-1\n", 12, "must be positive"),
        ("G0 X0 Z5\nM3\nG33.1 Z-10 K0\n", 12, "must be positive"),
        ("G0 X0 Z5\nM3\nG33.1 X4 K1\n", 1, "along X only"),
    ] {
        let e = run(text).unwrap_err();
        assert_eq!((e.line, e.col), (3, col), "{text}: {e}");
        assert!(e.message.contains(want), "{text}: {e}");
    }
    let m = run("G0 X0 Z5\nM3\nG33.1 Z5 K1\n").unwrap();
    assert_eq!(m.len(), 1);
}

/// G90.1 (issue 27): I and K are the arc's centre in the program's frame (work offset and
/// G92 applied, I a radius in G7 and G8), G91.1 the centre less the start. Seeded random
/// arcs in random frames: the same arc written both ways (the centre worked out by hand
/// for each) gives the same moves and the same centre; rs274 itself is the oracle of
/// `corpus-g10l2-fixtures` (tests/integration/linuxcnc.rs).
#[test]
fn absolute_arc_centres_equal_incremental_ones() {
    let mut state = 0x0002_7901_u64;
    let mut next = move || {
        // xorshift64*: uniform in [0, 1).
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..64 {
        let (ox, oz) = (4.0 * next() - 2.0, 60.0 * next() - 30.0);
        let g92z = if case % 3 == 0 { 5.0 * next() } else { 0.0 };
        let diameter = case % 2 == 0;
        // Centre (radius, z) in the program frame, start and end on the circle.
        let (cr, cz, r) = (5.0 + 10.0 * next(), -20.0 * next(), 1.0 + 4.0 * next());
        let (a0, a1) = (
            std::f64::consts::TAU * next(),
            std::f64::consts::TAU * next(),
        );
        let s = (cr + r * a0.sin(), cz + r * a0.cos());
        let e = (cr + r * a1.sin(), cz + r * a1.cos());
        let xw = |rad: f64| if diameter { 2.0 * rad } else { rad };
        let head = format!(
            "G18 G21 {}\nG10 L2 P2 X{ox:.6} Z{oz:.6}\nG55\nG92.1\nG0 X{:.9} Z{:.9}\n{}",
            if diameter { "G7" } else { "G8" },
            xw(s.0),
            s.1 - g92z,
            if g92z != 0.0 {
                format!("G92 Z{:.9}\n", s.1)
            } else {
                String::new()
            }
        );
        let g = if case % 4 < 2 { "G2" } else { "G3" };
        let abs = format!(
            "{head}G90.1 {g} X{:.9} Z{:.9} I{:.9} K{:.9} F100\nM2\n",
            xw(e.0),
            e.1,
            cr,
            cz
        );
        let inc = format!(
            "{head}G91.1 {g} X{:.9} Z{:.9} I{:.9} K{:.9} F100\nM2\n",
            xw(e.0),
            e.1,
            cr - s.0,
            cz - s.1
        );
        let (a, b) = (run(&abs), run(&inc));
        let (a, b) = (
            a.unwrap_or_else(|e| panic!("{abs}{e}")),
            b.unwrap_or_else(|e| panic!("{inc}{e}")),
        );
        assert_eq!(a.len(), b.len(), "{abs}");
        let arc = |m: &[Move]| m.iter().find(|m| m.kind == MoveKind::Arc).cloned().unwrap();
        let (p, q) = (arc(&a), arc(&b));
        let (pc, qc) = (p.arc.unwrap(), q.arc.unwrap());
        for (u, v) in [
            (p.x_dia, q.x_dia),
            (p.z, q.z),
            (pc.x_centre_dia, qc.x_centre_dia),
            (pc.z_centre, qc.z_centre),
        ] {
            assert!((u - v).abs() < 1e-6, "{abs}{p:?}\n{q:?}");
        }
    }
}

/// A named parameter a line sets exists (as 0) once its name is read, before the value:
/// `#<k> = [#<k> + 1]` counts from 0 (rs274 2.9.0~pre1, `add_named_param` in
/// `read_named_parameter_setting`). rs274's canon for the same lines: X1 X2 (counter),
/// X2 (global), X3 X3 (a local, fresh in each call), X1 (`#<a> = 2 #<c> = [#<a> + 1]`:
/// the line's settings take effect after it, so `#<a>` reads 0), and "Named parameter
/// #<a> not defined" where the value reads a name set later on the line, or never.
#[test]
fn a_parameter_being_set_reads_as_zero() {
    close(
        &xs("#<k> = [#<k> + 1]\nG0 X#<k>\n#<k> = [#<k> + 1]\nG0 X#<k>\n"),
        &[1.0, 2.0],
    );
    close(&xs("#<_g> = [#<_g> + 2]\nG0 X#<_g>\n"), &[2.0]);
    close(
        &xs("o1 sub\n#<loc> = [#<loc> + 3]\nG0 X#<loc>\no1 endsub\no1 call\nG0 X0\no1 call\n"),
        &[3.0, 0.0, 3.0],
    );
    close(&xs("#<a> = 2 #<c> = [#<a> + 1]\nG0 X#<c>\n"), &[1.0]);
    for text in ["#<c> = [#<a> + 1] #<a> = 2\n", "#<a> = [#<b> + 1]\n"] {
        let e = run(text).unwrap_err();
        assert!(e.message.contains("is not defined"), "{text}: {e}");
    }
}

/// rs274 2.9.0~pre1 changes tools with the spindle stopped (`STOP_SPINDLE_TURNING` before
/// `CHANGE_TOOL`) and refuses a synchronised move while the spindle stands: "Spindle not
/// turning in G33" (and G33.1), "Chosen spindle (0) not turning in G76" after `T3 M6`, after
/// M5, or before any M3; an M3 in the M6 block (run after the change) or after it starts it
/// again; feeds and the G7x cycles do not need it (each checked with `rs274 -g`).
#[test]
fn a_tool_change_stops_the_spindle() {
    let head = "G18 G21 G8 G95\nS500 M3 F0.2\nG0 X10 Z2\n";
    for (stop, block, says) in [
        ("T3 M6", "G33 Z-10 K1.5", "Spindle not turning in G33"),
        (
            "T3 M6",
            "G76 P1.5 Z-10 I-1 J0.2 K1",
            "Chosen spindle (0) not turning in G76",
        ),
        (
            "T3 M6",
            "G0 X0\nG33.1 Z-10 K1.5",
            "Spindle not turning in G33.1",
        ),
        ("M5", "G33 Z-10 K1.5", "Spindle not turning in G33"),
    ] {
        let e = run(&format!("{head}{stop}\n{block}\nM2\n")).unwrap_err();
        assert!(e.message.contains(says), "{stop} {block}: {e}");
        assert!(e.message.contains("M6"), "{e}");
    }
    let e = run("G18 G21 G8 S500\nG0 X10 Z2\nG33 Z-10 K1.5\n").unwrap_err();
    assert!(e.message.contains("Spindle not turning in G33"), "{e}");
    for after in [
        "T3 M6 M3\nG33 Z-10 K1.5",
        "T3 M6\nM3\nG33 Z-10 K1.5",
        "T3 M6\nG1 Z-10",
    ] {
        let m = run(&format!("{head}{after}\nM2\n")).unwrap_or_else(|e| panic!("{after}: {e}"));
        assert_eq!(m.last().unwrap().z, -10.0, "{after}");
    }
}

/// M70..M73 (rs274 2.9.0~pre1's canon for the same program): a sub's M73 brings the
/// caller's G21, G90, G7, F0.25 (written back as `F%.1f`: 0.2), S600 and M3 back at its
/// endsub; M70 then M72 restore G90 G7, F0.2 (from 0.12) and M3 (from M5). Moves: X10 Z2
/// rapid, the sub's G0 X0.1 Z0.1 in G20 G91 G8 to radius 12.54 z 4.54, then G1 X22 Z0 (r 11,
/// diameter mode again), G1 X1 in G91 G8 (r 12), G1 X24 Z-2 (r 12, G90 G7). M72 with no
/// M70 before, or after M71, is rs274's error.
#[test]
fn m70_to_m73_save_and_restore_the_modes() {
    let text = "G18 G21 G7 G95 G90\nF0.25 S600 M3\no<thread> sub\n  M73\n  G20 G91 G8 F0.01 S300 M4\n  G0 X0.1 Z0.1\no<thread> endsub\nG0 X20 Z2\no<thread> call\nG1 X22 Z0\nM70\nG91 G8 F0.12 M5\nG1 X1\nM72\nG1 X24 Z-2\nM2\n";
    let m = run(text).unwrap_or_else(|e| panic!("{e}"));
    let ends: Vec<(f64, f64)> = m.iter().map(|m| (m.x_dia / 2.0, m.z)).collect();
    let want = [
        (10.0, 2.0),
        (12.54, 4.54),
        (11.0, 0.0),
        (12.0, 0.0),
        (12.0, -2.0),
    ];
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (g, w) in ends.iter().zip(want) {
        assert!(
            (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
            "{ends:?}"
        );
    }
    let feeds: Vec<Option<f64>> = m.iter().map(|m| m.feed.map(|f| f.value)).collect();
    assert_eq!(feeds[2], Some(0.2), "restored as F%.1f: {feeds:?}");
    assert_eq!(feeds[3], Some(0.12));
    assert_eq!(feeds[4], Some(0.2));
    assert_eq!(m[1].spindle, crate::model::helix::Spindle::Ccw);
    assert_eq!(m[2].spindle, crate::model::helix::Spindle::Cw);
    for bad in ["F1\nM72\n", "F1\nM70\nM71\nM72\n"] {
        let e = run(bad).unwrap_err();
        assert!(e.message.contains("missing M70/M73"), "{bad}: {e}");
    }
}

/// `o[expression] call` (LinuxCNC manual, O Codes, "Indirection"; rs274 2.9.0~pre1): the
/// number is computed when the line runs and must be whole within 1e-4 ("Non integer value
/// for integer"); `o[101] sub` with a constant works where it is defined. A computed label
/// of `if` or a loop, which rs274 runs too, is refused by name.
#[test]
fn indirect_o_word_calls() {
    close(
        &xs("o101 sub\nG0 X#1 Z1\no101 endsub\n#2 = 100\no[#2 + 1] call [7]\n"),
        &[7.0],
    );
    close(
        &xs("o[101] sub\nG0 X#1 Z1\no[101] endsub\no101 call [3]\n"),
        &[3.0],
    );
    close(
        &xs("o101 sub\nG0 X#1 Z1\no101 endsub\no[101.00005] call [5]\n"),
        &[5.0],
    );
    let e = run("o101 sub\nG0 X#1 Z1\no101 endsub\no[101.4] call [7]\n").unwrap_err();
    assert!(e.message.contains("Non integer value for integer"), "{e}");
    let e = run("#1 = 5\no[#1] if [1]\nG0 X2\no[#1] endif\n").unwrap_err();
    assert!(e.message.contains("call only"), "{e}");
}

/// Tool table words (rs274 2.9.0~pre1's canon): G10 L1/L10/L11, G43.1 and G43.2 send
/// offsets to the machine (`USE_TOOL_LENGTH_OFFSET`) and the tip follows the program (G43.1
/// X1 Z2 makes no move; the next G0 X10 Z5 goes to X10 Z5); G42.1 D0 moves as programmed,
/// G41.1 D0.8 L2 compensates with radius 0.4 and orientation 2 (rs274's canon);
/// a radius set with G10 L1 R makes rs274 offset a G42 path (rs274 2.9.0~pre1: X10 Z0 from
/// X10 Z5 with R0.4 and orientation 0 is fed to X10.4 Z0), as vpcut does (`nose`); G42.1
/// without D is rs274's "G42.1 with no D word".
#[test]
fn tool_table_words_leave_the_tip_on_the_program() {
    let m = run("G18 G21 G8 F100\nG0 X10 Z5\nG43.1 X1 Z2\nG0 X12 Z5\nG1 Z0\nG49\n").unwrap();
    let ends: Vec<(f64, f64)> = m.iter().map(|m| (m.x_dia / 2.0, m.z)).collect();
    assert_eq!(ends, [(10.0, 5.0), (12.0, 5.0), (12.0, 0.0)]);
    let m = run("G18 G21 G8 F100\nG10 L1 P3 X1 Z2 R0\nT3 M6 G43\nG10 L10 P3 Z4\nG43.2 H4\nG0 X10 Z5\nG42.1 D0 L2\nG1 X12 Z0\nG40\n").unwrap();
    let ends: Vec<(f64, f64)> = m.iter().map(|m| (m.x_dia / 2.0, m.z)).collect();
    assert_eq!(ends, [(10.0, 5.0), (12.0, 0.0)]);
    let m = run("G18 G21 G8 F100\nG10 L1 P3 R0.4\nT3 M6\nG0 X10 Z5\nG42\nG1 X10 Z0\n").unwrap();
    let ends: Vec<(f64, f64)> = m.iter().map(|m| (m.x_dia / 2.0, m.z)).collect();
    assert_eq!(ends.len(), 2, "{ends:?}");
    assert!(
        (ends[1].0 - 10.4).abs() < 1e-9 && ends[1].1.abs() < 1e-9,
        "{ends:?}"
    );
    let e = run("G18 G21 G8 F100\nG0 X10 Z5\nG42.1\n").unwrap_err();
    assert!(e.message.contains("G42.1 with no D word"), "{e}");
    // G41.1 D0.8 L2: radius 0.4, orientation 2 (rs274: X10 Z0 from X10 Z5 is fed to
    // X9.2 Z-0.4).
    let m = run("G18 G21 G8 F100\nG0 X10 Z5\nG41.1 D0.8 L2\nG1 X10 Z0\n").unwrap();
    let end = (m[1].x_dia / 2.0, m[1].z);
    assert!(
        (end.0 - 9.2).abs() < 1e-9 && (end.1 + 0.4).abs() < 1e-9,
        "{end:?}"
    );
}

/// G70 under G42 (rs274 2.9.0~pre1 runs it, each pass's rapid to its start made with
/// compensation off): with a tool of radius 0 the moves are the contour's; with a nonzero
/// radius (G10 L1 R0.8) vpcut refuses it at the G70 block rather than compensate it
/// otherwise than rs274.
#[test]
fn g70_under_compensation_runs_at_radius_zero_and_is_refused_otherwise() {
    let body = "T1 M6 S800 M3 F0.25\nG0 X52 Z3\nG42\nG70 Q100 X52 Z3 P1\nG40\nG0 X80 Z50\nM2\no100 sub\nG0 X0 Z2\nG1 Z0\nG1 X16\nG1 Z-20\nG1 X50\nG1 Z-70\no100 endsub\n";
    let m = run(&format!("G18 G21 G7 G95 G40 G90\n{body}")).unwrap();
    assert!(
        m.iter()
            .any(|m| (m.x_dia - 16.0).abs() < 1e-9 && (m.z + 20.0).abs() < 1e-9),
        "the contour's corner X16 Z-20 is made as programmed"
    );
    let e = run(&format!(
        "G18 G21 G7 G95 G40 G90\nG10 L1 P1 R0.8 Q3\n{body}"
    ))
    .unwrap_err();
    assert_eq!(e.line, 6, "{e}");
    assert!(e.message.contains("G70 under cutter compensation"), "{e}");
}
