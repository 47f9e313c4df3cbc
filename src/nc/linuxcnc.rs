//! LinuxCNC: the G76 threading cycle, as `Interp::convert_threading_cycle` computes it.

use super::expr::Fail;
use super::{Machine, MoveKind, Program, Step, Sync, Words};

impl Machine<'_> {
    /// LinuxCNC G76 (`controllers.md` 2.5, from `Interp::convert_threading_cycle`): the
    /// drive line is the current X; pass n is cut `|I| + J n^(1/R)` from it while that is
    /// less than `|I| + K`, then at `|I| + K` once plus H spring passes; each pass is shifted
    /// by `(depth - |I|) tan Q` in z and ends at `Z + K tan Q` less that shift. In G7, I, J
    /// and K are diameters. Reproduced against rs274's output in the tests.
    pub(super) fn lcnc_g76(&mut self, w: &Words, prog: &Program, pc: usize) -> Result<Step, Fail> {
        let scale = if self.inch { 25.4 } else { 1.0 };
        let val = |k: &str| w.vals.get(k).map(|v| v.0);
        let half = if self.diameter_mode { 0.5 } else { 1.0 };
        let pitch = val("P").ok_or((1, "G76 needs P (the pitch)".to_string()))? * scale;
        let end_z = val("Z").ok_or((1, "G76 needs Z".to_string()))? * scale;
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
        let tapers = match val("L").unwrap_or(0.0).round() as i64 {
            0 => false,
            3 if taper_len > 0.0 => true,
            3 => return Err((1, "G76 L3 needs a taper length E > 0".into())),
            _ => {
                return Err((
                    1,
                    "G76 entry-only or exit-only tapers (L1, L2) are not supported yet".into(),
                ))
            }
        };
        let mut degression = val("R").unwrap_or(1.0);
        if degression < 1.0 {
            degression = 1.0;
        }
        let (x0, start_z) = (self.x / 2.0, self.z); // drive line, radius
        let mut angle = val("Q").unwrap_or(0.0).to_radians();
        if end_z > start_z {
            angle = -angle;
        }
        let springs = val("H").unwrap_or(0.0).max(0.0) as u32;
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
        if tapers && 2.0 * taper_len > (target_z - start_z).abs() {
            return Err((1, "G76 E is greater than half the drive line length".into()));
        }
        for d in depths {
            let zoff = (d - full) * angle.tan();
            let x = 2.0 * (x0 + side * d);
            let (zs, ze) = (start_z - zoff, target_z - zoff);
            if tapers {
                // rs274: from the retract line, a synchronised radial move (|I| long) to the
                // taper start K above the pass, the entry taper over E, the pass, and the
                // exit taper back up by K. Feeds are per path length (P hypot(E,K)/E on the
                // tapers), so the axial lead is P throughout; the radial move uses up
                // |I| / (P hypot(E,K)/E) revolutions before the entry taper starts.
                let kx = 2.0 * (x0 + side * (d - k.abs()));
                let p_taper = pitch * taper_len.hypot(k.abs()) / taper_len;
                let mut revs = full / p_taper;
                let (z1, z2) = (zs + dir * taper_len, ze - dir * taper_len);
                let segments = [(kx, zs, x, z1), (x, z1, x, z2), (x, z2, kx, ze)];
                for (xa, za, xb, zb) in segments {
                    let sync = Sync {
                        lead: pitch,
                        change: 0.0,
                        angle: (revs * 360.0).rem_euclid(360.0),
                    };
                    self.emit(prog, pc, MoveKind::Thread, (xa, za), (xb, zb), Some(sync));
                    revs += (zb - za).abs() / pitch;
                }
                continue;
            }
            let sync = Sync {
                lead: pitch,
                change: 0.0,
                angle: 0.0,
            };
            self.cycle_pass(prog, pc, (2.0 * x0, start_z), (x, zs), (x, ze), sync);
        }
        Ok(Step::Next)
    }
}
