//! Issue 29: messages in the user's words. An inch job (an inch class or designation, an
//! inch form, or a program that cuts its thread in inches) reads in inches and threads per
//! inch beside mm, with the values derived by hand from ASME B1.1's basic profile; a metric
//! job shows no inch; a tool the job does not define is named as the program writes it.

use crate::support::{root, scene_text, with};
use std::path::Path;
use vpcut::{simulate_report, Job, Report, SimOptions};

/// Run the job text `text` with its program read from `dir` through `edit`.
fn run(dir: &Path, text: &str, edit: &dyn Fn(&str) -> String) -> Report {
    let load = |f: &str| Some(edit(&std::fs::read_to_string(dir.join(f)).ok()?));
    let job = Job::from_toml_with(text, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"));
    simulate_report(&job, &SimOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The seed 003 program (inch, G20) written in mm: every inch value times 25.4, the
/// G76's Q/P words in the least input increment of mm (0.001 mm): Q0040 (0.0040 in) is
/// Q102, P0511 (0.0511 in) P1298, Q0100 Q254.
const SEED003_MM: &str = "%\nO0031\nG21\nN31 T0600\nN32 G97 S800 M03\nN33 G00 X55.88 Z7.62 T0606 M08\nN34 G76 P010060 Q102 R0.051\nN35 G76 X48.204 Z-38.1 R0 P1298 Q254 F2.116667\nN36 G00 X203.2 Z127.0 T0600\nN37 M01\nM30\n%\n";

/// seed003-g76-2in-12tpi is 2-12 UN (ASME B1.1, basic profile): P = 1/12 in, pitch
/// diameter d2 = d - 0.649519 P = 2 - 0.054127 = 1.945873 in, design root (external)
/// d3 = d - 1.226869 P = 1.897761 in, depth 0.613435 P = 0.051120 in, 12 TPI. The summary
/// gives them beside mm and the worst places in inches; the report's `thread.inch` holds
/// them to 1e-6 in.
#[test]
fn an_inch_job_reads_in_inches_and_threads_per_inch() {
    let scene = "seed003-g76-2in-12tpi";
    let dir = root().join("scenes").join(scene);
    let r = run(&dir, &scene_text(scene), &|t| t.to_string());
    let p = 1.0 / 12.0;
    let (d2, d3, h) = (2.0 - 0.649519 * p, 2.0 - 1.226869 * p, 0.613435 * p);
    let i = r.thread.inch.as_ref().expect("an inch job");
    for (got, want, what) in [
        (i.major_diameter_in, 2.0, "major"),
        (i.pitch_diameter_in, d2, "pitch"),
        (i.minor_diameter_in, d3, "minor"),
        (i.depth_in, h, "depth"),
        (i.tpi, 12.0, "tpi"),
        (i.lead_in, p, "lead"),
    ] {
        assert!((got - want).abs() < 2e-6, "{what}: {got} vs {want}");
    }
    let s = r.summary();
    let line = format!(
        "major diameter 2.00000 in, pitch diameter {d2:.5} in, minor diameter {d3:.5} in, depth {h:.5} in, 12.000 TPI"
    );
    assert!(s.contains(&line), "{line}\n{s}");
    assert!(
        s.contains("worst leftover") && s.contains(" in)  turn "),
        "{s}"
    );
    let json: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    assert_eq!(json["thread"]["inch"]["tpi"], 12.0);
}

/// The same program with F0.076923 (13 TPI: 25.4 / 13 = 1.953846 mm) against the 12 TPI
/// drawing (2.116667 mm): the turns' table gives 12.000 TPI ideal and 13.000 measured on
/// turn 1, whose measured lead is 1.9538 mm; the G76's finding gives its sizes in inches,
/// the lead among them.
#[test]
fn a_wrong_tpi_reads_as_threads_per_inch() {
    let scene = "seed003-g76-2in-12tpi";
    let dir = root().join("scenes").join(scene);
    let r = run(&dir, &scene_text(scene), &|t| {
        t.replace("F0.083333", "F0.076923")
    });
    let t1 = &r.turns[0];
    assert!(
        (t1.measured_lead_mm.unwrap() - 25.4 / 13.0).abs() < 1e-3,
        "{t1:?}"
    );
    let s = r.summary();
    let row = s
        .lines()
        .find(|l| l.trim_start().starts_with("1 "))
        .expect("turn 1's row");
    assert!(row.trim_end().ends_with("12.000  13.000"), "{row}");
    assert!(s.contains("TPI: ideal measured"), "{s}");
    let g76 = r
        .findings
        .iter()
        .find(|f| f.line == Some(10) && f.is_error())
        .expect("the G76's error");
    assert!(g76.message.contains(" lead up to "), "{}", g76.message);
    let inches = g76.message.matches(" in)").count();
    assert!(inches >= 3, "{}", g76.message);
}

/// Which jobs are inch jobs: the inch form alone (the program in mm), the inch program
/// alone (the form ISO metric); neither: no inch anywhere in the summary or a message.
#[test]
fn inch_by_form_or_program_and_metric_stays_metric() {
    let scene = "seed003-g76-2in-12tpi";
    let dir = root().join("scenes").join(scene);
    let text = scene_text(scene);
    let metric_form = with(&text, &[("thread", "form", "\"iso-metric\"")]);
    let mm = |_: &str| SEED003_MM.to_string();
    let same = |t: &str| t.to_string();
    for (what, text, edit, inch) in [
        (
            "unified form, mm program",
            &text,
            &mm as &dyn Fn(&str) -> String,
            true,
        ),
        ("metric form, inch program", &metric_form, &same, true),
        ("metric form, mm program", &metric_form, &mm, false),
    ] {
        let r = run(&dir, text, edit);
        assert_eq!(r.thread.inch.is_some(), inch, "{what}");
        let s = r.summary();
        assert_eq!(
            s.contains(" in,") || s.contains(" in)"),
            inch,
            "{what}: {s}"
        );
        if !inch {
            assert!(!s.contains("TPI"), "{what}: {s}");
            for f in &r.findings {
                assert!(!f.message.contains(" in)"), "{what}: {}", f.message);
            }
        }
    }
}

/// A thread move whose tool the job does not define names the tool as the program wrote it
/// and the id the job must give it: FANUC `T0505` (tool 5 with offset 5), a Siemens 840D
/// tool by name (numbered 1000 in the order named); given that id, the Siemens job runs
/// and its cycle time names the tool by its name.
#[test]
fn an_undefined_tool_is_named_as_the_program_writes_it() {
    let fanuc = root().join("scenes/seed003-g76-2in-12tpi");
    let load = |f: &str| {
        std::fs::read_to_string(fanuc.join(f))
            .ok()
            .map(|t| t.replace("T0606", "T0505"))
    };
    let e = Job::from_toml_with(&scene_text("seed003-g76-2in-12tpi"), "job.toml", &load)
        .map(|_| ())
        .expect_err("tool 5 is not in the job")
        .to_string();
    assert!(e.contains("threading with T0505 (id 5 in [[tool]])"), "{e}");

    let siemens = root().join("scenes/seed002-siemens-equal-groove");
    let text = scene_text("seed002-siemens-equal-groove").replace("siemens-802d", "siemens-840d");
    let load = |f: &str| {
        std::fs::read_to_string(siemens.join(f))
            .ok()
            .map(|t| t.replace("G90 T1", "G90 T=\"GEW_AUSSEN_3.0\" D1"))
    };
    let e = Job::from_toml_with(&text, "job.toml", &load)
        .map(|_| ())
        .expect_err("no tool 1000 in the job")
        .to_string();
    assert!(
        e.contains("threading with T=\"GEW_AUSSEN_3.0\" D1 (id 1000 in [[tool]]"),
        "{e}"
    );
    let named = text.replacen("id = 1\n", "id = 1000\n", 1);
    let job = Job::from_toml_with(&named, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"));
    let r = simulate_report(&job, &SimOptions::default()).unwrap();
    let tools = &r.cycle_time_s.as_ref().unwrap().tools;
    assert_eq!(tools[0].name.as_deref(), Some("T=\"GEW_AUSSEN_3.0\" D1"));
    assert!(
        r.summary().contains("T=\"GEW_AUSSEN_3.0\" D1 "),
        "{}",
        r.summary()
    );
}

/// Copy a folder's files (and its folders') into `to`.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let dest = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

/// Quiet success with every output: `simulate -q` writing the report, the plots, the page,
/// the model, JUnit and SARIF for every scene (made small), then `check -q` over them all
/// with the records and `--changed-since` them, without a desktop session
/// (`XDG_RUNTIME_DIR` unset): nothing on standard error. `simulate` without `--check`
/// exits 0 whatever the verdict; `check` 0 or 1 (a fail verdict is a result, not an error).
#[test]
fn quiet_runs_with_every_output_print_nothing_on_standard_error() {
    let base = std::env::temp_dir().join(format!("vpcut-words-quiet-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let mut jobs = Vec::new();
    for scene in crate::support::scenes() {
        let dir = base.join(&scene);
        copy_dir(&root().join("scenes").join(&scene), &dir);
        std::fs::write(dir.join("job.toml"), crate::support::small(&scene)).unwrap();
        jobs.push(format!("{scene}/job.toml"));
    }
    let vpcut = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .current_dir(&base)
            .args(args)
            .env_remove("XDG_RUNTIME_DIR")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap()
    };
    for job in &jobs {
        let out = vpcut(&[
            "simulate", "-q", job, "--report", "r.json", "--plots", "plots", "--html", "p.html",
            "--gltf", "m.glb", "--junit", "j.xml", "--sarif", "s.sarif",
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{job}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stderr.is_empty(),
            "{job}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out.stdout.is_empty(), "{job}: -q prints nothing");
    }
    let mut args = vec![
        "check",
        "-q",
        "--junit",
        "j.xml",
        "--sarif",
        "s.sarif",
        "--report-dir",
        "rec",
    ];
    args.extend(jobs.iter().map(String::as_str));
    for round in 0..2 {
        let out = vpcut(&args);
        assert!(
            matches!(out.status.code(), Some(0 | 1)),
            "round {round}: {:?}",
            out.status
        );
        assert!(
            out.stderr.is_empty(),
            "round {round}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out.stdout.is_empty());
        // The second round carries every job from the first's records.
        args.splice(1..1, ["--changed-since", "rec"]);
    }
    let junit = std::fs::read_to_string(base.join("j.xml")).unwrap();
    assert_eq!(junit.matches("unchanged_since").count(), jobs.len());
    let _ = std::fs::remove_dir_all(&base);
}
