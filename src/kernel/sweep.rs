//! The sweep kernel: planar tool profiles cut along every pass, one angular column at a time.
//!
//! For a tool on centre height the edge profile lies in the axial plane through the tool,
//! so the material on the generator at angle `theta` is touched only at the revolutions
//! where the pass crosses `theta`. There the column is cut by the profile placed at the
//! tool's z and radius: `q_j = min(q_j, q_tip + h(z_j - z_tip))`. That is exact in angle (no
//! angular sampling), and each column is independent, so columns run in parallel with
//! rayon and the result does not depend on the thread count (`min` is order-free).
//!
//! A tool with a [`crate::model::tool::Body`] also cuts with the sections of its body behind the
//! edge, at the instants after each crossing when they pass the column ([`crate::kernel::body`]);
//! passes whose body cannot reach beyond the edge's own cut skip them.
//!
//! One *dexel update* is one dexel tested against one tool placement; the kernel counts them.

use crate::kernel::body::{self, fmin, Ray, Sections, Tables};
use crate::model::pass::Pass;
use crate::model::stock::{first_cell, Grid, Stock, Surface};
use crate::model::tool::{round_v_height, trapezoid_height, Kernel, Tool};
use rayon::prelude::*;

/// What a sweep did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SweepStats {
    /// Tool placements applied (pass crossings of a column).
    pub placements: u64,
    /// Dexel updates (one dexel against one placement).
    pub dexel_updates: u64,
}

impl std::ops::Add for SweepStats {
    type Output = SweepStats;
    fn add(self, o: SweepStats) -> SweepStats {
        SweepStats {
            placements: self.placements + o.placements,
            dexel_updates: self.dexel_updates + o.dexel_updates,
        }
    }
}

/// A pass made ready for the kernel: its helix, end revolution and tool data.
#[derive(Clone, Debug)]
struct Prepared {
    pass_idx: usize,
    t_end: f64,
    ref_offset: f64,
    kernel: Kernel,
    /// The body's sections, when they can cut something the edge does not.
    body: Option<Sections>,
    /// Their sections on the rays (straight passes), and their cut tabulated (grid sweeps
    /// of straight passes).
    rays: Option<Vec<Ray>>,
    tables: Option<Tables>,
    /// A mesh tool's edge on the rays (straight passes).
    edge_ray: Option<Ray>,
}

/// Cut `surface` of the stock with every pass (passes whose lead vanishes are skipped;
/// the job validation rejects them before).
pub fn sweep(stock: &mut Stock, surface: Surface, passes: &[Pass], tools: &[Tool]) -> SweepStats {
    let grid = stock.grid;
    let kernel = GridSweep::new(grid, stock.blank_q(surface), surface, passes, tools);
    let Some(q) = stock.surface_mut(surface) else {
        return SweepStats::default();
    };
    q.par_chunks_mut(grid.n_z)
        .enumerate()
        .map(|(i, col)| kernel.column(i, col))
        .reduce(SweepStats::default, |a, b| a + b)
}

/// The passes made ready to cut the columns of one grid, one column at a time (the
/// streaming pipeline calls [`GridSweep::column`] per column of its tiles).
pub(crate) struct GridSweep<'a> {
    grid: Grid,
    q_blank: f64,
    surface: Surface,
    passes: &'a [Pass],
    prepared: Vec<Prepared>,
}

impl<'a> GridSweep<'a> {
    /// The passes prepared for `grid` (the bodies' tables built once).
    pub(crate) fn new(
        grid: Grid,
        q_blank: f64,
        surface: Surface,
        passes: &'a [Pass],
        tools: &[Tool],
    ) -> GridSweep<'a> {
        GridSweep {
            grid,
            q_blank,
            surface,
            passes,
            prepared: prepare(passes, tools, q_blank, surface, true),
        }
    }

    /// The heap memory the prepared passes hold (bytes): the bodies' sections, their rays
    /// and tables. [`sweep_column`] prepares the same but the tables:
    /// `(with tables, without)`.
    pub(crate) fn heap_bytes(&self) -> (u64, u64) {
        let mut without = (self.prepared.capacity() * std::mem::size_of::<Prepared>()) as u64;
        let mut tables = 0;
        for p in &self.prepared {
            without += p.body.as_ref().map_or(0, Sections::heap_bytes);
            without += p
                .rays
                .iter()
                .flatten()
                .chain(&p.edge_ray)
                .map(Ray::heap_bytes)
                .sum::<u64>();
            without += p
                .rays
                .as_ref()
                .map_or(0, |r| (r.capacity() * std::mem::size_of::<Ray>()) as u64);
            tables += p.tables.as_ref().map_or(0, Tables::heap_bytes);
        }
        (without + tables, without)
    }

    /// Cut column `i` of the grid, held in `col` (`n_z` values, `q - q_blank`), in place.
    pub(crate) fn column(&self, i: usize, col: &mut [f32]) -> SweepStats {
        let g = &self.grid;
        cut_column(
            col,
            g.theta(i),
            g.z0,
            g.dz,
            self.q_blank,
            self.surface,
            self.passes,
            &self.prepared,
        )
    }
}

/// A free-standing column: its angle, its cells `z0 + j*dz`, and the surface it samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Column {
    /// Angle on the part (rad).
    pub theta: f64,
    /// z of cell 0 (mm).
    pub z0: f64,
    /// Cell spacing (mm).
    pub dz: f64,
    /// The blank's signed radius (`q = r` outside, `-r` inside).
    pub q_blank: f64,
    /// Which surface.
    pub surface: Surface,
}

/// Cut one free-standing column (used for the fine measurement generators). `q` holds
/// `q - q_blank` (zeros for the blank) and is cut in place.
pub fn sweep_column(q: &mut [f32], c: Column, passes: &[Pass], tools: &[Tool]) -> SweepStats {
    let prepared = prepare(passes, tools, c.q_blank, c.surface, false);
    cut_column(
        q, c.theta, c.z0, c.dz, c.q_blank, c.surface, passes, &prepared,
    )
}

/// The passes made ready; `tabulate` builds the bodies' [`Tables`], which pay off over a
/// whole grid but not for one column.
fn prepare(
    passes: &[Pass],
    tools: &[Tool],
    q_blank: f64,
    surface: Surface,
    tabulate: bool,
) -> Vec<Prepared> {
    passes
        .iter()
        .enumerate()
        .filter_map(|(pass_idx, p)| {
            let tool = tools.get(p.tool)?;
            let zone = body::zone(p, q_blank, surface);
            let sense = surface.sense();
            let body = body::sections(p, tool, zone, sense);
            let rays = body.as_ref().and_then(|b| b.rays(p, sense, q_blank));
            let tables = match (&body, &rays) {
                (Some(b), Some(r)) if tabulate => b.tabulate(p, sense, q_blank, r),
                _ => None,
            };
            let kernel = tool.kernel();
            let edge_ray = match &kernel {
                Kernel::Mesh(solid) if p.x_start == p.x_end => Some(body::ray(
                    &solid.faces,
                    1.0,
                    0.0,
                    p.x_start / 2.0,
                    sense,
                    q_blank,
                )),
                _ => None,
            };
            Some(Prepared {
                pass_idx,
                t_end: p.revolutions()?,
                ref_offset: tool.reference_offset(),
                kernel,
                body,
                rays,
                tables,
                edge_ray,
            })
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn cut_column(
    col: &mut [f32],
    theta: f64,
    z0: f64,
    dz: f64,
    q_blank: f64,
    surface: Surface,
    passes: &[Pass],
    prepared: &[Prepared],
) -> SweepStats {
    let mut stats = SweepStats::default();
    let n = col.len();
    if n == 0 {
        return stats;
    }
    let sense = surface.sense();
    for pr in prepared {
        let pass = &passes[pr.pass_idx];
        let helix = pass.helix();
        for t in helix.crossings(theta, 0.0, pr.t_end) {
            let z_ref = helix.z(t);
            let z_tip = z_ref - pr.ref_offset;
            let q_tip = sense * pass.radius_at(z_ref);
            let reach = q_blank - q_tip;
            if reach <= 0.0 {
                continue;
            }
            let (v_min, v_max) = pr.kernel.span(reach);
            // The cells with z_tip + v_min <= z < z_tip + v_max (the stock's tie rule).
            let j0 = first_cell((z_tip + v_min - z0) / dz).max(0.0);
            let j1 = (first_cell((z_tip + v_max - z0) / dz) - 1.0).min(n as f64 - 1.0);
            if j1 < j0 {
                continue;
            }
            let (j0, j1) = (j0 as usize, j1 as usize);
            let v_start = z0 + j0 as f64 * dz - z_tip;
            let seg = &mut col[j0..=j1];
            stats.placements += 1;
            stats.dexel_updates += seg.len() as u64;
            match &pr.edge_ray {
                Some(ray) => ray.cut(seg, v_start, dz),
                None => apply(seg, &pr.kernel, v_start, dz, q_tip, q_blank, sense),
            }
            match (&pr.tables, &pr.body) {
                (Some(tables), _) if t <= tables.t_last => {
                    let (placements, cells) = tables.apply(col, t, z_tip, (z0, dz));
                    stats.placements += placements;
                    stats.dexel_updates += cells;
                }
                (_, Some(b)) => {
                    let rays = pr.rays.as_deref();
                    stats =
                        stats + body_sections(col, b, rays, pass, pr, t, (z0, dz), q_blank, sense);
                }
                _ => {}
            }
        }
    }
    stats
}

/// The body's sections after the edge's crossing at `t`: each at its own instant, tip and
/// axial position, over the bands along the flanks where it can reach beyond the edge.
/// `rays` are the samples' sections made ready, for a straight pass.
#[allow(clippy::too_many_arguments)]
fn body_sections(
    col: &mut [f32],
    b: &Sections,
    rays: Option<&[Ray]>,
    pass: &Pass,
    pr: &Prepared,
    t: f64,
    (z0, dz): (f64, f64),
    q_blank: f64,
    sense: f64,
) -> SweepStats {
    let mut stats = SweepStats::default();
    let n = col.len();
    let helix = pass.helix();
    let z_tip_edge = helix.z(t) - pr.ref_offset;
    for (i, &(dt, c, s)) in b.samples.iter().enumerate() {
        let ts = t + dt;
        if ts > pr.t_end {
            break;
        }
        let z_ref = helix.z(ts);
        let z_tip = z_ref - pr.ref_offset;
        let r_tip = pass.radius_at(z_ref);
        let reach = q_blank - sense * r_tip;
        if reach <= 0.0 {
            continue;
        }
        // Two cells of slack around each band: the cells a corner falls between.
        let delta = z_tip - z_tip_edge;
        let mut last = None;
        for (v_lo, v_hi) in b.bands(reach, 2.0 * dz, delta, s).into_iter().flatten() {
            let j0 = ((z_tip + v_lo - z0) / dz).ceil().max(0.0);
            let j1 = ((z_tip + v_hi - z0) / dz).floor().min(n as f64 - 1.0);
            if j1 < j0 {
                continue;
            }
            // Bands of a narrow tip may overlap: cut each cell once.
            let j0 = (j0 as usize).max(last.map_or(0, |l: usize| l + 1));
            let j1 = j1 as usize;
            if j1 < j0 {
                continue;
            }
            last = Some(j1);
            let v_start = z0 + j0 as f64 * dz - z_tip;
            let seg = &mut col[j0..=j1];
            stats.placements += 1;
            stats.dexel_updates += seg.len() as u64;
            match rays {
                Some(rays) => rays[i].cut(seg, v_start, dz),
                None => b.apply(seg, v_start, dz, c, s, r_tip, sense, q_blank),
            }
        }
    }
    stats
}

/// `seg[k] = min(seg[k], base + h(v_start + k*dz))` with `base = q_tip - q_blank`: the edge
/// stands back from the tip away from the material, `+h` outside (external) and `-h`
/// inside, which in signed radii is always `+h` since `q = -r` there. A solid's edge is its
/// section at the rake face, cut per ray like its body's sections ([`body::ray`]).
fn apply(
    seg: &mut [f32],
    kernel: &Kernel,
    v_start: f64,
    dz: f64,
    q_tip: f64,
    q_blank: f64,
    sense: f64,
) {
    if let Kernel::Mesh(solid) = kernel {
        body::ray(&solid.faces, 1.0, 0.0, sense * q_tip, sense, q_blank).cut(seg, v_start, dz);
        return;
    }
    let v0 = v_start as f32;
    let dz = dz as f32;
    let base = (q_tip - q_blank) as f32;
    match *kernel {
        Kernel::Mesh(_) => {}
        Kernel::Trapezoid { vl, vr, cl, cr } => {
            // Vertical flanks only limit the span (done by the caller).
            let cl = if cl.is_finite() { cl as f32 } else { 0.0 };
            let cr = if cr.is_finite() { cr as f32 } else { 0.0 };
            if cl == 0.0 && cr == 0.0 {
                for c in seg.iter_mut() {
                    *c = fmin(*c, base);
                }
                return;
            }
            let (vl, vr) = (vl as f32, vr as f32);
            for (k, c) in seg.iter_mut().enumerate() {
                let v = v0 + (k as i32) as f32 * dz;
                *c = fmin(*c, base + trapezoid_height(v, vl, vr, cl, cr));
            }
        }
        Kernel::RoundV {
            radius,
            vt,
            ht,
            cot,
        } => {
            let (r, vt, ht, cot) = (radius as f32, vt as f32, ht as f32, cot as f32);
            for (k, c) in seg.iter_mut().enumerate() {
                let v = v0 + (k as i32) as f32 * dz;
                *c = fmin(*c, base + round_v_height(v, r, vt, ht, cot));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::Spindle;
    use crate::model::tool::{Edge, Reference};

    /// The kernel's profile placement against a direct evaluation of the tool height.
    #[test]
    fn column_matches_direct_evaluation() {
        let tools = vec![Tool {
            id: 1,
            edge: Edge::RoundV {
                radius: 0.2,
                half_angle: 30f64.to_radians(),
            },
            reference: Reference::Tip,
            body: None,
            length: None,
            depth_per_pass: Default::default(),
        }];
        let pass = Pass {
            tool: 0,
            x_start: 18.0,
            x_end: 18.0,
            z_start: 3.0,
            z_end: -20.0,
            lead: 2.0,
            lead_change: 0.1,
            start_angle: 0.4,
            spindle: Spindle::Cw,
        };
        let (z0, dz, n) = (-25.0, 0.01, 3000);
        let mut q = vec![0.0f32; n];
        let theta = 1.3;
        let column = Column {
            theta,
            z0,
            dz,
            q_blank: 10.0,
            surface: Surface::Outer,
        };
        sweep_column(&mut q, column, std::slice::from_ref(&pass), &tools);
        let helix = pass.helix();
        let ts: Vec<f64> = helix
            .crossings(theta, 0.0, pass.revolutions().unwrap())
            .collect();
        for (j, &qj) in q.iter().enumerate() {
            let z = z0 + j as f64 * dz;
            let mut want: f64 = 10.0;
            for &t in &ts {
                want = want.min(9.0 + tools[0].height(z - helix.z(t)));
            }
            let got = qj as f64 + 10.0;
            assert!((got - want).abs() < 1e-6, "j={j} {got} vs {want}");
        }
    }

    /// A square tool with a body on a variable-lead pass (leads 8 to 30 mm over 5.5 turns
    /// at radius 22: the helix angle at the tip grows from 3.3 to 12.2 deg).
    fn bodied(left_deg: f64, right_deg: f64) -> (Pass, Tool) {
        let pass = Pass {
            tool: 0,
            x_start: 44.0,
            x_end: 44.0,
            z_start: 8.0,
            z_end: -100.0,
            lead: 8.0,
            lead_change: 4.0,
            start_angle: 0.0,
            spindle: Spindle::Cw,
        };
        let tool = Tool {
            id: 1,
            edge: Edge::Trapezoid {
                tip: 5.0,
                left_angle: 0.0,
                right_angle: 0.0,
            },
            reference: Reference::Center,
            body: Some(crate::model::tool::Body {
                thickness: 4.0,
                clearance_left: left_deg.to_radians(),
                clearance_right: right_deg.to_radians(),
                clearance_front: 5f64.to_radians(),
                inclination: 0.0,
            }),
            length: None,
            depth_per_pass: Default::default(),
        };
        (pass, tool)
    }

    /// One column cut by the pass, with the body's sections as given.
    fn cut(pass: &Pass, tool: &Tool, body: Option<Sections>) -> Vec<f32> {
        cut_surface(pass, tool, body, Surface::Outer, 25.0)
    }

    /// Whether every cell of `x` (cells `dz` apart) lies within `bound` along the axis of a
    /// cell of `y` at least as deep. Radial differences at a wall are heights, so cuts are
    /// compared by position.
    fn within_axially(x: &[f32], y: &[f32], bound: f64, dz: f64) -> bool {
        let reach = (bound / dz).ceil() as usize + 1;
        (0..x.len()).all(|j| {
            let lo = j.saturating_sub(reach);
            let hi = (j + reach).min(y.len() - 1);
            (lo..=hi).any(|k| y[k] <= x[j] + 1e-4 + bound as f32)
        })
    }

    fn cut_surface(
        pass: &Pass,
        tool: &Tool,
        body: Option<Sections>,
        surface: Surface,
        q_blank: f64,
    ) -> Vec<f32> {
        cut_with(pass, tool, body, None, surface, q_blank, 0.01)
    }

    fn cut_with(
        pass: &Pass,
        tool: &Tool,
        body: Option<Sections>,
        tables: Option<Tables>,
        surface: Surface,
        q_blank: f64,
        dz: f64,
    ) -> Vec<f32> {
        let (z0, n) = (-110.0, (120.0 / dz) as usize);
        let mut q = vec![0.0f32; n];
        let prepared = [Prepared {
            pass_idx: 0,
            t_end: pass.revolutions().unwrap(),
            ref_offset: tool.reference_offset(),
            kernel: tool.kernel(),
            rays: None,
            body,
            tables,
            edge_ray: None,
        }];
        cut_column(
            &mut q,
            0.7,
            z0,
            dz,
            q_blank,
            surface,
            std::slice::from_ref(pass),
            &prepared,
        );
        q
    }

    /// A body whose clearance exceeds the helix angle everywhere cuts nothing the edge did
    /// not, even when its sections are swept (the skip rule is exact), and is skipped.
    #[test]
    fn a_cleared_body_cuts_what_the_edge_cuts() {
        let (pass, tool) = bodied(20.0, 20.0);
        let zone = (22.0, 25.0);
        assert!(
            body::sections(&pass, &tool, zone, 1.0).is_none(),
            "not skipped"
        );
        let forced = body::sample(&pass, &tool, zone, 1.0, body::SAMPLING_ERROR_MM, true).unwrap();
        assert!(forced.samples.len() > 10);
        let planar = cut(&pass, &tool, None);
        assert!(planar.iter().any(|&q| q < -2.9), "the edge cut the groove");
        assert_eq!(planar, cut(&pass, &tool, Some(forced)));
    }

    /// The same for a nut: an internal thread in a 20 mm bore cut 3 mm deep, the body
    /// reaching towards the axis. In the bore the helix angle is larger (up to
    /// atan(30 / (2 pi 10)) = 25.5 deg), so the clearance must be too: 35 deg. Sections
    /// swept or not, the cut is the edge's; with 20 deg the body rubs (a check that the
    /// internal case is not cleared by accident).
    #[test]
    fn a_cleared_body_in_a_bore_cuts_what_the_edge_cuts() {
        let (mut pass, tool) = bodied(35.0, 35.0);
        pass.x_start = 26.0;
        pass.x_end = 26.0;
        let zone = (10.0, 13.0);
        assert!(
            body::sections(&pass, &tool, zone, -1.0).is_none(),
            "not skipped"
        );
        let (_, rubbing) = bodied(20.0, 20.0);
        let planar = cut_surface(&pass, &tool, None, Surface::Inner, -10.0);
        let rubbed = cut_surface(
            &pass,
            &rubbing,
            body::sections(&pass, &rubbing, zone, -1.0),
            Surface::Inner,
            -10.0,
        );
        assert!(rubbed.iter().zip(&planar).any(|(r, p)| r < &(p - 0.01)));
        let forced = body::sample(&pass, &tool, zone, -1.0, body::SAMPLING_ERROR_MM, true).unwrap();
        assert!(planar.iter().any(|&q| q < -2.9), "the edge cut the groove");
        let bodied = cut_surface(&pass, &tool, Some(forced), Surface::Inner, -10.0);
        let diff: Vec<(usize, f32, f32)> = (0..planar.len())
            .filter(|&j| planar[j] != bodied[j])
            .map(|j| (j, planar[j], bodied[j]))
            .take(8)
            .collect();
        assert!(diff.is_empty(), "{diff:?}");
    }

    /// An interfering body sampled at the default density is within its stated bound of
    /// the same body sampled four times finer, and the body cut past the edge on the -z
    /// flank (the pass travels towards -z).
    #[test]
    fn body_sampling_stays_within_its_bound() {
        let (pass, tool) = bodied(3.0, 20.0);
        let zone = (22.0, 25.0);
        let coarse = body::sections(&pass, &tool, zone, 1.0).expect("interferes");
        let bound = coarse.bound;
        assert!(bound <= body::SAMPLING_ERROR_MM * (1.0 + 1e-9), "{bound}");
        let fine = body::sample(
            &pass,
            &tool,
            zone,
            1.0,
            body::SAMPLING_ERROR_MM / 4.0,
            false,
        )
        .unwrap();
        assert!(fine.samples.len() >= 4 * coarse.samples.len() - 4);
        let planar = cut(&pass, &tool, None);
        let a = cut(&pass, &tool, Some(coarse));
        let b = cut(&pass, &tool, Some(fine));
        assert!(within_axially(&a, &b, bound, 0.01) && within_axially(&b, &a, bound, 0.01));
        let extra: Vec<usize> = (0..a.len()).filter(|&j| a[j] < planar[j] - 1e-3).collect();
        assert!(!extra.is_empty(), "the body cut nothing");
        // Every extra cell lies just -z of a wall the edge cut: the next cells towards +z
        // were cut by the edge, within the body's reach 4 mm x (tan psi - tan 3 deg) at
        // most 4 x (30 / (2 pi 22) - 0.052) = 0.66 mm.
        for &j in &extra {
            assert!(
                (j + 1..(j + 70).min(a.len())).any(|k| planar[k] < -2.9),
                "cell {j} is not on a -z flank"
            );
        }
    }

    /// The tabulated sections (the grid sweep's) against the same sections swept at every
    /// crossing (the measurement columns'): within their bounds, on a variable-lead pass
    /// (the tables' bins, sampled more sparsely where the lead is small) and with the body
    /// rubbing.
    #[test]
    fn tables_agree_with_direct_sections() {
        let (pass, tool) = bodied(3.0, 20.0);
        let sections = body::sections(&pass, &tool, (22.0, 25.0), 1.0).expect("interferes");
        let tables = sections
            .tabulate(&pass, 1.0, 25.0, &sections.rays(&pass, 1.0, 25.0).unwrap())
            .expect("a straight pass");
        assert!(tables.t_last > 5.0, "{}", tables.t_last);
        // Cells of 1 um, finer than the tables' entries (2.5 um).
        let dz = 0.001;
        let column = |s: Option<Sections>, t: Option<Tables>| {
            cut_with(&pass, &tool, s, t, Surface::Outer, 25.0, dz)
        };
        let planar = column(None, None);
        let direct = column(Some(sections.clone()), None);
        let tabled = column(Some(sections.clone()), Some(tables));
        // Each within its bound of the continuous body: the sampling's (the tables may use
        // every k-th sample where the bin's leads allow) plus the tables' own.
        let bound = sections.bound + body::SAMPLING_ERROR_MM / 2.0;
        assert!(within_axially(&direct, &tabled, bound, dz));
        assert!(within_axially(&tabled, &direct, bound, dz));
        // The tables did cut beside the edge, and not everywhere alike.
        let extra = |c: &[f32]| (0..c.len()).filter(|&j| c[j] < planar[j] - 1e-3).count();
        assert!(extra(&tabled) > 500, "{}", extra(&tabled));
        assert!(extra(&tabled).abs_diff(extra(&direct)) < extra(&direct) / 10);
    }

    /// A Tr-like tool (tip 1.9, 15 deg flanks) with a body on the variable-lead pass.
    fn bodied_tr(clearance_deg: f64) -> (Pass, Tool) {
        let (pass, mut tool) = bodied(clearance_deg, clearance_deg);
        tool.edge = Edge::Trapezoid {
            tip: 1.9,
            left_angle: 15f64.to_radians(),
            right_angle: 15f64.to_radians(),
        };
        (pass, tool)
    }

    /// Sloped flanks: the sampling bound holds against four times the samples, outside
    /// and in a bore (where the ray's falling height above the tip moves a sloped flank
    /// towards the material).
    #[test]
    fn sloped_body_sampling_stays_within_its_bound() {
        for (surface, x, q_blank, zone) in [
            (Surface::Outer, 44.0, 25.0, (22.0, 25.0)),
            (Surface::Inner, 26.0, -10.0, (10.0, 13.0)),
        ] {
            let (mut pass, tool) = bodied_tr(3.0);
            pass.x_start = x;
            pass.x_end = x;
            let sense = surface.sense();
            let coarse = body::sections(&pass, &tool, zone, sense).expect("interferes");
            let bound = coarse.bound;
            let fine = body::sample(
                &pass,
                &tool,
                zone,
                sense,
                body::SAMPLING_ERROR_MM / 4.0,
                false,
            )
            .unwrap();
            let dz = 0.001;
            let a = cut_with(&pass, &tool, Some(coarse), None, surface, q_blank, dz);
            let b = cut_with(&pass, &tool, Some(fine), None, surface, q_blank, dz);
            let planar = cut_with(&pass, &tool, None, None, surface, q_blank, dz);
            assert!(
                (0..a.len()).filter(|&j| a[j] < planar[j] - 1e-3).count() > 100,
                "{surface:?}: the body cut nothing"
            );
            assert!(
                within_axially(&a, &b, bound, dz) && within_axially(&b, &a, bound, dz),
                "{surface:?}"
            );
        }
    }

    /// The skip rule at its edge: the smallest whole-degree clearance that a sloped body
    /// is skipped with cuts exactly what the edge cuts even when its sections are forced,
    /// in a bore (where a sloped flank reaches out by `r (1 - cos phi) tan 15`) and
    /// outside; one degree less is not skipped and does rub.
    #[test]
    fn the_skip_rule_is_exact_at_its_threshold() {
        for (surface, x, q_blank, zone) in [
            (Surface::Outer, 44.0, 25.0, (22.0, 25.0)),
            (Surface::Inner, 26.0, -10.0, (10.0, 13.0)),
        ] {
            let sense = surface.sense();
            // A constant lead, so that every crossing of the column sees the largest.
            let setup = |deg: f64| {
                let (mut pass, tool) = bodied_tr(deg);
                pass.x_start = x;
                pass.x_end = x;
                pass.lead = 24.0;
                pass.lead_change = 0.0;
                (pass, tool)
            };
            let skipped = |deg: f64| {
                let (pass, tool) = setup(deg);
                body::sections(&pass, &tool, zone, sense).is_none()
            };
            let deg = (1..60)
                .map(f64::from)
                .find(|&d| skipped(d))
                .expect("some clearance");
            // How much deeper than the edge the forced sections cut.
            let deeper = |deg: f64| {
                let (pass, tool) = setup(deg);
                let forced =
                    body::sample(&pass, &tool, zone, sense, body::SAMPLING_ERROR_MM, true).unwrap();
                let planar = cut_with(&pass, &tool, None, None, surface, q_blank, 0.01);
                let bodied = cut_with(&pass, &tool, Some(forced), None, surface, q_blank, 0.01);
                (0..planar.len())
                    .map(|j| planar[j] - bodied[j])
                    .fold(0f32, f32::max)
            };
            assert!(
                deeper(deg) == 0.0,
                "{surface:?} at {deg} deg: {}",
                deeper(deg)
            );
            // One degree less rubs (the rule is sharp to a degree, not just safe).
            assert!(!skipped(deg - 1.0));
            assert!(
                deeper(deg - 1.0) > 0.01,
                "{surface:?}: {}",
                deeper(deg - 1.0)
            );
        }
    }
}
