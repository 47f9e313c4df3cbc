//! Pictures that need no GPU, the ones a process engineer reads first (issues 4 and 18),
//! drawn with plotters in DejaVu Sans (embedded), text sized by the picture:
//!
//! - the **developed view** ([`developed`]): the deviation field unrolled over the compared
//!   span, in tolerance bands (within, 1-2x, 2-5x, over 5x; gouge blue, leftover orange-red);
//! - the **axial section** and the **deviation trace** ([`section`]), by default through the
//!   report's worst deviation ([`section_angle`]).
//!
//! Here: the signed deviation they share and the colours of the 3D model's vertices (the
//! same tolerance bands, with the uncut blank and the cut but not compared surface in
//! their own greys). Pure: images are returned, `main.rs` writes them.

pub(crate) mod chart;
pub(crate) mod developed;
pub(crate) mod section;

use crate::analysis::compare::Deviation;
use crate::model::stock::{Grid, Stock, Surface};
use crate::model::thread::{ColumnIdeal, Side, ThreadSpec};

/// Where a tool body cut past its edge (3D model and renders).
pub(crate) const BODY_RUB: [u8; 3] = [160, 40, 200];
/// The ideal thread, everywhere it is drawn (plots, renders, the .glb): teal, neither the
/// gouge blues nor the leftover oranges nor the body-rub violet.
pub(crate) const IDEAL_COLOUR: [u8; 3] = [0, 150, 140];
/// The blank's own surface where no tool touched it (crests left at the blank's diameter,
/// the stock beyond the thread, the end faces), in the 3D outputs: a darker, warmer grey
/// than the machined "within tolerance" grey, so the cut reads apart from the bar.
pub(crate) const BLANK: [u8; 3] = [158, 152, 142];
/// Cut, but outside the drawing's compared span (run-in, run-out), in the 3D outputs.
pub(crate) const CUT_NOT_COMPARED: [u8; 3] = [190, 192, 196];

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

/// The colour of a point of the 3D outputs' stock surface: the plots' tolerance bands
/// ([`chart::band_colour`]) for a compared point beyond the tolerance or a cut one within
/// it; [`BLANK`] where the tool left the blank's surface (`cut` false) and the point is
/// within tolerance or not compared; [`CUT_NOT_COMPARED`] for a cut outside the span.
pub(crate) fn surface_colour(d: Option<f64>, cut: bool, tol: f64) -> [u8; 3] {
    match d {
        Some(d) if cut || d.abs() > tol => chart::band_colour(Some(d), tol),
        None if cut => CUT_NOT_COMPARED,
        _ => BLANK,
    }
}

/// The dexel column nearest to the angle `theta` (rad).
pub(crate) fn generator(stock: &Stock, theta: f64) -> usize {
    let grid = stock.grid;
    (((theta - grid.theta0).rem_euclid(std::f64::consts::TAU) / grid.dtheta()).round() as usize)
        % grid.n_theta
}

/// The angle (rad) the axial section and the trace show when none is asked for: that of
/// the report's worst deviation beyond the tolerance (the one the close-up shows), so both
/// pictures run through it; 0 when the cut is within the tolerance.
pub fn section_angle(dev: &Deviation, grid: &Grid, tol: f64) -> f64 {
    crate::output::mesh::worst(dev, grid, tol).map_or(0.0, |w| grid.theta(w.2))
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
