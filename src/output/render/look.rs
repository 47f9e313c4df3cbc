//! Whether the toolpath would hide the part, measured: the fraction of the part's pixels
//! that the toolpath's one-pixel lines cross in a picture, and what the renders and the HTML
//! viewer do with it by default (draw it, draw it translucent, leave it out). Pure
//! arithmetic on the camera's projection, tested without a GPU.
//!
//! The part's pixels are its silhouette, taken as the convex hull of its projected vertices
//! (a solid of revolution seen in parallel projection: exact for a bar or a tube, a little
//! generous over a thread's grooves). The toolpath's pixels are its segments stepped at
//! half a pixel, counted only where the camera sees them over the part: on the near half of
//! a whole part (the far half is hidden behind it), on the kept half of a cut-away one.

use super::camera::Camera;
use crate::output::scene::Scene;
use glam::DVec3;

/// Up to this fraction of the part's pixels under toolpath lines, the toolpath is drawn in
/// full.
pub(crate) const FULL_UP_TO: f64 = 0.12;
/// Up to this fraction it is drawn translucent ([`DIM_ALPHA`]); beyond it, left out.
pub(crate) const DIM_UP_TO: f64 = 0.3;
/// The opacity of a dimmed toolpath.
pub(crate) const DIM_ALPHA: f64 = 0.3;

/// How the toolpath is drawn by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Look {
    /// Opaque lines.
    Full,
    /// Translucent lines ([`DIM_ALPHA`]).
    Dimmed,
    /// Not drawn.
    Hidden,
}

impl Look {
    /// The look for a coverage (fraction of the part's pixels under toolpath lines).
    pub(crate) fn of(coverage: f64) -> Look {
        if coverage <= FULL_UP_TO {
            Look::Full
        } else if coverage <= DIM_UP_TO {
            Look::Dimmed
        } else {
            Look::Hidden
        }
    }

    /// The name the HTML viewer reads.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Look::Full => "full",
            Look::Dimmed => "dimmed",
            Look::Hidden => "hidden",
        }
    }
}

/// Lower convex hull chain + upper chain (Andrew's monotone chain), counter-clockwise.
fn hull(mut pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut h: Vec<(f64, f64)> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = h.len();
        let it: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in it {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], p) <= 0.0 {
                h.pop();
            }
            h.push(p);
        }
        h.pop();
    }
    h
}

/// The fraction (0 to 1) of the part's pixels in a `cam` picture that the toolpath's lines
/// cross where the camera sees them; 0 without a toolpath.
pub(crate) fn coverage(scene: &Scene, cam: &Camera) -> f64 {
    let (w, h) = (cam.size.0 as usize, cam.size.1 as usize);
    if scene.toolpath.is_empty() || w == 0 || h == 0 {
        return 0.0;
    }
    let p3 = |p: &[f32; 3]| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
    let outline = hull(
        scene
            .stock
            .positions
            .iter()
            .map(|p| cam.pixel(p3(p)))
            .collect(),
    );
    if outline.len() < 3 {
        return 0.0;
    }
    // The silhouette's x interval on each pixel row (at the row's centre).
    let mut rows = vec![(f64::INFINITY, f64::NEG_INFINITY); h];
    let n = outline.len();
    for (y, row) in rows.iter_mut().enumerate() {
        let yc = y as f64 + 0.5;
        for k in 0..n {
            let (a, b) = (outline[k], outline[(k + 1) % n]);
            if (a.1 <= yc) != (b.1 <= yc) {
                let x = a.0 + (yc - a.1) / (b.1 - a.1) * (b.0 - a.0);
                row.0 = row.0.min(x);
                row.1 = row.1.max(x);
            }
        }
    }
    let inside = |x: usize, y: usize| {
        let xc = x as f64 + 0.5;
        xc >= rows[y].0 && xc <= rows[y].1
    };
    let area: usize = (0..h)
        .map(|y| {
            let (a, b) = rows[y];
            if a > b {
                return 0;
            }
            let lo = (a - 0.5).ceil().max(0.0) as usize;
            let hi = ((b - 0.5).floor() as i64).min(w as i64 - 1);
            if hi < lo as i64 {
                0
            } else {
                hi as usize - lo + 1
            }
        })
        .sum();
    if area == 0 {
        return 0.0;
    }
    // Which side of the part the camera sees lines on.
    let seen = |p: DVec3| match cam.plane {
        Some(pl) => pl.truncate().dot(p) <= pl.w,
        None => DVec3::new(p.x, p.y, 0.0).dot(cam.back) >= 0.0,
    };
    let mut hit = vec![false; w * h];
    let mut covered = 0usize;
    for line in &scene.toolpath {
        for s in line.points.windows(2) {
            let (a, b) = (p3(&s[0]), p3(&s[1]));
            if !seen(0.5 * (a + b)) {
                continue;
            }
            let (pa, pb) = (cam.pixel(a), cam.pixel(b));
            let len = (pb.0 - pa.0).hypot(pb.1 - pa.1);
            let steps = (2.0 * len).ceil().max(1.0) as usize;
            for k in 0..=steps {
                let t = k as f64 / steps as f64;
                let (x, y) = (pa.0 + t * (pb.0 - pa.0), pa.1 + t * (pb.1 - pa.1));
                if x < 0.0 || y < 0.0 || x >= w as f64 || y >= h as f64 {
                    continue;
                }
                let (x, y) = (x as usize, y as usize);
                if !hit[y * w + x] && inside(x, y) {
                    hit[y * w + x] = true;
                    covered += 1;
                }
            }
        }
    }
    covered as f64 / area as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::render::camera::camera;
    use crate::output::render::View;
    use crate::output::scene::{Legend, Mesh, PathKind, Polyline};
    use std::f64::consts::TAU;

    /// A bar of radius `r` along z in `[0, len]` (vertices only) with `passes` straight
    /// feed lines on its top generator's plane, `dz` apart... as helices of lead `lead`.
    fn scene(r: f64, len: f64, passes: &[Vec<[f32; 3]>]) -> Scene {
        let mut positions = Vec::new();
        for k in 0..360 {
            let a = (k as f64).to_radians();
            for z in [0.0, len] {
                positions.push([(r * a.cos()) as f32, (r * a.sin()) as f32, z as f32]);
            }
        }
        Scene {
            stock: Mesh {
                colors: vec![[0; 3]; positions.len()],
                positions,
                indices: Vec::new(),
            },
            ideal: None,
            toolpath: passes
                .iter()
                .map(|p| Polyline {
                    kind: PathKind::Feed,
                    points: p.clone(),
                })
                .collect(),
            tool: Mesh::default(),
            legend: Legend {
                tolerance_mm: 0.01,
                scale_mm: 0.02,
            },
            focus: None,
            summary: String::new(),
        }
    }

    /// The hull of a square's corners and inner points is the square, counter-clockwise.
    #[test]
    fn hull_of_a_square() {
        let mut pts = vec![(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        pts.extend([(1.0, 1.0), (0.5, 1.5), (1.0, 0.0)]);
        let h = hull(pts);
        assert_eq!(h, vec![(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]);
    }

    /// In the front view a bar is a rectangle `L x 2R` (in pixels, `mm_per_px` from the
    /// camera); straight lines along z over its near half, `n` rows apart by more than a
    /// pixel, each cover `L / mm_per_px` pixels: coverage `n / (2R / mm_per_px)`, to the
    /// rounding of the rectangle's edges (closed form). Lines on the far half do not count.
    #[test]
    fn coverage_of_straight_lines_over_a_bar() {
        let (r, len) = (10.0, 80.0);
        let empty = scene(r, len, &[]);
        let cam = camera(&empty, View::Front, 640, 400);
        let px = cam.mm_per_px;
        let rows_px = 2.0 * r / px;
        for n in [1usize, 5, 20, 40] {
            // Lines at x = r - (k + 0.5) * 2r/n in front (y = +r/2 > 0: the near half,
            // back is +y in the front view), from end to end.
            let mut lines = Vec::new();
            for k in 0..n {
                let x = r - (k as f64 + 0.5) * 2.0 * r / n as f64;
                lines.push(vec![
                    [x as f32, (0.5 * r) as f32, 0.0],
                    [x as f32, (0.5 * r) as f32, len as f32],
                ]);
            }
            let s = scene(r, len, &lines);
            let c = coverage(&s, &cam);
            let want = n as f64 / rows_px;
            assert!(
                (c - want).abs() <= 0.02 * want + 1.0 / rows_px,
                "{n} lines: coverage {c}, want {want}"
            );
            // The same lines behind the axis are hidden by the part.
            let back: Vec<Vec<[f32; 3]>> = lines
                .iter()
                .map(|l| l.iter().map(|p| [p[0], -p[1], p[2]]).collect())
                .collect();
            assert_eq!(coverage(&scene(r, len, &back), &cam), 0.0);
        }
    }

    /// Helical passes over a bar in the iso view: one is drawn in full; sixty shifted
    /// across one lead (a line every pixel or so, as a many-pass program's feeds lie)
    /// cover most of the near half and are left out.
    #[test]
    fn many_passes_hide_the_part() {
        let (r, len, lead) = (20.0, 60.0, 6.0);
        let helix = |shift: f64| -> Vec<[f32; 3]> {
            let turns = len / lead;
            let n = (turns * 180.0) as usize;
            (0..=n)
                .map(|k| {
                    let t = turns * k as f64 / n as f64;
                    let a = TAU * t;
                    [
                        (r * a.cos()) as f32,
                        (r * a.sin()) as f32,
                        (len - lead * t - shift) as f32,
                    ]
                })
                .collect()
        };
        let one = scene(r, len, &[helix(0.0)]);
        let cam = camera(&one, View::Iso, 640, 400);
        // About 60 px per lead here: a lone helix is a few per cent of the part.
        assert!(lead / cam.mm_per_px > 40.0, "{}", cam.mm_per_px);
        let c1 = coverage(&one, &cam);
        assert!(c1 > 0.005 && c1 <= FULL_UP_TO, "one helix: {c1}");
        assert_eq!(Look::of(c1), Look::Full);
        let many: Vec<Vec<[f32; 3]>> = (0..60).map(|k| helix(lead * k as f64 / 60.0)).collect();
        let cm = coverage(&scene(r, len, &many), &cam);
        assert!(cm > DIM_UP_TO, "sixty helices: {cm}");
        assert_eq!(Look::of(cm), Look::Hidden);
        assert_eq!(Look::of(0.25), Look::Dimmed);
    }
}
