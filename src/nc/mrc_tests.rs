//! Randomized property tests of the FANUC G71 and G72 roughing cycles and G70 (`cycles.rs`):
//! for random monotonic shapes (G71 outside and inside, G72 outside), the oracle is the shape
//! itself (its vertices as written in the program, moved by the allowance), not the code
//! under test. In the cycle's frame (`a` the axis the depth steps along: radius for G71, Z
//! for G72; `b` the axis the passes run along):
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
    interpret_with(
        &src,
        Dialect::Fanuc,
        &|_| None,
        &Options {
            settings: Settings::in_mm(),
            ..Options::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
    .moves
}

/// The lowest (`s = 1`) or highest (`s = -1`) `a` of the polyline `pts` (a, b) at `b`
/// (called `z` here), where it covers it.
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
fn g71_g72_random_shapes_rough_within_the_allowance_and_g70_follows_the_shape() {
    let mut rng = Rng(17);
    let q = |v: f64| (v * 1000.0).round() / 1000.0;
    for case in 0..450 {
        let facing = case % 3 == 2;
        let outside = facing || case % 3 == 0;
        let s = if outside { 1.0 } else { -1.0 };
        let g = if facing { 72 } else { 71 };
        // The shape in (a, b): from A' one way in a (towards the start's side) and towards
        // -b, with flats, tapers and shoulders.
        let a_first = if facing {
            rng.mm(-25.0, -10.0)
        } else if outside {
            rng.mm(5.0, 15.0)
        } else {
            rng.mm(25.0, 35.0)
        };
        let b0 = if facing {
            rng.mm(40.0, 60.0)
        } else {
            rng.mm(1.0, 3.0)
        };
        let db_max = if facing { 6.0 } else { 12.0 };
        let mut pts = vec![(q(a_first), q(b0))];
        let n = 2 + (rng.next() % 5) as usize;
        for k in 0..n {
            let (a, b) = *pts.last().expect("one");
            let kind = if k == 0 { 0 } else { rng.next() % 3 };
            let db = rng.mm(1.0, db_max);
            let da = rng.mm(0.5, 4.0);
            pts.push(match kind {
                0 => (a, q(b - db)),
                1 => (q(a + s * da), q(b - db)),
                _ => (q(a + s * da), b),
            });
        }
        let b0 = q(b0);
        let a_last = pts.last().expect("points").0;
        // The start: on the start's side of the whole shape, by a random clearance.
        let a_start = q(a_last + s * rng.mm(0.5, 5.0));
        let dd = q(rng.mm(0.3, 3.0));
        let e = q(rng.mm(0.0, 1.0));
        let du = q(s * rng.mm(0.0, 1.0));
        let dw = q(rng.mm(0.0, 0.3));
        // (a, b) to the program's (X diameter, Z) and back.
        let xz = |(a, b): (f64, f64)| if facing { (2.0 * b, a) } else { (2.0 * a, b) };
        let ab = |x: f64, z: f64| if facing { (z, x / 2.0) } else { (x / 2.0, z) };
        let start = xz((a_start, b0));
        let depth_word = if facing { "W" } else { "U" };
        let mut text = format!(
            "G0 X{:.3} Z{:.3}\nG{g} {depth_word}{dd:.3} R{e:.3}\nG{g} P10 Q20 U{du:.3} W{dw:.3} F0.2\n",
            start.0, start.1
        );
        let first = xz(pts[0]);
        if facing {
            text.push_str(&format!("N10 G0 Z{:.3}\n", first.1));
        } else {
            text.push_str(&format!("N10 G0 X{:.3}\n", first.0));
        }
        for (i, &p) in pts.iter().enumerate().skip(1) {
            let n = if i == pts.len() - 1 { "N20 " } else { "" };
            let (x, z) = xz(p);
            text.push_str(&format!("{n}G1 X{x:.3} Z{z:.3}\n"));
        }
        text.push_str("G70 P10 Q20\nM30\n");
        let moves = run(&text);
        // The allowance in (a, b): (du/2, dw) for G71, (dw, du/2) for G72.
        let shift = if facing {
            (dw, du / 2.0)
        } else {
            (du / 2.0, dw)
        };
        let moved: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(a, b)| (a + shift.0, b + shift.1))
            .collect();
        let rough: Vec<&Move> = moves.iter().filter(|m| m.line == 3).collect();
        // The last pass starts with the move to A' moved; the roughing passes (the feeds
        // along b at one a) come before it.
        let last_pass = 1 + rough
            .iter()
            .rposition(|m| {
                let p = ab(m.x_dia, m.z);
                (p.0 - moved[0].0).abs() < 1e-9 && (p.1 - moved[0].1).abs() < 1e-9
            })
            .unwrap_or_else(|| panic!("case {case}: no move to A'\n{text}"));
        let passes: Vec<(f64, f64, f64)> = rough[..last_pass]
            .iter()
            .filter(|m| m.kind == MoveKind::Feed)
            .map(|m| {
                let (p, r) = (ab(m.x_start, m.z_start), ab(m.x_dia, m.z));
                assert!(
                    (p.0 - r.0).abs() < 1e-12,
                    "case {case}: a pass along b only\n{text}"
                );
                (r.0, p.1, r.1)
            })
            .collect();
        // Depth steps: dd from the start; the last within dd of the moved shape's bottom.
        let bottom = moved[0].0;
        for (k, p) in passes.iter().enumerate() {
            let want = a_start - s * dd * (k + 1) as f64;
            assert!((p.0 - want).abs() < 1e-9, "case {case}: level {k}\n{text}");
        }
        let deepest = passes.last().map_or(a_start, |p| p.0);
        assert!(
            s * (deepest - bottom) > 0.0 && s * (deepest - bottom) <= dd + 1e-9,
            "case {case}: the last level {deepest} is within dd of {bottom}\n{text}"
        );
        // No pass inside the moved shape: sample every pass.
        for &(a, ba, bb) in &passes {
            for i in 0..=50 {
                let b = ba + (bb - ba) * f64::from(i) / 50.0;
                if let Some(sa) = shape_at(&moved, s, b) {
                    assert!(
                        s * (a - sa) >= -1e-9,
                        "case {case}: the pass at a = {a} cuts inside the allowance at b = {b} (shape {sa})\n{text}"
                    );
                }
            }
        }
        // What is left after the passes: within dd of the moved shape, from the start's b
        // (the passes start there; before it is air) to the shape's end.
        let b_end = moved.last().expect("points").1;
        for i in 1..200 {
            let b = b0 + (b_end - b0) * f64::from(i) / 200.0;
            let Some(sa) = shape_at(&moved, s, b) else {
                continue;
            };
            let covered = passes
                .iter()
                .filter(|p| b <= p.1.max(p.2) + 1e-12 && b >= p.1.min(p.2) - 1e-12)
                .map(|p| p.0)
                .fold(a_start, |x, y| if s * (y - x) < 0.0 { y } else { x });
            assert!(
                s * (covered - sa) <= dd + 1e-9,
                "case {case}: at b = {b} the passes leave {covered} over the shape's {sa}\n{text}"
            );
        }
        // The last pass: along the moved shape, vertex by vertex.
        let fin = &rough[last_pass..];
        for (k, w) in moved.windows(2).enumerate() {
            let (p, r) = (
                ab(fin[k].x_start, fin[k].z_start),
                ab(fin[k].x_dia, fin[k].z),
            );
            let ok = (p.0 - w[0].0).abs() < 1e-9
                && (p.1 - w[0].1).abs() < 1e-9
                && (r.0 - w[1].0).abs() < 1e-9
                && (r.1 - w[1].1).abs() < 1e-9;
            assert!(ok, "case {case}: last pass move {k}\n{text}");
        }
        // G70: the shape as written, from the start point, and back.
        let g70: Vec<&Move> = moves.iter().filter(|m| m.line >= 4).collect();
        assert_eq!(g70.len(), pts.len() + 1, "case {case}\n{text}");
        let near =
            |m: &Move, (x, z): (f64, f64)| (m.x_dia - x).abs() < 1e-9 && (m.z - z).abs() < 1e-9;
        assert!(
            (g70[0].x_start - start.0).abs() < 1e-9 && (g70[0].z_start - start.1).abs() < 1e-9,
            "case {case}"
        );
        for (k, &p) in pts.iter().enumerate() {
            assert!(near(g70[k], xz(p)), "case {case}: G70 move {k}\n{text}");
        }
        let back = g70.last().expect("moves");
        assert_eq!(back.kind, MoveKind::Rapid);
        assert!(near(back, start), "case {case}");
    }
}

/// G-code system C numbers the cycles G72..G77 (G70..G75 in A) and B keeps A's numbers
/// (FANUC 0i-TF "G code list"): the same program in the three systems makes the same moves.
#[test]
fn cycles_in_gcode_systems_b_and_c_are_the_system_a_cycles() {
    let body = |g: [u32; 5]| {
        format!(
            "G0 X62 Z2\nG{} U2 R0.5\nG{} P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X30\nG1 Z-20\nX40 Z-30\nN20 X62\n\
             G{} P10 Q20\nG0 X64 Z2\nG{} R0.5\nG{} X50 Z-12 P2000 Q3000 F0.1\nM30\n",
            g[0], g[0], g[1], g[2], g[3]
        )
    };
    let run_in = |system: GcodeSystem, text: &str| {
        super::fanuc::tap_tests::run(text, system).unwrap_or_else(|e| panic!("{e}"))
    };
    let a = run_in(GcodeSystem::A, &body([71, 70, 75, 75, 75]));
    assert!(a.len() > 20);
    let b = run_in(GcodeSystem::B, &body([71, 70, 75, 75, 75]));
    let c = run_in(GcodeSystem::C, &body([73, 72, 77, 77, 77]));
    assert_eq!(a, b);
    assert_eq!(a, c);
    // Under G91 (systems B/C) the G75 end point is incremental: X64 Z2 + (-14, -14).
    let inc = body([71, 70, 75, 75, 75]).replace("G75 X50 Z-12", "G91 G75 X-14 Z-14");
    let b_inc = run_in(GcodeSystem::B, &inc);
    assert_eq!(a, b_inc);
}

/// Issue 27: a shape that ends by going back along the passes (`N20 G00 G40 Z0.1`, Haas and
/// FANUC shop programs) runs when the move lies above the first pass, and then the
/// second method is the same shape without it: every move of the cycle up to the end of
/// the last pass along the shape is the same (no pass meets the added move). Where the
/// move goes back at a level the passes meet, the run stops with FANUC's alarm PS0064.
/// Random monotonic shapes for G71 outside and inside and G72 (seeded).
#[test]
fn a_shape_that_goes_back_above_the_first_pass_roughs_as_without_it() {
    let mut rng = Rng(27);
    let mut alarms = 0;
    let q = |v: f64| (v * 1000.0).round() / 1000.0;
    let run_result = |text: &str| {
        let src = Source {
            name: "T.NC".into(),
            text: text.into(),
        };
        let opts = Options {
            settings: Settings::in_mm(),
            ..Options::default()
        };
        interpret_with(&src, Dialect::Fanuc, &|_| None, &opts)
    };
    for case in 0..240 {
        let facing = case % 3 == 2;
        let outside = facing || case % 3 == 0;
        let s = if outside { 1.0 } else { -1.0 };
        let g = if facing { 72 } else { 71 };
        let a_first = if facing {
            rng.mm(-25.0, -10.0)
        } else if outside {
            rng.mm(5.0, 15.0)
        } else {
            rng.mm(25.0, 35.0)
        };
        let b0 = if facing {
            rng.mm(40.0, 60.0)
        } else {
            rng.mm(1.0, 3.0)
        };
        let mut pts = vec![(q(a_first), q(b0))];
        for k in 0..2 + (rng.next() % 4) as usize {
            let (a, b) = *pts.last().expect("one");
            let db = rng.mm(1.0, 6.0);
            let da = rng.mm(0.5, 4.0);
            pts.push(if k == 0 {
                (a, q(b - db))
            } else {
                (q(a + s * da), q(b - db))
            });
        }
        let a_last = pts.last().expect("points").0;
        let a_start = q(a_last + s * rng.mm(0.5, 5.0));
        let dd = q(rng.mm(0.3, 3.0));
        let xz = |(a, b): (f64, f64)| if facing { (2.0 * b, a) } else { (2.0 * a, b) };
        let start = xz((a_start, b0));
        let depth_word = if facing { "W" } else { "U" };
        let head = format!(
            "G0 X{:.3} Z{:.3}\nG{g} {depth_word}{dd:.3} R0.5\nG{g} P10 Q20 U0 W0 F0.2\n",
            start.0, start.1
        );
        let first = xz(pts[0]);
        let mut body = if facing {
            format!("N10 G0 Z{:.3}\n", first.1)
        } else {
            format!("N10 G0 X{:.3}\n", first.0)
        };
        for &p in &pts[1..] {
            let (x, z) = xz(p);
            body.push_str(&format!("G1 X{x:.3} Z{z:.3}\n"));
        }
        let plain = format!("{head}{body}N20 G1\nM30\n");
        // Up to a level `up` above the last point, then back to the start's b.
        let back = |up: f64| {
            let top = xz((q(a_last + s * up), b0));
            let (x, z) = xz((q(a_last + s * up), pts.last().expect("points").1));
            format!(
                "{head}{body}G1 X{x:.3} Z{z:.3}\nN20 G0 X{:.3} Z{:.3}\nM30\n",
                top.0, top.1
            )
        };
        // Above the first pass (the start's level less dd): the same roughing.
        let above = back((a_start * s - a_last * s - dd + 0.2).max(0.05));
        let want = run_result(&plain).unwrap_or_else(|e| panic!("case {case}: {e}\n{plain}"));
        let got = run_result(&above).unwrap_or_else(|e| panic!("case {case}: {e}\n{above}"));
        // The plain cycle ends with the last pass along the shape and the rapids back.
        let cycle = |t: &Toolpath| -> Vec<Move> {
            t.moves.iter().filter(|m| m.line == 3).cloned().collect()
        };
        let (w, gm) = (cycle(&want), cycle(&got));
        let rapids_back = w
            .iter()
            .rev()
            .take_while(|m| m.kind == MoveKind::Rapid)
            .count();
        let common = w.len() - rapids_back;
        assert_eq!(w[..common], gm[..common], "case {case}\n{above}");
        // Below the first pass: a pass meets the move that goes back: PS0064.
        if s * (a_start - a_last) > dd + 0.3 {
            let below = back(0.1);
            let e = run_result(&below).expect_err(&below);
            assert!(e.message.contains("PS0064"), "case {case}: {e}\n{below}");
            alarms += 1;
        }
    }
    assert!(
        alarms > 40,
        "{alarms} shapes went back where a pass meets them"
    );
}

/// Issue 27: G71/G72 shapes with troughs (the shape goes back towards the start's level in
/// the stepping axis, vertical walls included), type I and type II, G71 outside and inside
/// and G72, random (seeded). The oracle is the shape as written, moved by the allowance,
/// and a stock kept independently of the code under test: at each `b`, the material lies
/// below the lowest point (on the start's side) that a feed move has passed there, and
/// starts just below the start point's level. Then:
///
/// - no move (rapid, feed or the last pass) runs inside the moved shape;
/// - no rapid runs into material (every rapid goes where a feed has already cut);
/// - after the roughing passes, what is left over the moved shape is at most dd;
/// - the last pass runs along the moved shape, vertex by vertex.
#[test]
fn g71_g72_troughs_rough_level_by_level_without_rapids_into_the_stock() {
    let mut rng = Rng(2727);
    let q = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut troughs = 0;
    for case in 0..300 {
        let facing = case % 3 == 2;
        let outside = facing || case % 3 == 0;
        let s = if outside { 1.0 } else { -1.0 };
        let g = if facing { 72 } else { 71 };
        let a_first = if facing {
            rng.mm(-25.0, -15.0)
        } else if outside {
            rng.mm(8.0, 15.0)
        } else {
            rng.mm(25.0, 32.0)
        };
        let b0 = if facing {
            rng.mm(40.0, 60.0)
        } else {
            rng.mm(1.0, 3.0)
        };
        let mut pts = vec![(q(a_first), q(b0))];
        let n = 3 + (rng.next() % 5) as usize;
        for k in 0..n {
            let (a, b) = *pts.last().expect("one");
            let db = if k > 0 && rng.next() % 4 == 0 {
                0.0
            } else {
                rng.mm(1.0, 6.0)
            };
            // Up or down in a (towards the start's side or away from it), never below
            // 4 mm under the first point (the inside of a tube, the centre).
            let mut da = rng.mm(0.0, 4.0) * if rng.next() % 3 == 0 { -s } else { s };
            if s * (a + da - a_first) < -4.0 {
                da = -da;
            }
            if db == 0.0 && da == 0.0 {
                da = s;
            }
            if k == 0 {
                // From A' along the passes first (the start point's b is then in front of
                // the allowance too).
                da = 0.0;
            }
            pts.push((q(a + da), q(b - db)));
        }
        let top = pts
            .iter()
            .map(|p| s * p.0)
            .fold(f64::NEG_INFINITY, f64::max);
        let a_start = q(s * (top + rng.mm(0.5, 4.0)));
        let dd = q(rng.mm(0.3, 2.0));
        let e = q(rng.mm(0.0, 1.0));
        let du = q(s * rng.mm(0.0, 0.6));
        let dw = q(rng.mm(0.0, 0.2));
        let type_ii = rng.next() % 2 == 0;
        let xz = |(a, b): (f64, f64)| if facing { (2.0 * b, a) } else { (2.0 * a, b) };
        let start = xz((a_start, b0));
        let depth_word = if facing { "W" } else { "U" };
        let mut text = format!(
            "G0 X{:.3} Z{:.3}\nG{g} {depth_word}{dd:.3} R{e:.3}\nG{g} P10 Q20 U{du:.3} W{dw:.3} F0.2\n",
            start.0, start.1
        );
        let first = xz(pts[0]);
        text.push_str(&match (facing, type_ii) {
            (false, false) => format!("N10 G0 X{:.3}\n", first.0),
            (true, false) => format!("N10 G0 Z{:.3}\n", first.1),
            _ => format!("N10 G0 X{:.3} Z{:.3}\n", first.0, first.1),
        });
        for (i, &p) in pts.iter().enumerate().skip(1) {
            let n = if i == pts.len() - 1 { "N20 " } else { "" };
            let (x, z) = xz(p);
            text.push_str(&format!("{n}G1 X{x:.3} Z{z:.3}\n"));
        }
        text.push_str("M30\n");
        let src = Source {
            name: "T.NC".into(),
            text: text.clone(),
        };
        let opts = Options {
            settings: Settings::in_mm(),
            ..Options::default()
        };
        let t = interpret_with(&src, Dialect::Fanuc, &|_| None, &opts)
            .unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        if t.warnings.iter().any(|w| w.message.contains("trough")) {
            troughs += 1;
        }
        let shift = if facing {
            (dw, du / 2.0)
        } else {
            (du / 2.0, dw)
        };
        let moved: Vec<(f64, f64)> = pts
            .iter()
            .map(|&(a, b)| (a + shift.0, b + shift.1))
            .collect();
        check_roughing(
            &t.moves,
            &moved,
            (s, facing),
            (a_start, b0, dd),
            &format!("case {case}"),
            &text,
            true,
        );
    }
    assert!(troughs > 100, "only {troughs} shapes had troughs");
}

/// A move as its kind and its two ends in the cycle's (a, b) frame.
type Seg = (MoveKind, (f64, f64), (f64, f64));

/// The checks of the trough test on the moves of the cycle block (line 3): `moved` the
/// shape moved by the allowance as a polyline in (a, b) (arcs sampled), `last` whether the
/// last pass is checked vertex by vertex (a polyline shape only).
fn check_roughing(
    moves: &[Move],
    moved: &[(f64, f64)],
    (s, facing): (f64, bool),
    (a_start, b0, dd): (f64, f64, f64),
    what: &str,
    text: &str,
    last: bool,
) {
    let ab = |x: f64, z: f64| if facing { (z, x / 2.0) } else { (x / 2.0, z) };
    let cycle: Vec<&Move> = moves.iter().filter(|m| m.line == 3).collect();
    // The moves as (a, b) segments and their kinds.
    let segs: Vec<Seg> = cycle
        .iter()
        .map(|m| (m.kind, ab(m.x_start, m.z_start), ab(m.x_dia, m.z)))
        .collect();
    // The last pass starts after the move to A' moved by the allowance.
    let last_pass = 1 + segs
        .iter()
        .rposition(|m| (m.2 .0 - moved[0].0).abs() < 1e-9 && (m.2 .1 - moved[0].1).abs() < 1e-9)
        .unwrap_or_else(|| panic!("{what}: no move to A'\n{text}"));
    // Material: at b (past the start point's b, in front of which is air), below the
    // least `s a` of the feeds so far and of the blank, just under the start's level.
    let blank = s * a_start - 0.25 * dd.min(0.4);
    let stock = |done: &[Seg], b: f64| -> f64 {
        if b >= b0 - 1e-6 {
            // The start point's b: in front of the part, no material.
            return f64::NEG_INFINITY;
        }
        let mut h = blank;
        for &(kind, p, r) in done {
            if matches!(kind, MoveKind::Rapid | MoveKind::Arc) {
                continue;
            }
            let (lo, hi) = (p.1.min(r.1), p.1.max(r.1));
            if b < lo - 1e-9 || b > hi + 1e-9 {
                continue;
            }
            let a = if (r.1 - p.1).abs() < 1e-12 {
                if s * (p.0 - r.0) < 0.0 {
                    p.0
                } else {
                    r.0
                }
            } else {
                p.0 + (b - p.1) / (r.1 - p.1) * (r.0 - p.0)
            };
            h = h.min(s * a);
        }
        h
    };
    for (k, &(kind, p, r)) in segs.iter().enumerate() {
        if kind == MoveKind::Arc {
            // An arc of the last pass along the shape: not a straight line between its ends.
            continue;
        }
        for i in 0..=40 {
            let u = f64::from(i) / 40.0;
            let (a, b) = (p.0 + u * (r.0 - p.0), p.1 + u * (r.1 - p.1));
            if let Some(sa) = shape_at(moved, s, b) {
                assert!(
                    s * (a - sa) >= -1e-9,
                    "{what}: move {k} inside the allowance at b = {b}\n{text}"
                );
            }
            if kind == MoveKind::Rapid {
                let st = stock(&segs[..k], b);
                assert!(
                    s * a >= st - 1e-9,
                    "{what}: rapid {k} into the stock at ({a}, {b}), stock {st}\n{text}"
                );
            }
        }
    }
    // Left after the roughing: within dd of the moved shape.
    let b_end = moved.last().expect("points").1;
    for i in 1..300 {
        let b = b0 + (b_end - b0) * f64::from(i) / 300.0;
        let Some(sa) = shape_at(moved, s, b) else {
            continue;
        };
        let left = stock(&segs[..last_pass], b);
        assert!(
            left - s * sa <= dd + 1e-9,
            "{what}: at b = {b} the roughing leaves {left} over {}\n{text}",
            s * sa
        );
    }
    // The last pass along the moved shape.
    if !last {
        return;
    }
    let fin = &segs[last_pass..];
    for (k, w) in moved.windows(2).enumerate() {
        let (_, p, r) = fin[k];
        let ok = (p.0 - w[0].0).abs() < 1e-9
            && (p.1 - w[0].1).abs() < 1e-9
            && (r.0 - w[1].0).abs() < 1e-9
            && (r.1 - w[1].1).abs() < 1e-9;
        assert!(ok, "{what}: last pass move {k}: {:?}\n{text}", fin[k]);
    }
}

/// A trough made by an arc (a Haas ST-20 style bolt, issue 27: `G03 X20. Z-35. R20.` from
/// X16 Z-15 bulges outward to a peak at radius 11.79, so the shape goes back down to X20):
/// type I, a warning; the same checks as the random troughs, against the arc sampled from
/// its centre worked by hand: the chord from (z, r) = (-15, 8) to (-35, 10) has midpoint
/// (-25, 9) and length sqrt(404); the centre lies sqrt(400 - 101) = sqrt(299) from it on the
/// left of the travel (G03), along (-2, -20)/sqrt(404): (-26.7206, -8.2058), peak r = 11.7942.
#[test]
fn an_arc_trough_is_roughed_under_its_peak() {
    let text = "G0 X26. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0 W0 F0.25\nN10 G00 X16.\nG01 Z0. F0.15\nG01 X16. Z-15.\nG03 X20. Z-35. R20.\nG01 Z-75.\nN20 G01 X26.\nM30\n";
    let src = Source {
        name: "T.NC".into(),
        text: text.into(),
    };
    let t = interpret_with(&src, Dialect::Fanuc, &|_| None, &Options::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(t
        .warnings
        .iter()
        .any(|w| w.message.contains("a trough") && w.message.contains("PS0064")));
    let l = 404f64.sqrt();
    let h = 299f64.sqrt();
    let c = (-25.0 + h * -2.0 / l, 9.0 + h * -20.0 / l);
    assert!(
        (c.0 + 26.7206).abs() < 1e-4 && (c.1 + 8.2058).abs() < 1e-4,
        "{c:?}"
    );
    let (t0, t1) = (
        (8.0 - c.1).atan2(-15.0 - c.0),
        (10.0 - c.1).atan2(-35.0 - c.0),
    );
    let mut shape = vec![(8.0, 2.0), (8.0, 0.0), (8.0, -15.0)];
    for k in 1..=2000 {
        let t = t0 + (t1 - t0) * f64::from(k) / 2000.0;
        shape.push((c.1 + 20.0 * t.sin(), c.0 + 20.0 * t.cos()));
    }
    let peak = shape.iter().map(|p| p.0).fold(0.0, f64::max);
    shape.extend([(10.0, -75.0), (13.0, -75.0)]);
    assert!((peak - 11.7942).abs() < 1e-4, "{peak}");
    check_roughing(
        &t.moves,
        &shape,
        (1.0, false),
        (13.0, 2.0, 1.0),
        "the bolt",
        text,
        false,
    );
    // The trough under the peak is roughed: a feed at radius 10.0..11.0 (X20..22) past z -30.
    let deep = t.moves.iter().filter(|m| {
        m.line == 3 && m.kind == MoveKind::Feed && m.x_dia < 22.0 && m.x_dia > 19.9 && m.z < -40.0
    });
    assert!(deep.count() >= 1);
}
