//! Convex tool solids as half-spaces in the tool frame, made from a triangle mesh.
//!
//! The tool frame is the one of [`crate::model::tool`]: `H` the height above the tip away from the
//! material (radially outward for an external tool), `Y` the depth behind the rake face
//! (tangential, on the side the freshly cut surface moves to), `V` the axial offset from the
//! tool's reference point along +z of the part. A convex solid is the intersection of the
//! half-spaces of its faces, `h H + y Y + v V >= d`, each with a unit normal `(h, y, v)`
//! pointing into the solid. That is the form the sweep cuts with ([`crate::kernel::body`]): on a ray
//! of a column every face is a linear bound on the radius, so a convex solid is cut exactly
//! per ray, like the parametric insert.
//!
//! A mesh is accepted when it is closed (every edge shared by two triangles, after merging
//! vertices closer than a micrometre), convex (every vertex on the inner side of every face
//! plane), has its rake face flat on `Y = 0` (no point in front of it, and a face on that
//! plane: the edge lies in it), and has its lowest point at `Y = 0` on `H = 0` (the
//! reference point is on the tip). Its edge profile is its section at
//! `Y = 0`: `h(V)`, the largest of the lower bounds of the faces there.

use glam::DVec3;

/// One face: `h H + y Y + v V >= d` inside, `(h, y, v)` a unit vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Normal component along `H`.
    pub h: f64,
    /// Normal component along `Y`.
    pub y: f64,
    /// Normal component along `V`.
    pub v: f64,
    /// Offset.
    pub d: f64,
}

/// A convex tool solid.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// The faces (coplanar triangles merged).
    pub faces: Vec<Face>,
    /// The vertices `[H, Y, V]` (mm) and triangles, for drawing.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[usize; 3]>,
    /// How far the solid reaches behind the rake face (mm).
    pub depth: f64,
    /// The axial extent of the edge (the section at `Y = 0`) (mm).
    pub v_range: (f64, f64),
}

/// Why a mesh is not a tool solid.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SolidError {
    /// Fewer than 4 vertices or triangles, or no volume.
    #[error("the mesh has no volume (it needs at least 4 vertices and 4 triangles off one plane)")]
    Flat,
    /// An edge not shared by exactly two triangles.
    #[error("the mesh is not closed: the edge between vertices {0} and {1} belongs to {2} triangle(s), expected 2")]
    Open(usize, usize, usize),
    /// A vertex outside a face plane.
    #[error("the mesh is not convex: vertex {vertex} lies {by:.4} mm outside the plane of triangle {triangle}; split the tool into convex parts or use its convex hull")]
    NotConvex {
        /// The vertex (0-based, after merging).
        vertex: usize,
        /// The triangle (0-based).
        triangle: usize,
        /// How far outside (mm).
        by: f64,
    },
    /// Part of the solid in front of the rake face.
    #[error("the rake face must lie at depth 0 (Y = 0 after `mesh_origin` and `mesh_axes`): the mesh reaches {0:.4} mm in front of it")]
    Rake(f64),
    /// The solid does not reach `Y = 0`.
    #[error("the rake face must lie at depth 0 (Y = 0 after `mesh_origin` and `mesh_axes`): the mesh starts {0:.4} mm behind it")]
    NoRake(f64),
    /// No face on the plane `Y = 0`.
    #[error("the rake face must be a flat face at depth 0 (Y = 0 after `mesh_origin` and `mesh_axes`): a tilted rake face (top rake) is not modelled yet")]
    TiltedRake,
    /// The lowest point of the edge is not at the reference height.
    #[error("the reference point must be on the tip: the lowest point of the rake face's section is at H = {0:.4} mm (expected 0; check `mesh_origin` and the sign of the height axis in `mesh_axes`)")]
    Tip(f64),
    /// A vertex not finite, or a triangle naming a vertex that does not exist.
    #[error("the mesh has a vertex that is not a finite number or a face naming a vertex that does not exist")]
    Invalid,
    /// Too many vertices.
    #[error(
        "the mesh has {0} vertices; at most {MAX_VERTICES} are supported (a tool solid needs few)"
    )]
    TooManyVertices(usize),
    /// Too many faces.
    #[error("the mesh has {0} distinct face planes; at most {MAX_FACES} are supported")]
    TooManyFaces(usize),
}

/// Most vertices of a mesh.
pub(crate) const MAX_VERTICES: usize = 5_000;

/// Most distinct face planes of a solid.
pub(crate) const MAX_FACES: usize = 128;

/// Distances below this are zero (mm).
const EPS: f64 = 1e-6;

impl Solid {
    /// The solid of a closed convex triangle mesh, vertices `[H, Y, V]` in mm.
    pub fn from_mesh(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<Solid, SolidError> {
        if vertices.len() > MAX_VERTICES {
            return Err(SolidError::TooManyVertices(vertices.len()));
        }
        if vertices.iter().flatten().any(|x| !x.is_finite())
            || triangles.iter().flatten().any(|&i| i >= vertices.len())
        {
            return Err(SolidError::Invalid);
        }
        // Merge vertices closer than a micrometre (exporters repeat them per face).
        let mut merged: Vec<DVec3> = Vec::new();
        let mut map = Vec::with_capacity(vertices.len());
        for p in vertices.iter().map(|&p| DVec3::from_array(p)) {
            let found = merged.iter().position(|q| p.distance(*q) < 1e-3);
            map.push(found.unwrap_or_else(|| {
                merged.push(p);
                merged.len() - 1
            }));
        }
        let tris: Vec<[usize; 3]> = triangles
            .iter()
            .map(|t| [map[t[0]], map[t[1]], map[t[2]]])
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        if merged.len() < 4 || tris.len() < 4 {
            return Err(SolidError::Flat);
        }
        let mut edges = std::collections::BTreeMap::new();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0usize) += 1;
            }
        }
        if let Some((&(a, b), &n)) = edges.iter().find(|(_, &n)| n != 2) {
            return Err(SolidError::Open(a, b, n));
        }
        let centre = merged.iter().fold(DVec3::ZERO, |c, p| c + *p) / merged.len() as f64;
        let mut faces: Vec<Face> = Vec::new();
        for (ti, t) in tris.iter().enumerate() {
            let (a, b, c) = (merged[t[0]], merged[t[1]], merged[t[2]]);
            let n = (b - a).cross(c - a);
            let len = n.length();
            if len < 1e-12 {
                continue;
            }
            let mut n = n / len;
            let mut d = n.dot(a);
            // Inward: the centre of the vertices is inside a convex solid.
            if n.dot(centre) < d {
                n = -n;
                d = -d;
            }
            for (vi, p) in merged.iter().enumerate() {
                let by = d - n.dot(*p);
                if by > EPS.max(1e-9 * d.abs()) {
                    return Err(SolidError::NotConvex {
                        vertex: vi,
                        triangle: ti,
                        by,
                    });
                }
            }
            let face = Face {
                h: n[0],
                y: n[1],
                v: n[2],
                d,
            };
            let same = |f: &Face| {
                (f.h - face.h).abs() < 1e-9
                    && (f.y - face.y).abs() < 1e-9
                    && (f.v - face.v).abs() < 1e-9
                    && (f.d - face.d).abs() < EPS
            };
            if !faces.iter().any(same) {
                faces.push(face);
            }
        }
        if faces.len() < 4 {
            return Err(SolidError::Flat);
        }
        if faces.len() > MAX_FACES {
            return Err(SolidError::TooManyFaces(faces.len()));
        }
        let y_min = merged.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        if y_min < -EPS {
            return Err(SolidError::Rake(-y_min));
        }
        if y_min > EPS {
            return Err(SolidError::NoRake(y_min));
        }
        // The edge must lie in the rake face: a face on the plane Y = 0 (its inward normal
        // +Y). A rake face tilted away from it would cut with edge points behind or ahead
        // of the tip's instant, which the edge-at-`phi = 0` model does not sample.
        if !faces
            .iter()
            .any(|f| (f.y - 1.0).abs() < 1e-9 && f.d.abs() <= EPS)
        {
            return Err(SolidError::TiltedRake);
        }
        let depth = merged.iter().map(|p| p[1]).fold(0.0, f64::max);
        // The section at Y = 0: the rake face's vertices span it (a convex solid's section
        // by a supporting plane is the face on it).
        let rake: Vec<&DVec3> = merged.iter().filter(|p| p[1].abs() <= EPS).collect();
        let v_range = rake
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[2]), b.max(p[2]))
            });
        let h_min = rake.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
        if h_min.abs() > EPS {
            return Err(SolidError::Tip(h_min));
        }
        Ok(Solid {
            faces,
            vertices: merged.iter().map(|p| p.to_array()).collect(),
            triangles: tris,
            depth,
            v_range,
        })
    }

    /// Height of the edge above its lowest point at axial offset `v` (the section at
    /// `Y = 0`): the largest lower bound on `H` there, `+inf` outside the edge.
    pub fn height(&self, v: f64) -> f64 {
        if v < self.v_range.0 - EPS || v > self.v_range.1 + EPS {
            return f64::INFINITY;
        }
        self.faces
            .iter()
            .filter(|f| f.h > 1e-12)
            .map(|f| (f.d - f.v * v) / f.h)
            .fold(0.0, f64::max)
    }

    /// Offsets `[v_min, v_max]` where the edge is lower than `reach` above the tip (the
    /// edge's axial extent, clipped where a face bounds it).
    pub fn span(&self, reach: f64) -> (f64, f64) {
        let (a, b) = self.v_range;
        // The profile is convex in v: bisect each side for the crossing of `reach`.
        let lowest = if (a..=b).contains(&0.0) {
            0.0
        } else {
            0.5 * (a + b)
        };
        let cross = |mut inside: f64, mut outside: f64| {
            if self.height(outside) <= reach {
                return outside;
            }
            for _ in 0..60 {
                let m = 0.5 * (inside + outside);
                if self.height(m) <= reach {
                    inside = m;
                } else {
                    outside = m;
                }
            }
            outside
        };
        (cross(lowest, a), cross(lowest, b))
    }

    /// The width of the edge's flat at its lowest point (mm).
    pub fn tip_width(&self) -> f64 {
        let (a, b) = self.span(1e-9);
        (b - a).max(0.0)
    }
}

/// A prism's closed triangle mesh: the polygon `bottom` (`[H, V]`, counter-clockwise or
/// not) at `Y = 0` and `top` at `Y = depth`, vertex for vertex (for tests and the
/// parametric insert's mesh).
pub fn prism(
    front: &[[f64; 2]],
    back: &[[f64; 2]],
    depth: f64,
) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let n = front.len();
    let mut vertices: Vec<[f64; 3]> = front.iter().map(|p| [p[0], 0.0, p[1]]).collect();
    vertices.extend(back.iter().map(|p| [p[0], depth, p[1]]));
    let mut triangles = Vec::new();
    for i in 1..n - 1 {
        triangles.push([0, i, i + 1]);
        triangles.push([n, n + i + 1, n + i]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        triangles.push([i, j, n + j]);
        triangles.push([i, n + j, n + i]);
    }
    (vertices, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A trapezoidal insert: tip 2 at H = 0, 15 deg flanks up to H = 5, 6 mm deep, its
    /// back section receded 0.2 mm per flank.
    fn insert() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
        let t = 15f64.to_radians().tan();
        let front = [
            [0.0, -1.0],
            [0.0, 1.0],
            [5.0, 1.0 + 5.0 * t],
            [5.0, -1.0 - 5.0 * t],
        ];
        let back = [
            [0.0, -0.8],
            [0.0, 0.8],
            [5.0, 0.8 + 5.0 * t],
            [5.0, -0.8 - 5.0 * t],
        ];
        prism(&front, &back, 6.0)
    }

    #[test]
    fn an_insert_mesh_has_its_edge_profile() {
        let (v, t) = insert();
        let s = Solid::from_mesh(&v, &t).unwrap();
        assert_eq!(s.faces.len(), 6);
        assert!((s.depth - 6.0).abs() < 1e-12);
        let cot = 1.0 / 15f64.to_radians().tan();
        assert_eq!(s.height(0.3), 0.0);
        assert!((s.height(1.5) - 0.5 * cot).abs() < 1e-9);
        assert!((s.height(-1.2) - 0.2 * cot).abs() < 1e-9);
        assert!(s.height(3.0).is_infinite());
        assert!((s.tip_width() - 2.0).abs() < 1e-6);
        let (a, b) = s.span(1.0);
        let run = 15f64.to_radians().tan();
        assert!((a + 1.0 + run).abs() < 1e-6 && (b - 1.0 - run).abs() < 1e-6);
    }

    #[test]
    fn bad_meshes_are_refused() {
        let (mut v, t) = insert();
        // One back corner pulled out past the +V flank's plane: a twisted, non-convex side.
        v[5][2] += 0.7;
        assert!(matches!(
            Solid::from_mesh(&v, &t),
            Err(SolidError::NotConvex { .. })
        ));
        let (v, mut t) = insert();
        t.pop();
        assert!(matches!(
            Solid::from_mesh(&v, &t),
            Err(SolidError::Open(..))
        ));
        let (mut v, t) = insert();
        for p in &mut v {
            p[1] -= 0.5;
        }
        assert_eq!(Solid::from_mesh(&v, &t), Err(SolidError::Rake(0.5)));
        let (mut v, t) = insert();
        for p in &mut v {
            p[0] += 0.25;
        }
        assert_eq!(Solid::from_mesh(&v, &t), Err(SolidError::Tip(0.25)));
        // Top rake: the front face leans back with height (Y = 0.1 H), the tip still at
        // Y = 0.
        let run = 5.0 * 15f64.to_radians().tan();
        let section = [[0.0, -1.0], [0.0, 1.0], [5.0, 1.0 + run], [5.0, -1.0 - run]];
        let (mut v, t) = prism(&section, &section, 6.0);
        for p in v.iter_mut().filter(|p| p[1] == 0.0) {
            p[1] = 0.1 * p[0];
        }
        assert_eq!(Solid::from_mesh(&v, &t), Err(SolidError::TiltedRake));
    }
}
