//! LinuxCNC G70/G71/G72 in the interpreter: the cycle's block, its contour subroutine read
//! as rs274 2.9.0~pre1 reads it, and the cycle's moves (`lcnc_contour`) made as moves.
//!
//! rs274 (`Interp::convert_g7x`): the block's checks, a rapid to its X/Z (which, under
//! G91, goes to the words' values as absolute coordinates while the cycle starts at the
//! current point plus them), then `O<Q> call`: every line of the subroutine (and of what it
//! calls) runs its O-words and parameter settings, and its motion words (G0 read as G1, G1,
//! G2/G3 with I/K or R, X/Z, and U/W as increments in G90) make the contour; everything
//! else (feeds, speeds, other G and M codes) is ignored. `A` on a block asks for a fillet
//! at its end, `C` for a chamfer. While it reads, the current point (`#<_x>`, `#<_z>`) is
//! the contour's. When the subroutine returns, the cycle runs from the start point with
//! `D` (allowance), `I` (depth of cut, G71/G72), `R` (retract), `E`, `P` (G70's last
//! allowance and passes); its errors are rs274's ("G7X error: Not monotonic").

use super::lcnc_contour::{c, g_format, Contour, Out, Seg, C};
use super::{ArcGeometry, Interp, MoveKind, Program, Step, Words};
use crate::nc::expr::Fail;

/// A G7x cycle whose contour subroutine is being read.
#[derive(Debug)]
pub(super) struct G7xRead {
    /// 700, 710, 711, 712, 720, 721, 722.
    code: u32,
    /// The call depth of the cycle's block.
    depth: usize,
    /// The cycle's block (its moves are recorded there).
    file: String,
    line: usize,
    /// Where the tool is (after the rapid to X/Z), program units.
    pos: C,
    /// The cycle's start point (program units, x a radius).
    start: C,
    /// The contour's current point.
    pub(super) at: C,
    /// The motion mode while reading: 0..3, or another of group 1 (no segment).
    motion: u32,
    segs: Vec<Seg>,
    /// D, E, I, P, R of the block.
    words: [Option<f64>; 5],
    incremental: bool,
    ijk_incremental: bool,
    diameter: bool,
}

/// A G code that is one of the cycles: its number x 10 (G71.1: 711).
pub(super) fn g7x_code(g: u32) -> Option<u32> {
    use super::motion::DECIMAL_G;
    match g {
        70..=72 => Some(g * 10),
        g if g == DECIMAL_G + 711 || g == DECIMAL_G + 712 => Some(g - DECIMAL_G),
        g if g == DECIMAL_G + 721 || g == DECIMAL_G + 722 => Some(g - DECIMAL_G),
        _ => None,
    }
}

/// The G codes of rs274's motion group (modal group 1) other than G0..G3.
fn other_motion(g: u32) -> bool {
    use super::motion::DECIMAL_G;
    g7x_code(g).is_some()
        || matches!(g, 5 | 33 | 73 | 74 | 76 | 80..=89)
        || (DECIMAL_G + 331..=DECIMAL_G + 385).contains(&g)
}

/// rs274's name of a cycle in its messages ("G71.0").
fn name(code: u32) -> String {
    format!("G{}.{}", code / 10, code % 10)
}

/// rs274's text for a word no G code of the block uses (`check_other_codes`).
fn unused_word(letter: &str) -> &'static str {
    match letter {
        "E" => "E word with no G70, G76, M66, M67 or M68 to use it",
        "H" => "H word with no G43 or G76 to use it",
        "I" => "I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it",
        "J" => "J word with no G2, G3, G5, G5.1, G10, G76 or G87 to use it",
        "K" => "K word with no G2, G3, G33, G33.1, G76, or G87 to use it",
        "L" => "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code",
        "P" => "P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it",
        _ => "R word with no g code that uses it",
    }
}

impl Interp<'_> {
    /// The program's frame: (x offset as a diameter, z offset) in mm, and the unit scale.
    fn lc_frame(&self) -> (f64, f64, f64) {
        let (ox, oz) = self.frames.offsets[self.frames.work];
        let (gx, gz) = self.frames.g92_off;
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        (ox + gx, oz + gz, scale)
    }

    /// A block with G70, G71 or G72 (`code`): checks, the rapid to X/Z, and the call of the
    /// contour subroutine.
    pub(super) fn lc_g7x_start(
        &mut self,
        w: &Words,
        code: u32,
        prog: &Program,
        pc: usize,
    ) -> Result<Step, Fail> {
        let col = |k: &str| w.vals.get(k).map_or(1, |v| v.1);
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let g70 = code == 700;
        let unused: &[&str] = if g70 {
            &["I", "J", "K", "H", "L", "R"]
        } else {
            &["E", "J", "K", "H", "L", "P"]
        };
        for &k in unused {
            if w.vals.contains_key(k) {
                return Err((col(k), unused_word(k).into()));
            }
        }
        if let Some(&(_, at)) = w.vals.get("U").or(w.vals.get("W")) {
            let l = if w.vals.contains_key("U") { 'u' } else { 'w' };
            return Err((
                at,
                format!("Bad character '{l}' used (rs274 reads U and W as increments only inside the contour subroutine)"),
            ));
        }
        let Some(q) = val("Q") else {
            return Err((1, "G7x.x  requires a Q word".into()));
        };
        if !g70 && self.lc.st.ccomp != 400 {
            return Err((
                1,
                format!(
                    "{} cannot be used with cutter compensation enabled",
                    name(code)
                ),
            ));
        }
        // rs274 runs G70 under G41/G42: its rapids to each pass's start with compensation
        // off for the move, the rest compensated as ordinary moves. vpcut's compensation
        // does not model a move made with it off for the move, so a tool of nonzero radius
        // is refused rather than run differently (a radius of 0 makes the moves as
        // programmed, as rs274's).
        if g70 && self.nose_on() {
            return Err((
                1,
                "G70 under cutter compensation (G41/G42) with a tool of nonzero radius is not simulated: cancel it with G40 before the G70, or give the tool radius 0 and offset the contour (rs274 runs it with compensation off for each pass's rapid to its start)".into(),
            ));
        }
        if self.lc.st.plane != 180 {
            return Err((
                1,
                format!("{} can only be used in XZ plane (G18)", name(code)),
            ));
        }
        // rs274 calls `O<Q with 6 decimals> call`, whose number it reads as a whole number
        // within 1e-4.
        let text = format!("{q:.6}");
        let Some(number) = text.parse().ok().and_then(super::linuxcnc::integer_value) else {
            return Err((
                col("Q"),
                format!("Non integer value for integer: Q{q} (rs274 reads `O{text} CALL`: Q names the contour subroutine)"),
            ));
        };
        let key = format!("O{number}");
        // The rest of the block (feed, speed, spindle, other modes) first, as rs274 runs it.
        let mut rest = Words {
            g: w.g
                .iter()
                .copied()
                .filter(|&g| g7x_code(g).is_none())
                .collect(),
            m: w.m.clone(),
            ..Words::default()
        };
        for k in ["F", "S", "T"] {
            if let Some(&v) = w.vals.get(k) {
                rest.vals.insert(k.into(), v);
            }
        }
        if let Step::End = self.apply(&rest, prog, pc)? {
            return Ok(Step::End);
        }
        let (ox, oz, scale) = self.lc_frame();
        let half = if self.modal.diameter_mode { 0.5 } else { 1.0 };
        let here = c((self.z - oz) / scale, (self.x - ox) / 2.0 / scale);
        let (wx, wz) = (val("X").map(|v| v * half), val("Z"));
        let mut start = here;
        if self.modal.incremental {
            start.im += wx.unwrap_or(0.0);
            start.re += wz.unwrap_or(0.0);
        } else {
            start.im = wx.unwrap_or(start.im);
            start.re = wz.unwrap_or(start.re);
        }
        // rs274's rapid reads the block's words as absolute coordinates (the cycle forces
        // G90 before it moves), so under G91 it goes to the words' values themselves.
        let target = c(wz.unwrap_or(here.re), wx.unwrap_or(here.im));
        let (file, line) = (prog.name.clone(), prog.blocks[pc].0);
        let pos = self.lc_g7x_emit(Out::Rapid(target), here, &file, line)?;
        let words = ["D", "E", "I", "P", "R"].map(val);
        self.lc.g7x = Some(Box::new(G7xRead {
            code,
            depth: self.lc_depth(),
            file,
            line,
            pos,
            start,
            at: start,
            motion: 0,
            segs: Vec::new(),
            words,
            incremental: self.modal.incremental,
            ijk_incremental: !self.lc.st.ijk_absolute,
            diameter: self.modal.diameter_mode,
        }));
        if !self.progs.by_name.contains_key(&key) {
            self.lc.g7x = None;
            return Err((
                col("Q"),
                format!(
                    "EOF in file:{file} seeking o-word: o<{number}> from line: {line} (G{} Q{number} calls the contour subroutine o{number} sub, not in this file)",
                    code / 10,
                    file = prog.name,
                    line = prog.blocks[pc].0,
                ),
            ));
        }
        self.lc_push_level();
        Ok(Step::Call(key, 1, Some(Vec::new())))
    }

    /// A line of the contour subroutine that is no O-word: its motion words as a segment.
    pub(super) fn lc_g7x_block(&mut self, w: &Words) -> Result<(), Fail> {
        let g = self.lc.g7x.as_mut().expect("reading a contour");
        let col = |k: &str| w.vals.get(k).map_or(1, |v| v.1);
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        for &code in &w.g {
            if code <= 3 {
                g.motion = code;
            } else if other_motion(code) {
                g.motion = 99;
            }
        }
        let half = if g.diameter { 0.5 } else { 1.0 };
        let mut end = if g.incremental { c(0.0, 0.0) } else { g.at };
        if let Some(u) = val("U") {
            if g.incremental {
                return Err((
                    col("U"),
                    "G7x error: Cannot use U in incremental mode (G91)".into(),
                ));
            }
            if w.vals.contains_key("X") {
                return Err((
                    col("U"),
                    "G7x error: Cannot use U and X in the same block".into(),
                ));
            }
            end.im += u * half;
        } else if let Some(x) = val("X") {
            end.im = x * half;
        }
        if let Some(wv) = val("W") {
            if g.incremental {
                return Err((
                    col("W"),
                    "G7x error: Cannot use W in incremental mode (G91)".into(),
                ));
            }
            if w.vals.contains_key("Z") {
                return Err((
                    col("W"),
                    "G7x error: Cannot use W and Z in the same block".into(),
                ));
            }
            end.re += wv;
        } else if let Some(z) = val("Z") {
            end.re = z;
        }
        let mut centre = c(val("K").unwrap_or(0.0), val("I").unwrap_or(0.0));
        if g.incremental {
            end = end + g.at;
        }
        if end == g.at {
            return Ok(());
        }
        let start = g.at;
        match g.motion {
            0 | 1 => g.segs.push(Seg::line(start, end)),
            2 | 3 => {
                let has_ik = w.vals.contains_key("I") || w.vals.contains_key("K");
                if let Some(r) = val("R") {
                    if has_ik {
                        return Err((
                            col("R"),
                            "G7X error: both R and I or K flag used for arc".into(),
                        ));
                    }
                    let chord = end - start;
                    let n = chord.norm();
                    let h = (r * r - n / 4.0) / n;
                    if h.is_nan() || h < 0.0 {
                        return Err((
                            col("R"),
                            format!("G{} R{r}: the end point is farther from the start than the diameter (rs274 2.9.0~pre1 makes no arc of it)", g.motion),
                        ));
                    }
                    centre = (start + end) / 2.0;
                    let d = c(0.0, h.sqrt()) * chord;
                    centre = if g.motion == 3 {
                        centre + d
                    } else {
                        centre - d
                    };
                } else {
                    if !has_ik {
                        return Err((1, "G7X error: either I or K must be present for arc".into()));
                    }
                    if g.ijk_incremental {
                        centre = centre + start;
                    }
                }
                g.segs.push(Seg::arc(g.motion == 3, start, centre, end));
            }
            _ => {}
        }
        if g.motion <= 3 {
            match (val("A"), val("C")) {
                (Some(_), Some(_)) => {
                    return Err((
                        col("C"),
                        "G7X error: Both A and C parameters on a corner".into(),
                    ))
                }
                (Some(a), None) => g.segs.push(Seg::fillet(a, end)),
                (None, Some(r)) => g.segs.push(Seg::chamfer(r, end)),
                (None, None) => {}
            }
        }
        g.at = end;
        Ok(())
    }

    /// At an `endsub`/`return`: whether it ends the contour subroutine of a cycle, and if
    /// so the cycle's moves (recorded at the cycle's block `line` of `file`).
    pub(super) fn lc_g7x_end(&mut self) -> Result<(), Fail> {
        let ends = self
            .lc
            .g7x
            .as_ref()
            .is_some_and(|g| self.lc_depth() == g.depth + 1);
        if !ends {
            return Ok(());
        }
        let g = *self.lc.g7x.take().expect("checked");
        if g.segs.len() <= 1 {
            return Ok(());
        }
        let [d, e, i, p, r] = g.words;
        let i = i.unwrap_or(1.0);
        if i <= 0.0 {
            return Err((1, "G7X error: I must be greater than zero.".into()));
        }
        let (d, e, p, r) = (
            d.unwrap_or(0.0),
            e.unwrap_or(0.0),
            p.unwrap_or(1.0),
            r.unwrap_or(0.5),
        );
        let contour = Contour::new(g.segs);
        let moves = match g.code {
            700 => contour.g70(g.start, d, e, p),
            code => contour.g71(code >= 720, code % 10, g.start, d, i, r),
        }
        .map_err(|m| (1, format!("G7X error: {m}")))?;
        let mut at = g.pos;
        for m in moves {
            at = self.lc_g7x_emit(m, at, &g.file, g.line)?;
        }
        Ok(())
    }

    /// One move of a cycle from `at` (program units), as rs274's `convert_straight` /
    /// `convert_arc` make it: an arc that ends within 1e-4 of where the tool is makes no
    /// move; an arc whose end is off its circle is rs274's error. Returns where the tool
    /// is after it.
    fn lc_g7x_emit(&mut self, m: Out, at: C, file: &str, line: usize) -> Result<C, Fail> {
        let (ox, oz, scale) = self.lc_frame();
        let mach = |p: C| (2.0 * p.im * scale + ox, p.re * scale + oz);
        let from = (self.x, self.z);
        let (kind, end) = match m {
            Out::Rapid(p) => (MoveKind::Rapid, p),
            Out::Feed(p) => (MoveKind::Feed, p),
            Out::Arc { end, .. } => (MoveKind::Arc, end),
        };
        if let Out::Arc { ccw, centre, .. } = m {
            if (at.re - end.re).abs() < 1e-4 && (at.im - end.im).abs() < 1e-4 {
                return Ok(at);
            }
            self.lc_g7x_arc_check(at, centre, end)?;
            self.modal.motion = if ccw { 3 } else { 2 };
            self.need_feed(&Words::default())?;
        } else if kind == MoveKind::Feed {
            self.modal.motion = 1;
            self.need_feed(&Words::default())?;
        } else {
            self.modal.motion = 0;
        }
        let to = mach(end);
        self.emit_in(file, line, kind, from, to, None);
        if let Out::Arc { ccw, centre, .. } = m {
            let shift = self.out.applied;
            let (cx, cz) = mach(centre);
            if let Some(last) = self.out.moves.last_mut() {
                last.arc = Some(ArcGeometry {
                    x_centre_dia: cx + shift.0,
                    z_centre: cz + shift.1,
                    clockwise: !ccw,
                });
            }
        }
        (self.x, self.z) = to;
        Ok(end)
    }

    /// rs274's `arc_data_ijk` checks of a cycle's arc from `at` about `centre` to `end`
    /// (XZ plane, program units).
    fn lc_g7x_arc_check(&self, at: C, centre: C, end: C) -> Result<(), Fail> {
        let (min_r, spiral) = if self.modal.inch {
            (0.00005, 2.0 * 0.001 * std::f64::consts::SQRT_2)
        } else {
            (0.00005 * 25.4, 2.0 * 0.01 * std::f64::consts::SQRT_2)
        };
        let r1 = (centre.re - at.re).hypot(centre.im - at.im);
        let r2 = (centre.re - end.re).hypot(centre.im - end.im);
        let pts = format!(
            "start=(Z{:.4},X{:.4}) center=(Z{:.4},X{:.4}) end=(Z{:.4},X{:.4}) r1={r1:.4} r2={r2:.4}",
            at.re, at.im, centre.re, centre.im, end.re, end.im
        );
        if r1 < min_r || r2 < min_r {
            return Err((1, format!("Zero-radius arc: {pts}")));
        }
        let abs_err = (r1 - r2).abs();
        let rel_err = abs_err / r1.max(r2);
        if abs_err > spiral * 100.0 || (rel_err > 0.001 && abs_err > spiral) {
            return Err((
                1,
                format!(
                    "Radius to end of arc differs from radius to start: {pts} abs_err={} rel_err={:.4}%",
                    g_format(abs_err, 4),
                    rel_err * 100.0
                ),
            ));
        }
        Ok(())
    }
}
