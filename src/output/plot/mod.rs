//! Pictures that need no GPU, the ones a process engineer reads first (issues 4 and 18),
//! drawn with plotters in DejaVu Sans (embedded), text sized by the picture:
//!
//! - the **developed view** ([`developed`]): the deviation field unrolled over the compared
//!   span, in tolerance bands (within, 1-2x, 2-5x, over 5x; gouge blue, leftover orange-red);
//! - the **axial section** and the **deviation trace** ([`section`]).
//!
//! Here: the signed deviation they share and the continuous colour map of the 3D model's
//! vertex colours (the renders' colour bar). Pure: images are
//! returned, `main.rs` writes them.

pub(crate) mod chart;
pub(crate) mod developed;
pub(crate) mod section;

use crate::model::stock::{Stock, Surface};
use crate::model::thread::{ColumnIdeal, Side, ThreadSpec};

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
