//! Pictures that need no GPU, the ones a process engineer reads first (issue 4):
//!
//! - the **developed view**: the deviation field unrolled, angle (x, 0..360 deg left to
//!   right) against z (y, the front of the part at the top), one diverging colour map
//!   (gouge blue, within tolerance neutral grey, leftover red, saturating at the largest
//!   deviation), not-compared dexels dark grey, thin dark lines where the pitch helix of
//!   each turn and start crosses (drawn over neutral pixels only, so they never hide a
//!   deviation), and a colour bar with mm values;
//! - the **axial section**: the machined profile (black) and the ideal profile (blue) along
//!   one generator, r against z, over the band of points within the tolerance of the ideal
//!   surface (pale blue; exact: every pixel whose normal distance to the ideal polyline is at
//!   most the tolerance), with gouged material (blue) and leftover stock (red) filled between
//!   the two profiles where they are further apart than the tolerance.
//!
//! A pixel of the developed view covers a block of dexels; it shows the largest signed normal
//! deviation of the block (as `compare` measures it: distance in the axial plane to the
//! ideal polyline, negative for gouge), so no extreme is lost to the picture's resolution.
//! A block without compared dexels is "not compared". Pure: images are returned, `main.rs`
//! writes them.

use crate::model::stock::{Stock, Surface};
use crate::model::thread::{ColumnIdeal, Side, ThreadSpec};
use image::{Rgb, RgbImage};
use rayon::prelude::*;

/// Neutral (within tolerance).
pub(crate) const NEUTRAL: [u8; 3] = [215, 215, 210];
/// Not compared (outside the drawing's turns).
pub(crate) const OUTSIDE: [u8; 3] = [70, 70, 70];
/// Full gouge colour.
pub(crate) const GOUGE: [u8; 3] = [25, 70, 200];
/// Full leftover colour.
pub(crate) const LEFTOVER: [u8; 3] = [200, 30, 30];
/// Where a tool body cut past its edge (3D model and renders).
pub(crate) const BODY_RUB: [u8; 3] = [160, 40, 200];
const PALE_GOUGE: [u8; 3] = [150, 180, 240];
const PALE_LEFTOVER: [u8; 3] = [245, 160, 150];
const BAND: [u8; 3] = [200, 225, 250];
const INK: [u8; 3] = [20, 20, 20];
const IDEAL: [u8; 3] = [20, 60, 220];
const WHITE: [u8; 3] = [255, 255, 255];

/// Which surface of the stock the thread is on.
fn surface(thread: &ThreadSpec) -> Surface {
    match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    }
}

/// Signed normal deviation of a cut point `(z, r)` from the ideal profile of its generator
/// (negative: gouge), or `None` outside the compared span.
pub fn signed_deviation(thread: &ThreadSpec, ideal: &ColumnIdeal, z: f64, r: f64) -> Option<f64> {
    let (a, b) = ideal.span?;
    if z < a || z > b {
        return None;
    }
    let h_cut = thread.height(r);
    let gap = h_cut - ideal.height_at(z);
    if gap == 0.0 {
        return Some(0.0);
    }
    Some(gap.signum() * ideal.distance(z, h_cut, gap.abs()).0)
}

/// The colour of a deviation `d` (mm) with tolerance `tol`, saturating at `scale`.
pub(crate) fn colour(d: Option<f64>, tol: f64, scale: f64) -> [u8; 3] {
    let Some(d) = d else { return OUTSIDE };
    if d.abs() <= tol {
        return NEUTRAL;
    }
    let t = ((d.abs() - tol) / (scale - tol).max(1e-12)).clamp(0.0, 1.0);
    let (a, b) = if d < 0.0 {
        (PALE_GOUGE, GOUGE)
    } else {
        (PALE_LEFTOVER, LEFTOVER)
    };
    let mix = |k: usize| (a[k] as f64 + t * (b[k] as f64 - a[k] as f64)).round() as u8;
    [mix(0), mix(1), mix(2)]
}

/// The developed view, `width` x `height` pixels of field plus a legend strip on the right.
pub fn developed_view(
    stock: &Stock,
    thread: &ThreadSpec,
    tol: f64,
    width: u32,
    height: u32,
) -> RgbImage {
    let grid = stock.grid;
    let s = surface(thread);
    let Some(q) = stock.surface(s) else {
        return RgbImage::from_pixel(width, height, Rgb(OUTSIDE));
    };
    let q_blank = stock.blank_q(s);
    let sense = s.sense();
    let (w, h) = (width as usize, height as usize);
    let (z_first, z_last) = (grid.z(0), grid.z(grid.n_z - 1));
    // Per pixel column: for every pixel row, the signed deviation of the block's dexel with
    // the largest radial gap, and whether a feature line crosses the row.
    let cols: Vec<Vec<(Option<f64>, bool)>> = (0..w)
        .into_par_iter()
        .map(|px| {
            let i0 = px * grid.n_theta / w;
            let i1 = ((px + 1) * grid.n_theta / w).max(i0 + 1);
            // Each dexel column against its own ideal generator (the walls move with angle).
            let ideals: Vec<ColumnIdeal> = (i0..i1)
                .map(|i| thread.column(grid.theta(i), z_first, z_last))
                .collect();
            let ideal = &ideals[(i1 - i0) / 2];
            let mut out = Vec::with_capacity(h);
            for py in 0..h {
                // Row 0 is the top: the largest z.
                let j1 = grid.n_z - py * grid.n_z / h;
                let j0 = (grid.n_z - (py + 1) * grid.n_z / h).min(j1 - 1);
                // The largest normal deviation of the block; the radial gap bounds the
                // normal distance, so most dexels need no distance query.
                let mut d: Option<f64> = None;
                for (i, col_ideal) in (i0..i1).zip(&ideals) {
                    let col = &q[i * grid.n_z..(i + 1) * grid.n_z];
                    let span = col_ideal.span;
                    for (j, &qj) in col.iter().enumerate().take(j1).skip(j0) {
                        let z = grid.z(j);
                        if !span.is_some_and(|(a, b)| z >= a && z <= b) {
                            continue;
                        }
                        let r = sense * (qj as f64 + q_blank);
                        let best = d.map_or(-1.0, f64::abs);
                        let gap = (thread.height(r) - col_ideal.height_at(z)).abs();
                        if gap <= best {
                            continue;
                        }
                        if let Some(v) = signed_deviation(thread, col_ideal, z, r) {
                            if v.abs() > best {
                                d = Some(v);
                            }
                        }
                    }
                }
                let (za, zb) = (grid.z(j0) - 0.5 * grid.dz, grid.z(j1 - 1) + 0.5 * grid.dz);
                let line = ideal.features.iter().any(|f| f.z >= za && f.z < zb);
                out.push((d, line));
            }
            out
        })
        .collect();
    let scale = cols
        .iter()
        .flatten()
        .filter_map(|c| c.0)
        .fold(2.0 * tol, |m, d| m.max(d.abs()));
    let legend = 170;
    let mut img = RgbImage::from_pixel(width + legend, height.max(220), Rgb(WHITE));
    for (px, col) in cols.iter().enumerate() {
        for (py, &(d, line)) in col.iter().enumerate() {
            // Turn lines never hide a deviation: drawn over neutral pixels only.
            let c = if line && d.is_some_and(|d| d.abs() <= tol) {
                INK
            } else {
                colour(d, tol, scale)
            };
            img.put_pixel(px as u32, py as u32, Rgb(c));
        }
    }
    colour_bar(&mut img, width + 12, 20, 160, tol, scale);
    img
}

/// A vertical colour bar at `(bx, by)`, `bh` pixels high, from `+scale` (leftover, top) to
/// `-scale` (gouge, bottom), with mm labels at the ends, the tolerance and zero, and a unit.
pub(crate) fn colour_bar(img: &mut RgbImage, bx: u32, by: u32, bh: u32, tol: f64, scale: f64) {
    for k in 0..bh {
        let d = scale * (1.0 - 2.0 * (k as f64 + 0.5) / bh as f64);
        for x in bx..bx + 18 {
            img.put_pixel(x, by + k, Rgb(colour(Some(d), tol, scale)));
        }
    }
    // Labels at the ends, at zero and at the tolerance, where they do not overlap.
    let mut drawn: Vec<u32> = Vec::new();
    for v in [scale, -scale, tol, -tol, 0.0] {
        let y = by + ((1.0 - v / scale) * 0.5 * (bh - 1) as f64).round() as u32;
        if drawn.iter().any(|&d| d.abs_diff(y) < 12) {
            continue;
        }
        drawn.push(y);
        for x in bx + 18..bx + 22 {
            img.put_pixel(x, y, Rgb(INK));
        }
        text(img, bx + 25, y.saturating_sub(3), &format!("{v:+.4}"));
    }
    text(img, bx + 25, by + bh + 8, "MM");
}

/// The dexel column nearest to the angle `theta` (rad).
fn generator(stock: &Stock, theta: f64) -> usize {
    let grid = stock.grid;
    ((theta.rem_euclid(std::f64::consts::TAU) / grid.dtheta()).round() as usize) % grid.n_theta
}

/// Machined and ideal radius along the generator at `theta`: `(z, r_cut, r_ideal)` per cell
/// of the grid, `r_ideal` `None` outside the compared span.
pub fn section_profile(
    stock: &Stock,
    thread: &ThreadSpec,
    theta: f64,
) -> Vec<(f64, f64, Option<f64>)> {
    let grid = stock.grid;
    let s = surface(thread);
    let Some(q) = stock.surface(s) else {
        return Vec::new();
    };
    let i = generator(stock, theta);
    let ideal = thread.column(grid.theta(i), grid.z(0), grid.z(grid.n_z - 1));
    let (q_blank, sense) = (stock.blank_q(s), s.sense());
    let col = &q[i * grid.n_z..(i + 1) * grid.n_z];
    col.iter()
        .enumerate()
        .map(|(j, &qj)| {
            let z = grid.z(j);
            let inside = ideal.span.is_some_and(|(a, b)| z >= a && z <= b);
            let r_ideal = inside.then(|| thread.radius(ideal.height_at(z)));
            (z, sense * (qj as f64 + q_blank), r_ideal)
        })
        .collect()
}

/// The axial section at `theta` (rad), `width` x `height` pixels.
pub fn section_view(
    stock: &Stock,
    thread: &ThreadSpec,
    theta: f64,
    tol: f64,
    width: u32,
    height: u32,
) -> RgbImage {
    let prof = section_profile(stock, thread, theta);
    let mut img = RgbImage::from_pixel(width, height, Rgb(WHITE));
    if prof.is_empty() {
        return img;
    }
    let grid = stock.grid;
    let ideal = thread.column(
        grid.theta(generator(stock, theta)),
        grid.z(0),
        grid.z(grid.n_z - 1),
    );
    let (z_lo, z_hi) = (prof[0].0, prof[prof.len() - 1].0);
    let radii = prof
        .iter()
        .flat_map(|p| [Some(p.1), p.2])
        .flatten()
        .chain([thread.root_radius, thread.crest_radius]);
    let (r_lo, r_hi) = radii.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
        (a.min(r), b.max(r))
    });
    let pad = 0.08 * (r_hi - r_lo).max(1e-3);
    let (r_lo, r_hi) = (r_lo - pad, r_hi + pad);
    let (top, bottom) = (14u32, height.saturating_sub(14));
    let y_of =
        |r: f64| (top as f64 + (r_hi - r) / (r_hi - r_lo) * (bottom - top) as f64).round() as i64;
    let z_of = |x: u32| z_lo + (x as f64 + 0.0) / (width - 1) as f64 * (z_hi - z_lo);
    let r_of = |y: u32| r_hi - (y as f64 - top as f64) / (bottom - top) as f64 * (r_hi - r_lo);
    let at = |z: f64| {
        let j = (((z - z_lo) / grid.dz).round().max(0.0) as usize).min(prof.len() - 1);
        prof[j]
    };
    // Tolerance band and the filled deviations, pixel by pixel.
    let rows: Vec<Vec<[u8; 3]>> = (top..bottom)
        .into_par_iter()
        .map(|y| {
            let r = r_of(y);
            (0..width)
                .map(|x| {
                    let z = z_of(x);
                    let (_, r_cut, r_ideal) = at(z);
                    let Some(r_ideal) = r_ideal else { return WHITE };
                    let h = thread.height(r);
                    let near = ideal.distance(z, h, tol * 1.000001).0 <= tol;
                    let between = (r - r_cut) * (r - r_ideal) < 0.0;
                    if between {
                        let d = signed_deviation(thread, &ideal, z, r_cut).unwrap_or(0.0);
                        if d.abs() > tol {
                            return if d < 0.0 { PALE_GOUGE } else { PALE_LEFTOVER };
                        }
                    }
                    if near {
                        BAND
                    } else {
                        WHITE
                    }
                })
                .collect()
        })
        .collect();
    for (k, row) in rows.iter().enumerate() {
        for (x, c) in row.iter().enumerate() {
            img.put_pixel(x as u32, top + k as u32, Rgb(*c));
        }
    }
    // The two profiles as connected polylines (vertical runs join steps).
    let mut draw = |pts: &[(i64, i64)], c: [u8; 3]| {
        for pair in pts.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            for x in x0.min(x1)..=x0.max(x1) {
                for y in y0.min(y1)..=y0.max(y1) {
                    if x >= 0 && y >= 0 && (x as u32) < width && (y as u32) < height {
                        img.put_pixel(x as u32, y as u32, Rgb(c));
                    }
                }
            }
        }
    };
    let ideal_pts: Vec<(i64, i64)> = (0..width)
        .filter_map(|x| at(z_of(x)).2.map(|r| (x as i64, y_of(r))))
        .collect();
    draw(&ideal_pts, IDEAL);
    let cut_pts: Vec<(i64, i64)> = (0..width)
        .map(|x| (x as i64, y_of(at(z_of(x)).1)))
        .collect();
    draw(&cut_pts, INK);
    text(
        &mut img,
        4,
        2,
        &format!(
            "Z {z_lo:.3} TO {z_hi:.3} MM  R {r_lo:.3} TO {r_hi:.3} MM  ANGLE {:.1}",
            theta.to_degrees()
        ),
    );
    img
}

/// A 3x5 pixel font (drawn 2x) for legends and captions: digits, capitals (lower case is
/// drawn as upper case) and `+ - . : / _ ( ) = %`.
fn glyph(c: char) -> [u8; 5] {
    match c.to_ascii_uppercase() {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '+' => [0, 2, 7, 2, 0],
        '-' => [0, 0, 7, 0, 0],
        '.' => [0, 0, 0, 0, 2],
        ':' => [0, 2, 0, 2, 0],
        '/' => [1, 1, 2, 4, 4],
        '_' => [0, 0, 0, 0, 7],
        '(' => [2, 4, 4, 4, 2],
        ')' => [2, 1, 1, 1, 2],
        '=' => [0, 7, 0, 7, 0],
        '%' => [5, 1, 2, 4, 5],
        'A' => [2, 5, 7, 5, 5],
        'B' => [6, 5, 6, 5, 6],
        'C' => [7, 4, 4, 4, 7],
        'D' => [6, 5, 5, 5, 6],
        'E' => [7, 4, 6, 4, 7],
        'F' => [7, 4, 6, 4, 4],
        'G' => [7, 4, 5, 5, 7],
        'H' => [5, 5, 7, 5, 5],
        'I' => [7, 2, 2, 2, 7],
        'J' => [1, 1, 1, 5, 7],
        'K' => [5, 5, 6, 5, 5],
        'L' => [4, 4, 4, 4, 7],
        'M' => [5, 7, 7, 5, 5],
        'N' => [7, 5, 5, 5, 5],
        'O' => [7, 5, 5, 5, 7],
        'P' => [7, 5, 7, 4, 4],
        'Q' => [7, 5, 5, 7, 1],
        'R' => [6, 5, 6, 5, 5],
        'S' => [7, 4, 7, 1, 7],
        'T' => [7, 2, 2, 2, 2],
        'U' => [5, 5, 5, 5, 7],
        'V' => [5, 5, 5, 5, 2],
        'W' => [5, 5, 7, 7, 5],
        'X' => [5, 5, 2, 5, 5],
        'Y' => [5, 5, 2, 2, 2],
        'Z' => [7, 1, 2, 4, 7],
        _ => [0; 5],
    }
}

/// Write `s` at `(x, y)` in the 3x5 font, twice the size.
pub(crate) fn text(img: &mut RgbImage, x: u32, y: u32, s: &str) {
    for (k, c) in s.chars().enumerate() {
        let g = glyph(c);
        for (row, bits) in g.iter().enumerate() {
            for col in 0..3u32 {
                if bits & (4 >> col) != 0 {
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let px = x + k as u32 * 8 + col * 2 + dx;
                        let py = y + row as u32 * 2 + dy;
                        if px < img.width() && py < img.height() {
                            img.put_pixel(px, py, Rgb(INK));
                        }
                    }
                }
            }
        }
    }
}
