//! The axial section (machined and ideal profile along one generator, r against z, over the
//! tolerance band, gouge and leftover filled between them, the radial exaggeration stated)
//! and the deviation trace (signed normal deviation against z along four generators, with
//! the tolerance lines, so deviations under the tolerance can be seen).

use super::chart::{legend_row, mm, picture, rgb, text_px, Swatch, GOUGE_BANDS, LEFTOVER_BANDS};
use super::{generator, section_profile, signed_deviation, IDEAL_COLOUR};
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
        let at = |z: f64| {
            let j = (((z - z0) / grid.dz).round().max(0.0) as usize).min(prof.len() - 1);
            prof[j]
        };
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
                            let d = signed_deviation(thread, &ideal, z, r_cut).unwrap_or(0.0);
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

/// Signed normal deviation (mm) per cell along the generator at `theta` over its compared
/// span: `(z, d)`.
pub(crate) fn trace(stock: &Stock, thread: &ThreadSpec, theta: f64) -> Vec<(f64, f64)> {
    let grid = stock.grid;
    let i = generator(stock, theta);
    let ideal = thread.column(grid.theta(i), grid.z(0), grid.z(grid.n_z - 1));
    section_profile(stock, thread, theta)
        .iter()
        .filter_map(|&(z, r, ri)| {
            ri?;
            signed_deviation(thread, &ideal, z, r).map(|d| (z, d))
        })
        .collect()
}

/// The deviation trace, `width` x `height` pixels, titled `title`: the signed normal
/// deviation against z along the generators at `theta`, +90, +180 and +270 deg, with the
/// tolerance lines; the vertical scale is at least three tolerances either way.
pub fn trace_view(
    stock: &Stock,
    thread: &ThreadSpec,
    theta: f64,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> RgbImage {
    let px = text_px(width, height);
    let grid = stock.grid;
    let lines: Vec<(f64, Vec<(f64, f64)>)> = (0..4)
        .map(|k| {
            let t = theta + k as f64 * std::f64::consts::FRAC_PI_2;
            let i = generator(stock, t);
            (grid.theta(i).to_degrees(), trace(stock, thread, t))
        })
        .collect();
    picture(width, height, |root| {
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
        let title_h = (px * 4.4) as u32;
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
            .build_cartesian_2d(z_lo..z_hi.max(z_lo + 1e-6), -d_max..d_max)?;
        chart
            .configure_mesh()
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(225, 225, 225))
            .x_labels(12)
            .y_labels(9)
            .x_desc("z [mm]")
            .y_desc("normal deviation [mm]")
            .label_style(("sans-serif", px))
            .axis_desc_style(("sans-serif", px))
            .y_label_formatter(&|v| mm(*v, d_max / 10.0))
            .draw()?;
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
            items.push((Swatch::Line(c), format!("{deg:.0}\u{b0}")));
        }
        items.push((
            Swatch::Line(IDEAL_COLOUR),
            format!("\u{b1}tol = \u{b1}{} mm", mm(tol, tol / 10.0)),
        ));
        legend_row(root, (px * 0.8) as i32, (px * 2.6) as i32, px * 0.9, &items)?;
        Ok(())
    })
}
