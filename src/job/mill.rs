//! Milling jobs: `[machine] kind = "mill"`, thread mills (`kind = "thread-mill"`) and the
//! machining centre's settings of the `[program]`. The program's moves become the kernel's
//! path in the program stage ([`crate::toolpath`]).

use super::ctx::Ctx;
use super::schema::{RawJob, RawProgram, RawTool, ToolKind};
use super::JobError;
use crate::kernel::mill::{Cutter, CutterSpec, MillPath};
use crate::nc::{MillMove, MillSettings};
use crate::toolpath::Program;
use serde::Deserialize;

/// Lathe (the part turns) or mill (the part stands, the cutter moves).
#[derive(Deserialize, Clone, Copy, Default, PartialEq, Eq, Debug)]
#[serde(rename_all = "kebab-case")]
pub(super) enum MachineKind {
    #[default]
    Lathe,
    Mill,
}

/// The kinds of thread mill.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Debug)]
#[serde(rename_all = "kebab-case")]
pub(super) enum CutterName {
    /// One tooth.
    Single,
    /// Teeth at the pitch.
    Comb,
    /// Drill point, teeth, chamfer.
    DrillMill,
}

/// A milling job's cutters and path.
#[derive(Clone, Debug)]
pub struct MillJob {
    /// The cutters, in the order of the job's `[[tool]]` tables.
    pub cutters: Vec<Cutter>,
    /// Their ids.
    pub cutter_ids: Vec<u32>,
    /// The program's moves as interpreted (job frame).
    pub moves: Vec<MillMove>,
    /// The part axis (x, y) in the job frame.
    pub axis: [f64; 2],
    /// The sampled path in the part's frame, one path move per program move.
    pub path: MillPath,
    /// Spindle speed (rev/min) per move: the program's S, or the job's.
    pub rpm: Vec<f64>,
}

fn resolve_cutter(t: &RawTool, i: usize, cx: &Ctx) -> Result<Cutter, JobError> {
    let key = |k: &str| format!("tool[{i}].{k}");
    let name = t.cutter.ok_or_else(|| {
        cx.err(
            &key("kind"),
            "a thread mill needs `cutter = \"single\"`, `\"comb\"` or `\"drill-mill\"`",
        )
    })?;
    let diameter = cx.positive(
        &key("diameter"),
        t.diameter.ok_or_else(|| {
            cx.err(
                &key("kind"),
                "a thread mill needs `diameter` (mm, at the tooth tips)",
            )
        })?,
    )?;
    let half_angles = match (t.angle, t.flank_angles) {
        (Some(_), Some(_)) => {
            return Err(cx.err(
                &key("flank_angles"),
                "give `angle` (included) or `flank_angles` ([lower, upper]), not both",
            ))
        }
        (None, Some([a, b])) => [
            cx.angle(&key("flank_angles"), a, 0.0, 80.0)?,
            cx.angle(&key("flank_angles"), b, 0.0, 80.0)?,
        ],
        (a, None) => {
            let h = cx.angle(&key("angle"), a.unwrap_or(60.0), 0.0, 160.0)? / 2.0;
            [h, h]
        }
    };
    let tip_flat = cx.non_negative(&key("tip_flat"), t.tip_flat.unwrap_or(0.0))?;
    let teeth = match (name, t.teeth) {
        (CutterName::Single, None | Some(1)) => 1,
        (CutterName::Single, Some(_)) => {
            return Err(cx.err(&key("teeth"), "a single-profile mill has one tooth"))
        }
        (_, Some(n)) if (1..=1000).contains(&n) => n,
        (_, Some(n)) => {
            return Err(cx.err(&key("teeth"), format!("expected 1 to 1000 teeth, got {n}")))
        }
        (_, None) => {
            return Err(cx.err(
                &key("teeth"),
                "a comb or drill-mill needs `teeth` (how many at the pitch)",
            ))
        }
    };
    let pitch = match t.pitch {
        Some(p) => cx.positive(&key("pitch"), p)?,
        None if teeth == 1 => 0.0,
        None => return Err(cx.err(&key("pitch"), "several teeth need `pitch` (mm)")),
    };
    let tans = half_angles[0].tan() + half_angles[1].tan();
    let tooth_depth = match t.tooth_depth {
        Some(d) => cx.positive(&key("tooth_depth"), d)?,
        None if pitch > 0.0 && tans > 0.0 => 0.8 * (pitch - tip_flat).max(0.0) / tans,
        None => {
            return Err(cx.err(
                &key("tooth_depth"),
                "expected `tooth_depth` (mm): no pitch to derive it from",
            ))
        }
    };
    let drill = match (name, t.drill_diameter, t.point_angle) {
        (CutterName::DrillMill, Some(d), a) => Some((
            cx.positive(&key("drill_diameter"), d)?,
            cx.angle(&key("point_angle"), a.unwrap_or(118.0), 60.0, 180.0)?,
        )),
        (CutterName::DrillMill, None, _) => {
            return Err(cx.err(
                &key("drill_diameter"),
                "a drill-mill needs `drill_diameter` (mm)",
            ))
        }
        (_, Some(_), _) => {
            return Err(cx.err(
                &key("drill_diameter"),
                "only a drill-mill has a drill point",
            ))
        }
        (_, None, Some(_)) => {
            return Err(cx.err(&key("point_angle"), "only a drill-mill has a drill point"))
        }
        (_, None, None) => None,
    };
    let chamfer = match (name, t.chamfer_diameter) {
        (CutterName::DrillMill, c) => c
            .map(|c| cx.positive(&key("chamfer_diameter"), c))
            .transpose()?,
        (_, Some(_)) => {
            return Err(cx.err(&key("chamfer_diameter"), "only a drill-mill has a chamfer"))
        }
        (_, None) => None,
    };
    let core = diameter - 2.0 * tooth_depth;
    let mut spec = CutterSpec {
        diameter,
        half_angles,
        tip_flat,
        teeth,
        pitch,
        tooth_depth,
        first_tooth: 0.0,
        shank_diameter: cx.positive(&key("shank_diameter"), t.shank_diameter.unwrap_or(core))?,
        neck: cx.non_negative(&key("neck"), t.neck.unwrap_or(0.0))?,
        length: 0.0,
        flutes: match t.flutes.unwrap_or(1) {
            n @ 1..=64 => n,
            n => return Err(cx.err(&key("flutes"), format!("expected 1 to 64 flutes, got {n}"))),
        },
        drill,
        chamfer,
    };
    let [hb_lo, hb_hi] = spec.half_base();
    spec.first_tooth = match t.first_tooth {
        Some(u) => cx.non_negative(&key("first_tooth"), u)?,
        None if drill.is_some() => {
            return Err(cx.err(&key("first_tooth"), "a drill-mill needs `first_tooth`: the height of its first tooth's tip centre above the drill point (mm)"))
        }
        // The first tooth's lower flank starts at the cutter's end.
        None => hb_lo,
    };
    let span = spec.first_tooth + (teeth - 1) as f64 * pitch + hb_hi + spec.neck;
    spec.length = cx.positive(&key("length"), t.length.unwrap_or(span + 20.0))?;
    Cutter::from_spec(&spec).map_err(|e| cx.err(&key("kind"), e))
}

/// A milling job's cutters and the program to run for its path (the program stage makes
/// the [`MillJob`]).
pub(super) struct MillParts {
    pub(super) cutters: Vec<Cutter>,
    pub(super) ids: Vec<u32>,
    pub(super) axis: [f64; 2],
    pub(super) program: Program,
}

/// Resolve a milling job's cutters and `[program]`.
pub(super) fn resolve_mill(
    raw: &RawJob,
    blank_top: f64,
    cx: &Ctx,
    strict: bool,
) -> Result<MillParts, JobError> {
    if !raw.pass.is_empty() {
        return Err(cx.err(
            "pass",
            "a milling job's moves come from its [program], not from [[pass]] tables",
        ));
    }
    if raw.process.is_some() {
        return Err(cx.err(
            "process",
            "pass generators are for lathe jobs; a milling job needs a [program]",
        ));
    }
    let mut cutters = Vec::new();
    let mut ids = Vec::new();
    let mut radius_offsets = Vec::new();
    let mut length_offsets = Vec::new();
    for (i, t) in raw.tool.iter().enumerate() {
        if t.kind != ToolKind::ThreadMill {
            return Err(cx.err(
                &format!("tool[{i}].kind"),
                "a milling job's tools are thread mills (`kind = \"thread-mill\"`)",
            ));
        }
        let c = resolve_cutter(t, i, cx)?;
        let d = t.d.unwrap_or(t.id);
        let d_value = match t.d_value {
            Some(v) => cx.non_negative(&format!("tool[{i}].d_value"), v)?,
            None => c.radius,
        };
        if let Some((_, other)) = radius_offsets.iter().find(|(n, _)| *n == d) {
            if *other != d_value {
                return Err(cx.err(&format!("tool[{i}].d"), format!("D{d} is given two values")));
            }
        }
        radius_offsets.push((d, d_value));
        length_offsets.push(t.h.unwrap_or(t.id));
        ids.push(t.id);
        cutters.push(c);
    }
    if cutters.is_empty() {
        return Err(cx.err(
            "tool",
            "a milling job needs a thread mill: [[tool]] kind = \"thread-mill\"",
        ));
    }
    let pr: &RawProgram = raw.program.as_ref().ok_or_else(|| {
        cx.err(
            "program",
            "a milling job needs a [program] (its moves are the toolpath)",
        )
    })?;
    if pr.dialect != "fanuc" {
        return Err(cx.err(
            "program.dialect",
            format!(
                "milling programs are read as FANUC (machining centre) programs; got `{}`",
                pr.dialect
            ),
        ));
    }
    let mut work_offsets = [[0.0; 3]; 6];
    for (name, off) in &pr.work_offsets {
        let key = format!("program.work_offsets.{name}");
        let i = super::program::work_index(name)
            .ok_or_else(|| cx.err(&key, format!("expected one of G54..G59, got `{name}`")))?;
        work_offsets[i] = [
            cx.finite(&format!("{key}.x"), off.x)?,
            cx.finite(&format!("{key}.y"), off.y.unwrap_or(0.0))?,
            cx.finite(&format!("{key}.z"), off.z)?,
        ];
    }
    if pr.reference_point.is_some() {
        return Err(cx.err(
            "program.reference_point",
            "G28 is not simulated on mills yet",
        ));
    }
    if pr.second_reference_point.is_some() {
        return Err(cx.err(
            "program.second_reference_point",
            "G30 is not simulated on mills yet",
        ));
    }
    if pr.feed_mode.is_some() {
        return Err(cx.err(
            "program.feed_mode",
            "a lathe setting: a milling program sets its feed mode with G94/G95",
        ));
    }
    if pr.x_mode.is_some() {
        return Err(cx.err(
            "program.x_mode",
            "a lathe setting: a milling program's X is a position, never a diameter",
        ));
    }
    if pr.gcode_system.is_some() {
        return Err(cx.err(
            "program.gcode_system",
            "G-code systems B and C are lathe settings (a milling program has one system)",
        ));
    }
    let axis = match raw.machine.axis {
        Some([x, y]) => [cx.finite("machine.axis", x)?, cx.finite("machine.axis", y)?],
        None => [0.0, 0.0],
    };
    let home_z = match raw.machine.home_z {
        Some(z) => cx.finite("machine.home_z", z)?,
        None => blank_top + 50.0,
    };
    let settings = crate::nc::Settings {
        block_skip: pr.block_skip,
        mill: Some(MillSettings {
            work_offsets,
            radius_offsets,
            length_offsets,
            home_z,
        }),
        ..crate::nc::Settings::default()
    };
    Ok(MillParts {
        cutters,
        ids,
        axis,
        program: super::program::program(pr, settings, cx, strict)?,
    })
}
