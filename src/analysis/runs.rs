//! Which points of a run of the comparison cannot beat the extremes found so far, decided
//! for the whole run at once.
//!
//! A **run** is a stretch of cells of one column with the same cut height `h` over one
//! flat of the ideal profile at the same stored height (an uncut groove at crest height, a
//! tool's flat bottom above or below a root or a crest). Every point of it deviates by the
//! same radial gap `g`, so the comparison's volumes are the same for each; its normal
//! distances differ (a wall is near one end and far from the other). The comparison keeps,
//! per flank, the first point with the largest distance: a point can change that only if
//! its distance beats the flank's maximum so far. [`safe_middle`] proves, for the points
//! in the middle of a run, that none can, from a few distances of the run's ends:
//!
//! - every point's distance is at most `g` (the flat under it) and at most the larger of
//!   its distances to the segments either side of the flat (the nearer of two walls,
//!   whose distances grow and shrink along the run): one bound `u` for the run;
//! - a segment can be a point's nearest only if it lies within `u` of the run, and not
//!   where the point's nearest spot on it is a vertex whose other segment the vertex rule
//!   ([`ColumnIdeal::distance`]'s bisector of the normals) always prefers;
//! - for a segment that can be nearest and whose flank's maximum is below `u`, the
//!   distance to it along the run is convex, so the points within the maximum form one
//!   interval, found by bisection from the run's point nearest to the segment.
//!
//! The points outside the interval of every such segment (a prefix and a suffix of the
//! run) are compared one by one, exactly as before: the extremes, and which point holds
//! each, are those of computing every distance. Distances are computed with the same
//! function as the comparison's (the same bits), and the bounds derived from exact
//! geometry carry a relative margin of 1e-9 over the rounding.

use crate::model::geom::segment_foot;
use crate::model::thread::{ColumnIdeal, Flank, Vertex};
use glam::DVec2;

/// Relative margin over rounding for bounds derived from exact geometry.
const REL: f64 = 1e-9;
/// Absolute margin (mm).
const ABS: f64 = 1e-12;

/// A run of points `(z_of(i), h)`, `i` in `0..m`, `z_of` increasing by about `dz`.
pub(crate) struct Run<F: Fn(usize) -> f64> {
    /// The z of the run's `i`-th point, exactly as the comparison computes it.
    pub z_of: F,
    /// Points in the run.
    pub m: usize,
    /// The grid's axial spacing.
    pub dz: f64,
    /// The cut height of every point.
    pub h: f64,
    /// The ideal height stored for every point (the flat's height).
    pub ideal_h: f64,
    /// The segment of the ideal holding every point (a flat).
    pub seg: usize,
}

/// The points `[a, b)` of `run` that cannot beat `floor` (per flank, in [`Flank::ALL`]
/// order, the largest distance so far; `-inf` for none) on whichever flank they are
/// nearest to; `a == b` when none is proven. `kinds`: the flank of each segment.
pub(crate) fn safe_middle<F: Fn(usize) -> f64>(
    ideal: &ColumnIdeal,
    kinds: &[Flank],
    run: &Run<F>,
    floor: &[f64; 4],
) -> (usize, usize) {
    let none = (0, 0);
    let v = &ideal.verts;
    let (m, h, seg) = (run.m, run.h, run.seg);
    if m < 2 || seg >= kinds.len() {
        return none;
    }
    let (za, zb) = ((run.z_of)(0), (run.z_of)(m - 1));
    let (a, b) = (v[seg], v[seg + 1]);
    let g = (h - run.ideal_h).abs();
    // The comparison's distance search starts from the flat with the bound `g`: the flat
    // is found at exactly `g` (its height is the stored one, the point above it, and the
    // axial rounding of the foot, at most ~1e-15 of the largest |z|, vanishes in `g^2`),
    // so the search never falls back to its "nothing within the bound" answer.
    let big = za
        .abs()
        .max(zb.abs())
        .max(a.z.abs())
        .max(b.z.abs())
        .max(1.0);
    if !(a.h == run.ideal_h
        && b.h == run.ideal_h
        && a.z <= za
        && zb <= b.z
        && za < zb
        && g > 1e-6 * big)
    {
        return none;
    }
    if floor.iter().all(|&f| g <= f) {
        return (0, m);
    }
    let u = g.min(sides_bound(v, seg, kinds.len(), (za, zb), h));
    let reach = u * (1.0 + REL) + ABS;
    let (mut lo, mut hi) = (0usize, m);
    let mut visit = |i: usize| -> bool {
        let (s0, s1) = (v[i], v[i + 1]);
        if s0.z == s1.z && s0.h == s1.h {
            // A point segment: its part is decided by index; not handled here.
            return false;
        }
        let f = floor[kinds[i].index()];
        if g <= f || reach <= f {
            return true;
        }
        if segment_to_run(s0, s1, (za, zb), h) > reach || never_nearest(v, i, (za, zb), h) {
            return true;
        }
        // Points nearest to this segment whose distance to it exceeds `f` may win.
        if !f.is_finite() {
            return false;
        }
        let c = (f - ABS) / (1.0 + REL);
        match within(run, s0, s1, c, (lo, hi)) {
            Some((x, y)) => {
                lo = x;
                hi = y;
                true
            }
            None => false,
        }
    };
    let n = kinds.len();
    let mut i = seg;
    while i < n && v[i].z - zb <= reach {
        if !visit(i) {
            return none;
        }
        i += 1;
    }
    let mut i = seg;
    while i > 0 && za - v[i].z <= reach {
        i -= 1;
        if !visit(i) {
            return none;
        }
    }
    if lo < hi {
        (lo, hi)
    } else {
        none
    }
}

/// The distance the comparison computes from `p` to segment `[s0, s1]` (the same bits).
#[inline]
fn dist(p: DVec2, s0: Vertex, s1: Vertex) -> f64 {
    segment_foot(p, s0.vec(), s1.vec()).0.sqrt()
}

/// An upper bound of the largest, over the run `[za, zb]` at height `h`, of the smaller
/// of the distances to the segments before and after the flat `seg`: the one before ends
/// at or before `za`, so the distance to it does not decrease along the run; the one after
/// begins at or after `zb`, so the distance to it does not increase. `inf` without either.
fn sides_bound(v: &[Vertex], seg: usize, n: usize, (za, zb): (f64, f64), h: f64) -> f64 {
    let inc = |z: f64| dist(DVec2::new(z, h), v[seg - 1], v[seg]);
    let dec = |z: f64| dist(DVec2::new(z, h), v[seg + 1], v[seg + 2]);
    match (seg > 0, seg + 1 < n) {
        (false, false) => f64::INFINITY,
        (true, false) => inc(zb),
        (false, true) => dec(za),
        (true, true) => {
            if inc(zb) <= dec(zb) {
                return inc(zb);
            }
            if inc(za) >= dec(za) {
                return dec(za);
            }
            // inc < dec at `lo`, inc >= dec at `hi`: the largest of the smaller one lies
            // between them and is at most min(inc(hi), dec(lo)).
            let (mut lo, mut hi) = (za, zb);
            for _ in 0..16 {
                let mid = 0.5 * (lo + hi);
                if inc(mid) < dec(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            inc(hi).min(dec(lo))
        }
    }
}

/// Distance from segment `[s0, s1]` to the horizontal segment from `(za, h)` to `(zb, h)`
/// (0 where they cross).
fn segment_to_run(s0: Vertex, s1: Vertex, (za, zb): (f64, f64), h: f64) -> f64 {
    let crosses = (s0.h - h) * (s1.h - h) <= 0.0 && s0.h != s1.h && {
        let z = s0.z + (h - s0.h) / (s1.h - s0.h) * (s1.z - s0.z);
        z >= za && z <= zb
    };
    if crosses {
        return 0.0;
    }
    let (ra, rb) = (Vertex { z: za, h }, Vertex { z: zb, h });
    dist(DVec2::new(za, h), s0, s1)
        .min(dist(DVec2::new(zb, h), s0, s1))
        .min(dist(s0.vec(), ra, rb))
        .min(dist(s1.vec(), ra, rb))
}

/// Whether no point of the run is ever given segment `i`: the nearest spot on the segment
/// is one of its vertices for every point (the foot lies outside it), and there the other
/// segment meeting at that vertex is strictly preferred by the vertex rule for every
/// point (its normal is closer to the direction from the vertex to the point).
fn never_nearest(v: &[Vertex], i: usize, (za, zb): (f64, f64), h: f64) -> bool {
    let (s0, s1) = (v[i], v[i + 1]);
    let (sz, sh) = (s1.z - s0.z, s1.h - s0.h);
    let l2 = sz * sz + sh * sh;
    let t = |z: f64| ((z - s0.z) * sz + (h - s0.h) * sh) / l2;
    let (ta, tb) = (t(za), t(zb));
    let last = v.len() - 2;
    let proper = |k: usize| v[k].z != v[k + 1].z || v[k].h != v[k + 1].h;
    // The vertex and the proper segment across it, as the vertex rule finds them.
    let (vertex, other) = if ta.max(tb) < -REL {
        let mut k = i;
        while k > 0 && !proper(k - 1) {
            k -= 1;
        }
        (s0, (k > 0).then(|| k - 1))
    } else if ta.min(tb) > 1.0 + REL {
        let mut k = i + 1;
        while k <= last && !proper(k) {
            k += 1;
        }
        (s1, (k <= last).then_some(k))
    } else {
        return false;
    };
    let Some(o) = other else {
        return false;
    };
    // dot_k(x) = -sh_k x + sz_k (h - vertex.h), x = z - vertex.z; the rule compares
    // dot_o^2 |s_i|^2 against dot_i^2 |s_o|^2.
    let coef = |k: usize| {
        let (p, q) = (v[k], v[k + 1]);
        let (kz, kh) = (q.z - p.z, q.h - p.h);
        (-kh, kz * (h - vertex.h), kz * kz + kh * kh)
    };
    let (ao, bo, lo) = coef(o);
    let (ai, bi, li) = coef(i);
    let prefers_other = |x: f64| {
        let (dotted_o, dotted_i) = (ao * x + bo, ai * x + bi);
        let (wo, wi) = (dotted_o * dotted_o * li, dotted_i * dotted_i * lo);
        wo - wi > REL * (wo + wi) + 1e-300
    };
    let (xa, xb) = (za - vertex.z, zb - vertex.z);
    if !(prefers_other(xa) && prefers_other(xb)) {
        return false;
    }
    // The difference is quadratic in x; convex, its least value may lie inside.
    let curv = li * ao * ao - lo * ai * ai;
    if curv > 0.0 {
        let x = -(li * ao * bo - lo * ai * bi) / curv;
        if x > xa && x < xb && !prefers_other(x) {
            return false;
        }
    }
    true
}

/// The points of `[lo, hi)` of the run within `c` of segment `[s0, s1]` (computed
/// distance), `None` when there are none. The distance along the run is convex: the
/// points within `c` form one interval around the run's point nearest to the segment,
/// whose ends are found by bisection.
fn within<F: Fn(usize) -> f64>(
    run: &Run<F>,
    s0: Vertex,
    s1: Vertex,
    c: f64,
    (lo, hi): (usize, usize),
) -> Option<(usize, usize)> {
    if lo >= hi || c < 0.0 {
        return None;
    }
    let h = run.h;
    let d = |i: usize| dist(DVec2::new((run.z_of)(i), h), s0, s1);
    // Where along the line z -> (z, h) the segment is nearest: where it crosses the line,
    // else at its end nearer to the line in height (either end of a level segment).
    let z_star = if (s0.h - h) * (s1.h - h) <= 0.0 && s0.h != s1.h {
        s0.z + (h - s0.h) / (s1.h - s0.h) * (s1.z - s0.z)
    } else if (s0.h - h).abs() <= (s1.h - h).abs() {
        s0.z
    } else {
        s1.z
    };
    let z0 = (run.z_of)(0);
    let guess = ((z_star - z0) / run.dz).round();
    let guess = guess.clamp(lo as f64, (hi - 1) as f64) as usize;
    let start = [guess, guess.saturating_sub(1), guess + 1]
        .into_iter()
        .filter(|&i| i >= lo && i < hi)
        .find(|&i| d(i) <= c)?;
    // First safe index in [lo, start]: the unsafe ones form a prefix.
    let (mut a, mut b) = (lo, start);
    while a < b {
        let mid = a + (b - a) / 2;
        if d(mid) <= c {
            b = mid;
        } else {
            a = mid + 1;
        }
    }
    let first = a;
    // One past the last safe index in [start, hi): the unsafe ones form a suffix.
    let (mut a, mut b) = (start + 1, hi);
    while a < b {
        let mid = a + (b - a) / 2;
        if d(mid) <= c {
            a = mid + 1;
        } else {
            b = mid;
        }
    }
    Some((first, a))
}
