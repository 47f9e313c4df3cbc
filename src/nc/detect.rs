//! The FANUC lathe G-code system a program is written in, read from the program when the
//! job does not name it (issue 27: `G21 G40 G90 G95` ran only with `--gcode-system B`).
//!
//! FANUC 0i-TF/30i-B lathe manuals, "G code list" (the table in `codes::in_system_a`):
//! systems B and C have G90/G91 (absolute/incremental) and G94/G95 (feed per minute/
//! revolution), system A has none of these as modal codes (G90/G94 are its turning and
//! facing cycles and take X/Z; it has no G91 and no G95) and writes G98/G99 for the feed
//! modes and G50 for the spindle limit. A program with a mark of B/C and none of A is read
//! as system B, or C where it sets inch/metric with G70/G71 (C's codes for them); the
//! run then warns which system it read and which key names it.

use super::{Dialect, GcodeSystem, Options, Source};
use crate::diag::{Diagnostic, Severity};

/// What one block says about the system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mark {
    /// A system-B/C code (G91, G95, G90/G94 without coordinates).
    BorC,
    /// System C's inch/metric (G70/G71 without cycle words).
    C,
    /// A system-A code (G98/G99 feed modes, G50, G32, G92 with F).
    A,
}

/// The G codes of a comment-free, upper-case block (whole codes only) and whether it has
/// the letter `c` as a word address.
fn g_codes(block: &str) -> Vec<u32> {
    let b = block.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'G' && (i == 0 || !b[i - 1].is_ascii_alphabetic()) {
            let st = i + 1;
            let mut j = st;
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                j += 1;
            }
            if let Ok(v) = block[st..j].parse::<f64>() {
                if v.fract() == 0.0 && (0.0..1000.0).contains(&v) {
                    out.push(v as u32);
                }
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    out
}

/// Whether the block has a word with address `c` (a letter not inside a keyword).
fn has_word(block: &str, c: u8) -> bool {
    let b = block.as_bytes();
    (0..b.len()).any(|i| {
        b[i] == c
            && (i == 0 || !b[i - 1].is_ascii_alphabetic())
            && b.get(i + 1).is_some_and(|n| {
                n.is_ascii_digit() || matches!(n, b'-' | b'+' | b'.' | b'#' | b'[')
            })
    })
}

/// The marks of one block, with the code that makes each and why.
fn marks(block: &str) -> Vec<(Mark, String)> {
    let axes = [b'X', b'Z', b'U', b'W'].iter().any(|&c| has_word(block, c));
    let cycle_words = [b'P', b'Q', b'U', b'W', b'R', b'D', b'F', b'X', b'Z']
        .iter()
        .any(|&c| has_word(block, c));
    let mut out = Vec::new();
    for g in g_codes(block) {
        let m = match g {
            91 => Some((Mark::BorC, "G91 (incremental) is no system-A code")),
            95 => Some((Mark::BorC, "G95 (feed per revolution) is no system-A code")),
            90 if !axes => Some((
                Mark::BorC,
                "G90 without X/Z is absolute mode, not system A's turning cycle",
            )),
            94 if !axes => Some((
                Mark::BorC,
                "G94 without X/Z is feed per minute, not system A's facing cycle",
            )),
            70 | 71 if !cycle_words => Some((
                Mark::C,
                "G70/G71 without cycle words is system C's inch/metric",
            )),
            98 | 99 => Some((Mark::A, "G98/G99 are system A's feed modes")),
            50 => Some((Mark::A, "G50 is system A's")),
            32 => Some((Mark::A, "G32 is system A's threading")),
            92 if has_word(block, b'F') => {
                Some((Mark::A, "G92 with F is system A's threading cycle"))
            }
            _ => None,
        };
        if let Some((m, why)) = m {
            out.push((m, why.to_string()));
        }
    }
    out
}

/// The system a program is written in when its blocks (1-based line, comment-free
/// upper-case text) show it: `Some((system, line, why))` for B or C (the first block that
/// shows it), `None` when nothing marks B/C or something marks A.
pub(super) fn gcode_system<'a>(
    blocks: impl Iterator<Item = (usize, &'a str)>,
) -> Option<(GcodeSystem, usize, String)> {
    let mut first: Option<(usize, String)> = None;
    let mut c = false;
    for (line, text) in blocks {
        for (m, why) in marks(text) {
            match m {
                Mark::A => return None,
                Mark::C => c = true,
                Mark::BorC => {}
            }
            if m != Mark::A && first.is_none() {
                first = Some((line, why));
            }
        }
    }
    let (line, why) = first?;
    let system = if c { GcodeSystem::C } else { GcodeSystem::B };
    Some((system, line, why))
}

/// [`gcode_system`] of a program's text: comments `(..)` and `%` left out, `;` ends a
/// block as on a FANUC tape.
pub(super) fn gcode_system_of(text: &str) -> Option<(GcodeSystem, usize, String)> {
    let mut blocks = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut clean = String::new();
        let mut depth = 0;
        for ch in line.chars() {
            match ch {
                '(' => depth += 1,
                ')' if depth > 0 => depth -= 1,
                _ if depth > 0 => {}
                ';' => clean.push('\n'),
                c => clean.push(c.to_ascii_uppercase()),
            }
        }
        for b in clean.split('\n') {
            blocks.push((i + 1, b.to_string()));
        }
    }
    gcode_system(blocks.iter().map(|(l, b)| (*l, b.as_str())))
}

/// The system to read a FANUC lathe program in when the settings do not name one and the
/// program shows B or C: `(system, line, why)`.
pub(super) fn detected_system(
    main: &Source,
    dialect: Dialect,
    opts: &Options,
) -> Option<(GcodeSystem, usize, String)> {
    let s = &opts.settings;
    let open = dialect == Dialect::Fanuc
        && s.mill.is_none()
        && !s.gcode_system_named
        && s.gcode_system == GcodeSystem::A;
    if open {
        gcode_system_of(&main.text)
    } else {
        None
    }
}

/// The warning that says which system a program was read in and how to name it.
pub(super) fn system_warning(
    main: &Source,
    system: GcodeSystem,
    line: usize,
    why: &str,
) -> Diagnostic {
    let name = match system {
        GcodeSystem::A => "A",
        GcodeSystem::B => "B",
        GcodeSystem::C => "C",
    };
    Diagnostic {
        severity: Severity::Warning,
        file: main.name.clone(),
        line,
        col: 0,
        message: format!("read in FANUC G-code system {name}: {why}"),
        hint: Some(format!(
            "the program shows system {name} and nothing of system A; name the system with `[program] gcode_system = \"{name}\"` (or `--gcode-system {name}`) to silence this, or \"A\" to read it as system A"
        )),
        snippet: main.text.lines().nth(line.saturating_sub(1)).unwrap_or("").to_string(),
        stack: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sys(text: &str) -> Option<GcodeSystem> {
        gcode_system_of(text).map(|s| s.0)
    }

    /// Every code of the FANUC "G code list" that tells B/C from A, both ways, and the
    /// programs that must stay system A (vpcut's corpus writes A).
    #[test]
    fn programs_show_their_system() {
        use GcodeSystem::*;
        for (text, want) in [
            (
                "G21 G40 G90 G95\nG0 X40. Z5.\nG78 X39. Z-30. F1.5\n",
                Some(B),
            ),
            ("G20 G91\nG0 X-1.\n", Some(B)),
            ("G94\nG0 X40.\n", Some(B)),
            ("G71 G90 G95\nG0 X40. Z5.\n", Some(C)),
            ("G70\nG94\n", Some(C)),
            // System A: cycles with coordinates, feed modes, G50, G32, G92 threading.
            ("G21 G99\nG90 X40. Z-20. F0.2\n", None),
            ("G0 X40. Z5.\nG94 X10. Z-1. F0.2\n", None),
            ("G90 G95\nG50 S2000\n", None),
            ("G95\nG32 Z-20. F1.5\n", None),
            ("G90\nG92 X19. Z-20. F1.5\n", None),
            ("G71 U1. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.2\n", None),
            ("G0 X40. Z5.\nG1 Z-20. F0.2\n", None),
            // Comments and tape EOB: `(G95)` is no code, `;G95` is a block.
            ("(G91 G95)\nG0 X40.\n", None),
            ("G0 X40.;G95;\n", Some(B)),
        ] {
            assert_eq!(sys(text), want, "{text}");
        }
    }
}
