//! Planar tool profiles: the cutting edge in the axial plane, as a height function.
//!
//! A lathe tool on centre height cuts with the edge profile lying in the axial plane
//! through the tool (the rake face, on centre). An optional [`Body`] gives the insert its
//! thickness behind the rake face with side and front clearance and an inclination: the
//! solid that can rub a flank when the helix angle outgrows the clearance (see
//! [`crate::kernel::sweep`] for how it is swept). The profile is a function `h(v) >= 0`: how far the edge stands back
//! from its tip at axial offset `v` from the tip centre, `+inf` outside the edge. The
//! tool's reference point (the point the program drives) sits at the tip height and at
//! axial offset [`Tool::reference_offset`] from the tip centre.

use crate::model::solid::Solid;
use std::sync::Arc;

/// Which point of the tool the passes drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// Middle of the tip.
    Center,
    /// The corner on the -z side.
    Left,
    /// The corner on the +z side.
    Right,
    /// The lowest point of the tip (the middle, for symmetric tools).
    Tip,
}

/// The edge profile.
#[derive(Clone, Debug, PartialEq)]
pub enum Edge {
    /// A flat tip of width `tip` with straight flanks; angles from the radial direction
    /// (0 = square grooving tool).
    Trapezoid {
        /// Width of the flat tip (mm).
        tip: f64,
        /// Inclination of the -z flank (rad).
        left_angle: f64,
        /// Inclination of the +z flank (rad).
        right_angle: f64,
    },
    /// A symmetric V with a round nose tangent to both flanks.
    RoundV {
        /// Nose radius (mm).
        radius: f64,
        /// Half of the included angle (rad).
        half_angle: f64,
    },
    /// A convex solid from a mesh: its section at the rake face is the edge; with `body`,
    /// the rest of it behind the rake face is swept too (a tool body).
    Mesh {
        /// The solid, in the tool frame with the reference point at the origin.
        solid: Arc<Solid>,
        /// Whether the solid behind the rake face cuts too (else the edge alone).
        body: bool,
    },
}

/// The insert behind its cutting edge: the edge profile extruded `thickness` back from the
/// rake face (tangentially, on the side the freshly cut surface moves to), its flanks
/// receding with the side clearances, its tip with the front clearance, and the whole
/// section shifted axially by the inclination. At depth `y` behind the rake face the
/// section is the edge profile with the -z flank moved `y (tan a_l + tan l)` towards +z,
/// the +z flank moved `y (tan a_r - tan l)` towards -z, and the tip raised by
/// `y tan a_f`. A positive inclination `l` leans the body towards +z with depth: it follows
/// a pass that travels towards -z (a right-hand thread cut towards the chuck).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Tangential thickness behind the rake face (mm).
    pub thickness: f64,
    /// Side clearance of the -z flank (rad; negative: the body stands out).
    pub clearance_left: f64,
    /// Side clearance of the +z flank (rad).
    pub clearance_right: f64,
    /// Front (end) clearance under the tip (rad, >= 0).
    pub clearance_front: f64,
    /// Inclination (shim tilt) about the radial axis (rad).
    pub inclination: f64,
}

impl Body {
    /// How far the -z flank recedes per mm of depth behind the rake face.
    pub(crate) fn slope_left(&self) -> f64 {
        self.clearance_left.tan() + self.inclination.tan()
    }

    /// How far the +z flank recedes per mm of depth behind the rake face.
    pub(crate) fn slope_right(&self) -> f64 {
        self.clearance_right.tan() - self.inclination.tan()
    }
}

/// A cutting tool.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// The id passes refer to.
    pub id: u32,
    /// Edge profile.
    pub edge: Edge,
    /// Reference point.
    pub reference: Reference,
    /// The insert behind the edge, if modelled (else the edge alone: a planar profile).
    pub body: Option<Body>,
    /// How far the head reaches above its tip (mm), if given: past it the holder would
    /// meet the part (a mesh's is its own height).
    pub length: Option<f64>,
    /// The radial depth of cut one pass may take with this insert, if given.
    pub depth_per_pass: DepthLimits,
}

/// What holds a lathe tool, as a solid the part must not meet (`[[tool]] holder`), in the
/// axial plane and relative to the insert's tip (a turning insert's imaginary tip). The
/// part turns, so only how far each point of it lies from the axis matters: a shank's
/// nearest, a bar's farthest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Holder {
    /// An external tool's shank or head: a block from `left` mm to the -z side of the tip
    /// to `right` mm to its +z side, from `clearance` mm above the tip outward.
    Shank {
        /// Its -z face's distance from the tip (mm).
        left: f64,
        /// Its +z face's distance from the tip (mm).
        right: f64,
        /// How far above the tip it starts (mm, radial).
        clearance: f64,
    },
    /// A boring bar: a cylinder of `diameter` along the axis, the tip `reach` mm from its
    /// centre line (half the smallest bore of its catalogue page), from `front` mm to the
    /// -z side of the tip to `length` mm to its +z side (out of the bore). Its farthest
    /// point from the spindle's axis lies `diameter / 2 + |r - reach|` from it, the tip at
    /// radius `r`.
    Bar {
        /// Bar diameter (mm).
        diameter: f64,
        /// The tip's distance from the bar's centre line (mm).
        reach: f64,
        /// How far it reaches past the tip toward -z (mm).
        front: f64,
        /// How far it reaches from the tip toward +z (mm).
        length: f64,
    },
}

/// The radial depth of cut per pass an insert stands: over `max` it breaks, under `min` it
/// rubs instead of cutting (mm, radial; `None`: not given).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DepthLimits {
    /// The most (mm).
    pub max: Option<f64>,
    /// The least that still cuts (mm); a pass that cuts nothing (a spring pass) is no
    /// cut and not held to it.
    pub min: Option<f64>,
}

/// A tap (`kind = "tap"`): on the lathe's axis, the internal thread's profile at full depth
/// behind a chamfer. Its section at one angle is a row of teeth one pitch apart, each the
/// groove of the basic internal thread (ISO 68-1: 60 deg flanks, the root flat P/8 at the
/// major diameter, the tooth's [`Tap::tooth`]); the chamfer's cone cuts them down from the
/// major diameter at `chamfer_length` behind the tip to `chamfer_diameter` at the tip.
/// With a feed equal to the pitch every tooth runs in the first tooth's groove, so the cut
/// at the end of the stroke is the thread's helix at full depth where the full teeth
/// reached and, in the chamfer zone, the helix cut down to the cone at the tap's last
/// position (`toolpath::tap_passes`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tap {
    /// The id the program's T words select.
    pub id: u32,
    /// Pitch (mm): the lead the tap's thread has.
    pub pitch: f64,
    /// Major diameter of the thread it cuts (mm).
    pub major_diameter: f64,
    /// Length of the chamfer along the axis (mm), from the tip to the first full tooth.
    pub chamfer_length: f64,
    /// Diameter of the chamfer at the tip (mm).
    pub chamfer_diameter: f64,
}

impl Tap {
    /// One tooth, as a threading insert: the basic internal thread's groove (60 deg, the
    /// P/8 root flat at the major diameter), its reference point in the middle of the flat.
    pub fn tooth(&self) -> Tool {
        Tool {
            id: self.id,
            edge: Edge::Trapezoid {
                tip: self.pitch / 8.0,
                left_angle: 30f64.to_radians(),
                right_angle: 30f64.to_radians(),
            },
            reference: Reference::Tip,
            body: None,
            length: None,
            depth_per_pass: DepthLimits::default(),
        }
    }

    /// The diameter the chamfer's cone reaches `s` mm behind the tip: `chamfer_diameter`
    /// at the tip, rising linearly to the major diameter at `chamfer_length`, the major
    /// diameter beyond.
    pub fn cone_diameter(&self, s: f64) -> f64 {
        if self.chamfer_length <= 0.0 || s >= self.chamfer_length {
            return self.major_diameter;
        }
        let u = (s / self.chamfer_length).max(0.0);
        self.chamfer_diameter + u * (self.major_diameter - self.chamfer_diameter)
    }
}

/// The profile prepared for the sweep kernel: `h(v) = max(0, (vl - v)*cl, (v - vr)*cr)`
/// inside `[v_min, v_max]`, the round nose, or a solid's section.
#[derive(Clone, Debug)]
pub(crate) enum Kernel {
    Trapezoid {
        vl: f64,
        vr: f64,
        cl: f64,
        cr: f64,
    },
    RoundV {
        radius: f64,
        vt: f64,
        ht: f64,
        cot: f64,
    },
    Mesh(Arc<Solid>),
}

impl Tool {
    /// Whether the tool has a body behind its edge that the sweep cuts with.
    pub fn has_body(&self) -> bool {
        self.body.is_some() || matches!(self.edge, Edge::Mesh { body: true, .. })
    }

    /// How far the head reaches above its tip (mm): the job's `length`, or a mesh's height.
    pub fn head_length(&self) -> Option<f64> {
        match &self.edge {
            Edge::Mesh { solid, .. } => {
                Some(solid.vertices.iter().map(|p| p[0]).fold(0.0, f64::max))
            }
            _ => self.length,
        }
    }

    /// The same tool with its edge alone (no body).
    pub fn edge_only(&self) -> Tool {
        let edge = match &self.edge {
            Edge::Mesh { solid, .. } => Edge::Mesh {
                solid: solid.clone(),
                body: false,
            },
            e => e.clone(),
        };
        Tool {
            edge,
            body: None,
            ..self.clone()
        }
    }

    /// Axial offset of the reference point from the tip centre.
    pub fn reference_offset(&self) -> f64 {
        let half = match &self.edge {
            Edge::Trapezoid { tip, .. } => tip / 2.0,
            Edge::RoundV { .. } => 0.0,
            // The mesh is placed by its reference point: that is the origin.
            Edge::Mesh { .. } => return 0.0,
        };
        match self.reference {
            Reference::Center | Reference::Tip => 0.0,
            Reference::Left => -half,
            Reference::Right => half,
        }
    }

    /// Width of the flat tip (0 for a round nose).
    pub fn tip_width(&self) -> f64 {
        match &self.edge {
            Edge::Trapezoid { tip, .. } => *tip,
            Edge::RoundV { .. } => 0.0,
            Edge::Mesh { solid, .. } => solid.tip_width(),
        }
    }

    /// Height of the edge above its tip at offset `v` from the tip centre.
    pub fn height(&self, v: f64) -> f64 {
        self.kernel().height(v)
    }

    /// Offsets `[v_min, v_max]` where the edge is lower than `reach` above the tip.
    pub fn span(&self, reach: f64) -> (f64, f64) {
        self.kernel().span(reach)
    }

    pub(crate) fn kernel(&self) -> Kernel {
        match self.edge.clone() {
            Edge::Trapezoid {
                tip,
                left_angle,
                right_angle,
            } => Kernel::Trapezoid {
                vl: -tip / 2.0,
                vr: tip / 2.0,
                cl: cot(left_angle),
                cr: cot(right_angle),
            },
            Edge::RoundV { radius, half_angle } => Kernel::RoundV {
                radius,
                vt: radius * half_angle.cos(),
                ht: radius * (1.0 - half_angle.sin()),
                cot: cot(half_angle),
            },
            Edge::Mesh { solid, .. } => Kernel::Mesh(solid),
        }
    }
}

/// Cotangent, infinite at zero (a vertical flank).
/// The imaginary tip of a turning insert seen from its nose centre, by tip direction:
/// `(dz, dx)` in units of the nose radius, `dx` along +X (away from the spindle axis).
/// The numbering is FANUC's "imaginary tool nose direction" (0i-TF "Tool nose radius
/// compensation"; Haas and Okuma write the same, Siemens its cutting-edge position SL):
/// 1 (+Z, +X), 2 (-Z, +X), 3 (-Z, -X), 4 (+Z, -X), 5 (+Z), 6 (+X), 7 (-Z), 8 (-X), 0 and 9
/// the nose centre itself. An external right-hand tool turning towards the chuck is 3, a
/// boring bar 2. LinuxCNC numbers its tool table's orientation otherwise
/// ([`linuxcnc_orientation`]). `None` past 9.
pub fn tip_direction(tip: u8) -> Option<(f64, f64)> {
    Some(match tip {
        0 | 9 => (0.0, 0.0),
        1 => (1.0, 1.0),
        2 => (-1.0, 1.0),
        3 => (-1.0, -1.0),
        4 => (1.0, -1.0),
        5 => (1.0, 0.0),
        6 => (0.0, 1.0),
        7 => (-1.0, 0.0),
        8 => (0.0, -1.0),
        _ => return None,
    })
}

/// LinuxCNC's tool-table orientation (`Q`) for the tip direction `tip` ([`tip_direction`]):
/// the same vector, numbered as rs274 places the controlled point (measured with rs274
/// 2.9: orientation 1 is (+Z, -X), 2 (-Z, -X), 3 (-Z, +X), 4 (+Z, +X), 5 +Z, 6 -X, 7 -Z,
/// 8 +X): 1 <-> 4, 2 <-> 3, 6 <-> 8 swap, the rest agree.
pub fn linuxcnc_orientation(tip: u8) -> u8 {
    match tip {
        1 => 4,
        4 => 1,
        2 => 3,
        3 => 2,
        6 => 8,
        8 => 6,
        t => t,
    }
}

pub(crate) fn cot(a: f64) -> f64 {
    if a <= 0.0 {
        f64::INFINITY
    } else {
        1.0 / a.tan()
    }
}

/// The float types the edge profiles are evaluated in: `f64` for geometry, `f32` in the
/// sweep's vectorised loops. [`trapezoid_height`] and [`round_v_height`] are the one
/// formula of each profile for both.
pub(crate) trait Real:
    Copy
    + PartialOrd
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
{
    /// Zero.
    const ZERO: Self;
    /// The square root.
    fn root(self) -> Self;
    /// The absolute value.
    fn magnitude(self) -> Self;
}

impl Real for f64 {
    const ZERO: f64 = 0.0;
    #[inline(always)]
    fn root(self) -> f64 {
        self.sqrt()
    }
    #[inline(always)]
    fn magnitude(self) -> f64 {
        self.abs()
    }
}

impl Real for f32 {
    const ZERO: f32 = 0.0;
    #[inline(always)]
    fn root(self) -> f32 {
        self.sqrt()
    }
    #[inline(always)]
    fn magnitude(self) -> f32 {
        self.abs()
    }
}

/// The larger of two values (`a` unless `b` is larger; branch-free where it matters).
#[inline(always)]
pub(crate) fn larger<R: Real>(a: R, b: R) -> R {
    if a > b {
        a
    } else {
        b
    }
}

/// A trapezoid's height above its tip at `v`: zero on the flat `[vl, vr]`, rising with the
/// flanks' cotangents `cl` and `cr` outside it (a vertical flank, cotangent 0 here, only
/// bounds the span, which the caller clips).
#[inline(always)]
pub(crate) fn trapezoid_height<R: Real>(v: R, vl: R, vr: R, cl: R, cr: R) -> R {
    larger(larger((vl - v) * cl, (v - vr) * cr), R::ZERO)
}

/// A round-nose V's height above its tip at `v`: the nose circle of `radius` out to `vt`
/// (where the flanks touch it, at height `ht`), then the flanks with cotangent `cot`.
#[inline(always)]
pub(crate) fn round_v_height<R: Real>(v: R, radius: R, vt: R, ht: R, cot: R) -> R {
    let a = v.magnitude();
    let inner = radius - larger(radius * radius - a * a, R::ZERO).root();
    let outer = ht + (a - vt) * cot;
    if a <= vt {
        inner
    } else {
        outer
    }
}

impl Kernel {
    pub(crate) fn height(&self, v: f64) -> f64 {
        match *self {
            Kernel::Mesh(ref solid) => solid.height(v),
            Kernel::Trapezoid { vl, vr, cl, cr } => {
                // Beyond a vertical flank the edge never reaches down.
                if (v < vl && cl.is_infinite()) || (v > vr && cr.is_infinite()) {
                    return f64::INFINITY;
                }
                let finite = |c: f64| if c.is_finite() { c } else { 0.0 };
                trapezoid_height(v, vl, vr, finite(cl), finite(cr))
            }
            Kernel::RoundV {
                radius,
                vt,
                ht,
                cot,
            } => round_v_height(v, radius, vt, ht, cot),
        }
    }

    pub(crate) fn span(&self, reach: f64) -> (f64, f64) {
        let reach = reach.max(0.0);
        match *self {
            Kernel::Mesh(ref solid) => solid.span(reach),
            Kernel::Trapezoid { vl, vr, cl, cr } => {
                let l = if cl.is_infinite() { 0.0 } else { reach / cl };
                let r = if cr.is_infinite() { 0.0 } else { reach / cr };
                (vl - l, vr + r)
            }
            Kernel::RoundV {
                radius,
                vt,
                ht,
                cot,
            } => {
                let a = if reach <= ht {
                    (radius * radius - (radius - reach).powi(2)).max(0.0).sqrt()
                } else {
                    vt + (reach - ht) / cot
                };
                (-a, a)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_nose_is_tangent_to_flanks() {
        let t = Tool {
            id: 1,
            edge: Edge::RoundV {
                radius: 0.3,
                half_angle: 30f64.to_radians(),
            },
            reference: Reference::Tip,
            body: None,
            length: None,
            depth_per_pass: DepthLimits::default(),
        };
        let k = t.kernel();
        if let Kernel::RoundV { vt, .. } = k {
            let e = 1e-7;
            let inner = k.height(vt - e);
            let outer = k.height(vt + e);
            assert!((outer - inner).abs() < 1e-6);
            // Slope on both sides equals cot(30).
            let s1 = (k.height(vt) - k.height(vt - e)) / e;
            let s2 = (k.height(vt + e) - k.height(vt)) / e;
            assert!((s1 - 3f64.sqrt()).abs() < 1e-4 && (s2 - 3f64.sqrt()).abs() < 1e-4);
        }
        let (a, b) = t.span(1.0);
        assert!((t.height(b) - 1.0).abs() < 1e-12 && (t.height(a) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn grooving_tool_reference_corners() {
        let mut t = Tool {
            id: 1,
            edge: Edge::Trapezoid {
                tip: 3.0,
                left_angle: 0.0,
                right_angle: 0.0,
            },
            reference: Reference::Right,
            body: None,
            length: None,
            depth_per_pass: DepthLimits::default(),
        };
        assert_eq!(t.reference_offset(), 1.5);
        t.reference = Reference::Left;
        assert_eq!(t.reference_offset(), -1.5);
        assert_eq!(t.span(10.0), (-1.5, 1.5));
        assert_eq!(t.height(1.6), f64::INFINITY);
    }
}
