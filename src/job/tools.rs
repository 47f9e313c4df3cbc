//! `[[tool]]` tables into [`Tool`]s: the edge of each kind of tool, the keys each kind
//! takes, mesh tools (OBJ, read through the loader) and the insert body behind the edge;
//! turning tools (`kind = "turning"`) into [`TurningTool`]s; taps (`kind = "tap"`) into a
//! [`Tap`] and the threading insert of its tooth.

use super::ctx::Ctx;
use super::schema::{HolderKind, RawTool, RefName, SideName, ToolKind};
use super::JobError;
use crate::kernel::turn::TurningTool;
use crate::model::solid::Solid;
use crate::model::tool::{Body, DepthLimits, Edge, Holder, Reference, Tap, Tool};

pub(super) fn resolve_tool(
    t: &RawTool,
    i: usize,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
) -> Result<Tool, JobError> {
    let key = |k: &str| format!("tool[{i}].{k}");
    let reference = match t.reference.unwrap_or_default() {
        RefName::Center => Reference::Center,
        RefName::Left => Reference::Left,
        RefName::Right => Reference::Right,
        RefName::Tip => Reference::Tip,
    };
    let edge = match t.kind {
        ToolKind::Grooving => Edge::Trapezoid {
            tip: cx.positive(
                &key("width"),
                t.width
                    .ok_or_else(|| cx.err(&key("kind"), "a grooving tool needs `width` (mm)"))?,
            )?,
            left_angle: 0.0,
            right_angle: 0.0,
        },
        ToolKind::Threading => {
            let angle = t.angle.ok_or_else(|| {
                cx.err(
                    &key("kind"),
                    "a threading tool needs `angle` (included, degrees)",
                )
            })?;
            let half = cx.angle(&key("angle"), angle, 1.0, 160.0)? / 2.0;
            match (t.tip_flat, t.nose_radius) {
                (Some(_), Some(_)) => {
                    return Err(cx.err(
                        &key("nose_radius"),
                        "give `tip_flat` or `nose_radius`, not both",
                    ))
                }
                (None, Some(r)) => Edge::RoundV {
                    radius: cx.positive(&key("nose_radius"), r)?,
                    half_angle: half,
                },
                (flat, None) => Edge::Trapezoid {
                    tip: cx.non_negative(&key("tip_flat"), flat.unwrap_or(0.0))?,
                    left_angle: half,
                    right_angle: half,
                },
            }
        }
        ToolKind::Trapezoidal => {
            let tip = cx.positive(
                &key("tip_width"),
                t.tip_width.ok_or_else(|| {
                    cx.err(&key("kind"), "a trapezoidal tool needs `tip_width` (mm)")
                })?,
            )?;
            let (l, r) =
                match (t.flank_angles, t.flank_angle) {
                    (Some([l, r]), None) => (l, r),
                    (None, Some(a)) => (a / 2.0, a / 2.0),
                    (None, None) => (15.0, 15.0),
                    (Some(_), Some(_)) => return Err(cx.err(
                        &key("flank_angle"),
                        "give `flank_angle` (included) or `flank_angles` ([left, right]), not both",
                    )),
                };
            Edge::Trapezoid {
                tip,
                left_angle: cx.angle(&key("flank_angles"), l, 0.0, 80.0)?,
                right_angle: cx.angle(&key("flank_angles"), r, 0.0, 80.0)?,
            }
        }
        ToolKind::Mesh => resolve_mesh(t, &key, cx, load)?,
        ToolKind::ThreadMill => {
            return Err(cx.err(
                &key("kind"),
                "a thread mill needs a milling job: set [machine] kind = \"mill\"",
            ))
        }
        ToolKind::Turning => {
            return Err(cx.err(
                &key("kind"),
                "a turning tool cuts no thread: passes and [process] need a threading tool",
            ))
        }
        ToolKind::Tap => return Ok(resolve_tap(t, i, cx)?.tooth()),
    };
    let depth_per_pass = depth_limits(t, &key, cx)?;
    if t.kind == ToolKind::Mesh {
        return Ok(Tool {
            id: t.id,
            edge,
            reference,
            body: None,
            length: None,
            depth_per_pass,
        });
    }
    let body = resolve_body(t, &edge, &key, cx)?;
    let length = t
        .length
        .map(|l| cx.positive(&key("length"), l))
        .transpose()?;
    Ok(Tool {
        id: t.id,
        edge,
        reference,
        body,
        length,
        depth_per_pass,
    })
}

/// `max_depth_per_pass` and `min_depth_per_pass`: positive, the least under the most.
fn depth_limits(
    t: &RawTool,
    key: &dyn Fn(&str) -> String,
    cx: &Ctx,
) -> Result<DepthLimits, JobError> {
    let get = |k: &str, v: Option<f64>| v.map(|v| cx.positive(&key(k), v)).transpose();
    let max = get("max_depth_per_pass", t.max_depth_per_pass)?;
    let min = get("min_depth_per_pass", t.min_depth_per_pass)?;
    if let (Some(max), Some(min)) = (max, min) {
        if min >= max {
            return Err(cx.err(
                &key("min_depth_per_pass"),
                format!("expected less than max_depth_per_pass ({max} mm), got {min}"),
            ));
        }
    }
    Ok(DepthLimits { max, min })
}

/// Default nose radius of a turning tool (mm): the most common insert, CNMG 120404.
pub(super) const TURNING_NOSE_RADIUS: f64 = 0.4;
/// Default edge angles of a turning tool (deg, leading and trailing edge from the radial
/// direction): an 80 deg rhombic insert (C) in a 95 deg approach holder (PCLNR).
pub(super) const TURNING_EDGE_ANGLES: [f64; 2] = [-5.0, 85.0];

/// A `kind = "turning"` tool: nose radius, the edges' angles and the side it cuts.
pub(super) fn resolve_turning(t: &RawTool, i: usize, cx: &Ctx) -> Result<TurningTool, JobError> {
    let key = |k: &str| format!("tool[{i}].{k}");
    let nose_radius = cx.non_negative(
        &key("nose_radius"),
        t.nose_radius.unwrap_or(TURNING_NOSE_RADIUS),
    )?;
    if nose_radius > 25.0 {
        return Err(cx.err(
            &key("nose_radius"),
            format!("expected at most 25 mm, got {nose_radius}"),
        ));
    }
    let [l, r] = t.edge_angles.unwrap_or(TURNING_EDGE_ANGLES);
    let lead = cx.angle(&key("edge_angles"), l, -89.0, 89.0)?;
    let trail = cx.angle(&key("edge_angles"), r, -89.0, 89.0)?;
    if l + r < 1.0 {
        return Err(cx.err(
            &key("edge_angles"),
            format!(
                "expected an insert's included angle (the sum) of at least 1 degree, got {}",
                l + r
            ),
        ));
    }
    let internal = t.side.unwrap_or_default() == SideName::Internal;
    // The imaginary tip the program drives (FANUC numbering): 3 outside, 2 in a bore.
    let tip = t.tip_direction.unwrap_or(if internal { 2 } else { 3 });
    TurningTool::turning(t.id, nose_radius, (lead, trail), internal)
        .with_tip(u8::try_from(tip).unwrap_or(u8::MAX))
        .ok_or_else(|| {
            cx.err(
                &key("tip_direction"),
                format!("expected an imaginary tip direction 0 to 9 (FANUC numbering: 3 an external tool turning towards the chuck, 2 a boring bar), got {tip}"),
            )
        })
}

/// A `kind = "tap"` tool: `diameter` (the major diameter), `pitch`, the chamfer by
/// `chamfer_length` (mm) or `chamfer_threads` (pitches), and `chamfer_diameter` at its tip
/// (default: the basic minor diameter `D - 1.082532 P`, ISO 68-1).
pub(super) fn resolve_tap(t: &RawTool, i: usize, cx: &Ctx) -> Result<Tap, JobError> {
    let key = |k: &str| format!("tool[{i}].{k}");
    let need = |k: &str, v: Option<f64>, what: &str| {
        v.ok_or_else(|| cx.err(&key("kind"), format!("a tap needs `{k}` ({what})")))
    };
    let major = cx.positive(
        &key("diameter"),
        need("diameter", t.diameter, "the major diameter, mm")?,
    )?;
    let pitch = cx.positive(&key("pitch"), need("pitch", t.pitch, "mm")?)?;
    if pitch >= major {
        return Err(cx.err(
            &key("pitch"),
            format!("expected a pitch below the diameter {major} mm, got {pitch}"),
        ));
    }
    let chamfer_length = match (t.chamfer_length, t.chamfer_threads) {
        (Some(_), Some(_)) => {
            return Err(cx.err(
                &key("chamfer_threads"),
                "give `chamfer_length` (mm) or `chamfer_threads` (pitches), not both",
            ))
        }
        (Some(l), None) => cx.non_negative(&key("chamfer_length"), l)?,
        (None, Some(n)) => cx.non_negative(&key("chamfer_threads"), n)? * pitch,
        (None, None) => {
            return Err(cx.err(
                &key("kind"),
                "a tap needs `chamfer_length` (mm) or `chamfer_threads` (pitches): the length of its chamfer",
            ))
        }
    };
    let minor = major - 1.082532 * pitch;
    let chamfer_diameter = match t.chamfer_diameter {
        Some(d) => cx.positive(&key("chamfer_diameter"), d)?,
        None => minor,
    };
    if chamfer_diameter > major {
        return Err(cx.err(
            &key("chamfer_diameter"),
            format!("expected at most the major diameter {major} mm, got {chamfer_diameter}"),
        ));
    }
    Ok(Tap {
        id: t.id,
        pitch,
        major_diameter: major,
        chamfer_length,
        chamfer_diameter,
    })
}

/// Every optional `[[tool]]` key and the kinds of tool it applies to: a key set on a tool
/// of another kind is an error that says so.
pub(super) fn check_tool_keys(t: &RawTool, i: usize, cx: &Ctx) -> Result<(), JobError> {
    use ToolKind::{Grooving, Mesh, Tap, ThreadMill, Threading, Trapezoidal, Turning};
    const INSERTS: &[ToolKind] = &[Grooving, Threading, Trapezoidal];
    const MILL: &[ToolKind] = &[ThreadMill];
    const LIMITED: &[ToolKind] = &[Grooving, Threading, Trapezoidal, Mesh];
    const LATHE: &[ToolKind] = &[Grooving, Threading, Trapezoidal, Mesh, Turning];
    let keys: [(&str, bool, &[ToolKind]); 42] = [
        ("holder", t.holder.is_some(), LATHE),
        (
            "max_depth_per_pass",
            t.max_depth_per_pass.is_some(),
            LIMITED,
        ),
        (
            "min_depth_per_pass",
            t.min_depth_per_pass.is_some(),
            LIMITED,
        ),
        ("width", t.width.is_some(), &[Grooving]),
        ("angle", t.angle.is_some(), &[Threading, ThreadMill]),
        ("tip_flat", t.tip_flat.is_some(), &[Threading, ThreadMill]),
        (
            "nose_radius",
            t.nose_radius.is_some(),
            &[Threading, Turning],
        ),
        ("edge_angles", t.edge_angles.is_some(), &[Turning]),
        ("tip_direction", t.tip_direction.is_some(), &[Turning]),
        ("side", t.side.is_some(), &[Turning]),
        ("tip_width", t.tip_width.is_some(), &[Trapezoidal]),
        ("flank_angle", t.flank_angle.is_some(), &[Trapezoidal]),
        (
            "flank_angles",
            t.flank_angles.is_some(),
            &[Trapezoidal, ThreadMill],
        ),
        ("reference", t.reference.is_some(), INSERTS),
        (
            "length",
            t.length.is_some(),
            &[Grooving, Threading, Trapezoidal, ThreadMill],
        ),
        ("thickness", t.thickness.is_some(), INSERTS),
        (
            "side_clearance_left",
            t.side_clearance_left.is_some(),
            INSERTS,
        ),
        (
            "side_clearance_right",
            t.side_clearance_right.is_some(),
            INSERTS,
        ),
        ("front_clearance", t.front_clearance.is_some(), INSERTS),
        ("inclination", t.inclination.is_some(), INSERTS),
        ("file", t.file.is_some(), &[Mesh]),
        ("mesh_origin", t.mesh_origin.is_some(), &[Mesh]),
        ("mesh_axes", t.mesh_axes.is_some(), &[Mesh]),
        ("mesh_units", t.mesh_units.is_some(), &[Mesh]),
        ("mesh_body", t.mesh_body.is_some(), &[Mesh]),
        ("cutter", t.cutter.is_some(), MILL),
        ("diameter", t.diameter.is_some(), &[ThreadMill, Tap]),
        ("pitch", t.pitch.is_some(), &[ThreadMill, Tap]),
        ("teeth", t.teeth.is_some(), MILL),
        ("tooth_depth", t.tooth_depth.is_some(), MILL),
        ("first_tooth", t.first_tooth.is_some(), MILL),
        ("shank_diameter", t.shank_diameter.is_some(), MILL),
        ("neck", t.neck.is_some(), MILL),
        ("flutes", t.flutes.is_some(), MILL),
        ("drill_diameter", t.drill_diameter.is_some(), MILL),
        ("point_angle", t.point_angle.is_some(), MILL),
        (
            "chamfer_diameter",
            t.chamfer_diameter.is_some(),
            &[ThreadMill, Tap],
        ),
        ("chamfer_length", t.chamfer_length.is_some(), &[Tap]),
        ("chamfer_threads", t.chamfer_threads.is_some(), &[Tap]),
        ("h", t.h.is_some(), MILL),
        ("d", t.d.is_some(), MILL),
        ("d_value", t.d_value.is_some(), MILL),
    ];
    if let Some((k, _, kinds)) = keys
        .iter()
        .find(|(_, set, kinds)| *set && !kinds.contains(&t.kind))
    {
        let why = if t.kind == Mesh {
            "this key does not apply to a mesh tool: the mesh gives its shape and body, `mesh_origin` its reference point"
        } else if *kinds == [Mesh] {
            "this key applies to `kind = \"mesh\"` tools only"
        } else if *kinds == MILL {
            "this key applies to `kind = \"thread-mill\"` tools only"
        } else if *kinds == [Tap] {
            "this key applies to `kind = \"tap\"` tools only"
        } else {
            "this key does not apply to this kind of tool"
        };
        return Err(cx.err(&format!("tool[{i}].{k}"), why));
    }
    Ok(())
}

/// A mesh tool: the OBJ `file` (read through `load`, relative to the job file), placed by
/// `mesh_origin` (the reference point: on the tip, in the rake face; OBJ units) and
/// `mesh_axes` (the OBJ axes along the part's axis, the height above the tip away from the
/// material, and the depth behind the rake face), in `mesh_units`.
fn resolve_mesh(
    t: &RawTool,
    key: &dyn Fn(&str) -> String,
    cx: &Ctx,
    load: &dyn Fn(&str) -> Option<String>,
) -> Result<Edge, JobError> {
    let file = t.file.as_deref().ok_or_else(|| {
        cx.err(
            &key("kind"),
            "a mesh tool needs `file` (an OBJ file, relative to the job file)",
        )
    })?;
    let text = load(file).ok_or_else(|| {
        cx.err(
            &key("file"),
            format!("cannot read `{file}` (relative to the job file)"),
        )
    })?;
    let scale = match t.mesh_units.as_deref().unwrap_or("mm") {
        "mm" => 1.0,
        "inch" => 25.4,
        "m" => 1000.0,
        other => {
            return Err(cx.err(
                &key("mesh_units"),
                format!("expected \"mm\", \"inch\" or \"m\", got \"{other}\""),
            ))
        }
    };
    let origin = t.mesh_origin.unwrap_or([0.0; 3]);
    for v in origin {
        cx.finite(&key("mesh_origin"), v)?;
    }
    let names = t
        .mesh_axes
        .clone()
        .unwrap_or_else(|| ["+x".into(), "+y".into(), "+z".into()]);
    // (OBJ axis, sign) for the part's axis, the height and the depth.
    let mut axes = [(0usize, 1.0f64); 3];
    for (k, name) in names.iter().enumerate() {
        let (sign, axis) = match name.as_str() {
            "+x" | "x" => (1.0, 0),
            "-x" => (-1.0, 0),
            "+y" | "y" => (1.0, 1),
            "-y" => (-1.0, 1),
            "+z" | "z" => (1.0, 2),
            "-z" => (-1.0, 2),
            other => {
                return Err(cx.err(
                    &key("mesh_axes"),
                    format!("expected three of \"+x\", \"-x\", \"+y\", \"-y\", \"+z\", \"-z\" (the part's axis, the height above the tip, the depth behind the rake face), got \"{other}\""),
                ))
            }
        };
        axes[k] = (axis, sign);
    }
    if axes[0].0 == axes[1].0 || axes[0].0 == axes[2].0 || axes[1].0 == axes[2].0 {
        return Err(cx.err(
            &key("mesh_axes"),
            "expected each OBJ axis once (the part's axis, the height, the depth)",
        ));
    }
    let opts = tobj::LoadOptions {
        triangulate: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| {
        cx.err(
            &key("file"),
            format!("{file}: not a readable OBJ mesh: {e}"),
        )
    })?;
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    for m in &models {
        let base = vertices.len();
        for p in m.mesh.positions.chunks_exact(3) {
            let tool = axes.map(|(axis, sign)| sign * (p[axis] - origin[axis]) * scale);
            // [V, H, Y] -> the solid's [H, Y, V].
            vertices.push([tool[1], tool[2], tool[0]]);
        }
        for t in m.mesh.indices.chunks_exact(3) {
            triangles.push([
                base + t[0] as usize,
                base + t[1] as usize,
                base + t[2] as usize,
            ]);
        }
    }
    if vertices.iter().flatten().any(|v| !v.is_finite()) {
        return Err(cx.err(
            &key("file"),
            format!("{file}: a vertex is not a finite number"),
        ));
    }
    let solid = Solid::from_mesh(&vertices, &triangles)
        .map_err(|e| cx.err(&key("file"), format!("{file}: {e}")))?;
    Ok(Edge::Mesh {
        solid: std::sync::Arc::new(solid),
        body: t.mesh_body.unwrap_or(true),
    })
}

/// The insert behind the edge: present with `thickness`, which then needs both side
/// clearances (no default: a clearance is what the check is about).
fn resolve_body(
    t: &RawTool,
    edge: &Edge,
    key: &dyn Fn(&str) -> String,
    cx: &Ctx,
) -> Result<Option<Body>, JobError> {
    let Some(thickness) = t.thickness else {
        let stray = [
            ("side_clearance_left", t.side_clearance_left.is_some()),
            ("side_clearance_right", t.side_clearance_right.is_some()),
            ("front_clearance", t.front_clearance.is_some()),
            ("inclination", t.inclination.is_some()),
        ];
        if let Some((k, _)) = stray.iter().find(|(_, set)| *set) {
            return Err(cx.err(
                &key(k),
                "a tool body needs `thickness` (mm behind the rake face) too",
            ));
        }
        return Ok(None);
    };
    if matches!(edge, Edge::RoundV { .. }) {
        return Err(cx.err(
            &key("thickness"),
            "a tool body is modelled for flat-tipped edges only (grooving, trapezoidal, threading with `tip_flat`)",
        ));
    }
    let thickness = cx.positive(&key("thickness"), thickness)?;
    if thickness > 50.0 {
        return Err(cx.err(
            &key("thickness"),
            format!("expected at most 50 mm, got {thickness}"),
        ));
    }
    let side = |k: &str, v: Option<f64>| -> Result<f64, JobError> {
        let v = v.ok_or_else(|| {
            cx.err(
                &key("thickness"),
                format!("a tool body needs `{k}` (degrees; negative when ground to stand out)"),
            )
        })?;
        cx.angle(&key(k), v, -30.0, 45.0)
    };
    Ok(Some(Body {
        thickness,
        clearance_left: side("side_clearance_left", t.side_clearance_left)?,
        clearance_right: side("side_clearance_right", t.side_clearance_right)?,
        clearance_front: cx.angle(
            &key("front_clearance"),
            t.front_clearance.unwrap_or(0.0),
            0.0,
            45.0,
        )?,
        inclination: cx.angle(
            &key("inclination"),
            t.inclination.unwrap_or(0.0),
            -30.0,
            30.0,
        )?,
    }))
}

/// `tool[i].holder`: a shank (external tools) or a boring bar (internal ones), each key
/// checked; `internal` says where the tool cuts.
pub(super) fn resolve_holder(
    t: &RawTool,
    i: usize,
    internal: bool,
    cx: &Ctx,
) -> Result<Option<Holder>, JobError> {
    let Some(h) = &t.holder else {
        return Ok(None);
    };
    let key = |k: &str| format!("tool[{i}].holder.{k}");
    let (own, other): (&[&str], &[&str]) = match h.kind {
        HolderKind::Shank => (
            &["left", "right", "clearance"],
            &["diameter", "reach", "front", "length"],
        ),
        HolderKind::Bar => (
            &["diameter", "reach", "front", "length"],
            &["left", "right", "clearance"],
        ),
    };
    let given = |k: &str| match k {
        "left" => h.left,
        "right" => h.right,
        "clearance" => h.clearance,
        "diameter" => h.diameter,
        "reach" => h.reach,
        "front" => h.front,
        _ => h.length,
    };
    if let Some(k) = other.iter().find(|k| given(k).is_some()) {
        return Err(cx.err(
            &key(k),
            format!(
                "a {} holder takes {}",
                if h.kind == HolderKind::Shank {
                    "shank"
                } else {
                    "bar"
                },
                own.iter()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    let need = |k: &str, what: &str| {
        given(k).ok_or_else(|| cx.err(&key(k), format!("expected {what} (mm)")))
    };
    let finite = |k: &str, v: f64, lo: f64| {
        if v.is_finite() && v >= lo && v <= 10_000.0 {
            Ok(v)
        } else {
            Err(cx.err(
                &key(k),
                format!("expected a length from {lo} to 10000 mm, got {v}"),
            ))
        }
    };
    match h.kind {
        HolderKind::Shank => {
            if internal {
                return Err(cx.err(
                    &key("kind"),
                    "this tool cuts in the bore: its holder is a `bar` (a shank holds external tools)",
                ));
            }
            let left = finite(
                "left",
                need(
                    "left",
                    "how far the shank reaches to the -z side of the tip (negative: it starts that far to the +z side)",
                )?,
                -10_000.0,
            )?;
            let right = finite(
                "right",
                need(
                    "right",
                    "how far the shank reaches to the +z side of the tip",
                )?,
                -10_000.0,
            )?;
            let clearance = finite(
                "clearance",
                need("clearance", "how far above the tip the shank starts")?,
                0.0,
            )?;
            if left + right <= 0.0 {
                return Err(cx.err(
                    &key("right"),
                    "expected a shank of some width (left + right > 0)",
                ));
            }
            Ok(Some(Holder::Shank {
                left,
                right,
                clearance,
            }))
        }
        HolderKind::Bar => {
            if !internal {
                return Err(cx.err(
                    &key("kind"),
                    "this tool cuts outside: its holder is a `shank` (a bar holds tools that cut in the bore)",
                ));
            }
            let diameter = finite("diameter", need("diameter", "the bar's diameter")?, 0.0)?;
            let reach = finite(
                "reach",
                need("reach", "the tip's distance from the bar's centre line")?,
                0.0,
            )?;
            let front = finite("front", h.front.unwrap_or(0.0), -10_000.0)?;
            let length = finite(
                "length",
                need(
                    "length",
                    "how far the bar reaches from the tip toward +z, out of the bore",
                )?,
                -10_000.0,
            )?;
            if front + length <= 0.0 {
                return Err(cx.err(
                    &key("length"),
                    "expected a bar of some length (front + length > 0)",
                ));
            }
            if diameter <= 0.0 {
                return Err(cx.err(&key("diameter"), "expected a bar diameter over 0 mm"));
            }
            Ok(Some(Holder::Bar {
                diameter,
                reach,
                front,
                length,
            }))
        }
    }
}
