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

/// `vpcut check --report-dir R` then `--changed-since R`: a job whose files (the job, its
/// program, the subprogram found on its `subroutine_path`) all keep their SHA-256 is not
/// run and its outcome stands in the JUnit and SARIF (the same testcases, failures and
/// results, marked `unchanged_since`; a failing job still exits 1); a changed subprogram,
/// a subprogram that appears where the interpreter looks first, another vpcut version or
/// other options run the job again; the same bytes rewritten do not. A missing folder or
/// a record that is not one is an error (exit 2) naming it.
#[test]
fn check_changed_since_runs_only_changed_jobs() {
    let d = tmp_dir();
    let lcnc = "[blank]\ndiameter = 24.0\nlength = 40.0\nz_front = 0.0\n\n[thread]\nside = \"external\"\nform = \"iso-metric\"\nmajor_diameter = 24.0\npitch = 1.5\nturns = 10\nz_start = 0.0\n\n[[tool]]\nid = 1\nkind = \"threading\"\nangle = 60.0\ntip_flat = 0.1875\nreference = \"tip\"\n\n[program]\nfile = \"main.ngc\"\ndialect = \"linuxcnc\"\nsubroutine_path = [\"macros\"]\n\n[simulation]\nangular_cells = 72\naxial_spacing = 0.05\nmeasure_generators = 2\n";
    let main = "G18 G21 G7 G95\nG0 X26 Z5 S300 M3\no<pass> call [22.2]\nM2\n";
    let pass = "o<pass> sub\nG0 X#1 Z5\nG33 Z-15 K1.5\nG0 X26\nG0 Z5\no<pass> endsub\n";
    std::fs::create_dir_all(d.join("a/macros")).unwrap();
    std::fs::create_dir_all(d.join("b")).unwrap();
    std::fs::write(d.join("a/job.toml"), lcnc).unwrap();
    std::fs::write(d.join("a/main.ngc"), main).unwrap();
    std::fs::write(d.join("a/macros/pass.ngc"), pass).unwrap();
    std::fs::write(d.join("b/job.toml"), small("seed002-equal-groove")).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["check", "-q", "--junit", "-", "--sarif", "out.sarif"];
        args.extend_from_slice(extra);
        args.extend(["a/job.toml", "b/job.toml"]);
        let out = Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .current_dir(&d)
            .args(&args)
            .output()
            .unwrap();
        let sarif = std::fs::read_to_string(d.join("out.sarif")).unwrap_or_default();
        (out, sarif)
    };
    // Which jobs were carried: the suites' files with an `unchanged_since` property.
    let carried = |junit: &str| -> Vec<String> {
        junit
            .split("<testsuite ")
            .skip(1)
            .filter(|s| {
                s.split("</testsuite>")
                    .next()
                    .unwrap()
                    .contains("unchanged_since")
            })
            .map(|s| {
                s.split("file=\"")
                    .nth(1)
                    .unwrap()
                    .split('"')
                    .next()
                    .unwrap()
                    .to_string()
            })
            .collect()
    };
    // The JUnit and SARIF without times and the carried marks.
    let plain = |text: &str| -> String {
        text.lines()
            .filter(|l| !l.contains("unchanged_since"))
            .map(|l| match l.find(" time=\"") {
                Some(i) => l[..i].to_string(),
                None => l.to_string(),
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let (first, sarif1) = run(&["--report-dir", "rec"]);
    assert_eq!(
        first.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let junit1 = String::from_utf8(first.stdout).unwrap();
    assert!(carried(&junit1).is_empty());
    let records: Vec<String> = std::fs::read_dir(d.join("rec"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(records.len(), 2, "{records:?}");
    let rec_a = d.join("rec/a%2Fjob.toml.json");
    let text_a = std::fs::read_to_string(&rec_a).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text_a).unwrap();
    assert_eq!(v["schema"], "vpcut.check/1");
    let paths: Vec<&str> = v["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, ["a/job.toml", "a/main.ngc", "a/macros/pass.ngc"]);
    assert_eq!(v["absent"], serde_json::json!(["a/pass.ngc"]));
    assert_eq!(v["report"]["schema"], "vpcut.report/1");

    // Nothing changed (the subprogram rewritten with the same bytes): nothing runs, the
    // same outcome; the records written again are the same bytes.
    std::fs::write(d.join("a/macros/pass.ngc"), pass).unwrap();
    let (second, sarif2) = run(&["--changed-since", "rec", "--report-dir", "rec2"]);
    assert_eq!(
        second.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );
    let junit2 = String::from_utf8(second.stdout).unwrap();
    assert_eq!(carried(&junit2), ["a/job.toml", "b/job.toml"]);
    assert_eq!(plain(&junit1), plain(&junit2));
    assert_eq!(plain(&sarif1), plain(&sarif2));
    assert!(junit2.contains("<failure"), "the failing job still fails");
    assert_eq!(
        std::fs::read_to_string(d.join("rec2/a%2Fjob.toml.json")).unwrap(),
        text_a
    );

    // The subprogram changed: a runs again, b stays.
    std::fs::write(
        d.join("a/macros/pass.ngc"),
        pass.replace("X#1", "X[#1 - 0.2]"),
    )
    .unwrap();
    let (out, _) = run(&["--changed-since", "rec"]);
    assert_eq!(
        carried(&String::from_utf8_lossy(&out.stdout)),
        ["b/job.toml"]
    );
    std::fs::write(d.join("a/macros/pass.ngc"), pass).unwrap();
    // A subprogram appears beside the program, where LinuxCNC looks first.
    std::fs::write(d.join("a/pass.ngc"), pass).unwrap();
    let (out, _) = run(&["--changed-since", "rec"]);
    assert_eq!(
        carried(&String::from_utf8_lossy(&out.stdout)),
        ["b/job.toml"]
    );
    std::fs::remove_file(d.join("a/pass.ngc")).unwrap();
    // Other options run everything.
    let (out, _) = run(&["--changed-since", "rec", "--strict"]);
    assert!(carried(&String::from_utf8_lossy(&out.stdout)).is_empty());
    let (out, _) = run(&["--changed-since", "rec", "--max-dexels", "1e8"]);
    assert!(carried(&String::from_utf8_lossy(&out.stdout)).is_empty());
    // Another version's record: run again, no error.
    std::fs::write(
        &rec_a,
        text_a.replacen(
            &format!("\"vpcut_version\": \"{}\"", vpcut::VERSION),
            "\"vpcut_version\": \"0.0.0-other\"",
            1,
        ),
    )
    .unwrap();
    let (out, _) = run(&["--changed-since", "rec"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        carried(&String::from_utf8_lossy(&out.stdout)),
        ["b/job.toml"]
    );
    // A record that is not one: exit 2, naming it.
    std::fs::write(
        &rec_a,
        "{\"schema\": \"vpcut.check/1\", \"vpcut_version\": 3}",
    )
    .unwrap();
    let (out, _) = run(&["--changed-since", "rec"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("a%2Fjob.toml.json:1:") && err.contains("not a record"),
        "{err}"
    );
    for (dir, says) in [
        ("nowhere", "no such folder"),
        ("a/job.toml", "not a folder"),
    ] {
        let (out, _) = run(&["--changed-since", dir]);
        assert_eq!(out.status.code(), Some(2), "{dir}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{dir}: {err}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
