//! Which points of a run of the comparison cannot beat the extremes found so far, decided
//! for the whole run at once.
//!
//! A **run** is a stretch of cells of one column with the same cut height `h` over one
//! flat of the ideal profile at the same stored height (an uncut groove at crest height, a
//! tool's flat bottom above or below a root or a crest). Every point of it deviates by the
//! same radial gap `g`, so the comparison's volumes are the same for each; its normal
//! distances differ (a wall is near one end and far from the other). The comparison keeps,
//! per flank, the first point with the largest distance: a point can change that only if
//! its distance beats the flank's maximum so far. [`danger`] proves, for most points of a
//! run, that none can, from a few distances computed for the whole run:
//!
//! - every point's distance is at most `g` (the flat under it) and at most the larger of
//!   its distances to the segments either side of the flat (the nearer of two walls,
//!   whose distances grow and shrink along the run): one bound `u` for the run;
//! - a segment can be a point's nearest only if it lies within `u` of the run, and not
//!   where the point's nearest spot on it is a vertex whose other segment the vertex rule
//!   ([`ColumnIdeal::distance`]'s bisector of the normals) always prefers;
//! - for a segment that can be nearest and whose flank's maximum is below `u`, a point
//!   nearest to it may beat that maximum only if its distance to the segment does (the
//!   distance to a segment is convex along the run: the points within the maximum form
//!   one interval, found by bisection from the run's point nearest to the segment), is at
//!   most `g` (another interval) and its distance to both sides beats it too (an
//!   interval, found by bisection as well).
//!
//! The points left (a few ranges, at a run's ends or around a wall's far side) are
//! compared one by one, exactly as before: the extremes, and which point holds each, are
//! those of computing every distance. Distances are computed with the same
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

/// The points of `run` that may beat `floor` (per flank, in [`Flank::ALL`] order, the
/// largest distance so far; `-inf` for none) on whichever flank they are nearest to, as
/// sorted disjoint index ranges in `out`; every other point is proven unable to (its
/// distance is at most its flank's maximum so far). `kinds`: the flank of each segment.
pub(crate) fn danger<F: Fn(usize) -> f64>(
    ideal: &ColumnIdeal,
    kinds: &[Flank],
    run: &Run<F>,
    floor: &[f64; 4],
    out: &mut Vec<(usize, usize)>,
) {
    out.clear();
    let v = &ideal.verts;
    let (m, h, seg) = (run.m, run.h, run.seg);
    if m < 2 || seg >= kinds.len() {
        out.push((0, m));
        return;
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
        out.push((0, m));
        return;
    }
    if floor.iter().all(|&f| g <= f) {
        return;
    }
    let n = kinds.len();
    let sides = Sides { v, seg, n, h };
    let u = g.min(sides.bound((za, zb)));
    let reach = u * (1.0 + REL) + ABS;
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
        // The points nearest to this segment that may beat `f`: those whose distance to
        // it exceeds `f` (outside one interval, the distance to it being convex along
        // the run) and whose distance to both sides of the flat does too (an interval:
        // one distance grows along the run, the other shrinks).
        let c = if f.is_finite() {
            (f - ABS) / (1.0 + REL)
        } else {
            -1.0
        };
        let (i1, i2) = if c < 0.0 { (0, m) } else { sides.above(run, c) };
        if i1 >= i2 {
            return true;
        }
        // Nor can a point farther than `g` from the segment be nearest to it (its
        // distance is at most `g`): those within it form an interval too.
        let Some((x1, x2)) = within(run, s0, s1, g * (1.0 + REL) + ABS, (i1, i2)) else {
            return true;
        };
        match within(run, s0, s1, c, (x1, x2)) {
            Some((w1, w2)) => {
                out.push((x1, w1));
                out.push((w2, x2));
            }
            None => out.push((x1, x2)),
        }
        true
    };
    let mut i = seg;
    while i < n && v[i].z - zb <= reach {
        if !visit(i) {
            out.clear();
            out.push((0, m));
            return;
        }
        i += 1;
    }
    let mut i = seg;
    while i > 0 && za - v[i].z <= reach {
        i -= 1;
        if !visit(i) {
            out.clear();
            out.push((0, m));
            return;
        }
    }
    // Sorted, empty ones dropped, overlapping and touching ones merged.
    out.retain(|r| r.0 < r.1);
    out.sort_unstable();
    let mut k = 0;
    for r in 0..out.len() {
        if k > 0 && out[r].0 <= out[k - 1].1 {
            out[k - 1].1 = out[k - 1].1.max(out[r].1);
        } else {
            out[k] = out[r];
            k += 1;
        }
    }
    out.truncate(k);
}

/// The first index in `[lo, hi)` where `pred` fails (`hi` if none), `pred` holding on a
/// prefix of the range. The index before the answer, when in range, is one `pred` was
/// evaluated on and held.
fn partition(mut lo: usize, mut hi: usize, pred: impl Fn(usize) -> bool) -> usize {
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The distance the comparison computes from `p` to segment `[s0, s1]` (the same bits).
#[inline]
fn dist(p: DVec2, s0: Vertex, s1: Vertex) -> f64 {
    segment_foot(p, s0.vec(), s1.vec()).0.sqrt()
}

/// The segments either side of the flat `seg` under a run at height `h`: the one before
/// ends at or before the run, so the distance to it does not decrease along the run; the
/// one after begins at or after it, so the distance to it does not increase. Every
/// point's distance is at most the smaller of the two.
struct Sides<'a> {
    v: &'a [Vertex],
    seg: usize,
    n: usize,
    h: f64,
}

impl Sides<'_> {
    /// Distance to the segment before (`inf` without one).
    fn inc(&self, z: f64) -> f64 {
        if self.seg == 0 {
            return f64::INFINITY;
        }
        dist(
            DVec2::new(z, self.h),
            self.v[self.seg - 1],
            self.v[self.seg],
        )
    }

    /// Distance to the segment after (`inf` without one).
    fn dec(&self, z: f64) -> f64 {
        if self.seg + 1 >= self.n {
            return f64::INFINITY;
        }
        dist(
            DVec2::new(z, self.h),
            self.v[self.seg + 1],
            self.v[self.seg + 2],
        )
    }

    /// An upper bound of the largest, over `[za, zb]`, of the smaller distance.
    fn bound(&self, (za, zb): (f64, f64)) -> f64 {
        let (ib, da) = (self.inc(zb), self.dec(za));
        if ib <= self.dec(zb) {
            return ib;
        }
        if self.inc(za) >= da {
            return da;
        }
        // inc < dec at `lo`, inc >= dec at `hi`: the largest of the smaller one lies
        // between them and is at most min(inc(hi), dec(lo)).
        let (mut lo, mut hi) = (za, zb);
        for _ in 0..16 {
            let mid = 0.5 * (lo + hi);
            if self.inc(mid) < self.dec(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.inc(hi).min(self.dec(lo))
    }

    /// The run's points whose smaller distance exceeds `c` (with the margin of the
    /// rounding): an index interval, after the distance before passes `c` and before the
    /// distance after falls to it. Points outside it are within `c` of a side (the points
    /// next to the answer's ends were computed to be).
    fn above<F: Fn(usize) -> f64>(&self, run: &Run<F>, c: f64) -> (usize, usize) {
        let z = &run.z_of;
        let i1 = partition(0, run.m, |i| self.inc(z(i)) <= c);
        let i2 = partition(i1, run.m, |i| self.dec(z(i)) > c);
        (i1, i2)
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

/// `x + v + v + ... + v` (`n` additions of `v`, each rounded, in order) without the `n`
/// dependent additions: the bits of the serial sum, which the report's volumes are.
/// `x` and `v` non-negative and finite.
///
/// Within one binade `[2^e, 2^(e+1))` the representable numbers are evenly spaced by
/// `ulp = 2^(e-52)`, so adding `v` to any of them rounds to the same step, the multiple of
/// `ulp` nearest to `v`, unless `v` lies exactly halfway between two multiples (then the
/// tie goes to the even neighbour, which alternates): the sum advances by that one step
/// until it would reach the next binade. Those steps are taken at once (`k * step` and
/// `x + k * step` are multiples of `ulp` below `2^(e+1)`: exact); the rest one by one.
#[inline(always)]
pub(crate) fn add_repeated(x: f64, v: f64, n: usize) -> f64 {
    match n {
        0 => x,
        1 => x + v,
        2 => x + v + v,
        3 => x + v + v + v,
        _ => add_many(x, v, n),
    }
}

/// [`add_repeated`] for longer runs.
#[inline(never)]
fn add_many(mut x: f64, v: f64, mut n: usize) -> f64 {
    debug_assert!(x >= 0.0 && v >= 0.0 && x.is_finite() && v.is_finite());
    while n > 0 {
        // Small counts, sums not yet normal, or steps not small against the sum: add.
        if n < 4 || x < f64::MIN_POSITIVE || v >= 0.25 * x {
            x += v;
            n -= 1;
            continue;
        }
        let e = (x.to_bits() >> 52) as i64; // biased exponent, x normal and positive
        if e < 53 {
            x += v;
            n -= 1;
            continue;
        }
        // ulp = 2^(e - 1075) and its inverse 2^(1075 - e), both normal here.
        let ulp = f64::from_bits(((e - 52) as u64) << 52);
        let inv_ulp = f64::from_bits(((2098 - e) as u64) << 52);
        let top = f64::from_bits(((e + 1) as u64) << 52);
        // v = q ulp + r, 0 <= r < ulp; all exact (scaling by a power of two; v / ulp <
        // 2^51 here, so truncation is the floor, without a libm call).
        let q = ((v * inv_ulp) as u64) as f64;
        let r = v - q * ulp;
        if r == 0.5 * ulp {
            x += v;
            n -= 1;
            continue;
        }
        let step = if r < 0.5 * ulp {
            q * ulp
        } else {
            (q + 1.0) * ulp
        };
        if step == 0.0 {
            return x;
        }
        // Whole steps that stay strictly below the next binade: all `n` when even their
        // rounded product leaves a margin, else as many as the quotient allows (one
        // short, for safety against its rounding).
        let span = top - x;
        let room = if (n as f64) * step < span * (1.0 - 1e-15) {
            n as f64
        } else {
            (((span / step) as u64) as f64 - 1.0).min(n as f64)
        };
        if room < 1.0 {
            x += v;
            n -= 1;
            continue;
        }
        let k = room as usize;
        x += k as f64 * step;
        n -= k;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Lcg;

    /// The closed form equals the serial sum bit for bit: random sums and terms over many
    /// magnitudes (terms from far below an ulp of the sum to above it), terms exactly half
    /// an ulp and an ulp and a half (ties to even, which alternate), sums starting at 0 and
    /// at binade edges, counts that cross several binades, and the volumes' own
    /// magnitudes (1e-9 to 1e-3 mm^3 per cell, sums to 1e5).
    #[test]
    fn repeated_additions_equal_the_serial_sum() {
        let mut rng = Lcg(7);
        let serial = |mut x: f64, v: f64, n: usize| {
            for _ in 0..n {
                x += v;
            }
            x
        };
        let mut cases = 0;
        for _ in 0..20_000 {
            let x = match (rng.next() * 4.0) as u32 {
                0 => 0.0,
                1 => 2f64.powi((rng.next() * 40.0) as i32 - 20),
                2 => 2f64.powi((rng.next() * 40.0) as i32 - 20) * (1.0 - 1e-16 * rng.next()),
                _ => 10f64.powf(rng.next() * 10.0 - 5.0),
            };
            let v = match (rng.next() * 5.0) as u32 {
                0 if x > 0.0 => {
                    // Exactly half (or one and a half) ulps of x.
                    let e = (x.to_bits() >> 52) as i64;
                    let ulp = f64::from_bits(((e - 52).max(1) as u64) << 52);
                    ulp * if rng.next() < 0.5 { 0.5 } else { 1.5 }
                }
                1 => 0.0,
                _ => x.max(1e-12) * 10f64.powf(-rng.next() * 18.0),
            };
            let n = (10f64.powf(rng.next() * 5.0)) as usize;
            assert_eq!(
                add_repeated(x, v, n).to_bits(),
                serial(x, v, n).to_bits(),
                "x={x:e} v={v:e} n={n}"
            );
            cases += 1;
        }
        // The volumes' own magnitudes.
        for _ in 0..2_000 {
            let x = rng.next() * 10f64.powf(rng.next() * 5.0);
            let v = 10f64.powf(-9.0 + 6.0 * rng.next());
            let n = (rng.next() * 20_000.0) as usize;
            assert_eq!(add_repeated(x, v, n).to_bits(), serial(x, v, n).to_bits());
            cases += 1;
        }
        // Sums that reach the next binade exactly after k0 steps (and one before, one
        // after, a few after): the steps taken at once must stop short of it.
        for _ in 0..4_000 {
            let e = (rng.next() * 60.0) as i32 - 30;
            let top = 2f64.powi(e + 1);
            let ulp = 2f64.powi(e - 52);
            let step = ulp * (1.0 + (rng.next() * 1e6).floor());
            let k0 = 4 + (rng.next() * 5_000.0) as usize;
            let x = top - k0 as f64 * step;
            if x < top / 2.0 {
                continue;
            }
            // The term: the step itself, or off it by less than half an ulp.
            let v = step + ulp * 0.49 * (rng.next() - 0.5);
            for n in [k0 - 1, k0, k0 + 1, k0 + 7] {
                assert_eq!(
                    add_repeated(x, v, n).to_bits(),
                    serial(x, v, n).to_bits(),
                    "edge x={x:e} v={v:e} n={n}"
                );
            }
            cases += 1;
        }
        assert!(cases > 23_000, "{cases}");
    }
}
