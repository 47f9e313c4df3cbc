//! The streaming pipeline (`simulate_report`: a column per thread, the grid never held)
//! gives the report of the full-grid run (`simulate`), byte for byte, for any thread
//! count; the dexel budget is on the memory a run holds, and says so.

use crate::support::in_pool;
use crate::support::{report_json, scene_job, scenes, small};
use vpcut::{simulate, simulate_report, Job, SimError, SimOptions};

/// A report as the tests compare it (timing, version and inputs aside).
fn json(r: vpcut::Report) -> String {
    let mut v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    let o = v.as_object_mut().unwrap();
    for key in ["timing_s", "vpcut_version", "inputs"] {
        o.remove(key);
    }
    v.to_string()
}

fn streamed(j: &Job, threads: usize) -> String {
    json(in_pool(threads, || {
        simulate_report(j, &SimOptions::default()).unwrap()
    }))
}

/// Every scene, coarsened (with its program files), streamed on 1 and 2 threads, against
/// the full-grid run.
#[test]
fn streaming_and_full_grid_reports_are_identical() {
    for scene in scenes() {
        let mut j = scene_job(&scene);
        j.sim.angular_cells = 72;
        j.sim.axial_spacing = j.sim.axial_spacing.max(0.05);
        j.sim.measure_generators = 2;
        let full = report_json(&simulate(&j, &SimOptions::default()).unwrap()).to_string();
        for threads in [1, 2] {
            assert_eq!(full, streamed(&j, threads), "{scene}, {threads} thread(s)");
        }
    }
}

/// At the scenes' own resolution: a badly wrong cut (seed 002's literal passes, where most
/// points need a normal distance) and a rubbing tool body (the edges' second sweep and the
/// interference table), 1 and 2 threads.
#[test]
fn streaming_matches_at_full_resolution() {
    for scene in ["seed002-equal-tooth", "seed000-tool-rub"] {
        let j = scene_job(scene);
        let full = report_json(&simulate(&j, &SimOptions::default()).unwrap()).to_string();
        for threads in [1, 2] {
            assert_eq!(full, streamed(&j, threads), "{scene}, {threads} thread(s)");
        }
    }
}

/// The budget counts what is held: the whole grid for a full-grid run (twice with swept
/// bodies), a column per thread for a streaming one, each with what the comparison and
/// the measurement hold, in bytes, and the error says which. (`tests/budget.rs` checks
/// the bytes against a counting allocator.)
#[test]
fn the_dexel_budget_error_states_the_memory_held() {
    let j = crate::support::job(&small("seed002-equal-tooth"));
    let (n_theta, n_z) = (72u64, 2000u64);
    let opts = |n: u64| SimOptions {
        max_dexels: Some(n),
    };
    // The full grid: 72 x 2000 dexels of 4 bytes, and the rest (on 2 threads, as the
    // streamed run below).
    let err = in_pool(2, || simulate(&j, &opts(0))).unwrap_err();
    let msg = err.to_string();
    let SimError::DexelBudget { bytes, .. } = err else {
        panic!("{msg}")
    };
    let kept = bytes;
    assert!(bytes > 4 * n_theta * n_z, "{msg}");
    assert!(
        msg.contains("the whole grid, 72 angular x 2000 axial x 1 surface(s)"),
        "{msg}"
    );
    assert!(msg.contains("(576 kB)"), "{msg}");
    assert!(
        msg.contains("over the budget of 0 bytes (0 dexels of 4 bytes)"),
        "{msg}"
    );
    // A budget of the bytes stated, in dexels, admits the run; one dexel less does not.
    let dexels = bytes.div_ceil(4);
    assert!(simulate(&j, &opts(dexels)).is_ok());
    assert!(simulate(&j, &opts(dexels - 1)).is_err());
    // Streamed: a column per thread.
    let err = in_pool(2, || simulate_report(&j, &opts(0))).unwrap_err();
    let msg = err.to_string();
    let SimError::DexelBudget { bytes, .. } = err else {
        panic!("{msg}")
    };
    // Less than the kept run by the grid (the measurement generators are the peak of both).
    assert_eq!(kept - bytes, 4 * n_theta * n_z, "{msg}");
    assert!(
        msg.contains("2 column(s) of 2000 axial cells, 1 per thread on 2 thread(s)"),
        "{msg}"
    );
    assert!(in_pool(2, || simulate_report(&j, &opts(bytes.div_ceil(4)))).is_ok());
    // With a rubbing body the edges' cut is held too: two columns per thread.
    let rub = crate::support::job(&small("seed000-tool-rub"));
    let err = in_pool(1, || simulate_report(&rub, &opts(1))).unwrap_err();
    assert!(err.to_string().contains("2 per thread"), "{err}");
}
