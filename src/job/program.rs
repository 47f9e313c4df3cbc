//! The `[program]` table: the program file, its dialect and the machine's settings that the
//! program cannot say (thread chamfer, work offsets, reference points, G-code system,
//! decimal-point input, the least input increment, the modes at power-on, the main program),
//! checked and made into the program stage's [`Program`]. The program itself runs in the
//! program stage ([`crate::toolpath`]), after parsing.

use super::ctx::Ctx;
use super::schema::RawProgram;
use super::JobError;
use crate::nc::{DecimalPoint, Dialect, GcodeSystem, InputIncrement, Settings};
use crate::toolpath::Program;

/// A lathe job's `[program]`.
pub(super) fn lathe_program(pr: &RawProgram, cx: &Ctx, strict: bool) -> Result<Program, JobError> {
    let mut settings = Settings {
        thread_chamfer: cx.non_negative("program.thread_chamfer", pr.thread_chamfer)?,
        block_skip: pr.block_skip,
        ..Settings::default()
    };
    if settings.thread_chamfer > 9.9 {
        return Err(cx.err(
            "program.thread_chamfer",
            format!(
                "expected at most 9.9 leads (FANUC's 99 x 0.1 L), got {}",
                settings.thread_chamfer
            ),
        ));
    }
    if let Some(g) = &pr.gcode_system {
        settings.gcode_system = GcodeSystem::from_name(g).ok_or_else(|| {
            cx.err(
                "program.gcode_system",
                format!("expected \"A\", \"B\" or \"C\" (FANUC lathe G-code system), got `{g}`"),
            )
        })?;
    }
    if let Some(m) = &pr.feed_mode {
        settings.power_on.per_minute = match m.as_str() {
            "per-revolution" => false,
            "per-minute" => true,
            _ => {
                return Err(cx.err(
                    "program.feed_mode",
                    format!("expected \"per-revolution\" (G99, G95) or \"per-minute\" (G98, G94): the feed mode at power-on, got `{m}`"),
                ))
            }
        };
    }
    if let Some(m) = &pr.x_mode {
        settings.power_on.diameter = Some(match m.as_str() {
            "diameter" => true,
            "radius" => false,
            _ => {
                return Err(cx.err(
                    "program.x_mode",
                    format!(
                    "expected \"diameter\" or \"radius\": how X words are programmed, got `{m}`"
                ),
                ))
            }
        });
    }
    if let Some(p) = &pr.second_reference_point {
        settings.second_reference_point = Some((
            cx.finite("program.second_reference_point.x", p.x)?,
            cx.finite("program.second_reference_point.z", p.z)?,
        ));
    }
    if let Some(p) = &pr.reference_point {
        settings.reference_point = Some((
            cx.finite("program.reference_point.x", p.x)?,
            cx.finite("program.reference_point.z", p.z)?,
        ));
    }
    for (name, off) in &pr.work_offsets {
        let key = format!("program.work_offsets.{name}");
        let i = work_index(name)
            .ok_or_else(|| cx.err(&key, format!("expected one of G54..G59, got `{name}`")))?;
        if off.y.is_some() {
            return Err(cx.err(
                &format!("{key}.y"),
                "a lathe's work offsets have x (a diameter) and z; y is for milling jobs",
            ));
        }
        settings.work_offsets[i] = (
            cx.finite(&format!("{key}.x"), off.x)?,
            cx.finite(&format!("{key}.z"), off.z)?,
        );
    }
    program(pr, settings, cx, strict)
}

/// The program of `pr` with `settings`: its dialect checked, and the settings every
/// program has (decimal-point input, the least input increment, the units at power-on,
/// the main program) read.
pub(super) fn program(
    pr: &RawProgram,
    mut settings: Settings,
    cx: &Ctx,
    strict: bool,
) -> Result<Program, JobError> {
    if let Some(d) = &pr.decimal_point {
        settings.decimal_point = DecimalPoint::from_name(d).ok_or_else(|| {
            cx.err(
                "program.decimal_point",
                format!("expected \"standard\" (a number without a decimal point counts in the least input increment: X30 is 0.030 mm) or \"calculator\" (in mm: X30 is 30 mm), got `{d}`"),
            )
        })?;
    }
    if let Some(i) = pr.input_increment {
        settings.input_increment = InputIncrement::from_mm(i).ok_or_else(|| {
            cx.err(
                "program.input_increment",
                format!("expected 0.001 (mm; 0.0001 in in inch programs, FANUC's IS-B) or 0.0001 (IS-C), got {i}"),
            )
        })?;
    }
    if let Some(u) = &pr.units {
        settings.power_on.inch = match u.as_str() {
            "mm" => false,
            "inch" => true,
            _ => {
                return Err(cx.err(
                    "program.units",
                    format!(
                        "expected \"mm\" (G21) or \"inch\" (G20): the units at power-on, got `{u}`"
                    ),
                ))
            }
        };
    }
    if let Some(m) = &pr.main {
        let t = m.trim();
        let digits = t.strip_prefix('O').unwrap_or(t);
        if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) || digits.len() > 5 {
            return Err(cx.err(
                "program.main",
                format!("expected a program number such as \"O1000\", got `{m}`"),
            ));
        }
        settings.main = Some(format!("O{digits}"));
    }
    let dialect = Dialect::from_name(&pr.dialect).ok_or_else(|| {
        cx.err(
            "program.dialect",
            format!(
                "expected `fanuc`, `gsk980`, `linuxcnc`, `siemens-802d` or `siemens-840d`, got `{}`",
                pr.dialect
            ),
        )
    })?;
    if !matches!(dialect, Dialect::Fanuc | Dialect::Gsk980) {
        // Siemens and LinuxCNC read every number in program units and a file is one program
        // (its subprograms are called by name).
        for (key, given) in [
            ("program.decimal_point", pr.decimal_point.is_some()),
            ("program.input_increment", pr.input_increment.is_some()),
            ("program.main", pr.main.is_some()),
        ] {
            if given {
                return Err(cx.err(
                    key,
                    format!("a FANUC/GSK setting: {} reads every number in program units, one program a file", pr.dialect),
                ));
            }
        }
    }
    Ok(Program {
        file: pr.file.clone(),
        dialect,
        options: crate::nc::Options {
            strict: strict || pr.strict,
            settings,
            ..crate::nc::Options::default()
        },
    })
}

/// G54..G59 as an index.
pub(super) fn work_index(name: &str) -> Option<usize> {
    ["G54", "G55", "G56", "G57", "G58", "G59"]
        .iter()
        .position(|g| *g == name)
}
