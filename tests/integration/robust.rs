//! Bad input never panics: every number of every scene replaced by hostile values must give
//! either a job that simulates or a clean error.

use crate::support::{scene_text, scenes};
use vpcut::{simulate, Job, SimOptions};

const HOSTILE: [&str; 9] = [
    "0",
    "-1",
    "-0.0",
    "1e300",
    "1e-300",
    "nan",
    "inf",
    "\"x\"",
    "123456789",
];

/// Replace the value of line `i` (a `key = value` line) with `v`.
fn mutate(text: &str, i: usize, v: &str) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let line = lines[i];
    let (key, value) = line.split_once('=')?;
    if key.trim_start().starts_with('#') || value.trim_start().starts_with('"') {
        return None;
    }
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out[i] = format!("{key}= {v}");
    Some(out.join("\n"))
}

#[test]
fn hostile_numbers_never_panic() {
    let mut runs = 0;
    for scene in scenes() {
        let text = scene_text(&scene);
        for i in 0..text.lines().count() {
            for v in HOSTILE {
                let Some(m) = mutate(&text, i, v) else {
                    continue;
                };
                let result = std::panic::catch_unwind(|| match Job::from_toml(&m, "job.toml") {
                    Ok(mut job) => {
                        // Keep the run small: the point is the absence of panics.
                        job.sim.angular_cells = 8;
                        job.sim.measure_generators = 1;
                        job.sim.measure_spacing = job.sim.measure_spacing.max(0.01);
                        let run = simulate(
                            &job,
                            &SimOptions {
                                max_dexels: Some(4_000_000),
                            },
                        );
                        match run {
                            Ok(out) => {
                                for f in &out.report.findings {
                                    let e = crate::support::debug_shape(&f.message);
                                    assert_eq!(e, None, "{scene}: {}", f.message);
                                }
                            }
                            Err(e) => crate::support::no_debug_text(&scene, &format!("error: {e}")),
                        }
                    }
                    Err(e) => {
                        let msg = e.to_string();
                        assert!(crate::support::place(&msg).starts_with("job.toml"), "{msg}");
                        crate::support::no_debug_text(&scene, &msg);
                    }
                });
                assert!(result.is_ok(), "{scene}: line {} = {v} panicked", i + 1);
                runs += 1;
            }
        }
    }
    assert!(runs > 300, "{runs}");
}

/// Corrupted NC programs never panic and never hang: every seed program with one character
/// replaced at every 5th position by a hostile one interprets or fails cleanly.
#[test]
fn corrupted_programs_never_panic() {
    use vpcut::{Dialect, Limits};
    let root = crate::support::root().join("scenes");
    let cases = [
        (
            "seed002-siemens-equal-tooth",
            "MYBBB.SPF",
            Dialect::Siemens802d,
        ),
        ("seed004-tr100x12-macro-b", "TR100X12.NC", Dialect::Fanuc),
        ("seed003-g76-2in-12tpi", "G76-2IN-12TPI.NC", Dialect::Fanuc),
        ("seed000-gsk-equal-groove", "O0001.NC", Dialect::Gsk980),
        ("seed000-macro-a-equal-tooth", "O0003.NC", Dialect::Gsk980),
        (
            "../tests/data/linuxcnc",
            "oword-sub-g76.ngc",
            Dialect::Linuxcnc,
        ),
        (
            "../tests/data/linuxcnc",
            "oword-g33-loop.ngc",
            Dialect::Linuxcnc,
        ),
    ];
    let limits = Limits {
        max_blocks: 20_000,
        max_depth: 8,

        ..Limits::default()
    };
    let mut runs = 0;
    for (scene, file, dialect) in cases {
        runs += corrupt_and_run(&root.join(scene), file, dialect, 5, "[#=-X9 (;:/.", limits);
    }
    assert!(runs > 300, "{runs}");
}

/// The same corruption over issue 17's whole corpus (every dialect, the G70-G75 cycles,
/// CYCLE97/99, the 840D's DEF/PROC/structures, tapping): every 3rd character replaced in
/// turn by one that breaks syntax or values; the interpreter answers every variant with
/// moves or an error, never a panic.
#[test]
fn corrupted_corpus_programs_never_panic() {
    use vpcut::{Dialect, Limits};
    let folders = [
        ("fanuc", Dialect::Fanuc),
        ("gsk", Dialect::Gsk980),
        ("siemens", Dialect::Siemens802d),
        ("siemens-840d", Dialect::Siemens840d),
        ("linuxcnc", Dialect::Linuxcnc),
        ("okuma", Dialect::Okuma),
    ];
    let limits = Limits {
        max_blocks: 20_000,
        max_depth: 8,
        ..Limits::default()
    };
    let mut runs = 0;
    for (folder, dialect) in folders {
        let dir = crate::support::root().join("tests/data/nc").join(folder);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                p.extension().is_some_and(|x| x == "nc" || x == "MIN")
                    && p.file_name()
                        .unwrap()
                        .to_string_lossy()
                        .starts_with("corpus-")
            })
            .collect();
        files.sort();
        for path in files {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            runs += corrupt_and_run(&dir, &name, dialect, 3, "[#=-X9 (;:/.)]G,E", limits);
        }
    }
    assert!(runs > 5000, "{runs}");
}

/// Run `file` (in `dir`, subprograms beside it) with every `step`-th character replaced in
/// turn by one of `bad`, each variant under `catch_unwind`: a panic fails the test. Returns
/// the number of variants run.
fn corrupt_and_run(
    dir: &std::path::Path,
    file: &str,
    dialect: vpcut::Dialect,
    step: usize,
    bad: &str,
    limits: vpcut::Limits,
) -> usize {
    use vpcut::{interpret, Source};
    let chars: Vec<char> = std::fs::read_to_string(dir.join(file))
        .unwrap()
        .chars()
        .collect();
    let mut runs = 0;
    for (i, b) in (0..chars.len()).step_by(step).zip(bad.chars().cycle()) {
        let mut c = chars.clone();
        c[i] = b;
        let src = Source {
            name: file.into(),
            text: c.into_iter().collect(),
        };
        let load = |n: &str| {
            std::fs::read_to_string(dir.join(n)).ok().map(|t| Source {
                name: n.into(),
                text: t,
            })
        };
        let r = std::panic::catch_unwind(|| {
            if let Err(e) = interpret(&src, dialect, &load, limits) {
                crate::support::no_debug_text(file, &e.to_string());
            }
        });
        assert!(
            r.is_ok(),
            "{}/{file}: char {i} -> {b:?} panicked",
            dir.display()
        );
        runs += 1;
    }
    runs
}
