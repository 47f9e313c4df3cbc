//! Modal state and motion: G/M codes, tool and spindle words, X/Z/U/W end points, thread
//! moves of every dialect, and the recording of moves and threading-cycle passes.

use super::expr::Fail;
use super::{Dialect, Machine, Move, MoveKind, Program, Step, Sync, Words};
use crate::helix::Spindle;

impl Machine<'_> {
    /// Modal state and motion of one block's words.
    pub(super) fn apply(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.inch { 25.4 } else { 1.0 };
        let mut set_position = false;
        for &g in &w.g {
            match g {
                0 | 1 | 32 | 33 | 34 | 35 => self.motion = g,
                // G92 is the threading cycle on FANUC/GSK lathes, an offset on LinuxCNC.
                92 if self.dialect == Dialect::Fanuc && !self.lcnc => self.motion = 92,
                90 => self.incremental = false,
                91 => self.incremental = true,
                20 => self.inch = true,
                21 => self.inch = false,
                70 if self.dialect == Dialect::Siemens802d => self.inch = true,
                71 if self.dialect == Dialect::Siemens802d => self.inch = false,
                7 if self.lcnc => self.diameter_mode = true,
                8 if self.lcnc => self.diameter_mode = false,
                // FANUC/GSK G50 with X/Z sets the coordinates of the current position.
                50 if self.dialect == Dialect::Fanuc && !self.lcnc => set_position = true,
                17 | 18 | 40 | 54..=59 | 64 | 94 | 95 | 96 | 97 | 98 | 99 => {}
                other => return Err((1, format!("G{other} is not supported yet"))),
            }
        }
        let mut end = false;
        for &mc in &w.m {
            match mc {
                3 | 13 => self.spindle = Spindle::Cw,
                4 | 14 => self.spindle = Spindle::Ccw,
                5 | 8 | 9 | 0 | 1 => {}
                2 | 30 => end = true,
                17 if self.dialect == Dialect::Siemens802d => return Ok(Step::Return),
                98 if self.dialect == Dialect::Fanuc => {
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
                    return Ok(Step::Call(format!("O{prog}"), times, None));
                }
                99 if self.dialect == Dialect::Fanuc => {
                    if w.vals.contains_key("P") {
                        return Err((
                            1,
                            "M99 P (return to a sequence number) is not supported yet".into(),
                        ));
                    }
                    return Ok(Step::Return);
                }
                98 | 99 => {
                    return Err((
                        1,
                        format!("M{mc} is not a Siemens word: call subprograms by name"),
                    ))
                }
                other => return Err((1, format!("M{other} is not supported yet"))),
            }
        }
        if let Some(&(t, _)) = w.vals.get("T") {
            let t = t.round() as u32;
            self.tool = Some(if self.dialect == Dialect::Fanuc && t >= 100 {
                t / 100
            } else {
                t
            });
        }
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let scale = if self.inch { 25.4 } else { scale };
        let mut x = self.x;
        let mut z = self.z;
        let mut moved = false;
        let xs = if self.diameter_mode { 1.0 } else { 2.0 };
        if let Some(v) = val("X").map(|v| v * xs) {
            x = if self.incremental {
                self.x + v * scale
            } else {
                v * scale
            };
            moved = true;
        }
        if let Some(v) = val("Z") {
            z = if self.incremental {
                self.z + v * scale
            } else {
                v * scale
            };
            moved = true;
        }
        if self.dialect == Dialect::Fanuc {
            if let Some(v) = val("U") {
                x = self.x + v * scale;
                moved = true;
            }
            if let Some(v) = val("W") {
                z = self.z + v * scale;
                moved = true;
            }
        }
        if set_position {
            self.x = x;
            self.z = z;
            return Ok(if end { Step::End } else { Step::Next });
        }
        if moved && self.dialect == Dialect::Fanuc && self.motion == 92 && !self.lcnc {
            return self.g92(w, prog, pc, x, z, scale);
        }
        if moved {
            let (kind, lead, change, angle) = match (self.dialect, self.motion) {
                (_, 0) => (MoveKind::Rapid, None, None, None),
                (_, 1) => (MoveKind::Feed, None, None, None),
                (Dialect::Linuxcnc, 33) => {
                    let k = val("K").ok_or((1, "G33 needs K (the pitch)".to_string()))? * scale;
                    (MoveKind::Thread, Some(k), Some(0.0), Some(0.0))
                }
                (Dialect::Fanuc, 34) if self.gsk => {
                    return self.gsk_g34(w, prog, pc, x, z, scale);
                }
                (Dialect::Fanuc, 32) | (Dialect::Fanuc, 34) => {
                    let f = val("F").ok_or((1, format!("G{} needs F (the lead)", self.motion)))?
                        * scale;
                    let k = if self.motion == 34 {
                        val("K").unwrap_or(0.0) * scale
                    } else {
                        0.0
                    };
                    let q = val("Q").unwrap_or(0.0) / 1000.0;
                    (MoveKind::Thread, Some(f), Some(k), Some(q))
                }
                (Dialect::Siemens802d, 33..=35) => {
                    let k = val("K")
                        .or(val("I"))
                        .ok_or((1, format!("G{} needs K (the lead)", self.motion)))?
                        * scale;
                    let f = if self.motion == 33 {
                        0.0
                    } else {
                        val("F").unwrap_or(0.0).abs() * scale
                    };
                    let f = if self.motion == 35 { -f } else { f };
                    (
                        MoveKind::Thread,
                        Some(k),
                        Some(f),
                        Some(val("SF").unwrap_or(0.0)),
                    )
                }
                (_, g) => {
                    return Err((
                        1,
                        format!("G{g} moves are not supported in this dialect yet"),
                    ))
                }
            };
            let sync = lead.map(|lead| Sync {
                lead,
                change: change.unwrap_or(0.0),
                angle: angle.unwrap_or(0.0),
            });
            self.emit(prog, pc, kind, (self.x, self.z), (x, z), sync);
            self.x = x;
            self.z = z;
        }
        Ok(if end { Step::End } else { Step::Next })
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
        self.moves.push(Move {
            file: prog.name.clone(),
            line: prog.blocks[pc].0,
            kind,
            x_start: a.0,
            z_start: a.1,
            x_dia: b.0,
            z: b.1,
            lead: sync.map(|s| s.lead),
            lead_change: sync.map(|s| s.change),
            sync_angle_deg: sync.map(|s| s.angle),
            tool: self.tool,
            spindle: self.spindle,
        });
    }

    /// One pass of a threading cycle: rapid from `home` to the start (Z first, then X),
    /// thread to `end`, rapid out to home's X and back to home's Z. Zero-length rapids are
    /// left out.
    pub(super) fn cycle_pass(
        &mut self,
        prog: &Program,
        pc: usize,
        home: (f64, f64),
        start: (f64, f64),
        end: (f64, f64),
        sync: Sync,
    ) {
        let path = [home, (home.0, start.1), start];
        for w in path.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
        }
        self.emit(prog, pc, MoveKind::Thread, start, end, Some(sync));
        let back = [end, (home.0, end.1), home];
        for w in back.windows(2) {
            if w[0] != w[1] {
                self.emit(prog, pc, MoveKind::Rapid, w[0], w[1], None);
            }
        }
    }
}
