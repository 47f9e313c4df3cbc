//! Siemens 802D blocks: R parameter assignment, address = expression, labels, GOTOF/GOTOB/
//! GOTO, IF .. GOTOF, subprogram calls by name with P repeats, RET, the thread cycles
//! CYCLE97/CYCLE99 (`siemens_cycles`); with the 840D (`Config::s840`) its statements
//! (`siemens_840d`), user variables (`siemens_vars`) and structured control flow
//! (`siemens_flow`); G74/G75 reference and fixed point approach; a GUD the program assigns
//! without a DEF and a cycle of the machine that is not found are warnings.

use super::codes;
use super::expr::{r_index, Fail};
use super::lex::Cursor;
use super::{Interp, MoveKind, Program, Step, Words};

impl Interp<'_> {
    pub(super) fn siemens_block(
        &mut self,
        prog: &Program,
        pc: usize,
        text: &str,
    ) -> Result<Step, Fail> {
        let mut c = Cursor::new(text, self.cfg.dialect);
        c.ws();
        if c.peek() == Some(b'%') {
            // `%_N_NAME_MPF` (and `%_N_NAME_SPF`): the header of the transfer format, the
            // program's name as the control stores it (802D and 840D alike).
            return Ok(Step::Next);
        }
        // Skip N and a label.
        // A block number (not the first letter of a name such as NEXT_PASS).
        if c.s.get(c.i) == Some(&b'N') && c.s.get(c.i + 1).is_some_and(u8::is_ascii_digit) {
            c.i += 1;
            let _ = c.number();
        }
        let save = c.i;
        let name = c.name_with_digits();
        if name.is_empty() || !c.eat(":") {
            // Not a label: read the block from the start.
            c.i = save;
        }
        if let Some(step) = self.fixed_point(prog, pc, &c.s[c.i..])? {
            return Ok(step);
        }
        if self.cfg.s840 {
            if let Some(step) = self.s840_statement(prog, pc, &mut c)? {
                return Ok(step);
            }
        } else if let Some(step) = self.proc_802(&mut c)? {
            return Ok(step);
        }
        let s840 = self.cfg.s840;
        let mut w = Words::default();
        // SUPA or G53 (840D): this block's X/Z in machine coordinates.
        let mut machine = false;
        while !c.done() {
            let at = c.i;
            let mut name = c.ident();
            // A name that goes on with digits: a cycle, a user variable, a subprogram.
            let (letters, short) = (c.i, name.clone());
            while name.len() > 1
                && c.i < c.s.len()
                && (c.s[c.i].is_ascii_alphanumeric() || c.s[c.i] == b'_')
            {
                name.push(char::from(c.s[c.i]));
                c.i += 1;
            }
            if matches!(name.as_str(), "CYCLE97" | "CYCLE99") {
                self.apply(&w, prog, pc)?;
                return self.in_cycle(|m| m.thread_cycle(&mut c, prog, pc, &name, at + 1));
            }
            if name == "CYCLE84" {
                self.apply(&w, prog, pc)?;
                return self.cycle84(&mut c, prog, pc, at + 1);
            }
            if self.user_var(&name).is_some() {
                self.assign_user(&mut c, &name)?;
                continue;
            }
            // `NAME=` with a name that is no address: a GUD of the machine (840D; the 802D
            // reads it the same way, issue 27: a warning naming it).
            if name.len() > 1
                && !codes::siemens_address(&name)
                && !codes::siemens_keyword(&name)
                && {
                    let mut k = c.i;
                    while c.s.get(k) == Some(&b' ') {
                        k += 1;
                    }
                    c.s.get(k) == Some(&b'=') && c.s.get(k + 1) != Some(&b'=')
                }
            {
                self.assign_gud(&mut c, &name, at + 1)?;
                continue;
            }
            // An address letter (or R) and its number.
            if codes::siemens_address(&short) || short.len() == 1 {
                c.i = letters;
                name = short;
            }
            match name.as_str() {
                // DIAMON/DIAMOF: the 802D sl has them too (802D sl programming manual,
                // "Dimensions: diameter and radius programming"); DIAM90 is the 840D's.
                "DIAMON" | "DIAMOF" | "DIAM90" if s840 || name != "DIAM90" => {
                    self.modal.diameter_mode = name != "DIAMOF";
                    self.vars.s840.diam90 = name == "DIAM90";
                }
                "SUPA" if s840 => machine = true,
                // The approach and retraction of tool radius compensation (`nose`).
                "NORM" | "KONT" => self.modal.nose_kont = name == "KONT",
                "KONTC" | "KONTT" => {
                    return Err((
                        at + 1,
                        format!("`{name}` (approach with constant curvature or tangent, a polynomial) is not simulated by vpcut: write NORM or KONT"),
                    ))
                }
                "TRANS" | "ATRANS" if s840 => {
                    self.trans(&mut c, name == "ATRANS", at + 1)?;
                    break;
                }
                "LIMS" => {
                    // The spindle speed limit of G96 (rev/min).
                    let _ = c.eat("=");
                    self.modal.speed_max = Some(self.expr(&mut c)?);
                }
                "G" if c.peek() == Some(b'5')
                    && c.s[c.i..].starts_with(b"53")
                    && !c.s.get(c.i + 2).is_some_and(u8::is_ascii_digit) =>
                {
                    let _ = c.number();
                    machine = true;
                }
                "IF" => {
                    let v = self.expr(&mut c)?;
                    let kw = c.ident();
                    let target = c.name_with_digits();
                    // The label is looked for only when the jump is taken, as on the control.
                    if v == 0.0 {
                        return Ok(Step::Next);
                    }
                    return Ok(Step::Jump(self.label(prog, pc, &kw, &target, at)?));
                }
                "GOTOF" | "GOTOB" | "GOTO" => {
                    let target = c.name_with_digits();
                    return Ok(Step::Jump(self.label(prog, pc, &name, &target, at)?));
                }
                "RET" => return Ok(Step::Return),
                "R" if c.s.get(c.i).is_some_and(|b| b.is_ascii_digit()) => {
                    let n = c.number().unwrap_or(f64::NAN);
                    let n = r_index(n, at + 1)?;
                    if !c.eat("=") {
                        return c.err("expected `=` after an R parameter");
                    }
                    let v = self.expr(&mut c)?;
                    self.vars.r.insert(n, v);
                }
                "" => return Err((at + 1, format!("unexpected {}", c.here()))),
                "T" if s840 && c.eat("=") && c.peek() == Some(b'"') => {
                    let t = self.tool_name(&mut c)?;
                    let k = (t - 1000.0) as usize;
                    w.t_text = Some(format!("T=\"{}\"", self.vars.s840.tool_names[k]));
                    w.vals.insert("T".into(), (t, at + 1));
                }
                addr if codes::siemens_address(addr) => {
                    let v = if c.eat("=") {
                        let ac_ic = if s840 && matches!(addr, "X" | "Z") {
                            self.ac_ic(&mut c, addr)?
                        } else {
                            None
                        };
                        match ac_ic {
                            Some(v) => v,
                            None => self.expr(&mut c)?,
                        }
                    } else {
                        let neg = c.eat("-");
                        let v = self.literal(&mut c)?.ok_or((
                            c.i + 1,
                            format!("expected a value after `{addr}`, found {}", c.here()),
                        ))?;
                        if !neg && matches!(addr, "M" | "S") && c.peek() == Some(b'=') {
                            // `M3=4`, `S3=1500`: the function or speed of spindle 3 (Fundamentals,
                            // "Spindle" with several spindles). Spindle 1 is the work spindle
                            // vpcut models (the master spindle of a lathe's channel).
                            c.i += 1;
                            let value = self.expr(&mut c)?;
                            if v == 1.0 {
                                value
                            } else {
                                self.out.notes.push((
                                    at + 1,
                                    format!("`{addr}{v}=`: spindle {v} is not the work spindle (vpcut models spindle 1); ignored"),
                                    "a grinding wheel, a driven tool or a second spindle: nothing of the turning tool's path".into(),
                                ));
                                continue;
                            }
                        } else if neg {
                            -v
                        } else {
                            v
                        }
                    };
                    let v = self.word_value(addr, v, at + 1)?;
                    match addr {
                        "G" => w.g.push(v as u32),
                        "M" => w.m.push(v as u32),
                        _ => {
                            w.vals.insert(addr.to_string(), (v, at + 1));
                        }
                    }
                }
                cycle
                    if cycle.len() > 5
                        && cycle.starts_with("CYCLE")
                        && cycle[5..].bytes().all(|b| b.is_ascii_digit()) =>
                {
                    // Another Siemens cycle (stock removal, grooving, drilling, tapping):
                    // its moves are missing from the toolpath.
                    self.unknown(
                        at + 1,
                        format!("`{cycle}` is not simulated: its moves are missing from the toolpath (vpcut runs CYCLE97 and CYCLE99)"),
                    )?;
                    break;
                }
                // A message to the operator, a preprocessing stop: no motion (802D too).
                "MSG" | "STOPRE" => break,
                kw if codes::siemens_keyword(kw) => {
                    // A statement vpcut does not simulate: skip the rest of the block.
                    self.unknown(at + 1, format!("`{kw}` is not simulated"))?;
                    break;
                }
                call if call.len() > 2 => {
                    // A subprogram called by name, with an optional repeat `P n`; on the
                    // 840D with arguments `NAME(a, b)` for its PROC, in a scope of its own.
                    if c.peek() == Some(b'(') {
                        // A cycle that is nowhere to be found (a manufacturer's cycle of
                        // the machine, `_APPROACH_WITH_A_AXIS(..)`): a warning naming it
                        // (802D and 840D).
                        if self.find_program(call).is_none() {
                            self.unknown(
                                at + 1,
                                format!("cycle `{call}` not found (in this file or as {call}.SPF beside it): a cycle of the machine, skipped; its moves are missing from the toolpath"),
                            )?;
                            break;
                        }
                        self.call_args(&mut c, at + 1)?;
                    }
                    let mut times = 1;
                    if c.eat("P") {
                        times = c.number().unwrap_or(1.0).max(1.0) as u32;
                    }
                    self.apply(&w, prog, pc)?;
                    if s840 || self.vars.s840.args.is_some() {
                        // (A cycle called with arguments on the 802D binds them by its PROC too.)
                        self.new_scope();
                        return Ok(Step::Call(call.to_string(), times, Some(Vec::new())));
                    }
                    return Ok(Step::Call(call.to_string(), times, None));
                }
                other => {
                    self.unknown(at + 1, format!("unknown address `{other}`"))?;
                    if c.eat("=") {
                        self.expr(&mut c)?;
                    } else {
                        let _ = c.eat("-");
                        let _ = c.number();
                    }
                }
            }
        }
        if s840 {
            if self.vars.s840.diam90 && self.modal.incremental && w.vals.contains_key("X") {
                return Err((
                    w.vals["X"].1,
                    "DIAM90 with G91: incremental X in radius is not modelled (program DIAMON or G90)".into(),
                ));
            }
            if w.g.contains(&500) {
                // G500: no settable work offset (the zero frame).
                self.frames.work = 8;
            }
        }
        if machine {
            return self.machine_block(w, prog, pc);
        }
        self.apply(&w, prog, pc)
    }

    /// `G74 X1=0 Z1=0` (reference point approach) and `G75 [FP=n] X1=0 Z1=0` (fixed point
    /// approach), SINUMERIK 802D/840D programming manuals, "Fixed point approach G75" and
    /// "Reference point approach G74": the named axes go at rapid straight to the point the
    /// machine data holds (the values written are ignored); nothing else in the block. The
    /// reference point is the job's `reference_point`, fixed point 1 (the default) its
    /// `second_reference_point` (machine coordinates, as FANUC's G28/G30).
    fn fixed_point(
        &mut self,
        prog: &Program,
        pc: usize,
        rest: &[u8],
    ) -> Result<Option<Step>, Fail> {
        let text = String::from_utf8_lossy(rest).to_string();
        let t = text.trim_start();
        let g = if t.starts_with("G74") {
            74
        } else if t.starts_with("G75") {
            75
        } else {
            return Ok(None);
        };
        if t[3..].starts_with(|ch: char| ch.is_ascii_digit() || ch == '.') {
            return Ok(None);
        }
        let after = &t[3..];
        if let Some(k) = after.find("FP=") {
            let digits: String = after[k + 3..]
                .chars()
                .take_while(char::is_ascii_digit)
                .collect();
            if g == 75 && digits != "1" {
                return Err((
                    1,
                    format!("G75 FP={digits}: only fixed point 1 is known (the job's [program] second_reference_point)"),
                ));
            }
        }
        let named = |a: char| after.contains(a);
        let point = if g == 74 {
            self.frames.reference
        } else {
            self.frames.reference2
        };
        let end = (
            if named('X') { point.0 } else { self.x },
            if named('Z') { point.1 } else { self.z },
        );
        if end != (self.x, self.z) {
            self.emit(prog, pc, MoveKind::Rapid, (self.x, self.z), end, None);
        }
        (self.x, self.z) = end;
        Ok(Some(Step::Next))
    }

    pub(super) fn label(
        &self,
        prog: &Program,
        pc: usize,
        kw: &str,
        target: &str,
        at: usize,
    ) -> Result<usize, Fail> {
        let Some(&to) = prog.labels.get(target) else {
            return Err((
                at + 1,
                format!("label `{target}` not found in {}", prog.name),
            ));
        };
        match kw {
            "GOTOF" if to <= pc => Err((
                at + 1,
                format!("GOTOF jumps forward, but `{target}` is above"),
            )),
            "GOTOB" if to > pc => {
                Err((at + 1, format!("GOTOB jumps back, but `{target}` is below")))
            }
            "GOTOF" | "GOTOB" | "GOTO" => Ok(to),
            _ => Err((at + 1, format!("expected GOTOF, GOTOB or GOTO, got `{kw}`"))),
        }
    }
}
