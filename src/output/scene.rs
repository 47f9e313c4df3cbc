//! The 3D scene of a simulated job: what the glTF export writes and the renderer draws.
//!
//! Everything is in the part's frame, in mm: `z` along the part axis, `x = r cos(theta)`,
//! `y = r sin(theta)` with `theta` the angle on the part (the same angle the report gives).
//! Colours are sRGB bytes, the same bands of the tolerance the developed view and the
//! legend use, so a picture and a model of the same job agree colour for colour.
//!
//! A [`Scene`] is plain data: [`crate::output::mesh`] builds one from a simulation, [`crate::output::glb`]
//! writes it to a `.glb` and reads it back, [`crate::output::render`] draws it.

/// A triangle mesh with one sRGB colour per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions (mm, part frame).
    pub positions: Vec<[f32; 3]>,
    /// Vertex colours (sRGB), one per position.
    pub colors: Vec<[u8; 3]>,
    /// Triangles, counter-clockwise seen from outside the material.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// The axis-aligned bounds `(min, max)`, or `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        }))
    }
}

/// What a toolpath line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathKind {
    /// A synchronised threading move (the tool's reference point on the pass helix).
    Feed,
    /// A positioning move between passes.
    Rapid,
}

/// One line strip of the toolpath.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Feed or rapid.
    pub kind: PathKind,
    /// The points (mm, part frame), at least two.
    pub points: Vec<[f32; 3]>,
}

/// The colour scale of the deviation colours: the bands of the tolerance (within, 1-2x,
/// 2-5x, over 5x), as in the plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Legend {
    /// Deviations up to this (mm) are within tolerance; the bands are multiples of it.
    pub tolerance_mm: f64,
    /// The largest deviation (mm, at least twice the tolerance), as the report rounds it.
    pub scale_mm: f64,
}

/// The place a close-up looks at: the worst finding.
#[derive(Clone, Debug, PartialEq)]
pub struct Focus {
    /// `"gouge"` or `"leftover"`.
    pub kind: String,
    /// Its deviation (mm).
    pub value_mm: f64,
    /// Where it is on the cut surface (mm, part frame).
    pub point: [f32; 3],
    /// Its turn (1-based, as the report's location; 0 before the first feature).
    pub turn: i64,
    /// Its flank as the report names it (`left`, `right`, `root`, `crest`), or empty.
    pub flank: String,
    /// Its angle on the part (deg, 0..360) and axial position (mm), as the report rounds
    /// them (its `max_gouge_at` or `max_leftover_at`).
    pub angle_deg: f64,
    /// See `angle_deg`.
    pub z_mm: f64,
}

/// A simulated job as a 3D scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The cut part: a closed surface (outer, inner when the blank is a tube, end faces),
    /// coloured by the signed deviation from the ideal thread.
    pub stock: Mesh,
    /// The ideal thread surface over the compared span, if asked for.
    pub ideal: Option<Mesh>,
    /// The toolpath: one feed strip per pass and the rapids between them.
    pub toolpath: Vec<Polyline>,
    /// The tool at its last pose.
    pub tool: Mesh,
    /// The deviation colour scale.
    pub legend: Legend,
    /// The worst finding, if the cut deviates beyond the tolerance anywhere.
    pub focus: Option<Focus>,
    /// The report summary (JSON text) carried into the glTF's `extras`.
    pub summary: String,
}
