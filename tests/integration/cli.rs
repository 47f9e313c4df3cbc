//! The command line: exit codes, error messages that name file, line and key, atomic output.

use crate::support::{scene_text, small, with};
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

fn tmp_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "vpcut-cli-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn vpcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args(args)
        .output()
        .unwrap()
}

/// Write a job, run `simulate` on it with a report path, return (output, job path, report path).
fn simulate_text(text: &str, extra: &[&str]) -> (Output, PathBuf, PathBuf) {
    let d = tmp_dir();
    let job = d.join("job.toml");
    std::fs::write(&job, text).unwrap();
    let report = d.join("report.json");
    let mut args = vec![
        "simulate",
        job.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "-q",
    ];
    args.extend_from_slice(extra);
    (vpcut(&args), job, report)
}

const BASE: &str = r#"[blank]
diameter = 28.0
length = 100.0

[thread]
form = "square"
major_diameter = 28.0
minor_diameter = 22.0
pitch = { first = 7.0, increment = 1.5, last = 16.0 }
width = { tooth = 3.0 }

[[tool]]
id = 1
kind = "grooving"
width = 3.0

[[pass]]
tool = 1
x = 22.0
z_start = 5.0
z_end = -80.0
lead = 4.0
lead_change = 1.5
"#;

/// Each malformed job: the text to replace in `BASE`, its replacement, and what the error
/// must say (file:line:col and the key or the problem).
#[test]
fn bad_jobs_exit_2_naming_file_line_and_key() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "length = 100.0",
            "length = 100.0\nwidht = 3",
            &["job.toml:4:1", "unknown field `widht`"],
        ),
        (
            "form = \"square\"\n",
            "",
            &["`thread.form`", "missing: expected `form`"],
        ),
        (
            "width = { tooth = 3.0 }",
            "width = { tooth = 8.0 }",
            &[
                "job.toml:10:19",
                "`thread.width.tooth`",
                "narrower than the first pitch",
            ],
        ),
        (
            "lead = 4.0",
            "lead = -4.0",
            &["job.toml:22:8", "`pass[0].lead`", "> 0"],
        ),
        (
            "lead_change = 1.5\n",
            "lead_change = -1.5\n",
            &["job.toml:23:15", "`pass[0].lead_change`", "reach zero"],
        ),
        ("x = 22.0", "x = nan", &["`pass[0].x`", "finite"]),
        (
            "tool = 1\nx",
            "tool = 2\nx",
            &["`pass[0].tool`", "no [[tool]] with id 2"],
        ),
        (
            "form = \"square\"",
            "form = \"round\"",
            &["job.toml:6:8", "unknown variant `round`"],
        ),
        (
            "diameter = 28.0",
            "diameter = \"28\"",
            &["job.toml:2:12", "`blank.diameter`", "expected a number"],
        ),
    ];
    for (from, to, wants) in cases {
        assert!(BASE.contains(from), "{from}");
        let (out, _, report) = simulate_text(&BASE.replacen(from, to, 1), &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{to}: {err}");
        for w in *wants {
            assert!(err.contains(w), "{to}: wanted {w:?} in:\n{err}");
        }
        assert!(!err.contains("panicked"), "{err}");
        assert!(!report.exists(), "a failed run left {}", report.display());
    }
}

#[test]
fn tool_wider_than_the_groove_is_refused() {
    let text = with(&scene_text("seed002-equal-groove-radial"), &[])
        .replace("width = 5.0\nreference", "width = 5.5\nreference");
    let (out, _, _) = simulate_text(&text, &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("`process.tool`") && err.contains("wider than the groove"),
        "{err}"
    );
}

#[test]
fn dexel_budget_is_checked_before_allocating() {
    let (out, _, report) = simulate_text(&small("iso-m20x2.5-radial"), &["--max-dexels", "1000"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("over the budget of 4.00 kB (1000 dexels of 4 bytes)"),
        "{err}"
    );
    assert!(!report.exists());
}

#[test]
fn check_flag_exits_1_on_fail_and_0_on_pass() {
    let (out, _, report) = simulate_text(&small("seed002-equal-groove"), &["--check"]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["verdict"], "fail");
    assert_eq!(r["schema"], "vpcut.report/1");
    let (out, _, _) = simulate_text(&small("seed002-equal-groove"), &[]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "without --check a fail verdict is still a success"
    );
    let (out, _, _) = simulate_text(&small("iso-m20x2.5-radial"), &["--check"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn unwritable_report_path_exits_2() {
    let d = tmp_dir();
    let job = d.join("job.toml");
    std::fs::write(&job, small("iso-m20x2.5-radial")).unwrap();
    let out = vpcut(&[
        "simulate",
        job.to_str().unwrap(),
        "--report",
        "/nonexistent-dir/r.json",
        "-q",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("cannot write"), "{err}");
}

#[test]
fn missing_job_file_exits_2() {
    let out = vpcut(&["simulate", "/nonexistent/job.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read the job file"));
}

#[test]
fn summary_names_verdict_and_worst_places() {
    let d = tmp_dir();
    let job = d.join("job.toml");
    std::fs::write(&job, small("seed002-equal-tooth")).unwrap();
    let out = vpcut(&["simulate", job.to_str().unwrap()]);
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(s.contains("FAIL"), "{s}");
    assert!(
        s.contains("worst gouge") && s.contains("worst leftover"),
        "{s}"
    );
    assert!(s.contains("turn  lead: ideal measured"), "{s}");
}

/// M04 with a feed toward the chuck cuts a left-hand helix: on a right-hand drawing that is
/// an error finding naming the pass.
#[test]
fn wrong_hand_is_a_finding() {
    let text = with(
        &small("iso-m20x2.5-radial"),
        &[("machine", "spindle", "\"ccw\"")],
    );
    // The generator follows the spindle (it feeds toward +z with M04): still right-hand.
    let (out, _, report) = simulate_text(&text, &["--check"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["verdict"], "pass");
    // Explicit passes toward -z with M04 cut a left-hand helix.
    let text = with(
        &small("equal-groove-single-pass"),
        &[("machine", "spindle", "\"ccw\"")],
    );
    let (out, _, report) = simulate_text(&text, &["--check"]);
    assert_eq!(out.status.code(), Some(1));
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let f = &r["findings"][0];
    assert_eq!(f["kind"], "hand", "{f}");
    assert!(
        f["message"].as_str().unwrap().contains("left-hand helix"),
        "{f}"
    );
}

/// The report records the version, the input files with their SHA-256, the findings
/// counted by severity, and program findings with file, line and column and no value.
#[test]
fn report_names_version_inputs_and_counts() {
    use sha2::Digest as _;
    let scene = crate::support::root().join("scenes/seed000-macro-a-equal-tooth");
    let d = tmp_dir();
    let report = d.join("r.json");
    let out = vpcut(&[
        "simulate",
        scene.join("job.toml").to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["vpcut_version"], env!("CARGO_PKG_VERSION"));
    let hex = |p: &std::path::Path| {
        sha2::Sha256::digest(std::fs::read(p).unwrap())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<String>()
    };
    let inputs = r["inputs"].as_array().unwrap();
    assert_eq!(inputs.len(), 2, "{inputs:?}");
    assert_eq!(inputs[0]["role"], "job");
    assert_eq!(inputs[0]["sha256"], hex(&scene.join("job.toml")));
    assert_eq!(inputs[1]["role"], "program");
    assert_eq!(inputs[1]["path"], "O0003.NC");
    assert_eq!(inputs[1]["sha256"], hex(&scene.join("O0003.NC")));
    let findings = r["findings"].as_array().unwrap();
    let count = |s: &str| findings.iter().filter(|f| f["severity"] == s).count();
    assert_eq!(r["finding_counts"]["errors"], count("error"));
    assert_eq!(r["finding_counts"]["warnings"], count("warning"));
    let program: Vec<_> = findings.iter().filter(|f| f["kind"] == "program").collect();
    assert_eq!(program.len(), 3);
    for f in program {
        assert_eq!(f["file"], "O0003.NC", "{f}");
        assert!(f["line"].as_u64().unwrap() >= 1 && f["column"].as_u64().unwrap() >= 1);
        assert!(f.get("value").is_none() && f.get("unit").is_none(), "{f}");
    }
}

/// Numbers in messages are readable: a huge grid is "more than 1.8e19" dexels, never the
/// 20 digits of a capped count or hundreds of digits of a float.
#[test]
fn messages_print_numbers_readably() {
    for (key, value) in [("axial_spacing", "1e-300"), ("angular_cells", "100000000")] {
        let text = with(&small("iso-m20x2.5-radial"), &[("simulation", key, value)]);
        let (out, _, _) = simulate_text(&text, &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        let longest = err
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest <= 10, "{key} = {value}: {err}");
    }
}
