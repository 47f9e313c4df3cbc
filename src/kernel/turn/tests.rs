//! Turning envelopes against independent oracles: the closed forms of an uncompensated
//! nose on straight moves, tapers and arcs (derived in each test), and a brute-force
//! sampling of the swept shape (a second method) on random tools and paths.

use super::*;
use crate::model::tool::{Edge, Tool};
use crate::model::Rng;
use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2};

fn tool(rn: f64, lead_deg: f64, trail_deg: f64) -> TurningTool {
    TurningTool::turning(
        1,
        rn,
        (lead_deg.to_radians(), trail_deg.to_radians()),
        false,
    )
}

/// A CNMG 80 deg insert in a 95 deg holder: the job's default.
fn cnmg(rn: f64) -> TurningTool {
    tool(rn, -5.0, 85.0)
}

/// The shape's lower boundary by brute force: the lowest point at `u` of the pieces of the
/// shape's outline, each taken whole: the two nose circles (`flat` apart), the flat between
/// their bottoms, and the edges' rays from their tangent points on the outer noses.
fn lower_brute(t: &TurningTool, u: f64) -> f64 {
    let r = t.nose_radius;
    let mut best = f64::INFINITY;
    // Noses: every point of each circle with this u.
    for c in [0.0, t.flat] {
        if (u - c).abs() <= r {
            best = best.min(-(r * r - (u - c) * (u - c)).sqrt());
        }
    }
    // The flat.
    if (0.0..=t.flat).contains(&u) {
        best = best.min(-r);
    }
    // Leading edge ray from its tangent point, direction (-sin a, cos a).
    let a = t.lead_angle;
    let (pu, ph) = (-r * a.cos(), -r * a.sin());
    let du = -a.sin();
    if du != 0.0 {
        let s = (u - pu) / du;
        if s >= 0.0 {
            best = best.min(ph + s * a.cos());
        }
    }
    let b = t.trail_angle;
    let (pu, ph) = (t.flat + r * b.cos(), -r * b.sin());
    let du = b.sin();
    if du != 0.0 {
        let s = (u - pu) / du;
        if s >= 0.0 {
            best = best.min(ph + s * b.cos());
        }
    }
    best
}

#[test]
fn the_lower_boundary_is_the_nose_and_the_edges() {
    let mut rng = Rng(7);
    for case in 0..300 {
        let mut t = tool(
            rng.range(0.0, 1.6),
            rng.range(-30.0, 80.0),
            rng.range(-30.0, 88.0),
        );
        // A third with a flat between two noses (grooving and threading inserts).
        if case % 3 == 0 {
            t.flat = rng.range(0.0, 3.0);
        }
        if t.lead_angle + t.trail_angle <= 0.05 {
            continue;
        }
        for k in 0..100 {
            let u = -5.0 + 0.1 * k as f64 + 0.013;
            let (g, b) = (t.lower(u), lower_brute(&t, u));
            assert!(
                (g.is_infinite() && b.is_infinite()) || (g - b).abs() < 1e-9,
                "{t:?} u {u}: {g} vs {b}"
            );
        }
    }
}

/// The envelope of a path by brute force: the nose centre at `n` points of the path.
fn envelope_brute(t: &TurningTool, path: &TurnPath, z: f64, n: usize) -> f64 {
    (0..=n)
        .map(|k| {
            let s = k as f64 / n as f64;
            let c = match *path {
                TurnPath::Line { from, to } => {
                    (from.0 + s * (to.0 - from.0), from.1 + s * (to.1 - from.1))
                }
                TurnPath::Arc {
                    centre,
                    radius,
                    start,
                    sweep,
                } => {
                    let th = start + s * sweep;
                    (centre.0 + radius * th.cos(), centre.1 + radius * th.sin())
                }
            };
            c.1 + lower_brute(t, z - c.0)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn envelopes_equal_a_fine_sampling_of_the_path() {
    // Second method: the swept shape sampled at 20000 positions along the path. The exact
    // envelope is never above the sampled one (every candidate is a point of the shape)
    // and within the sampling's error below it (the path moves at most L/20000 between
    // samples; the shape's boundary has slope at most 1/tan(2 deg) here).
    let mut rng = Rng(11);
    let n = 20_000;
    for case in 0..450 {
        let lead = rng.range(-20.0, 70.0);
        let mut t = tool(
            rng.range(0.0, 1.2),
            lead,
            rng.range((1.0 - lead).max(2.0), 88.0),
        );
        // A third with a flat (inserts), some of them with sharp corners.
        if case % 3 == 2 {
            t.flat = rng.range(0.0, 3.0);
            if case % 2 == 0 {
                t.nose_radius = 0.0;
            }
        }
        let p0 = (rng.range(-20.0, 0.0), rng.range(5.0, 15.0));
        let path = if case % 2 == 0 {
            TurnPath::Line {
                from: p0,
                to: (rng.range(-20.0, 0.0), rng.range(5.0, 15.0)),
            }
        } else {
            TurnPath::Arc {
                centre: p0,
                radius: rng.range(0.1, 6.0),
                start: rng.range(-PI, PI),
                sweep: rng.range(-TAU, TAU),
            }
        };
        let len = match path {
            TurnPath::Line { from, to } => (to.0 - from.0).hypot(to.1 - from.1),
            TurnPath::Arc { radius, sweep, .. } => radius * sweep.abs(),
        };
        let step = len / n as f64;
        let slope = 1.0 / 2f64.to_radians().tan();
        for k in 0..60 {
            let z = -28.0 + 0.6 * k as f64 + 0.0037;
            let e = envelope(&t, &path, z);
            let b = envelope_brute(&t, &path, z, n);
            if b.is_infinite() {
                assert!(
                    e.is_infinite() || e > 1e3,
                    "case {case} z {z}: {e} where sampling finds nothing"
                );
                continue;
            }
            assert!(
                e <= b + 1e-9,
                "case {case} z {z}: {e} above the sampled {b}"
            );
            assert!(
                e >= b - step * (1.0 + slope) - 1e-9,
                "case {case} z {z}: {e} far below the sampled {b}"
            );
        }
    }
}

#[test]
fn a_straight_turn_and_a_face_leave_the_programmed_diameter_and_face() {
    // Imaginary tip along x = 40 from z = 0 to z = -30: the nose centre runs from z 0.8 to
    // -29.2, 0.8 above r = 20, so its bottom leaves r = 20 there. Beyond the move's end
    // (towards the chuck) the nose's arc: r = 20 + r_n - sqrt(r_n^2 - u^2), u the distance
    // past -29.2; beyond its start (+z) the trailing edge, tangent to the nose at 85 deg:
    // r = 20 + r_n - r_n sin 85 + (u - r_n cos 85) / tan 85.
    let t = cnmg(0.8);
    let p = TurnPath::of_move(&t, 1.0, (0.0, 40.0), (-30.0, 40.0), None);
    for k in 0..=300 {
        let z = -29.2 + 0.1 * k as f64;
        assert!((envelope(&t, &p, z) - 20.0).abs() < 1e-12, "z {z}");
    }
    for u in [0.1, 0.4, 0.79] {
        let want = 20.0 + 0.8 - (0.64f64 - u * u).sqrt();
        assert!((envelope(&t, &p, -29.2 - u) - want).abs() < 1e-12);
    }
    assert!(envelope(&t, &p, -30.0 - 1e-9).is_infinite());
    let a = 85f64.to_radians();
    for u in [0.1, 1.0, 5.0] {
        let want = 20.0 + 0.8 - 0.8 * a.sin() + (u - 0.8 * a.cos()) / a.tan();
        assert!((envelope(&t, &p, 0.8 + u) - want).abs() < 1e-12);
    }
    // Facing at z = -2 from x 50 down to x -1.6: everything at z >= -2 + r_n is below the
    // axis (clamped there); between -2 and -2 + r_n the nose's arc leaves
    // r_n - sqrt(r_n^2 - (z - (-2 + r_n))^2) above r = -0.8 + ... (the tip at r = -0.8).
    let f = TurnPath::of_move(&t, 1.0, (-2.0, 50.0), (-2.0, -1.6), None);
    assert!(envelope(&t, &f, -2.0 - 1e-9).is_infinite());
    for k in 1..10 {
        let u = 0.08 * k as f64 - 0.8;
        let want = -0.8 + 0.8 - (0.64f64 - u * u).sqrt();
        assert!((envelope(&t, &f, -2.0 + 0.8 + u) - want).abs() < 1e-12);
    }
}

#[test]
fn an_uncompensated_taper_leaves_the_textbook_nose_error() {
    // The imaginary tip on a line of slope m = dr/dz: the nose centre runs on the same line
    // shifted by (r_n, r_n), the cut surface is that line offset by r_n along its normal:
    // r_cut(z) = r_P(z) + r_n (1 - m - sqrt(1 + m^2)). For a taper falling towards +z at
    // beta from the axis (m = -tan beta) the radius is left r_n (1 + tan b - sec b) high,
    // the controls' nose-radius compensation fx = r_n (1 - tan((90 - b)/2)); a 45 deg
    // chamfer is left r_n (2 - sqrt 2) high radially, r_n (sqrt 2 - 1) along its normal.
    // Rising towards +z (m = tan beta, a back taper met by the nose's -z side) it gouges
    // r_n (tan b + sec b - 1), but only while the leading edge clears it.
    let mut rng = Rng(3);
    for _ in 0..200 {
        let rn = rng.range(0.05, 1.6);
        let t = cnmg(rn);
        let beta = rng.range(1.0, 85.0).to_radians();
        let m = -beta.tan();
        let (z0, r0) = (0.0, 10.0);
        let z1 = -5.0;
        let r1 = r0 + m * (z1 - z0);
        let p = TurnPath::of_move(&t, 1.0, (z0, 2.0 * r0), (z1, 2.0 * r1), None);
        let fx = rn * (1.0 - ((PI / 2.0 - beta) / 2.0).tan());
        for k in 1..40 {
            let z = z1 + (z0 - z1) * k as f64 / 40.0;
            // Inside the move (the contact point's z within it).
            let contact = z + rn * beta.sin();
            if contact - rn > z0 || contact - rn < z1 {
                continue;
            }
            let rp = r0 + m * (z - z0);
            let e = envelope(&t, &p, z);
            assert!(
                (e - rp - fx).abs() < 1e-9,
                "b {} z {z}: {} vs {fx}",
                beta.to_degrees(),
                e - rp
            );
        }
    }
    // The 45 deg chamfer in numbers: 0.8 nose, 0.4686 mm radially, 0.3314 mm normal.
    let t = cnmg(0.8);
    let p = TurnPath::of_move(&t, 1.0, (0.0, 16.0), (-2.0, 20.0), None);
    let left = envelope(&t, &p, -1.0) - 9.0;
    assert!((left - 0.8 * (2.0 - SQRT_2)).abs() < 1e-12);
    assert!((left * FRAC_1_SQRT_2 - 0.8 * (SQRT_2 - 1.0)).abs() < 1e-12);
}

#[test]
fn an_uncompensated_corner_radius_is_concentric_and_short_by_the_nose() {
    // G03 of the imaginary tip around a convex front corner: radius R about O = (zo, ro),
    // from the face (O + (R, 0)... here from the top O + (0, R) to the face O + (R, 0)
    // clockwise. The nose centre runs R about O + (r_n, r_n); the cut is its inner offset,
    // radius R - r_n about O + (r_n, r_n), where the contact angle lies within the arc.
    let mut rng = Rng(5);
    for _ in 0..100 {
        let rn = rng.range(0.1, 1.2);
        let big = rng.range(rn + 0.2, 6.0);
        let t = cnmg(rn);
        let (zo, ro) = (-big, 12.0);
        let from = (zo, 2.0 * (ro + big));
        let to = (zo + big, 2.0 * ro);
        let p = TurnPath::of_move(&t, 1.0, from, to, Some(((zo, 2.0 * ro), true)));
        let (cz, cr) = (zo + rn, ro + rn);
        for k in 1..30 {
            let th = PI / 2.0 * k as f64 / 30.0;
            let z = cz + (big - rn) * th.cos();
            let want = cr + (big - rn) * th.sin();
            assert!((envelope(&t, &p, z) - want).abs() < 1e-9);
        }
    }
}

#[test]
fn a_bore_mirrors_the_outside() {
    // A boring bar on h = -r: turning the bore to x = 20 from z = 0 to -10 leaves r = 10
    // (h = -10) under the move; its chamfer into the bore is the mirror of the outside's.
    let mut t = cnmg(0.4);
    t.internal = true;
    let p = TurnPath::of_move(&t, -1.0, (0.0, 20.0), (-10.0, 20.0), None);
    assert!((envelope(&t, &p, -5.0) + 10.0).abs() < 1e-12);
    let outer = TurnPath::of_move(
        &t,
        1.0,
        (0.0, 16.0),
        (-2.0, 20.0),
        Some(((-2.0, 16.0), true)),
    );
    let inner = TurnPath::of_move(
        &t,
        -1.0,
        (0.0, -16.0),
        (-2.0, -20.0),
        Some(((-2.0, -16.0), false)),
    );
    for k in 0..20 {
        let z = -2.5 + 0.15 * k as f64;
        let (a, b) = (envelope(&t, &outer, z), envelope(&t, &inner, z));
        assert!(
            (a.is_infinite() && b.is_infinite()) || (a - b).abs() < 1e-12,
            "z {z}: {a} {b}"
        );
    }
}

#[test]
fn clamping_is_the_envelope_at_each_cell_and_order_free() {
    let t = cnmg(0.4);
    let cuts: Vec<TurnCut> = [
        ((0.0, 30.0), (-20.0, 30.0)),
        ((0.0, 26.0), (-8.0, 26.0)),
        ((1.0, 20.0), (-2.0, 26.0)),
    ]
    .iter()
    .map(|&(a, b)| TurnCut {
        tool: t,
        path: TurnPath::of_move(&t, 1.0, a, b, None),
    })
    .collect();
    let fwd = Turned { cuts: cuts.clone() };
    let rev = Turned {
        cuts: cuts.iter().rev().copied().collect(),
    };
    let (z0, dz, n) = (-30.0, 0.01, 3100);
    let a = fwd.profile(n, z0, dz, 16.0, 0.0);
    assert_eq!(a, rev.profile(n, z0, dz, 16.0, 0.0));
    for (j, v) in a.iter().enumerate() {
        let z = z0 + dz * j as f64;
        let e = cuts
            .iter()
            .map(|c| envelope(&c.tool, &c.path, z))
            .fold(16.0, f64::min)
            .max(0.0);
        assert_eq!(*v, (e - 16.0) as f32, "cell {j}");
    }
    // Under the 30 mm turn, r = 15; under the 26 mm one, 13.
    assert_eq!(a[((-15.0 - z0) / dz) as usize], -1.0);
    assert_eq!(a[((-5.0 - z0) / dz) as usize], -3.0);
}

#[test]
fn a_rapid_meets_only_the_stock_left_at_its_time() {
    // Turned to x = 30 over z in [-20, 0], then a rapid along x = 31 (inside the blank's
    // 32 but outside what was turned): it meets nothing after the turn, 0.5 mm before it.
    let t = cnmg(0.4);
    let turn = TurnCut {
        tool: t,
        path: TurnPath::of_move(&t, 1.0, (1.0, 30.0), (-20.0, 30.0), None),
    };
    let rapid = TurnPath::of_move(&t, 1.0, (1.0, 31.0), (-10.0, 31.0), None);
    let mut stock = Profile::new((-40.0, 0.0), 0.01, 16.0, 0.0);
    let (depth, z) = stock.rapid_depth(&t, &rapid).unwrap();
    assert!((depth - 0.5).abs() < 1e-12 && (-10.0..=0.0).contains(&z));
    stock.cut(&turn);
    assert_eq!(stock.rapid_depth(&t, &rapid), None);
    // The profile is the envelope at every cell, floored at the axis.
    for j in 0..stock.q.len() {
        let z = stock.z(j);
        let want = envelope(&t, &turn.path, z).clamp(0.0, 16.0);
        assert_eq!(stock.q[j], want, "z {z}");
    }
    // Off the part (z > 0) nothing is met, whatever the diameter.
    let air = TurnPath::of_move(&t, 1.0, (5.0, 0.0), (5.0, 40.0), None);
    assert_eq!(stock.rapid_depth(&t, &air), None);
}

/// An insert's edge with a reference point, random: a trapezoid (grooving when square) or
/// a round-nose V.
fn random_insert(rng: &mut Rng, case: usize) -> Tool {
    use crate::model::tool::Reference;
    let edge = if case % 2 == 0 {
        let square = case % 4 == 0;
        Edge::Trapezoid {
            tip: rng.range(0.0, 3.0),
            left_angle: if square {
                0.0
            } else {
                rng.range(2.0, 40.0).to_radians()
            },
            right_angle: if square {
                0.0
            } else {
                rng.range(2.0, 40.0).to_radians()
            },
        }
    } else {
        Edge::RoundV {
            radius: rng.range(0.05, 0.6),
            half_angle: rng.range(10.0, 40.0).to_radians(),
        }
    };
    Tool {
        id: 3,
        edge,
        reference: [
            Reference::Center,
            Reference::Left,
            Reference::Right,
            Reference::Tip,
        ][case % 4],
        body: None,
        length: None,
        depth_per_pass: Default::default(),
    }
}

#[test]
fn an_inserts_swept_edge_is_its_own_height_function_along_the_move() {
    // Second method: the edge's height function of `model::tool` (the one the thread sweep
    // cuts with) placed at 20000 positions of the reference point along the move: the tip
    // centre at the reference point minus its offset, the cut at `h + height(z - tip)`.
    let mut rng = Rng(17);
    let n = 20_000;
    for case in 0..200 {
        let tool = random_insert(&mut rng, case);
        let shape = TurningTool::insert(&tool, false);
        let off = tool.reference_offset();
        let from = (rng.range(-20.0, 0.0), rng.range(10.0, 30.0));
        let to = if case % 3 == 0 {
            (rng.range(-20.0, 0.0), from.1)
        } else {
            (rng.range(-20.0, 0.0), rng.range(10.0, 30.0))
        };
        let path = TurnPath::of_move(&shape, 1.0, from, (to.0, to.1), None);
        let steep = match &tool.edge {
            Edge::Trapezoid {
                left_angle,
                right_angle,
                ..
            } => crate::model::tool::cot(left_angle.min(*right_angle).max(2f64.to_radians())),
            _ => 1.0 / 10f64.to_radians().tan(),
        };
        let len = (to.0 - from.0).hypot((to.1 - from.1) / 2.0);
        let step = len / n as f64;
        for k in 0..60 {
            let z = -24.0 + 0.5 * k as f64 + 0.0037;
            let brute = (0..=n)
                .map(|i| {
                    let s = i as f64 / n as f64;
                    let (cz, cx) = (from.0 + s * (to.0 - from.0), from.1 + s * (to.1 - from.1));
                    cx / 2.0 + tool.height(z - (cz - off))
                })
                .fold(f64::INFINITY, f64::min);
            let e = envelope(&shape, &path, z);
            if brute.is_infinite() {
                assert!(e.is_infinite() || e > 1e3, "case {case} z {z}: {e}");
                continue;
            }
            assert!(e <= brute + 1e-9, "case {case} z {z}: {e} above {brute}");
            assert!(
                e >= brute - step * (1.0 + steep) - 1e-9,
                "case {case} z {z}: {e} far below {brute} ({tool:?})"
            );
        }
    }
}

#[test]
fn a_threading_inserts_rapid_along_the_bar_meets_the_crest_by_its_depth() {
    // Issue 28's first program: a 60 deg insert (tip flat P/8 = 0.25, driven by its tip)
    // returning at X28 along a 30 mm bar: its tip runs 1 mm under the crest, so the rapid
    // meets material 1 mm deep (radial), over the whole bar from z -39.5 up to the face.
    let tool = Tool {
        id: 3,
        edge: Edge::Trapezoid {
            tip: 0.25,
            left_angle: 30f64.to_radians(),
            right_angle: 30f64.to_radians(),
        },
        reference: crate::model::tool::Reference::Tip,
        body: None,
        length: None,
        depth_per_pass: Default::default(),
    };
    let shape = TurningTool::insert(&tool, false);
    let stock = Profile::new((-60.0, 0.0), 0.01, 15.0, 0.0);
    let rapid = TurnPath::of_move(&shape, 1.0, (-39.5, 28.0), (5.0, 28.0), None);
    let (depth, z) = stock.rapid_depth(&shape, &rapid).unwrap();
    assert!((depth - 1.0).abs() < 1e-12, "{depth}");
    assert!((-39.625..=0.0).contains(&z), "{z}");
    // At X30 its tip grazes the bar (nothing below the crest); at X30.001 it clears it.
    let graze = TurnPath::of_move(&shape, 1.0, (-39.5, 30.0), (5.0, 30.0), None);
    assert!(stock.rapid_depth(&shape, &graze).is_none());
    // Plunging radially at z -20 to X29: 0.5 deep; the flank reaches 0.5 tan 30 beside it.
    let plunge = TurnPath::of_move(&shape, 1.0, (-20.0, 40.0), (-20.0, 29.0), None);
    let (depth, z) = stock.rapid_depth(&shape, &plunge).unwrap();
    assert!((depth - 0.5).abs() < 1e-12 && (z + 20.0).abs() <= 0.125 + 1e-9);
    // A square grooving insert 3 wide driven by its left corner plunged to X24 at z -10
    // leaves r 12 over [-10, -7) and nothing beyond (vertical sides).
    let groove = Tool {
        id: 2,
        edge: Edge::Trapezoid {
            tip: 3.0,
            left_angle: 0.0,
            right_angle: 0.0,
        },
        reference: crate::model::tool::Reference::Left,
        body: None,
        length: None,
        depth_per_pass: Default::default(),
    };
    let g = TurningTool::insert(&groove, false);
    let p = TurnPath::of_move(&g, 1.0, (-10.0, 40.0), (-10.0, 24.0), None);
    for k in 0..30 {
        let z = -10.0 + 0.1 * k as f64 + 0.01;
        assert_eq!(envelope(&g, &p, z), 12.0, "z {z}");
    }
    assert!(envelope(&g, &p, -10.001).is_infinite());
    assert!(envelope(&g, &p, -6.999).is_infinite());
}
