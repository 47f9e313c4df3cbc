//! Okuma OSP-P expressions (OSP-P200L programming manual 5238-E, "User task" chapter:
//! arithmetic operators `+ - * /` and `MOD`, brackets `[ ]`, the functions `SIN`, `COS`,
//! `TAN`, `ATAN`, `SQRT`, `ABS`, `ROUND`, `FIX`, `FUP` (angles in degrees), comparisons
//! `EQ NE GT GE LT LE` and the logic `AND`, `OR` of `IF [..]` conditions) over common
//! variables `VC1..` and local variables (names of letters and digits that the program
//! assigns, and the arguments of a `CALL`).
//!
//! Columns are 0-based character positions in the block's text; errors name the column
//! and what was expected.

use super::expr::Fail;
use std::collections::HashMap;

/// The variables an expression reads: common `VC<n>` (global, 0 until set) and the locals
/// of the running program (an unset local is an error, as on the control: alarm "variable
/// not defined").
pub(super) struct Vars<'a> {
    pub(super) common: &'a HashMap<u32, f64>,
    pub(super) local: &'a HashMap<String, f64>,
}

/// A variable's name as the control reads it: `VC<n>` common, else a local name.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Var {
    /// `VC<n>`.
    Common(u32),
    /// A local variable.
    Local(String),
}

/// Read a variable name (`VC12`, `PTCH`): `VC` followed by digits is common, any other run
/// of letters and digits starting with a letter is local. Returns `None` for no name.
pub(super) fn var_of(name: &str) -> Option<Var> {
    let first = name.chars().next()?;
    if !first.is_ascii_alphabetic() || !name.chars().all(|c| c.is_ascii_alphanumeric()) {
        return None;
    }
    if let Some(d) = name.strip_prefix("VC") {
        if !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()) {
            return d.parse().ok().map(Var::Common);
        }
    }
    Some(Var::Local(name.to_string()))
}

/// An expression parser over `text` (uppercase), starting at column `base` of the block.
pub(super) struct Parser<'a, 'v> {
    s: Vec<char>,
    i: usize,
    base: usize,
    vars: &'a Vars<'v>,
}

const FUNCTIONS: [&str; 9] = [
    "SIN", "COS", "TAN", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP",
];

impl<'a, 'v> Parser<'a, 'v> {
    pub(super) fn new(text: &str, base: usize, vars: &'a Vars<'v>) -> Parser<'a, 'v> {
        Parser {
            s: text.chars().collect(),
            i: 0,
            base,
            vars,
        }
    }

    fn col(&self) -> usize {
        self.base + self.i
    }

    fn skip_ws(&mut self) {
        while self.s.get(self.i).is_some_and(|c| *c == ' ' || *c == '\t') {
            self.i += 1;
        }
    }

    fn peek(&mut self) -> Option<char> {
        self.skip_ws();
        self.s.get(self.i).copied()
    }

    fn word(&self) -> String {
        self.s[self.i..]
            .iter()
            .take_while(|c| c.is_ascii_alphabetic())
            .collect()
    }

    /// A whole expression; the text must end after it.
    pub(super) fn whole(mut self) -> Result<f64, Fail> {
        let start = self.col();
        let v = self.condition()?;
        if !(v.is_finite() && v.abs() < 1e12) {
            return Err((
                start,
                format!("the expression's value {v:e} is out of range"),
            ));
        }
        if let Some(c) = self.peek() {
            return Err((self.col(), format!("unexpected `{c}` after the expression")));
        }
        Ok(v)
    }

    /// `or` level: comparisons joined by AND/OR (1 true, 0 false).
    fn condition(&mut self) -> Result<f64, Fail> {
        let mut v = self.comparison()?;
        loop {
            self.skip_ws();
            let w = self.word();
            let and = match w.as_str() {
                "AND" => true,
                "OR" => false,
                _ => return Ok(v),
            };
            self.i += w.len();
            let r = self.comparison()?;
            let (a, b) = (v != 0.0, r != 0.0);
            v = f64::from(u8::from(if and { a && b } else { a || b }));
        }
    }

    fn comparison(&mut self) -> Result<f64, Fail> {
        let a = self.sum()?;
        self.skip_ws();
        let w = self.word();
        let op: Option<fn(f64, f64) -> bool> = match w.as_str() {
            "EQ" => Some(|a, b| a == b),
            "NE" => Some(|a, b| a != b),
            "GT" => Some(|a, b| a > b),
            "GE" => Some(|a, b| a >= b),
            "LT" => Some(|a, b| a < b),
            "LE" => Some(|a, b| a <= b),
            _ => None,
        };
        let Some(op) = op else { return Ok(a) };
        self.i += w.len();
        let b = self.sum()?;
        Ok(f64::from(u8::from(op(a, b))))
    }

    fn sum(&mut self) -> Result<f64, Fail> {
        let mut v = self.product()?;
        loop {
            match self.peek() {
                Some('+') => {
                    self.i += 1;
                    v += self.product()?;
                }
                Some('-') => {
                    self.i += 1;
                    v -= self.product()?;
                }
                _ => return Ok(v),
            }
        }
    }

    fn product(&mut self) -> Result<f64, Fail> {
        let mut v = self.unary()?;
        loop {
            match self.peek() {
                Some('*') => {
                    self.i += 1;
                    v *= self.unary()?;
                }
                Some('/') => {
                    let col = self.col();
                    self.i += 1;
                    let d = self.unary()?;
                    if d == 0.0 {
                        return Err((col, "division by zero".into()));
                    }
                    v /= d;
                }
                Some('M') if self.word() == "MOD" => {
                    let col = self.col();
                    self.i += 3;
                    let d = self.unary()?;
                    if d == 0.0 {
                        return Err((col, "MOD by zero".into()));
                    }
                    v %= d;
                }
                _ => return Ok(v),
            }
        }
    }

    fn unary(&mut self) -> Result<f64, Fail> {
        match self.peek() {
            Some('-') => {
                self.i += 1;
                Ok(-self.unary()?)
            }
            Some('+') => {
                self.i += 1;
                self.unary()
            }
            _ => self.atom(),
        }
    }

    fn bracket(&mut self) -> Result<f64, Fail> {
        let col = self.col();
        if self.peek() != Some('[') {
            return Err((col, "expected `[`".into()));
        }
        self.i += 1;
        let v = self.condition()?;
        if self.peek() != Some(']') {
            return Err((self.col(), "expected `]` closing the bracket".into()));
        }
        self.i += 1;
        Ok(v)
    }

    fn atom(&mut self) -> Result<f64, Fail> {
        let col = self.col();
        match self.peek() {
            None => Err((col, "expected a number, a variable or `[`".into())),
            Some('[') => self.bracket(),
            Some(c) if c.is_ascii_digit() || c == '.' => {
                let start = self.i;
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|c| c.is_ascii_digit() || *c == '.')
                {
                    self.i += 1;
                }
                let t: String = self.s[start..self.i].iter().collect();
                t.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or((col, format!("`{t}` is not a number")))
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let w = self.word();
                if FUNCTIONS.contains(&w.as_str()) && self.s.get(self.i + w.len()) == Some(&'[') {
                    self.i += w.len();
                    let a = self.bracket()?;
                    return function(&w, a).ok_or((col, format!("{w}[{a}] is out of its domain")));
                }
                let start = self.i;
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|c| c.is_ascii_alphanumeric())
                {
                    self.i += 1;
                }
                let name: String = self.s[start..self.i].iter().collect();
                match var_of(&name) {
                    Some(Var::Common(n)) => Ok(self.vars.common.get(&n).copied().unwrap_or(0.0)),
                    Some(Var::Local(l)) => self.vars.local.get(&l).copied().ok_or((
                        col,
                        format!("local variable `{l}` is read before the program sets it"),
                    )),
                    None => Err((col, format!("`{name}` is not a variable"))),
                }
            }
            Some(c) => Err((
                col,
                format!("unexpected `{c}`: expected a number, a variable or `[`"),
            )),
        }
    }
}

/// The functions, in degrees; `None` outside their domain.
fn function(name: &str, a: f64) -> Option<f64> {
    let v = match name {
        "SIN" => a.to_radians().sin(),
        "COS" => a.to_radians().cos(),
        "TAN" => a.to_radians().tan(),
        "ATAN" => a.atan().to_degrees(),
        "SQRT" if a >= 0.0 => a.sqrt(),
        "ABS" => a.abs(),
        "ROUND" => a.round(),
        "FIX" => a.trunc(),
        "FUP" => {
            if a >= 0.0 {
                a.ceil()
            } else {
                a.floor()
            }
        }
        _ => return None,
    };
    v.is_finite().then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(s: &str) -> Result<f64, Fail> {
        let common: HashMap<u32, f64> = [(1, 2.5), (12, -4.0)].into_iter().collect();
        let local: HashMap<String, f64> = [("PTCH".to_string(), 1.5)].into_iter().collect();
        let vars = Vars {
            common: &common,
            local: &local,
        };
        Parser::new(s, 0, &vars).whole()
    }

    #[test]
    fn expressions_evaluate_as_written_by_hand() {
        // Each expected value worked by hand from the operator rules (products before sums,
        // left to right, degrees in the functions).
        let cases: [(&str, f64); 16] = [
            ("1+2*3", 7.0),
            ("[1+2]*3", 9.0),
            ("VC1*2", 5.0),
            ("VC12+VC1", -1.5),
            ("VC99", 0.0),
            ("PTCH*4", 6.0),
            ("-PTCH", -1.5),
            ("SIN[30]", 0.5),
            ("COS[60]*2", 1.0),
            ("ATAN[1]", 45.0),
            ("SQRT[16]+ABS[-2]", 6.0),
            ("FIX[2.7]+FUP[2.2]", 5.0),
            ("ROUND[2.5]", 3.0),
            ("7 MOD 4", 3.0),
            ("VC1 GT 2 AND VC12 LT 0", 1.0),
            ("VC1 EQ 2 OR 1 NE 1", 0.0),
        ];
        for (s, want) in cases {
            let got = eval(s).unwrap_or_else(|e| panic!("{s}: {e:?}"));
            assert!((got - want).abs() < 1e-12, "{s}: {got} != {want}");
        }
    }

    #[test]
    fn bad_expressions_name_their_column() {
        let cases: [(&str, usize, &str); 5] = [
            ("1/0", 1, "division by zero"),
            ("[1+2", 4, "expected `]`"),
            ("ABC+1", 0, "local variable `ABC`"),
            ("SQRT[-1]", 0, "out of its domain"),
            ("1+", 2, "expected a number"),
        ];
        for (s, col, msg) in cases {
            let (c, m) = eval(s).expect_err(s);
            assert_eq!(c, col, "{s}: {m}");
            assert!(m.contains(msg), "{s}: {m}");
        }
    }
}
