//! The command line's outputs: a run that fails leaves every existing file byte-identical
//! (table-driven over the ways to fail), symbolic links are followed, devices are written
//! in place, `-` is standard output, a closed pipe ends quietly, `-j` and `--size` are
//! refused before any work, the JUnit XML parses, the SARIF has the structure SARIF 2.1.0
//! requires, and `vpcut check` exits 0, 1 or 2.

use crate::support::{root, small};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

fn tmp_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "vpcut-outputs-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn vpcut_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vpcut"))
        .current_dir(dir)
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every file under `dir` (relative path -> bytes; symlinks as `-> target`).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(base: &Path, d: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(d).unwrap().flatten() {
            let p = e.path();
            let rel = p.strip_prefix(base).unwrap().to_path_buf();
            let m = std::fs::symlink_metadata(&p).unwrap();
            if m.file_type().is_symlink() {
                let t = std::fs::read_link(&p).unwrap();
                out.insert(rel, format!("-> {}", t.display()).into_bytes());
            } else if m.is_dir() {
                out.insert(rel.clone(), b"<dir>".to_vec());
                walk(base, &p, out);
            } else {
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// A folder with a small job and a sentinel in every place an output could go.
fn sentinel_dir() -> PathBuf {
    let d = tmp_dir();
    std::fs::write(d.join("job.toml"), small("iso-m20x2.5-radial")).unwrap();
    std::fs::write(d.join("broken.toml"), "[blank\n").unwrap();
    for f in [
        "r.json",
        "m.glb",
        "v.png",
        "j.xml",
        "s.sarif",
        "target.json",
    ] {
        std::fs::write(d.join(f), format!("sentinel {f}\n")).unwrap();
    }
    for (dir, files) in [
        ("plots", &["developed.png", "section.png"][..]),
        (
            "renders",
            &["iso.png", "front.png", "section.png", "closeup.png"][..],
        ),
    ] {
        std::fs::create_dir_all(d.join(dir)).unwrap();
        for f in files {
            std::fs::write(d.join(dir).join(f), format!("sentinel {dir}/{f}\n")).unwrap();
        }
    }
    std::fs::create_dir_all(d.join("adir")).unwrap();
    std::os::unix::fs::symlink("target.json", d.join("link.json")).unwrap();
    d
}

/// Each way to fail, with what the error must say: exit 2, every pre-existing file
/// byte-identical, no temporary left, no folder made.
#[test]
fn failed_runs_leave_existing_files_untouched() {
    let cases: &[(&[&str], &str)] = &[
        (&["--report", "r.json", "--gltf", "nodir/x.glb"], "nodir"),
        (
            &["--report", "r.json", "--png", "v.png", "--size", "100x100"],
            "100x100",
        ),
        (
            &[
                "--report",
                "r.json",
                "--png",
                "v.png",
                "--size",
                "16384x16384",
            ],
            "8192",
        ),
        (
            &["--report", "r.json", "--png", "v.png", "--msaa", "2"],
            "1 or 4",
        ),
        (&["--report", "r.json", "--view", "front"], "--png"),
        (&["--report", "r.json", "--size", "512x384"], "--png"),
        (&["--report", "r.json", "--edges"], "--png"),
        (&["--report", "r.json", "--gltf-ideal"], "--gltf"),
        (&["--report", "r.json", "--gltf-full"], "--gltf"),
        (
            &["--report", "r.json", "--gltf-tolerance", "0.01"],
            "--gltf",
        ),
        (
            &[
                "--report",
                "r.json",
                "--gltf",
                "m.glb",
                "--gltf-tolerance=-1",
            ],
            "0 or more",
        ),
        (&["--report", "r.json", "--section-angle", "5"], "--plots"),
        (
            &[
                "--report",
                "r.json",
                "--plots",
                "plots",
                "--section-angle",
                "nan",
            ],
            "finite",
        ),
        (&["--report", "r.json", "-j", "100000"], "at most"),
        (&["--report", "r.json", "-j", "0"], "at least 1"),
        (&["--report", "r.json", "--gltf", "adir"], "folder"),
        (
            &["--report", "r.json", "--gltf", "r.json"],
            "written there too",
        ),
        (
            &["--report", "link.json", "--gltf", "target.json"],
            "written there too",
        ),
        (&["--report", "job.toml"], "input"),
        (&["--report", "-", "--gltf", "-"], "standard output"),
        (&["--report", "r.json", "--png", "-"], "standard output"),
        (&["--report", "r.json", "--plots", "r.json"], "not a folder"),
        (
            &["--report", "r.json", "--renders", "v.png"],
            "not a folder",
        ),
        (
            &[
                "--report",
                "r.json",
                "--junit",
                "j.xml",
                "--sarif",
                "nodir/s.sarif",
            ],
            "nodir",
        ),
        (
            &[
                "--report", "r.json", "--sarif", "s.sarif", "--junit", "adir",
            ],
            "folder",
        ),
        // These fail only after the checks, when simulating: the temporaries go, the new
        // folder goes.
        (
            &[
                "--report",
                "r.json",
                "--gltf",
                "m.glb",
                "--junit",
                "j.xml",
                "--plots",
                "newplots",
                "--max-dexels",
                "10",
            ],
            "over the budget",
        ),
        (
            &[
                "--report",
                "link.json",
                "--sarif",
                "s.sarif",
                "--max-dexels",
                "10",
            ],
            "budget",
        ),
    ];
    let d = sentinel_dir();
    let before = snapshot(&d);
    for (args, says) in cases {
        let mut all = vec!["simulate", "job.toml", "-q"];
        all.extend_from_slice(args);
        let out = vpcut_in(&d, &all);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: wanted {says:?} in\n{err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains(".tmp"), "{args:?} names a temporary: {err}");
        assert_eq!(
            err.matches("error:").count(),
            1,
            "{args:?}: one message, once:\n{err}"
        );
        let after = snapshot(&d);
        assert_eq!(
            before.keys().collect::<Vec<_>>(),
            after.keys().collect::<Vec<_>>(),
            "{args:?}: files came or went"
        );
        for (k, v) in &before {
            assert!(after[k] == *v, "{args:?} changed {}", k.display());
        }
    }
    // A job that cannot be read, with every output asked for.
    let out = vpcut_in(
        &d,
        &[
            "simulate",
            "broken.toml",
            "--report",
            "r.json",
            "--gltf",
            "m.glb",
            "--plots",
            "plots",
            "--junit",
            "j.xml",
            "--sarif",
            "s.sarif",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert_eq!(snapshot(&d), before);
}

/// The same runs succeed when nothing is wrong, replacing the sentinels.
#[test]
fn good_runs_replace_the_outputs() {
    let d = sentinel_dir();
    let out = vpcut_in(
        &d,
        &[
            "simulate", "job.toml", "--report", "r.json", "--gltf", "m.glb", "--plots", "plots",
            "--junit", "j.xml", "--sarif", "s.sarif",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("r.json")).unwrap()).unwrap();
    assert_eq!(r["verdict"], "pass");
    assert_eq!(&std::fs::read(d.join("m.glb")).unwrap()[..4], b"glTF");
    assert_eq!(
        &std::fs::read(d.join("plots/developed.png")).unwrap()[..4],
        b"\x89PNG"
    );
    // The summary lists every file written.
    let s = text(&out.stdout);
    for f in [
        "r.json",
        "m.glb",
        "plots/developed.png",
        "plots/section.png",
        "j.xml",
        "s.sarif",
    ] {
        assert!(s.contains(&format!("wrote {f}")), "{f}:\n{s}");
    }
    let names: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.contains("vpcut-")),
        "a temporary is left: {names:?}"
    );
}

/// A symbolic link is followed: the link stays a link and its target gets the report
/// (also a link to a file not there yet, and a relative link in another folder); a device is
/// written in place, never replaced.
#[test]
fn symlinks_are_followed_and_devices_written_in_place() {
    let d = sentinel_dir();
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::os::unix::fs::symlink("../target.json", d.join("sub/up.json")).unwrap();
    std::os::unix::fs::symlink("new.json", d.join("dangling.json")).unwrap();
    for (link, target) in [
        ("link.json", "target.json"),
        ("sub/up.json", "target.json"),
        ("dangling.json", "new.json"),
    ] {
        std::fs::write(d.join("target.json"), "old\n").unwrap();
        let out = vpcut_in(&d, &["simulate", "job.toml", "-q", "--report", link]);
        assert!(out.status.success(), "{link}: {}", text(&out.stderr));
        let m = std::fs::symlink_metadata(d.join(link)).unwrap();
        assert!(m.file_type().is_symlink(), "{link} was replaced by a file");
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(d.join(target)).unwrap()).unwrap();
        assert_eq!(r["schema"], "vpcut.report/1", "{link}");
    }
    let out = vpcut_in(
        &d,
        &[
            "simulate",
            "job.toml",
            "-q",
            "--report",
            "/dev/null",
            "--gltf",
            "/dev/null",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    use std::os::unix::fs::FileTypeExt as _;
    let m = std::fs::metadata("/dev/null").unwrap();
    assert!(
        m.file_type().is_char_device(),
        "/dev/null is no longer a device"
    );
    // /dev/stdout (a link through /proc/self/fd to the pipe) is written, not replaced.
    let out = vpcut_in(
        &d,
        &["simulate", "job.toml", "-q", "--report", "/dev/stdout"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["schema"], "vpcut.report/1");
}

/// `-` is standard output; the summary then goes to standard error.
#[test]
fn dash_is_standard_output() {
    let d = sentinel_dir();
    let out = vpcut_in(&d, &["simulate", "job.toml", "--report", "-"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["verdict"], "pass");
    assert!(text(&out.stderr).contains("PASS"), "{}", text(&out.stderr));
    let out = vpcut_in(&d, &["simulate", "job.toml", "--gltf", "-"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(&out.stdout[..4], b"glTF");
    vpcut::from_glb(&out.stdout).unwrap();
    for (flag, starts) in [("--junit", "<?xml"), ("--sarif", "{")] {
        let out = vpcut_in(&d, &["simulate", "job.toml", flag, "-"]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(text(&out.stdout).starts_with(starts), "{flag}");
    }
    let plan = root().join("tests/data/plans/seed002-equal-tooth.toml");
    let out = vpcut_in(
        &d,
        &[
            "plan",
            plan.to_str().unwrap(),
            "--dialect",
            "fanuc",
            "-o",
            "-",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let program = text(&out.stdout);
    assert!(program.starts_with("%\nO1000"), "{program}");
    assert!(!program.contains("layers"), "the summary went to stdout");
    assert!(text(&out.stderr).contains("layer"), "{}", text(&out.stderr));
}

/// Spawn with standard output piped and close it at once: the command ends quietly, with
/// its own exit code and no panic.
#[test]
fn a_closed_pipe_ends_quietly() {
    let d = sentinel_dir();
    let program = root().join("scenes/seed004-tr100x12-macro-b/TR100X12.NC");
    let plan = root().join("tests/data/plans/seed002-equal-tooth.toml");
    let runs: Vec<Vec<&str>> = vec![
        // The seed's program writes plain numbers in mm (its job says decimal_point =
        // "calculator").
        vec![
            "toolpath",
            program.to_str().unwrap(),
            "--dialect",
            "fanuc",
            "--decimal-point",
            "calculator",
            "--json",
        ],
        vec![
            "toolpath",
            program.to_str().unwrap(),
            "--dialect",
            "fanuc",
            "--decimal-point",
            "calculator",
        ],
        vec!["simulate", "job.toml"],
        vec!["simulate", "job.toml", "--report", "-", "-q"],
        vec!["plan", plan.to_str().unwrap(), "--dialect", "fanuc"],
        vec!["check", "job.toml"],
    ];
    for args in runs {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .current_dir(&d)
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("Broken pipe"),
            "{args:?}: {err}"
        );
    }
}

/// `-j 100000` is refused at once, with one message; so is a picture larger than 8192.
#[test]
fn absurd_threads_and_sizes_are_refused_at_once() {
    let d = sentinel_dir();
    let t = std::time::Instant::now();
    let out = vpcut_in(&d, &["simulate", "job.toml", "-j", "100000"]);
    assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert_eq!(err.matches("100000").count(), 1, "{err}");
    for cmd in [
        &[
            "render",
            "m.glb",
            "--png",
            "big.png",
            "--size",
            "16384x16384",
        ][..],
        &[
            "simulate",
            "job.toml",
            "--png",
            "big.png",
            "--size",
            "16384x16384",
        ][..],
    ] {
        let out = vpcut_in(&d, cmd);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{cmd:?}: {err}");
        assert!(err.contains("8192") && !err.contains("panicked"), "{err}");
        assert!(!d.join("big.png").exists());
    }
}

/// A job file that cannot be read says why.
#[test]
fn unreadable_job_files_say_why() {
    let d = sentinel_dir();
    std::fs::write(d.join("latin1.toml"), b"[blank]\n# caf\xe9\n").unwrap();
    for (job, says) in [
        ("missing.toml", "no such file"),
        ("adir", "a folder"),
        (
            "latin1.toml",
            "not UTF-8 text: byte 0xE9 at byte offset 13 (line 2, column 6)",
        ),
    ] {
        let out = vpcut_in(&d, &["simulate", job]);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(job) && err.contains(says), "{job}: {err}");
    }
}

/// Run a scene with its program files copied beside the job, small; returns the folder.
fn program_scene(scene: &str) -> PathBuf {
    let d = tmp_dir();
    for e in std::fs::read_dir(root().join("scenes").join(scene))
        .unwrap()
        .flatten()
    {
        std::fs::copy(e.path(), d.join(e.file_name())).unwrap();
    }
    std::fs::write(d.join("job.toml"), small(scene)).unwrap();
    d
}

/// JUnit XML parses, has one testsuite per job and a failure per error finding.
#[test]
fn junit_is_well_formed() {
    use quick_xml::events::Event;
    let d = sentinel_dir();
    std::fs::write(d.join("fail.toml"), small("seed002-equal-groove")).unwrap();
    let out = vpcut_in(
        &d,
        &[
            "check",
            "job.toml",
            "fail.toml",
            "broken.toml",
            "--junit",
            "j.xml",
            "-q",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let xml = std::fs::read_to_string(d.join("j.xml")).unwrap();
    let mut reader = quick_xml::Reader::from_str(&xml);
    let (mut suites, mut cases, mut failures, mut errors, mut depth) = (0, 0, 0, 0, 0i32);
    let mut root_attrs = BTreeMap::new();
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Start(e)) | Ok(Event::Empty(e)) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                match name.as_str() {
                    "testsuites" => {
                        for a in e.attributes() {
                            let a = a.unwrap();
                            root_attrs.insert(
                                String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                                String::from_utf8(a.value.to_vec()).unwrap(),
                            );
                        }
                    }
                    "testsuite" => suites += 1,
                    "testcase" => cases += 1,
                    "failure" => failures += 1,
                    "error" => errors += 1,
                    _ => {}
                }
                depth += 1;
            }
            Ok(_) => {}
            Err(e) => panic!(
                "not well-formed at {}: {e}\n{xml}",
                reader.buffer_position()
            ),
        }
    }
    assert!(depth > 0);
    assert_eq!(suites, 3, "{xml}");
    // Ten turns, six turns, one error case.
    let turns = 6 + 10;
    assert!(cases > turns, "{cases}\n{xml}");
    // The failing job's deviations were all cut by its one [[pass]]: one finding (issue 29).
    assert!(failures >= 1, "{xml}");
    assert_eq!(errors, 1, "{xml}");
    assert_eq!(root_attrs["errors"], "1");
    // Every error finding is a failure.
    let out = vpcut_in(
        &d,
        &[
            "simulate",
            "fail.toml",
            "--report",
            "r.json",
            "--junit",
            "-",
            "-q",
        ],
    );
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("r.json")).unwrap()).unwrap();
    let errors = r["finding_counts"]["errors"].as_u64().unwrap() as usize;
    assert_eq!(text(&out.stdout).matches("<failure ").count(), errors);
}

/// SARIF has what SARIF 2.1.0 requires of a log, and program findings point at the NC
/// program's line and column.
#[test]
fn sarif_has_the_required_structure_and_program_lines() {
    let d = program_scene("seed000-macro-a-equal-tooth");
    std::fs::write(d.join("fail.toml"), small("seed002-equal-groove")).unwrap();
    std::fs::write(d.join("broken.toml"), "[blank]\ndiameter = \"x\"\n").unwrap();
    let out = vpcut_in(
        &d,
        &[
            "check",
            "job.toml",
            "fail.toml",
            "broken.toml",
            "--sarif",
            "s.sarif",
            "-q",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("s.sarif")).unwrap()).unwrap();
    assert_eq!(s["version"], "2.1.0");
    assert!(s["$schema"]
        .as_str()
        .unwrap()
        .contains("sarif-schema-2.1.0"));
    let runs = s["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 1);
    let run = &runs[0];
    assert_eq!(run["tool"]["driver"]["name"], "vpcut");
    let rules: Vec<&str> = run["tool"]["driver"]["rules"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["id"].as_str().unwrap())
        .collect();
    let results = run["results"].as_array().unwrap();
    // macro-a: one error for its 48 uncut findings and 3 program warnings; the failing job's
    // one finding; the broken job.
    assert!(results.len() >= 6, "{results:?}");
    for r in results {
        assert!(!r["message"]["text"].as_str().unwrap().is_empty(), "{r}");
        let id = r["ruleId"].as_str().unwrap();
        assert!(rules.contains(&id), "{id}");
        assert_eq!(rules[r["ruleIndex"].as_u64().unwrap() as usize], id);
        assert!(
            ["none", "note", "warning", "error"].contains(&r["level"].as_str().unwrap()),
            "{r}"
        );
        let locs = r["locations"].as_array().unwrap();
        assert!(!locs.is_empty());
        for l in locs {
            let p = &l["physicalLocation"];
            let uri = p["artifactLocation"]["uri"].as_str().unwrap();
            assert!(!uri.is_empty() && !uri.contains(' '), "{uri}");
            assert!(p["region"]["startLine"].as_u64().unwrap() >= 1, "{r}");
            assert!(p["region"]["startColumn"].as_u64().unwrap() >= 1, "{r}");
        }
    }
    let at = |rule: &str| -> Vec<(String, u64, u64)> {
        results
            .iter()
            .filter(|r| r["ruleId"] == rule)
            .map(|r| {
                let p = &r["locations"][0]["physicalLocation"];
                (
                    p["artifactLocation"]["uri"].as_str().unwrap().to_string(),
                    p["region"]["startLine"].as_u64().unwrap(),
                    p["region"]["startColumn"].as_u64().unwrap(),
                )
            })
            .collect()
    };
    // O0003.NC:24:10: subprogram O0005 not found.
    let program = at("program");
    assert!(
        program.contains(&("O0003.NC".to_string(), 24, 10)),
        "{program:?}"
    );
    // Deviations point at the pass that cut them: the job's one [[pass]] (no program).
    let gouge = at("gouge");
    let text = small("seed002-equal-groove");
    assert_eq!(text.matches("[[pass]]").count(), 1);
    let thread_line = text
        .lines()
        .position(|l| l.trim_start().starts_with("[[pass]]"))
        .unwrap() as u64
        + 1;
    assert!(
        gouge
            .iter()
            .all(|g| *g == ("fail.toml".to_string(), thread_line, 1)),
        "{gouge:?}"
    );
    // The job that cannot be read: its line and column.
    assert_eq!(at("input"), vec![("broken.toml".to_string(), 2, 12)]);
}

/// `vpcut check` exits 0 when all pass, 1 when one fails, 2 when one cannot be read, and
/// still lists every job.
#[test]
fn check_exit_codes() {
    let d = sentinel_dir();
    std::fs::write(d.join("fail.toml"), small("seed002-equal-groove")).unwrap();
    for (jobs, code) in [
        (&["job.toml"][..], 0),
        (&["job.toml", "job.toml"][..], 0),
        (&["job.toml", "fail.toml"][..], 1),
        (&["job.toml", "fail.toml", "broken.toml"][..], 2),
        (&["job.toml", "missing.toml"][..], 2),
    ] {
        let mut args = vec!["check"];
        args.extend_from_slice(jobs);
        let out = vpcut_in(&d, &args);
        let s = text(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(code),
            "{jobs:?}: {s}{}",
            text(&out.stderr)
        );
        for j in jobs {
            assert!(s.lines().any(|l| l.starts_with(j)), "{j} not listed:\n{s}");
        }
        if code == 2 {
            assert!(s.contains("ERROR"), "{s}");
            assert!(text(&out.stderr).contains("error"), "{}", text(&out.stderr));
        }
        if code >= 1 {
            assert!(s.contains("FAIL") || code == 2, "{s}");
        }
    }
    let out = vpcut_in(&d, &["check"]);
    assert_eq!(out.status.code(), Some(2));
}

/// Diagnostics and toolpath rows name the file that holds a FANUC subprogram (`O2` inside
/// `MAIN.NC`), with the file's line.
#[test]
fn subprograms_are_named_by_their_file() {
    let d = tmp_dir();
    std::fs::write(
        d.join("MAIN.NC"),
        "O0001\nG0 X30. Z5.\nM98 P2\nM30\nO0002\nG32 X26. Z-20. F2.\nM77\nG0 X30.\nM99\n",
    )
    .unwrap();
    let out = vpcut_in(&d, &["toolpath", "MAIN.NC", "--dialect", "fanuc"]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        crate::support::has_diagnostic(&err, "warning: M77", "MAIN.NC:7:1"),
        "{err}"
    );
    assert!(!err.contains("O2:"), "{err}");
    let csv = text(&out.stdout);
    assert!(csv.contains("\nMAIN.NC,6,thread,"), "{csv}");
    assert!(!csv.contains("\nO2,"), "{csv}");
}

/// A FIFO is written in place (it stays a FIFO and its reader gets the report).
#[test]
fn a_fifo_is_written_in_place() {
    let d = sentinel_dir();
    let fifo = d.join("pipe.json");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("no mkfifo here: skipped");
        return;
    }
    // Held open for reading and writing (which does not wait for a writer on Linux) and
    // non-blocking: vpcut's writer finds a reader, and a vpcut that replaced the FIFO instead
    // leaves nothing to read rather than a test that waits forever.
    use std::io::Read as _;
    use std::os::unix::fs::OpenOptionsExt as _;
    let mut pipe = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(&fifo)
        .unwrap();
    let out = vpcut_in(&d, &["simulate", "job.toml", "-q", "--report", "pipe.json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut got = Vec::new();
    let mut buf = [0u8; 65536];
    loop {
        match pipe.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => break,
            Err(e) => panic!("{e}"),
        }
    }
    let r: serde_json::Value = serde_json::from_slice(&got).unwrap();
    assert_eq!(r["schema"], "vpcut.report/1");
    use std::os::unix::fs::FileTypeExt as _;
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
}

/// Output that is not a terminal has no colour codes, whatever `NO_COLOR` says; the summary
/// groups findings by kind with counts.
#[test]
fn no_colour_off_a_terminal_and_findings_grouped() {
    let d = sentinel_dir();
    std::fs::write(d.join("fail.toml"), small("seed002-equal-groove")).unwrap();
    for args in [
        &["simulate", "fail.toml"][..],
        &["check", "fail.toml", "broken.toml"][..],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .current_dir(&d)
            .args(args)
            .env_remove("NO_COLOR")
            .output()
            .unwrap();
        assert!(
            !out.stdout.contains(&0x1b) && !out.stderr.contains(&0x1b),
            "{args:?}"
        );
        if args[0] == "simulate" {
            let s = text(&out.stdout);
            assert!(s.contains("error   gouge x"), "{s}");
            assert!(s.contains("findings with this source"), "{s}");
            assert!(s.contains("s in all"), "{s}");
        }
    }
}

/// No output replaces a file the job read: the job, or its program (known once read, still
/// before the simulation).
#[test]
fn outputs_never_replace_inputs() {
    let d = program_scene("seed000-macro-a-equal-tooth");
    let before = snapshot(&d);
    for args in [
        &["simulate", "job.toml", "--report", "O0003.NC"][..],
        &["simulate", "job.toml", "--gltf", "./job.toml"][..],
        &["check", "job.toml", "--sarif", "O0003.NC"][..],
    ] {
        let out = vpcut_in(&d, args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("input of this run"), "{args:?}: {err}");
        assert_eq!(snapshot(&d), before, "{args:?}");
    }
}

/// A pass check of a pass that comes from the program points at the pass's thread block in
/// SARIF (the re-synced G32 on line 6 lacks run-in; the chained one on line 3 of the first
/// program re-programs the lead).
#[test]
fn sarif_points_pass_checks_at_their_thread_blocks() {
    let d = tmp_dir();
    let toml = "[blank]\ndiameter = 30.0\nlength = 40.0\n\
                [thread]\nform = \"square\"\nmajor_diameter = 30.0\nminor_diameter = 29.0\n\
                pitch = 2.0\nturns = 3\nz_start = -2.0\nwidth = { groove = 1.0 }\n\
                [[tool]]\nid = 1\nkind = \"grooving\"\nwidth = 1.0\n\
                [program]\nfile = \"P.NC\"\ndialect = \"fanuc\"\n\
                [machine]\nacceleration = 1000.0\n\
                [simulation]\naxial_spacing = 0.05\nangular_cells = 90\nmeasure_generators = 1\n";
    std::fs::write(d.join("job.toml"), toml).unwrap();
    for (program, rule, line) in [
        (
            "M03\nG0 X29. Z5.\nG32 Z-7. F2.\nG0 X31.\nG0 X29.\nG32 Z-20. F3.\nM30\n",
            "run_in",
            6,
        ),
        (
            "M03\nG0 X29. Z5.\nG32 Z-7. F2.\nG32 Z-20. F3.\nM30\n",
            "thread_chain",
            4,
        ),
    ] {
        std::fs::write(d.join("P.NC"), program).unwrap();
        let out = vpcut_in(&d, &["simulate", "job.toml", "-q", "--sarif", "-"]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let hits: Vec<_> = s["runs"][0]["results"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r["ruleId"] == rule)
            .map(|r| {
                let p = &r["locations"][0]["physicalLocation"];
                (
                    p["artifactLocation"]["uri"].as_str().unwrap().to_string(),
                    p["region"]["startLine"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(hits, vec![("P.NC".to_string(), line)], "{rule}");
    }
}
