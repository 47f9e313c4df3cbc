//! The tool body behind the cutting edge, swept through the radial dexels.
//!
//! The edge (the rake face, on centre) cuts a column exactly at the revolution `t_c` where
//! the pass crosses the column's angle ([`crate::sweep`]). The body trails the edge: at
//! relative angle `phi > 0` behind the rake face it meets the same column at `t_c + phi/2pi`,
//! when the tool has moved on along the helix by the travel of that fraction of a turn. So
//! the column sees a sequence of body sections, each placed at the tool's position of its
//! own instant. A radial ray of the column at relative angle `phi` crosses the tool frame at
//! `X = r cos phi` (radial) and `Y = r sin phi` (depth behind the rake face), and every face
//! of a planar-faced insert is then a linear constraint `A r >= B` on the radius along the
//! ray (the section's tip, its two flanks with their clearance and inclination, its back at
//! `Y = thickness`). The first radius inside all of them is where the body meets the ray
//! (external: the smallest; internal: the largest), and the column is cut there.
//!
//! **Sampling.** `phi` is sampled evenly up to the body's angular extent. What the body cuts
//! beyond the edge lies between the edge's wall and the section's flank, which moves across
//! the wall at `speed = |L/2pi + K phi/4pi^2 -/+ r cos(phi) slope|` mm per radian (the
//! helical travel against the recession `Y slope` at depth `Y = r sin phi`), bounded over the
//! pass's leads, the zone's radii and both flanks. A point the continuous body cuts between
//! two samples lies, axially, within `dphi * speed` of the later sample's flank, which cuts
//! everything on its side down to its own tip; the tip rises between samples too, but a
//! point under the rising tip is also within that axial distance of the flank. So the
//! sampled cut is within `dphi * speed` of the continuous body's, and the sample count keeps
//! that under [`SAMPLING_ERROR_MM`] (a test checks it against four times the samples).
//!
//! **Skipped when harmless.** When no section can reach outside what the edge itself cut at
//! the same crossing (the effective clearance stays positive on both flanks over the pass's
//! leads and radii, and the tip clearance is not negative), the body cuts nothing the edge
//! did not and the pass needs no sections: the result is exactly the planar one.

use crate::pass::Pass;
use crate::stock::Surface;
use crate::tool::{Body, Edge, Tool};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Largest distance (mm) between the cut of the sampled body sections and that of the
/// continuous body (the sample count keeps the bound under this).
/// A quarter of the default tolerance (0.02 mm).
pub(crate) const SAMPLING_ERROR_MM: f64 = 0.005;
/// Most sections per pass.
pub(crate) const MAX_SAMPLES: usize = 4096;

/// A body made ready for one pass: the sampled sections and the insert's faces.
#[derive(Clone, Debug)]
pub(crate) struct Sections {
    /// Per sample: `(dt, cos phi, sin phi)` with `dt = phi / 2pi` revolutions after the edge.
    pub(crate) samples: Vec<(f64, f64, f64)>,
    /// Edge: tip corners and flank cotangents (`INFINITY` for a vertical flank).
    vl: f64,
    vr: f64,
    cl: f64,
    cr: f64,
    /// Recession of the flanks and of the tip per mm of depth, and the depth.
    slope_l: f64,
    slope_r: f64,
    tan_front: f64,
    thickness: f64,
    /// The radii the body can meet (mm).
    r_zone: (f64, f64),
    /// The bound on the sampling error (mm).
    pub(crate) bound: f64,
}

/// The radii a pass's body can meet on `surface`: from its tip to the blank (`q_blank`).
pub(crate) fn zone(pass: &Pass, q_blank: f64, surface: Surface) -> (f64, f64) {
    let (a, b) = (
        pass.x_start.min(pass.x_end) / 2.0,
        pass.x_start.max(pass.x_end) / 2.0,
    );
    let r_blank = surface.sense() * q_blank;
    match surface {
        Surface::Outer => (a, r_blank.max(b)),
        Surface::Inner => (r_blank.min(a), b),
    }
}

/// The sections of a pass's body for the radii `r_zone` it can meet (tip to blank), or
/// `None` when the tool has no body or the body cannot cut beyond the edge.
pub(crate) fn sections(pass: &Pass, tool: &Tool, r_zone: (f64, f64)) -> Option<Sections> {
    sample(pass, tool, r_zone, SAMPLING_ERROR_MM, false)
}

/// The sections with the sampling error kept under `error_mm`; `force` samples even a body
/// that [`harmless`] would skip (for the tests that check the skip).
pub(crate) fn sample(
    pass: &Pass,
    tool: &Tool,
    r_zone: (f64, f64),
    error_mm: f64,
    force: bool,
) -> Option<Sections> {
    let body = tool.body?;
    let Edge::Trapezoid {
        tip,
        left_angle,
        right_angle,
    } = tool.edge
    else {
        return None;
    };
    let t_end = pass.revolutions()?;
    let law = pass.helix().law;
    let (l0, l1) = (law.lead(0.0).abs(), law.lead(t_end).abs());
    let (r_lo, r_hi) = (r_zone.0.min(r_zone.1).max(1e-3), r_zone.0.max(r_zone.1));
    // The body's angular extent: the largest phi at which some ray of the zone is still
    // within `thickness` of the rake face.
    let phi_max = (body.thickness / r_lo).min(1.0).asin().min(FRAC_PI_2);
    if !force
        && harmless(
            &body,
            law.lead(0.0),
            law.lead(t_end),
            law.k,
            pass,
            (r_lo, r_hi),
            phi_max,
        )
    {
        return None;
    }
    let (sl, sr, tf) = (
        body.slope_left(),
        body.slope_right(),
        body.clearance_front.tan(),
    );
    // Per radian of phi, how fast a flank of the section moves across the edge's wall: it
    // travels `L/2pi + K phi/4pi^2` along the axis and recedes `r cos(phi) slope` (see the
    // module docs for why the tip's rise does not count).
    let speed = [l0, l1]
        .into_iter()
        .flat_map(|l| [r_lo, r_hi].map(move |r| (l, r)))
        .flat_map(|(l, r)| [1.0, phi_max.cos()].map(move |c| (l, r * c)))
        .flat_map(|(l, rc)| {
            let travel = l / TAU + law.k.abs() * phi_max / (TAU * TAU);
            [sl, sr].map(move |slope| (travel - rc * slope).abs().max((travel + rc * slope).abs()))
        })
        .fold(0.0, f64::max)
        .max(1e-9);
    let n = ((phi_max * speed / error_mm).ceil() as usize).clamp(1, MAX_SAMPLES);
    let dphi = phi_max / n as f64;
    let samples = (1..=n)
        .map(|s| {
            let phi = s as f64 * dphi;
            (phi / TAU, phi.cos(), phi.sin())
        })
        .collect();
    let cot = |a: f64| {
        if a <= 0.0 {
            f64::INFINITY
        } else {
            1.0 / a.tan()
        }
    };
    Some(Sections {
        samples,
        vl: -tip / 2.0,
        vr: tip / 2.0,
        cl: cot(left_angle),
        cr: cot(right_angle),
        slope_l: sl,
        slope_r: sr,
        tan_front: tf,
        thickness: body.thickness,
        r_zone: (r_lo, r_hi),
        bound: dphi * speed,
    })
}

/// Whether no section of the body can reach outside the edge's own cut at the same crossing:
/// at depth `Y = r sin phi` the -z flank has receded by `Y slope_l` and the section has
/// travelled `dir * travel(phi / 2pi)` along the axis; it stays inside while
/// `Y slope_l + dir * travel >= 0`, and likewise `Y slope_r - dir * travel >= 0` on the +z
/// flank. Checked at both ends of the pass (the lead is monotonic in revolutions) and both
/// radii of the zone, on 64 angles up to `phi_max`.
fn harmless(
    body: &Body,
    lead_start: f64,
    lead_end: f64,
    k: f64,
    pass: &Pass,
    r: (f64, f64),
    phi_max: f64,
) -> bool {
    if body.clearance_front < 0.0 {
        return false;
    }
    let dir = pass.helix().dir;
    let (sl, sr) = (body.slope_left(), body.slope_right());
    for lead in [lead_start, lead_end] {
        for rr in [r.0, r.1] {
            for i in 1..=64 {
                let phi = phi_max * i as f64 / 64.0;
                let dt = phi / TAU;
                let travel = dir * (lead * dt + 0.5 * k * dt * dt);
                let y = rr * phi.sin();
                if y * sl + travel < 1e-9 || y * sr - travel < 1e-9 {
                    return false;
                }
            }
        }
    }
    true
}

impl Sections {
    /// The axial bands (offsets from the section's tip centre) where the section of sample
    /// `sin phi = s`, placed `delta` mm along the axis from where the edge cut the same
    /// column, can cut below that cut, for material `reach` mm above the tip. The edge's
    /// flanks lie at `vl - delta` and `vr - delta` in the section's frame; the section's
    /// own flanks are set back by `Y slope` at depth `Y = r s` (`r` over the zone, `Y` at
    /// most the thickness). A flank whose section stays behind the edge's gives no band;
    /// otherwise the band runs from the edge's flank, where it leaves the material, to the
    /// section's, with `pad` of slack. Everywhere else the section lies inside the edge's
    /// cut (its tip stands higher: front clearance >= 0) or above the material.
    pub(crate) fn bands(
        &self,
        reach: f64,
        pad: f64,
        delta: f64,
        s: f64,
    ) -> [Option<(f64, f64)>; 2] {
        let run = |c: f64| if c.is_finite() { reach / c } else { 0.0 };
        let y_lo = (self.r_zone.0 * s).min(self.thickness);
        let y_hi = (self.r_zone.1 * s).min(self.thickness);
        // Offsets of the section's flanks from the edge's, towards the material (+).
        let out_l = -(y_lo * self.slope_l).min(y_hi * self.slope_l) - delta;
        let out_r = -(y_lo * self.slope_r).min(y_hi * self.slope_r) + delta;
        let (el, er) = (self.vl - delta, self.vr - delta);
        [
            (out_l > 0.0).then(|| (el - out_l - run(self.cl) - pad, el + pad)),
            (out_r > 0.0).then(|| (er - pad, er + out_r + run(self.cr) + pad)),
        ]
    }

    /// Cut `seg` (cells at axial offsets `v_start + k dz` from the section's tip centre,
    /// values `q - q_blank`) with the section of sample `(c, s)` whose tip is at radius
    /// `r_tip`. `sense` is +1 for an outer surface (external thread), -1 for an inner one.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn apply(
        &self,
        seg: &mut [f32],
        v_start: f64,
        dz: f64,
        c: f64,
        s: f64,
        r_tip: f64,
        sense: f64,
        q_blank: f64,
    ) {
        // Constraints `a r >= b` on the radius along the ray; the v-independent ones first.
        let mut lo = 0.0f64;
        let mut hi = if s > 0.0 {
            self.thickness / s
        } else {
            f64::INFINITY
        };
        let add = |a: f64, b: f64, lo: &mut f64, hi: &mut f64| {
            if a > 0.0 {
                *lo = lo.max(b / a);
            } else if a < 0.0 {
                *hi = hi.min(b / a);
            } else if b > 0.0 {
                *lo = f64::INFINITY;
            }
        };
        // Tip: sense (r c - r_tip) >= Y tan_front.
        add(
            sense * c - s * self.tan_front,
            sense * r_tip,
            &mut lo,
            &mut hi,
        );
        if lo > hi {
            return;
        }
        let (lo0, hi0) = (lo, hi);
        for (k, cell) in seg.iter_mut().enumerate() {
            let v = v_start + k as f64 * dz;
            let (mut lo, mut hi) = (lo0, hi0);
            // -z flank: H >= (vl + Y slope_l - v) cl, or for a vertical flank v >= vl + Y slope_l.
            if self.cl.is_finite() {
                add(
                    sense * c - s * self.slope_l * self.cl,
                    sense * r_tip + (self.vl - v) * self.cl,
                    &mut lo,
                    &mut hi,
                );
            } else {
                add(-s * self.slope_l, self.vl - v, &mut lo, &mut hi);
            }
            // +z flank: H >= (v - vr + Y slope_r) cr, or v <= vr - Y slope_r.
            if self.cr.is_finite() {
                add(
                    sense * c - s * self.slope_r * self.cr,
                    sense * r_tip + (v - self.vr) * self.cr,
                    &mut lo,
                    &mut hi,
                );
            } else {
                add(-s * self.slope_r, v - self.vr, &mut lo, &mut hi);
            }
            if lo > hi {
                continue;
            }
            // The material side meets the body first: the smallest radius outside, the
            // largest inside.
            let r = if sense > 0.0 { lo } else { hi };
            if !r.is_finite() {
                continue;
            }
            let q = (sense * r - q_blank) as f32;
            if q < *cell {
                *cell = q;
            }
        }
    }
}
