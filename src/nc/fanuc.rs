//! FANUC and GSK 980TDC blocks: Macro B statements and control flow, Macro A (`G65 H..`),
//! G65 macro calls, the two-block G76, the modal G92 and GSK's G34.

use super::codes;
use super::expr::{z, Fail};
use super::lex::Cursor;
use super::{Interp, MoveKind, Program, Step, Sync, Words};

/// The first G76 block's `P(mm)(rr)(aa)` (`controllers.md` 2.3; GSK 980TDc writes it the
/// same way): six digits at most, mm finishing passes 00..99 (00, which program generators
/// write, cuts no pass at the full depth after the roughing's last at k - d), rr chamfer 00..99 (0.1 L),
/// aa tool angle one of 80, 60, 55, 30, 29, 0 degrees. Anything else is an alarm on the
/// control and an error here, at the P word.
fn g76_p(p: f64, col: usize) -> Result<(u32, u32, u32), Fail> {
    if p.fract() != 0.0 || !(0.0..=999_999.0).contains(&p) {
        return Err((
            col,
            format!("G76 P{p}: expected six digits mmrraa (finishing passes, chamfer, tool angle), e.g. P010060"),
        ));
    }
    let p = p as u32;
    let (m, r, a) = (p / 10_000, (p / 100) % 100, p % 100);
    if ![80, 60, 55, 30, 29, 0].contains(&a) {
        return Err((
            col,
            format!("G76 P{p:06}: the tool angle aa must be one of 80, 60, 55, 30, 29, 0 degrees, got {a}"),
        ));
    }
    Ok((m, r, a))
}

/// Whether the value the cursor read since `st` was a number written without a decimal
/// point (not a variable or an expression).
fn plain_literal(c: &Cursor, st: usize) -> bool {
    let written = &c.s[st..c.i];
    !written.iter().any(|b| matches!(b, b'.' | b'#' | b'['))
}

/// A jump to the block numbered `n` (`col`: where the number stands): a whole sequence
/// number that the program has.
fn goto(prog: &Program, n: f64, col: usize) -> Result<Step, Fail> {
    if n.is_nan() {
        return Err((col, "GOTO to a vacant (null) variable".into()));
    }
    if n.fract() != 0.0 || !(0.0..=99_999.0).contains(&n) {
        return Err((
            col,
            format!("GOTO {n}: expected a sequence number 1..99999"),
        ));
    }
    prog.numbers
        .get(&(n as u32))
        .map(|&k| Step::Jump(k))
        .ok_or((col, format!("no block N{n} in {}", prog.name)))
}

impl Interp<'_> {
    pub(super) fn fanuc_block(
        &mut self,
        prog: &Program,
        pc: usize,
        text: &str,
        loops: &mut Vec<(u32, usize)>,
    ) -> Result<Step, Fail> {
        let mut c = Cursor::new(text, self.cfg.dialect);
        if text.starts_with('O') && text[1..].chars().all(|ch| ch.is_ascii_digit()) {
            return Ok(Step::Next);
        }
        let mut w = Words::default();
        while !c.done() {
            let at = c.i;
            if c.eat("#") {
                let idx = self.var_index(&mut c)?;
                if !c.eat("=") {
                    return c.err("expected `=` after a variable");
                }
                let v = self.expr(&mut c)?;
                self.set_var(idx, v);
                continue;
            }
            if c.eat("WHILE") {
                let v = self.bracket(&mut c)?;
                if !c.eat("DO") {
                    return c.err("expected DOn after WHILE [..]");
                }
                let n = c.number().unwrap_or(0.0) as u32;
                if v != 0.0 {
                    loops.retain(|l| l.1 != pc);
                    loops.push((n, pc));
                    return Ok(Step::Next);
                }
                // Skip to the block after the matching ENDn.
                for (k, b) in prog.blocks.iter().enumerate().skip(pc + 1) {
                    if b.2.replace(' ', "") == format!("END{n}") {
                        loops.retain(|l| l.1 != pc);
                        return Ok(Step::Jump(k + 1));
                    }
                }
                return Err((at + 1, format!("WHILE .. DO{n} without END{n}")));
            }
            if c.eat("END") {
                let n = c.number().unwrap_or(0.0) as u32;
                let Some(&(_, start)) = loops.iter().rev().find(|l| l.0 == n) else {
                    return Err((at + 1, format!("END{n} without DO{n}")));
                };
                return Ok(Step::Jump(start));
            }
            if c.eat("IF") {
                let v = self.bracket(&mut c)?;
                if c.eat("GOTO") {
                    c.ws();
                    let col = c.i + 1;
                    let n = self.fanuc_value(&mut c)?;
                    if v == 0.0 {
                        return Ok(Step::Next);
                    }
                    return goto(prog, n, col);
                }
                if c.eat("THEN") {
                    if v == 0.0 {
                        return Ok(Step::Next);
                    }
                    continue;
                }
                return c.err("expected GOTO or THEN after IF [..]");
            }
            if c.eat("GOTO") {
                // The target may be a number, a variable or an expression (`controllers.md`
                // 4.3).
                c.ws();
                let col = c.i + 1;
                let n = self.fanuc_value(&mut c)?;
                return goto(prog, n, col);
            }
            if c.eat("G65") {
                return self.macro_a(&mut c, prog);
            }
            let Some(letter) = c.peek().filter(u8::is_ascii_alphabetic) else {
                return Err((at + 1, format!("unexpected {}", c.here())));
            };
            c.i += 1;
            let st = c.i;
            let v = self.fanuc_value(&mut c)?;
            let v = self.word_value(&(letter as char).to_string(), v, at + 1)?;
            if v.is_nan() {
                // An address whose value is a vacant variable is left out (FANUC).
                continue;
            }
            let written = &text[st..c.i];
            if letter == b'T' && !written.is_empty() && written.bytes().all(|b| b.is_ascii_digit())
            {
                w.t_text = Some(format!("T{written}"));
            }
            if written.contains('.') {
                w.points.push((letter as char).to_string());
            } else if !written.contains(['#', '[']) {
                w.plain.push((letter as char).to_string());
            }
            match letter {
                b'G' => w.g.push(v.round() as u32),
                b'M' => w.m.push(v.round() as u32),
                b'N' | b'O' => {}
                l if codes::address(self.cfg.milling, l as char) => {
                    w.vals.insert((letter as char).to_string(), (v, at + 1));
                }
                // A and D: only the one-block G76 (and D the one-block G71..G73) reads them
                // (checked below).
                b'A' | b'D' if !self.cfg.milling => {
                    w.vals.insert((letter as char).to_string(), (v, at + 1));
                }
                other => self.unknown(at + 1, format!("unknown address `{}`", other as char))?,
            }
        }
        if self.cfg.milling {
            return self.mill_apply(&w, prog, pc);
        }
        if self.cfg.system != codes::GcodeSystem::A {
            // G-code system B or C: read as the system-A codes they are.
            let mut g = Vec::with_capacity(w.g.len());
            for &code in &w.g {
                match codes::in_system_a(self.cfg.system, code) {
                    codes::InA::Code(c) => g.push(c),
                    codes::InA::Absolute => self.modal.incremental = false,
                    codes::InA::Incremental => self.modal.incremental = true,
                    // G98/G99: the canned cycle's (G84's) return level.
                    codes::InA::ReturnLevel => self.thread.tap.to_r = code == 99,
                }
            }
            w.g = g;
        }
        if w.g.contains(&76) {
            return self.in_cycle(|m| m.g76(&w, prog, pc));
        }
        if let Some(step) = self.tap_modes(&w, prog, pc)? {
            return Ok(step);
        }
        if let Some(&g) = w.g.iter().find(|g| (70..=75).contains(*g)) {
            // G70 runs its shape's blocks under the modal compensation; the others make
            // their moves from a compensated shape (`nose_shape`) with the vector held.
            if g == 70 {
                return self.repetitive_cycle(g, &w, prog, pc);
            }
            return self.nose_held(|m| m.repetitive_cycle(g, &w, prog, pc));
        }
        for k in ["A", "D"] {
            if let Some(&(_, col)) = w.vals.get(k) {
                self.unknown(col, format!("unknown address `{k}`"))?;
            }
        }
        self.apply(&w, prog, pc)
    }

    /// FANUC/GSK Custom Macro A: `G65 Hnn P#i Q#j R#k` (`controllers.md` 5). P names the
    /// result variable (or the block number of a jump); Q and R are variables or constants.
    pub(super) fn macro_a(&mut self, c: &mut Cursor, prog: &Program) -> Result<Step, Fail> {
        let mut h = None;
        let mut p: Option<(f64, bool, usize)> = None; // (value, written as #n, column)
        let (mut q, mut r) = (0.0, 0.0);
        let mut repeats = 1.0;
        // Macro call arguments (specifications I and II): (local variable, value), in order.
        let mut args: Vec<(u32, f64)> = Vec::new();
        // How many I, J, K words were read (specification II sets).
        let mut ijk = [0u32; 3];
        while !c.done() {
            let at = c.i;
            let Some(letter) = c.peek().filter(u8::is_ascii_alphabetic) else {
                return Err((at + 1, format!("unexpected {} in G65", c.here())));
            };
            c.i += 1;
            match letter {
                b'H' => {
                    h = Some(
                        c.number()
                            .ok_or((c.i + 1, "expected the H code".to_string()))?
                            as u32,
                    )
                }
                b'P' => {
                    let var = c.eat("#");
                    let v = c
                        .number()
                        .ok_or((c.i + 1, "expected a number".to_string()))?;
                    p = Some((v, var, at + 1));
                }
                // In a macro call Q and R are the arguments #17 and #18, set in block order
                // (a later argument for the same variable wins).
                b'Q' => {
                    let v = self.fanuc_value(c)?;
                    args.push((17, v));
                    q = z(v);
                }
                b'R' => {
                    let st = c.i;
                    let v = self.fanuc_value(c)?;
                    args.push((18, self.argument(b'R', v, plain_literal(c, st))));
                    r = z(v);
                }
                b'L' => repeats = z(self.fanuc_value(c)?),
                // Argument specification II (`controllers.md` 4.4): the n-th I, J, K of the
                // block (n = 1..10) set #(3n+1), #(3n+2), #(3n+3). The first set is
                // specification I's #4..#6; like FANUC, a letter that repeats opens the next
                // set, and where I and II name the same variable the later word wins.
                b'I' | b'J' | b'K' => {
                    let slot = usize::from(letter - b'I');
                    let n = ijk[slot];
                    if n >= 10 {
                        return Err((
                            at + 1,
                            format!(
                                "more than 10 `{}` arguments in one G65 (specification II)",
                                letter as char
                            ),
                        ));
                    }
                    ijk[slot] += 1;
                    let st = c.i;
                    let v = self.fanuc_value(c)?;
                    let v = self.argument(letter, v, plain_literal(c, st));
                    args.push((4 + slot as u32 + 3 * n, v));
                }
                other => {
                    let var = match other {
                        b'A' => 1,
                        b'B' => 2,
                        b'C' => 3,
                        b'D' => 7,
                        b'E' => 8,
                        b'F' => 9,
                        b'M' => 13,
                        b'S' => 19,
                        b'T' => 20,
                        b'U' => 21,
                        b'V' => 22,
                        b'W' => 23,
                        b'X' => 24,
                        b'Y' => 25,
                        b'Z' => 26,
                        _ => {
                            return Err((
                                at + 1,
                                format!("`{}` cannot pass a G65 argument", other as char),
                            ))
                        }
                    };
                    let st = c.i;
                    let v = self.fanuc_value(c)?;
                    args.push((var, self.argument(other, v, plain_literal(c, st))));
                }
            }
        }
        let Some(h) = h else {
            // G65 P<program> L<repeats> <arguments>: a macro call with its own locals. Q and
            // R were read as Macro A operands above; as arguments they are #17 and #18.
            let (pv, _, _) = p.ok_or((1, "G65 needs P (the macro program) or H".to_string()))?;
            let times = repeats.round().clamp(1.0, 9999.0) as u32;
            return Ok(Step::Call(
                format!("O{}", pv.round() as u64),
                times,
                Some(args),
            ));
        };
        let (pv, pvar, pcol) = p.ok_or((1, format!("G65 H{h:02} needs P")))?;
        let jump = |m: &Self, cond: bool| -> Result<Step, Fail> {
            if !cond {
                return Ok(Step::Next);
            }
            // `P#i` jumps to the block number that #i holds.
            let n = if pvar { m.get(c, pv, pcol + 1)? } else { pv };
            goto(prog, n, pcol)
        };
        let set = |m: &mut Self, v: f64| -> Result<Step, Fail> {
            if !pvar {
                return Err((pcol, format!("G65 H{h:02}: P must name a variable (#n)")));
            }
            let v = super::expr::in_range(m.cfg.dialect, 1, v, || format!("G65 H{h:02}"))?;
            let idx = super::expr::var_number(pv, pcol + 1, false)?;
            m.set_var(idx, v);
            Ok(Step::Next)
        };
        let nonzero = |v: f64| {
            if v == 0.0 {
                Err((1, "division by zero".to_string()))
            } else {
                Ok(v)
            }
        };
        match h {
            1 => set(self, q),
            2 => set(self, q + r),
            3 => set(self, q - r),
            4 => set(self, q * r),
            5 => set(self, q / nonzero(r)?),
            21 if q >= 0.0 => set(self, q.sqrt()),
            21 => Err((
                1,
                format!("G65 H21: the square root of {q}, a negative number (alarm 111)"),
            )),
            22 => set(self, q.abs()),
            23 => set(self, q % nonzero(r)?),
            27 => set(self, q.hypot(r)),
            31 => set(self, q * r.to_radians().sin()),
            32 => set(self, q * r.to_radians().cos()),
            33 => set(self, q * r.to_radians().tan()),
            34 => set(self, q.atan2(r).to_degrees()),
            80 => jump(self, true),
            81 => jump(self, q == r),
            82 => jump(self, q != r),
            83 => jump(self, q > r),
            84 => jump(self, q < r),
            85 => jump(self, q >= r),
            86 => jump(self, q <= r),
            99 => Err((
                1,
                format!(
                    "alarm {} raised by the program (G65 H99)",
                    500 + pv.round() as i64
                ),
            )),
            _ => Err((1, format!("G65 H{h:02} is not supported yet"))),
        }
    }

    /// FANUC G76, two-block form (`domain.md` section 3, `controllers.md` 2.3): block 1
    /// sets `P(mmrraa) Q(dmin) R(d)`; block 2 `X(U) Z(W) R(i) P(k) Q(dd) F(L)` cuts rough
    /// passes at `d_n = max(dd*sqrt(n), d_(n-1) + dmin)` until `k - d`, one at `k - d`, then
    /// `m` at `k`, each on single-flank infeed: shifted against the cutting direction by
    /// `(k - d_n) tan(a/2)` so the trailing flank follows the final groove's wall.
    /// Taper: `R(i)` of block 2 is the radius at the start minus the radius at the end (as
    /// G92's R); every pass starts 2i (diameter) off its end X, both ends shifted alike.
    /// Chamfer: `rr` of block 1 (0.1 L steps; it is FANUC's parameter 5130, so it also sets
    /// G92's) ends every pass in a 45 deg pull-out (`cycle_pass_chamfered`).
    pub(super) fn g76(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let is_second = ["X", "Z", "U", "W"].iter().any(|k| w.vals.contains_key(*k));
        if !is_second {
            if let Some(&(p, col)) = w.vals.get("P") {
                if w.points.iter().any(|k| k == "P") {
                    return Err((
                        col,
                        "G76 P (mmrraa: finishing passes, chamfer, tool angle) takes no decimal point".into(),
                    ));
                }
                let (m, r, a) = g76_p(p, col)?;
                self.thread.g76.m = m;
                self.thread.g76.r = r;
                // As on FANUC, rr is the chamfer parameter (5130) that G92 uses too.
                self.thread.chamfer = f64::from(r) / 10.0;
                self.thread.g76.a = f64::from(a);
            }
            if let Some(q) = self.increment_word(w, "Q", "G76")? {
                self.thread.g76.dmin = q;
            }
            // d, the finishing allowance: a length (FANUC's own example `R200` is 0.200 mm
            // in standard decimal-point input, `R0.2` 0.2 mm in either).
            if let Some(r) = self.length(w, "R") {
                self.thread.g76.d = r;
            }
            // GSK's run-out J/K given with the first block: modal, for the passes.
            if self.cfg.gsk && (w.vals.contains_key("J") || w.vals.contains_key("K")) {
                self.gsk_cycle_runout(w);
            }
            self.thread.g76.given = true;
            return Ok(Step::Next);
        }
        let (x0, z0) = (self.x, self.z);
        let (x_end, z_end) = self.cycle_end(w);
        // GSK's second block takes J/K (the run-out) beside P and Q: K there is no thread
        // height, and GSK has no one-block G76.
        let gsk_two_block = self.cfg.gsk && w.vals.contains_key("P") && w.vals.contains_key("Q");
        if !gsk_two_block && (w.vals.contains_key("K") || w.vals.contains_key("D")) {
            return self.g76_one_block(w, prog, pc, (x0, z0), (x_end, z_end));
        }
        // i: taper, radius at the start minus radius at the end (as G92's R).
        let taper = self.length(w, "R").unwrap_or(0.0);
        let k = self
            .increment_word(w, "P", "G76")?
            .ok_or((1, "G76 needs P (thread height)".to_string()))?;
        let dd = self
            .increment_word(w, "Q", "G76")?
            .ok_or((1, "G76 needs Q (first cut depth)".to_string()))?;
        let lead = self
            .lead_word(w, "F", "G76")?
            .ok_or((1, "G76 needs F (the lead)".to_string()))?;
        if k <= 0.0 || dd <= 0.0 || lead <= 0.0 || z_end == z0 {
            return Err((
                1,
                "G76 needs a positive height, first cut, lead and a Z move".into(),
            ));
        }
        self.check_thread_height(w, "P", k, x_end);
        let s = self.thread.g76;
        if !s.given {
            self.g76_defaults_note(lead);
        }
        let chamfer = self.thread_pullout(lead, z_end - z0, w)?;
        let stop = (k - s.d).max(0.0);
        let mut depths = Vec::new();
        let mut prev = 0.0;
        for n in 1..=100_000 {
            let dn = (dd * (n as f64).sqrt()).max(prev + s.dmin);
            if dn >= stop {
                break;
            }
            depths.push(dn);
            prev = dn;
        }
        if depths.len() >= 100_000 {
            return Err((1, "G76 would cut more than 100000 rough passes".into()));
        }
        if stop > 0.0 && depths.last().is_none_or(|&l| l < stop) {
            depths.push(stop);
        }
        for _ in 0..s.m {
            depths.push(k);
        }
        if s.m == 0 && s.d > 0.0 {
            self.out.notes.push((
                1,
                format!("G76 with 00 finishing passes (P00rraa) and a finishing allowance R ({} mm): the last pass stops that much short of the thread height", s.d),
                "the finishing passes mm of P(mmrraa) cut the full height k; with 00 only the roughing runs, to k - d".into(),
            ));
        }
        // The root diameter is X; passes stand back from it by (k - d_n), on the side
        // of the start point (outside for external threads, inside for internal).
        let side = if x0 >= x_end { 1.0 } else { -1.0 };
        let dir = if z_end < z0 { -1.0 } else { 1.0 };
        let tan = (s.a.to_radians() / 2.0).tan();
        for dn in depths {
            let back = k - dn;
            let x = x_end + side * 2.0 * back;
            let shift = -dir * back * tan;
            let (zs, ze) = (z0 + shift, z_end + shift);
            let sync = Sync {
                lead,
                change: 0.0,
                angle: 0.0,
            };
            self.cycle_pass_chamfered(
                prog,
                pc,
                (x0, z0),
                (x + 2.0 * taper, zs),
                (x, ze),
                sync,
                chamfer,
            );
        }
        Ok(Step::Next)
    }

    /// The warning of a two-block G76 run without its first block: the control cuts with
    /// its parameters' values, which the program does not show; it says which.
    fn g76_defaults_note(&mut self, lead: f64) {
        let s = self.thread.g76;
        let (numbers, keys) = if self.cfg.gsk {
            ("the control's G76 parameters", "")
        } else {
            (
                "FANUC parameters No. 5142, 5143, 5140, 5141 and 5130",
                " ([machine] g76_finish_passes, g76_tool_angle, g76_min_cut, g76_finish_allowance; [program] thread_chamfer)",
            )
        };
        self.out.notes.push((
            1,
            format!(
                "G76 without its first block (P(m r a) Q(dmin) R(d)): the cycle runs on the machine's parameters: {} finishing pass{}, tool angle {} deg, minimum cut {} mm, finishing allowance {} mm, chamfer {} leads ({:.3} mm)",
                s.m,
                if s.m == 1 { "" } else { "es" },
                s.a,
                s.dmin,
                s.d,
                self.thread.chamfer,
                self.thread.chamfer * lead
            ),
            format!(
                "these are {numbers}{keys} as the job gives them; write the first block to cut what the program says"
            ),
        ));
    }

    /// The one-block G76 of Haas lathes and FANUC 0T-style controls (`docs/job-format.md`,
    /// "One-block G76"; Haas lathe operator's manual, G76 "Threading cycle, multiple pass";
    /// FANUC 0-TC operator's manual, G76 of the old format):
    /// `G76 X(U) Z(W) K(height) D(first depth) F(lead) [I(taper)] [A(tool angle)] [P(method)]`.
    /// K and D with a decimal point are in program units, without one in the least input
    /// increment (as 0T writes them). Pass n reaches the depth `D sqrt(n)` (P1, P2: constant
    /// cutting amount) or `n D` (P3, P4: constant depth) below the crest while less than K,
    /// then K once. P1/P3 feed in along one flank (each pass shifted by `(K - d_n)
    /// tan(A/2)` as the two-block G76), P2/P4 alternate the flanks. A defaults to 0 (radial
    /// infeed, as on Haas); I is the radius at the start minus the radius at the end (as
    /// G92's R). Each pass is a G92-style pass (rapid in, thread, rapid out and back), with
    /// the thread chamfer of `Settings::thread_chamfer` / M23.
    fn g76_one_block(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        (x0, z0): (f64, f64),
        (x_end, z_end): (f64, f64),
    ) -> Result<Step, Fail> {
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let col = |k: &str| w.vals.get(k).map_or(1, |v| v.1);
        // A decimal point: program units; none: the least input increment.
        let k = self.increment_or_units(w, "K").ok_or((
            1,
            "the one-block G76 (with D) needs K (the thread height)".to_string(),
        ))?;
        let d = self.increment_or_units(w, "D").ok_or((
            1,
            "the one-block G76 (with K) needs D (the first cut depth)".to_string(),
        ))?;
        let lead = self
            .lead_word(w, "F", "G76")?
            .ok_or((1, "G76 needs F (the lead)".to_string()))?;
        if k <= 0.0 || d <= 0.0 || lead <= 0.0 || z_end == z0 {
            return Err((1, "G76 needs K > 0, D > 0, F > 0 and a Z move".into()));
        }
        self.check_thread_height(w, "K", k, x_end);
        // Q: the start angle (Haas G76 "Q - Thread Start Angle (Do not use a decimal
        // point)"), as G92's.
        let angle = self.start_angle(w, "G76")?;
        let a = val("A").unwrap_or(0.0);
        if !(0.0..=120.0).contains(&a) {
            return Err((
                col("A"),
                format!("G76 A{a}: the tool angle must be 0..120 degrees"),
            ));
        }
        let method = val("P").unwrap_or(1.0);
        if ![1.0, 2.0, 3.0, 4.0].contains(&method) {
            return Err((
                col("P"),
                format!("G76 P{method}: the one-block cutting method is P1, P2, P3 or P4"),
            ));
        }
        let taper = self.length(w, "I").unwrap_or(0.0);
        let chamfer = self.thread_chamfer(lead, z_end - z0, w)?;
        let mut depths = Vec::new();
        for n in 1..=100_001u32 {
            let dn = if method <= 2.0 {
                d * f64::from(n).sqrt()
            } else {
                d * f64::from(n)
            };
            if dn >= k {
                break;
            }
            depths.push(dn);
        }
        if depths.len() > 100_000 {
            return Err((1, "G76 would cut more than 100000 rough passes".into()));
        }
        depths.push(k);
        let side = if x0 >= x_end { 1.0 } else { -1.0 };
        let dir = if z_end < z0 { -1.0 } else { 1.0 };
        let tan = (a.to_radians() / 2.0).tan();
        let alternate = method == 2.0 || method == 4.0;
        for (n, dn) in depths.into_iter().enumerate() {
            let back = k - dn;
            let x = x_end + side * 2.0 * back;
            let flank = if alternate && n % 2 == 1 { -1.0 } else { 1.0 };
            let shift = -dir * back * tan * flank;
            let sync = Sync {
                lead,
                change: 0.0,
                angle,
            };
            self.cycle_pass_chamfered(
                prog,
                pc,
                (x0, z0),
                (x + 2.0 * taper, z0 + shift),
                (x, z_end + shift),
                sync,
                (chamfer, chamfer),
            );
        }
        Ok(Step::Next)
    }

    /// GSK 980TDC `G34 X(U) Z(W) F(I) J K R` (`domain.md` section 3, seed 000): F start
    /// lead (or I threads per inch), R lead change per revolution, J/K the thread run-out
    /// (`Interp::thread_block`, `chain.rs`).
    pub(super) fn gsk_g34(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        x: f64,
        z: f64,
    ) -> Result<Step, Fail> {
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let lead = match (self.lead_word(w, "F", "G34")?, val("I")) {
            (Some(f), _) => f,
            (None, Some(tpi)) if tpi > 0.0 => 25.4 / tpi,
            _ => return Err((1, "G34 needs F (lead) or I (threads per inch)".into())),
        };
        let change = self.lead_word(w, "R", "G34")?.unwrap_or(0.0);
        let sync = Sync {
            lead,
            change,
            angle: 0.0,
        };
        self.thread_block(w, prog, pc, (x, z), sync)?;
        Ok(Step::Next)
    }

    /// FANUC G92 (modal, `controllers.md` 2.2): rapid to the X of the block (plus 2R: R is
    /// the taper, radius at the start minus radius at the end), thread to X at its Z,
    /// rapid back out in X and back in Z to the start point. Z(W), F and R are modal, so
    /// later X-only blocks repeat it at a new depth. With chamfering on (M23, the default)
    /// and a chamfer length set (`Settings::thread_chamfer`, or G76's `rr`), the thread
    /// ends in a 45 deg pull-out over the last `chamfer x F` of Z (`cycle_pass_chamfered`).
    pub(super) fn g92(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        x: f64,
        z: f64,
    ) -> Result<Step, Fail> {
        let (x0, z0) = (self.x, self.z);

        let z_target = if w.vals.contains_key("Z") || w.vals.contains_key("W") {
            z
        } else {
            self.thread
                .g92
                .map(|g| g.0)
                .ok_or((1, "G92 needs Z (or W) the first time".to_string()))?
        };
        let lead = match self.lead_word(w, "F", "G92")? {
            Some(f) => f,
            None => self
                .thread
                .g92
                .map(|g| g.1)
                .ok_or((1, "G92 needs F (the lead)".to_string()))?,
        };
        let taper = match self.length(w, "R") {
            Some(r) => r,
            None => self.thread.g92.map_or(0.0, |g| g.2),
        };
        let chamfer = self.thread_pullout(lead, z_target - z0, w)?;
        self.thread.g92 = Some((z_target, lead, taper));
        let q = self.start_angle(w, "G92")?;
        let sync = Sync {
            lead,
            change: 0.0,
            angle: q,
        };
        self.cycle_pass_chamfered(
            prog,
            pc,
            (x0, z0),
            (x + 2.0 * taper, z0),
            (x, z_target),
            sync,
            chamfer,
        );
        Ok(Step::Next)
    }

    /// FANUC/GSK `G90 X(U) Z(W) R F` (outer or inner diameter cutting) and `G94 X(U) Z(W) R F`
    /// (end face cutting), modal like G92: a later block with only X (G90) or only Z (G94)
    /// repeats the cycle at a new depth. G90: rapid to X (+2R at the start Z for a taper),
    /// feed to the end point, feed out to the start X, rapid back to the start Z. G94: rapid to
    /// Z (+R at the start X), feed to the end point, feed back to the start Z, rapid to the
    /// start X. They cut no thread; vpcut records their moves so that the tool's position
    /// after them is right (the blank is taken as the job gives it).
    pub(super) fn cutting_cycle(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        x: f64,
        z: f64,
    ) -> Result<Step, Fail> {
        let (x0, z0) = (self.x, self.z);
        let g = self.modal.motion;
        let face = g == 94;
        let given = |k: &[&str]| k.iter().any(|k| w.vals.contains_key(*k));
        // The modal target of the other axis and the taper.
        let (other, taper) = self
            .thread
            .cycle90
            .filter(|c| c.0 == g)
            .map_or((None, 0.0), |c| (Some(c.1), c.2));
        let (x_end, z_end) = if face {
            let x_end = if given(&["X", "U"]) {
                x
            } else {
                other.ok_or((1, "G94 needs X (or U) the first time".to_string()))?
            };
            (x_end, z)
        } else {
            let z_end = if given(&["Z", "W"]) {
                z
            } else {
                other.ok_or((1, "G90 needs Z (or W) the first time".to_string()))?
            };
            (x, z_end)
        };
        let r = self.length(w, "R").unwrap_or(taper);
        if r != 0.0 {
            // Its moves run with the nose vector held (`nose`): a taper is where FANUC's
            // compensation would move them.
            self.nose_note(&format!("G{g} with a taper (R)"));
        }
        self.thread.cycle90 = Some((g, if face { x_end } else { z_end }, r));
        use MoveKind::{Feed, Rapid};
        let path: [(MoveKind, (f64, f64)); 4] = if face {
            [
                (Rapid, (x0, z_end + r)),
                (Feed, (x_end, z_end)),
                (Feed, (x_end, z0)),
                (Rapid, (x0, z0)),
            ]
        } else {
            [
                (Rapid, (x_end + 2.0 * r, z0)),
                (Feed, (x_end, z_end)),
                (Feed, (x0, z_end)),
                (Rapid, (x0, z0)),
            ]
        };
        let mut at = (x0, z0);
        for (kind, to) in path {
            if to != at {
                self.emit(prog, pc, kind, at, to, None);
                at = to;
            }
        }
        Ok(Step::Next)
    }

    /// The chamfer (pull-out) length in mm of a threading cycle with lead `lead` over the
    /// Z travel `travel`: 0 when chamfering is off (M24) or no length is set; an error when
    /// it would not be shorter than the thread.
    /// A threading cycle's pull-out `(length along Z, radial rise)`: GSK's run-out J/K where
    /// the block or an earlier cycle block gave one (980TDi manual, G92 and G76: "J: the
    /// movement in the short axis in thread run-out ... K: the length in the long axis";
    /// K omitted or 0 with J != 0: K = J; J0 cancels; the rise goes the way the tool
    /// retracts, towards the start point; modal until programmed again), else the thread
    /// chamfer (`thread_chamfer`: 45 deg, `rise = length`).
    fn thread_pullout(&mut self, lead: f64, travel: f64, w: &Words) -> Result<(f64, f64), Fail> {
        if self.cfg.gsk {
            self.gsk_cycle_runout(w);
            if let Some((k, j)) = self.thread.cycle_runout {
                if j == 0.0 {
                    return Ok((0.0, 0.0));
                }
                if k >= travel.abs() {
                    let col = w.vals.get("K").or(w.vals.get("J")).map_or(1, |v| v.1);
                    return Err((
                        col,
                        format!("thread run-out K = {k} mm is not shorter than the thread's Z travel {}", travel.abs()),
                    ));
                }
                return Ok((k, j));
            }
        }
        let c = self.thread_chamfer(lead, travel, w)?;
        Ok((c, c))
    }

    /// GSK G92/G76 J/K words into the modal run-out `(K, |J|)` (`thread_pullout`).
    fn gsk_cycle_runout(&mut self, w: &Words) {
        let j = self.length(w, "J");
        let k = self.length(w, "K");
        if j.is_some() || k.is_some() {
            let j = j
                .or(self.thread.cycle_runout.map(|r| r.1))
                .unwrap_or(0.0)
                .abs();
            let k = k.map(f64::abs).filter(|&k| k != 0.0).unwrap_or(j);
            self.thread.cycle_runout = Some((k, j));
        }
    }

    fn thread_chamfer(&self, lead: f64, travel: f64, w: &Words) -> Result<f64, Fail> {
        if !self.thread.chamfer_on || self.thread.chamfer <= 0.0 {
            return Ok(0.0);
        }
        let len = self.thread.chamfer * lead;
        if len >= travel.abs() {
            let col = ["Z", "W"]
                .iter()
                .find_map(|k| w.vals.get(*k))
                .map_or(1, |v| v.1);
            return Err((
                col,
                format!(
                    "the thread chamfer ({len} mm = {} leads) is not shorter than the thread's Z travel {}",
                    self.thread.chamfer,
                    travel.abs()
                ),
            ));
        }
        Ok(len)
    }
}

impl Interp<'_> {
    /// FANUC lathe rigid tapping (FANUC 0i-TF/30i lathe manuals, "Canned cycle for drilling"
    /// and "Rigid tapping"): `M29 S..` selects rigid mode (the spindle is position-controlled
    /// and the Z feed follows it); `G84 X(U) Z(W) R P F K` taps on the face. Modal until G80
    /// (or a group-01 G code). Per hole: positioning in X at the initial level (rapid), a
    /// rapid to the R point (`R`: from the initial level, signed, incremental), the tap in to
    /// the bottom (Z absolute, W from the R point) synchronised at the pitch (G99: F is the
    /// pitch; G98: F is the feed per minute, pitch F / S), a dwell P, the spindle reverses,
    /// the tap comes back to the R point in the same groove, the spindle is restored; then a
    /// rapid to the initial level (system A; systems B/C: G98, or stays at the R point with
    /// G99). `K` repeats it at the same place. Without M29 (a floating holder: the spindle
    /// not synchronised) G84 is refused, and so is a hole off the spindle axis (live
    /// tooling). `None` when the block is no tapping block.
    pub(super) fn tap_modes(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
    ) -> Result<Option<Step>, Fail> {
        // GSK taps with its G33 cycle (`motion::gsk_tap`).
        if self.cfg.gsk {
            return Ok(None);
        }
        if w.m.contains(&29) {
            self.thread.tap.rigid = true;
        }
        let g84 = w.g.contains(&84);
        if w.g.contains(&80) || w.g.iter().any(|&g| matches!(g, 0..=3 | 32 | 34)) {
            if self.thread.tap.initial.take().is_some() && !g84 {
                self.modal.motion = self.thread.tap.before;
            }
            self.thread.tap.rigid = false;
        }
        if g84 {
            if !self.thread.tap.rigid {
                return Err((
                    1,
                    "G84 without M29 (tapping with a floating holder: the spindle is not synchronised) is not simulated: program `M29 S..` before G84".into(),
                ));
            }
            if self.thread.tap.initial.is_none() {
                self.thread.tap.before = self.modal.motion;
                self.thread.tap.initial = Some(self.z);
                self.thread.tap.r = None;
                self.thread.tap.bottom = None;
            }
        }
        let Some(initial) = self.thread.tap.initial else {
            return Ok(None);
        };
        let mut end = false;
        if let Some(step) = self.m_words(w, &mut end)? {
            return Ok(Some(step));
        }
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let moved = ["X", "Z", "U", "W", "R"]
            .iter()
            .any(|k| w.vals.contains_key(*k));
        if !moved {
            return Ok(Some(if end { Step::End } else { Step::Next }));
        }
        if let Some(s) = val("S") {
            self.modal.speed = Some(s);
        }
        if let Some(f) = val("F") {
            self.modal.feed = Some(f);
            self.modal.feed_plain = w.plain.iter().any(|p| p == "F");
        }
        let oz = self.frames.offsets[self.frames.work].1;
        let ox = self.frames.offsets[self.frames.work].0;
        let x = match (self.x_length(w, "X"), self.x_length(w, "U")) {
            (Some(v), _) => v + ox,
            (None, Some(u)) => self.x + u,
            (None, None) => self.x,
        };
        if x.abs() > 1e-9 {
            return Err((
                1,
                "G84 off the spindle axis (X not 0) taps with a driven tool (live tooling, C axis): not modelled".into(),
            ));
        }
        if let Some(r) = self.length(w, "R") {
            self.thread.tap.r = Some(r);
        }
        let r_point = initial
            + self.thread.tap.r.ok_or((
                1,
                "G84 needs R (the R point, from the initial level)".to_string(),
            ))?;
        let bottom = match (self.length(w, "Z"), self.length(w, "W")) {
            (Some(z), _) => z + oz,
            (None, Some(wv)) => r_point + wv,
            (None, None) => self
                .thread
                .tap
                .bottom
                .ok_or((1, "G84 needs Z or W (the hole bottom)".to_string()))?,
        };
        self.thread.tap.bottom = Some(bottom);
        if bottom == r_point {
            return Err((1, "G84: the hole bottom is at the R point".into()));
        }
        let feed = self.modal.feed.filter(|f| *f > 0.0).ok_or((
            1,
            "G84 needs F > 0 (the pitch in G99, the feed in G98)".to_string(),
        ))?;
        if self.modal.feed_plain {
            // The pitch (G99) or the feed (G98) written without a decimal point, in this
            // block or before it: refused in standard input as every lead is.
            let col = w.vals.get("F").map_or(1, |v| v.1);
            self.plain_lead(feed, col, "G84", "F")?;
        }
        let scale = self.unit();
        let lead = if self.modal.per_rev {
            feed * scale
        } else {
            let s = self.modal.speed.filter(|s| *s > 0.0).ok_or((
                1,
                "G84 in G98 (feed per minute) needs S > 0: the pitch is F / S".to_string(),
            ))?;
            feed / s * scale
        };
        let times = match w.vals.get("K") {
            Some(&(k, col)) if k < 0.0 || k.fract() != 0.0 || k > 9999.0 => {
                return Err((col, format!("G84 K{k}: expected a repeat count 0..9999")))
            }
            Some(&(k, _)) => k as u32,
            None => 1,
        };
        let ret = if self.thread.tap.to_r {
            r_point
        } else {
            initial
        };
        if (x, self.z) != (self.x, self.z) {
            self.emit(
                prog,
                pc,
                MoveKind::Rapid,
                (self.x, self.z),
                (x, self.z),
                None,
            );
        }
        self.x = x;
        for _ in 0..times {
            self.tap_on_axis(prog, pc, x, (self.z, r_point, bottom, ret), lead);
        }
        Ok(Some(if end { Step::End } else { Step::Next }))
    }
}

#[cfg(test)]
pub(super) mod tap_tests {
    //! G84/M29 beyond the reviewed programs of `tests/data/nc/fanuc/tap-*`: every expected
    //! number derived by hand in the comments.
    use super::super::{
        interpret_with, Dialect, GcodeSystem, Move, MoveKind, NcError, Options, Settings, Source,
    };

    /// Run `text` on the FANUC lathe in G-code system `system` (also `mrc_tests`'s runner).
    pub(in crate::nc) fn run(text: &str, system: GcodeSystem) -> Result<Vec<Move>, NcError> {
        let src = Source {
            name: "T.NC".into(),
            text: text.into(),
        };
        let opts = Options {
            settings: Settings {
                gcode_system: system,
                ..Settings::in_mm()
            },
            ..Options::default()
        };
        interpret_with(&src, Dialect::Fanuc, &|_| None, &opts).map(|t| t.moves)
    }

    fn path(m: &[Move]) -> Vec<(MoveKind, f64, f64)> {
        m.iter().map(|m| (m.kind, m.z_start, m.z)).collect()
    }

    /// System B: G99 returns to the R point (Z3 = 10 - 7), G98 to the initial level; K2
    /// taps twice at the same place; K0 only positions.
    #[test]
    fn return_levels_and_repeats() {
        use MoveKind::{Rapid, Thread};
        let b = "G0 X0 Z10\nM3 S300\nM29 S300\nG99 G84 Z-20 R-7 F1.5\nG80\n";
        // In system B G95 is feed per revolution; F1.5 the pitch.
        let m = run(&format!("G95\n{b}"), GcodeSystem::B).unwrap();
        assert_eq!(
            path(&m[1..]),
            [
                (Rapid, 10.0, 3.0),
                (Thread, 3.0, -20.0),
                (Thread, -20.0, 3.0)
            ]
        );
        let m = run(
            "G99\nG0 X0 Z10\nM3 S300\nM29 S300\nG84 Z-20 R-7 F1.5 K2\nG80\n",
            GcodeSystem::A,
        )
        .unwrap();
        assert_eq!(m.iter().filter(|m| m.kind == Thread).count(), 4);
        assert_eq!(
            (m.last().unwrap().z_start, m.last().unwrap().z),
            (3.0, 10.0)
        );
        let m = run(
            "G99\nG0 X0 Z10\nM3 S300\nM29 S300\nG84 Z-20 R-7 F1.5 K0\nG80\nG0 Z40\n",
            GcodeSystem::A,
        )
        .unwrap();
        assert_eq!(path(&m[1..]), [(Rapid, 10.0, 40.0)]);
    }

    /// G80 restores the motion before G84 (G01 here: `Z5` feeds); off the axis, without R,
    /// without F, and G98 without S are refused at their blocks.
    #[test]
    fn cancel_and_refusals() {
        let m = run(
            "G99\nG1 X0 Z10 F0.2\nM3 S300\nM29 S300\nG84 Z-20 R-7 F1.5\nG80\nZ5\n",
            GcodeSystem::A,
        )
        .unwrap();
        assert_eq!(m.last().unwrap().kind, MoveKind::Feed);
        for (text, line, want) in [
            (
                "G0 X20 Z10\nM29 S300\nG84 Z-20 R-7 F1.5\n",
                3,
                "off the spindle axis",
            ),
            ("G0 X0 Z10\nM29 S300\nG84 Z-20 F1.5\n", 3, "needs R"),
            ("G0 X0 Z10\nM29 S300\nG84 R-2 F1.5\n", 3, "needs Z or W"),
            ("G0 X0 Z10\nM29 S300\nG84 Z-20 R-7\n", 3, "needs F"),
            ("G98\nG0 X0 Z10\nM29\nG84 Z-20 R-7 F300\n", 4, "needs S"),
            (
                "G0 X0 Z10\nM29 S300\nG84 Z-20 R-7 F1.5 K-1\n",
                3,
                "repeat count",
            ),
        ] {
            let e = run(text, GcodeSystem::A).unwrap_err();
            assert_eq!(e.line, line, "{text}: {e}");
            assert!(e.message.contains(want), "{text}: {e}");
        }
    }

    /// GSK G33 (Z tapping): off the axis, with an X move, or without a positive F or I it
    /// is refused.
    #[test]
    fn gsk_tap_refusals() {
        for (text, want) in [
            ("G0 X20 Z5\nG33 Z-10 F1\n", "off the spindle axis"),
            ("G0 X0 Z5\nG33 X4 Z-10 F1\n", "off the spindle axis"),
            ("G0 X0 Z5\nG33 Z-10\n", "needs F"),
            ("G0 X0 Z5\nG33 Z-10 F0\n", "must be positive"),
            ("G0 X0 Z5\nG33 Z-10 I-2\n", "must be positive"),
        ] {
            let src = Source {
                name: "T.NC".into(),
                text: text.into(),
            };
            let e = interpret_with(
                &src,
                Dialect::Gsk980,
                &|_| None,
                &Options {
                    settings: Settings::in_mm(),
                    ..Options::default()
                },
            )
            .unwrap_err();
            assert_eq!(e.line, 2, "{text}: {e}");
            assert!(e.message.contains(want), "{text}: {e}");
        }
    }
}
