//! The axial section (machined and ideal profile along one generator, r against z, over the
//! tolerance band, gouge and leftover filled between them, the radial exaggeration stated)
//! and the deviation trace (signed deviation against z along four generators, with the
//! tolerance lines, so deviations under the tolerance can be seen, and the report's worst
//! gouge and leftover marked where they lie on a traced generator).
//!
//! Both take the deviation of each cell from the report's comparison
//! ([`column_deviation`]: the normal distance, or a root or crest off all across at its
//! radial size), so a value read off them is the report's.

use super::chart::{legend_row, mm, picture, rgb, text_px, Swatch, GOUGE_BANDS, LEFTOVER_BANDS};
use super::{generator, section_profile, IDEAL_COLOUR};
use crate::analysis::compare::{column_deviation, Deviation, Extreme};
use crate::model::stock::Stock;
use crate::model::thread::ThreadSpec;
use image::RgbImage;
use plotters::prelude::*;
use rayon::prelude::*;

/// The tolerance band around the ideal (a pale shade of the ideal's colour).
const BAND: [u8; 3] = [200, 236, 232];
/// The machined profile.
const MACHINED: [u8; 3] = [20, 20, 20];
/// Colours of the trace's generators.
const TRACES: [[u8; 3]; 4] = [[20, 20, 20], [200, 90, 0], [0, 120, 200], [150, 60, 170]];

/// The axial section at `theta` (rad), `width` x `height` pixels, titled `title`.
pub fn section_view(
    stock: &Stock,
    thread: &ThreadSpec,
    theta: f64,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> RgbImage {
    let prof = section_profile(stock, thread, theta);
    let px = text_px(width, height);
    let grid = stock.grid;
    let i = generator(stock, theta);
    let ideal = thread.column(grid.theta(i), grid.z(0), grid.z(grid.n_z - 1));
    let cells = column_deviation(stock, thread, i);
    picture(width, height, |root| {
        root.fill(&WHITE)?;
        if prof.is_empty() {
            return Ok(());
        }
        let (z0, z1) = (prof[0].0, prof[prof.len() - 1].0);
        let (z_lo, z_hi) = ideal.span.map_or((z0, z1), |(a, b)| {
            let pad = 0.02 * (b - a);
            ((a - pad).max(z0), (b + pad).min(z1))
        });
        let radii = prof
            .iter()
            .filter(|p| p.0 >= z_lo && p.0 <= z_hi)
            .flat_map(|p| [Some(p.1), p.2])
            .flatten()
            .chain([thread.root_radius, thread.crest_radius]);
        let (r_lo, r_hi) = radii.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r), b.max(r))
        });
        let pad = 0.08 * (r_hi - r_lo).max(1e-3);
        let (r_lo, r_hi) = (r_lo - pad, r_hi + pad);
        let title_h = (px * 4.4) as u32;
        let (top, body) = root.split_vertically(title_h);
        top.draw(&Text::new(
            format!(
                "{title} \u{2014} axial section at {:.1}\u{b0}",
                grid.theta(i).to_degrees()
            ),
            ((px * 0.8) as i32, (px * 0.6) as i32),
            ("sans-serif", px * 1.3).into_font().color(&BLACK),
        ))?;
        let mut chart = ChartBuilder::on(&body)
            .margin((px * 0.6) as u32)
            .x_label_area_size((px * 3.2) as u32)
            .y_label_area_size((px * 5.5) as u32)
            .build_cartesian_2d(z_lo..z_hi, r_lo..r_hi)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(12)
            .y_labels(6)
            .x_desc("z [mm]   (+z \u{2192})")
            .y_desc("r [mm]")
            .label_style(("sans-serif", px))
            .axis_desc_style(("sans-serif", px))
            .y_label_formatter(&|v| format!("{v:.2}"))
            .draw()?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let (fw, fh) = ((xr.end - xr.start).max(1), (yr.end - yr.start).max(1));
        let z_of = |x: i32| z_lo + (x as f64 + 0.5) / fw as f64 * (z_hi - z_lo);
        let r_of = |y: i32| r_hi - (y as f64 + 0.5) / fh as f64 * (r_hi - r_lo);
        let cell = |z: f64| (((z - z0) / grid.dz).round().max(0.0) as usize).min(prof.len() - 1);
        let at = |z: f64| prof[cell(z)];
        // The band and the fills, pixel by pixel.
        let rows: Vec<Vec<Option<[u8; 3]>>> = (0..fh)
            .into_par_iter()
            .map(|y| {
                let r = r_of(y);
                (0..fw)
                    .map(|x| {
                        let z = z_of(x);
                        let (_, r_cut, r_ideal) = at(z);
                        let r_ideal = r_ideal?;
                        let between = (r - r_cut) * (r - r_ideal) < 0.0;
                        if between {
                            let d = cells.get(cell(z)).copied().flatten().unwrap_or(0.0);
                            if d.abs() > tol {
                                return Some(if d < 0.0 {
                                    GOUGE_BANDS[0]
                                } else {
                                    LEFTOVER_BANDS[0]
                                });
                            }
                        }
                        let h = thread.height(r);
                        (ideal.distance(z, h, tol * 1.000001).0 <= tol).then_some(BAND)
                    })
                    .collect()
            })
            .collect();
        for (y, row) in rows.iter().enumerate() {
            for (x, c) in row.iter().enumerate() {
                if let Some(c) = c {
                    root.draw_pixel((xr.start + x as i32, yr.start + y as i32), &rgb(*c))?;
                }
            }
        }
        let lw = ((px / 8.0).round() as u32).max(1);
        let inside = |p: &&(f64, f64, Option<f64>)| p.0 >= z_lo && p.0 <= z_hi;
        // Steps drawn as steps: each cell's value held over the cell.
        let stepped = |v: Vec<(f64, f64)>| {
            let mut out = Vec::with_capacity(2 * v.len());
            for (k, &(z, r)) in v.iter().enumerate() {
                if k > 0 {
                    out.push((z - 0.5 * grid.dz, v[k - 1].1));
                    out.push((z - 0.5 * grid.dz, r));
                } else {
                    out.push((z, r));
                }
            }
            out
        };
        let ideal_pts: Vec<(f64, f64)> = prof
            .iter()
            .filter(inside)
            .filter_map(|p| p.2.map(|r| (p.0, r)))
            .collect();
        chart.draw_series(LineSeries::new(
            ideal_pts,
            rgb(IDEAL_COLOUR).stroke_width(lw + 1),
        ))?;
        let cut_pts: Vec<(f64, f64)> = prof.iter().filter(inside).map(|p| (p.0, p.1)).collect();
        chart.draw_series(LineSeries::new(
            stepped(cut_pts),
            rgb(MACHINED).stroke_width(lw),
        ))?;
        // The legend and the scale, above the field.
        let exaggeration = (fh as f64 / (r_hi - r_lo)) / (fw as f64 / (z_hi - z_lo)).max(1e-12);
        let items = [
            (Swatch::Line(MACHINED), "machined".to_string()),
            (Swatch::Line(IDEAL_COLOUR), "ideal".to_string()),
            (
                Swatch::Fill(BAND),
                format!("tolerance band \u{b1}{} mm", mm(tol, tol / 10.0)),
            ),
            (Swatch::Fill(GOUGE_BANDS[0]), "gouge > tol".to_string()),
            (
                Swatch::Fill(LEFTOVER_BANDS[0]),
                "leftover > tol".to_string(),
            ),
        ];
        let (lx, ly) = ((px * 0.8) as i32, (px * 2.6) as i32);
        let x = legend_row(root, lx, ly, px * 0.9, &items)?;
        root.draw(&Text::new(
            format!("radial scale {exaggeration:.1}x the axial"),
            (x, ly - (px * 0.1) as i32),
            ("sans-serif", px * 0.9).into_font().color(&BLACK),
        ))?;
        Ok(())
    })
}

/// Signed deviation (mm) per cell along the generator at `theta` over its compared span,
/// as the report's comparison counts it: `(z, d)`.
pub(crate) fn trace(stock: &Stock, thread: &ThreadSpec, theta: f64) -> Vec<(f64, f64)> {
    let grid = stock.grid;
    let i = generator(stock, theta);
    column_deviation(stock, thread, i)
        .iter()
        .enumerate()
        .filter_map(|(j, d)| d.map(|d| (grid.z(j), d)))
        .collect()
}

/// The report's worst gouge or leftover as the trace marks it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceMark {
    /// The signed value (mm, negative: gouge): the comparison's extreme, the report's.
    pub value: f64,
    /// Its axial position (mm).
    pub z: f64,
    /// Its angle on the part (deg, 0..360).
    pub angle_deg: f64,
    /// The traced generator it lies on (index into [`TracePlot::generators`]), and the
    /// pixel of its mark; `None` when it lies on none of them (the legend still says it).
    pub on: Option<(usize, [u32; 2])>,
}

/// The deviation trace and what it shows.
#[derive(Clone, Debug)]
pub struct TracePlot {
    /// The picture.
    pub image: RgbImage,
    /// The field's pixels `[x0, y0, x1, y1]` (z from `z.0` at `x0` to `z.1` at `x1`, the
    /// deviation from `d.1` at `y0` down to `d.0` at `y1`).
    pub field: [u32; 4],
    /// The z span shown (mm).
    pub z: (f64, f64),
    /// The deviation span shown (mm).
    pub d: (f64, f64),
    /// The traced generators' angles (deg), as their legend names them.
    pub generators: Vec<f64>,
    /// The curves as drawn, one per generator: `(z, deviation)` per compared cell (mm).
    pub curves: Vec<Vec<(f64, f64)>>,
    /// The report's worst gouge and worst leftover beyond the tolerance.
    pub worst: [Option<TraceMark>; 2],
}

/// The deviation trace, `width` x `height` pixels, titled `title` (see [`trace_plot`]).
#[allow(clippy::too_many_arguments)]
pub fn trace_view(
    stock: &Stock,
    thread: &ThreadSpec,
    dev: &Deviation,
    theta: f64,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> RgbImage {
    trace_plot(stock, thread, dev, theta, tol, width, height, title).image
}

/// The deviation trace, `width` x `height` pixels, titled `title`: the signed deviation
/// against z along the generators at `theta`, +90, +180 and +270 deg, with the tolerance
/// lines; the vertical scale is at least three tolerances either way. The report's worst
/// gouge and leftover beyond the tolerance (`dev`'s extremes) are ringed on the generator
/// they lie on, with their value, turn and place in the legend.
#[allow(clippy::too_many_arguments)]
pub fn trace_plot(
    stock: &Stock,
    thread: &ThreadSpec,
    dev: &Deviation,
    theta: f64,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> TracePlot {
    let px = text_px(width, height);
    let grid = stock.grid;
    let columns: Vec<usize> = (0..4)
        .map(|k| generator(stock, theta + k as f64 * std::f64::consts::FRAC_PI_2))
        .collect();
    let lines: Vec<(f64, Vec<(f64, f64)>)> = columns
        .iter()
        .map(|&i| {
            let t = grid.theta(i);
            (t.to_degrees().rem_euclid(360.0), trace(stock, thread, t))
        })
        .collect();
    let extremes = [
        dev.max_gouge()
            .filter(|e| e.value > tol)
            .map(|e| (-e.value, e)),
        dev.max_leftover()
            .filter(|e| e.value > tol)
            .map(|e| (e.value, e)),
    ];
    let mut field = [0u32; 4];
    let mut spans = ((0.0, 0.0), (0.0, 0.0));
    let mut worst: [Option<TraceMark>; 2] = [None, None];
    let image = picture(width, height, |root| {
        root.fill(&WHITE)?;
        let all = lines.iter().flat_map(|l| l.1.iter());
        let (z_lo, z_hi) = all
            .clone()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
        if !z_lo.is_finite() {
            return Ok(());
        }
        let d_max = all.fold(3.0 * tol, |m, p| m.max(p.1.abs())) * 1.1;
        let z_hi = z_hi.max(z_lo + 1e-6);
        spans = ((z_lo, z_hi), (-d_max, d_max));
        // A second legend row for the report's worst places.
        let marks = extremes.iter().any(Option::is_some);
        let title_h = (px * if marks { 5.7 } else { 4.4 }) as u32;
        let (top, body) = root.split_vertically(title_h);
        top.draw(&Text::new(
            format!("{title} \u{2014} deviation along z (+ leftover, \u{2212} gouge)"),
            ((px * 0.8) as i32, (px * 0.6) as i32),
            ("sans-serif", px * 1.3).into_font().color(&BLACK),
        ))?;
        let mut chart = ChartBuilder::on(&body)
            .margin((px * 0.6) as u32)
            .x_label_area_size((px * 3.2) as u32)
            .y_label_area_size((px * 6.0) as u32)
            .build_cartesian_2d(z_lo..z_hi, -d_max..d_max)?;
        chart
            .configure_mesh()
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(225, 225, 225))
            .x_labels(12)
            .y_labels(9)
            .x_desc("z [mm]")
            .y_desc("deviation [mm] (normal; a root or crest off all across: radial)")
            .label_style(("sans-serif", px))
            .axis_desc_style(("sans-serif", px * 0.8))
            .y_label_formatter(&|v| mm(*v, d_max / 10.0))
            .draw()?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        field = [
            xr.start as u32,
            yr.start as u32,
            xr.end as u32,
            yr.end as u32,
        ];
        let lw = ((px / 10.0).round() as u32).max(1);
        for s in [-tol, tol] {
            chart.draw_series(LineSeries::new(
                [(z_lo, s), (z_hi, s)],
                rgb(IDEAL_COLOUR).stroke_width(lw + 1),
            ))?;
        }
        chart.draw_series(LineSeries::new(
            [(z_lo, 0.0), (z_hi, 0.0)],
            RGBColor(150, 150, 150).stroke_width(1),
        ))?;
        let mut items = Vec::new();
        for (k, (deg, pts)) in lines.iter().enumerate() {
            let c = TRACES[k % TRACES.len()];
            chart.draw_series(LineSeries::new(
                pts.iter().copied(),
                rgb(c).stroke_width(lw),
            ))?;
            items.push((Swatch::Line(c), format!("{deg:.1}\u{b0}")));
        }
        items.push((
            Swatch::Line(IDEAL_COLOUR),
            format!("\u{b1}tol = \u{b1}{} mm", mm(tol, tol / 10.0)),
        ));
        // The report's worst places: ringed on the generator they lie on.
        let (fw, fh) = ((xr.end - xr.start).max(1), (yr.end - yr.start).max(1));
        let pixel = |z: f64, d: f64| {
            let x = ((z - z_lo) / (z_hi - z_lo) * fw as f64).floor();
            let y = ((d_max - d) / (2.0 * d_max) * fh as f64).floor();
            [
                xr.start as u32 + (x.max(0.0) as u32).min(fw as u32 - 1),
                yr.start as u32 + (y.max(0.0) as u32).min(fh as u32 - 1),
            ]
        };
        let ring = (px * 0.9) as i32;
        let mut marked = Vec::new();
        for (slot, (found, colour, what)) in worst.iter_mut().zip([
            (extremes[0], GOUGE_BANDS[2], "gouge"),
            (extremes[1], LEFTOVER_BANDS[2], "leftover"),
        ]) {
            let Some((value, e)) = found else { continue };
            let column = generator(stock, e.theta);
            let on = columns
                .iter()
                .position(|&c| c == column)
                .map(|k| (k, pixel(e.z, value)));
            let angle_deg = e.theta.to_degrees().rem_euclid(360.0);
            *slot = Some(TraceMark {
                value,
                z: e.z,
                angle_deg,
                on,
            });
            if let Some((_, [x, y])) = on {
                let (x, y) = (x as i32, y as i32);
                root.draw(&Circle::new((x, y), ring, rgb(colour).stroke_width(3)))?;
                root.draw(&Circle::new((x, y), ring + 3, WHITE.stroke_width(1)))?;
            }
            marked.push((
                Swatch::Ring(colour),
                format!(
                    "report's worst {what} {value:+.3} mm: {}, {angle_deg:.1}\u{b0}, z {:.3}{}",
                    place_words(&e),
                    e.z,
                    if on.is_some() { "" } else { " (not traced)" }
                ),
            ));
        }
        legend_row(root, (px * 0.8) as i32, (px * 2.6) as i32, px * 0.9, &items)?;
        legend_row(
            root,
            (px * 0.8) as i32,
            (px * 3.9) as i32,
            px * 0.9,
            &marked,
        )?;
        Ok(())
    });
    TracePlot {
        image,
        field,
        z: spans.0,
        d: spans.1,
        generators: lines.iter().map(|l| l.0).collect(),
        curves: lines.into_iter().map(|l| l.1).collect(),
        worst,
    }
}

/// "turn 7 crest", as the report names an extreme's place.
fn place_words(e: &Extreme) -> String {
    format!("turn {} {}", e.turn, e.flank.name())
}
