//! Siemens 802D blocks: R parameter assignment, address = expression, labels, GOTOF/GOTOB/
//! GOTO, IF .. GOTOF, subprogram calls by name with P repeats, RET.

use super::codes;
use super::expr::{r_index, Fail};
use super::lex::Cursor;
use super::{Interp, Program, Step, Words};

impl Interp<'_> {
    pub(super) fn siemens_block(
        &mut self,
        prog: &Program,
        pc: usize,
        text: &str,
    ) -> Result<Step, Fail> {
        let mut c = Cursor::new(text, self.cfg.dialect);
        // Skip N and a label.
        // A block number (not the first letter of a name such as NEXT_PASS).
        c.ws();
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
        let mut w = Words::default();
        while !c.done() {
            let at = c.i;
            let name = c.ident();
            match name.as_str() {
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
                addr if codes::siemens_address(addr) => {
                    let v = if c.eat("=") {
                        self.expr(&mut c)?
                    } else {
                        let neg = c.eat("-");
                        let v = self.literal(&mut c)?.ok_or((
                            c.i + 1,
                            format!("expected a value after `{addr}`, found {}", c.here()),
                        ))?;
                        if neg {
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
                kw if codes::siemens_keyword(kw) => {
                    // A statement vpcut does not simulate: skip the rest of the block.
                    self.unknown(at + 1, format!("`{kw}` is not simulated"))?;
                    break;
                }
                call if call.len() > 2 => {
                    // A subprogram called by name, with an optional repeat `P n`.
                    let mut times = 1;
                    if c.eat("P") {
                        times = c.number().unwrap_or(1.0).max(1.0) as u32;
                    }
                    self.apply(&w, prog, pc)?;
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
        self.apply(&w, prog, pc)
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
