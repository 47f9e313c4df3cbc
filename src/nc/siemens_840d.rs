//! Siemens 840D statements beyond the 802D (`docs/job-format.md`, "Siemens 840D"): the
//! program header `%_N_NAME_MPF`, `DEF`, `PROC` with parameters, the structured control
//! flow (`siemens_flow`), `MSG`/`WORKPIECE` (nothing to simulate), `TRANS`/`ATRANS` along
//! Z, `DIAMON`/`DIAMOF`/`DIAM90`, `AC(..)`/`IC(..)`, `T="name"`, and calls `NAME(a, b)`.

use super::expr::Fail;
use super::lex::Cursor;
use super::siemens_flow::{self, Kw};
use super::siemens_vars::VarType;
use super::{Interp, Program, Step};

impl Interp<'_> {
    /// A block that is an 840D statement of its own, run here (`None`: an ordinary
    /// block, the cursor unmoved).
    pub(super) fn s840_statement(
        &mut self,
        prog: &Program,
        pc: usize,
        c: &mut Cursor,
    ) -> Result<Option<Step>, Fail> {
        c.ws();
        if c.peek() == Some(b'%') {
            // `%_N_NAME_MPF`: the program's name as the control stores it.
            return Ok(Some(Step::Next));
        }
        let save = c.i;
        let word = c.name_with_digits();
        let step = match word.as_str() {
            "DEF" => {
                self.def(c)?;
                Step::Next
            }
            "PROC" => {
                self.proc(c)?;
                Step::Next
            }
            "MSG" | "WORKPIECE" | "STOPRE" | "WAITM" | "SETMS" | "SPOS" | "SOFT" | "BRISK"
            | "FFWON" | "FFWOF" | "CFC" | "CFTCP" | "CFIN" | "SPCON" | "SPCOF" | "G64" => {
                // Messages, the simulation's blank, preprocessing stops, acceleration and
                // feed modes, spindle positioning: nothing that moves the tool path.
                Step::Next
            }
            _ => match siemens_flow::keyword(&prog.blocks[pc].2) {
                Some(kw) => self.structure(prog, pc, c, kw)?,
                None => {
                    c.i = save;
                    return Ok(None);
                }
            },
        };
        Ok(Some(step))
    }

    /// The 802D's `PROC NAME(params)` (a cycle's first block, reached by a call with
    /// arguments): bound as on the 840D. `None`: no PROC, the cursor unmoved.
    pub(super) fn proc_802(&mut self, c: &mut Cursor) -> Result<Option<Step>, Fail> {
        let save = c.i;
        if c.name_with_digits() == "PROC" {
            self.proc(c)?;
            return Ok(Some(Step::Next));
        }
        c.i = save;
        Ok(None)
    }

    /// A structure keyword (the cursor after it).
    fn structure(
        &mut self,
        prog: &Program,
        pc: usize,
        c: &mut Cursor,
        kw: Kw,
    ) -> Result<Step, Fail> {
        let at = c.col();
        let partner = |else_too: bool| {
            siemens_flow::partner(prog, pc, else_too).ok_or((
                at,
                "this control structure has no partner in the program".to_string(),
            ))
        };
        let cond = |m: &Interp, c: &mut Cursor| -> Result<bool, Fail> {
            let v = m.expr(c)?;
            if !c.done() {
                return c.err(format!("unexpected {} after the condition", c.here()));
            }
            Ok(v != 0.0)
        };
        Ok(match kw {
            Kw::If => {
                if cond(self, c)? {
                    Step::Next
                } else {
                    Step::Jump(partner(true)? + 1)
                }
            }
            // Reached from the IF branch: on past the ENDIF.
            Kw::Else => Step::Jump(partner(false)? + 1),
            Kw::EndIf | Kw::Repeat | Kw::Loop => Step::Next,
            Kw::While => {
                if cond(self, c)? {
                    Step::Next
                } else {
                    Step::Jump(partner(false)? + 1)
                }
            }
            Kw::EndWhile => Step::Jump(partner(false)?),
            Kw::Until => {
                if cond(self, c)? {
                    Step::Next
                } else {
                    Step::Jump(partner(false)? + 1)
                }
            }
            Kw::EndLoop => Step::Jump(partner(false)? + 1),
            Kw::For => {
                let (var, start, end) = self.for_head(c)?;
                self.set_counter(&var, start, at)?;
                if start > end {
                    Step::Jump(partner(false)? + 1)
                } else {
                    Step::Next
                }
            }
            Kw::EndFor => {
                let head = partner(false)?;
                let text = &prog.blocks[head].2;
                let mut hc = Cursor::new(text, c.dialect);
                hc.i = siemens_flow::head_offset(text);
                let _ = hc.name_with_digits(); // FOR
                let (var, _, end) = self.for_head(&mut hc)?;
                let v = self.counter(&var, at)? + 1.0;
                self.set_counter(&var, v, at)?;
                if v <= end {
                    Step::Jump(head + 1)
                } else {
                    Step::Next
                }
            }
        })
    }

    /// `FOR var = start TO end` (the cursor after FOR): the counter, start and end.
    fn for_head(&self, c: &mut Cursor) -> Result<(String, f64, f64), Fail> {
        let var = c.name_with_digits();
        if var.is_empty() {
            return c.err("expected the FOR loop's counter variable");
        }
        if !c.eat("=") {
            return c.err("expected `=` after the FOR counter");
        }
        let start = self.expr(c)?;
        if !c.eat("TO") {
            return c.err("expected TO in the FOR loop");
        }
        let end = self.expr(c)?;
        Ok((var, start, end))
    }

    /// A FOR counter: an R parameter or an INT/REAL user variable.
    fn counter(&self, var: &str, at: usize) -> Result<f64, Fail> {
        if let Some(n) = r_number(var) {
            return Ok(*self.vars.r.get(&n).unwrap_or(&0.0));
        }
        match self.user_var(var) {
            Some(v) if v.dims == (1, 1) && matches!(v.ty, VarType::Int | VarType::Real) => {
                Ok(v.values[0])
            }
            Some(_) => Err((
                at,
                format!("`{var}`: a FOR counter is an INT or REAL scalar"),
            )),
            None => Err((at, format!("`{var}` is not defined (DEF INT {var})"))),
        }
    }

    fn set_counter(&mut self, var: &str, v: f64, at: usize) -> Result<(), Fail> {
        self.counter(var, at)?;
        if let Some(n) = r_number(var) {
            self.vars.r.insert(n, v);
            return Ok(());
        }
        if let Some(slot) = self.scope_mut().get_mut(var) {
            slot.values[0] = if slot.ty == VarType::Int {
                v.round()
            } else {
                v
            };
        }
        Ok(())
    }

    /// `PROC NAME(type name, ..)`: binds the caller's arguments (0 where left out).
    fn proc(&mut self, c: &mut Cursor) -> Result<(), Fail> {
        let _name = c.name_with_digits();
        let (args, _) = self.vars.s840.args.take().unwrap_or((Vec::new(), 0));
        let mut params = Vec::new();
        if c.eat("(") && !c.eat(")") {
            loop {
                c.ws();
                let at = c.col();
                let ty = c.ident();
                let ty = match ty.as_str() {
                    "REAL" => VarType::Real,
                    "INT" => VarType::Int,
                    "BOOL" => VarType::Bool,
                    "CHAR" => VarType::Char,
                    "STRING" => {
                        // STRING[n]: a name or text (a wheel's, a tool's) the cycle shows or
                        // passes on; no number vpcut computes with.
                        if c.eat("[") {
                            let _ = c.number();
                            if !c.eat("]") {
                                return c.err("expected `]` after the STRING length");
                            }
                        }
                        VarType::Str
                    }
                    "VAR" => {
                        return Err((
                            at,
                            "VAR parameters (call by reference) are not modelled".into(),
                        ))
                    }
                    other => {
                        return Err((
                            at,
                            format!(
                            "PROC parameter type `{other}` is not modelled (REAL, INT, BOOL, CHAR, STRING)"
                        ),
                        ))
                    }
                };
                let name = c.name_with_digits();
                if name.len() < 2 {
                    return c.err("expected a parameter name");
                }
                params.push((ty, name));
                if c.eat(")") {
                    break;
                }
                if !c.eat(",") {
                    return c.err("expected `,` or `)` in the PROC parameters");
                }
            }
        }
        if args.len() > params.len() {
            return Err((
                1,
                format!(
                    "{} arguments for {} parameters of the PROC",
                    args.len(),
                    params.len()
                ),
            ));
        }
        // SAVE, DISPLOF and the like after the list change nothing simulated.
        for (k, (ty, name)) in params.into_iter().enumerate() {
            let v = args.get(k).copied().unwrap_or(0.0);
            let v = match ty {
                VarType::Int | VarType::Char => v.round(),
                VarType::Bool => f64::from(v != 0.0),
                _ => v,
            };
            self.scope_mut().insert(
                name,
                super::siemens_vars::UserVar {
                    ty,
                    dims: (1, 1),
                    values: vec![v],
                },
            );
        }
        Ok(())
    }

    /// `NAME(a, , b)`: the arguments of a call (the cursor at `(`), kept for the callee's
    /// PROC.
    pub(super) fn call_args(&mut self, c: &mut Cursor, at: usize) -> Result<(), Fail> {
        let _ = c.eat("(");
        let mut args = Vec::new();
        if !c.eat(")") {
            loop {
                if matches!(c.peek(), Some(b',') | Some(b')')) {
                    args.push(0.0);
                } else if c.peek() == Some(b'"') {
                    // A string argument (for a STRING parameter): no number.
                    c.i += 1;
                    while c.peek().is_some_and(|b| b != b'"') {
                        c.i += 1;
                    }
                    if !c.eat("\"") {
                        return c.err("expected `\"` closing the string");
                    }
                    args.push(0.0);
                } else {
                    args.push(self.expr(c)?);
                }
                if c.eat(")") {
                    break;
                }
                if !c.eat(",") {
                    return c.err("expected `,` or `)` in the call's arguments");
                }
            }
        }
        self.vars.s840.args = Some((args, at));
        Ok(())
    }

    /// `TRANS`/`ATRANS` with Z (and X0): the programmable frame's offset along Z
    /// (the cursor after the keyword).
    pub(super) fn trans(&mut self, c: &mut Cursor, add: bool, at: usize) -> Result<(), Fail> {
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        if !add {
            self.frames.g92_off = (0.0, 0.0);
        }
        while !c.done() {
            c.ws();
            let wat = c.col();
            let axis = c.ident();
            let _ = c.eat("=");
            let v = self.expr(c)?;
            match axis.as_str() {
                "Z" => self.frames.g92_off.1 += v * scale,
                "X" if v == 0.0 => {}
                "X" => {
                    return Err((
                        wat,
                        "TRANS/ATRANS along X is not modelled (its radius or diameter reading is machine data)".into(),
                    ))
                }
                _ => return Err((wat, format!("TRANS/ATRANS along `{axis}`: a lathe has X and Z"))),
            }
        }
        let _ = at;
        Ok(())
    }

    /// `T="name"`: a tool by name, numbered 1000, 1001, .. in the order first named
    /// (the cursor at the opening quote).
    pub(super) fn tool_name(&mut self, c: &mut Cursor) -> Result<f64, Fail> {
        let _ = c.eat("\"");
        let st = c.i;
        while c.i < c.s.len() && c.s[c.i] != b'"' {
            c.i += 1;
        }
        if c.i >= c.s.len() {
            return c.err("expected the closing `\"` of the tool name");
        }
        let name = String::from_utf8_lossy(&c.s[st..c.i]).into_owned();
        c.i += 1;
        let names = &mut self.vars.s840.tool_names;
        let k = match names.iter().position(|n| *n == name) {
            Some(k) => k,
            None => {
                names.push(name);
                names.len() - 1
            }
        };
        Ok(1000.0 + k as f64)
    }

    /// `AC(v)`/`IC(v)` after `X=`/`Z=`: the value in the active G90/G91 mode (`None`: not
    /// an AC/IC value, the cursor unmoved).
    pub(super) fn ac_ic(&self, c: &mut Cursor, axis: &str) -> Result<Option<f64>, Fail> {
        let save = c.i;
        let inc = if c.eat("AC") {
            false
        } else if c.eat("IC") {
            true
        } else {
            return Ok(None);
        };
        if !c.eat("(") {
            c.i = save;
            return Ok(None);
        }
        let v = self.expr(c)?;
        if !c.eat(")") {
            return c.err("expected `)`");
        }
        if inc == self.modal.incremental {
            return Ok(Some(v));
        }
        // The current point in program units of this axis.
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let (ox, oz) = self.frames.offsets[self.frames.work];
        let here = match axis {
            "X" => {
                let xs = if self.modal.diameter_mode { 1.0 } else { 2.0 };
                (self.x - ox - self.frames.g92_off.0) / (xs * scale)
            }
            _ => (self.z - oz - self.frames.g92_off.1) / scale,
        };
        Ok(Some(if inc { here + v } else { v - here }))
    }
}

/// `R12` as the R parameter number 12.
fn r_number(name: &str) -> Option<u32> {
    let d = name.strip_prefix('R')?;
    if d.is_empty() || !d.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    d.parse().ok()
}

impl Interp<'_> {
    /// A block with `SUPA` or `G53` (840D): its X/Z are machine coordinates (the job's
    /// frame), reached by G0 or G1; the block's other words run as usual.
    pub(super) fn machine_block(
        &mut self,
        mut w: super::Words,
        prog: &Program,
        pc: usize,
    ) -> Result<Step, Fail> {
        let x = w.vals.remove("X");
        let z = w.vals.remove("Z");
        let step = self.apply(&w, prog, pc)?;
        if x.is_none() && z.is_none() {
            return Ok(step);
        }
        let kind = match self.modal.motion {
            0 => super::MoveKind::Rapid,
            1 => {
                self.need_feed(&w)?;
                super::MoveKind::Feed
            }
            g => {
                return Err((
                    1,
                    format!(
                        "SUPA/G53 with G{g}: vpcut moves in machine coordinates with G0 or G1 only"
                    ),
                ))
            }
        };
        if self.modal.incremental {
            return Err((1, "SUPA/G53 needs absolute coordinates (G90)".into()));
        }
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let xs = if self.modal.diameter_mode { 1.0 } else { 2.0 };
        let to = (
            x.map_or(self.x, |v| v.0 * xs * scale),
            z.map_or(self.z, |v| v.0 * scale),
        );
        if to != (self.x, self.z) {
            self.emit(prog, pc, kind, (self.x, self.z), to, None);
        }
        (self.x, self.z) = to;
        Ok(step)
    }
}
