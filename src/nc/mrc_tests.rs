//! Randomized property tests of the FANUC G71 roughing cycle and G70 (`cycles.rs`): for
//! random monotonic shapes, outside and inside, the oracle is the shape itself (its vertices
//! as written in the program, moved by the allowance), not the code under test:
//!
//! - no roughing pass runs inside the shape moved by the allowance (U/2, W);
//! - the depth steps are dd from the start, and the last level is within dd of the shape's
//!   bottom;
//! - after the roughing passes, at every z what is left above the moved shape is at most dd
//!   (the cusp between passes), and the last pass runs exactly along the moved shape, so the
//!   allowance is all that is left;
//! - G70 runs exactly along the shape as written.

use super::*;

/// splitmix64: the same cases on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A multiple of 0.001 in [lo, hi].
    fn mm(&mut self, lo: f64, hi: f64) -> f64 {
        let n = ((hi - lo) * 1000.0) as u64;
        lo + (self.next() % (n + 1)) as f64 / 1000.0
    }
}

fn run(text: &str) -> Vec<Move> {
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    interpret_with(&src, Dialect::Fanuc, &|_| None, &Options::default())
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .moves
}

/// The lowest (outside: `s = 1`) or highest (inside: `s = -1`) radius of the polyline
/// `pts` (radius, z) at `z`, where it covers `z`.
fn shape_at(pts: &[(f64, f64)], s: f64, z: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for w in pts.windows(2) {
        let ((r0, z0), (r1, z1)) = (w[0], w[1]);
        let (lo, hi) = (z0.min(z1), z0.max(z1));
        if z < lo - 1e-12 || z > hi + 1e-12 {
            continue;
        }
        let r = if z0 == z1 {
            if s > 0.0 {
                r0.min(r1)
            } else {
                r0.max(r1)
            }
        } else {
            r0 + (z - z0) / (z1 - z0) * (r1 - r0)
        };
        best = Some(best.map_or(r, |b: f64| if s * (r - b) < 0.0 { r } else { b }));
    }
    best
}

#[test]
fn g71_random_shapes_rough_within_the_allowance_and_g70_follows_the_shape() {
    let mut rng = Rng(17);
    for case in 0..300 {
        let outside = case % 2 == 0;
        let s = if outside { 1.0 } else { -1.0 };
        // The shape, radius and z: from A' one way in X (away from the axis outside,
        // towards it inside) and towards -Z, with flats, tapers and shoulders.
        let r_first = if outside {
            rng.mm(5.0, 15.0)
        } else {
            rng.mm(25.0, 35.0)
        };
        let z0 = rng.mm(1.0, 3.0);
        let mut pts = vec![(r_first, z0)];
        let n = 2 + (rng.next() % 5) as usize;
        for k in 0..n {
            let (r, z) = *pts.last().expect("one");
            let kind = if k == 0 { 0 } else { rng.next() % 3 };
            let dz = rng.mm(1.0, 12.0);
            let dr = rng.mm(0.5, 4.0);
            pts.push(match kind {
                0 => (r, z - dz),
                1 => (r + s * dr, z - dz),
                _ => (r + s * dr, z),
            });
        }
        // As the program writes them (X as a diameter, three decimals).
        let q = |v: f64| (v * 1000.0).round() / 1000.0;
        let pts: Vec<(f64, f64)> = pts.iter().map(|&(r, z)| (q(r), q(z))).collect();
        let z0 = q(z0);
        let r_last = pts.last().expect("points").0;
        // The start: outside (inside) the whole shape, by a random clearance.
        let r_start = q(r_last + s * rng.mm(0.5, 5.0));
        let dd = q(rng.mm(0.3, 3.0));
        let e = q(rng.mm(0.0, 1.0));
        let du = q(s * rng.mm(0.0, 1.0));
        let dw = q(rng.mm(0.0, 0.3));
        let mut text = format!(
            "G0 X{:.3} Z{:.3}\nG71 U{dd:.3} R{e:.3}\nG71 P10 Q20 U{du:.3} W{dw:.3} F0.2\n",
            2.0 * r_start,
            z0
        );
        text.push_str(&format!("N10 G0 X{:.3}\n", 2.0 * r_first));
        for (i, &(r, z)) in pts.iter().enumerate().skip(1) {
            let n = if i == pts.len() - 1 {
                "N20 ".to_string()
            } else {
                String::new()
            };
            text.push_str(&format!("{n}G1 X{:.3} Z{z:.3}\n", 2.0 * r));
        }
        text.push_str("G70 P10 Q20\nM30\n");
        let moves = run(&text);
        let moved: Vec<(f64, f64)> = pts.iter().map(|&(r, z)| (r + du / 2.0, z + dw)).collect();
        let rough: Vec<&Move> = moves.iter().filter(|m| m.line == 3).collect();
        // The last pass starts with the move to A' moved; the roughing passes (the feeds
        // along Z at one X) come before it.
        let a_moved = (2.0 * moved[0].0, moved[0].1);
        let last_pass = 1 + rough
            .iter()
            .rposition(|m| (m.x_dia - a_moved.0).abs() < 1e-9 && (m.z - a_moved.1).abs() < 1e-9)
            .unwrap_or_else(|| panic!("case {case}: no move to A'\n{text}"));
        let passes: Vec<(f64, f64, f64)> = rough[..last_pass]
            .iter()
            .filter(|m| m.kind == MoveKind::Feed && m.z != m.z_start)
            .map(|m| {
                assert_eq!(
                    m.x_start, m.x_dia,
                    "case {case}: a pass along Z only\n{text}"
                );
                (m.x_dia / 2.0, m.z_start, m.z)
            })
            .collect();
        // Depth steps: dd from the start; the last within dd of the moved shape's bottom.
        let bottom = moved[0].0;
        for (k, p) in passes.iter().enumerate() {
            let want = r_start - s * dd * (k + 1) as f64;
            assert!((p.0 - want).abs() < 1e-9, "case {case}: level {k}\n{text}");
        }
        let deepest = passes.last().map_or(r_start, |p| p.0);
        assert!(
            s * (deepest - bottom) > 0.0 && s * (deepest - bottom) <= dd + 1e-9,
            "case {case}: the last level {deepest} is within dd of {bottom}\n{text}"
        );
        // No pass inside the moved shape: sample every pass.
        for &(r, za, zb) in &passes {
            for i in 0..=50 {
                let z = za + (zb - za) * f64::from(i) / 50.0;
                if let Some(rs) = shape_at(&moved, s, z) {
                    assert!(
                        s * (r - rs) >= -1e-9,
                        "case {case}: the pass at r{r} cuts inside the allowance at Z{z} (shape r{rs})\n{text}"
                    );
                }
            }
        }
        // What is left after the passes: within dd of the moved shape, from the start's Z
        // (the passes start there; before it is air) to the shape's end.
        let z_end = moved.last().expect("points").1;
        for i in 1..200 {
            let z = z0 + (z_end - z0) * f64::from(i) / 200.0;
            let Some(rs) = shape_at(&moved, s, z) else {
                continue;
            };
            let covered = passes
                .iter()
                .filter(|p| z <= p.1.max(p.2) + 1e-12 && z >= p.1.min(p.2) - 1e-12)
                .map(|p| p.0)
                .fold(r_start, |a, b| if s * (b - a) < 0.0 { b } else { a });
            assert!(
                s * (covered - rs) <= dd + 1e-9,
                "case {case}: at Z{z} the passes leave r{covered} over the shape's r{rs}\n{text}"
            );
        }
        // The last pass: to A' moved, then along the moved shape, vertex by vertex.
        let fin = &rough[last_pass..];
        for (k, w) in moved.windows(2).enumerate() {
            let m = fin[k];
            let ok = (m.x_start / 2.0 - w[0].0).abs() < 1e-9
                && (m.z_start - w[0].1).abs() < 1e-9
                && (m.x_dia / 2.0 - w[1].0).abs() < 1e-9
                && (m.z - w[1].1).abs() < 1e-9;
            assert!(ok, "case {case}: last pass move {k}\n{text}");
        }
        // G70: the shape as written, from the start point, and back.
        let g70: Vec<&Move> = moves.iter().filter(|m| m.line >= 4).collect();
        assert_eq!(g70.len(), pts.len() + 1, "case {case}\n{text}");
        assert!(
            (g70[0].x_start - 2.0 * r_start).abs() < 1e-9 && (g70[0].z_start - z0).abs() < 1e-9,
            "case {case}"
        );
        for (k, &(r, z)) in pts.iter().enumerate() {
            assert!(
                (g70[k].x_dia / 2.0 - r).abs() < 1e-9 && (g70[k].z - z).abs() < 1e-9,
                "case {case}: G70 move {k}\n{text}"
            );
        }
        let back = g70.last().expect("moves");
        assert_eq!(back.kind, MoveKind::Rapid);
        assert!(
            (back.x_dia - 2.0 * r_start).abs() < 1e-9 && (back.z - z0).abs() < 1e-9,
            "case {case}"
        );
    }
}
