//! A lathe tool's holder as the shapes its moves sweep: the solid behind the insert that
//! must not meet the part (`model::tool::Holder`).
//!
//! The part turns, so a holder meets it where some point of the holder lies nearer the
//! axis (outside) or farther from it (in a bore) than the stock's surface at that z: what
//! counts of the holder at each z is its extreme distance from the axis. A shank's is its
//! bottom face, `clearance` above the tip: a block with vertical sides from `left` before
//! the tip to `right` after it, a flat-bottomed [`TurningTool`] with sharp corners and
//! radial edges (a grooving insert's shape) driven with the tip. A boring bar's is its
//! farthest point, `b + |r - reach|` from the axis for the tip at radius `r` (`b` the
//! bar's radius; its centre line lies `r - reach` from the axis, on the tip's side or
//! past the axis): while the tip stays at or beyond `reach` that is `reach - b` below the
//! tip in the bore's height (a block driven with the tip), and nearer the axis it is a
//! block on the tip's path mirrored about `reach`. A straight move that crosses `reach` is
//! split there; an arc is taken whole on the near side when both its ends are, else as
//! its chord.

use crate::kernel::turn::{TurnPath, TurningTool};
use crate::model::tool::Holder;

/// How the holder's tool is driven: its id, which surface, and the tip's axial offset from
/// the driven point (0 for a turning insert's imaginary tip, the tip's centre for an
/// insert driven by a reference point off it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mount {
    /// The tool's id.
    pub(crate) id: u32,
    /// In the bore.
    pub(crate) internal: bool,
    /// The tip's z less the driven point's.
    pub(crate) tip_dz: f64,
}

/// The shapes and paths `holder` sweeps on a move of the driven point from `from` to `to`
/// (`(z, x diameter)`), straight or about `arc` (`((z, x diameter) centre, clockwise)`).
pub(crate) fn sweeps(
    holder: &Holder,
    mount: Mount,
    from: (f64, f64),
    to: (f64, f64),
    arc: Option<((f64, f64), bool)>,
) -> Vec<(TurningTool, TurnPath)> {
    let sense = if mount.internal { -1.0 } else { 1.0 };
    let block = |lo: f64, hi: f64, dh: f64| TurningTool {
        id: mount.id,
        nose_radius: 0.0,
        flat: lo + hi,
        lead_angle: 0.0,
        trail_angle: 0.0,
        internal: mount.internal,
        anchor: (mount.tip_dz - lo, dh),
    };
    match *holder {
        Holder::Shank {
            left,
            right,
            clearance,
        } => {
            let b = block(left, right, clearance);
            vec![(b, TurnPath::of_move(&b, sense, from, to, arc))]
        }
        Holder::Bar {
            diameter,
            reach,
            front,
            length,
        } => {
            let half = diameter / 2.0;
            let near = block(front, length, reach - half);
            let (r0, r1) = (from.1 / 2.0, to.1 / 2.0);
            if r0 >= reach && r1 >= reach && arc.is_some() {
                return vec![(near, TurnPath::of_move(&near, sense, from, to, arc))];
            }
            // Past the axis: the bar's far side, `half + reach - r` from the axis, is the
            // height `r - half - reach` of a block driven along that line.
            let far = block(front, length, 0.0);
            let far_path = |a: (f64, f64), b: (f64, f64)| TurnPath::Line {
                from: (a.0 + far.anchor.0, a.1 / 2.0 - half - reach),
                to: (b.0 + far.anchor.0, b.1 / 2.0 - half - reach),
            };
            let piece = |a: (f64, f64), b: (f64, f64)| {
                if (a.1 / 2.0).min(b.1 / 2.0) >= reach {
                    (near, TurnPath::of_move(&near, sense, a, b, None))
                } else {
                    (far, far_path(a, b))
                }
            };
            if (r0 - reach) * (r1 - reach) < 0.0 {
                let u = (reach - r0) / (r1 - r0);
                let mid = (from.0 + u * (to.0 - from.0), 2.0 * reach);
                vec![piece(from, mid), piece(mid, to)]
            } else {
                vec![piece(from, to)]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::turn::envelope;
    use crate::model::Rng;

    /// The holder's extreme height at `z` (outside: its lowest `q = r`; in a bore: the
    /// lowest `q = -r` of its farthest point) for the tip at `(zt, rt)`, from its
    /// definition (the oracle); `None` where it does not reach.
    fn extreme(h: &Holder, tip_z: f64, rt: f64, z: f64) -> Option<f64> {
        match *h {
            Holder::Shank {
                left,
                right,
                clearance,
            } => (z >= tip_z - left && z <= tip_z + right).then_some(rt + clearance),
            Holder::Bar {
                diameter,
                reach,
                front,
                length,
            } => (z >= tip_z - front && z <= tip_z + length)
                .then_some(-(diameter / 2.0 + (rt - reach).abs())),
        }
    }

    #[test]
    fn the_swept_holder_is_its_extreme_over_the_move() {
        // Straight moves: the lowest height any position of the holder reaches at z, by
        // sampling the move finely, against the swept shapes' envelope.
        let mut rng = Rng(0x401d);
        for case in 0..300 {
            let internal = case % 2 == 1;
            let holder = if internal {
                Holder::Bar {
                    diameter: rng.range(6.0, 30.0),
                    reach: rng.range(4.0, 20.0),
                    front: rng.range(0.0, 2.0),
                    length: rng.range(5.0, 60.0),
                }
            } else {
                Holder::Shank {
                    left: rng.range(0.0, 10.0),
                    right: rng.range(1.0, 30.0),
                    clearance: rng.range(0.0, 6.0),
                }
            };
            let mount = Mount {
                id: 1,
                internal,
                tip_dz: rng.range(-1.0, 1.0),
            };
            let from = (rng.range(-30.0, 10.0), rng.range(4.0, 50.0));
            let to = (rng.range(-30.0, 10.0), rng.range(4.0, 50.0));
            let shapes = sweeps(&holder, mount, from, to, None);
            for k in 0..200 {
                let z = -100.0 + 200.0 * (k as f64 + 0.37) / 200.0;
                let got = shapes
                    .iter()
                    .map(|(t, p)| envelope(t, p, z))
                    .fold(f64::INFINITY, f64::min);
                // The positions u in [0, 1] of the move at which the holder covers z: an
                // interval (the tip's z is linear in u); the extreme height is linear (a
                // shank) or concave (a bar) in u, so its least is at an end of it.
                let (lo, hi) = match holder {
                    Holder::Shank { left, right, .. } => (left, right),
                    Holder::Bar { front, length, .. } => (front, length),
                };
                let z0 = from.0 + mount.tip_dz;
                let dz = to.0 - from.0;
                let (ua, ub) = if dz == 0.0 {
                    if z >= z0 - lo && z <= z0 + hi {
                        (0.0, 1.0)
                    } else {
                        (1.0, 0.0)
                    }
                } else {
                    let (a, b) = ((z - hi - z0) / dz, (z + lo - z0) / dz);
                    (a.min(b).max(0.0), a.max(b).min(1.0))
                };
                let mut want = f64::INFINITY;
                if ua <= ub {
                    for u in [ua, ub] {
                        let tz = z0 + u * dz;
                        let rt = (from.1 + u * (to.1 - from.1)) / 2.0;
                        let h = extreme(&holder, tz, rt, z.clamp(tz - lo, tz + hi)).unwrap();
                        want = want.min(h);
                    }
                }
                let step = 1e-9;
                if want.is_finite() || got.is_finite() {
                    assert!(
                        (got - want).abs() <= step,
                        "case {case} z {z}: swept {got} vs sampled {want} ({holder:?}, {from:?} -> {to:?})"
                    );
                }
            }
        }
    }
}
