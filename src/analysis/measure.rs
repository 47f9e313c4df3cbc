//! Inspection along generators: lead, groove width and tooth width at the pitch line.
//!
//! An inspector measures a thread along a generator (a line of the part at one angle):
//! where the flanks cross the pitch diameter, how far apart the same-side flanks of
//! neighbouring turns are (the lead, or the pitch for one start), and how wide the groove
//! and the tooth are there. vpcut does this on a *measurement column*: the generator cut
//! again by the same sweep kernel at a fine axial spacing (default 0.5 um), so the flank
//! crossings, found by linear interpolation between cells, are within a quarter of a
//! micrometre even on the vertical walls of a square thread. The ideal is measured in
//! exactly the same way, on the ideal profile sampled at the same cells.
//!
//! Features are the grooves (equal groove width) or the teeth (equal tooth width): the
//! things centred on the pitch helix. Turn `n` runs from the feature at `t = n-1` to the
//! one at `t = n`; its lead is the mean of the two same-side flank spacings, its groove
//! and tooth are the pair that starts at its first feature.

use crate::analysis::gauge::GaugeColumn;
use crate::kernel::sweep::{sweep_column, Column};
use crate::model::pass::Pass;
use crate::model::stock::Surface;
use crate::model::thread::{Feature, Side, ThreadSpec, WidthRule};
use crate::model::tool::Tool;

/// An interval of the pitch line inside a feature, `lo < hi` in z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Interval {
    /// -z end (the feature's left flank at the pitch line).
    pub lo: f64,
    /// +z end (the right flank).
    pub hi: f64,
    /// The left end is the end of the measured window, not a flank.
    pub lo_open: bool,
    /// The right end is the end of the measured window, not a flank.
    pub hi_open: bool,
}

/// The smallest `f32` whose value is above `level` (`strict`) or at least `level`: for an
/// `f32` `x` (not NaN), `x as f64 > level` is `x >= above(level, true)` and
/// `x as f64 >= level` is `x >= above(level, false)` (the conversion is exact and
/// monotone). `level` is not NaN.
fn above(level: f64, strict: bool) -> f32 {
    let beyond = |x: f32| {
        if strict {
            x as f64 > level
        } else {
            x as f64 >= level
        }
    };
    // The nearest f32 is within half a step of `level`: the answer is it or a neighbour.
    let c = level as f32;
    if beyond(c) {
        let d = step(c, false);
        if beyond(d) {
            d
        } else {
            c
        }
    } else {
        step(c, true)
    }
}

/// The next `f32` up (towards +inf) or down from `x` (`f32::next_up`/`next_down`, which
/// came after the crate's minimum Rust version); NaN and the infinity in the direction
/// stay.
fn step(x: f32, up: bool) -> f32 {
    if x.is_nan() || x == if up { f32::INFINITY } else { f32::NEG_INFINITY } {
        return x;
    }
    if x == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let b = x.to_bits();
    // Away from zero the bits count up, towards it down (sign and magnitude).
    f32::from_bits(if (x > 0.0) == up { b + 1 } else { b - 1 })
}

/// Cells of one state skipped at a time: a chunk's cells are tested together (no branch
/// per cell: vectorised).
const SCAN_CHUNK: usize = 32;

/// The first cell from `from` on whose state (`x >= t` where `ge`, else `x < t`) is not
/// `state`, or `h.len()`.
fn next_change(h: &[f32], from: usize, t: f32, ge: bool, state: bool) -> usize {
    let test = |x: f32| if ge { x >= t } else { x < t };
    let mut j = from;
    while let Some(chunk) = h.get(j..j + SCAN_CHUNK) {
        let changed = chunk.iter().fold(false, |any, &x| any | (test(x) != state));
        if changed {
            break;
        }
        j += SCAN_CHUNK;
    }
    while j < h.len() && test(h[j]) == state {
        j += 1;
    }
    j
}

/// Intervals where the column is inside a feature (above `level` for a tooth, below it for
/// a groove) on a sampled column, with flank crossings at `level` found by linear
/// interpolation. The cells' states are one `f32` comparison each with a threshold that
/// gives exactly the `f64` comparison's answer ([`above`]), so runs of one state are
/// skipped a chunk at a time; the crossings are computed as before.
pub(crate) fn intervals(h: &[f32], z0: f64, dz: f64, level: f64, tooth: bool) -> Vec<Interval> {
    let mut out = Vec::new();
    if level.is_nan() {
        return out;
    }
    // Inside: `x as f64 > level` (tooth), or `x as f64 < level` (groove), that is not
    // `x as f64 >= level`; NaN cells are outside either way.
    let (t, ge) = if tooth {
        (above(level, true), true)
    } else {
        (above(level, false), false)
    };
    let cross = |j: usize| {
        // Crossing between cells j-1 and j.
        let (a, b) = (h[j - 1] as f64, h[j] as f64);
        let u = if b != a { (level - a) / (b - a) } else { 0.5 };
        z0 + (j as f64 - 1.0 + u.clamp(0.0, 1.0)) * dz
    };
    let mut open: Option<(f64, bool)> = None;
    let mut j = 0;
    loop {
        let k = next_change(h, j, t, ge, open.is_some());
        if k >= h.len() {
            break;
        }
        match open {
            None => {
                open = Some(if k == 0 {
                    (z0, true)
                } else {
                    (cross(k), false)
                });
            }
            Some((lo, lo_open)) => {
                out.push(Interval {
                    lo,
                    hi: cross(k),
                    lo_open,
                    hi_open: false,
                });
                open = None;
            }
        }
        j = k + 1;
    }
    if let Some((lo, lo_open)) = open {
        out.push(Interval {
            lo,
            hi: z0 + (h.len() as f64 - 1.0) * dz,
            lo_open,
            hi_open: true,
        });
    }
    out
}

/// One turn measured on one generator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnMeasure {
    /// Start.
    pub start: u32,
    /// Turn (1-based).
    pub turn: i64,
    /// Revolution of the pitch helix at the turn's first feature on this generator.
    pub t: f64,
    /// Ideal lead (pitch for one start) on this generator.
    pub ideal_lead: Option<f64>,
    /// Measured lead.
    pub lead: Option<f64>,
    /// Ideal groove width at the pitch line.
    pub ideal_groove: Option<f64>,
    /// Measured groove width.
    pub groove: Option<f64>,
    /// Ideal tooth width at the pitch line.
    pub ideal_tooth: Option<f64>,
    /// Measured tooth width.
    pub tooth: Option<f64>,
    /// The cut has more than one crossing pair where the ideal has one feature (a ridge
    /// or a notch at the pitch line).
    pub split: bool,
    /// Smallest and largest measured height above the root between the turn's features.
    pub cut_heights: Option<(f64, f64)>,
    /// Measured simple pitch diameter of the turn's first groove (see `pitch_level`),
    /// when [`MeasureConfig::pitch_diameter`] asks for it.
    pub pitch_diameter: Option<f64>,
    /// The ideal's, measured the same way.
    pub ideal_pitch_diameter: Option<f64>,
}

/// Settings of the measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasureConfig {
    /// Axial spacing of the measurement columns (mm).
    pub spacing: f64,
    /// Number of generators, equally spaced from the thread's start angle.
    pub generators: usize,
    /// Also measure the simple pitch diameter of each turn (constant pitch, grooves as
    /// features).
    pub pitch_diameter: bool,
    /// Keep each generator's cut heights for the gauges ([`measure_kept`]).
    pub keep_columns: bool,
}

/// Measure every whole turn on each generator; `generators[0]` is the reference one.
pub fn measure(
    thread: &ThreadSpec,
    passes: &[Pass],
    tools: &[Tool],
    blank_q: f64,
    window: (f64, f64),
    cfg: MeasureConfig,
) -> Vec<Vec<TurnMeasure>> {
    let cut = |q: &mut [f32], c: Column| {
        sweep_column(q, c, passes, tools);
    };
    measure_by(thread, &cut, blank_q, window, cfg)
}

/// [`measure`] with any kernel: `cut` cuts a free-standing column in place.
pub(crate) fn measure_by(
    thread: &ThreadSpec,
    cut: &(dyn Fn(&mut [f32], Column) + Sync),
    blank_q: f64,
    window: (f64, f64),
    cfg: MeasureConfig,
) -> Vec<Vec<TurnMeasure>> {
    measure_kept(thread, cut, blank_q, window, cfg).0
}

/// [`measure_by`], and each generator's cut heights when `cfg.keep_columns` (else empty).
pub(crate) fn measure_kept(
    thread: &ThreadSpec,
    cut: &(dyn Fn(&mut [f32], Column) + Sync),
    blank_q: f64,
    window: (f64, f64),
    cfg: MeasureConfig,
) -> (Vec<Vec<TurnMeasure>>, Vec<GaugeColumn>) {
    use rayon::prelude::*;
    let both: Vec<(Vec<TurnMeasure>, Option<GaugeColumn>)> = (0..cfg.generators.max(1))
        .into_par_iter()
        .map_init(Buffers::default, |bufs, g| {
            let theta = thread.helix.theta0
                + std::f64::consts::TAU * g as f64 / cfg.generators.max(1) as f64;
            let turns = measure_generator(thread, cut, blank_q, window, cfg, theta, bufs);
            let kept = cfg.keep_columns.then(|| GaugeColumn {
                theta,
                z0: window.0,
                dz: cfg.spacing,
                h: bufs.cut_h.clone(),
            });
            (turns, kept)
        })
        .collect();
    let mut turns = Vec::with_capacity(both.len());
    let mut columns = Vec::new();
    for (t, c) in both {
        turns.push(t);
        columns.extend(c);
    }
    (turns, columns)
}

/// A generator's columns (the cut, its heights, the ideal's heights), kept by a worker
/// from one generator to the next: their pages are touched once, not per generator.
#[derive(Default)]
struct Buffers {
    q: Vec<f32>,
    cut_h: Vec<f32>,
    ideal_h: Vec<f32>,
}

/// The most heap memory one generator of `cells` cells holds at once, its ideal column
/// (`ideal_bytes`, with `features` features) aside (bytes): the cut, its heights and the
/// ideal's heights (`f32` each); the intervals of the cut and of the ideal (at most one per
/// feature and one at each end, doubled for a vector's growth: a cut split by ridges has
/// more, a few per turn); the features in the window, their matches and the turns.
pub(crate) fn generator_bytes(cells: usize, features: usize) -> u64 {
    use std::mem::size_of;
    let cells = cells.max(2) as u64;
    let f = features as u64 + 2;
    3 * cells * size_of::<f32>() as u64
        + 2 * 2 * 2 * f * size_of::<Interval>() as u64
        + f * (size_of::<Feature>()
            + size_of::<(Option<Interval>, Option<Interval>, bool)>()
            + 2 * size_of::<TurnMeasure>()) as u64
}

/// The axial cells of a measurement column over `window` at `spacing`.
pub(crate) fn generator_cells(window: (f64, f64), spacing: f64) -> usize {
    ((window.1 - window.0) / spacing).floor().max(2.0) as usize
}

fn measure_generator(
    thread: &ThreadSpec,
    cut: &(dyn Fn(&mut [f32], Column) + Sync),
    blank_q: f64,
    window: (f64, f64),
    cfg: MeasureConfig,
    theta: f64,
    bufs: &mut Buffers,
) -> Vec<TurnMeasure> {
    let spacing = cfg.spacing;
    let (z_lo, z_hi) = window;
    let n = generator_cells(window, spacing);
    let surface = match thread.side {
        Side::External => Surface::Outer,
        Side::Internal => Surface::Inner,
    };
    let sense = surface.sense();
    let Buffers { q, cut_h, ideal_h } = bufs;
    q.clear();
    q.resize(n, 0.0);
    let column = Column {
        theta,
        z0: z_lo,
        dz: spacing,
        q_blank: blank_q,
        surface,
    };
    cut(q, column);
    // Heights above the local root: a taper thread's cones taken off, cut and ideal alike
    // (widths at a level are the same along z before and after).
    let z_of = |j: usize| z_lo + j as f64 * spacing;
    cut_h.clear();
    cut_h.extend(
        q.iter()
            .enumerate()
            .map(|(j, &v)| thread.local_height(z_of(j), sense * (v as f64 + blank_q)) as f32),
    );
    let ideal = thread.column(theta, z_lo, z_hi);
    ideal_h.clear();
    ideal_h.resize(n, 0.0);
    ideal.fill_heights(z_lo, spacing, 0, ideal_h);
    if thread.taper.is_some() {
        for (j, h) in ideal_h.iter_mut().enumerate() {
            *h = (*h as f64 - thread.cone_height(z_of(j))) as f32;
        }
    }
    let (cut_h, ideal_h) = (&cut_h[..], &ideal_h[..]);
    let tooth = matches!(thread.width, WidthRule::Tooth(_));
    let level = thread.pitch_height();
    // Flanks outside this generator's thread span border the run-in and run-out, which
    // the drawing does not define: they are neither compared nor measured.
    let span = ideal.span.unwrap_or((z_lo, z_hi));
    let clip = |mut ivs: Vec<Interval>| {
        for iv in &mut ivs {
            iv.lo_open |= iv.lo < span.0 - 1e-9;
            iv.hi_open |= iv.hi > span.1 + 1e-9;
        }
        ivs
    };
    let cut_iv = clip(intervals(cut_h, z_lo, spacing, level, tooth));
    let ideal_iv = clip(intervals(ideal_h, z_lo, spacing, level, tooth));

    // Features in the window, in t order per start (z falls with t).
    let whole = thread.turns + 1e-9;
    let mut feats: Vec<Feature> = ideal
        .features
        .iter()
        .copied()
        .filter(|f| f.z >= z_lo && f.z <= z_hi && f.t >= -1e-9 && f.t <= whole)
        .collect();
    feats.sort_by(|a, b| b.z.total_cmp(&a.z));
    // A feature at the window's edge may sit just past its last cell.
    let find = |ivs: &[Interval], z: f64| {
        ivs.iter()
            .position(|iv| iv.lo - 2.0 * spacing <= z && z <= iv.hi + 2.0 * spacing)
    };
    let matched: Vec<(Option<Interval>, Option<Interval>, bool)> = feats
        .iter()
        .map(|f| {
            let Some(ii) = find(&ideal_iv, f.z) else {
                return (None, None, false);
            };
            let iv = ideal_iv[ii];
            let overlapping: Vec<&Interval> = cut_iv
                .iter()
                .filter(|c| c.hi > iv.lo && c.lo < iv.hi)
                .collect();
            let cut = match overlapping.as_slice() {
                [] => None,
                [one] => Some(**one),
                many => Some(Interval {
                    lo: many[0].lo,
                    hi: many[many.len() - 1].hi,
                    lo_open: many[0].lo_open,
                    hi_open: many[many.len() - 1].hi_open,
                }),
            };
            (Some(iv), cut, overlapping.len() > 1)
        })
        .collect();

    let lead_of = |a: Option<Interval>, b: Option<Interval>| -> Option<f64> {
        let (a, b) = (a?, b?);
        let mut sum = 0.0;
        let mut n = 0;
        if !a.lo_open && !b.lo_open {
            sum += a.lo - b.lo;
            n += 1;
        }
        if !a.hi_open && !b.hi_open {
            sum += a.hi - b.hi;
            n += 1;
        }
        (n > 0).then(|| sum / n as f64)
    };
    let width = |a: Option<Interval>| a.filter(|i| !i.lo_open && !i.hi_open).map(|i| i.hi - i.lo);
    let gap = |upper: Option<Interval>, lower: Option<Interval>| -> Option<f64> {
        let (u, l) = (upper?, lower?);
        (!u.lo_open && !l.hi_open).then_some(u.lo - l.hi)
    };

    let mut out = Vec::new();
    for (m, f) in feats.iter().enumerate() {
        // Next feature of the same start (one turn on) and next feature in z (any start).
        let Some(next_same) = (m + 1..feats.len()).find(|&k| feats[k].start == f.start) else {
            continue;
        };
        let next_any = m + 1;
        let (iv_i, iv_c, split) = matched[m];
        let (nx_i, nx_c, _) = matched[next_same];
        let (na_i, na_c, _) = matched[next_any];
        let (groove_i, groove_c, tooth_i, tooth_c) = if tooth {
            (gap(iv_i, na_i), gap(iv_c, na_c), width(iv_i), width(iv_c))
        } else {
            (width(iv_i), width(iv_c), gap(iv_i, na_i), gap(iv_c, na_c))
        };
        let (z_top, z_bot) = (f.z, feats[next_same].z);
        let j0 = ((z_bot - z_lo) / spacing).ceil().max(0.0) as usize;
        let j1 = (((z_top - z_lo) / spacing).floor() as usize).min(n - 1);
        let cut_heights = (j1 > j0).then(|| {
            cut_h[j0..=j1]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x as f64), b.max(x as f64))
                })
        });
        let half_pitch = 0.5 * thread.pitch_of_turn(f.turn().max(1));
        let simple = cfg.pitch_diameter && !tooth && thread.helix.law.k == 0.0;
        let d2 = |h: &[f32]| {
            simple
                .then(|| pitch_level(h, z_lo, spacing, f.z, half_pitch, thread.depth()))
                .flatten()
                .map(|l| 2.0 * thread.local_radius(f.z, l))
        };
        out.push(TurnMeasure {
            pitch_diameter: d2(cut_h),
            ideal_pitch_diameter: d2(ideal_h),
            start: f.start,
            turn: f.turn(),
            t: f.t,
            ideal_lead: lead_of(iv_i, nx_i),
            lead: lead_of(iv_c, nx_c),
            ideal_groove: groove_i,
            groove: groove_c,
            ideal_tooth: tooth_i,
            tooth: tooth_c,
            split,
            cut_heights,
        });
    }
    out
}

/// The height above the root at which the groove around `z_c` (where `h < level`) is
/// `half_pitch` wide: the *simple pitch diameter* of ISO 5408 (groove width = half the
/// pitch), what three-wire measurement gives on a thread with true flank angles and lead.
/// The groove width grows with the level; bisection to 1e-9 mm over `[0, depth]`. `None`
/// if the groove is not there, runs out of the column, or never reaches that width.
pub(crate) fn pitch_level(
    h: &[f32],
    z0: f64,
    dz: f64,
    z_c: f64,
    half_pitch: f64,
    depth: f64,
) -> Option<f64> {
    let jc = ((z_c - z0) / dz).round();
    if jc < 1.0 || jc >= h.len() as f64 - 1.0 {
        return None;
    }
    let jc = jc as usize;
    let width = |level: f64| -> Option<f64> {
        if h[jc] as f64 >= level {
            return Some(0.0);
        }
        let cross = |j: usize, k: usize| {
            // Between cells j (inside) and k (outside).
            let (a, b) = (h[j] as f64, h[k] as f64);
            let u = if b != a { (level - a) / (b - a) } else { 0.5 };
            z0 + (j as f64 + (k as f64 - j as f64) * u.clamp(0.0, 1.0)) * dz
        };
        let mut l = jc;
        while (h[l] as f64) < level {
            l = l.checked_sub(1)?;
        }
        let mut r = jc;
        while (h[r] as f64) < level {
            r += 1;
            if r >= h.len() {
                return None;
            }
        }
        Some(cross(r - 1, r) - cross(l + 1, l))
    };
    // The groove is closed at any level below both neighbouring crests (within a pitch
    // either side): the top of the search is the lower crest (less 1 nm), never above the
    // depth. A crest turned below the drawing's (or stored as an f32 a rounding under it)
    // still bounds a groove whose width can be found.
    let reach = ((2.0 * half_pitch / dz).ceil() as usize).max(1);
    let peak = |a: usize, b: usize| {
        h[a..b]
            .iter()
            .fold(f64::NEG_INFINITY, |m, &x| m.max(x as f64))
    };
    let crest = peak(jc.saturating_sub(reach), jc + 1).min(peak(jc, (jc + reach + 1).min(h.len())));
    let (mut lo, mut hi) = (0.0, depth.min(crest - 1e-6));
    if hi <= lo || width(hi)? < half_pitch || width(lo)? > half_pitch {
        return None;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if width(mid)? < half_pitch {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-9 {
            break;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The intervals cell by cell, each state an `f64` comparison: the oracle of
    /// [`intervals`]' thresholds and chunked scan.
    fn intervals_by_cell(h: &[f32], z0: f64, dz: f64, level: f64, tooth: bool) -> Vec<Interval> {
        let inside = |x: f32| {
            if tooth {
                x as f64 > level
            } else {
                (x as f64) < level
            }
        };
        let cross = |j: usize| {
            let (a, b) = (h[j - 1] as f64, h[j] as f64);
            let u = if b != a { (level - a) / (b - a) } else { 0.5 };
            z0 + (j as f64 - 1.0 + u.clamp(0.0, 1.0)) * dz
        };
        let mut out = Vec::new();
        let mut open: Option<(f64, bool)> = None;
        for (j, &hj) in h.iter().enumerate() {
            match (&open, inside(hj)) {
                (None, true) => {
                    open = Some(if j == 0 {
                        (z0, true)
                    } else {
                        (cross(j), false)
                    });
                }
                (Some((lo, lo_open)), false) => {
                    out.push(Interval {
                        lo: *lo,
                        hi: cross(j),
                        lo_open: *lo_open,
                        hi_open: false,
                    });
                    open = None;
                }
                _ => {}
            }
        }
        if let Some((lo, lo_open)) = open {
            out.push(Interval {
                lo,
                hi: z0 + (h.len() as f64 - 1.0) * dz,
                lo_open,
                hi_open: true,
            });
        }
        out
    }

    /// Randomized: columns of runs (long and short, across chunk edges) of values at the
    /// level, the f32 neighbours around it, far from it, NaN and infinities; levels that are
    /// f32 values, between them, and extreme; both features. The same intervals, bit for
    /// bit, as the cell-by-cell oracle.
    #[test]
    fn chunked_intervals_match_the_cell_by_cell_oracle() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for case in 0..4000 {
            let level = match case % 6 {
                0 => 0.75,
                1 => 0.1,
                2 => (next() % 1000) as f64 * 1e-3 + 1e-12,
                3 => f32::MAX as f64 * 2.0,
                4 => -1e-40,
                _ => (next() % 2000) as f64 * 1e-3 - 1.0,
            };
            let c = level as f32;
            let near = [
                c,
                step(c, true),
                step(c, false),
                step(step(c, true), true),
                step(step(c, false), false),
            ];
            let n = (next() % 300) as usize;
            let mut h = Vec::with_capacity(n);
            while h.len() < n {
                let run = 1 + (next() % 70) as usize;
                let v = match next() % 8 {
                    0 => f32::NAN,
                    1 => f32::INFINITY,
                    2 => f32::NEG_INFINITY,
                    3 => (next() % 3000) as f32 * 1e-3 - 1.0,
                    _ => near[(next() % 5) as usize],
                };
                for _ in 0..run.min(n - h.len()) {
                    h.push(v);
                }
            }
            for tooth in [false, true] {
                let (a, b) = (
                    intervals(&h, -2.0, 5e-4, level, tooth),
                    intervals_by_cell(&h, -2.0, 5e-4, level, tooth),
                );
                let bits = |v: &[Interval]| {
                    v.iter()
                        .map(|i| (i.lo.to_bits(), i.hi.to_bits(), i.lo_open, i.hi_open))
                        .collect::<Vec<_>>()
                };
                assert_eq!(
                    bits(&a),
                    bits(&b),
                    "case {case}, level {level}, tooth {tooth}"
                );
            }
        }
        // The steps against the bits of known neighbours.
        assert_eq!(step(1.0, true), 1.0 + f32::EPSILON);
        assert_eq!(step(1.0 + f32::EPSILON, false), 1.0);
        assert_eq!(step(-1.0, false), -1.0 - f32::EPSILON);
        assert_eq!(step(f32::MAX, true), f32::INFINITY);
        assert_eq!(step(f32::NEG_INFINITY, true), f32::MIN);
        assert_eq!(step(0.0, false), -f32::from_bits(1));
        assert_eq!(step(-0.0, true), f32::from_bits(1));
        // A NaN level: nothing is inside.
        assert!(intervals(&[0.0, 1.0], 0.0, 1.0, f64::NAN, true).is_empty());
        assert!(intervals_by_cell(&[0.0, 1.0], 0.0, 1.0, f64::NAN, true).is_empty());
    }

    #[test]
    fn pitch_level_of_a_sixty_degree_groove() {
        // A V groove: h = |z| / tan 30 above its root... capped at depth 1; its width at
        // level L is 2 L tan 30, half a pitch of 1.5 at L = 0.75 / (2 tan 30).
        let t = 30f64.to_radians().tan();
        let dz = 1e-4;
        let h: Vec<f32> = (0..20001)
            .map(|j| ((-1.0 + j as f64 * dz).abs() / t).min(1.0) as f32)
            .collect();
        let l = pitch_level(&h, -1.0, dz, 0.0, 0.75, 1.0).unwrap();
        assert!((l - 0.75 / (2.0 * t)).abs() < 1e-6, "{l}");
    }

    #[test]
    fn intervals_interpolate_crossings() {
        // A ramp 0..10 over 11 cells crossing 4.5 at z = 4.5.
        let h: Vec<f32> = (0..11).map(|j| j as f32).collect();
        let iv = intervals(&h, 0.0, 1.0, 4.5, false);
        assert_eq!(iv.len(), 1);
        assert!(iv[0].lo_open && !iv[0].hi_open);
        assert!((iv[0].hi - 4.5).abs() < 1e-12);
        let iv = intervals(&h, 0.0, 1.0, 4.5, true);
        assert!((iv[0].lo - 4.5).abs() < 1e-12 && iv[0].hi_open);
    }
}
