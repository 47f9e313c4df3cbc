//! Criterion benchmark of the NC interpreter on large LinuxCNC programs (issue 17: 200k
//! blocks were super-linear in `vpcut toolpath`): `interpret` and `to_csv` of generated
//! programs of 20k and 200k blocks (G1 turning, G0, parameter arithmetic and G33 passes);
//! throughput in blocks/s, so a quadratic regression shows as the 200k figure falling
//! far below the 20k one. See benches/README.md.

#![allow(missing_docs)] // criterion_group! generates undocumented functions.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::fmt::Write as _;
use std::time::Duration;
use vpcut::{interpret, to_csv, Dialect, Limits, Source};

/// A LinuxCNC program of `n` blocks, deterministic (no random source: values from k).
fn program(n: usize) -> String {
    let mut s = String::from("G18 G7 G21 G90\nM3 S500\nG0 X40 Z5\n#<a> = 0\n");
    for k in 0..n.saturating_sub(5) {
        let f = (k % 97) as f64 / 97.0;
        let _ = match k % 4 {
            0 => writeln!(s, "G1 X{:.4} Z{:.4} F0.2", 30.0 + f, -50.0 * f),
            1 => writeln!(s, "G0 X{:.4}", 40.0 + f),
            2 => writeln!(s, "#<a> = [#<a> + 1]"),
            _ => writeln!(s, "G33 Z{:.4} K1.5", -10.0 - 20.0 * f),
        };
    }
    s.push_str("M2\n");
    s
}

fn bench_interpret(c: &mut Criterion) {
    let mut g = c.benchmark_group("interpret/linuxcnc");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for n in [20_000, 200_000] {
        let src = Source {
            name: "big.ngc".into(),
            text: program(n),
        };
        let limits = Limits {
            max_blocks: 10 * n as u64,
            max_moves: 10 * n,
            max_depth: Limits::default().max_depth,
        };
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(format!("{n}-blocks"), |b| {
            b.iter(|| {
                let moves = interpret(&src, Dialect::Linuxcnc, &|_| None, limits).unwrap();
                to_csv(&moves).len()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_interpret);
criterion_main!(benches);
