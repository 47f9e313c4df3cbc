//! Issue 28: the cycle time of three programs against derivations by hand (each written
//! out below): a G76 (rapids, threading, the one-rev waits), the turned scene's whole
//! program (G96 under a G50 clamp: facing through the clamp's diameter, turning, G92
//! passes at G97), and a program with a feed per minute, an arc per revolution, a dwell,
//! a chained thread block and the job's own rapid rate. Within 2 % each part; the
//! model's own integrals are exact, so they agree to far less.

use crate::crashes::{case_job, G76_DEPTHS};
use crate::support::scene_job;
use vpcut::{CycleTime, Job};

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 0.02 * want.abs() + 1e-9,
        "{what}: {got} s against {want} s by hand"
    );
}

fn time_of(job: &Job) -> &CycleTime {
    job.cycle_time
        .as_ref()
        .expect("a lathe program's cycle time")
}

#[test]
fn a_g76_cycle_by_hand() {
    // tests/data/crash/rapid-below-crest/fixed.nc: G76 from X32 Z5 to X27.546 Z-39.5,
    // k 1.227, dd 0.4, dmin 0.1, d 0.05: depths 0.4, 0.4 sqrt 2, 0.4 sqrt 3, 0.8, 0.9, 1.0,
    // 1.1, 1.177, 1.227; pass X = 27.546 + 2 (1.227 - d). Each pass: rapid along Z by its
    // shift s, in to X, thread 44.5 mm, out, back 44.5 - s: rapid 44.5 + (32 - X) mm. Then
    // G00 X100 Z100 from X32 Z5: hypot(34, 95). The first move (G00 X32 Z5 from where the
    // machine was) is not counted. Rapids at the default 10000 mm/min.
    let job = case_job("rapid-below-crest", "fixed.nc", &[]);
    let c = time_of(&job);
    let rapid_mm: f64 = G76_DEPTHS
        .iter()
        .map(|d| 44.5 + (32.0 - (27.546 + 2.0 * (1.227 - d))))
        .sum::<f64>()
        + 34f64.hypot(95.0);
    let thread = 9.0 * (44.5 / 2.0) / 800.0 * 60.0;
    let wait = 9.0 * 0.5 / 800.0 * 60.0;
    let rapid = rapid_mm / 10_000.0 * 60.0;
    close(c.rapid, rapid, "rapids");
    close(c.thread, thread, "threading");
    close(c.wait, wait, "waits");
    assert_eq!(c.feed, 0.0);
    close(c.total(), rapid + thread + wait, "total");
    assert!(!c.rapid_rate_given);
    assert_eq!(c.by_tool.len(), 1);
    assert_eq!(c.by_tool[0].0, Some(3));
}

#[test]
fn the_turned_scenes_program_by_hand() {
    // scenes/turned-m20x2.5-fanuc/O0017.NC. T0101 under G96 S180 (m/min), G50 S2500: the
    // speed is 1000 x 180 / (pi x) rev/min, clamped at 2500 under x = 180000 / (2500 pi) =
    // 22.918 mm. Minutes per revolution m(x) = max(1/2500, pi x / 180000).
    let xc = 180_000.0 / (2500.0 * std::f64::consts::PI);
    let m = |x: f64| (1.0 / 2500.0f64).max(std::f64::consts::PI * x.abs() / 180_000.0);
    // A straight move from x0 to x1 (both on one side of xc or through it): the mean of
    // m over the move, by pieces where it is linear in x.
    let mean = |x0: f64, x1: f64| {
        let (lo, hi) = (x0.min(x1), x0.max(x1));
        if hi <= xc {
            return 1.0 / 2500.0;
        }
        let unclamped = (hi - xc.max(lo)) / (hi - lo);
        unclamped * 0.5 * (m(hi) + m(xc.max(lo))) + (1.0 - unclamped) / 2500.0
    };
    // N60 face X27 -> X-1.6 at 0.15 mm/rev; N85 Z2 -> Z0 at X17, 0.2; N90 the chamfer
    // X17 Z0 -> X19.8 Z-1.4 (hypot(1.4, 1.4)), 0.15; N100 28.6 mm at X19.8; N110 X19.8 ->
    // X26 (3.1 mm): minutes = length / feed x mean minutes per revolution.
    let feed_min = 14.3 / 0.15 * mean(27.0, -1.6)
        + 2.0 / 0.2 * mean(17.0, 17.0)
        + 1.4f64.hypot(1.4) / 0.15 * mean(17.0, 19.8)
        + 28.6 / 0.15 * mean(19.8, 19.8)
        + 3.1 / 0.15 * mean(19.8, 26.0);
    // T0303 at G97 S600: ten G92 passes Z5 -> Z-25, 12 revolutions each, each after half a
    // revolution's wait.
    let thread = 10.0 * 12.0 / 600.0 * 60.0;
    let wait = 10.0 * 0.5 / 600.0 * 60.0;
    // Rapids: N70 Z2 (2 mm), N80 X17 (9.3 radial), N120 X100 Z100 from X26 Z-30
    // (hypot(37, 130)), N150 X24 Z5 (hypot(38, 95)), each G92 pass (24 - X) radial in and
    // out and 30 back, N260 X100 Z100 (hypot(38, 95)).
    let xs = [
        19.3, 18.75, 18.25, 17.85, 17.5, 17.25, 17.07, 16.96, 16.933, 16.933,
    ];
    let rapid_mm = 2.0
        + 9.3
        + 37f64.hypot(130.0)
        + 2.0 * 38f64.hypot(95.0)
        + xs.iter().map(|x| (24.0 - x) + 30.0).sum::<f64>();
    let job = scene_job("turned-m20x2.5-fanuc");
    let c = time_of(&job);
    close(c.feed, feed_min * 60.0, "feeds");
    close(c.thread, thread, "threading");
    close(c.wait, wait, "waits");
    close(c.rapid, rapid_mm / 10_000.0 * 60.0, "rapids");
    // The face in numbers: 2.317 s (the clamp holds 2500 rev/min under X22.918).
    close(14.3 / 0.15 * mean(27.0, -1.6) * 60.0, 2.3171, "the face");
}

#[test]
fn feeds_per_minute_an_arc_a_dwell_and_a_chained_thread_by_hand() {
    // [machine] rapid_rate 6000. After the first move: G98 G01 Z-20 F120 (20 mm at 120
    // mm/min: 10 s); G99 G97 S500 G02 X30 Z-25 R5 F0.1 (a quarter circle of 5: 7.854 mm,
    // 78.54 revolutions at 500: 9.425 s); G04 X1.5 (1.5 s); G00 X22 Z5 (hypot(4, 30));
    // G32 Z-10 F2 then, chained, G32 X26 Z-12 F2 (15 + 2 mm of Z: 8.5 revolutions: 1.02
    // s; one wait of half a revolution: 0.06 s); G00 X40 (7 radial).
    let prog = "T0101\nG0 X20 Z0\nG98 G1 Z-20 F120\nG99 G97 S500\nG2 X30 Z-25 R5 F0.1\nG4 X1.5\nG0 X22 Z5\nG32 Z-10 F2\nG32 X26 Z-12 F2\nG0 X40\nM30\n";
    let text = r#"
[blank]
diameter = 30.0
length = 60.0
[thread]
form = "iso-metric"
major_diameter = 30.0
pitch = 2.0
length = 10.0
z_start = -1.0
[[tool]]
id = 1
kind = "threading"
angle = 60.0
[program]
file = "p.nc"
dialect = "fanuc"
decimal_point = "calculator"
[machine]
spindle_rpm = 500
rapid_rate = 6000
"#;
    let job = Job::from_toml_with(text, "job.toml", &|f: &str| {
        (f == "p.nc").then(|| prog.to_string())
    })
    .unwrap();
    let c = time_of(&job);
    close(
        c.feed,
        10.0 + 5.0 * std::f64::consts::FRAC_PI_2 / 0.1 / 500.0 * 60.0,
        "feeds",
    );
    close(c.wait, 1.5 + 0.5 / 500.0 * 60.0, "waits");
    close(c.thread, 17.0 / 2.0 / 500.0 * 60.0, "threading");
    close(c.rapid, (4f64.hypot(30.0) + 7.0) / 6000.0 * 60.0, "rapids");
    assert!(c.rapid_rate_given);
}
