//! The cameras of the rendered views: orthographic (an engineering drawing, no perspective
//! foreshortening of the thread), framed on the cut part. Pure arithmetic, tested without a
//! GPU.
//!
//! Screen conventions follow the lathe drawing: the part axis `z` runs left to right, the
//! radius `x` points up. A section plane contains the axis; the half of the part on the
//! camera's side of it is cut away.

use crate::output::plot::{BLANK, CUT_NOT_COMPARED};
use crate::output::scene::Scene;
use glam::{DMat4, DVec3, DVec4};

/// Which picture to take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum View {
    /// The whole part from above the front end, at an angle.
    Iso,
    /// The whole part from the side: axis left to right, `x` up.
    Front,
    /// The front view with the near half cut away along the axis: the machined profile at
    /// 0 deg (top) and 180 deg (bottom) as a solid cut face, the ideal profile over it.
    Section,
    /// A section through the worst finding (or, when the cut is within tolerance, the
    /// middle of the compared surface), a few mm wide.
    Closeup,
}

impl View {
    /// Every view, in the order goldens and help texts list them.
    pub const ALL: [View; 4] = [View::Iso, View::Front, View::Section, View::Closeup];

    /// The view's name on the command line and in file names.
    pub fn name(self) -> &'static str {
        match self {
            View::Iso => "iso",
            View::Front => "front",
            View::Section => "section",
            View::Closeup => "closeup",
        }
    }

    /// The view of a name, if it is one.
    pub fn from_name(name: &str) -> Option<View> {
        View::ALL.into_iter().find(|v| v.name() == name)
    }
}

/// A camera: an orthographic projection, its frame, and the section plane if any.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Camera {
    /// World (mm) to clip space, depth 0..1.
    pub(crate) view_proj: DMat4,
    /// Screen right, up and towards the camera, in world coordinates (orthonormal).
    pub(crate) right: DVec3,
    pub(crate) up: DVec3,
    pub(crate) back: DVec3,
    /// Fragments with `dot(n, p) > w` are cut away.
    pub(crate) plane: Option<DVec4>,
    /// Angle of the section's upper generator (rad), for the caption.
    pub(crate) section_angle: Option<f64>,
    /// A whole-part view of an internal thread with its near half cut away (the plane
    /// through the axis facing the camera), so the bore's thread shows.
    pub(crate) cutaway: bool,
    /// The part's axial extent and largest radius (mm): `(z_lo, z_hi, r_max)`.
    pub(crate) part: (f64, f64, f64),
    /// Image size in pixels.
    pub(crate) size: (u32, u32),
    /// Millimetres per pixel.
    pub(crate) mm_per_px: f64,
    /// The eye's position across the view (along `right`, `up`) and the picture's
    /// (left, right, bottom, top) around it, mm.
    pub(crate) centre: (f64, f64),
    pub(crate) window: (f64, f64, f64, f64),
}

impl Camera {
    /// The section plane's quad covering the picture (a triangle strip), for sections.
    pub(crate) fn cap_quad(&self) -> Option<[DVec3; 4]> {
        let plane = self.plane?;
        if self.cutaway {
            // The plane holds the axis and `t`: a quad over the part's extent with a margin.
            let n = plane.truncate();
            let t = n.cross(DVec3::Z);
            let (z0, z1, r) = self.part;
            let m = 0.05 * (z1 - z0 + r) + 1.0;
            let at = |z: f64, s: f64| DVec3::Z * z + t * s;
            let (z0, z1, r) = (z0 - m, z1 + m, r + m);
            return Some([at(z0, -r), at(z1, -r), at(z0, r), at(z1, r)]);
        }
        let (l, r, b, t) = self.window;
        let at = |x: f64, y: f64| self.right * (self.centre.0 + x) + self.up * (self.centre.1 + y);
        Some([at(l, b), at(r, b), at(l, t), at(r, t)])
    }

    /// The pixel `(x, y)` (from the top left, continuous) where `p` lands.
    pub(crate) fn pixel(&self, p: DVec3) -> (f64, f64) {
        let c = self.view_proj * p.extend(1.0);
        (
            (c.x / c.w + 1.0) * 0.5 * self.size.0 as f64,
            (1.0 - c.y / c.w) * 0.5 * self.size.1 as f64,
        )
    }
}

/// Whether a picture of `scene` draws the tool: not for an internal thread, in any view (in
/// the bore it would hide the thread the cut-away and the sections are there to show),
/// and not when there is none. The caption says when a tool is left out, and the framing
/// leaves it out too.
pub(crate) fn draws_tool(scene: &Scene) -> bool {
    !scene.tool.indices.is_empty() && !internal(scene)
}

/// Frame `view` of `scene` in a `width` x `height` image.
pub(crate) fn camera(scene: &Scene, view: View, width: u32, height: u32) -> Camera {
    let tool: &[[f32; 3]] = if draws_tool(scene) {
        &scene.tool.positions
    } else {
        &[]
    };
    let pts = || {
        scene
            .stock
            .positions
            .iter()
            .chain(tool)
            .chain(scene.toolpath.iter().flat_map(|p| &p.points))
            .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
    };
    let stock = || {
        scene
            .stock
            .positions
            .iter()
            .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
    };
    let z_axis = DVec3::Z;
    // (right, up) of each view; `back = right x up` points at the camera.
    let (right, up, theta) = match view {
        View::Iso => {
            // Looking down on the front end: from x (up) 0.55, y 1 (side) and z 0.45.
            let back = DVec3::new(0.55, 1.0, 0.45).normalize();
            let right = DVec3::X.cross(back).normalize();
            (right, back.cross(right), None)
        }
        View::Front => (z_axis, DVec3::X, None),
        View::Section => (z_axis, DVec3::X, Some(0.0)),
        View::Closeup => {
            let theta = closeup_target(scene).1;
            (
                z_axis,
                DVec3::new(theta.cos(), theta.sin(), 0.0),
                Some(theta),
            )
        }
    };
    let back = right.cross(up);
    // An internal thread's whole-part views cut the near half away (the plane through the
    // axis square to the view's direction across it).
    let cutaway = matches!(view, View::Iso | View::Front) && internal(scene);
    let across = DVec3::new(back.x, back.y, 0.0).normalize_or_zero();
    // Extents of the part in the screen frame; depth over everything drawn.
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in stock() {
        let s = DVec3::new(p.dot(right), p.dot(up), 0.0);
        lo = lo.min(s);
        hi = hi.max(s);
    }
    if !lo.x.is_finite() {
        lo = DVec3::splat(-1.0);
        hi = DVec3::splat(1.0);
    }
    let (mut d_lo, mut d_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in pts() {
        d_lo = d_lo.min(p.dot(back));
        d_hi = d_hi.max(p.dot(back));
    }
    let (w_px, h_px) = (width as f64, height as f64);
    // (left, right, bottom, top) of the picture around the eye, in mm.
    let (centre, window) = match view {
        View::Closeup => {
            let (p, _) = closeup_target(scene);
            // A window a sixth of the part long (two or three turns of the seed screws),
            // at least 2 mm, centred on the target.
            let half_w = ((hi.x - lo.x) / 6.0).max(2.0) * 0.5;
            let half_h = half_w * h_px / w_px;
            (
                (p.dot(right), p.dot(up)),
                (-half_w, half_w, -half_h, half_h),
            )
        }
        _ => {
            // The part fills the picture with a margin, centred in it (the legend has its
            // own strip above the picture the camera sees).
            let margin = 1.08;
            let (free_w, free_h) = (w_px.max(1.0), h_px.max(1.0));
            let mm_per_px = ((hi.x - lo.x) / free_w)
                .max((hi.y - lo.y) / free_h)
                .max(1e-6)
                * margin;
            let (hw, hh) = (0.5 * free_w * mm_per_px, 0.5 * free_h * mm_per_px);
            (
                (0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)),
                (-hw, hw, -hh, hh),
            )
        }
    };
    let pad = 1.0 + 0.01 * (d_hi - d_lo).abs();
    let eye_d = d_hi + pad;
    let eye = right * centre.0 + up * centre.1 + back * eye_d;
    let view_m = DMat4::look_to_rh(eye, -back, up);
    let proj = DMat4::orthographic_rh(
        window.0,
        window.1,
        window.2,
        window.3,
        0.0,
        (eye_d - d_lo + pad).max(1e-3),
    );
    let (mut z_lo, mut z_hi, mut r_max) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for p in stock() {
        z_lo = z_lo.min(p.z);
        z_hi = z_hi.max(p.z);
        r_max = r_max.max(p.x.hypot(p.y));
    }
    if !z_lo.is_finite() {
        (z_lo, z_hi) = (-1.0, 1.0);
    }
    let plane = match theta {
        Some(_) => Some(back.extend(0.0)),
        None if cutaway && across != DVec3::ZERO => Some(across.extend(0.0)),
        None => None,
    };
    Camera {
        view_proj: proj * view_m,
        right,
        up,
        back,
        plane,
        section_angle: theta,
        cutaway: plane.is_some() && theta.is_none(),
        part: (z_lo, z_hi, r_max),
        size: (width, height),
        mm_per_px: (window.1 - window.0) / w_px,
        centre,
        window,
    }
}

/// Whether the scene is of an internal thread (its report summary says so).
pub(crate) fn internal(scene: &Scene) -> bool {
    serde_json::from_str::<serde_json::Value>(&scene.summary)
        .is_ok_and(|v| v["thread"]["side"] == "internal")
}

/// Where the close-up looks: the worst finding's point and angle, or, for a cut within
/// tolerance, the compared surface vertex nearest to the middle of the compared thread at
/// 0 deg.
pub(crate) fn closeup_target(scene: &Scene) -> (DVec3, f64) {
    if let Some(f) = &scene.focus {
        let p = DVec3::new(f.point[0] as f64, f.point[1] as f64, f.point[2] as f64);
        return (p, p.y.atan2(p.x));
    }
    let m = &scene.stock;
    let compared = m
        .positions
        .iter()
        .zip(&m.colors)
        .filter(|(_, c)| **c != BLANK && **c != CUT_NOT_COMPARED)
        .map(|(p, _)| p[2] as f64);
    let (z_lo, z_hi) = compared
        .fold(None, |acc: Option<(f64, f64)>, z| {
            Some(acc.map_or((z, z), |(a, b)| (a.min(z), b.max(z))))
        })
        .or_else(|| m.bounds().map(|(lo, hi)| (lo[2] as f64, hi[2] as f64)))
        .unwrap_or((0.0, 0.0));
    let mid = 0.5 * (z_lo + z_hi);
    let r_max = m
        .positions
        .iter()
        .map(|p| (p[0] as f64).hypot(p[1] as f64))
        .fold(0.0, f64::max);
    let target = DVec3::new(r_max, 0.0, mid);
    let best = m
        .positions
        .iter()
        .zip(&m.colors)
        .filter(|(_, c)| **c != BLANK && **c != CUT_NOT_COMPARED)
        .map(|(p, _)| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
        .min_by(|a, b| a.distance(target).total_cmp(&b.distance(target)));
    let p = best.unwrap_or(target);
    (p, p.y.atan2(p.x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::scene::{Focus, Legend, Mesh};

    /// The vertices of a bar of radius `r` from `z0` to `z1` (no triangles needed here).
    fn bar(r: f64, z0: f64, z1: f64) -> Scene {
        let mut positions = Vec::new();
        for k in 0..360 {
            let a = (k as f64).to_radians();
            for z in [z0, z1] {
                positions.push([(r * a.cos()) as f32, (r * a.sin()) as f32, z as f32]);
            }
        }
        let colors = vec![[215, 215, 210]; positions.len()];
        Scene {
            stock: Mesh {
                positions,
                colors,
                indices: Vec::new(),
            },
            ideal: None,
            toolpath: Vec::new(),
            tool: Mesh::default(),
            legend: Legend {
                tolerance_mm: 0.01,
                scale_mm: 0.02,
            },
            focus: None,
            summary: String::new(),
        }
    }

    /// Whole-part views show every vertex inside the picture (the legend has its own strip
    /// outside it), in front of the camera; the front view puts
    /// the axis left to right with `x` up.
    #[test]
    fn whole_part_views_frame_the_part() {
        let s = bar(20.0, -120.0, 0.0);
        for view in [View::Iso, View::Front, View::Section] {
            let c = camera(&s, view, 640, 480);
            for p in &s.stock.positions {
                let q = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                let (x, y) = c.pixel(q);
                assert!((0.0..=640.0).contains(&x), "{view:?}: x {x}");
                assert!((0.0..=480.0).contains(&y), "{view:?}: y {y}");
                let d = (c.view_proj * q.extend(1.0)).z;
                assert!((0.0..=1.0).contains(&d), "{view:?}: depth {d}");
            }
        }
        let c = camera(&s, View::Front, 640, 480);
        let (xa, ya) = c.pixel(DVec3::new(0.0, 0.0, -120.0));
        let (xb, yb) = c.pixel(DVec3::new(0.0, 0.0, 0.0));
        assert!(xb > xa && (ya - yb).abs() < 1e-9);
        let (_, y_up) = c.pixel(DVec3::new(20.0, 0.0, -60.0));
        assert!(y_up < ya);
        // 120 mm over the 640 pixels with the 8 % margin.
        assert!((c.mm_per_px - 1.08 * 120.0 / 640.0).abs() < 1e-12);
    }

    /// An internal thread's iso and front views cut the near half away: the plane holds
    /// the axis, faces the camera (the kept half is the far one), and its cap quad lies on
    /// it and covers the part's section; an external thread's are whole.
    #[test]
    fn internal_threads_are_cut_away_in_whole_views() {
        let mut s = bar(20.0, -120.0, 0.0);
        for view in [View::Iso, View::Front] {
            assert!(camera(&s, view, 640, 480).plane.is_none());
        }
        s.summary = r#"{"thread": {"side": "internal"}}"#.into();
        for view in [View::Iso, View::Front] {
            let c = camera(&s, view, 640, 480);
            assert!(c.cutaway);
            let p = c.plane.unwrap();
            let n = p.truncate();
            assert!(p.w == 0.0 && n.z.abs() < 1e-12 && (n.length() - 1.0).abs() < 1e-12);
            assert!(
                n.dot(c.back) > 0.1,
                "{view:?}: the cut half must face the camera"
            );
            let q = c.cap_quad().unwrap();
            for v in q {
                assert!(n.dot(v).abs() < 1e-9);
            }
            let (zs, ss): (Vec<f64>, Vec<f64>) =
                q.iter().map(|v| (v.z, v.dot(n.cross(DVec3::Z)))).unzip();
            assert!(zs.iter().cloned().fold(f64::INFINITY, f64::min) < -120.0);
            assert!(zs.iter().cloned().fold(f64::NEG_INFINITY, f64::max) > 0.0);
            assert!(ss.iter().all(|x| x.abs() > 20.0));
        }
        // Sections keep their own plane (square to the view), not the cut-away one.
        let c = camera(&s, View::Section, 640, 480);
        assert!(!c.cutaway && c.section_angle.is_some());
    }

    /// The close-up centres the worst finding, and its section plane contains the axis and
    /// the finding's generator, with the finding's side up.
    #[test]
    fn closeup_centres_the_finding_in_its_section_plane() {
        let mut s = bar(20.0, -120.0, 0.0);
        let theta = 2.0_f64;
        let p = DVec3::new(19.0 * theta.cos(), 19.0 * theta.sin(), -47.0);
        s.focus = Some(Focus {
            kind: "gouge".into(),
            value_mm: 0.3,
            point: [p.x as f32, p.y as f32, p.z as f32],
            turn: 3,
            flank: "left".into(),
            angle_deg: theta.to_degrees(),
            z_mm: -47.0,
        });
        let c = camera(&s, View::Closeup, 640, 480);
        let (x, y) = c.pixel(p);
        assert!(
            (x - 320.0).abs() < 1e-3 && (y - 240.0).abs() < 1e-3,
            "{x} {y}"
        );
        let plane = c.plane.unwrap();
        assert!(plane.truncate().dot(p).abs() < 1e-5);
        assert!(plane.truncate().dot(DVec3::Z).abs() < 1e-12);
        assert!((c.section_angle.unwrap() - theta).abs() < 1e-6);
        assert!(c.up.dot(p) > 0.0);
        // A sixth of the part wide.
        assert!((c.mm_per_px * 640.0 - 20.0).abs() < 1e-9);
    }
}
