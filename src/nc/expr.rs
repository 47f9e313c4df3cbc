//! The block cursor and the expression evaluators: FANUC Macro B (`#` variables with null,
//! `[ ]`, EQ..LE, AND/OR, functions in degrees) and Siemens (`R` parameters, `( )`, `==`..).

use super::{deg, Dialect, Machine, Program};

/// A cursor over one block's text.
pub(super) struct Cur<'a> {
    pub(super) s: &'a [u8],
    pub(super) i: usize,
    pub(super) dialect: Dialect,
}

pub(super) type Fail = (usize, String);

impl<'a> Cur<'a> {
    pub(super) fn new(s: &'a str, dialect: Dialect) -> Cur<'a> {
        Cur {
            s: s.as_bytes(),
            i: 0,
            dialect,
        }
    }
    pub(super) fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    pub(super) fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }
    pub(super) fn eat(&mut self, t: &str) -> bool {
        self.ws();
        if self.s[self.i..].starts_with(t.as_bytes()) {
            self.i += t.len();
            true
        } else {
            false
        }
    }
    pub(super) fn done(&mut self) -> bool {
        self.peek().is_none()
    }
    pub(super) fn err<T>(&self, msg: impl Into<String>) -> Result<T, Fail> {
        Err((self.i + 1, msg.into()))
    }
    pub(super) fn ident(&mut self) -> String {
        self.ws();
        let st = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphabetic() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[st..self.i]).into_owned()
    }
    pub(super) fn name_with_digits(&mut self) -> String {
        self.ws();
        let st = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[st..self.i]).into_owned()
    }
    /// An unsigned decimal number (`12`, `12.`, `.5`, `1.5`).
    pub(super) fn number(&mut self) -> Option<f64> {
        self.ws();
        let st = self.i;
        while self.i < self.s.len() && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.') {
            self.i += 1;
        }
        if st == self.i {
            return None;
        }
        match ascii_number(&self.s[st..self.i]) {
            Some(v) => Some(v),
            None => {
                self.i = st;
                None
            }
        }
    }
}

/// An unsigned decimal of ASCII digits and at most one point (`12`, `12.`, `.5`, `1.5`).
/// Up to 15 digits and 22 decimals it is the integer of all digits divided by a power of
/// ten: one division of two exact values, so correctly rounded, as `str::parse` is (which
/// takes the rest). The interpreters read numbers in every executed block: this is their
/// hot path.
pub(super) fn ascii_number(b: &[u8]) -> Option<f64> {
    let mut int: u64 = 0;
    let mut digits = 0;
    let mut decimals = None;
    for &c in b {
        match c {
            b'0'..=b'9' => {
                int = int.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                digits += 1;
                if let Some(d) = decimals.as_mut() {
                    *d += 1;
                }
            }
            b'.' if decimals.is_none() => decimals = Some(0),
            _ => return None,
        }
    }
    if digits == 0 {
        return None;
    }
    let k: i32 = decimals.unwrap_or(0);
    if digits <= 15 && k <= 22 {
        return Some(int as f64 / 10f64.powi(k));
    }
    std::str::from_utf8(b).ok()?.parse().ok()
}

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

impl Machine<'_> {
    pub(super) fn register(&mut self, p: std::rc::Rc<Program>) {
        if let Some(a) = &p.alias {
            self.programs.insert(a.clone(), p.clone());
        }
        self.programs.insert(p.name.clone(), p);
    }

    pub(super) fn get(&self, c: &mut Cur, idx: u32) -> Result<f64, Fail> {
        match c.dialect {
            Dialect::Siemens802d => Ok(*self.r.get(&idx).unwrap_or(&0.0)),
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => {
                // Null (vacant, and #0) is carried as NaN: 0 in arithmetic, but not equal
                // to 0 under EQ/NE (controllers.md 4.1).
                let v = if idx == 0 {
                    None
                } else if (1..=33).contains(&idx) {
                    self.locals.last().and_then(|l| l.get(&idx))
                } else {
                    self.vars.get(&idx)
                };
                Ok(v.copied().unwrap_or(f64::NAN))
            }
        }
    }

    pub(super) fn expr(&self, c: &mut Cur) -> Result<f64, Fail> {
        self.or(c)
    }

    /// Store a FANUC variable; null (NaN) makes it vacant.
    pub(super) fn set_var(&mut self, idx: u32, v: f64) {
        let map = if (1..=33).contains(&idx) {
            self.locals.last_mut().expect("level 0 always exists")
        } else {
            &mut self.vars
        };
        if v.is_nan() {
            map.remove(&idx);
        } else {
            map.insert(idx, v);
        }
    }
    pub(super) fn or(&self, c: &mut Cur) -> Result<f64, Fail> {
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
    pub(super) fn and(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.cmp(c)?;
        while c.eat("AND") {
            let w = self.cmp(c)?;
            v = f64::from(z(v) != 0.0 && z(w) != 0.0);
        }
        Ok(v)
    }
    pub(super) fn cmp(&self, c: &mut Cur) -> Result<f64, Fail> {
        let v = self.add(c)?;
        let ops: &[(&str, Compare)] = match c.dialect {
            Dialect::Siemens802d => &[
                ("==", |a, b| a == b),
                ("<>", |a, b| a != b),
                ("<=", |a, b| a <= b),
                (">=", |a, b| a >= b),
                ("<", |a, b| a < b),
                (">", |a, b| a > b),
            ],
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => &[
                ("EQ", |a, b| a == b),
                ("NE", |a, b| a != b),
                ("LE", |a, b| a <= b),
                ("GE", |a, b| a >= b),
                ("LT", |a, b| a < b),
                ("GT", |a, b| a > b),
            ],
        };
        for (op, f) in ops {
            if c.eat(op) {
                let w = self.add(c)?;
                // Null equals only null under EQ/NE; elsewhere it is 0.
                let result = match *op {
                    "EQ" | "NE" if v.is_nan() || w.is_nan() => {
                        (v.is_nan() && w.is_nan()) == (*op == "EQ")
                    }
                    _ => f(z(v), z(w)),
                };
                return Ok(f64::from(result));
            }
        }
        Ok(v)
    }
    pub(super) fn add(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.mul(c)?;
        loop {
            if c.eat("+") {
                v = z(v) + z(self.mul(c)?);
            } else if c.peek() == Some(b'-') {
                c.i += 1;
                v = z(v) - z(self.mul(c)?);
            } else {
                return Ok(v);
            }
        }
    }
    pub(super) fn mul(&self, c: &mut Cur) -> Result<f64, Fail> {
        let mut v = self.unary(c)?;
        loop {
            if c.eat("*") {
                v = z(v) * z(self.unary(c)?);
            } else if c.eat("/") {
                let at = c.i;
                let w = z(self.unary(c)?);
                if w == 0.0 {
                    return Err((at + 1, "division by zero".into()));
                }
                v = z(v) / w;
            } else if c.eat("MOD") || (c.dialect == Dialect::Siemens802d && c.eat("DIV")) {
                let div = c.s[..c.i].ends_with(b"DIV");
                let at = c.i;
                let w = z(self.unary(c)?);
                if w == 0.0 {
                    return Err((at + 1, "division by zero".into()));
                }
                v = if div { (z(v) / w).trunc() } else { z(v) % w };
            } else {
                return Ok(v);
            }
        }
    }
    pub(super) fn unary(&self, c: &mut Cur) -> Result<f64, Fail> {
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
    pub(super) fn primary(&self, c: &mut Cur) -> Result<f64, Fail> {
        let (open, close) = match c.dialect {
            Dialect::Siemens802d => ("(", ")"),
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Linuxcnc => ("[", "]"),
        };
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
        if let Some(v) = c.number() {
            return Ok(v);
        }
        let at = c.i;
        let name = c.ident();
        if name.is_empty() {
            return c.err("expected a number, a parameter or a function");
        }
        if c.dialect == Dialect::Siemens802d && name == "R" {
            let Some(n) = c.number() else {
                return c.err("expected an R parameter number");
            };
            return self.get(c, n as u32);
        }
        if !c.eat(open) {
            return Err((at + 1, format!("unknown name `{name}`")));
        }
        let a = z(self.expr(c)?);
        let b = if c.eat(",") {
            Some(z(self.expr(c)?))
        } else {
            None
        };
        if !c.eat(close) {
            return c.err(format!("expected `{close}`"));
        }
        let v = match (name.as_str(), b) {
            ("ABS", None) => a.abs(),
            ("SQRT", None) if a >= 0.0 => a.sqrt(),
            ("SQRT", None) => return Err((at + 1, "square root of a negative number".into())),
            ("ASIN", None) | ("ACOS", None) if a.abs() > 1.0 => {
                return Err((
                    at + 1,
                    format!("{name} of {a}: the argument must lie in -1..1"),
                ))
            }
            ("ASIN", None) => a.asin().to_degrees(),
            ("ACOS", None) => a.acos().to_degrees(),
            ("SIN", None) => deg(a).sin(),
            ("COS", None) => deg(a).cos(),
            ("TAN", None) => deg(a).tan(),
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
            ("EXP", None) => a.exp(),
            _ => {
                return Err((
                    at + 1,
                    format!("unknown function `{name}` with these arguments"),
                ))
            }
        };
        Ok(v)
    }
    pub(super) fn var_ref(&self, c: &mut Cur) -> Result<f64, Fail> {
        let idx = if c.peek() == Some(b'[') {
            c.i += 1;
            let v = self.expr(c)?;
            if !c.eat("]") {
                return c.err("expected `]`");
            }
            v
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        self.get(c, idx.round() as u32)
    }

    /// A FANUC word value: a number, `#n`, `-#n` or `[expr]`.
    pub(super) fn fanuc_value(&self, c: &mut Cur) -> Result<f64, Fail> {
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
            c.number()
                .ok_or((c.i + 1, "expected a number".to_string()))?
        };
        Ok(if neg { -v } else { v })
    }

    pub(super) fn var_index(&self, c: &mut Cur) -> Result<u32, Fail> {
        let v = if c.peek() == Some(b'[') {
            self.bracket(c)?
        } else {
            c.number()
                .ok_or((c.i + 1, "expected a variable number".to_string()))?
        };
        if !(1.0..=9999.0).contains(&v) {
            return c.err(format!("variable #{v} cannot be set"));
        }
        Ok(v.round() as u32)
    }

    pub(super) fn bracket(&self, c: &mut Cur) -> Result<f64, Fail> {
        if !c.eat("[") {
            return c.err("expected `[`");
        }
        let v = self.expr(c)?;
        if !c.eat("]") {
            return c.err("expected `]`");
        }
        Ok(z(v))
    }
}
