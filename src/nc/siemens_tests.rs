//! Tests of the Siemens 840D additions and the thread cycles CYCLE97/CYCLE99: the cycles'
//! moves against their documented closed forms (depth schedule, lead, starts, run-in and
//! run-out, flank shift), table-driven over many parameter sets; the 840D language
//! against values worked by hand.

use super::*;
use crate::model::helix::Spindle;

fn run_with(text: &str, dialect: Dialect, strict: bool) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "T.MPF".into(),
        text: text.into(),
    };
    let opts = Options {
        strict,
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts)
}

fn run(text: &str) -> Result<Vec<Move>, NcError> {
    run_with(text, Dialect::Siemens840d, false).map(|t| t.moves)
}

fn threads(moves: &[Move]) -> Vec<&Move> {
    moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect()
}

/// A deterministic generator of parameter sets (xorshift).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick(&mut self, lo: f64, hi: f64) -> f64 {
        // Rounded to 0.001 as a program writes it.
        ((lo + (hi - lo) * self.next()) * 1000.0).round() / 1000.0
    }
    fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next() * f64::from(hi - lo + 1)) as u32 % (hi - lo + 1)
    }
}

/// CYCLE97 over 300 random parameter sets (external and internal, both directions,
/// tapers, every VARI, flank and alternating infeed, several starts), through the
/// interpreter, against the closed forms of the Siemens documentation as written in
/// `siemens_cycles`' header: cut n of NRC at depth `(TDEP - FAL) n / NRC` (VARI 1/2) or
/// `(TDEP - FAL) sqrt(n / NRC)` (3/4), so the last roughing cut reaches TDEP - FAL; one
/// cut at TDEP, NID more there; every thread move's lead is PIT; start k at NSP + 360 k /
/// NUMT; each cut from the run-in point SPL - APP to the run-out point FPL + ROP (in the
/// cutting direction), stood back by (TDEP - d) tan|IANG| against it.
#[test]
fn cycle97_moves_follow_the_documented_schedule() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for case in 0..300 {
        let pit = rng.pick(0.5, 4.0);
        let spl = rng.pick(-5.0, 5.0);
        let len = rng.pick(5.0, 40.0);
        let fpl = if case % 3 == 0 { spl + len } else { spl - len };
        let dm1 = rng.pick(10.0, 80.0);
        let dm2 = if case % 4 == 0 {
            dm1 + rng.pick(-3.0, 3.0)
        } else {
            dm1
        };
        let (app, rop) = (rng.pick(0.0, 5.0), rng.pick(0.0, 3.0));
        let tdep = rng.pick(0.3, 2.5);
        let fal = (rng.pick(0.0, 0.2)).min(tdep / 2.0);
        let iang: f64 = [0.0, 30.0, -30.0, 29.0, -14.5][case % 5];
        let nsp = rng.pick(0.0, 359.0);
        let nrc = rng.int(1, 12);
        let nid = rng.int(0, 3);
        let vari = 1 + (case as u32 % 4);
        let numt = rng.int(1, 4);
        let text = format!(
            "G0 X100 Z50\nCYCLE97({pit},,{spl},{fpl},{dm1},{dm2},{app},{rop},{tdep},{fal},{iang},{nsp},{nrc},{nid},{vari},{numt})\nM30\n"
        );
        let moves = run(&text).unwrap_or_else(|e| panic!("case {case}: {text}\n{e}"));
        let t = threads(&moves);
        let per_start = (nrc + 1 + nid) as usize;
        assert_eq!(t.len(), per_start * numt as usize, "case {case}");
        let dir = (fpl - spl).signum();
        let (za, ze) = (spl - dir * app, fpl + dir * rop);
        let dia = |z: f64| dm1 + (dm2 - dm1) * (z - spl) / (fpl - spl);
        let side = if vari % 2 == 0 { 1.0 } else { -1.0 };
        let rough = tdep - fal;
        let tan = iang.abs().to_radians().tan();
        for (k, m) in t.iter().enumerate() {
            let start = k / per_start;
            let n = k % per_start;
            let want_d = if n < nrc as usize {
                let i = (n + 1) as f64;
                if vari >= 3 {
                    rough * (i / f64::from(nrc)).sqrt()
                } else {
                    rough * i / f64::from(nrc)
                }
            } else {
                tdep
            };
            let flank = if iang < 0.0 && n % 2 == 1 { -1.0 } else { 1.0 };
            let shift = -dir * (tdep - want_d) * tan * flank;
            let close = |a: f64, b: f64, what: &str| {
                assert!(
                    (a - b).abs() < 1e-9,
                    "case {case} cut {k}: {what} {a} != {b}\n{text}"
                )
            };
            close(m.lead.unwrap(), pit, "lead");
            close(m.z_start, za + shift, "start z");
            close(m.z, ze + shift, "end z");
            close(m.x_start, dia(za) + side * 2.0 * want_d, "start diameter");
            close(m.x_dia, dia(ze) + side * 2.0 * want_d, "end diameter");
            let angle = (nsp + 360.0 * start as f64 / f64::from(numt)).rem_euclid(360.0);
            close(m.sync_angle_deg.unwrap(), angle, "start angle");
            if n == nrc as usize - 1 {
                close(want_d, tdep - fal, "last roughing depth");
            }
        }
        // Every move starts where the previous one ended; the cycle ends at its start
        // point (the retract diameter, 1 mm radius off the thread at the run-in point).
        for w in moves.windows(2) {
            assert_eq!(
                (w[1].x_start, w[1].z_start),
                (w[0].x_dia, w[0].z),
                "case {case}"
            );
        }
        let last = moves.last().unwrap();
        assert!(
            (last.x_dia - (dia(za) - side * 2.0)).abs() < 1e-9,
            "case {case}"
        );
        assert!((last.z - za).abs() < 1e-9, "case {case}");
        assert!(moves
            .iter()
            .all(|m| m.kind == MoveKind::Thread || m.kind == MoveKind::Rapid));
    }
}

/// CYCLE99 is CYCLE97 with the points first and the pitch later: the same moves.
#[test]
fn cycle99_is_cycle97_with_its_parameters_reordered() {
    let a = run("G0 X50 Z10\nCYCLE97(2,,0,-30,24,24,4,2,1.23,0.05,-29,90,6,2,3,2)\n").unwrap();
    let b = run("G0 X50 Z10\nCYCLE99(0,24,-30,24,4,2,1.23,0.05,-29,90,6,2,2,3,2)\n").unwrap();
    assert_eq!(a, b);
    assert_eq!(threads(&a).len(), 2 * (6 + 1 + 2));
}

/// MPIT names an ISO coarse thread (ISO 261: M10 = 1.5, M24 = 3, M60 = 5.5); a PIT that
/// disagrees, an unknown size, TDEP <= FAL, VARI 5 and SPL = FPL are errors on the call's
/// column.
#[test]
fn cycle97_pitch_by_size_and_its_errors() {
    for (m, p) in [(10.0, 1.5), (24.0, 3.0), (60.0, 5.5), (3.0, 0.5)] {
        let t = run(&format!(
            "CYCLE97(,{m},0,-10,{m},{m},2,1,1,0,0,0,2,0,1,1)\n"
        ))
        .unwrap();
        assert!(threads(&t).iter().all(|x| x.lead == Some(p)), "M{m}");
    }
    for (text, what) in [
        ("CYCLE97(1,10,0,-10,10,10,2,1,1,0,0,0,2,0,1,1)", "disagree"),
        ("CYCLE97(,11,0,-10,10,10,2,1,1,0,0,0,2,0,1,1)", "not an ISO"),
        ("CYCLE97(1,,0,-10,10,10,2,1,1,1,0,0,2,0,1,1)", "FAL"),
        ("CYCLE97(1,,0,-10,10,10,2,1,1,0,0,0,2,0,5,1)", "VARI"),
        ("CYCLE97(1,,0,0,10,10,2,1,1,0,0,0,2,0,1,1)", "SPL = FPL"),
        ("CYCLE97(1,,0,-10,10,10,2,1,1,0,0,0,0,0,1,1)", "NRC"),
        // A coded VARI is named whole, with the range that runs (the message was cut off).
        (
            "CYCLE97(1,,0,-10,10,10,2,1,1,0,0,0,2,0,300103,1)",
            "VARI 300103: the machining type is 1..4",
        ),
        (
            "CYCLE97(1,,0,-10,10,10,2,1,1,0,0,0,2.5,0,1,1)",
            "must be a whole number from 1 to 100000",
        ),
        ("CYCLE97(1,,0,-2,10,20,2,1,1,0,0,0,2,0,1,1)", "45 degrees"),
        (
            "CYCLE99(0,10,-10,10,2,1,1,0,0,0,2,0,1.5,1100103,1,0)",
            "coded machining type",
        ),
        (
            "CYCLE97(1,,0,-10,10,10,2,1,1,0,0,0,99999,99999,1,99999)",
            "cuts (at most",
        ),
    ] {
        let e = run(&format!("G0 X40 Z5\n{text}\n")).unwrap_err();
        assert!(e.message.contains(what), "{text}: {}", e.message);
        assert_eq!((e.line, e.col), (2, 1), "{text}");
    }
}

/// The 802D runs CYCLE97 too (its static check reads the arguments).
#[test]
fn cycle97_runs_on_the_802d() {
    let t = run_with(
        "G0 X30 Z5\nCYCLE97(1.5,,0,-20,20,20,3,2,0.92,0.05,30,0,4,1,1,1)\nM30\n",
        Dialect::Siemens802d,
        true,
    )
    .unwrap();
    assert_eq!(threads(&t.moves).len(), 6);
    assert!(t.warnings.is_empty());
}

/// DEF scalars and arrays, assignments, FOR/WHILE/REPEAT/LOOP/IF-ELSE, worked by hand:
/// the moves' X values are the variables' values.
#[test]
fn user_variables_and_control_structures() {
    let text = "\
%_N_VARS_MPF
DEF REAL TIEFE=1.2, AR2[2,3]
DEF INT NN=3, KK
DEF REAL LIST[4]=SET(5,6), ALL[2]=REP(7)
DEF BOOL FLAG=5
AR2[1,2]=TIEFE*10      ; 12
G0 X=AR2[1,2] Z0       ; X12
FOR KK=1 TO NN
  G1 X=KK*10 F0.1     ; X10, X20, X30
ENDFOR
G0 X=KK               ; after the loop KK = NN + 1 = 4
WHILE KK>2
  KK=KK-1
ENDWHILE
G0 X=KK               ; 2
REPEAT
  KK=KK+2.6           ; INT: 2 + 2.6 = 4.6 -> 5
UNTIL KK>=5
G0 X=KK               ; 5
IF FLAG==1
  G0 X=LIST[1]+ALL[1] ; 6 + 7 = 13
ELSE
  G0 X99
ENDIF
IF LIST[3]<>0
  G0 X98
ENDIF
LOOP
  KK=KK+1
  IF KK>=7 GOTOF OUT
ENDLOOP
OUT: G0 X=KK          ; 7
M30
";
    let xs: Vec<f64> = run(text).unwrap().iter().map(|m| m.x_dia).collect();
    assert_eq!(xs, [12.0, 10.0, 20.0, 30.0, 4.0, 2.0, 5.0, 13.0, 7.0]);
}

/// Unmatched structures are found before anything runs; names the 840D language does not
/// model are refused by name with their column.
#[test]
fn structure_and_definition_errors() {
    for (text, line, col, what) in [
        ("G0 X1\nIF 1\nG0 X2\n", 2, 1, "IF without ENDIF"),
        (
            "WHILE 1\nENDFOR\nENDWHILE\n",
            2,
            1,
            "ENDFOR closes FOR while WHILE",
        ),
        ("N10 ENDLOOP\n", 1, 5, "ENDLOOP without LOOP"),
        ("DEF AXIS AX1\n", 1, 5, "AXIS"),
        ("DEF REAL AB[3]\nAB[3]=1\n", 2, 3, "out of range"),
        ("G0 X=NOPE\n", 1, 6, "unknown name"),
        ("DEF STRING[8] TXT=\"ABC\"\nG0 X=TXT\n", 2, 6, "STRING"),
        ("TRANS X5\n", 1, 7, "TRANS/ATRANS along X"),
        ("G91 DIAM90\nG0 X5\n", 2, 4, "DIAM90"),
    ] {
        let e = run(text).unwrap_err();
        assert!(e.message.contains(what), "{text}: {}", e.message);
        assert_eq!((e.line, e.col), (line, col), "{text}: {}", e.message);
    }
}

/// PROC parameters: the caller's values (0 where left out), local to the call; TRANS
/// shifts Z; AC/IC override G90/G91 for one word; SUPA moves in machine coordinates.
#[test]
fn proc_calls_frames_and_absolute_incremental_words() {
    let sub = "PROC CUT(REAL DIA, REAL LEN, INT NN)\nG1 X=DIA Z=-LEN F0.2\nG0 X=NN\nRET\n";
    let main = "\
G54 G90
TRANS Z=-10
G0 X50 Z0
CUT(30, 5)
ATRANS Z-2
G0 Z=IC(-1)
G91 G0 X=AC(40) Z1
G90 G0 SUPA X100 Z200
M30
";
    let src = Source {
        name: "MAIN.MPF".into(),
        text: main.into(),
    };
    let load = |n: &str| {
        (n == "CUT.SPF").then(|| Source {
            name: "CUT.SPF".into(),
            text: sub.into(),
        })
    };
    let moves = interpret_with(&src, Dialect::Siemens840d, &load, &Options::default())
        .unwrap()
        .moves;
    let ends: Vec<(f64, f64)> = moves.iter().map(|m| (m.x_dia, m.z)).collect();
    // TRANS Z-10: Z0 is -10; CUT: X30 Z-5 -> -15, then X0 (NN left out); ATRANS Z-2: the
    // frame is at -12, IC(-1) from -15 is -16; G91 with X=AC(40): X40; Z1 more: -15;
    // SUPA: machine X100 Z200.
    assert_eq!(
        ends,
        [
            (50.0, -10.0),
            (30.0, -15.0),
            (0.0, -15.0),
            (0.0, -16.0),
            (40.0, -15.0),
            (100.0, 200.0)
        ]
    );
}

/// G331/G332 (840D rigid tapping): thread moves of lead K on the axis; G332 comes back
/// with the spindle reversed.
#[test]
fn rigid_tapping_is_thread_moves_on_the_spindle_axis() {
    let moves = run("G0 X0 Z5\nSPOS=0\nG331 Z-20 K1.25 S400\nG332 Z5 K1.25\nM30\n").unwrap();
    let t = threads(&moves);
    assert_eq!(t.len(), 2);
    assert_eq!((t[0].z_start, t[0].z, t[0].lead), (5.0, -20.0, Some(1.25)));
    assert_eq!((t[1].z_start, t[1].z, t[1].lead), (-20.0, 5.0, Some(1.25)));
    assert_eq!(t[0].spindle, crate::model::helix::Spindle::Cw);
    assert_eq!(t[1].spindle, crate::model::helix::Spindle::Ccw);
    assert!(t.iter().all(|m| m.x_dia == 0.0 && m.x_start == 0.0));
    // 20 turns in: the way back starts where the way in did (phase 0).
    assert_eq!(
        (t[0].sync_angle_deg, t[1].sync_angle_deg),
        (Some(0.0), Some(0.0))
    );
    // 25/1.5 = 16 2/3 turns in end at 240 deg; the reversed spindle counts the other way,
    // so G332 comes back in the same groove at -240 = 120 deg.
    let moves = run("G0 X0 Z5\nSPOS=0\nG331 Z-20 K1.5 S400\nG332 Z5 K1.5\nM30\n").unwrap();
    let t = threads(&moves);
    assert!(
        (t[1].sync_angle_deg.unwrap() - 120.0).abs() < 1e-9,
        "{:?}",
        t[1]
    );
}

/// CYCLE84 (rigid tapping, Cycles manual "CYCLE84"): RTP 10, RFP 0, SDIS 2, DP -18,
/// PIT 1.5: rapid to Z2, tap to Z-18 (lead 1.5, cw), back to Z2 (ccw), rapid to Z10; a
/// negative MPIT (M8, pitch 1.25) taps left-hand (ccw in, cw out); DPR gives the depth
/// from RFP; off the axis it is refused.
#[test]
fn cycle84_taps_on_the_axis() {
    use crate::model::helix::Spindle::{Ccw, Cw};
    let m = run("G0 X0 Z20 M3\nCYCLE84(10,0,2,-18,,0,3,,1.5,0,300,300)\n").unwrap();
    let got: Vec<(MoveKind, f64, f64, Option<f64>, Spindle)> = m[1..]
        .iter()
        .map(|m| (m.kind, m.z_start, m.z, m.lead, m.spindle))
        .collect();
    assert_eq!(
        got,
        [
            (MoveKind::Rapid, 20.0, 2.0, None, Cw),
            (MoveKind::Thread, 2.0, -18.0, Some(1.5), Cw),
            (MoveKind::Thread, -18.0, 2.0, Some(1.5), Ccw),
            (MoveKind::Rapid, 2.0, 10.0, None, Cw),
        ]
    );
    // 20 mm at 1.5 = 13 1/3 turns end at 120 deg: back at -120 = 240 deg, in the groove.
    assert_eq!(m[2].sync_angle_deg, Some(0.0));
    assert!(
        (m[3].sync_angle_deg.unwrap() - 240.0).abs() < 1e-9,
        "{:?}",
        m[3]
    );
    let m = run("G0 X0 Z5 M3\nCYCLE84(5,0,1,,12,0,3,-8,,0,300,300)\n").unwrap();
    let t = threads(&m);
    assert_eq!((t[0].z_start, t[0].z, t[0].lead), (1.0, -12.0, Some(1.25)));
    assert_eq!((t[0].spindle, t[1].spindle), (Ccw, Cw));
    let e = run("G0 X20 Z5\nCYCLE84(5,0,1,-10,,0,3,,1,0,300,300)\n").unwrap_err();
    assert!(e.message.contains("off the spindle axis"), "{}", e.message);
}
