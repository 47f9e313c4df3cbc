//! The HTML report: one self-contained page (no network, no third-party code) with the
//! verdict, the job and the thread, the per-turn table with the cells beyond tolerance
//! marked, the sortable findings (each with the pass and the NC block or job key the
//! report gives it), the pictures as `data:` PNGs, and a WebGL2 view of the cut part
//! written for this page (`html/viewer.js`).
//!
//! Every number and place on the page is the report's, written as the report writes it:
//! the page works nothing out again (`tests/integration/pictures.rs` reads the page back
//! against the report for every scene).
//!
//! The tables are written here as HTML, so the page reads without scripts; the 3D scene is
//! embedded as base64 of flat little-endian arrays (positions `f32`, sRGB colours `u8`,
//! indices `u32`, 4-byte aligned) described by a small JSON header. Pure: the caller writes
//! the returned text.

mod place;

pub use place::finding_point;

use crate::output::scene::{Mesh, PathKind, Scene};
use crate::report::{r6, Finding, Report};
use std::fmt::Write as _;

const TEMPLATE: &str = include_str!("html/page.html");
const STYLE: &str = include_str!("html/style.css");
const PAGE_JS: &str = include_str!("html/page.js");
const VIEWER_JS: &str = include_str!("html/viewer.js");

/// A picture on the page: its caption and PNG bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct HtmlPicture {
    /// Caption.
    pub caption: String,
    /// The PNG file's bytes.
    pub png: Vec<u8>,
}

/// Where a finding is on the cut part, beside the report's own fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FindingPlace {
    /// Its point on the cut surface (mm, part frame; [`finding_point`]), where the 3D view
    /// flies to.
    pub point: Option<[f32; 3]>,
}

/// What the page shows.
#[derive(Clone, Copy, Debug)]
pub struct HtmlPage<'a> {
    /// The report (complete: inputs named).
    pub report: &'a Report,
    /// The 3D scene (with the ideal for its toggle).
    pub scene: &'a Scene,
    /// One per finding of the report, in its order (missing ones have no place).
    pub places: &'a [FindingPlace],
    /// The plots (no GPU).
    pub plots: &'a [HtmlPicture],
    /// The renders (a GPU adapter); empty without one.
    pub renders: &'a [HtmlPicture],
    /// A line on why something is missing (no adapter), shown under the pictures.
    pub note: Option<&'a str>,
}

/// Escape text for HTML content and attribute values.
pub(crate) fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

/// Standard base64 with padding.
pub(crate) fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut o = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        o.push(A[(n >> 18) as usize & 63] as char);
        o.push(A[(n >> 12) as usize & 63] as char);
        o.push(if c.len() > 1 {
            A[(n >> 6) as usize & 63] as char
        } else {
            '='
        });
        o.push(if c.len() > 2 {
            A[n as usize & 63] as char
        } else {
            '='
        });
    }
    o
}

/// JSON text safe inside a `<script>` element.
fn script_json(v: &serde_json::Value) -> String {
    v.to_string()
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

/// A number as the report writes it (shortest round-trip form), or a dash.
fn num(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v}"),
        _ => "\u{2013}".into(),
    }
}

/// A table cell with a number; `bad` marks it beyond tolerance.
fn cell(s: &mut String, x: Option<f64>, bad: bool) {
    let class = if bad { " class=\"bad\"" } else { "" };
    let v = x
        .filter(|v| v.is_finite())
        .map_or(String::new(), |v| format!("{v}"));
    let _ = write!(s, "<td data-v=\"{v}\"{class}>{}</td>", num(x));
}

/// The flat arrays of the scene and the header that finds them.
fn scene_data(scene: &Scene) -> (serde_json::Value, Vec<u8>) {
    use serde_json::json;
    let mut bin: Vec<u8> = Vec::new();
    fn align(bin: &mut Vec<u8>) -> usize {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        bin.len()
    }
    let mesh = |m: &Mesh, bin: &mut Vec<u8>| {
        let pos = align(bin);
        for p in &m.positions {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let col = align(bin);
        for c in &m.colors {
            bin.extend_from_slice(c);
        }
        let idx = align(bin);
        for i in &m.indices {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        json!({"n": m.positions.len(), "pos": pos, "col": col, "idx": idx, "ni": m.indices.len()})
    };
    let stock = mesh(&scene.stock, &mut bin);
    let ideal = scene.ideal.as_ref().map(|m| mesh(m, &mut bin));
    let lines_at = align(&mut bin);
    let mut strips = Vec::new();
    let mut at = 0usize;
    for l in &scene.toolpath {
        for p in &l.points {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        let kind = match l.kind {
            PathKind::Feed => 0,
            PathKind::Rapid => 1,
        };
        strips.push(json!([at, l.points.len(), kind]));
        at += l.points.len();
    }
    let bounds = scene.stock.bounds().map(|(lo, hi)| json!([lo, hi]));
    // The renders' rule decides how the toolpath shows at first (the toggle stays).
    let (path_look, path_cover) = crate::output::render::default_toolpath_look(scene);
    let focus = scene
        .focus
        .as_ref()
        .map(|f| json!({"kind": f.kind, "value_mm": f.value_mm, "point": f.point}));
    let header = json!({
        "stock": stock,
        "ideal": ideal,
        "lines": {"pos": lines_at, "n": at, "strips": strips},
        "bounds": bounds,
        "legend": {"tolerance_mm": scene.legend.tolerance_mm, "scale_mm": scene.legend.scale_mm},
        "toolpath": {"look": path_look, "coverage": r6(path_cover)},
        "internal": crate::output::render::is_internal(scene),
        "focus": focus,
        "bytes": bin.len(),
    });
    (header, bin)
}

/// The job, the thread and the totals as a definition list.
fn summary(r: &Report) -> String {
    let t = &r.thread;
    let d = &r.deviation;
    let mut s = String::from("<dl class=\"facts\">");
    let mut fact = |k: &str, v: String| {
        let _ = write!(s, "<dt>{}</dt><dd>{}</dd>", esc(k), esc(&v));
    };
    fact("job", r.job.clone());
    for i in &r.inputs {
        fact(&format!("{} file", i.role), i.path.clone());
    }
    fact(
        "thread",
        format!(
            "{} {} {}-hand, {} start{}",
            t.side,
            t.form,
            t.hand,
            t.starts,
            if t.starts == 1 { "" } else { "s" }
        ),
    );
    fact(
        "diameters mm",
        format!(
            "major {} / pitch {} / minor {}",
            t.major_diameter_mm, t.pitch_diameter_mm, t.minor_diameter_mm
        ),
    );
    fact(
        "lead mm",
        format!(
            "{} at the start, {} per revolution; {} turns",
            t.lead_at_start_mm, t.lead_change_mm, t.turns
        ),
    );
    fact(
        "constant width",
        format!("{} {} mm", t.constant_width, t.width_mm),
    );
    fact("tolerance mm", format!("{}", r.tolerance_mm));
    fact("passes", format!("{}", r.passes));
    fact(
        "grid",
        format!(
            "{} x {} cells at {} mm ({} dexels)",
            r.stock.angular_cells, r.stock.axial_cells, r.stock.axial_spacing_mm, r.stock.dexels
        ),
    );
    fact("worst gouge mm", format!("{}", d.max_gouge_mm));
    fact("worst leftover mm", format!("{}", d.max_leftover_mm));
    fact(
        "volumes mm\u{b3}",
        format!(
            "gouge {} / leftover {} / removed {} (ideal {})",
            d.gouge_volume_mm3,
            d.leftover_volume_mm3,
            d.removed_volume_mm3,
            d.ideal_removed_volume_mm3
        ),
    );
    if let Some(g) = &r.gauge {
        fact(
            "gauges",
            format!(
                "{}: {} (resolution {} mm)",
                g.designation, g.verdict, g.resolution_mm
            ),
        );
        for e in &g.elements {
            fact(
                &format!("{} ({}) mm", e.element.replace('_', " "), e.limit),
                format!(
                    "{} against {}: {}",
                    e.value_mm.map_or("-".to_string(), |v| v.to_string()),
                    e.limit_mm,
                    e.verdict
                ),
            );
        }
        if let Some(t) = g.taper {
            fact(
                "taper gauge",
                format!(
                    "the {} stands {:+.3} turns off the gauge plane (allowed \u{b1}{}, resolution {} turns): the cut's pitch cone {} mm there, basic {} mm",
                    t.gauge,
                    t.stand_off_turns,
                    t.tolerance_turns,
                    t.resolution_turns,
                    t.pitch_diameter_at_gauge_plane_mm,
                    t.basic_pitch_diameter_mm
                ),
            );
        }
        if let (Some(v), Some(t)) = (g.not_go_simple_diameter_mm, g.not_go_simple_turn) {
            fact(
                "NOT GO as single elements mm",
                format!(
                    "simple pitch diameter {v} (turns from {t}); the gauge's truncated profile touches within {} mm of its pitch line",
                    g.not_go_band_mm
                ),
            );
        }
        if let Some(w) = g.over_wires {
            fact(
                "over three wires mm",
                format!(
                    "{} .. {} over {} mm wires",
                    w.measurement_mm.min, w.measurement_mm.max, w.wire_mm
                ),
            );
        }
    }
    fact("vpcut", r.vpcut_version.to_string());
    s.push_str("</dl>");
    s
}

/// Whether a measured value is off its drawing's by more than the tolerance (the rule the
/// report's lead and width findings apply; the row's are the reference angle's).
fn off(value: Option<f64>, ideal: Option<f64>, tol: f64) -> bool {
    matches!((value, ideal), (Some(v), Some(i)) if (v - i).abs() > tol)
}

/// The per-turn table, with a caption that says where its leads and widths are measured.
fn turns_table(r: &Report) -> String {
    let tol = r.tolerance_mm;
    let m = &r.measurement;
    let mut s = format!(
        "<p class=\"note\">Leads and widths of each turn as measured at the reference angle \
         {}\u{b0} (a variable lead's drawing widths change along a turn); \"lead err\" is \
         the largest over the {} measured angles. The findings give the worst angle's \
         values, with the angle.</p>",
        m.reference_angle_deg, m.generators
    );
    s.push_str(
        "<table id=\"turns\" class=\"sortable\"><thead><tr>\
         <th>turn</th><th>start</th><th>lead ideal</th><th>lead</th><th>lead err (all gen.)</th>\
         <th>groove ideal</th><th>groove</th><th>tooth ideal</th><th>tooth</th>\
         <th>min dia</th><th>max dia</th><th>helix deg</th>\
         <th>gouge</th><th>leftover</th>\
         <th>left g</th><th>left l</th><th>right g</th><th>right l</th>\
         <th>root g</th><th>root l</th><th>crest g</th><th>crest l</th>\
         <th>gouge mm\u{b3}</th><th>leftover mm\u{b3}</th></tr></thead><tbody>\n",
    );
    for t in &r.turns {
        let _ = write!(
            s,
            "<tr data-turn=\"{}\" data-start=\"{}\">",
            t.turn, t.start
        );
        cell(&mut s, Some(t.turn as f64), false);
        cell(&mut s, Some(f64::from(t.start)), false);
        cell(&mut s, t.ideal_lead_mm, false);
        cell(
            &mut s,
            t.measured_lead_mm,
            off(t.measured_lead_mm, t.ideal_lead_mm, tol),
        );
        cell(
            &mut s,
            t.lead_spread.max_error_mm,
            t.lead_spread.max_error_mm.is_some_and(|e| e > tol),
        );
        cell(&mut s, t.ideal_groove_width_mm, false);
        cell(
            &mut s,
            t.groove_width_mm,
            off(t.groove_width_mm, t.ideal_groove_width_mm, tol),
        );
        cell(&mut s, t.ideal_tooth_width_mm, false);
        cell(
            &mut s,
            t.tooth_width_mm,
            off(t.tooth_width_mm, t.ideal_tooth_width_mm, tol),
        );
        cell(&mut s, t.min_diameter_mm, false);
        cell(&mut s, t.max_diameter_mm, false);
        cell(&mut s, Some(t.helix_angle_deg), false);
        let dev = |s: &mut String, x: f64| cell(s, Some(x), x > tol);
        dev(&mut s, t.max_gouge_mm);
        dev(&mut s, t.max_leftover_mm);
        for f in [
            &t.flanks.left,
            &t.flanks.right,
            &t.flanks.root,
            &t.flanks.crest,
        ] {
            dev(&mut s, f.max_gouge_mm);
            dev(&mut s, f.max_leftover_mm);
        }
        cell(&mut s, Some(t.gouge_volume_mm3), false);
        cell(&mut s, Some(t.leftover_volume_mm3), false);
        s.push_str("</tr>\n");
    }
    s.push_str("</tbody></table>");
    s
}

/// The findings table: every finding, the pass that made it, and the point to fly to.
fn findings_table(r: &Report, places: &[FindingPlace]) -> String {
    let mut s = String::from(
        "<table id=\"findings\" class=\"sortable\"><thead><tr>\
         <th>#</th><th>severity</th><th>kind</th><th>turn</th><th>start</th><th>flank</th>\
         <th>angle deg</th><th>z mm</th><th>value</th><th>unit</th><th>pass</th>\
         <th>source</th><th>message</th></tr></thead><tbody>\n",
    );
    let none = FindingPlace::default();
    for (k, f) in r.findings.iter().enumerate() {
        let place = places.get(k).unwrap_or(&none);
        row(&mut s, k, f, place);
    }
    s.push_str("</tbody></table>");
    s
}

/// One finding's row.
fn row(s: &mut String, k: usize, f: &Finding, place: &FindingPlace) {
    let sev = crate::analysis::findings::severity_name(f.severity);
    let point = place.point.map_or(String::new(), |p| {
        format!(" data-point=\"{},{},{}\"", p[0], p[1], p[2])
    });
    let _ = write!(s, "<tr data-i=\"{k}\" class=\"{sev}\"{point}>");
    cell(s, Some(k as f64 + 1.0), false);
    let _ = write!(s, "<td>{sev}</td><td>{}</td>", f.kind.name());
    cell(s, f.turn.map(|t| t as f64), false);
    cell(s, f.start.map(f64::from), false);
    let _ = write!(s, "<td>{}</td>", f.flank.map_or("", |f| f.name()));
    cell(s, f.angle_deg, false);
    cell(s, f.z_mm, false);
    cell(s, f.value, false);
    let _ = write!(s, "<td>{}</td>", f.unit.unwrap_or(""));
    // The pass and the source are the report's (`report::blame`): the NC block of the pass
    // or turning move that cut the place, else the job key.
    cell(s, f.pass.map(|p| p as f64), false);
    let _ = writeln!(
        s,
        "<td>{}</td><td>{}</td></tr>",
        esc(&source(f)),
        esc(&f.message)
    );
}

/// Where a finding comes from, as the report says: `file:line:column` of its NC block,
/// else the job file's key (`job key process`), else nothing.
fn source(f: &Finding) -> String {
    match (&f.file, f.line, &f.key) {
        (Some(file), Some(line), _) => match f.column {
            Some(c) => format!("{file}:{line}:{c}"),
            None => format!("{file}:{line}"),
        },
        (_, _, Some(key)) => format!("job key {key}"),
        _ => String::new(),
    }
}

/// Pictures as figures with `data:` PNGs.
fn figures(s: &mut String, pics: &[HtmlPicture]) {
    for p in pics {
        let _ = write!(
            s,
            "<figure><img alt=\"{c}\" src=\"data:image/png;base64,{}\"><figcaption>{c}</figcaption></figure>",
            base64(&p.png),
            c = esc(&p.caption)
        );
    }
}

/// The colours of the 3D view as swatches: the plots' tolerance bands and the 3D greys
/// (the one colour map of every picture).
fn legend(scene: &Scene) -> String {
    use crate::output::plot::chart::{BAND_EDGES, GOUGE_BANDS, LEFTOVER_BANDS, WITHIN};
    use crate::output::plot::{BLANK, BODY_RUB, CUT_NOT_COMPARED, IDEAL_COLOUR};
    let tol = scene.legend.tolerance_mm;
    let swatch = |c: [u8; 3], what: &str| {
        format!(
            "<span class=\"swatch\" style=\"background:rgb({},{},{})\"></span> {}",
            c[0],
            c[1],
            c[2],
            esc(what)
        )
    };
    let band = |k: usize| {
        let (a, b) = (BAND_EDGES[k], BAND_EDGES.get(k + 1));
        match b {
            Some(b) => format!("{a}-{b}x"),
            None => format!("over {a}x"),
        }
    };
    let mut items = vec![swatch(WITHIN, &format!("within {tol} mm"))];
    for (k, c) in GOUGE_BANDS.iter().enumerate() {
        items.push(swatch(*c, &format!("gouge {}", band(k))));
    }
    for (k, c) in LEFTOVER_BANDS.iter().enumerate() {
        items.push(swatch(*c, &format!("leftover {}", band(k))));
    }
    items.push(swatch(BLANK, "uncut blank, end faces"));
    items.push(swatch(CUT_NOT_COMPARED, "cut, not compared"));
    if scene.stock.colors.contains(&BODY_RUB) {
        items.push(swatch(BODY_RUB, "body rub"));
    }
    items.push(swatch(IDEAL_COLOUR, "ideal"));
    format!(
        "Colours (bands of the tolerance, as in the plots): {}.",
        items.join(", ")
    )
}

/// The page.
pub fn to_html(page: &HtmlPage) -> String {
    let r = page.report;
    let verdict = match r.verdict {
        crate::report::Verdict::Pass => "pass",
        crate::report::Verdict::Fail => "fail",
    };
    let banner = format!(
        "<div id=\"verdict\" class=\"verdict {verdict}\">{} <span>{} error{}, {} warning{}; worst gouge {} mm, worst leftover {} mm (tolerance {} mm)</span></div>",
        verdict.to_uppercase(),
        r.finding_counts.errors,
        if r.finding_counts.errors == 1 { "" } else { "s" },
        r.finding_counts.warnings,
        if r.finding_counts.warnings == 1 { "" } else { "s" },
        r.deviation.max_gouge_mm,
        r.deviation.max_leftover_mm,
        r.tolerance_mm,
    );
    let mut pictures = String::new();
    figures(&mut pictures, page.plots);
    figures(&mut pictures, page.renders);
    if let Some(n) = page.note {
        let _ = write!(pictures, "<p class=\"note\">{}</p>", esc(n));
    }
    let (header, bin) = scene_data(page.scene);
    let report_json: serde_json::Value = serde_json::to_value(r).unwrap_or(serde_json::Value::Null);
    let title = if r.job.is_empty() {
        "vpcut report".to_string()
    } else {
        format!("vpcut report: {}", r.job)
    };
    fill(
        TEMPLATE,
        &[
            ("title", esc(&title)),
            ("style", STYLE.to_string()),
            ("verdict", banner),
            ("summary", summary(r)),
            ("turns", turns_table(r)),
            ("findings", findings_table(r, page.places)),
            ("pictures", pictures),
            ("legend", legend(page.scene)),
            ("page_js", PAGE_JS.to_string()),
            ("viewer_js", VIEWER_JS.to_string()),
            ("scene_header", script_json(&header)),
            ("report_json", script_json(&report_json)),
            ("scene_data", base64(&bin)),
        ],
    )
}

/// The template with each `{{key}}` replaced by its value, in one pass (values are never
/// searched for keys).
fn fill(template: &str, values: &[(&str, String)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(at) = rest.find("{{") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        match after.find("}}").and_then(|end| {
            values
                .iter()
                .find(|v| v.0 == &after[..end])
                .map(|v| (end, v))
        }) {
            Some((end, v)) => {
                out.push_str(&v.1);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn escapes() {
        assert_eq!(
            esc("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
        let j = script_json(&serde_json::json!({"m": "</script>"}));
        assert!(!j.contains("</script>"));
    }
}
