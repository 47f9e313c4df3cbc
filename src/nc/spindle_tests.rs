//! The machine as the program sets it: spindle speeds (G96/G97, G50 S and LIMS clamps),
//! tool offsets (T0305, T0300, Siemens D) and dwells, against values derived by hand.

use super::*;
use std::collections::BTreeMap;

fn run_with(text: &str, dialect: Dialect, settings: Settings) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        settings,
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts)
}

fn run(text: &str, dialect: Dialect) -> Toolpath {
    run_with(text, dialect, Settings::in_mm()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn g96_turns_at_its_surface_speed_within_the_g50_clamp() {
    // G96 S180 (m/min) at X19.8: n = 1000 x 180 / (pi x 19.8) = 2893.7 rev/min; at X40:
    // 1432.4; under G50 S2500 the first is clamped to 2500. G97 S600 is 600 anywhere.
    let t = run(
        "G50 S2500\nG96 S180 M03\nG0 X40 Z2\nG1 X19.8 F0.2\nG97 S600\nG0 X30\nM30\n",
        Dialect::Fanuc,
    );
    let m = &t.moves;
    let n = |x: f64| 1000.0 * 180.0 / (std::f64::consts::PI * x);
    assert_eq!(m[0].speed.surface, Some(180.0));
    assert_eq!(m[0].speed.max, Some(2500.0));
    assert!((m[0].speed.at(40.0).unwrap() - n(40.0)).abs() < 1e-9);
    assert!((n(40.0) - 1432.3945).abs() < 1e-4);
    assert_eq!(m[1].speed.at(19.8), Some(2500.0));
    assert!(n(19.8) > 2500.0);
    assert_eq!(m[2].speed.at(30.0), Some(600.0));
    assert_eq!(m[2].speed.surface, None);
    // G50 S is a clamp, never the speed: before any other S there is none.
    let t = run("G50 S2000\nG0 X40 Z2\nM30\n", Dialect::Fanuc);
    assert_eq!(t.moves[0].speed.at(40.0), None);
    // The feed of a feed move: F in mm/rev (G99) or mm/min (G98); inch F in mm.
    let t = run(
        "G99 G0 X40 Z2\nG1 Z-10 F0.25\nG98 G1 Z-20 F120\nG20 G99 G1 W-0.5 F0.01\nM30\n",
        Dialect::Fanuc,
    );
    let f: Vec<_> = t.moves.iter().map(|m| m.feed).collect();
    assert_eq!(
        f[1],
        Some(Feed {
            value: 0.25,
            per_rev: true
        })
    );
    assert_eq!(
        f[2],
        Some(Feed {
            value: 120.0,
            per_rev: false
        })
    );
    assert!((f[3].unwrap().value - 0.254).abs() < 1e-12 && f[3].unwrap().per_rev);
}

#[test]
fn g97_without_s_keeps_the_speed_the_spindle_turns_at() {
    // G96 S150 at X50 turns at 1000 x 150 / (pi x 50) = 954.93 rev/min; a G97 there
    // without S keeps it.
    let t = run("G96 S150\nG0 X50 Z2\nG97\nG0 Z5\nM30\n", Dialect::Fanuc);
    let want = 1000.0 * 150.0 / (std::f64::consts::PI * 50.0);
    assert!((t.moves[1].speed.rpm.unwrap() - want).abs() < 1e-9);
    // Inch G96 S is ft/min: S500 at X2.0 in is 12 x 500 / (pi x 2) = 954.93 rev/min.
    let t = run("G20 G96 S500\nG0 X2.0 Z0.1\nM30\n", Dialect::Fanuc);
    let n = t.moves[0].speed.at(t.moves[0].x_dia).unwrap();
    assert!(
        (n - 12.0 * 500.0 / (std::f64::consts::PI * 2.0)).abs() < 1e-6,
        "{n}"
    );
    // Siemens LIMS= and LinuxCNC G96 D are the clamps there.
    let t = run("G96 S200 LIMS=1800\nG0 X10 Z2\nM30\n", Dialect::Siemens802d);
    assert_eq!(t.moves[0].speed.at(10.0), Some(1800.0));
    let t = run("G7\nG96 D1500 S100\nG0 X10 Z2\nM2\n", Dialect::Linuxcnc);
    assert_eq!(t.moves[0].speed.max, Some(1500.0));
}

fn offsets(list: &[(u32, f64, f64)]) -> Settings {
    Settings {
        tool_offsets: Some(
            list.iter()
                .map(|&(n, x, z)| (n, (x, z)))
                .collect::<BTreeMap<_, _>>(),
        ),
        ..Settings::in_mm()
    }
}

#[test]
fn a_tool_offset_moves_the_tool_from_the_next_motion_on_and_t0300_cancels_it() {
    // Offset 5 = (X -0.1, Z +0.02): T0305 selects tool 3 with it; the next move ends at the
    // programmed point plus the offset and starts where the last one ended (the control
    // applies an offset with the next motion); T0300 cancels it with its next move.
    let text = "G0 X40 Z5\nT0305\nG0 X30 Z2\nG1 Z-10 F0.2\nT0300\nG0 X50\nM30\n";
    let t = run_with(text, Dialect::Fanuc, offsets(&[(5, -0.1, 0.02)])).unwrap();
    let p: Vec<_> = t
        .moves
        .iter()
        .map(|m| (m.x_start, m.z_start, m.x_dia, m.z, m.tool))
        .collect();
    assert_eq!(p[0], (0.0, 0.0, 40.0, 5.0, None));
    assert_eq!(p[1], (40.0, 5.0, 29.9, 2.02, Some(3)));
    assert_eq!(p[2], (29.9, 2.02, 29.9, -9.98, Some(3)));
    assert_eq!(p[3], (29.9, -9.98, 50.0, -10.0, Some(3)));
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    // An arc's centre moves with it.
    let t = run_with(
        "T0305\nG0 X20 Z0\nG3 X24 Z-2 R2 F0.1\nM30\n",
        Dialect::Fanuc,
        offsets(&[(5, -0.1, 0.02)]),
    )
    .unwrap();
    let a = t.moves[1].arc.unwrap();
    assert!(
        (a.x_centre_dia - (20.0 - 0.1)).abs() < 1e-12 && (a.z_centre - (-2.0 + 0.02)).abs() < 1e-12
    );
}

#[test]
fn an_offset_the_job_lacks_is_a_warning_at_its_block_and_zero() {
    let text = "G0 X40 Z5\nT0306\nG0 X30 Z2\nM30\n";
    let t = run_with(text, Dialect::Fanuc, offsets(&[(5, -0.1, 0.0)])).unwrap();
    assert_eq!(t.moves[1].x_dia, 30.0);
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    let w = &t.warnings[0];
    assert_eq!((w.line, w.severity), (2, Severity::Warning));
    assert!(w.message.contains("tool offset 6"), "{}", w.message);
    // Strict or not, it stays a warning (not an unknown word).
    let opts = Options {
        strict: true,
        settings: offsets(&[(5, -0.1, 0.0)]),
        ..Options::default()
    };
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    assert_eq!(
        interpret_with(&src, Dialect::Fanuc, &|_| None, &opts)
            .unwrap()
            .warnings
            .len(),
        1
    );
    // Without a table every offset is zero and nothing is said.
    let t = run(text, Dialect::Fanuc);
    assert!(t.warnings.is_empty());
    // Siemens D2 calls offset 2; D0 cancels.
    let t = run_with(
        "T1 D2\nG0 X30 Z2\nD0\nG0 X40\nM30\n",
        Dialect::Siemens802d,
        offsets(&[(2, 0.4, -0.1)]),
    )
    .unwrap();
    assert_eq!((t.moves[0].x_dia, t.moves[0].z), (30.4, 1.9));
    assert_eq!((t.moves[1].x_dia, t.moves[1].z), (40.0, 2.0));
}

#[test]
fn a_dwell_waits_without_moving() {
    // GSK/FANUC G04 X1 (seconds) after a plunge: the tool stays at X23.5 (it used to be
    // read as a move to X1); P500 is 500 ms; Siemens G4 S3 is three revolutions.
    let t = run(
        "G0 X30 Z-30\nG1 X23.5 F0.1\nG04 X1\nG04 P500\nG0 X30\nM30\n",
        Dialect::Fanuc,
    );
    assert_eq!(t.moves.len(), 3);
    assert_eq!((t.moves[2].x_start, t.moves[2].x_dia), (23.5, 30.0));
    let d: Vec<_> = t.dwells.iter().map(|d| (d.after, d.time, d.line)).collect();
    assert_eq!(
        d,
        [
            (2, DwellTime::Seconds(1.0), 3),
            (2, DwellTime::Seconds(0.5), 4)
        ]
    );
    let t = run(
        "S100 M3\nG0 X30 Z2\nG4 S3\nG4 F1.5\nM30\n",
        Dialect::Siemens802d,
    );
    assert_eq!(t.dwells[0].time, DwellTime::Revolutions(3.0));
    assert_eq!(t.dwells[1].time, DwellTime::Seconds(1.5));
    let t = run("G7\nG0 X30 Z2\nG4 P0.3\nM2\n", Dialect::Linuxcnc);
    assert_eq!(t.dwells[0].time, DwellTime::Seconds(0.3));
}
