//! A taper thread's gauge (ASME B1.20.1's L1 gauges, ISO 7-2's taper limit gauges): a
//! taper ring (external thread) or plug (internal) of the basic profile, screwed on by
//! hand over the gauge's length from the thread's face, stops where its flanks meet the
//! part's; the thread is good when the gauge's plane then lies within the standard's turns
//! of the part's nominal gauge plane.
//!
//! The gauge's crest stands H/4 from its pitch line (flank contact only); its root is
//! cleared. Computed exactly as the GO gauge is (`functional_over`): against the basic pitch cone
//! (the heights the measurement keeps are above the local root: the cones taken off), a
//! perfect taper gauge is a parallel one whose walls, seen against its cone, lean by the
//! slope: a wall of tangent `T` to the radial (`dz/dr = -T` on the +z side of the
//! gauge's groove or tooth centre, `+T` on the -z side) has `dz/dr' = -T/(1 + s T)` and
//! `T/(1 - s T)` against `r' = r - s (z - z_ref)` (`s` the radius's slope). The best-fitting
//! gauge's pitch radius at the cones' reference `R'` fixes its cone `R' + s (z - z_ref)`;
//! its gauge plane stops where that cone has the gauge diameter `E`:
//! `z* = z_ref + (E/2 - R')/s`. The stand-off is `z* - z_gp` (the part's gauge plane):
//! positive where the gauge stops short of it (more material: an external thread large,
//! an internal one small), in turns over the pitch.
//! Pure.

use super::{call, functional_over, Call, Element, Gauge, GaugeColumn, Profile, BINS};
use crate::model::thread::{Side, ThreadSpec};
use crate::model::tolerance::ThreadClass;

/// Where a taper gauge stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StandOff {
    /// The gauge plane's axial stand-off from the part's (mm, signed: positive where the
    /// gauge stops short of it, more material).
    pub mm: f64,
    /// The same in turns (over the pitch).
    pub turns: f64,
    /// z of the gauge's plane where it stopped (mm).
    pub plane_z: f64,
    /// z of the part's nominal gauge plane (mm).
    pub nominal_z: f64,
    /// The fitted gauge's pitch diameter at the part's gauge plane: the cut's pitch cone
    /// there as the gauge sees it (mm).
    pub diameter: f64,
    /// The allowed stand-off either way (turns).
    pub tolerance_turns: f64,
    /// The resolution of `mm` (mm).
    pub resolution: f64,
}

/// The stand-off of `class`'s taper gauge on the cut (`columns`: the measurement
/// generators' heights above the local root) and the gauge's verdict.
pub(super) fn judge(
    thread: &ThreadSpec,
    class: &ThreadClass,
    columns: &[GaugeColumn],
    spacing: f64,
) -> Gauge {
    let found = stand_off(thread, class, columns, spacing);
    let mut elements = Vec::new();
    if let Some(s) = found {
        let limit = s.tolerance_turns * class.pitch;
        for (limit, upper) in [(limit, true), (-limit, false)] {
            elements.push(Element {
                name: "gauge_plane_stand_off",
                value: Some(s.mm),
                limit,
                upper,
                resolution: s.resolution,
                call: call(Some(s.mm), limit, upper, s.resolution),
                advisory: false,
            });
        }
    } else if let Some(g) = class.taper_gauge {
        let limit = g.tolerance_turns * class.pitch;
        elements.push(Element {
            name: "gauge_plane_stand_off",
            value: None,
            limit,
            upper: true,
            resolution: 0.0,
            call: Call::NotMeasured,
            advisory: false,
        });
    }
    let verdict = elements.iter().fold(Call::Pass, |v, e| v.worse(e.call));
    Gauge {
        functional: found.map(|s| (s.diameter, (s.nominal_z, s.nominal_z))),
        simple: None,
        not_go: None,
        not_go_simple: None,
        crest: None,
        resolution: found.map_or(0.0, |s| s.resolution),
        root: None,
        root_radius: None,
        stand_off: found,
        elements,
        verdict,
        over_wires: None,
    }
}

/// The taper gauge's stand-off, `None` without the thread's cut over the gauge's length.
pub(super) fn stand_off(
    thread: &ThreadSpec,
    class: &ThreadClass,
    columns: &[GaugeColumn],
    spacing: f64,
) -> Option<StandOff> {
    let g = class.taper_gauge?;
    let taper = thread.taper?;
    let s = taper.slope;
    if s == 0.0 {
        return None;
    }
    let external = thread.side == Side::External;
    let t = (0.5 * class.flank_angle).tan();
    let cot = 1.0 / t;
    let profile = Profile {
        pitch: class.pitch,
        cot_lo: (1.0 - s * t) / t,
        cot_hi: (1.0 + s * t) / t,
        // The gauge's crest H/4 from its pitch line (as ISO's basic internal minor
        // diameter stands from the pitch line): it bears on the flanks and clears any
        // product root the standards allow (their gauges' own crest truncations were not
        // found in a public source).
        clear: 0.125 * class.pitch * cot,
        external,
        truncated: false,
    };
    // The stored radii's rounding (4 ulps of the largest, on a diameter twice).
    let ulp = (thread.crest_radius.max(thread.root_radius) as f32).to_bits();
    let ulp = f32::from_bits(ulp + 1) as f64 - f32::from_bits(ulp) as f64;
    let rounding = 2.0 * 4.0 * ulp;
    let span = (taper.z_ref - g.length, taper.z_ref);
    let (d, _, at_corner) = functional_over(thread, &profile, columns, span, 0.0, 0.5 * rounding)?;
    let r = 0.5 * d;
    let e = class.basic_pitch_diameter;
    let plane_z = taper.z_ref + (0.5 * e - r) / s;
    let nominal_z = taper.z_ref - g.gauge_plane;
    let mm = plane_z - nominal_z;
    // The GO envelope's resolution on a diameter (see `judge`), halved to a radius, over
    // the slope.
    let res_d = rounding
        + 2.0 * cot * class.pitch / BINS as f64
        + if at_corner { 2.0 * spacing * cot } else { 0.0 };
    Some(StandOff {
        mm,
        turns: mm / class.pitch,
        plane_z,
        nominal_z,
        diameter: 2.0 * (r + s * (nominal_z - taper.z_ref)),
        tolerance_turns: g.tolerance_turns,
        resolution: 0.5 * res_d / s.abs(),
    })
}
