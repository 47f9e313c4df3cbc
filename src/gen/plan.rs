//! The pass planner (`[process] kind = "plan"`): the fewest threading passes that respect
//! the job's limits and leave no ridge above the tolerance, in a form every post-processor
//! can write (`crate::gen::post`).
//!
//! **Layers.** Depths below the crest follow the schedule: `constant-depth` takes
//! `ceil(D_r / max_depth)` equal layers, `constant-area` FANUC G76's `d_n = d_1 sqrt(n)` with
//! `d_1 <= max_depth`, both with increments of at least `min_depth`. `D_r` is the depth less
//! the finish allowance, which `finish_passes` passes then split; `spring_passes` repeat the
//! full depth.
//!
//! **Positions.** Where the tool fills the groove's root (its tip and flanks span the root
//! between the walls) one position per layer is enough: radial infeed on the groove centre,
//! or flank infeed (the tip `h tan(phi)` off centre at height `h` above the root, so one
//! tool flank slides down one thread flank, as FANUC G76 does), or alternating flanks.
//! Where the groove is wider than the tool (wide square and trapezoidal grooves, equal
//! tooth width), every layer clears its band: positions spread from the tool touching the
//! left wall at its tip's height to touching the right wall, at most one tool width (at half
//! the tolerance above the tip) apart, which is the fewest passes that leave no ridge. For
//! equal tooth width the positions spread between the two flank helix families of
//! `domain.md` section 2 (start lead `F` to `F + K`, start point with it), so the spacing is
//! the groove width over `M` at every turn; `M` comes from the widest groove. A tool whose
//! flank is steeper than the thread's leaves a staircase on the flank: layers are then
//! capped so that its steps stay within the tolerance.
//!
//! **Runs.** Every pass starts at spindle angle 0 (no Q/SF word needed, so every dialect
//! writes it): at a revolution where its helix crosses angle 0, run-in `v^2/(2a)` (x 1.2,
//! at least 1 mm; one lead without an acceleration) in front of the face, and ends
//! `v^2/(2a)` past half a pitch beyond the last feature. The spindle turns so that the tool
//! always feeds away from the face. Positions are in the control's increments (0.001 mm;
//! leads 0.0001 mm/rev) and every pass is `round(run.z + shift + j (step + spread/M))`, the
//! expression the compact macro programs evaluate, so a program re-reads to these passes.
//!
//! **Check.** The plan is then cut on a line model along four generators (the tool's axial
//! profile placed at every crossing of every pass, in order, on a 0.004 mm grid): the
//! deepest chip of any pass and the leftover and gouge against the ideal profile. Coverage
//! beyond the tolerance is an error, not a hope.

use crate::gen::process::{GenError, Schedule};
use crate::model::helix::{Helix, Spindle};
use crate::model::pass::Pass;
use crate::model::setup::{Blank, Machine};
use crate::model::thread::{ThreadSpec, WidthRule};
use crate::model::tool::Tool;
use serde::Deserialize;
use std::f64::consts::TAU;

/// How the tool goes in from layer to layer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Infeed {
    /// Straight in on the groove centre.
    #[default]
    Radial,
    /// Along one flank (the one toward the run-in), cutting with the other edge.
    Flank,
    /// Along the two flanks in turn.
    Alternating,
}

/// The `[process]` limits of the planner.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlanLimits {
    /// Largest depth per layer (mm, radial).
    pub max_depth: f64,
    /// Smallest depth per layer (mm, radial).
    pub min_depth: f64,
    /// Depth schedule.
    pub schedule: Schedule,
    /// Infeed.
    pub infeed: Infeed,
    /// Passes that split the finish allowance.
    pub finish_passes: u32,
    /// Passes repeated at full depth.
    pub spring_passes: u32,
    /// Depth left for the finish passes (mm, radial).
    pub finish_allowance: f64,
}

/// What a layer is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Roughing.
    Rough,
    /// Finishing (the allowance).
    Finish,
    /// Spring pass (full depth again).
    Spring,
}

impl Role {
    /// Lower-case name for comments and reports.
    pub fn name(self) -> &'static str {
        match self {
            Role::Rough => "rough",
            Role::Finish => "finish",
            Role::Spring => "spring",
        }
    }
}

/// One depth layer: `count` passes at diameter `x`, pass `j` starting at
/// `run.z + shift + j (step + run.spread / max(count - 1, 1))` with lead
/// `run.lead + j lead_step`.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Roughing, finishing or spring.
    pub role: Role,
    /// Depth of the tip below the crest (mm).
    pub depth: f64,
    /// Diameter of the tip (mm, in 0.001).
    pub x: f64,
    /// Axial offset of the first pass from the run's start point (mm, in 1e-6).
    pub shift: f64,
    /// Axial step between passes (mm, in 1e-6).
    pub step: f64,
    /// Start lead step between passes (mm/rev, in 1e-6).
    pub lead_step: f64,
    /// Number of passes of each start.
    pub count: u32,
}

/// Where the passes of one start begin: the base helix at the revolution where it crosses
/// spindle angle 0 before the run-in.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// z of the base helix there (mm, in 1e-6).
    pub z: f64,
    /// Its lead there (mm/rev, in 1e-6).
    pub lead: f64,
    /// Extra axial spread across a layer from the start's lead law (mm, in 1e-6): equal
    /// tooth width, where the far flank family gains `K/starts` per revolution.
    pub spread: f64,
}

/// The line-model check of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// Largest height of stock left above the ideal profile (mm).
    pub max_leftover: f64,
    /// Largest cut below the ideal profile (mm).
    pub max_gouge: f64,
    /// Thickest chip of any pass measured along the radius (mm): the layer depth on a
    /// radial cut, more than the infeed where a pass cuts down a flank.
    pub max_chip: f64,
}

/// A plan: layers, runs and where the passes end.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// Tool index in the job.
    pub tool: usize,
    /// Layers in the order they are cut.
    pub layers: Vec<Layer>,
    /// One run per start.
    pub runs: Vec<Run>,
    /// Lead change per revolution along every pass (mm/rev^2, in 0.0001).
    pub lead_change: f64,
    /// Where every pass ends (mm, in 0.001).
    pub z_end: f64,
    /// Diameter the tool retracts to between passes (mm).
    pub clear_x: f64,
    /// Spindle direction: the tool feeds away from the face.
    pub spindle: Spindle,
    /// Spindle speed (rev/min).
    pub rpm: f64,
    /// Run-in in front of the face (mm) and run-out past the thread (mm).
    pub run_in: f64,
    /// Run-out past half a pitch beyond the last feature (mm).
    pub run_out: f64,
    /// Tolerance the plan was checked against (mm).
    pub tolerance: f64,
    /// The line-model check.
    pub check: Check,
    /// For equal tooth width: the passes seed 002's method would take over the same layers
    /// (`R11 + 1` per layer, `R11 = ceil((P_max - T - w)/w)`), for comparison.
    pub seed002_passes: Option<usize>,
}

/// `v` rounded to a multiple of `unit` (`unit` = 10^-k), the way a control reads a word.
pub(crate) fn quantize(v: f64, per_mm: f64) -> f64 {
    (v * per_mm).round() / per_mm
}

/// Per mm: positions in 0.001 mm, leads in 0.0001 mm/rev, table values in 1e-6.
pub(crate) const POS: f64 = 1e3;
pub(crate) const LEAD: f64 = 1e4;
pub(crate) const TABLE: f64 = 1e6;

impl Plan {
    /// The passes of layer `l`, start `s`: pass `j`.
    pub fn pass(&self, l: usize, s: usize, j: u32) -> Pass {
        let (layer, run) = (&self.layers[l], &self.runs[s]);
        let m = f64::from(layer.count.saturating_sub(1).max(1));
        let jf = f64::from(j);
        // The macro programs evaluate exactly this, in this order.
        let z = quantize(
            (run.z + layer.shift) + jf * (layer.step + run.spread / m),
            POS,
        );
        let lead = quantize(run.lead + jf * layer.lead_step, LEAD);
        Pass {
            tool: self.tool,
            x_start: layer.x,
            x_end: layer.x,
            z_start: z,
            z_end: self.z_end,
            lead,
            lead_change: self.lead_change,
            start_angle: 0.0,
            spindle: self.spindle,
        }
    }

    /// Every pass in the order it is cut: layer by layer, start by start, position by
    /// position.
    pub fn passes(&self) -> Vec<Pass> {
        let mut out = Vec::new();
        for (l, layer) in self.layers.iter().enumerate() {
            for s in 0..self.runs.len() {
                for j in 0..layer.count {
                    out.push(self.pass(l, s, j));
                }
            }
        }
        out
    }
}

fn fail<T>(key: &'static str, message: impl Into<String>) -> Result<T, GenError> {
    Err(GenError {
        key,
        message: message.into(),
    })
}

/// Most passes a plan may have.
const MAX_PASSES: usize = 20_000;

/// Plan the passes of `thread` with `tools[tool]` on `blank`, checked at `tolerance`.
pub(crate) fn plan(
    lim: &PlanLimits,
    tool_idx: usize,
    thread: &ThreadSpec,
    tools: &[Tool],
    blank: &Blank,
    machine: &Machine,
    tolerance: f64,
) -> Result<Plan, GenError> {
    let tool = &tools[tool_idx];
    check_limits(lim, thread)?;
    let depth = thread.depth();
    // The tool's walls: how far its tip centre stays from a wall at the tip's height.
    let (dl, dr, cap) = walls(tool, thread, tolerance)?;
    let base = thread.helix;
    let dir = base.dir;
    let n = f64::from(thread.starts);
    let law = base.law;
    // Width of the groove band the tip may move in at height h, at revolution t.
    let band = |h: f64, t: f64| -> f64 {
        match thread.width {
            WidthRule::Groove(w) => thread.groove_width_at(w, h) - dl - dr,
            WidthRule::Tooth(tw) => {
                let th = tw + (thread.pitch_height() - h) * thread.widening();
                law.travel(t + 1.0 / n) - law.travel(t) - th - dl - dr
            }
        }
    };
    let t_last = match thread.width {
        WidthRule::Groove(_) => 0.0,
        WidthRule::Tooth(_) => (thread.turns - 1.0 / n).max(0.0),
    };
    let band_max = |h: f64| band(h, 0.0).max(band(h, t_last));
    let band_min = |h: f64| band(h, 0.0).min(band(h, t_last));
    if band_min(0.0) < -1e-6 {
        return fail(
            "tool",
            format!(
                "the tool does not fit the groove at the root: it needs {:.4} mm more room",
                -band_min(0.0)
            ),
        );
    }
    let fills = band_max(0.0) <= 1e-6;
    if !fills && lim.infeed != Infeed::Radial {
        return fail(
            "infeed",
            "flank and alternating infeed need a tool that fills the groove's root; this groove is wider than the tool, so its layers are cut with axial passes (use `radial`)",
        );
    }
    // A staircase on a flank steeper than the tool's flank limits the layer depth.
    let max_layer = if fills {
        lim.max_depth
    } else {
        lim.max_depth.min(cap)
    };
    if max_layer < lim.min_depth {
        return fail(
            "min_depth",
            format!("the tool's flanks are steeper than the thread's: layers deeper than {max_layer:.4} mm leave steps beyond the tolerance on the flanks, less than min_depth"),
        );
    }
    let depths = schedule(lim, depth, max_layer)?;
    // The width a pass clears without a ridge: the tool's width at half the tolerance
    // above its tip, less the controls' rounding of two positions.
    let (vl, vr) = tool.span(0.5 * tolerance);
    let s_max = (vr - vl) - 2.0 / POS;
    let off = tool.reference_offset();
    let tan_l = thread.left_angle.tan();
    let tan_r = thread.right_angle.tan();
    // Flank infeed runs down the flank on the run-in's side.
    let up = -dir;
    let mut layers = Vec::with_capacity(depths.len());
    for (i, &(d, role)) in depths.iter().enumerate() {
        let h = (depth - d).max(0.0);
        let x = quantize(2.0 * thread.radius(h), POS);
        if band_min(h) < -1e-6 {
            return fail(
                "tool",
                format!("the tool does not fit the groove {d:.4} mm below the crest"),
            );
        }
        // Positions: one where the tool fills the root, else at most s_max apart.
        let span = band_max(h);
        let m = if fills || span <= 1e-6 {
            0
        } else {
            (span / s_max - 1e-9).ceil() as u32
        };
        let mf = f64::from(m.max(1));
        let (mut shift, step, lead_step) = match thread.width {
            WidthRule::Groove(w) => {
                let left = -0.5 * thread.groove_width_at(w, h) + dl;
                if m == 0 {
                    (left + 0.5 * band(h, 0.0), 0.0, 0.0)
                } else {
                    (left, span / mf, 0.0)
                }
            }
            WidthRule::Tooth(tw) => {
                let th = tw + (thread.pitch_height() - h) * thread.widening();
                // In travel from the tooth at t: the tip centres touching the near and far
                // walls (the far one moves with the next tooth, K/starts per revolution).
                let (d_near, d_far) = if dir < 0.0 { (dr, dl) } else { (dl, dr) };
                let o_near = 0.5 * th + d_near;
                let o_far = law.travel(1.0 / n) - 0.5 * th - d_far;
                if m == 0 {
                    (dir * 0.5 * (o_near + o_far), 0.0, 0.0)
                } else {
                    (dir * o_near, dir * (o_far - o_near) / mf, law.k / n / mf)
                }
            }
        };
        if fills {
            let sign = match lim.infeed {
                Infeed::Radial => 0.0,
                Infeed::Flank => 1.0,
                Infeed::Alternating if i % 2 == 0 => 1.0,
                Infeed::Alternating => -1.0,
            };
            // Up the flank on the run-in's side: the tip h tan(phi) off centre.
            let toward = sign * up;
            let tan = if toward > 0.0 { tan_r } else { tan_l };
            shift += toward * h * tan;
        }
        shift += off;
        let count = m + 1;
        layers.push(Layer {
            role,
            depth: d,
            x,
            shift: quantize(shift, TABLE),
            step: quantize(step, TABLE),
            lead_step: quantize(lead_step, TABLE),
            count,
        });
    }
    let total: usize =
        layers.iter().map(|l| l.count as usize).sum::<usize>() * thread.starts as usize;
    if total > MAX_PASSES {
        return fail(
            "max_depth",
            format!("the plan needs {total} passes, more than {MAX_PASSES}"),
        );
    }
    // The spindle turns so that the tool feeds away from the face (toward -z) along
    // the thread's helix.
    if dir > 0.0 {
        return fail(
            "kind",
            "the thread's pitch helix runs toward +z; the planner feeds from the face toward the chuck",
        );
    }
    let spindle = if base.spin == Spindle::Cw.sign() {
        Spindle::Cw
    } else {
        Spindle::Ccw
    };
    let rps = machine.spindle_rpm / 60.0;
    let stop = |lead: f64| -> f64 {
        match machine.acceleration {
            Some(a) => ((lead * rps).powi(2) / (2.0 * a) * 1.2).max(1.0),
            None => lead,
        }
    };
    // Run-in in front of the face: from the lead there (twice, since the lead where the
    // run starts depends on it).
    let floor = match law.zero_lead_revs() {
        Some(t0) if t0 < 0.0 => 0.75 * t0,
        _ => f64::NEG_INFINITY,
    };
    let t_in = |run_in: f64| {
        base.revs_at_z(blank.z_front - dir * run_in)
            .unwrap_or(floor)
            .max(floor)
    };
    let face_t = t_in(0.0);
    let mut run_in = stop(law.lead(face_t).abs());
    run_in = run_in.max(stop(law.lead(t_in(run_in)).abs()));
    let t_want = t_in(run_in);
    if !t_want.is_finite() {
        return fail(
            "kind",
            "no run-in in front of the face: the lead law vanishes there",
        );
    }
    let run_at = |h: &Helix, t_a: f64| Run {
        z: quantize(h.z(t_a), TABLE),
        lead: quantize(law.lead(t_a), TABLE),
        spread: match thread.width {
            WidthRule::Tooth(_) => quantize(dir * law.k / n * t_a, TABLE),
            WidthRule::Groove(_) => 0.0,
        },
    };
    let mut runs = Vec::new();
    for s in 0..thread.starts {
        let h: Helix = thread.start_helix(s);
        let phase = h.phase_at(0.0);
        let mut t_a = phase + (t_want - phase).floor();
        // Every pass of this start (they sit up to a groove width off the base helix)
        // starts the run-in in front of the face.
        loop {
            if law.lead(t_a) <= 0.0 || t_a < floor {
                return fail(
                    "kind",
                    "no room for the run-in: the lead law vanishes in front of the face",
                );
            }
            let run = run_at(&h, t_a);
            let short = layers.iter().any(|l| {
                let m = f64::from(l.count.saturating_sub(1).max(1));
                (0..l.count).any(|j| {
                    let z = (run.z + l.shift) + f64::from(j) * (l.step + run.spread / m);
                    -dir * (z - blank.z_front) < run_in - 1e-9
                })
            });
            if !short {
                runs.push(run);
                break;
            }
            t_a -= 1.0;
        }
    }
    let t_out = thread.turns + 0.5 / n;
    let lead_out = law.lead(t_out);
    if lead_out <= 0.0 {
        return fail("kind", "the lead law vanishes before the thread's end");
    }
    let run_out = stop(lead_out);
    let z_end = quantize(base.z(t_out) + dir * run_out, POS);
    let clear_x = match thread.side {
        crate::model::thread::Side::External => {
            quantize(blank.diameter.max(2.0 * thread.crest_radius) + 2.0, POS)
        }
        crate::model::thread::Side::Internal => {
            quantize((2.0 * thread.crest_radius - 1.0).max(0.0), POS)
        }
    };
    let mut plan = Plan {
        tool: tool_idx,
        layers,
        runs,
        lead_change: quantize(law.k, LEAD),
        z_end,
        clear_x,
        spindle,
        rpm: machine.spindle_rpm,
        run_in,
        run_out,
        tolerance,
        check: Check {
            max_leftover: 0.0,
            max_gouge: 0.0,
            max_chip: 0.0,
        },
        seed002_passes: None,
    };
    if let (WidthRule::Tooth(tw), b) = (thread.width, tool.tip_width()) {
        let p_max = (1..=thread.whole_turns())
            .map(|k| thread.pitch_of_turn(k))
            .fold(0.0, f64::max);
        if b > 0.0 && p_max > tw + b {
            let r11 = ((p_max - tw - b) / b - 0.001).ceil() as usize;
            plan.seed002_passes = Some((r11 + 1) * plan.layers.len() * thread.starts as usize);
        }
    }
    plan.check = line_check(&plan.passes(), thread, tool);
    if plan.check.max_leftover > tolerance || plan.check.max_gouge > tolerance {
        return fail(
            "tool",
            format!(
                "the plan does not cut the thread within the tolerance {tolerance} mm: it leaves {:.4} mm and gouges {:.4} mm (line model); check the tool's form against the thread's",
                plan.check.max_leftover, plan.check.max_gouge
            ),
        );
    }
    Ok(plan)
}

fn check_limits(lim: &PlanLimits, thread: &ThreadSpec) -> Result<(), GenError> {
    if !(lim.max_depth.is_finite() && lim.max_depth > 0.0) {
        return fail("max_depth", "expected a positive depth per pass (mm)");
    }
    if !(lim.min_depth.is_finite() && lim.min_depth >= 0.0 && lim.min_depth <= lim.max_depth) {
        return fail("min_depth", "expected a depth from 0 to max_depth (mm)");
    }
    if !(lim.finish_allowance.is_finite()
        && lim.finish_allowance >= 0.0
        && lim.finish_allowance < thread.depth())
    {
        return fail(
            "finish_allowance",
            format!(
                "expected 0 to less than the thread depth {:.4} mm",
                thread.depth()
            ),
        );
    }
    if lim.finish_allowance > 0.0 && lim.finish_passes == 0 {
        return fail(
            "finish_passes",
            "a finish allowance needs at least one finish pass",
        );
    }
    if lim.finish_passes > 100 {
        return fail("finish_passes", "expected at most 100 finish passes");
    }
    if lim.spring_passes > 100 {
        return fail("spring_passes", "expected at most 100 spring passes");
    }
    Ok(())
}

/// Depths below the crest of every layer, in cutting order, with their role.
fn schedule(lim: &PlanLimits, depth: f64, max_layer: f64) -> Result<Vec<(f64, Role)>, GenError> {
    let rough = depth - lim.finish_allowance;
    let mut out: Vec<f64> = Vec::new();
    match lim.schedule {
        Schedule::ConstantDepth => {
            let n = (rough / max_layer - 1e-9).ceil().max(1.0);
            if n > 10_000.0 {
                return fail("max_depth", "more than 10000 layers");
            }
            let n = n as u32;
            out.extend((1..=n).map(|i| rough * f64::from(i) / f64::from(n)));
        }
        Schedule::ConstantArea => {
            // Fewest layers with d_1 sqrt(n) reaching the depth and d_1 <= max: then the
            // increments d_1 (sqrt(n) - sqrt(n - 1)) all stay below d_1.
            let n = ((rough / max_layer).powi(2) - 1e-9).ceil().max(1.0);
            if n > 10_000.0 {
                return fail("max_depth", "more than 10000 layers");
            }
            let d1 = rough / n.sqrt();
            let mut prev = 0.0;
            let mut i = 1.0;
            while prev < rough - 1e-9 {
                let d = (d1 * f64::sqrt(i)).max(prev + lim.min_depth).min(rough);
                // A last increment below the minimum joins the one before.
                if rough - d < lim.min_depth && d < rough {
                    out.push(rough);
                    break;
                }
                out.push(d);
                prev = d;
                i += 1.0;
            }
        }
    }
    let mut layers: Vec<(f64, Role)> = out.into_iter().map(|d| (d, Role::Rough)).collect();
    for k in 1..=lim.finish_passes {
        let d = rough + lim.finish_allowance * f64::from(k) / f64::from(lim.finish_passes);
        layers.push((d, Role::Finish));
    }
    for _ in 0..lim.spring_passes {
        layers.push((depth, Role::Spring));
    }
    Ok(layers)
}

/// How far the tool's tip centre must stay from the left and right walls, at the tip's
/// height, for the tool to touch the wall without crossing it anywhere up to the crest;
/// and the layer depth at which a steeper tool flank leaves steps of the tolerance.
fn walls(tool: &Tool, thread: &ThreadSpec, tolerance: f64) -> Result<(f64, f64, f64), GenError> {
    let depth = thread.depth();
    let (tl, tr) = (thread.left_angle.tan(), thread.right_angle.tan());
    let (mut dl, mut dr) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut cap = f64::INFINITY;
    const N: usize = 256;
    for i in 0..=N {
        let u = depth * i as f64 / N as f64;
        let (vmin, vmax) = tool.span(u);
        // The tip at the wall's foot; the wall recedes by u tan(phi) at height u.
        dl = dl.max(-vmin - u * tl);
        dr = dr.max(vmax - u * tr);
    }
    // With the tip at a wall's foot, the gap between the tool's flank and the wall at
    // height u: a layer of depth u leaves a step of that gap (normal: x cos(phi)).
    for i in 1..=N {
        let u = depth * i as f64 / N as f64;
        let (vmin, vmax) = tool.span(u);
        let gap_l = (dl + vmin + u * tl).max(0.0) * thread.left_angle.cos();
        let gap_r = (dr - vmax + u * tr).max(0.0) * thread.right_angle.cos();
        for gap in [gap_l, gap_r] {
            if gap > 0.8 * tolerance {
                cap = cap.min(u * 0.8 * tolerance / gap);
            }
        }
    }
    if !(dl.is_finite() && dr.is_finite()) {
        return fail("tool", "the tool's profile has no width");
    }
    Ok((dl, dr, cap))
}

/// Cut `passes` on a line model of four generators: the tool's axial profile at every
/// crossing of every pass, in order, from the crest down; the deepest chip of any pass,
/// and the leftover and gouge against the ideal profile over the compared span (every groove of the thread, to mid-tooth beyond the end ones).
pub fn line_check(passes: &[Pass], thread: &ThreadSpec, tool: &Tool) -> Check {
    const DZ: f64 = 0.004;
    // The thread's own grooves: the passes cut the thread, the part's chamfers are turned.
    let thread = &ThreadSpec {
        outline: None,
        taper: None,
        ..thread.clone()
    };
    let depth = thread.depth();
    let (vl, vr) = tool.span(depth);
    let off = tool.reference_offset();
    let mut check = Check {
        max_leftover: 0.0,
        max_gouge: 0.0,
        max_chip: 0.0,
    };
    let theta0 = thread.helix.theta0;
    let (za, zb) = (thread.helix.z0, thread.helix.z(thread.turns));
    let (lo, hi) = (za.min(zb) - 1.0, za.max(zb) + 1.0);
    for g in 0..4 {
        let theta = theta0 + TAU * f64::from(g) / 4.0;
        let ideal = thread.column(theta, lo, hi);
        let Some((s_lo, s_hi)) = ideal.span else {
            continue;
        };
        let n = ((s_hi - s_lo) / DZ).ceil() as usize + 1;
        let zs: Vec<f64> = (0..n).map(|i| s_lo + i as f64 * DZ).collect();
        let mut cut = vec![depth; n];
        for p in passes {
            let h_tip = thread.height(p.x_start / 2.0);
            let hx = p.helix();
            let Some(revs) = p.revolutions() else {
                continue;
            };
            let mut chip: f64 = 0.0;
            for t in hx.crossings(theta, 0.0, revs) {
                let c = hx.z(t) - off;
                let a = (((c + vl - s_lo) / DZ).floor().max(0.0)) as usize;
                let b = ((((c + vr - s_lo) / DZ).ceil()).max(0.0) as usize).min(n);
                for i in a..b {
                    let new = h_tip + tool.height(zs[i] - c);
                    if new < cut[i] {
                        chip = chip.max(cut[i] - new);
                        cut[i] = new;
                    }
                }
            }
            check.max_chip = check.max_chip.max(chip);
        }
        for (i, &z) in zs.iter().enumerate() {
            let want = ideal.height_at(z);
            check.max_leftover = check.max_leftover.max(cut[i] - want);
            check.max_gouge = check.max_gouge.max(want - cut[i]);
        }
    }
    check
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(schedule: Schedule, max: f64, min: f64) -> PlanLimits {
        PlanLimits {
            max_depth: max,
            min_depth: min,
            schedule,
            infeed: Infeed::Radial,
            finish_passes: 0,
            spring_passes: 0,
            finish_allowance: 0.0,
        }
    }

    /// Constant depth: ceil(D / max) equal layers ending at the depth.
    #[test]
    fn constant_depth_is_the_fewest_equal_layers() {
        let d = schedule(&limits(Schedule::ConstantDepth, 0.4, 0.0), 3.0, 0.4).unwrap();
        assert_eq!(d.len(), 8); // 3 / 0.4 = 7.5
        for (i, (x, role)) in d.iter().enumerate() {
            assert!((x - 3.0 * (i + 1) as f64 / 8.0).abs() < 1e-12);
            assert_eq!(*role, Role::Rough);
        }
    }

    /// Constant area: d_n = d_1 sqrt(n) with d_1 = D / sqrt(N), N = ceil((D/max)^2), so the
    /// first (largest) increment is at most max; with min_depth the increments stay at least
    /// that (FANUC G76's rule), the last one joining its neighbour when it would be smaller.
    #[test]
    fn constant_area_follows_g76() {
        let (depth, max) = (1.227, 0.35);
        let d = schedule(&limits(Schedule::ConstantArea, max, 0.0), depth, max).unwrap();
        let n = ((depth / max) * (depth / max)).ceil() as usize; // 12.29 -> 13
        assert_eq!(d.len(), n);
        let d1 = depth / (n as f64).sqrt();
        for (i, (x, _)) in d.iter().enumerate() {
            assert!((x - d1 * ((i + 1) as f64).sqrt()).abs() < 1e-12);
        }
        let d = schedule(&limits(Schedule::ConstantArea, max, 0.08), depth, max).unwrap();
        let mut prev = 0.0;
        for (x, _) in &d {
            assert!(x - prev >= 0.08 - 1e-12 && x - prev <= max + 1e-12, "{d:?}");
            prev = *x;
        }
        assert_eq!(prev, depth);
        assert!(d.len() < n);
    }

    /// The finish allowance is split by the finish passes; spring passes repeat the depth.
    #[test]
    fn finish_and_spring_passes() {
        let lim = PlanLimits {
            finish_passes: 2,
            spring_passes: 1,
            finish_allowance: 0.1,
            ..limits(Schedule::ConstantDepth, 0.5, 0.0)
        };
        let d = schedule(&lim, 1.1, 0.5).unwrap();
        let roles: Vec<Role> = d.iter().map(|x| x.1).collect();
        assert_eq!(
            roles,
            [
                Role::Rough,
                Role::Rough,
                Role::Finish,
                Role::Finish,
                Role::Spring
            ]
        );
        let depths: Vec<f64> = d.iter().map(|x| x.0).collect();
        for (a, b) in depths.iter().zip([0.5, 1.0, 1.05, 1.1, 1.1]) {
            assert!((a - b).abs() < 1e-12, "{depths:?}");
        }
    }
}
