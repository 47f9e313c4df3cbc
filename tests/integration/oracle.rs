//! Geometry against independent oracles: closed forms, hand-computed passes, and a second
//! numerical method.

use crate::support::{run, scene_text, with, INTERNAL_M20};
use std::f64::consts::{PI, TAU};

/// A tool as wide as the groove on the groove's own helix cuts the ideal groove; the leads
/// along every generator are the closed-form `F + K*(t + 1/2)` (domain.md section 2).
#[test]
fn single_equal_groove_pass_is_exact() {
    let out = run(&scene_text("equal-groove-single-pass"));
    let r = &out.report;
    let dz = 0.005;
    assert!(
        r.deviation.max_gouge_mm <= dz,
        "gouge {}",
        r.deviation.max_gouge_mm
    );
    assert!(
        r.deviation.max_leftover_mm <= dz,
        "leftover {}",
        r.deviation.max_leftover_mm
    );
    assert_eq!(r.turns.len(), 5);
    let (f, k) = (8.0, 4.0);
    for t in &r.turns {
        let n = t.turn as f64;
        let p_n = 10.0 + 4.0 * (n - 1.0);
        let got = t.measured_lead_mm.expect("lead measured");
        assert!((got - p_n).abs() <= 0.002, "turn {n}: {got} vs {p_n}");
        // Generators at 30 deg steps: phase g/12 of a turn later, lead F + K(t + 1/2).
        if t.turn < 5 {
            let last = f + k * (n - 1.0 + 11.0 / 12.0 + 0.5);
            let hi = t.lead_spread.measured_max_mm.unwrap();
            assert!((hi - last).abs() <= 0.002, "turn {n}: max {hi} vs {last}");
        }
        assert!((t.groove_width_mm.unwrap_or(5.0) - 5.0).abs() <= 0.002);
    }
}

/// Closed-form first moment of a V tool's profile below radius `big_r`: the volume a pass
/// removes per radian of helix, `M = int (R^2 - r(u)^2)/2 du`.
fn v_moment(big_r: f64, r_tip: f64, flat: f64, half_angle: f64) -> f64 {
    let c = 1.0 / half_angle.tan();
    let w = (big_r - r_tip) / c;
    flat * (big_r * big_r - r_tip * r_tip) / 2.0 + big_r * big_r * w
        - (big_r.powi(3) - r_tip.powi(3)) / (3.0 * c)
}

fn v_pass_job(dz: f64, cells: usize, shift: f64) -> String {
    format!(
        r#"
        [blank]
        diameter = 20.0
        length = 40.0
        z_front = 0.0
        [thread]
        form = "iso-metric"
        major_diameter = 20.0
        pitch = 2.5
        length = 30.0
        z_start = 0.0
        [[tool]]
        id = 1
        kind = "threading"
        angle = 60.0
        tip_flat = 0.4166666666666667
        reference = "tip"
        [[pass]]
        tool = 1
        x = 16.9328275
        z_start = {z_start}
        z_end = -45.0
        lead = 2.5
        [simulation]
        axial_spacing = {dz}
        angular_cells = {cells}
        measure_generators = 4
        "#,
        z_start = 5.0 + shift,
    )
}

/// A constant-lead V pass through the whole blank removes `2*pi*M*length/L` (the groove's
/// first moment swept over length/L turns; both ends lie outside the blank). Over the whole
/// grid the axial sampling errors of the columns cancel (their groove positions are spread
/// evenly over a cell), so the sum matches to f32 precision at every spacing.
#[test]
fn removed_volume_matches_closed_form() {
    let (big_r, r_tip) = (10.0, 16.9328275 / 2.0);
    let exact = TAU * v_moment(big_r, r_tip, 0.4166666666666667, PI / 6.0) * 40.0 / 2.5;
    for dz in [0.08, 0.02] {
        let out = run(&v_pass_job(dz, 360, 0.0));
        let v = out.report.deviation.total_removed_volume_mm3;
        let rel = ((v - exact) / exact).abs();
        assert!(rel < 1e-6, "dz {dz}: {v} vs {exact} ({rel:e})");
    }
}

/// On one generator, around one groove, the removed area converges to the closed-form
/// moment at second order in the axial spacing: the midpoint rule on a profile with kinks.
/// The error of each spacing depends on where the kinks fall in their cells, so the order
/// is the least-squares slope of log(error) over eleven spacings (0.2 to 0.009 mm, ratio
/// 1.37). The whole-grid sum above hides this: its columns' errors cancel.
#[test]
fn single_groove_volume_converges_at_second_order() {
    let (big_r, r_tip) = (10.0, 16.9328275 / 2.0);
    let exact = v_moment(big_r, r_tip, 0.4166666666666667, PI / 6.0);
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    let mut dz: f64 = 0.2;
    while dz > 0.008 {
        // The window holds the groove centred at z = -2.5 on generator 0 and nothing else.
        let text = with(
            &v_pass_job(dz, 4, 0.0),
            &[("simulation", "z_range", "[-3.7, -1.1]")],
        );
        let out = run(&text);
        let g = out.stock.grid;
        let sum: f64 = (0..g.n_z)
            .map(|j| {
                let r = out.stock.radius(vpcut::Surface::Outer, 0, j).unwrap();
                (big_r * big_r - r * r) / 2.0 * g.dz
            })
            .sum();
        xs.push(dz.ln());
        ys.push(((sum - exact) / exact).abs().ln());
        dz /= 1.37;
    }
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    eprintln!(
        "convergence order {slope:.3}, errors {:?}",
        ys.iter().map(|y| y.exp()).collect::<Vec<_>>()
    );
    assert!(slope > 1.7, "order {slope}");
    assert!(ys.last().unwrap().exp() < 1e-4);
}

/// Ideal ISO M20x2.5 groove (60 deg, root flat P/6 at d3) and the same tool shifted
/// axially by `s`: height of each above the root at offset `u` from the groove centre.
fn iso_groove(u: f64, s: f64) -> f64 {
    let p = 2.5;
    let depth = (20.0 - (20.0 - 1.226869 * p)) / 2.0;
    let c = 1.0 / (PI / 6.0).tan();
    // One period: the nearest groove centre.
    let v = u - s - p * ((u - s) / p).round();
    ((v.abs() - p / 12.0).max(0.0) * c).min(depth)
}

/// A V pass at full depth moved 0.05 mm along the axis gouges one flank and leaves stock on
/// the other by the normal distance `0.05*cos(30 deg)`, and the gouge volume of a whole turn
/// equals `2*pi` times the gouge's first moment over one pitch, integrated here by a
/// second method (a fine trapezoid rule on the analytic profiles).
#[test]
fn shifted_v_pass_gouge_matches_normal_distance_and_moment() {
    let shift = 0.05;
    let want = shift * (PI / 6.0).cos();
    let r_root = (20.0 - 1.226869 * 2.5) / 2.0;
    let n = 2_000_000;
    let p = 2.5;
    let mut g = 0.0;
    for i in 0..n {
        let u = (i as f64 + 0.5) / n as f64 * p;
        let ideal = r_root + iso_groove(u, 0.0);
        let cut = r_root + iso_groove(u, shift);
        if cut < ideal {
            g += (ideal * ideal - cut * cut) / 2.0 * (p / n as f64);
        }
    }
    let turn_gouge = TAU * g;
    let mut vol_err = Vec::new();
    for dz in [0.01, 0.0025] {
        let out = run(&v_pass_job(dz, 360, shift));
        let r = &out.report;
        assert!(
            (r.deviation.max_gouge_mm - want).abs() < 2e-5,
            "{} vs {want}",
            r.deviation.max_gouge_mm
        );
        assert!((r.deviation.max_leftover_mm - want).abs() < 2e-5);
        let mid = r.turns.iter().find(|t| t.turn == 5).unwrap();
        assert!(mid.flanks.left.max_gouge_mm > 0.04 || mid.flanks.right.max_gouge_mm > 0.04);
        vol_err.push(((mid.gouge_volume_mm3 - turn_gouge) / turn_gouge).abs());
        let left = ((mid.leftover_volume_mm3 - turn_gouge) / turn_gouge).abs();
        assert!(
            left < 0.02,
            "leftover volume {} vs {turn_gouge}",
            mid.leftover_volume_mm3
        );
    }
    eprintln!("gouge volume relative errors {vol_err:?}");
    assert!(vol_err[1] < 2e-3, "{vol_err:?}");
    assert!(vol_err[1] < vol_err[0] || vol_err[0] < 1e-4, "{vol_err:?}");
}

/// The helix angle in the report is `atan(L / (pi d2))` (domain.md section 6: M20x2.5 has
/// psi = 2.48 deg).
#[test]
fn helix_angle_of_m20() {
    let text = with(
        &scene_text("iso-m20x2.5-radial"),
        &[
            ("simulation", "angular_cells", "36"),
            ("simulation", "axial_spacing", "0.05"),
        ],
    );
    let out = run(&text);
    for t in &out.report.turns {
        assert!(
            (t.helix_angle_deg - 2.48).abs() < 0.005,
            "{}",
            t.helix_angle_deg
        );
    }
}

/// An internal M20x2.5 (ISO 68-1: D1 = 17.2937, root flat P/8 at D) cut by radial layers
/// with an insert whose tip flat is that root flat: the nut comes out ideal.
#[test]
fn internal_thread_by_radial_infeed_is_ideal() {
    let text = INTERNAL_M20;
    let out = run(text);
    let r = &out.report;
    assert_eq!(r.thread.side, "internal");
    assert_eq!(r.stock.surfaces, vec!["outer", "inner"]);
    assert_eq!(r.verdict, vpcut::Verdict::Pass, "{}", r.summary());
    assert!(r.deviation.max_gouge_mm < 1e-4 && r.deviation.max_leftover_mm < 1e-4);
    let t = &r.turns[3];
    assert!((t.measured_lead_mm.unwrap() - 2.5).abs() < 1e-3);
    assert!(
        (t.groove_width_mm.unwrap() - 1.25).abs() < 1e-3,
        "groove at D2 is P/2"
    );
    // The cut reaches the major diameter (the internal thread's root) and keeps D1.
    assert!((t.max_diameter_mm.unwrap() - 20.0).abs() < 1e-5);
    assert!((t.min_diameter_mm.unwrap() - 17.29367).abs() < 1e-5);
    // The outer surface is untouched.
    assert!(out.stock.outer.iter().all(|&q| q == 0.0));
}

fn two_start(starts_cut: &str) -> String {
    format!(
        r#"
        [blank]
        diameter = 20.0
        length = 30.0
        [thread]
        form = "iso-metric"
        major_diameter = 20.0
        pitch = 2.5
        starts = 2
        turns = 4
        hand = "left"
        start_angle = 40.0
        [[tool]]
        id = 1
        kind = "threading"
        angle = 60.0
        tip_flat = 0.4166666666666667
        reference = "tip"
        {starts_cut}
        [machine]
        spindle = "ccw"
        [simulation]
        angular_cells = 360
        axial_spacing = 0.01
        measure_generators = 4
        "#
    )
}

/// A two-start left-hand thread (lead 5 = 2 x pitch, starts 180 deg apart): the radial
/// generator cuts both starts and the thread is ideal; cutting only the first start leaves
/// the second start's grooves as stock.
#[test]
fn two_start_thread_needs_both_starts() {
    let both = run(&two_start(
        "[process]\nkind = \"radial\"\ntool = 1\nlayers = 4",
    ));
    let r = &both.report;
    assert_eq!(r.verdict, vpcut::Verdict::Pass, "{}", r.summary());
    assert_eq!(r.thread.hand, "left");
    assert_eq!(r.turns.len(), 8, "4 turns x 2 starts");
    // On the reference generator start 1's features sit at t = 0.5, 1.5, ..: its 4th turn
    // ends past the thread there and is not measured.
    let measured: Vec<_> = r
        .turns
        .iter()
        .filter(|t| t.measured_lead_mm.is_some())
        .collect();
    assert_eq!(measured.len(), 7, "{}", r.summary());
    for t in measured {
        assert!(
            (t.measured_lead_mm.unwrap() - 5.0).abs() < 1e-3,
            "lead = starts x pitch"
        );
        assert!(
            (t.tooth_width_mm.unwrap() - 1.25).abs() < 1e-3,
            "neighbouring starts 2.5 apart"
        );
    }
    // The same passes for start 0 only: the helix of start 0 with the same law.
    assert_eq!(both.report.passes, 8, "4 layers x 2 starts");
    let first = vpcut::Job::from_toml(
        &two_start("[process]\nkind = \"radial\"\ntool = 1\nlayers = 4"),
        "t",
    )
    .unwrap();
    let mut job = first.clone();
    job.passes
        .retain(|p| (p.start_angle - first.passes[0].start_angle).abs() < 1e-9);
    assert_eq!(job.passes.len(), 4);
    let half = vpcut::simulate(&job, &vpcut::SimOptions::default()).unwrap();
    assert_eq!(half.report.verdict, vpcut::Verdict::Fail);
    // An uncut groove of start 1: its root is missing by the whole depth, reported at the
    // root with its radial size, (d - d3)/2 = 1.226869 P / 2 = 1.53359; on the flanks the
    // middle of the groove at the crest is half its crest width (7/16 P) from either 30 deg
    // flank, normal distance 7/16 * 2.5 * cos30 = 0.94722.
    let depth = 1.226869 * 2.5 / 2.0;
    let got = half.report.deviation.max_leftover_mm;
    assert!(
        (got - depth).abs() < 1e-4,
        "{got} vs {depth}: whole grooves of start 1 left"
    );
    let at = half.report.deviation.max_leftover_at.as_ref().unwrap();
    assert_eq!((at.start, at.flank), (1, "root"));
    let want = 7.0 / 16.0 * 2.5 * (PI / 6.0).cos();
    for t in half.report.turns.iter().filter(|t| t.start == 1) {
        for f in [&t.flanks.left, &t.flanks.right] {
            assert!(
                (f.max_leftover_mm - want).abs() < 0.01,
                "turn {}: {} vs {want}",
                t.turn,
                f.max_leftover_mm
            );
        }
    }
    assert!(half.report.deviation.max_gouge_mm < 1e-4);
}
