//! Bad input never panics: every number of every scene replaced by hostile values must give
//! either a job that simulates or a clean error.

use crate::support::{scene_text, scenes};
use vpcut::{simulate, Job, Options};

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
                        let _ = simulate(
                            &job,
                            &Options {
                                max_dexels: Some(4_000_000),
                            },
                        );
                    }
                    Err(e) => {
                        let msg = e.to_string();
                        assert!(msg.starts_with("job.toml"), "{msg}");
                    }
                });
                assert!(result.is_ok(), "{scene}: line {} = {v} panicked", i + 1);
                runs += 1;
            }
        }
    }
    assert!(runs > 300, "{runs}");
}
