//! The expression evaluators: FANUC Macro B (`#` variables with null,
//! `[ ]`, EQ..LE, AND/OR, functions in degrees) and Siemens (`R` parameters, `( )`, `==`..).

use super::lex::{Cursor, MAX_NEST};
use super::{to_rad, Dialect, Interp, Program};

/// The largest magnitude a FANUC/GSK macro variable holds: "-10^47 to 10^47" (FANUC Custom
/// Macro B; beyond it alarm 111, calculation data overflow).
pub(super) const FANUC_MAX_VALUE: f64 = 1e47;
/// The largest magnitude of a Siemens R parameter: "10^-300 .. 10^+300" (SINUMERIK
/// parameter programming, `controllers.md` 6).
pub(super) const SIEMENS_MAX_VALUE: f64 = 1e300;
/// The largest word value FANUC/GSK take: eight digits (alarm 003, too many digits).
pub(super) const FANUC_MAX_WORD: f64 = 99_999_999.0;
/// The largest word value Siemens 802D takes (nine digits; no axis goes further).
pub(super) const SIEMENS_MAX_WORD: f64 = 999_999_999.0;
/// Siemens 802D R parameters: R0..R299 (the 802D sl default of 300, `controllers.md` 6).
pub(super) const SIEMENS_R_PARAMETERS: u32 = 300;

/// The value of an arithmetic result, or why it cannot be one: not finite or beyond what
/// the dialect's variables hold. `what` names the operation for the message.
pub(super) fn in_range(
    dialect: Dialect,
    col: usize,
    v: f64,
    what: impl FnOnce() -> String,
) -> Result<f64, Fail> {
    let max = match dialect {
        Dialect::Siemens802d | Dialect::Siemens840d => SIEMENS_MAX_VALUE,
        _ => FANUC_MAX_VALUE,
    };
    if v.is_finite() && v.abs() <= max {
        return Ok(v);
    }
    let alarm = match dialect {
        Dialect::Siemens802d | Dialect::Siemens840d => "",
        _ => " (alarm 111)",
    };
    let why = if v.is_nan() {
        "is not a number".to_string()
    } else {
        format!("overflows: the result is beyond ±{max:e}{alarm}")
    };
    Err((col, format!("{} {why}", what())))
}

pub(super) type Fail = (usize, String);

/// Null (NaN) as 0, for arithmetic.
pub(super) fn z(v: f64) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        v
    }
}

/// A comparison operator.
type Compare = fn(f64, f64) -> bool;

/// FANUC/GSK/LinuxCNC/Okuma comparisons.
const WORD_COMPARISONS: &[(&str, Compare)] = &[
    ("EQ", |a, b| a == b),
    ("NE", |a, b| a != b),
    ("LE", |a, b| a <= b),
    ("GE", |a, b| a >= b),
    ("LT", |a, b| a < b),
    ("GT", |a, b| a > b),
];

/// Siemens comparisons (GSK's too); two-character symbols before their prefixes.
const SYMBOL_COMPARISONS: &[(&str, Compare)] = &[
    ("==", |a, b| a == b),
    ("<>", |a, b| a != b),
    ("<=", |a, b| a <= b),
    (">=", |a, b| a >= b),
    ("<", |a, b| a < b),
    (">", |a, b| a > b),
];

impl Interp<'_> {
    pub(super) fn register(&mut self, p: std::rc::Rc<Program>) {
        if let Some(a) = &p.alias {
            self.progs.by_name.insert(a.clone(), p.clone());
        }
        self.progs.by_name.insert(p.name.clone(), p);
    }

    /// The value of R parameter `idx` (Siemens) or variable `#idx` (FANUC/GSK); `col` is
    /// where the reference starts, for errors.
    pub(super) fn get(&self, c: &Cursor, idx: f64, col: usize) -> Result<f64, Fail> {
        match c.dialect {
            Dialect::Siemens802d | Dialect::Siemens840d => {
                let n = r_index(idx, col)?;
                Ok(*self.vars.r.get(&n).unwrap_or(&0.0))
            }
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc | Dialect::Okuma => {
                // Null (vacant, and #0) is carried as NaN: 0 in arithmetic, but not equal
                // to 0 under EQ/NE (controllers.md 4.1).
                let idx = var_number(idx, col, true)?;
                let v = if idx == 0 {
                    None
                } else if (1..=33).contains(&idx) {
                    self.vars.locals.last().and_then(|l| l.get(&idx))
                } else {
                    self.vars.common.get(&idx)
                };
                Ok(v.copied().unwrap_or(f64::NAN))
            }
        }
    }

    pub(super) fn expr(&self, c: &mut Cursor) -> Result<f64, Fail> {
        self.or(c)
    }

    /// Store a FANUC variable; null (NaN) makes it vacant.
    pub(super) fn set_var(&mut self, idx: u32, v: f64) {
        let map = if (1..=33).contains(&idx) {
            self.vars.locals.last_mut().expect("level 0 always exists")
        } else {
            &mut self.vars.common
        };
        if v.is_nan() {
            map.remove(&idx);
        } else {
            map.insert(idx, v);
        }
    }
    pub(super) fn or(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let mut v = self.and(c)?;
        loop {
            if c.eat("OR") {
                let w = self.and(c)?;
                v = f64::from(z(v) != 0.0 || z(w) != 0.0);
            } else if c.eat("XOR") {
                let w = self.and(c)?;
                v = f64::from((z(v) != 0.0) != (z(w) != 0.0));
            } else {
                return Ok(v);
            }
        }
    }
    pub(super) fn and(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let mut v = self.cmp(c)?;
        while c.eat("AND") {
            let w = self.cmp(c)?;
            v = f64::from(z(v) != 0.0 && z(w) != 0.0);
        }
        Ok(v)
    }
    pub(super) fn cmp(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let v = self.add(c)?;
        // Siemens compares with symbols, the others with words; GSK's statement macros
        // take both (980TDi manual 3.28: `IF[#100<100]GOTO10`, `IF[3<>2]GOTO2`).
        let tables: &[&[(&str, Compare)]] = match c.dialect {
            Dialect::Siemens802d | Dialect::Siemens840d => &[SYMBOL_COMPARISONS],
            _ if self.cfg.gsk => &[WORD_COMPARISONS, SYMBOL_COMPARISONS],
            _ => &[WORD_COMPARISONS],
        };
        for (op, f) in tables.iter().flat_map(|t| t.iter()) {
            if c.eat(op) {
                let w = self.add(c)?;
                // Null equals only null under EQ/NE; elsewhere it is 0.
                let result = match *op {
                    "EQ" | "NE" | "==" | "<>"
                        if (v.is_nan() || w.is_nan())
                            && !matches!(
                                c.dialect,
                                Dialect::Siemens802d | Dialect::Siemens840d
                            ) =>
                    {
                        (v.is_nan() && w.is_nan()) == (*op == "EQ" || *op == "==")
                    }
                    _ => f(z(v), z(w)),
                };
                return Ok(f64::from(result));
            }
        }
        Ok(v)
    }
    pub(super) fn add(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let mut v = self.mul(c)?;
        loop {
            c.ws();
            let at = c.i + 1;
            let (r, op) = if c.eat("+") {
                (z(v) + z(self.mul(c)?), "+")
            } else if c.peek() == Some(b'-') {
                c.i += 1;
                (z(v) - z(self.mul(c)?), "-")
            } else {
                return Ok(v);
            };
            v = in_range(c.dialect, at, r, || format!("`{op}`"))?;
        }
    }
    pub(super) fn mul(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let mut v = self.unary(c)?;
        loop {
            c.ws();
            let at = c.i + 1;
            let (r, op) = if c.eat("*") {
                (z(v) * z(self.unary(c)?), "*")
            } else if c.eat("/") {
                let at = c.i;
                let w = z(self.unary(c)?);
                if w == 0.0 {
                    return Err((at + 1, "division by zero".into()));
                }
                (z(v) / w, "/")
            } else if c.eat("MOD") || (c.dialect == Dialect::Siemens802d && c.eat("DIV")) {
                let div = c.s[..c.i].ends_with(b"DIV");
                let at = c.i;
                let w = z(self.unary(c)?);
                if w == 0.0 {
                    return Err((at + 1, "division by zero".into()));
                }
                if div {
                    ((z(v) / w).trunc(), "DIV")
                } else {
                    (z(v) % w, "MOD")
                }
            } else {
                return Ok(v);
            };
            v = in_range(c.dialect, at, r, || format!("`{op}`"))?;
        }
    }
    pub(super) fn unary(&self, c: &mut Cursor) -> Result<f64, Fail> {
        if c.nest >= MAX_NEST {
            c.ws();
            return c.err(format!(
                "the expression nests more than {MAX_NEST} levels deep"
            ));
        }
        c.nest += 1;
        let v = self.unary_inner(c);
        c.nest -= 1;
        v
    }
    fn unary_inner(&self, c: &mut Cursor) -> Result<f64, Fail> {
        if c.eat("-") {
            return Ok(-z(self.unary(c)?));
        }
        if c.eat("+") {
            return self.unary(c);
        }
        if c.dialect == Dialect::Siemens802d && c.eat("NOT") {
            return Ok(f64::from(z(self.unary(c)?) == 0.0));
        }
        self.primary(c)
    }
    /// An unsigned number in an expression or a word, in the dialect's range.
    pub(super) fn literal(&self, c: &mut Cursor) -> Result<Option<f64>, Fail> {
        c.ws();
        let at = c.i + 1;
        let Some(mut v) = c.number() else {
            return Ok(None);
        };
        let siemens = matches!(c.dialect, Dialect::Siemens802d | Dialect::Siemens840d);
        if siemens && c.s[c.i..].starts_with(b"EX") {
            // The exponent of a Siemens REAL: `1.5EX-3`, `1EX300` (Programming Manual,
            // "Variable types": REAL with exponent EX).
            let save = c.i;
            c.i += 2;
            let neg = c.eat("-");
            let _ = neg || c.eat("+");
            match c.number_span() {
                Some((st, end)) if c.s[st..end].iter().all(u8::is_ascii_digit) => {
                    c.i = end;
                    let e = String::from_utf8_lossy(&c.s[st..end]);
                    let sign = if neg { "-" } else { "" };
                    v = format!("{v:e}")
                        .replace('e', "x") // the mantissa's own exponent
                        .split_once('x')
                        .and_then(|(m, k)| {
                            let k: i64 = k.parse().ok()?;
                            let e: i64 = format!("{sign}{e}").parse().ok()?;
                            format!("{m}e{}", k + e).parse().ok()
                        })
                        .unwrap_or(f64::INFINITY);
                }
                _ => c.i = save,
            }
        }
        let max = if siemens {
            SIEMENS_MAX_VALUE
        } else {
            FANUC_MAX_VALUE
        };
        if v.abs() > max {
            let text = String::from_utf8_lossy(&c.s[at - 1..c.i]);
            let shown = if text.len() > 20 {
                format!("{}.. ({} characters)", &text[..12], text.len())
            } else {
                text.into_owned()
            };
            return Err((
                at,
                format!("the number {shown} is too large (at most ±{max:e})"),
            ));
        }
        Ok(Some(v))
    }
    pub(super) fn primary(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let (open, close) = c.brackets();
        if c.eat(open) {
            let v = self.expr(c)?;
            if !c.eat(close) {
                return c.err(format!("expected `{close}`"));
            }
            return Ok(v);
        }
        if c.dialect == Dialect::Fanuc && c.eat("#") {
            return self.var_ref(c);
        }
        if let Some(v) = self.literal(c)? {
            return Ok(v);
        }
        c.ws();
        let at = c.i;
        let name = c.ident();
        if name.is_empty() {
            return c.err(format!(
                "expected a number, a parameter or a function, found {}",
                c.here()
            ));
        }
        if c.dialect == Dialect::Siemens802d && name == "R" {
            let Some(n) = c.number() else {
                return c.err("expected an R parameter number");
            };
            return self.get(c, n, at + 1);
        }
        if self.cfg.s840 || self.has_user_vars() {
            // A Siemens 840D user variable (its name may go on with digits); on the 802D a
            // GUD it assigned or a cycle's PROC parameter.
            let save = c.i;
            let mut full = name.clone();
            while c.i < c.s.len() && (c.s[c.i].is_ascii_alphanumeric() || c.s[c.i] == b'_') {
                full.push(char::from(c.s[c.i]));
                c.i += 1;
            }
            if let Some(v) = self.read_user(c, &full, at + 1)? {
                return Ok(v);
            }
            c.i = save;
        }
        if !c.eat(open) {
            return Err((at + 1, format!("unknown name `{name}`")));
        }
        let a = z(self.expr(c)?);
        let mut b = if c.eat(",") {
            Some(z(self.expr(c)?))
        } else {
            None
        };
        if !c.eat(close) {
            return c.err(format!("expected `{close}`"));
        }
        // FANUC's two-argument arc tangent `ATAN[y]/[x]`.
        if name == "ATAN" && b.is_none() && c.dialect != Dialect::Siemens802d {
            let save = c.i;
            if c.eat("/") && c.peek() == Some(b'[') {
                c.i += 1;
                b = Some(z(self.expr(c)?));
                if !c.eat("]") {
                    return c.err("expected `]`");
                }
            } else {
                c.i = save;
            }
        }
        let domain = |what: &str| -> Result<f64, Fail> {
            let alarm = if c.dialect == Dialect::Siemens802d {
                ""
            } else {
                " (alarm 111)"
            };
            Err((at + 1, format!("{name} of {a}: {what}{alarm}")))
        };
        let v = match (name.as_str(), b) {
            ("ABS", None) => a.abs(),
            ("SQRT", None) if a >= 0.0 => a.sqrt(),
            ("SQRT", None) => return domain("the square root of a negative number"),
            ("ASIN", None) | ("ACOS", None) if a.abs() > 1.0 => {
                return domain("the argument must lie in -1..1")
            }
            ("ASIN", None) => a.asin().to_degrees(),
            ("ACOS", None) => a.acos().to_degrees(),
            ("SIN", None) => to_rad(a).sin(),
            ("COS", None) => to_rad(a).cos(),
            ("TAN", None) => to_rad(a).tan(),
            ("ATAN2", Some(b)) => a.atan2(b).to_degrees(),
            ("ATAN", Some(b)) => a.atan2(b).to_degrees(),
            ("ATAN", None) => a.atan().to_degrees(),
            ("TRUNC", None) | ("FIX", None) => a.trunc(),
            ("FUP", None) => {
                if a >= 0.0 {
                    a.ceil()
                } else {
                    a.floor()
                }
            }
            ("ROUND", None) => a.round(),
            ("POT", None) => a * a,
            ("LN", None) if a > 0.0 => a.ln(),
            ("LN", None) => return domain("the logarithm needs a positive argument"),
            ("EXP", None) => a.exp(),
            _ => {
                return Err((
                    at + 1,
                    format!("unknown function `{name}` with these arguments"),
                ))
            }
        };
        in_range(c.dialect, at + 1, v, || format!("{name} of {a}"))
    }
    pub(super) fn var_ref(&self, c: &mut Cursor) -> Result<f64, Fail> {
        // Errors point at the `#`.
        let col = c.i;
        let idx = if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            if v.is_nan() {
                return Err((col, "the variable number is vacant (null)".into()));
            }
            v
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        self.get(c, idx, col)
    }

    /// A FANUC word value: a number, `#n`, `-#n` or `[expr]`.
    pub(super) fn fanuc_value(&self, c: &mut Cursor) -> Result<f64, Fail> {
        let neg = c.eat("-");
        let _ = c.eat("+");
        let v = if c.eat("#") {
            self.var_ref(c)?
        } else if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            v
        } else {
            self.literal(c)?
                .ok_or((c.i + 1, format!("expected a number, found {}", c.here())))?
        };
        Ok(if neg { -v } else { v })
    }

    /// The variable a FANUC assignment `#n=` or `#[..]=` sets.
    pub(super) fn var_index(&self, c: &mut Cursor) -> Result<u32, Fail> {
        let col = c.i;
        let v = if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            if v.is_nan() {
                return Err((col, "the variable number is vacant (null)".into()));
            }
            v
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        var_number(v, col, false)
    }

    pub(super) fn bracket(&self, c: &mut Cursor) -> Result<f64, Fail> {
        if !c.eat("[") {
            return c.err("expected `[`");
        }
        let v = self.expr(c)?;
        if !c.eat("]") {
            return c.err("expected `]`");
        }
        Ok(z(v))
    }

    /// A word's value in the dialect's range (`col` is the word's letter); null (a vacant
    /// FANUC variable) passes, it leaves the word out.
    pub(super) fn word_value(&self, name: &str, v: f64, col: usize) -> Result<f64, Fail> {
        let (max, digits) = match self.cfg.dialect {
            Dialect::Siemens802d | Dialect::Siemens840d => (SIEMENS_MAX_WORD, "nine"),
            _ => (FANUC_MAX_WORD, "eight"),
        };
        if v.is_nan() && self.cfg.dialect != Dialect::Siemens802d {
            return Ok(v);
        }
        if v.is_finite() && v.abs() <= max {
            return Ok(v);
        }
        Err((
            col,
            format!("the {name} word's value {v} is out of range: a word has at most {digits} digits (±{max})"),
        ))
    }
}

/// A FANUC/GSK variable number: `#0` (null, read only), locals `#1..#33`, common
/// `#100..#999` (`controllers.md` 4.1). System variables (`#1000` and up: offsets,
/// positions, modal state, alarms) are not modelled: a program that uses one is refused
/// rather than run on a made-up value.
pub(super) fn var_number(v: f64, col: usize, read: bool) -> Result<u32, Fail> {
    let n = v.round();
    if (v - n).abs() > 1e-6 {
        return Err((col, format!("variable number {v} is not a whole number")));
    }
    let what = if read { "read" } else { "set" };
    match n {
        n if n < 0.0 => Err((col, format!("variable #{n} does not exist (a negative number)"))),
        0.0 if read => Ok(0),
        0.0 => Err((col, "#0 is always null: it cannot be set".into())),
        n if n <= 33.0 || (100.0..=999.0).contains(&n) => Ok(n as u32),
        n if n < 100.0 => Err((
            col,
            format!("variable #{n} does not exist: locals are #1..#33, common variables #100..#999"),
        )),
        n => Err((
            col,
            format!(
                "system variable #{n} (offsets, positions, modal state, alarms) is not modelled and cannot be {what}: use #1..#33 or #100..#999"
            ),
        )),
    }
}

/// A Siemens R parameter number: R0..R299.
pub(super) fn r_index(v: f64, col: usize) -> Result<u32, Fail> {
    if v.fract() != 0.0 || !(0.0..f64::from(SIEMENS_R_PARAMETERS)).contains(&v) {
        return Err((
            col,
            format!(
                "R{v} does not exist: the 802D has R0..R{}",
                SIEMENS_R_PARAMETERS - 1
            ),
        ));
    }
    Ok(v as u32)
}
