//! Where the thread is: the ideal thread's axial position fitted to the cut surface.
//!
//! A drawing never fixes the phase of a thread, and a gauge does not care about it; only
//! the simulation has to put its ideal thread somewhere. When the job does not say where
//! (`thread.z_start`), the ideal's first feature is placed on the cut:
//!
//! 1. A few generators (lines of the part at one angle) are cut at the measurement spacing
//!    and the features (grooves for equal groove width, teeth for equal tooth width) are
//!    found where they cross the pitch line, as an inspector finds them. Only features
//!    closed on both sides and about as wide as the drawing's (0.5 to 1.5 times) count: a
//!    groove that runs into a chamfer, a face or a relief groove is no witness of the phase.
//! 2. Constant lead: every feature's centre, less where the helix of the job's start angle
//!    crosses its generator, is the phase modulo the pitch; the phase is their circular
//!    mean (exact for any number of starts and either hand). Variable lead: the features of
//!    the reference generator, front to back, are the thread's turns 0, 1, ..; the phase is
//!    their mean offset from the lead law.
//! 3. The thread's first feature is put on the frontmost feature found: the thread starts
//!    where the cut does (a thread cut from in front of the face starts at the face).
//!
//! The fit's spread (the root mean square of the features' offsets from it) says how well
//! one helix explains the cut; a spread of more than an eighth of the pitch means it does
//! not (two threads on top of each other, a restart out of phase) and is reported.
//! Pure: the cut comes from the caller as a function that cuts a free-standing column.

use crate::analysis::measure::intervals;
use crate::kernel::sweep::Column;
use crate::model::stock::Surface;
use crate::model::thread::{Side, ThreadSpec, WidthRule};
use std::f64::consts::TAU;

/// Generators the fit looks at, equally spaced from the thread's start angle.
const GENERATORS: usize = 4;

/// The most cells of one fit column (a 1 m screw at 0.5 um would be 2e6: the spacing grows
/// instead).
const MAX_CELLS: f64 = 2.0e6;

/// Where the fit put the thread, and how well the cut agreed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// z of the thread's first feature at its start angle (mm): `thread.z_start`.
    pub z_start: f64,
    /// Features (grooves or teeth) the fit used.
    pub features: usize,
    /// Root mean square of the features' offsets from the fitted helix (mm).
    pub spread: f64,
    /// With a given `z_start`: how far the cut's helix lies from it (mm, signed, the
    /// nearest equivalent position for a constant lead); `None` when fitted or unknown.
    pub offset: Option<f64>,
}

/// The features found on one generator: (generator angle, centre z) of each closed feature
/// of plausible width.
fn features_on(
    thread: &ThreadSpec,
    cut: &(dyn Fn(&mut [f32], Column) + Sync),
    q_blank: f64,
    window: (f64, f64),
    spacing: f64,
    theta: f64,
) -> Vec<f64> {
    let surface = match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    };
    let dz = spacing.max((window.1 - window.0) / MAX_CELLS);
    let n = ((window.1 - window.0) / dz).floor().max(2.0) as usize;
    let mut q = vec![0.0f32; n];
    cut(
        &mut q,
        Column {
            theta,
            z0: window.0,
            dz,
            q_blank,
            surface,
        },
    );
    let sense = surface.sense();
    let h: Vec<f32> = q
        .iter()
        .enumerate()
        .map(|(j, &v)| {
            let z = window.0 + j as f64 * dz;
            thread.local_height(z, sense * (v as f64 + q_blank)) as f32
        })
        .collect();
    let tooth = matches!(thread.width, WidthRule::Tooth(_));
    let wanted = match thread.width {
        WidthRule::Groove(w) | WidthRule::Tooth(w) => w,
    };
    intervals(&h, window.0, dz, thread.pitch_height(), tooth)
        .into_iter()
        .filter(|iv| !iv.lo_open && !iv.hi_open)
        .filter(|iv| {
            let w = iv.hi - iv.lo;
            w >= 0.5 * wanted && w <= 1.5 * wanted
        })
        .map(|iv| 0.5 * (iv.lo + iv.hi))
        .collect()
}

/// Fit the thread's first feature to the cut over `window` (the blank's z range).
/// `given`: the job's `z_start`, kept (only its offset from the cut is measured). `None`
/// when the cut has no feature of the thread's width at its pitch line.
pub(crate) fn fit(
    thread: &ThreadSpec,
    cut: &(dyn Fn(&mut [f32], Column) + Sync),
    q_blank: f64,
    window: (f64, f64),
    spacing: f64,
    given: Option<f64>,
) -> Option<Placement> {
    let helix = thread.helix;
    let law = helix.law;
    let found: Vec<(f64, Vec<f64>)> = (0..GENERATORS)
        .map(|g| {
            let theta = helix.theta0 + TAU * g as f64 / GENERATORS as f64;
            (
                theta,
                features_on(thread, cut, q_blank, window, spacing, theta),
            )
        })
        .collect();
    if law.k == 0.0 {
        let lead = law.f;
        let pitch = lead / thread.starts as f64;
        // Each centre less the helix's crossing of its generator (for z_start = 0): the
        // phase modulo the pitch.
        let mut offsets = Vec::new();
        for (theta, centres) in &found {
            let cross = helix.dir * lead * helix.phase_at(*theta);
            offsets.extend(centres.iter().map(|c| c - cross));
        }
        let (phase, spread) = circular_mean(&offsets, pitch)?;
        if let Some(z) = given {
            let off = wrap(phase - z, pitch);
            return Some(Placement {
                z_start: z,
                features: offsets.len(),
                spread,
                offset: Some(off),
            });
        }
        // The thread starts at the frontmost feature found: the first lattice position at
        // or in front of it (within the fit's own scatter), in the direction the helix
        // comes from.
        let front = found
            .iter()
            .flat_map(|(theta, cs)| {
                let cross = helix.dir * lead * helix.phase_at(*theta);
                cs.iter().map(move |c| c - cross)
            })
            .fold(None, |acc: Option<f64>, z| {
                Some(match acc {
                    None => z,
                    Some(a) if helix.dir < 0.0 => a.max(z),
                    Some(a) => a.min(z),
                })
            })?;
        // Nearest lattice position to the frontmost feature's start-angle equivalent.
        let m = ((front - phase) / pitch).round();
        Some(Placement {
            z_start: phase + m * pitch,
            features: offsets.len(),
            spread,
            offset: None,
        })
    } else {
        // Variable lead: the reference generator's features, front to back, are turns 0, 1, ..
        // of start 0 (a multi-start variable lead needs its z_start).
        if thread.starts != 1 {
            return None;
        }
        let (theta, centres) = &found[0];
        let mut cs = centres.clone();
        cs.sort_by(|a, b| (helix.dir * a).total_cmp(&(helix.dir * b)));
        let phase0 = helix.phase_at(*theta);
        let max_n = thread.turns.floor() as usize + 1;
        let z0s: Vec<f64> = cs
            .iter()
            .take(max_n)
            .enumerate()
            .map(|(i, c)| c - helix.dir * law.travel(phase0 + i as f64))
            .collect();
        if z0s.is_empty() {
            return None;
        }
        let mean = z0s.iter().sum::<f64>() / z0s.len() as f64;
        let spread =
            (z0s.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / z0s.len() as f64).sqrt();
        Some(Placement {
            z_start: given.unwrap_or(mean),
            features: z0s.len(),
            spread,
            offset: given.map(|z| mean - z),
        })
    }
}

/// `x` wrapped into `[-p/2, p/2)`.
fn wrap(x: f64, p: f64) -> f64 {
    x - p * (x / p + 0.5).floor()
}

/// The phase of `xs` modulo `p`, in `[-p/2, p/2)`, and the root mean square of the inliers'
/// wrapped offsets from it. Robust: the circular mean gives the neighbourhood, the median
/// of the offsets wrapped around it the centre, and the values within four median
/// absolute deviations (at least 1e-4 of the pitch) of the median are averaged; a partial
/// groove at a run-out or a chamfer (a few features off by tenths of a millimetre) does not
/// move it. `None` for no value.
fn circular_mean(xs: &[f64], p: f64) -> Option<(f64, f64)> {
    if xs.is_empty() {
        return None;
    }
    let (s, c) = xs.iter().fold((0.0, 0.0), |(s, c), x| {
        let a = TAU * x / p;
        (s + a.sin(), c + a.cos())
    });
    let mean = wrap(p * s.atan2(c) / TAU, p);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        }
    };
    let mut d: Vec<f64> = xs.iter().map(|x| wrap(x - mean, p)).collect();
    let centre = median(&mut d);
    let mut dev: Vec<f64> = d.iter().map(|v| (v - centre).abs()).collect();
    let mad = median(&mut dev);
    let keep = (4.0 * mad).max(1e-4 * p);
    let inliers: Vec<f64> = d
        .iter()
        .copied()
        .filter(|v| (v - centre).abs() <= keep)
        .collect();
    let avg = inliers.iter().sum::<f64>() / inliers.len() as f64;
    let spread =
        (inliers.iter().map(|v| (v - avg).powi(2)).sum::<f64>() / inliers.len() as f64).sqrt();
    Some((wrap(mean + avg, p), spread))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circular_mean_finds_the_phase_across_the_wrap() {
        let p = 2.0;
        for phase in [-0.99, -0.5, 0.0, 0.3, 0.98] {
            let xs: Vec<f64> = (0..7)
                .map(|k| phase + k as f64 * p + [0.001, -0.001, 0.0][k % 3])
                .collect();
            let (m, s) = circular_mean(&xs, p).unwrap();
            let want = xs.iter().map(|x| x - phase).sum::<f64>() / 7.0 - 21.0 * p / 7.0 + phase;
            assert!(wrap(m - want, p).abs() < 1e-12, "{phase}: {m} vs {want}");
            assert!(s < 0.003, "{s}");
        }
        assert!(circular_mean(&[], 1.0).is_none());
        // A few partial grooves off by tenths do not move it.
        let mut xs: Vec<f64> = (0..12).map(|k| 0.3 + k as f64 * p).collect();
        xs.extend([0.3 + 0.4, 0.3 - 0.25, 0.3 + 0.6]);
        let (m, s) = circular_mean(&xs, p).unwrap();
        assert!((m - 0.3).abs() < 1e-12 && s < 1e-12, "{m} {s}");
    }
}
