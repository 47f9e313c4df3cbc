//! Every scene against its reviewed golden report and its hand-derived expectations.
//!
//! `goldens/<scene>/report.json` is the scene's report without `timing_s`, `vpcut_version` and
//! `inputs` (`support::report_json`); a change of any
//! byte fails (the new report is written beside it as `report.actual.json`), and
//! `VPCUT_BLESS=1` rewrites it. `goldens/<scene>/expect.toml` holds the numbers derived by
//! hand from the seed documents and closed forms, each with the reason; the golden must
//! satisfy them, so a golden is never just whatever the code printed.

use crate::support::{blessing, read, report_json, root, run_scene, scenes};
use serde_json::Value;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Expect {
    check: Vec<Check>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Check {
    path: String,
    value: Option<f64>,
    tol: Option<f64>,
    equals: Option<Value>,
    max: Option<f64>,
    min: Option<f64>,
    /// The length of an array.
    count: Option<usize>,
    why: String,
}

/// Look up `a.b[2].c` in a JSON value.
fn lookup<'a>(v: &'a Value, path: &str) -> Option<&'a Value> {
    let mut cur = v;
    for part in path.split('.') {
        let (name, idx) = match part.split_once('[') {
            Some((n, i)) => (n, Some(i.trim_end_matches(']').parse::<usize>().ok()?)),
            None => (part, None),
        };
        if !name.is_empty() {
            cur = cur.get(name)?;
        }
        if let Some(i) = idx {
            cur = cur.get(i)?;
        }
    }
    Some(cur)
}

fn check_expectations(scene: &str, report: &Value) -> Vec<String> {
    let path = root().join("goldens").join(scene).join("expect.toml");
    let Some(text) = read(&path) else {
        return vec![format!(
            "{scene}: no goldens/{scene}/expect.toml (hand-derived checks)"
        )];
    };
    let exp: Expect =
        toml_edit::de::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut bad = Vec::new();
    for c in &exp.check {
        let got = lookup(report, &c.path);
        let fail = |msg: String| format!("{scene}: {} {msg} ({})", c.path, c.why);
        match (got, c.value, &c.equals) {
            (None, _, _) => bad.push(fail("missing in the report".into())),
            (Some(g), Some(v), _) => match g.as_f64() {
                Some(x) if (x - v).abs() <= c.tol.unwrap_or(1e-9) => {}
                _ => bad.push(fail(format!(
                    "= {g}, expected {v} +- {}",
                    c.tol.unwrap_or(1e-9)
                ))),
            },
            (Some(g), None, Some(e)) => {
                // TOML has no null: the string "null" stands for it.
                let want = if *e == Value::String("null".into()) {
                    Value::Null
                } else {
                    e.clone()
                };
                if *g != want {
                    bad.push(fail(format!("= {g}, expected {want}")));
                }
            }
            (Some(g), None, None) if c.count.is_some() => {
                let n = g.as_array().map(Vec::len);
                if n != c.count {
                    bad.push(fail(format!("has {n:?} entries, expected {:?}", c.count)));
                }
            }
            (Some(g), None, None) => {
                let x = g.as_f64();
                if let Some(m) = c.max {
                    if x.is_none_or(|x| x > m) {
                        bad.push(fail(format!("= {g}, expected at most {m}")));
                    }
                }
                if let Some(m) = c.min {
                    if x.is_none_or(|x| x < m) {
                        bad.push(fail(format!("= {g}, expected at least {m}")));
                    }
                }
            }
        }
    }
    bad
}

#[test]
fn scenes_match_goldens_and_expectations() {
    let mut failures = Vec::new();
    for scene in scenes() {
        let out = run_scene(&scene);
        let report = report_json(&out);
        let mut text = serde_json::to_string_pretty(&report).unwrap();
        text.push('\n');
        let dir = root().join("goldens").join(&scene);
        let golden = dir.join("report.json");
        if blessing() {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&golden, &text).unwrap();
        }
        match read(&golden) {
            None => failures.push(format!(
                "{scene}: no golden report (run with VPCUT_BLESS=1, then review it)"
            )),
            Some(g) if g != text => {
                std::fs::write(dir.join("report.actual.json"), &text).unwrap();
                let gv: Value = serde_json::from_str(&g).unwrap();
                failures.push(format!(
                    "{scene}: report differs from the golden; first differences: {}",
                    diff(&gv, &report, "").join("; ")
                ));
            }
            Some(_) => {}
        }
        failures.extend(check_expectations(&scene, &report));
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

fn diff(a: &Value, b: &Value, at: &str) -> Vec<String> {
    let mut out = Vec::new();
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                match y.get(k) {
                    Some(w) => out.extend(diff(v, w, &format!("{at}.{k}"))),
                    None => out.push(format!("{at}.{k} removed")),
                }
            }
            for k in y.keys().filter(|k| !x.contains_key(*k)) {
                out.push(format!("{at}.{k} added"));
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                out.extend(diff(v, w, &format!("{at}[{i}]")));
            }
        }
        _ if a != b => out.push(format!("{at}: {a} -> {b}")),
        _ => {}
    }
    out.truncate(8);
    out
}
