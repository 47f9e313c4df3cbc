//! FANUC machining-centre blocks (`Settings::mill`): the modal state of a milling program
//! and its words turned into programmed moves ([`Programmed`]), which cutter radius
//! compensation (`comp`) turns into the tool centre's path at the end of the run.
//!
//! X/Y/Z are positions in the active work system G54..G59 (`MillSettings::work_offsets`),
//! absolute (G90) or incremental (G91); G17/G18/G19 choose the plane of arcs and of
//! compensation; G02/G03 take I/J/K (incremental centre) or R and move the plane's normal
//! axis linearly (helical). The tip's Z is known only under G43 with an H register of the
//! job's tools; a block that feeds or moves Z down without it is an error. At the start X,
//! Y and Z are unknown: a rapid from an unknown X or Y only sets its axes, one from an
//! unknown Z comes down from `MillSettings::home_z`.

use super::comp::{Comp, Programmed, Site};
use super::{CompSide, MillArc, MillKind, MillSettings, Plane};
use crate::model::helix::Spindle;
use crate::nc::codes::{self, Verdict};
use crate::nc::expr::Fail;
use crate::nc::motion::{radius_centre, ARC_TOLERANCE};
use crate::nc::{Interp, Program, Step, Words};
use std::f64::consts::TAU;

/// The modal state of a milling program.
pub(in crate::nc) struct MillState {
    settings: MillSettings,
    /// The programmed tool tip (job frame, before radius compensation); `None`: unknown.
    pos: [Option<f64>; 3],
    /// G00..G03.
    motion: u32,
    plane: Plane,
    incremental: bool,
    /// G95 feed per revolution (else G94 per minute).
    per_rev: bool,
    /// Active work system (0 = G54).
    work: usize,
    /// G43 in force: the tip follows the programmed Z.
    length: bool,
    /// The radius of the last D word (mm).
    d_radius: f64,
    /// G41/G42 in force (side, radius), and whether its start-up block has run.
    comp: Option<(CompSide, f64)>,
    comp_started: bool,
    /// F in mm (per minute or per revolution).
    feed: Option<f64>,
    rpm: Option<f64>,
    spindle: Option<Spindle>,
    tool: Option<u32>,
    /// The T word as written (`MillMove::tool_word`).
    tool_word: Option<std::sync::Arc<str>>,
    /// The programmed moves so far.
    pub(in crate::nc) path: Vec<Programmed>,
    /// The call stack of the block being run (for errors found after the run).
    pub(in crate::nc) stack: Vec<String>,
}

impl MillState {
    pub(in crate::nc) fn new(settings: MillSettings) -> MillState {
        MillState {
            settings,
            pos: [None; 3],
            motion: 0,
            plane: Plane::Xy,
            incremental: false,
            per_rev: false,
            work: 0,
            length: false,
            d_radius: 0.0,
            comp: None,
            comp_started: false,
            feed: None,
            rpm: None,
            spindle: None,
            tool: None,
            tool_word: None,
            path: Vec::new(),
            stack: Vec::new(),
        }
    }
}

/// The G codes of a block that act once: (G43, G49, G40/G41/G42).
#[derive(Default)]
struct OneShot {
    g43: bool,
    g49: bool,
    /// `Some(None)`: G40; `Some(Some(side))`: G41/G42.
    comp: Option<Option<CompSide>>,
}

impl Interp<'_> {
    /// One block of a milling program (its words read by `fanuc_block`).
    pub(in crate::nc) fn mill_apply(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
    ) -> Result<Step, Fail> {
        let mut st = self.mill.take().expect("a milling program has its state");
        let step = self.mill_block(&mut st, w, prog, pc);
        self.mill = Some(st);
        step
    }

    fn mill_block(
        &mut self,
        st: &mut MillState,
        w: &Words,
        prog: &Program,
        pc: usize,
    ) -> Result<Step, Fail> {
        let mut once = OneShot::default();
        for &g in &w.g {
            match g {
                0..=3 => st.motion = g,
                17..=19 => {
                    let plane = [Plane::Xy, Plane::Zx, Plane::Yz][(g - 17) as usize];
                    if st.comp.is_some() && plane != st.plane {
                        return Err((1, format!("G{g}: the plane cannot change under cutter radius compensation; cancel it with G40 first")));
                    }
                    st.plane = plane;
                }
                20 | 21 => {
                    self.modal.inch = g == 20;
                    self.modal.units_set = true;
                }
                40 => once.comp = Some(None),
                41 => once.comp = Some(Some(CompSide::Left)),
                42 => once.comp = Some(Some(CompSide::Right)),
                43 => once.g43 = true,
                49 => once.g49 = true,
                54..=59 => st.work = (g - 54) as usize,
                90 => st.incremental = false,
                91 => st.incremental = true,
                94 => st.per_rev = false,
                95 => st.per_rev = true,
                other => match codes::mill_g_code(f64::from(other)) {
                    Verdict::Run => {}
                    Verdict::Refused(msg) => return Err((1, msg)),
                    Verdict::Unknown(msg) => self.unknown(1, msg)?,
                },
            }
        }
        let mut end = false;
        if let Some(step) = self.m_words(w, &mut end)? {
            return Ok(step);
        }
        // The spindle starts before the block's move and stops after it.
        if w.m.contains(&3) {
            st.spindle = Some(Spindle::Cw);
        }
        if w.m.contains(&4) {
            st.spindle = Some(Spindle::Ccw);
        }
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let val = |k: &str| w.vals.get(k).copied();
        if let Some((t, _)) = val("T") {
            st.tool = Some(t.round().max(0.0) as u32);
            st.tool_word =
                Some(std::sync::Arc::from(w.t_text.clone().unwrap_or_else(
                    || crate::nc::tool_word(crate::nc::Dialect::Linuxcnc, t),
                )));
        }
        if let Some((s, _)) = val("S") {
            st.rpm = Some(s);
        }
        if let Some((f, _)) = val("F") {
            st.feed = Some(f * scale);
        }
        self.mill_registers(st, w, &once)?;
        // G04 (dwell, one shot): its X or P is the time; the block moves nothing.
        if w.g.contains(&4) {
            if let Some(&(_, col)) = w.vals.get("Y").or(w.vals.get("Z")) {
                return Err((
                    col,
                    "G04 (dwell) takes its time in X or P: Y and Z move nothing here (a control alarms)".into(),
                ));
            }
            return Ok(if end { Step::End } else { Step::Next });
        }
        let step = self.mill_motion(st, w, prog, pc, &once)?;
        if w.m.contains(&5) {
            st.spindle = None;
        }
        Ok(if end { Step::End } else { step })
    }

    /// G43 H, G49, D and G40/G41/G42.
    fn mill_registers(
        &mut self,
        st: &mut MillState,
        w: &Words,
        once: &OneShot,
    ) -> Result<(), Fail> {
        if let Some(&(h, col)) = w.vals.get("H") {
            let n = h.round() as u32;
            if h < 0.0 || !st.settings.length_offsets.contains(&n) {
                return Err((
                    col,
                    format!(
                        "H{h} is not a length offset of the job's tools (expected one of {})",
                        st.settings
                            .length_offsets
                            .iter()
                            .map(|o| o.to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
        } else if once.g43 {
            return Err((1, "G43 needs H (the tool length offset number)".into()));
        }
        if once.g43 {
            st.length = true;
        }
        if let Some(&(d, col)) = w.vals.get("D") {
            let known = st.settings.radius_offsets.iter().map(|o| o.0);
            let known: Vec<String> = known.map(|o| o.to_string()).collect();
            let expected = format!("expected D0 or one of {}", known.join(", "));
            let n = d.round() as u32;
            st.d_radius = match st.settings.radius_offsets.iter().find(|o| o.0 == n) {
                _ if d < 0.0 => None,
                _ if n == 0 => Some(0.0),
                found => found.map(|o| o.1),
            }
            .ok_or((
                col,
                format!("D{d} is not a radius offset of the job's tools ({expected})"),
            ))?;
            if !(st.d_radius >= 0.0 && st.d_radius.is_finite()) {
                return Err((col, format!("D{n} holds the radius {}: negative (or not finite) radius offsets are not modelled", st.d_radius)));
            }
        }
        match once.comp {
            Some(Some(side)) => {
                let want = (side, st.d_radius);
                match st.comp {
                    Some(c) if st.comp_started && c != want => {
                        return Err((1, "changing the side or radius of cutter radius compensation while it is on is not modelled: cancel it with G40 first".into()));
                    }
                    _ => st.comp = Some(want),
                }
            }
            Some(None) if !st.comp_started => st.comp = None,
            _ => {}
        }
        Ok(())
    }

    /// The axis words of a block: its move, recorded in `st.path`.
    fn mill_motion(
        &mut self,
        st: &mut MillState,
        w: &Words,
        prog: &Program,
        pc: usize,
        once: &OneShot,
    ) -> Result<Step, Fail> {
        let offset = st.settings.work_offsets[st.work];
        let mut target = st.pos;
        let mut named = false;
        // Lengths as FANUC reads them (decimal-point input, `units`).
        for (k, axis) in ["X", "Y", "Z"].into_iter().enumerate() {
            if let Some(v) = self.length(w, axis) {
                named = true;
                target[k] = if st.incremental {
                    st.pos[k].map(|p| p + v)
                } else {
                    Some(v + offset[k])
                };
            }
        }
        let arc_words: Vec<(&str, f64)> = ["R", "I", "J", "K"]
            .into_iter()
            .filter_map(|k| self.length(w, k).map(|v| (k, v)))
            .collect();
        let length = |k: &str| arc_words.iter().find(|a| a.0 == k).map(|a| a.1);
        // The tip's Z without tool length compensation.
        if once.g49 || !st.length {
            if let Some(&(v, col)) = w.vals.get("Z") {
                let up = if st.incremental {
                    v >= 0.0
                } else {
                    // An absolute Z from an unknown Z: the direction is unknown (a retract
                    // before G43 is common), the tip stays unknown.
                    st.pos[2].is_none_or(|z| target[2].is_some_and(|t| t >= z))
                };
                if !up {
                    return Err((col, "Z moves down with no tool length compensation: the tip's Z is unknown (program G43 H.. first)".into()));
                }
                target[2] = None;
            }
            if once.g49 {
                st.length = false;
                target[2] = None;
            }
        }
        let cancel = once.comp == Some(None) && st.comp_started;
        if !named && !cancel {
            return Ok(Step::Next);
        }
        let kind = match st.motion {
            0 => MillKind::Rapid,
            1 => MillKind::Feed,
            _ => MillKind::Arc,
        };
        if kind != MillKind::Rapid && !st.length {
            return Err((1, format!("a G{:02} move with no tool length compensation: the tip's Z is unknown (program G43 H.. first)", st.motion)));
        }
        let start = st.pos;
        st.pos = target;
        let (Some(x0), Some(y0), Some(to)) = (
            start[0],
            start[1],
            target.iter().copied().collect::<Option<Vec<f64>>>(),
        ) else {
            if kind != MillKind::Rapid {
                return Err((1, format!("a G{:02} move from or to an unknown position: program a G00 to a known X, Y and Z (under G43) first", st.motion)));
            }
            if st.comp.is_some() && (cancel || st.comp_started || in_plane(st.plane, start, target))
            {
                return Err((1, "a move under cutter radius compensation from or to an unknown position: program a G00 to a known X, Y and Z (under G43) first".into()));
            }
            return Ok(Step::Next);
        };
        let from = [x0, y0, start[2].unwrap_or(st.settings.home_z)];
        let to = [to[0], to[1], to[2]];
        let arc = if kind == MillKind::Arc {
            Some(arc_circle(st.plane, st.motion == 2, w, from, to, &length)?)
        } else {
            None
        };
        let moves_in_plane = arc.is_some() || {
            let [u, v, _] = st.plane.axes();
            from[u] != to[u] || from[v] != to[v]
        };
        let comp = match st.comp {
            Some((side, r)) if cancel => {
                if kind == MillKind::Arc {
                    return Err((1, "G40 cannot cancel cutter radius compensation in a G02/G03 block: cancel it in a G00 or G01 block".into()));
                }
                st.comp = None;
                st.comp_started = false;
                Comp::Cancel(side, r)
            }
            Some((side, r)) if st.comp_started => Comp::On(side, r),
            Some((side, r)) if moves_in_plane => {
                if kind == MillKind::Arc {
                    return Err((1, "cutter radius compensation cannot start in a G02/G03 block (FANUC alarm PS0034): start it in a G00 or G01 block".into()));
                }
                st.comp_started = true;
                Comp::Start(side, r)
            }
            _ => Comp::Off,
        };
        if arc.is_none() && from == to && !matches!(comp, Comp::Cancel(..)) {
            return Ok(Step::Next);
        }
        let feed = match kind {
            MillKind::Rapid => None,
            _ => Some(self.mill_feed(st)?),
        };
        st.path.push(Programmed {
            site: Site {
                file: prog.name.clone(),
                line: prog.blocks[pc].0,
                snippet: prog.blocks[pc].1.clone(),
                stack: st.stack.clone(),
            },
            kind,
            plane: st.plane,
            start: from,
            end: to,
            arc,
            comp,
            feed,
            spindle_rpm: st.rpm,
            spindle: st.spindle,
            tool: st.tool,
            tool_word: st.tool_word.clone(),
        });
        Ok(Step::Next)
    }

    /// The feed of a G01/G02/G03 move in mm/min.
    fn mill_feed(&self, st: &MillState) -> Result<f64, Fail> {
        let f = st
            .feed
            .ok_or((1, format!("G{:02} needs F (no feed given yet)", st.motion)))?;
        if f <= 0.0 {
            return Err((
                1,
                format!(
                    "G{:02} with the feed F{f}: a feed move needs F > 0 (a control alarms: alarm 011, feed zero)",
                    st.motion
                ),
            ));
        }
        if !st.per_rev {
            return Ok(f);
        }
        let s = st.rpm.ok_or((
            1,
            "G95 (feed per revolution) needs S (the spindle speed)".to_string(),
        ))?;
        Ok(f * s)
    }
}

/// Whether a move between two (possibly unknown) points moves in the plane.
fn in_plane(plane: Plane, a: [Option<f64>; 3], b: [Option<f64>; 3]) -> bool {
    let [u, v, _] = plane.axes();
    a[u] != b[u] || a[v] != b[v]
}

/// The programmed circle of a G02 (`cw`) or G03 block from `a` to `b` (job frame): centre
/// from I/J/K (incremental from the start) or R (positive: at most 180 deg, negative: more),
/// sweep from the start to the end in the plane (a full circle with I/J/K when they meet).
fn arc_circle(
    plane: Plane,
    cw: bool,
    w: &Words,
    a: [f64; 3],
    b: [f64; 3],
    length: &dyn Fn(&str) -> Option<f64>,
) -> Result<MillArc, Fail> {
    let g = if cw { 2 } else { 3 };
    let (pa, pb) = (plane.uv(a), plane.uv(b));
    let chord = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
    let full = chord < 1e-6;
    // The centre words of the plane's (u, v) axes.
    let words = match plane {
        Plane::Xy => ["I", "J"],
        Plane::Zx => ["K", "I"],
        Plane::Yz => ["J", "K"],
    };
    let centre = if let Some(&(_, col)) = w.vals.get("R") {
        let r = length("R").unwrap_or(0.0);
        if full || r == 0.0 {
            return Err((col, format!("G{g:02} with R: expected a nonzero radius and an end point away from the start in the plane (a full circle needs {}/{})", words[0], words[1])));
        }
        if chord / 2.0 > r.abs() + ARC_TOLERANCE {
            return Err((col, format!("G{g:02}: the end point is {chord:.4} mm from the start, more than the diameter {:.4} of radius {}", 2.0 * r.abs(), r.abs())));
        }
        let c = radius_centre((pa[0], pa[1]), (pb[0], pb[1]), r, cw);
        [c.0, c.1]
    } else if words.iter().any(|k| w.vals.contains_key(*k)) {
        let off = words.map(|k| length(k).unwrap_or(0.0));
        let c = [pa[0] + off[0], pa[1] + off[1]];
        let ra = (pa[0] - c[0]).hypot(pa[1] - c[1]);
        let rb = (pb[0] - c[0]).hypot(pb[1] - c[1]);
        let col = words.iter().find_map(|k| w.vals.get(*k)).map_or(1, |v| v.1);
        if ra == 0.0 {
            return Err((
                col,
                format!("G{g:02}: the centre is the start point (radius 0)"),
            ));
        }
        if (ra - rb).abs() > ARC_TOLERANCE {
            return Err((col, format!("G{g:02}: the end point is off the circle by {:.4} mm: {rb:.4} mm from the centre, the start {ra:.4} mm (tolerance {ARC_TOLERANCE} mm)", (rb - ra).abs())));
        }
        c
    } else {
        return Err((
            1,
            format!(
                "G{g:02} needs R (the radius) or {}/{} (the centre) in this plane",
                words[0], words[1]
            ),
        ));
    };
    let angle = |p: glam::DVec2| (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let ccw_sweep = if full {
        TAU
    } else {
        let s = (angle(pb) - angle(pa)).rem_euclid(TAU);
        if s == 0.0 {
            TAU
        } else {
            s
        }
    };
    let sweep = if !cw {
        ccw_sweep
    } else if full {
        -TAU
    } else {
        ccw_sweep - TAU
    };
    Ok(MillArc {
        centre: plane.point(centre.into(), a[plane.axes()[2]]),
        radius: (pa[0] - centre[0]).hypot(pa[1] - centre[1]),
        sweep,
        plane,
    })
}
