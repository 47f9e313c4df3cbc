//! LinuxCNC (rs274ngc) expressions and parameters.
//!
//! rs274 reads a line with its white space removed and case folded; a value is a number, a
//! `[ ]` expression, a parameter `#n`/`#<name>`/`#[expr]`, a function or a signed value.
//! Binary operators are left-associative on five levels, lowest first: `AND OR XOR`;
//! `EQ NE GT GE LT LE`; `+ -`; `* / MOD`; `**` (so `2**3**2` is 64 and `-2**2` is 4, the sign
//! binding to its value). `EQ`/`NE` compare with rs274's tolerance 1e-4, the others exactly;
//! `MOD` is never negative (and not a number for `MOD 0`, as in rs274); `FIX` is floor, `FUP` ceil, `ROUND` rounds half away from zero;
//! angles are in degrees; `ATAN[a]/[b]` is atan2. All checked against rs274 2.9.0~pre1.
//!
//! Parameters: `#1..#30` are local to a subroutine call, `#31..#5160` global, both read 0
//! until set; `#<name>` is local to the call and `#<_name>` global, and reading either
//! before it is set is an error ("Named parameter not defined").
//!
//! Machine state (LinuxCNC manual, "Predefined Named Parameters" and "Numbered Parameters",
//! as of LinuxCNC 2.9): every `#<_..>` of the manual's list reads the interpreter's state
//! (`lc_predefined`); where vpcut has no such state it reads the value a control reads at
//! start-up (overrides enabled 1, adaptive feed and feed hold 0, `_task` 1, `_remap_level` 0,
//! axes vpcut does not have 0, `_vmajor`/`_vminor` 2 and 9). `#5161..#5428` read homes,
//! offsets, the tool and the position (`lc_system`). Lengths read in program units and X in
//! the active X mode (a diameter in G7, a radius in G8), as the program writes them, but the
//! current point (`#<_x>`, `#<_abs_x>`, `#5420`), whose X rs274 reads as a radius in G7 too.
//! `#<_ini[..]>` and `#<_hal[..]>` are refused (no INI file or HAL).

use super::expr::Fail;
use super::lex::Cursor;
use super::Interp;
use std::collections::HashMap;

/// rs274's `TOLERANCE_EQUAL` for `EQ` and `NE`.
const TOLERANCE_EQUAL: f64 = 0.0001;
/// The last numbered parameter a program may use.
const LAST_PARAMETER: u32 = 5160;

/// rs274's predefined (read-only) named parameters, upper-cased, with the `_ini[..]` and
/// `_hal[..]` forms.
pub(super) fn predefined(name: &str) -> bool {
    const NAMES: [&str; 56] = [
        "_VMAJOR",
        "_VMINOR",
        "_LINE",
        "_MOTION_MODE",
        "_PLANE",
        "_CCOMP",
        "_METRIC",
        "_IMPERIAL",
        "_ABSOLUTE",
        "_INCREMENTAL",
        "_INVERSE_TIME",
        "_UNITS_PER_MINUTE",
        "_UNITS_PER_REV",
        "_COORD_SYSTEM",
        "_TOOL_OFFSET",
        "_RETRACT_R_PLANE",
        "_RETRACT_OLD_Z",
        "_SPINDLE_RPM_MODE",
        "_SPINDLE_CSS_MODE",
        "_IJK_ABSOLUTE_MODE",
        "_LATHE_DIAMETER_MODE",
        "_LATHE_RADIUS_MODE",
        "_SPINDLE_ON",
        "_SPINDLE_CW",
        "_MIST",
        "_FLOOD",
        "_SPEED_OVERRIDE",
        "_FEED_OVERRIDE",
        "_ADAPTIVE_FEED",
        "_FEED_HOLD",
        "_FEED",
        "_RPM",
        "_X",
        "_Y",
        "_Z",
        "_A",
        "_B",
        "_C",
        "_U",
        "_V",
        "_W",
        "_ABS_X",
        "_ABS_Y",
        "_ABS_Z",
        "_ABS_A",
        "_ABS_B",
        "_ABS_C",
        "_CURRENT_TOOL",
        "_CURRENT_POCKET",
        "_SELECTED_TOOL",
        "_SELECTED_POCKET",
        "_VALUE",
        "_VALUE_RETURNED",
        "_TASK",
        "_CALL_LEVEL",
        "_REMAP_LEVEL",
    ];
    NAMES.contains(&name) || name.starts_with("_INI[") || name.starts_with("_HAL[")
}

/// Why a program may not assign the system parameter `n` (`None`: it may). The homes
/// #5161..#5169 and #5181..#5189 are written as a program writes them on a control (the
/// next G28/G30 goes there); offsets are set with G10 L2/L20 and G92, which vpcut runs.
pub(super) fn system_write_refused(n: u32) -> Option<String> {
    match n {
        0..=LAST_PARAMETER | 5161..=5169 | 5181..=5189 => None,
        5210..=5390 => Some(format!(
            "assigning #{n} (offsets) is not simulated: set offsets with G10 L2/L20 or G92"
        )),
        _ => Some(format!(
            "#{n} is machine state that vpcut reads but does not let a program set"
        )),
    }
}

/// A parameter a line sets.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Param {
    Num(u32),
    /// Upper-cased; a leading `_` makes it global.
    Named(String),
}

/// LinuxCNC parameter storage beside the FANUC variables: named parameters, and one level
/// of named locals and repeat counters per subroutine call.
#[derive(Default)]
pub(super) struct Params {
    pub(super) globals: HashMap<String, f64>,
    /// Index = call depth (the main program is 0). Entries beyond the current depth are
    /// stale (left by calls that returned) and replaced on the next call.
    pub(super) levels: Vec<Level>,
}

/// One subroutine call's named locals.
#[derive(Default)]
pub(super) struct Level {
    pub(super) named: HashMap<String, f64>,
}

/// Operator precedence levels, lowest first.
const LEVELS: [&[&str]; 5] = [
    &["AND", "XOR", "OR"],
    &["EQ", "NE", "GT", "GE", "LT", "LE"],
    &["+", "-"],
    &["*", "/", "MOD"],
    &["**"],
];

impl Interp<'_> {
    /// The current call depth (0 in the main program).
    pub(super) fn lc_depth(&self) -> usize {
        self.vars.locals.len() - 1
    }

    /// This call's level of named locals and repeat counters.
    pub(super) fn lc_level(&mut self) -> &mut Level {
        let d = self.lc_depth();
        if self.lc.params.levels.len() <= d {
            self.lc.params.levels.resize_with(d + 1, Level::default);
        }
        &mut self.lc.params.levels[d]
    }

    /// A fresh level for a call about to start.
    pub(super) fn lc_push_level(&mut self) {
        let d = self.lc_depth() + 1;
        self.lc_context_enter(d);
        self.lc.params.levels.resize_with(d, Level::default);
        self.lc.params.levels.truncate(d);
        self.lc.params.levels.push(Level::default());
    }

    fn lc_named(&self, name: &str) -> Option<f64> {
        if let Some(v) = self.lc_predefined(name) {
            return Some(v);
        }
        if name.starts_with('_') {
            let v = self.lc.params.globals.get(name).copied();
            // rs274's predefined return-value parameters read 0 before any call returns.
            v.or(matches!(name, "_VALUE" | "_VALUE_RETURNED").then_some(0.0))
        } else {
            self.lc
                .params
                .levels
                .get(self.lc_depth())
                .and_then(|l| l.named.get(name).copied())
        }
    }

    /// A length in program units and the active X mode from mm (X as a diameter).
    fn lc_len(&self, v: f64, x_axis: bool) -> f64 {
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let xs = if x_axis && !self.modal.diameter_mode {
            0.5
        } else {
            1.0
        };
        v * xs / scale
    }

    /// A predefined named parameter (upper-cased name), `None` if `name` is not one (or is
    /// `_VALUE`/`_VALUE_RETURNED`, kept with the globals).
    pub(super) fn lc_predefined(&self, name: &str) -> Option<f64> {
        let st = &self.lc.st;
        let b = |v: bool| f64::from(u8::from(v));
        let (px, pz) = self.lc_position();
        Some(match name {
            "_VMAJOR" => 2.0,
            "_VMINOR" => 9.0,
            "_LINE" => st.line as f64,
            // G33.1 (rigid tapping) is held as 331: its code in tenths already.
            "_MOTION_MODE" if self.modal.motion == 331 => 331.0,
            "_MOTION_MODE" => f64::from(self.modal.motion * 10),
            "_PLANE" => f64::from(st.plane),
            "_CCOMP" => f64::from(st.ccomp),
            "_METRIC" => b(!self.modal.inch),
            "_IMPERIAL" => b(self.modal.inch),
            "_ABSOLUTE" => b(!self.modal.incremental),
            "_INCREMENTAL" => b(self.modal.incremental),
            "_INVERSE_TIME" => b(st.feed_mode == 93),
            "_UNITS_PER_MINUTE" => b(st.feed_mode == 94),
            "_UNITS_PER_REV" => b(st.feed_mode == 95),
            "_COORD_SYSTEM" => match self.frames.work {
                w @ 0..=5 => 540.0 + 10.0 * w as f64,
                w => 590.0 + (w - 5) as f64,
            },
            "_TOOL_OFFSET" => b(st.tool_offset),
            "_RETRACT_R_PLANE" => b(st.retract_r),
            "_RETRACT_OLD_Z" => b(!st.retract_r),
            "_SPINDLE_RPM_MODE" => b(!self.modal.css),
            "_SPINDLE_CSS_MODE" => b(self.modal.css),
            "_IJK_ABSOLUTE_MODE" => b(st.ijk_absolute),
            "_LATHE_DIAMETER_MODE" => b(self.modal.diameter_mode),
            "_LATHE_RADIUS_MODE" => b(!self.modal.diameter_mode),
            "_SPINDLE_ON" => b(st.spindle_on),
            "_SPINDLE_CW" => {
                b(st.spindle_on && self.modal.spindle == crate::model::helix::Spindle::Cw)
            }
            "_MIST" => b(st.mist),
            "_FLOOD" => b(st.flood),
            "_SPEED_OVERRIDE" => b(st.speed_override),
            "_FEED_OVERRIDE" => b(st.feed_override),
            "_ADAPTIVE_FEED" => b(st.adaptive_feed),
            "_FEED_HOLD" => b(st.feed_hold),
            "_FEED" => self.modal.feed.unwrap_or(0.0),
            "_RPM" => self.modal.speed.unwrap_or(0.0),
            "_X" => px,
            "_Z" => pz,
            "_ABS_X" => self.lc_radius(self.x),
            "_ABS_Z" => self.lc_len(self.z, false),
            "_Y" | "_A" | "_B" | "_C" | "_U" | "_V" | "_W" | "_ABS_Y" | "_ABS_A" | "_ABS_B"
            | "_ABS_C" => 0.0,
            "_CURRENT_TOOL" | "_CURRENT_POCKET" => f64::from(self.modal.tool.unwrap_or(0)),
            "_SELECTED_TOOL" | "_SELECTED_POCKET" => st.selected_tool as f64,
            "_TASK" => 1.0,
            "_CALL_LEVEL" => self.lc_depth() as f64,
            "_REMAP_LEVEL" => 0.0,
            _ => return None,
        })
    }

    /// The current position in the active coordinate system (work offset and G92 applied),
    /// in program units, X in the active X mode.
    /// The current point in program units, X as a radius in G7 and G8: rs274 2.9.0~pre1
    /// reads `#<_x>`, `#<_abs_x>` and `#5420` as the radius even in diameter mode (`G7 G0
    /// X25` then `#<_x>` reads 12.5; checked with `rs274`, see
    /// `tests/data/linuxcnc/corpus/`).
    fn lc_position(&self) -> (f64, f64) {
        // While a G7x contour is read, rs274's current point is the contour's.
        if let Some(g) = &self.lc.g7x {
            return (g.at.im, g.at.re);
        }
        let (ox, oz) = self.frames.offsets[self.frames.work];
        let (gx, gz) = self.frames.g92_off;
        (
            self.lc_radius(self.x - ox - gx),
            self.lc_len(self.z - oz - gz, false),
        )
    }

    /// A diameter in mm as the radius in program units.
    fn lc_radius(&self, dia: f64) -> f64 {
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        dia * 0.5 / scale
    }

    /// A numbered system parameter above #5160 (LinuxCNC manual, "Numbered Parameters"):
    /// `None` where vpcut does not model it. Axes vpcut does not have (Y, A, B, C, U, V,
    /// W, the rotation R) read 0.
    pub(super) fn lc_system(&self, n: u32) -> Option<f64> {
        let st = &self.lc.st;
        // (X, Z) of a block of nine axes X Y Z A B C U V W starting at `base`.
        let axis = |base: u32, p: (f64, f64)| -> Option<f64> {
            match n - base {
                0 => Some(self.lc_len(p.0, true)),
                2 => Some(self.lc_len(p.1, false)),
                _ => Some(0.0),
            }
        };
        match n {
            5161..=5169 => axis(5161, st.home28),
            5181..=5189 => axis(5181, st.home30),
            5210 => Some(f64::from(u8::from(st.g92_on))),
            5211..=5219 => axis(5211, st.g92_params),
            5220 => Some(self.frames.work as f64 + 1.0),
            5221..=5390 => {
                let k = ((n - 5221) / 20) as usize;
                let base = 5221 + 20 * k as u32;
                if n - base >= 10 {
                    return None;
                }
                if n - base == 9 {
                    return Some(0.0); // the XY rotation R
                }
                axis(base, self.frames.offsets[k])
            }
            5400 => Some(f64::from(self.modal.tool.unwrap_or(0))),
            // Tool offsets, diameter, angles and orientation: vpcut has no tool table.
            5401..=5413 => Some(0.0),
            // The current point, X as a radius (see `lc_position`).
            5420 => Some(self.lc_position().0),
            5422 => Some(self.lc_position().1),
            5421 | 5423..=5428 => Some(0.0),
            _ => None,
        }
    }

    /// Set a parameter (after its line was read).
    pub(super) fn lc_set(&mut self, p: Param, v: f64) {
        match p {
            Param::Num(n) if n <= 30 => {
                self.vars
                    .locals
                    .last_mut()
                    .expect("level 0 always exists")
                    .insert(n, v);
            }
            Param::Num(n) if n > LAST_PARAMETER => {
                // Only the homes are writable (`system_write_refused`): G28/G30 go there.
                let scale = if self.modal.inch { 25.4 } else { 1.0 };
                let xs = if self.modal.diameter_mode { 1.0 } else { 2.0 };
                let st = &mut self.lc.st;
                let home = if n < 5181 {
                    &mut st.home28
                } else {
                    &mut st.home30
                };
                match n % 20 {
                    1 => home.0 = v * scale * xs,
                    3 => home.1 = v * scale,
                    _ => {}
                }
            }
            Param::Num(n) => {
                self.vars.common.insert(n, v);
            }
            Param::Named(name) if name.starts_with('_') => {
                self.lc.params.globals.insert(name, v);
            }
            Param::Named(name) => {
                self.lc_level().named.insert(name, v);
            }
        }
    }

    /// rs274 (`read_named_parameter_setting` calls `add_named_param`): a named parameter a
    /// line sets exists (as 0) from the moment its name is read, before the value's
    /// expression, so `#<n> = [#<n> + 1]` counts from 0 where `#<n>` was never set.
    pub(super) fn lc_declare(&mut self, name: &str) {
        let table = if name.starts_with('_') {
            &mut self.lc.params.globals
        } else {
            &mut self.lc_level().named
        };
        table.entry(name.to_string()).or_insert(0.0);
    }

    /// After `#`: which parameter (`n`, `[expr]`, `#..`, `<name>`).
    pub(super) fn lc_param(&self, c: &mut Cursor) -> Result<Param, Fail> {
        let at = c.col();
        if c.eat("<") {
            return Ok(Param::Named(c.angle_name()?));
        }
        let v = self.lc_value(c)?;
        let n = v.round();
        if (v - n).abs() > 1e-4 {
            return Err((at, format!("parameter number {v} is not an integer")));
        }
        if !(1.0..=5601.0).contains(&n) {
            return Err((
                at,
                format!("parameter number {n} is out of range (1..5601)"),
            ));
        }
        if n > f64::from(LAST_PARAMETER) && self.lc_system(n as u32).is_none() {
            return Err((
                at,
                format!(
                    "system parameter #{n} is not modelled (vpcut models #5161..#5189 homes, #5210..#5219 G92, #5220..#5390 work offsets, #5400..#5413 the tool, #5420..#5428 the position)"
                ),
            ));
        }
        Ok(Param::Num(n as u32))
    }

    /// Read a parameter after `#`.
    fn lc_read(&self, c: &mut Cursor) -> Result<f64, Fail> {
        // Errors point at the `#`.
        let at = c.col_at(c.i.saturating_sub(1));
        match self.lc_param(c)? {
            Param::Num(n) if n <= 30 => Ok(self
                .vars
                .locals
                .last()
                .and_then(|l| l.get(&n))
                .copied()
                .unwrap_or(0.0)),
            Param::Num(n) if n > LAST_PARAMETER => Ok(self.lc_system(n).unwrap_or(0.0)),
            Param::Num(n) => Ok(self.vars.common.get(&n).copied().unwrap_or(0.0)),
            Param::Named(name) => self.lc_named(&name).ok_or_else(|| {
                let name = name.to_lowercase();
                let msg = if predefined(&name.to_uppercase()) {
                    format!("the predefined parameter #<{name}> (machine state) is not modelled")
                } else {
                    format!("named parameter #<{name}> is not defined")
                };
                (at, msg)
            }),
        }
    }

    /// A bracketed expression `[..]`.
    pub(super) fn lc_bracket(&self, c: &mut Cursor) -> Result<f64, Fail> {
        if !c.eat("[") {
            return c.err("expected `[` starting an expression");
        }
        let at = c.col_at(c.i.saturating_sub(1));
        let v = self.lc_binary(c, 0)?;
        if !c.eat("]") {
            return c.err("expected an operator or `]`");
        }
        if v.is_nan() {
            // rs274 checks each bracket's value (`[1 NE 1 MOD 0]` is 0, `[[1 MOD 0] NE 0]`
            // an error).
            return Err((at, "the calculation resulted in `not a number`".into()));
        }
        Ok(v)
    }

    fn lc_binary(&self, c: &mut Cursor, level: usize) -> Result<f64, Fail> {
        if level == LEVELS.len() {
            return self.lc_value(c);
        }
        let mut v = self.lc_binary(c, level + 1)?;
        loop {
            let at = c.col();
            // `**` before `*`: the multiplicative level must not take the power's first star.
            if level == 3 && c.s[c.i..].starts_with(b"**") {
                return Ok(v);
            }
            let Some(op) = LEVELS[level].iter().find(|op| c.eat(op)) else {
                return Ok(v);
            };
            let w = self.lc_binary(c, level + 1)?;
            v = match *op {
                "AND" => f64::from(v != 0.0 && w != 0.0),
                "OR" => f64::from(v != 0.0 || w != 0.0),
                "XOR" => f64::from((v != 0.0) != (w != 0.0)),
                "EQ" => f64::from((v - w).abs() < TOLERANCE_EQUAL),
                "NE" => f64::from((v - w).abs() >= TOLERANCE_EQUAL),
                "GT" => f64::from(v > w),
                "GE" => f64::from(v >= w),
                "LT" => f64::from(v < w),
                "LE" => f64::from(v <= w),
                "+" => v + w,
                "-" => v - w,
                "*" => v * w,
                "/" if w == 0.0 => return Err((at, "division by zero".into())),
                // rs274 computes fmod(v, 0), not a number, and goes on: a comparison or
                // logic operator can make a number of it again before the bracket closes.
                "MOD" if w == 0.0 => f64::NAN,
                "/" => v / w,
                "MOD" => {
                    let r = v % w;
                    if r < 0.0 {
                        r + w.abs()
                    } else {
                        r
                    }
                }
                "**" => {
                    if v < 0.0 && w.fract() != 0.0 {
                        return Err((at, "a negative number to a non-integer power".into()));
                    }
                    if v == 0.0 && w < 0.0 {
                        return Err((at, "zero to a negative power".into()));
                    }
                    v.powf(w)
                }
                _ => unreachable!("every operator of LEVELS is handled"),
            };
        }
    }

    /// rs274's `read_real_value`: a number, `[expr]`, a parameter, a function or a sign
    /// followed by one of those.
    pub(super) fn lc_value(&self, c: &mut Cursor) -> Result<f64, Fail> {
        if c.nest >= 100 {
            return c.err("values nested more than 100 deep");
        }
        c.nest += 1;
        let v = self.lc_value_inner(c);
        c.nest -= 1;
        v
    }

    fn lc_value_inner(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let at = c.col();
        match c.peek() {
            None => c.err("expected a value"),
            Some(b'[') => self.lc_bracket(c),
            Some(b'#') => {
                c.i += 1;
                self.lc_read(c)
            }
            Some(s @ (b'+' | b'-'))
                if !c
                    .peek_at(1)
                    .is_some_and(|b| b.is_ascii_digit() || b == b'.') =>
            {
                c.i += 1;
                let v = self.lc_value(c)?;
                Ok(if s == b'-' { -v } else { v })
            }
            Some(b'+' | b'-' | b'0'..=b'9' | b'.') => {
                let neg = c.eat("-");
                let _ = neg || c.eat("+");
                match c.number() {
                    Some(v) => Ok(if neg { -v } else { v }),
                    None => c.err("expected a number"),
                }
            }
            Some(b) if b.is_ascii_alphabetic() => {
                let name = c.ident();
                self.lc_function(c, &name, at)
            }
            Some(_) => Err((at, format!("expected a value, found {}", c.here()))),
        }
    }

    fn lc_function(&self, c: &mut Cursor, name: &str, at: usize) -> Result<f64, Fail> {
        if name == "EXISTS" {
            if !(c.eat("[") && c.eat("#") && c.eat("<")) {
                return c.err("expected EXISTS[#<name>]");
            }
            let n = c.angle_name()?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            return Ok(f64::from(self.lc_named(&n).is_some()));
        }
        const KNOWN: [&str; 13] = [
            "ABS", "ACOS", "ASIN", "ATAN", "COS", "EXP", "FIX", "FUP", "ROUND", "LN", "SIN",
            "SQRT", "TAN",
        ];
        if !KNOWN.contains(&name) {
            return Err((at, format!("unknown function or word `{name}`")));
        }
        let a = self.lc_bracket(c)?;
        let domain = |ok: bool, what: &str| -> Result<(), Fail> {
            if ok {
                Ok(())
            } else {
                Err((at, format!("{name} of {a}: {what}")))
            }
        };
        Ok(match name {
            "ATAN" => {
                if !c.eat("/") {
                    return c.err("expected ATAN[y]/[x]");
                }
                let b = self.lc_bracket(c)?;
                a.atan2(b).to_degrees()
            }
            "ABS" => a.abs(),
            "ACOS" => {
                domain((-1.0..=1.0).contains(&a), "outside -1..1")?;
                a.acos().to_degrees()
            }
            "ASIN" => {
                domain((-1.0..=1.0).contains(&a), "outside -1..1")?;
                a.asin().to_degrees()
            }
            "COS" => a.to_radians().cos(),
            "SIN" => a.to_radians().sin(),
            "TAN" => a.to_radians().tan(),
            "EXP" => a.exp(),
            "FIX" => a.floor(),
            "FUP" => a.ceil(),
            "ROUND" => a.round(),
            "LN" => {
                domain(a > 0.0, "not positive")?;
                a.ln()
            }
            "SQRT" => {
                domain(a >= 0.0, "negative")?;
                a.sqrt()
            }
            _ => unreachable!("KNOWN"),
        })
    }
}
