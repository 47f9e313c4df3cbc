//! Issue 29: every finding at its source. Each finding of every scene, of the crash jobs
//! (`tests/data/crash`, both programs) and of the M30x2 gauge jobs (`tests/data/gauge`,
//! with and without a tolerance class) names the NC block that made it (a line of a file
//! the job read) or the job's key (a table the job file has); the places the hand
//! derivations give are checked; every SARIF result has a physical location.

use crate::support::{debug_shape, root, scene_text, scenes};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;
use vpcut::{simulate_report, FindingKind, Job, Report, SimOptions};

/// Run a job text whose programs are read from `dir` (with `edit` applied to each program
/// text); the report and the programs read (name -> text).
fn run_in(
    dir: &Path,
    text: &str,
    edit: &dyn Fn(&str) -> String,
) -> (Job, Report, BTreeMap<String, String>) {
    let read = RefCell::new(BTreeMap::new());
    let load = |f: &str| {
        let t = edit(&std::fs::read_to_string(dir.join(f)).ok()?);
        read.borrow_mut().insert(f.to_string(), t.clone());
        Some(t)
    };
    let job = Job::from_toml_with(text, "job.toml", &load).unwrap_or_else(|e| panic!("{e}"));
    let report = simulate_report(&job, &SimOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    (job, report, read.into_inner())
}

/// Every finding has a source: a line of a program the job read, or a key whose table the
/// job file has (`pass[2]`: at least three `[[pass]]`). A check of a pass from the program
/// is at that pass's thread block.
fn check_sources(what: &str, text: &str, job: &Job, r: &Report, read: &BTreeMap<String, String>) {
    for f in &r.findings {
        match (&f.file, f.line, &f.key) {
            (Some(file), Some(line), _) => {
                // The file as the job names it, or a program of a file it read (`O2`).
                let lines = read
                    .get(file)
                    .map(|t| t.lines().count())
                    .or_else(|| read.values().map(|t| t.lines().count()).max());
                let lines = lines.unwrap_or_else(|| panic!("{what}: {file} not read: {f:?}"));
                assert!(
                    (1..=lines).contains(&line),
                    "{what}: line {line} of {file}: {f:?}"
                );
                if let Some(p) = f.pass {
                    let is_check = !matches!(
                        f.kind,
                        FindingKind::Gouge
                            | FindingKind::Leftover
                            | FindingKind::Lead
                            | FindingKind::GrooveWidth
                            | FindingKind::ToothWidth
                            | FindingKind::MissingFeature
                            | FindingKind::SplitFeature
                            | FindingKind::FlankInterference
                    );
                    if let (true, Some(b)) =
                        (is_check, job.pass_blocks.iter().find(|b| b.0 + 1 == p))
                    {
                        assert_eq!((&b.1, b.2), (file, line), "{what}: {f:?}");
                    }
                }
            }
            (_, _, Some(key)) => {
                let table = key.split(['.', '[']).next().unwrap();
                let nth = key.split_once('[').map_or(0, |(_, n)| {
                    n.split(']').next().unwrap().parse::<usize>().unwrap()
                });
                let headers = text
                    .lines()
                    .filter(|l| {
                        let t = l.trim();
                        t == format!("[{table}]") || t == format!("[[{table}]]")
                    })
                    .count();
                assert!(
                    headers > nth || (table == "simulation" && f.kind == FindingKind::NotCompared),
                    "{what}: key {key} has no table in the job: {f:?}"
                );
            }
            _ => panic!("{what}: a finding without a source: {f:?}"),
        }
    }
}

#[test]
fn every_finding_of_every_scene_is_at_its_source() {
    for scene in scenes() {
        let dir = root().join("scenes").join(&scene);
        let text = scene_text(&scene);
        let (job, r, read) = run_in(&dir, &text, &|t| t.to_string());
        check_sources(&scene, &text, &job, &r, &read);
    }
}

#[test]
fn every_finding_of_the_crash_and_gauge_jobs_is_at_its_source() {
    let crash = root().join("tests/data/crash");
    for case in [
        "first-cut-too-deep",
        "g76-first-block-missing",
        "rapid-below-crest",
        "thread-into-shoulder",
    ] {
        let dir = crash.join(case);
        let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
        for program in ["crash.nc", "fixed.nc"] {
            let text = text.replace("crash.nc", program);
            let (job, r, read) = run_in(&dir, &text, &|t| t.to_string());
            check_sources(&format!("{case}/{program}"), &text, &job, &r, &read);
        }
    }
    let dir = root().join("tests/data/gauge");
    let text = std::fs::read_to_string(dir.join("m30x2.toml")).unwrap();
    for program in ["O1001.NC", "O1002.NC"] {
        for designation in ["M30x2-6g", "M30x2-6h", "M30x2"] {
            let text = text
                .replace("O1001.NC", program)
                .replace("M30x2-6g", designation);
            let (job, r, read) = run_in(&dir, &text, &|t| t.to_string());
            check_sources(&format!("{program} {designation}"), &text, &job, &r, &read);
        }
    }
}

/// turned-m20x2.5-fanuc turns the major diameter to X19.8 at N100 (line 15 of O0017.NC)
/// before threading M20x2.5: the crest of every turn stands (20 - 19.8) / 2 = 0.1 mm under
/// the drawing's. Those crest gouges were made by N100, not by a thread pass.
#[test]
fn the_crest_a_turning_pass_cut_is_blamed_on_that_pass() {
    let scene = "turned-m20x2.5-fanuc";
    let dir = root().join("scenes").join(scene);
    let (_, r, read) = run_in(&dir, &scene_text(scene), &|t| t.to_string());
    let n100 = read["O0017.NC"].lines().nth(14).unwrap();
    assert!(n100.starts_with("N100 Z-30.0"), "{n100}");
    let crests: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Gouge && f.flank == Some(vpcut::Flank::Crest))
        .collect();
    assert!(!crests.is_empty());
    for f in crests {
        assert_eq!(
            (f.file.as_deref(), f.line),
            (Some("O0017.NC"), Some(15)),
            "{f:?}"
        );
        assert!((f.value.unwrap() - 0.1).abs() < 1e-3, "{f:?}");
        assert_eq!(f.pass, None, "a turning move is no thread pass: {f:?}");
    }
}

/// O1002 with the G76's final X27.8 instead of X27.546 (basic size M30x2, no class): the
/// root stands (27.8 - 27.546) / 2 = 0.127 mm high on every turn. Every leftover is at the
/// G76's second block (N210, line 24), the block whose passes stopped short.
#[test]
fn a_short_g76_final_x_is_blamed_on_its_block() {
    let dir = root().join("tests/data/gauge");
    let text = std::fs::read_to_string(dir.join("m30x2.toml"))
        .unwrap()
        .replace("O1001.NC", "O1002.NC")
        .replace("M30x2-6g", "M30x2");
    let (_, r, read) = run_in(&dir, &text, &|t| t.replace("X27.546", "X27.8"));
    assert!(read["O1002.NC"]
        .lines()
        .nth(23)
        .unwrap()
        .starts_with("N210 G76 X27.8"));
    let left: Vec<_> = r
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Leftover)
        .collect();
    assert!(!left.is_empty());
    for f in left {
        assert_eq!(
            (f.file.as_deref(), f.line),
            (Some("O1002.NC"), Some(24)),
            "{f:?}"
        );
    }
}

/// `vpcut check --sarif` over every scene: every result has a physical location with a
/// file and a line; a result in an NC program has the job file as its related location.
#[test]
fn every_sarif_result_has_a_physical_location() {
    let jobs: Vec<String> = scenes()
        .iter()
        .map(|s| {
            root()
                .join("scenes")
                .join(s)
                .join("job.toml")
                .display()
                .to_string()
        })
        .collect();
    let dir = std::env::temp_dir().join(format!("vpcut-sources-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sarif = dir.join("all.sarif");
    let mut args = vec![
        "check".to_string(),
        "-q".into(),
        "--sarif".into(),
        sarif.display().to_string(),
    ];
    args.extend(jobs);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .args(&args)
        .output()
        .unwrap();
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&sarif).unwrap()).unwrap();
    let results = v["runs"][0]["results"].as_array().unwrap();
    assert!(!results.is_empty());
    for r in results {
        let p = &r["locations"][0]["physicalLocation"];
        let uri = p["artifactLocation"]["uri"].as_str().unwrap_or("");
        assert!(!uri.is_empty(), "{r}");
        assert!(p["region"]["startLine"].as_u64().unwrap_or(0) >= 1, "{r}");
        if !uri.ends_with(".toml") {
            let j = &r["relatedLocations"][0]["physicalLocation"]["artifactLocation"]["uri"];
            assert!(j.as_str().unwrap_or("").ends_with("job.toml"), "{r}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// One mistake in a program: what, the text replaced and its replacement, the error's kind
/// (where it is fixed), its line, its size by hand (where it has a closed form) and a word
/// its message must hold.
type Mistake = (
    &'static str,
    &'static str,
    &'static str,
    Option<FindingKind>,
    usize,
    Option<f64>,
    Option<&'static str>,
);

/// Run each of `cases` on `program` (which passes) in `dir`'s job `text`: exactly one error
/// each, at its line of `file`, of its kind, size and words.
fn one_error_each(dir: &Path, text: &str, program: &str, file: &str, cases: &[Mistake]) {
    let (_, ok, _) = run_in(dir, text, &|_| program.to_string());
    assert_eq!(ok.finding_counts.errors, 0, "{:#?}", ok.findings);
    for &(what, from, to, kind, line, size, words) in cases {
        let changed = program.replace(from, to);
        assert_ne!(changed, program, "{what}");
        let (_, r, _) = run_in(dir, text, &|_| changed.clone());
        let errors: Vec<_> = r.findings.iter().filter(|f| f.is_error()).collect();
        assert_eq!(errors.len(), 1, "{what}: {:#?}", errors);
        let e = errors[0];
        assert_eq!(
            (e.file.as_deref(), e.line),
            (Some(file), Some(line)),
            "{what}: {e:?}"
        );
        if let Some(k) = kind {
            assert_eq!(e.kind, k, "{what}: {e:?}");
        }
        if let Some(v) = size {
            assert!((e.value.unwrap() - v).abs() < 2e-3, "{what}: {e:?}");
        }
        if let Some(w) = words {
            assert!(e.message.contains(w), "{what}: {}", e.message);
        }
    }
}

/// One cause, one finding: single mistakes in two programs that pass, each giving exactly
/// one error at the block that made it, of its size where it has a closed form.
///
/// The M30x2 G76 program of `tests/data/crash/g76-first-block-missing/fixed.nc` (its G76 is
/// line 9, N50, after `%`, O, a comment and N10..N45; the job given a second insert, T0505
/// a 55 deg one, and offsets 3 and 4, 4 being 0.2 mm larger on the diameter): a final X of
/// 27.8 instead of d3 = 27.546 leaves the root (27.8 - 27.546) / 2 = 0.127 mm high; X27.3
/// cuts it (27.546 - 27.3) / 2 = 0.123 mm deep, X27.4 0.073 mm; offset 4 leaves every pass
/// 0.2 / 2 = 0.1 mm high (less the 0.000131 mm d3 = 27.546262 is under X27.546); a rapid to
/// X28 through the 30 mm bar runs (30 - 28) / 2 = 1 mm into it; a start point X29 under the
/// bar's 30 makes every return rapid of the cycle (its block) run (30 - 29) / 2 = 0.5 mm in.
/// The wrong insert's finding names it as written (T0505).
///
/// The two-start M30x4 (P2) of `tests/data/sources/two-start-g92` (README.md): start 2's
/// finishing pass N140 (line 19) left out leaves its root (27.8 - 27.546262) / 2 = 0.1269
/// mm high, at N130 (line 18), the pass that cut there last; start 2 at Q171000 instead of
/// Q180000 puts its grooves 4 x 9 / 360 = 0.1 mm along the axis, a 60 deg flank
/// 0.1 cos 30 = 0.0866 mm off, at its finishing block N140.
#[test]
fn each_single_mistake_gives_one_error_at_its_block() {
    let dir = root().join("tests/data/crash/g76-first-block-missing");
    let text = std::fs::read_to_string(dir.join("job.toml"))
        .unwrap()
        .replace(
            "[program]",
            "[[tool]]\nid = 5\nkind = \"threading\"\nangle = 55.0\ntip_flat = 0.2\nreference = \"tip\"\n\n[program]",
        )
        .replace(
            "acceleration = 2000",
            "acceleration = 2000\noffsets.3 = { x = 0.0 }\noffsets.4 = { x = 0.2 }\noffsets.5 = { x = 0.0 }",
        );
    let fixed = std::fs::read_to_string(dir.join("fixed.nc")).unwrap();
    assert!(fixed.lines().nth(8).unwrap().starts_with("N50 G76 X27.546"));
    use FindingKind::{Gouge, Hand, Leftover, RapidCut};
    let g76: &[Mistake] = &[
        (
            "final depth short",
            "X27.546",
            "X27.8",
            Some(Leftover),
            9,
            Some(0.127),
            None,
        ),
        (
            "final depth too deep",
            "X27.546",
            "X27.3",
            Some(Gouge),
            9,
            Some(0.123),
            None,
        ),
        (
            "finishing pass too deep",
            "X27.546",
            "X27.4",
            Some(Gouge),
            9,
            Some(0.073),
            None,
        ),
        ("lead too long", "F2.0", "F2.1", None, 9, None, None),
        ("lead too short", "F2.0", "F1.5", None, 9, None, None),
        (
            "start point (phase) off",
            "X32.0 Z5.0",
            "X32.0 Z5.5",
            None,
            9,
            None,
            None,
        ),
        (
            "start point under the bar",
            "X32.0 Z5.0",
            "X29.0 Z5.0",
            Some(RapidCut),
            9,
            Some(0.5),
            None,
        ),
        ("spindle reversed", "M03", "M04", Some(Hand), 9, None, None),
        (
            "thread too short",
            "Z-39.5",
            "Z-20.0",
            Some(Leftover),
            9,
            None,
            None,
        ),
        (
            "a taper by mistake",
            "Z-39.5 P1227",
            "Z-39.5 R-0.5 P1227",
            Some(Gouge),
            9,
            None,
            None,
        ),
        (
            "rapid through the bar",
            "N60 G00 X100.0 Z100.0",
            "N60 G00 X100.0 Z100.0\nN65 G00 X28.0 Z-10.0",
            Some(RapidCut),
            11,
            Some(1.0),
            None,
        ),
        (
            "wrong insert",
            "N20 T0303",
            "N20 T0505",
            None,
            9,
            None,
            Some("T0505"),
        ),
        (
            "wrong offset",
            "N20 T0303",
            "N20 T0304",
            Some(Leftover),
            9,
            Some(0.1),
            Some("T0304"),
        ),
    ];
    one_error_each(&dir, &text, &fixed, "crash.nc", g76);

    let dir = root().join("tests/data/sources/two-start-g92");
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let program = std::fs::read_to_string(dir.join("two-start.nc")).unwrap();
    assert!(program
        .lines()
        .nth(18)
        .unwrap()
        .starts_with("N140 X27.546 Q180000"));
    let two: &[Mistake] = &[
        (
            "start 2's finishing block missing",
            "N140 X27.546 Q180000\n",
            "",
            Some(Leftover),
            18,
            Some(0.1269),
            None,
        ),
        (
            "start 2's start angle Q off",
            "Q180000",
            "Q171000",
            Some(Gouge),
            19,
            Some(0.0866),
            None,
        ),
    ];
    one_error_each(&dir, &text, &program, "two-start.nc", two);
    assert!(g76.len() + two.len() >= 12);
}

/// Every job the suites' sources tests run: the scenes, the crash jobs (both programs),
/// the M30x2 gauge jobs, the two-start G92 job: (name, folder, job text).
fn all_jobs() -> Vec<(String, std::path::PathBuf, String)> {
    let mut v: Vec<_> = scenes()
        .into_iter()
        .map(|s| (s.clone(), root().join("scenes").join(&s), scene_text(&s)))
        .collect();
    for case in [
        "first-cut-too-deep",
        "g76-first-block-missing",
        "rapid-below-crest",
        "thread-into-shoulder",
    ] {
        let dir = root().join("tests/data/crash").join(case);
        let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
        for program in ["crash.nc", "fixed.nc"] {
            let t = text.replace("crash.nc", program);
            v.push((format!("{case}/{program}"), dir.clone(), t));
        }
    }
    let dir = root().join("tests/data/gauge");
    let text = std::fs::read_to_string(dir.join("m30x2.toml")).unwrap();
    for program in ["O1001.NC", "O1002.NC"] {
        let t = text.replace("O1001.NC", program);
        v.push((format!("gauge {program}"), dir.clone(), t));
    }
    let dir = root().join("tests/data/sources/two-start-g92");
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    v.push(("two-start-g92".into(), dir, text));
    v
}

/// No message of any job's report (findings, summary: the scenes, the crash, gauge and
/// two-start jobs) and no diagnostic of the NC corpus (`tests/data/nc`: the reviewed
/// `*.moves` hold every warning and error the interpreter gives, equal to its output by
/// `nc_data`) has Rust's debug formatting (the job errors of the hostile and robust tests
/// are checked there, `support::no_debug_text`). A tool a message names (`T0303`,
/// `T="NAME"`) stands in the program as written.
#[test]
fn no_message_has_debug_formatting() {
    for (w, shape) in [
        ("Some(2)", true),
        ("tool T0202", false),
        ("None", true),
        ("Nonexistent", false),
        ("not `{ x = 0 }`", false),
        ("Inner { x: 1 }", true),
    ] {
        assert_eq!(debug_shape(w).is_some(), shape, "{w}");
    }
    let mut tools_named = 0;
    for (scene, dir, text) in all_jobs() {
        let (_, r, read) = run_in(&dir, &text, &|t| t.to_string());
        for f in &r.findings {
            assert_eq!(debug_shape(&f.message), None, "{scene}: {}", f.message);
            // Every tool word of the message (`T0303`, `T="A B"`) is written in a program.
            for (i, _) in f.message.match_indices(" T") {
                let rest = &f.message[i + 1..];
                let word: String = if let Some(name) = rest.strip_prefix("T=\"") {
                    let end = name.find('"').map_or(rest.len(), |k| k + 4);
                    rest[..end].to_string()
                } else {
                    rest.chars()
                        .take_while(|c| c.is_ascii_alphanumeric())
                        .collect()
                };
                let number = word.len() > 1 && word[1..].chars().all(|c| c.is_ascii_digit());
                // A job without a program names its `[[tool]]` id (`T1`).
                if !text.contains("[program]") || !(number || word.starts_with("T=")) {
                    continue;
                }
                tools_named += 1;
                assert!(
                    read.values()
                        .any(|t| t.to_uppercase().contains(&word.to_uppercase())),
                    "{scene}: {word} is not written in its program: {}",
                    f.message
                );
            }
        }
        let summary = r.summary_with(&Default::default());
        assert_eq!(debug_shape(&summary), None, "{scene}: {summary}");
        // The machinist's words: no internal terms; the thread's diameters and depth.
        let lower = summary.to_lowercase();
        for word in ["dexel", "generator"] {
            assert!(!lower.contains(word), "{scene}: {word} in {summary}");
        }
        let t = &r.thread;
        let line = format!(
            "thread: major diameter {:.4} mm, pitch diameter {:.4} mm, minor diameter {:.4} mm, depth {:.4} mm",
            t.major_diameter_mm,
            t.pitch_diameter_mm,
            t.minor_diameter_mm,
            (t.major_diameter_mm - t.minor_diameter_mm) / 2.0
        );
        assert!(summary.contains(&line), "{scene}: {summary}");
        if scene == "iso-m20x2.5-radial" {
            // ISO 68-1 M20x2.5, external root d3: d2 = 20 - 0.649519 x 2.5, depth h3 =
            // 0.613435 x 2.5 = 1.5336.
            assert!(summary.contains("major diameter 20.0000 mm, pitch diameter 18.3762 mm, minor diameter 16.9328 mm, depth 1.5336 mm"), "{summary}");
        }
    }
    let mut stack = vec![root().join("tests/data/nc")];
    let mut n = 0;
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "moves") {
                n += 1;
                let text = std::fs::read_to_string(&p).unwrap();
                for l in text.lines().filter(|l| !l.starts_with('#')) {
                    assert_eq!(debug_shape(l), None, "{}: {l}", p.display());
                }
            }
        }
    }
    assert!(n > 10, "{n} corpus programs");
    assert!(tools_named >= 5, "{tools_named} tools named in messages");
}

/// Quiet success: `simulate -q --png` on every scene, without a desktop session
/// (`XDG_RUNTIME_DIR` unset: the Vulkan stack's drivers print an `error:` line then), prints
/// nothing on standard error when the run succeeds (exit 0, or 1 for a fail verdict is not
/// asked for here). Without a GPU adapter `--png` fails; that run is not a success and is
/// skipped, as the render tests are.
#[test]
fn a_successful_quiet_run_prints_nothing_on_standard_error() {
    let dir = std::env::temp_dir().join(format!("vpcut-quiet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("x.png");
    let mut ran = 0;
    for scene in scenes() {
        let job = root().join("scenes").join(&scene).join("job.toml");
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(["simulate", "-q", "--size", "256x192", "--png"])
            .arg(&png)
            .arg(&job)
            .env_remove("XDG_RUNTIME_DIR")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        match out.status.code() {
            Some(0) => {
                ran += 1;
                assert!(
                    out.stderr.is_empty(),
                    "{scene}: {}",
                    String::from_utf8_lossy(&out.stderr)
                );
            }
            Some(2) if std::env::var_os("VPCUT_REQUIRE_RENDER").is_none() => {}
            c => panic!(
                "{scene}: exit {c:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            ),
        }
    }
    eprintln!("{ran} scenes rendered quietly");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `vpcut check --shard I/N`: over five jobs given in two orders, the shards of N = 1..4
/// check every job exactly once (by the JUnit suites' files), the same jobs whatever the
/// order; a bad spec is a usage error (exit 2) that says what was expected.
#[test]
fn check_shards_cover_the_jobs_once() {
    let dir = std::env::temp_dir().join(format!("vpcut-shard-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let names = ["e.toml", "a.toml", "c.toml", "b.toml", "d.toml"];
    for n in names {
        std::fs::write(dir.join(n), crate::support::small("iso-m20x2.5-radial")).unwrap();
    }
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .current_dir(&dir)
            .args(args)
            .output()
            .unwrap()
    };
    let files = |xml: &str| -> Vec<String> {
        xml.match_indices("<testsuite name=")
            .map(|(i, _)| {
                let rest = &xml[i..];
                let f = rest.find(" file=\"").unwrap() + 7;
                rest[f..f + rest[f..].find('"').unwrap()].to_string()
            })
            .collect()
    };
    let mut reversed = names;
    reversed.reverse();
    for count in 1..=4 {
        let mut all = Vec::new();
        for index in 1..=count {
            let spec = format!("{index}/{count}");
            let mut got = Vec::new();
            for order in [&names, &reversed] {
                let mut args = vec!["check", "-q", "--junit", "-", "--shard", &spec];
                args.extend(order.iter());
                let out = run(&args);
                assert_eq!(
                    out.status.code(),
                    Some(0),
                    "{}",
                    String::from_utf8_lossy(&out.stderr)
                );
                got.push(files(&String::from_utf8_lossy(&out.stdout)));
            }
            assert_eq!(got[0], got[1], "shard {spec}");
            all.extend(got.swap_remove(0));
        }
        all.sort();
        let mut want: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        want.sort();
        assert_eq!(all, want, "{count} shards");
    }
    for bad in ["0/2", "3/2", "x"] {
        let out = run(&["check", "--shard", bad, "a.toml"]);
        assert_eq!(out.status.code(), Some(2));
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("expected I/N"),
            "{bad}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
