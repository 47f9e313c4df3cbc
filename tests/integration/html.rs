//! The HTML report without a browser (`tests/browser/check.sh` opens it in one): the page is
//! self-contained (no address outside it), holds the verdict, every turn row and every
//! finding of the report; the pass the report gives a gouge or leftover is the first pass
//! after which the dexel is as deep as it ends; program jobs name the pass's NC block; the
//! CLI writes the page for the biggest seed scene under 15 MB. (`pictures.rs` reads every
//! scene's page back against its report.)

use crate::support::{root, run_scene, scene_job};
use std::process::Command;
use vpcut::{
    build_scene, finding_point, sweep_column, to_html, Column, FindingKind, FindingPlace, Flank,
    HtmlPage, HtmlPicture, Outcome, SceneOptions, Surface,
};

/// The page of a simulated scene, with a stand-in picture.
fn page(name: &str) -> (Outcome, Vec<FindingPlace>, String) {
    let job = scene_job(name);
    let out = run_scene(name);
    let scene = build_scene(
        &job,
        &out,
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
            point: finding_point(&out, &job, f),
        })
        .collect();
    let pic = HtmlPicture {
        caption: "a <picture> & its caption".into(),
        png: vec![0x89, b'P', b'N', b'G'],
    };
    let html = to_html(&HtmlPage {
        report: &out.report,
        scene: &scene,
        places: &places,
        plots: std::slice::from_ref(&pic),
        renders: &[],
        note: Some("no adapter"),
    });
    (out, places, html)
}

/// Every `src=`/`href=` value of a page: none may leave it.
fn assert_self_contained(html: &str) {
    for attr in ["src=", "href=", "url("] {
        for (at, _) in html.match_indices(attr) {
            let v = &html[at + attr.len()..(at + attr.len() + 12).min(html.len())];
            let v = v.trim_start_matches(['"', '\'']);
            assert!(
                v.starts_with("data:") || v.starts_with('#'),
                "{attr}{v}... leaves the page"
            );
        }
    }
    for needle in ["http://", "https://", "<link", "@import", "<iframe"] {
        assert!(!html.contains(needle), "the page contains {needle}");
    }
}

#[test]
fn page_is_self_contained_and_holds_the_report() {
    let (out, places, html) = page("seed002-equal-tooth");
    let r = &out.report;
    assert_self_contained(&html);
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.contains("<div id=\"verdict\" class=\"verdict fail\">FAIL"));
    assert!(html.contains("a &lt;picture&gt; &amp; its caption"));
    assert!(html.contains("src=\"data:image/png;base64,iVBORw==\""));
    // Every turn row, with its deviations.
    assert_eq!(html.matches("<tr data-turn=").count(), r.turns.len());
    for t in &r.turns {
        let at = html
            .find(&format!(
                "<tr data-turn=\"{}\" data-start=\"{}\">",
                t.turn, t.start
            ))
            .unwrap_or_else(|| panic!("turn {} has no row", t.turn));
        let row = &html[at..at + html[at..].find("</tr>").unwrap()];
        for v in [t.max_gouge_mm, t.max_leftover_mm, t.gouge_volume_mm3] {
            assert!(
                row.contains(&format!("data-v=\"{v}\"")),
                "turn {}: {v}",
                t.turn
            );
        }
        // Beyond tolerance is marked.
        let bad = format!("data-v=\"{}\" class=\"bad\"", t.max_gouge_mm);
        assert_eq!(row.contains(&bad), t.max_gouge_mm > r.tolerance_mm, "{row}");
    }
    // Every finding, in the report's order, with its message and pass.
    assert_eq!(html.matches("<tr data-i=").count(), r.findings.len());
    assert!(!r.findings.is_empty());
    for (k, f) in r.findings.iter().enumerate() {
        let at = html
            .find(&format!("<tr data-i=\"{k}\" "))
            .unwrap_or_else(|| panic!("finding {k} has no row"));
        let row = &html[at..at + html[at..].find("</tr>").unwrap()];
        assert!(
            row.contains(&format!("<td>{}</td>", f.kind.name())),
            "{row}"
        );
        assert!(row.contains(&f.message.replace('<', "&lt;")), "{row}");
        if let Some(v) = f.value {
            assert!(row.contains(&format!("data-v=\"{v}\"")), "{row}");
        }
        if let Some(p) = f.pass {
            assert!(row.contains(&format!("data-v=\"{p}\"")), "{row}");
        }
        // A gouge was cut by some pass.
        if f.kind == FindingKind::Gouge {
            assert!(f.pass.is_some(), "finding {k} has no pass");
        }
        if matches!(f.kind, FindingKind::Gouge | FindingKind::Leftover) {
            assert!(places[k].point.is_some(), "finding {k} has no place");
            assert!(row.contains("data-point=\""), "finding {k} has no place");
        }
    }
    // The report embedded as data, the scene as base64.
    assert!(html.contains("<script type=\"application/json\" id=\"report-data\">{"));
    assert!(html.contains("<script type=\"text/plain\" id=\"scene-data\">"));
}

/// The report's pass of a gouge or leftover (the page shows it) is the first after which
/// the dexel is as deep as it ends: the passes before it leave it shallower, those up to
/// it reach its final value.
#[test]
fn the_pass_of_a_finding_is_the_one_that_cut_it() {
    for name in ["seed002-equal-tooth", "seed002-siemens-equal-groove"] {
        let job = scene_job(name);
        if job.mill.is_some() {
            continue;
        }
        let out = run_scene(name);
        let g = out.stock.grid;
        let mut checked = 0;
        for f in &out.report.findings {
            if !matches!(f.kind, FindingKind::Gouge | FindingKind::Leftover) {
                continue;
            }
            // The exact place of the extreme the finding reports.
            let td = &out.deviation.turns[&(f.start.unwrap(), f.turn.unwrap())];
            let k = Flank::ALL.iter().position(|&x| Some(x) == f.flank).unwrap();
            let e = match f.kind {
                FindingKind::Gouge => td.gouge[k],
                _ => td.leftover[k],
            }
            .unwrap();
            let d = (e.theta.to_degrees() - f.angle_deg.unwrap()).rem_euclid(360.0);
            assert!(d.min(360.0 - d) < 0.051, "{}: {d} deg off", f.message);
            let z = e.z;
            let t = (e.theta - g.theta0).rem_euclid(std::f64::consts::TAU);
            let i = (t / g.dtheta()).round() as usize % g.n_theta;
            let j = ((z - g.z0) / g.dz).round() as usize;
            let fin = out.stock.outer[i * g.n_z + j];
            let Some(pass) = f.pass else {
                assert!(
                    fin >= 0.0,
                    "{name}: {}: a cut dexel without a pass",
                    f.message
                );
                continue;
            };
            let c = Column {
                theta: g.theta(i),
                z0: g.z0,
                dz: g.dz,
                q_blank: out.stock.blank_q(Surface::Outer),
                surface: Surface::Outer,
            };
            let cut = |n: usize| {
                let mut col = vec![0f32; g.n_z];
                sweep_column(&mut col, c, &job.passes[..n], &job.tools);
                col[j]
            };
            let k = pass - 1;
            assert!(
                (cut(k + 1) - fin).abs() < 1e-5,
                "{name}: {}: passes 1..={pass} cut {} not {fin}",
                f.message,
                cut(k + 1)
            );
            assert!(
                cut(k) > fin + 1e-6,
                "{name}: {}: the passes before {pass} already cut {}",
                f.message,
                cut(k)
            );
            checked += 1;
        }
        assert!(checked > 0, "{name}: no finding with a pass");
    }
}

/// A program's findings name the thread block of their pass.
#[test]
fn program_findings_name_the_nc_block() {
    let name = "seed002-siemens-equal-tooth";
    let job = scene_job(name);
    assert!(!job.pass_blocks.is_empty());
    let out = run_scene(name);
    let blocks: Vec<_> = out
        .report
        .findings
        .iter()
        .filter_map(|f| Some((f.file.clone()?, f.line?)))
        .collect();
    assert!(!blocks.is_empty());
    let dir = root().join("scenes").join(name);
    for (file, line) in blocks {
        let text = std::fs::read_to_string(dir.join(&file)).unwrap();
        assert!(line >= 1 && line <= text.lines().count(), "{file}:{line}");
    }
}

/// `simulate --html` for the biggest seed scene: one file, under 15 MB, self-contained,
/// with the same verdict as the report written beside it.
#[test]
fn cli_writes_the_page() {
    let dir = std::env::temp_dir().join(format!("vpcut-html-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let html = dir.join("r.html");
    let json = dir.join("r.json");
    let job = root().join("scenes/seed004-tr100x12/job.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args(["simulate", "-q", "--html"])
        .arg(&html)
        .arg("--report")
        .arg(&json)
        .arg(&job)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(&html).unwrap();
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(page.len() < 15_000_000, "{} bytes", page.len());
    assert_self_contained(&page);
    let verdict = report["verdict"].as_str().unwrap();
    assert!(page.contains(&format!("class=\"verdict {verdict}\"")));
    assert_eq!(
        page.matches("<tr data-turn=").count(),
        report["turns"].as_array().unwrap().len()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
