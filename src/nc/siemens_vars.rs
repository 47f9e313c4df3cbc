//! Siemens 840D user variables (`DEF`, local to the program that defines them, as the
//! control's LUD variables) and the state of the 840D additions: `PROC` arguments waiting
//! for the callee, tools called by name.
//!
//! `DEF REAL|INT|BOOL|CHAR name[=value], ..` with 1-D and 2-D arrays (`A[3]`, `B[2,3]`,
//! indices from 0) initialised by a value, a list `(1,2,3)`, `SET(..)` or `REP(v)`
//! (SINUMERIK 840D sl Programming Manual, "Definition of user variables (DEF)", "Definition
//! and initialization of array variables"). INT values are rounded, BOOL is 0 or 1, CHAR
//! holds its code. `STRING` variables are defined (so `MSG` texts can name them) but are
//! not numbers: reading one in an expression is an error. `AXIS`, `FRAME` and the
//! storage classes of global data (`NCK`, `CHAN`) are refused by name.

use super::expr::Fail;
use super::lex::Cursor;
use super::Interp;
use std::collections::HashMap;

/// The type of a user variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum VarType {
    Real,
    Int,
    Bool,
    Char,
    Str,
}

/// A user variable: its type, array sizes (1 and 1 for a scalar) and values (row-major).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct UserVar {
    pub(super) ty: VarType,
    pub(super) dims: (usize, usize),
    pub(super) values: Vec<f64>,
}

/// The largest array vpcut defines (elements), so that a typo cannot fill the memory.
const MAX_ELEMENTS: usize = 100_000;

/// The 840D additions' state.
#[derive(Default)]
pub(super) struct S840State {
    /// User variables, one scope per program level (kept as long as the FANUC-style
    /// level stack `Vars::locals`, which every Siemens call pushes).
    pub(super) scopes: Vec<HashMap<String, UserVar>>,
    /// Arguments of a `NAME(a, b)` call, bound by the callee's `PROC` block.
    pub(super) args: Option<(Vec<f64>, usize)>,
    /// Tools called by name (`T="THREAD_60"`): tool number = 1000 + position here.
    pub(super) tool_names: Vec<String>,
    /// DIAM90 is active (diameters in G90; G91 X, in radius there, is refused).
    pub(super) diam90: bool,
    /// Global user data (GUD): defined by the machine's definition files (`[program]
    /// definitions`, `siemens_defs`), or assigned by the program without a DEF (issue 27,
    /// `TEST=1`: a REAL scalar); seen by every program level.
    pub(super) gud: HashMap<String, UserVar>,
    /// Macros of the definition files (`DEFINE NAME AS text`): a block's names are replaced
    /// by their text as it is loaded (`siemens_defs::expand`).
    pub(super) macros: HashMap<String, String>,
}

impl UserVar {
    /// A value stored as the type holds it.
    fn typed(&self, v: f64) -> f64 {
        match self.ty {
            VarType::Real | VarType::Str => v,
            VarType::Int | VarType::Char => v.round(),
            VarType::Bool => f64::from(v != 0.0),
        }
    }
}

impl Interp<'_> {
    /// The user variables of the running program.
    pub(super) fn scope(&self) -> Option<&HashMap<String, UserVar>> {
        let n = self.vars.locals.len();
        self.vars.s840.scopes.get(n - 1)
    }

    /// The running program's scope, made when missing and cut to its level.
    pub(super) fn scope_mut(&mut self) -> &mut HashMap<String, UserVar> {
        let n = self.vars.locals.len();
        let s = &mut self.vars.s840.scopes;
        s.truncate(n);
        while s.len() < n {
            s.push(HashMap::new());
        }
        s.last_mut().expect("one level at least")
    }

    /// A fresh scope for a program about to be called (its level is pushed by the run).
    pub(super) fn new_scope(&mut self) {
        let n = self.vars.locals.len();
        self.scope_mut();
        self.vars.s840.scopes.truncate(n);
        self.vars.s840.scopes.push(HashMap::new());
    }

    /// `DEF type name[dims][=init], ..` (the cursor after `DEF`): local variables of the
    /// running program.
    pub(super) fn def(&mut self, c: &mut Cursor) -> Result<(), Fail> {
        for (name, var) in self.def_vars(c, false)? {
            self.scope_mut().insert(name, var);
        }
        Ok(())
    }

    /// A GUD definition file's `DEF [NCK|CHAN] type name[dims][=init], ..` (the cursor after
    /// `DEF`): global user data every program level sees. `AXIS` and `FRAME` data are
    /// skipped (nothing of them is modelled).
    pub(super) fn def_global(&mut self, c: &mut Cursor) -> Result<(), Fail> {
        for (name, var) in self.def_vars(c, true)? {
            self.vars.s840.gud.insert(name, var);
        }
        Ok(())
    }

    /// The variables a `DEF` defines (`global`: in a definition file, with its storage
    /// class `NCK`/`CHAN`; `AXIS`/`FRAME` data give none).
    fn def_vars(&mut self, c: &mut Cursor, global: bool) -> Result<Vec<(String, UserVar)>, Fail> {
        c.ws();
        let mut at = c.col();
        let mut ty_name = c.ident();
        if matches!(ty_name.as_str(), "NCK" | "CHAN") {
            if !global {
                return Err((
                    at,
                    format!("DEF {ty_name}: global user data (GUD) lives in the control's definition files (give them to vpcut as [program] definitions); vpcut models program-local variables (DEF without {ty_name})"),
                ));
            }
            c.ws();
            at = c.col();
            ty_name = c.ident();
        }
        if global && matches!(ty_name.as_str(), "AXIS" | "FRAME") {
            c.i = c.s.len();
            return Ok(Vec::new());
        }
        if ty_name == "LLI" || ty_name == "PHU" {
            return Err((
                at,
                format!("DEF with {ty_name} (limits, units) is not modelled"),
            ));
        }
        let ty = match ty_name.as_str() {
            "REAL" => VarType::Real,
            "INT" => VarType::Int,
            "BOOL" => VarType::Bool,
            "CHAR" => VarType::Char,
            "STRING" => {
                // STRING[n]: its length.
                if c.eat("[") {
                    let _ = c.number();
                    if !c.eat("]") {
                        return c.err("expected `]` after the STRING length");
                    }
                }
                VarType::Str
            }
            "AXIS" | "FRAME" => {
                return Err((
                    at,
                    format!(
                        "DEF {ty_name}: {} variables are not modelled by vpcut",
                        ty_name
                    ),
                ))
            }
            "" => return c.err("expected a type after DEF (REAL, INT, BOOL, CHAR, STRING)"),
            _ => {
                return Err((at, format!("`{ty_name}` is not a type of DEF (REAL, INT, BOOL, CHAR, STRING, AXIS, FRAME)")));
            }
        };
        let mut out = Vec::new();
        loop {
            c.ws();
            let at = c.col();
            let name = c.name_with_digits();
            if name.is_empty() || name.as_bytes()[0].is_ascii_digit() {
                return c.err("expected a variable name");
            }
            if name.len() < 2 || name == "R" {
                return Err((
                    at,
                    format!("`{name}`: a user variable's name has at least two characters and is not an address letter"),
                ));
            }
            let mut dims = (1usize, 1usize);
            let mut array = false;
            if c.eat("[") {
                array = true;
                let a = self.expr(c)?;
                dims.0 = size(a, at)?;
                if c.eat(",") {
                    let b = self.expr(c)?;
                    dims.1 = size(b, at)?;
                }
                if !c.eat("]") {
                    return c.err("expected `]` after the array sizes");
                }
            }
            let n = dims.0 * dims.1;
            if n > MAX_ELEMENTS {
                return Err((
                    at,
                    format!("array `{name}` of {n} elements: vpcut defines at most {MAX_ELEMENTS}"),
                ));
            }
            let mut var = UserVar {
                ty,
                dims,
                values: vec![0.0; n],
            };
            if c.eat("=") {
                if global && matches!(ty, VarType::Str | VarType::Char) {
                    skip_string_init(c)?;
                } else if ty == VarType::Str {
                    skip_string(c)?;
                } else {
                    let vals = self.init_values(c, n, array)?;
                    for (slot, v) in var.values.iter_mut().zip(vals) {
                        *slot = v;
                    }
                    for k in 0..n {
                        var.values[k] = var.typed(var.values[k]);
                    }
                }
            }
            out.push((name, var));
            if !c.eat(",") {
                break;
            }
        }
        if !c.done() {
            return c.err(format!("unexpected {} after DEF", c.here()));
        }
        Ok(out)
    }

    /// The initial values: one value (every element of an array), `(a, b, ..)`,
    /// `SET(a, b, ..)` (the first elements) or `REP(v)` (all elements).
    fn init_values(&self, c: &mut Cursor, n: usize, array: bool) -> Result<Vec<f64>, Fail> {
        let list = if c.eat("SET") {
            if !c.eat("(") {
                return c.err("expected `(` after SET");
            }
            true
        } else if c.eat("REP") {
            if !c.eat("(") {
                return c.err("expected `(` after REP");
            }
            let v = self.expr(c)?;
            if !c.eat(")") {
                return c.err("expected `)`");
            }
            return Ok(vec![v; n]);
        } else if array && c.peek() == Some(b'(') {
            // A list in brackets (an expression in brackets for a scalar).
            c.i += 1;
            true
        } else {
            false
        };
        if !list {
            let v = self.expr(c)?;
            return Ok(vec![v; if array { n } else { 1 }]);
        }
        let mut out = Vec::new();
        loop {
            let at = c.col();
            out.push(self.expr(c)?);
            if out.len() > n {
                return Err((at, format!("more initial values than the {n} elements")));
            }
            if !c.eat(",") {
                break;
            }
        }
        if !c.eat(")") {
            return c.err("expected `,` or `)` in the list of initial values");
        }
        Ok(out)
    }

    /// Whether any user variable (a GUD, or one of the running program) exists.
    pub(super) fn has_user_vars(&self) -> bool {
        !self.vars.s840.gud.is_empty() || self.scope().is_some_and(|s| !s.is_empty())
    }

    /// The user variable `name` of the running program, if defined.
    pub(super) fn user_var(&self, name: &str) -> Option<&UserVar> {
        self.scope()
            .and_then(|s| s.get(name))
            .or_else(|| self.vars.s840.gud.get(name))
    }

    /// `NAME = value` where NAME is no variable of the program: on the control a global user
    /// variable (GUD) that a definition file of the machine defines (`DEF NCK REAL TEST` in
    /// `_N_UGUD_DEF`); kept as a REAL scalar from here on, with a warning naming it.
    pub(super) fn assign_gud(&mut self, c: &mut Cursor, name: &str, at: usize) -> Result<(), Fail> {
        self.vars.s840.gud.insert(
            name.to_string(),
            UserVar {
                ty: VarType::Real,
                dims: (1, 1),
                values: vec![0.0],
            },
        );
        self.out.notes.push((
            at,
            format!("`{name}` is not defined in the program: taken as a global user variable (GUD) of the machine"),
            format!("the control needs `{name}` in a GUD definition file (DEF NCK REAL {name} or DEF CHAN ...); vpcut keeps it as a REAL from this assignment on"),
        ));
        self.assign_user(c, name)
    }

    /// The element index of `var` named at `c` (`[i]`, `[i, j]`, or nothing for a
    /// scalar).
    pub(super) fn element(&self, c: &mut Cursor, name: &str, var: &UserVar) -> Result<usize, Fail> {
        c.ws();
        let at = c.col();
        let scalar = var.dims == (1, 1);
        if !c.eat("[") {
            if scalar {
                return Ok(0);
            }
            return Err((
                at,
                format!("`{name}` is an array: name an element, `{name}[i]`"),
            ));
        }
        let i = self.expr(c)?;
        let j = if c.eat(",") {
            Some(self.expr(c)?)
        } else {
            None
        };
        if !c.eat("]") {
            return c.err("expected `]`");
        }
        let two = var.dims.1 > 1;
        let index = |v: f64, n: usize| -> Result<usize, Fail> {
            if v.fract() != 0.0 || v < 0.0 || v >= n as f64 {
                return Err((
                    at,
                    format!(
                        "index {v} of `{name}` is out of range 0..{} (Siemens alarm 12140)",
                        n - 1
                    ),
                ));
            }
            Ok(v as usize)
        };
        match (two, j) {
            (false, None) => index(i, var.dims.0),
            (true, Some(j)) => Ok(index(i, var.dims.0)? * var.dims.1 + index(j, var.dims.1)?),
            (false, Some(_)) => Err((at, format!("`{name}` has one index"))),
            (true, None) => Err((at, format!("`{name}` has two indices: `{name}[i, j]`"))),
        }
    }

    /// The value of user variable `name` (read at `c`, after the name; `at`: its column).
    pub(super) fn read_user(
        &self,
        c: &mut Cursor,
        name: &str,
        at: usize,
    ) -> Result<Option<f64>, Fail> {
        let Some(var) = self.user_var(name) else {
            return Ok(None);
        };
        if var.ty == VarType::Str {
            return Err((at, format!("`{name}` is a STRING, not a number")));
        }
        let k = self.element(c, name, var)?;
        Ok(Some(var.values[k]))
    }

    /// `name[index] = expression` (the cursor after the name).
    pub(super) fn assign_user(&mut self, c: &mut Cursor, name: &str) -> Result<(), Fail> {
        let var = self.user_var(name).expect("checked by the caller").clone();
        let k = self.element(c, name, &var)?;
        if !c.eat("=") {
            return c.err(format!("expected `=` after `{name}`"));
        }
        if var.ty == VarType::Str {
            return skip_string(c);
        }
        let v = self.expr(c)?;
        let v = var.typed(v);
        let local = self.scope().is_some_and(|s| s.contains_key(name));
        let slot = if local {
            self.scope_mut().get_mut(name)
        } else {
            self.vars.s840.gud.get_mut(name)
        };
        if let Some(slot) = slot {
            slot.values[k] = v;
        }
        Ok(())
    }
}

/// An array size: a whole number from 1.
fn size(v: f64, at: usize) -> Result<usize, Fail> {
    if v.fract() != 0.0 || !(1.0..=MAX_ELEMENTS as f64).contains(&v) {
        return Err((
            at,
            format!("array size {v}: expected a whole number from 1 to {MAX_ELEMENTS}"),
        ));
    }
    Ok(v as usize)
}

/// A STRING array's initial values in a GUD file: `"text"`, `("a", "b", ..)`, `REP("a")`
/// or `SET(..)`, skipped (strings are no numbers vpcut computes with).
fn skip_string_init(c: &mut Cursor) -> Result<(), Fail> {
    c.ws();
    let _ = c.eat("REP") || c.eat("SET");
    c.ws();
    if c.peek() != Some(b'(') {
        return skip_string(c);
    }
    let mut depth = 0usize;
    while let Some(b) = c.s.get(c.i).copied() {
        c.i += 1;
        match b {
            b'"' => {
                while c.s.get(c.i).is_some_and(|&q| q != b'"') {
                    c.i += 1;
                }
                c.i += 1;
            }
            b'(' => depth += 1,
            b')' => {
                depth -= 1;
                if depth == 0 {
                    return Ok(());
                }
            }
            _ => {}
        }
    }
    c.err("expected `)` closing the initial values")
}

/// A string value: `"text"` or a concatenation `"a" << B` (not evaluated: strings are
/// only shown by MSG).
pub(super) fn skip_string(c: &mut Cursor) -> Result<(), Fail> {
    c.ws();
    if c.peek() != Some(b'"') {
        return c.err("expected a string in double quotes");
    }
    // Everything to the end of the block belongs to the text and its concatenations.
    c.i = c.s.len();
    Ok(())
}
