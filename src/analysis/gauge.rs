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
//! - **NOT GO (truncated profile).** The NOT GO gauge of ISO 1502 and ASME B1.2 touches the
//!   flanks only near its pitch line: a perfect gauge whose crest is truncated and whose
//!   root is relieved `b` from its pitch line (`not_go_band`), over `not_go_turns` turns. Its
//!   envelope is the GO's with that profile (see `bound`), over each window of that many
//!   complete turns on every generator; the thread fails when, in some window, the gauge
//!   that just assembles is past the minimum-material limit (a smaller ring would enter).
//!   It reads a flank-angle error only within its band and a lead error over its turns.
//!   Beside it, the single elements: the simple pitch diameter (the groove half a pitch
//!   wide, `measure::pitch_level`) per turn on every generator, minimum and maximum, and
//!   the windows' largest (external) or smallest (internal).
//! - **Major / minor diameter**: the crests of the complete turns (both grooves found at the
//!   pitch line) against the class's limits; the root's diameter, and an external ISO
//!   thread's root radius (`root`, advisory: ISO 965-1 recommends it).
//! - **Taper threads** (`taper`): the taper gauge's stand-off from the gauge plane, in turns.
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

mod root;
mod taper;

pub(crate) use taper::StandOff;

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
    /// A recommendation rather than a limit (ISO 965-1's least root radius): its call is
    /// reported, a failure as a warning, and does not decide the verdict.
    pub advisory: bool,
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
    /// The least effective root radius of the complete turns (external threads whose
    /// class has a root zone; mm) and the turn it was found on.
    pub root_radius: Option<(f64, i64)>,
    /// A taper thread's gauge: where it stopped against its gauge plane.
    pub stand_off: Option<StandOff>,
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
    /// The gauge's walls' cotangents on the -z and +z side of its groove (ring) or tooth
    /// (plug) centre: `cot` both for a parallel thread; a taper's walls, seen against its
    /// pitch cone, differ (see `taper`).
    cot_lo: f64,
    cot_hi: f64,
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
    let xs = x - p.pitch * (x / p.pitch).round();
    let u = xs.abs();
    let cot = if xs >= 0.0 { p.cot_hi } else { p.cot_lo };
    let need = r - (0.25 * p.pitch - u) * cot;
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
    if class.taper_gauge.is_some() && thread.taper.is_some() {
        return taper::judge(thread, class, columns, spacing);
    }
    let profile = Profile {
        pitch: class.pitch,
        cot_lo: cot,
        cot_hi: cot,
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
        + 2.0 * cot * class.pitch / NG_BINS as f64
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
    // The root's radius against ISO 965-1's recommended least (external threads with a
    // root zone), measured up to twice that.
    let radius = class.root.filter(|_| external).and_then(|zone| {
        let r = zone.radius_min;
        root::root_radius(thread, columns, turns, r, 2.0 * r, 0.5 * rounding).map(|f| (r, f))
    });
    // A gap of `g` is a radius `g / (1/sin(b/2) - 1)` short at a corner of angle `b`; the
    // widest corner a root has is a flat root's, b = 90 deg + a/2: its factor bounds the
    // radius's resolution.
    let corner_factor = 1.0 / (std::f64::consts::FRAC_PI_4 + 0.25 * class.flank_angle).sin() - 1.0;
    let radius_res = radius.map_or(0.0, |(_, f)| f.2 / corner_factor);
    let mut elements = Vec::new();
    let mut element = |name: &'static str, value: Option<f64>, limit: f64, upper: bool| {
        if limit.is_finite() {
            let res = match name {
                "go_functional_pitch_diameter" => go_res,
                "not_go_pitch_diameter" => ng_res,
                "root_radius" => radius_res,
                _ => simple_res,
            };
            elements.push(Element {
                name,
                value,
                limit,
                upper,
                resolution: res,
                call: call(value, limit, upper, res),
                advisory: name == "root_radius",
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
    if let Some((r_min, (rho, _, _))) = radius {
        element("root_radius", Some(rho), r_min, false);
    }
    let verdict = elements
        .iter()
        .filter(|e| !e.advisory)
        .fold(Call::Pass, |v, e| v.worse(e.call));
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
        root_radius: radius.map(|(_, f)| (f.0, f.1)),
        stand_off: None,
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
    // The best phase over every complete window at once seeds each window's search.
    let (lo, hi) = match (complete.first(), complete.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => return None,
    };
    let all = points_by(thread, columns, p.pitch, &|theta| {
        let phase = helix.phase_at(theta);
        let (a, b) = (helix.z(lo as f64 - 1.0 + phase), helix.z(hi as f64 + phase));
        (a.min(b), a.max(b))
    });
    if all.is_empty() {
        return None;
    }
    let (_, phi0) = functional_radius(p, &reduce_in(p, &all, NG_BINS), None);
    drop(all);
    // Each window's gauge on its own (in parallel), the worst taken in turn order.
    use rayon::prelude::*;
    let firsts: Vec<i64> = complete
        .iter()
        .copied()
        .filter(|&first| (first..first + k).all(|t| complete.contains(&t)))
        .collect();
    let sizes: Vec<Option<(f64, i64, bool)>> = firsts
        .par_iter()
        .map(|&first| {
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
                return None;
            }
            let (_, phi) = functional_radius(p, &reduce_in(p, &pts, NG_BINS), Some(phi0));
            let r = size_at(p, &pts, phi);
            r.is_finite()
                .then(|| (2.0 * r, first, corner(p, &pts, phi, r, rounding)))
        })
        .collect();
    let mut worst: Option<(f64, i64, bool)> = None;
    for (d, first, at_corner) in sizes.into_iter().flatten() {
        let worse = worst.is_none_or(|(v, _, _)| if p.external { d < v } else { d > v });
        if worse {
            worst = Some((d, first, at_corner));
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

/// Bins of the NOT GO's search (its windows are many and short: a coarser search, the
/// size then from every point as for the GO): 2^13, 0.25 um at a 2 mm pitch.
const NG_BINS: usize = 1 << 13;

/// The points reduced to the binding one per bin of offset (in bin order: deterministic).
fn reduce(p: &Profile, pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
    reduce_in(p, pts, BINS)
}

/// [`reduce`] into `bins` bins per pitch.
fn reduce_in(p: &Profile, pts: &[(f64, f64)], bins: usize) -> Vec<(f64, f64)> {
    let mut best: Vec<Option<(f64, f64)>> = vec![None; bins];
    for &(z, r) in pts {
        let u = z - p.pitch * (z / p.pitch).round();
        let k = (((u / p.pitch + 0.5) * bins as f64) as usize).min(bins - 1);
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
mod tests;
