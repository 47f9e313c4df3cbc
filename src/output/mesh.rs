//! Triangle meshes from the dexel stock, the ideal thread, the tool and the passes: the
//! [`Scene`] that the glTF export writes and the renderer draws.
//!
//! **The cut part.** Each kept angular column of the stock becomes a profile polyline in
//! `(z, r)` through its dexel samples, simplified (Douglas-Peucker in the axial plane, the
//! plane in which `compare` measures deviations) to within a set fraction of the mesh
//! tolerance, with vertices forced where the ideal profile has corners so the deviation
//! colours follow the drawing. Neighbouring profiles are joined by a strip of triangles
//! that advances along both in the thread's helical coordinate, so a groove wall at `z` on
//! one column meets the same wall `L dtheta / 2pi` further on the next. End faces close the
//! surface (a fan to the axis for a bar, an annulus for a tube): the mesh is watertight,
//! every edge shared by exactly two triangles, wound counter-clockwise seen from outside.
//!
//! **Error bound.** The mesh stays within `e` (the job's tolerance unless asked otherwise)
//! of the dexel data, in the axial plane. Kept profiles are simplified to `e/2`. Columns
//! are first spread evenly so that the chord of the circle `r (1 - cos(dtheta/2))` plus the
//! twist of a helical wall across one strip, `(L/2pi) (dtheta/2) (depth/r)` axially, stay
//! under `e/4` (these are what the 3D triangles add to the strip's linear interpolation in
//! `(theta, z, r)`). Then every strip is checked against the dexels of the column halfway
//! between its two profiles; where it strays more than `3e/4` (a groove that ends, a wall
//! that leaves through an end face: features that are not helical), the middle column is
//! kept too and both halves are checked again. With `e = 0` every column and every dexel
//! becomes a vertex (`--gltf-full`). The integration tests measure the bound on columns the
//! mesh skipped (sections of the triangles against dexel data the mesh never saw).
//!
//! **Colours** are the developed view's tolerance bands ([`crate::output::plot`]: within,
//! 1-2x, 2-5x, over 5x the tolerance, gouge blues and leftover oranges) of the signed
//! normal deviation at each vertex (an exact dexel sample), so the 3D model, the developed
//! view and the legend agree; the blank's own uncut surface (and the end faces, the blank's
//! ends) is a darker warm grey and a cut outside the compared span a light one. Columns are built in parallel (rayon) and concatenated in column
//! order, so the mesh does not depend on the thread count.

use crate::analysis::compare::{Deviation, Extreme};
use crate::job::Job;
use crate::model::helix::Hand;
use crate::model::pass::Pass;
use crate::model::stock::{Grid, Stock, Surface};
use crate::model::thread::{Side, ThreadSpec};
use crate::output::plot::BLANK;
use crate::output::profile::{
    refined, strip_rungs, surfacers, MeshColumn, Profile, Shape, WholeStock,
};
use crate::output::scene::{Focus, Legend, Mesh, PathKind, Polyline, Scene};
use crate::pipeline::Outcome;
use crate::report::{r6, Report};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Colour of the ideal surface (sRGB): the one colour of the ideal (plots, renders, .glb).
pub(crate) use crate::output::plot::IDEAL_COLOUR;
/// How to build a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneOptions {
    /// Largest distance (mm, in the axial plane) the stock mesh may stray from the dexel
    /// data; `None` takes the job's tolerance; `Some(0.0)` exports every dexel.
    pub mesh_tolerance: Option<f64>,
    /// Also mesh the ideal thread surface.
    pub ideal: bool,
}

/// Build the 3D scene of a simulated job.
pub fn build_scene(job: &Job, out: &Outcome, opts: &SceneOptions) -> Scene {
    let tol = job.sim.tolerance;
    let legend = legend(&out.deviation, tol);
    let e = mesh_tolerance(job, opts);
    let stock = stock_mesh_with(&out.stock, out.edge_stock.as_ref(), &job.thread, legend, e);
    let s = surface(&job.thread);
    let focus = focus(&out.deviation, &out.stock.grid, tol, |i, j| {
        out.stock.radius(s, i, j)
    });
    finish_scene(
        job,
        &Shape::of(&out.stock),
        opts,
        legend,
        stock,
        focus,
        &out.report,
    )
}

/// The stock mesh's tolerance: the asked one, else the job's.
pub(crate) fn mesh_tolerance(job: &Job, opts: &SceneOptions) -> f64 {
    opts.mesh_tolerance.unwrap_or(job.sim.tolerance).max(0.0)
}

/// The scene around a stock mesh: the ideal sheet if asked, the toolpath, the tool, the
/// legend, the focus, and the report's summary.
pub(crate) fn finish_scene(
    job: &Job,
    shape: &Shape,
    opts: &SceneOptions,
    legend: Legend,
    stock: Mesh,
    focus: Option<Focus>,
    report: &Report,
) -> Scene {
    let tol = job.sim.tolerance;
    let e = mesh_tolerance(job, opts);
    let ideal = opts
        .ideal
        .then(|| ideal_sheet(&job.thread, shape, e.max(tol)));
    Scene {
        stock,
        ideal,
        toolpath: match &job.mill {
            Some(mj) => mill_toolpath(mj),
            None => toolpath(
                &job.passes,
                &(job.blank.diameter / 2.0, job.blank.bore / 2.0),
                &job.thread,
            ),
        },
        tool: match &job.mill {
            Some(mj) => cutter_mesh(mj),
            None => crate::output::tool::tool_mesh(job),
        },
        legend,
        focus,
        summary: report.summary_json(legend.scale_mm),
    }
}

/// The colour scale: the tolerance, and the largest deviation (at least twice the
/// tolerance, and as the report rounds it), as the developed view uses.
pub(crate) fn legend(dev: &Deviation, tol: f64) -> Legend {
    let worst = |e: Option<Extreme>| r6(e.map_or(0.0, |e| e.value));
    Legend {
        tolerance_mm: tol,
        scale_mm: (2.0 * tol)
            .max(worst(dev.max_gouge()))
            .max(worst(dev.max_leftover())),
    }
}

/// The worst deviation beyond the tolerance and its dexel (column, cell), as the report
/// rounds it.
pub(crate) fn worst(
    dev: &Deviation,
    grid: &Grid,
    tol: f64,
) -> Option<(&'static str, Extreme, usize, usize)> {
    let (gouge, leftover) = (dev.max_gouge(), dev.max_leftover());
    let value = |e: &Option<Extreme>| r6(e.map_or(0.0, |e| e.value));
    let (kind, e) = if value(&gouge) >= value(&leftover) {
        ("gouge", gouge?)
    } else {
        ("leftover", leftover?)
    };
    if r6(e.value) <= tol {
        return None;
    }
    let i = ((e.theta - grid.theta0) / grid.dtheta())
        .round()
        .rem_euclid(grid.n_theta as f64) as usize
        % grid.n_theta;
    let j = ((e.z - grid.z0) / grid.dz)
        .round()
        .clamp(0.0, (grid.n_z - 1) as f64) as usize;
    Some((kind, e, i, j))
}

/// The worst deviation beyond the tolerance, on the cut surface: the exact extreme's dexel
/// (its value as the report rounds it), `radius(i, j)` the thread surface's radius at
/// column `i`, cell `j`.
pub(crate) fn focus(
    dev: &Deviation,
    grid: &Grid,
    tol: f64,
    radius: impl Fn(usize, usize) -> Option<f64>,
) -> Option<Focus> {
    let (kind, e, i, j) = worst(dev, grid, tol)?;
    let r = radius(i, j)?;
    Some(Focus {
        kind: kind.to_string(),
        value_mm: r6(e.value),
        point: point(r, e.theta, e.z),
        turn: e.turn,
        flank: e.flank.name().to_string(),
        angle_deg: crate::report::r4(e.theta.to_degrees().rem_euclid(360.0)),
        z_mm: r6(e.z),
    })
}

pub(crate) fn surface(thread: &ThreadSpec) -> Surface {
    match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    }
}

fn point(r: f64, theta: f64, z: f64) -> [f32; 3] {
    [(r * theta.cos()) as f32, (r * theta.sin()) as f32, z as f32]
}

/// The kept columns for a mesh tolerance `e`: every column for `e = 0`, else evenly spread
/// columns whose spacing keeps the chord and the twist of a helical wall under `e/2`.
pub(crate) fn kept_columns(shape: &Shape, thread: &ThreadSpec, e: f64) -> Vec<usize> {
    let n = shape.grid.n_theta;
    if e <= 0.0 {
        return (0..n).collect();
    }
    let r_max = shape.outer.max(thread.crest_radius.max(thread.root_radius));
    let r_min = thread
        .crest_radius
        .min(thread.root_radius)
        .max(shape.inner)
        .max(1e-3);
    let law = thread.helix.law;
    let lead = law.lead(0.0).abs().max(law.lead(thread.turns).abs());
    let depth = (thread.crest_radius - thread.root_radius).abs();
    let budget = 0.5 * e;
    // Largest dtheta with r_max (1 - cos(dtheta/2)) + (lead/2pi)(dtheta/2)(depth/r_min)
    // <= budget: the left side grows with dtheta, so bisect.
    let err = |d: f64| r_max * (1.0 - (0.5 * d).cos()) + lead / TAU * 0.5 * d * depth / r_min;
    let (mut lo, mut hi) = (0.0, PI / 8.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if err(mid) <= budget {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let m = ((TAU / lo.max(1e-9)).ceil() as usize).clamp(16.min(n), n);
    (0..m).map(|k| k * n / m).collect()
}

/// The rungs of the strip between two profiles: pairs `(i, j)` of vertices joined by an
/// edge, from `(0, 0)` to the last pair. The walk advances on whichever profile's next
/// vertex comes first in the helical coordinate halfway between the two generators
/// (`shift(z)`: how far a helical feature at `z` moves from `a` to `b`), so a wall meets
/// the same wall on the next generator. Positions within `eps` count as equal (the shift's
/// own error), and equal ones go in the order of their runs of equal z.
pub(crate) fn rungs(
    za: &[f64],
    zb: &[f64],
    shift: impl Fn(f64) -> f64,
    eps: f64,
) -> Vec<(u32, u32)> {
    // The rank of each vertex in its run of equal z (a vertical wall is two vertices at
    // one z): where two next vertices meet within `eps` after the shift, the one earlier
    // in its run goes first, so a wall's top pairs with the other wall's top and its foot
    // with its foot, whatever rounding does to the shift.
    let rank = |z: &[f64], i: usize| {
        let mut k = 0;
        while k < i && z[i - k - 1] == z[i] {
            k += 1;
        }
        k
    };
    let (na, nb) = (za.len(), zb.len());
    let (mut i, mut j) = (0usize, 0usize);
    let mut out = Vec::with_capacity(na + nb);
    out.push((0, 0));
    while i + 1 < na || j + 1 < nb {
        let advance_a = if i + 1 >= na {
            false
        } else if j + 1 >= nb {
            true
        } else {
            let a = za[i + 1] + 0.5 * shift(za[i + 1]);
            let b = zb[j + 1] - 0.5 * shift(zb[j + 1]);
            if (a - b).abs() <= eps {
                rank(za, i + 1) <= rank(zb, j + 1)
            } else {
                a <= b
            }
        };
        if advance_a {
            i += 1;
        } else {
            j += 1;
        }
        out.push((i as u32, j as u32));
    }
    out
}

/// Triangles of a strip from its rungs, `oa`/`ob` the profiles' first vertex indices.
/// Wound outward for an outer surface when `b` is at the larger angle; `flip` reverses.
fn strip_triangles(rungs: &[(u32, u32)], oa: u32, ob: u32, flip: bool, out: &mut Vec<u32>) {
    for w in rungs.windows(2) {
        let ((i, j), (i1, j1)) = (w[0], w[1]);
        let third = if i1 > i { oa + i1 } else { ob + j1 };
        let (p, q) = (oa + i, ob + j);
        if flip {
            out.extend_from_slice(&[p, third, q]);
        } else {
            out.extend_from_slice(&[p, q, third]);
        }
    }
}

/// Axial shift of a feature at `z` from one generator to the next, `dtheta` further on:
/// the thread's local lead over 2 pi, with the sign of its hand.
pub(crate) fn helical_shift(thread: &ThreadSpec, z: f64, dtheta: f64) -> f64 {
    let h = &thread.helix;
    let s = ((z - h.z0) * h.dir)
        .max(0.0)
        .min(h.law.travel(thread.turns).abs());
    let t = h.law.revs_at(s).unwrap_or(0.0);
    let lead = h.law.lead(t).max(0.0);
    let sign = match h.hand() {
        Hand::Right => 1.0,
        Hand::Left => -1.0,
    };
    sign * lead * dtheta / TAU
}

/// The closed, coloured mesh of the cut stock, within `e` (mm) of the dexel data.
pub fn stock_mesh(stock: &Stock, thread: &ThreadSpec, legend: Legend, e: f64) -> Mesh {
    stock_mesh_with(stock, None, thread, legend, e)
}

/// [`stock_mesh`], with the dexels a tool body cut past its edge (deeper than in `edge`,
/// the stock the edges alone cut) in the body-rub colour.
///
/// Columns: evenly spread ones whose chord and twist stay under `e/4`, then, wherever the
/// strip between two kept columns strays more than `3e/4` from the dexels of the column
/// halfway (the end of a groove, a wall leaving through an end face), the middle column
/// too, recursively. Kept profiles are simplified to `e/2`.
pub(crate) fn stock_mesh_with(
    stock: &Stock,
    edge: Option<&Stock>,
    thread: &ThreadSpec,
    legend: Legend,
    e: f64,
) -> Mesh {
    let shape = Shape::of(stock);
    let dexels = WholeStock { stock, edge };
    let sfs = surfacers(&shape, &dexels, thread, legend.tolerance_mm, e);
    let n = shape.grid.n_theta;
    let kept = kept_columns(&shape, thread, 0.5 * e);
    let profiles: Vec<Vec<Profile>> = kept
        .par_iter()
        .map(|&u| sfs.iter().map(|sf| sf.profile(u)).collect())
        .collect();
    let m = kept.len();
    let added: Vec<Vec<MeshColumn>> = (0..m)
        .into_par_iter()
        .map(|k| {
            let ub = if k + 1 < m { kept[k + 1] } else { kept[0] + n };
            refined(&sfs, kept[k], &profiles[k], ub, &profiles[(k + 1) % m])
        })
        .collect();
    let mut columns: Vec<MeshColumn> = Vec::new();
    for ((&u, p), add) in kept.iter().zip(profiles).zip(added) {
        columns.push((u, p));
        columns.extend(add);
    }
    assemble(&shape, thread, columns)
}

/// The watertight mesh from every column's profiles (in column order, each on every
/// surface of the blank): strips between neighbouring columns, end faces.
pub(crate) fn assemble(shape: &Shape, thread: &ThreadSpec, columns: Vec<MeshColumn>) -> Mesh {
    let grid = shape.grid;
    let n = grid.n_theta;
    let window = shape.window();
    let surfaces = shape.surfaces();
    let cols: Vec<usize> = columns.iter().map(|c| c.0).collect();
    let m = cols.len();
    let mut per: Vec<Vec<Profile>> = surfaces.iter().map(|_| Vec::with_capacity(m)).collect();
    for (_, ps) in columns {
        for (s, p) in per.iter_mut().zip(ps) {
            s.push(p);
        }
    }
    let mut mesh = Mesh::default();
    // Per surface: first vertex and vertex count of every column's profile.
    let mut layout: Vec<Vec<(u32, usize)>> = Vec::new();
    for (s, profiles) in surfaces.iter().zip(&per) {
        let mut lay = Vec::with_capacity(m);
        for (p, &i) in profiles.iter().zip(&cols) {
            lay.push((mesh.positions.len() as u32, p.zr.len()));
            let theta = grid.theta(i % n);
            mesh.positions
                .extend(p.zr.iter().map(|&(z, r)| point(r, theta, z)));
            mesh.colors.extend_from_slice(&p.colors);
        }
        let flip = *s == Surface::Inner;
        let strips: Vec<Vec<u32>> = (0..m)
            .into_par_iter()
            .map(|k| {
                let k1 = (k + 1) % m;
                let ub = if k1 == 0 { cols[0] + n } else { cols[k1] };
                let r = strip_rungs(&grid, thread, cols[k], &profiles[k], ub, &profiles[k1]);
                let mut out = Vec::with_capacity(3 * r.len());
                strip_triangles(&r, lay[k].0, lay[k1].0, flip, &mut out);
                out
            })
            .collect();
        for s in strips {
            mesh.indices.extend(s);
        }
        layout.push(lay);
    }
    // End faces: z = window.0 (normal -z) and z = window.1 (normal +z).
    let ring = |lay: &[(u32, usize)], end: bool| -> Vec<u32> {
        lay.iter()
            .map(|&(o, len)| if end { o + len as u32 - 1 } else { o })
            .collect()
    };
    for (end, z) in [(false, window.0), (true, window.1)] {
        let outer = ring(&layout[0], end);
        if layout.len() == 2 {
            let inner = ring(&layout[1], end);
            for k in 0..m {
                let k1 = (k + 1) % m;
                let (o0, o1, i0, i1) = (outer[k], outer[k1], inner[k], inner[k1]);
                if end {
                    mesh.indices.extend_from_slice(&[i0, o0, o1, i0, o1, i1]);
                } else {
                    mesh.indices.extend_from_slice(&[i0, o1, o0, i0, i1, o1]);
                }
            }
        } else {
            let c = mesh.positions.len() as u32;
            mesh.positions.push([0.0, 0.0, z as f32]);
            mesh.colors.push(BLANK);
            for k in 0..m {
                let k1 = (k + 1) % m;
                if end {
                    mesh.indices.extend_from_slice(&[c, outer[k], outer[k1]]);
                } else {
                    mesh.indices.extend_from_slice(&[c, outer[k1], outer[k]]);
                }
            }
        }
    }
    mesh
}

/// The ideal thread surface over the compared span of every kept column (a sheet, not a
/// solid), in one colour. Every column's profile covers the same z range (the union of the
/// compared spans), so the strip between two columns joins the same grooves' corners and
/// is the helicoid they share; a triangle is kept where all its corners lie in their own
/// column's compared span. Where the drawing's thread begins or ends abruptly (its first
/// and last groove) the sheet ends with it instead of joining different grooves.
pub fn ideal_mesh(thread: &ThreadSpec, stock: &Stock, e: f64) -> Mesh {
    ideal_sheet(thread, &Shape::of(stock), e)
}

/// [`ideal_mesh`] on the grid and blank of `shape`.
pub(crate) fn ideal_sheet(thread: &ThreadSpec, shape: &Shape, e: f64) -> Mesh {
    let grid = shape.grid;
    let cols = kept_columns(shape, thread, e);
    let (lo, hi) = (
        grid.z(0) - 0.5 * grid.dz,
        grid.z(grid.n_z - 1) + 0.5 * grid.dz,
    );
    let ideals: Vec<crate::model::thread::ColumnIdeal> = cols
        .par_iter()
        .map(|&i| thread.column(grid.theta(i), lo, hi))
        .collect();
    let spans: Vec<Option<(f64, f64)>> = ideals
        .iter()
        .map(|id| {
            id.span
                .map(|(a, b)| (a.max(lo), b.min(hi)))
                .filter(|(a, b)| a < b)
        })
        .collect();
    let Some((za, zb)) = spans
        .iter()
        .flatten()
        .fold(None, |acc: Option<(f64, f64)>, s| {
            Some(acc.map_or(*s, |(a, b)| (a.min(s.0), b.max(s.1))))
        })
    else {
        return Mesh::default();
    };
    // Each profile: the polyline over [za, zb] with its own span's ends as vertices, and
    // whether each vertex lies in the span.
    let profiles: Vec<Vec<(f64, f64, bool)>> = ideals
        .par_iter()
        .zip(&spans)
        .map(|(id, span)| {
            let mut zs: Vec<f64> = vec![za, zb];
            zs.extend(id.verts.iter().map(|v| v.z).filter(|&z| z > za && z < zb));
            if let Some((a, b)) = span {
                zs.extend([*a, *b]);
            }
            zs.sort_by(f64::total_cmp);
            zs.dedup();
            let mut out: Vec<(f64, f64, bool)> = Vec::with_capacity(zs.len() + 2);
            let mut vi = 0;
            for z in zs {
                let inside = span.is_some_and(|(a, b)| z >= a && z <= b);
                // A vertical wall is two vertices at one z: emit both heights in order.
                let at: Vec<f64> = {
                    while vi < id.verts.len() && id.verts[vi].z < z {
                        vi += 1;
                    }
                    let mut k = vi;
                    let mut hs = Vec::new();
                    while k < id.verts.len() && id.verts[k].z == z {
                        hs.push(id.verts[k].h);
                        k += 1;
                    }
                    if hs.is_empty() {
                        hs.push(id.height_at(z));
                    }
                    hs
                };
                for h in at {
                    let p = (z, thread.radius(h), inside);
                    if out.last().is_none_or(|q| q.0 != p.0 || q.1 != p.1) {
                        out.push(p);
                    }
                }
            }
            out
        })
        .collect();
    let mut mesh = Mesh::default();
    let mut offsets = Vec::with_capacity(cols.len());
    let mut inside = Vec::new();
    for (p, &i) in profiles.iter().zip(&cols) {
        offsets.push(mesh.positions.len() as u32);
        let theta = grid.theta(i);
        mesh.positions
            .extend(p.iter().map(|&(z, r, _)| point(r, theta, z)));
        inside.extend(p.iter().map(|v| v.2));
    }
    mesh.colors = vec![IDEAL_COLOUR; mesh.positions.len()];
    let m = cols.len();
    let flip = thread.side == Side::Internal;
    let mut tris = Vec::new();
    for k in 0..m {
        let k1 = (k + 1) % m;
        if profiles[k].len() < 2 || profiles[k1].len() < 2 {
            continue;
        }
        let mut dtheta = grid.dtheta() * (cols[k1] as f64 - cols[k] as f64);
        if k1 == 0 {
            dtheta += TAU;
        }
        let za: Vec<f64> = profiles[k].iter().map(|v| v.0).collect();
        let zb: Vec<f64> = profiles[k1].iter().map(|v| v.0).collect();
        // The shift is the lead of the reference generator at z: on a variable lead the
        // grooves' own leads differ by at most K per revolution of phase.
        let eps = thread.helix.law.k.abs() * dtheta.abs() / TAU + 1e-9;
        let r = rungs(&za, &zb, |z| helical_shift(thread, z, dtheta), eps);
        tris.clear();
        strip_triangles(&r, offsets[k], offsets[k1], flip, &mut tris);
        for t in tris.chunks_exact(3) {
            if t.iter().all(|&v| inside[v as usize]) {
                mesh.indices.extend_from_slice(t);
            }
        }
    }
    mesh
}

/// A schematic rapid from `a` to `b` (each `(r, theta, z)`), as a lathe makes it in the
/// axial plane: out to the clearance radius at `a`'s angle, along the axis at that radius
/// and angle to `b`'s z, around the clearance circle there (the shorter way, 5 deg a
/// step) to `b`'s angle, and in. Every point but the ends lies on the clearance radius,
/// outside the part (inside the bore), and the axial stretch runs parallel to the part's
/// outline: no view draws it across the part's silhouette (a helix around the part from
/// one end to the other would cross it in every view).
fn rapid(a: (f64, f64, f64), b: (f64, f64, f64), clear: f64) -> Vec<[f32; 3]> {
    let turn = (b.1 - a.1 + PI).rem_euclid(TAU) - PI;
    let steps = ((turn.abs() / 5f64.to_radians()).ceil() as usize).max(1);
    let mut pts = vec![point(a.0, a.1, a.2), point(clear, a.1, a.2)];
    pts.extend((0..=steps).map(|k| {
        let u = k as f64 / steps as f64;
        point(clear, a.1 + u * turn, b.2)
    }));
    pts.push(point(b.0, b.1, b.2));
    pts
}

/// Points per revolution of a drawn pass helix.
const PATH_STEPS_PER_REV: f64 = 72.0;

/// A milling job's cutter as its solid of revolution (48 segments), where the last cutting
/// move ends.
fn cutter_mesh(mj: &crate::MillJob) -> Mesh {
    let Some((_, pm)) = mj
        .moves
        .iter()
        .zip(&mj.path.moves)
        .rev()
        .find(|(m, _)| m.kind != crate::nc::MillKind::Rapid)
        .or_else(|| mj.moves.iter().zip(&mj.path.moves).next_back())
    else {
        return Mesh::default();
    };
    let cutter = &mj.cutters[pm.cutter];
    let [cx, cy, cz] = pm.end;
    let n = 48u32;
    let mut mesh = Mesh::default();
    // Each profile vertex: a pole (on the axis) or a ring of n vertices.
    let mut rings: Vec<(u32, bool)> = Vec::new();
    for &[u, r] in &cutter.profile {
        let first = mesh.positions.len() as u32;
        if r <= 0.0 {
            mesh.positions.push([cx as f32, cy as f32, (cz + u) as f32]);
            rings.push((first, true));
        } else {
            for k in 0..n {
                let a = TAU * k as f64 / n as f64;
                mesh.positions.push([
                    (cx + r * a.cos()) as f32,
                    (cy + r * a.sin()) as f32,
                    (cz + u) as f32,
                ]);
            }
            rings.push((first, false));
        }
    }
    for w in rings.windows(2) {
        let ((i0, p0), (i1, p1)) = (w[0], w[1]);
        for k in 0..n {
            let k1 = (k + 1) % n;
            match (p0, p1) {
                (true, true) => {}
                (true, false) => mesh.indices.extend_from_slice(&[i0, i1 + k1, i1 + k]),
                (false, true) => mesh.indices.extend_from_slice(&[i0 + k, i0 + k1, i1]),
                (false, false) => mesh.indices.extend_from_slice(&[
                    i0 + k,
                    i0 + k1,
                    i1 + k1,
                    i0 + k,
                    i1 + k1,
                    i1 + k,
                ]),
            }
        }
    }
    mesh.colors = vec![crate::output::tool::TOOL_COLOUR; mesh.positions.len()];
    mesh
}

/// A milling path: the tool tip centre along every move (rapids and cutting moves), at
/// most [`PATH_STEPS_PER_REV`] points per revolution of an arc.
fn mill_toolpath(mj: &crate::MillJob) -> Vec<Polyline> {
    use crate::kernel::mill::Motion;
    mj.path
        .moves
        .iter()
        .zip(&mj.moves)
        .map(|(m, nc)| {
            let steps = match m.motion {
                Motion::Line => 1,
                Motion::Arc { sweep, .. } => {
                    ((sweep.abs() / TAU * PATH_STEPS_PER_REV).ceil() as usize).clamp(2, 1 << 16)
                }
            };
            let points = (0..=steps)
                .map(|k| {
                    let p = m.at(k as f64 / steps as f64);
                    point(p[0].hypot(p[1]), p[1].atan2(p[0]), p[2])
                })
                .collect();
            Polyline {
                kind: if nc.kind == crate::nc::MillKind::Rapid {
                    PathKind::Rapid
                } else {
                    PathKind::Feed
                },
                points,
            }
        })
        .collect()
}

/// The toolpath: the reference point along every pass (feed), and schematic rapids
/// between passes: out to a clearance radius 1 mm beyond the blank, around it to the next
/// start and in. A rapid has no spindle phase (the part turns under it); it is drawn from
/// the angle where one pass ends to the angle where the next begins.
pub fn toolpath(passes: &[Pass], blank: &(f64, f64), thread: &ThreadSpec) -> Vec<Polyline> {
    let mut out = Vec::new();
    let clear = match thread.side {
        Side::External => blank.0 + 1.0,
        Side::Internal => (blank.1 - 1.0).max(0.0),
    };
    let mut prev_end: Option<(f64, f64, f64)> = None; // (r, theta, z)
    for p in passes {
        let Some(t_end) = p.revolutions() else {
            continue;
        };
        let h = p.helix();
        let steps = ((t_end * PATH_STEPS_PER_REV).ceil() as usize).clamp(1, 1 << 16);
        let pose = |t: f64| {
            let z = h.z(t);
            (p.radius_at(z), h.theta0 - h.spin * TAU * t, z)
        };
        let start = pose(0.0);
        if let Some(e) = prev_end {
            out.push(Polyline {
                kind: PathKind::Rapid,
                points: rapid(e, start, clear),
            });
        }
        let points: Vec<[f32; 3]> = (0..=steps)
            .map(|k| {
                let (r, th, z) = pose(t_end * k as f64 / steps as f64);
                point(r, th, z)
            })
            .collect();
        out.push(Polyline {
            kind: PathKind::Feed,
            points,
        });
        prev_end = Some(pose(t_end));
    }
    out
}
