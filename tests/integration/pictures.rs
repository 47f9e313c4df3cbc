//! Issue 29: the pictures and the page equal the report. For every scene, every number and
//! place the developed view, the trace, the renders' captions, the HTML page and the
//! `.glb`'s extras show is read back and compared with the report (its JSON as written):
//!
//! - the developed view: the worst value any pixel shows is the report's worst gouge and
//!   leftover, the rings sit on the report's places with its values, and the turn labels
//!   are the report's turn rows, every one;
//! - the trace, through the report's worst deviation by default: its marks carry the
//!   report's values, angles and places, and its curve at the mark reads that value;
//! - the page: the banner, the facts, every cell of every turn row and every field of
//!   every finding row (pass and source included) are the report's, and the section's and
//!   trace's captions name the angle they are drawn at;
//! - the model: its focus and summary are the report's worst and deviation;
//! - the renders' captions (no GPU needed): the close-up's label gives the report's worst
//!   (kind, turn, flank, angle, z, value), and a tool left out is said to be left out.
//!
//! Also: the tool is drawn as the solid the sweep cuts with (seed 000's insert body against
//! its closed form), rapids stay off the part, and no spot of the part is given as a
//! finding twice under two turns (random threads and start angles, seeded).

use crate::support::{job, run_scene, scene_job, scenes, Rng};
use serde_json::Value;
use vpcut::{
    build_scene, captions, developed_plot, finding_point, from_glb, section_angle, simulate,
    to_glb, to_html, trace_plot, FindingPlace, HtmlPage, HtmlPicture, Job, Outcome, PathKind,
    RenderOptions, SceneOptions, SimOptions, ToolpathMode, View,
};

/// The report as its JSON says it (the numbers as written).
fn report_value(out: &Outcome) -> Value {
    serde_json::from_str(&out.report.to_json()).unwrap()
}

/// A picture's value equals the report's written one: the report rounds to 1e-6 mm.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1.0e-6 + 1e-12
}

/// Two angles (deg) equal modulo 360 within `tol`.
fn same_angle(a: f64, b: f64, tol: f64) -> bool {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d) <= tol
}

/// The report's worst gouge and leftover beyond the tolerance: (value, place JSON).
fn worsts(r: &Value) -> [Option<(f64, Value)>; 2] {
    let tol = r["tolerance_mm"].as_f64().unwrap();
    let d = &r["deviation"];
    let one = |v: &str, at: &str| {
        let value = d[v].as_f64().unwrap();
        (value > tol).then(|| (value, d[at].clone()))
    };
    [
        one("max_gouge_mm", "max_gouge_at"),
        one("max_leftover_mm", "max_leftover_at"),
    ]
}

/// `&amp;` and friends back to text.
fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&amp;", "&")
}

/// The cells of a table row: `(data-v, text)`.
fn cells(row: &str) -> Vec<(Option<String>, String)> {
    let mut out = Vec::new();
    let mut rest = row;
    while let Some(at) = rest.find("<td") {
        let open_end = at + rest[at..].find('>').unwrap();
        let attrs = &rest[at..open_end];
        let close = open_end + rest[open_end..].find("</td>").unwrap();
        let text = unescape(&rest[open_end + 1..close]);
        let v = attrs.find("data-v=\"").map(|k| {
            let s = &attrs[k + 8..];
            s[..s.find('"').unwrap()].to_string()
        });
        out.push((v, text));
        rest = &rest[close + 5..];
    }
    out
}

/// The rows of the table `id` of a page, each from its `<tr` to its `</tr>`, body only.
fn rows<'a>(page: &'a str, id: &str) -> Vec<&'a str> {
    let at = page
        .find(&format!("<table id=\"{id}\""))
        .unwrap_or_else(|| panic!("no table {id}"));
    let body = &page[at..];
    let body = &body[body.find("<tbody>").unwrap()..body.find("</tbody>").unwrap()];
    body.split("<tr ")
        .skip(1)
        .map(|r| &r[..r.find("</tr>").unwrap()])
        .collect()
}

/// A number cell against the report's value (`null` is the dash).
fn check_number(what: &str, cell: &(Option<String>, String), want: &Value) {
    match want.as_f64() {
        Some(w) => {
            let v: f64 = cell.0.as_deref().unwrap_or("").parse().unwrap_or_else(|_| {
                panic!("{what}: no number in the cell, the report has {w}");
            });
            assert_eq!(v, w, "{what}: the page {v}, the report {w}");
        }
        None => assert!(
            cell.0.as_deref().unwrap_or("").is_empty(),
            "{what}: the page {:?}, the report none",
            cell.0
        ),
    }
}

/// The page of a simulated scene, as `simulate --html` writes it (with stand-in PNGs).
fn page(job: &Job, out: &Outcome, angle: f64) -> String {
    let scene = build_scene(
        job,
        out,
        &SceneOptions {
            mesh_tolerance: None,
            ideal: true,
        },
    );
    let places: Vec<FindingPlace> = out
        .report
        .findings
        .iter()
        .map(|f| FindingPlace {
            point: finding_point(out, job, f),
        })
        .collect();
    let deg = angle.to_degrees().rem_euclid(360.0);
    let pic = |caption: String| HtmlPicture {
        caption,
        png: vec![0x89, b'P', b'N', b'G'],
    };
    let plots = [
        pic("developed view".into()),
        pic(format!("axial section at {deg:.1}\u{b0}")),
        pic(format!(
            "deviation along z on the generators at {deg:.1}\u{b0}"
        )),
    ];
    to_html(&HtmlPage {
        report: &out.report,
        scene: &scene,
        places: &places,
        plots: &plots,
        renders: &[],
        note: None,
    })
}

/// The page's numbers and places against the report: banner, facts, turn rows, findings.
fn check_page(name: &str, page: &str, r: &Value) {
    // The banner.
    let c = &r["finding_counts"];
    let banner = format!(
        "{} error{}, {} warning{}; worst gouge {} mm, worst leftover {} mm (tolerance {} mm)",
        c["errors"],
        if c["errors"] == 1 { "" } else { "s" },
        c["warnings"],
        if c["warnings"] == 1 { "" } else { "s" },
        r["deviation"]["max_gouge_mm"].as_f64().unwrap(),
        r["deviation"]["max_leftover_mm"].as_f64().unwrap(),
        r["tolerance_mm"].as_f64().unwrap(),
    );
    assert!(page.contains(&banner), "{name}: banner without {banner}");
    for (fact, key) in [
        ("worst gouge mm", "max_gouge_mm"),
        ("worst leftover mm", "max_leftover_mm"),
    ] {
        let want = format!(
            "<dt>{fact}</dt><dd>{}</dd>",
            r["deviation"][key].as_f64().unwrap()
        );
        assert!(page.contains(&want), "{name}: no {want}");
    }
    // The turn rows: every cell is the report's.
    let turns = r["turns"].as_array().unwrap();
    let trs = rows(page, "turns");
    assert_eq!(trs.len(), turns.len(), "{name}: turn rows");
    for (tr, t) in trs.iter().zip(turns) {
        let c = cells(tr);
        let fl = &t["flanks"];
        let want: Vec<(&str, &Value)> = vec![
            ("turn", &t["turn"]),
            ("start", &t["start"]),
            ("lead ideal", &t["ideal_lead_mm"]),
            ("lead", &t["measured_lead_mm"]),
            ("lead err", &t["lead_spread"]["max_error_mm"]),
            ("groove ideal", &t["ideal_groove_width_mm"]),
            ("groove", &t["groove_width_mm"]),
            ("tooth ideal", &t["ideal_tooth_width_mm"]),
            ("tooth", &t["tooth_width_mm"]),
            ("min dia", &t["min_diameter_mm"]),
            ("max dia", &t["max_diameter_mm"]),
            ("helix", &t["helix_angle_deg"]),
            ("gouge", &t["max_gouge_mm"]),
            ("leftover", &t["max_leftover_mm"]),
            ("left g", &fl["left"]["max_gouge_mm"]),
            ("left l", &fl["left"]["max_leftover_mm"]),
            ("right g", &fl["right"]["max_gouge_mm"]),
            ("right l", &fl["right"]["max_leftover_mm"]),
            ("root g", &fl["root"]["max_gouge_mm"]),
            ("root l", &fl["root"]["max_leftover_mm"]),
            ("crest g", &fl["crest"]["max_gouge_mm"]),
            ("crest l", &fl["crest"]["max_leftover_mm"]),
            ("gouge mm3", &t["gouge_volume_mm3"]),
            ("leftover mm3", &t["leftover_volume_mm3"]),
        ];
        assert_eq!(c.len(), want.len(), "{name}: turn {} cells", t["turn"]);
        for (cell, (what, v)) in c.iter().zip(want) {
            check_number(&format!("{name} turn {} {what}", t["turn"]), cell, v);
        }
    }
    // The note over the turn rows names the reference angle the row's widths are at.
    let note = format!(
        "at the reference angle {}\u{b0}",
        r["measurement"]["reference_angle_deg"].as_f64().unwrap()
    );
    assert!(page.contains(&note), "{name}: no {note}");
    // The findings: every field.
    let findings = r["findings"].as_array().unwrap();
    let trs = rows(page, "findings");
    assert_eq!(trs.len(), findings.len(), "{name}: finding rows");
    for (k, (tr, f)) in trs.iter().zip(findings).enumerate() {
        let c = cells(tr);
        let what = |s: &str| format!("{name} finding {k} {s}");
        assert_eq!(c.len(), 13, "{}", what("cells"));
        assert_eq!(
            c[1].1,
            f["severity"].as_str().unwrap(),
            "{}",
            what("severity")
        );
        assert_eq!(c[2].1, f["kind"].as_str().unwrap(), "{}", what("kind"));
        check_number(&what("turn"), &c[3], &f["turn"]);
        check_number(&what("start"), &c[4], &f["start"]);
        assert_eq!(
            c[5].1,
            f["flank"].as_str().unwrap_or(""),
            "{}",
            what("flank")
        );
        check_number(&what("angle"), &c[6], &f["angle_deg"]);
        check_number(&what("z"), &c[7], &f["z_mm"]);
        check_number(&what("value"), &c[8], &f["value"]);
        assert_eq!(c[9].1, f["unit"].as_str().unwrap_or(""), "{}", what("unit"));
        check_number(&what("pass"), &c[10], &f["pass"]);
        let source = match (&f["file"], &f["line"], &f["key"]) {
            (Value::String(file), Value::Number(line), _) => match f["column"].as_u64() {
                Some(col) => format!("{file}:{line}:{col}"),
                None => format!("{file}:{line}"),
            },
            (_, _, Value::String(key)) => format!("job key {key}"),
            _ => String::new(),
        };
        assert_eq!(c[11].1, source, "{}", what("source"));
        assert_eq!(
            c[12].1,
            f["message"].as_str().unwrap(),
            "{}",
            what("message")
        );
        // A turn's finding has a source: every finding names its block or job key.
        if !f["turn"].is_null() {
            assert!(!source.is_empty(), "{}", what("no source"));
        }
    }
}

/// Every scene: the developed view, the trace, the page, the model's extras and the renders'
/// captions against the report.
#[test]
fn every_picture_and_the_page_equal_the_report() {
    let mut checked_marks = 0;
    for name in scenes() {
        let job = scene_job(&name);
        let out = run_scene(&name);
        let r = report_value(&out);
        let tol = job.sim.tolerance;
        let worst = worsts(&r);
        let grid = out.stock.grid;

        // The developed view.
        let plot = developed_plot(
            &out.stock,
            &job.thread,
            &out.deviation,
            tol,
            1200,
            800,
            &name,
        );
        let d = &r["deviation"];
        if d["compared_dexels"].as_u64().unwrap() > 0 {
            for (k, key, sign) in [(0, "max_gouge_mm", -1.0), (1, "max_leftover_mm", 1.0)] {
                let want = d[key].as_f64().unwrap();
                let got = plot.shown[k].map_or(0.0, |v| sign * v);
                assert!(
                    same(got, want),
                    "{name}: the developed view's worst {key} {got}, the report's {want}"
                );
            }
        }
        let [x0, y0, x1, y1] = plot.field;
        let (z_bot, z_top) = plot.z;
        for (k, sign) in [(0, -1.0), (1, 1.0)] {
            match (&worst[k], plot.worst[k]) {
                (None, None) => {}
                (Some((v, at)), Some((rv, [x, y]))) => {
                    assert!(same(rv, sign * v), "{name}: ring {rv} vs {v}");
                    let a = at["angle_deg"].as_f64().unwrap();
                    let z = at["z_mm"].as_f64().unwrap();
                    let ex = x0 as f64 + a / 360.0 * (x1 - x0) as f64;
                    let ey = y0 as f64 + (z_top - z) / (z_top - z_bot) * (y1 - y0) as f64;
                    assert!(
                        (x as f64 - ex).abs() <= 1.5 && (y as f64 - ey).abs() <= 1.5,
                        "{name}: ring at {x},{y}, the report's place at {ex:.1},{ey:.1}"
                    );
                }
                (w, p) => panic!("{name}: report {w:?}, ring {p:?}"),
            }
        }
        let mut labels: Vec<(i64, u32)> = plot.turn_labels.iter().map(|l| (l.0, l.1)).collect();
        labels.sort_unstable();
        let mut want: Vec<(i64, u32)> = r["turns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                (
                    t["turn"].as_i64().unwrap(),
                    t["start"].as_u64().unwrap() as u32 + 1,
                )
            })
            .collect();
        want.sort_unstable();
        assert_eq!(labels, want, "{name}: the developed view's turn labels");

        // The trace, through the report's worst by default.
        let angle = section_angle(&out.deviation, &grid, tol);
        let trace = trace_plot(
            &out.stock,
            &job.thread,
            &out.deviation,
            angle,
            tol,
            1200,
            500,
            &name,
        );
        assert!(same_angle(trace.generators[0], angle.to_degrees(), 1e-9));
        let worse = match (&worst[0], &worst[1]) {
            (Some(g), Some(l)) => Some(if l.0 > g.0 { 1 } else { 0 }),
            (Some(_), None) => Some(0),
            (None, Some(_)) => Some(1),
            _ => None,
        };
        for (k, sign) in [(0, -1.0), (1, 1.0)] {
            match (&worst[k], trace.worst[k]) {
                (None, None) => {}
                (Some((v, at)), Some(m)) => {
                    assert!(
                        same(m.value, sign * v),
                        "{name}: trace mark {} vs {v}",
                        m.value
                    );
                    assert!(same(m.z, at["z_mm"].as_f64().unwrap()), "{name}: z");
                    assert!(
                        same_angle(m.angle_deg, at["angle_deg"].as_f64().unwrap(), 5e-5),
                        "{name}: angle {} vs {}",
                        m.angle_deg,
                        at["angle_deg"]
                    );
                    if worse == Some(k) {
                        let (g, _) = m.on.unwrap_or_else(|| {
                            panic!("{name}: the worst is not on the trace at its own angle")
                        });
                        assert_eq!(g, 0, "{name}: the worst on the first generator");
                    }
                    if let Some((g, [x, y])) = m.on {
                        // The curve as drawn reads the value there.
                        // (A flat's place is the middle of its dexels: a cell's centre
                        // or half way between two, which read the same.)
                        let read = trace.curves[g]
                            .iter()
                            .filter(|p| (p.0 - m.z).abs() <= 0.5 * grid.dz + 1e-9)
                            .map(|p| p.1)
                            .min_by(|a, b| (a - m.value).abs().total_cmp(&(b - m.value).abs()))
                            .unwrap_or_else(|| panic!("{name}: no curve at z {}", m.z));
                        assert!(
                            (read - m.value).abs() <= 2e-6,
                            "{name}: the curve reads {read} where the mark says {}",
                            m.value
                        );
                        let [fx0, fy0, fx1, fy1] = trace.field;
                        assert!((fx0..fx1).contains(&x) && (fy0..fy1).contains(&y));
                        let ey = fy0 as f64
                            + (trace.d.1 - m.value) / (trace.d.1 - trace.d.0) * (fy1 - fy0) as f64;
                        assert!((y as f64 - ey).abs() <= 1.5, "{name}: mark's y");
                        checked_marks += 1;
                    }
                }
                (w, m) => panic!("{name}: report {w:?}, trace mark {m:?}"),
            }
        }

        // The page.
        let html = page(&job, &out, angle);
        check_page(&name, &html, &r);

        // The model's extras: the focus is the report's worst, the summary its deviation.
        let scene = build_scene(
            &job,
            &out,
            &SceneOptions {
                mesh_tolerance: None,
                ideal: false,
            },
        );
        let back = from_glb(&to_glb(&scene).unwrap()).unwrap();
        let summary: Value = serde_json::from_str(&back.summary).unwrap();
        assert_eq!(
            summary["deviation"], r["deviation"],
            "{name}: model summary"
        );
        assert_eq!(summary["verdict"], r["verdict"], "{name}: model verdict");
        match (worse, &back.focus) {
            (None, None) => {}
            (Some(k), Some(f)) => {
                let (v, at) = worst[k].clone().unwrap();
                assert_eq!(f.kind, ["gouge", "leftover"][k], "{name}");
                assert!(same(f.value_mm, v), "{name}: focus {} vs {v}", f.value_mm);
                assert_eq!(f.turn, at["turn"].as_i64().unwrap(), "{name}");
                assert_eq!(f.flank, at["flank"].as_str().unwrap(), "{name}");
                assert_eq!(f.z_mm, at["z_mm"].as_f64().unwrap(), "{name}");
                assert_eq!(f.angle_deg, at["angle_deg"].as_f64().unwrap(), "{name}");
            }
            (w, f) => panic!("{name}: worst {w:?}, focus {f:?}"),
        }

        // The renders' words.
        for view in View::ALL {
            let opts = RenderOptions {
                view,
                width: 640,
                height: 480,
                edges: false,
                toolpath: ToolpathMode::Auto,
            };
            let c = captions(&scene, &opts);
            let internal = r["thread"]["side"] == "internal";
            assert_eq!(c.tool_drawn, !internal && !scene.tool.indices.is_empty());
            assert_eq!(
                c.title.contains("tool not drawn"),
                !c.tool_drawn && !scene.tool.indices.is_empty(),
                "{name} {}: {}",
                view.name(),
                c.title
            );
            if view == View::Closeup {
                match (worse, &c.marker) {
                    (None, None) => {}
                    (Some(k), Some(label)) => {
                        let (v, at) = worst[k].clone().unwrap();
                        let flank = match at["flank"].as_str().unwrap() {
                            f @ ("left" | "right") => format!(" {f} flank"),
                            f => format!(" {f}"),
                        };
                        let want = format!(
                            "worst {}: turn {}{flank}, {:.1}\u{b0}, z {:.3} mm, {v} mm",
                            ["gouge", "leftover"][k],
                            at["turn"],
                            at["angle_deg"].as_f64().unwrap(),
                            at["z_mm"].as_f64().unwrap(),
                        );
                        assert!(label.starts_with(&want), "{name}: {label} vs {want}");
                    }
                    (w, m) => panic!("{name}: worst {w:?}, label {m:?}"),
                }
            }
        }
    }
    assert!(checked_marks >= 5, "{checked_marks} marks checked");
}

/// A drift between a picture and the report fails the comparison: the page of one scene
/// with one turn row's value, one finding's pass and one finding's source changed.
#[test]
fn a_drifted_page_fails_the_comparison() {
    let name = "seed002-equal-tooth";
    let job = scene_job(name);
    let out = run_scene(name);
    let r = report_value(&out);
    let html = page(&job, &out, 0.0);
    check_page(name, &html, &r);
    let row = rows(&html, "turns")[2];
    let v = r["turns"][2]["max_gouge_mm"].as_f64().unwrap();
    let drifted = html.replacen(
        row,
        &row.replacen(&format!("data-v=\"{v}\""), "data-v=\"1.25\"", 1),
        1,
    );
    assert_ne!(drifted, html);
    let r2 = r.clone();
    assert!(std::panic::catch_unwind(|| check_page(name, &drifted, &r2)).is_err());
    let mut moved = r.clone();
    moved["findings"][0]["pass"] = serde_json::json!(99);
    assert!(std::panic::catch_unwind(|| check_page(name, &html, &moved)).is_err());
    let mut moved = r.clone();
    moved["findings"][0]["key"] = serde_json::json!("pass[3]");
    assert!(std::panic::catch_unwind(|| check_page(name, &html, &moved)).is_err());
}

/// Seed 000's rubbing insert is drawn as the solid the sweep cuts with: width 3 mm at the
/// rake face, 4 mm thick behind it, its -z flank set back `y tan 11 deg` and its +z flank
/// standing out `y tan 1 deg` at depth `y` (side clearances 11 and -1 deg), its tip raised
/// `y tan 5 deg` (front clearance 5): at the back (y = 4) the tip is 3 - 0.7775 + 0.0698 =
/// 2.2923 mm wide and 0.3500 mm up. A closed surface.
#[test]
fn the_tool_is_the_solid_the_sweep_cuts_with() {
    let name = "seed000-tool-rub";
    let job = scene_job(name);
    let out = run_scene(name);
    let scene = build_scene(
        &job,
        &out,
        &SceneOptions {
            mesh_tolerance: None,
            ideal: false,
        },
    );
    let m = &scene.tool;
    assert!(m.triangles() >= 8);
    // Closed: every edge of two triangles, once each way (positions merged).
    let key = |p: [f32; 3]| p.map(|c| (c * 1e4).round() as i64);
    let mut edges = std::collections::BTreeMap::<([i64; 3], [i64; 3]), i32>::new();
    for t in m.indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (pa, pb) = (key(m.positions[a as usize]), key(m.positions[b as usize]));
            if pa == pb {
                continue;
            }
            *edges.entry((pa, pb)).or_default() += 1;
            *edges.entry((pb, pa)).or_default() -= 1;
        }
    }
    assert!(
        edges.values().all(|&n| n == 0),
        "the tool's surface is not closed"
    );
    // The tool frame: radial `e_r` at the tool's angle, tangential `e_t` behind the rake.
    let pts: Vec<[f64; 3]> = m.positions.iter().map(|p| p.map(f64::from)).collect();
    let lowest = pts
        .iter()
        .copied()
        .min_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])))
        .unwrap();
    let theta = lowest[1].atan2(lowest[0]);
    let (er, et) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
    let frame: Vec<[f64; 3]> = pts
        .iter()
        .map(|p| {
            [
                p[0] * er[0] + p[1] * er[1],
                p[0] * et[0] + p[1] * et[1],
                p[2],
            ]
        })
        .collect();
    let r_tip = frame.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
    let ys: Vec<f64> = frame.iter().map(|p| p[1]).collect();
    let (y_lo, y_hi) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    assert!(
        ((y_hi - y_lo) - 4.0).abs() < 1e-4,
        "thickness {}",
        y_hi - y_lo
    );
    // The rake face is the end nearest... the tip's width there is the edge's 3 mm; at the
    // back the closed forms above.
    let width_at = |y: f64| {
        let tip: Vec<f64> = frame
            .iter()
            .filter(|p| (p[1] - y).abs() < 1e-4 && (p[0] - frame_tip(&frame, y)).abs() < 1e-4)
            .map(|p| p[2])
            .collect();
        tip.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - tip.iter().copied().fold(f64::INFINITY, f64::min)
    };
    let (rake, back) = if (frame_tip(&frame, y_lo) - r_tip).abs() < 1e-6 {
        (y_lo, y_hi)
    } else {
        (y_hi, y_lo)
    };
    assert!((frame_tip(&frame, rake) - r_tip).abs() < 1e-5);
    assert!(
        (width_at(rake) - 3.0).abs() < 1e-4,
        "rake {}",
        width_at(rake)
    );
    let back_width = 3.0 - 4.0 * 11f64.to_radians().tan() + 4.0 * 1f64.to_radians().tan();
    assert!(
        (width_at(back) - back_width).abs() < 1e-4,
        "back {} vs {back_width}",
        width_at(back)
    );
    let rise = 4.0 * 5f64.to_radians().tan();
    assert!(
        ((frame_tip(&frame, back) - r_tip) - rise).abs() < 1e-4,
        "rise {} vs {rise}",
        frame_tip(&frame, back) - r_tip
    );
}

/// The lowest radius of the tool's points at tangential depth `y`.
fn frame_tip(frame: &[[f64; 3]], y: f64) -> f64 {
    frame
        .iter()
        .filter(|p| (p[1] - y).abs() < 1e-4)
        .map(|p| p[0])
        .fold(f64::INFINITY, f64::min)
}

/// Rapids are drawn off the part: every point between a rapid's ends lies on the clearance
/// radius outside the blank (inside the bore), and its segments run either along the axis
/// at one angle or around at one z, so no view draws one across the part's outline.
#[test]
fn rapids_stay_off_the_part() {
    let mut rapids = 0;
    for name in scenes() {
        let job = scene_job(&name);
        if job.mill.is_some() {
            continue;
        }
        let out = run_scene(&name);
        let scene = build_scene(
            &job,
            &out,
            &SceneOptions {
                mesh_tolerance: None,
                ideal: false,
            },
        );
        let outside = job.thread.side == vpcut::Side::External;
        for p in scene.toolpath.iter().filter(|p| p.kind == PathKind::Rapid) {
            rapids += 1;
            let inner = &p.points[1..p.points.len() - 1];
            for q in inner {
                let r = f64::from(q[0]).hypot(f64::from(q[1]));
                if outside {
                    assert!(r > job.blank.diameter / 2.0, "{name}: rapid at r {r}");
                } else {
                    assert!(r < job.blank.bore / 2.0, "{name}: rapid at r {r}");
                }
            }
            for w in inner.windows(2) {
                let (a, b) = (w[0], w[1]);
                let axial = (a[0] - b[0]).abs() < 1e-4 && (a[1] - b[1]).abs() < 1e-4;
                let around = (a[2] - b[2]).abs() < 1e-4;
                assert!(axial || around, "{name}: a rapid segment {a:?} {b:?}");
            }
        }
    }
    assert!(rapids > 10, "{rapids}");
}

/// One finding per place: random square threads (variable lead, either hand, either
/// spindle direction, any start angle, 180 to 720 columns) cut by `[process] radial` with a
/// defect along the whole thread (the root left too shallow, or a tool narrower than the
/// groove: both walls left standing), then no two of the report's deviation findings lie on
/// one spot (columns within 1.5 and cells within 2, across the 0/360 deg join), and every
/// per-turn extreme beyond the tolerance is given, or is at the spot of a larger one of the
/// adjacent turn that is. A root too shallow all across (the same value everywhere) is
/// given half a turn from each turn's start, where no turns meet.
#[test]
fn one_finding_per_place() {
    let mut rng = Rng(2929);
    let mut cases = 0;
    let mut met = 0;
    for _ in 0..24 {
        let first = rng.range(5.0, 9.0);
        let k = rng.pick(&[0.0, 0.5, 1.0, 2.0]);
        let turns = rng.pick(&[3, 4]);
        let start = rng.range(0.0, 360.0);
        let n_theta = rng.pick(&[180, 360, 720]);
        let dz = rng.pick(&[0.02, 0.025, 0.04]);
        let hand = rng.pick(&["right", "left"]);
        let spindle = rng.pick(&["cw", "ccw"]);
        let shallow = rng.range(0.0, 1.0) < 0.5;
        let groove = 3.0;
        let (tool, depth) = if shallow {
            (groove, 2.0 - rng.range(0.05, 0.4))
        } else {
            (groove - 2.0 * rng.range(0.05, 0.4), 2.0)
        };
        let toml = format!(
            r#"
            [blank]
            diameter = 30.0
            length = 120.0
            z_front = 10.0
            [thread]
            form = "square"
            major_diameter = 30.0
            minor_diameter = 26.0
            pitch = {{ first = {first}, increment = {k}, turns = {turns} }}
            width = {{ groove = {groove} }}
            z_start = 0.0
            start_angle = {start}
            hand = "{hand}"
            [[tool]]
            id = 1
            kind = "grooving"
            width = {tool}
            reference = "center"
            [process]
            kind = "radial"
            tool = 1
            depths = [{depth}]
            [machine]
            spindle = "{spindle}"
            [simulation]
            axial_spacing = {dz}
            angular_cells = {n_theta}
            tolerance = 0.02
            measure_generators = 2
            "#
        );
        let j = job(&toml);
        let out = simulate(&j, &SimOptions::default()).unwrap();
        let grid = out.stock.grid;
        let tol = j.sim.tolerance;
        let places = out.deviation.places(tol, &grid);
        assert!(!places.is_empty(), "{toml}: no defect");
        cases += 1;
        let spot = |a: &vpcut::Extreme, b: &vpcut::Extreme| {
            let d = (a.theta - b.theta).rem_euclid(std::f64::consts::TAU);
            let gap = d.min(std::f64::consts::TAU - d);
            gap <= 1.5 * grid.dtheta() + 1e-9 && (a.z - b.z).abs() <= 2.0 * grid.dz + 1e-9
        };
        for (i, a) in places.iter().enumerate() {
            for b in &places[i + 1..] {
                assert!(
                    a.gouge != b.gouge || !spot(&a.extreme, &b.extreme),
                    "{toml}: one spot given twice: {a:?} {b:?}"
                );
            }
        }
        // Nothing beyond the tolerance is lost.
        for td in out.deviation.turns.values() {
            for (gouge, slots) in [(true, &td.gouge), (false, &td.leftover)] {
                for e in slots.iter().flatten().filter(|e| e.value > tol) {
                    let given = places.iter().any(|p| {
                        p.gouge == gouge
                            && (p.extreme == *e
                                || (spot(&p.extreme, e)
                                    && p.extreme.value >= e.value
                                    && p.also == Some(e.turn)))
                    });
                    assert!(given, "{toml}: {e:?} lost");
                }
            }
        }
        met += places.iter().filter(|p| p.also.is_some()).count();
        // A root too shallow all across: every turn's root leftover half a turn from its
        // start (its groove half way through its turn), where no turns meet.
        if shallow {
            for td in out.deviation.turns.values() {
                let e = td.leftover[vpcut::Flank::Root.index()].expect("a root too shallow");
                assert!(
                    (e.turn_fraction - 0.5).abs() <= 1.0 / n_theta as f64 + 1e-9,
                    "{toml}: the root leftover at {} of its turn",
                    e.turn_fraction
                );
            }
        }
    }
    assert_eq!(cases, 24);
    eprintln!("one_finding_per_place: {met} spots where two turns' worst met, given once");
}
