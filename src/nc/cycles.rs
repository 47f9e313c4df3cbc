//! FANUC/GSK multiple repetitive cycles (lathe): G70 finishing, G71 stock removal in
//! turning, G72 in facing, G73 pattern repeating, G74 end face peck drilling, G75 outer/
//! inner diameter grooving (system-A numbers; B and C are read as A). Both the two-block
//! form of FANUC 0i and GSK 980TDC (`G71 U(dd) R(e)` / `G71 P Q U W F`) and the one-block
//! form of FANUC 0T and Haas (`G71 P Q U W D F`). The finishing shape (blocks `P`..`Q`) is
//! read by running its blocks on a copy of the modal state (so arcs, macro variables and
//! U/W work as anywhere), and the cycle's moves are made from it as ordinary rapid, feed
//! and arc moves of the cycle's block (`docs/job-format.md`, "Multiple repetitive cycles",
//! says which move the control makes where).

use super::expr::Fail;
use super::troughs;
use super::{Interp, Move, MoveKind, Program, Step, Words};

/// The modal data the cycles' first blocks set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct CycleSetup {
    /// G71/G72 depth of cut dd (mm; a radius for G71): `G71 U(dd)`, `G72 W(dd)`.
    pub(super) depth: Option<f64>,
    /// G71/G72 retract e (mm, at 45 deg): `G71 R(e)`.
    pub(super) retract: Option<f64>,
    /// G73: relief in X (radius, mm), in Z (mm), and the number of divisions:
    /// `G73 U(di) W(dk) R(d)`.
    pub(super) g73: Option<(f64, f64, u32)>,
    /// G74/G75 return amount e after each peck (mm): `G74 R(e)`, `G75 R(e)`.
    pub(super) peck_return: Option<f64>,
    /// Reading a finishing shape: a cycle inside it is an error.
    pub(super) in_shape: bool,
}

/// The retract of the one-block G71/G72 when no two-block first block set one (FANUC 0T
/// parameter 0717, Haas setting 73: machine data vpcut does not have), mm.
pub(super) const DEFAULT_RETRACT: f64 = 0.5;

/// At most this many passes a roughing cycle may cut (a limit, not a hang).
const MAX_PASSES: usize = 100_000;

/// A point in the cycle's frame: `a` the axis the depth steps along (radius for G71, z for
/// G72), `b` the axis the passes run along.
type Ab = (f64, f64);

/// One move of the finishing shape, in the cycle's frame, and the move it came from.
#[derive(Clone, Debug)]
pub(super) struct Seg {
    p: Ab,
    q: Ab,
    /// An arc's centre and radius in the cycle's frame.
    arc: Option<(Ab, f64)>,
    pub(super) mv: Move,
}

/// The cycle's frame: G71 steps in radius and cuts along Z; G72 the other way round.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    pub(super) facing: bool,
}

impl Frame {
    pub(super) fn ab(self, (x, z): (f64, f64)) -> Ab {
        if self.facing {
            (z, x / 2.0)
        } else {
            (x / 2.0, z)
        }
    }
    pub(super) fn xz(self, (a, b): Ab) -> (f64, f64) {
        if self.facing {
            (2.0 * b, a)
        } else {
            (2.0 * a, b)
        }
    }
}

fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Whether the arc of `mv` (in the Z-right, X-up plane) passes an extreme of X or Z strictly
/// inside: then it is not monotonic in both axes.
fn arc_turns(mv: &Move) -> bool {
    let Some(g) = mv.arc else { return false };
    let c = (g.z_centre, g.x_centre_dia / 2.0);
    let ang = |z: f64, r: f64| (r - c.1).atan2(z - c.0);
    let (t0, t1) = (ang(mv.z_start, mv.x_start / 2.0), ang(mv.z, mv.x_dia / 2.0));
    let tau = std::f64::consts::TAU;
    // The sweep from t0, positive counter-clockwise.
    let sweep = if g.clockwise {
        -(t0 - t1).rem_euclid(tau)
    } else {
        (t1 - t0).rem_euclid(tau)
    };
    if sweep == 0.0 {
        return true;
    }
    (0..8).any(|k| {
        let axis = f64::from(k - 4) * std::f64::consts::FRAC_PI_2;
        // Where the axis direction lies along the sweep (same sense), strictly inside.
        let off = if sweep > 0.0 {
            (axis - t0).rem_euclid(tau)
        } else {
            -(t0 - axis).rem_euclid(tau)
        };
        off.abs() > 1e-9 && off.abs() < sweep.abs() - 1e-9
    })
}

impl Interp<'_> {
    /// A block with G70..G75 (system-A numbers).
    pub(super) fn repetitive_cycle(
        &mut self,
        g: u32,
        w: &Words,
        prog: &Program,
        pc: usize,
    ) -> Result<Step, Fail> {
        if self.thread.cycles.in_shape {
            return Err((
                1,
                format!("G{g} inside the finishing shape of another cycle (P..Q)"),
            ));
        }
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        if let Some(f) = val("F") {
            self.modal.feed = Some(f);
            self.modal.feed_plain = w.plain.iter().any(|p| p == "F");
        }
        if let Some(s) = val("S") {
            self.modal.speed = Some(s);
        }
        for k in ["A", "E", "H", "J", "L"] {
            if let Some(&(_, col)) = w.vals.get(k) {
                return Err((col, format!("G{g} does not read `{k}`")));
            }
        }
        match g {
            70 => self.g70(w, prog, pc),
            71 | 72 => {
                let has_pq = w.vals.contains_key("P") || w.vals.contains_key("Q");
                if !has_pq {
                    // First block: G71 U(dd) R(e) / G72 W(dd) R(e).
                    // Depth of cut dd (G71: a radius) and retract e: lengths.
                    let depth_word = if g == 71 { "U" } else { "W" };
                    if let Some(d) = self.length(w, depth_word) {
                        self.thread.cycles.depth = Some(d);
                    }
                    if let Some(e) = self.length(w, "R") {
                        self.thread.cycles.retract = Some(e);
                    }
                    if w.vals.contains_key("D") {
                        return Err((
                            w.vals["D"].1,
                            format!("G{g} with D (the one-block form) needs P and Q"),
                        ));
                    }
                    return Ok(Step::Next);
                }
                for k in ["I", "K"] {
                    if let Some(&(_, col)) = w.vals.get(k) {
                        return Err((
                            col,
                            format!("G{g} {k}: the Haas rough-pass allowance (I/K) is not simulated by vpcut"),
                        ));
                    }
                }
                // Haas `R1` in the P/Q block asks for type II (Haas lathe manual, G71 "R1 Type
                // II roughing"); FANUC takes type II from block P naming both X and Z.
                let haas_type_ii = match w.vals.get("R") {
                    None => false,
                    Some(&(1.0, _)) => true,
                    Some(&(r, col)) => {
                        return Err((
                            col,
                            format!(
                                "G{g} R{r} in the P/Q block: Haas reads R1 (type II roughing) only"
                            ),
                        ))
                    }
                };
                let depth = match self.increment_or_units(w, "D") {
                    Some(d) => d,
                    None => self.thread.cycles.depth.ok_or((
                        1,
                        format!("G{g} P Q needs the depth of cut: a first block `G{g} {}(depth) R(retract)` before it, or D (one-block form)", if g == 71 { "U" } else { "W" }),
                    ))?,
                };
                let retract = self.thread.cycles.retract.unwrap_or(DEFAULT_RETRACT);
                let fine = depth > 0.0 && depth.is_finite() && retract >= 0.0;
                if !fine {
                    return Err((
                        1,
                        format!("G{g} needs a depth of cut > 0 and a retract >= 0"),
                    ));
                }
                // The finishing allowances: U in X (a diameter in diameter programming), W.
                let du = self.x_length(w, "U").unwrap_or(0.0);
                let dw = self.length(w, "W").unwrap_or(0.0);
                self.rough(
                    Frame { facing: g == 72 },
                    g,
                    w,
                    prog,
                    pc,
                    (depth, retract),
                    (du, dw),
                    haas_type_ii,
                )
            }
            73 => {
                let has_pq = w.vals.contains_key("P") || w.vals.contains_key("Q");
                if !has_pq {
                    // First block: G73 U(di) W(dk) R(d).
                    // The relief di (a radius) and dk: lengths.
                    let mut s = self.thread.cycles.g73.unwrap_or((0.0, 0.0, 1));
                    if let Some(u) = self.length(w, "U") {
                        s.0 = u;
                    }
                    if let Some(wv) = self.length(w, "W") {
                        s.1 = wv;
                    }
                    if let Some(&(r, col)) = w.vals.get("R") {
                        s.2 = count(r, col)?;
                    }
                    self.thread.cycles.g73 = Some(s);
                    return Ok(Step::Next);
                }
                // One-block (0T): G73 P Q I(di) K(dk) U W D(d) F.
                let mut s = self.thread.cycles.g73.unwrap_or((0.0, 0.0, 1));
                if let Some(i) = self.length(w, "I") {
                    s.0 = i;
                }
                if let Some(k) = self.length(w, "K") {
                    s.1 = k;
                }
                if let Some(&(d, col)) = w.vals.get("D") {
                    s.2 = count(d, col)?;
                }
                if let Some(&(r, col)) = w.vals.get("R") {
                    return Err((col, format!("G73 R{r} in the P/Q block: the number of divisions is the first block's R (or D in the one-block form)")));
                }
                let du = self.x_length(w, "U").unwrap_or(0.0);
                let dw = self.length(w, "W").unwrap_or(0.0);
                self.g73(w, prog, pc, s, (du, dw))
            }
            _ => self.peck(g, w, prog, pc),
        }
    }

    /// The blocks P..Q: their indices in `prog`.
    fn shape_range(&self, w: &Words, prog: &Program, g: u32) -> Result<(usize, usize), Fail> {
        let get = |k: &str| -> Result<usize, Fail> {
            let &(n, col) = w.vals.get(k).ok_or((
                1,
                format!("G{g} needs P and Q (the first and last block of the finishing shape)"),
            ))?;
            if n.fract() != 0.0 || !(0.0..=99_999.0).contains(&n) {
                return Err((col, format!("G{g} {k}{n}: expected a sequence number")));
            }
            prog.numbers
                .get(&(n as u32))
                .copied()
                .ok_or((col, format!("G{g} {k}{n}: no block N{n} in {}", prog.name)))
        };
        let (p, q) = (get("P")?, get("Q")?);
        if q < p {
            return Err((
                w.vals["Q"].1,
                format!("G{g}: the block Q comes before the block P"),
            ));
        }
        Ok((p, q))
    }

    /// The moves of the finishing shape P..Q from the current point, made on a copy of the
    /// state (nothing is recorded, the position and modes are put back), and how many of
    /// them the first block (`ns`) made.
    fn read_shape(
        &mut self,
        g: u32,
        prog: &Program,
        (p, q): (usize, usize),
    ) -> Result<(Vec<Move>, usize), Fail> {
        let saved = (self.x, self.z, self.modal.clone(), self.thread.chain_end);
        // The shape's moves carry the compensation they are programmed under.
        let hold = std::mem::replace(&mut self.out.nose_hold, false);
        let before = self.out.moves.len();
        let pending = self.out.pending.len();
        self.thread.cycles.in_shape = true;
        let mut first = 0;
        let mut result = Ok(());
        for k in p..=q {
            let (line, _, text) = &prog.blocks[k];
            let mut loops = Vec::new();
            match self.fanuc_block(prog, k, text, &mut loops) {
                Ok(Step::Next) => {}
                Ok(_) => {
                    result = Err((
                        1,
                        format!("G{g}: the finishing shape's block at line {line} jumps, calls or ends: a shape is straight blocks of G00/G01/G02/G03"),
                    ));
                    break;
                }
                Err((_, msg)) => {
                    result = Err((
                        1,
                        format!("G{g}: in the finishing shape's block at line {line}: {msg}"),
                    ));
                    break;
                }
            }
            if k == p {
                first = self.out.moves.len() - before;
            }
        }
        self.thread.cycles.in_shape = false;
        let moves: Vec<Move> = self.out.moves.drain(before..).collect();
        // Warnings of the shape's blocks are the cycle's (said once, at the cycle).
        for (_, m) in self.out.pending.iter_mut().skip(pending) {
            *m = format!("in the finishing shape of G{g}: {m}");
        }
        for m in self.out.pending.iter_mut().skip(pending) {
            m.0 = 1;
        }
        (self.x, self.z, self.modal, self.thread.chain_end) = saved;
        self.out.nose_hold = hold;
        result?;
        if let Some(m) = moves.iter().find(|m| m.kind == MoveKind::Thread) {
            return Err((
                1,
                format!(
                    "G{g}: the finishing shape has a thread move (line {}): not a turning shape",
                    m.line
                ),
            ));
        }
        if moves.is_empty() {
            return Err((1, format!("G{g}: the finishing shape P..Q makes no move")));
        }
        Ok((moves, first))
    }

    /// Record `mv` moved by `(dx, dz)` (diameter, z) as a move of the block at `pc`, from
    /// `from` when given (else its own shifted start).
    fn emit_shifted(
        &mut self,
        prog: &Program,
        pc: usize,
        mv: &Move,
        (dx, dz): (f64, f64),
        from: Option<(f64, f64)>,
    ) {
        let a = from.unwrap_or((mv.x_start + dx, mv.z_start + dz));
        let b = (mv.x_dia + dx, mv.z + dz);
        if a == b {
            return;
        }
        self.emit(prog, pc, mv.kind, a, b, None);
        if let (Some(g), Some(last)) = (mv.arc, self.out.moves.last_mut()) {
            let mut g = g;
            g.x_centre_dia += dx;
            g.z_centre += dz;
            last.arc = Some(g);
        }
    }

    /// A rapid from the current point to `to` in two moves: along `a` first when that goes
    /// away from the part (`first_a`), else along `b` first.
    fn rapid_back(&mut self, prog: &Program, pc: usize, f: Frame, to: (f64, f64), first_a: bool) {
        let (from, end) = (f.ab((self.x, self.z)), f.ab(to));
        let mid = if first_a {
            (end.0, from.1)
        } else {
            (from.0, end.1)
        };
        let mut at = (self.x, self.z);
        for p in [f.xz(mid), to] {
            if p != at {
                self.emit(prog, pc, MoveKind::Rapid, at, p, None);
                at = p;
            }
        }
        (self.x, self.z) = to;
    }

    /// After a cycle whose shape follows its block directly: go on after the shape.
    fn after_shape(pc: usize, (p, q): (usize, usize)) -> Step {
        if p == pc + 1 {
            Step::Jump(q + 1)
        } else {
            Step::Next
        }
    }

    /// G71/G72 type I: depth steps of `dd` from the start point towards the finishing shape
    /// moved by the allowance (U/2 in radius, W in z); each pass runs from the start's `b`
    /// to the shifted shape, retracts `e` at 45 deg (rapid), returns at rapid to the start's
    /// `b`; the next infeed is in the mode of block P (G00 or G01). Then one pass along the
    /// shifted shape and a rapid return to the start point.
    #[allow(clippy::too_many_arguments)]
    fn rough(
        &mut self,
        f: Frame,
        g: u32,
        w: &Words,
        prog: &Program,
        pc: usize,
        (dd, e): (f64, f64),
        (du, dw): (f64, f64),
        haas_type_ii: bool,
    ) -> Result<Step, Fail> {
        let range = self.shape_range(w, prog, g)?;
        let start = (self.x, self.z);
        let (moves, first) = self.read_shape(g, prog, range)?;
        let moves = self.nose_shape(g, moves)?;
        let (axis, other) = if f.facing { ("Z", "X") } else { ("X", "Z") };
        if first > 1 {
            return Err((
                1,
                format!("G{g}: block P must make one move (to the shape's start, along {axis})"),
            ));
        }
        let infeed = moves
            .first()
            .filter(|_| first == 1)
            .map_or(MoveKind::Rapid, |m| m.kind);
        // Type II (FANUC 0i: block P names both X and Z, `W0` where Z stays; Haas: R1). A
        // type II shape may have pockets; without one it is cut as type I (below).
        let named_both = prog.blocks[range.0].2.to_ascii_uppercase();
        let names = |c: &[char]| named_both.chars().any(|ch| c.contains(&ch));
        let type_ii = haas_type_ii || (names(&['X', 'U']) && names(&['Z', 'W']));
        if first == 1 && moves[0].kind == MoveKind::Arc {
            // FANUC alarm PS0065 (G00/G01 IS NOT IN THE FIRST BLOCK OF SHAPE PROGRAM).
            return Err((
                1,
                format!("G{g}: block P is an arc: the control alarms (FANUC PS0065, G00/G01 is not in the first block of shape program)"),
            ));
        }
        let segs: Vec<Seg> = moves[first..]
            .iter()
            .map(|m| {
                let mut mv = m.clone();
                mv.x_start += du;
                mv.x_dia += du;
                mv.z_start += dw;
                mv.z += dw;
                if let Some(a) = mv.arc.as_mut() {
                    a.x_centre_dia += du;
                    a.z_centre += dw;
                }
                let arc = mv.arc.map(|a| {
                    let c = f.ab((a.x_centre_dia, a.z_centre));
                    let p = f.ab((mv.x_start, mv.z_start));
                    (c, (p.0 - c.0).hypot(p.1 - c.1))
                });
                Seg {
                    p: f.ab((mv.x_start, mv.z_start)),
                    q: f.ab((mv.x_dia, mv.z)),
                    arc,
                    mv,
                }
            })
            .collect();
        let a_start = f.ab(start);
        let bottom = match (moves.first(), first) {
            (Some(m), 1) => f.ab((m.x_dia + du, m.z + dw)),
            _ => f.ab((start.0 + du, start.1 + dw)),
        };
        let s = sign(a_start.0 - bottom.0);
        if s == 0.0 {
            return Err((1, format!("G{g}: the start point is on the shape's start (moved by the allowance) in {axis}: no stock to remove")));
        }
        // The shape's direction along the passes: towards its point farthest from its start.
        let far = segs
            .iter()
            .map(|sg| sg.q.1)
            .max_by(|x, y| (x - bottom.1).abs().total_cmp(&(y - bottom.1).abs()))
            .unwrap_or(bottom.1);
        let end = (bottom.0, far);
        let dir = sign(far - bottom.1);
        if dir == 0.0 {
            return Err((
                1,
                format!("G{g}: the finishing shape does not move along {other}"),
            ));
        }
        // A move that goes back along the passes is no alarm when it runs wholly at or
        // beyond the first pass's level (a last block that retracts over the finished
        // shape, `N20 G00 G40 Z0.1`): no pass meets it, only the finishing pass runs it.
        let top = s * (a_start.0 - s * dd - bottom.0);
        let inside: Vec<&Seg> = segs
            .iter()
            .filter(|sg| {
                let h = |p: Ab| s * (p.0 - bottom.0);
                let above = h(sg.p) >= top - 1e-9 && h(sg.q) >= top - 1e-9;
                !(above && dir * (sg.q.1 - sg.p.1) < 0.0)
            })
            .collect();
        let mut trough = None;
        for sg in &inside {
            if dir * (sg.q.1 - sg.p.1) < -1e-9 {
                return Err((
                    1,
                    format!(
                        "G{g}: the finishing shape goes back along {other} at line {}: the control alarms (FANUC PS0064, the finishing shape is not a monotonous change); only moves above the first pass (none meets them) may go back",
                        sg.mv.line
                    ),
                ));
            }
            if trough.is_none() && (s * (sg.q.0 - sg.p.0) < -1e-9 || arc_turns(&sg.mv)) {
                trough = Some(sg.mv.line);
            }
        }
        if let Some(line) = trough {
            // Troughs (`troughs`): FANUC type II and Haas (both types) rough them; FANUC type
            // I alarms, so a shape without type II's mark is ambiguous: a warning.
            let (message, hint) = if type_ii {
                (
                    format!("G{g}: type II roughing of a shape with troughs (line {line} goes back in {axis}): the troughs are roughed after the material above them, level by level"),
                    "the material removed is the control's; the retract moves between passes are vpcut's (docs/job-format.md, \"Multiple repetitive cycles\")".to_string(),
                )
            } else {
                (
                    format!("G{g}: the finishing shape goes back in {axis} at line {line} (a trough) in type I roughing: roughed as a Haas does (troughs after the material above them); a FANUC 0i alarms here (PS0064)"),
                    "for a FANUC, write block P with both X and Z (type II, `W0` where Z stays), which roughs troughs".to_string(),
                )
            };
            self.out.notes.push((1, message, hint));
        } else if type_ii {
            self.out.notes.push((
                1,
                format!("G{g}: type II roughing (block P names both X and Z, or Haas R1) of a shape without pockets, cut as type I"),
                "each rough pass retracts at 45 deg instead of following the shape up to the pass above; the last pass along the shape is the same".into(),
            ));
        }
        let b0 = a_start.1;
        let mut at = start;
        let mut k = 1;
        loop {
            let level = a_start.0 - s * dd * k as f64;
            if s * (level - bottom.0) <= 1e-9 {
                break;
            }
            if k > MAX_PASSES {
                return Err((1, format!("G{g} would cut more than {MAX_PASSES} passes")));
            }
            let b_end = if trough.is_some() {
                // The first stretch below the level, from the shape's start.
                match troughs::stretches(f, &inside, s, level)
                    .first()
                    .filter(|t| t.2)
                {
                    Some(t) => t.1,
                    None => break,
                }
            } else {
                pass_end(&segs, s, level).unwrap_or(end.1)
            };
            step(self, (prog, pc, f), &mut at, infeed, (level, b0));
            step(self, (prog, pc, f), &mut at, MoveKind::Feed, (level, b_end));
            step(
                self,
                (prog, pc, f),
                &mut at,
                MoveKind::Rapid,
                (level + s * e, b_end - dir * e),
            );
            step(
                self,
                (prog, pc, f),
                &mut at,
                MoveKind::Rapid,
                (level + s * e, b0),
            );
            k += 1;
        }
        if trough.is_some() {
            self.rough_troughs(
                (prog, pc, f),
                &mut at,
                &inside,
                (s, dir),
                a_start.0,
                (dd, e),
                MAX_PASSES,
            )?;
            // Back to the start level before the last pass.
            let a = f.ab(at);
            if a.0 != a_start.0 {
                step(
                    self,
                    (prog, pc, f),
                    &mut at,
                    MoveKind::Rapid,
                    (a_start.0, a.1),
                );
            }
            step(
                self,
                (prog, pc, f),
                &mut at,
                MoveKind::Rapid,
                (a_start.0, b0),
            );
        }
        // The last pass along the shape moved by the allowance.
        step(self, (prog, pc, f), &mut at, infeed, bottom);
        self.x = at.0;
        self.z = at.1;
        for sg in &segs {
            self.emit_shifted(prog, pc, &sg.mv, (0.0, 0.0), None);
            (self.x, self.z) = (sg.mv.x_dia, sg.mv.z);
        }
        let last = f.ab((self.x, self.z));
        let first_a = s * (last.0 - a_start.0) < 0.0;
        self.rapid_back(prog, pc, f, start, first_a);
        Ok(Self::after_shape(pc, range))
    }

    /// G73: the shape cut `d` times, moved by `(di, dk) (d - k)/(d - 1)` plus the allowance
    /// on pass k; each pass from the start point to the moved shape in the mode of block P,
    /// along it, and back to the start at rapid.
    fn g73(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        (di, dk, d): (f64, f64, u32),
        (du, dw): (f64, f64),
    ) -> Result<Step, Fail> {
        let range = self.shape_range(w, prog, 73)?;
        let start = (self.x, self.z);
        let (moves, _) = self.read_shape(73, prog, range)?;
        let moves = self.nose_shape(73, moves)?;
        let f = Frame { facing: false };
        let s = sign(start.0 - moves[0].x_dia);
        for k in 1..=d {
            let t = if d == 1 {
                0.0
            } else {
                f64::from(d - k) / f64::from(d - 1)
            };
            let shift = (2.0 * di * t + du, dk * t + dw);
            for (n, mv) in moves.iter().enumerate() {
                let from = (n == 0).then_some(start);
                self.emit_shifted(prog, pc, mv, shift, from);
            }
            let last = moves.last().expect("not empty");
            (self.x, self.z) = (last.x_dia + shift.0, last.z + shift.1);
            let first_a = s == 0.0 || s * (self.x - start.0) < 0.0;
            self.rapid_back(prog, pc, f, start, first_a);
        }
        Ok(Self::after_shape(pc, range))
    }

    /// G70 P Q: the blocks P..Q run as written (their moves keep their own lines), then a
    /// rapid straight back to the start point.
    fn g70(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let (p, q) = self.shape_range(w, prog, 70)?;
        let start = (self.x, self.z);
        self.thread.cycles.in_shape = true;
        for k in p..=q {
            let (line, _, text) = &prog.blocks[k];
            let mut loops = Vec::new();
            let r = self.fanuc_block(prog, k, text, &mut loops);
            match r {
                Ok(Step::Next) => {}
                Ok(_) => {
                    self.thread.cycles.in_shape = false;
                    return Err((1, format!("G70: the finishing shape's block at line {line} jumps, calls or ends: a shape is straight blocks of G00/G01/G02/G03")));
                }
                Err((_, msg)) => {
                    self.thread.cycles.in_shape = false;
                    return Err((
                        1,
                        format!("G70: in the finishing shape's block at line {line}: {msg}"),
                    ));
                }
            }
        }
        self.thread.cycles.in_shape = false;
        if (self.x, self.z) != start {
            self.emit(prog, pc, MoveKind::Rapid, (self.x, self.z), start, None);
            (self.x, self.z) = start;
        }
        Ok(Step::Next)
    }

    /// G74 (end face peck drilling, pecks along Z, steps in X) and G75 (grooving, pecks
    /// along X, steps in Z): `G74 R(e)` / `G74 X(U) Z(W) P(di) Q(dk) F`. Each peck feeds
    /// `dk` (G74; G75: `di` in radius), returns `e` at rapid and feeds on from there; at the
    /// bottom a rapid back to the start's level, a rapid step of `di` (G74; G75: `dk`) to the
    /// next position, and at the end a rapid back to the start point.
    fn peck(&mut self, g: u32, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let target_given = ["X", "Z", "U", "W"].iter().any(|k| w.vals.contains_key(*k));
        if !target_given {
            // The return e after each peck: a length.
            if let Some(e) = self.length(w, "R") {
                self.thread.cycles.peck_return = Some(e);
            }
            return Ok(Step::Next);
        }
        // The one-block form (FANUC 0T, Haas: `G75 X Z I K D F`): I the X amount (G75: the
        // peck, in radius; G74: the step between plunges), K the Z amount (G74: the peck;
        // G75: the step), as P and Q of the two-block form; D (0T: the relief at the bottom,
        // Haas: the clearance of the return) moves nothing vpcut removes material with.
        let one_block = ["I", "K"].iter().any(|k| w.vals.contains_key(*k));
        if let Some(&(dv, col)) = w.vals.get("D") {
            if dv != 0.0 {
                self.out.notes.push((
                    col,
                    format!("G{g} D: the relief at the bottom (FANUC 0T) or the return clearance (Haas) is not simulated"),
                    "the pecks and steps are; the tool's last moves at each plunge's bottom are left out".into(),
                ));
            }
        }
        if one_block && (w.vals.contains_key("P") || w.vals.contains_key("Q")) {
            let col = w.vals.get("I").or(w.vals.get("K")).map_or(1, |v| v.1);
            return Err((
                col,
                format!("G{g}: I/K (the one-block form) and P/Q (the two-block form) in one block"),
            ));
        }
        if let Some(&(r, col)) = w.vals.get("R") {
            if r != 0.0 {
                return Err((col, format!("G{g} R{r}: the relief at the bottom (dd) is not simulated by vpcut (write R0 or leave it out)")));
            }
        }
        for k in ["P", "Q"] {
            if let Some(&(v, col)) = w.vals.get(k) {
                if v < 0.0 {
                    return Err((col, format!("G{g} {k}: an amount in the least input increment, without sign or decimal point")));
                }
            }
        }
        let (x0, z0) = (self.x, self.z);
        // In G-code systems B/C under G91, X/Z are incremental too.
        let (x1, z1) = self.cycle_end(w);
        // P (di) and Q (dk) never take a decimal point: the least input increment. The
        // one-block I/K: in program units with a point, else in the increment. Without a
        // peck (no I in G75, no K in G74) the plunge is one feed to the bottom.
        let what = format!("G{g}");
        let (di, dk) = if one_block {
            let full = |v: Option<f64>, len: f64| v.filter(|x| *x > 0.0).unwrap_or(len);
            let (x1, z1) = self.cycle_end(w);
            let (ix, kz) = (
                self.increment_or_units(w, "I").map(f64::abs),
                self.increment_or_units(w, "K").map(f64::abs),
            );
            if g == 75 {
                (full(ix, (x1 - x0).abs() / 2.0), kz.unwrap_or(0.0))
            } else {
                (ix.unwrap_or(0.0), full(kz, (z1 - z0).abs()))
            }
        } else {
            // The peck word left out: one plunge to the bottom (no pecking).
            let (x1, z1) = self.cycle_end(w);
            let p = self.increment_word(w, "P", &what)?;
            let q = self.increment_word(w, "Q", &what)?;
            if g == 75 {
                (p.unwrap_or((x1 - x0).abs() / 2.0), q.unwrap_or(0.0))
            } else {
                (p.unwrap_or(0.0), q.unwrap_or((z1 - z0).abs()))
            }
        };
        let e = self.thread.cycles.peck_return.unwrap_or(0.0);
        self.need_feed(w)?;
        // (c, d): c the peck axis, d the step axis; radius for X.
        let face = g == 74;
        let to_cd = |x: f64, z: f64| if face { (z, x / 2.0) } else { (x / 2.0, z) };
        let to_xz = |c: f64, d: f64| if face { (2.0 * d, c) } else { (2.0 * c, d) };
        let (c0, d0) = to_cd(x0, z0);
        let (c1, d1) = to_cd(x1, z1);
        let (peck, mut step) = if face { (dk, di) } else { (di, dk) };
        let (pw, sw) = if face { ("Q", "P") } else { ("P", "Q") };
        if c1 == c0 {
            return Err((
                1,
                format!(
                    "G{g} needs a {} target away from the start",
                    if face { "Z" } else { "X" }
                ),
            ));
        }
        if peck <= 0.0 {
            return Err((1, format!("G{g} needs {pw} (the peck depth) > 0")));
        }
        if d1 != d0 && step <= 0.0 {
            // A zero step with a shift to go (`G75 X30. Z-33. P3000 Q0` from a start at
            // another Z): one plunge at the start and one at the end, a warning.
            let axis = if face { "X" } else { "Z" };
            self.out.notes.push((
                1,
                format!("G{g} {sw}0 with an end {axis} away from the start: one plunge at the start {axis} and one at the end {axis}"),
                format!("{sw} is the step between plunges; write it (or move to the end {axis} first) to say where the control plunges"),
            ));
            step = (d1 - d0).abs();
        }
        let (sc, sd) = (sign(c1 - c0), sign(d1 - d0));
        let (len, span) = ((c1 - c0).abs(), (d1 - d0).abs());
        let pecks = (len / peck).ceil();
        let steps = if span > 0.0 {
            (span / step).ceil()
        } else {
            0.0
        };
        if pecks * (steps + 1.0) > MAX_PASSES as f64 {
            return Err((1, format!("G{g} would cut more than {MAX_PASSES} pecks")));
        }
        let mut at = (x0, z0);
        let mut go = |m: &mut Self, kind: MoveKind, (c, d): (f64, f64)| {
            let to = to_xz(c, d);
            if to != at {
                m.emit(prog, pc, kind, at, to, None);
                at = to;
            }
        };
        let mut j = 0.0;
        loop {
            let d = if j * step >= span {
                d1
            } else {
                d0 + sd * j * step
            };
            go(self, MoveKind::Rapid, (c0, d));
            let mut t: f64 = 0.0;
            loop {
                let next = (t + peck).min(len);
                go(self, MoveKind::Feed, (c0 + sc * next, d));
                if next >= len {
                    break;
                }
                t = next;
                go(self, MoveKind::Rapid, (c0 + sc * (t - e).max(0.0), d));
            }
            go(self, MoveKind::Rapid, (c0, d));
            if d == d1 {
                break;
            }
            j += 1.0;
        }
        go(self, MoveKind::Rapid, (c0, d0));
        (self.x, self.z) = (x0, z0);
        Ok(Step::Next)
    }
}

/// A move of a cycle's block from `at` to `to` (in the cycle's frame), left out when it
/// has no length; `at` follows.
pub(super) fn step(
    m: &mut Interp,
    (prog, pc, f): (&Program, usize, Frame),
    at: &mut (f64, f64),
    kind: MoveKind,
    to: Ab,
) {
    let to = f.xz(to);
    if to != *at {
        m.emit(prog, pc, kind, *at, to, None);
        *at = to;
    }
}

/// A G73 division count or G71 `R`-style count: a whole number 1..9999.
fn count(v: f64, col: usize) -> Result<u32, Fail> {
    if v.fract() != 0.0 || !(1.0..=9999.0).contains(&v) {
        return Err((
            col,
            format!("G73: the number of divisions must be a whole number 1..9999, got {v}"),
        ));
    }
    Ok(v as u32)
}

/// Where a roughing pass at `level` meets the shape (the `b` of the first point along the
/// shape at or past the level, side `s`); `None` if the shape ends short of it.
fn pass_end(segs: &[Seg], s: f64, level: f64) -> Option<f64> {
    for sg in segs {
        let (p, q) = (sg.p, sg.q);
        if s * (p.0 - level) >= 0.0 {
            return Some(p.1);
        }
        if s * (q.0 - level) < 0.0 {
            continue;
        }
        match sg.arc {
            None => {
                let t = (level - p.0) / (q.0 - p.0);
                return Some(p.1 + t * (q.1 - p.1));
            }
            Some((c, r)) => {
                let h = (r * r - (level - c.0).powi(2)).max(0.0).sqrt();
                let (lo, hi) = (p.1.min(q.1) - 1e-9, p.1.max(q.1) + 1e-9);
                let guess = p.1 + (level - p.0) / (q.0 - p.0) * (q.1 - p.1);
                let best = [c.1 - h, c.1 + h]
                    .into_iter()
                    .filter(|b| (lo..=hi).contains(b))
                    .min_by(|x, y| (x - guess).abs().total_cmp(&(y - guess).abs()));
                return Some(best.unwrap_or(guess).clamp(lo + 1e-9, hi - 1e-9));
            }
        }
    }
    None
}
