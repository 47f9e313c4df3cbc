//! Tests of issue 17 ("real programs run end to end"): LinuxCNC predefined and system
//! parameters, G53, G28/G30, G92 and G10 L2/L20, G80, G96 D; FANUC `;` end of block and
//! `%O1200` headers; G-code systems B and C; the one-block G76 of Haas and 0T controls.
//! Expected values are derived by hand in the comments from the manuals' semantics
//! (`/work/shared/reference/controllers.md`, LinuxCNC's G-code manual).

use crate::nc::{interpret_with, Dialect, MoveKind, Options, Settings, Source, Toolpath};

fn run_s(text: &str, dialect: Dialect, settings: Settings) -> Toolpath {
    let src = Source {
        name: "t.nc".into(),
        text: text.into(),
    };
    let opts = Options {
        settings,
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts).unwrap_or_else(|e| panic!("{text}\n{e}"))
}

fn run(text: &str, dialect: Dialect) -> Toolpath {
    run_s(text, dialect, Settings::in_mm())
}

/// The end points (x_dia, z) of every move.
fn ends(t: &Toolpath) -> Vec<(f64, f64)> {
    t.moves.iter().map(|m| (m.x_dia, m.z)).collect()
}

/// The value of a LinuxCNC expression after `setup`, read as the X (diameter, G7) of a G0
/// move from X1.
fn lc_value(setup: &str, expr: &str) -> f64 {
    let text = format!("{setup}\nG7\nG0 X[{expr}]\n");
    let t = run(&text, Dialect::Linuxcnc);
    t.moves.last().expect("a move").x_dia
}

#[test]
fn linuxcnc_predefined_parameters_read_the_state() {
    let cases: [(&str, &str, f64); 41] = [
        ("", "#<_vmajor>*10+#<_vminor>", 29.0),
        ("", "#<_metric>", 1.0),
        // (In G20 the X word is in inches: 1 reads 25.4 mm.)
        ("G20", "#<_imperial>", 25.4),
        ("G20", "#<_metric>", 0.0),
        ("", "#<_absolute>", 1.0),
        ("G91", "#<_incremental>+#<_absolute>*10", 1.0),
        ("", "#<_units_per_minute>", 1.0),
        ("G95", "#<_units_per_rev>", 1.0),
        ("G93", "#<_inverse_time>", 1.0),
        ("", "#<_coord_system>", 540.0),
        ("G55", "#<_coord_system>", 550.0),
        ("G59.2", "#<_coord_system>", 592.0),
        ("G43", "#<_tool_offset>", 1.0),
        ("", "#<_retract_r_plane>*10+#<_retract_old_z>", 10.0),
        ("G98", "#<_retract_r_plane>*10+#<_retract_old_z>", 1.0),
        ("", "#<_spindle_rpm_mode>", 1.0),
        ("G96 D2000 S100", "#<_spindle_css_mode>", 1.0),
        ("G90.1", "#<_ijk_absolute_mode>", 1.0),
        // (The helper's G7 runs before the read.)
        ("", "#<_lathe_radius_mode>", 0.0),
        ("G7", "#<_lathe_diameter_mode>", 1.0),
        ("M3 S500", "#<_spindle_on>*10+#<_spindle_cw>", 11.0),
        ("M4 S500", "#<_spindle_on>*10+#<_spindle_cw>", 10.0),
        ("M3 S500\nM5", "#<_spindle_on>", 0.0),
        ("M7 M8", "#<_mist>*10+#<_flood>", 11.0),
        ("M7 M8\nM9", "#<_mist>+#<_flood>", 0.0),
        ("", "#<_speed_override>*10+#<_feed_override>", 11.0),
        ("M49", "#<_speed_override>+#<_feed_override>", 0.0),
        ("", "#<_adaptive_feed>+#<_feed_hold>", 0.0),
        ("F150", "#<_feed>", 150.0),
        ("S800", "#<_rpm>", 800.0),
        ("", "#<_selected_tool>", -1.0),
        ("T3 M6", "#<_current_tool>*10+#<_selected_tool>", 33.0),
        ("", "#<_task>*10+#<_remap_level>", 10.0),
        ("", "#<_call_level>", 0.0),
        ("", "#<_line>", 3.0),
        ("G0 X10 Z5", "#<_z>", 5.0),
        // rs274 2.9.0~pre1 reads the current X as a radius in G7 too (`G7 G0 X25` then
        // `G0 X[100+#<_x>]` goes to X112.5): G8 X10 reads 10; G7 X30 reads 15.
        ("G8 G0 X10 Z5", "#<_x>", 10.0),
        ("G7 G0 X30 Z5", "#<_x>*100+#<_abs_x>", 1515.0),
        ("G10 L2 P1 Z100\nG0 Z5", "#<_abs_z>*1000+#<_z>", 105005.0),
        ("", "#<_y>+#<_a>+#<_abs_c>", 0.0),
        ("G0 Z3\nG1 F10 Z2", "#<_motion_mode>", 10.0),
    ];
    for (setup, expr, want) in cases {
        let got = lc_value(setup, expr);
        assert!(
            (got - want).abs() < 1e-9,
            "{setup} / {expr}: {got} != {want}"
        );
    }
}

#[test]
fn linuxcnc_numbered_system_parameters() {
    let s = Settings {
        reference_point: Some((300.0, 200.0)),
        ..Settings::in_mm()
    };
    let value = |setup: &str, expr: &str| -> f64 {
        let text = format!("G7\n{setup}\nG0 X1\nG0 X[{expr}]\n");
        run_s(&text, Dialect::Linuxcnc, s.clone())
            .moves
            .last()
            .expect("a move")
            .x_dia
    };
    let cases: [(&str, &str, f64); 12] = [
        // The job's reference point is G28's home.
        ("", "#5161", 300.0),
        ("", "#5163", 200.0),
        ("", "#5181+#5183", 0.0),
        ("G0 X40 Z7\nG30.1", "#5181*100+#5183", 4007.0),
        ("#5163=12", "#5163", 12.0),
        // The current Z0 reads Z10: the offset is -10.
        ("G92 Z10", "#5210*100+#5213", 90.0),
        ("G56", "#5220", 3.0),
        ("G10 L2 P2 X4 Z-50", "#5241*1000+#5243", 3950.0),
        ("G10 L2 P9 Z-7", "#5383", -7.0),
        ("T5 M6", "#5400", 5.0),
        // After the helper's G7 G0 X1: X reads as the radius 0.5 (rs274, see `#<_x>`).
        ("G0 X30 Z9", "#5420*100+#5422", 59.0),
        // L20: Z0 (machine) reads Z2, so G54's Z offset is -2.
        ("G10 L20 P1 Z2\nG0 Z0", "#5422*100+#<_abs_z>", -2.0),
    ];
    for (setup, expr, want) in cases {
        let got = value(setup, expr);
        assert!(
            (got - want).abs() < 1e-9,
            "{setup} / {expr}: {got} != {want}"
        );
    }
}

#[test]
fn linuxcnc_offsets_homes_and_machine_coordinates() {
    let s = Settings {
        reference_point: Some((100.0, 50.0)),
        ..Settings::in_mm()
    };
    // (program, end points (x_dia, z) in machine coordinates of every move)
    let cases: [(&str, Vec<(f64, f64)>); 8] = [
        // G53: machine coordinates for one block, then G54's offset again.
        (
            "G7 G10 L2 P1 X0 Z-100\nG0 X20 Z5\nG53 G0 X60 Z0\nG0 Z1",
            vec![(20.0, -95.0), (60.0, 0.0), (60.0, -99.0)],
        ),
        // G28 without axes: all axes home in one rapid.
        ("G7 G0 X20 Z5\nG28", vec![(20.0, 5.0), (100.0, 50.0)]),
        // G28 with X: through the intermediate point, then X only home.
        (
            "G7 G0 X20 Z5\nG28 X30",
            vec![(20.0, 5.0), (30.0, 5.0), (100.0, 5.0)],
        ),
        // G30 goes to #5181.. (set by a program here).
        // (Parameters are set after the line is read, before its G7 runs: on a line of
        // their own.)
        ("G7\n#5181=10 #5183=20\nG30", vec![(10.0, 20.0)]),
        // G92: the current point reads Z0 from then on; G92.1 cancels it.
        (
            "G7 G0 X20 Z5\nG92 Z0\nG0 Z-2\nG92.1\nG0 Z-2",
            vec![(20.0, 5.0), (20.0, 3.0), (20.0, -2.0)],
        ),
        // G92.2 suspends and G92.3 restores the offset.
        (
            "G7 G0 Z5\nG92 Z0\nG92.2\nG0 Z1\nG92.3\nG0 Z1",
            vec![(0.0, 5.0), (0.0, 1.0), (0.0, 6.0)],
        ),
        // G10 L20: the current point reads X10 Z0 in G55, then used.
        (
            "G7 G0 X40 Z30\nG10 L20 P2 X10 Z0\nG55 G0 X0 Z-1",
            vec![(40.0, 30.0), (30.0, 29.0)],
        ),
        // G80 is a no-op, G96 D the CSS spindle limit.
        (
            "G18 G7 G90 G40 G80\nG96 D1500 S120 M3\nG0 X10 Z2",
            vec![(10.0, 2.0)],
        ),
    ];
    for (text, want) in cases {
        let got = ends(&run_s(text, Dialect::Linuxcnc, s.clone()));
        assert_eq!(got.len(), want.len(), "{text}: {got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
                "{text}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn linuxcnc_codes_refused_by_name() {
    let cases: [(&str, &str); 5] = [
        ("G10 L3 P1 Z2\n", "G10 L3 (other data) is not simulated"),
        ("G91 G53 G0 X1\n", "G53 needs absolute coordinates"),
        ("G92\n", "G92 needs X or Z"),
        ("#5221=3\n", "assigning #5221 (offsets) is not simulated"),
        ("G0 X#5399\n", "#5399 is not modelled"),
    ];
    for (text, msg) in cases {
        let src = Source {
            name: "t.ngc".into(),
            text: text.into(),
        };
        let e = interpret_with(
            &src,
            Dialect::Linuxcnc,
            &|_| None,
            &Options {
                settings: Settings::in_mm(),
                ..Options::default()
            },
        )
        .unwrap_err();
        assert!(e.message.contains(msg), "{text}: {e}");
    }
}

#[test]
fn fanuc_semicolon_ends_a_block_and_percent_headers() {
    // One line of tape with `;` as EOB; a `%O1200(..)` header; a `;` inside a comment.
    let cases: [(&str, usize, usize); 4] = [
        ("%;O1200;G0 X30 Z5;G32 Z-20 F1.5;G0 X40;M30;%", 3, 1),
        (
            "%O1200(M20 THREAD; OD)\nG0 X30 Z5;\nG32 Z-20 F1.5;\nG0 X40;\nM30;\n%\n",
            3,
            1,
        ),
        (
            "O1200 (A; B)\nG0 X30 Z5 ; G32 Z-20 F1.5 ; G0 X40\nM30\n",
            3,
            1,
        ),
        // G92: rapid in, thread, rapid out, rapid back: 4 moves a pass.
        (
            "%\nO0001;\nG0 X30 Z5;G92 X19 Z-20 F1.5;X18.5;G0 X40;M30;\n",
            10,
            2,
        ),
    ];
    for (text, n, threads) in cases {
        for d in [Dialect::Fanuc, Dialect::Gsk980] {
            let t = run(text, d);
            assert_eq!(t.moves.len(), n, "{text}: {:?}", ends(&t));
            let th = t
                .moves
                .iter()
                .filter(|m| m.kind == MoveKind::Thread)
                .count();
            assert_eq!(th, threads, "{text}");
        }
    }
    // Columns stay those of the file: the third block of line 1.
    let src = Source {
        name: "t.nc".into(),
        text: "G0 X30;G0 Z5;G0 Q@\n".into(),
    };
    let e = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap_err();
    assert_eq!((e.line, e.col), (1, 18), "{e}");
}

#[test]
fn fanuc_gcode_systems_b_and_c_read_as_system_a() {
    use crate::nc::GcodeSystem::{B, C};
    // (system, program in it, the same program in system A)
    let cases = [
        (
            B,
            "G0 X30 Z5\nG78 X19 Z-20 F1.5\nX18.5\nG0 X40\nM30\n",
            "G0 X30 Z5\nG92 X19 Z-20 F1.5\nX18.5\nG0 X40\nM30\n",
        ),
        (
            C,
            "G0 X30 Z5\nG21 X19 Z-20 F1.5\nX18.5\nG0 X40\nM30\n",
            "G0 X30 Z5\nG92 X19 Z-20 F1.5\nX18.5\nG0 X40\nM30\n",
        ),
        (
            B,
            "G92 X100 Z50\nG0 X24 Z5\nG33 Z-20 F2\nG91 G0 X6\nZ25\nG90 G0 X10\nM30\n",
            "G50 X100 Z50\nG0 X24 Z5\nG32 Z-20 F2\nG0 U6\nW25\nG0 X10\nM30\n",
        ),
        (
            B,
            "G0 X40 Z2\nG95 G77 X30 Z-10 F0.2\nM30\n",
            "G0 X40 Z2\nG99 G90 X30 Z-10 F0.2\nM30\n",
        ),
        (
            C,
            "G0 X40 Z2\nG20 X30 Z-10 F0.2\nG24 X20 Z-1 F0.2\nM30\n",
            "G0 X40 Z2\nG90 X30 Z-10 F0.2\nG94 X20 Z-1 F0.2\nM30\n",
        ),
        (
            C,
            "G70\nG0 X1.2 Z0.2\nG33 Z-1 F0.1\nG71\nG0 X40\nM30\n",
            "G20\nG0 X1.2 Z0.2\nG32 Z-1 F0.1\nG21\nG0 X40\nM30\n",
        ),
        (
            C,
            "G0 X30 Z5\nG78 P010060 Q100 R0.05\nG78 X24 Z-20 P1000 Q600 F2\nM30\n",
            "G0 X30 Z5\nG76 P010060 Q100 R0.05\nG76 X24 Z-20 P1000 Q600 F2\nM30\n",
        ),
        (
            B,
            "G0 X30 Z5\nG76 P010060 Q100 R0.05\nG91 G76 X-6 Z-25 P1000 Q600 F2\nM30\n",
            "G0 X30 Z5\nG76 P010060 Q100 R0.05\nG76 X24 Z-20 P1000 Q600 F2\nM30\n",
        ),
    ];
    for (system, text, in_a) in cases {
        let s = Settings {
            gcode_system: system,
            ..Settings::in_mm()
        };
        let got = run_s(text, Dialect::Fanuc, s);
        let want = run(in_a, Dialect::Fanuc);
        assert!(!want.moves.is_empty());
        assert_eq!(ends(&got), ends(&want), "{system:?}: {text}");
        let kinds = |t: &Toolpath| t.moves.iter().map(|m| m.kind).collect::<Vec<_>>();
        assert_eq!(kinds(&got), kinds(&want), "{system:?}: {text}");
        assert!(got.warnings.is_empty(), "{text}: {:?}", got.warnings);
    }
}

#[test]
fn one_block_g76_of_haas_and_0t() {
    // (program, thread moves, x_dia and z_start of the first thread move)
    let t60 = (30f64.to_radians()).tan();
    let cases: [(&str, usize, f64, f64); 5] = [
        // D sqrt(n) < K: 0.5, 0.707, 0.866, 1.0, 1.118, then K = 1.2: 6 passes; the first
        // 2(1.2 - 0.5) = 1.4 over the root X24, radial (A0).
        ("G0 X30 Z5\nG76 X24 Z-20 K1.2 D0.5 F2\nM30\n", 6, 25.4, 5.0),
        // The same in the least input increment (0T: no decimal point, um).
        ("G0 X30 Z5\nG76 X24 Z-20 K1200 D500 F2\nM30\n", 6, 25.4, 5.0),
        // P3: constant depth n D: 0.3, 0.6, 0.9, then 1.2.
        (
            "G0 X30 Z5\nG76 X24 Z-20 K1.2 D0.3 F2 P3\nM30\n",
            4,
            24.0 + 2.0 * 0.9,
            5.0,
        ),
        // A60, one flank: the first pass stands back 0.7 and is shifted 0.7 tan 30 away
        // from the cut (towards +Z when cutting towards -Z).
        (
            "G0 X30 Z5\nG76 X24 Z-20 K1.2 D0.5 F2 A60\nM30\n",
            6,
            25.4,
            5.0 + 0.7 * t60,
        ),
        // Haas's example (inches): K/D = 4, so D sqrt(n) < K for n = 1..15, then K: 16.
        (
            "G20\nG0 X0.5 Z0.2\nG76 X0.4069 Z-1.5 K0.043075 D0.01076875 F0.0769\nM30\n",
            16,
            (0.4069 + 2.0 * (0.043075 - 0.01076875)) * 25.4,
            0.2 * 25.4,
        ),
    ];
    for (text, n, x, z) in cases {
        let t = run(text, Dialect::Fanuc);
        let th: Vec<_> = t
            .moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect();
        assert_eq!(th.len(), n, "{text}");
        assert!((th[0].x_dia - x).abs() < 1e-9, "{text}: {}", th[0].x_dia);
        assert!(
            (th[0].z_start - z).abs() < 1e-9,
            "{text}: {}",
            th[0].z_start
        );
        // Every pass ends at the last one's depth or above it, the last at the root X.
        assert!((th[n - 1].x_dia - th[n - 1].x_dia.min(x)).abs() < 1e-9);
        assert!(t.warnings.is_empty(), "{text}: {:?}", t.warnings);
    }
    // P2: the flanks alternate.
    let t = run(
        "G0 X30 Z5\nG76 X24 Z-20 K1.2 D0.5 F2 A60 P2\nM30\n",
        Dialect::Fanuc,
    );
    let th: Vec<_> = t
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect();
    assert!(th[0].z_start > 5.0 && th[1].z_start < 5.0, "{:?}", ends(&t));
    // K without D (or D without K) is refused by name.
    let src = Source {
        name: "t.nc".into(),
        text: "G0 X30 Z5\nG76 X24 Z-20 K1.2 F2\n".into(),
    };
    let e = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap_err();
    assert!(e.message.contains("needs D"), "{e}");
}

#[test]
fn linuxcnc_tapered_g33_k_is_along_the_path() {
    // (program in G8, K, radial rise, z travel)
    let cases: [(&str, f64, f64, f64); 3] = [
        ("G8 G0 X10 Z2 M3\nG33 X12 Z-18 K2\n", 2.0, 2.0, 20.0),
        ("G8 G0 X10 Z2 M3\nG33 X9 Z-8 K1.5\n", 1.5, 1.0, 10.0),
        ("G8 G0 X10 Z2 M3\nG33 Z-8 K1.5\n", 1.5, 0.0, 10.0),
    ];
    for (text, k, rise, travel) in cases {
        let t = run(text, Dialect::Linuxcnc);
        let m = t.moves.iter().find(|m| m.kind == MoveKind::Thread).unwrap();
        let want = k * travel / rise.hypot(travel);
        assert!(
            (m.lead.unwrap() - want).abs() < 1e-12,
            "{text}: {:?}",
            m.lead
        );
        assert!(
            (crate::nc::path_lead(m).unwrap() - k).abs() < 1e-12,
            "{text}"
        );
    }
}

#[test]
fn fanuc_g53_moves_in_machine_coordinates_at_rapid() {
    let mut s = Settings::in_mm();
    s.work_offsets[0] = (0.0, -100.0);
    let t = run_s(
        "G0 X30 Z5\nG1 F0.2 Z2\nG53 X100 Z0\nG53 X40\nG0 Z1\nM30\n",
        Dialect::Fanuc,
        s,
    );
    let kinds: Vec<MoveKind> = t.moves.iter().map(|m| m.kind).collect();
    assert_eq!(
        ends(&t),
        vec![
            (30.0, -95.0),
            (30.0, -98.0),
            (100.0, 0.0),
            (40.0, 0.0),
            (40.0, -99.0)
        ]
    );
    assert_eq!(kinds[2], MoveKind::Rapid);
    assert_eq!(kinds[3], MoveKind::Rapid);
}

#[test]
fn fanuc_g30_goes_to_the_second_reference_point() {
    let s = Settings {
        reference_point: Some((300.0, 200.0)),
        second_reference_point: Some((150.0, 100.0)),
        ..Settings::in_mm()
    };
    // (program, end points) from (X30, Z5): the intermediate point, then the named axes.
    let cases: [(&str, Vec<(f64, f64)>); 3] = [
        ("G0 X30 Z5\nG30 U0 W0\n", vec![(30.0, 5.0), (150.0, 100.0)]),
        (
            "G0 X30 Z5\nG30 P2 U10\n",
            vec![(30.0, 5.0), (40.0, 5.0), (150.0, 5.0)],
        ),
        (
            "G0 X30 Z5\nG28 W0\nG30 U0\n",
            vec![(30.0, 5.0), (30.0, 200.0), (150.0, 200.0)],
        ),
    ];
    for (text, want) in cases {
        assert_eq!(
            ends(&run_s(text, Dialect::Fanuc, s.clone())),
            want,
            "{text}"
        );
    }
    // Without the key: the machine zero. P3 is refused by name.
    assert_eq!(
        ends(&run("G0 X30 Z5\nG30 U0 W0\n", Dialect::Fanuc)),
        vec![(30.0, 5.0), (0.0, 0.0)]
    );
    let src = Source {
        name: "t.nc".into(),
        text: "G30 P3 U0\n".into(),
    };
    let e = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap_err();
    assert!(e.message.contains("G30 P3"), "{e}");
}

#[test]
fn a_long_line_of_blocks_runs_every_block() {
    // Blocks far into a line count their columns from their own start (the padding that
    // keeps columns is bounded, so a line of many blocks costs what its length does).
    let text = "G0 X1 Z1;G0 X2 Z2;".repeat(500);
    let t = run(&text, Dialect::Fanuc);
    assert_eq!(t.moves.len(), 1000);
    let src = Source {
        name: "t.nc".into(),
        text: format!("{text}G0 Q@\n"),
    };
    let e = interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap_err();
    assert_eq!((e.line, e.col), (1, 5), "{e}");
}
