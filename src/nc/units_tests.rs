//! Issue 30: every word of every cycle that carries a unit, read as its dialect's manual
//! says, written with and without a decimal point, in mm and in inch, on a FANUC/GSK in
//! standard and in calculator-type decimal-point input.
//!
//! The oracle is [`manual`]: the unit rule of each class of word, stated from the manuals
//! (not from the code under test), applied to the literal written in the program. Each row
//! measures its word on the moves by a relation derived by hand in its comment (the G76
//! pass that stands `d` above the last one, the taper of a pass, the peck's return, ...).
//! The rules:
//!
//! - FANUC decimal-point input (parameter 3401#0 DPI; FANUC 0i/30i operator's manuals,
//!   "Decimal point programming"; the same on Mitsubishi M700 "5.3 Decimal Point Input":
//!   "Command X1 in the 1 um system is equivalent to command X0.001" in type I,
//!   "equivalent to command X1." in type II): an address that takes a point reads a number
//!   without one in the least input increment (standard, the factory setting) or in mm/inch
//!   (calculator type); with a point always in mm/inch.
//! - G74..G76 `P`/`Q` "never take a point; they count in the least input increment of their
//!   axis" (gEdit's FANUC notes from the 30i manuals; `controllers.md` 2.3: Q(dmin), P(k),
//!   Q(dd) "µm, no decimal point"); a point is an alarm.
//! - The threading start angle `Q`: "Increment: 0.001 degrees" (FANUC 30i-A lathe manual
//!   B-63944EN, G92, p. 35, `controllers.md` 2.2); Haas G76: "Do not use a decimal point".
//! - The one-block G76's `K`/`D` (FANUC 0T, Haas) and G71's `D`: the least increment without
//!   a point (`D0140`, `K1083`), program units with one (Haas writes `K.0511`), in either
//!   input mode (`controllers.md` 2.4).
//! - A lead without a point in standard input: its unit is a parameter of its own (30i:
//!   0.01 or 0.001 mm/rev; Haas setting 77 "Scale Integer F"): vpcut refuses it.
//! - Siemens (SINUMERIK programming manual, G70/G71: "inch/metric dimensions") and
//!   LinuxCNC (G20/G21): a number is in program units whether or not it has a point.

use super::*;

/// The least input increment and the program unit of a reading, in mm.
#[derive(Clone, Copy, Debug)]
struct Ctx {
    /// mm per program unit (25.4 under G20/G70).
    unit: f64,
    /// mm per least input increment (0.001 mm, or 0.0001 in = 0.00254 mm).
    inc: f64,
}

/// The unit rule of a class of word.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Unit {
    /// An address that takes a point (X, Z, U, W, R, I, K, J, G71 U/R, ...).
    Length,
    /// The least input increment (G74..G76 P/Q: "never a point" on a FANUC 0i, which
    /// alarms PS0007); written with a point, program units with a warning, as Haas and the
    /// FANUC-style controls of program generators read `G76 P0.974 Q0.3` (issue 27).
    Increment,
    /// The least increment without a point, program units with one, in either mode
    /// (one-block G76 K/D, G71 D).
    IncrementOrUnits,
    /// A lead (F, G34 K, GSK G34 R): program units with a point; without one refused in
    /// standard input, program units in calculator type.
    Lead,
    /// The start angle Q: 0.001 deg, no point.
    Angle,
    /// Siemens and LinuxCNC: program units, point or not.
    Units,
}

/// What the manuals say word `unit` written `literal` (with a point or not) is, in mm (deg
/// for an angle); `None`: the control alarms.
fn manual(unit: Unit, literal: f64, point: bool, calculator: bool, c: Ctx) -> Option<f64> {
    match unit {
        Unit::Length if point || calculator => Some(literal * c.unit),
        Unit::Length => Some(literal * c.inc),
        Unit::Increment if point => Some(literal * c.unit),
        Unit::Increment => Some(literal * c.inc),
        Unit::IncrementOrUnits if point => Some(literal * c.unit),
        Unit::IncrementOrUnits => Some(literal * c.inc),
        Unit::Lead if point || calculator || literal == 0.0 => Some(literal * c.unit),
        Unit::Lead => None,
        Unit::Angle if point => None,
        Unit::Angle => Some(literal / 1000.0),
        Unit::Units => Some(literal * c.unit),
    }
}

/// One word: the program (`{v}` the word's literal, `{h}` a companion literal written the
/// same way), the literals without and with a point, the rule and how the moves show it.
struct Row {
    what: &'static str,
    dialects: &'static [Dialect],
    template: &'static str,
    word: &'static str,
    plain: (&'static str, &'static str),
    point: (&'static str, &'static str),
    unit: Unit,
    probe: fn(&[Move], Ctx) -> f64,
}

const FG: &[Dialect] = &[Dialect::Fanuc, Dialect::Gsk980];
const F: &[Dialect] = &[Dialect::Fanuc];
const G: &[Dialect] = &[Dialect::Gsk980];
const S: &[Dialect] = &[Dialect::Siemens802d, Dialect::Siemens840d];
const S840: &[Dialect] = &[Dialect::Siemens840d];
const L: &[Dialect] = &[Dialect::Linuxcnc];

fn threads(m: &[Move]) -> Vec<&Move> {
    m.iter().filter(|m| m.kind == MoveKind::Thread).collect()
}

fn first(m: &[Move]) -> &Move {
    threads(m)[0]
}

fn last(m: &[Move]) -> &Move {
    threads(m).last().expect("a thread move")
}

/// The rows. FANUC/GSK templates start at X600 Z10 (written with points, so that only the
/// word under test changes with the reading); sizes are chosen so that every reading of
/// the literal (0.001, 0.00254, 1 or 25.4 mm a unit) still makes a valid cycle.
fn rows() -> Vec<Row> {
    vec![
        // G76 block 1 R(d): with Q(dd) deeper than P(k) roughing stops at once; the passes
        // are k - d (the allowance left) and k: the first stands d above the last.
        Row {
            what: "G76 (first block) R: d, the finishing allowance",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R{v}\nG76 X300. Z-100. P90000 Q100000 F2.\n",
            word: "R",
            plain: ("2", ""),
            point: ("0.5", ""),
            unit: Unit::Length,
            probe: |m, _| (first(m).x_dia - threads(m)[1].x_dia) / 2.0,
        },
        // G76 block 1 Q(dmin): with dd one increment, pass 2 is max(dd sqrt 2, dd + dmin) =
        // dd + dmin below pass 1.
        Row {
            what: "G76 (first block) Q: the minimum cut",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q{v} R0.\nG76 X300. Z-100. P90000 Q1 F2.\n",
            word: "Q",
            plain: ("50", ""),
            point: ("0.05", ""),
            unit: Unit::Increment,
            probe: |m, _| (first(m).x_dia - threads(m)[1].x_dia) / 2.0,
        },
        // G76 block 2 X: the last pass (at k) ends on the root diameter X.
        Row {
            what: "G76 (second block) X: the root diameter",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 X{v} Z-100. P1000 Q100000 F2.\n",
            word: "X",
            plain: ("300", ""),
            point: ("300.", ""),
            unit: Unit::Length,
            probe: |m, _| last(m).x_dia,
        },
        Row {
            what: "G76 (second block) Z: the thread's end",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 X300. Z{v} P1000 Q100000 F2.\n",
            word: "Z",
            plain: ("-100", ""),
            point: ("-100.", ""),
            unit: Unit::Length,
            probe: |m, _| last(m).z,
        },
        Row {
            what: "G76 (second block) U: the root diameter from the start",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 U{v} Z-100. P1000 Q100000 F2.\n",
            word: "U",
            plain: ("-300", ""),
            point: ("-300.", ""),
            unit: Unit::Length,
            probe: |m, _| last(m).x_dia - m[0].x_dia,
        },
        Row {
            what: "G76 (second block) W: the thread's end from the start",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 X300. W{v} P1000 Q100000 F2.\n",
            word: "W",
            plain: ("-110", ""),
            point: ("-110.", ""),
            unit: Unit::Length,
            probe: |m, _| last(m).z - m[0].z,
        },
        // R(i): every pass starts 2i (diameter) off its end X.
        Row {
            what: "G76 (second block) R: i, the taper (radius at the start less at the end)",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 X300. Z-100. R{v} P1000 Q100000 F2.\n",
            word: "R",
            plain: ("-5", ""),
            point: ("-5.", ""),
            unit: Unit::Length,
            probe: |m, _| (last(m).x_start - last(m).x_dia) / 2.0,
        },
        // P(k): pass 1 cuts max(dd, dmin) = dmin = Q100 (100 increments; dd is one) deep,
        // k - dmin above the last pass.
        Row {
            what: "G76 (second block) P: k, the thread height",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q100 R0.\nG76 X300. Z-100. P{v} Q1 F2.\n",
            word: "P",
            plain: ("5000", ""),
            point: ("5.", ""),
            unit: Unit::Increment,
            probe: |m, c| (first(m).x_dia - last(m).x_dia) / 2.0 + 100.0 * c.inc,
        },
        // Q(dd): pass 1 stands k - dd above the last, k = P5000 increments.
        Row {
            what: "G76 (second block) Q: the first cut's depth",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q100 R0.\nG76 X300. Z-100. P5000 Q{v} F2.\n",
            word: "Q",
            plain: ("1000", ""),
            // Below the height in inch too (0.1 in < P5000 = 0.5 in).
            point: ("0.1", ""),
            unit: Unit::Increment,
            probe: |m, c| 5000.0 * c.inc - (first(m).x_dia - last(m).x_dia) / 2.0,
        },
        Row {
            what: "G76 (second block) F: the lead",
            dialects: FG,
            template: "G0 X600. Z10.\nG76 P010060 Q0 R0.\nG76 X300. Z-100. P1000 Q100000 F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        // One-block G76 (FANUC 0T, Haas): pass 1 at D, K - D above the last pass.
        Row {
            what: "one-block G76 K: the thread height",
            dialects: F,
            template: "G0 X600. Z10.\nG76 X300. Z-100. K{v} D0.1 F2. A60\n",
            word: "K",
            plain: ("5000", ""),
            point: ("5.", ""),
            unit: Unit::IncrementOrUnits,
            probe: |m, c| (first(m).x_dia - last(m).x_dia) / 2.0 + 0.1 * c.unit,
        },
        Row {
            what: "one-block G76 D: the first cut's depth",
            dialects: F,
            template: "G0 X600. Z10.\nG76 X300. Z-100. K1. D{v} F2. A60\n",
            word: "D",
            plain: ("100", ""),
            point: ("0.1", ""),
            unit: Unit::IncrementOrUnits,
            probe: |m, c| c.unit - (first(m).x_dia - last(m).x_dia) / 2.0,
        },
        Row {
            what: "one-block G76 I: the taper",
            dialects: F,
            template: "G0 X600. Z10.\nG76 X300. Z-100. I{v} K1. D2. F2.\n",
            word: "I",
            plain: ("-5", ""),
            point: ("-5.", ""),
            unit: Unit::Length,
            probe: |m, _| (last(m).x_start - last(m).x_dia) / 2.0,
        },
        Row {
            what: "one-block G76 Q: the start angle (Haas)",
            dialects: F,
            template: "G0 X600. Z10.\nG76 X300. Z-100. K1. D2. F2. Q{v}\n",
            word: "Q",
            plain: ("90000", ""),
            point: ("90.", ""),
            unit: Unit::Angle,
            probe: |m, _| first(m).sync_angle_deg.unwrap(),
        },
        Row {
            what: "one-block G76 F: the lead",
            dialects: F,
            template: "G0 X600. Z10.\nG76 X300. Z-100. K1. D2. F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        // G92: the pass threads to X at Z; R tapers it; Q shifts its start angle.
        Row {
            what: "G92 X",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X{v} Z-100. F2.\n",
            word: "X",
            plain: ("300", ""),
            point: ("300.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).x_dia,
        },
        Row {
            what: "G92 Z",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X300. Z{v} F2.\n",
            word: "Z",
            plain: ("-100", ""),
            point: ("-100.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).z,
        },
        Row {
            what: "G92 U",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 U{v} Z-100. F2.\n",
            word: "U",
            plain: ("-300", ""),
            point: ("-300.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).x_dia - m[0].x_dia,
        },
        Row {
            what: "G92 W",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X300. W{v} F2.\n",
            word: "W",
            plain: ("-110", ""),
            point: ("-110.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).z - m[0].z,
        },
        Row {
            what: "G92 R: the taper",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X300. Z-100. R{v} F2.\n",
            word: "R",
            plain: ("-5", ""),
            point: ("-5.", ""),
            unit: Unit::Length,
            probe: |m, _| (first(m).x_start - first(m).x_dia) / 2.0,
        },
        Row {
            what: "G92 F: the lead",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X300. Z-100. F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "G92 Q: the start angle",
            dialects: FG,
            template: "G0 X600. Z10.\nG92 X300. Z-100. F2. Q{v}\n",
            word: "Q",
            plain: ("180000", ""),
            point: ("180.", ""),
            unit: Unit::Angle,
            probe: |m, _| first(m).sync_angle_deg.unwrap(),
        },
        // G90: rapid to X + 2R at the start Z, then feed to the end: the two X differ by 2R.
        Row {
            what: "G90 R: the taper",
            dialects: FG,
            template: "G0 X600. Z10.\nG90 X300. Z-100. R{v} F.2\n",
            word: "R",
            plain: ("-5", ""),
            point: ("-5.", ""),
            unit: Unit::Length,
            probe: |m, _| (m[1].x_dia - m[2].x_dia) / 2.0,
        },
        Row {
            what: "G90 X",
            dialects: FG,
            template: "G0 X600. Z10.\nG90 X{v} Z-100. F.2\n",
            word: "X",
            plain: ("300", ""),
            point: ("300.", ""),
            unit: Unit::Length,
            probe: |m, _| m[2].x_dia,
        },
        // G94: rapid to Z + R at the start X, then feed to the end: the two Z differ by R.
        Row {
            what: "G94 R: the taper",
            dialects: FG,
            template: "G0 X600. Z10.\nG94 X300. Z-100. R{v} F.2\n",
            word: "R",
            plain: ("-5", ""),
            point: ("-5.", ""),
            unit: Unit::Length,
            probe: |m, _| m[1].z - m[2].z,
        },
        Row {
            what: "G32 F: the lead",
            dialects: FG,
            template: "G0 X300. Z10.\nG32 Z-100. F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "G32 Q: the start angle",
            dialects: F,
            template: "G0 X300. Z10.\nG32 Z-100. F2. Q{v}\n",
            word: "Q",
            plain: ("45000", ""),
            point: ("45.", ""),
            unit: Unit::Angle,
            probe: |m, _| first(m).sync_angle_deg.unwrap(),
        },
        Row {
            what: "G34 K: the lead change per revolution (FANUC)",
            dialects: F,
            template: "G0 X300. Z10.\nG34 Z-100. F2. K{v}\n",
            word: "K",
            plain: ("1", ""),
            point: ("0.5", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead_change.unwrap(),
        },
        Row {
            what: "G00 X",
            dialects: FG,
            template: "G0 X{v} Z10.\n",
            word: "X",
            plain: ("300", ""),
            point: ("300.", ""),
            unit: Unit::Length,
            probe: |m, _| m[0].x_dia,
        },
        Row {
            what: "G00 Z",
            dialects: FG,
            template: "G0 X300. Z{v}\n",
            word: "Z",
            plain: ("-40", ""),
            point: ("-40.", ""),
            unit: Unit::Length,
            probe: |m, _| m[0].z,
        },
        Row {
            what: "G00 U",
            dialects: FG,
            template: "G0 X300. Z10.\nG0 U{v}\n",
            word: "U",
            plain: ("-20", ""),
            point: ("-20.", ""),
            unit: Unit::Length,
            probe: |m, _| m[1].x_dia - m[0].x_dia,
        },
        Row {
            what: "G00 W",
            dialects: FG,
            template: "G0 X300. Z10.\nG0 W{v}\n",
            word: "W",
            plain: ("-20", ""),
            point: ("-20.", ""),
            unit: Unit::Length,
            probe: |m, _| m[1].z - m[0].z,
        },
        // G03 from the origin to radius v (diameter h = 2v) at z -v: with R = v, I = v or
        // K = -v the circle through both has radius v (its centre v from the start).
        Row {
            what: "G03 R: the radius",
            dialects: FG,
            template: "G0 X0. Z0.\nG3 X{h} Z-{v} R{v} F.2\n",
            word: "R",
            plain: ("5000", "10000"),
            point: ("5.", "10."),
            unit: Unit::Length,
            probe: |m, _| {
                let a = m[1].arc.unwrap();
                (a.x_centre_dia / 2.0).hypot(a.z_centre)
            },
        },
        Row {
            what: "G03 I: the centre in X (radius)",
            dialects: FG,
            template: "G0 X0. Z0.\nG3 X{h} Z-{v} I{v} K0. F.2\n",
            word: "I",
            plain: ("5000", "10000"),
            point: ("5.", "10."),
            unit: Unit::Length,
            probe: |m, _| m[1].arc.unwrap().x_centre_dia / 2.0,
        },
        Row {
            what: "G03 K: the centre in Z",
            dialects: FG,
            template: "G0 X0. Z0.\nG3 X{h} Z-{v} I0. K-{v} F.2\n",
            word: "K",
            plain: ("5000", "10000"),
            point: ("5.", "10."),
            unit: Unit::Length,
            probe: |m, _| -m[1].arc.unwrap().z_centre,
        },
        // G71: from X100 the first pass is dd (radius) inside; after it the retract goes
        // out e at 45 deg; the finishing pass runs along the shape moved by U (diameter)
        // and W.
        Row {
            what: "G71 (first block) U: the depth of cut",
            dialects: FG,
            template: "G0 X100. Z2.\nG71 U{v} R1.\nG71 P10 Q20 U0. W0. F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "U",
            plain: ("20", ""),
            point: ("2.5", ""),
            unit: Unit::Length,
            probe: |m, _| (m[0].x_dia - m[1].x_dia) / 2.0,
        },
        Row {
            what: "G71 (first block) R: the retract",
            dialects: FG,
            template: "G0 X100. Z2.\nG71 U2.5 R{v}\nG71 P10 Q20 U0. W0. F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "R",
            plain: ("500", ""),
            point: ("0.5", ""),
            unit: Unit::Length,
            probe: |m, _| (m[3].x_dia - m[2].x_dia) / 2.0,
        },
        Row {
            what: "G71 (second block) U: the finishing allowance in X (diameter)",
            dialects: FG,
            template: "G0 X100. Z2.\nG71 U2.5 R1.\nG71 P10 Q20 U{v} W0. F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "U",
            plain: ("1", ""),
            point: ("0.4", ""),
            unit: Unit::Length,
            probe: |m, c| finishing_feed(m).x_dia - 40.0 * c.unit,
        },
        Row {
            what: "G71 (second block) W: the finishing allowance in Z",
            dialects: FG,
            template: "G0 X100. Z2.\nG71 U2.5 R1.\nG71 P10 Q20 U0. W{v} F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "W",
            plain: ("1", ""),
            point: ("0.2", ""),
            unit: Unit::Length,
            probe: |m, c| finishing_feed(m).z + 30.0 * c.unit,
        },
        Row {
            what: "one-block G71 D: the depth of cut (0T, Haas)",
            dialects: F,
            template: "G0 X100. Z2.\nG71 P10 Q20 U0. W0. D{v} F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "D",
            plain: ("2000", ""),
            point: ("2.", ""),
            unit: Unit::IncrementOrUnits,
            probe: |m, _| (m[0].x_dia - m[1].x_dia) / 2.0,
        },
        // G72 steps in Z: the first pass is dd below the start's Z.
        Row {
            what: "G72 (first block) W: the depth of cut",
            dialects: FG,
            template: "G0 X84. Z2.\nG72 W{v} R0.5\nG72 P50 Q60 U0. W0. F.2\nN50 G0 Z-12.\nN51 G1 X50.\nN52 X30. Z-2.\nN53 Z0.\nN60 X0.\n",
            word: "W",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Length,
            probe: |m, _| m[0].z - m[1].z,
        },
        // G73: pass 1 is the shape moved by (2 di, dk): its first point, X40 Z2, lands
        // 2 di and dk away.
        Row {
            what: "G73 (first block) U: the relief in X (radius)",
            dialects: FG,
            template: "G0 X100. Z2.\nG73 U{v} W0. R2\nG73 P10 Q20 U0. W0. F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "U",
            plain: ("5", ""),
            point: ("5.", ""),
            unit: Unit::Length,
            probe: |m, c| (m[1].x_dia - 40.0 * c.unit) / 2.0,
        },
        Row {
            what: "G73 (first block) W: the relief in Z",
            dialects: FG,
            template: "G0 X100. Z2.\nG73 U0. W{v} R2\nG73 P10 Q20 U0. W0. F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "W",
            plain: ("3", ""),
            point: ("3.", ""),
            unit: Unit::Length,
            probe: |m, c| m[1].z - 2.0 * c.unit,
        },
        Row {
            what: "one-block G73 I: the relief in X (radius)",
            dialects: F,
            template: "G0 X100. Z2.\nG73 P10 Q20 I{v} K0. U0. W0. D2 F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "I",
            plain: ("5", ""),
            point: ("5.", ""),
            unit: Unit::Length,
            probe: |m, c| (m[1].x_dia - 40.0 * c.unit) / 2.0,
        },
        Row {
            what: "one-block G73 K: the relief in Z",
            dialects: F,
            template: "G0 X100. Z2.\nG73 P10 Q20 I0. K{v} U0. W0. D2 F.2\nN10 G0 X40.\nG1 Z-30.\nN20 X100.\n",
            word: "K",
            plain: ("3", ""),
            point: ("3.", ""),
            unit: Unit::Length,
            probe: |m, c| m[1].z - 2.0 * c.unit,
        },
        // G75: each peck feeds P (radius) and goes back e; G74 pecks Q along Z.
        Row {
            what: "G75 (first block) R: the return after each peck",
            dialects: FG,
            template: "G0 X200. Z-10.\nG75 R{v}\nG75 X0. Z-10. P20000 Q0 F.1\n",
            word: "R",
            plain: ("1", ""),
            point: ("0.5", ""),
            unit: Unit::Length,
            probe: |m, _| (m[2].x_dia - m[1].x_dia) / 2.0,
        },
        Row {
            what: "G75 P: the peck depth (radius)",
            dialects: FG,
            template: "G0 X200. Z-10.\nG75 R0.\nG75 X0. Z-10. P{v} Q0 F.1\n",
            word: "P",
            plain: ("20000", ""),
            point: ("20.", ""),
            unit: Unit::Increment,
            probe: |m, _| (m[0].x_dia - m[1].x_dia) / 2.0,
        },
        Row {
            what: "G75 Q: the step along Z",
            dialects: FG,
            template: "G0 X200. Z-10.\nG75 R0.\nG75 X100. Z-30. P1000000 Q{v} F.1\n",
            word: "Q",
            plain: ("5000", ""),
            point: ("5.", ""),
            unit: Unit::Increment,
            probe: |m, _| m[0].z - m[3].z,
        },
        Row {
            what: "G74 Q: the peck depth along Z",
            dialects: FG,
            template: "G0 X0. Z10.\nG74 R0.\nG74 Z-20. Q{v} F.1\n",
            word: "Q",
            plain: ("5000", ""),
            point: ("5.", ""),
            unit: Unit::Increment,
            probe: |m, _| m[0].z - m[1].z,
        },
        // G84 (rigid tapping): the tap starts at the R point, R from the initial level; W
        // from the R point to the bottom; F the pitch (G99).
        Row {
            what: "G84 R: the R point from the initial level",
            dialects: F,
            template: "G0 X0. Z10.\nM29 S300\nG84 Z-20. R{v} F1.5\n",
            word: "R",
            plain: ("-7", ""),
            point: ("-7.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).z_start - m[0].z,
        },
        Row {
            what: "G84 W: the bottom from the R point",
            dialects: F,
            template: "G0 X0. Z10.\nM29 S300\nG84 W{v} R-7. F1.5\n",
            word: "W",
            plain: ("-10", ""),
            point: ("-10.", ""),
            unit: Unit::Length,
            probe: |m, _| first(m).z - first(m).z_start,
        },
        Row {
            what: "G84 F: the pitch",
            dialects: F,
            template: "G0 X0. Z10.\nM29 S300\nG84 Z-20. R-7. F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("1.5", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        // GSK 980TDc G34 F(lead) R(lead change) and the run-out J/K of its thread blocks:
        // the thread ends K before its end along Z, then goes out 2J (diameter).
        Row {
            what: "GSK G34 R: the lead change per revolution",
            dialects: G,
            template: "G0 X60. Z8.\nG34 Z-70. F4. R{v}\n",
            word: "R",
            plain: ("1", ""),
            point: ("0.5", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead_change.unwrap(),
        },
        Row {
            what: "GSK G34 F: the start lead",
            dialects: G,
            template: "G0 X60. Z8.\nG34 Z-70. F{v} R1.\n",
            word: "F",
            plain: ("4", ""),
            point: ("4.", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "GSK thread run-out J (X, radius)",
            dialects: G,
            template: "G0 X60. Z8.\nG32 Z-70. F4. J{v} K{h}\n",
            word: "J",
            plain: ("1", "2"),
            point: ("1.", "2."),
            unit: Unit::Length,
            probe: |m, _| (last(m).x_dia - m[0].x_dia) / 2.0,
        },
        Row {
            what: "GSK thread run-out K (Z)",
            dialects: G,
            template: "G0 X60. Z8.\nG32 Z-70. F4. J{h} K{v}\n",
            word: "K",
            plain: ("2", "1"),
            point: ("2.", "1."),
            unit: Unit::Length,
            probe: |m, _| first(m).z - last(m).z,
        },
        Row {
            what: "GSK G33 F: the tap's pitch",
            dialects: G,
            template: "G0 X0. Z5.\nG33 Z-10. F{v}\n",
            word: "F",
            plain: ("2", ""),
            point: ("1.5", ""),
            unit: Unit::Lead,
            probe: |m, _| first(m).lead.unwrap(),
        },
        // Siemens: program units, point or not (G70 inch, G71 mm).
        Row {
            what: "Siemens G33 K: the lead",
            dialects: S,
            template: "G0 X30 Z5\nG33 Z-20 K{v}\n",
            word: "K",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "Siemens G34 F: the lead change per revolution",
            dialects: S,
            template: "G0 X30 Z5\nG34 Z-20 K2 F{v}\n",
            word: "F",
            plain: ("1", ""),
            point: ("0.5", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead_change.unwrap(),
        },
        // CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID,
        // VARI, NUMT, _VRT), VARI 1: cuts at n (TDEP - FAL) / NRC, then TDEP; the thread runs
        // from SPL + APP to FPL - ROP; the tool waits _VRT (radius) above DM1.
        Row {
            what: "CYCLE97 PIT: the pitch",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97({v},,0,-30,20,20,2,3,1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "PIT",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "CYCLE97 SPL: the thread's start",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,{v},-30,20,20,2,3,1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "SPL",
            plain: ("1", ""),
            point: ("1.", ""),
            unit: Unit::Units,
            probe: |m, c| first(m).z_start - 2.0 * c.unit,
        },
        Row {
            what: "CYCLE97 FPL: the thread's end",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,{v},20,20,2,3,1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "FPL",
            plain: ("-30", ""),
            point: ("-30.", ""),
            unit: Unit::Units,
            probe: |m, c| first(m).z + 3.0 * c.unit,
        },
        Row {
            what: "CYCLE97 DM1/DM2: the diameter",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,{v},{v},2,3,1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "DM1",
            plain: ("20", ""),
            point: ("20.", ""),
            unit: Unit::Units,
            probe: |m, c| last(m).x_dia + 2.0 * c.unit,
        },
        Row {
            what: "CYCLE97 APP: the run-in",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,20,20,{v},3,1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "APP",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).z_start,
        },
        Row {
            what: "CYCLE97 ROP: the run-out",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,20,20,2,{v},1,0.2,0,0,4,1,1,1,1.5)\n",
            word: "ROP",
            plain: ("3", ""),
            point: ("3.", ""),
            unit: Unit::Units,
            probe: |m, c| -30.0 * c.unit - first(m).z,
        },
        Row {
            what: "CYCLE97 TDEP: the thread depth",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,20,20,2,3,{v},0.2,0,0,4,1,1,1,1.5)\n",
            word: "TDEP",
            plain: ("1", ""),
            point: ("1.", ""),
            unit: Unit::Units,
            probe: |m, c| (20.0 * c.unit - last(m).x_dia) / 2.0,
        },
        Row {
            what: "CYCLE97 FAL: the finishing allowance",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,20,20,2,3,2,{v},0,0,4,1,1,1,1.5)\n",
            word: "FAL",
            plain: ("1", ""),
            point: ("0.5", ""),
            unit: Unit::Units,
            probe: |m, _| (threads(m)[3].x_dia - last(m).x_dia) / 2.0,
        },
        Row {
            what: "CYCLE97 _VRT: the retract (radius)",
            dialects: S,
            template: "G0 X40 Z10\nCYCLE97(2,,0,-30,20,20,2,3,1,0.2,0,0,4,1,1,1,{v})\n",
            word: "_VRT",
            plain: ("2", ""),
            point: ("1.5", ""),
            unit: Unit::Units,
            probe: |m, c| (m[1].x_dia - 20.0 * c.unit) / 2.0,
        },
        // CYCLE99(_SPL, _SPD, _FPL, _FPD, _APP, _ROP, _TDEP, _FAL, _IANG, _NSP, _NRC, _NID,
        // _PIT, _VARI, _NUMTH, _VRT): the pitch comes late.
        Row {
            what: "CYCLE99 _PIT: the pitch",
            dialects: S840,
            template: "G0 X40 Z10\nCYCLE99(0,20,-30,20,2,3,1,0.2,0,0,4,1,{v},1,1,1.5)\n",
            word: "_PIT",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "CYCLE99 _SPD/_FPD: the diameter",
            dialects: S840,
            template: "G0 X40 Z10\nCYCLE99(0,{v},-30,{v},2,3,1,0.2,0,0,4,1,2,1,1,1.5)\n",
            word: "_SPD",
            plain: ("20", ""),
            point: ("20.", ""),
            unit: Unit::Units,
            probe: |m, c| last(m).x_dia + 2.0 * c.unit,
        },
        Row {
            what: "CYCLE99 _TDEP: the thread depth",
            dialects: S840,
            template: "G0 X40 Z10\nCYCLE99(0,20,-30,20,2,3,{v},0.2,0,0,4,1,2,1,1,1.5)\n",
            word: "_TDEP",
            plain: ("1", ""),
            point: ("1.", ""),
            unit: Unit::Units,
            probe: |m, c| (20.0 * c.unit - last(m).x_dia) / 2.0,
        },
        // LinuxCNC (G8 radius mode): G33 K; G76 from the drive line X15 (radius): pass 1 at
        // |I| + J below it, the last at |I| + K.
        Row {
            what: "LinuxCNC G33 K: the pitch",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG33 Z-20 K{v}\n",
            word: "K",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "LinuxCNC G76 P: the pitch",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P{v} Z-20 I-1 J0.4 K1.5\n",
            word: "P",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).lead.unwrap(),
        },
        Row {
            what: "LinuxCNC G76 I: the crest from the drive line",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P2 Z-20 I{v} J0.4 K1.5\n",
            word: "I",
            plain: ("-1", ""),
            point: ("-1.", ""),
            unit: Unit::Units,
            probe: |m, c| last(m).x_dia / 2.0 - (15.0 - 1.5) * c.unit,
        },
        Row {
            what: "LinuxCNC G76 J: the first cut",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P2 Z-20 I-1 J{v} K1.5\n",
            word: "J",
            plain: ("1", ""),
            point: ("0.4", ""),
            unit: Unit::Units,
            probe: |m, c| (15.0 - 1.0) * c.unit - first(m).x_dia / 2.0,
        },
        Row {
            what: "LinuxCNC G76 K: the thread depth",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P2 Z-20 I-1 J0.4 K{v}\n",
            word: "K",
            plain: ("2", ""),
            point: ("1.5", ""),
            unit: Unit::Units,
            probe: |m, c| (15.0 - 1.0) * c.unit - last(m).x_dia / 2.0,
        },
        // E with L1: each pass begins with the entry taper, a thread move over E along Z.
        Row {
            what: "LinuxCNC G76 E: the taper length",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P2 Z-20 I-1 J0.4 K1.5 E{v} L1\n",
            word: "E",
            plain: ("2", ""),
            point: ("2.", ""),
            unit: Unit::Units,
            probe: |m, _| first(m).z_start - first(m).z,
        },
        Row {
            what: "LinuxCNC G76 Z: the thread's end",
            dialects: L,
            template: "G8 G0 X15 Z5 M3\nG76 P2 Z{v} I-1 J0.4 K1.5\n",
            word: "Z",
            plain: ("-20", ""),
            point: ("-20.", ""),
            unit: Unit::Units,
            probe: |m, _| last(m).z,
        },
    ]
}

/// The last feed along Z of a G71's moves: its finishing pass along the shape's `G1 Z-30.`
/// (moved by the allowances).
fn finishing_feed(m: &[Move]) -> &Move {
    m.iter()
        .rev()
        .find(|m| m.kind == MoveKind::Feed && m.x_start == m.x_dia && m.z != m.z_start)
        .expect("a feed along Z")
}

fn run(
    text: &str,
    dialect: Dialect,
    decimal_point: DecimalPoint,
    increment: InputIncrement,
) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "U.NC".into(),
        text: text.into(),
    };
    let opts = Options {
        settings: Settings {
            decimal_point,
            input_increment: increment,
            ..Settings::default()
        },
        ..Options::default()
    };
    interpret_with(&src, dialect, &|_| None, &opts)
}

/// Every row in every reading: its dialects, standard and calculator-type input (FANUC,
/// GSK), mm and inch, without and with a decimal point; the word's effect on the moves
/// equals what the manual's rule makes of the literal, or the run stops at the word.
#[test]
fn every_cycle_word_reads_as_its_manual_says() {
    let mut checked = 0;
    for row in rows() {
        for &dialect in row.dialects {
            let fanuc = matches!(dialect, Dialect::Fanuc | Dialect::Gsk980);
            let inputs: &[bool] = if fanuc { &[false, true] } else { &[false] };
            for &calculator in inputs {
                for inch in [false, true] {
                    for point in [false, true] {
                        let (v, h) = if point { row.point } else { row.plain };
                        let units = match (dialect, inch) {
                            (Dialect::Siemens802d | Dialect::Siemens840d, true) => "G70\n",
                            (Dialect::Siemens802d | Dialect::Siemens840d, false) => "G71\n",
                            (_, true) => "G20\n",
                            (_, false) => "G21\n",
                        };
                        let text = format!(
                            "{units}{}",
                            row.template.replace("{v}", v).replace("{h}", h)
                        );
                        let c = Ctx {
                            unit: if inch { 25.4 } else { 1.0 },
                            inc: if inch { 0.00254 } else { 0.001 },
                        };
                        let literal: f64 = v.parse().unwrap();
                        let want = manual(row.unit, literal, point, calculator, c);
                        let mode = if calculator {
                            DecimalPoint::Calculator
                        } else {
                            DecimalPoint::Standard
                        };
                        let got = run(&text, dialect, mode, InputIncrement::Micrometre);
                        let at = format!(
                            "{} ({dialect:?}, {}, {}, {}):\n{text}",
                            row.what,
                            mode.name(),
                            if inch { "inch" } else { "mm" },
                            if point { "point" } else { "no point" }
                        );
                        match (want, got) {
                            (Some(want), Ok(t)) => {
                                let v = (row.probe)(&t.moves, c);
                                assert!(
                                    (v - want).abs() <= 1e-9 * want.abs().max(1.0),
                                    "{at}\nmeasured {v}, the manual's rule gives {want}"
                                );
                            }
                            (None, Err(e)) => {
                                // Stopped at the word: its line, its column, its letter.
                                let line = text
                                    .lines()
                                    .position(|l| l.contains(&format!("{}{v}", row.word)))
                                    .unwrap()
                                    + 1;
                                let col = text
                                    .lines()
                                    .nth(line - 1)
                                    .unwrap()
                                    .find(&format!("{}{v}", row.word))
                                    .unwrap()
                                    + 1;
                                assert_eq!((e.line, e.col), (line, col), "{at}\n{e}");
                                assert!(e.message.contains("decimal point"), "{at}\n{e}");
                            }
                            (Some(want), Err(e)) => panic!("{at}\nwanted {want}, got: {e}"),
                            (None, Ok(t)) => {
                                panic!("{at}\nwanted an error, got {:?}", threads(&t.moves))
                            }
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 400, "{checked} readings");
}
