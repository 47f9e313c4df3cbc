//! Criterion benchmarks of the hot paths on the seed 002 equal-tooth scene at the issue's
//! resolution (0.01 mm axial, 3600 angular cells): the sweep kernel (throughput in dexel
//! updates per second, one and two threads), the comparison, and the whole simulation.
//! See benches/README.md.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;
use vpcut::{
    compare, plan_grid, simulate, simulate_report, sweep, Job, SimOptions, Stock, Surface,
};

fn scene(name: &str) -> Job {
    let path = format!("{}/scenes/{name}/job.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("scene");
    Job::from_toml(&text, &path).expect("valid scene")
}

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

fn bench_sweep(c: &mut Criterion) {
    for name in ["seed002-equal-tooth", "seed004-tr100x12"] {
        let job = scene(name);
        let (grid, _) = plan_grid(&job).unwrap();
        let mut probe = Stock::blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0);
        let updates = sweep(&mut probe, Surface::Outer, &job.passes, &job.tools).dexel_updates;
        let mut g = c.benchmark_group(format!("sweep/{name}"));
        g.sample_size(10).measurement_time(Duration::from_secs(8));
        g.throughput(Throughput::Elements(updates));
        for threads in [1, 2] {
            let p = pool(threads);
            // The kernel on a stock that is already faulted in: `min` against the same
            // passes again costs what the first sweep's arithmetic costs.
            g.bench_function(format!("{threads}-thread"), |b| {
                b.iter(|| p.install(|| sweep(&mut probe, Surface::Outer, &job.passes, &job.tools)))
            });
        }
        g.finish();
    }
}

fn bench_compare(c: &mut Criterion) {
    let mut g = c.benchmark_group("compare");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for name in ["seed002-equal-tooth", "seed002-equal-tooth-interpolated"] {
        let job = scene(name);
        let (grid, _) = plan_grid(&job).unwrap();
        let mut stock = Stock::blank(grid, job.blank.diameter / 2.0, 0.0);
        sweep(&mut stock, Surface::Outer, &job.passes, &job.tools);
        let window = (grid.z(0) - grid.dz, grid.z(grid.n_z - 1) + grid.dz);
        g.throughput(Throughput::Elements(grid.dexels() as u64));
        g.bench_function(name, |b| b.iter(|| compare(&stock, &job.thread, window)));
    }
    g.finish();
}

fn bench_simulate(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulate");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for name in ["seed002-equal-tooth", "seed002-equal-tooth-interpolated"] {
        let job = scene(name);
        g.bench_function(name, |b| {
            b.iter(|| simulate(&job, &SimOptions::default()).unwrap())
        });
        // The streaming pipeline (the CLI without --gltf/--png/--plots): the same report.
        g.bench_function(format!("{name}/stream"), |b| {
            b.iter(|| simulate_report(&job, &SimOptions::default()).unwrap())
        });
    }
    g.finish();
}

/// The gauges (issue 26): the M30x2 FANUC program of `tests/data/gauge` judged under
/// `M30x2-6g` (GO envelope, truncated NOT GO windows, root radius) against the same job
/// without a class (the nominal comparison only).
fn bench_gauge(c: &mut Criterion) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gauge");
    let text = std::fs::read_to_string(dir.join("m30x2.toml")).expect("gauge job");
    let load = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
    let mut g = c.benchmark_group("gauge/m30x2");
    g.sample_size(10).measurement_time(Duration::from_secs(15));
    for (name, designation) in [("6g", "M30x2-6g"), ("no-class", "M30x2")] {
        let text = text.replace("M30x2-6g", designation);
        let job = Job::from_toml_with(&text, "m30x2.toml", &load).expect("valid job");
        g.bench_function(name, |b| {
            b.iter(|| simulate_report(&job, &SimOptions::default()).unwrap())
        });
    }
    g.finish();
}

/// Issue 20's long screw (benches/jobs/screw-1m.toml, 3.6e8 dexels): streamed, and with
/// the whole grid kept (1.44 GB, over the default budget: raised here).
fn bench_long(c: &mut Criterion) {
    let path = format!("{}/benches/jobs/screw-1m.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("bench job");
    let job = Job::from_toml(&text, &path).expect("valid bench job");
    let mut g = c.benchmark_group("long/screw-1m");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    g.bench_function("stream", |b| {
        b.iter(|| simulate_report(&job, &SimOptions::default()).unwrap())
    });
    let whole = SimOptions {
        max_dexels: Some(400_000_000),
    };
    g.bench_function("full-grid", |b| b.iter(|| simulate(&job, &whole).unwrap()));
    g.finish();
}

/// `vpcut plan` (issue 7): planning seed 002's equal tooth width screw from its job text
/// (parse, plan, line check), writing and re-reading the FANUC program, and the whole
/// plan + simulate (target: under 2 s; the planner negligible beside the simulation).
fn bench_plan(c: &mut Criterion) {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/plans/seed002-equal-tooth.toml"),
    )
    .unwrap();
    let mut g = c.benchmark_group("plan/seed002-equal-tooth");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("plan", |b| {
        b.iter(|| Job::from_toml(&text, "job.toml").unwrap())
    });
    let job = Job::from_toml(&text, "job.toml").unwrap();
    let plan = job.plan.clone().unwrap();
    g.bench_function("post-and-read-back-fanuc", |b| {
        b.iter(|| {
            let nc = vpcut::post::post(&plan, 1, "bench", vpcut::post::Post::Fanuc).unwrap();
            job.with_program("plan.nc", &nc, "fanuc").unwrap()
        })
    });
    g.bench_function("plan-and-simulate", |b| {
        b.iter(|| {
            let job = Job::from_toml(&text, "job.toml").unwrap();
            simulate(&job, &SimOptions::default()).unwrap()
        })
    });
    g.finish();
}

/// Thread milling (issue 6): the seed 001 scene at 0.01 mm, the whole simulation and the
/// kernel alone, on two threads (target: under 2 s for the whole simulation).
fn bench_mill(c: &mut Criterion) {
    let dir = format!(
        "{}/scenes/seed001-m20x1.5-thread-mill",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(format!("{dir}/job.toml")).expect("scene");
    let load = |name: &str| std::fs::read_to_string(format!("{dir}/{name}")).ok();
    let job = Job::from_toml_with(&text, "job.toml", &load).expect("valid scene");
    let mill = job.mill.as_ref().expect("a milling job");
    let (grid, _) = plan_grid(&job).unwrap();
    let mut g = c.benchmark_group("mill/seed001-m20x1.5");
    g.sample_size(10).measurement_time(Duration::from_secs(15));
    let p = pool(2);
    g.bench_function("simulate-2-threads", |b| {
        b.iter(|| p.install(|| simulate(&job, &SimOptions::default()).unwrap()))
    });
    g.bench_function("sweep-2-threads", |b| {
        b.iter(|| {
            let mut stock = Stock::blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0);
            p.install(|| vpcut::sweep_mill(&mut stock, Surface::Inner, &mill.path, &mill.cutters))
        })
    });
    g.finish();
}

criterion_group!(benches, bench_sweep, bench_compare, bench_simulate);
criterion_group!(gauges, bench_gauge);
criterion_group!(milling, bench_mill);
criterion_group!(planning, bench_plan);
criterion_group!(long, bench_long);
criterion_main!(
    bodies,
    benches,
    gauges,
    interpreters,
    milling,
    planning,
    long
);

fn bench_interpreter(c: &mut Criterion) {
    use vpcut::{interpret, Dialect, Limits, Source};
    let mut g = c.benchmark_group("interpret");
    g.sample_size(10);
    // A Macro B loop of 1,000,000 executed blocks (4 per iteration).
    let macro_b = Source {
        name: "LOOP.NC".into(),
        text: "#1=0\nWHILE[#1LT250000]DO1\n#1=#1+1\n#2=#1*2+SIN[#1]\nEND1\nM30\n".into(),
    };
    g.bench_function("macro-b-1e6-blocks", |b| {
        b.iter(|| interpret(&macro_b, Dialect::Fanuc, &|_| None, Limits::default()).unwrap())
    });
    // A G76 whose depth schedule gives 10,000 passes (tiny first cut, no minimum step).
    let g76 = Source {
        name: "G76.NC".into(),
        text: "G0 X30 Z5\nG76 P010060 Q0 R0\nG76 X20 Z-20 P5000 Q50 F1\nM30\n".into(),
    };
    g.bench_function("g76-many-passes", |b| {
        b.iter(|| interpret(&g76, Dialect::Fanuc, &|_| None, Limits::default()).unwrap())
    });
    // The same loop in LinuxCNC O-words (3 blocks per iteration) and Siemens R parameters
    // with a label and a conditional backward jump (4 blocks per iteration).
    let lcnc = Source {
        name: "loop.ngc".into(),
        text: "#1=0\no1 while [#1 LT 333333]\n#1=[#1+1]\n#2=[#1*2+SIN[#1]]\no1 endwhile\nM2\n"
            .into(),
    };
    g.bench_function("linuxcnc-1e6-blocks", |b| {
        b.iter(|| interpret(&lcnc, Dialect::Linuxcnc, &|_| None, Limits::default()).unwrap())
    });
    let siemens = Source {
        name: "LOOP.MPF".into(),
        text: "R1=0\nTOP: R1=R1+1\nR2=R1*2+SIN(R1)\nIF R1<250000 GOTOB TOP\nM30\n".into(),
    };
    g.bench_function("siemens-1e6-blocks", |b| {
        b.iter(|| interpret(&siemens, Dialect::Siemens802d, &|_| None, Limits::default()).unwrap())
    });
    g.finish();
}

/// The sweep with a tool body behind the edge (issue 5's target: within 10x the planar
/// sweep), on the seed 002 equal-tooth scene at full resolution, two threads: the planar
/// edge; a body whose 2 deg side clearances the helix angle (up to 13 deg at the root)
/// overtakes on the leading flank all along the screw; seed 000's 11/-1 deg grind, which
/// rubs at the root of the last turns only; a 20 deg body that clears everywhere and is
/// skipped; and the 2 deg insert given as a mesh. Each run includes the preparation of the
/// sections and their tables.
fn bench_body(c: &mut Criterion) {
    let job = scene("seed002-equal-tooth");
    let (grid, _) = plan_grid(&job).unwrap();
    let with_body = |left: f64, right: f64| {
        let mut tools = job.tools.clone();
        for t in &mut tools {
            t.body = Some(vpcut::Body {
                thickness: 4.0,
                clearance_left: left.to_radians(),
                clearance_right: right.to_radians(),
                clearance_front: 5f64.to_radians(),
                inclination: 0.0,
            });
        }
        tools
    };
    // The rubbing 2 deg insert as a mesh (its six planes): the face-plane code a mesh tool
    // runs, with its bands beside the edge's flat instead of the insert's along the flanks.
    let mesh = {
        let (s2, t5) = (2f64.to_radians().tan(), 5f64.to_radians().tan());
        let (w, d, top) = (3.0f64, 4.0f64, 8.0f64);
        // The scene's tool drives its right corner: the mesh's origin.
        let front = [[0.0, -w], [0.0, 0.0], [top, 0.0], [top, -w]];
        let back = [
            [d * t5, -w + d * s2],
            [d * t5, -d * s2],
            [top, -d * s2],
            [top, -w + d * s2],
        ];
        let (v, t) = vpcut::prism(&front, &back, d);
        let solid = std::sync::Arc::new(vpcut::Solid::from_mesh(&v, &t).unwrap());
        let mut tools = job.tools.clone();
        for tool in &mut tools {
            tool.edge = vpcut::Edge::Mesh {
                solid: solid.clone(),
                body: true,
            };
        }
        tools
    };
    let mut g = c.benchmark_group("sweep-body/seed002-equal-tooth");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let p = pool(2);
    for (name, tools) in [
        ("planar", job.tools.clone()),
        ("body-rubbing-2deg", with_body(2.0, 2.0)),
        ("body-11-minus-1deg", with_body(11.0, -1.0)),
        ("body-clear-20deg", with_body(20.0, 20.0)),
        ("mesh-rubbing-2deg", mesh),
    ] {
        let mut stock = Stock::blank(grid, job.blank.diameter / 2.0, job.blank.bore / 2.0);
        g.bench_function(name, |b| {
            b.iter(|| p.install(|| sweep(&mut stock, Surface::Outer, &job.passes, &tools)))
        });
    }
    g.finish();
}

criterion_group!(interpreters, bench_interpreter);
criterion_group!(bodies, bench_body);
