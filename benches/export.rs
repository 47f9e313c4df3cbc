//! Criterion benchmarks of the export path on the seed scenes at their own resolution:
//! mesh extraction from the dexel grid (one and two threads), `.glb` encoding, and the
//! headless render of a 1024x768 picture with 4x MSAA, and the whole `--gltf` run streamed
//! against the full grid. See benches/README.md.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;
use vpcut::{
    build_scene, simulate, simulate_meshed, simulate_report, to_glb, Job, RenderOptions, Renderer,
    SceneOptions, SimOptions, View,
};

fn scene(name: &str) -> Job {
    let dir = format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(format!("{dir}/job.toml")).expect("scene");
    let load = |f: &str| std::fs::read_to_string(format!("{dir}/{f}")).ok();
    Job::from_toml_with(&text, "job.toml", &load).expect("valid scene")
}

fn bench_mesh(c: &mut Criterion) {
    for name in ["seed002-equal-tooth", "seed004-tr100x12"] {
        let job = scene(name);
        let out = simulate(&job, &SimOptions::default()).unwrap();
        let mut g = c.benchmark_group(format!("mesh/{name}"));
        g.sample_size(10).measurement_time(Duration::from_secs(6));
        g.throughput(Throughput::Elements(out.stock.stored_dexels() as u64));
        for threads in [1, 2] {
            let p = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            g.bench_function(format!("{threads}-thread"), |b| {
                b.iter(|| p.install(|| build_scene(&job, &out, &SceneOptions::default())))
            });
        }
        let s = build_scene(&job, &out, &SceneOptions::default());
        g.bench_function("glb", |b| b.iter(|| to_glb(&s).unwrap()));
        g.finish();
    }
}

/// Issue 20, fourth round: the whole `--gltf` run streamed (`simulate_meshed`) against the
/// full grid kept and meshed (`simulate` + `build_scene`) and the report alone
/// (`simulate_report`), on the machine's threads.
fn bench_streamed_model(c: &mut Criterion) {
    for name in ["seed002-equal-tooth", "seed004-tr100x12"] {
        let job = scene(name);
        let (sim, mesh) = (SimOptions::default(), SceneOptions::default());
        let mut g = c.benchmark_group(format!("model/{name}"));
        g.sample_size(10).measurement_time(Duration::from_secs(10));
        g.bench_function("report-only", |b| {
            b.iter(|| simulate_report(&job, &sim).unwrap())
        });
        g.bench_function("streamed", |b| {
            b.iter(|| simulate_meshed(&job, &sim, &mesh).unwrap().into_scene())
        });
        g.bench_function("full-grid", |b| {
            b.iter(|| build_scene(&job, &simulate(&job, &sim).unwrap(), &mesh))
        });
        g.finish();
    }
}

/// One picture, 1024x768 with 4x MSAA, on the adapter wgpu picks (lavapipe on the CI
/// machine), the device made once: upload, draw, read back, legend, PNG encoding.
fn bench_render(c: &mut Criterion) {
    let Ok(r) = Renderer::new(4) else {
        eprintln!("no adapter: render benchmarks skipped");
        return;
    };
    eprintln!("adapter: {}", r.adapter());
    for name in ["seed002-equal-tooth", "seed004-tr100x12"] {
        let job = scene(name);
        let out = simulate(&job, &SimOptions::default()).unwrap();
        let scene = build_scene(
            &job,
            &out,
            &SceneOptions {
                mesh_tolerance: None,
                ideal: true,
            },
        );
        let mut g = c.benchmark_group(format!("render/{name}"));
        g.sample_size(10).measurement_time(Duration::from_secs(5));
        for view in [View::Iso, View::Section] {
            let opts = RenderOptions {
                view,
                ..RenderOptions::default()
            };
            g.bench_function(format!("{}-1024x768-msaa4", view.name()), |b| {
                b.iter(|| r.png(&scene, &opts).unwrap())
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench_mesh, bench_streamed_model, bench_render);
criterion_main!(benches);
