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

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
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

/// Table: scenes with and without tool bodies, a turned profile, a thread mill; grids
/// fine and coarse in both directions; 1 and 2 threads; kept and streamed. Every run's
/// real peak is within its budget; on the grids whose cells dominate (over 20 MB) the
/// budget is at most twice the peak.
#[test]
fn the_budget_bounds_the_real_peak() {
    let cases: &[(&str, usize, f64)] = &[
        ("seed002-equal-tooth", 720, 0.01),
        ("seed002-equal-tooth", 3600, 0.005),
        ("seed002-equal-tooth", 90, 0.002),
        ("seed000-tool-rub", 720, 0.01),
        ("seed000-tool-rub", 180, 0.002),
        ("turned-m20x2.5-fanuc", 720, 0.01),
        ("seed001-m20x1.5-thread-mill", 360, 0.01),
        ("seed004-tr100x12", 360, 0.01),
    ];
    let mut failures = Vec::new();
    for &(scene, angular, axial) in cases {
        let mut job = scene_job(scene);
        job.sim.angular_cells = angular;
        job.sim.axial_spacing = axial;
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
