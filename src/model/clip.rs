//! The lower of two axial profiles: the ideal thread where the finished part's contour
//! (its lead-in chamfer, a run-out relief, a smaller diameter) lies below it.
//!
//! Both profiles are polylines of `(z, h)` vertices with z non-decreasing, a vertical step
//! being two vertices at one z. The thread's ideal covers its whole window; the part's
//! contour only its own span, outside of which it says nothing (taken as no bound). The
//! result is the pointwise minimum, again such a polyline: the vertices of whichever
//! profile is lower, the steps of both, and the points where they cross. Where the thread
//! is lower on both sides of a vertex it keeps its own vertex bit for bit and gains none of
//! the contour's, so a contour that stays strictly above the thread leaves its profile
//! unchanged (one that touches it adds vertices on its segments).

use crate::model::thread::Vertex;

/// The values just below and just above `z` of the polyline `p` (the first and the last
/// vertex at `z` where it is a vertex; a point of a segment otherwise), and whether `z` is
/// a vertex. `None` outside the polyline's span; at its ends the missing side is
/// infinite (no bound past them).
fn limits(p: &[Vertex], z: f64) -> Option<(f64, f64, bool)> {
    let (first, last) = (p[0].z, p[p.len() - 1].z);
    if z < first || z > last {
        return None;
    }
    // The vertices at exactly z: [a, b).
    let a = p.partition_point(|v| v.z < z);
    let b = p.partition_point(|v| v.z <= z);
    if a < b {
        let below = if z == first { f64::INFINITY } else { p[a].h };
        let above = if z == last { f64::INFINITY } else { p[b - 1].h };
        return Some((below, above, true));
    }
    let (u, v) = (p[a - 1], p[a]);
    let h = u.h + (v.h - u.h) * (z - u.z) / (v.z - u.z);
    Some((h, h, false))
}

/// The lower envelope of the ideal `f` (covering every z the result needs) and the part's
/// contour `g` (its own span only), as described in the module docs.
pub(crate) fn lower(f: &[Vertex], g: &[Vertex]) -> Vec<Vertex> {
    if f.len() < 2 || g.len() < 2 {
        return f.to_vec();
    }
    let (f_lo, f_hi) = (f[0].z, f[f.len() - 1].z);
    let mut zs: Vec<f64> = f
        .iter()
        .map(|v| v.z)
        .chain(g.iter().map(|v| v.z).filter(|&z| z > f_lo && z < f_hi))
        .collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup();
    let inf = (f64::INFINITY, f64::INFINITY, false);
    let mut out: Vec<Vertex> = Vec::with_capacity(f.len() + 2 * g.len());
    let push = |out: &mut Vec<Vertex>, z: f64, h: f64| {
        if out.last() != Some(&Vertex { z, h }) {
            out.push(Vertex { z, h });
        }
    };
    let n = zs.len();
    for k in 0..n {
        let z = zs[k];
        let (fl, fr, is_f) = limits(f, z).unwrap_or(inf);
        let (gl, gr, is_g) = limits(g, z).unwrap_or(inf);
        // A vertex of one profile where the other is strictly lower on both sides is not
        // on the envelope; where they touch it may be (the other turns away from it).
        let f_below = fl < gl && fr < gr;
        let g_below = gl < fl && gr < fr;
        let keep = (k == 0 || k + 1 == n) || ((is_f || !f_below) && (is_g || !g_below));
        if keep {
            // The ends of the window: the ideal's own first and last values.
            let (l, r) = if k == 0 {
                (fr.min(gr), fr.min(gr))
            } else if k + 1 == n {
                (fl.min(gl), fl.min(gl))
            } else {
                (fl.min(gl), fr.min(gr))
            };
            push(&mut out, z, l);
            push(&mut out, z, r);
        }
        if k + 1 < n {
            // Both are straight on (z, z1): at most one crossing.
            let z1 = zs[k + 1];
            let (f1, _, _) = limits(f, z1).unwrap_or(inf);
            let (g1, _, _) = limits(g, z1).unwrap_or(inf);
            let (d0, d1) = (fr - gr, f1 - g1);
            if d0.is_finite()
                && d1.is_finite()
                && ((d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0))
            {
                let u = d0 / (d0 - d1);
                let zc = z + (z1 - z) * u;
                if zc > z && zc < z1 {
                    push(&mut out, zc, fr + (f1 - fr) * u);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Rng;

    fn v(z: f64, h: f64) -> Vertex {
        Vertex { z, h }
    }

    /// The value of a polyline at `z` from below or above, by brute force over its
    /// segments (the oracle): `None` outside its span.
    fn at(p: &[Vertex], z: f64, above: bool) -> Option<f64> {
        if z < p[0].z || z > p[p.len() - 1].z {
            return None;
        }
        let mut val = None;
        for w in p.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a.z <= z && z <= b.z && a.z < b.z {
                let h = a.h + (b.h - a.h) * (z - a.z) / (b.z - a.z);
                // Below: the last segment reaching z from below; above: the first leaving it.
                if above && z < b.z && val.is_none() {
                    val = Some(h);
                }
                if !above && z > a.z {
                    val = Some(h);
                }
            }
        }
        val.or_else(|| {
            // Only vertical segments there: the first or last vertex at z.
            let at_z: Vec<&Vertex> = p.iter().filter(|q| q.z == z).collect();
            at_z.first()
                .map(|q| if above { at_z[at_z.len() - 1].h } else { q.h })
        })
    }

    fn profile(rng: &mut Rng, z0: f64, z1: f64, n: usize) -> Vec<Vertex> {
        let mut zs: Vec<f64> = (0..n).map(|_| rng.range(z0, z1)).collect();
        zs.push(z0);
        zs.push(z1);
        zs.sort_by(f64::total_cmp);
        let mut out = Vec::new();
        for (i, &z) in zs.iter().enumerate() {
            out.push(v(z, rng.range(0.0, 2.0).round() * 0.5));
            // Some vertical steps.
            if i > 0 && i + 1 < zs.len() && rng.next() < 0.3 {
                out.push(v(z, rng.range(-0.5, 2.0)));
            }
        }
        out
    }

    #[test]
    fn the_envelope_is_the_pointwise_minimum_everywhere() {
        let mut rng = Rng(0x5eed_c11f);
        for case in 0..400 {
            let f = profile(&mut rng, -10.0, 10.0, 12);
            let (a, b) = (rng.range(-14.0, 4.0), rng.range(-4.0, 14.0));
            let g = profile(&mut rng, a.min(b), a.max(b) + 0.5, 5);
            let m = lower(&f, &g);
            assert!(
                m.windows(2).all(|w| w[0].z <= w[1].z),
                "case {case}: z order"
            );
            for i in 0..=2000 {
                let z = -10.0 + 20.0 * i as f64 / 2000.0 + 1e-7;
                if z >= 10.0 {
                    continue;
                }
                for above in [false, true] {
                    let want = match at(&g, z, above) {
                        Some(h) => at(&f, z, above).unwrap().min(h),
                        None => at(&f, z, above).unwrap(),
                    };
                    let got = at(&m, z, above).unwrap();
                    assert!(
                        (got - want).abs() < 1e-9,
                        "case {case} z {z}: {got} vs min {want}\nf {f:?}\ng {g:?}\nm {m:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_contour_above_the_thread_changes_nothing() {
        let mut rng = Rng(7);
        for _ in 0..200 {
            let f = profile(&mut rng, -10.0, 10.0, 12);
            let mut g = profile(&mut rng, -12.0, 8.0, 5);
            for p in &mut g {
                p.h += 3.0;
            }
            assert_eq!(lower(&f, &g), f);
        }
    }

    #[test]
    fn a_lead_in_chamfer_cuts_the_first_crest() {
        // A crest at h 1.0, a groove from z -1 to 1; the part's 45 deg chamfer from h 0 at
        // z 2 up to h 2 at z 0 (z decreasing into the part) lowers the crest beyond z 1.
        let f = [
            v(-3.0, 1.0),
            v(-1.0, 1.0),
            v(-0.5, 0.0),
            v(0.5, 0.0),
            v(1.0, 1.0),
            v(4.0, 1.0),
        ];
        let g = [v(-5.0, 3.0), v(0.0, 2.0), v(2.0, 0.0)];
        let m = lower(&f, &g);
        // The crest meets the chamfer at h 1: z 1.0, where the flank reaches it too.
        assert_eq!(
            m,
            vec![
                v(-3.0, 1.0),
                v(-1.0, 1.0),
                v(-0.5, 0.0),
                v(0.5, 0.0),
                v(1.0, 1.0),
                v(2.0, 0.0),
                v(2.0, 1.0),
                v(4.0, 1.0)
            ]
        );
    }

    #[test]
    fn a_chamfer_from_a_crest_flat_at_crest_height() {
        // The chamfer starts on a crest flat at exactly the crest's height (a part drawn at
        // the thread's major diameter): its corner is on the envelope.
        let f = [
            v(-3.0, 1.0),
            v(-2.5, 0.0),
            v(-1.5, 0.0),
            v(-1.0, 1.0),
            v(1.0, 1.0),
            v(2.0, 0.0),
            v(3.0, 0.0),
        ];
        let g = [v(-4.0, 1.0), v(0.0, 1.0), v(1.0, 0.0)];
        assert_eq!(
            lower(&f, &g),
            vec![
                v(-3.0, 1.0),
                v(-2.5, 0.0),
                v(-1.5, 0.0),
                v(-1.0, 1.0),
                v(0.0, 1.0),
                v(1.0, 0.0),
                v(1.0, 1.0),
                v(2.0, 0.0),
                v(3.0, 0.0)
            ]
        );
    }
}
