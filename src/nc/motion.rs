//! Modal state and motion: G/M codes, tool and spindle words, X/Z/U/W end points, thread
//! moves of every dialect, and the recording of moves and threading-cycle passes.

use super::codes::{self, Verdict};
use super::expr::Fail;
use super::{
    ArcGeometry, Dialect, Dwell, DwellTime, Feed, Interp, Move, MoveKind, Program, SpindleSpeed,
    Step, Sync, Words,
};
use crate::model::helix::{LeadLaw, Spindle};

/// G codes with a decimal (LinuxCNC's G92.1, G59.1, ..) are kept in `Words::g` as this plus
/// the code in tenths (G92.1: `DECIMAL_G + 921`).
pub(super) const DECIMAL_G: u32 = 100_000;

/// The G code `Words::g` holds `g` for, as a number (G92.1 for `DECIMAL_G + 921`).
pub(super) fn g_number(g: u32) -> f64 {
    if g >= DECIMAL_G {
        f64::from(g - DECIMAL_G) / 10.0
    } else {
        f64::from(g)
    }
}

/// The way back of a tap that went in with `inward` for `revs` spindle revolutions: the
/// same helix with the spindle reversed. The spindle has turned `revs` past the phase it
/// started at; reversed, the angle past the index counts the other way, so the way back
/// starts at minus that (mod 360).
pub(super) fn tap_back(inward: Sync, revs: f64) -> Sync {
    Sync {
        angle: (-(inward.angle + 360.0 * revs)).rem_euclid(360.0),
        ..inward
    }
}

/// How far an arc's end may lie off the circle through its start (mm of radius).
pub(super) const ARC_TOLERANCE: f64 = 0.002;

impl Sync {
    /// The sync of a move that continues this one without a new index wait after `travel`
    /// mm of axial travel: the lead and the spindle angle (mod 360) reached there.
    pub(super) fn after(&self, travel: f64) -> Option<Sync> {
        let law = LeadLaw {
            f: self.lead,
            k: self.change,
        };
        let t = law.revs_at(travel.abs())?;
        Some(Sync {
            lead: law.lead(t),
            change: self.change,
            angle: (self.angle + 360.0 * t).rem_euclid(360.0),
        })
    }
}

/// The centre of the arc from `a` to `b` (a right-handed plane, `a != b`) of signed radius
/// `r` (positive: the arc of at most 180 deg, negative: the longer one), clockwise or not.
/// A radius shorter than half the chord (within `ARC_TOLERANCE`, checked by the caller)
/// puts the centre on the chord's middle.
pub(super) fn radius_centre(a: (f64, f64), b: (f64, f64), r: f64, cw: bool) -> (f64, f64) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let chord = dx.hypot(dy);
    let half = chord / 2.0;
    let h = (r * r - half * half).max(0.0).sqrt();
    // A counter-clockwise minor arc has its centre left of the chord a -> b.
    let left = (-dy / chord, dx / chord);
    let s = if cw { -1.0 } else { 1.0 } * r.signum();
    (
        a.0 + dx / 2.0 + s * h * left.0,
        a.1 + dy / 2.0 + s * h * left.1,
    )
}

impl Interp<'_> {
    /// Modal state and motion of one block's words.
    pub(super) fn apply(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let mut set_position = false;
        let mut home = false;
        let mut second = false;
        let lcnc = self.cfg.dialect == Dialect::Linuxcnc;
        // LinuxCNC non-modal codes: G53 (this block in machine coordinates), G28/G30 (go
        // home, optionally through an intermediate point), G92 (offset), G10 (set offsets).
        let mut machine_coords = false;
        let mut fanuc_g53 = false;
        let mut lc_home: Option<u32> = None;
        let mut g92_set = false;
        let mut g10 = false;
        for &g in &w.g {
            match g {
                53 if lcnc => machine_coords = true,
                // FANUC/GSK G53: this block's X/Z in machine coordinates, at rapid.
                53 if self.cfg.dialect == Dialect::Fanuc => {
                    machine_coords = true;
                    fanuc_g53 = true;
                }
                28 | 30 if lcnc => lc_home = Some(g),
                92 if lcnc => g92_set = true,
                10 if lcnc => g10 = true,
                // G28.1/G30.1: store the current machine position as the home.
                g if lcnc && (g == DECIMAL_G + 281 || g == DECIMAL_G + 301) => {
                    let st = &mut self.lc.st;
                    if g == DECIMAL_G + 281 {
                        st.home28 = (self.x, self.z);
                    } else {
                        st.home30 = (self.x, self.z);
                    }
                }
                // G92.1 clears the G92 offsets and their parameters, G92.2 clears the
                // offsets and keeps the parameters, G92.3 applies the parameters again.
                g if lcnc && g == DECIMAL_G + 921 => {
                    self.frames.g92_off = (0.0, 0.0);
                    self.lc.st.g92_params = (0.0, 0.0);
                    self.lc.st.g92_on = false;
                }
                g if lcnc && g == DECIMAL_G + 922 => {
                    self.frames.g92_off = (0.0, 0.0);
                    self.lc.st.g92_on = false;
                }
                g if lcnc && g == DECIMAL_G + 923 => {
                    self.frames.g92_off = self.lc.st.g92_params;
                    self.lc.st.g92_on = true;
                }
                g if lcnc && (DECIMAL_G + 591..=DECIMAL_G + 593).contains(&g) => {
                    self.frames.work = (g - DECIMAL_G - 591) as usize + 6;
                }
                0..=3 | 32 | 33 | 34 | 35 => self.modal.motion = g,
                // LinuxCNC G33.1 (rigid tapping, modal like G33): `lc_rigid_tap`.
                g if lcnc && g == DECIMAL_G + 331 => self.modal.motion = 331,
                // Siemens 840D rigid tapping (`siemens_840d`): thread moves, lead K.
                331 | 332 if self.cfg.s840 => self.modal.motion = g,
                // G92 is the threading cycle on FANUC/GSK lathes, an offset on LinuxCNC.
                92 if self.cfg.dialect == Dialect::Fanuc => self.modal.motion = 92,
                // FANUC/GSK system A: G90 outer/inner diameter and G94 end face cutting
                // cycles (modal, like G92).
                90 | 94 if self.cfg.dialect == Dialect::Fanuc => self.modal.motion = g,
                // Absolute/incremental on Siemens and LinuxCNC; FANUC/GSK lathes (G-code
                // system A) write U/W instead, and their G90 is a turning cycle.
                90 if matches!(self.cfg.dialect, Dialect::Siemens802d | Dialect::Linuxcnc) => {
                    self.modal.incremental = false
                }
                91 if matches!(self.cfg.dialect, Dialect::Siemens802d | Dialect::Linuxcnc) => {
                    self.modal.incremental = true
                }
                20 | 21 => {
                    self.modal.inch = g == 20;
                    self.modal.units_set = true;
                }
                70 | 71 if self.cfg.dialect == Dialect::Siemens802d => {
                    self.modal.inch = g == 70;
                    self.modal.units_set = true;
                }
                7 if self.cfg.dialect == Dialect::Linuxcnc => self.modal.diameter_mode = true,
                8 if self.cfg.dialect == Dialect::Linuxcnc => self.modal.diameter_mode = false,
                // FANUC/GSK G50 with X/Z sets the coordinates of the current position.
                50 if self.cfg.dialect == Dialect::Fanuc => set_position = true,
                // FANUC/GSK G28 (non-modal): rapid to the intermediate point, then to the
                // reference point in the named axes.
                28 if self.cfg.dialect == Dialect::Fanuc => home = true,
                // FANUC/GSK G30 (P2, the default): the same through the second reference
                // point. P3/P4 (third and fourth) are machine data vpcut does not have.
                30 if self.cfg.dialect == Dialect::Fanuc && !self.cfg.milling => {
                    if let Some(&(p, col)) = w.vals.get("P") {
                        if p != 2.0 {
                            return Err((
                                col,
                                format!("G30 P{p}: only the second reference point (P2) is known (the job's [program] second_reference_point)"),
                            ));
                        }
                    }
                    home = true;
                    second = true;
                }
                54..=59 => self.frames.work = (g - 54) as usize,
                // Tool nose radius compensation (`nose`); SINUMERIK's corner modes.
                40..=42 => self.nose_word(g, w)?,
                // LinuxCNC's dynamic compensation G41.1/G42.1 D L.
                g if self.cfg.dialect == Dialect::Linuxcnc
                    && (g == DECIMAL_G + 411 || g == DECIMAL_G + 421) =>
                {
                    self.nose_word(g, w)?
                }
                450 | 451 if self.cfg.dialect == Dialect::Siemens802d => self.nose_word(g, w)?,
                96 => self.modal.css = true,
                97 => {
                    // G97 without S keeps the speed the spindle turns at (FANUC: the speed
                    // at that moment becomes the programmed one).
                    if self.modal.css && !w.vals.contains_key("S") {
                        self.modal.speed = self.spindle_speed().at(self.x);
                    }
                    self.modal.css = false
                }
                // A dwell (non-modal): its X/U/P are its time, not a position.
                4 => return self.dwell(w, prog, pc),
                // Feed per minute / per revolution: G98/G99 on FANUC lathes (system A),
                // G94/G95 on LinuxCNC and Siemens. Thread leads (F of G32/G34/G92/G76) are
                // per revolution whichever is active.
                98 if self.cfg.dialect == Dialect::Fanuc => self.modal.per_rev = false,
                99 if self.cfg.dialect == Dialect::Fanuc => self.modal.per_rev = true,
                94 if matches!(self.cfg.dialect, Dialect::Linuxcnc | Dialect::Siemens802d) => {
                    self.modal.per_rev = false
                }
                95 if matches!(self.cfg.dialect, Dialect::Linuxcnc | Dialect::Siemens802d) => {
                    self.modal.per_rev = true
                }
                other => match codes::g_code(self.real_dialect(), g_number(other)) {
                    // Nothing vpcut simulates changes (planes, dwell, feed and speed modes).
                    Verdict::Run => {}
                    Verdict::Refused(msg) => return Err((1, msg)),
                    Verdict::Unknown(msg) => self.unknown(1, msg)?,
                },
            }
        }
        let mut end = false;
        if let Some(step) = self.m_words(w, &mut end)? {
            return Ok(step);
        }
        if let Some(&(t, col)) = w.vals.get("T") {
            let t = t.round() as u32;
            // A tool change: the next thread block starts a new chain.
            self.thread.chain_end = None;
            // FANUC/GSK T0305: tool 3 with offset 5 (T0300 cancels the offset).
            let split = self.cfg.dialect == Dialect::Fanuc && t >= 100;
            self.modal.tool = Some(if split { t / 100 } else { t });
            self.modal.tool_t = Some(
                w.t_text
                    .clone()
                    .unwrap_or_else(|| super::tool_word(self.cfg.dialect, t as f64)),
            );
            if split {
                self.call_offset(t % 100, col);
            }
        }
        let mut d_word = None;
        if self.cfg.dialect == Dialect::Siemens802d {
            // Siemens D5: offset 5 of the active tool (D0 cancels).
            if let Some(&(d, col)) = w.vals.get("D") {
                let d = d.round().max(0.0) as u32;
                self.call_offset(d, col);
                d_word = Some(d);
            }
        }
        if w.vals.contains_key("T") || d_word.is_some() {
            // The tool as written: the T word, and on Siemens the D in force (D0: none).
            let d = match self.modal.offset {
                Some(d) if self.cfg.dialect == Dialect::Siemens802d && d > 0 => {
                    format!(" D{d}")
                }
                _ => String::new(),
            };
            self.modal.tool_word = self
                .modal
                .tool_t
                .as_ref()
                .map(|t| std::sync::Arc::from(format!("{t}{d}")));
        }
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let scale = if self.modal.inch { 25.4 } else { scale };
        if let Some(s) = val("S") {
            // FANUC/GSK G50 S: the clamp on G96's spindle speed, not a speed.
            if set_position {
                self.modal.speed_max = Some(s);
            } else {
                self.modal.speed = Some(s);
            }
        }
        // F is modal: the feed of G01/G02/G03 (and the lead of FANUC's thread blocks, which
        // share its register). On Siemens G34/G35 it is the lead change instead.
        if let Some(f) = val("F") {
            if !(self.cfg.dialect == Dialect::Siemens802d && matches!(self.modal.motion, 34 | 35)) {
                self.modal.feed = Some(f);
                self.modal.feed_plain = w.plain.iter().any(|p| p == "F");
            }
        }
        let mut x = self.x;
        let mut z = self.z;
        let mut moved = false;
        let xs = if self.modal.diameter_mode { 1.0 } else { 2.0 };
        // Absolute X/Z are in the active work system (G54..G59): its zero lies at the
        // offset in the job's frame.
        let (ox, oz) = if machine_coords {
            if self.modal.incremental {
                return Err((
                    1,
                    "G53 needs absolute coordinates (G90): it cannot be used with G91".into(),
                ));
            }
            if !fanuc_g53 && !matches!(self.modal.motion, 0 | 1) {
                return Err((
                    1,
                    format!("G53 needs G0 or G1 active, not G{}", self.modal.motion),
                ));
            }
            (0.0, 0.0)
        } else {
            let (ox, oz) = self.frames.offsets[self.frames.work];
            (ox + self.frames.g92_off.0, oz + self.frames.g92_off.1)
        };
        if g10 {
            return self.lc_g10(w, xs, scale).map(|()| Step::Next);
        }
        // FANUC/GSK G04 (dwell, one shot): its X, U or P is the time, not a position (FANUC
        // 0i-TF "Dwell (G04)": `G04 X_ ;` / `G04 U_ ;` / `G04 P_ ;`; GSK 980TDc "Dwell
        // G04"). The block moves nothing.
        if self.cfg.dialect == Dialect::Fanuc && w.g.contains(&4) {
            if let Some(&(_, col)) = w.vals.get("Z").or(w.vals.get("W")) {
                return Err((
                    col,
                    "G04 (dwell) takes its time in X, U or P: Z and W move nothing here (a control alarms)".into(),
                ));
            }
            return Ok(if end { Step::End } else { Step::Next });
        }
        if g92_set {
            // The current point reads X/Z from now on: the offset is what lies between.
            let (wx, wz) = self.frames.offsets[self.frames.work];
            if let Some(v) = val("X") {
                self.frames.g92_off.0 = self.x - wx - v * xs * scale;
            }
            if let Some(v) = val("Z") {
                self.frames.g92_off.1 = self.z - wz - v * scale;
            }
            if !w.vals.contains_key("X") && !w.vals.contains_key("Z") {
                return Err((
                    1,
                    "G92 needs X or Z (the coordinates the current point gets)".into(),
                ));
            }
            self.lc.st.g92_params = self.frames.g92_off;
            self.lc.st.g92_on = true;
            return Ok(Step::Next);
        }
        // Lengths as the dialect reads them (FANUC/GSK: decimal-point input, `units`).
        if let Some(v) = self.x_length(w, "X") {
            x = if self.modal.incremental {
                self.x + v
            } else {
                v + ox
            };
            moved = true;
        }
        if let Some(v) = self.length(w, "Z") {
            z = if self.modal.incremental {
                self.z + v
            } else {
                v + oz
            };
            moved = true;
        }
        if self.cfg.dialect == Dialect::Fanuc {
            if let Some(v) = self.x_length(w, "U") {
                x = self.x + v;
                moved = true;
            }
            if let Some(v) = self.length(w, "W") {
                z = self.z + v;
                moved = true;
            }
        }
        if fanuc_g53 {
            // FANUC: absolute X/Z only (U/W are not read with G53), a rapid move.
            if w.vals.contains_key("U") || w.vals.contains_key("W") {
                return Err((1, "G53 takes X/Z in machine coordinates, not U/W".into()));
            }
            if (x, z) != (self.x, self.z) {
                self.emit(prog, pc, MoveKind::Rapid, (self.x, self.z), (x, z), None);
            }
            (self.x, self.z) = (x, z);
            return Ok(if end { Step::End } else { Step::Next });
        }
        if let Some(g) = lc_home {
            // LinuxCNC G28/G30: with axis words a rapid to that point (offsets applied),
            // then a rapid of the named axes to #5161../#5181..; without, all axes go home.
            let target = if g == 28 {
                self.lc.st.home28
            } else {
                self.lc.st.home30
            };
            let named_x = w.vals.contains_key("X");
            let named_z = w.vals.contains_key("Z");
            let any = named_x || named_z;
            let end_point = (
                if named_x || !any { target.0 } else { x },
                if named_z || !any { target.1 } else { z },
            );
            let path = [(self.x, self.z), (x, z), end_point];
            for seg in path.windows(2) {
                if seg[0] != seg[1] {
                    self.emit(prog, pc, MoveKind::Rapid, seg[0], seg[1], None);
                }
            }
            (self.x, self.z) = end_point;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if home {
            let reference = if second {
                self.frames.reference2
            } else {
                self.frames.reference
            };
            let named = |a: &str, b: &str| w.vals.contains_key(a) || w.vals.contains_key(b);
            let end_point = (
                if named("X", "U") { reference.0 } else { x },
                if named("Z", "W") { reference.1 } else { z },
            );
            let path = [(self.x, self.z), (x, z), end_point];
            for seg in path.windows(2) {
                if seg[0] != seg[1] {
                    self.emit(prog, pc, MoveKind::Rapid, seg[0], seg[1], None);
                }
            }
            (self.x, self.z) = end_point;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if set_position {
            self.x = x;
            self.z = z;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if moved && self.cfg.dialect == Dialect::Fanuc && self.modal.motion == 92 {
            return self.in_cycle(|m| m.g92(w, prog, pc, x, z));
        }
        if moved && self.cfg.dialect == Dialect::Fanuc && matches!(self.modal.motion, 90 | 94) {
            self.need_feed(w)?;
            return self.nose_held(|m| m.cutting_cycle(w, prog, pc, x, z));
        }
        if moved && matches!(self.modal.motion, 1..=3) {
            self.need_feed(w)?;
        }
        if moved && (self.modal.motion == 2 || self.modal.motion == 3) {
            self.arc(w, prog, pc, (x, z))?;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if moved {
            let (kind, lead, change, angle) = match (self.cfg.dialect, self.modal.motion) {
                (_, 0) => (MoveKind::Rapid, None, None, None),
                (_, 1) => (MoveKind::Feed, None, None, None),
                (Dialect::Linuxcnc, 331) => {
                    self.lc_rigid_tap(w, prog, pc, (x, z), scale)?;
                    return Ok(if end { Step::End } else { Step::Next });
                }
                (Dialect::Linuxcnc, 33) => {
                    if !self.lc.st.spindle_on {
                        return Err((
                            1,
                            super::linuxcnc::spindle_stopped("Spindle not turning in G33"),
                        ));
                    }
                    let k = val("K").ok_or((1, "G33 needs K (the pitch)".to_string()))? * scale;
                    // rs274/LinuxCNC: K is the distance per revolution along the programmed
                    // move (the trajectory planner ties path progress to the spindle), so a
                    // tapered G33 advances K cos(taper) in Z per revolution; vpcut's lead is
                    // the Z lead.
                    let (dr, dz) = ((x - self.x) / 2.0, z - self.z);
                    let path = dr.hypot(dz);
                    // (Exactly K on a straight thread.)
                    let lead = if dz != 0.0 && dr != 0.0 {
                        k * dz.abs() / path
                    } else {
                        k
                    };
                    (MoveKind::Thread, Some(lead), Some(0.0), Some(0.0))
                }
                // GSK 980TDc G33: the Z tapping cycle (`gsk_tap`).
                (Dialect::Fanuc, 33) if self.cfg.gsk => {
                    self.gsk_tap(w, prog, pc, (x, z))?;
                    return Ok(if end { Step::End } else { Step::Next });
                }
                (Dialect::Fanuc, 34) if self.cfg.gsk => {
                    return self.gsk_g34(w, prog, pc, x, z);
                }
                (Dialect::Fanuc, 32) | (Dialect::Fanuc, 34) => {
                    let g = format!("G{}", self.modal.motion);
                    let f = self
                        .lead_word(w, "F", &g)?
                        .ok_or((1, format!("{g} needs F (the lead)")))?;
                    let k = if self.modal.motion == 34 {
                        self.lead_word(w, "K", &g)?.unwrap_or(0.0)
                    } else {
                        0.0
                    };
                    let q = self.start_angle(w, &g)?;
                    (MoveKind::Thread, Some(f), Some(k), Some(q))
                }
                (Dialect::Siemens802d, 33..=35) => {
                    let k = val("K")
                        .or(val("I"))
                        .ok_or((1, format!("G{} needs K (the lead)", self.modal.motion)))?
                        * scale;
                    let f = if self.modal.motion == 33 {
                        0.0
                    } else {
                        val("F").unwrap_or(0.0).abs() * scale
                    };
                    let f = if self.modal.motion == 35 { -f } else { f };
                    (
                        MoveKind::Thread,
                        Some(k),
                        Some(f),
                        Some(val("SF").unwrap_or(0.0)),
                    )
                }
                (Dialect::Siemens802d, 331 | 332) => {
                    let k = val("K").ok_or((
                        1,
                        format!("G{} needs K (the tap's lead)", self.modal.motion),
                    ))? * scale;
                    (MoveKind::Thread, Some(k.abs()), Some(0.0), Some(0.0))
                }
                (_, g) => {
                    return Err((
                        1,
                        format!("G{g} moves are not supported in this dialect yet"),
                    ))
                }
            };
            let mut sync = lead.map(|lead| Sync {
                lead,
                change: change.unwrap_or(0.0),
                angle: angle.unwrap_or(0.0),
            });
            // G332, the tap's way out: the spindle turns the other way, in the groove the
            // G331 before it cut (the spindle stays in position control between them).
            let reverse = self.cfg.s840 && self.modal.motion == 332;
            let tap_from = self.z;
            if reverse {
                if let (Some(s), Some((inward, revs))) =
                    (sync.as_mut(), self.thread.tap.g331.take())
                {
                    s.angle = tap_back(inward, revs).angle;
                }
            }
            if reverse {
                self.modal.spindle = self.modal.spindle.reversed();
            }
            let done = match sync {
                Some(sync) => {
                    self.nose_note("a thread block");
                    self.thread_block(w, prog, pc, (x, z), sync)
                }
                None => {
                    self.emit(prog, pc, kind, (self.x, self.z), (x, z), sync);
                    self.x = x;
                    self.z = z;
                    Ok(())
                }
            };
            if reverse {
                self.modal.spindle = self.modal.spindle.reversed();
            }
            done?;
            if self.cfg.s840 && self.modal.motion == 331 {
                self.thread.tap.g331 = sync.map(|s| (s, (self.z - tap_from).abs() / s.lead));
            }
        }
        Ok(if end { Step::End } else { Step::Next })
    }

    /// LinuxCNC `G33.1 X Z K` (rigid tapping, rs274's `RIGID_TAP(x, y, z)` canon call;
    /// LinuxCNC manual, G33.1): from the current point, at an index pulse, a move synchronised
    /// to the spindle at K per revolution along the path to the end point; there the spindle
    /// reverses and the tap goes back along the same line, still synchronised (the same
    /// groove), to where it started; the spindle direction is then restored and the block
    /// ends at its start point (rs274's next incremental move counts from there). The
    /// overtravel while the spindle stops and reverses (machine dynamics, not in the
    /// canon) is not modelled. K is the distance per revolution along the path, as G33's:
    /// the z lead is K |dz| / path. A tap off the spindle axis (X not 0) or along a slope is
    /// run as LinuxCNC runs it (its interpreter accepts any end point): the two thread
    /// moves lie where the control puts them. `I` (the return's speed multiplier, LinuxCNC
    /// 2.9) changes no path and is not read. K must be positive.
    fn lc_rigid_tap(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        end: (f64, f64),
        scale: f64,
    ) -> Result<(), Fail> {
        let &(k, col) = w
            .vals
            .get("K")
            .ok_or((1, "G33.1 needs K (the tap's pitch)".to_string()))?;
        if k <= 0.0 || !k.is_finite() {
            return Err((
                col,
                format!("G33.1 with K{k}: the tap's pitch must be positive"),
            ));
        }
        if !self.lc.st.spindle_on {
            return Err((
                1,
                super::linuxcnc::spindle_stopped("Spindle not turning in G33.1"),
            ));
        }
        let k = k * scale;
        let start = (self.x, self.z);
        let (dr, dz) = ((end.0 - start.0) / 2.0, end.1 - start.1);
        let path = dr.hypot(dz);
        if path == 0.0 {
            // rs274 prints the call; nothing moves.
            return Ok(());
        }
        if dz == 0.0 {
            return Err((
                1,
                "G33.1 along X only: a tap needs travel along Z (the spindle axis)".into(),
            ));
        }
        let lead = k * dz.abs() / path;
        let inward = Sync {
            lead,
            change: 0.0,
            angle: 0.0,
        };
        // At the bottom the spindle has turned path / K revolutions; reversed, the angle
        // past the index counts the other way, so the way back (the same helix) starts at
        // minus that.
        let back = tap_back(inward, path / k);
        let spindle = self.modal.spindle;
        self.emit(prog, pc, MoveKind::Thread, start, end, Some(inward));
        self.modal.spindle = spindle.reversed();
        self.emit(prog, pc, MoveKind::Thread, end, start, Some(back));
        self.modal.spindle = spindle;
        // The final placement is unsynchronised: the next thread block waits for the index.
        self.thread.chain_end = None;
        (self.x, self.z) = start;
        Ok(())
    }

    /// A tap on the axis at diameter `x`, `levels` = (from, R point, bottom, return) Z: a
    /// rapid from `from` to the R point, the tap in to the bottom (lead `lead`, spindle as
    /// programmed, at an index pulse), back to the R point with the spindle reversed in the
    /// same groove (`tap_back`), the spindle restored, a rapid to the return level. Moves of
    /// no length are left out.
    pub(super) fn tap_on_axis(
        &mut self,
        prog: &Program,
        pc: usize,
        x: f64,
        levels: (f64, f64, f64, f64),
        lead: f64,
    ) {
        let (from, r, bottom, ret) = levels;
        if from != r {
            self.emit(prog, pc, MoveKind::Rapid, (x, from), (x, r), None);
        }
        let inward = Sync {
            lead,
            change: 0.0,
            angle: 0.0,
        };
        let spindle = self.modal.spindle;
        self.emit(
            prog,
            pc,
            MoveKind::Thread,
            (x, r),
            (x, bottom),
            Some(inward),
        );
        self.modal.spindle = spindle.reversed();
        let back = tap_back(inward, (bottom - r).abs() / lead);
        self.emit(prog, pc, MoveKind::Thread, (x, bottom), (x, r), Some(back));
        self.modal.spindle = spindle;
        if r != ret {
            self.emit(prog, pc, MoveKind::Rapid, (x, r), (x, ret), None);
        }
        self.thread.chain_end = None;
        (self.x, self.z) = (x, ret);
    }

    /// GSK 980TDc `G33 Z(W) F(I)` (the Z tapping cycle, GSK 980TDc manual "G33 Z axis
    /// tapping cycle"): from the current point the tap goes in to Z at F per revolution (I:
    /// threads per inch), the spindle stops and reverses at the bottom and the tap comes back
    /// to the start point, where the spindle is restored; on the spindle axis only (X 0).
    fn gsk_tap(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        end: (f64, f64),
    ) -> Result<(), Fail> {
        let lead = match (w.vals.get("F"), w.vals.get("I")) {
            (Some(&(f, col)), _) if f <= 0.0 => {
                return Err((col, format!("G33 F{f}: the tap's pitch must be positive")))
            }
            (Some(_), _) => self.lead_word(w, "F", "G33")?.unwrap_or(0.0),
            (None, Some(&(i, col))) if i <= 0.0 => {
                return Err((col, format!("G33 I{i}: threads per inch must be positive")))
            }
            (None, Some(&(i, _))) => 25.4 / i,
            (None, None) => {
                return Err((1, "G33 needs F (the pitch) or I (threads per inch)".into()))
            }
        };
        if end.0 != self.x || self.x.abs() > 1e-9 {
            return Err((
                1,
                "G33 tapping off the spindle axis (X not 0) or with an X move is not modelled"
                    .into(),
            ));
        }
        if end.1 == self.z {
            return Ok(());
        }
        let z0 = self.z;
        self.tap_on_axis(prog, pc, self.x, (z0, z0, end.1, z0), lead);
        Ok(())
    }

    /// A feed move (G01, G02/G03, the feed legs of G90/G94) needs a positive feed: with F0,
    /// or before any F, a control alarms (FANUC/GSK alarm 011 "feed zero", Siemens 10860
    /// "feedrate not programmed", LinuxCNC "cannot do G1 with zero feed rate").
    pub(super) fn need_feed(&self, w: &Words) -> Result<(), Fail> {
        let g = self.modal.motion;
        let alarm = match self.real_dialect() {
            Dialect::Fanuc | Dialect::Gsk980 | Dialect::Okuma => "alarm 011, feed zero",
            Dialect::Siemens802d | Dialect::Siemens840d => "alarm 10860, feedrate not programmed",
            Dialect::Linuxcnc => "\"cannot do G1 with zero feed rate\"",
        };
        match self.modal.feed {
            Some(f) if f > 0.0 => Ok(()),
            Some(f) => {
                let col = w.vals.get("F").map_or(1, |v| v.1);
                Err((
                    col,
                    format!("G{g:02} with the feed F{f}: a feed move needs F > 0 (a control alarms: {alarm})"),
                ))
            }
            None => Err((
                1,
                format!(
                    "G{g:02} without a feed: no F has been programmed (a control alarms: {alarm})"
                ),
            )),
        }
    }

    /// The M codes of a block: spindle, chamfering, the end (`end`), subprogram calls and
    /// returns. `Some(step)` when the block calls or returns: its motion is not run.
    pub(super) fn m_words(&mut self, w: &Words, end: &mut bool) -> Result<Option<Step>, Fail> {
        for &mc in &w.m {
            if matches!(mc, 3..=5 | 13 | 14) {
                // A spindle start, stop or reversal: the next thread block waits for the
                // one-rev signal again.
                self.thread.chain_end = None;
            }
            match mc {
                // GSK 980TDc/TDi M14/M15: the spindle under position / speed control (the
                // TDi's G92.1 runs between them), not a direction; M13 no direction either.
                13..=15 if self.cfg.gsk => {}
                3 | 13 => self.modal.spindle = Spindle::Cw,
                4 | 14 => self.modal.spindle = Spindle::Ccw,
                5 | 8 | 9 | 0 | 1 => {}
                // Thread chamfering in G92/G76 on (M23) and off (M24), as on Mach4 lathes.
                23 if self.cfg.dialect == Dialect::Fanuc && !self.cfg.milling => {
                    self.thread.chamfer_on = true
                }
                24 if self.cfg.dialect == Dialect::Fanuc && !self.cfg.milling => {
                    self.thread.chamfer_on = false
                }
                2 | 30 => *end = true,
                17 if self.cfg.dialect == Dialect::Siemens802d => return Ok(Some(Step::Return)),
                98 if self.cfg.dialect == Dialect::Fanuc => {
                    // `M98 P<count><prog>` (the last four digits name O<prog>) or `P<prog> L<n>`.
                    let p = w
                        .vals
                        .get("P")
                        .map(|v| v.0.round() as u64)
                        .ok_or((1, "M98 needs P".to_string()))?;
                    let (times, prog) = match w.vals.get("L") {
                        Some(l) => (l.0.round().max(1.0) as u32, p),
                        None => (((p / 10_000).max(1)) as u32, p % 10_000),
                    };
                    if times > 9999 {
                        return Err((1, format!("M98 repeat count {times} is over 9999")));
                    }
                    return Ok(Some(Step::Call(format!("O{prog}"), times, None)));
                }
                99 if self.cfg.dialect == Dialect::Fanuc => {
                    if let Some(&(p, col)) = w.vals.get("P") {
                        if !(0.0..=99_999.0).contains(&p) || p.fract() != 0.0 {
                            return Err((col, format!("M99 P{p}: expected a sequence number")));
                        }
                        return Ok(Some(Step::ReturnTo(p as u32)));
                    }
                    return Ok(Some(Step::Return));
                }
                other => {
                    match codes::m_verdict(self.real_dialect(), self.cfg.milling, f64::from(other))
                    {
                        Verdict::Run => {}
                        Verdict::Refused(msg) => return Err((1, msg)),
                        Verdict::Unknown(msg) => self.unknown(1, msg)?,
                    }
                }
            }
        }
        Ok(None)
    }

    /// Record a move of the block at `pc` from `a` to `b` (diameter, z); `sync` makes it a
    /// thread move.
    pub(super) fn emit(
        &mut self,
        prog: &Program,
        pc: usize,
        kind: MoveKind,
        a: (f64, f64),
        b: (f64, f64),
        sync: Option<Sync>,
    ) {
        self.emit_in(&prog.name, prog.blocks[pc].0, kind, a, b, sync);
    }

    /// [`Interp::emit`] for a block given by its file and 1-based line.
    pub(super) fn emit_in(
        &mut self,
        file: &str,
        line: usize,
        kind: MoveKind,
        a: (f64, f64),
        b: (f64, f64),
        sync: Option<Sync>,
    ) {
        if self.out.moves.len() >= self.cfg.limits.max_moves {
            // The run stops after this block (`Interp::run`); nothing more is kept.
            self.out.too_many_moves = true;
            return;
        }
        // The tool's point is where the program drives it plus the active tool offset; a
        // move starts where the last one ended and absorbs a change of offset.
        let shift = self.offset_shift();
        let a = (a.0 + self.out.applied.0, a.1 + self.out.applied.1);
        let b = (b.0 + shift.0, b.1 + shift.1);
        self.out.applied = shift;
        let speed = self.spindle_speed();
        let feed = self.modal.feed.map(|f| Feed {
            value: f * if self.modal.inch { 25.4 } else { 1.0 },
            per_rev: self.modal.per_rev,
        });
        self.out.inch_threads |= kind == MoveKind::Thread && self.modal.inch;
        self.out.moves.push(Move {
            file: file.to_string(),
            line,
            kind,
            x_start: a.0,
            z_start: a.1,
            x_dia: b.0,
            z: b.1,
            lead: sync.map(|s| s.lead),
            lead_change: sync.map(|s| s.change),
            sync_angle_deg: sync.map(|s| s.angle),
            chained: false,
            tool: self.modal.tool,
            tool_word: self.modal.tool_word.clone(),
            spindle: self.modal.spindle,
            arc: None,
            speed,
            feed,
            cycle: self.out.cycle && kind == MoveKind::Thread,
            nose: self.nose_now(kind),
        });
        // Only a thread block (`Interp::thread_block`) leaves a chain open.
        self.thread.chain_end = None;
    }

    /// G02/G03 in the XZ plane from the current point to `end` (diameter, z): centre from
    /// `R` (Siemens `CR=`; positive: the arc of at most 180 deg, negative: the longer one)
    /// or from `I`/`K` (centre minus start, or under LinuxCNC's G90.1 the centre; I is a
    /// radius value in every X mode, as FANUC and Siemens lathes, Beckhoff's G51 diameter
    /// mode and rs274 write it). The end must lie on
    /// the circle through the start within `ARC_TOLERANCE`.
    fn arc(&mut self, w: &Words, prog: &Program, pc: usize, end: (f64, f64)) -> Result<(), Fail> {
        let g = self.modal.motion;
        let cw = g == 2;
        // rs274 draws a G2/G3 in the plane G17/G19 select (XY, YZ): vpcut's lathe moves
        // are in XZ only.
        if self.cfg.dialect == Dialect::Linuxcnc && self.lc.st.plane != 180 {
            let (name, axes) = if self.lc.st.plane == 170 {
                ("G17", "XY")
            } else {
                ("G19", "YZ")
            };
            return Err((
                1,
                format!("G{g} in the {name} plane ({axes}) is not simulated: vpcut's lathe arcs are in the XZ plane (G18)"),
            ));
        }
        let radius_word = if self.cfg.dialect == Dialect::Siemens802d {
            "CR"
        } else {
            "R"
        };
        // (u, v) = (z, radius): the plane seen from +Y, Z to the right, X up.
        let a = (self.z, self.x / 2.0);
        let b = (end.1, end.0 / 2.0);
        let centre = if let Some(&(_, col)) = w.vals.get(radius_word) {
            let r = self.length(w, radius_word).unwrap_or(0.0);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let chord = dx.hypot(dy);
            if chord == 0.0 || r == 0.0 {
                return Err((
                    col,
                    format!("G{g:02} with {radius_word}: expected a nonzero radius and an end point away from the start"),
                ));
            }
            let half = chord / 2.0;
            if half > r.abs() + ARC_TOLERANCE {
                return Err((
                    col,
                    format!(
                        "G{g:02}: the end point is {chord:.4} mm from the start, more than the diameter {:.4} of radius {}",
                        2.0 * r.abs(),
                        r.abs()
                    ),
                ));
            }
            radius_centre(a, b, r, cw)
        } else if w.vals.contains_key("I") || w.vals.contains_key("K") {
            let i = self.length(w, "I").unwrap_or(0.0);
            let k = self.length(w, "K").unwrap_or(0.0);
            // LinuxCNC G90.1: I and K are the centre itself, in the program's frame
            // (work offset and G92 applied; I a radius value in G7 too, as rs274 reads it).
            let c = if self.cfg.dialect == Dialect::Linuxcnc && self.lc.st.ijk_absolute {
                let (ox, oz) = self.frames.offsets[self.frames.work];
                let (gx, gz) = self.frames.g92_off;
                (oz + gz + k, (ox + gx) / 2.0 + i)
            } else {
                (a.0 + k, a.1 + i)
            };
            let (ra, rb) = ((a.0 - c.0).hypot(a.1 - c.1), (b.0 - c.0).hypot(b.1 - c.1));
            if (ra - rb).abs() > ARC_TOLERANCE {
                let col = w.vals.get("I").or(w.vals.get("K")).map_or(1, |v| v.1);
                return Err((
                    col,
                    format!(
                        "G{g:02}: the end point is off the circle: {rb:.4} mm from the centre, the start {ra:.4} mm (tolerance {ARC_TOLERANCE} mm)"
                    ),
                ));
            }
            c
        } else {
            return Err((
                1,
                format!("G{g:02} needs {radius_word} (the radius) or I/K (the centre)"),
            ));
        };
        self.emit(prog, pc, MoveKind::Arc, (self.x, self.z), end, None);
        // The circle moves with the tool offset, as the end point does.
        let shift = self.out.applied;
        if let Some(last) = self.out.moves.last_mut() {
            last.arc = Some(ArcGeometry {
                x_centre_dia: 2.0 * centre.1 + shift.0,
                z_centre: centre.0 + shift.1,
                clockwise: cw,
            });
        }
        self.x = end.0;
        self.z = end.1;
        Ok(())
    }

    /// Run a threading cycle's block: its thread moves are marked as a cycle's
    /// ([`Move::cycle`]).
    pub(super) fn in_cycle<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        self.nose_note("a threading cycle");
        self.out.cycle = true;
        let r = f(self);
        self.out.cycle = false;
        r
    }

    /// The spindle speed as the program has set it so far.
    pub(super) fn spindle_speed(&self) -> SpindleSpeed {
        let max = match self.cfg.dialect {
            Dialect::Linuxcnc => self.lc.st.max_rpm,
            _ => self.modal.speed_max,
        };
        if self.modal.css {
            // G96's S is m/min, or ft/min in inch mode.
            let unit = if self.modal.inch { 0.3048 } else { 1.0 };
            SpindleSpeed {
                rpm: None,
                surface: self.modal.speed.map(|v| v * unit),
                max,
            }
        } else {
            SpindleSpeed {
                rpm: self.modal.speed,
                surface: None,
                max,
            }
        }
    }

    /// Call tool offset `n` (0 cancels) at the block's column `col`: a number the job's
    /// offsets lack is a warning (taken as zero), as is a call when the job gives none.
    pub(super) fn call_offset(&mut self, n: u32, col: usize) {
        self.modal.offset = (n > 0).then_some(n);
        if n == 0 {
            return;
        }
        if let Some(table) = &self.cfg.offsets {
            if !table.contains_key(&n) {
                self.out.notes.push((
                    col,
                    format!("tool offset {n} is not in the job's [machine] offsets: taken as zero"),
                    "the control applies whatever its offset page holds for this number; give it in the job (`[machine] offsets`)".into(),
                ));
            }
        }
    }

    /// The active tool offset's shift (X diameter, Z), zero without one.
    pub(super) fn offset_shift(&self) -> (f64, f64) {
        match (self.modal.offset, &self.cfg.offsets) {
            (Some(n), Some(table)) => table.get(&n).copied().unwrap_or((0.0, 0.0)),
            _ => (0.0, 0.0),
        }
    }

    /// A dwell block (G04 / G4): FANUC/GSK `X` or `U` in seconds, `P` in milliseconds;
    /// Siemens `F` in seconds, `S` in spindle revolutions; LinuxCNC `P` in seconds. The
    /// axes do not move.
    fn dwell(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let time = match self.cfg.dialect {
            Dialect::Fanuc => match (val("X").or(val("U")), val("P")) {
                (Some(s), _) => DwellTime::Seconds(s),
                (None, Some(ms)) => DwellTime::Seconds(ms / 1000.0),
                (None, None) => return Err((1, "G04 needs X, U (seconds) or P (ms)".into())),
            },
            Dialect::Siemens802d | Dialect::Siemens840d => match (val("F"), val("S")) {
                (Some(s), _) => DwellTime::Seconds(s),
                (None, Some(r)) => DwellTime::Revolutions(r),
                (None, None) => return Err((1, "G4 needs F (seconds) or S (revolutions)".into())),
            },
            _ => match val("P") {
                Some(s) => DwellTime::Seconds(s),
                None => return Err((1, "G4 needs P (seconds)".into())),
            },
        };
        let (DwellTime::Seconds(t) | DwellTime::Revolutions(t)) = time;
        if !(t >= 0.0 && t.is_finite()) {
            return Err((1, format!("a dwell of {t}: expected a time of at least 0")));
        }
        self.out.dwells.push(Dwell {
            after: self.out.moves.len(),
            time,
            speed: self.spindle_speed(),
            x: self.x,
            file: prog.name.clone(),
            line: prog.blocks[pc].0,
        });
        Ok(Step::Next)
    }

    /// One pass of a threading cycle: rapid from `home` to the start (Z first, then X),
    /// thread to `end`, rapid out to home's X and back to home's Z (zero-length rapids are
    /// left out), with a thread pull-out `(chamfer, rise)` in mm (`chamfer` 0 = none; less
    /// than the Z travel): the thread runs to `chamfer` before `end`'s Z, then a second
    /// thread move, continuing the same sync (lead and spindle phase, no new index wait: see
    /// `Sync::after`), goes out by `rise` in radius towards home's X while Z runs on to
    /// `end`'s Z (FANUC's chamfer: `rise = chamfer`, 45 deg; GSK's run-out J/K: `rise` J over
    /// `chamfer` K). The rapid retract then starts from there.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn cycle_pass_chamfered(
        &mut self,
        prog: &Program,
        pc: usize,
        home: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        sync: Sync,
        (chamfer, rise): (f64, f64),
    ) {
        let path = [home, (home.0, start.1), start];
        for w in path.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
        }
        let len = (end.1 - start.1).abs();
        let end = if chamfer > 0.0 && chamfer < len {
            let u = (len - chamfer) / len;
            let split = (
                start.0 + u * (end.0 - start.0),
                start.1 + u * (end.1 - start.1),
            );
            let side = if home.0 >= end.0 { 1.0 } else { -1.0 };
            let out = (split.0 + side * 2.0 * rise, end.1);
            self.emit(prog, pc, MoveKind::Thread, start, split, Some(sync));
            // Constant lead: always defined (a lead that is not positive is refused below,
            // at the block, as every thread move's is).
            let chained = sync.after(len - chamfer).unwrap_or(sync);
            self.emit(prog, pc, MoveKind::Thread, split, out, Some(chained));
            // The pull-out continues the thread without a re-sync (already at speed).
            if let Some(last) = self.out.moves.last_mut() {
                last.chained = true;
            }
            out
        } else {
            self.emit(prog, pc, MoveKind::Thread, start, end, Some(sync));
            end
        };
        let back = [end, (home.0, end.1), home];
        for w in back.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
        }
    }
}
