//! Variable-lead helices: the continuous lead law of the controls and its inverse.
//!
//! A controller that cuts a variable-lead thread (FANUC/GSK `G34`, Siemens `G34`/`G35`)
//! changes the lead continuously with spindle revolutions `t` (see `domain.md` §2):
//! `L(t) = F + K*t` and the axial travel is `s(t) = F*t + K*t^2/2`. Every helix in vpcut,
//! the thread's pitch helix and every tool pass, is a [`Helix`]: an axial origin, a travel
//! direction, a lead law and an angular law tying revolutions to the angle on the part.

use std::f64::consts::TAU;

/// The lead law `L(t) = f + k*t`, `s(t) = f*t + k*t^2/2` (mm, revolutions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeadLaw {
    /// Lead at `t = 0` (mm/rev).
    pub f: f64,
    /// Change of lead per revolution (mm/rev^2), signed.
    pub k: f64,
}

impl LeadLaw {
    /// A constant lead.
    pub fn constant(lead: f64) -> LeadLaw {
        LeadLaw { f: lead, k: 0.0 }
    }

    /// Lead after `t` revolutions.
    pub fn lead(&self, t: f64) -> f64 {
        self.f + self.k * t
    }

    /// Axial travel after `t` revolutions.
    pub fn travel(&self, t: f64) -> f64 {
        t * (self.f + 0.5 * self.k * t)
    }

    /// The revolutions `t` at which the travel reaches `s`, on the branch where the lead is
    /// positive; `None` when the helix never gets there (the lead would reach zero first).
    pub fn revs_at(&self, s: f64) -> Option<f64> {
        let disc = self.f * self.f + 2.0 * self.k * s;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let den = self.f + root;
        if den <= 0.0 {
            // f <= 0 and k*s <= 0: the travel is not reachable with a positive lead.
            return if s == 0.0 { Some(0.0) } else { None };
        }
        // 2s / (f + sqrt(f^2 + 2ks)) is the positive-lead root, stable for k -> 0.
        Some(2.0 * s / den)
    }

    /// The revolution at which the lead reaches zero, if it ever does for `t > 0` (`k < 0`)
    /// or did for `t < 0` (`k > 0`).
    pub fn zero_lead_revs(&self) -> Option<f64> {
        if self.k == 0.0 {
            None
        } else {
            Some(-self.f / self.k)
        }
    }

    /// The same helix seen from `t0`: `L'(u) = L(t0 + u)`.
    pub fn shifted(&self, t0: f64) -> LeadLaw {
        LeadLaw {
            f: self.lead(t0),
            k: self.k,
        }
    }
}

/// Rotation of the spindle, seen the usual way (M03 = clockwise).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    /// M03.
    Cw,
    /// M04.
    Ccw,
}

impl Spindle {
    /// The other direction (M03 <-> M04): a tap's way out.
    pub fn reversed(self) -> Spindle {
        match self {
            Spindle::Cw => Spindle::Ccw,
            Spindle::Ccw => Spindle::Cw,
        }
    }

    /// +1 for clockwise, -1 for counter-clockwise: the sign with which the contact angle on
    /// the part *decreases* per revolution.
    pub fn sign(self) -> f64 {
        match self {
            Spindle::Cw => 1.0,
            Spindle::Ccw => -1.0,
        }
    }
}

/// Hand of a helix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hand {
    /// z grows with the angle on the part.
    Right,
    /// z falls with the angle on the part.
    Left,
}

/// A helix on the part: `z(t) = z0 + dir*s(t)`, angle `theta(t) = theta0 - spin*2*pi*t`.
///
/// Angles are in the part's frame (radians). `spin` is +1 when the angle falls with `t`
/// (a clockwise spindle seen from the tool), `dir` is the axial direction of travel.
/// The hand follows: right-handed when `dir * spin < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Helix {
    /// z at `t = 0` (mm).
    pub z0: f64,
    /// Axial direction of travel, +1 or -1.
    pub dir: f64,
    /// Lead law along the travel.
    pub law: LeadLaw,
    /// Angle on the part at `t = 0` (rad).
    pub theta0: f64,
    /// +1 when the angle falls with revolutions, -1 when it grows.
    pub spin: f64,
}

impl Helix {
    /// z after `t` revolutions.
    pub fn z(&self, t: f64) -> f64 {
        self.z0 + self.dir * self.law.travel(t)
    }

    /// Hand of this helix.
    pub fn hand(&self) -> Hand {
        if self.dir * self.spin < 0.0 {
            Hand::Right
        } else {
            Hand::Left
        }
    }

    /// The fractional revolution in `[0, 1)` at which the helix passes the angle `theta`;
    /// it passes again at every integer revolution after that.
    pub fn phase_at(&self, theta: f64) -> f64 {
        let t = self.spin * (self.theta0 - theta) / TAU;
        let f = t - t.floor();
        if f >= 1.0 {
            0.0
        } else {
            f
        }
    }

    /// The revolutions `t` in `[t_lo, t_hi]` at which the helix crosses the angle `theta`,
    /// in increasing order.
    pub fn crossings(&self, theta: f64, t_lo: f64, t_hi: f64) -> impl Iterator<Item = f64> {
        let phase = self.phase_at(theta);
        let first = (t_lo - phase).ceil();
        let last = (t_hi - phase).floor();
        let n = if last >= first {
            (last - first) as i64 + 1
        } else {
            0
        };
        (0..n).map(move |m| phase + first + m as f64)
    }

    /// The revolutions at which the helix reaches `z`, on its positive-lead branch.
    pub fn revs_at_z(&self, z: f64) -> Option<f64> {
        self.law.revs_at(self.dir * (z - self.z0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn travel_and_inverse_agree() {
        for &(f, k) in &[(7.0 - 0.75, 1.5), (10.0, 0.0), (12.0, -0.5), (2.0, 4.0)] {
            let law = LeadLaw { f, k };
            for i in 0..50 {
                let t = i as f64 * 0.173;
                if law.lead(t) <= 0.0 {
                    continue;
                }
                let s = law.travel(t);
                let back = law.revs_at(s).unwrap();
                assert!((back - t).abs() < 1e-11, "f={f} k={k} t={t} back={back}");
            }
        }
    }

    /// `domain.md` §2: crest-to-crest spacing is `F + K*(t + 1/2)`, so `F = P1 - dP/2`,
    /// `K = dP` gives seed 002's series `P_n = P1 + (n-1)*dP` between turns.
    #[test]
    fn seed002_series_between_whole_turns() {
        let (p1, dp) = (7.0, 1.5);
        let law = LeadLaw {
            f: p1 - dp / 2.0,
            k: dp,
        };
        for n in 1..=7 {
            let pitch = law.travel(n as f64) - law.travel(n as f64 - 1.0);
            assert!((pitch - (p1 + (n - 1) as f64 * dp)).abs() < 1e-12);
        }
        // Seed 002: L_n = n*P1 + n(n-1)dP/2 = 80.5 mm for 7 turns.
        assert!((law.travel(7.0) - 80.5).abs() < 1e-12);
    }

    #[test]
    fn siemens_end_pitch_formula() {
        // Pe^2 - Ps^2 = 2*G*Z1 holds only for the continuous law.
        let law = LeadLaw { f: 4.0, k: 0.8 };
        let t = 6.3;
        let z1 = law.travel(t);
        let pe = law.lead(t);
        assert!(((pe * pe - 16.0) / (2.0 * z1) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn crossings_are_where_the_angle_matches() {
        let h = Helix {
            z0: 5.0,
            dir: -1.0,
            law: LeadLaw { f: 3.0, k: 0.5 },
            theta0: 0.3,
            spin: 1.0,
        };
        assert_eq!(h.hand(), Hand::Right);
        let theta = 2.0;
        let ts: Vec<f64> = h.crossings(theta, 0.0, 5.0).collect();
        assert_eq!(ts.len(), 5);
        for t in ts {
            let ang = h.theta0 - h.spin * TAU * t;
            let d = (ang - theta).rem_euclid(TAU);
            assert!(d < 1e-9 || TAU - d < 1e-9);
        }
    }

    #[test]
    fn lead_reaching_zero_is_unreachable() {
        let law = LeadLaw { f: 2.0, k: -1.0 };
        // Max travel is f^2/(2|k|) = 2 mm.
        assert!(law.revs_at(1.9).is_some());
        assert!(law.revs_at(2.1).is_none());
        assert_eq!(law.zero_lead_revs(), Some(2.0));
    }
}
