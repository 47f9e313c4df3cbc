//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};
use vpcut::{simulate, Job, Outcome, SimOptions};

/// The repository root.
pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The text of a scene's job file.
pub(crate) fn scene_text(name: &str) -> String {
    let p = root().join("scenes").join(name).join("job.toml");
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Set `table.key = value` in a TOML text (values written as TOML literals).
pub(crate) fn with(text: &str, edits: &[(&str, &str, &str)]) -> String {
    let mut doc: toml_edit::DocumentMut = text.parse().expect("valid TOML");
    for (table, key, value) in edits {
        let v: toml_edit::Item = format!("x = {value}")
            .parse::<toml_edit::DocumentMut>()
            .expect("valid value")["x"]
            .clone();
        if table.is_empty() {
            doc[key] = v;
        } else {
            if doc.get(table).is_none() {
                doc[table] = toml_edit::table();
            }
            doc[table][key] = v;
        }
    }
    doc.to_string()
}

/// A scene's job text made small for CLI tests: 72 angular cells, 0.05 mm axially, two
/// measurement generators (a run takes milliseconds).
pub(crate) fn small(scene: &str) -> String {
    with(
        &scene_text(scene),
        &[
            ("simulation", "angular_cells", "72"),
            ("simulation", "axial_spacing", "0.05"),
            ("simulation", "measure_generators", "2"),
        ],
    )
}

/// Parse a job or fail the test with the error.
pub(crate) fn job(text: &str) -> Job {
    Job::from_toml(text, "test.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// A scene's job, with its program files read from the scene's folder.
pub(crate) fn scene_job(name: &str) -> Job {
    let dir = root().join("scenes").join(name);
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    Job::from_toml_with(&scene_text(name), "job.toml", &load)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Simulate a scene.
pub(crate) fn run_scene(name: &str) -> Outcome {
    simulate(&scene_job(name), &SimOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Simulate a job text.
pub(crate) fn run(text: &str) -> Outcome {
    simulate(&job(text), &SimOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The report as JSON without the timing (the only part that changes between runs), the
/// version (it changes with every release, not with the results) and the input files (the
/// caller that reads them fills them in; the CLI tests check them).
pub(crate) fn report_json(out: &Outcome) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(&out.report.to_json()).unwrap();
    let o = v.as_object_mut().unwrap();
    for key in ["timing_s", "vpcut_version", "inputs"] {
        o.remove(key);
    }
    v
}

/// Scene folder names, sorted.
pub(crate) fn scenes() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .filter_map(|e| {
            let e = e.ok()?;
            e.path()
                .join("job.toml")
                .exists()
                .then(|| e.file_name().to_string_lossy().into_owned())
        })
        .collect();
    v.sort();
    v
}

/// Whether goldens are being re-blessed.
pub(crate) fn blessing() -> bool {
    std::env::var_os("VPCUT_BLESS").is_some_and(|v| v == "1")
}

/// Read a file as text, `None` when missing.
pub(crate) fn read(p: &Path) -> Option<String> {
    std::fs::read_to_string(p).ok()
}

/// An internal M20x2.5 (ISO 68-1: D1 = 17.2937, root flat P/8 at D) in a bore of D1, cut by
/// five radial layers with an insert whose tip flat is that root flat: the nut comes out
/// ideal (360 x 0.01 mm cells, 4 measurement generators; tests override what they need).
pub(crate) const INTERNAL_M20: &str = r#"
    [blank]
    diameter = 40.0
    bore = 17.29367
    length = 30.0
    [thread]
    side = "internal"
    form = "iso-metric"
    major_diameter = 20.0
    pitch = 2.5
    length = 20.0
    [[tool]]
    id = 1
    kind = "threading"
    angle = 60.0
    tip_flat = 0.3125
    reference = "tip"
    [process]
    kind = "radial"
    tool = 1
    layers = 5
    [simulation]
    angular_cells = 360
    axial_spacing = 0.01
    measure_generators = 4
"#;

/// Where a rendered job or program diagnostic points: the `file:line:col` of its first
/// `--> ` line, or the file of its `= in FILE` note when it has no line ("" when neither).
pub(crate) fn place(msg: &str) -> &str {
    msg.lines()
        .find_map(|l| {
            let l = l.trim_start();
            l.strip_prefix("--> ").or_else(|| l.strip_prefix("= in "))
        })
        .unwrap_or("")
}

/// Whether `text` holds a rendered diagnostic whose first line starts with `head`
/// (`error: message`) and whose next line points at `at` (`file:line:col`, the file's
/// name possibly after its folder).
pub(crate) fn has_diagnostic(text: &str, head: &str, at: &str) -> bool {
    let lines: Vec<&str> = text.lines().collect();
    lines.windows(2).any(|w| {
        let place = w[1].trim_start();
        w[0].starts_with(head) && place.starts_with("--> ") && place.ends_with(at)
    })
}

/// Run `f` in a pool of `threads` threads (the thread-count invariance tests).
pub(crate) fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// A small deterministic generator (splitmix64): the cases are the same on every run.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[a, b)`.
    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub(crate) fn pick<T: Copy>(&mut self, v: &[T]) -> T {
        v[(self.next() % v.len() as u64) as usize]
    }
}

/// Rust's debug formatting in a text a person reads (issue 29): `Some(..)`, `None`,
/// `Ok(..)`, `Err(..)`, a struct's `{ field: .. }`, an escaped quote `\"`. What a message
/// quotes of the user's own text, in backticks, is left out (a job's `{ x = 0 }` is the
/// user's, not a debug print).
pub(crate) fn debug_shape(s: &str) -> Option<&'static str> {
    // The text outside backtick quotes.
    let own: String = s
        .split('`')
        .enumerate()
        .filter(|(i, _)| i % 2 == 0)
        .map(|(_, t)| t)
        .collect::<Vec<_>>()
        .join(" ");
    let words = ["Some(", "Ok(", "Err(", "None", " { ", "\\\""];
    words.into_iter().find(|w| {
        own.match_indices(w).any(|(i, _)| match *w {
            // `None` as a word, not inside another one.
            "None" => {
                !own[i + 4..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_alphanumeric())
                    && !own[..i]
                        .chars()
                        .next_back()
                        .is_some_and(|c| c.is_alphanumeric())
            }
            // A struct's fields: `Name { field: ..`.
            " { " => {
                let rest = &own[i + 3..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                !name.is_empty() && rest[name.len()..].starts_with(':')
            }
            _ => true,
        })
    })
}

/// The lines of a rendered diagnostic (or of standard error) that are vpcut's own words:
/// `error: ..`, `warning: ..` and the `= ..` notes and hints; not the quoted source lines
/// (`3 | G0 X{`) or their carets.
pub(crate) fn own_lines(text: &str) -> impl Iterator<Item = &str> {
    text.lines().filter(|l| {
        let t = l.trim_start();
        t.starts_with("error") || t.starts_with("warning") || t.starts_with("= ")
    })
}

/// Assert that no own line of `text` has debug formatting (`what` names the case).
pub(crate) fn no_debug_text(what: &str, text: &str) {
    for l in own_lines(text) {
        assert_eq!(debug_shape(l), None, "{what}: {l}");
    }
}
