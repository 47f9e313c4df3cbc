//! The finished part against what every tool cut: material removed inside the drawn
//! contour (a gouge, by the pass or move that did it) and stock left outside it where the
//! program turned (a leftover).
//!
//! Per axial position the deepest cut is exact in closed form: a turning or grooving move
//! removes its shape swept along its path (`kernel::turn`), and a threading pass's deepest
//! point at a z, over all angles, is its edge swept along the pass's (z, radius) line (the
//! tip crosses every z of the pass once per start at some angle; beyond the pass's ends its
//! flanks reach). The contour is compared with it every `dz` along the contour's span and
//! just beside each of its points on both sides (a step's two radii). The thread's own grooves are
//! the thread, not a gouge: where the contour is drawn at the thread (its section, with
//! the chamfers that run into it: [`PartProfile::band_around`] the thread's middle, between
//! the thread's root and crest radii) a threading pass may cut down to the thread's root; a turning move is
//! held to the contour everywhere. The span the thread comparison covers
//! (`Deviation::compared_z`) is left to it. The stock a program left outside the contour
//! is the turned profile (the threading passes leave the crest at some angle of every z),
//! checked only where a feed move turned.

use crate::kernel::turn::{envelope, TurnCut, TurnPath, Turned, TurningTool};
use crate::model::part::{Approach, PartProfile};
use crate::model::pass::Pass;
use crate::model::thread::ThreadSpec;
use crate::model::tool::Tool;

/// What cut material away: a threading pass or a turning (or grooving) move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cutter {
    /// The pass of this index.
    Pass(usize),
    /// The surface's feed move of this index (in `Turned::cuts`).
    Move(usize),
}

/// How deep one cutter went into the part: its deepest point below the contour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PartGouge {
    /// Who.
    pub(crate) by: Cutter,
    /// Radial depth below the contour (or the thread's root), mm.
    pub(crate) depth: f64,
    /// Where (z, mm).
    pub(crate) z: f64,
    /// The radius it went below (the contour's, or the thread's root), mm.
    pub(crate) floor: f64,
}

/// Stock left outside the contour over a stretch where the program turned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PartLeftover {
    /// How far the stock stands outside the contour at its worst (mm, radial).
    pub(crate) height: f64,
    /// Where (z, mm).
    pub(crate) z: f64,
    /// The stretch (z from, z to).
    pub(crate) span: (f64, f64),
}

/// One surface's check: its contour and what cut it.
pub(crate) struct Surface<'a> {
    /// The contour as drawn.
    pub(crate) profile: &'a PartProfile,
    /// 1 outside, -1 in the bore.
    pub(crate) sense: f64,
    /// The blank's `q` and the floor no cut goes below.
    pub(crate) q_blank: f64,
    /// The lowest `q` material can have.
    pub(crate) q_floor: f64,
    /// The feed moves on this surface.
    pub(crate) turned: &'a Turned,
    /// The thread, when it is on this surface, and the span its comparison covers.
    pub(crate) thread: Option<(&'a ThreadSpec, Option<(f64, f64)>)>,
    /// The threading passes (on the thread's surface) and their tools.
    pub(crate) passes: &'a [Pass],
    /// The tools the passes name.
    pub(crate) tools: &'a [Tool],
    /// Sampling step (mm).
    pub(crate) dz: f64,
    /// The blank's z span: nothing is cut beyond it, and the contour is sampled only on it.
    pub(crate) z_span: (f64, f64),
    /// Deviations up to it are no finding (mm).
    pub(crate) tolerance: f64,
}

/// The gouges (each cutter's deepest, beyond the tolerance) and the leftover stretches.
pub(crate) fn check(s: &Surface) -> (Vec<PartGouge>, Vec<PartLeftover>) {
    let (lo, hi) = s.profile.z_span();
    let (lo, hi) = (lo.max(s.z_span.0), hi.min(s.z_span.1));
    if lo > hi {
        return (Vec::new(), Vec::new());
    }
    // Sample every dz, and just beside every point of the contour on both sides (a step's
    // two radii; a tenth of a micrometre off it, so that a move ending on a face's z is
    // not read as cutting into the face).
    const BESIDE: f64 = 1e-7;
    let mut zs: Vec<f64> = Vec::new();
    let n = ((hi - lo) / s.dz).ceil().max(1.0) as usize;
    let points = s.profile.points();
    for j in 0..=n {
        let z = (lo + s.dz * j as f64).min(hi);
        // On a point of the contour (to rounding) only the samples beside it stand.
        if points.iter().all(|p| (p.0 - z).abs() > 10.0 * BESIDE) {
            zs.push(z);
        }
    }
    for &(z, _) in points {
        zs.push(z - BESIDE);
        zs.push(z + BESIDE);
    }
    zs.retain(|z| *z >= lo && *z <= hi);
    zs.sort_by(f64::total_cmp);
    let compared = s.thread.and_then(|t| t.1);
    let zone = s.thread.and_then(|(t, _)| {
        let (a, b) = (t.helix.z0, t.helix.z(t.turns));
        // A taper thread's radii change along it (its cones): the band takes them all.
        let spread = t.taper.map_or(0.0, |tp| tp.slope.abs() * (b - a).abs());
        let radii = (
            t.root_radius.min(t.crest_radius) - spread,
            t.root_radius.max(t.crest_radius) + spread,
        );
        // Around the thread's middle: its ends may lie in a chamfer that runs below the
        // root (the part's contour is then lower than any groove there).
        let m = 0.5 * (a + b);
        s.profile.band_around((m, m), radii)
    });
    let q_root = s.thread.map(|(t, _)| s.sense * t.root_radius);
    // The contour's q at each sample (None off the contour or inside the compared span).
    let part: Vec<Option<f64>> = zs
        .iter()
        .map(|&z| {
            if compared.is_some_and(|(a, b)| z > a && z < b) {
                return None;
            }
            s.profile
                .radius(z, Approach::FromAbove)
                .map(|r| s.sense * r)
        })
        .collect();
    let mut gouges: Vec<PartGouge> = Vec::new();
    let mut worst = |by: Cutter, cut: &dyn Fn(f64) -> f64, z_range: (f64, f64), pass: bool| {
        let first = zs.partition_point(|z| *z < z_range.0);
        let mut best: Option<PartGouge> = None;
        for (k, &z) in zs.iter().enumerate().skip(first) {
            if z > z_range.1 {
                break;
            }
            let Some(q_part) = part[k] else { continue };
            let floor = match (pass, zone, q_root) {
                (true, Some((a, b)), Some(q)) if z > a && z < b => q.min(q_part),
                _ => q_part,
            };
            let depth = floor - cut(z).max(s.q_floor);
            if depth > s.tolerance && best.is_none_or(|g| depth > g.depth) {
                best = Some(PartGouge {
                    by,
                    depth,
                    z,
                    floor: s.sense * floor,
                });
            }
        }
        gouges.extend(best);
    };
    for (i, c) in s.turned.cuts.iter().enumerate() {
        let Some(span) = c.span(s.q_blank) else {
            continue;
        };
        worst(
            Cutter::Move(i),
            &|z| envelope(&c.tool, &c.path, z),
            span,
            false,
        );
    }
    for (i, p) in s.passes.iter().enumerate() {
        let shape = TurningTool::insert(&s.tools[p.tool], s.sense < 0.0);
        let cut = TurnCut {
            tool: shape,
            path: TurnPath::of_move(
                &shape,
                s.sense,
                (p.z_start, p.x_start),
                (p.z_end, p.x_end),
                None,
            ),
        };
        let Some(span) = cut.span(s.q_blank) else {
            continue;
        };
        worst(
            Cutter::Pass(i),
            &|z| envelope(&cut.tool, &cut.path, z),
            span,
            true,
        );
    }
    // Leftover: the turned stock outside the contour where a feed move cut.
    let mut leftovers: Vec<PartLeftover> = Vec::new();
    let mut run: Option<PartLeftover> = None;
    for (k, &z) in zs.iter().enumerate() {
        let turned = s
            .turned
            .cuts
            .iter()
            .map(|c| envelope(&c.tool, &c.path, z))
            .fold(f64::INFINITY, f64::min);
        let height = match part[k] {
            Some(q_part) if turned < s.q_blank => turned.max(s.q_floor) - q_part,
            _ => f64::NEG_INFINITY,
        };
        if height > s.tolerance {
            let r = run.get_or_insert(PartLeftover {
                height,
                z,
                span: (z, z),
            });
            r.span.1 = z;
            if height > r.height {
                (r.height, r.z) = (height, z);
            }
        } else if let Some(r) = run.take() {
            leftovers.push(r);
        }
    }
    leftovers.extend(run);
    (gouges, leftovers)
}

#[cfg(test)]
mod tests;
