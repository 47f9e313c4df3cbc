//! Step 1 of loading a job: the deserialized schema checked key by key into a [`Job`] in
//! mm and radians, whose `[program]` has not run yet, and the program to run (step 2, the
//! program stage, [`crate::toolpath`]).

use super::ctx::Ctx;
use super::forms::resolve_thread;
use super::mill::{self, MillParts};
use super::schema::ToolKind;
use super::schema::{RawJob, SideName, SpindleName};
use super::tools::{check_tool_keys, resolve_holder, resolve_tap, resolve_tool, resolve_turning};
use super::{process, program, Job, JobError, SimConfig, DEFAULT_MAX_DEXELS};
use crate::model::helix::Spindle;
use crate::model::part::{PartError, PartProfile};
use crate::model::setup::{Blank, Machine};
use crate::toolpath::Program;

/// A parsed job and the program still to run for its passes or path.
pub(super) struct Parsed {
    /// The job without its program's passes (a milling job without its path).
    pub(super) job: Job,
    /// The program, when the job has one.
    pub(super) program: Option<Pending>,
}

/// A program to run in the program stage.
pub(super) enum Pending {
    /// A lathe program: its thread moves become passes.
    Lathe(Program),
    /// A milling program: its moves become the path of these cutters.
    Mill(MillParts),
}

/// The checked job of `raw`, and its program to run.
pub(super) fn resolve(
    raw: RawJob,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
    strict: bool,
) -> Result<Parsed, JobError> {
    let b = &raw.blank;
    let blank = Blank {
        diameter: cx.positive("blank.diameter", b.diameter)?,
        bore: cx.non_negative("blank.bore", b.bore)?,
        length: cx.positive("blank.length", b.length)?,
        z_front: cx.finite("blank.z_front", b.z_front)?,
    };
    if blank.bore >= blank.diameter {
        return Err(cx.err("blank.bore", "expected a bore smaller than the diameter"));
    }
    let machine = Machine {
        spindle_rpm: cx.positive("machine.spindle_rpm", raw.machine.spindle_rpm)?,
        max_feed: raw
            .machine
            .max_feed
            .map(|v| cx.positive("machine.max_feed", v))
            .transpose()?,
        acceleration: raw
            .machine
            .acceleration
            .map(|v| cx.positive("machine.acceleration", v))
            .transpose()?,
        rapid_rate: raw
            .machine
            .rapid_rate
            .map(|v| cx.positive("machine.rapid_rate", v))
            .transpose()?,
        spindle: match raw.machine.spindle {
            SpindleName::Cw => Spindle::Cw,
            SpindleName::Ccw => Spindle::Ccw,
        },
    };
    let s = &raw.simulation;
    let sim = SimConfig {
        axial_spacing: cx.positive("simulation.axial_spacing", s.axial_spacing)?,
        angular_cells: if s.angular_cells >= 4 {
            s.angular_cells
        } else {
            return Err(cx.err("simulation.angular_cells", "expected at least 4 cells"));
        },
        tolerance: cx.positive("simulation.tolerance", s.tolerance)?,
        z_range: match s.z_range {
            None => None,
            Some([a, b]) => {
                cx.finite("simulation.z_range", a)?;
                cx.finite("simulation.z_range", b)?;
                if a >= b {
                    return Err(cx.err(
                        "simulation.z_range",
                        "expected [z_min, z_max] with z_min < z_max",
                    ));
                }
                Some((a, b))
            }
        },
        max_dexels: s.max_dexels.unwrap_or(DEFAULT_MAX_DEXELS),
        measure_spacing: cx.positive("simulation.measure_spacing", s.measure_spacing)?,
        measure_generators: if (1..=3600).contains(&s.measure_generators) {
            s.measure_generators
        } else {
            return Err(cx.err(
                "simulation.measure_generators",
                "expected 1 to 3600 generators",
            ));
        },
    };
    let (mut thread, form, thread_class) = resolve_thread(&raw.thread, &blank, cx)?;
    // With a class, the ideal (the deviations' reference, and the planner's target) is the
    // middle of its zone.
    if let Some(class) = &thread_class {
        // An external thread's root is its minor diameter, an internal one's its major
        // (which a designation fixes): a given root stays where the job puts it.
        let root_given = !class.internal && raw.thread.minor_diameter.is_some();
        super::place::zone_middle(&mut thread, class, root_given);
    }
    if raw.thread.pitch_diameter_limits.is_some() && thread_class.is_some() {
        let by = if raw.thread.designation.is_some() {
            "designation"
        } else {
            "class"
        };
        return Err(cx.err(
            "thread.pitch_diameter_limits",
            format!("the thread's `{by}` already gives the pitch diameter's limits: give `pitch_diameter_limits` or the class, not both"),
        ));
    }
    // The grid must resolve the thread (and a pitch far below the spacing would make the
    // ideal profile of each column enormous).
    let p_min = thread
        .pitch_of_turn(1)
        .min(thread.pitch_of_turn(thread.turns.ceil().max(1.0) as i64));
    if sim.axial_spacing * 4.0 > p_min {
        return Err(cx.err(
            "simulation.axial_spacing",
            format!(
                "expected at most a quarter of the smallest pitch ({p_min:.4} mm), got {}",
                sim.axial_spacing
            ),
        ));
    }
    for (i, t) in raw.tool.iter().enumerate() {
        if raw.tool[..i].iter().any(|o| o.id == t.id) {
            return Err(cx.err(
                &format!("tool[{i}].id"),
                format!("tool id {} is used twice", t.id),
            ));
        }
        check_tool_keys(t, i, cx)?;
    }
    if raw.machine.kind == mill::MachineKind::Mill {
        let m = &raw.machine;
        let lathe_only = [
            ("machine.offsets", m.offsets.is_some()),
            ("machine.g76_finish_passes", m.g76_finish_passes.is_some()),
            ("machine.g76_tool_angle", m.g76_tool_angle.is_some()),
            ("machine.g76_min_cut", m.g76_min_cut.is_some()),
            (
                "machine.g76_finish_allowance",
                m.g76_finish_allowance.is_some(),
            ),
        ];
        let lathe_only = [lathe_only.as_slice(), &[("part", raw.part.is_some())]].concat();
        if let Some((key, _)) = lathe_only.iter().find(|k| k.1) {
            return Err(cx.err(key, "this key is for lathe jobs (a mill's offsets are G43 H and G41 D, from the program's own words)"));
        }
        if raw.machine.spindle != SpindleName::Cw {
            return Err(cx.err(
                "machine.spindle",
                "a mill's spindle direction comes from the program (M03/M04)",
            ));
        }
        let parts = mill::resolve_mill(&raw, blank.z_front, cx, strict)?;
        let pitch_diameter_limits = match raw.thread.pitch_diameter_limits {
            Some([a, b]) => {
                let key = "thread.pitch_diameter_limits";
                if cx.positive(key, a)? >= cx.positive(key, b)? {
                    return Err(cx.err(key, "expected [smallest, largest] pitch diameter (mm)"));
                }
                Some((a, b))
            }
            None => None,
        };
        let job = Job {
            name: raw.name.unwrap_or_default(),
            blank,
            form,
            thread,
            tools: Vec::new(),
            passes: Vec::new(),
            machine,
            sim,
            program_warnings: Vec::new(),
            chains: Vec::new(),
            pass_blocks: Vec::new(),
            explicit_passes: 0,
            pass_rpm: Vec::new(),
            pass_cycle: Vec::new(),
            pass_tool_words: Vec::new(),
            program_inch: false,
            mill: None,
            pitch_diameter_limits,
            thread_class,
            plan: None,
            placement: None,
            fit_thread: raw.thread.z_start.is_none(),
            part_profile: None,
            bore_profile: None,
            holders: Vec::new(),
            chuck: None,
            cycle_time: None,
            turning_tools: Vec::new(),
            turning: Default::default(),
            taps: Vec::new(),
            tap_feeds: Vec::new(),
        };
        return Ok(Parsed {
            job,
            program: Some(Pending::Mill(parts)),
        });
    }
    if raw.thread.pitch_diameter_limits.is_some() {
        return Err(cx.err(
            "thread.pitch_diameter_limits",
            "the pitch diameter is measured on milling jobs only, for now",
        ));
    }
    if raw.machine.axis.is_some() || raw.machine.home_z.is_some() {
        return Err(cx.err(
            if raw.machine.axis.is_some() {
                "machine.axis"
            } else {
                "machine.home_z"
            },
            "this key is for milling jobs ([machine] kind = \"mill\")",
        ));
    }
    let mut tools = Vec::with_capacity(raw.tool.len());
    let mut turning_tools = Vec::new();
    let mut taps = Vec::new();
    for (i, t) in raw.tool.iter().enumerate() {
        if t.kind == ToolKind::Tap {
            if raw.program.is_none() {
                return Err(cx.err(
                    &format!("tool[{i}].kind"),
                    "a tap cuts by the strokes of a [program] (G84, G33.1, G331, CYCLE84); this job has none",
                ));
            }
            taps.push(resolve_tap(t, i, cx)?);
        }
        if t.kind == ToolKind::Turning {
            if raw.program.is_none() {
                return Err(cx.err(
                    &format!("tool[{i}].kind"),
                    "a turning tool cuts by the moves of a [program]; this job has none",
                ));
            }
            turning_tools.push(resolve_turning(t, i, cx)?);
        } else {
            tools.push(resolve_tool(t, i, cx, load)?);
        }
    }
    let (passes, plan) = process::job_passes(&raw, &thread, &tools, &blank, &machine, &sim, cx)?;
    let program = match &raw.program {
        Some(pr) => Some(Pending::Lathe(program::lathe_program(
            pr,
            Some(&raw.machine),
            &blank,
            cx,
            strict,
        )?)),
        None => None,
    };
    let (part_profile, bore_profile) = part(&raw, &blank, cx)?;
    // The ideal thread follows the drawn part where it lies below the thread (chamfers,
    // reliefs on the thread's own surface).
    let mut holders = Vec::new();
    for (i, t) in raw.tool.iter().enumerate() {
        let internal = match t.kind {
            ToolKind::Turning => t.side.unwrap_or_default() == SideName::Internal,
            _ => thread.side == crate::model::thread::Side::Internal,
        };
        if let Some(h) = resolve_holder(t, i, internal, cx)? {
            holders.push((t.id, h));
        }
    }
    let chuck = raw
        .machine
        .chuck
        .as_ref()
        .map(|pts| {
            PartProfile::from_diameters(pts).map_err(|e| {
                let at = match e {
                    PartError::NotANumber(i) | PartError::Backwards(i) | PartError::Repeated(i) => {
                        format!("machine.chuck[{i}]")
                    }
                    PartError::TooFew => "machine.chuck".to_string(),
                };
                cx.err(&at, e.to_string())
            })
        })
        .transpose()?;
    thread.outline = match thread.side {
        crate::model::thread::Side::External => part_profile.clone(),
        crate::model::thread::Side::Internal => bore_profile.clone(),
    }
    .map(std::sync::Arc::new);
    let n_passes = passes.len();
    let job = Job {
        name: raw.name.unwrap_or_default(),
        blank,
        form,
        thread,
        tools,
        passes,
        machine,
        sim,
        program_warnings: Vec::new(),
        chains: Vec::new(),
        pass_blocks: Vec::new(),
        explicit_passes: raw.pass.len(),
        pass_rpm: vec![machine.spindle_rpm; n_passes],
        pass_cycle: vec![false; n_passes],
        pass_tool_words: vec![None; n_passes],
        program_inch: false,
        mill: None,
        pitch_diameter_limits: None,
        thread_class,
        plan,
        placement: None,
        fit_thread: raw.thread.z_start.is_none() && raw.process.is_none(),
        part_profile,
        bore_profile,
        holders,
        chuck,
        cycle_time: None,
        turning_tools,
        turning: Default::default(),
        taps,
        tap_feeds: Vec::new(),
    };
    Ok(Parsed { job, program })
}

/// `[part]`: the contours, each checked point by point; a bore's only on a tube.
fn part(
    raw: &RawJob,
    blank: &Blank,
    cx: &Ctx,
) -> Result<(Option<PartProfile>, Option<PartProfile>), JobError> {
    let Some(p) = &raw.part else {
        return Ok((None, None));
    };
    let contour = |key: &str, pts: &Option<Vec<[f64; 2]>>| {
        pts.as_ref()
            .map(|pts| {
                PartProfile::from_diameters(pts).map_err(|e| {
                    let at = match e {
                        PartError::NotANumber(i)
                        | PartError::Backwards(i)
                        | PartError::Repeated(i) => {
                            format!("{key}[{i}]")
                        }
                        PartError::TooFew => key.to_string(),
                    };
                    cx.err(&at, e.to_string())
                })
            })
            .transpose()
    };
    let outer = contour("part.profile", &p.profile)?;
    let bore = contour("part.bore_profile", &p.bore_profile)?;
    if bore.is_some() && blank.bore <= 0.0 {
        return Err(cx.err(
            "part.bore_profile",
            "a bore's contour needs a blank with a bore (blank.bore)",
        ));
    }
    if outer.is_none() && bore.is_none() {
        return Err(cx.err(
            "part",
            "expected `profile` (the outer contour, [[z, d], ...]) or `bore_profile`",
        ));
    }
    Ok((outer, bore))
}
