//! The tool body behind the cutting edge, swept through the radial dexels.
//!
//! The edge (the rake face, on centre) cuts a column exactly at the revolution `t_c` where
//! the pass crosses the column's angle ([`crate::kernel::sweep`]). The body trails the edge: at
//! relative angle `phi > 0` behind the rake face it meets the same column at `t_c + phi/2pi`,
//! when the tool has moved on along the helix by the travel of that fraction of a turn. So
//! the column sees a sequence of body sections, each placed at the tool's position of its
//! own instant. A radial ray of the column at relative angle `phi` crosses the tool frame at
//! `X = r cos phi` (radial) and `Y = r sin phi` (depth behind the rake face), and every face
//! of the solid is then a linear constraint `A r >= B` on the radius along the ray: the
//! parametric insert's (the section's tip, its two flanks with their clearance and
//! inclination, its back at `Y = thickness`) or a convex mesh's ([`crate::model::solid`]). The first
//! radius inside all of them is where the body meets the ray (external: the smallest;
//! internal: the largest), and the column is cut there ([`ray`]; at `phi = 0` the same is a
//! mesh's edge).
//!
//! **Sampling.** `phi` is sampled evenly up to the body's angular extent. What the body cuts
//! beyond the edge lies between the edge's wall and the section's flank, which moves across
//! the wall at `speed = |dir L/2pi -/+ (r cos(phi) slope + sense r sin(phi) tan a)|` mm per
//! radian (the helical travel at the section's lead `L` against the recession `Y slope` at
//! depth `Y = r sin phi`, and, for a flank sloped at `a`, the ray's falling height above the
//! tip), bounded over the pass's leads, the zone's radii and the flanks that can reach beyond
//! the edge (a mesh: every face with an axial component, in the same terms). A point the continuous body cuts between two samples lies, axially, within
//! `dphi * speed` of the later sample's flank, which cuts everything on its side down to its
//! own tip; the tip rises between samples too, but a point under the rising tip is also
//! within that axial distance of the flank. So the sampled cut is within `dphi * speed` of
//! the continuous body's, and the sample count keeps that under half of
//! [`SAMPLING_ERROR_MM`] (a test checks it against four times the samples).
//!
//! **Tables.** A grid sweep does not place every section at every crossing: on a straight
//! pass the sections' cut beside the edge depends on the crossing only through its lead, so
//! it is tabulated once per bin of revolutions and looked up ([`Tables`], the other half of
//! the bound; a test checks the tables against the sections placed directly). That makes a
//! rubbing body cost about ten planar sweeps instead of hundreds.
//!
//! **Skipped when harmless.** When no section can reach outside what the edge itself cut at
//! the same crossing (the effective clearance stays positive on both flanks over the pass's
//! leads and radii, and the tip clearance is not negative), the body cuts nothing the edge
//! did not and the pass needs no sections: the result is exactly the planar one. Likewise a
//! flank that cannot reach out does not count in the sampling speed.

use crate::model::pass::Pass;
use crate::model::solid::{Face, Solid};
use crate::model::stock::{first_cell, Surface};
use crate::model::tool::{cot, Body, Edge, Tool};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::sync::Arc;

/// Largest distance (mm) between the cut of the sampled body sections and that of the
/// continuous body (the sample count keeps the bound under this).
/// A quarter of the default tolerance (0.02 mm).
pub(crate) const SAMPLING_ERROR_MM: f64 = 0.005;
/// Most sections per pass.
pub(crate) const MAX_SAMPLES: usize = 4096;

/// A body made ready for one pass: the sampled sections and the solid's faces.
#[derive(Clone, Debug)]
pub(crate) struct Sections {
    /// Per sample: `(dt, cos phi, sin phi)` with `dt = phi / 2pi` revolutions after the edge.
    pub(crate) samples: Vec<(f64, f64, f64)>,
    /// The solid's faces in the tool frame (the insert's, or a mesh's).
    faces: Vec<Face>,
    /// What the bands are made from.
    shape: Shape,
    /// The radii the body can meet (mm), and the surface's sense (+1 outer, -1 inner).
    r_zone: (f64, f64),
    sense: f64,
    /// The bound on the error of the sections' cut against the continuous body's (mm): the
    /// angular sampling's and, where the sweep uses [`Tables`], the tables' (see there).
    pub(crate) bound: f64,
    /// The part of `error_mm` left to the angular sampling, and how fast the faces that
    /// count move across the edge's walls (mm).
    phi_error: f64,
    corners: Corners,
    /// The part of `error_mm` left to the tables (mm).
    table_error: f64,
    /// The pass's direction of travel and lead law.
    dir: f64,
    lead_f: f64,
    lead_k: f64,
}

/// The sections' cut beside the edge's, tabulated once for a straight pass instead of
/// being swept anew at every crossing.
///
/// For a pass of constant radius the sections after a crossing at revolution `t` depend on
/// `t` only through the lead `L(t)`: section `phi` stands `dir (L(t) u + K u^2/2)` from the
/// edge's tip, `u = phi/2pi`. So the revolutions are cut into bins, and per bin the
/// sections at the bin's middle lead are applied once to a fine axial table (offsets from
/// the edge's tip centre) over each flank's bands. A crossing in the bin then cuts each
/// cell with the table's nearest entry. Against the sections swept at the crossing itself,
/// each section stands at most `|K| (dt/2) u_max` off axially (the bin's half width) and
/// the nearest entry at most `h/2`: the table's part of the bound, kept under a quarter of
/// the error each. A bin whose sections see smaller leads than the pass's largest moves
/// its flanks slower and uses every k-th sample, still within the sampling's half of the
/// bound. Crossings whose sections would run past the pass's end, and tapered passes, sweep
/// the sections directly.
#[derive(Clone, Debug)]
pub(crate) struct Tables {
    /// Revolutions per bin.
    dt: f64,
    /// Axial spacing of the entries (mm).
    h: f64,
    /// The last crossing (revolutions) whose sections all lie within the pass.
    pub(crate) t_last: f64,
    /// Per bin, the table of each flank (-z, +z) that can reach beyond the edge.
    bins: Vec<[Option<Table>; 2]>,
}

/// The solid behind the edge, as far as the bands need it.
#[derive(Clone, Debug)]
enum Shape {
    /// The parametric insert: tip corners, flank cotangents (`INFINITY` for a vertical
    /// flank), the flanks' recession per mm of depth, and the depth.
    Insert {
        vl: f64,
        vr: f64,
        cl: f64,
        cr: f64,
        slope_l: f64,
        slope_r: f64,
        thickness: f64,
    },
    /// A mesh: its axial extent (a section lies within it), its lowest height `h_min`
    /// above the tip, and the stretch of its edge no higher than that (outside).
    Mesh {
        solid: Arc<Solid>,
        v_lo: f64,
        v_hi: f64,
        h_min: f64,
        flat: Option<(f64, f64)>,
    },
}

/// One flank's table: the offset of entry 0 from the edge's tip centre (mm), and the
/// entries `h` apart (stored values `q - q_blank`, at most 0).
#[derive(Clone, Debug)]
struct Table {
    w0: f64,
    entries: Vec<f32>,
}

/// Most bins per pass, and entries per table (beyond either, the pass sweeps its sections
/// directly): at most 64 MB of tables per pass.
const MAX_BINS: usize = 1024;
const MAX_ENTRIES: usize = 8192;

/// The radii a pass's body can meet on `surface`: from its tip to the blank (`q_blank`).
pub(crate) fn zone(pass: &Pass, q_blank: f64, surface: Surface) -> (f64, f64) {
    let (a, b) = (
        pass.x_start.min(pass.x_end) / 2.0,
        pass.x_start.max(pass.x_end) / 2.0,
    );
    let r_blank = surface.sense() * q_blank;
    match surface {
        Surface::Outer => (a, r_blank.max(b)),
        Surface::Inner => (r_blank.min(a), b),
    }
}

/// The sections of a pass's body for the radii `r_zone` it can meet (tip to blank), or
/// `None` when the tool has no body or the body cannot cut beyond the edge.
pub(crate) fn sections(
    pass: &Pass,
    tool: &Tool,
    r_zone: (f64, f64),
    sense: f64,
) -> Option<Sections> {
    sample(pass, tool, r_zone, sense, SAMPLING_ERROR_MM, false)
}

/// The sections with the sampling error kept under `error_mm`; `force` samples even a body
/// that [`reaches_out`] finds harmless (for the tests that check the skip).
pub(crate) fn sample(
    pass: &Pass,
    tool: &Tool,
    r_zone: (f64, f64),
    sense: f64,
    error_mm: f64,
    force: bool,
) -> Option<Sections> {
    let t_end = pass.revolutions()?;
    let law = pass.helix().law;
    let (r_lo, r_hi) = (r_zone.0.min(r_zone.1).max(1e-3), r_zone.0.max(r_zone.1));
    let leads = [law.lead(0.0), law.lead(t_end)];
    let dir = pass.helix().dir;
    let (faces, shape, phi_max, rates) = match (&tool.edge, tool.body) {
        (
            &Edge::Trapezoid {
                tip,
                left_angle,
                right_angle,
            },
            Some(body),
        ) => {
            // The body's angular extent: the largest phi at which some ray of the zone is
            // still within `thickness` of the rake face.
            let phi_max = (body.thickness / r_lo).min(1.0).asin().min(FRAC_PI_2);
            let tan_flanks = [left_angle.max(0.0).tan(), right_angle.max(0.0).tan()];
            let out = reaches_out(
                &body,
                tan_flanks,
                sense,
                leads,
                law.k,
                pass,
                (r_lo, r_hi),
                phi_max,
            );
            if !force && out == [false, false] {
                return None;
            }
            let (sl, sr) = (body.slope_left(), body.slope_right());
            // Per radian of phi, how fast a flank of the section moves across the edge's
            // wall: the rate of `out_l` and `out_r` (see [`reaches_out`]), `-/+ dir L/2pi -
            // r cos(phi) slope - sense r sin(phi) tan a` with `L` the lead at the section's
            // instant (between the pass's first and last), plus, on a taper, the tip's
            // radial travel along the sloped flank. Linear in `L`, `r cos phi` and
            // `r sin phi` apart, so its largest size is at a corner. Only a flank that can
            // reach beyond the edge's wall counts (a forced body counts both); see the
            // module docs for why the tip's rise does not.
            let taper = taper(pass);
            let counted = if out == [false, false] {
                [true, true]
            } else {
                out
            };
            let rates: Vec<Rate> = [(sl, -dir), (sr, dir)]
                .into_iter()
                .enumerate()
                .filter(|&(f, _)| counted[f])
                .map(|(f, (slope, d))| Rate {
                    l: d / TAU,
                    rc: -slope,
                    rs: -sense * tan_flanks[f],
                    taper: taper / TAU * tan_flanks[f],
                })
                .collect();
            let (vl, vr) = (-tip / 2.0, tip / 2.0);
            let (cl, cr) = (cot(left_angle), cot(right_angle));
            let faces = insert_faces(&body, vl, vr, cl, cr);
            let shape = Shape::Insert {
                vl,
                vr,
                cl,
                cr,
                slope_l: sl,
                slope_r: sr,
                thickness: body.thickness,
            };
            (faces, shape, phi_max, rates)
        }
        (Edge::Mesh { solid, body: true }, _) => {
            let phi_max = (solid.depth / r_lo).min(1.0).asin().min(FRAC_PI_2);
            // Every face with an axial component moves along the axis at fixed radius at
            // `dir L/2pi + (h sense r sin phi - y r cos phi) / v` (the insert's flank rate
            // in a face's terms); faces parallel to the axis (tip, top, back) are covered
            // by the neighbouring samples as the insert's tip is. A mesh is not skipped.
            let taper = taper(pass);
            let rates: Vec<Rate> = solid
                .faces
                .iter()
                .filter(|f| f.v.abs() > 1e-9)
                .map(|f| Rate {
                    l: dir / TAU,
                    rc: -f.y / f.v,
                    rs: f.h * sense / f.v,
                    taper: taper / TAU * (f.h / f.v).abs(),
                })
                .collect();
            let (v_lo, v_hi) = solid
                .vertices
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p[2]), b.max(p[2]))
                });
            let h_min = solid
                .vertices
                .iter()
                .map(|p| p[0])
                .fold(f64::INFINITY, f64::min);
            let flat = (h_min >= 0.0).then(|| solid.span(h_min));
            (
                solid.faces.clone(),
                Shape::Mesh {
                    solid: solid.clone(),
                    v_lo,
                    v_hi,
                    h_min,
                    flat,
                },
                phi_max,
                rates,
            )
        }
        _ => return None,
    };
    let corners = Corners {
        rc: [r_lo * phi_max.cos(), r_hi],
        rs: [0.0, r_hi * phi_max.sin()],
        rates,
    };
    let speed = corners.speed(leads);
    // Half the error to the angular sampling, half to the tables (if the sweep uses them).
    let phi_error = error_mm / 2.0;
    let n = ((phi_max * speed / phi_error).ceil() as usize).clamp(1, MAX_SAMPLES);
    let dphi = phi_max / n as f64;
    let samples = (1..=n)
        .map(|s| {
            let phi = s as f64 * dphi;
            (phi / TAU, phi.cos(), phi.sin())
        })
        .collect();
    Some(Sections {
        samples,
        faces,
        shape,
        r_zone: (r_lo, r_hi),
        sense,
        bound: dphi * speed + error_mm / 2.0,
        phi_error,
        corners,
        table_error: error_mm / 2.0,
        dir,
        lead_f: law.f,
        lead_k: law.k,
    })
}

/// How fast (mm per radian of `phi`) a face of the section moves across the edge's wall
/// along the axis, linear in the section's lead `L`, `r cos phi` and `r sin phi`:
/// `l L + rc r cos(phi) + rs r sin(phi)`, plus `taper |L|` on a taper.
#[derive(Clone, Copy, Debug)]
struct Rate {
    l: f64,
    rc: f64,
    rs: f64,
    taper: f64,
}

/// The faces' rates and the corners of the `r cos phi`, `r sin phi` box they are bounded on.
#[derive(Clone, Debug)]
struct Corners {
    rc: [f64; 2],
    rs: [f64; 2],
    rates: Vec<Rate>,
}

impl Corners {
    /// The largest rate for sections whose lead lies between `leads` (each rate is linear
    /// in the lead and in both radii, so its size is largest at a corner).
    fn speed(&self, leads: [f64; 2]) -> f64 {
        let mut speed: f64 = 1e-9;
        for r in &self.rates {
            for l in leads {
                for rc in self.rc {
                    for rs in self.rs {
                        let rate = r.l * l + r.rc * rc + r.rs * rs;
                        speed = speed.max(rate.abs() + r.taper * l.abs());
                    }
                }
            }
        }
        speed
    }
}

/// The radial change of a pass's tip per mm along the axis (0 for a straight pass).
fn taper(pass: &Pass) -> f64 {
    if pass.z_end != pass.z_start {
        ((pass.x_end - pass.x_start) / 2.0 / (pass.z_end - pass.z_start)).abs()
    } else {
        0.0
    }
}

/// The tool's solid behind its edge as faces in the tool frame (`V` from the tip centre, the
/// reference point for a mesh): the insert's ([`insert_faces`]: what the sweep cuts with)
/// or the mesh's; `None` for an edge without a body. What the 3D outputs draw.
pub(crate) fn body_faces(tool: &Tool) -> Option<Vec<Face>> {
    match (&tool.edge, tool.body) {
        (
            &Edge::Trapezoid {
                tip,
                left_angle,
                right_angle,
            },
            Some(body),
        ) => Some(insert_faces(
            &body,
            -tip / 2.0,
            tip / 2.0,
            cot(left_angle),
            cot(right_angle),
        )),
        (Edge::Mesh { solid, .. }, _) => Some(solid.faces.clone()),
        _ => None,
    }
}

/// The insert's faces in the tool frame (`h H + y Y + v V >= d`): the tip, raised by the
/// front clearance with depth; each flank (sloped: `H >= (vl + Y slope_l - V) cl`;
/// vertical: `V >= vl + Y slope_l`), set back by its clearance and the inclination; the back
/// `Y <= thickness`.
fn insert_faces(body: &Body, vl: f64, vr: f64, cl: f64, cr: f64) -> Vec<Face> {
    let face = |h: f64, y: f64, v: f64, d: f64| Face { h, y, v, d };
    let (sl, sr) = (body.slope_left(), body.slope_right());
    vec![
        face(1.0, -body.clearance_front.tan(), 0.0, 0.0),
        if cl.is_finite() {
            face(1.0, -sl * cl, cl, vl * cl)
        } else {
            face(0.0, -sl, 1.0, vl)
        },
        if cr.is_finite() {
            face(1.0, -sr * cr, -cr, -vr * cr)
        } else {
            face(0.0, -sr, -1.0, -vr)
        },
        face(0.0, -1.0, 0.0, -body.thickness),
    ]
}

/// Which flanks' sections can reach outside the edge's own cut at the same crossing (-z,
/// +z). At relative angle `phi`, radius `r` (depth `Y = r sin phi`) the section's -z flank
/// stands `out_l = -dir travel - Y slope_l - sense r (1 - cos phi) tan a_l` beyond the
/// edge's (towards the material): it has travelled with the helix, receded with its
/// clearance, and, when sloped, moved with the ray's lower height above the tip
/// (`r cos phi` instead of `r`), which recedes outside and reaches out inside a bore. The
/// +z flank likewise with `+dir travel`. Checked at both ends of the pass (the lead is
/// monotonic in revolutions), on 64 angles up to `phi_max`, at both ends of the radii the
/// body spans on the ray. A tip without front clearance can cut below the edge's: both
/// count then.
#[allow(clippy::too_many_arguments)]
fn reaches_out(
    body: &Body,
    tan_flanks: [f64; 2],
    sense: f64,
    leads: [f64; 2],
    k: f64,
    pass: &Pass,
    r: (f64, f64),
    phi_max: f64,
) -> [bool; 2] {
    if body.clearance_front < 0.0 {
        return [true, true];
    }
    let dir = pass.helix().dir;
    let (sl, sr) = (body.slope_left(), body.slope_right());
    let mut out = [false, false];
    for lead in leads {
        for i in 1..=64 {
            let phi = phi_max * i as f64 / 64.0;
            let dt = phi / TAU;
            let travel = dir * (lead * dt + 0.5 * k * dt * dt);
            // `out` is linear in the radius: its largest is at an end of the radii the
            // body has on this ray (within `thickness` of the rake face).
            for rr in [r.0, r.1.min(body.thickness / phi.sin())] {
                let y = rr * phi.sin();
                let lift = sense * rr * (1.0 - phi.cos());
                out[0] |= -travel - y * sl - lift * tan_flanks[0] > -1e-9;
                out[1] |= travel - y * sr - lift * tan_flanks[1] > -1e-9;
            }
        }
    }
    out
}

impl Sections {
    /// The heap memory the sections hold (bytes; a mesh body's solid is the tool's).
    pub(crate) fn heap_bytes(&self) -> u64 {
        (self.samples.capacity() * std::mem::size_of::<(f64, f64, f64)>()
            + self.faces.capacity() * std::mem::size_of::<Face>()
            + self.corners.rates.capacity() * std::mem::size_of::<Rate>()) as u64
    }

    /// The body's angular extent (the last sample's angle).
    fn phi_max(&self) -> f64 {
        self.samples.last().map_or(0.0, |&(dt, _, _)| dt * TAU)
    }

    /// How far (mm) section `dt` revolutions after a crossing at lead `lead` stands from
    /// the edge's tip, along the axis.
    fn delta(&self, lead: f64, dt: f64) -> f64 {
        self.dir * (lead * dt + 0.5 * self.lead_k * dt * dt)
    }

    /// The tables of a straight pass (`None` for a tapered one, one whose tip does not
    /// reach the blank, or one too short for its sections).
    pub(crate) fn tabulate(
        &self,
        pass: &Pass,
        sense: f64,
        q_blank: f64,
        rays: &[Ray],
    ) -> Option<Tables> {
        if pass.x_start != pass.x_end {
            return None;
        }
        let r_tip = pass.x_start / 2.0;
        let reach = q_blank - sense * r_tip;
        let u_max = self.samples.last()?.0;
        let t_last = pass.revolutions()? - u_max;
        if reach <= 0.0 || t_last <= 0.0 {
            return None;
        }
        let share = self.table_error / 2.0;
        let h = 2.0 * share;
        let n_bins = if self.lead_k == 0.0 {
            1
        } else {
            (t_last * self.lead_k.abs() * u_max / (2.0 * share)).ceil() as usize
        };
        if n_bins > MAX_BINS {
            return None;
        }
        let dt = t_last / n_bins as f64;
        use rayon::prelude::*;
        let bins = (0..n_bins)
            .into_par_iter()
            .map(|i| {
                let lead = self.lead_f + self.lead_k * (i as f64 + 0.5) * dt;
                // The bin's sections see the leads from its first crossing to its last
                // crossing's last section: where those are smaller than the pass's largest,
                // the faces move slower and every `stride`-th sample keeps the bound.
                let leads = [
                    self.lead_f + self.lead_k * i as f64 * dt,
                    self.lead_f + self.lead_k * ((i + 1) as f64 * dt + u_max),
                ];
                let n = self.samples.len();
                let needed = (self.phi_max() * self.corners.speed(leads) / self.phi_error).ceil();
                let stride = ((n as f64 / needed.max(1.0)).floor() as usize).clamp(1, n);
                self.table(lead, reach, h, rays, stride)
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Tables {
            dt,
            h,
            t_last,
            bins,
        })
    }

    /// Each sample's section on the rays of a straight pass (`None` for a tapered one, whose
    /// tip radius changes along it): made once per pass, used at every crossing.
    pub(crate) fn rays(&self, pass: &Pass, sense: f64, q_blank: f64) -> Option<Vec<Ray>> {
        (pass.x_start == pass.x_end).then(|| {
            let r_tip = pass.x_start / 2.0;
            self.samples
                .iter()
                .map(|&(_, c, s)| self.ray(c, s, r_tip, sense, q_blank))
                .collect()
        })
    }

    /// The two flank tables for crossings at lead `lead`, from every `stride`-th sample's
    /// `rays`; `None` when one would exceed [`MAX_ENTRIES`].
    fn table(
        &self,
        lead: f64,
        reach: f64,
        h: f64,
        rays: &[Ray],
        stride: usize,
    ) -> Option<[Option<Table>; 2]> {
        // Every `stride`-th sample and the last (the body's end), with their rays.
        let n = self.samples.len();
        let used: Vec<(&(f64, f64, f64), &Ray)> = self
            .samples
            .iter()
            .zip(rays)
            .enumerate()
            .filter(|&(k, _)| (k + 1) % stride == 0 || k + 1 == n)
            .map(|(_, x)| x)
            .collect();
        // Each sample's bands, in offsets from the edge's tip centre.
        let bands: Vec<[Option<(f64, f64)>; 2]> = used
            .iter()
            .map(|&(&(dt, _, s), _)| {
                let delta = self.delta(lead, dt);
                self.bands(reach, 2.0 * h, delta, s)
                    .map(|b| b.map(|(lo, hi)| (lo + delta, hi + delta)))
            })
            .collect();
        let mut out = [None, None];
        for (f, slot) in out.iter_mut().enumerate() {
            let (lo, hi) = bands
                .iter()
                .filter_map(|b| b[f])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (lo, hi)| {
                    (a.min(lo), b.max(hi))
                });
            if lo > hi {
                continue;
            }
            let w0 = (lo / h).floor() * h;
            let n = ((hi - w0) / h).ceil() + 1.0;
            if n.is_nan() || n > MAX_ENTRIES as f64 {
                return None;
            }
            let n = n as usize;
            let mut entries = vec![0.0f32; n];
            for (&(&(dt, _, _), ray), b) in used.iter().zip(&bands) {
                let Some((b_lo, b_hi)) = b[f] else { continue };
                let i0 = ((b_lo - w0) / h).ceil().max(0.0) as usize;
                let i1 = (((b_hi - w0) / h).floor() as usize).min(n - 1);
                if i1 < i0 {
                    continue;
                }
                let delta = self.delta(lead, dt);
                ray.cut(&mut entries[i0..=i1], w0 + i0 as f64 * h - delta, h);
            }
            *slot = Some(Table { w0, entries });
        }
        Some(out)
    }

    /// The axial bands (offsets from the section's tip centre) where the section of sample
    /// `sin phi = s`, placed `delta` mm along the axis from where the edge cut the same
    /// column, can cut below that cut, for material `reach` mm above the tip. The edge's
    /// flanks lie at `vl - delta` and `vr - delta` in the section's frame; the section's
    /// own flanks are set back by `Y slope` at depth `Y = r s` (`r` over the zone, `Y` at
    /// most the thickness). A flank whose section stays behind the edge's gives no band;
    /// otherwise the band runs from the edge's flank, where it leaves the material, to the
    /// section's, with `pad` of slack. Everywhere else the section lies inside the edge's
    /// cut (its tip stands higher: front clearance >= 0) or above the material.
    pub(crate) fn bands(
        &self,
        reach: f64,
        pad: f64,
        delta: f64,
        s: f64,
    ) -> [Option<(f64, f64)>; 2] {
        let Shape::Insert {
            vl,
            vr,
            cl,
            cr,
            slope_l,
            slope_r,
            thickness,
        } = self.shape
        else {
            return self.mesh_bands(pad, delta, s);
        };
        let run = |c: f64| if c.is_finite() { reach / c } else { 0.0 };
        let tan = |c: f64| if c.is_finite() { 1.0 / c } else { 0.0 };
        // Offsets of the section's flanks from the edge's, towards the material (+), at
        // the zone's two radii (linear in the radius, so the larger is at one of them);
        // see [`reaches_out`].
        let lift = 1.0 - (1.0 - s * s).max(0.0).sqrt();
        let out = |slope: f64, tan_a: f64, travel: f64| {
            [self.r_zone.0, self.r_zone.1]
                .map(|r| travel - (r * s).min(thickness) * slope - self.sense * r * lift * tan_a)
                .into_iter()
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let out_l = out(slope_l, tan(cl), -delta);
        let out_r = out(slope_r, tan(cr), delta);
        let (el, er) = (vl - delta, vr - delta);
        [
            (out_l > 0.0).then(|| (el - out_l - run(cl) - pad, el + pad)),
            (out_r > 0.0).then(|| (er - pad, er + out_r + run(cr) + pad)),
        ]
    }

    /// A mesh's bands: its axial extent, less where the edge's own cut at the crossing is
    /// already as deep as any point of the section can reach. Outside, a ray meets the
    /// section no lower than `h_min` above the tip (`r >= X = r_tip + H`); inside a bore,
    /// no lower than `h_min - r (1/cos phi - 1)` (the ray reaches out to `X / cos phi`).
    /// Where the edge stands no higher than that, the section cuts nothing new.
    fn mesh_bands(&self, pad: f64, delta: f64, s: f64) -> [Option<(f64, f64)>; 2] {
        let Shape::Mesh {
            ref solid,
            v_lo,
            v_hi,
            h_min,
            flat,
        } = self.shape
        else {
            return [None, None];
        };
        let whole = [Some((v_lo - pad, v_hi + pad)), None];
        let flat = if self.sense > 0.0 {
            flat
        } else {
            let c = (1.0 - s * s).max(1e-12).sqrt();
            let level = h_min - self.r_zone.1 * (1.0 / c - 1.0);
            (level >= 0.0).then(|| solid.span(level))
        };
        // The flat in the section's frame, shrunk by the slack.
        match flat {
            Some((a, b)) if a - delta + pad < b - delta - pad => [
                Some((v_lo - pad, a - delta + pad)),
                Some((b - delta - pad, v_hi + pad)),
            ],
            _ => whole,
        }
    }

    /// Cut `seg` (cells at axial offsets `v_start + k dz` from the section's tip centre,
    /// values `q - q_blank`) with the section of sample `(c, s)` whose tip is at radius
    /// `r_tip`. `sense` is +1 for an outer surface (external thread), -1 for an inner one.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn apply(
        &self,
        seg: &mut [f32],
        v_start: f64,
        dz: f64,
        c: f64,
        s: f64,
        r_tip: f64,
        sense: f64,
        q_blank: f64,
    ) {
        self.ray(c, s, r_tip, sense, q_blank).cut(seg, v_start, dz);
    }

    /// The section of sample `(c, s)` with its tip at radius `r_tip`, as bounds on the
    /// stored value along the rays at every axial offset `v` from its tip centre.
    ///
    /// Every face is a constraint `a r >= b0 + b1 v` on the radius along the ray; written
    /// for the stored value `rho = sense r - q_blank` it is a lower bound (the body lies
    /// above a line in `v`), an upper bound, or, when `a = 0`, a limit on `v` alone.
    fn ray(&self, c: f64, s: f64, r_tip: f64, sense: f64, q_blank: f64) -> Ray {
        ray(&self.faces, c, s, r_tip, sense, q_blank)
    }
}

/// The section of a solid (`faces` in the tool frame) at relative angle `(c, s) = (cos phi,
/// sin phi)` with its tip at radius `r_tip`, as bounds on the stored value along the rays at
/// every axial offset `v` from its reference point. `(1, 0)` is the edge.
///
/// On the ray `H = sense (r c - r_tip)` and `Y = r s`, so a face `h H + y Y + v V >= d` is
/// the constraint `(h sense c + y s) r >= d + h sense r_tip - v V` on the radius; written for
/// the stored value `rho = sense r - q_blank` it is a lower bound (the solid lies above a
/// line in `V`), an upper bound, or, when its factor is 0, a limit on `V` alone.
pub(crate) fn ray(faces: &[Face], c: f64, s: f64, r_tip: f64, sense: f64, q_blank: f64) -> Ray {
    let mut ray = Ray {
        lower: Vec::with_capacity(faces.len()),
        upper: Vec::with_capacity(faces.len()),
        v_lo: f64::NEG_INFINITY,
        v_hi: f64::INFINITY,
    };
    let mut add = |a: f64, b0: f64, b1: f64| {
        // a r >= b0 + b1 v with r = sense (rho + q_blank).
        let a = a * sense;
        let b0 = b0 - a * q_blank;
        if a > 0.0 {
            ray.lower.push((b0 / a, b1 / a));
        } else if a < 0.0 {
            ray.upper.push((b0 / a, b1 / a));
        } else if b1 > 0.0 {
            ray.v_hi = ray.v_hi.min(-b0 / b1);
        } else if b1 < 0.0 {
            ray.v_lo = ray.v_lo.max(-b0 / b1);
        } else if b0 > 0.0 {
            ray.v_lo = f64::INFINITY;
        }
    };
    // The ray itself (r >= 0).
    add(1.0, 0.0, 0.0);
    for f in faces {
        add(f.h * sense * c + f.y * s, f.d + f.h * sense * r_tip, -f.v);
    }
    ray
}

/// Lines per kind an insert's section can have: of its five faces (the ray's start, the
/// back, the tip, two flanks), the first two bound opposite sides. A mesh may have more
/// (evaluated line by line).
const RAY_LINES: usize = 4;

/// One section on the rays of a column: lower and upper bounds `alpha + beta v` on the
/// stored value at axial offset `v` from the section's tip centre, and the offsets
/// `[v_lo, v_hi]` it spans.
#[derive(Clone, Debug)]
pub(crate) struct Ray {
    lower: Vec<(f64, f64)>,
    upper: Vec<(f64, f64)>,
    v_lo: f64,
    v_hi: f64,
}

impl Ray {
    /// The heap memory the ray holds (bytes).
    pub(crate) fn heap_bytes(&self) -> u64 {
        ((self.lower.capacity() + self.upper.capacity()) * std::mem::size_of::<(f64, f64)>()) as u64
    }

    /// Cut `seg` (cells at offsets `v_start + k dz`). The material side meets the body at
    /// the highest lower bound (the smallest radius outside, the largest inside), so a cell
    /// is cut to it where that does not exceed the lowest upper bound. The lines are moved
    /// to the first cell in f64 and evaluated per cell in f32, like the edge.
    pub(crate) fn cut(&self, seg: &mut [f32], v_start: f64, dz: f64) {
        // The cells with v_lo <= v < v_hi (the stock's tie rule).
        let k0 = first_cell((self.v_lo - v_start) / dz).max(0.0);
        let k1 = (first_cell((self.v_hi - v_start) / dz) - 1.0).min(seg.len() as f64 - 1.0);
        if k0.is_nan() || k1.is_nan() || k0 > k1 {
            return;
        }
        let (k0, k1) = (k0 as usize, k1 as usize);
        let v0 = v_start + k0 as f64 * dz;
        let seg = &mut seg[k0..=k1];
        let n = self.lower.len().max(self.upper.len());
        if n > RAY_LINES {
            // A mesh's many faces: each line over the cells in turn.
            let dz = dz as f32;
            let mut lo = vec![f32::NEG_INFINITY; seg.len()];
            let mut hi = vec![f32::INFINITY; seg.len()];
            for &(alpha, beta) in &self.lower {
                let (a, b) = ((alpha + beta * v0) as f32, beta as f32);
                for (k, l) in lo.iter_mut().enumerate() {
                    *l = fmax(*l, a + b * ((k as i32) as f32 * dz));
                }
            }
            for &(alpha, beta) in &self.upper {
                let (a, b) = ((alpha + beta * v0) as f32, beta as f32);
                for (k, h) in hi.iter_mut().enumerate() {
                    *h = fmin(*h, a + b * ((k as i32) as f32 * dz));
                }
            }
            for ((cell, l), h) in seg.iter_mut().zip(&lo).zip(&hi) {
                let cut = if l <= h { *l } else { f32::INFINITY };
                *cell = fmin(*cell, cut);
            }
            return;
        }
        let lower = Lines::<RAY_LINES>::new(&self.lower, v0, f32::NEG_INFINITY);
        let upper = Lines::<RAY_LINES>::new(&self.upper, v0, f32::INFINITY);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            unsafe { cut_avx2(seg, &lower, &upper, dz as f32) };
            return;
        }
        cut_cells(seg, &lower, &upper, dz as f32);
    }
}

/// The cells' loop of [`Ray::cut`]: each cell cut to the highest lower bound where that
/// does not exceed the lowest upper bound.
#[inline(always)]
fn cut_cells(seg: &mut [f32], lower: &Lines<RAY_LINES>, upper: &Lines<RAY_LINES>, dz: f32) {
    for (k, cell) in seg.iter_mut().enumerate() {
        let w = (k as i32) as f32 * dz;
        let lo = lower.max_at(w);
        let hi = upper.min_at(w);
        let cut = if lo <= hi { lo } else { f32::INFINITY };
        *cell = fmin(*cell, cut);
    }
}

/// [`cut_cells`] compiled for AVX2: eight cells a step instead of four. The same f32
/// operations in the same order (no fused multiply-add), so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn cut_avx2(seg: &mut [f32], lower: &Lines<RAY_LINES>, upper: &Lines<RAY_LINES>, dz: f32) {
    cut_cells(seg, lower, upper, dz);
}

/// Up to `N` lines `alpha + beta w` in f32.
struct Lines<const N: usize> {
    alpha: [f32; N],
    beta: [f32; N],
}

impl<const N: usize> Lines<N> {
    /// The lines `alpha + beta v` moved to `w = v - v0`, padded with the constant `fill`.
    fn new(lines: &[(f64, f64)], v0: f64, fill: f32) -> Self {
        let mut out = Lines {
            alpha: [fill; N],
            beta: [0.0; N],
        };
        for (i, &(alpha, beta)) in lines.iter().enumerate() {
            out.alpha[i] = (alpha + beta * v0) as f32;
            out.beta[i] = beta as f32;
        }
        out
    }

    #[inline(always)]
    fn max_at(&self, w: f32) -> f32 {
        let mut m = self.alpha[0] + self.beta[0] * w;
        for i in 1..N {
            m = fmax(m, self.alpha[i] + self.beta[i] * w);
        }
        m
    }

    #[inline(always)]
    fn min_at(&self, w: f32) -> f32 {
        let mut m = self.alpha[0] + self.beta[0] * w;
        for i in 1..N {
            m = fmin(m, self.alpha[i] + self.beta[i] * w);
        }
        m
    }
}

/// `min` without the NaN handling of `f32::min`: one instruction, so loops vectorise.
#[inline(always)]
pub(crate) fn fmin(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `max` without the NaN handling of `f32::max`.
#[inline(always)]
pub(crate) fn fmax(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

impl Tables {
    /// The heap memory the tables hold (bytes).
    pub(crate) fn heap_bytes(&self) -> u64 {
        let entries: usize = self
            .bins
            .iter()
            .flatten()
            .flatten()
            .map(|t| t.entries.capacity() * std::mem::size_of::<f32>())
            .sum();
        (self.bins.capacity() * std::mem::size_of::<[Option<Table>; 2]>() + entries) as u64
    }

    /// Cut a column (cells `z0 + j dz`) with the tables of a crossing at revolution
    /// `t <= t_last` whose edge tip centre stands at `z_tip`; returns the tables applied and
    /// the cells they touched.
    pub(crate) fn apply(
        &self,
        col: &mut [f32],
        t: f64,
        z_tip: f64,
        (z0, dz): (f64, f64),
    ) -> (u64, u64) {
        let bin = ((t / self.dt) as usize).min(self.bins.len() - 1);
        let (mut tables, mut cells) = (0, 0);
        let last = col.len() as f64 - 1.0;
        for Table { w0, entries } in self.bins[bin].iter().flatten() {
            // Cells whose nearest entry is in the table: w within h/2 of its ends.
            let w_hi = w0 + (entries.len() as f64 - 0.5) * self.h;
            let j0 = ((z_tip + w0 - 0.5 * self.h - z0) / dz).ceil().max(0.0);
            let j1 = ((z_tip + w_hi - z0) / dz).floor().min(last);
            if j1 < j0 {
                continue;
            }
            let (j0, j1) = (j0 as usize, j1 as usize);
            // Entry index of cell j: round((z0 + j dz - z_tip - w0) / h).
            let x0 = (z0 + j0 as f64 * dz - z_tip - w0) / self.h + 0.5;
            let step = dz / self.h;
            let top = entries.len() - 1;
            for (k, cell) in col[j0..=j1].iter_mut().enumerate() {
                // x >= 0 up to rounding (the first cell is within h/2 of entry 0), so the
                // saturating cast floors it.
                let i = ((x0 + k as f64 * step) as usize).min(top);
                *cell = fmin(*cell, entries[i]);
            }
            tables += 1;
            cells += (j1 - j0 + 1) as u64;
        }
        (tables, cells)
    }
}
