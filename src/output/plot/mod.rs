//! Pictures that need no GPU, the ones a process engineer reads first (issues 4 and 18),
//! drawn with plotters in DejaVu Sans (embedded), text sized by the picture:
//!
//! - the **developed view** ([`developed`]): the deviation field unrolled over the compared
//!   span, in tolerance bands (within, 1-2x, 2-5x, over 5x; gouge blue, leftover orange-red);
//! - the **axial section** and the **deviation trace** ([`section`]).
//!
//! Here: the signed deviation they share, the renders' continuous colour map and colour bar
//! (the 3D model's vertex colours) and the renders' 3x5 pixel font. Pure: images are
//! returned, `main.rs` writes them.

pub(crate) mod chart;
pub(crate) mod developed;
pub(crate) mod section;

use crate::model::stock::{Stock, Surface};
use crate::model::thread::{ColumnIdeal, Side, ThreadSpec};
use image::{Rgb, RgbImage};

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
/// The ideal thread, everywhere it is drawn (plots, renders, the .glb): teal, neither the
/// gouge blue nor the leftover red nor the body-rub violet.
pub(crate) const IDEAL_COLOUR: [u8; 3] = [0, 150, 140];
const PALE_GOUGE: [u8; 3] = [150, 180, 240];
const PALE_LEFTOVER: [u8; 3] = [245, 160, 150];
const INK: [u8; 3] = [20, 20, 20];

/// Which surface of the stock the thread is on.
pub(crate) fn surface(thread: &ThreadSpec) -> Surface {
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
pub(crate) fn generator(stock: &Stock, theta: f64) -> usize {
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
