//! LinuxCNC's threading cycle G76 as rs274 2.9.0~pre1's `convert_threading_cycle` makes it:
//! every pass and every rapid (tests: `tests/integration/linuxcnc.rs`).

use super::expr::Fail;
use super::{Interp, MoveKind, Program, Step, Sync, Words};

impl Interp<'_> {
    /// LinuxCNC G76 (`controllers.md` 2.5, from `Interp::convert_threading_cycle`): the
    /// drive line is the current X; pass n is cut `|I| + J n^(1/R)` from it while that is
    /// less than `|I| + K`, then at `|I| + K` once plus H spring passes; each pass is shifted
    /// by `(depth - |I|) tan Q` in z and ends at `Z + K tan Q` less that shift. In G7, I, J
    /// and K are diameters. Reproduced against rs274's output in the tests.
    pub(super) fn lcnc_g76(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        if !self.lc.st.spindle_on {
            return Err((
                1,
                super::linuxcnc::spindle_stopped("Chosen spindle (0) not turning in G76"),
            ));
        }
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let half = if self.modal.diameter_mode { 0.5 } else { 1.0 };
        let pitch = val("P").ok_or((1, "G76 needs P (the pitch)".to_string()))? * scale;
        // Z is in the work frame (work offset and G92), or under G91 from the current Z,
        // as rs274 has it.
        let frame_z = if self.modal.incremental {
            self.z
        } else {
            self.frames.offsets[self.frames.work].1 + self.frames.g92_off.1
        };
        let end_z = val("Z").ok_or((1, "G76 needs Z".to_string()))? * scale + frame_z;
        let i = val("I").ok_or((
            1,
            "G76 needs I (crest offset from the drive line)".to_string(),
        ))? * scale
            * half;
        let j = val("J").unwrap_or(0.0) * scale * half;
        let k = val("K").unwrap_or(0.0) * scale * half;
        if i == 0.0 || j <= 0.0 || k <= j || pitch <= 0.0 {
            return Err((1, "G76 needs I != 0, J > 0, K > J and P > 0".into()));
        }
        let taper_len = val("E").unwrap_or(0.0) * scale;
        if taper_len < 0.0 {
            return Err((1, "G76 E (the taper length) must not be negative".into()));
        }
        // L1 entry taper, L2 exit taper, L3 both; rs274 tapers nothing when E is 0.
        let (entry, exit) = match val("L").unwrap_or(0.0) {
            0.0 => (false, false),
            1.0 => (true, false),
            2.0 => (false, true),
            3.0 => (true, true),
            l => return Err((1, format!("G76 L{l}: expected L0, L1, L2 or L3"))),
        };
        let (entry, exit) = (entry && taper_len > 0.0, exit && taper_len > 0.0);
        let mut degression = val("R").unwrap_or(1.0);
        if degression < 1.0 {
            degression = 1.0;
        }
        let (x0, start_z) = (self.x / 2.0, self.z); // drive line, radius
        let mut angle = val("Q").unwrap_or(0.0).to_radians();
        if end_z > start_z {
            angle = -angle;
        }
        let springs = val("H").unwrap_or(0.0).max(0.0);
        if springs >= self.cfg.limits.max_moves as f64 {
            let col = w.vals.get("H").map_or(1, |v| v.1);
            return Err((
                col,
                format!(
                    "G76 H{springs}: more spring passes than the {} moves a program may make",
                    self.cfg.limits.max_moves
                ),
            ));
        }
        let springs = springs as u32;
        let full = i.abs();
        let end_depth = k.abs() + full;
        let target_z = end_z + k.abs() * angle.tan();
        // External (I < 0): passes below the drive line; internal: above.
        let side = if i < 0.0 { -1.0 } else { 1.0 };
        let mut depths = Vec::new();
        let mut depth = full + j.abs();
        let mut n = 1.0f64;
        while depth < end_depth {
            depths.push(depth);
            if depths.len() > 100_000 {
                return Err((1, "G76 would cut more than 100000 passes".into()));
            }
            n += 1.0;
            depth = full + j.abs() * n.powf(1.0 / degression);
        }
        for _ in 0..=springs {
            depths.push(end_depth);
        }
        let dir = if end_z < start_z { -1.0 } else { 1.0 };
        // rs274 2.9.0~pre1 does not check this; tapers longer than the pass are refused.
        let tapers = u8::from(entry) + u8::from(exit);
        if f64::from(tapers) * taper_len > (target_z - start_z).abs() {
            return Err((
                1,
                "G76 E: the tapers are longer than the drive line (E > half of it with L3)".into(),
            ));
        }
        // rs274's moves, pass by pass (checked against its canon output): a rapid straight
        // to the pass's retract point `K + |I|` above the pass at its start Z (diagonal from
        // the previous pass's end), then either a rapid down to the pass (no entry taper) or
        // the synchronised radial move down to the taper start `K` above it; the thread; a
        // rapid out to the retract X at the end Z. After the last pass a rapid to the drive
        // line at the end Z, where the cycle leaves the tool.
        let mut end = (self.x, self.z);
        for d in depths {
            let zoff = (d - full) * angle.tan();
            let x = 2.0 * (x0 + side * d);
            let (zs, ze) = (start_z - zoff, target_z - zoff);
            let retract = 2.0 * (x0 + side * (d - k.abs() - full));
            let rapid = |m: &mut Self, a: (f64, f64), b: (f64, f64)| {
                if a != b {
                    m.emit(prog, pc, MoveKind::Rapid, a, b, None);
                }
            };
            rapid(self, end, (retract, zs));
            let kx = 2.0 * (x0 + side * (d - k.abs()));
            if tapers > 0 {
                // rs274: with an entry taper, from the retract line a synchronised radial
                // move (|I| long) to the taper start K above the pass, then the taper over E;
                // else a rapid to the pass. Then the pass, and with an exit taper the taper
                // back up by K over E. Feeds are per path length (P hypot(E,K)/E on the
                // tapers), so the axial lead is P throughout; the radial move uses up
                // |I| / (P hypot(E,K)/E) revolutions before the entry taper starts. It is
                // listed as a feed move: it advances no Z, so it cuts no thread.
                let p_taper = pitch * taper_len.hypot(k.abs()) / taper_len;
                let mut revs = if entry { full / p_taper } else { 0.0 };
                let z1 = if entry { zs + dir * taper_len } else { zs };
                let z2 = if exit { ze - dir * taper_len } else { ze };
                if entry {
                    self.emit(prog, pc, MoveKind::Feed, (retract, zs), (kx, zs), None);
                } else {
                    rapid(self, (retract, zs), (x, zs));
                }
                let mut segments = Vec::with_capacity(3);
                if entry {
                    segments.push((kx, zs, x, z1));
                }
                segments.push((x, z1, x, z2));
                if exit {
                    segments.push((x, z2, kx, ze));
                }
                let mut last = (x, ze);
                for (i, (xa, za, xb, zb)) in segments.into_iter().enumerate() {
                    let sync = Sync {
                        lead: pitch,
                        change: 0.0,
                        angle: (revs * 360.0).rem_euclid(360.0),
                    };
                    self.emit(prog, pc, MoveKind::Thread, (xa, za), (xb, zb), Some(sync));
                    // The segments after the first continue one synchronised motion.
                    if let Some(last) = self.out.moves.last_mut() {
                        last.chained = i > 0 || entry;
                    }
                    revs += (zb - za).abs() / pitch;
                    last = (xb, zb);
                }
                rapid(self, last, (retract, ze));
            } else {
                rapid(self, (retract, zs), (x, zs));
                let sync = Sync {
                    lead: pitch,
                    change: 0.0,
                    angle: 0.0,
                };
                self.emit(prog, pc, MoveKind::Thread, (x, zs), (x, ze), Some(sync));
                rapid(self, (x, ze), (retract, ze));
            }
            end = (retract, ze);
        }
        let home = (2.0 * x0, end.1);
        if end != home {
            self.emit(prog, pc, MoveKind::Rapid, end, home, None);
        }
        (self.x, self.z) = home;
        Ok(Step::Next)
    }
}
