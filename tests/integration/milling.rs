//! Thread milling: the same bytes with 1 and 2 threads, the sampled envelope against a path
//! sampled four times finer (the stated bound), and milling-job errors that name the key.

use crate::support::{report_json, root, scene_job};
use vpcut::{simulate, sweep_mill, MillPath, SimOptions, Stock, Surface};

fn small(scene: &str) -> vpcut::Job {
    let mut job = scene_job(scene);
    job.sim.angular_cells = 360;
    job.sim.axial_spacing = 0.02;
    job
}

#[test]
fn milling_gives_identical_bytes_with_one_and_two_threads() {
    let job = small("seed001-m20x1.5-thread-mill");
    let run = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| simulate(&job, &SimOptions::default()).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(report_json(&a).to_string(), report_json(&b).to_string());
    let (ia, ib) = (a.stock.inner.unwrap(), b.stock.inner.unwrap());
    assert!(ia.iter().zip(&ib).all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// Four times the samples: the cut can only deepen (the coarse samples are a subset), and by no more than the stated
/// bound, counted on the radius with the flank slope (1 / sin 30 for a 60 deg tooth).
#[test]
fn finer_sampling_stays_within_the_stated_bound() {
    let job = small("seed001-m20x1.5-thread-mill");
    let mill = job.mill.as_ref().unwrap();
    let (grid, _) = vpcut::plan_grid(&job).unwrap();
    let fine = MillPath::refined(mill.path.moves.clone(), &mill.cutters, 4).unwrap();
    assert!(fine.len() + 4 * mill.path.moves.len() >= 4 * mill.path.len());
    let cut = |path: &MillPath| {
        let mut s = Stock::blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0);
        sweep_mill(&mut s, Surface::Inner, path, &mill.cutters);
        s.inner.unwrap()
    };
    let (coarse, fine) = (cut(&mill.path), cut(&fine));
    let worst = coarse
        .iter()
        .zip(&fine)
        .map(|(c, f)| (c - f) as f64)
        .fold(f64::NEG_INFINITY, f64::max);
    let bound = vpcut::MILL_SAMPLING_BOUND_MM / 30f64.to_radians().sin();
    assert!(
        worst <= bound,
        "coarse is {worst} mm shallower, bound {bound}"
    );
    assert!(
        worst > 1e-5,
        "the test must see the sampling at all ({worst})"
    );
}

#[test]
fn milling_job_errors_name_the_key() {
    let dir = root().join("scenes").join("seed001-m20x1.5-thread-mill");
    let text = std::fs::read_to_string(dir.join("job.toml")).unwrap();
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    let cases = [
        ("teeth = 18", "teeth = 0", "tool[0].teeth"),
        ("tooth_depth = 0.92", "tooth_depth = 1.3", "overlap"),
        ("kind = \"mill\"", "kind = \"lathe\"", "milling jobs only"),
        ("d = 60 ", "width = 2.0\nd = 60 ", "tool[0].width"),
        (
            "dialect = \"fanuc\"",
            "dialect = \"linuxcnc\"",
            "program.dialect",
        ),
    ];
    for (from, to, want) in cases {
        assert!(text.contains(from), "{from}");
        let bad = text.replacen(from, to, 1);
        let e = vpcut::Job::from_toml_with(&bad, "job.toml", &load)
            .unwrap_err()
            .to_string();
        assert!(crate::support::place(&e).starts_with("job.toml"), "{e}");
        assert!(e.contains(want), "{to}: {e}");
    }
    // A program error names the program's file and line: D61 is no radius offset of the job.
    let prog = std::fs::read_to_string(dir.join("O0001.nc")).unwrap();
    let bad_prog = prog.replace("D60", "D61");
    let load2 = |f: &str| {
        if f == "O0001.nc" {
            Some(bad_prog.clone())
        } else {
            None
        }
    };
    let e = vpcut::Job::from_toml_with(&text, "job.toml", &load2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("O0001.nc:6") && e.contains("D61"), "{e}");
}
