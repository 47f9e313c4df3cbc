//! Pass generators: the common ways to cut a thread, so a job need not list every pass.
//!
//! - `radial`: depth layers, the tool's tip centre on the groove centre (the pitch helix)
//!   of every start. For equal groove width and constant pitch, with any form tool.
//! - `equal-tooth-axial`: for equal tooth width, where the groove grows by the pitch
//!   increment per turn. Per depth layer the passes spread from the near flank family
//!   (start lead `F`) to the far one (start lead `F + K`): pass `j` of `M` follows the
//!   helix with start lead `F + (j/M) K`, so the gap between neighbouring passes is
//!   `(G(t) - w)/M` everywhere and `M = ceil((G_max - w)/w)` (seed 002's count) covers the
//!   groove. `method = "seed002"` instead transcribes seed 002's `MYBBB.SPF` arithmetic
//!   literally (start point and start lead both shifted by `(P1 - T - w)/M` per pass) so
//!   the report shows what that program really cuts.
//! - `flank-borrow`: seed 004's Tr method: depth layers of `layer_depth`, each cut in the
//!   middle and then borrowed right and left by half of (groove width at the tip's depth
//!   less the tool's tip width).
//!
//! Generators are pure: thread, tools and blank in, passes out.

use crate::model::helix::{Helix, LeadLaw, Spindle};
use crate::model::pass::Pass;
use crate::model::setup::Blank;
use crate::model::thread::{ThreadSpec, WidthRule};
use crate::model::tool::Tool;
use serde::Deserialize;

/// Which generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Kind {
    /// Radial depth layers on the groove centre.
    Radial,
    /// Axial passes between the flank families of an equal-tooth-width thread.
    EqualToothAxial,
    /// Middle, right and left cuts per layer along the flank angle (seed 004).
    FlankBorrow,
    /// The planner (`crate::gen::plan`): the fewest passes within the limits, checked.
    Plan,
}

/// Depth schedule of radial layers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Schedule {
    /// Equal depth per layer.
    #[default]
    ConstantDepth,
    /// Equal chip area per layer for a V tool: depth grows with sqrt(layer).
    ConstantArea,
}

/// How the equal-tooth passes are placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum AxialMethod {
    /// Start lead interpolated between the two flank families (covers the groove).
    #[default]
    Interpolated,
    /// Seed 002's program arithmetic, transcribed literally.
    Seed002,
}

/// A `[process]` section, resolved.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Process {
    /// Generator.
    pub kind: Kind,
    /// Tool index.
    pub tool: usize,
    /// Number of depth layers.
    pub layers: Option<u32>,
    /// Explicit depths below the crest, one per layer.
    pub depths: Option<Vec<f64>>,
    /// Depth schedule for `layers`.
    pub schedule: Schedule,
    /// Depth per layer for `flank-borrow` (mm).
    pub layer_depth: Option<f64>,
    /// Placement method for `equal-tooth-axial`.
    pub method: AxialMethod,
    /// Where the tool's tip centre starts (mm).
    pub z_from: Option<f64>,
    /// Where it stops (mm).
    pub z_to: Option<f64>,
    /// Seed 002's `R0` (thread origin) for the literal method.
    pub origin_z: Option<f64>,
    /// `flank-borrow`: the groove's root width the offsets are computed from (seed 004
    /// writes 4.12 for Tr100x12); default the ideal one.
    pub root_width: Option<f64>,
}

/// A generator error, attributed to a `[process]` key.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GenError {
    /// Key under `[process]`.
    pub key: &'static str,
    /// What is wrong.
    pub message: String,
}

fn fail<T>(key: &'static str, message: impl Into<String>) -> Result<T, GenError> {
    Err(GenError {
        key,
        message: message.into(),
    })
}

/// Most passes a generator may produce.
const MAX_PASSES: usize = 20_000;

/// Generate the passes of a process.
pub(crate) fn generate(
    p: &Process,
    thread: &ThreadSpec,
    tools: &[Tool],
    blank: &Blank,
    spindle: Spindle,
) -> Result<Vec<Pass>, GenError> {
    let tool = &tools[p.tool];
    let passes = match p.kind {
        Kind::Radial => radial(p, thread, tool, blank, spindle),
        Kind::EqualToothAxial => match p.method {
            AxialMethod::Interpolated => equal_tooth(p, thread, tool, blank, spindle),
            AxialMethod::Seed002 => seed002(p, thread, tool, spindle),
        },
        Kind::FlankBorrow => flank_borrow(p, thread, tool, blank, spindle),
        Kind::Plan => return fail("kind", "the planner runs from the job (`crate::gen::plan`)"),
    }?;
    if passes.len() > MAX_PASSES {
        return fail("kind", format!("the process generates {} passes, more than {MAX_PASSES}: use fewer or deeper layers", passes.len()));
    }
    Ok(passes)
}

/// Tip heights above the root, one per layer, from the first (shallowest) to the root.
fn layer_heights(p: &Process, depth: f64) -> Result<Vec<f64>, GenError> {
    if let Some(d) = &p.depths {
        if d.is_empty() {
            return fail("depths", "expected at least one depth");
        }
        let mut prev = 0.0;
        for &x in d {
            if !x.is_finite() || x <= prev || x > depth + 1e-9 {
                return fail(
                    "depths",
                    format!("expected increasing depths in (0, {depth}] mm below the crest"),
                );
            }
            prev = x;
        }
        return Ok(d.iter().map(|x| (depth - x).max(0.0)).collect());
    }
    let n = p.layers.unwrap_or(1);
    if n == 0 || n > 10_000 {
        return fail("layers", "expected 1 to 10000 layers");
    }
    Ok((1..=n)
        .map(|i| {
            let u = i as f64 / n as f64;
            let d = match p.schedule {
                Schedule::ConstantDepth => depth * u,
                Schedule::ConstantArea => depth * u.sqrt(),
            };
            if i == n {
                0.0
            } else {
                depth - d
            }
        })
        .collect())
}

/// The revolutions of `h` where a run from `z_from` to `z_to` starts and ends. Defaults:
/// one lead of run-in in front of the blank's face (less where a falling lead would get
/// too small), and half a pitch past the thread's last feature.
fn t_range(
    p: &Process,
    thread: &ThreadSpec,
    h: &Helix,
    blank: &Blank,
) -> Result<(f64, f64), GenError> {
    let law = h.law;
    let t_a = match p.z_from {
        Some(z) => h.revs_at_z(z).ok_or(GenError {
            key: "z_from",
            message: format!("the helix never reaches z = {z} with a positive lead"),
        })?,
        None => {
            let want = blank.z_front + law.f.abs();
            let t = h.revs_at_z(want).unwrap_or(f64::NEG_INFINITY);
            let floor = match law.zero_lead_revs() {
                Some(t0) if t0 < 0.0 => 0.75 * t0,
                _ => f64::NEG_INFINITY,
            };
            t.max(floor)
        }
    };
    let t_b = match p.z_to {
        Some(z) => h.revs_at_z(z).ok_or(GenError {
            key: "z_to",
            message: format!("the helix never reaches z = {z} with a positive lead"),
        })?,
        None => thread.turns + 0.5 / thread.starts as f64,
    };
    if t_b <= t_a {
        return fail("z_to", "the run ends before it starts");
    }
    if law.lead(t_b) <= 0.0 {
        return fail("z_to", "the lead reaches zero before the end of the run");
    }
    Ok((t_a, t_b))
}

/// A pass whose tool tip centre follows `h` from revolution `t_a` to `t_b`, tip at radius
/// `r_tip`, run in whichever direction the spindle gives the thread's hand.
fn follow(
    h: &Helix,
    t_a: f64,
    t_b: f64,
    r_tip: f64,
    tool_idx: usize,
    tool: &Tool,
    spindle: Spindle,
) -> Pass {
    let off = tool.reference_offset();
    let x = 2.0 * r_tip;
    if spindle.sign() == h.spin {
        Pass {
            tool: tool_idx,
            x_start: x,
            x_end: x,
            z_start: h.z(t_a) + off,
            z_end: h.z(t_b) + off,
            lead: h.law.lead(t_a),
            lead_change: h.law.k,
            start_angle: h.theta0 - h.spin * std::f64::consts::TAU * t_a,
            spindle,
        }
    } else {
        Pass {
            tool: tool_idx,
            x_start: x,
            x_end: x,
            z_start: h.z(t_b) + off,
            z_end: h.z(t_a) + off,
            lead: h.law.lead(t_b),
            lead_change: -h.law.k,
            start_angle: h.theta0 - h.spin * std::f64::consts::TAU * t_b,
            spindle,
        }
    }
}

/// A pass whose tip centre follows `hx` over the process's run (`z_from`..`z_to`), tip at
/// radius `r_tip`.
fn along(
    p: &Process,
    thread: &ThreadSpec,
    hx: &Helix,
    blank: &Blank,
    r_tip: f64,
    tool: &Tool,
    spindle: Spindle,
) -> Result<Pass, GenError> {
    let (t_a, t_b) = t_range(p, thread, hx, blank)?;
    Ok(follow(hx, t_a, t_b, r_tip, p.tool, tool, spindle))
}

fn radial(
    p: &Process,
    thread: &ThreadSpec,
    tool: &Tool,
    blank: &Blank,
    spindle: Spindle,
) -> Result<Vec<Pass>, GenError> {
    let WidthRule::Groove(w) = thread.width else {
        return fail("kind", "`radial` cuts grooves centred on the pitch helix; an equal tooth width thread needs `equal-tooth-axial`");
    };
    let root = thread.groove_width_at(w, 0.0);
    if tool.tip_width() > root + thread.fit_tolerance() {
        return fail(
            "tool",
            format!("the tool's tip ({} mm) is wider than the groove at the root ({root:.4} mm): it would gouge both flanks", tool.tip_width()),
        );
    }
    let heights = layer_heights(p, thread.depth())?;
    let mut out = Vec::new();
    for &h_tip in &heights {
        for s in 0..thread.starts {
            let hx = thread.start_helix(s);
            out.push(along(
                p,
                thread,
                &hx,
                blank,
                thread.radius(h_tip),
                tool,
                spindle,
            )?);
        }
    }
    Ok(out)
}

fn equal_tooth(
    p: &Process,
    thread: &ThreadSpec,
    tool: &Tool,
    blank: &Blank,
    spindle: Spindle,
) -> Result<Vec<Pass>, GenError> {
    let WidthRule::Tooth(tw) = thread.width else {
        return fail(
            "kind",
            "`equal-tooth-axial` is for `width = { tooth = .. }` threads",
        );
    };
    let b = tool.tip_width();
    if b <= 0.0 {
        return fail(
            "tool",
            "expected a tool with a flat tip (grooving or trapezoidal)",
        );
    }
    let heights = layer_heights(p, thread.depth())?;
    let n = thread.starts as f64;
    let law = thread.helix.law;
    // Groove widths at the pitch line over the thread: P(t) - T, extreme at the ends.
    let gap = |t: f64| (law.travel(t + 1.0 / n) - law.travel(t)) - tw;
    let mut out = Vec::new();
    for &h_tip in &heights {
        let t_h = tw + (thread.pitch_height() - h_tip) * thread.widening();
        let g = |t: f64| gap(t) + tw - t_h;
        let (g_a, g_b) = (g(0.0), g(thread.turns - 1.0 / n));
        let (g_min, g_max) = (g_a.min(g_b), g_a.max(g_b));
        if b > g_min + thread.fit_tolerance() {
            return fail("tool", format!("the tool's tip ({b} mm) is wider than the narrowest groove at its depth ({g_min:.4} mm)"));
        }
        let m = ((g_max - b) / b - 1e-9).ceil().max(1.0);
        if m * (thread.starts as f64) * (heights.len() as f64) > MAX_PASSES as f64 {
            return fail(
                "tool",
                format!("a {b} mm tool needs {m} axial passes per layer for a {g_max:.3} mm groove: more than {MAX_PASSES} passes in all"),
            );
        }
        let m = m as u32;
        for s in 0..thread.starts {
            let base = thread.start_helix(s);
            for j in 0..=m {
                let lam = j as f64 / m as f64;
                let near = base.z0 - t_h / 2.0 - b / 2.0;
                let far = base.z0 + t_h / 2.0 - law.travel(1.0 / n) + b / 2.0;
                let hx = Helix {
                    z0: (1.0 - lam) * near + lam * far,
                    law: LeadLaw {
                        f: law.f + lam * law.k / n,
                        k: law.k,
                    },
                    ..base
                };
                out.push(along(
                    p,
                    thread,
                    &hx,
                    blank,
                    thread.radius(h_tip),
                    tool,
                    spindle,
                )?);
            }
        }
    }
    Ok(out)
}

/// Seed 002, `MYBBB.SPF`, transcribed: `R0` origin, `R1`/`R2` major/minor, `R3` layers,
/// `R4` first pitch, `R5` increment, `R6` last pitch, `R7` tooth, `R8` tool width.
fn seed002(
    p: &Process,
    thread: &ThreadSpec,
    tool: &Tool,
    spindle: Spindle,
) -> Result<Vec<Pass>, GenError> {
    let WidthRule::Tooth(r7) = thread.width else {
        return fail(
            "method",
            "`seed002` is seed 002's equal tooth width program",
        );
    };
    if thread.starts != 1 {
        return fail("method", "`seed002` cuts single-start threads only");
    }
    let r0 = p.origin_z.unwrap_or(0.0);
    let (r1, r2) = match thread.side {
        crate::model::thread::Side::External => {
            (2.0 * thread.crest_radius, 2.0 * thread.root_radius)
        }
        crate::model::thread::Side::Internal => {
            return fail("method", "`seed002` is an external program")
        }
    };
    let r3 = p.layers.unwrap_or(1) as f64;
    let r5 = thread.helix.law.k;
    let r4 = thread.helix.law.f + r5 / 2.0;
    let r6 = r4 + (thread.turns - 1.0) * r5;
    let r8 = tool.tip_width();
    let r10 = r6 - r7 - r8;
    let r20: f64 = if r4 < r6 { 1.0 } else { -1.0 };
    let r21 = (r6 - r4).abs() / r5.abs() + 1.0;
    let r22 = r21 * r4 + r20 * r21 * (r21 - 1.0) * r5.abs() / 2.0;
    let r11 = if (r10 / r8 - (r10 / r8).trunc()).abs() < 0.001 {
        (r10 / r8).trunc()
    } else {
        (r10 / r8).trunc() + 1.0
    };
    if r11 < 1.0 {
        return fail(
            "method",
            "seed 002's R11 (number of axial passes) is below 1 for this thread and tool",
        );
    }
    if (r11 + 1.0) * r3 > MAX_PASSES as f64 {
        return fail(
            "tool",
            format!(
                "seed 002's program would run {} passes, more than {MAX_PASSES}",
                (r11 + 1.0) * r3
            ),
        );
    }
    let r12 = (r4 - r7 - r8) / r11;
    let r15 = r4 - r5.abs() * r20;
    let mut out = Vec::new();
    let mut r13 = 1.0;
    while r13 <= r3 {
        let r14 = r1 - (r1 - r2) / r3 * r13;
        let mut r19 = 0.0;
        let mut r18 = r11;
        loop {
            let lead = r15 - r5.abs() * r20 - r19;
            out.push(Pass {
                tool: p.tool,
                x_start: r14,
                x_end: r14,
                z_start: r0 + r15 - r19,
                z_end: r0 - r22,
                lead,
                lead_change: r20 * r5.abs(),
                start_angle: 0.0,
                spindle,
            });
            if r18 <= 0.0 {
                break;
            }
            r18 -= 1.0;
            r19 += r12;
        }
        r13 += 1.0;
    }
    Ok(out)
}

fn flank_borrow(
    p: &Process,
    thread: &ThreadSpec,
    tool: &Tool,
    blank: &Blank,
    spindle: Spindle,
) -> Result<Vec<Pass>, GenError> {
    let WidthRule::Groove(w) = thread.width else {
        return fail(
            "kind",
            "`flank-borrow` is for grooves of equal width (constant pitch)",
        );
    };
    let step = p.layer_depth.unwrap_or(0.1);
    if !(step.is_finite() && step > 0.0) {
        return fail("layer_depth", "expected a positive depth per layer (mm)");
    }
    let depth = thread.depth();
    if depth / step > 5_000.0 {
        return fail("layer_depth", "more than 5000 layers");
    }
    let b = tool.tip_width();
    if p.depths.is_some() {
        return fail("depths", "`flank-borrow` uses `layer_depth`");
    }
    let root = match p.root_width {
        Some(r) if r.is_finite() && r > 0.0 => r,
        Some(_) => return fail("root_width", "expected a positive width (mm)"),
        None => thread.groove_width_at(w, 0.0),
    };
    let mut out = Vec::new();
    let mut k = 1u32;
    loop {
        let h = (depth - k as f64 * step).max(0.0);
        // Groove width at the tip's height, less the tool's tip: seed 004's `#5`.
        let width = root + h * thread.widening();
        let off = ((width - b) / 2.0).max(0.0);
        for s in 0..thread.starts {
            let base = thread.start_helix(s);
            for shift in [0.0, off, -off] {
                if shift != 0.0 && off == 0.0 {
                    continue;
                }
                let hx = Helix {
                    z0: base.z0 + shift,
                    ..base
                };
                out.push(along(
                    p,
                    thread,
                    &hx,
                    blank,
                    thread.radius(h),
                    tool,
                    spindle,
                )?);
            }
        }
        if h <= 0.0 {
            break;
        }
        k += 1;
    }
    Ok(out)
}
