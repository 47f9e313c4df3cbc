//! The pictures that need no GPU (developed view, axial section, deviation trace) against the
//! report and the exact single pass: the tolerance band of the report's worst gouge and
//! leftover where the report says they are, nothing coloured on an exact cut, the field
//! cropped to the compared span, the same bytes with 1 and 2 threads, and the CLI files.

use crate::support::{job, scene_text, with};
use image::RgbImage;
use vpcut::{
    band_colour, developed_plot, section_profile, signed_deviation, simulate, trace_view,
    SimOptions,
};

/// Gouge pixels are clearly blue, leftover clearly red or orange, neutral grey.
fn kind(img: &RgbImage, x: u32, y: u32) -> &'static str {
    let p = img.get_pixel(x, y).0;
    let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
    if b > r + 40 {
        "gouge"
    } else if r > b + 40 && r > g + 40 {
        "leftover"
    } else {
        "other"
    }
}

/// Seed 002's misplaced grooves: the pixel under the report's worst gouge is in the gouge
/// band of that value against the tolerance, and the one under its worst leftover in the
/// leftover band of its value; the field spans the report's compared z. The report finds them with `compare` over every
/// dexel; the picture computes its own deviations per pixel block: two computations that
/// must agree on where the worst is.
#[test]
fn developed_view_shows_the_reported_extremes() {
    let text = with(
        &scene_text("seed002-equal-groove"),
        &[
            ("simulation", "angular_cells", "720"),
            ("simulation", "axial_spacing", "0.02"),
        ],
    );
    let j = job(&text);
    let out = simulate(&j, &SimOptions::default()).unwrap();
    let tol = j.sim.tolerance;
    let plot = developed_plot(
        &out.stock,
        &j.thread,
        &out.deviation,
        tol,
        1000,
        900,
        "seed002",
    );
    let img = &plot.image;
    let [x0, y0, x1, y1] = plot.field;
    let (z_bot, z_top) = plot.z;
    let pixel = |angle_deg: f64, z: f64| {
        let w = (x1 - x0) as f64;
        let h = (y1 - y0) as f64;
        let x = x0 + ((angle_deg / 360.0 * w).floor() as u32).min(x1 - x0 - 1);
        let y = y0 + (((z_top - z) / (z_top - z_bot) * h).floor() as u32).min(y1 - y0 - 1);
        (x, y)
    };
    let [za, zb] = out.report.deviation.compared_z_mm.unwrap();
    let cell = out.stock.grid.dz;
    assert!(
        (za - z_bot).abs() <= cell && (zb - z_top).abs() <= cell,
        "{:?} vs {za} {zb}",
        plot.z
    );
    let d = &out.report.deviation;
    assert!(d.max_gouge_mm > 1.0 && d.max_leftover_mm > 1.0, "{d:?}");
    let g = d.max_gouge_at.as_ref().unwrap();
    let (x, y) = pixel(g.angle_deg, g.z_mm);
    assert_eq!(
        img.get_pixel(x, y).0,
        band_colour(Some(-d.max_gouge_mm), tol),
        "worst gouge at {g:?} -> pixel {x},{y}"
    );
    assert_eq!(kind(img, x, y), "gouge");
    let l = d.max_leftover_at.as_ref().unwrap();
    let (x, y) = pixel(l.angle_deg, l.z_mm);
    assert_eq!(
        img.get_pixel(x, y).0,
        band_colour(Some(d.max_leftover_mm), tol),
        "worst leftover at {l:?} -> pixel {x},{y}"
    );
    assert_eq!(kind(img, x, y), "leftover");
    // The rings and the legend's values are the report's extremes, not the picture's own
    // per-pixel distance (a root short all across is reported at its radial size).
    for (worst, value, at) in [
        (plot.worst[0], -d.max_gouge_mm, g),
        (plot.worst[1], d.max_leftover_mm, l),
    ] {
        let (v, [x, y]) = worst.expect("the worst place is ringed");
        assert!((v - value).abs() <= 1e-6, "ringed {v} vs reported {value}");
        let (ex, ey) = pixel(at.angle_deg, at.z_mm);
        assert!(
            x.abs_diff(ex) <= 1 && y.abs_diff(ey) <= 1,
            "ring at {x},{y}, the report's place at {ex},{ey}"
        );
    }
    // Same bytes with 1 and 2 threads.
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let draw = || developed_plot(&out.stock, &j.thread, &out.deviation, tol, 500, 300, "t").image;
    let (a, b) = (pool(1).install(draw), pool(2).install(draw));
    assert_eq!(a.as_raw(), b.as_raw());
    let draw = || {
        trace_view(
            &out.stock,
            &j.thread,
            &out.deviation,
            0.3,
            tol,
            500,
            300,
            "t",
        )
    };
    let (a, b) = (pool(1).install(draw), pool(2).install(draw));
    assert_eq!(a.as_raw(), b.as_raw());
}

/// The exact single pass (checked against hand-computed values in `oracle`) leaves nothing
/// outside the tolerance: no gouge or leftover pixel anywhere, and along a generator every
/// compared cell's normal deviation is within one axial cell of zero.
#[test]
fn an_exact_cut_is_all_neutral() {
    let j = job(&scene_text("equal-groove-single-pass"));
    let out = simulate(&j, &SimOptions::default()).unwrap();
    assert_eq!(out.report.verdict, vpcut::Verdict::Pass);
    let plot = developed_plot(
        &out.stock,
        &j.thread,
        &out.deviation,
        j.sim.tolerance,
        600,
        400,
        "exact",
    );
    let [x0, y0, x1, y1] = plot.field;
    assert!(x1 - x0 > 300 && y1 - y0 > 200, "{:?}", plot.field);
    let coloured = (x0..x1)
        .flat_map(|x| (y0..y1).map(move |y| (x, y)))
        .filter(|&(x, y)| kind(&plot.image, x, y) != "other")
        .count();
    assert_eq!(coloured, 0);
    assert_eq!(plot.worst, [None, None]);
    let prof = section_profile(&out.stock, &j.thread, 0.0);
    let ideal = j.thread.column(
        0.0,
        out.stock.grid.z(0),
        out.stock.grid.z(out.stock.grid.n_z - 1),
    );
    let mut compared = 0;
    for &(z, r_cut, r_ideal) in &prof {
        if r_ideal.is_some() {
            let d = signed_deviation(&j.thread, &ideal, z, r_cut).unwrap();
            assert!(d.abs() <= out.stock.grid.dz, "z {z}: {d}");
            compared += 1;
        }
    }
    assert!(compared > 100, "{compared}");
}

/// `--plots DIR` writes the three PNGs with the documented sizes; an unwritable folder is exit 2.
#[test]
fn cli_writes_the_plots() {
    let dir = std::env::temp_dir().join(format!("vpcut-plots-{}", std::process::id()));
    let job = crate::support::root()
        .join("scenes")
        .join("equal-groove-single-pass")
        .join("job.toml");
    let run = |plots: &std::path::Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(["simulate", job.to_str().unwrap(), "-q", "--plots"])
            .arg(plots)
            .output()
            .unwrap()
    };
    let out = run(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dev = image::open(dir.join("developed.png")).unwrap();
    let sec = image::open(dir.join("section.png")).unwrap();
    let tr = image::open(dir.join("trace.png")).unwrap();
    assert_eq!((dev.width(), dev.height()), (1600, 900));
    assert_eq!((sec.width(), sec.height()), (1600, 600));
    assert_eq!((tr.width(), tr.height()), (1600, 500));
    let _ = std::fs::remove_dir_all(&dir);
    let out = run(std::path::Path::new("/proc/vpcut-no-such-place"));
    assert_eq!(out.status.code(), Some(2));
    // --plot-size: the developed view's size, the others its width and 2/3, 5/9 of its
    // height (rounded up); out-of-range or malformed sizes and a size without plots are
    // refused with exit 2 before anything is simulated.
    let sized = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_vpcut"))
            .args(["simulate", job.to_str().unwrap(), "-q"])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = sized(&["--plots", dir.to_str().unwrap(), "--plot-size", "800x600"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (file, want) in [
        ("developed.png", (800, 600)),
        ("section.png", (800, 400)),
        ("trace.png", (800, 334)),
    ] {
        let img = image::open(dir.join(file)).unwrap();
        assert_eq!((img.width(), img.height()), want, "{file}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    for bad in ["100x600", "800x9000", "800", "axb", "800x-1"] {
        let out = sized(&["--plots", dir.to_str().unwrap(), "--plot-size", bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--plot-size"),
            "{bad}"
        );
        assert!(!dir.exists(), "{bad}: nothing written");
    }
    let out = sized(&["--plot-size", "800x600"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--plots"));
}

/// A two-start thread: the developed view labels every groove of the drawing on the 360 deg
/// generator with its turn and start, as the report files them. Oracle: the report's
/// per-turn rows (the comparison's (turn, start) pairs) are the labels' pairs; the labels
/// alternate starts and lie one pitch (`lead / 2`, the closed form) apart in z; each
/// start's turns count up by one per lead towards -z (the thread is cut from +z).
#[test]
fn developed_view_labels_every_start() {
    let text = with(
        &scene_text("iso-m20x2.5-radial"),
        &[
            ("thread", "starts", "2"),
            ("simulation", "angular_cells", "360"),
            ("simulation", "axial_spacing", "0.02"),
        ],
    );
    let j = job(&text);
    assert_eq!(j.thread.starts, 2);
    let out = simulate(&j, &SimOptions::default()).unwrap();
    let plot = developed_plot(
        &out.stock,
        &j.thread,
        &out.deviation,
        j.sim.tolerance,
        1200,
        1600,
        "two starts",
    );
    let labels = &plot.turn_labels;
    assert!(labels.len() >= 8, "{labels:?}");
    let mut got: Vec<(i64, u32)> = labels.iter().map(|l| (l.0, l.1)).collect();
    got.sort_unstable();
    let mut want: Vec<(i64, u32)> = out
        .report
        .turns
        .iter()
        .map(|t| (t.turn, t.start + 1))
        .collect();
    want.sort_unstable();
    want.dedup();
    assert_eq!(got, want, "labels against the report's turns");
    let pitch = 2.5;
    for w in labels.windows(2) {
        let ((ta, sa, za), (tb, sb, zb)) = (w[0], w[1]);
        assert_ne!(sa, sb, "{w:?}: starts alternate");
        assert!(((za - zb) - pitch).abs() < 0.05, "{w:?}: one pitch apart");
        let _ = (ta, tb);
    }
    for s in [1, 2] {
        let mine: Vec<&(i64, u32, f64)> = labels.iter().filter(|l| l.1 == s).collect();
        for w in mine.windows(2) {
            assert_eq!(w[1].0, w[0].0 + 1, "start {s}: {w:?}");
            assert!(((w[0].2 - w[1].2) - 2.0 * pitch).abs() < 0.05);
        }
    }
}
