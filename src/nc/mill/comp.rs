//! FANUC cutter radius compensation (G41/G42/G40, type A start-up and cancel) as a pure
//! pass over the programmed milling moves: [`compensate`] turns the contour the program
//! writes ([`Programmed`]) into the path of the tool centre ([`MillMove`]).
//!
//! In the plane of compensation (G17 XY, G18 ZX, G19 YZ; the coordinate along its normal
//! is left as programmed):
//! - start-up (the G00/G01 block with G41/G42): from the uncompensated start to the block's
//!   end plus `r` perpendicular to the start direction of the next block that moves in the
//!   plane, on the left (G41) or right (G42);
//! - joints between compensated blocks: tangent (below 1e-6 rad): the common perpendicular;
//!   inner corners: the intersection of the two offset paths (line/line, line/arc, arc/arc)
//!   nearest the joint; outer corners of 90 deg or more inside: the offset paths extended
//!   to their intersection (lines as lines, arcs as their full circles), as FANUC does for
//!   `180 > alpha >= 90` deg. Acute outer corners (FANUC inserts extra segments there),
//!   and offset paths that do not meet, are errors;
//! - arcs: the same centre and radius `R -+ r`; `R - r <= 0`, or a tool-centre segment that
//!   runs against its programmed direction, is an interference error;
//! - blocks without motion in the plane (a Z move) keep the tool centre where the joint of
//!   the in-plane blocks around them put it;
//! - cancel (the G00/G01 block with G40): from the previous block's end offset point
//!   (perpendicular to its end direction) to the block's programmed end.

use super::{CompSide, MillArc, MillKind, MillMove, Plane};
use crate::model::helix::Spindle;
use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// Below this change of direction (rad) a joint is tangent.
const TANGENT: f64 = 1e-6;

/// Where a programmed move was written: for its errors.
#[derive(Clone, Debug, PartialEq)]
pub(in crate::nc) struct Site {
    pub(in crate::nc) file: String,
    pub(in crate::nc) line: usize,
    /// The block's text.
    pub(in crate::nc) snippet: String,
    /// Callers, innermost first.
    pub(in crate::nc) stack: Vec<String>,
}

/// The compensation state of one programmed move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::nc) enum Comp {
    /// No compensation.
    Off,
    /// The start-up block (G41/G42), with side and radius.
    Start(CompSide, f64),
    /// A block under compensation.
    On(CompSide, f64),
    /// The cancel block (G40).
    Cancel(CompSide, f64),
}

/// One programmed milling move: the contour as written (job frame, after work offsets and
/// tool length), before cutter radius compensation.
#[derive(Clone, Debug, PartialEq)]
pub(in crate::nc) struct Programmed {
    pub(in crate::nc) site: Site,
    pub(in crate::nc) kind: MillKind,
    pub(in crate::nc) plane: Plane,
    pub(in crate::nc) start: [f64; 3],
    pub(in crate::nc) end: [f64; 3],
    /// The programmed circle of an arc.
    pub(in crate::nc) arc: Option<MillArc>,
    pub(in crate::nc) comp: Comp,
    pub(in crate::nc) feed: Option<f64>,
    pub(in crate::nc) spindle_rpm: Option<f64>,
    pub(in crate::nc) spindle: Option<Spindle>,
    pub(in crate::nc) tool: Option<u32>,
    pub(in crate::nc) tool_word: Option<std::sync::Arc<str>>,
}

impl Plane {
    /// Indices into `[x, y, z]` of the plane's (u, v) axes, right-handed about its normal,
    /// and of the normal: XY (x, y, z), ZX (z, x, y), YZ (y, z, x).
    pub(in crate::nc) fn axes(self) -> [usize; 3] {
        match self {
            Plane::Xy => [0, 1, 2],
            Plane::Zx => [2, 0, 1],
            Plane::Yz => [1, 2, 0],
        }
    }

    /// A point's (u, v) coordinates in the plane.
    pub(in crate::nc) fn uv(self, p: [f64; 3]) -> V2 {
        let [u, v, _] = self.axes();
        DVec2::new(p[u], p[v])
    }

    /// The point with (u, v) in the plane and `w` along its normal.
    pub(in crate::nc) fn point(self, uv: V2, w: f64) -> [f64; 3] {
        let [u, v, n] = self.axes();
        let mut p = [0.0; 3];
        p[u] = uv[0];
        p[v] = uv[1];
        p[n] = w;
        p
    }
}

/// A vector in the plane.
pub(in crate::nc) type V2 = DVec2;

/// Length of a plane vector (`hypot`, as the controls' arithmetic was checked with).
fn len(a: V2) -> f64 {
    a.x.hypot(a.y)
}
/// An angle in (-pi, pi].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// A programmed move seen in the plane of compensation.
#[derive(Clone, Copy, Debug)]
struct Elem {
    a: V2,
    b: V2,
    /// Arcs: centre, radius and counter-clockwise.
    circle: Option<(V2, f64, bool)>,
}

impl Elem {
    fn of(p: &Programmed) -> Elem {
        let circle = p.arc.map(|c| {
            let centre = p.plane.uv(c.centre);
            (centre, len(p.plane.uv(p.start) - centre), c.sweep > 0.0)
        });
        Elem {
            a: p.plane.uv(p.start),
            b: p.plane.uv(p.end),
            circle,
        }
    }

    /// The unit direction of travel at `at` (a point of the element).
    fn tangent(&self, at: V2) -> V2 {
        match self.circle {
            Some((c, r, ccw)) => {
                let t = (at - c).perp() * (1.0 / r);
                if ccw {
                    t
                } else {
                    t * -1.0
                }
            }
            None => {
                let d = self.b - self.a;
                d * (1.0 / len(d))
            }
        }
    }

    /// Whether the element moves in the plane.
    fn moves(&self) -> bool {
        self.circle.is_some() || len(self.b - self.a) > 1e-12
    }

    /// The offset path at `s * r` to the left (s = +1 G41, -1 G42): a line (point, unit
    /// direction) or a circle (centre, radius).
    fn offset(&self, s: f64, r: f64) -> Offset {
        match self.circle {
            Some((c, rad, ccw)) => {
                // The left of a counter-clockwise arc is its inside.
                let sigma = if ccw { 1.0 } else { -1.0 };
                Offset::Circle(c, rad - s * sigma * r)
            }
            None => {
                let t = self.tangent(self.a);
                Offset::Line(self.a + (t.perp() * (s * r)), t)
            }
        }
    }
}

/// An offset path: a line (a point and its unit direction) or a circle (centre, radius).
#[derive(Clone, Copy, Debug)]
pub(in crate::nc) enum Offset {
    Line(V2, V2),
    Circle(V2, f64),
}

/// The intersections of two offset paths (also the lathe's nose radius compensation's,
/// `nc::nose`).
pub(in crate::nc) fn intersections(p: Offset, q: Offset) -> Vec<V2> {
    match (p, q) {
        (Offset::Line(a, d), Offset::Line(b, e)) => {
            let den = d.perp_dot(e);
            if den.abs() < 1e-15 {
                return Vec::new();
            }
            vec![(a + (d * ((b - a).perp_dot(e) / den)))]
        }
        (Offset::Line(a, d), Offset::Circle(c, r)) | (Offset::Circle(c, r), Offset::Line(a, d)) => {
            // |a + t d - c|^2 = r^2 with |d| = 1.
            let f = a - c;
            let bh = f.dot(d);
            let disc = bh * bh - (f.dot(f) - r * r);
            if disc < -1e-12 {
                return Vec::new();
            }
            let q = disc.max(0.0).sqrt();
            vec![(a + (d * (-bh - q))), (a + (d * (-bh + q)))]
        }
        (Offset::Circle(c1, r1), Offset::Circle(c2, r2)) => {
            let dv = c2 - c1;
            let d = len(dv);
            if d < 1e-15 || d > r1 + r2 + 1e-12 || d < (r1 - r2).abs() - 1e-12 {
                return Vec::new();
            }
            let along = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h = (r1 * r1 - along * along).max(0.0).sqrt();
            let e = dv * (1.0 / d);
            let m = c1 + (e * along);
            vec![(m + (e.perp() * h)), (m - (e.perp() * h))]
        }
    }
}

fn sign(side: CompSide) -> f64 {
    match side {
        CompSide::Left => 1.0,
        CompSide::Right => -1.0,
    }
}

fn side_name(side: CompSide) -> &'static str {
    match side {
        CompSide::Left => "G41",
        CompSide::Right => "G42",
    }
}

fn shape(e: &Elem) -> &'static str {
    if e.circle.is_some() {
        "arc"
    } else {
        "line"
    }
}

/// The tool centre at the joint `p` from element `a` to element `b` (both compensated).
fn corner(a: &Elem, b: &Elem, side: CompSide, r: f64, a_line: usize) -> Result<V2, String> {
    let s = sign(side);
    let p = a.b;
    let (ta, tb) = (a.tangent(p), b.tangent(p));
    let turn = ta.perp_dot(tb).atan2(ta.dot(tb));
    let end_a = p + (ta.perp() * (s * r));
    if turn.abs() < TANGENT {
        return Ok(end_a);
    }
    let start_b = p + (tb.perp() * (s * r));
    let inner = s * turn > 0.0;
    if !inner && ta.dot(tb) < -1e-12 {
        return Err(format!(
            "{} outer corner of less than 90 deg inside between the {} of line {a_line} and this {}, turning {:.3} deg: vpcut does not model that corner yet (FANUC inserts extra segments there)",
            side_name(side),
            shape(a),
            shape(b),
            turn.abs().to_degrees()
        ));
    }
    // The intersection nearest the offset points at the joint.
    let near = (end_a + start_b) * 0.5;
    intersections(a.offset(s, r), b.offset(s, r))
        .into_iter()
        .min_by(|x, y| len((*x) - near).total_cmp(&len((*y) - near)))
        .ok_or_else(|| {
            format!(
                "{} with radius {r}: the offset paths of the {} of line {a_line} and of this {} do not meet at their corner (FANUC interference alarm)",
                side_name(side),
                shape(a),
                shape(b)
            )
        })
}

/// The index of the next move after `i` that moves in the plane, within the same
/// compensation (up to its cancel block).
fn next_in_plane(path: &[Programmed], i: usize) -> Option<usize> {
    for (k, p) in path.iter().enumerate().skip(i + 1) {
        match p.comp {
            Comp::On(..) | Comp::Cancel(..) => {
                if Elem::of(p).moves() {
                    return Some(k);
                }
                if matches!(p.comp, Comp::Cancel(..)) {
                    return None;
                }
            }
            Comp::Off | Comp::Start(..) => return None,
        }
    }
    None
}

/// The tool centre's path of the programmed moves `path`: cutter radius compensation
/// applied. An error gives the index of the move it is about and what is wrong.
pub(in crate::nc) fn compensate(path: &[Programmed]) -> Result<Vec<MillMove>, (usize, String)> {
    let mut out = Vec::with_capacity(path.len());
    // The tool centre in the plane at the end of the last compensated move.
    let mut at: Option<V2> = None;
    for (i, p) in path.iter().enumerate() {
        let (side, r) = match p.comp {
            Comp::Off => {
                at = None;
                out.push(tool_move(p, p.start, p.end, p.arc, None));
                continue;
            }
            Comp::Start(s, r) | Comp::On(s, r) | Comp::Cancel(s, r) => (s, r),
        };
        let s = sign(side);
        let e = Elem::of(p);
        let start = match (p.comp, at) {
            (Comp::On(..) | Comp::Cancel(..), Some(a)) => a,
            _ => e.a,
        };
        let next = next_in_plane(path, i);
        let end = match p.comp {
            Comp::Start(..) => {
                if p.arc.is_some() {
                    return Err((i, "cutter radius compensation cannot start in a G02/G03 block (FANUC alarm PS0034): start it in a G00 or G01 block".into()));
                }
                if !e.moves() {
                    return Err((
                        i,
                        "the start-up block of cutter radius compensation must move in the plane"
                            .into(),
                    ));
                }
                let dir = match next {
                    Some(k) => Elem::of(&path[k]).tangent(e.b),
                    None => e.tangent(e.b),
                };
                e.b + (dir.perp() * (s * r))
            }
            Comp::Cancel(..) => {
                if p.arc.is_some() {
                    return Err((i, "G40 cannot cancel cutter radius compensation in a G02/G03 block: cancel it in a G00 or G01 block".into()));
                }
                e.b
            }
            _ if !e.moves() => start,
            _ => match next.map(|k| (k, &path[k])) {
                Some((k, q)) if matches!(q.comp, Comp::On(..)) => {
                    corner(&e, &Elem::of(q), side, r, p.site.line).map_err(|m| (k, m))?
                }
                _ => e.b + (e.tangent(e.b).perp() * (s * r)),
            },
        };
        let (u0, u1) = (p.start[p.plane.axes()[2]], p.end[p.plane.axes()[2]]);
        let arc = match (e.circle, p.arc) {
            (Some((c, rad, _)), Some(arc)) => {
                let Offset::Circle(_, tool_r) = e.offset(s, r) else {
                    unreachable!("an arc's offset is a circle")
                };
                if tool_r <= 1e-9 {
                    return Err((i, format!(
                        "{}: the tool radius {r} does not fit inside this arc of radius {rad:.4} (R - r <= 0: FANUC interference alarm)",
                        side_name(side)
                    )));
                }
                let sweep = arc.sweep + wrap((end - c).to_angle() - (e.b - c).to_angle())
                    - wrap((start - c).to_angle() - (e.a - c).to_angle());
                if sweep * arc.sweep <= 0.0 {
                    return Err((i, format!(
                        "{}: with the tool radius {r} the tool centre would run this arc backwards (FANUC interference alarm)",
                        side_name(side)
                    )));
                }
                Some(MillArc {
                    centre: p.plane.point(c, u0),
                    radius: tool_r,
                    sweep,
                    plane: p.plane,
                })
            }
            _ => {
                if matches!(p.comp, Comp::On(..)) && (end - start).dot(e.b - e.a) < 0.0 {
                    return Err((i, format!(
                        "{}: with the tool radius {r} the tool centre would run this line backwards (FANUC interference alarm)",
                        side_name(side)
                    )));
                }
                None
            }
        };
        at = match p.comp {
            Comp::Cancel(..) => None,
            _ => Some(end),
        };
        let (a3, b3) = (p.plane.point(start, u0), p.plane.point(end, u1));
        if arc.is_none() && a3 == b3 {
            continue;
        }
        out.push(tool_move(p, a3, b3, arc, Some((side, r))));
    }
    Ok(out)
}

/// The output move of `p` with the tool centre's start, end and circle.
fn tool_move(
    p: &Programmed,
    start: [f64; 3],
    end: [f64; 3],
    arc: Option<MillArc>,
    comp: Option<(CompSide, f64)>,
) -> MillMove {
    MillMove {
        file: p.site.file.clone(),
        line: p.site.line,
        kind: p.kind,
        start,
        end,
        arc,
        programmed_end: p.end,
        feed: p.feed,
        spindle_rpm: p.spindle_rpm,
        spindle: p.spindle,
        tool: p.tool,
        tool_word: p.tool_word.clone(),
        comp,
    }
}
