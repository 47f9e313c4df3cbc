//! The model meshed while the columns stream (`simulate_meshed`, what `--gltf` alone runs)
//! against the oracle of the full-grid run (`simulate` then `build_scene`, which keeps the
//! whole grid): the same scene, mesh for mesh, and the same `.glb` bytes, on every scene
//! (coarsened) at several mesh tolerances (the kept columns' intervals from one column to
//! a hundred), 1 and 2 threads; at full resolution on an external thread, an internal
//! one on a tube (both surfaces meshed, the uncut one the blank), an external thread on
//! a tube, a rubbing tool body (the edge stock's colours) and thread milling. The report
//! is the full-grid run's, byte for byte; the dexel budget counts the interval buffers.

use crate::support::in_pool;
use crate::support::{report_json, scene_job, scenes, small};
use vpcut::{
    build_scene, simulate, simulate_meshed, to_glb, Job, Scene, SceneOptions, SimError, SimOptions,
};

/// A report as the tests compare it (timing, version and inputs aside).
fn json(r: &vpcut::Report) -> String {
    let mut v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
    let o = v.as_object_mut().unwrap();
    for key in ["timing_s", "vpcut_version", "inputs"] {
        o.remove(key);
    }
    v.to_string()
}

/// The streamed scene of `j` against the full grid's, for every option in `opts`, on 1
/// and 2 threads: the scene equal (the stock mesh exactly, the focus, the ideal sheet),
/// the `.glb` bytes equal, the report equal. Returns whether some scene had a focus.
fn both_ways(what: &str, j: &Job, opts: &[SceneOptions]) -> bool {
    let full = simulate(j, &SimOptions::default()).unwrap();
    let report = report_json(&full).to_string();
    let mut focused = false;
    for o in opts {
        let want: Scene = build_scene(j, &full, o);
        assert!(!want.stock.indices.is_empty(), "{what}: an empty mesh");
        let want_glb = to_glb(&want).unwrap();
        focused |= want.focus.is_some();
        for threads in [1, 2] {
            let m = in_pool(threads, || simulate_meshed(j, &SimOptions::default(), o)).unwrap();
            let here = format!("{what}, {o:?}, {threads} thread(s)");
            assert_eq!(report, json(&m.report), "{here}: the report");
            assert_eq!(full.deviation, m.deviation, "{here}: the deviation");
            let got = m.into_scene();
            assert_eq!(want.stock.positions, got.stock.positions, "{here}");
            assert_eq!(want.stock.colors, got.stock.colors, "{here}");
            assert_eq!(want.stock.indices, got.stock.indices, "{here}");
            assert_eq!(want.focus, got.focus, "{here}: the focus");
            assert!(want == got, "{here}: the scenes differ");
            assert!(
                want_glb == to_glb(&got).unwrap(),
                "{here}: the .glb bytes differ"
            );
        }
    }
    focused
}

/// The default mesh, the ideal sheet, every dexel (intervals of one column), and a coarse
/// tolerance (the fewest kept columns: long intervals).
fn options() -> Vec<SceneOptions> {
    vec![
        SceneOptions::default(),
        SceneOptions {
            mesh_tolerance: None,
            ideal: true,
        },
        SceneOptions {
            mesh_tolerance: Some(0.0),
            ideal: false,
        },
        SceneOptions {
            mesh_tolerance: Some(0.5),
            ideal: false,
        },
    ]
}

#[test]
fn every_scene_meshes_the_same_streamed_and_from_the_full_grid() {
    let mut focused = 0;
    for scene in scenes() {
        let mut j = scene_job(&scene);
        j.sim.angular_cells = 72;
        j.sim.axial_spacing = j.sim.axial_spacing.max(0.05);
        j.sim.measure_generators = 2;
        focused += both_ways(&scene, &j, &options()) as usize;
    }
    // The focus (the worst dexel's radius, from the column cut again) is exercised.
    assert!(focused > 3, "{focused} scenes with a focus");
}

#[test]
fn full_resolution_scenes_mesh_the_same_streamed() {
    let opts = [SceneOptions {
        mesh_tolerance: None,
        ideal: true,
    }];
    // External, badly cut (a focus); a rubbing body (edge colours); internal on a tube;
    // thread milling (internal, a tube).
    for scene in [
        "seed002-equal-tooth",
        "seed000-tool-rub",
        "seed001-comp-flipped",
        "seed001-m20x1.5-thread-mill",
    ] {
        both_ways(scene, &scene_job(scene), &opts);
    }
    // An external thread on a tube: the uncut bore is meshed from the blank.
    let mut j = scene_job("seed002-equal-tooth");
    j.blank.bore = 10.0;
    both_ways("seed002-equal-tooth on a tube", &j, &opts);
}

/// The streamed mesh's budget: a buffer of the widest interval between kept columns per
/// thread (and the edges' cut beside it with rubbing bodies) instead of a column, far under
/// the grid; the error says so, and a budget of the bytes stated admits the run.
#[test]
fn the_streamed_mesh_budget_counts_the_interval_buffers() {
    let j = crate::support::job(&small("seed002-equal-tooth"));
    let (n_theta, n_z) = (72u64, 2000u64);
    let opts = |n: u64| SimOptions {
        max_dexels: Some(n),
    };
    let mesh = SceneOptions::default();
    let bytes_of = |e: SimError| match e {
        SimError::DexelBudget { bytes, held_as, .. } => (bytes, held_as),
        e => panic!("{e}"),
    };
    let (report, _) = bytes_of(in_pool(2, || vpcut::simulate_report(&j, &opts(0))).unwrap_err());
    let err = in_pool(2, || simulate_meshed(&j, &opts(0), &mesh)).unwrap_err();
    let msg = err.to_string();
    let (bytes, held_as) = bytes_of(err);
    // 72 columns, at least 16 kept: intervals of at most 5 columns, held whole (both
    // ends) on each of 2 threads, where the report holds one column per thread.
    assert!(
        held_as.contains("(the model is meshed as they stream: the columns from one of its kept columns to the next, at most"),
        "{msg}"
    );
    assert!(bytes >= report, "{msg}");
    assert!(bytes < report + 4 * n_theta * n_z / 4, "{msg}");
    let dexels = bytes.div_ceil(4);
    assert!(in_pool(2, || simulate_meshed(&j, &opts(dexels), &mesh)).is_ok());
    assert!(in_pool(2, || simulate_meshed(&j, &opts(dexels - 1), &mesh)).is_err());
}
