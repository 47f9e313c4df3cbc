//! A tap's moves (thread moves on the lathe's axis: FANUC G84 and G33 tapping, LinuxCNC
//! G33.1, Siemens G331/G332 and CYCLE84, GSK G33) as passes of the tap's tooth
//! ([`Tap::tooth`]).
//!
//! With a feed equal to its pitch every tooth of a tap runs in the groove the first one
//! cut, so the part at the end of a stroke is the thread's helix cut to the major diameter
//! where the full teeth reached, and in the chamfer zone the helix cut down to the chamfer's
//! cone at the tap's deepest position. Two passes of the tooth on the stroke's helix give
//! exactly that at every groove's centre: one at the major diameter from `L` behind the
//! stroke's start to `L` behind its end (`L` the chamfer length), and one tapered from the
//! major diameter `L` behind the end to the chamfer's diameter at the end. Across a tooth's
//! width the chamfer pass cuts flat at the cone's height at the groove's centre where the
//! cone itself slopes (at most `slope x P/16` apart on the root flat). The way back (the
//! spindle reversed, the same helix) cuts nothing more and makes no pass. A feed that is
//! not the pitch strips the thread: that is a `tap_feed` finding at the block; the passes
//! then follow the programmed lead (one tooth's cut, not the whole tap's).

use crate::model::pass::Pass;
use crate::model::tool::Tap;
use crate::nc::Move;
use std::f64::consts::TAU;

/// A tap stroke whose feed per revolution is not the tap's pitch.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TapFeed {
    /// The program file and 1-based line of the block.
    pub(crate) file: String,
    pub(crate) line: usize,
    /// The programmed feed (mm/rev) and the tap's pitch (mm).
    pub(crate) feed: f64,
    pub(crate) pitch: f64,
}

/// How far a tap's feed may differ from its pitch (mm/rev): the controls' lead words are
/// in 0.0001 mm/rev at the finest.
pub(crate) const FEED_TOLERANCE: f64 = 5e-5;

/// The passes of one inward stroke `m` of `tap` (the tooth is tool `tool`): the full-depth
/// pass and the chamfer pass on the stroke's helix (module doc). The start angle of a pass
/// on the same helix `s` mm further along it is `theta0 - spin 2 pi s / F`.
pub(crate) fn stroke_passes(m: &Move, tap: &Tap, tool: usize) -> Result<Vec<Pass>, String> {
    let f = m.lead.unwrap_or(0.0);
    if m.lead_change.is_some_and(|k| k != 0.0) {
        return Err("a tap cannot follow a changing lead (a G34-style move on the axis)".into());
    }
    if f <= 0.0 {
        return Err(format!(
            "a tap stroke needs a positive feed per revolution, got {f}"
        ));
    }
    let dir = if m.z < m.z_start { -1.0 } else { 1.0 };
    let travel = (m.z - m.z_start).abs();
    let l = tap.chamfer_length;
    let spin = m.spindle.sign();
    let theta0 = -spin * m.sync_angle_deg.unwrap_or(0.0).to_radians();
    let at = |s: f64| theta0 - spin * TAU * s / f;
    let mut v = vec![Pass {
        tool,
        x_start: tap.major_diameter,
        x_end: tap.major_diameter,
        z_start: m.z_start - dir * l,
        z_end: m.z - dir * l,
        lead: f,
        lead_change: 0.0,
        start_angle: at(-l),
        spindle: m.spindle,
    }];
    if l > 0.0 {
        v.push(Pass {
            tool,
            x_start: tap.major_diameter,
            x_end: tap.chamfer_diameter,
            z_start: m.z - dir * l,
            z_end: m.z,
            lead: f,
            lead_change: 0.0,
            start_angle: at(travel - l),
            spindle: m.spindle,
        });
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::Spindle;

    fn stroke(z0: f64, z1: f64, lead: f64, sync: f64) -> Move {
        Move {
            file: "T.NC".into(),
            line: 3,
            kind: crate::nc::MoveKind::Thread,
            x_start: 0.0,
            z_start: z0,
            x_dia: 0.0,
            z: z1,
            lead: Some(lead),
            lead_change: Some(0.0),
            sync_angle_deg: Some(sync),
            chained: false,
            tool: Some(5),
            tool_word: None,
            spindle: Spindle::Cw,
            arc: None,
            speed: Default::default(),
            feed: None,
            cycle: false,
            nose: None,
        }
    }

    #[test]
    fn both_passes_lie_on_the_strokes_helix() {
        // The tip's helix from z = 5 (sync 30 deg) into -20 at 1.5 mm/rev; chamfer 4.5.
        // Every point of either pass must be where the tip's helix, extended, is.
        let tap = Tap {
            id: 5,
            pitch: 1.5,
            major_diameter: 10.0,
            chamfer_length: 4.5,
            chamfer_diameter: 8.376,
        };
        let m = stroke(5.0, -20.0, 1.5, 30.0);
        let tip = Pass {
            tool: 0,
            x_start: 0.0,
            x_end: 0.0,
            z_start: 5.0,
            z_end: -20.0,
            lead: 1.5,
            lead_change: 0.0,
            start_angle: -30f64.to_radians(),
            spindle: Spindle::Cw,
        }
        .helix();
        let v = stroke_passes(&m, &tap, 0).unwrap();
        assert_eq!(v.len(), 2);
        // Full pass: 4.5 behind the start and the end (behind = +z for a stroke to -z).
        assert_eq!((v[0].z_start, v[0].z_end), (9.5, -15.5));
        assert_eq!((v[1].z_start, v[1].z_end), (-15.5, -20.0));
        assert_eq!((v[1].x_start, v[1].x_end), (10.0, 8.376));
        for p in &v {
            let h = p.helix();
            for k in 0..=10 {
                let t = p.revolutions().unwrap() * f64::from(k) / 10.0;
                let z = h.z(t);
                // The tip's helix at that z: revolutions (z0 - z)/F (may be negative).
                let tt = (5.0 - z) / 1.5;
                let a = (h.theta0 - h.spin * TAU * t).rem_euclid(TAU);
                let b = (tip.theta0 - tip.spin * TAU * tt).rem_euclid(TAU);
                let d = (a - b).abs();
                assert!(d.min(TAU - d) < 1e-9, "{p:?} at {z}");
            }
        }
        // No chamfer: the tip's own pass.
        let v = stroke_passes(
            &m,
            &Tap {
                chamfer_length: 0.0,
                ..tap
            },
            0,
        )
        .unwrap();
        assert_eq!(v.len(), 1);
        assert_eq!(
            (v[0].z_start, v[0].z_end, v[0].start_angle),
            (5.0, -20.0, -30f64.to_radians())
        );
    }
}
