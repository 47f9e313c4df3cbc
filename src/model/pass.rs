//! Threading passes: a tool's reference point moving along a variable-lead helix.
//!
//! A pass is what one `G32`/`G33`/`G34` block does: the tool's reference point moves from
//! `z_start` to `z_end` while the spindle turns, synchronised so that at `t = 0` the tool
//! is at `start_angle` on the part. The lead law is the continuous one of
//! [`crate::model::helix::LeadLaw`]; the diameter may change linearly with z (a taper thread).
//! Handedness is not a flag: it follows from the spindle direction and the feed direction.

use crate::model::helix::{Helix, LeadLaw, Spindle};

/// One synchronised threading move.
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    /// Index of the tool in the job's tool list.
    pub tool: usize,
    /// Diameter of the reference point at `z_start` (mm).
    pub x_start: f64,
    /// Diameter of the reference point at `z_end` (mm); equal to `x_start` unless tapered.
    pub x_end: f64,
    /// Axial start of the move (mm).
    pub z_start: f64,
    /// Axial end of the move (mm).
    pub z_end: f64,
    /// Lead at the start (mm/rev).
    pub lead: f64,
    /// Change of lead per revolution (mm/rev^2), signed.
    pub lead_change: f64,
    /// Angle on the part under the tool at the start (rad).
    pub start_angle: f64,
    /// Spindle direction during the pass.
    pub spindle: Spindle,
}

impl Pass {
    /// The helix the reference point follows.
    pub fn helix(&self) -> Helix {
        Helix {
            z0: self.z_start,
            dir: if self.z_end >= self.z_start {
                1.0
            } else {
                -1.0
            },
            law: LeadLaw {
                f: self.lead,
                k: self.lead_change,
            },
            theta0: self.start_angle,
            spin: self.spindle.sign(),
        }
    }

    /// Revolutions from start to end, or `None` when the lead would reach zero first.
    pub fn revolutions(&self) -> Option<f64> {
        if self.lead <= 0.0 {
            return None;
        }
        self.helix()
            .law
            .revs_at((self.z_end - self.z_start).abs())
            .filter(|t| self.helix().law.lead(*t) > 0.0 || self.lead_change == 0.0)
    }

    /// Lead at the end of the pass.
    pub fn end_lead(&self) -> Option<f64> {
        self.revolutions().map(|t| self.helix().law.lead(t))
    }

    /// Radius of the reference point when it is at `z`.
    pub fn radius_at(&self, z: f64) -> f64 {
        let len = self.z_end - self.z_start;
        if len == 0.0 || self.x_end == self.x_start {
            return self.x_start / 2.0;
        }
        let u = ((z - self.z_start) / len).clamp(0.0, 1.0);
        (self.x_start + u * (self.x_end - self.x_start)) / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::Hand;

    fn pass(z_end: f64, spindle: Spindle) -> Pass {
        Pass {
            tool: 0,
            x_start: 20.0,
            x_end: 20.0,
            z_start: 5.0,
            z_end,
            lead: 2.0,
            lead_change: 0.0,
            start_angle: 0.0,
            spindle,
        }
    }

    #[test]
    fn hand_follows_spindle_and_feed() {
        assert_eq!(pass(-30.0, Spindle::Cw).helix().hand(), Hand::Right);
        assert_eq!(pass(-30.0, Spindle::Ccw).helix().hand(), Hand::Left);
        assert_eq!(pass(30.0, Spindle::Cw).helix().hand(), Hand::Left);
        assert_eq!(pass(30.0, Spindle::Ccw).helix().hand(), Hand::Right);
    }

    #[test]
    fn revolutions_and_zero_lead() {
        let mut p = pass(-15.0, Spindle::Cw);
        assert!((p.revolutions().unwrap() - 10.0).abs() < 1e-12);
        p.lead_change = -0.25; // lead 2 reaches 0 after 8 revs, 8 mm of travel
        assert!(p.revolutions().is_none());
        p.z_end = 0.0;
        assert!(p.revolutions().is_some());
    }
}
