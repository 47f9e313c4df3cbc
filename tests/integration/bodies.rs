//! Tool bodies: the insert behind the edge against closed forms. A body whose side
//! clearance beats the helix angle leaves exactly the planar cut; one whose clearance the
//! growing helix angle of a variable lead overtakes rubs the leading flank only, from the
//! turn where the analytic helix angle at the root crosses the clearance, by the closed-form
//! amount at the back of the insert.

use crate::support::{job, run, scene_text, with};
use std::f64::consts::TAU;

/// seed 002's equal-groove screw (leads 10 to 30 mm, root radius 22) by radial layers,
/// on fewer angular cells, its grooving tool given a 4 mm body with these side clearances.
fn screw(left: f64, right: f64) -> String {
    let text = with(
        &scene_text("seed002-equal-groove-radial"),
        &[
            ("simulation", "angular_cells", "720"),
            ("simulation", "measure_generators", "2"),
        ],
    );
    text.replace(
        "reference = \"center\"",
        &format!(
            "reference = \"center\"\nthickness = 4.0\nside_clearance_left = {left}\nside_clearance_right = {right}\nfront_clearance = 5.0"
        ),
    )
}

#[test]
fn a_cleared_body_leaves_the_planar_cut() {
    let plain = run(&with(
        &scene_text("seed002-equal-groove-radial"),
        &[
            ("simulation", "angular_cells", "720"),
            ("simulation", "measure_generators", "2"),
        ],
    ));
    // 14 deg beats the largest helix angle at the root, atan(30 / (2 pi 22)) = 12.2 deg.
    let bodied = run(&screw(14.0, 14.0));
    assert_eq!(plain.stock.outer, bodied.stock.outer);
    assert_eq!(bodied.report.interference, Some(vec![]));
    assert!(bodied
        .report
        .findings
        .iter()
        .all(|f| f.kind != vpcut::FindingKind::FlankInterference));
    // The effective clearance is reported per turn, positive everywhere.
    for t in &bodied.report.turns {
        let c = t.clearance_deg.as_ref().expect("clearance per turn");
        assert!(c.left_root > 0.0 && c.right_root > 0.0, "turn {}", t.turn);
    }
}

#[test]
fn the_helix_angle_overtaking_the_clearance_rubs_the_leading_flank() {
    let alpha = 8.0f64;
    let text = screw(alpha, 20.0);
    let j = job(&text);
    let out = run(&text);
    let rows = out.report.interference.as_ref().unwrap();
    assert!(!rows.is_empty(), "no interference");
    // The passes travel towards -z: the -z flank leads; the +z flank never rubs.
    assert!(rows.iter().all(|r| r.flank == "left"), "{rows:?}");
    // Onset: the thread's lead law L = F + K t reaches 2 pi r_root tan(alpha) at t*.
    let law = j.thread.helix.law;
    let r_root = j.thread.root_radius;
    let t_star = (TAU * r_root * alpha.to_radians().tan() - law.f) / law.k;
    let n_star = t_star.floor() as i64 + 1;
    let first = rows
        .iter()
        .filter(|r| r.max_mm > 0.001)
        .map(|r| r.turn)
        .min()
        .unwrap();
    assert!(
        first == n_star || first == n_star + 1,
        "interference starts in turn {first}, the helix angle crosses {alpha} deg in turn {n_star} (t* = {t_star:.3})"
    );
    assert!(rows.iter().all(|r| r.turn >= n_star), "{rows:?}");
    // The clearance row says the same: negative at the root from turn n*+1 on.
    for t in &out.report.turns {
        let c = t.clearance_deg.as_ref().unwrap();
        assert_eq!(c.left_root < 0.0, t.turn > n_star, "turn {}: {c:?}", t.turn);
        assert!(c.right_root > 0.0);
    }
    // Depth at the worst place of the drawing's turns (past them the pass ends before its
    // body has gone by): the deepest ray through the back of the insert (Y = 4 mm) runs
    // along its bottom face, which rises with the 5 deg front clearance: r sin phi = 4 and
    // r (cos phi - sin phi tan 5) = r_root give tan phi = 4 / (r_root + 4 tan 5). That is a
    // fraction phi / 2pi of a turn after the edge: the section has travelled
    // L phi / 2pi + K (phi / 2pi)^2 / 2 along the axis and its flank receded 4 tan(alpha).
    let worst = rows
        .iter()
        .filter(|r| r.turn <= j.thread.whole_turns())
        .max_by(|a, b| a.max_mm.total_cmp(&b.max_mm))
        .unwrap();
    let last = j.passes.last().unwrap();
    let h = last.helix();
    let t = h.revs_at_z(worst.z_mm).unwrap();
    let lead = h.law.lead(t);
    let dt = (4.0 / (r_root + 4.0 * 5f64.to_radians().tan())).atan() / TAU;
    let expected = lead * dt + 0.5 * h.law.k * dt * dt - 4.0 * alpha.to_radians().tan();
    assert!(
        // Two axial cells (0.01 mm each: where the dexel wall of the edge's cut and the
        // farthest body-cut cell fall between cells) and the 0.005 mm sampling bound.
        (worst.max_mm - expected).abs() <= 0.025,
        "worst {} mm at z {}, closed form {expected:.4} (lead {lead:.3})",
        worst.max_mm,
        worst.z_mm
    );
    assert!(out
        .report
        .findings
        .iter()
        .any(|f| f.kind == vpcut::FindingKind::FlankInterference
            && f.severity == vpcut::Severity::Error));
}

#[test]
fn body_keys_are_checked() {
    let base = scene_text("seed002-equal-groove-radial");
    for (extra, says) in [
        ("thickness = 4.0", "side_clearance_left"),
        ("side_clearance_left = 5.0", "needs `thickness`"),
        (
            "thickness = 4.0\nside_clearance_left = 5.0\nside_clearance_right = 50.0",
            "side_clearance_right",
        ),
        (
            "thickness = 4.0\nside_clearance_left = 5.0\nside_clearance_right = 5.0\nfront_clearance = -1.0",
            "front_clearance",
        ),
        (
            "thickness = -1.0\nside_clearance_left = 5.0\nside_clearance_right = 5.0",
            "thickness",
        ),
        ("angle = 60.0", "does not apply to this kind of tool"),
        ("file = \"insert.obj\"", "applies to `kind = \"mesh\"` tools only"),
        ("mesh_axes = [\"+x\", \"+y\", \"+z\"]", "tool[0].mesh_axes"),
    ] {
        let text = base.replace(
            "reference = \"center\"",
            &format!("reference = \"center\"\n{extra}"),
        );
        let err = vpcut::Job::from_toml(&text, "job.toml").unwrap_err().to_string();
        assert!(err.contains(says), "{extra}: {err}");
    }
}

/// The 3D model colours the rub: no purple vertex with a cleared body; with the rubbing one,
/// purple vertices only where the helix angle has passed the clearance (past the turn
/// where the root's clearance crosses zero).
#[test]
fn the_model_shows_the_rub() {
    const BODY_RUB: [u8; 3] = [160, 40, 200];
    let scene = |text: &str| {
        let j = job(text);
        let out = run(text);
        vpcut::build_scene(&j, &out, &vpcut::SceneOptions::default())
    };
    let clear = scene(&screw(14.0, 14.0));
    assert!(!clear.stock.colors.contains(&BODY_RUB));
    let alpha = 8.0f64;
    let text = screw(alpha, 20.0);
    let j = job(&text);
    let rubbed = scene(&text);
    let purple: Vec<[f32; 3]> = rubbed
        .stock
        .positions
        .iter()
        .zip(&rubbed.stock.colors)
        .filter(|(_, c)| **c == BODY_RUB)
        .map(|(p, _)| *p)
        .collect();
    assert!(purple.len() > 100, "{} purple vertices", purple.len());
    // The thread's groove centre z(t) = -(F t + K t^2 / 2) at t* where the root clearance
    // crosses zero; the rub cannot come before (towards +z of) it, less one lead of margin
    // for the groove's width and the mesh.
    let law = j.thread.helix.law;
    let t_star = (TAU * j.thread.root_radius * alpha.to_radians().tan() - law.f) / law.k;
    let z_star = j.thread.helix.z(t_star);
    for p in &purple {
        assert!(
            (p[2] as f64) < z_star + 3.0,
            "rub at z {} before {z_star}",
            p[2]
        );
    }
}

/// The Tr scene's shim: with it (2 deg) the laydown insert clears both flanks and the cut
/// is seed 004's bit for bit; without it the leading flank rubs in every turn by the closed
/// form of the scene's README (0.0550 mm along the axis at phi = 0.095, r = 44.14, so
/// 0.0531 mm normal to the 15 deg flank), the trailing flank never.
#[test]
fn the_shim_clears_a_tr_insert() {
    let cells = [("simulation", "angular_cells", "720")];
    let shim = with(&scene_text("seed004-tr100x12-shim"), &cells);
    let plain = run(&with(&scene_text("seed004-tr100x12"), &cells));
    let shimmed = run(&shim);
    assert_eq!(plain.stock.outer, shimmed.stock.outer);
    assert_eq!(shimmed.report.interference, Some(vec![]));
    assert!(
        shimmed.edge_stock.is_none(),
        "a skipped body needs no second sweep"
    );
    let bare = run(&shim.replace("inclination = 2.0", "inclination = 0.0"));
    // In the drawn thread's turns the rub is on the -z flank, up to its top edge (rows of
    // the crest); the last 2 mm before the pass ends at Z-80, where the body's sections stop
    // with the pass and the edge leaves the groove, are the run-out's.
    let j = job(&shim);
    let rows: Vec<_> = bare
        .report
        .interference
        .as_ref()
        .unwrap()
        .iter()
        .filter(|r| (1..=j.thread.whole_turns()).contains(&r.turn) && r.z_mm > -78.0)
        .collect();
    assert!(
        rows.iter().all(|r| r.flank == "left" || r.flank == "crest"),
        "{rows:?}"
    );
    let left: Vec<_> = rows.iter().filter(|r| r.flank == "left").collect();
    for turn in 1..=j.thread.whole_turns() {
        assert!(
            left.iter().any(|r| r.turn == turn),
            "turn {turn} does not rub: {left:?}"
        );
    }
    for r in &left {
        // Two axial cells (0.01 mm) and the 0.005 mm sampling bound, as for seed 000's.
        assert!(
            (r.max_mm - 0.0531).abs() <= 0.025,
            "turn {}: {} mm at z {}",
            r.turn,
            r.max_mm,
            r.z_mm
        );
    }
    for t in &bare.report.turns {
        let c = t.clearance_deg.as_ref().unwrap();
        assert!((c.left_root - -1.5151).abs() < 1e-4, "{c:?}");
        assert!((c.right_crest - 3.1854).abs() < 1e-4, "{c:?}");
    }
}

/// An OBJ of the parametric insert (axes: x along the part, y the height above the tip, z
/// the depth behind the rake face; the origin at the tip centre): the edge section at z = 0
/// (tip `width` at y = 0, flanks at `left`/`right` deg from radial up to y = `top`), the same
/// section at z = `thickness` with the tip raised by the front clearance and each flank set
/// back by its side clearance, and the faces between. All faces are planes of the
/// parametric insert, so the mesh has no faceting error.
fn insert_obj(width: f64, flanks: [f64; 2], thickness: f64, sides: [f64; 2], front: f64) -> String {
    let top = 20.0;
    let (tl, tr) = (flanks[0].to_radians().tan(), flanks[1].to_radians().tan());
    let (sl, sr) = (sides[0].to_radians().tan(), sides[1].to_radians().tan());
    let (vl, vr) = (-width / 2.0, width / 2.0);
    let lift = thickness * front.to_radians().tan();
    // (V, H) at depth y: the tip at H = y tan(front), the flanks set back y tan(side).
    let section = |y: f64, h_tip: f64| {
        let (l, r) = (vl + y * sl, vr - y * sr);
        [
            (l - h_tip * tl, h_tip),
            (r + h_tip * tr, h_tip),
            (r + top * tr, top),
            (l - top * tl, top),
        ]
    };
    let mut obj = String::from("# the parametric insert as a mesh\n");
    for (y, h_tip) in [(0.0, 0.0), (thickness, lift)] {
        for (v, h) in section(y, h_tip) {
            obj += &format!("v {v:.15} {h:.15} {y:.15}\n");
        }
    }
    // Front 1-4, back 5-8; sides: tip (1 2 6 5), right (2 3 7 6), top (3 4 8 7), left (4 1 5 8).
    obj += "f 1 2 3 4\nf 8 7 6 5\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    obj
}

/// A mesh tool of the insert's shape cuts what the parametric insert cuts: the same edge
/// (to float rounding: the mesh's edge is its section at the rake face) and the same rub,
/// on seed 002's screw (groove and tool 5 mm) with 8 deg sides that the helix outgrows.
#[test]
fn a_mesh_insert_cuts_as_the_parametric_one() {
    let parametric = screw(8.0, 20.0);
    let obj = insert_obj(5.0, [0.0, 0.0], 4.0, [8.0, 20.0], 5.0);
    let mesh_tool = "kind = \"mesh\"\nfile = \"insert.obj\"\nmesh_origin = [0.0, 0.0, 0.0]\nmesh_axes = [\"+x\", \"+y\", \"+z\"]";
    let start = parametric.find("[[tool]]").unwrap();
    let end = parametric[start..].find("\n[").unwrap() + start;
    let text = format!(
        "{}[[tool]]\nid = 1\n{mesh_tool}\n{}",
        &parametric[..start],
        &parametric[end + 1..]
    );
    let load = |f: &str| (f == "insert.obj").then(|| obj.clone());
    let mesh_job =
        vpcut::Job::from_toml_with(&text, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(mesh_job.tools[0].edge, vpcut::Edge::Mesh { .. }));
    let a = run(&parametric);
    let b = vpcut::simulate(&mesh_job, &vpcut::SimOptions::default()).unwrap();
    // The edges alone: the same cut to float rounding, which may put a cell whose centre
    // lies on a flank on the other side (the mesh's planes are normalized): then the cell
    // beside it agrees.
    let (ea, eb) = (
        a.edge_stock.as_ref().unwrap(),
        b.edge_stock.as_ref().unwrap(),
    );
    let nz = ea.grid.n_z;
    let mut walls = 0;
    for (k, (x, y)) in ea.outer.iter().zip(&eb.outer).enumerate() {
        if (x - y).abs() <= 1e-4 {
            continue;
        }
        walls += 1;
        let j = k % nz;
        let beside = [j.wrapping_sub(1), j + 1]
            .into_iter()
            .filter(|&jj| jj < nz)
            .any(|jj| (x - eb.outer[k - j + jj]).abs() <= 1e-4);
        assert!(beside, "cell {k}: {x} vs {y}");
    }
    assert!(walls < ea.grid.dexels() / 1000, "{walls} cells differ");
    // The rub: the same turns and flanks, depths within the two sampling bounds.
    let bound = a.report.kernel.body_sampling_bound_mm.unwrap()
        + b.report.kernel.body_sampling_bound_mm.unwrap();
    let (ra, rb) = (
        a.report.interference.as_ref().unwrap(),
        b.report.interference.as_ref().unwrap(),
    );
    assert!(!ra.is_empty());
    assert_eq!(ra.len(), rb.len(), "{ra:?}\n{rb:?}");
    for (x, y) in ra.iter().zip(rb) {
        assert_eq!((x.turn, x.flank), (y.turn, y.flank));
        assert!(
            (x.max_mm - y.max_mm).abs() <= bound + 1e-4,
            "turn {}: {} vs {} mm",
            x.turn,
            x.max_mm,
            y.max_mm
        );
    }
}

#[test]
fn mesh_tool_errors_name_the_key() {
    let base = screw(8.0, 20.0);
    let start = base.find("[[tool]]").unwrap();
    let end = base[start..].find("\n[").unwrap() + start;
    let good = insert_obj(5.0, [0.0, 0.0], 4.0, [8.0, 20.0], 5.0);
    // The back corner of the tip on the +V side pulled out past the +V flank's plane.
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    let mut corner: Vec<f64> = lines[6][2..]
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    corner[0] += 0.7;
    lines[6] = format!("v {} {} {}", corner[0], corner[1], corner[2]);
    let dented = lines.join("\n");
    for (tool, obj, says) in [
        (
            "file = \"missing.obj\"",
            good.as_str(),
            "cannot read `missing.obj`",
        ),
        (
            "file = \"insert.obj\"\nmesh_axes = [\"+x\", \"+x\", \"+z\"]",
            &good,
            "each OBJ axis once",
        ),
        (
            "file = \"insert.obj\"\nmesh_units = \"cubit\"",
            &good,
            "mesh_units",
        ),
        (
            "file = \"insert.obj\"\nwidth = 3.0",
            &good,
            "does not apply to a mesh tool",
        ),
        (
            "file = \"insert.obj\"\nmesh_origin = [0.0, 1.0, 0.0]",
            &good,
            "the reference point must be on the tip",
        ),
        (
            "file = \"insert.obj\"\nmesh_origin = [0.0, 0.0, 1.0]",
            &good,
            "in front of it",
        ),
        (
            "file = \"insert.obj\"",
            "v 1 2\nf 1 2 3\n",
            "not a readable OBJ mesh",
        ),
        (
            "file = \"insert.obj\"",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "no volume",
        ),
        ("file = \"insert.obj\"", &dented, "not convex"),
    ] {
        let text = format!(
            "{}[[tool]]\nid = 1\nkind = \"mesh\"\n{tool}\n{}",
            &base[..start],
            &base[end + 1..]
        );
        let load = |f: &str| (f == "insert.obj").then(|| obj.to_string());
        let err = vpcut::Job::from_toml_with(&text, "job.toml", &load)
            .unwrap_err()
            .to_string();
        assert!(err.contains(says), "{tool}: {err}");
        assert!(
            crate::support::place(&err).starts_with("job.toml:"),
            "{err}"
        );
    }
}

/// Faceting: a mesh whose nose is a polygon of `n` chords inscribed in the round nose of a
/// threading tool (M20x2.5, 60 deg, nose radius 0.3) cuts no deeper than the round nose and
/// at most one sagitta `r (1 - cos(dtheta / 2))` less, measured radially from the nose's
/// centre; as a height above the tip that is at most `sagitta / cos 60` (the nose meets the
/// flanks at 60 deg from the bottom). Finer facets, closer cut.
#[test]
fn a_faceted_round_nose_cuts_within_its_sagitta() {
    let text = with(
        &scene_text("iso-m20x2.5-radial"),
        &[("simulation", "angular_cells", "180")],
    )
    .replace("tip_flat = 0.4166666667", "nose_radius = 0.3");
    let round_job = job(&text);
    assert!(matches!(
        round_job.tools[0].edge,
        vpcut::Edge::RoundV { .. }
    ));
    let round = vpcut::simulate(&round_job, &vpcut::SimOptions::default()).unwrap();
    let (r, reach) = (0.3f64, 60f64.to_radians());
    let tan30 = 30f64.to_radians().tan();
    let mut worst_by_n = Vec::new();
    for n in [8usize, 32] {
        // [H, V] around the profile: the -z flank's top, the nose's chords, the +z flank's top.
        let top = 3.0;
        let mut profile = Vec::new();
        let tangent = |theta: f64| [r - r * theta.cos(), r * theta.sin()];
        let [ht, vt] = tangent(-reach);
        profile.push([top, vt - (top - ht) * tan30]);
        for k in 0..=n {
            profile.push(tangent(-reach + 2.0 * reach * k as f64 / n as f64));
        }
        let [ht, vt] = tangent(reach);
        profile.push([top, vt + (top - ht) * tan30]);
        let (vertices, triangles) = vpcut::prism(&profile, &profile, 2.0);
        let solid = vpcut::Solid::from_mesh(&vertices, &triangles).unwrap();
        let mut mesh_job = round_job.clone();
        mesh_job.tools[0].edge = vpcut::Edge::Mesh {
            solid: std::sync::Arc::new(solid),
            body: false,
        };
        let mesh = vpcut::simulate(&mesh_job, &vpcut::SimOptions::default()).unwrap();
        let sagitta = r * (1.0 - (reach / n as f64).cos());
        let bound = sagitta / reach.cos();
        let (mut lo, mut hi) = (0f32, 0f32);
        for (m, o) in mesh.stock.outer.iter().zip(&round.stock.outer) {
            lo = lo.min(m - o);
            hi = hi.max(m - o);
        }
        assert!(
            lo > -1e-5,
            "n = {n}: the facets cut {lo} mm deeper than the nose"
        );
        assert!(
            (hi as f64) <= bound + 1e-5,
            "n = {n}: {hi} mm above the nose, bound {bound:.6}"
        );
        assert!(
            (hi as f64) >= 0.5 * sagitta,
            "n = {n}: {hi} (sagitta {sagitta:.6})"
        );
        worst_by_n.push(hi);
    }
    assert!(worst_by_n[1] < worst_by_n[0] / 8.0, "{worst_by_n:?}");
}

/// The head's `length`: seed 000 asks for a head 2 to 3 mm longer than the tooth (3 mm on
/// its 36/30 screw). A 2.5 mm head fails the last of the three radial layers (its tip runs
/// 3 mm below the blank's surface), and only it; 5.5 mm passes. A mesh's head is its own
/// height.
#[test]
fn a_head_shorter_than_the_cut_is_an_error() {
    let text = |length: &str| {
        scene_text("seed000-tool-clear").replace(
            "reference = \"center\"",
            &format!("reference = \"center\"\nlength = {length}"),
        )
    };
    let short = run(&with(
        &text("2.5"),
        &[("simulation", "angular_cells", "360")],
    ));
    let heads: Vec<_> = short
        .report
        .findings
        .iter()
        .filter(|f| f.kind == vpcut::FindingKind::HeadLength)
        .collect();
    assert_eq!(heads.len(), 1, "{heads:?}");
    assert_eq!(heads[0].severity, vpcut::Severity::Error);
    assert_eq!(heads[0].pass, Some(3));
    let depth = heads[0].value.expect("a depth");
    assert!((depth - 3.0).abs() < 1e-9, "{depth}");
    assert_eq!(short.report.verdict, vpcut::Verdict::Fail);
    let long = run(&with(
        &text("5.5"),
        &[("simulation", "angular_cells", "360")],
    ));
    assert!(long
        .report
        .findings
        .iter()
        .all(|f| f.kind != vpcut::FindingKind::HeadLength));
    let err = vpcut::Job::from_toml(&text("-1.0"), "job.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("length"), "{err}");
}
