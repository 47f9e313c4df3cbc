//! The pictures that need no GPU (developed view, axial section) against the report and the
//! exact single pass: colours where the report says the worst gouge and leftover are,
//! nothing coloured on an exact cut, the same bytes with 1 and 2 threads, and the CLI files.

use crate::support::{job, scene_text, with};
use image::RgbImage;
use vpcut::{developed_view, section_profile, signed_deviation, simulate, SimOptions};

/// Gouge pixels are clearly blue, leftover clearly red, neutral grey (r = g within 10).
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

/// Seed 002's misplaced grooves: the pixel under the report's worst gouge is blue and the
/// one under its worst leftover is red. The report finds them with `compare` over every
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
    let (w, h) = (720u32, 850u32);
    let img = developed_view(&out.stock, &j.thread, j.sim.tolerance, w, h);
    let grid = out.stock.grid;
    let (z_top, z_bot) = (
        grid.z(grid.n_z - 1) + 0.5 * grid.dz,
        grid.z(0) - 0.5 * grid.dz,
    );
    let pixel = |angle_deg: f64, z: f64| {
        let x = ((angle_deg / 360.0 * w as f64).floor() as u32).min(w - 1);
        let y = (((z_top - z) / (z_top - z_bot) * h as f64).floor() as u32).min(h - 1);
        (x, y)
    };
    let d = &out.report.deviation;
    assert!(d.max_gouge_mm > 1.0 && d.max_leftover_mm > 1.0, "{d:?}");
    let g = d.max_gouge_at.as_ref().unwrap();
    let (x, y) = pixel(g.angle_deg, g.z_mm);
    assert_eq!(
        kind(&img, x, y),
        "gouge",
        "worst gouge at {g:?} -> pixel {x},{y}"
    );
    let l = d.max_leftover_at.as_ref().unwrap();
    let (x, y) = pixel(l.angle_deg, l.z_mm);
    assert_eq!(
        kind(&img, x, y),
        "leftover",
        "worst leftover at {l:?} -> pixel {x},{y}"
    );
    // Same bytes with 1 and 2 threads.
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let a = pool(1).install(|| developed_view(&out.stock, &j.thread, j.sim.tolerance, 300, 200));
    let b = pool(2).install(|| developed_view(&out.stock, &j.thread, j.sim.tolerance, 300, 200));
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
    let img = developed_view(&out.stock, &j.thread, j.sim.tolerance, 360, 400);
    let coloured = (0..360)
        .flat_map(|x| (0..400).map(move |y| (x, y)))
        .filter(|&(x, y)| kind(&img, x, y) != "other")
        .count();
    assert_eq!(coloured, 0);
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

/// `--plots DIR` writes both PNGs with the documented sizes; an unwritable folder is exit 2.
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
    assert_eq!((dev.width(), dev.height()), (1440 + 170, 900));
    assert_eq!((sec.width(), sec.height()), (1600, 600));
    let _ = std::fs::remove_dir_all(&dir);
    let out = run(std::path::Path::new("/proc/vpcut-no-such-place"));
    assert_eq!(out.status.code(), Some(2));
}
