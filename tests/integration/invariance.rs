//! Same answer whatever the thread count; a left-hand thread is the mirror of a right-hand one.

use crate::support::in_pool;
use crate::support::{job, report_json, scene_text, with};
use vpcut::{simulate, SimOptions};

/// The report (timing aside) and every dexel are bit-identical with 1 and 2 threads, with
/// planar edges and with a rubbing tool body (its interference table included).
#[test]
fn one_and_two_threads_give_identical_bytes() {
    for scene in ["seed002-equal-tooth", "seed000-tool-rub"] {
        let text = with(
            &scene_text(scene),
            &[
                ("simulation", "angular_cells", "360"),
                ("simulation", "axial_spacing", "0.02"),
            ],
        );
        let j = job(&text);
        let a = in_pool(1, || simulate(&j, &SimOptions::default()).unwrap());
        let b = in_pool(2, || simulate(&j, &SimOptions::default()).unwrap());
        assert_eq!(report_json(&a).to_string(), report_json(&b).to_string());
        assert!(a
            .stock
            .outer
            .iter()
            .zip(&b.stock.outer)
            .all(|(x, y)| x.to_bits() == y.to_bits()));
        if scene == "seed000-tool-rub" {
            assert!(!a.report.interference.as_ref().unwrap().is_empty());
        }
    }
}

fn shifted(hand: &str, spindle: &str, angle: f64) -> String {
    format!(
        r#"
        [blank]
        diameter = 20.0
        length = 30.0
        [thread]
        form = "iso-metric"
        major_diameter = 20.0
        pitch = 2.5
        length = 20.0
        hand = "{hand}"
        start_angle = {angle}
        [[tool]]
        id = 1
        kind = "threading"
        angle = 58.0
        reference = "tip"
        [[pass]]
        tool = 1
        x = 17.2
        z_start = 5.03
        z_end = -35.0
        lead = 2.5
        lead_change = 0.01
        start_angle = {angle}
        [machine]
        spindle = "{spindle}"
        [simulation]
        angular_cells = 240
        axial_spacing = 0.02
        measure_generators = 1
        "#
    )
}

/// Mirroring the angle turns a right-hand thread cut with M03 into a left-hand one cut
/// with M04: column `i` of one is column `-i` of the other, and the deviations agree.
#[test]
fn left_and_right_hands_mirror() {
    let a = simulate(&job(&shifted("right", "cw", 30.0)), &SimOptions::default()).unwrap();
    let b = simulate(&job(&shifted("left", "ccw", -30.0)), &SimOptions::default()).unwrap();
    let g = a.stock.grid;
    let mut worst: f32 = 0.0;
    for i in 0..g.n_theta {
        let m = (g.n_theta - i) % g.n_theta;
        let ca = &a.stock.outer[i * g.n_z..(i + 1) * g.n_z];
        let cb = &b.stock.outer[m * g.n_z..(m + 1) * g.n_z];
        for (x, y) in ca.iter().zip(cb) {
            worst = worst.max((x - y).abs());
        }
    }
    assert!(worst < 1e-5, "columns differ by {worst} mm");
    let (ra, rb) = (&a.report, &b.report);
    assert!(
        ra.deviation.max_gouge_mm > 0.01,
        "the test needs a real deviation"
    );
    assert!((ra.deviation.max_gouge_mm - rb.deviation.max_gouge_mm).abs() < 1e-5);
    assert!((ra.deviation.max_leftover_mm - rb.deviation.max_leftover_mm).abs() < 1e-5);
    let rel = (ra.deviation.gouge_volume_mm3 - rb.deviation.gouge_volume_mm3).abs()
        / ra.deviation.gouge_volume_mm3;
    assert!(rel < 1e-6, "{rel}");
    assert_eq!(ra.thread.hand, "right");
    assert_eq!(rb.thread.hand, "left");
    for (x, y) in ra.turns.iter().zip(&rb.turns) {
        assert_eq!(
            x.measured_lead_mm.map(|v| (v * 1e4).round()),
            y.measured_lead_mm.map(|v| (v * 1e4).round())
        );
    }
}
