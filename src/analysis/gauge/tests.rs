//! The gauges against closed forms: the GO envelope, the truncated NOT GO, the phase
//! search, the calls, the over-wire values and the root radius.
use super::*;
use crate::model::helix::{Helix, LeadLaw};
use crate::model::thread::WidthRule;
use crate::model::Rng;

const P: f64 = 2.0;

/// An ISO M30x2 thread at the basic size, external or internal, its first feature at
/// z = 0 going -z.
fn m30(side: Side) -> ThreadSpec {
    let (d, d2, d1) = (30.0, 30.0 - 0.649519 * P, 30.0 - 1.082532 * P);
    let d3 = 30.0 - 1.226869 * P;
    let (root, crest) = match side {
        Side::External => (d3 / 2.0, d / 2.0),
        Side::Internal => (d / 2.0, d1 / 2.0),
    };
    ThreadSpec {
        side,
        root_radius: root,
        crest_radius: crest,
        pitch_radius: d2 / 2.0,
        left_angle: 30f64.to_radians(),
        right_angle: 30f64.to_radians(),
        width: WidthRule::Groove(P / 2.0),
        starts: 1,
        helix: Helix {
            z0: 0.0,
            dir: -1.0,
            law: LeadLaw::constant(P),
            theta0: 0.0,
            spin: 1.0,
        },
        turns: 10.0,
        outline: None,
        taper: None,
    }
}

fn class(side: Side) -> ThreadClass {
    ThreadClass {
        designation: "M30x2-6g".into(),
        class: "6g".into(),
        units: crate::model::tolerance::UnitSystem::Metric,
        internal: side == Side::Internal,
        basic_major: 30.0,
        basic_pitch_diameter: 30.0 - 0.649519 * P,
        basic_minor: 30.0 - 1.082532 * P,
        pitch: P,
        starts: 1,
        flank_angle: 60f64.to_radians(),
        taper: 0.0,
        pitch_diameter: SizeLimits::new(28.493, 28.663),
        major_diameter: SizeLimits::new(29.682, 29.962),
        minor_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
        engagement_length: 0.0,
        not_go_turns: 2.0,
        root: None,
        taper_gauge: None,
        source: "test".into(),
    }
}

/// The surface of a 60 deg thread on a generator: grooves (external: where the part is
/// low) centred at `centres`, each of half-width P/4 at pitch radius `r2`, flanks
/// tilted by `tilt` (rad, both flanks opening), clamped to the thread's radii.
fn column(
    t: &ThreadSpec,
    theta: f64,
    r2: f64,
    centres: &[f64],
    tilt: f64,
    dz: f64,
    span: (f64, f64),
) -> GaugeColumn {
    let n = ((span.1 - span.0) / dz).round() as usize + 1;
    let cot = 1.0 / (30f64.to_radians() + tilt).tan();
    let (lo, hi) = (
        t.root_radius.min(t.crest_radius),
        t.root_radius.max(t.crest_radius),
    );
    let h = (0..n)
        .map(|j| {
            let z = span.0 + j as f64 * dz;
            let u = centres
                .iter()
                .map(|c| (z - c).abs())
                .fold(f64::INFINITY, f64::min);
            // Distance from the groove centre: external, the radius grows with it
            // (the groove's wall); internal, it falls.
            let r = match t.side {
                Side::External => r2 + (u - P / 4.0) * cot,
                Side::Internal => r2 - (u - P / 4.0) * cot,
            };
            t.height(r.clamp(lo, hi)) as f32
        })
        .collect();
    GaugeColumn {
        theta,
        z0: span.0,
        dz,
        h,
    }
}

fn profile(side: Side) -> Profile {
    let c = class(side);
    Profile {
        pitch: P,
        cot_lo: 1.0 / 30f64.to_radians().tan(),
        cot_hi: 1.0 / 30f64.to_radians().tan(),
        clear: match side {
            Side::External => 0.5 * (c.basic_pitch_diameter - c.basic_minor),
            Side::Internal => 0.5 * (c.basic_major - c.basic_pitch_diameter),
        },
        external: side == Side::External,
        truncated: false,
    }
}

/// The NOT GO gauge's truncated profile for [`class`] (band H/8).
fn truncated(side: Side) -> Profile {
    Profile {
        clear: not_go_band(&class(side)),
        truncated: true,
        ..profile(side)
    }
}

/// The truncated NOT GO on a perfect thread reads its pitch diameter; with both flanks
/// opened or closed by `d` (half-angle 30 + d, k = tan(30 + d)/tan 30 - 1) it reads
/// `d2 + 2 |k| b/(1 + k)` (external; internal `-`): the part's flank crosses the gauge's at
/// the band's edge `b` from the pitch line, at `b/(1 + k)` from the part's (the hand
/// derivation in the module doc of `tests/integration/gauging.rs`). The full-profile
/// gauge (crest `c` below its pitch line, the part's crest `y_c` above) reads
/// `2 k c/(1 + k)` (opening) or `2 |k| y_c` (closing): more by the difference.
#[test]
fn the_truncated_not_go_reads_flank_angle_errors_at_its_band() {
    let dz = 0.0002;
    for side in [Side::External, Side::Internal] {
        let t = m30(side);
        let (ng, go) = (truncated(side), profile(side));
        let b = ng.clear;
        assert!((b - 0.125 * 0.866_025_4 * P).abs() < 1e-3, "band {b}");
        let sign = if side == Side::External { 1.0 } else { -1.0 };
        for (r2, deg) in [(14.29, 0.0), (14.30, 0.5), (14.27, -0.5), (14.31, 1.0)] {
            let tilt = f64::to_radians(deg);
            let centres: Vec<f64> = (0..=3).map(|k| -(k as f64) * P).collect();
            let span = (centres[3], 0.0);
            let cols = vec![column(&t, 0.0, r2, &centres, tilt, dz, span)];
            let pts = points(&t, &cols, P, span);
            let (r_ng, _) = functional_radius(&ng, &reduce(&ng, &pts), None);
            let (r_go, _) = functional_radius(&go, &reduce(&go, &pts), None);
            let k = (30f64.to_radians() + tilt).tan() / 30f64.to_radians().tan() - 1.0;
            let want_ng = 2.0 * r2 + sign * 2.0 * k.abs() * b / (1.0 + k);
            // The full profile: to the ring's crest (opening) or the part's crest
            // (closing), whichever the flank reaches first.
            let crest_y = (t.crest_radius - r2).abs();
            let root_y = (r2 - t.root_radius).abs();
            let full = if k > 0.0 {
                k * (go.clear / (1.0 + k)).min(root_y)
            } else {
                -k * crest_y
            };
            let want_go = 2.0 * r2 + sign * 2.0 * full;
            let tol = 2.0 * dz * go.cot_hi + 1e-6;
            assert!(
                (2.0 * r_ng - want_ng).abs() < tol,
                "{side:?} {deg} deg: NOT GO {} vs {want_ng}",
                2.0 * r_ng
            );
            assert!(
                (2.0 * r_go - want_go).abs() < tol,
                "{side:?} {deg} deg: full {} vs {want_go}",
                2.0 * r_go
            );
            if deg != 0.0 {
                // The truncated gauge reads less of the angle error than the full one.
                assert!(sign * (r_go - r_ng) > 1e-4, "{side:?} {deg}");
            }
        }
    }
}

/// Parallel flanks with a lead error: the truncated NOT GO over two turns reads what a
/// full-profile gauge over the same turns reads, the pitch diameter plus the lead's
/// diameter equivalent over those two teeth (2 dp cot 30 for a longer lead, 0 for a
/// shorter one, see `functional_size_is_the_pitch_diameter_plus_the_lead_equivalent`).
#[test]
fn the_truncated_not_go_reads_the_lead_over_its_turns() {
    for side in [Side::External, Side::Internal] {
        let t = m30(side);
        let (ng, go) = (truncated(side), profile(side));
        let sign = if side == Side::External { 1.0 } else { -1.0 };
        for (r2, dp) in [(14.29, 0.004), (14.32, -0.003), (14.28, 0.0)] {
            let centres: Vec<f64> = (0..=2).map(|k| -(k as f64) * (P + dp)).collect();
            let span = (centres[2], 0.0);
            let cols = vec![column(&t, 0.0, r2, &centres, 0.0, 0.0002, span)];
            let pts = points(&t, &cols, P, span);
            let (r_ng, _) = functional_radius(&ng, &reduce(&ng, &pts), None);
            let (r_go, _) = functional_radius(&go, &reduce(&go, &pts), None);
            let want = 2.0 * r2 + sign * 2.0 * dp.max(0.0) * go.cot_hi;
            let tol = 2.0 * 0.0002 * go.cot_hi + 1e-6;
            assert!(
                (2.0 * r_ng - want).abs() < tol && (2.0 * r_go - want).abs() < tol,
                "{side:?} dp {dp}: NOT GO {} full {} vs {want}",
                2.0 * r_ng,
                2.0 * r_go
            );
        }
    }
}

/// A perfect thread's functional size is its pitch diameter; a cumulative lead error
/// adds |dP_sum| cot(a/2) on diameter (external) or takes it off (internal): the
/// diameter-equivalent formula of `thread-gauging.md`, as a test of the envelope.
#[test]
fn functional_size_is_the_pitch_diameter_plus_the_lead_equivalent() {
    for side in [Side::External, Side::Internal] {
        let t = m30(side);
        let p = profile(side);
        for (r2, dp, teeth) in [
            (14.29, 0.0, 6),
            (14.25, 0.004, 6),
            (14.31, -0.003, 9),
            (14.35, 0.01, 3),
        ] {
            // Grooves at 0, -(P+dp), ...; the span from the first groove's centre to
            // the last's: whole teeth only.
            let centres: Vec<f64> = (0..=teeth).map(|k| -(k as f64) * (P + dp)).collect();
            let span = (centres[teeth], 0.0);
            let cols: Vec<GaugeColumn> = [0.0]
                .iter()
                .map(|&th| column(&t, th, r2, &centres, 0.0, 0.0002, span))
                .collect();
            let pts = points(&t, &cols, P, span);
            let (r, _) = functional_radius(&p, &pts, None);
            // Tooth k lies between grooves k and k+1. Against a ring of perfect pitch
            // its +z flank (the wall of groove k) is shifted by -k dp and its -z flank
            // (the wall of groove k+1) by -(k+1) dp. A flank shifted by s against the
            // ring's phase phi needs (s - phi) cot(a/2) more radius (+z flanks) or
            // (phi - s) cot(a/2) (-z flanks): the best ring takes phi halfway, and the
            // diameter grows by (max s+ - min s-) cot(a/2): the cumulative pitch
            // deviation between the outermost engaged flanks (teeth dp for dp > 0; for
            // dp < 0 the narrower teeth give back two pitches of it).
            let s_plus = (0..teeth)
                .map(|k| -(k as f64) * dp)
                .fold(f64::MIN, f64::max);
            let s_minus = (0..teeth)
                .map(|k| -(k as f64 + 1.0) * dp)
                .fold(f64::MAX, f64::min);
            let drift = s_plus - s_minus;
            let sign = if side == Side::External { 1.0 } else { -1.0 };
            let want = 2.0 * r2 + sign * drift * p.cot_hi;
            assert!(
                (2.0 * r - want).abs() < 2.0 * 0.0002 * p.cot_hi + 1e-6,
                "{side:?} r2 {r2} dp {dp}: {} vs {want}",
                2.0 * r
            );
        }
    }
}

/// The search against a dense scan of the phase (an independent minimisation) on
/// random threads: random tooth shifts, flank tilts and pitch radii.
#[test]
fn the_phase_search_finds_the_scans_optimum() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for case in 0..24 {
        let side = if case % 2 == 0 {
            Side::External
        } else {
            Side::Internal
        };
        let t = m30(side);
        let p = profile(side);
        let r2 = rng.range(14.2, 14.35);
        let teeth = 3 + (rng.next() * 5.0) as usize;
        let centres: Vec<f64> = (0..=teeth)
            .map(|k| -(k as f64) * P + rng.range(-0.02, 0.02) + 0.3)
            .collect();
        let tilt = rng.range(-0.01, 0.01);
        let span = (centres[teeth] - 0.5, centres[0] + 0.5);
        let cols = vec![
            column(&t, 0.0, r2, &centres, tilt, 0.001, span),
            column(&t, 1.0, r2 + 0.01, &centres, 0.0, 0.001, span),
        ];
        let pts = points(&t, &cols, P, span);
        let (r, _) = functional_radius(&p, &pts, None);
        let scan = (0..2000)
            .map(|k| size_at(&p, &pts, k as f64 * P / 2000.0))
            .fold(
                if p.external {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                },
                |a, b| if p.external { a.min(b) } else { a.max(b) },
            );
        // The scan's step is P/2000 in phase: at most that times cot(a/2) in radius
        // above (ring) or below (plug) the true optimum.
        let slack = P / 2000.0 * p.cot_hi;
        if p.external {
            assert!(
                r <= scan + 1e-9 && r >= scan - slack,
                "{case}: {r} vs {scan}"
            );
        } else {
            assert!(
                r >= scan - 1e-9 && r <= scan + slack,
                "{case}: {r} vs {scan}"
            );
        }
    }
}

/// The calls: a value within the resolution of a limit is undecided, beyond it a
/// fail, inside a pass; nothing measured is said.
#[test]
fn calls_respect_the_resolution() {
    let res = 0.002;
    assert_eq!(call(Some(28.6), 28.663, true, res), Call::Pass);
    assert_eq!(call(Some(28.662), 28.663, true, res), Call::Undecided);
    assert_eq!(call(Some(28.6645), 28.663, true, res), Call::Undecided);
    assert_eq!(call(Some(28.67), 28.663, true, res), Call::Fail);
    assert_eq!(call(Some(28.49), 28.493, false, res), Call::Fail);
    assert_eq!(call(Some(28.6), 28.493, false, res), Call::Pass);
    assert_eq!(call(None, 28.493, false, res), Call::NotMeasured);
    assert_eq!(Call::Pass.worse(Call::Undecided), Call::Undecided);
    assert_eq!(Call::Fail.worse(Call::Undecided), Call::Fail);
}

/// Over-wire values of `thread-gauging.md`: M20x2.5-6g over best wires (1.4434 mm) is
/// 20.329 .. 20.499 mm for d2 18.164 .. 18.334.
#[test]
fn over_wires_match_the_published_example() {
    let half = 30f64.to_radians();
    let p = 2.5;
    let w = p / (2.0 * half.cos());
    let m = |d2: f64| d2 + w * (1.0 + 1.0 / half.sin()) - 0.5 * p / half.tan();
    assert!((w - 1.4434).abs() < 5e-5);
    assert!((m(18.164) - 20.329).abs() < 5e-4, "{}", m(18.164));
    assert!((m(18.334) - 20.499).abs() < 5e-4, "{}", m(18.334));
    let _ = class(Side::External);
}

/// A V groove of 60 degrees (flanks 30 deg from the radial) with its root rounded to
/// `rho` (the arc tangent to both flanks: centre 2 rho above the V's apex), or with a flat
/// root `2 a` wide whose two corners are rounded to `rho` (the arc tangent to the flat and
/// the flank: its centre `rho` above the flat at `a' = a - rho (1/sin 60 - 1) tan 30 ...`
/// computed below), heights above the apex, capped at `cap`.
fn round_root(z: f64, rho: f64, flat: f64, cap: f64) -> f64 {
    let cot = 1.0 / 30f64.to_radians().tan();
    let u = z.abs();
    let h = if flat == 0.0 {
        // The arc meets the flank at z = rho cos 30.
        if u <= rho * 30f64.to_radians().cos() {
            2.0 * rho - (rho * rho - u * u).sqrt()
        } else {
            u * cot
        }
    } else {
        // Flat root at h = 0 for |z| <= flat, flank h = (|z| - flat) cot 30 beyond; the
        // corner arc's centre is rho above the flat, rho from the flank: at z = flat + c
        // with c = rho (1 - sin 30)/cos 30 ... the tangent to the flank.
        let c = rho * (1.0 - 30f64.to_radians().sin()) / 30f64.to_radians().cos();
        let zc = flat - c; // the arc's centre's z (it meets the flat at zc)
        let t = zc + rho * 30f64.to_radians().cos(); // it meets the flank here
        if u <= zc {
            0.0
        } else if u <= t {
            rho - (rho * rho - (u - zc).powi(2)).sqrt()
        } else {
            (u - flat) * cot
        }
    };
    h.min(cap)
}

/// The root radius found on the cut is the arc's radius (round V roots and rounded corners
/// of flat roots), and 0 for sharp corners, within the stated resolution; the disk's gap
/// at a V corner is `R - rho` (1/sin 30 - 1 = 1).
#[test]
fn the_root_radius_is_the_roots_arc() {
    let t = m30(Side::External);
    let dz = 0.0005;
    let (r_min, cap) = (0.25, 0.5);
    for (rho, flat) in [
        (0.0, 0.0),
        (0.1, 0.0),
        (0.2, 0.0),
        (0.3, 0.0),
        (0.5, 0.0),
        (0.0, 0.15),
        (0.08, 0.15),
        (0.12, 0.2),
    ] {
        // Grooves at z = 0, -2, -4, -6 (t = 0 .. 3); the root's apex on the thread's root.
        let (z0, n) = (-7.0, (8.0 / dz) as usize);
        let h: Vec<f32> = (0..n)
            .map(|j| {
                let z = z0 + j as f64 * dz;
                let k = (-z / P).round();
                round_root(z + k * P, rho, flat, t.depth()) as f32
            })
            .collect();
        let col = GaugeColumn {
            theta: 0.0,
            z0,
            dz,
            h,
        };
        let turns: Vec<TurnMeasure> = (1..=2)
            .map(|k| TurnMeasure {
                start: 0,
                turn: k + 1,
                t: k as f64,
                ideal_lead: None,
                lead: None,
                ideal_groove: None,
                groove: None,
                ideal_tooth: None,
                tooth: None,
                split: false,
                cut_heights: None,
                pitch_diameter: Some(0.0),
                ideal_pitch_diameter: None,
            })
            .collect();
        let rounding = 4e-6;
        let (got, _, res) =
            root::root_radius(&t, &[col], &[turns], r_min, cap, rounding).expect("a root");
        // The radius's resolution as `judge` states it (a flat root's 120 deg corner).
        // A V root's arc meets the disk at its bottom (1/sin 30 - 1 = 1): the gap's
        // resolution is the radius's.
        let factor = if flat == 0.0 {
            1.0
        } else {
            1.0 / (std::f64::consts::FRAC_PI_4 + 15f64.to_radians()).sin() - 1.0
        };
        assert!(
            (got - rho).abs() <= res / factor + 1e-6,
            "rho {rho} flat {flat}: {got} (resolution {})",
            res / factor
        );
    }
    // The gap on a sharp V of 30 deg flanks is R (1/sin 30 - 1) = R.
    let h: Vec<f64> = (0..2001)
        .map(|j| (-0.5 + j as f64 * 0.0005).abs() / 30f64.to_radians().tan())
        .collect();
    let g = root::gap(&h, 0.0005, 0.2, (990, 1011));
    assert!((g - 0.2).abs() < 0.002, "{g}");
}
