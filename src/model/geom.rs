//! Plane geometry in the axial plane, on glam's `DVec2` (`x` axial, `y` radial or height):
//! the one point-to-segment distance every stage uses.

use glam::DVec2;

/// Squared distance from `p` to the segment `[a, b]`, and whether the nearest point is an
/// end of the segment (-1 `a`, 1 `b`, 0 neither). A degenerate segment is the point `a`.
#[inline]
pub(crate) fn segment_foot(p: DVec2, a: DVec2, b: DVec2) -> (f64, i8) {
    let d = b - a;
    let len2 = d.length_squared();
    let raw = if len2 > 0.0 {
        (p - a).dot(d) / len2
    } else {
        0.0
    };
    let u = raw.clamp(0.0, 1.0);
    let q = a + u * d;
    let end = if u <= 0.0 {
        -1
    } else if u >= 1.0 {
        1
    } else {
        0
    };
    (p.distance_squared(q), end)
}

/// Squared distance from `p` to the segment `[a, b]`.
#[inline]
pub(crate) fn segment_distance2(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    segment_foot(p, a, b).0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_segment_agree_with_the_closed_form() {
        let (a, b) = (DVec2::new(0.0, 0.0), DVec2::new(4.0, 0.0));
        // Beside the segment: the perpendicular; beyond an end: the distance to that end.
        assert_eq!(segment_foot(DVec2::new(1.0, 3.0), a, b), (9.0, 0));
        assert_eq!(segment_foot(DVec2::new(-3.0, 4.0), a, b), (25.0, -1));
        assert_eq!(segment_foot(DVec2::new(7.0, -4.0), a, b), (25.0, 1));
        // A slanted segment: (0,0)-(2,2), the point (2,0) is sqrt(2) from its middle.
        let d = segment_distance2(DVec2::new(2.0, 0.0), a, DVec2::new(2.0, 2.0));
        assert!((d - 2.0).abs() < 1e-15);
        // Degenerate: the point.
        assert_eq!(segment_distance2(DVec2::new(3.0, 4.0), a, a), 25.0);
    }
}
