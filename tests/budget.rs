//! The dexel budget bounds the memory a run really holds (issue 20). A test binary of its
//! own: it installs a counting global allocator (every allocation, deallocation and
//! reallocation of every thread adds to or takes from one count, and the count's peak is
//! kept), which must not leak into the other tests.
//!
//! The oracle is the allocator: for each case the run's budget is read from the error a
//! budget of 0 gives (`SimError::DexelBudget { bytes, .. }`: what the run says it would
//! hold at once), then the run is made with a budget that admits it, and the peak of the
//! bytes allocated above the count before the run (the returned stocks and report
//! included) must not exceed it, up to a fixed allowance for what does not grow with the
//! part (the job's copies, the thread pool's bookkeeping, the report's fixed fields). The
//! budget must also not be loose: on the large grids the real peak is at least half of it.
//!
//! Also here: how a budget is written, on the command line (`--max-dexels`) and in the
//! job (`[simulation] max_dexels`), good and bad values in a table. The tests of this
//! binary take one lock, so that no other test allocates while a peak is measured.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use vpcut::{simulate, simulate_report, Job, SimError, SimOptions};

/// The system allocator, counting the bytes held and their peak.
struct Counting;

static HELD: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(n: usize) {
    let now = HELD.fetch_add(n, Ordering::SeqCst) + n;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

// SAFETY: every call goes to `System` with the same arguments; the counts are only read.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            grow(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            grow(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        HELD.fetch_sub(layout.size(), Ordering::SeqCst);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            // Count the new block before the old one goes: a moving realloc holds both.
            grow(new_size);
            HELD.fetch_sub(layout.size(), Ordering::SeqCst);
        }
        p
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// One test at a time in this binary.
static ONE: Mutex<()> = Mutex::new(());

/// What does not grow with the part: the allowance over the budget.
const FIXED: u64 = 1_000_000;

fn scene_job(name: &str) -> Job {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    Job::from_toml_with(&text, "job.toml", &load).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// What a run of `job` says it would hold, and the peak it really holds, on `threads`
/// threads, the whole grid kept (`keep`) or streamed.
fn budget_and_peak(job: &Job, threads: usize, keep: bool) -> (u64, u64, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let run = |limit: u64| {
            let opts = SimOptions {
                max_dexels: Some(limit),
            };
            if keep {
                simulate(job, &opts).map(|o| drop(std::hint::black_box(o)))
            } else {
                simulate_report(job, &opts).map(|r| drop(std::hint::black_box(r)))
            }
        };
        let (bytes, said) = match run(0) {
            Err(e @ SimError::DexelBudget { bytes, .. }) => (bytes, e.to_string()),
            other => panic!("a budget of 0 admits the run: {other:?}"),
        };
        // Warm the pool's threads (their first jobs allocate bookkeeping).
        pool.broadcast(|_| ());
        let base = HELD.load(Ordering::SeqCst);
        PEAK.store(base, Ordering::SeqCst);
        run(bytes.div_ceil(4)).unwrap_or_else(|e| panic!("the budget it states: {e}"));
        let peak = PEAK.load(Ordering::SeqCst).saturating_sub(base) as u64;
        (bytes, peak, said)
    })
}

/// Table: scenes with and without tool bodies (seed 000's rubbing insert), a turned
/// profile, a thread mill in a bore (two surfaces), a multi-start trapezoidal screw; grids
/// fine and coarse in both directions; fine measurement columns; 1 and 2 threads; kept and
/// streamed. Every run's
/// real peak is within its budget; on the grids whose cells dominate (over 20 MB) the
/// budget is at most twice the peak.
#[test]
fn the_budget_bounds_the_real_peak() {
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    // (scene, angular cells, axial spacing, measurement spacing: the default 0.5 um, or
    // 0.05 um where the measurement generators hold more than the columns).
    let cases: &[(&str, usize, f64, f64)] = &[
        ("seed002-equal-tooth", 720, 0.01, 5e-4),
        ("seed002-equal-tooth", 3600, 0.005, 5e-4),
        ("seed002-equal-tooth", 90, 0.002, 5e-4),
        ("seed002-equal-tooth", 72, 0.05, 5e-5),
        ("iso-m20x2.5-radial", 3600, 0.01, 5e-4),
        ("seed000-tool-rub", 720, 0.01, 5e-4),
        ("seed000-tool-rub", 180, 0.002, 5e-4),
        ("turned-m20x2.5-fanuc", 720, 0.01, 5e-4),
        ("seed001-m20x1.5-thread-mill", 360, 0.01, 5e-4),
        ("seed004-tr100x12", 360, 0.01, 5e-4),
    ];
    let mut failures = Vec::new();
    for &(scene, angular, axial, measure) in cases {
        let mut job = scene_job(scene);
        job.sim.angular_cells = angular;
        job.sim.axial_spacing = axial;
        job.sim.measure_spacing = measure;
        job.sim.measure_generators = 4;
        for threads in [1, 2] {
            for keep in [true, false] {
                let (budget, peak, said) = budget_and_peak(&job, threads, keep);
                let case = format!(
                    "{scene} {angular} x {axial} mm, {threads} thread(s), {}: budget {budget}, peak {peak}",
                    if keep { "kept" } else { "streamed" }
                );
                eprintln!("{case}");
                if peak > budget + FIXED {
                    failures.push(format!("{case}: over the budget\n  {said}"));
                }
                if budget > 20_000_000 && budget > 2 * peak {
                    failures.push(format!("{case}: the budget is loose\n  {said}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Values a CNC engineer writes for a count, with the budget they mean (`None`: refused,
/// with the words the error must hold). TOML reads `4e8` and `4.0e8` as floats and
/// `400_000_000` as an integer; the command line takes the same text.
const VALUES: &[(&str, Option<u64>, &str)] = &[
    ("400000000", Some(400_000_000), ""),
    ("400_000_000", Some(400_000_000), ""),
    ("4e8", Some(400_000_000), ""),
    ("4.0e8", Some(400_000_000), ""),
    ("4E8", Some(400_000_000), ""),
    ("2.5e8", Some(250_000_000), ""),
    ("1e15", Some(1_000_000_000_000_000), ""),
    ("0", Some(0), ""),
    ("1.5", None, "whole number"),
    ("1e-3", None, "whole number"),
    ("4.5e0", None, "whole number"),
    ("-1", None, "0"),
    ("-4e8", None, "0"),
    ("nan", None, ""),
    ("inf", None, ""),
    ("1e16", None, "1e15"),
];

fn scene_text(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .join("job.toml");
    std::fs::read_to_string(p).unwrap()
}

/// The job with `max_dexels = value` in its `[simulation]` table (on a line of its own
/// right after the header: the error's line is known).
fn with_budget(text: &str, value: &str) -> (String, usize) {
    let at = text.find("[simulation]\n").expect("a [simulation] table");
    let line = text[..at].lines().count() + 2;
    let out = format!(
        "{}[simulation]\nmax_dexels = {value}\n{}",
        &text[..at],
        &text[at + "[simulation]\n".len()..]
    );
    (out, line)
}

/// `[simulation] max_dexels` takes every good value as the budget it means, and refuses
/// every bad one with an error that names the key, its line and column.
#[test]
fn the_job_key_takes_counts_as_written() {
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let text = scene_text("iso-m20x2.5-radial");
    for &(value, want, words) in VALUES {
        let (job, line) = with_budget(&text, value);
        match (Job::from_toml(&job, "job.toml"), want) {
            (Ok(j), Some(n)) => assert_eq!(j.sim.max_dexels, n, "{value}"),
            (Err(e), None) => {
                let msg = e.to_string();
                let vpcut::JobError::Invalid {
                    key, line: l, col, ..
                } = &e
                else {
                    panic!("{value}: not a key's error: {msg}")
                };
                assert_eq!(key, "simulation.max_dexels", "{value}: {msg}");
                assert_eq!((*l, *col), (line, 14), "{value}: {msg}");
                assert!(msg.contains(words), "{value}: wanted {words:?} in {msg}");
            }
            (got, _) => panic!("{value}: {got:?}"),
        }
    }
    // Not a number at all.
    let (job, _) = with_budget(&text, "\"4e8\"");
    let e = Job::from_toml(&job, "job.toml").unwrap_err().to_string();
    assert!(
        e.contains("simulation.max_dexels") && e.contains("whole number"),
        "{e}"
    );
}

/// `--max-dexels` takes the same values as the key (and refuses the same, exit 2, with
/// the value in the message), on `simulate` and on `check`; the budget it sets is the one
/// the run is held to (a budget of 0 refuses the run, saying what it would hold).
#[test]
fn the_option_takes_counts_as_written() {
    let _one = ONE.lock().unwrap_or_else(|e| e.into_inner());
    let dir = std::env::temp_dir().join(format!("vpcut-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let job = dir.join("job.toml");
    let mut doc: toml_edit::DocumentMut = scene_text("iso-m20x2.5-radial").parse().unwrap();
    doc["simulation"]["angular_cells"] = toml_edit::value(72);
    doc["simulation"]["axial_spacing"] = toml_edit::value(0.05);
    doc["simulation"]["measure_generators"] = toml_edit::value(2);
    let text = doc.to_string();
    std::fs::write(&job, text).unwrap();
    let bad_words = [
        "not a whole number",
        "whole number of dexels",
        "from 0 to 1e15",
    ];
    for command in ["simulate", "check"] {
        for &(value, want, words) in VALUES {
            let out = Command::new(env!("CARGO_BIN_EXE_vpcut"))
                .args([command, job.to_str().unwrap(), "-q"])
                .arg(format!("--max-dexels={value}"))
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            match want {
                Some(0) => {
                    assert_eq!(out.status.code(), Some(2), "{command} {value}: {err}");
                    assert!(
                        err.contains("the run would hold")
                            && err.contains("over the budget of 0 bytes"),
                        "{command} {value}: {err}"
                    );
                }
                Some(_) => assert!(
                    out.status.code() == Some(0) || out.status.code() == Some(1),
                    "{command} {value}: {err}"
                ),
                None => {
                    assert_eq!(out.status.code(), Some(2), "{command} {value}: {err}");
                    assert!(
                        err.contains(&format!("`{value}`"))
                            && err.contains(words)
                            && bad_words.iter().any(|w| err.contains(w)),
                        "{command} {value}: {err}"
                    );
                }
            }
        }
        for value in ["", "abc", "_4", "4__0", "4e8.5", "0x10"] {
            let out = Command::new(env!("CARGO_BIN_EXE_vpcut"))
                .args([command, job.to_str().unwrap(), "-q"])
                .arg(format!("--max-dexels={value}"))
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{command} {value}: {err}");
            assert!(
                err.contains("whole number of dexels"),
                "{command} {value}: {err}"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
