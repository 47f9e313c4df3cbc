//! The stock mesh's profiles: the dexels of one column of one surface (`Samples`, read
//! in place from the whole stock or from the columns a streamed run holds, [`Dexels`]),
//! simplified (Douglas-Peucker) into a [`Profile`] with the deviation colours, and the
//! refinement that adds a skipped column where the strip between two profiles strays from
//! its dexels ([`refined`]). `mesh` spreads the kept columns and assembles the strips;
//! the same functions serve the full-grid and the streamed meshes (`output::stream`), so
//! both give the same bytes.

use crate::model::geom::segment_distance2;
use crate::model::stock::{Grid, Stock, Surface};
use crate::model::thread::ThreadSpec;
use crate::output::mesh::{helical_shift, rungs, surface};
use crate::output::plot::{signed_deviation, surface_colour, BODY_RUB};
use glam::DVec2;

/// One profile of the mesh: the kept samples of a column.
#[derive(Clone, Debug)]
pub(crate) struct Profile {
    /// (z, r) of each vertex, z increasing.
    pub(crate) zr: Vec<(f64, f64)>,
    pub(crate) colors: Vec<[u8; 3]>,
}

/// Douglas-Peucker on the polyline `(z_j, r_j)` between forced indices: keep the fewest
/// samples so that every sample lies within `eps` of the kept polyline (2D distance).
///
/// A stretch whose samples all have one stored value is flat: every sample lies on the
/// chord (the foot's radius is the chord's exactly, `r + u 0`) up to the rounding of its z,
/// a few ulps of the largest |z|, so its squared distance is at most `(8 eps_f64 z)^2`,
/// far under `eps^2` when `eps` exceeds `1e-9 (1 + |z|)`: no sample can split it, and it
/// is not searched.
fn simplify(pts: Samples<'_>, forced: &[usize], eps: f64, out: &mut Vec<usize>) {
    out.clear();
    let z_max = if pts.is_empty() {
        0.0
    } else {
        pts.at(0).0.abs().max(pts.at(pts.len() - 1).0.abs())
    };
    let flat_ok = eps > 1e-9 * (1.0 + z_max);
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for w in forced.windows(2) {
        out.push(w[0]);
        stack.push((w[0], w[1]));
        while let Some((a, b)) = stack.pop() {
            if b <= a + 1 {
                continue;
            }
            if flat_ok && pts.q[a + 1..=b].iter().all(|&v| v == pts.q[a]) {
                continue;
            }
            let (pa, pb) = (pts.at(a), pts.at(b));
            let (worst, at) = (a + 1..b)
                .map(|j| (seg_dist2(pts.at(j), pa, pb), j))
                .fold((0.0, a), |m, x| if x.0 > m.0 { x } else { m });
            if worst > eps * eps {
                stack.push((at, b));
                stack.push((a, at));
                out.push(at);
            }
        }
    }
    if let Some(&last) = forced.last() {
        out.push(last);
    }
    out.sort_unstable();
    out.dedup();
}

/// The raw dexel polyline `(z, r)` of one column of one surface, each sample computed
/// when it is read.
#[derive(Clone, Copy)]
struct Samples<'a> {
    q: &'a [f32],
    grid: Grid,
    sense: f64,
    q0: f64,
}

impl<'a> Samples<'a> {
    fn len(&self) -> usize {
        self.q.len()
    }

    fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// Sample `j`.
    #[inline]
    fn at(&self, j: usize) -> (f64, f64) {
        (self.grid.z(j), self.sense * (self.q[j] as f64 + self.q0))
    }

    #[cfg(test)]
    fn iter(self) -> impl Iterator<Item = (f64, f64)> + 'a {
        (0..self.q.len()).map(move |j| self.at(j))
    }
}

/// Squared distance from `p` to the segment `[a, b]` in the axial plane.
fn seg_dist2(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    segment_distance2(DVec2::from(p), DVec2::from(a), DVec2::from(b))
}

/// Whether some sample of `pts` lies further than `limit` from the polyline `line` (both
/// in the axial plane; `line` need not be monotone in z). Segments are binned by z; a
/// sample is first tried against the segments around its z (walking along `line` as the
/// samples advance in z) whose bins hold its own, and only when none of them is near does
/// it look through its bin (the segments whose bins hold it, indexed when many samples
/// need them): the answer is the bins' alone.
fn strays(line: &[(f64, f64)], pts: Samples<'_>, limit: f64) -> bool {
    if line.len() < 2 || pts.is_empty() {
        return !pts.is_empty();
    }
    // The samples' z increase with their index: their extremes are the first and last.
    let (z_first, z_last) = (pts.grid.z(0), pts.grid.z(pts.len() - 1));
    let lo = line.iter().map(|p| p.0).fold(z_first.min(z_last), f64::min) - limit;
    let hi = line.iter().map(|p| p.0).fold(z_first.max(z_last), f64::max) + limit;
    let width = ((hi - lo) / (2 * pts.len()).max(1) as f64)
        .max(limit)
        .max(1e-9);
    let nb = (((hi - lo) / width).ceil() as usize).max(1);
    let bin = |z: f64| (((z - lo) / width) as usize).min(nb - 1);
    // The z span of each segment, widened by the limit: its bins are those of its ends
    // (`bin` is monotone), so a sample inside it is in one of them.
    let spans: Vec<(f64, f64)> = line
        .windows(2)
        .map(|w| (w[0].0.min(w[1].0) - limit, w[0].0.max(w[1].0) + limit))
        .collect();
    let range = |k: usize| bin(spans[k].0)..=bin(spans[k].1);
    let segments = spans.len();
    // Segments per bin, in one flat array (counts, prefix sums, fill).
    let index = || {
        let mut start = vec![0u32; nb + 1];
        for k in 0..segments {
            for b in range(k) {
                start[b + 1] += 1;
            }
        }
        for b in 0..nb {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut segs = vec![0u32; start[nb] as usize];
        for k in 0..segments {
            for b in range(k) {
                segs[fill[b] as usize] = k as u32;
                fill[b] += 1;
            }
        }
        (start, segs)
    };
    let mut bins: Option<(Vec<u32>, Vec<u32>)> = None;
    let mut ranges: Option<Vec<std::ops::RangeInclusive<usize>>> = None;
    let mut slow = 0;
    let l2 = limit * limit;
    let near = |p: (f64, f64), k: usize| seg_dist2(p, line[k], line[k + 1]) <= l2;
    // Whether sample `p` strays, `k` walking along the line as the samples advance.
    let mut stray = |p: (f64, f64), k: &mut usize| -> bool {
        while *k + 1 < segments && line[*k + 1].0 < p.0 {
            *k += 1;
        }
        // The segment whose z span holds the sample, then its neighbours.
        let around = [
            Some(*k),
            (*k + 1 < segments).then_some(*k + 1),
            k.checked_sub(1),
        ];
        if around
            .into_iter()
            .flatten()
            .any(|k| spans[k].0 <= p.0 && p.0 <= spans[k].1 && near(p, k))
        {
            return false;
        }
        // The segments of the sample's bin: the first few times by their bins (often the
        // first such sample strays), then through the index.
        let b = bin(p.0);
        slow += 1;
        let near_one = if slow <= SCAN_SAMPLES {
            let ranges = ranges.get_or_insert_with(|| (0..segments).map(range).collect());
            ranges
                .iter()
                .enumerate()
                .any(|(k, r)| r.contains(&b) && near(p, k))
        } else {
            let (start, segs) = bins.get_or_insert_with(index);
            segs[start[b] as usize..start[b + 1] as usize]
                .iter()
                .any(|&k| near(p, k as usize))
        };
        !near_one
    };
    // Samples with one stored value (one radius) in a row along a segment lie within the
    // limit of it when the row's two ends do, with a margin over the rounding (the
    // distance to a segment is convex along the row): such rows are passed at once, the
    // other samples one by one.
    let l2_row = (limit * (1.0 - 1e-9)) * (limit * (1.0 - 1e-9));
    let n = pts.len();
    let mut k = 0;
    let mut i = 0;
    while i < n {
        let pa = pts.at(i);
        while k + 1 < segments && line[k + 1].0 < pa.0 {
            k += 1;
        }
        let (s0, s1) = (line[k], line[k + 1]);
        if s0.0 <= pa.0 && pa.0 <= s1.0 && seg_dist2(pa, s0, s1) <= l2_row {
            // The last sample of the row on this segment's z span.
            let bits = pts.q[i].to_bits();
            // The last sample at or before the segment's end (an estimate by division,
            // settled on the grid's own z).
            let g = &pts.grid;
            let est = ((s1.0 - g.z0) / g.dz).max(0.0);
            let mut end = if est < (n - 1) as f64 {
                est as usize
            } else {
                n - 1
            }
            .max(i);
            while end > i && g.z(end) > s1.0 {
                end -= 1;
            }
            while end + 1 < n && g.z(end + 1) <= s1.0 {
                end += 1;
            }
            let last = i + pts.q[i + 1..=end]
                .iter()
                .take_while(|v| v.to_bits() == bits)
                .count();
            if last > i + 1 && seg_dist2(pts.at(last), s0, s1) <= l2_row {
                i = last + 1;
                continue;
            }
            // Not passed at once: the row's samples one by one (not scanned again).
            for j in i..=last {
                if stray(pts.at(j), &mut k) {
                    return true;
                }
            }
            i = last + 1;
            continue;
        }
        if stray(pa, &mut k) {
            return true;
        }
        i += 1;
    }
    false
}

/// Samples of a column checked against every segment's bins before the bins are indexed.
const SCAN_SAMPLES: usize = 32;

/// Where the profiles read the dexels: the whole stock, or the columns a streamed run
/// holds (`output::stream`).
pub(crate) trait Dexels: Sync {
    /// The stored values (`q - q_blank`) of surface `s` at unwrapped column `u`.
    fn column(&self, s: Surface, u: usize) -> &[f32];
    /// The edges' cut there, when tool bodies were swept.
    fn edge(&self, s: Surface, u: usize) -> Option<&[f32]>;
}

/// The whole stock (and the edges' cut) as [`Dexels`].
pub(crate) struct WholeStock<'a> {
    pub(crate) stock: &'a Stock,
    pub(crate) edge: Option<&'a Stock>,
}

impl Dexels for WholeStock<'_> {
    fn column(&self, s: Surface, u: usize) -> &[f32] {
        let (n, n_z) = (self.stock.grid.n_theta, self.stock.grid.n_z);
        let i = u % n;
        &self.stock.surface(s).expect("surface present")[i * n_z..(i + 1) * n_z]
    }

    fn edge(&self, s: Surface, u: usize) -> Option<&[f32]> {
        let (n, n_z) = (self.stock.grid.n_theta, self.stock.grid.n_z);
        let i = u % n;
        self.edge
            .and_then(|e| e.surface(s))
            .map(|q| &q[i * n_z..(i + 1) * n_z])
    }
}

/// The grid and the blank's radii: what the mesh's columns and window depend on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub(crate) grid: Grid,
    pub(crate) outer: f64,
    pub(crate) inner: f64,
}

impl Shape {
    pub(crate) fn of(stock: &Stock) -> Shape {
        Shape {
            grid: stock.grid,
            outer: stock.blank_outer,
            inner: stock.blank_inner,
        }
    }

    /// The surfaces the blank has.
    pub(crate) fn surfaces(&self) -> Vec<Surface> {
        let mut v = vec![Surface::Outer];
        if self.inner > 0.0 {
            v.push(Surface::Inner);
        }
        v
    }

    fn blank_q(&self, s: Surface) -> f64 {
        match s {
            Surface::Outer => self.outer,
            Surface::Inner => -self.inner,
        }
    }

    /// The axial span of the cells.
    pub(crate) fn window(&self) -> (f64, f64) {
        let grid = self.grid;
        (
            grid.z(0) - 0.5 * grid.dz,
            grid.z(grid.n_z - 1) + 0.5 * grid.dz,
        )
    }
}

/// What the profiles of one surface are built from.
pub(crate) struct Surfacer<'a> {
    grid: Grid,
    /// The surface's blank value (`q_blank`).
    q0: f64,
    dexels: &'a dyn Dexels,
    thread: &'a ThreadSpec,
    s: Surface,
    compared: bool,
    /// The tolerance (the colours' bands).
    tol: f64,
    e: f64,
    window: (f64, f64),
}

/// A surfacer per surface of the blank (outer first).
pub(crate) fn surfacers<'a>(
    shape: &Shape,
    dexels: &'a dyn Dexels,
    thread: &'a ThreadSpec,
    tol: f64,
    e: f64,
) -> Vec<Surfacer<'a>> {
    shape
        .surfaces()
        .into_iter()
        .map(|s| Surfacer {
            grid: shape.grid,
            q0: shape.blank_q(s),
            dexels,
            thread,
            s,
            compared: s == surface(thread),
            tol,
            e,
            window: shape.window(),
        })
        .collect()
}

impl Surfacer<'_> {
    /// The raw dexel polyline `(z, r)` of unwrapped column `u`.
    fn points(&self, u: usize) -> Samples<'_> {
        Samples {
            q: self.dexels.column(self.s, u),
            grid: self.grid,
            sense: self.s.sense(),
            q0: self.q0,
        }
    }

    /// The profile of unwrapped column `u`, simplified to `e/2` (every sample for `e = 0`).
    pub(crate) fn profile(&self, u: usize) -> Profile {
        let grid = self.grid;
        let i = u % grid.n_theta;
        let pts = self.points(u);
        let ideal = self.compared.then(|| {
            self.thread
                .column(grid.theta(i), self.window.0, self.window.1)
        });
        let n = pts.len();
        let keep: Vec<usize> = if self.e <= 0.0 {
            (0..n).collect()
        } else {
            // Forced: both ends, the samples either side of every ideal corner (colours
            // follow the drawing), and one every 2 mm (colour interpolation stays local).
            let mut forced = vec![0, n - 1];
            if let Some(id) = &ideal {
                for v in &id.verts {
                    let x = (v.z - grid.z0) / grid.dz;
                    if x > -1.0 && x < n as f64 {
                        forced.push(x.floor().max(0.0) as usize);
                        forced.push((x.ceil() as usize).min(n - 1));
                    }
                }
            }
            let step = ((2.0 / grid.dz).ceil() as usize).max(1);
            forced.extend((0..n).step_by(step));
            forced.sort_unstable();
            forced.dedup();
            let mut keep = Vec::new();
            simplify(pts, &forced, 0.5 * self.e, &mut keep);
            keep
        };
        let tol = self.tol;
        // Dexels a tool body cut past its edge get their own colour.
        let edge = self.dexels.edge(self.s, u);
        let own = self.dexels.column(self.s, u);
        let rubbed = |j: usize| {
            edge.is_some_and(|e| self.s.sense() * (e[j] as f64 - own[j] as f64) > RUB_MM)
        };
        let colors = keep
            .iter()
            .map(|&j| {
                if rubbed(j) {
                    return BODY_RUB;
                }
                let d = ideal.as_ref().and_then(|id| {
                    let (z, r) = pts.at(j);
                    signed_deviation(self.thread, id, z, r)
                });
                // The blank is stored as zero: any other value was cut.
                surface_colour(d, own[j] != 0.0, tol)
            })
            .collect();
        let mut zr: Vec<(f64, f64)> = keep.iter().map(|&j| pts.at(j)).collect();
        // The first and last samples stand for their whole cells: the surface reaches the
        // window's ends.
        zr[0].0 = self.window.0;
        let last = zr.len() - 1;
        zr[last].0 = self.window.1;
        Profile { zr, colors }
    }

    /// Columns to add between kept unwrapped columns `ua < ub` so that the strip's section
    /// at the middle skipped column stays within `limit` of that column's dexels, checked
    /// again on both halves after a split.
    fn refine(
        &self,
        ua: usize,
        a: &Profile,
        ub: usize,
        b: &Profile,
        limit: f64,
    ) -> Vec<(usize, Profile)> {
        if ub <= ua + 1 {
            return Vec::new();
        }
        let um = (ua + ub) / 2;
        let u = (um - ua) as f64 / (ub - ua) as f64;
        let section: Vec<(f64, f64)> = strip_rungs(&self.grid, self.thread, ua, a, ub, b)
            .iter()
            .map(|&(i, j)| {
                let (p, q) = (a.zr[i as usize], b.zr[j as usize]);
                (p.0 + u * (q.0 - p.0), p.1 + u * (q.1 - p.1))
            })
            .collect();
        if !strays(&section, self.points(um), limit) {
            return Vec::new();
        }
        let m = self.profile(um);
        let mut out = self.refine(ua, a, um, &m, limit);
        let right = self.refine(um, &m, ub, b, limit);
        out.push((um, m));
        out.extend(right);
        out
    }
}

/// The strip's rungs between unwrapped columns `ua < ub`.
pub(crate) fn strip_rungs(
    grid: &Grid,
    thread: &ThreadSpec,
    ua: usize,
    a: &Profile,
    ub: usize,
    b: &Profile,
) -> Vec<(u32, u32)> {
    let theta = |u: usize| grid.theta0 + grid.dtheta() * u as f64;
    let dtheta = theta(ub) - theta(ua);
    let za: Vec<f64> = a.zr.iter().map(|v| v.0).collect();
    let zb: Vec<f64> = b.zr.iter().map(|v| v.0).collect();
    rungs(&za, &zb, |z| helical_shift(thread, z, dtheta), 0.0)
}

/// A mesh column: its (unwrapped) index and its profile on every surface of the blank.
pub(crate) type MeshColumn = (usize, Vec<Profile>);

/// The columns the refinement adds between kept unwrapped columns `ua < ub` (profiles
/// `a` and `b`, one per surface), in column order: wherever a surface's strip strays more
/// than `3e/4` from the dexels of a skipped column (recursively), on every surface (both
/// surfaces of a tube use the same columns: the end annuli join them pairwise).
pub(crate) fn refined(
    sfs: &[Surfacer<'_>],
    ua: usize,
    a: &[Profile],
    ub: usize,
    b: &[Profile],
) -> Vec<MeshColumn> {
    let Some(e) = sfs.first().map(|sf| sf.e).filter(|&e| e > 0.0) else {
        return Vec::new();
    };
    let mut found: Vec<Vec<(usize, Profile)>> = sfs
        .iter()
        .enumerate()
        .map(|(s, sf)| sf.refine(ua, &a[s], ub, &b[s], 0.75 * e))
        .collect();
    let mut cols: Vec<usize> = found.iter().flatten().map(|c| c.0).collect();
    cols.sort_unstable();
    cols.dedup();
    let mut out: Vec<MeshColumn> = cols.iter().map(|&u| (u, Vec::new())).collect();
    for (sf, mine) in sfs.iter().zip(&mut found) {
        let mut mine = std::mem::take(mine).into_iter().peekable();
        for (u, ps) in &mut out {
            let p = mine.next_if(|c| c.0 == *u).map(|(_, p)| p);
            ps.push(p.unwrap_or_else(|| sf.profile(*u)));
        }
    }
    out
}

/// A body cut deeper than this past its edge (mm) is coloured as a rub.
const RUB_MM: f64 = 1e-3;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Rng;

    /// `strays` on stored values `q` (radius `q + 9.5`) against the definition, some sample
    /// farther than `limit` from every segment; the answer.
    fn strays_as_defined(
        line: &[(f64, f64)],
        q: &[f32],
        grid: Grid,
        limit: f64,
        case: usize,
    ) -> bool {
        let pts = Samples {
            q,
            grid,
            sense: 1.0,
            q0: 9.5,
        };
        let l2 = limit * limit;
        let want = pts
            .iter()
            .any(|p| line.windows(2).all(|w| seg_dist2(p, w[0], w[1]) > l2));
        assert_eq!(strays(line, pts, limit), want, "case {case}");
        want
    }

    /// Rows of one stored value along long segments (a flat cut under a level or sloping
    /// stretch of the strip), off the line by 0.5 to 1.25 times the limit: `strays` (which
    /// passes a row at once when both its ends are near one segment) against the
    /// definition, sample by sample.
    #[test]
    fn rows_along_long_segments_against_the_definition() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut yes, mut no) = (0, 0);
        for case in 0..300 {
            let n_z = 400;
            let grid = Grid {
                n_theta: 8,
                n_z,
                theta0: 0.0,
                z0: 0.0,
                dz: 0.01,
            };
            let limit = 0.01;
            // Four segments, level or sloping by up to 0.02 (rows meet them at an angle).
            let mut line = vec![(-0.05, 10.0)];
            for s in 1..=4 {
                let slope = if case % 2 == 0 {
                    0.0
                } else {
                    rng.range(-0.02, 0.02)
                };
                let (z, r) = *line.last().unwrap();
                let z1 = if s == 4 { 4.05 } else { z + 1.0 };
                line.push((z1, r + slope * (z1 - z)));
            }
            let base = |z: f64| {
                line.windows(2)
                    .find(|w| w[0].0 <= z && z <= w[1].0)
                    .map(|w| w[0].1 + (z - w[0].0) / (w[1].0 - w[0].0) * (w[1].1 - w[0].1))
                    .unwrap()
            };
            let spread = if case % 4 < 2 { 1.25 } else { 0.98 };
            let mut q = vec![0f32; n_z];
            let mut j = 0;
            while j < n_z {
                let len = 1 + (rng.next() * 120.0) as usize;
                let off =
                    rng.range(0.5, spread) * limit * if rng.next() < 0.5 { 1.0 } else { -1.0 };
                let v = (base(grid.z(j)) + off - 9.5) as f32;
                for c in q.iter_mut().skip(j).take(len) {
                    *c = v;
                }
                j += len;
            }
            if strays_as_defined(&line, &q, grid, limit, case) {
                yes += 1;
            } else {
                no += 1;
            }
        }
        assert!(yes > 30 && no > 30, "{yes} straying, {no} not");
    }

    /// `strays` (the walk along the line, the bins scanned, then indexed) against the
    /// definition: some sample farther than the limit from every segment. Random
    /// polylines with vertical walls and steps back in z (where the walk's segment is not
    /// the near one and the bins decide), random columns near and off them.
    #[test]
    fn strays_is_the_distance_to_every_segment() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut yes, mut no) = (0, 0);
        for case in 0..400 {
            let n_z = 50 + (rng.next() * 400.0) as usize;
            let grid = Grid {
                n_theta: 8,
                n_z,
                theta0: 0.0,
                z0: rng.range(-5.0, 5.0),
                dz: rng.range(0.005, 0.05),
            };
            let (z_lo, z_hi) = (grid.z(0), grid.z(n_z - 1));
            // The line: z mostly increasing, with walls (equal z) and steps back.
            let mut line = vec![(z_lo - rng.range(0.0, 0.1), rng.range(9.0, 10.0))];
            while line.last().unwrap().0 < z_hi {
                let (z, _) = *line.last().unwrap();
                let step = match (rng.next() * 6.0) as u32 {
                    0 => 0.0,
                    1 if case % 2 == 0 => -rng.range(0.0, 0.3),
                    _ => rng.range(0.0, 0.4),
                };
                line.push((z + step, rng.range(9.0, 10.0)));
            }
            let limit = rng.range(0.001, 0.05);
            // The column: each sample on the line (the nearest vertex's radius, or the
            // radius interpolated along the first segment over its z) plus noise; a few
            // samples far off in some cases.
            let base = |z: f64| {
                line.windows(2)
                    .find(|w| w[0].0 <= z && z <= w[1].0 && w[1].0 > w[0].0)
                    .map(|w| w[0].1 + (z - w[0].0) / (w[1].0 - w[0].0) * (w[1].1 - w[0].1))
                    .unwrap_or(line[0].1)
            };
            let noise = if case % 8 >= 6 {
                0.0
            } else {
                [0.0, 0.5, 1.0, 3.0][case % 4] * limit
            };
            let mut q: Vec<f32> = (0..n_z)
                .map(|j| (base(grid.z(j)) + rng.range(-noise, noise) - 9.5) as f32)
                .collect();
            // Half the cases hold values in rows (a flat cut): rows near the line at
            // both ends, across its vertices and walls, and off it.
            if case % 8 >= 4 {
                for j in 1..n_z {
                    if rng.next() < 0.93 {
                        q[j] = q[j - 1];
                    } else if case % 8 >= 6 {
                        // A new row off the line by about the limit.
                        let off = rng.range(0.5, 1.25) * limit;
                        let off = if rng.next() < 0.5 { off } else { -off };
                        q[j] = (base(grid.z(j)) + off - 9.5) as f32;
                    }
                }
            }
            if strays_as_defined(&line, &q, grid, limit, case) {
                yes += 1;
            } else {
                no += 1;
            }
        }
        assert!(yes > 50 && no > 50, "{yes} straying, {no} not");
    }
}
