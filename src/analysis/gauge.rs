//! The gauges' verdict: a cut thread judged against its tolerance class as GO and NOT GO
//! gauges and a micrometer would judge it, computed exactly from the cut surface.
//!
//! - **GO (functional size).** The GO ring of an external thread is a perfect internal
//!   thread of the basic profile (pitch `P`, flank angle `a`, its root cleared, its crest at
//!   the basic minor diameter's distance below its pitch line) at the maximum-material pitch
//!   diameter; it must assemble with the part over the length of engagement. The
//!   functional (virtual) pitch diameter is the smallest such ring's pitch diameter that
//!   assembles, found from the surface itself: a point of the part at radius `r`, axial
//!   distance `u` from the ring's groove centre (`|u| <= P/2`), is clear of a ring of pitch
//!   radius `R` when `r < R + (P/4 - |u|) cot(a/2)` (the flank) or `r < R - c` (below the
//!   ring's crest, `c` = basic pitch radius less basic minor radius). So the smallest ring at
//!   phase `phi` has `R(phi) = max_p min(r_p - (P/4 - |u_p|) cot(a/2), r_p + c)`, and the
//!   functional radius is `min_phi R(phi)`. An internal thread mirrors it with a GO plug:
//!   `R(phi) = min_p max(r_p - (P/4 - |u_p|) cot(a/2), r_p - c')` (`u` from the plug's
//!   tooth centre, `c'` = basic major radius less basic pitch radius) and the largest plug
//!   `max_phi R(phi)`. Each point's bound is a truncated V in `phi`; their max is unimodal
//!   about the ring's best phase, found by a scan and golden-section search. Over a thread
//!   longer than the length of engagement the ring is slid along it, one pitch at a time,
//!   and the worst window counts (the GO ring must pass the whole thread).
//! - **NOT GO (simple pitch diameter).** The diameter where the groove is half a pitch
//!   wide (`measure::pitch_level`), per turn on every generator: minimum and maximum, and the
//!   NOT GO gauge's view: it engages `not_go_turns` turns at a time and is stopped by the
//!   largest (external) or smallest (internal) simple pitch diameter among them; the
//!   thread fails when, in some window, that value is past the minimum-material limit.
//! - **Major / minor diameter**: the crests of the complete turns (both grooves found at the
//!   pitch line) against the class's limits.
//!
//! Every value within the simulation's own resolution of a limit is `undecided`, never a
//! pass. The resolution is the stored radii's `f32` rounding, plus for the GO element,
//! where a binding point is a corner of the sampled surface (no binding neighbour), the
//! measurement's axial spacing times the flank's slope; where the binding points lie on
//! flanks parallel to the gauge's, the sampled size is exact. The simple pitch diameter is
//! interpolated linearly between cells (exact on straight flanks): the rounding and a
//! hundredth of a cell's slope. The report states the larger.
//! Pure: the generators' cut heights come from `measure`.

use crate::analysis::measure::TurnMeasure;
use crate::model::thread::{Side, ThreadSpec};
use crate::model::tolerance::{SizeLimits, ThreadClass};

/// One generator's cut, as the measurement cut it: heights above the root per cell.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GaugeColumn {
    /// Angle on the part (rad).
    pub theta: f64,
    /// z of cell 0 (mm).
    pub z0: f64,
    /// Cell spacing (mm).
    pub dz: f64,
    /// Height above the thread's root of the cut surface, per cell.
    pub h: Vec<f32>,
}

/// The verdict of one gauge element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Call {
    /// Within the limits by more than the resolution.
    Pass,
    /// Past a limit by more than the resolution.
    Fail,
    /// Within the resolution of a limit: the simulation cannot tell.
    Undecided,
    /// Nothing to measure (no complete turn).
    NotMeasured,
}

impl Call {
    /// The name the report uses.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Call::Pass => "pass",
            Call::Fail => "fail",
            Call::Undecided => "undecided",
            Call::NotMeasured => "not_measured",
        }
    }

    /// The worse of two calls (fail > undecided > not measured > pass).
    fn worse(self, o: Call) -> Call {
        let rank = |c: Call| match c {
            Call::Pass => 0,
            Call::NotMeasured => 1,
            Call::Undecided => 2,
            Call::Fail => 3,
        };
        if rank(o) > rank(self) {
            o
        } else {
            self
        }
    }
}

/// The call of `value` against `limits` with the resolution `res`: the checked end is
/// `max` (`upper`) or `min`.
fn call(value: Option<f64>, limit: f64, upper: bool, res: f64) -> Call {
    let Some(v) = value else {
        return Call::NotMeasured;
    };
    if !limit.is_finite() {
        return Call::Pass;
    }
    let beyond = if upper { v - limit } else { limit - v };
    if beyond > res {
        Call::Fail
    } else if beyond >= -res {
        Call::Undecided
    } else {
        Call::Pass
    }
}

/// One element a gauge or a micrometer checks: its value against one limit.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Element {
    /// What is checked (`go_functional_pitch_diameter`, `not_go_pitch_diameter`,
    /// `major_diameter`, `minor_diameter`, `root_diameter`).
    pub name: &'static str,
    /// The measured value (mm); `None` where nothing was measured.
    pub value: Option<f64>,
    /// The limit it is checked against (mm).
    pub limit: f64,
    /// Whether the limit is a maximum (else a minimum).
    pub upper: bool,
    /// The resolution the call used (mm, on a diameter).
    pub resolution: f64,
    /// The call.
    pub call: Call,
}

/// The gauges' results on one thread.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Gauge {
    /// Functional (virtual) pitch diameter over the worst window of the length of
    /// engagement (mm), and the window's z range.
    pub functional: Option<(f64, (f64, f64))>,
    /// Smallest and largest simple pitch diameter of a complete turn on any generator (mm).
    pub simple: Option<(f64, f64)>,
    /// The NOT GO gauge's worst window of `not_go_turns` turns: the size of the virtual
    /// truncated-profile gauge that just assembles with them (the smallest ring, the
    /// largest plug), least (ring) or greatest (plug) over the windows (mm), and the
    /// window's first turn.
    pub not_go: Option<(f64, i64)>,
    /// The NOT GO as single elements: the largest (external) or smallest (internal) simple
    /// pitch diameter of a window's turns, in the window going furthest towards minimum
    /// material (mm), and its first turn.
    pub not_go_simple: Option<(f64, i64)>,
    /// Smallest and largest crest diameter of the complete turns (mm): the major diameter
    /// of an external thread, the minor of an internal one.
    pub crest: Option<(f64, f64)>,
    /// The simulation's resolution on a diameter (mm).
    pub resolution: f64,
    /// Root diameter (minor of an external thread, major of an internal one): smallest and
    /// largest of the complete turns (mm).
    pub root: Option<(f64, f64)>,
    /// Every element checked, in report order.
    pub elements: Vec<Element>,
    /// All of them.
    pub verdict: Call,
    /// The best-wire size (mm) and the predicted measurement over three wires for the
    /// smallest and largest simple pitch diameter (external threads).
    pub over_wires: Option<(f64, f64, f64)>,
}

/// The flank geometry the gauges use: pitch, `cot(a/2)`, and the gauge's truncation.
#[derive(Clone, Copy, Debug)]
struct Profile {
    pitch: f64,
    cot: f64,
    /// External: the ring's crest below its pitch line; internal: the plug's crest above.
    /// A truncated (NOT GO) gauge: the half-height of its flanks' contact band.
    clear: f64,
    external: bool,
    /// The NOT GO gauge's truncated profile: its flanks touch only within `clear` of its
    /// pitch line (crest truncated there, root relieved beyond it).
    truncated: bool,
}

/// Each point's bound at phase `phi`: (z relative to the gauge's lattice, radius).
///
/// A truncated ring (external) is solid where `r >= R - b` (its crest truncated) and the
/// groove it leaves for the part's tooth is `P/4 - min(r - R, b) tan(a/2)` wide either side
/// of its centre (the flank, then the relief beyond the band): a point `|u|` from the groove
/// centre clears it when `R > min(r + b, r - (P/4 - |u|) cot(a/2))`, and never binds where
/// `|u| < P/4 - b tan(a/2)` (in the relief: the flank term is below `r - b`). A truncated
/// plug (internal) mirrors it.
fn bound(p: &Profile, zr: f64, r: f64, phi: f64) -> f64 {
    let x = zr - phi;
    let u = (x - p.pitch * (x / p.pitch).round()).abs();
    let need = r - (0.25 * p.pitch - u) * p.cot;
    match (p.external, p.truncated) {
        (true, false) => need.min(r + p.clear),
        (false, false) => need.max(r - p.clear),
        (true, true) if need < r - p.clear => f64::NEG_INFINITY,
        (true, true) => need.min(r + p.clear),
        (false, true) if need > r + p.clear => f64::INFINITY,
        (false, true) => need.max(r - p.clear),
    }
}

/// The gauge's size at phase `phi` over `pts`: the smallest ring (external) or largest
/// plug (internal) pitch radius that assembles.
fn size_at(p: &Profile, pts: &[(f64, f64)], phi: f64) -> f64 {
    if p.external {
        pts.iter()
            .fold(f64::NEG_INFINITY, |m, &(z, r)| m.max(bound(p, z, r, phi)))
    } else {
        pts.iter()
            .fold(f64::INFINITY, |m, &(z, r)| m.min(bound(p, z, r, phi)))
    }
}

/// The functional pitch radius over `pts` (and the best phase): the best over phases of
/// [`size_at`], by a scan of the period and a golden-section search about its best.
fn functional_radius(p: &Profile, pts: &[(f64, f64)], hint: Option<f64>) -> (f64, f64) {
    // "Better" is smaller for a ring, larger for a plug.
    let key = |v: f64| if p.external { v } else { -v };
    let scan = 48;
    let (mut best_phi, mut best) = (0.0, f64::INFINITY);
    let consider = |phi: f64, best_phi: &mut f64, best: &mut f64| {
        let v = key(size_at(p, pts, phi));
        if v < *best {
            *best = v;
            *best_phi = phi;
        }
    };
    let step = p.pitch / scan as f64;
    match hint {
        Some(h) => {
            for k in -4..=4 {
                consider(h + k as f64 * step, &mut best_phi, &mut best);
            }
        }
        None => {
            for k in 0..scan {
                consider(k as f64 * step, &mut best_phi, &mut best);
            }
        }
    }
    // Golden-section search on [best - step, best + step].
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (best_phi - step, best_phi + step);
    let f = |phi: f64| key(size_at(p, pts, phi));
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > 1e-7 * p.pitch {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let (phi, v) = if fc < fd { (c, fc) } else { (d, fd) };
    let v = v.min(best);
    let phi = if v == best && best < fc.min(fd) {
        best_phi
    } else {
        phi
    };
    (key(v), phi)
}

/// Points of the cut in `[z_lo, z_hi]` on every column, as (z relative to the gauge's
/// lattice at phase 0, radius): the lattice is the ring's groove centre (external: the
/// part's tooth centre, half a pitch from the thread's feature) or the plug's tooth centre
/// (internal: the part's groove centre, the feature itself).
fn points(
    thread: &ThreadSpec,
    columns: &[GaugeColumn],
    pitch: f64,
    span: (f64, f64),
) -> Vec<(f64, f64)> {
    points_by(thread, columns, pitch, &|_| span)
}

/// [`points`] with each column's own z range (`span_of` its angle).
fn points_by(
    thread: &ThreadSpec,
    columns: &[GaugeColumn],
    pitch: f64,
    span_of: &dyn Fn(f64) -> (f64, f64),
) -> Vec<(f64, f64)> {
    let helix = thread.helix;
    let shift = match thread.side {
        Side::External => 0.5 * pitch,
        Side::Internal => 0.0,
    };
    let mut out = Vec::new();
    for c in columns {
        let span = span_of(c.theta);
        let lattice = helix.z(helix.phase_at(c.theta)) + shift;
        let j0 = ((span.0 - c.z0) / c.dz).ceil().max(0.0) as usize;
        let j1 = (((span.1 - c.z0) / c.dz).floor().max(-1.0) + 1.0) as usize;
        let j1 = j1.min(c.h.len());
        for j in j0..j1.max(j0) {
            let z = c.z0 + j as f64 * c.dz;
            out.push((z - lattice, thread.radius(c.h[j] as f64)));
        }
    }
    out
}

/// Judge the cut: `class` the limits, `columns` the measurement generators' cuts,
/// `turns` their per-turn measures (with simple pitch diameters), `spacing` the
/// measurement's axial spacing.
pub(crate) fn judge(
    thread: &ThreadSpec,
    class: &ThreadClass,
    columns: &[GaugeColumn],
    turns: &[Vec<TurnMeasure>],
    spacing: f64,
) -> Gauge {
    let external = thread.side == Side::External;
    let half = 0.5 * class.flank_angle;
    let cot = 1.0 / half.tan();
    let profile = Profile {
        pitch: class.pitch,
        cot,
        clear: if external {
            0.5 * (class.basic_pitch_diameter - class.basic_minor)
        } else {
            0.5 * (class.basic_major - class.basic_pitch_diameter)
        },
        external,
        truncated: false,
    };
    // Resolution on a diameter: a flank point is found within a cell (the spacing) along
    // z, that is `spacing cot(a/2)` in radius, twice on a diameter; plus the f32 rounding
    // of the stored radius (4 ulps at the crest).
    let ulp = (thread.crest_radius.max(thread.root_radius) as f32).to_bits();
    let ulp = f32::from_bits(ulp + 1) as f64 - f32::from_bits(ulp) as f64;
    let rounding = 2.0 * 4.0 * ulp;

    // The thread's span at its start angle: from its first feature to its last.
    let helix = thread.helix;
    let (za, zb) = (helix.z(0.0), helix.z(thread.turns));
    let span = (za.min(zb), za.max(zb));
    let pd = class.pitch_diameter;
    let functional = functional_over(
        thread,
        &profile,
        columns,
        span,
        class.engagement_length,
        0.5 * rounding,
    );
    // The GO element's resolution: exact to the rounding where the binding points lie on
    // a flank plateau, one cell's slope more where one is a corner (see `corner`).
    // The search on the reduced points finds a phase whose size (from every point) is over
    // the optimum by at most a bin's width times cot(a/2) (`reduce`).
    let go_res = rounding
        + 2.0 * cot * class.pitch / BINS as f64
        + functional.map_or(0.0, |f| if f.2 { 2.0 * spacing * cot } else { 0.0 });
    let functional = functional.map(|f| (f.0, f.1));
    // The simple pitch diameter is where the groove, interpolated linearly between cells,
    // is half a pitch wide: exact on straight flanks, so the rounding and a hundredth of a
    // cell's slope (curved flanks).
    let simple_res = rounding + 2.0 * 0.01 * spacing * cot;
    let resolution = go_res.max(simple_res);

    // Simple pitch diameters of the complete turns, per generator.
    let simple_of = |m: &TurnMeasure| m.pitch_diameter;
    let all: Vec<f64> = turns.iter().flatten().filter_map(simple_of).collect();
    let simple = (!all.is_empty()).then(|| {
        all.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    });
    let not_go_simple = not_go_windows(turns, class.not_go_turns, external);
    // The NOT GO gauge as a virtual truncated-profile gauge over its turns.
    let truncated = Profile {
        clear: not_go_band(class),
        truncated: true,
        ..profile
    };
    let not_go_env = not_go_envelope(
        thread,
        &truncated,
        columns,
        turns,
        class.not_go_turns,
        0.5 * rounding,
    );
    let ng_res = rounding
        + 2.0 * cot * class.pitch / BINS as f64
        + not_go_env.map_or(0.0, |f| if f.2 { 2.0 * spacing * cot } else { 0.0 });
    let not_go = not_go_env.map(|f| (f.0, f.1));
    // Crests of the complete turns: the largest cut height between the turn's features.
    let crests: Vec<f64> = turns
        .iter()
        .flatten()
        .filter(|m| m.pitch_diameter.is_some())
        .filter_map(|m| m.cut_heights.map(|(_, hi)| 2.0 * thread.radius(hi)))
        .collect();
    let crest = (!crests.is_empty()).then(|| {
        crests
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    });
    let roots: Vec<f64> = turns
        .iter()
        .flatten()
        .filter(|m| m.pitch_diameter.is_some())
        .filter_map(|m| m.cut_heights.map(|(lo, _)| 2.0 * thread.radius(lo)))
        .collect();
    let root = (!roots.is_empty()).then(|| {
        roots
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    });
    let (crest_limits, root_limits, crest_name): (SizeLimits, SizeLimits, &'static str) =
        if external {
            (class.major_diameter, class.minor_diameter, "major_diameter")
        } else {
            (class.minor_diameter, class.major_diameter, "minor_diameter")
        };
    let mut elements = Vec::new();
    let mut element = |name: &'static str, value: Option<f64>, limit: f64, upper: bool| {
        if limit.is_finite() {
            let res = match name {
                "go_functional_pitch_diameter" => go_res,
                "not_go_pitch_diameter" => ng_res,
                _ => simple_res,
            };
            elements.push(Element {
                name,
                value,
                limit,
                upper,
                resolution: res,
                call: call(value, limit, upper, res),
            });
        }
    };
    // GO: the functional size at maximum material; NOT GO: the simple pitch diameter at
    // minimum material.
    let (go_limit, ng_limit) = if external {
        (pd.max, pd.min)
    } else {
        (pd.min, pd.max)
    };
    element(
        "go_functional_pitch_diameter",
        functional.map(|f| f.0),
        go_limit,
        external,
    );
    element(
        "not_go_pitch_diameter",
        not_go.map(|n| n.0),
        ng_limit,
        !external,
    );
    element(crest_name, crest.map(|c| c.1), crest_limits.max, true);
    element(crest_name, crest.map(|c| c.0), crest_limits.min, false);
    // The root of an external thread (d3) and of an internal one (D): the mating thread's
    // crest must clear it.
    element("root_diameter", root.map(|c| c.1), root_limits.max, true);
    element("root_diameter", root.map(|c| c.0), root_limits.min, false);
    let verdict = elements.iter().fold(Call::Pass, |v, e| v.worse(e.call));
    let over_wires = (external && simple.is_some()).then(|| {
        let (lo, hi) = simple.unwrap_or_default();
        let w = class.pitch / (2.0 * half.cos());
        let m = |d2: f64| d2 + w * (1.0 + 1.0 / half.sin()) - 0.5 * class.pitch * cot;
        (w, m(lo), m(hi))
    });
    Gauge {
        functional,
        simple,
        not_go,
        not_go_simple,
        crest,
        resolution: resolution.max(ng_res),
        root,
        elements,
        verdict,
        over_wires,
    }
}

/// The functional diameter over the worst window of `engagement` length in `span`, one
/// pitch apart (the whole span when it is no longer than 1.25 engagements).
fn functional_over(
    thread: &ThreadSpec,
    p: &Profile,
    columns: &[GaugeColumn],
    span: (f64, f64),
    engagement: f64,
    rounding: f64,
) -> Option<(f64, (f64, f64), bool)> {
    let all = points(thread, columns, p.pitch, span);
    if all.is_empty() {
        return None;
    }
    let len = span.1 - span.0;
    let windows: Vec<(f64, f64)> = if engagement <= 0.0 || len <= 1.25 * engagement {
        vec![span]
    } else {
        let n = ((len - engagement) / p.pitch).ceil() as usize;
        (0..=n)
            .map(|k| {
                let hi = (span.1 - k as f64 * p.pitch).max(span.0 + engagement);
                (hi - engagement, hi)
            })
            .collect()
    };
    // The best phase over the whole span seeds each window's search.
    let (_, phi0) = functional_radius(p, &reduce(p, &all), None);
    let mut worst: Option<(f64, (f64, f64), bool)> = None;
    for w in windows {
        let sub = points(thread, columns, p.pitch, w);
        if sub.is_empty() {
            continue;
        }
        // The search on the reduced points; the size at its phase from every point.
        let (_, phi) = functional_radius(p, &reduce(p, &sub), Some(phi0));
        let r = size_at(p, &sub, phi);
        let d = 2.0 * r;
        let worse = match worst {
            None => true,
            Some((v, _, _)) => {
                if p.external {
                    d > v
                } else {
                    d < v
                }
            }
        };
        if worse {
            worst = Some((d, w, corner(p, &sub, phi, r, rounding)));
        }
    }
    worst
}

/// The NOT GO gauge's flank contact band (half its height, radial, mm): a tenth of the
/// basic profile's engaged height `(D - D1)/2` either side of the pitch line, H/8 for the
/// ISO and Unified 60 degree profiles (5H/8 engaged). ISO 1502 §10.2 and ASME B1.2 give
/// NOT GO gauges a truncated profile touching the flanks near the pitch line only; their
/// truncation dimensions were not found in a public source, so this is vpcut's choice,
/// stated in the report.
pub(crate) fn not_go_band(class: &ThreadClass) -> f64 {
    0.1 * (class.basic_major - class.basic_minor)
}

/// The NOT GO gauge as a virtual truncated-profile gauge (`p`, its band in `p.clear`):
/// over each window of `n` consecutive complete turns (rounded up, at least 1; turns whose
/// simple pitch diameter every generator measured, for every start), on every generator,
/// the smallest ring (external) or largest plug (internal) of perfect pitch and angle that
/// assembles with the cut; the worst window is the one whose gauge is nearest minimum
/// material (the smallest ring, the largest plug). Returns its diameter, first turn, and
/// whether a binding point is a corner of the sampled surface (see [`corner`]).
fn not_go_envelope(
    thread: &ThreadSpec,
    p: &Profile,
    columns: &[GaugeColumn],
    turns: &[Vec<TurnMeasure>],
    n: f64,
    rounding: f64,
) -> Option<(f64, i64, bool)> {
    use std::collections::{BTreeMap, BTreeSet};
    if columns.is_empty() {
        return None;
    }
    // Complete turns: measured by every generator, for every start.
    let mut seen: BTreeMap<i64, usize> = BTreeMap::new();
    for m in turns.iter().flatten() {
        if m.pitch_diameter.is_some() {
            *seen.entry(m.turn).or_default() += 1;
        }
    }
    let need = turns.len() * thread.starts as usize;
    let complete: BTreeSet<i64> = seen
        .into_iter()
        .filter(|&(_, c)| c >= need)
        .map(|(t, _)| t)
        .collect();
    let k = (n.ceil() as i64).max(1);
    let helix = thread.helix;
    let mut worst: Option<(f64, i64, bool)> = None;
    for &first in &complete {
        if !(first..first + k).all(|t| complete.contains(&t)) {
            continue;
        }
        // Turn `t` on the generator at `theta` runs from its feature at revolution
        // `t - 1 + phase` to the next: the window from `first - 1` to `first - 1 + k`.
        let span_of = |theta: f64| {
            let phase = helix.phase_at(theta);
            let (a, b) = (
                helix.z(first as f64 - 1.0 + phase),
                helix.z((first - 1 + k) as f64 + phase),
            );
            (a.min(b), a.max(b))
        };
        let pts = points_by(thread, columns, p.pitch, &span_of);
        if pts.is_empty() {
            continue;
        }
        let (_, phi) = functional_radius(p, &reduce(p, &pts), None);
        let r = size_at(p, &pts, phi);
        if !r.is_finite() {
            continue;
        }
        let d = 2.0 * r;
        let worse = worst.map_or(true, |(v, _, _)| if p.external { d < v } else { d > v });
        if worse {
            worst = Some((d, first, corner(p, &pts, phi, r, rounding)));
        }
    }
    worst
}

/// Bins of the reduced points per pitch: a point's bound depends only on its offset from
/// the gauge's lattice modulo the pitch and its radius, and grows with the radius (ring) or
/// falls with it (plug), so of the points whose offsets share a bin only the outermost
/// (innermost) can bind, up to the bin's width times cot(a/2): 2^16 bins, 0.03 um at a
/// 2 mm pitch. The search runs on these (a few per bin instead of every cell of every
/// turn of every generator); the size is then taken from every point at the phase found.
const BINS: usize = 1 << 16;

/// The points reduced to the binding one per bin of offset (in bin order: deterministic).
fn reduce(p: &Profile, pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut best: Vec<Option<(f64, f64)>> = vec![None; BINS];
    for &(z, r) in pts {
        let u = z - p.pitch * (z / p.pitch).round();
        let k = (((u / p.pitch + 0.5) * BINS as f64) as usize).min(BINS - 1);
        let slot = &mut best[k];
        let better = match slot {
            None => true,
            Some((_, r0)) => {
                if p.external {
                    r > *r0
                } else {
                    r < *r0
                }
            }
        };
        if better {
            *slot = Some((u, r));
        }
    }
    best.into_iter().flatten().collect()
}
/// Whether a point that binds the gauge at `phi` (its bound within the stored radii's
/// rounding of `r`) is a
/// corner of the sampled surface: one whose neighbouring cells (the points are each
/// column's cells in order) both bind less. A binding point with a binding neighbour lies
/// on a flank parallel to the gauge's (a plateau of the bound): the straight flank between
/// the cells binds no more, and the sampled size is exact. At a corner the true surface
/// may reach up to a cell's slope beyond the samples.
fn corner(p: &Profile, pts: &[(f64, f64)], phi: f64, r: f64, rounding: f64) -> bool {
    let binds = |i: usize| {
        pts.get(i)
            .is_some_and(|&(z, rr)| (bound(p, z, rr, phi) - r).abs() <= rounding)
    };
    (0..pts.len()).any(|i| binds(i) && !(i > 0 && binds(i - 1)) && !binds(i + 1))
}

/// The NOT GO gauge's worst window of `n` turns (rounded up, at least 1) over the turns
/// measured on every generator: the gauge is stopped by the largest (external) or smallest
/// (internal) simple pitch diameter among them; the worst window is the one whose
/// stopping value is smallest (external) or largest (internal).
fn not_go_windows(turns: &[Vec<TurnMeasure>], n: f64, external: bool) -> Option<(f64, i64)> {
    use std::collections::BTreeMap;
    // Per turn (start, turn): the stopping value over all generators.
    let mut per: BTreeMap<(u32, i64), f64> = BTreeMap::new();
    for m in turns.iter().flatten() {
        if let Some(d) = m.pitch_diameter {
            per.entry((m.start, m.turn))
                .and_modify(|v| {
                    *v = if external { v.max(d) } else { v.min(d) };
                })
                .or_insert(d);
        }
    }
    let k = (n.ceil() as usize).max(1);
    let mut worst: Option<(f64, i64)> = None;
    let keys: Vec<(u32, i64)> = per.keys().copied().collect();
    for (i, &(s, t)) in keys.iter().enumerate() {
        // A window of k consecutive turns of one start, all measured.
        let win: Vec<f64> = (0..k)
            .filter_map(|j| {
                keys.get(i + j)
                    .filter(|&&(s2, t2)| s2 == s && t2 == t + j as i64)
                    .and_then(|key| per.get(key).copied())
            })
            .collect();
        if win.len() < k {
            continue;
        }
        let stop = if external {
            win.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        } else {
            win.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let worse = match worst {
            None => true,
            Some((v, _)) => {
                if external {
                    stop < v
                } else {
                    stop > v
                }
            }
        };
        if worse {
            worst = Some((stop, t));
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::{Helix, LeadLaw};
    use crate::model::thread::WidthRule;
    use crate::model::Rng;

    const P: f64 = 2.0;

    /// An ISO M30x2 thread at the basic size, external or internal, its first feature at
    /// z = 0 going -z.
    fn m30(side: Side) -> ThreadSpec {
        let (d, d2, d1) = (30.0, 30.0 - 0.649519 * P, 30.0 - 1.082532 * P);
        let d3 = 30.0 - 1.226869 * P;
        let (root, crest) = match side {
            Side::External => (d3 / 2.0, d / 2.0),
            Side::Internal => (d / 2.0, d1 / 2.0),
        };
        ThreadSpec {
            side,
            root_radius: root,
            crest_radius: crest,
            pitch_radius: d2 / 2.0,
            left_angle: 30f64.to_radians(),
            right_angle: 30f64.to_radians(),
            width: WidthRule::Groove(P / 2.0),
            starts: 1,
            helix: Helix {
                z0: 0.0,
                dir: -1.0,
                law: LeadLaw::constant(P),
                theta0: 0.0,
                spin: 1.0,
            },
            turns: 10.0,
            outline: None,
        }
    }

    fn class(side: Side) -> ThreadClass {
        ThreadClass {
            designation: "M30x2-6g".into(),
            class: "6g".into(),
            units: crate::model::tolerance::UnitSystem::Metric,
            internal: side == Side::Internal,
            basic_major: 30.0,
            basic_pitch_diameter: 30.0 - 0.649519 * P,
            basic_minor: 30.0 - 1.082532 * P,
            pitch: P,
            starts: 1,
            flank_angle: 60f64.to_radians(),
            taper: 0.0,
            pitch_diameter: SizeLimits::new(28.493, 28.663),
            major_diameter: SizeLimits::new(29.682, 29.962),
            minor_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
            engagement_length: 0.0,
            not_go_turns: 2.0,
            root: None,
            source: "test".into(),
        }
    }

    /// The surface of a 60 deg thread on a generator: grooves (external: where the part is
    /// low) centred at `centres`, each of half-width P/4 at pitch radius `r2`, flanks
    /// tilted by `tilt` (rad, both flanks opening), clamped to the thread's radii.
    fn column(
        t: &ThreadSpec,
        theta: f64,
        r2: f64,
        centres: &[f64],
        tilt: f64,
        dz: f64,
        span: (f64, f64),
    ) -> GaugeColumn {
        let n = ((span.1 - span.0) / dz).round() as usize + 1;
        let cot = 1.0 / (30f64.to_radians() + tilt).tan();
        let (lo, hi) = (
            t.root_radius.min(t.crest_radius),
            t.root_radius.max(t.crest_radius),
        );
        let h = (0..n)
            .map(|j| {
                let z = span.0 + j as f64 * dz;
                let u = centres
                    .iter()
                    .map(|c| (z - c).abs())
                    .fold(f64::INFINITY, f64::min);
                // Distance from the groove centre: external, the radius grows with it
                // (the groove's wall); internal, it falls.
                let r = match t.side {
                    Side::External => r2 + (u - P / 4.0) * cot,
                    Side::Internal => r2 - (u - P / 4.0) * cot,
                };
                t.height(r.clamp(lo, hi)) as f32
            })
            .collect();
        GaugeColumn {
            theta,
            z0: span.0,
            dz,
            h,
        }
    }

    fn profile(side: Side) -> Profile {
        let c = class(side);
        Profile {
            pitch: P,
            cot: 1.0 / 30f64.to_radians().tan(),
            clear: match side {
                Side::External => 0.5 * (c.basic_pitch_diameter - c.basic_minor),
                Side::Internal => 0.5 * (c.basic_major - c.basic_pitch_diameter),
            },
            external: side == Side::External,
            truncated: false,
        }
    }

    /// The NOT GO gauge's truncated profile for [`class`] (band H/8).
    fn truncated(side: Side) -> Profile {
        Profile {
            clear: not_go_band(&class(side)),
            truncated: true,
            ..profile(side)
        }
    }

    /// The truncated NOT GO on a perfect thread reads its pitch diameter; with both flanks
    /// opened or closed by `d` (half-angle 30 + d, k = tan(30 + d)/tan 30 - 1) it reads
    /// `d2 + 2 |k| b/(1 + k)` (external; internal `-`): the part's flank crosses the gauge's at
    /// the band's edge `b` from the pitch line, at `b/(1 + k)` from the part's (the hand
    /// derivation in the module doc of `tests/integration/gauging.rs`). The full-profile
    /// gauge (crest `c` below its pitch line, the part's crest `y_c` above) reads
    /// `2 k c/(1 + k)` (opening) or `2 |k| y_c` (closing): more by the difference.
    #[test]
    fn the_truncated_not_go_reads_flank_angle_errors_at_its_band() {
        let dz = 0.0002;
        for side in [Side::External, Side::Internal] {
            let t = m30(side);
            let (ng, go) = (truncated(side), profile(side));
            let b = ng.clear;
            assert!((b - 0.125 * 0.866_025_4 * P).abs() < 1e-3, "band {b}");
            let sign = if side == Side::External { 1.0 } else { -1.0 };
            for (r2, deg) in [(14.29, 0.0), (14.30, 0.5), (14.27, -0.5), (14.31, 1.0)] {
                let tilt = f64::to_radians(deg);
                let centres: Vec<f64> = (0..=3).map(|k| -(k as f64) * P).collect();
                let span = (centres[3], 0.0);
                let cols = vec![column(&t, 0.0, r2, &centres, tilt, dz, span)];
                let pts = points(&t, &cols, P, span);
                let (r_ng, _) = functional_radius(&ng, &reduce(&ng, &pts), None);
                let (r_go, _) = functional_radius(&go, &reduce(&go, &pts), None);
                let k = (30f64.to_radians() + tilt).tan() / 30f64.to_radians().tan() - 1.0;
                let want_ng = 2.0 * r2 + sign * 2.0 * k.abs() * b / (1.0 + k);
                // The full profile: to the ring's crest (opening) or the part's crest
                // (closing), whichever the flank reaches first.
                let crest_y = (t.crest_radius - r2).abs();
                let root_y = (r2 - t.root_radius).abs();
                let full = if k > 0.0 {
                    k * (go.clear / (1.0 + k)).min(root_y)
                } else {
                    -k * crest_y
                };
                let want_go = 2.0 * r2 + sign * 2.0 * full;
                let tol = 2.0 * dz * go.cot + 1e-6;
                assert!(
                    (2.0 * r_ng - want_ng).abs() < tol,
                    "{side:?} {deg} deg: NOT GO {} vs {want_ng}",
                    2.0 * r_ng
                );
                assert!(
                    (2.0 * r_go - want_go).abs() < tol,
                    "{side:?} {deg} deg: full {} vs {want_go}",
                    2.0 * r_go
                );
                if deg != 0.0 {
                    // The truncated gauge reads less of the angle error than the full one.
                    assert!(sign * (r_go - r_ng) > 1e-4, "{side:?} {deg}");
                }
            }
        }
    }

    /// Parallel flanks with a lead error: the truncated NOT GO over two turns reads what a
    /// full-profile gauge over the same turns reads, the pitch diameter plus the lead's
    /// diameter equivalent over those two teeth (2 dp cot 30 for a longer lead, 0 for a
    /// shorter one, see `functional_size_is_the_pitch_diameter_plus_the_lead_equivalent`).
    #[test]
    fn the_truncated_not_go_reads_the_lead_over_its_turns() {
        for side in [Side::External, Side::Internal] {
            let t = m30(side);
            let (ng, go) = (truncated(side), profile(side));
            let sign = if side == Side::External { 1.0 } else { -1.0 };
            for (r2, dp) in [(14.29, 0.004), (14.32, -0.003), (14.28, 0.0)] {
                let centres: Vec<f64> = (0..=2).map(|k| -(k as f64) * (P + dp)).collect();
                let span = (centres[2], 0.0);
                let cols = vec![column(&t, 0.0, r2, &centres, 0.0, 0.0002, span)];
                let pts = points(&t, &cols, P, span);
                let (r_ng, _) = functional_radius(&ng, &reduce(&ng, &pts), None);
                let (r_go, _) = functional_radius(&go, &reduce(&go, &pts), None);
                let want = 2.0 * r2 + sign * 2.0 * dp.max(0.0) * go.cot;
                let tol = 2.0 * 0.0002 * go.cot + 1e-6;
                assert!(
                    (2.0 * r_ng - want).abs() < tol && (2.0 * r_go - want).abs() < tol,
                    "{side:?} dp {dp}: NOT GO {} full {} vs {want}",
                    2.0 * r_ng,
                    2.0 * r_go
                );
            }
        }
    }

    /// A perfect thread's functional size is its pitch diameter; a cumulative lead error
    /// adds |dP_sum| cot(a/2) on diameter (external) or takes it off (internal): the
    /// diameter-equivalent formula of `thread-gauging.md`, as a test of the envelope.
    #[test]
    fn functional_size_is_the_pitch_diameter_plus_the_lead_equivalent() {
        for side in [Side::External, Side::Internal] {
            let t = m30(side);
            let p = profile(side);
            for (r2, dp, teeth) in [
                (14.29, 0.0, 6),
                (14.25, 0.004, 6),
                (14.31, -0.003, 9),
                (14.35, 0.01, 3),
            ] {
                // Grooves at 0, -(P+dp), ...; the span from the first groove's centre to
                // the last's: whole teeth only.
                let centres: Vec<f64> = (0..=teeth).map(|k| -(k as f64) * (P + dp)).collect();
                let span = (centres[teeth], 0.0);
                let cols: Vec<GaugeColumn> = [0.0]
                    .iter()
                    .map(|&th| column(&t, th, r2, &centres, 0.0, 0.0002, span))
                    .collect();
                let pts = points(&t, &cols, P, span);
                let (r, _) = functional_radius(&p, &pts, None);
                // Tooth k lies between grooves k and k+1. Against a ring of perfect pitch
                // its +z flank (the wall of groove k) is shifted by -k dp and its -z flank
                // (the wall of groove k+1) by -(k+1) dp. A flank shifted by s against the
                // ring's phase phi needs (s - phi) cot(a/2) more radius (+z flanks) or
                // (phi - s) cot(a/2) (-z flanks): the best ring takes phi halfway, and the
                // diameter grows by (max s+ - min s-) cot(a/2): the cumulative pitch
                // deviation between the outermost engaged flanks (teeth dp for dp > 0; for
                // dp < 0 the narrower teeth give back two pitches of it).
                let s_plus = (0..teeth)
                    .map(|k| -(k as f64) * dp)
                    .fold(f64::MIN, f64::max);
                let s_minus = (0..teeth)
                    .map(|k| -(k as f64 + 1.0) * dp)
                    .fold(f64::MAX, f64::min);
                let drift = s_plus - s_minus;
                let sign = if side == Side::External { 1.0 } else { -1.0 };
                let want = 2.0 * r2 + sign * drift * p.cot;
                assert!(
                    (2.0 * r - want).abs() < 2.0 * 0.0002 * p.cot + 1e-6,
                    "{side:?} r2 {r2} dp {dp}: {} vs {want}",
                    2.0 * r
                );
            }
        }
    }

    /// The search against a dense scan of the phase (an independent minimisation) on
    /// random threads: random tooth shifts, flank tilts and pitch radii.
    #[test]
    fn the_phase_search_finds_the_scans_optimum() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for case in 0..24 {
            let side = if case % 2 == 0 {
                Side::External
            } else {
                Side::Internal
            };
            let t = m30(side);
            let p = profile(side);
            let r2 = rng.range(14.2, 14.35);
            let teeth = 3 + (rng.next() * 5.0) as usize;
            let centres: Vec<f64> = (0..=teeth)
                .map(|k| -(k as f64) * P + rng.range(-0.02, 0.02) + 0.3)
                .collect();
            let tilt = rng.range(-0.01, 0.01);
            let span = (centres[teeth] - 0.5, centres[0] + 0.5);
            let cols = vec![
                column(&t, 0.0, r2, &centres, tilt, 0.001, span),
                column(&t, 1.0, r2 + 0.01, &centres, 0.0, 0.001, span),
            ];
            let pts = points(&t, &cols, P, span);
            let (r, _) = functional_radius(&p, &pts, None);
            let scan = (0..2000)
                .map(|k| size_at(&p, &pts, k as f64 * P / 2000.0))
                .fold(
                    if p.external {
                        f64::INFINITY
                    } else {
                        f64::NEG_INFINITY
                    },
                    |a, b| if p.external { a.min(b) } else { a.max(b) },
                );
            // The scan's step is P/2000 in phase: at most that times cot(a/2) in radius
            // above (ring) or below (plug) the true optimum.
            let slack = P / 2000.0 * p.cot;
            if p.external {
                assert!(
                    r <= scan + 1e-9 && r >= scan - slack,
                    "{case}: {r} vs {scan}"
                );
            } else {
                assert!(
                    r >= scan - 1e-9 && r <= scan + slack,
                    "{case}: {r} vs {scan}"
                );
            }
        }
    }

    /// The calls: a value within the resolution of a limit is undecided, beyond it a
    /// fail, inside a pass; nothing measured is said.
    #[test]
    fn calls_respect_the_resolution() {
        let res = 0.002;
        assert_eq!(call(Some(28.6), 28.663, true, res), Call::Pass);
        assert_eq!(call(Some(28.662), 28.663, true, res), Call::Undecided);
        assert_eq!(call(Some(28.6645), 28.663, true, res), Call::Undecided);
        assert_eq!(call(Some(28.67), 28.663, true, res), Call::Fail);
        assert_eq!(call(Some(28.49), 28.493, false, res), Call::Fail);
        assert_eq!(call(Some(28.6), 28.493, false, res), Call::Pass);
        assert_eq!(call(None, 28.493, false, res), Call::NotMeasured);
        assert_eq!(Call::Pass.worse(Call::Undecided), Call::Undecided);
        assert_eq!(Call::Fail.worse(Call::Undecided), Call::Fail);
    }

    /// Over-wire values of `thread-gauging.md`: M20x2.5-6g over best wires (1.4434 mm) is
    /// 20.329 .. 20.499 mm for d2 18.164 .. 18.334.
    #[test]
    fn over_wires_match_the_published_example() {
        let half = 30f64.to_radians();
        let p = 2.5;
        let w = p / (2.0 * half.cos());
        let m = |d2: f64| d2 + w * (1.0 + 1.0 / half.sin()) - 0.5 * p / half.tan();
        assert!((w - 1.4434).abs() < 5e-5);
        assert!((m(18.164) - 20.329).abs() < 5e-4, "{}", m(18.164));
        assert!((m(18.334) - 20.499).abs() < 5e-4, "{}", m(18.334));
        let _ = class(Side::External);
    }
}
