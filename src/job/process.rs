//! Passes of a lathe job that come from the job itself: `[[pass]]` tables, and the pass
//! generators of `[process]` (radial, flank, ... and the planner of `kind = "plan"`).

use super::ctx::Ctx;
use super::schema::{RawJob, RawProcess};
use super::{JobError, SimConfig};
use crate::gen::plan::Plan;
use crate::gen::process::{self, Process};
use crate::model::pass::Pass;
use crate::model::setup::{Blank, Machine};
use crate::model::thread::ThreadSpec;
use crate::model::tool::Tool;

impl RawProcess {
    /// The first planner key given to another generator.
    fn plan_key(&self) -> Option<&'static str> {
        [
            ("max_depth", self.max_depth.is_some()),
            ("min_depth", self.min_depth.is_some()),
            ("infeed", self.infeed.is_some()),
            ("finish_passes", self.finish_passes.is_some()),
            ("spring_passes", self.spring_passes.is_some()),
            ("finish_allowance", self.finish_allowance.is_some()),
        ]
        .into_iter()
        .find(|k| k.1)
        .map(|k| k.0)
    }
}

/// `[process] kind = "plan"`: the planner's limits, and the plan.
#[allow(clippy::too_many_arguments)]
fn plan_process(
    pr: &RawProcess,
    thread: &ThreadSpec,
    tools: &[Tool],
    blank: &Blank,
    machine: &Machine,
    sim: &SimConfig,
    tool_index: &dyn Fn(u32, &str) -> Result<usize, JobError>,
    cx: &Ctx,
) -> Result<crate::gen::plan::Plan, JobError> {
    for (key, given) in [
        ("layers", pr.layers.is_some()),
        ("depths", pr.depths.is_some()),
        ("layer_depth", pr.layer_depth.is_some()),
        ("origin_z", pr.origin_z.is_some()),
        ("root_width", pr.root_width.is_some()),
        ("z_from", pr.z_from.is_some()),
        ("z_to", pr.z_to.is_some()),
    ] {
        if given {
            return Err(cx.err(
                &format!("process.{key}"),
                "the planner chooses its layers and runs itself: give max_depth, min_depth, schedule, infeed, finish_allowance, finish_passes, spring_passes",
            ));
        }
    }
    let max_depth = pr.max_depth.ok_or_else(|| {
        cx.err(
            "process.max_depth",
            "the planner needs max_depth (mm per pass)",
        )
    })?;
    let allowance = pr.finish_allowance.unwrap_or(0.0);
    let limits = crate::gen::plan::PlanLimits {
        max_depth,
        min_depth: pr.min_depth.unwrap_or(0.0),
        schedule: pr.schedule,
        infeed: pr.infeed.unwrap_or_default(),
        finish_passes: pr
            .finish_passes
            .unwrap_or(if allowance > 0.0 { 1 } else { 0 }),
        spring_passes: pr.spring_passes.unwrap_or(0),
        finish_allowance: allowance,
    };
    let tool = tool_index(pr.tool, "process.tool")?;
    crate::gen::plan::plan(&limits, tool, thread, tools, blank, machine, sim.tolerance)
        .map_err(|e| cx.err(&format!("process.{}", e.key), e.message))
}

fn check_pass(p: &Pass, key: &dyn Fn(&str) -> String, cx: &Ctx) -> Result<(), JobError> {
    if p.z_start == p.z_end {
        return Err(cx.err(&key("z_end"), "expected z_end different from z_start"));
    }
    if p.revolutions().is_none() {
        let law = p.helix().law;
        let at = law
            .zero_lead_revs()
            .map(|t| {
                format!(
                    " after {t:.3} revolutions ({:.3} mm of travel)",
                    law.travel(t)
                )
            })
            .unwrap_or_default();
        return Err(cx.err(
            &key("lead_change"),
            format!(
                "the lead would reach zero{at} before z_end = {}; a real control alarms here",
                p.z_end
            ),
        ));
    }
    Ok(())
}

/// The passes of a lathe job's `[[pass]]` tables and `[process]` generator, in that order,
/// and the plan of `kind = "plan"`.
pub(super) fn job_passes(
    raw: &RawJob,
    thread: &ThreadSpec,
    tools: &[Tool],
    blank: &Blank,
    machine: &Machine,
    sim: &SimConfig,
    cx: &Ctx,
) -> Result<(Vec<Pass>, Option<Plan>), JobError> {
    let tool_index = |id: u32, key: &str| -> Result<usize, JobError> {
        tools.iter().position(|t| t.id == id).ok_or_else(|| {
            let ids: Vec<String> = tools.iter().map(|t| t.id.to_string()).collect();
            cx.err(
                key,
                format!(
                    "no [[tool]] with id {id} (defined: {})",
                    if ids.is_empty() {
                        "none".into()
                    } else {
                        ids.join(", ")
                    }
                ),
            )
        })
    };
    let mut passes = Vec::new();
    for (i, p) in raw.pass.iter().enumerate() {
        let key = |k: &str| format!("pass[{i}].{k}");
        let pass = Pass {
            tool: tool_index(p.tool, &key("tool"))?,
            x_start: cx.positive(&key("x"), p.x)?,
            x_end: cx.positive(&key("x_end"), p.x_end.unwrap_or(p.x))?,
            z_start: cx.finite(&key("z_start"), p.z_start)?,
            z_end: cx.finite(&key("z_end"), p.z_end)?,
            lead: cx.positive(&key("lead"), p.lead)?,
            lead_change: cx.finite(&key("lead_change"), p.lead_change)?,
            start_angle: cx.finite(&key("start_angle"), p.start_angle)?.to_radians(),
            spindle: machine.spindle,
        };
        check_pass(&pass, &key, cx)?;
        passes.push(pass);
    }
    if raw.process.is_some() && thread.taper.is_some() {
        // The generators and the planner lay parallel passes; a taper thread's passes
        // follow its cone (G76/G92 with R, `[[pass]] x_end`).
        return Err(cx.err(
            "process",
            "the pass generators and the planner cut parallel threads: a taper thread (NPT, R, Rc) needs tapered passes, from a [program] (G76 or G92 with R, G33 with X) or [[pass]] with x_end",
        ));
    }
    let mut plan = None;
    if let Some(pr) = raw
        .process
        .as_ref()
        .filter(|p| p.kind == process::Kind::Plan)
    {
        let p = plan_process(pr, thread, tools, blank, machine, sim, &tool_index, cx)?;
        passes.extend(p.passes());
        plan = Some(p);
    } else if let Some(pr) = &raw.process {
        if let Some(key) = pr.plan_key() {
            return Err(cx.err(
                &format!("process.{key}"),
                "this key belongs to the planner (`kind = \"plan\"`)",
            ));
        }
        let process = Process {
            kind: pr.kind,
            tool: tool_index(pr.tool, "process.tool")?,
            layers: pr.layers,
            depths: pr.depths.clone(),
            schedule: pr.schedule,
            layer_depth: pr.layer_depth,
            method: pr.method,
            z_from: pr.z_from,
            z_to: pr.z_to,
            origin_z: pr.origin_z,
            root_width: pr.root_width,
        };
        let generated = process::generate(&process, thread, tools, blank, machine.spindle)
            .map_err(|e| cx.err(&format!("process.{}", e.key), e.message))?;
        for (i, p) in generated.iter().enumerate() {
            check_pass(
                p,
                &|k: &str| format!("process (generated pass {i}, {k})"),
                cx,
            )?;
        }
        passes.extend(generated);
    }
    Ok((passes, plan))
}
