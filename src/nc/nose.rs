//! Tool nose radius compensation on the lathe (G40/G41/G42) as a pure pass over the
//! programmed moves: [`compensate`] turns the contour a program writes into the path of
//! the point the control drives, the insert's imaginary tip (the point its offsets are
//! measured to), so that the nose circle runs tangent to the programmed contour.
//!
//! The model (FANUC 0i-TF operator's manual, "Tool nose radius compensation": the offset
//! vector, its start-up, offset mode and cancel; Haas lathe manual, "Imaginary tool tip and
//! direction": the tip direction is the vector from the nose centre to the imaginary tip):
//! in the plane `(z, r)` seen from +Y (Z to the right, X up), the nose centre of a
//! compensated move runs on the programmed path offset by the nose radius `r_n` to the
//! left (G41) or right (G42) of the direction of travel; the control drives the imaginary
//! tip, `r_n q` from the centre (`q` the tip direction, [`tip_direction`]). Outside
//! compensation the tip runs on the programmed path. How the offset paths join is the
//! control's ([`NoseRule`]):
//!
//! - **FANUC** (GSK 980TDc and Okuma OSP read the same): start-up type A (parameter No.
//!   5003#0 SUP = 0, the default; type B is not simulated): the start-up block (G00/G01)
//!   runs from its uncompensated start to its end plus `r_n` perpendicular to the next
//!   block's start direction. In offset mode, tangent joints share the perpendicular; inner
//!   corners meet at the intersection of the two offset paths (lines as lines, arcs as their
//!   circles) nearest the joint; outer corners of 90 deg or more inside at the intersection
//!   of the offset paths extended; sharper outer corners go round on two straight vectors:
//!   each offset path extended by `r_n` along its tangent, joined by a line. Cancel (the
//!   G00/G01 block with G40, type A): from the previous block's end offset perpendicular to
//!   the block's programmed end. A side change (G41 to G42 in offset mode, as the Okuma
//!   OSP-P200L manual's "G41 and G42" figures draw it) meets at the intersection of the
//!   offset paths on their two sides.
//! - **LinuxCNC** (rs274 2.9 `convert_straight_comp1/2`, `convert_arc_comp2`,
//!   `move_endpoint_and_flush`, checked move for move against rs274's canon): the entry move
//!   (a straight move longer than `r_n`) ends `r_n` perpendicular to itself at its end,
//!   then joins the next move as any corner; corners turning by at most 0.05 rad (`TOLERANCE_CONCAVE_CORNER`) keep the
//!   previous end's perpendicular; inner corners meet at the intersection; outer corners go
//!   round on an arc of radius `r_n` about the programmed corner (a straight traverse when
//!   the move after the corner is a G0); G40 is no special move: the next move runs from
//!   where the tool is to its programmed end.
//! - **SINUMERIK** (802D/840D "Tool radius compensation", W1 function manual: NORM/KONT,
//!   G450/G451): NORM start-up and cancel as FANUC's type A; KONT differs only when the
//!   start point lies behind the contour (on its material side): then the tool goes round
//!   the contour's start point as round any corner. Outer corners: G450 (the default) a
//!   transition circle of radius `r_n`, G451 the intersection of the offset paths (a
//!   transition circle where the corner turns more than 90 deg). Inner corners: the
//!   intersection.
//!
//! Arcs keep their centre; the nose centre runs on radius `R -+ r_n`. A nose that does not
//! fit (`R - r_n <= 0`), a compensated move that would run against its programmed
//! direction, inner corners whose offset paths do not meet: errors, as the controls alarm.
//! Moves made with the vector held (threading, the single and multiple repetitive cycles
//! whose own shapes are compensated beforehand, reference-point returns) run as programmed:
//! the compensated move before them ends on its programmed point, the one after them starts
//! up again from theirs.

use super::mill::{intersections, CompSide, Offset};
use super::{ArcGeometry, Diagnostic, Interp, Move, MoveKind, NcError};
use crate::model::tool::tip_direction;
use glam::DVec2;
use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, TAU};

type V2 = DVec2;

/// How a control joins the compensated path (see the module's text).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoseRule {
    /// FANUC 0i-TF, GSK 980TDc, Okuma OSP: type A start-up and cancel, intersections, two
    /// vectors round acute outer corners.
    Fanuc,
    /// LinuxCNC (rs274): entry perpendicular to the entry move, arcs round outer corners.
    Linuxcnc,
    /// SINUMERIK: `arc`: G450 transition circles at outer corners (else G451
    /// intersections); `kont`: the KONT approach (else NORM).
    Siemens {
        /// G450 (else G451).
        arc: bool,
        /// KONT (else NORM).
        kont: bool,
    },
}

/// The tool nose radius compensation a move was programmed under.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nose {
    /// G41 (left of the direction of travel) or G42 (right).
    pub side: CompSide,
    /// The nose radius the control uses (mm).
    pub radius: f64,
    /// The imaginary tip direction (FANUC numbering, 0 to 9).
    pub tip: u8,
    /// How the control joins the offset paths.
    pub rule: NoseRule,
    /// The move runs with the vector held (as programmed): threading, a cycle whose shape
    /// was compensated before its moves were made, a reference-point return.
    pub held: bool,
}

/// Where compensation finds the nose radius and the tip direction the control uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NoseData {
    /// By tool number: the tool's nose radius (mm) and tip direction (FANUC numbering).
    pub tool: BTreeMap<u32, (f64, u8)>,
    /// By offset number (FANUC/GSK `T0305` calls 5, Siemens `D5`, Okuma's third pair):
    /// what the control's offset page holds.
    pub offset: BTreeMap<u32, NoseOffset>,
}

/// A nose radius offset as the control's offset page holds it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoseOffset {
    /// The geometry's R (mm); `None`: the tool's own nose radius.
    pub radius: Option<f64>,
    /// The wear R, added (mm).
    pub wear: f64,
    /// The tip direction T; `None`: the tool's own.
    pub tip: Option<u8>,
}

impl NoseData {
    /// The radius and tip direction for tool `tool` called with offset `offset`: the offset
    /// page's where it gives them, else the tool's; a tool the job does not know has none
    /// (radius 0: nothing to compensate).
    pub(super) fn of(&self, tool: Option<u32>, offset: Option<u32>) -> (f64, u8) {
        let own = tool
            .and_then(|t| self.tool.get(&t))
            .copied()
            .unwrap_or((0.0, 0));
        let page = offset
            .and_then(|n| self.offset.get(&n))
            .copied()
            .unwrap_or_default();
        (
            (page.radius.unwrap_or(own.0) + page.wear).max(0.0),
            page.tip.unwrap_or(own.1),
        )
    }
}

/// [`compensate`] on a program's moves, its errors as the interpreter's (`m` knows the
/// programs' text for the block it quotes).
pub(super) fn apply(
    m: &Interp<'_>,
    moves: Vec<Move>,
    warnings: &[Diagnostic],
) -> Result<Vec<Move>, NcError> {
    compensate(&moves).map_err(|(k, message)| {
        let mv = &moves[k];
        let snippet = m
            .progs
            .by_name
            .values()
            .filter(|p| p.name == mv.file)
            .flat_map(|p| p.blocks.iter())
            .find(|b| b.0 == mv.line)
            .map_or_else(String::new, |b| b.1.clone());
        NcError {
            file: mv.file.clone(),
            line: mv.line,
            col: 0,
            message,
            snippet,
            stack: Vec::new(),
            hint: Some("tool nose radius compensation (G41/G42) with the nose radius of the tool's offset: check the contour against the radius, or the radius ([[tool]] nose_radius, [machine] offsets r)".into()),
            others: warnings.to_vec(),
        }
    })
}

/// A move in the plane `(z, r)`: from `a` to `b`, an arc's centre, radius and sense
/// (counter-clockwise seen from +Y).
#[derive(Clone, Copy, Debug)]
struct El {
    a: V2,
    b: V2,
    circle: Option<(V2, f64, bool)>,
}

impl El {
    fn of(m: &Move) -> El {
        let a = V2::new(m.z_start, m.x_start / 2.0);
        let b = V2::new(m.z, m.x_dia / 2.0);
        let circle = match (m.kind, m.arc) {
            (MoveKind::Arc, Some(g)) => {
                let c = V2::new(g.z_centre, g.x_centre_dia / 2.0);
                // rs274 offsets an arc by its radius at the end (`convert_arc_comp2`); the
                // others by the radius the arc starts on (they differ within the arc
                // tolerance).
                let lcnc = m.nose.is_some_and(|n| n.rule == NoseRule::Linuxcnc);
                let radius = if lcnc { b - c } else { a - c }.length();
                Some((c, radius, !g.clockwise))
            }
            _ => None,
        };
        El { a, b, circle }
    }

    fn line(a: V2, b: V2) -> El {
        El { a, b, circle: None }
    }

    /// No motion in the plane.
    fn still(&self) -> bool {
        self.circle.is_none() && (self.b - self.a).length() < 1e-12
    }

    /// The unit direction of travel at `at` (a point of the element).
    fn tangent(&self, at: V2) -> V2 {
        match self.circle {
            Some((c, r, ccw)) => {
                let t = (at - c).perp() / r;
                if ccw {
                    t
                } else {
                    -t
                }
            }
            None => (self.b - self.a).normalize_or_zero(),
        }
    }

    /// The offset path `s r` to the left (`s` +1 G41, -1 G42).
    fn offset(&self, s: f64, r: f64) -> Offset {
        match self.circle {
            Some((c, rad, ccw)) => {
                let sigma = if ccw { 1.0 } else { -1.0 };
                Offset::Circle(c, rad - s * sigma * r)
            }
            None => Offset::Line(
                self.a + self.tangent(self.a).perp() * (s * r),
                self.tangent(self.a),
            ),
        }
    }

    /// The offset point at `at` (a point of the element).
    fn normal_point(&self, at: V2, s: f64, r: f64) -> V2 {
        at + self.tangent(at).perp() * (s * r)
    }
}

fn sign(side: CompSide) -> f64 {
    match side {
        CompSide::Left => 1.0,
        CompSide::Right => -1.0,
    }
}

/// The tip direction's vector `q` (`(dz, dr)` per mm of nose radius).
fn tip_vec(tip: u8) -> V2 {
    let (dz, dx) = tip_direction(tip).unwrap_or((0.0, 0.0));
    V2::new(dz, dx)
}

/// A straight or circular piece the tool centre runs between two programmed moves.
#[derive(Clone, Copy, Debug)]
enum Extra {
    Line(V2),
    Arc { centre: V2, to: V2, ccw: bool },
}

/// Where the centre ends the move before a joint, and the pieces it runs to reach the next
/// move's start.
struct Joint {
    end: V2,
    extra: Vec<Extra>,
    /// rs274 checks that the move before the corner still runs its way
    /// (`move_endpoint_and_flush`: at inner corners, whose intersection moves its end,
    /// and at outer corners before a straight move).
    checked: bool,
}

impl Joint {
    fn at(end: V2) -> Joint {
        Joint {
            end,
            extra: Vec::new(),
            checked: false,
        }
    }
}

/// The joint of the compensated elements `ei` (ending at the corner) and `ej`.
/// `j_rapid`: the move after the corner is a G00 (LinuxCNC goes round it on a traverse).
fn joint(ei: &El, ej: &El, ni: &Nose, nj: &Nose, j_rapid: bool) -> Result<Joint, String> {
    let p = ei.b;
    let (si, sj) = (sign(ni.side), sign(nj.side));
    let (ri, rj) = (ni.radius, nj.radius);
    let (ti, tj) = (ei.tangent(p), ej.tangent(p));
    let turn = ti.perp_dot(tj).atan2(ti.dot(tj));
    let end_i = ei.normal_point(p, si, ri);
    let start_j = ej.normal_point(p, sj, rj);
    let mid = (end_i + start_j) * 0.5;
    let nearest = |pts: Vec<V2>, to: V2| {
        pts.into_iter()
            .min_by(|x, y| (*x - to).length().total_cmp(&(*y - to).length()))
    };
    if si != sj {
        // A change of side in offset mode: the offset paths on their two sides meet.
        return Ok(
            match nearest(intersections(ei.offset(si, ri), ej.offset(sj, rj)), mid) {
                Some(q) => Joint {
                    checked: true,
                    ..Joint::at(q)
                },
                None => Joint {
                    extra: vec![Extra::Line(start_j)],
                    ..Joint::at(end_i)
                },
            },
        );
    }
    let small = match ni.rule {
        NoseRule::Linuxcnc => 0.05,
        _ => 1e-6,
    };
    if turn.abs() <= small {
        // Tangent (rs274: within 0.05 rad): the next move starts where this one ends.
        return Ok(Joint::at(end_i));
    }
    let inner = si * turn > 0.0;
    if inner {
        let q =
            nearest(intersections(ei.offset(si, ri), ej.offset(sj, rj)), mid).ok_or_else(|| {
                alarm(
                    ni.rule,
                    Alarm::Corner(ei.circle.is_some(), ej.circle.is_some()),
                )
            })?;
        return Ok(Joint {
            checked: true,
            ..Joint::at(q)
        });
    }
    let round = Joint {
        checked: ej.circle.is_none(),
        end: end_i,
        extra: vec![if j_rapid && ni.rule == NoseRule::Linuxcnc {
            Extra::Line(start_j)
        } else {
            Extra::Arc {
                centre: p,
                to: start_j,
                ccw: turn > 0.0,
            }
        }],
    };
    match ni.rule {
        NoseRule::Linuxcnc | NoseRule::Siemens { arc: true, .. } => Ok(round),
        NoseRule::Fanuc | NoseRule::Siemens { arc: false, .. } => {
            let obtuse = turn.abs() <= FRAC_PI_2 + 1e-9;
            if obtuse {
                if let Some(q) = nearest(intersections(ei.offset(si, ri), ej.offset(sj, rj)), p) {
                    return Ok(Joint::at(q));
                }
            }
            if ni.rule != NoseRule::Fanuc {
                return Ok(round);
            }
            // FANUC, inside angle under 90 deg: each offset path extended by r along its
            // tangent, the two ends joined by a line.
            let p1 = end_i + ti * ri;
            let p2 = start_j - tj * rj;
            let mut extra = Vec::new();
            let end = if ei.circle.is_some() {
                extra.push(Extra::Line(p1));
                end_i
            } else {
                p1
            };
            extra.push(Extra::Line(p2));
            if ej.circle.is_some() {
                extra.push(Extra::Line(start_j));
            }
            Ok(Joint {
                extra,
                ..Joint::at(end)
            })
        }
    }
}

/// What a control says where compensation cannot go on.
#[derive(Clone, Copy)]
enum Alarm {
    /// The start-up block is an arc.
    StartArc,
    /// The cancel block is an arc.
    CancelArc,
    /// LinuxCNC's entry move is not longer than the radius.
    ShortEntry,
    /// The nose does not fit inside an arc.
    ArcRadius,
    /// Inner corner offset paths that do not meet: (from an arc, into an arc).
    Corner(bool, bool),
    /// A compensated line would run backwards.
    Reversed(bool),
    /// A compensated arc would run backwards.
    ArcReversed,
}

fn alarm(rule: NoseRule, a: Alarm) -> String {
    let lcnc = rule == NoseRule::Linuxcnc;
    let siemens = matches!(rule, NoseRule::Siemens { .. });
    match a {
        Alarm::StartArc if lcnc => "an arc as the entry move of cutter compensation is not simulated (rs274 builds an auxiliary arc there): enter with a G0 or G1 move".into(),
        Alarm::StartArc if siemens => "tool radius compensation (G41/G42) can only be selected in a G0 or G1 block (SINUMERIK)".into(),
        Alarm::StartArc => "tool nose radius compensation cannot start in a G02/G03 block (FANUC alarm PS0034): start it in a G00 or G01 block".into(),
        Alarm::CancelArc if lcnc => "The move just after exiting cutter compensation mode must be straight, not an arc (rs274)".into(),
        Alarm::CancelArc if siemens => "tool radius compensation can only be deselected (G40) in a G0 or G1 block (SINUMERIK)".into(),
        Alarm::CancelArc => "G40 cannot cancel tool nose radius compensation in a G02/G03 block (FANUC alarm PS0034): cancel it in a G00 or G01 block".into(),
        Alarm::ShortEntry => "Length of cutter compensation entry move is not greater than the tool radius (rs274)".into(),
        Alarm::ArcRadius if lcnc => "Tool radius not less than arc radius with comp (rs274)".into(),
        Alarm::ArcRadius => "the nose radius does not fit inside this arc (R - r <= 0: the control's interference alarm)".into(),
        Alarm::Corner(true, false) if lcnc => "Arc to straight motion makes a corner the compensated tool can't fit in without gouging (rs274)".into(),
        Alarm::Corner(true, true) if lcnc => "Arc to arc motion makes a corner the compensated tool can't fit in without gouging (rs274)".into(),
        Alarm::Corner(..) if lcnc => "Arc move in concave corner cannot be reached by the tool without gouging (rs274)".into(),
        Alarm::Corner(..) => "the nose's offset paths of this corner do not meet (the control's interference alarm)".into(),
        Alarm::Reversed(rapid) if lcnc => format!(
            "Straight {} in concave corner cannot be reached by the tool without gouging (rs274)",
            if rapid { "traverse" } else { "feed" }
        ),
        Alarm::Reversed(_) => "with this nose radius the compensated path would run this line backwards (the control's interference alarm)".into(),
        Alarm::ArcReversed if lcnc => "Arc move in concave corner cannot be reached by the tool without gouging (rs274)".into(),
        Alarm::ArcReversed => "with this nose radius the compensated path would run this arc backwards (the control's interference alarm)".into(),
    }
}

/// The compensation that applies to a move: on, not held, with a radius.
fn active(m: &Move) -> Option<Nose> {
    m.nose.filter(|n| !n.held && n.radius > 0.0)
}

/// What comes after a compensated move.
#[derive(Clone, Copy)]
enum Next {
    /// Another compensated move (its index).
    Comp(usize),
    /// A move with the vector held.
    Held,
    /// A move without compensation (the G40 block).
    Cancel,
    /// Nothing.
    End,
}

fn next_of(moves: &[Move], els: &[El], i: usize) -> Next {
    for (k, m) in moves.iter().enumerate().skip(i + 1) {
        if els[k].still() {
            continue;
        }
        return match (active(m), m.nose) {
            (Some(_), _) => Next::Comp(k),
            (None, Some(n)) if n.held => Next::Held,
            _ => Next::Cancel,
        };
    }
    Next::End
}

/// The sweep (rad, signed as the arc runs) from `from` to `to` about `c`, the way `ccw`
/// says, in `[0, 2 pi)` in magnitude.
fn sweep(c: V2, from: V2, to: V2, ccw: bool) -> f64 {
    let d = (to - c).to_angle() - (from - c).to_angle();
    if ccw {
        d.rem_euclid(TAU)
    } else {
        -(-d).rem_euclid(TAU)
    }
}

/// The path of the driven point of `moves` (in execution order) with tool nose radius
/// compensation applied where their [`Move::nose`] says so; the moves that are not
/// compensated are returned as they are. An error gives the index of the move it is about
/// and what the control says.
pub(super) fn compensate(moves: &[Move]) -> Result<Vec<Move>, (usize, String)> {
    if !moves.iter().any(|m| active(m).is_some()) {
        return Ok(moves
            .iter()
            .map(|m| Move {
                nose: None,
                ..m.clone()
            })
            .collect());
    }
    let els: Vec<El> = moves.iter().map(El::of).collect();
    let mut out: Vec<Move> = Vec::with_capacity(moves.len());
    // The nose centre where the last compensated move left it, while compensation runs.
    let mut centre: Option<V2> = None;
    // Where the driven point is: the end of the last move made.
    let mut at: Option<V2> = None;
    for (i, m) in moves.iter().enumerate() {
        let e = els[i];
        let Some(nz) = active(m) else {
            let mut plain = m.clone();
            plain.nose = None;
            if centre.is_some() && e.still() {
                // No motion: the tool stays where compensation left it.
                if let Some(p) = at {
                    set_start(&mut plain, p);
                    set_end(&mut plain, p, None);
                }
                out.push(plain);
                continue;
            }
            if centre.is_some() {
                centre = None;
                let held = m.nose.is_some_and(|n| n.held);
                if !held {
                    // The cancel block: from where the tool is to its programmed end.
                    let rule = moves[..i]
                        .iter()
                        .rev()
                        .find_map(active)
                        .map_or(NoseRule::Fanuc, |n| n.rule);
                    if e.circle.is_some() {
                        return Err((i, alarm(rule, Alarm::CancelArc)));
                    }
                    if let Some(p) = at {
                        set_start(&mut plain, p);
                    }
                }
            }
            at = Some(els[i].b);
            out.push(plain);
            continue;
        };
        let (s, r, q) = (sign(nz.side), nz.radius, tip_vec(nz.tip));
        let tip_of = |c: V2| c + q * r;
        if e.still() {
            // No motion in the plane: the tool stays where it is.
            let mut still = m.clone();
            if let Some(p) = at {
                set_start(&mut still, p);
                set_end(&mut still, p, None);
            }
            out.push(still);
            continue;
        }
        let next = next_of(moves, &els, i);
        let start_tip = at.unwrap_or(e.a);
        // The element as compensated, the direction a line may not run against, the centre
        // where it starts (`None` for a start-up: it starts at the driven point), and
        // whether a start-up joins the next move as a corner (LinuxCNC; SINUMERIK KONT
        // behind the contour) rather than ending perpendicular to its start (type A).
        let (el, guard, start_c, corner_entry) = match centre {
            Some(c) => (e, e.tangent(e.a), Some(c), false),
            None => {
                if e.circle.is_some() {
                    return Err((i, alarm(nz.rule, Alarm::StartArc)));
                }
                let entry = El::line(start_tip, e.b);
                let corner_entry = match (nz.rule, next) {
                    (NoseRule::Linuxcnc, _) => true,
                    // KONT: the start point behind the contour (on its material side).
                    (NoseRule::Siemens { kont: true, .. }, Next::Comp(j)) => {
                        let n = els[j].tangent(e.b).perp() * s;
                        (start_tip - e.b).dot(n) < 0.0
                    }
                    _ => false,
                };
                if nz.rule == NoseRule::Linuxcnc && (e.b - start_tip).length() <= r {
                    return Err((i, alarm(nz.rule, Alarm::ShortEntry)));
                }
                // rs274 checks the entry against the side's normal, not its direction.
                (entry, entry.tangent(e.b).perp() * s, None, corner_entry)
            }
        };
        // rs274 finds an arc the nose does not fit inside converting the arc's own block,
        // before the corner after it.
        if nz.rule == NoseRule::Linuxcnc && start_c.is_some() {
            if let Some(Offset::Circle(_, r_tool)) = el.circle.map(|_| el.offset(s, r)) {
                if r_tool <= 1e-9 {
                    return Err((i, alarm(nz.rule, Alarm::ArcRadius)));
                }
            }
        }
        let joint = match next {
            Next::Comp(j) if start_c.is_none() && !corner_entry => {
                // Type A start-up (FANUC, SINUMERIK NORM): perpendicular to the next
                // block's start.
                Joint::at(els[j].normal_point(e.b, s, r))
            }
            Next::Comp(j) => {
                let nj = active(&moves[j]).expect("a compensated move");
                if nz.rule == NoseRule::Linuxcnc && nj.side != nz.side {
                    return Err((
                        j,
                        "Cannot turn cutter radius comp on when on (rs274)".into(),
                    ));
                }
                joint(&el, &els[j], &nz, &nj, moves[j].kind == MoveKind::Rapid)
                    .map_err(|msg| (j, msg))?
            }
            Next::Held => Joint::at(e.b - q * r),
            Next::Cancel | Next::End => Joint::at(el.normal_point(e.b, s, r)),
        };
        // The block an alarm of this move's end names: rs274 finds it converting the
        // block after the corner; FANUC's interference check, this block.
        let at_fault = match next {
            Next::Comp(j) if nz.rule == NoseRule::Linuxcnc => j,
            _ => i,
        };
        // This move.
        let mut mv = m.clone();
        mv.nose = Some(nz);
        set_start(&mut mv, start_tip);
        match (el.circle, start_c) {
            (Some((c, _, ccw)), Some(sc)) => {
                let Offset::Circle(_, r_tool) = el.offset(s, r) else {
                    unreachable!("an arc's offset is a circle")
                };
                if r_tool <= 1e-9 {
                    return Err((i, alarm(nz.rule, Alarm::ArcRadius)));
                }
                // The end on the offset circle: a joint off it (held, FANUC's acute corner)
                // ends the arc at its perpendicular and goes on in a straight line.
                let on_circle = ((joint.end - c).length() - r_tool).abs() < 1e-9;
                let arc_end = if on_circle {
                    joint.end
                } else {
                    el.normal_point(e.b, s, r)
                };
                let old = sweep(c, e.a, e.b, ccw);
                let new = sweep(c, sc, arc_end, ccw);
                // Run backwards: the sweep the programmed way wraps round. rs274 checks an
                // arc before a corner as a line (beyond 0.0254 of its sweep); the
                // others may grow by outer corners' intersections (up to 90 deg an end), so
                // only a wrap past half a turn more is a reversal.
                let lcnc = nz.rule == NoseRule::Linuxcnc;
                let (check, tol) = if lcnc {
                    (joint.checked, 0.0254)
                } else {
                    (true, std::f64::consts::PI)
                };
                if check && new.abs() > old.abs() + tol && old.abs() > 0.0 {
                    return Err((at_fault, alarm(nz.rule, Alarm::ArcReversed)));
                }
                set_end(&mut mv, tip_of(arc_end), Some((tip_of(c), !ccw)));
                out.push(mv);
                if !on_circle {
                    push_line(&mut out, m, nz, tip_of(arc_end), tip_of(joint.end));
                }
            }
            _ => {
                // A line: check it does not run backwards.
                // rs274 checks a line before an inner corner, or an outer one into a
                // straight move, against its programmed direction (an entry move against
                // its side's normal); FANUC's interference check every line in offset mode.
                let from = start_c.unwrap_or(start_tip);
                let lcnc = nz.rule == NoseRule::Linuxcnc;
                let check = if lcnc {
                    joint.checked
                } else {
                    start_c.is_some()
                };
                if check {
                    let dir = if start_c.is_some() {
                        e.tangent(e.a)
                    } else {
                        guard
                    };
                    if (joint.end - from).dot(dir) < 0.0 {
                        return Err((
                            at_fault,
                            alarm(nz.rule, Alarm::Reversed(m.kind == MoveKind::Rapid)),
                        ));
                    }
                }
                set_end(&mut mv, tip_of(joint.end), None);
                out.push(mv);
            }
        }
        // The pieces round the corner.
        let mut c_at = joint.end;
        let kind = match next {
            Next::Comp(j) if moves[j].kind == MoveKind::Rapid => MoveKind::Rapid,
            _ => MoveKind::Feed,
        };
        for x in &joint.extra {
            match *x {
                Extra::Line(to) => {
                    let mut piece = piece_of(m, nz, kind);
                    set_start(&mut piece, tip_of(c_at));
                    set_end(&mut piece, tip_of(to), None);
                    out.push(piece);
                    c_at = to;
                }
                Extra::Arc {
                    centre: pc,
                    to,
                    ccw,
                } => {
                    let mut piece = piece_of(m, nz, MoveKind::Arc);
                    set_start(&mut piece, tip_of(c_at));
                    set_end(&mut piece, tip_of(to), Some((tip_of(pc), !ccw)));
                    out.push(piece);
                    c_at = to;
                }
            }
        }
        // Before a held move the vector is gone (the driven point on the programmed one);
        // a cancel block starts from where the compensated path left the tool.
        at = Some(tip_of(c_at));
        centre = (!matches!(next, Next::Held)).then_some(c_at);
    }
    Ok(out)
}

/// A piece of path the compensation adds after move `m` (a corner's), of `kind`.
fn piece_of(m: &Move, nz: Nose, kind: MoveKind) -> Move {
    let mut p = m.clone();
    p.kind = kind;
    p.arc = None;
    p.nose = Some(nz);
    p
}

/// Add a straight feed piece from `a` to `b` (tip positions) after move `m`.
fn push_line(out: &mut Vec<Move>, m: &Move, nz: Nose, a: V2, b: V2) {
    let kind = if m.kind == MoveKind::Rapid {
        MoveKind::Rapid
    } else {
        MoveKind::Feed
    };
    let mut p = piece_of(m, nz, kind);
    set_start(&mut p, a);
    set_end(&mut p, b, None);
    out.push(p);
}

fn set_start(m: &mut Move, p: V2) {
    m.z_start = p.x;
    m.x_start = 2.0 * p.y;
}

/// Set the end (and for an arc its centre and sense: clockwise) of `m`.
fn set_end(m: &mut Move, p: V2, arc: Option<(V2, bool)>) {
    m.z = p.x;
    m.x_dia = 2.0 * p.y;
    if let Some((c, clockwise)) = arc {
        m.kind = MoveKind::Arc;
        m.arc = Some(ArcGeometry {
            x_centre_dia: 2.0 * c.y,
            z_centre: c.x,
            clockwise,
        });
    }
}

impl Interp<'_> {
    /// G40/G41/G42 of a lathe block (and the SINUMERIK corner modes G450/G451): the modal
    /// compensation state the moves are made under. LinuxCNC's `D` names the tool table
    /// entry whose radius and orientation compensate (rs274 `convert_cutter_compensation_on`:
    /// a whole number, not negative; without it the tool in the spindle), and turning it on
    /// while it is on is rs274's error. LinuxCNC's G41.1/G42.1 (`DECIMAL_G + 411/421`)
    /// compensate with the block's radius `D / 2` (program units; a negative D swaps the
    /// side) and orientation `L` (0 without it), as rs274's
    /// `convert_cutter_compensation_on`.
    pub(super) fn nose_word(&mut self, g: u32, w: &super::Words) -> Result<(), super::expr::Fail> {
        use super::motion::DECIMAL_G;
        use super::Dialect;
        if g == DECIMAL_G + 411 || g == DECIMAL_G + 421 {
            let name = if g == DECIMAL_G + 411 {
                "G41.1"
            } else {
                "G42.1"
            };
            if self.modal.nose.is_some() {
                return Err((
                    1,
                    "Cannot turn cutter radius comp on when on (rs274): G40 first".into(),
                ));
            }
            let Some(&(d, _)) = w.vals.get("D") else {
                return Err((1, format!("{name} with no D word")));
            };
            let tip = match w.vals.get("L") {
                None => 0,
                Some(&(l, col)) => {
                    if l.fract() != 0.0 || !(0.0..=9.0).contains(&l) {
                        return Err((
                            col,
                            format!(
                                "{name} L{l}: expected a tool orientation, a whole number 0 to 9"
                            ),
                        ));
                    }
                    l as u8
                }
            };
            let mut side = if g == DECIMAL_G + 411 {
                CompSide::Left
            } else {
                CompSide::Right
            };
            if d < 0.0 {
                side = match side {
                    CompSide::Left => CompSide::Right,
                    CompSide::Right => CompSide::Left,
                };
            }
            let scale = if self.modal.inch { 25.4 } else { 1.0 };
            self.modal.nose = Some((side, None));
            self.modal.nose_dynamic = Some((
                d.abs() / 2.0 * scale,
                crate::model::tool::linuxcnc_orientation(tip),
            ));
            return Ok(());
        }
        match g {
            40 => {
                self.modal.nose = None;
                self.modal.nose_dynamic = None;
            }
            41 | 42 => {
                let side = if g == 41 {
                    CompSide::Left
                } else {
                    CompSide::Right
                };
                let mut d = None;
                if self.cfg.dialect == Dialect::Linuxcnc {
                    if self.modal.nose.is_some() {
                        return Err((
                            1,
                            "Cannot turn cutter radius comp on when on (rs274): G40 first".into(),
                        ));
                    }
                    if let Some(&(v, col)) = w.vals.get("D") {
                        if v.fract() != 0.0 || v < 0.0 {
                            return Err((
                                col,
                                format!("G{g} requires D word to be a whole number, not negative (rs274), got {v}"),
                            ));
                        }
                        d = Some(v as u32);
                    }
                }
                self.modal.nose = Some((side, d));
                self.modal.nose_dynamic = None;
            }
            450 | 451 => self.modal.nose_arc = g == 450,
            _ => {}
        }
        Ok(())
    }

    /// The compensation the move being made now runs under, if any (`kind`: a thread move
    /// holds the vector).
    pub(super) fn nose_now(&self, kind: MoveKind) -> Option<Nose> {
        use super::Dialect;
        let (side, d) = self.modal.nose?;
        let (radius, tip) = match self.cfg.dialect {
            Dialect::Linuxcnc => match self.modal.nose_dynamic {
                Some(dynamic) => dynamic,
                None => self.cfg.noses.of(d.or(self.modal.tool), None),
            },
            _ => self.cfg.noses.of(self.modal.tool, self.modal.offset),
        };
        let rule = match self.cfg.dialect {
            Dialect::Linuxcnc => NoseRule::Linuxcnc,
            Dialect::Siemens802d | Dialect::Siemens840d => NoseRule::Siemens {
                arc: self.modal.nose_arc,
                kont: self.modal.nose_kont,
            },
            _ => NoseRule::Fanuc,
        };
        Some(Nose {
            side,
            radius,
            tip,
            rule,
            held: self.out.nose_hold || self.out.cycle || kind == MoveKind::Thread,
        })
    }

    /// Whether a move made now would be compensated by a nose radius.
    pub(super) fn nose_on(&self) -> bool {
        self.nose_now(MoveKind::Feed)
            .is_some_and(|n| n.radius > 0.0)
    }

    /// Run `f` (a cycle's block) with the vector held: its moves run as made.
    pub(super) fn nose_held<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        let before = self.out.nose_hold;
        self.out.nose_hold = true;
        let r = f(self);
        self.out.nose_hold = before;
        r
    }

    /// The warning of a block whose moves run with the vector held although compensation
    /// is on (`what` the block: a threading block or cycle).
    pub(super) fn nose_note(&mut self, what: &str) {
        if self.nose_on() {
            self.out.notes.push((
                1,
                format!("{what} with tool nose radius compensation on (G41/G42): vpcut runs its moves as programmed (the imaginary tip), the compensated move before it ending on its programmed point"),
                "cancel compensation with G40 before the cycle (FANUC applies none to threading; a taper G90/G94 it offsets by the nose)".into(),
            ));
        }
    }

    /// A G71/G72/G73 finishing shape compensated for the nose (FANUC 0i-TF: with G41/G42
    /// given before the cycle, or in its shape, the roughing cuts to the compensated shape;
    /// the cycle's moves then run with the vector held).
    pub(super) fn nose_shape(
        &self,
        g: u32,
        moves: Vec<Move>,
    ) -> Result<Vec<Move>, super::expr::Fail> {
        if !moves.iter().any(|m| active(m).is_some()) {
            return Ok(moves);
        }
        compensate(&moves)
            .map(|v| {
                v.into_iter()
                    .map(|m| Move { nose: None, ..m })
                    .collect()
            })
            .map_err(|(k, msg)| {
                (
                    1,
                    format!(
                        "G{g}: the finishing shape with the nose radius compensated, at line {}: {msg}",
                        moves[k].line
                    ),
                )
            })
    }

    /// LinuxCNC `G10 L1/L10/L11 P R Q`: tool P's radius R (program units) and orientation Q
    /// in the tool table, as rs274's `convert_setup_tool` sets them (words left out keep
    /// their values; the front and back angles I/J only draw the tool). The tool's X/Z
    /// offsets go to the machine (rs274's `USE_TOOL_LENGTH_OFFSET`): the canon's points, and
    /// vpcut's, are the tip's, which follows the program.
    pub(super) fn lc_g10_tool(
        &mut self,
        w: &super::Words,
        l: f64,
        scale: f64,
    ) -> Result<(), super::expr::Fail> {
        let get = |k: &str| w.vals.get(k).copied();
        let (p, pcol) = get("P").ok_or((1, format!("G10 L{l} needs P (the tool number)")))?;
        if p.fract() != 0.0 || p < 0.0 {
            return Err((pcol, format!("G10 L{l} P{p}: expected a tool number")));
        }
        if l == 1.0
            && !["R", "Q", "X", "Z", "I", "J"]
                .iter()
                .any(|k| w.vals.contains_key(*k))
        {
            return Err((1, "G10 L1 without offsets has no effect (rs274)".into()));
        }
        let entry = self.cfg.noses.tool.entry(p as u32).or_insert((0.0, 0));
        if let Some((r, col)) = get("R") {
            if r < 0.0 {
                return Err((col, format!("G10 L{l} R{r}: a nose radius is not negative")));
            }
            entry.0 = r * scale;
        }
        if let Some((q, col)) = get("Q") {
            if q.fract() != 0.0 || !(0.0..=9.0).contains(&q) {
                return Err((
                    col,
                    format!("Invalid tool orientation Q{q} (rs274: a whole number 0 to 9)"),
                ));
            }
            entry.1 = crate::model::tool::linuxcnc_orientation(q as u8);
        }
        Ok(())
    }
}
