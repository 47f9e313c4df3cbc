//! Which G and M codes, addresses and keywords vpcut runs in each dialect, which it refuses
//! (known codes that would make the toolpath wrong if they were skipped), and which it does
//! not know (skipped with a warning, an error in strict mode). One table for the static
//! check and the interpreter, so that both say the same thing.

use super::Dialect;
pub(super) use super::GcodeSystem;

/// What to do with a code.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Verdict {
    /// vpcut runs it (or it changes nothing vpcut simulates: coolant, dwell, speed modes).
    Run,
    /// A code of the dialect that vpcut does not simulate and that moves the tool or the
    /// coordinates: skipping it would make the toolpath after it wrong, so it is an error.
    Refused(String),
    /// Not a code vpcut knows: skipped with a warning (an error in strict mode).
    Unknown(String),
}

/// What a G code of system B or C is in system A.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum InA {
    /// This system-A code.
    Code(u32),
    /// G90 (absolute) of B/C.
    Absolute,
    /// G91 (incremental) of B/C.
    Incremental,
    /// G98/G99 of B/C: the canned drilling cycles' return level; no lathe cycle of vpcut
    /// uses it.
    ReturnLevel,
}

/// The system-A code for the whole G code `g` of `system` (FANUC 0i-TF "G code list"):
///
/// | A | B | C | function |
/// |---|---|---|---|
/// | G20/G21 | G20/G21 | G70/G71 | inch/metric input |
/// | G32 | G33 | G33 | threading |
/// | G50 | G92 | G92 | coordinate system setting, maximum spindle speed |
/// | G70..G76 | G70..G76 | G72..G78 | multiple repetitive cycles (G76/G78: threading) |
/// | G90 | G77 | G20 | outer/inner diameter cutting cycle |
/// | G92 | G78 | G21 | threading cycle |
/// | G94 | G79 | G24 | end face turning cycle |
/// | G98/G99 | G94/G95 | G94/G95 | feed per minute/revolution |
/// | (U/W) | G90/G91 | G90/G91 | absolute/incremental |
/// | - | G98/G99 | G98/G99 | canned cycle return: initial level / R point |
///
/// Other codes are the same in the three systems.
pub(super) fn in_system_a(system: GcodeSystem, g: u32) -> InA {
    use GcodeSystem::*;
    InA::Code(match (system, g) {
        (A, g) => g,
        (B | C, 90) => return InA::Absolute,
        (B | C, 91) => return InA::Incremental,
        (B | C, 98 | 99) => return InA::ReturnLevel,
        (B | C, 33) => 32,
        (B | C, 92) => 50,
        (B | C, 94) => 98,
        (B | C, 95) => 99,
        (B, 77) => 90,
        (B, 78) => 92,
        (B, 79) => 94,
        (C, 20) => 90,
        (C, 21) => 92,
        (C, 24) => 94,
        (C, 70) => 20,
        (C, 71) => 21,
        (C, 72..=78) => g - 2,
        (_, g) => g,
    })
}

/// Codes with one decimal as integers x10 (G33.1 = 331).
fn tenths(code: f64) -> i64 {
    (code * 10.0).round() as i64
}

/// A G code of `dialect`.
pub(super) fn g_code(dialect: Dialect, code: f64) -> Verdict {
    let c = tenths(code);
    let whole = c % 10 == 0;
    let g = c / 10;
    let refused = |what: &str| {
        Verdict::Refused(format!(
            "G{} ({what}) is not simulated by vpcut yet",
            fmt(code)
        ))
    };
    match dialect {
        Dialect::Fanuc | Dialect::Gsk980 | Dialect::Okuma => match (g, whole) {
            (0..=4 | 17 | 18 | 19 | 20 | 21 | 28 | 32 | 34 | 40 | 41 | 42 | 50, true) => {
                Verdict::Run
            }
            (53 | 54..=59 | 65 | 76 | 92 | 96 | 97 | 98 | 99, true) => Verdict::Run,
            // G80 cancels a canned drilling cycle: none is modal in vpcut (a no-op; safety
            // lines such as `G18 G20 G40 G80 G99` carry it).
            (80, true) => Verdict::Run,
            (30, true) => Verdict::Run,
            // G84 (rigid tapping with M29; `fanuc::tap_modes`).
            (84, true) if dialect == Dialect::Fanuc => Verdict::Run,
            (10 | 52, true) => refused("coordinate system setting"),
            // Multiple repetitive cycles (`cycles.rs`).
            (70..=75, true) => Verdict::Run,
            (90 | 94, true) => Verdict::Run,
            // GSK G33, the Z tapping cycle: `motion::gsk_tap`.
            (33, true) if dialect == Dialect::Gsk980 => Verdict::Run,
            // The 980TDi's G92.1 (the threading cycle with the spindle under position
            // control, M14/M15): the same path as G92, which the block runs.
            (92, false) if dialect == Dialect::Gsk980 && c == 921 => Verdict::Run,
            // The 980TDi/988TA's enhanced multiple thread cycle (G76's words plus infeed
            // modes): skipping it would drop the thread, so it is refused by name.
            (78, true) if dialect == Dialect::Gsk980 => {
                refused("the 980TDi's enhanced multiple thread cutting cycle; write it as G76")
            }
            _ => Verdict::Unknown(format!(
                "G{} is not a {} code vpcut knows",
                fmt(code),
                name(dialect)
            )),
        },
        Dialect::Siemens840d => match (g, whole) {
            // Rigid tapping (thread moves on the spindle axis), the 840D's frame
            // suppression G500 (G53 as the 802D's).
            (331 | 332 | 500, true) => Verdict::Run,
            (153, true) => refused("frame and tool offset suppression"),
            _ => g_code(Dialect::Siemens802d, code),
        },
        Dialect::Siemens802d => match (g, whole) {
            (0..=4 | 9 | 17 | 18 | 19 | 25 | 26 | 33 | 34 | 35 | 40 | 41 | 42, true) => {
                Verdict::Run
            }
            (54..=59 | 60 | 64 | 70 | 71 | 90 | 91 | 94 | 95 | 96 | 97 | 450 | 451, true) => {
                Verdict::Run
            }
            (500 | 601 | 602 | 603 | 700 | 710, true) => Verdict::Run,
            // Reference and fixed point approach (`siemens::fixed_point`).
            (74 | 75, true) => Verdict::Run,
            // G53: this block in machine coordinates (802D sl "G53, G153 suppression of
            // settable frames"; `siemens`).
            (53, true) => Verdict::Run,
            (153 | 158 | 159, true) => refused("frame or machine coordinates"),
            (110..=112, true) => refused("polar coordinates"),
            (331 | 332, true) => refused("tapping"),
            _ => Verdict::Unknown(format!(
                "G{} is not a {} code vpcut knows",
                fmt(code),
                name(dialect)
            )),
        },
        Dialect::Linuxcnc => match (g, whole) {
            (0..=4 | 7 | 8 | 17 | 18 | 19 | 20 | 21 | 33 | 40 | 41 | 42 | 43 | 49, true) => {
                Verdict::Run
            }
            (54..=59 | 61 | 64 | 76 | 90 | 91 | 93 | 94 | 95 | 96 | 97 | 98 | 99, true) => {
                Verdict::Run
            }
            // Go home, machine coordinates, G92 offsets, G10 L2/L20: run by `apply`; G80
            // cancels a canned cycle (none is modal in vpcut: a no-op).
            (10 | 28 | 30 | 53 | 80 | 92, true) => Verdict::Run,
            _ if matches!(c, 281 | 301 | 591..=593 | 611 | 901 | 911 | 921..=923) => Verdict::Run,
            (52, true) => refused("local coordinate system offset"),
            // LinuxCNC 2.9's G70 (finishing) and G71/G72 (.1, .2: roughing) over an o-word
            // subroutine's contour (`lcnc_g7x`).
            (70..=72, true) => Verdict::Run,
            _ if matches!(c, 711 | 712 | 721 | 722) => Verdict::Run,
            // G33.1, rigid tapping: thread moves in and out (`motion::lc_rigid_tap`).
            _ if c == 331 => Verdict::Run,
            // G41.1/G42.1 (compensation with the block's D and L: `nose::nose_word`),
            // G43.1/G43.2 (tool length offsets: the tool's tip follows the program).
            _ if matches!(c, 411 | 421 | 431 | 432) => Verdict::Run,
            (38, false) => refused("probing"),
            (73 | 74 | 81..=89, true) => refused("canned cycle"),
            _ => Verdict::Unknown(format!(
                "G{} is not a {} code vpcut knows",
                fmt(code),
                name(dialect)
            )),
        },
    }
}

/// An M code of `dialect`.
pub(super) fn m_code(dialect: Dialect, code: f64) -> Verdict {
    let c = tenths(code);
    if c % 10 != 0 {
        return Verdict::Unknown(format!("M{} is not an M code vpcut knows", fmt(code)));
    }
    let m = c / 10;
    let known = match dialect {
        Dialect::Fanuc | Dialect::Gsk980 | Dialect::Okuma => {
            // M29: rigid tapping mode (`fanuc::tap_modes`).
            matches!(m, 0..=5 | 8 | 9 | 13 | 14 | 19 | 23 | 24 | 29 | 30 | 41..=44 | 98 | 99)
                || (dialect == Dialect::Gsk980 && m == 15)
        }
        Dialect::Siemens802d | Dialect::Siemens840d => {
            if m == 98 || m == 99 {
                return Verdict::Refused(format!(
                    "M{m} is not a Siemens word: call subprograms by name"
                ));
            }
            matches!(m, 0..=5 | 8 | 9 | 17 | 19 | 30 | 40..=45)
                || (dialect == Dialect::Siemens840d && matches!(m, 6 | 7 | 10 | 11 | 70))
        }
        // M70..M73: modal state saved and restored (`lcnc_modes`).
        Dialect::Linuxcnc => matches!(m, 0..=9 | 30 | 48 | 49 | 50..=53 | 60 | 70..=73),
    };
    if known {
        Verdict::Run
    } else {
        Verdict::Unknown(format!(
            "M{m} is not a {} M code vpcut knows (a machine-specific function?)",
            name(dialect)
        ))
    }
}

/// A G code of a FANUC machining centre (a milling program, `Settings::mill`).
pub(super) fn mill_g_code(code: f64) -> Verdict {
    let c = tenths(code);
    let whole = c % 10 == 0;
    let g = c / 10;
    let refused = |what: &str| {
        Verdict::Refused(format!(
            "G{} ({what}) is not simulated by vpcut's milling interpreter yet",
            fmt(code)
        ))
    };
    match (g, whole) {
        (0..=4 | 15 | 17..=21 | 40..=43 | 49 | 50 | 54..=59 | 61 | 64 | 65 | 69, true) => {
            Verdict::Run
        }
        // G80 cancels canned cycles (none runs); G98/G99 only choose their return level.
        (80 | 90 | 91 | 94 | 95 | 98 | 99, true) => Verdict::Run,
        (50, false) if c == 501 => Verdict::Run,
        (32..=34, true) => refused(
            "lathe threading: a machining centre mills threads by helical G02/G03 with a Z move",
        ),
        (73 | 74 | 76 | 81..=89, true) => refused("canned drilling cycle"),
        (28 | 30, true) => refused("reference point return: the position after it is unknown"),
        (10 | 52 | 53 | 92, true) => refused("coordinate system setting"),
        (16, true) => refused("polar coordinate command"),
        (31, true) => refused("skip function"),
        (44, true) => refused("tool length compensation in the - direction"),
        (51, true) => refused("scaling"),
        (51, false) if c == 511 => refused("programmable mirror image"),
        (68, true) => refused("coordinate system rotation"),
        _ => Verdict::Unknown(format!(
            "G{} is not a FANUC milling code vpcut knows",
            fmt(code)
        )),
    }
}

/// An M code of a FANUC machining centre.
pub(super) fn mill_m_code(code: f64) -> Verdict {
    let c = tenths(code);
    if c % 10 == 0 && matches!(c / 10, 0..=6 | 8 | 9 | 19 | 30 | 98 | 99) {
        Verdict::Run
    } else {
        Verdict::Unknown(format!(
            "M{} is not a FANUC milling M code vpcut knows (a machine-specific function?)",
            fmt(code)
        ))
    }
}

/// A G code: a milling program's (`mill`) or the dialect's lathe code.
pub(super) fn g_verdict(dialect: Dialect, mill: bool, code: f64) -> Verdict {
    if mill {
        mill_g_code(code)
    } else {
        g_code(dialect, code)
    }
}

/// An M code: a milling program's (`mill`) or the dialect's lathe code.
pub(super) fn m_verdict(dialect: Dialect, mill: bool, code: f64) -> Verdict {
    if mill {
        mill_m_code(code)
    } else {
        m_code(dialect, code)
    }
}

/// Address letters a FANUC milling program's blocks may carry (G, M, N, O aside).
pub(super) fn mill_address(letter: char) -> bool {
    matches!(
        letter,
        'X' | 'Y' | 'Z' | 'I' | 'J' | 'K' | 'R' | 'F' | 'S' | 'T' | 'P' | 'L' | 'H' | 'D' | 'Q'
    )
}

/// Address letters of a FANUC-syntax block: a milling program's (`mill`) or a lathe's.
pub(super) fn address(mill: bool, letter: char) -> bool {
    if mill {
        mill_address(letter)
    } else {
        fanuc_address(letter)
    }
}

/// Address letters the FANUC-syntax interpreter reads.
pub(super) fn fanuc_address(letter: char) -> bool {
    matches!(
        letter,
        'X' | 'Z'
            | 'U'
            | 'W'
            | 'F'
            | 'K'
            | 'Q'
            | 'S'
            | 'T'
            | 'R'
            | 'P'
            | 'L'
            | 'J'
            | 'I'
            | 'H'
            | 'E'
            | 'G'
            | 'M'
            | 'N'
            | 'O'
    )
}

/// Siemens addresses the interpreter reads (`X20`, `X=R1+2`, `SF=90`).
pub(super) fn siemens_address(name: &str) -> bool {
    matches!(
        name,
        "G" | "M" | "S" | "T" | "X" | "Z" | "F" | "K" | "I" | "SF" | "D" | "P" | "CR"
    )
}

/// Siemens words that are statements of their own and do nothing vpcut simulates; the rest
/// of their block is skipped with a warning.
pub(super) fn siemens_keyword(name: &str) -> bool {
    matches!(
        name,
        "MSG"
            | "DIAMON"
            | "DIAMOF"
            | "DIAM"
            | "STOPRE"
            | "SUPA"
            | "WAITM"
            | "SETMS"
            | "SPOS"
            | "SOFT"
            | "BRISK"
            | "FFWON"
            | "FFWOF"
            | "CFC"
            | "CFTCP"
            | "G64"
            | "LIMS"
            | "TRANS"
            | "ATRANS"
            | "ROT"
            | "AROT"
            | "SCALE"
            | "ASCALE"
            | "MIRROR"
            | "AMIRROR"
            | "DEF"
            | "CYCLE"
            | "CYCLE95"
            | "LCYC"
            | "LCYC97"
            | "STOPFIFO"
            | "STARTFIFO"
            | "GOTOC"
    )
}

/// Where a FANUC program `O<n>` may be found beside the main file (for messages).
pub(super) fn fanuc_file_name(name: &str) -> String {
    match name.strip_prefix('O').and_then(|n| n.parse::<u32>().ok()) {
        Some(n) => format!("O{n:04}"),
        None => name.to_string(),
    }
}

fn name(d: Dialect) -> &'static str {
    match d {
        Dialect::Fanuc => "FANUC lathe",
        Dialect::Gsk980 => "GSK 980TDC",
        Dialect::Siemens802d => "Siemens 802D",
        Dialect::Siemens840d => "Siemens 840D",
        Dialect::Linuxcnc => "LinuxCNC lathe",
        Dialect::Okuma => "Okuma OSP-P",
    }
}

fn fmt(code: f64) -> String {
    if code.fract() == 0.0 {
        format!("{}", code as i64)
    } else {
        format!("{code}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g90_is_absolute_on_siemens_and_a_cycle_on_fanuc() {
        assert_eq!(g_code(Dialect::Siemens802d, 90.0), Verdict::Run);
        assert_eq!(g_code(Dialect::Fanuc, 90.0), Verdict::Run);
        assert!(matches!(g_code(Dialect::Fanuc, 91.0), Verdict::Unknown(_)));
        assert_eq!(g_code(Dialect::Linuxcnc, 33.1), Verdict::Run);
        assert_eq!(g_code(Dialect::Linuxcnc, 33.0), Verdict::Run);
        for g in [70.0, 71.0, 71.1, 71.2, 72.0, 72.1, 72.2] {
            assert_eq!(g_code(Dialect::Linuxcnc, g), Verdict::Run, "G{g}");
        }
        assert!(matches!(m_code(Dialect::Fanuc, 123.0), Verdict::Unknown(_)));
        assert!(matches!(
            m_code(Dialect::Siemens802d, 98.0),
            Verdict::Refused(_)
        ));
    }

    #[test]
    fn mill_codes_run_refuse_or_are_unknown() {
        for g in [
            0.0, 2.0, 17.0, 18.0, 41.0, 43.0, 49.0, 57.0, 80.0, 90.0, 91.0, 95.0,
        ] {
            assert_eq!(mill_g_code(g), Verdict::Run, "G{g}");
        }
        for g in [32.0, 76.0, 81.0, 83.0, 28.0, 44.0, 52.0, 68.0, 51.0] {
            assert!(matches!(mill_g_code(g), Verdict::Refused(_)), "G{g}");
        }
        assert!(matches!(mill_g_code(12.0), Verdict::Unknown(_)));
        assert_eq!(mill_m_code(6.0), Verdict::Run);
        assert!(matches!(mill_m_code(23.0), Verdict::Unknown(_)));
        assert!(mill_address('Y') && mill_address('D') && !mill_address('U'));
    }
}
