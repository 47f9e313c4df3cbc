//! Compare the cut stock with the ideal thread: signed deviation per dexel, volumes, and
//! the worst gouge and leftover per turn and flank.
//!
//! The deviation of a dexel is the distance, in the axial plane, from the cut surface point
//! `(z, h_cut)` to the exact ideal profile polyline of its generator, signed by the side:
//! **gouge** when the cut lies inside the ideal part (material removed that should stay),
//! **leftover** when it lies outside (stock that should be gone). The true distance is used
//! rather than the radial gap scaled by the local slope: on a square groove a wall moved
//! 0.1 mm axially leaves dexels whose radial gap is the full thread depth, and only the
//! distance to the wall gives 0.1 mm. Distances ignore the helix angle (a tilt of a few
//! degrees, cos 5 deg = 0.996).
//!
//! Volumes are exact per dexel in cylindrical coordinates, `|r1^2 - r2^2|/2 * dtheta * dz`,
//! summed in a fixed order (columns, then cells) so they do not depend on the thread count.

use crate::stock::{Stock, Surface};
use crate::thread::{Flank, ThreadSpec, WidthRule};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Where an extreme value was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extreme {
    /// Normal distance (mm), >= 0.
    pub value: f64,
    /// Angle on the part (rad).
    pub theta: f64,
    /// Axial position (mm).
    pub z: f64,
    /// Turn (1-based; 0 = before the first feature).
    pub turn: i64,
    /// Start.
    pub start: u32,
    /// Part of the profile nearest to the point.
    pub flank: Flank,
}

impl Extreme {
    fn keep_max(slot: &mut Option<Extreme>, e: Extreme) {
        if slot.is_none_or(|s| e.value > s.value) {
            *slot = Some(e);
        }
    }
}

/// Deviation statistics of one turn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TurnDeviation {
    /// Worst gouge per flank ([`Flank::ALL`] order).
    pub gouge: [Option<Extreme>; 4],
    /// Worst leftover per flank.
    pub leftover: [Option<Extreme>; 4],
    /// Gouge volume (mm^3).
    pub gouge_volume: f64,
    /// Leftover volume (mm^3).
    pub leftover_volume: f64,
    /// Dexels compared.
    pub compared: u64,
}

impl TurnDeviation {
    /// Worst gouge over all flanks.
    pub fn max_gouge(&self) -> Option<Extreme> {
        worst(&self.gouge)
    }

    /// Worst leftover over all flanks.
    pub fn max_leftover(&self) -> Option<Extreme> {
        worst(&self.leftover)
    }

    fn merge(&mut self, o: &TurnDeviation) {
        for f in 0..4 {
            if let Some(e) = o.gouge[f] {
                Extreme::keep_max(&mut self.gouge[f], e);
            }
            if let Some(e) = o.leftover[f] {
                Extreme::keep_max(&mut self.leftover[f], e);
            }
        }
        self.gouge_volume += o.gouge_volume;
        self.leftover_volume += o.leftover_volume;
        self.compared += o.compared;
    }
}

fn worst(v: &[Option<Extreme>; 4]) -> Option<Extreme> {
    let mut best = None;
    for e in v.iter().flatten() {
        Extreme::keep_max(&mut best, *e);
    }
    best
}

/// The comparison of a whole stock.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Per (start, turn).
    pub turns: BTreeMap<(u32, i64), TurnDeviation>,
    /// Volume removed from the blank inside the compared region (mm^3).
    pub removed_volume: f64,
    /// Volume the ideal thread removes from the blank in the same region (mm^3).
    pub ideal_removed_volume: f64,
    /// Volume removed anywhere on the grid (mm^3).
    pub total_removed_volume: f64,
    /// Dexels compared.
    pub compared_dexels: u64,
    /// The z range of the compared dexels over all columns (mm, cell centres).
    pub compared_z: Option<(f64, f64)>,
}

impl Deviation {
    /// Worst gouge anywhere.
    pub fn max_gouge(&self) -> Option<Extreme> {
        let mut best = None;
        for t in self.turns.values() {
            if let Some(e) = t.max_gouge() {
                Extreme::keep_max(&mut best, e);
            }
        }
        best
    }

    /// Worst leftover anywhere.
    pub fn max_leftover(&self) -> Option<Extreme> {
        let mut best = None;
        for t in self.turns.values() {
            if let Some(e) = t.max_leftover() {
                Extreme::keep_max(&mut best, e);
            }
        }
        best
    }

    /// Total gouge volume.
    pub fn gouge_volume(&self) -> f64 {
        self.turns.values().map(|t| t.gouge_volume).sum()
    }

    /// Total leftover volume.
    pub fn leftover_volume(&self) -> f64 {
        self.turns.values().map(|t| t.leftover_volume).sum()
    }
}

/// Compare the thread's surface of `stock` with the ideal, inside the axial window
/// `[z_lo, z_hi]` intersected with each generator's thread span.
pub fn compare(stock: &Stock, thread: &ThreadSpec, window: (f64, f64)) -> Deviation {
    let grid = stock.grid;
    let surface = match thread.side {
        crate::thread::Side::External => Surface::Outer,
        crate::thread::Side::Internal => Surface::Inner,
    };
    let Some(q) = stock.surface(surface) else {
        return Deviation::default();
    };
    let q_blank = stock.blank_q(surface);
    let r_blank = surface.sense() * q_blank;
    let cell = grid.dtheta() * grid.dz;
    let z_first = grid.z(0);
    let z_last = grid.z(grid.n_z.saturating_sub(1));
    let columns: Vec<Deviation> = q
        .par_chunks(grid.n_z)
        .enumerate()
        .map(|(i, col)| {
            let theta = grid.theta(i);
            let ideal = thread.column(theta, z_first, z_last);
            let mut out = Deviation::default();
            let sense = surface.sense();
            for &qj in col.iter() {
                let r = sense * (qj as f64 + q_blank);
                out.total_removed_volume += (r_blank * r_blank - r * r).abs() * 0.5 * cell;
            }
            let Some((a, b)) = ideal.span else {
                return out;
            };
            let lo = a.max(window.0);
            let hi = b.min(window.1);
            if hi < lo {
                return out;
            }
            let j0 = ((lo - grid.z0) / grid.dz).ceil().max(0.0) as usize;
            let j1 = (((hi - grid.z0) / grid.dz).floor().max(-1.0) + 1.0) as usize;
            let j1 = j1.min(grid.n_z);
            if j1 <= j0 {
                return out;
            }
            out.compared_z = Some((grid.z(j0), grid.z(j1 - 1)));
            let mut ideal_h = vec![0f32; j1 - j0];
            ideal.fill_heights(grid.z0, grid.dz, j0, &mut ideal_h);
            let depth = thread.depth() as f32;
            let mut groove = 0usize;
            let mut current: Option<((u32, i64), TurnDeviation)> = None;
            let mut seg = ideal.advance(0, grid.z(j0));
            // Flats: the least deviation over the dexels of one root or crest flat of one
            // crossing. A root that is too shallow all across (leftover) or a crest that is
            // too low all across (gouge) is reported at the root (crest) with its radial
            // size, even where a flank is nearer to every dexel (a narrow root under a
            // shallow cut); a deviation over part of a flat only (a ridge, a notch, a wall
            // moved sideways) is the normal distance of its dexels. Each flat is taken
            // whole where the walk enters it (a reduction over its dexels), if the compared
            // range holds all of it, and placed at the middle of its dexels, in the turn
            // of the groove whose region holds that middle.
            let mut flats: Vec<((u32, i64), Extreme)> = Vec::new();
            let depth32 = depth;
            let thread_depth = thread.depth();
            let lean_out = thread.left_angle >= 0.0 && thread.right_angle >= 0.0;
            let mut enter = |seg: usize, k: usize, hint: usize| {
                let Some(root) = ideal.flat(seg) else { return };
                let (a, b) = (ideal.verts[seg].z, ideal.verts[seg + 1].z);
                if a < lo || b > hi {
                    return;
                }
                let target = if root { 0.0 } else { depth32 };
                let end = ((b - grid.z0) / grid.dz).ceil().max(0.0) as usize;
                let mut kb = end.saturating_sub(j0).min(ideal_h.len());
                let mut ka = k.min(kb);
                while ka < kb && ideal_h[ka] != target {
                    ka += 1;
                }
                while kb > ka && ideal_h[kb - 1] != target {
                    kb -= 1;
                }
                if ka == kb {
                    return;
                }
                let cells = &col[j0 + ka..j0 + kb];
                // The height grows with q on both sides: the root's least leftover is at the
                // lowest q, the crest's least gouge at the highest.
                // Plain comparisons (no NaN in the grid) so the loops vectorise.
                let q = if root {
                    cells
                        .iter()
                        .fold(f32::INFINITY, |m, &x| if x < m { x } else { m })
                } else {
                    cells
                        .iter()
                        .fold(f32::NEG_INFINITY, |m, &x| if x > m { x } else { m })
                };
                let h = thread.height(sense * (q as f64 + q_blank));
                let v = if root { h } else { thread.depth() - h };
                if v <= 0.0 {
                    return;
                }
                let z = 0.5 * (grid.z(j0 + ka) + grid.z(j0 + kb - 1));
                let gs = &ideal.grooves;
                let pick = if root {
                    ideal.groove_at(hint, z)
                } else {
                    // A crest lies between two grooves, centred where their regions meet:
                    // it goes with the turn whose measurement takes that tooth, the groove
                    // before it along the helix for equal groove width, the one after it
                    // for equal tooth width (see `measure`).
                    let i = gs.partition_point(|g| g.z_hi <= z);
                    match (i.checked_sub(1), gs.get(i)) {
                        (Some(a), Some(b)) => {
                            let before = gs[a].g.min(b.g) == gs[a].g;
                            let equal_groove = matches!(thread.width, WidthRule::Groove(_));
                            Some(if before == equal_groove { a } else { i })
                        }
                        _ => ideal.groove_at(hint, z),
                    }
                };
                let key = pick.map_or((0, 0), |g| (gs[g].start, gs[g].turn));
                flats.push((
                    key,
                    Extreme {
                        value: v,
                        theta,
                        z,
                        turn: key.1,
                        start: key.0,
                        flank: if root { Flank::Root } else { Flank::Crest },
                    },
                ));
            };
            enter(seg, 0, 0);
            // Where the walk next changes groove (the middle of the tooth to the next one)
            // and segment: checked against z once per dexel.
            let grooves = &ideal.grooves;
            let boundary = |g: usize| {
                grooves
                    .get(g + 1)
                    .map_or(f64::INFINITY, |n| 0.5 * (grooves[g].z_hi + n.z_lo))
            };
            let mut next_groove = boundary(groove);
            let mut key = grooves.first().map_or((0, 0), |g| (g.start, g.turn));
            let seg_end = |seg: usize| {
                if seg + 2 < ideal.verts.len() {
                    ideal.verts[seg + 1].z
                } else {
                    f64::INFINITY
                }
            };
            let mut next_seg = seg_end(seg);
            for (k, &hi32) in ideal_h.iter().enumerate() {
                let j = j0 + k;
                let z = grid.z(j);
                if z >= next_groove {
                    if let Some(g) = ideal.groove_at(groove, z) {
                        groove = g;
                        key = (grooves[g].start, grooves[g].turn);
                    }
                    next_groove = boundary(groove);
                }
                if current.as_ref().is_none_or(|c| c.0 != key) {
                    if let Some((k0, td)) = current.take() {
                        out.turns.entry(k0).or_default().merge(&td);
                    }
                    current = Some((key, TurnDeviation::default()));
                }
                let td = &mut current.as_mut().expect("set above").1;
                let r_cut = sense * (col[j] as f64 + q_blank);
                let h_cut = thread.height(r_cut);
                let h_ideal = hi32 as f64;
                let r_ideal = thread.radius(h_ideal);
                out.compared_dexels += 1;
                td.compared += 1;
                out.removed_volume += (r_blank * r_blank - r_cut * r_cut).abs() * 0.5 * cell;
                let ideal_removed = if sense * (r_blank - r_ideal) > 0.0 {
                    (r_blank * r_blank - r_ideal * r_ideal).abs() * 0.5 * cell
                } else {
                    0.0
                };
                out.ideal_removed_volume += ideal_removed;
                let gap = h_cut - h_ideal;
                // Flats: how far the whole root (crest) of this crossing stays above (below)
                // its ideal height, measured radially.
                if z >= next_seg {
                    seg = ideal.advance(seg, z);
                    next_seg = seg_end(seg);
                    enter(seg, k, groove);
                }
                if gap == 0.0 {
                    continue;
                }
                let vol = (r_ideal * r_ideal - r_cut * r_cut).abs() * 0.5 * cell;
                let slots = if gap < 0.0 {
                    td.gouge_volume += vol;
                    &mut td.gouge
                } else {
                    td.leftover_volume += vol;
                    &mut td.leftover
                };
                // The normal distance never exceeds the radial gap: skip points that
                // cannot beat the smallest maximum so far of the parts they can belong to.
                // With walls that lean outward (or stand upright), a gouge at or above the
                // root's height is never nearest to a root (its foot on the wall lies on
                // the wall), and leftover at or below the crest's never to a crest.
                let cannot = if !lean_out {
                    usize::MAX
                } else if gap < 0.0 && h_cut >= 0.0 {
                    Flank::Root.index()
                } else if gap > 0.0 && h_cut <= thread_depth {
                    Flank::Crest.index()
                } else {
                    usize::MAX
                };
                let g = gap.abs();
                let beaten = |f: usize| f == cannot || slots[f].is_some_and(|e| g <= e.value);
                if (0..4).all(beaten) {
                    continue;
                }
                let (d, flank) = match ideal.nearest(seg, z, h_cut, g) {
                    Some((d, i, end)) => {
                        // At a vertex, deciding the part costs more than the distance:
                        // a point that beats no part's maximum needs no decision.
                        let low = |f: Flank| slots[f.index()].is_some_and(|e| d <= e.value);
                        if end != 0 {
                            let (f1, f2) = ideal.vertex_parts(i, end);
                            if low(f1) && f2.is_some_and(low) {
                                continue;
                            }
                        }
                        (d, ideal.flank_of(i, end, z, h_cut))
                    }
                    None => (g, Flank::Crest),
                };
                let slot = &mut slots[flank.index()];
                if slot.is_none_or(|e| d > e.value) {
                    *slot = Some(Extreme {
                        value: d,
                        theta,
                        z,
                        turn: key.1,
                        start: key.0,
                        flank,
                    });
                }
            }
            if let Some((k0, td)) = current.take() {
                out.turns.entry(k0).or_default().merge(&td);
            }
            for (k0, e) in flats {
                let td = out.turns.entry(k0).or_default();
                let slots = if e.flank == Flank::Root {
                    &mut td.leftover
                } else {
                    &mut td.gouge
                };
                Extreme::keep_max(&mut slots[e.flank.index()], e);
            }
            out
        })
        .collect();
    let mut total = Deviation::default();
    for c in &columns {
        for (k, t) in &c.turns {
            total.turns.entry(*k).or_default().merge(t);
        }
        total.removed_volume += c.removed_volume;
        total.ideal_removed_volume += c.ideal_removed_volume;
        total.total_removed_volume += c.total_removed_volume;
        total.compared_dexels += c.compared_dexels;
        if let Some((a, b)) = c.compared_z {
            total.compared_z = Some(
                total
                    .compared_z
                    .map_or((a, b), |(x, y)| (x.min(a), y.max(b))),
            );
        }
    }
    total
}
