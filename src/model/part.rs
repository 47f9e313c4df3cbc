//! The finished part as drawn: an outer (or bore) contour along the axis.
//!
//! A [`PartProfile`] is the contour of one surface as a polyline of points `(z, r)` in the
//! order of z: faces and shoulders are vertical steps (two points at one z), chamfers and
//! tapers slanted segments, diameters horizontal ones, relief grooves dips. A thread is
//! drawn as a drawing draws it: its section at the thread's major diameter (outside; the
//! minor diameter of a nut in a bore), with the grooves that the thread's designation
//! stands for not drawn. Beyond its first and last points the profile says nothing (no
//! part there: the bar's end is cut off, or held in the chuck).
//!
//! Queries: the radius at a z on either side of a vertical step ([`PartProfile::radius`]),
//! the z span, and the stretch around a z where the contour stays within a band of radii
//! ([`PartProfile::band_around`]: a thread's section, its chamfers included).

/// One side of an axial position, for a profile's radius at a vertical step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Approach {
    /// Coming from -z: the radius just below `z`.
    FromBelow,
    /// Coming from +z: the radius just above `z`.
    FromAbove,
}

/// Why points are not a contour.
#[derive(Clone, Debug, PartialEq)]
pub enum PartError {
    /// Fewer than two points.
    TooFew,
    /// A coordinate is not a finite number, or a radius is negative.
    NotANumber(usize),
    /// Point `i` goes back along z against the order of the ones before it.
    Backwards(usize),
    /// Point `i` is a third point at one z (a step has two), or repeats the point before.
    Repeated(usize),
}

impl std::fmt::Display for PartError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PartError::TooFew => f.write_str("expected at least two points [z, d]"),
            PartError::NotANumber(i) => write!(
                f,
                "point {i}: expected a finite z and a diameter of at least 0"
            ),
            PartError::Backwards(i) => write!(
                f,
                "point {i}: expected the points in the order of z (all increasing or all decreasing; a face or shoulder is two points at one z)"
            ),
            PartError::Repeated(i) => write!(
                f,
                "point {i}: repeats the point before, or is a third point at one z (a step has two)"
            ),
        }
    }
}

/// A surface's contour as drawn: points `(z, r)` with z non-decreasing; a vertical step is
/// two consecutive points at one z.
#[derive(Clone, Debug, PartialEq)]
pub struct PartProfile {
    points: Vec<(f64, f64)>,
}

impl PartProfile {
    /// The contour of the points `[z, d]` (`d` a diameter) in the order of z, increasing
    /// or decreasing (as a drawing is read from either end).
    pub fn from_diameters(points: &[[f64; 2]]) -> Result<PartProfile, PartError> {
        if points.len() < 2 {
            return Err(PartError::TooFew);
        }
        for (i, p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite() && p[1] >= 0.0) {
                return Err(PartError::NotANumber(i));
            }
        }
        let dir = if points[points.len() - 1][0] >= points[0][0] {
            1.0
        } else {
            -1.0
        };
        for k in 1..points.len() {
            if (points[k][0] - points[k - 1][0]) * dir < 0.0 {
                return Err(PartError::Backwards(k));
            }
            let third = k >= 2 && points[k][0] == points[k - 2][0];
            if points[k] == points[k - 1] || third {
                return Err(PartError::Repeated(k));
            }
        }
        if points[0][0] == points[points.len() - 1][0] {
            return Err(PartError::Backwards(points.len() - 1));
        }
        let mut pts: Vec<(f64, f64)> = points.iter().map(|p| (p[0], p[1] / 2.0)).collect();
        if dir < 0.0 {
            pts.reverse();
        }
        Ok(PartProfile { points: pts })
    }

    /// The points `(z, r)`, z non-decreasing.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The z span the contour covers.
    pub fn z_span(&self) -> (f64, f64) {
        (self.points[0].0, self.points[self.points.len() - 1].0)
    }

    /// The part's radius at `z`, approached from `side` (at a vertical step the two sides
    /// differ; elsewhere they agree); `None` outside the span (at its ends, only from
    /// inside).
    pub fn radius(&self, z: f64, side: Approach) -> Option<f64> {
        let (lo, hi) = self.z_span();
        let outside = match side {
            Approach::FromBelow => z <= lo || z > hi,
            Approach::FromAbove => z < lo || z >= hi,
        };
        if outside {
            return None;
        }
        // The segment holding z on that side: the last one starting below z (from below),
        // or the first one ending above it (from above).
        let seg = match side {
            Approach::FromBelow => self.points.windows(2).rfind(|w| w[0].0 < z && z <= w[1].0),
            Approach::FromAbove => self.points.windows(2).find(|w| w[0].0 <= z && z < w[1].0),
        }?;
        let ((z0, r0), (z1, r1)) = (seg[0], seg[1]);
        Some(r0 + (r1 - r0) * (z - z0) / (z1 - z0))
    }

    /// The largest z interval around `[z_lo, z_hi]` on which the contour's radius stays in
    /// `[r_min, r_max]` (every point of it, both points of its steps): a thread's section
    /// with the chamfers that run into it; `None` where `[z_lo, z_hi]` itself leaves the
    /// band or the span. Its ends are where the contour leaves the band (a chamfer crossing
    /// `r_min`, a shoulder's face) or the span's ends.
    pub fn band_around(
        &self,
        (z_lo, z_hi): (f64, f64),
        (r_min, r_max): (f64, f64),
    ) -> Option<(f64, f64)> {
        let (lo, hi) = self.z_span();
        if z_lo < lo || z_hi > hi {
            return None;
        }
        let inside = |r: f64| (r_min..=r_max).contains(&r);
        // Where the contour is out of the band: z intervals (a point for a step).
        let mut outs: Vec<(f64, f64)> = Vec::new();
        for w in self.points.windows(2) {
            let ((z0, r0), (z1, r1)) = (w[0], w[1]);
            if z0 == z1 {
                if !(inside(r0) && inside(r1)) {
                    outs.push((z0, z0));
                }
                continue;
            }
            // The part of the segment in the band, as parameters along it.
            let (ta, tb) = if r0 == r1 {
                if inside(r0) {
                    (0.0, 1.0)
                } else {
                    (1.0, 0.0)
                }
            } else {
                let ta = (r_min - r0) / (r1 - r0);
                let tb = (r_max - r0) / (r1 - r0);
                (ta.min(tb).max(0.0), ta.max(tb).min(1.0))
            };
            if ta > tb {
                outs.push((z0, z1));
                continue;
            }
            let at = |t: f64| z0 + t * (z1 - z0);
            if ta > 0.0 {
                outs.push((z0, at(ta)));
            }
            if tb < 1.0 {
                outs.push((at(tb), z1));
            }
        }
        let mut zone = (lo, hi);
        for (a, b) in outs {
            if (a == b && (z_lo..=z_hi).contains(&a)) || (a < z_hi && b > z_lo) {
                return None;
            }
            if a >= z_hi {
                zone.1 = zone.1.min(a);
            }
            if b <= z_lo {
                zone.0 = zone.0.max(b);
            }
        }
        Some(zone)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 28's second part: a 45 deg chamfer from d26 at the face to d30 at z -2, the
    /// thread section d30 to the D36 shoulder at z -42, D36 to z -60.
    fn shaft() -> PartProfile {
        PartProfile::from_diameters(&[
            [0.0, 26.0],
            [-2.0, 30.0],
            [-42.0, 30.0],
            [-42.0, 36.0],
            [-60.0, 36.0],
        ])
        .unwrap()
    }

    #[test]
    fn the_radius_on_each_side_of_a_step_and_along_a_chamfer() {
        let p = shaft();
        use Approach::{FromAbove, FromBelow};
        assert_eq!(p.z_span(), (-60.0, 0.0));
        assert_eq!(p.radius(-42.0, FromBelow), Some(18.0));
        assert_eq!(p.radius(-42.0, FromAbove), Some(15.0));
        assert_eq!(p.radius(-20.0, FromBelow), Some(15.0));
        assert_eq!(p.radius(-1.0, FromAbove), Some(14.0));
        assert_eq!(p.radius(-1.5, FromBelow), Some(14.5));
        assert_eq!(p.radius(0.0, FromBelow), Some(13.0));
        assert_eq!(p.radius(0.0, FromAbove), None);
        assert_eq!(p.radius(-60.0, FromBelow), None);
        assert_eq!(p.radius(-60.0, FromAbove), Some(18.0));
        assert_eq!(p.radius(1.0, FromBelow), None);
        // Read from the other end, the same contour.
        let mut rev = [
            [0.0, 26.0],
            [-2.0, 30.0],
            [-42.0, 30.0],
            [-42.0, 36.0],
            [-60.0, 36.0],
        ];
        rev.reverse();
        assert_eq!(PartProfile::from_diameters(&rev).unwrap(), p);
    }

    #[test]
    fn a_thread_section_with_its_chamfer_is_the_band_around_the_thread() {
        // M30x2: root r = 13.773131, crest 15. The chamfer enters the band where r =
        // 13.773131: z = -(13.773131 - 13) = -0.773131; the shoulder's face ends it at -42.
        let p = shaft();
        let root = 15.0 - 0.613435 * 2.0;
        let (a, b) = p.band_around((-38.0, -1.0), (root, 15.0)).unwrap();
        assert!((a + 42.0).abs() < 1e-12, "{a}");
        assert!((b + (root - 13.0)).abs() < 1e-12, "{b}");
        // A relief groove d26.5 from -38 to -40 below the root ends the band there.
        let g = PartProfile::from_diameters(&[
            [0.0, 30.0],
            [-38.0, 30.0],
            [-38.0, 26.5],
            [-40.0, 26.5],
            [-40.0, 36.0],
            [-50.0, 36.0],
        ])
        .unwrap();
        assert_eq!(
            g.band_around((-30.0, -1.0), (root, 15.0)),
            Some((-38.0, 0.0))
        );
        // A thread that runs past the section is not within one band.
        assert_eq!(g.band_around((-39.0, -1.0), (root, 15.0)), None);
    }

    #[test]
    fn points_that_are_no_contour_are_refused_by_index() {
        let e = |pts: &[[f64; 2]]| PartProfile::from_diameters(pts).unwrap_err();
        assert_eq!(e(&[[0.0, 10.0]]), PartError::TooFew);
        assert_eq!(
            e(&[[0.0, 10.0], [-1.0, f64::NAN]]),
            PartError::NotANumber(1)
        );
        assert_eq!(e(&[[0.0, 10.0], [-1.0, -2.0]]), PartError::NotANumber(1));
        assert_eq!(
            e(&[[0.0, 10.0], [-2.0, 10.0], [-1.0, 12.0], [-5.0, 12.0]]),
            PartError::Backwards(2)
        );
        assert_eq!(
            e(&[[0.0, 10.0], [-2.0, 10.0], [-2.0, 12.0], [-2.0, 14.0]]),
            PartError::Repeated(3)
        );
        assert_eq!(e(&[[0.0, 10.0], [0.0, 12.0]]), PartError::Backwards(1));
        assert!(e(&[[0.0, 10.0], [0.0, 10.0]])
            .to_string()
            .contains("point 1"));
    }
}
