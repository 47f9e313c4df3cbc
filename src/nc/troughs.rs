//! G71/G72 roughing of a finishing shape with troughs (pockets): a shape that goes back
//! towards the start level in the stepping axis (`cycles::rough` sends it here).
//!
//! Haas lathe operator's manual, "G71 O.D./I.D. Stock Removal Cycle", "Troughs": all the
//! material above the troughs is roughed first, then the troughs in the direction of Z,
//! in type 1 and type 2 alike. FANUC 0i-TF, "Stock removal in turning (G71)": type II (block
//! P names both axes) roughs pockets; type I alarms PS0064 on a shape that is not monotonic
//! (the caller warns). The moves vpcut makes, at the levels `dd` apart as type I's:
//!
//! - first, at every level, the pass from the start point's `b` to where the shape first
//!   rises through the level (as type I), 45 deg retract, rapid back;
//! - then, level by level from the top, every further stretch along `b` where the shape
//!   lies below the level (a trough at that depth), in the order along `b`: a rapid down
//!   from the start level to the level above, a feed plunge to the level (into stock not yet
//!   cut), the pass along the level to where the shape rises again, a retract of `e` back at
//!   45 deg (no more than the stretch is long) and a rapid up to the start level.
//!
//! So every rapid runs through material that an earlier pass removed (a stretch at one
//! level lies within a stretch at the level above), and every pass stops at the shape
//! moved by the allowance. The last pass along the whole shape (the caller's) finishes the
//! troughs' walls. The retract paths differ from a control's (FANUC's type II follows the
//! shape up to the level above; Haas retracts by setting 73); the material removed is the
//! same.

use super::cycles::{step, Frame, Seg};
use super::expr::Fail;
use super::{Interp, Move, MoveKind, Program};

/// Points of a move as a function of `u` in [0, 1] along it: a line, or an arc by its angle.
fn point(mv: &Move, u: f64) -> (f64, f64) {
    match mv.arc {
        None => (
            mv.x_start + u * (mv.x_dia - mv.x_start),
            mv.z_start + u * (mv.z - mv.z_start),
        ),
        Some(g) => {
            let (c, t0, sweep, r) = arc_angles(mv, g);
            let t = t0 + u * sweep;
            (2.0 * (c.1 + r * t.sin()), c.0 + r * t.cos())
        }
    }
}

/// An arc's centre (z, radius), start angle, signed sweep (counter-clockwise positive, in
/// the Z-right, X-up plane) and radius.
fn arc_angles(mv: &Move, g: super::ArcGeometry) -> ((f64, f64), f64, f64, f64) {
    let c = (g.z_centre, g.x_centre_dia / 2.0);
    let ang = |z: f64, r: f64| (r - c.1).atan2(z - c.0);
    let (t0, t1) = (ang(mv.z_start, mv.x_start / 2.0), ang(mv.z, mv.x_dia / 2.0));
    let tau = std::f64::consts::TAU;
    let mut sweep = if g.clockwise {
        -(t0 - t1).rem_euclid(tau)
    } else {
        (t1 - t0).rem_euclid(tau)
    };
    if sweep == 0.0 {
        sweep = if g.clockwise { -tau } else { tau };
    }
    let r = (mv.z_start - c.0).hypot(mv.x_start / 2.0 - c.1);
    (c, t0, sweep, r)
}

/// Where along `mv` (u in (0, 1)) the stepping axis `a` passes `level` (`f` the frame).
fn crossings(f: Frame, mv: &Move, level: f64) -> Vec<f64> {
    let a_of = |p: (f64, f64)| f.ab(p).0;
    match mv.arc {
        None => {
            let (a0, a1) = (a_of((mv.x_start, mv.z_start)), a_of((mv.x_dia, mv.z)));
            if a0 == a1 {
                return Vec::new();
            }
            let t = (level - a0) / (a1 - a0);
            if t > 0.0 && t < 1.0 {
                vec![t]
            } else {
                Vec::new()
            }
        }
        Some(g) => {
            let (c, t0, sweep, r) = arc_angles(mv, g);
            // The level as a line of the Z-right, X-up plane: radius = level (G71) or z =
            // level (G72); the angles where the circle meets it.
            let (centre, sin_axis) = if f.facing { (c.0, false) } else { (c.1, true) };
            let q = (level - centre) / r;
            if !(-1.0..=1.0).contains(&q) || (1.0 - q.abs()) < 1e-12 {
                return Vec::new();
            }
            let base = if sin_axis { q.asin() } else { q.acos() };
            let cands = if sin_axis {
                [base, std::f64::consts::PI - base]
            } else {
                [base, -base]
            };
            let tau = std::f64::consts::TAU;
            let mut us: Vec<f64> = cands
                .iter()
                .filter(|&&t| within(t, t0, sweep))
                .map(|&t| {
                    let off = if sweep > 0.0 {
                        (t - t0).rem_euclid(tau)
                    } else {
                        -(t0 - t).rem_euclid(tau)
                    };
                    off / sweep
                })
                .collect();
            us.sort_by(f64::total_cmp);
            us
        }
    }
}

/// The stretches along `b` where the shape lies below `level` (on the start's side `s` of
/// it the shape is above): `(b_in, b_out, opens)` in the order along the shape; `opens`
/// says the stretch starts at the shape's first point (the first pass's stretch).
pub(super) fn stretches(f: Frame, segs: &[&Seg], s: f64, level: f64) -> Vec<(f64, f64, bool)> {
    let below = |p: (f64, f64)| s * (f.ab(p).0 - level) < -1e-9;
    let mut out: Vec<(f64, f64, bool)> = Vec::new();
    let mut open: Option<(f64, bool)> = None;
    let mut first = true;
    for sg in segs {
        let mut us = vec![0.0];
        us.extend(crossings(f, &sg.mv, level));
        us.push(1.0);
        for w in us.windows(2) {
            let (u0, u1) = (w[0], w[1]);
            if u1 - u0 <= 0.0 {
                continue;
            }
            let mid = point(&sg.mv, 0.5 * (u0 + u1));
            let b0 = f.ab(point(&sg.mv, u0)).1;
            match (below(mid), open) {
                (true, None) => open = Some((b0, first && u0 == 0.0)),
                (false, Some((st, opens))) => {
                    out.push((st, b0, opens));
                    open = None;
                }
                _ => {}
            }
            first = false;
        }
    }
    if let (Some((st, opens)), Some(last)) = (open, segs.last()) {
        out.push((st, f.ab((last.mv.x_dia, last.mv.z)).1, opens));
    }
    out
}

/// Whether angle `t` lies strictly inside the sweep from `t0` (signed, radians).
fn within(t: f64, t0: f64, sweep: f64) -> bool {
    let tau = std::f64::consts::TAU;
    let off = if sweep > 0.0 {
        (t - t0).rem_euclid(tau)
    } else {
        -(t0 - t).rem_euclid(tau)
    };
    off.abs() > 1e-12 && off.abs() < sweep.abs() - 1e-12
}

/// The lowest point of the shape on the start's side `s` (its least `s a`): the moves' ends
/// and the arcs' extremes in `a` that their sweeps pass.
pub(super) fn deepest(f: Frame, segs: &[&Seg], s: f64) -> f64 {
    let mut best = f64::INFINITY;
    for sg in segs {
        for p in [(sg.mv.x_start, sg.mv.z_start), (sg.mv.x_dia, sg.mv.z)] {
            best = best.min(s * f.ab(p).0);
        }
        if let Some(g) = sg.mv.arc {
            let (c, t0, sweep, r) = arc_angles(&sg.mv, g);
            let half = std::f64::consts::FRAC_PI_2;
            // G71 steps in the radius (extremes at +-90 deg), G72 in z (0 and 180 deg).
            let (centre, extremes) = if f.facing {
                (c.0, [(0.0, 1.0), (2.0 * half, -1.0)])
            } else {
                (c.1, [(half, 1.0), (-half, -1.0)])
            };
            for (t, sign) in extremes {
                if within(t, t0, sweep) {
                    best = best.min(s * (centre + sign * r));
                }
            }
        }
    }
    best
}

impl Interp<'_> {
    /// The troughs' passes (module docs), after the first passes: at levels `a_start - s
    /// dd k` down to the deepest point of the shape.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rough_troughs(
        &mut self,
        block: (&Program, usize, Frame),
        at: &mut (f64, f64),
        segs: &[&Seg],
        (s, dir): (f64, f64),
        a_start: f64,
        (dd, e): (f64, f64),
        max_passes: usize,
    ) -> Result<(), Fail> {
        let f = block.2;
        let floor = deepest(f, segs, s);
        let mut k = 1;
        loop {
            let level = a_start - s * dd * k as f64;
            if s * level <= floor + 1e-9 {
                break;
            }
            if k > max_passes {
                return Err((
                    1,
                    format!("the roughing would cut more than {max_passes} passes"),
                ));
            }
            let above = a_start - s * dd * (k - 1) as f64;
            for (b_in, b_out, opens) in stretches(f, segs, s, level) {
                if opens || dir * (b_out - b_in) <= 1e-9 {
                    continue;
                }
                let back = e.min(dir * (b_out - b_in));
                let here = f.ab(*at).1;
                step(self, block, at, MoveKind::Rapid, (a_start, here));
                step(self, block, at, MoveKind::Rapid, (a_start, b_in));
                step(self, block, at, MoveKind::Rapid, (above, b_in));
                step(self, block, at, MoveKind::Feed, (level, b_in));
                step(self, block, at, MoveKind::Feed, (level, b_out));
                step(
                    self,
                    block,
                    at,
                    MoveKind::Rapid,
                    (level + s * back, b_out - dir * back),
                );
                step(
                    self,
                    block,
                    at,
                    MoveKind::Rapid,
                    (a_start, b_out - dir * back),
                );
            }
            k += 1;
        }
        Ok(())
    }
}
