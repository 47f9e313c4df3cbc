//! The tool in the 3D outputs, at the end of the last pass: the solid the sweep cuts with
//! where the tool has one (a parametric insert's faces, [`crate::kernel::body::body_faces`],
//! or a mesh's), as the convex solid those faces bound (a box clipped by each face's plane,
//! up to one and a half thread depths above the tip); an edge without a body as its profile
//! extruded 3 mm tangentially (a planar edge has no thickness to draw).
//!
//! The tool frame is mapped as the sweep reads it: `H` radially away from the material
//! (`r = r_tip + sense H`), `Y` behind the rake face in the direction the part turns under
//! the tool (a section `phi` behind the rake face meets a column `phi / 2pi` revolutions
//! after the edge, so it lies at the tool's angle `+ spin phi`), `V` along +z from the tip
//! centre.

use crate::job::Job;
use crate::kernel::body::body_faces;
use crate::model::solid::Face;
use crate::model::tool::Tool;
use crate::output::scene::Mesh;
use glam::DVec3;
use std::f64::consts::TAU;

/// Colour of the tool (sRGB).
pub(crate) const TOOL_COLOUR: [u8; 3] = [150, 155, 165];

/// Where the tool stands: its tip's radius, angle and axial position, the thread's sense
/// (+1 outside), the part's spin under it (the pass helix's), and the height to draw up to.
#[derive(Clone, Copy, Debug)]
struct Pose {
    r_tip: f64,
    theta: f64,
    z_tip: f64,
    sense: f64,
    spin: f64,
    top: f64,
}

impl Pose {
    /// A point of the tool frame `[H, Y, V]` in the part frame (mm).
    fn at(&self, p: DVec3) -> [f32; 3] {
        let (c, s) = (self.theta.cos(), self.theta.sin());
        let r = self.r_tip + self.sense * p.x;
        let y = self.spin * p.y;
        [
            (r * c - y * s) as f32,
            (r * s + y * c) as f32,
            (self.z_tip + p.z) as f32,
        ]
    }
}

/// The tool at the end of the last pass (empty without passes): its body's solid where it
/// has one, else its edge profile extruded 3 mm tangentially.
pub fn tool_mesh(job: &Job) -> Mesh {
    let Some((p, tool, t_end)) = job.passes.iter().rev().find_map(|p| {
        let tool = job.tools.get(p.tool)?;
        Some((p, tool, p.revolutions()?))
    }) else {
        return Mesh::default();
    };
    let h = p.helix();
    let z_ref = h.z(t_end);
    let pose = Pose {
        r_tip: p.radius_at(z_ref),
        theta: h.theta0 - h.spin * TAU * t_end,
        z_tip: z_ref - tool.reference_offset(),
        sense: job.thread.sense(),
        spin: h.spin,
        top: job.thread.depth().max(0.5) * 1.5,
    };
    match body_faces(tool) {
        Some(faces) => body_mesh(&faces, tool, &pose),
        None => edge_solid(tool, &pose),
    }
}

/// The convex solid the faces bound (inside `h H + y Y + v V >= d`), in front of nothing
/// (`Y >= 0`, the rake face) and up to `top` above the tip, as triangles.
fn body_mesh(faces: &[Face], tool: &Tool, pose: &Pose) -> Mesh {
    let (v0, v1) = tool.span(pose.top);
    let reach = 4.0 * (pose.top + (v1 - v0).abs()) + 10.0;
    let mut planes: Vec<(DVec3, f64)> = faces
        .iter()
        .map(|f| (DVec3::new(f.h, f.y, f.v), f.d))
        .collect();
    planes.push((DVec3::Y, 0.0));
    planes.push((-DVec3::X, -pose.top));
    let lo = DVec3::new(-reach, -reach, v0.min(v1) - reach);
    let hi = DVec3::new(reach, reach, v0.max(v1) + reach);
    let mut polys = cuboid(lo, hi);
    for (n, d) in planes {
        polys = clip(polys, n, d);
        if polys.is_empty() {
            break;
        }
    }
    let mut mesh = Mesh::default();
    for poly in &polys {
        let first = mesh.positions.len() as u32;
        mesh.positions.extend(poly.iter().map(|&p| pose.at(p)));
        for k in 1..poly.len() as u32 - 1 {
            mesh.indices
                .extend_from_slice(&[first, first + k, first + k + 1]);
        }
    }
    if pose.sense * pose.spin < 0.0 {
        // The map from the tool frame mirrors: keep the triangles outward.
        for t in mesh.indices.chunks_mut(3) {
            t.swap(1, 2);
        }
    }
    mesh.colors = vec![TOOL_COLOUR; mesh.positions.len()];
    mesh
}

/// The six faces of the box `lo..hi`, each counter-clockwise seen from outside.
fn cuboid(lo: DVec3, hi: DVec3) -> Vec<Vec<DVec3>> {
    let c = |x: bool, y: bool, z: bool| {
        DVec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let (f, t) = (false, true);
    vec![
        vec![c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)],
        vec![c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)],
        vec![c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)],
        vec![c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)],
        vec![c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)],
        vec![c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)],
    ]
}

/// A convex polyhedron (its faces, counter-clockwise from outside) cut by the half-space
/// `n . p >= d`: each face clipped, and the cut closed by a face on the plane.
fn clip(polys: Vec<Vec<DVec3>>, n: DVec3, d: f64) -> Vec<Vec<DVec3>> {
    const EPS: f64 = 1e-9;
    let mut out = Vec::with_capacity(polys.len() + 1);
    let mut cut: Vec<DVec3> = Vec::new();
    for poly in polys {
        let mut kept = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (n.dot(a) - d, n.dot(b) - d);
            if da >= -EPS {
                kept.push(a);
            }
            if (da >= -EPS) != (db >= -EPS) {
                let p = a + (b - a) * (da / (da - db));
                kept.push(p);
                cut.push(p);
            }
        }
        if kept.len() >= 3 {
            out.push(kept);
        }
    }
    if cut.len() >= 3 {
        // The new face: the cut points in order around their centre, seen along -n (its
        // outward normal).
        let centre = cut.iter().copied().sum::<DVec3>() / cut.len() as f64;
        let u = (cut[0] - centre).normalize_or_zero();
        let w = n.cross(u);
        cut.sort_by(|a, b| {
            let (pa, pb) = (*a - centre, *b - centre);
            let ang = |p: DVec3| -(p.dot(w)).atan2(p.dot(u));
            ang(pa).total_cmp(&ang(pb))
        });
        cut.dedup_by(|a, b| a.distance(*b) < 1e-9);
        if cut.len() >= 3 {
            out.push(cut);
        }
    }
    out
}

/// The prism of an edge profile: `h(v) <= h <= top` in the axial plane at the pose's angle,
/// 3 mm wide tangentially, its tip at the pose's radius and axial position, standing away
/// from the part.
fn edge_solid(tool: &Tool, pose: &Pose) -> Mesh {
    let Pose {
        r_tip,
        theta,
        z_tip,
        sense,
        top,
        ..
    } = *pose;
    let (v0, v1) = tool.span(top);
    let n = 48;
    // The profile polygon, counter-clockwise in (v, h): the edge from v1 down to the tip
    // and up to v0 is convex, then the top edge closes it.
    let mut poly: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let v = v1 + (v0 - v1) * k as f64 / n as f64;
            (v, tool.height(v).min(top))
        })
        .collect();
    if let crate::model::tool::Edge::Trapezoid { tip, .. } = tool.edge {
        // The tip corners exactly.
        poly.push((-tip / 2.0, 0.0));
        poly.push((tip / 2.0, 0.0));
        poly.retain(|&(_, h)| h.is_finite());
        poly.sort_by(|a, b| b.0.total_cmp(&a.0));
        poly.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-12);
    }
    let half = 1.5;
    let (c, s) = (theta.cos(), theta.sin());
    let at = |v: f64, hh: f64, w: f64| -> [f32; 3] {
        let r = r_tip + sense * hh;
        [
            (r * c - w * s) as f32,
            (r * s + w * c) as f32,
            (z_tip + v) as f32,
        ]
    };
    let mut mesh = Mesh::default();
    let k = poly.len() as u32;
    for w in [-half, half] {
        for &(v, hh) in &poly {
            mesh.positions.push(at(v, hh, w));
        }
    }
    mesh.colors = vec![TOOL_COLOUR; mesh.positions.len()];
    // Caps (fans; the polygon is convex) and sides.
    for a in 1..k - 1 {
        mesh.indices.extend_from_slice(&[0, a + 1, a]);
        mesh.indices.extend_from_slice(&[k, k + a, k + a + 1]);
    }
    for a in 0..k {
        let b = (a + 1) % k;
        mesh.indices
            .extend_from_slice(&[a, b, k + b, a, k + b, k + a]);
    }
    if sense < 0.0 {
        for t in mesh.indices.chunks_mut(3) {
            t.swap(1, 2);
        }
    }
    mesh
}
