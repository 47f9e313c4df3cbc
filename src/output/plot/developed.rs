//! The developed view: the deviation field unrolled over the compared span, angle on the
//! part (x, 0..360 deg) against z (y, +z up), in tolerance bands, with the pitch-helix
//! crossings as thin lines, turn numbers on the right, the worst gouge and leftover ringed,
//! axes with units, a title and a legend.
//!
//! A pixel covers a block of dexels and shows the largest signed deviation of the block as
//! the report's comparison counts it ([`column_deviation`]: the normal distance, a root or
//! crest off all across at its radial size), so no extreme is lost to the picture's
//! resolution and the worst pixel is the report's worst value.

use super::chart::{
    band_colour, legend_column, mm, picture, rgb, text_px, Swatch, BAND_EDGES, GOUGE_BANDS,
    LEFTOVER_BANDS, NOT_COMPARED, WITHIN,
};
use crate::analysis::compare::{column_deviation, Deviation, Extreme};
use crate::model::stock::Stock;
use crate::model::thread::{ColumnIdeal, ThreadSpec};
use image::RgbImage;
use plotters::prelude::*;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Colour of the pitch-helix (turn) lines over within-tolerance pixels.
const TURN_LINE: [u8; 3] = [90, 90, 90];

/// The developed view and where its field lies in the picture.
#[derive(Clone, Debug)]
pub struct DevelopedPlot {
    /// The picture.
    pub image: RgbImage,
    /// The field's pixels: `x0..x1` (0 deg at `x0`, 360 deg at `x1`) and `y0..y1` (`z_max`
    /// at `y0`, `z_min` at `y1`).
    pub field: [u32; 4],
    /// The z span shown (mm): the compared span of every generator together.
    pub z: (f64, f64),
    /// The worst gouge and the worst leftover beyond the tolerance, ringed: the signed
    /// value (mm; the comparison's, so the report's) and the pixel of its dexel.
    pub worst: [Option<(f64, [u32; 2])>; 2],
    /// The largest gouge (negative) and leftover any pixel of the field shows (mm): the
    /// deviations the colours stand for.
    pub shown: [Option<f64>; 2],
    /// The turn labels on the right edge: `(turn, start, z)`, start 1-based, at the centre
    /// of each turn's groove on the last generator (towards 360 deg) where the turn has
    /// one in the field: the 360 deg generator for every whole turn, an earlier one (with a
    /// dotted leader to it) for a turn that ends before it. Labels that would overlap one
    /// already drawn are left out.
    pub turn_labels: Vec<(i64, u32, f64)>,
}

/// The z span compared on any generator (the union of the columns' spans), or the grid.
fn compared_span(stock: &Stock, thread: &ThreadSpec) -> (f64, f64) {
    let grid = stock.grid;
    let (z_first, z_last) = (grid.z(0), grid.z(grid.n_z - 1));
    let step = (grid.n_theta / 360).max(1);
    let span = (0..grid.n_theta)
        .step_by(step)
        .filter_map(|i| thread.column(grid.theta(i), z_first, z_last).span)
        .fold(None, |acc: Option<(f64, f64)>, (a, b)| {
            Some(acc.map_or((a, b), |(x, y)| (x.min(a), y.max(b))))
        });
    let (a, b) = span.unwrap_or((z_first, z_last));
    (
        (a - 0.5 * grid.dz).max(z_first - 0.5 * grid.dz),
        (b + 0.5 * grid.dz).min(z_last + 0.5 * grid.dz),
    )
}

/// Where each turn of the drawing is labelled: `(turn, start, z, theta)`, the centre of its
/// groove on the last generator towards 360 deg where that centre lies in the field
/// `z_lo..z_hi` (the 360 deg one for a whole turn), ordered from the largest z down.
/// Generators are tried from 360 deg down, 720 of them at most.
pub(crate) fn turn_places(
    stock: &Stock,
    thread: &ThreadSpec,
    (z_lo, z_hi): (f64, f64),
) -> Vec<(i64, u32, f64, f64)> {
    let grid = stock.grid;
    let (z_first, z_last) = (grid.z(0), grid.z(grid.n_z - 1));
    let n = grid.n_theta;
    let step = n.div_ceil(720).max(1);
    let mut out: Vec<(i64, u32, f64, f64)> = Vec::new();
    let last = n - 1;
    let mut i = last as isize;
    while i >= 0 {
        let theta = grid.theta(i as usize);
        let ideal = thread.column(theta, z_first, z_last);
        for g in &ideal.grooves {
            let mid = 0.5 * (g.z_lo + g.z_hi);
            let inside =
                mid >= z_lo && mid <= z_hi && ideal.span.is_some_and(|(a, b)| mid >= a && mid <= b);
            if inside && !out.iter().any(|o| (o.0, o.1) == (g.turn, g.start)) {
                // The 360 deg generator's place is at the field's right edge.
                let at = if i as usize == last { TAU } else { theta };
                out.push((g.turn, g.start, mid, at));
            }
        }
        i -= step as isize;
    }
    out.sort_by(|a, b| b.2.total_cmp(&a.2));
    out
}

/// Per pixel column of a `w` x `h` field over `z_lo..z_hi`: for every row (top = largest z)
/// the block's largest signed deviation and whether a pitch-helix crossing lies in it.
#[allow(clippy::type_complexity)]
fn field(
    stock: &Stock,
    thread: &ThreadSpec,
    w: usize,
    h: usize,
    (z_lo, z_hi): (f64, f64),
) -> Option<Vec<Vec<(Option<f64>, bool)>>> {
    let grid = stock.grid;
    stock.surface(super::surface(thread))?;
    let (z_first, z_last) = (grid.z(0), grid.z(grid.n_z - 1));
    let j_of = |z: f64| (((z - z_first) / grid.dz).round().max(0.0) as usize).min(grid.n_z);
    let (ja, jb) = (
        j_of(z_lo + 0.5 * grid.dz),
        j_of(z_hi + 0.5 * grid.dz).max(1),
    );
    let ja = ja.min(jb - 1);
    let n = jb - ja;
    Some(
        (0..w)
            .into_par_iter()
            .map(|px| {
                let i0 = px * grid.n_theta / w;
                let i1 = ((px + 1) * grid.n_theta / w).max(i0 + 1);
                let ideal: ColumnIdeal = thread.column(grid.theta((i0 + i1) / 2), z_first, z_last);
                let cols: Vec<Vec<Option<f64>>> = (i0..i1)
                    .map(|i| column_deviation(stock, thread, i))
                    .collect();
                let mut out = Vec::with_capacity(h);
                for py in 0..h {
                    let j1 = ja + n - py * n / h;
                    let j0 = (ja + n - (py + 1) * n / h).min(j1 - 1);
                    let mut d: Option<f64> = None;
                    for col in &cols {
                        for v in col.iter().take(j1).skip(j0).flatten() {
                            if d.is_none_or(|b| v.abs() > b.abs()) {
                                d = Some(*v);
                            }
                        }
                    }
                    let (za, zb) = (grid.z(j0) - 0.5 * grid.dz, grid.z(j1 - 1) + 0.5 * grid.dz);
                    let line = ideal.features.iter().any(|f| f.z >= za && f.z < zb);
                    out.push((d, line));
                }
                out
            })
            .collect(),
    )
}

/// The developed view as a `width` x `height` picture titled `title` (the job and its
/// verdict), with its field's place. See the module doc.
pub fn developed_plot(
    stock: &Stock,
    thread: &ThreadSpec,
    dev: &Deviation,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> DevelopedPlot {
    let px = text_px(width, height);
    let (z_lo, z_hi) = compared_span(stock, thread);
    let mut field_px = [0u32; 4];
    let mut worst = [None, None];
    let mut shown: [Option<f64>; 2] = [None, None];
    let mut labels = Vec::new();
    let image = picture(width, height, |root| {
        root.fill(&WHITE)?;
        let title_h = (px * 2.4) as u32;
        let (top, body) = root.split_vertically(title_h);
        top.draw(&Text::new(
            format!("{title} \u{2014} developed view: deviation from the ideal, unrolled"),
            ((px * 0.8) as i32, (px * 0.6) as i32),
            ("sans-serif", px * 1.3).into_font().color(&BLACK),
        ))?;
        let legend_w = (px * 17.0) as u32;
        let (left, right) = body.split_horizontally(width.saturating_sub(legend_w));
        let mut chart = ChartBuilder::on(&left)
            .margin((px * 0.6) as u32)
            .x_label_area_size((px * 3.2) as u32)
            .y_label_area_size((px * 5.5) as u32)
            .margin_right((px * if thread.starts > 1 { 4.5 } else { 3.5 }) as u32)
            .build_cartesian_2d(0f64..360f64, z_lo..z_hi)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(9)
            .y_labels(10)
            .x_desc("angle on the part [deg]  (0\u{b0} = the spindle's zero)")
            .y_desc("z [mm]   (+z \u{2191})")
            .label_style(("sans-serif", px))
            .axis_desc_style(("sans-serif", px))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.1}"))
            .draw()?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let (fw, fh) = ((xr.end - xr.start).max(1), (yr.end - yr.start).max(1));
        field_px = [
            xr.start as u32,
            yr.start as u32,
            xr.end as u32,
            yr.end as u32,
        ];
        let cols = field(stock, thread, fw as usize, fh as usize, (z_lo, z_hi))
            .unwrap_or_else(|| vec![vec![(None, false); fh as usize]; fw as usize]);
        for d in cols.iter().flatten().filter_map(|c| c.0) {
            let k = usize::from(d > 0.0);
            if d != 0.0 && shown[k].is_none_or(|s: f64| d.abs() > s.abs()) {
                shown[k] = Some(d);
            }
        }
        for (x, col) in cols.iter().enumerate() {
            let within = |y: usize| col[y].0.is_some_and(|d| d.abs() <= tol);
            for (y, &(d, line)) in col.iter().enumerate() {
                let mut c = if line && within(y) {
                    TURN_LINE
                } else {
                    band_colour(d, tol)
                };
                // A band one pixel high (a 0.1 mm rub on a 100 mm part) is widened onto its
                // within-tolerance neighbours above and below, so it is never a hairline.
                if within(y) {
                    let out = |k: usize| !within(k) && col[k].0.is_some();
                    let thin = |k: usize| {
                        out(k) && (k == 0 || !out(k - 1)) && (k + 1 == col.len() || !out(k + 1))
                    };
                    if let Some(k) = [y.checked_sub(1), Some(y + 1)]
                        .into_iter()
                        .flatten()
                        .find(|&k| k < col.len() && thin(k))
                    {
                        c = band_colour(col[k].0, tol);
                    }
                }
                root.draw_pixel((xr.start + x as i32, yr.start + y as i32), &rgb(c))?;
            }
        }
        // The worst places ringed, so a narrow band is found at a glance: the comparison's
        // extremes (the report's values and places; a pixel's own normal distance can
        // differ, e.g. a root short all across is reported at its radial size).
        let at = |e: &Extreme| {
            let x = (e.theta.to_degrees().rem_euclid(360.0) / 360.0 * fw as f64).floor();
            let y = ((z_hi - e.z) / (z_hi - z_lo) * fh as f64).floor();
            [
                xr.start as u32 + (x as u32).min(fw as u32 - 1),
                yr.start as u32 + (y.max(0.0) as u32).min(fh as u32 - 1),
            ]
        };
        let beyond = |e: Option<Extreme>| e.filter(|e| e.value > tol);
        worst = [
            beyond(dev.max_gouge()).map(|e| (-e.value, at(&e))),
            beyond(dev.max_leftover()).map(|e| (e.value, at(&e))),
        ];
        let ring = (px * 1.1) as i32;
        for (w, c) in worst.iter().zip([GOUGE_BANDS[2], LEFTOVER_BANDS[2]]) {
            if let Some((_, [x, y])) = *w {
                let (x, y) = (x as i32, y as i32);
                root.draw(&Circle::new((x, y), ring, rgb(c).stroke_width(3)))?;
                root.draw(&Circle::new((x, y), ring + 3, WHITE.stroke_width(1)))?;
            }
        }
        // Turn numbers on the right: every turn of the drawing (the report's turn rows), at
        // the centre of its groove on the last generator towards 360 deg where it has one in
        // the field, with the turn (and start) the comparison files its dexels under. A
        // turn that ends before 360 deg (a part turn) gets a dotted leader from there.
        let multi = thread.starts > 1;
        let style = ("sans-serif", px * if multi { 0.75 } else { 0.9 })
            .into_font()
            .color(&BLACK);
        let y_of = |z: f64| yr.start as f64 + (z_hi - z) / (z_hi - z_lo) * fh as f64;
        let gap = px * if multi { 0.95 } else { 1.1 };
        let mut placed: Vec<f64> = Vec::new();
        for (turn, start, mid, theta) in turn_places(stock, thread, (z_lo, z_hi)) {
            let y = y_of(mid);
            if placed.iter().any(|p| (y - p).abs() < gap) {
                continue;
            }
            placed.push(y);
            labels.push((turn, start + 1, mid));
            let x = xr.start as f64 + theta.to_degrees() / 360.0 * fw as f64;
            if x < xr.end as f64 - 2.0 {
                let mut k = x.ceil() as i32;
                while k < xr.end {
                    root.draw_pixel((k, y as i32), &BLACK)?;
                    k += 3;
                }
            }
            let text = if multi {
                format!("T{turn} s{}", start + 1)
            } else {
                format!("T{turn}")
            };
            root.draw(&Text::new(
                text,
                (xr.end + (px * 0.4) as i32, (y - px * 0.45) as i32),
                style.clone(),
            ))?;
        }
        root.draw(&Text::new(
            if multi { "turn, start" } else { "turn" },
            (xr.end + (px * 0.2) as i32, yr.start - (px * 1.3) as i32),
            style.clone(),
        ))?;
        // The legend: the bands with their mm limits, the lines and rings, the worst values.
        let t = |k: f64| mm(k * tol, tol / 10.0);
        let mut items = vec![
            (
                Swatch::Fill(LEFTOVER_BANDS[2]),
                format!("leftover > {}x tol (> {} mm)", BAND_EDGES[2], t(5.0)),
            ),
            (
                Swatch::Fill(LEFTOVER_BANDS[1]),
                format!("leftover 2-5x tol ({}..{})", t(2.0), t(5.0)),
            ),
            (
                Swatch::Fill(LEFTOVER_BANDS[0]),
                format!("leftover 1-2x tol ({}..{})", t(1.0), t(2.0)),
            ),
            (
                Swatch::Fill(WITHIN),
                format!("within \u{b1}tol (\u{b1}{} mm)", t(1.0)),
            ),
            (
                Swatch::Fill(GOUGE_BANDS[0]),
                format!("gouge 1-2x tol ({}..{})", t(1.0), t(2.0)),
            ),
            (
                Swatch::Fill(GOUGE_BANDS[1]),
                format!("gouge 2-5x tol ({}..{})", t(2.0), t(5.0)),
            ),
            (
                Swatch::Fill(GOUGE_BANDS[2]),
                format!("gouge > 5x tol (> {} mm)", t(5.0)),
            ),
            (Swatch::Fill(NOT_COMPARED), "not compared".to_string()),
            (
                Swatch::Line(TURN_LINE),
                "pitch helix (turn line)".to_string(),
            ),
        ];
        if let Some((d, _)) = worst[0] {
            items.push((
                Swatch::Ring(GOUGE_BANDS[2]),
                format!("worst gouge {d:+.3} mm ({:.1}x)", d.abs() / tol),
            ));
        }
        if let Some((d, _)) = worst[1] {
            items.push((
                Swatch::Ring(LEFTOVER_BANDS[2]),
                format!("worst leftover {d:+.3} mm ({:.1}x)", d.abs() / tol),
            ));
        }
        let lx = (px * 0.5) as i32;
        let y = legend_column(&right, lx, (px * 1.5) as i32, px * 0.85, &items)?;
        let note = ("sans-serif", px * 0.8).into_font().color(&BLACK);
        for (k, line) in [
            "the report's deviation: the",
            "normal distance in the axial",
            "plane (a root or crest off",
            "all across: its radial size);",
            "a pixel shows the largest",
            "of its dexels; 1-pixel",
            "bands drawn 3 high",
        ]
        .iter()
        .enumerate()
        {
            right.draw(&Text::new(
                *line,
                (lx, y + (px * 0.5) as i32 + k as i32 * (px * 1.1) as i32),
                note.clone(),
            ))?;
        }
        Ok(())
    });
    DevelopedPlot {
        image,
        field: field_px,
        z: (z_lo, z_hi),
        worst,
        shown,
        turn_labels: labels,
    }
}

/// The developed view as a `width` x `height` picture (see [`developed_plot`]).
pub fn developed_view(
    stock: &Stock,
    thread: &ThreadSpec,
    dev: &Deviation,
    tol: f64,
    width: u32,
    height: u32,
    title: &str,
) -> RgbImage {
    developed_plot(stock, thread, dev, tol, width, height, title).image
}
