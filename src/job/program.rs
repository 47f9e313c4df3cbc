//! The `[program]` table: the program file, its dialect and the machine's settings that the
//! program cannot say (thread chamfer, work offsets, reference points, G-code system,
//! decimal-point input, the least input increment, the modes at power-on, the main program),
//! checked and made into the program stage's [`Program`]. The program itself runs in the
//! program stage ([`crate::toolpath`]), after parsing.

use super::ctx::Ctx;
use super::schema::{RawMachine, RawProgram};
use super::JobError;
use crate::model::setup::Blank;
use crate::nc::{
    DecimalPoint, Dialect, G76Params, GcodeSystem, InputIncrement, NoseOffset, Settings,
    ToolOffsets,
};
use crate::toolpath::Program;
use std::collections::BTreeMap;

/// Where a lathe's reference points are when the job does not say: clear of the blank,
/// `HOME_CLEARANCE` mm over its diameter and in front of its face. A lathe's reference
/// point (its machine zero on most) lies far from the part; the job's frame puts the work
/// zero, and with no work offset the machine zero too, on the part's axis at its face, so
/// the machine zero would send every `G28 U0 W0` through the part.
pub(crate) const HOME_CLEARANCE: f64 = 100.0;

/// The reference point a lathe job without `[program] reference_point` (or
/// `second_reference_point`) assumes: (diameter, z) clear of `blank` ([`HOME_CLEARANCE`]).
pub(crate) fn assumed_home(blank: &Blank) -> (f64, f64) {
    (
        blank.diameter + HOME_CLEARANCE,
        blank.z_front + HOME_CLEARANCE,
    )
}

/// A lathe job's `[program]`, with what `[machine]` says about the control (`None`: the
/// defaults): the tool offsets and G76's parameters; the reference points not given are
/// taken clear of `blank` ([`assumed_home`]).
pub(super) fn lathe_program(
    pr: &RawProgram,
    machine: Option<&RawMachine>,
    blank: &Blank,
    cx: &Ctx,
    strict: bool,
) -> Result<Program, JobError> {
    let mut settings = Settings {
        thread_chamfer: cx.non_negative("program.thread_chamfer", pr.thread_chamfer)?,
        block_skip: pr.block_skip,
        ..Settings::default()
    };
    if let Some(m) = machine {
        settings.tool_offsets = tool_offsets(m, cx)?;
        settings.noses.offset = nose_offsets(m, cx)?;
        settings.g76 = g76_params(m, cx)?;
    }
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
        settings.gcode_system_named = true;
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
    settings.second_reference_point = Some(match &pr.second_reference_point {
        Some(p) => (
            cx.finite("program.second_reference_point.x", p.x)?,
            cx.finite("program.second_reference_point.z", p.z)?,
        ),
        None => assumed_home(blank),
    });
    settings.reference_point = Some(match &pr.reference_point {
        Some(p) => (
            cx.finite("program.reference_point.x", p.x)?,
            cx.finite("program.reference_point.z", p.z)?,
        ),
        None => assumed_home(blank),
    });
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
                "expected `fanuc`, `gsk980`, `linuxcnc`, `siemens-802d`, `siemens-840d` or `okuma`, got `{}`",
                pr.dialect
            ),
        )
    })?;
    if !pr.subroutine_path.is_empty() && dialect != Dialect::Linuxcnc {
        return Err(cx.err(
            "program.subroutine_path",
            format!(
                "a LinuxCNC setting (the INI's SUBROUTINE_PATH, where `o<name> call` finds name.ngc): {} programs call subprograms otherwise",
                pr.dialect
            ),
        ));
    }
    for (k, d) in pr.subroutine_path.iter().enumerate() {
        if d.trim().is_empty() {
            return Err(cx.err(
                "program.subroutine_path",
                format!("expected folder names, entry {} is empty", k + 1),
            ));
        }
    }
    settings.subroutine_path = pr.subroutine_path.clone();
    if !pr.definitions.is_empty() && !matches!(dialect, Dialect::Siemens802d | Dialect::Siemens840d)
    {
        return Err(cx.err(
            "program.definitions",
            format!(
                "Siemens data (GUD and macro definition files, the machine's cycles): {} programs have none",
                pr.dialect
            ),
        ));
    }
    for (k, d) in pr.definitions.iter().enumerate() {
        if d.trim().is_empty() {
            return Err(cx.err(
                "program.definitions",
                format!("expected file names, entry {} is empty", k + 1),
            ));
        }
    }
    settings.definitions = pr.definitions.clone();
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

/// `[machine] g76_*`: the G76 first block's values the control's parameters hold (FANUC
/// No. 5142, 5143, 5140, 5141), vpcut's defaults where the job gives none.
fn g76_params(m: &RawMachine, cx: &Ctx) -> Result<G76Params, JobError> {
    let mut p = G76Params::default();
    if let Some(n) = m.g76_finish_passes {
        if !(1..=99).contains(&n) {
            return Err(cx.err(
                "machine.g76_finish_passes",
                format!("expected 1 to 99 finishing passes, got {n}"),
            ));
        }
        p.finish_passes = n;
    }
    if let Some(a) = m.g76_tool_angle {
        if ![80.0, 60.0, 55.0, 30.0, 29.0, 0.0].contains(&a) {
            return Err(cx.err(
                "machine.g76_tool_angle",
                format!("expected one of 80, 60, 55, 30, 29, 0 degrees (G76's aa), got {a}"),
            ));
        }
        p.tool_angle = a;
    }
    for (key, v, slot) in [
        ("machine.g76_min_cut", m.g76_min_cut, &mut p.min_cut),
        (
            "machine.g76_finish_allowance",
            m.g76_finish_allowance,
            &mut p.finish_allowance,
        ),
    ] {
        if let Some(v) = v {
            let v = cx.non_negative(key, v)?;
            if v > 10.0 {
                return Err(cx.err(key, format!("expected at most 10 mm, got {v}")));
            }
            *slot = v;
        }
    }
    Ok(p)
}

/// `[machine] offsets`: each number's shift of the tool's point (X as a diameter, Z), its
/// `x`/`z` (the geometry's) and `wear_x`/`wear_z` added; `None` without the table.
fn tool_offsets(m: &RawMachine, cx: &Ctx) -> Result<Option<ToolOffsets>, JobError> {
    let Some(table) = &m.offsets else {
        return Ok(None);
    };
    let mut out = BTreeMap::new();
    for (name, o) in table {
        let key = format!("machine.offsets.{name}");
        let n = name
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=99).contains(n))
            .ok_or_else(|| {
                cx.err(
                    &key,
                    format!("expected an offset number 1 to 99 (T0305 calls 5), got `{name}`"),
                )
            })?;
        let v = |k: &str, v: f64| cx.finite(&format!("{key}.{k}"), v);
        out.insert(
            n,
            (
                v("x", o.x)? + v("wear_x", o.wear_x)?,
                v("z", o.z)? + v("wear_z", o.wear_z)?,
            ),
        );
    }
    Ok(Some(out))
}

/// `[machine] offsets`: each number's nose radius R (`r` + `wear_r`) and tip direction T
/// (`t`), as the offset page holds them for tool nose radius compensation.
fn nose_offsets(m: &RawMachine, cx: &Ctx) -> Result<BTreeMap<u32, NoseOffset>, JobError> {
    let mut out = BTreeMap::new();
    for (name, o) in m.offsets.iter().flatten() {
        let Ok(n) = name.parse::<u32>() else {
            continue; // `tool_offsets` says what is wrong with the number
        };
        let key = |k: &str| format!("machine.offsets.{name}.{k}");
        let radius = match o.r {
            Some(r) => {
                let r = cx.non_negative(&key("r"), r)?;
                if r > 25.0 {
                    return Err(cx.err(&key("r"), format!("expected at most 25 mm, got {r}")));
                }
                Some(r)
            }
            None => None,
        };
        let wear = cx.finite(&key("wear_r"), o.wear_r)?;
        if wear.abs() > 25.0 {
            return Err(cx.err(
                &key("wear_r"),
                format!("expected at most 25 mm either way, got {wear}"),
            ));
        }
        let tip = match o.t {
            Some(t) if t <= 9 => Some(t as u8),
            Some(t) => {
                return Err(cx.err(
                    &key("t"),
                    format!(
                        "expected an imaginary tip direction 0 to 9 (the offset page's T), got {t}"
                    ),
                ))
            }
            None => None,
        };
        out.insert(n, NoseOffset { radius, wear, tip });
    }
    Ok(out)
}

/// G54..G59 as an index.
pub(super) fn work_index(name: &str) -> Option<usize> {
    ["G54", "G55", "G56", "G57", "G58", "G59"]
        .iter()
        .position(|g| *g == name)
}
