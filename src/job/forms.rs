//! Thread standards and forms: the form's name, the standard depth data of each form
//! (`form_defaults`) and `[thread]` resolved into a [`ThreadSpec`] checked against the blank
//! (the keys a designation or class fills come from `standard`).

use super::ctx::Ctx;
use super::schema::{HandName, RawPitch, RawThread, RawWidth};
use super::standard;
use super::JobError;
use crate::model::helix::{Hand, Helix, LeadLaw};
use crate::model::setup::Blank;
use crate::model::thread::{Side, ThreadSpec, WidthRule};
use crate::model::tolerance::ThreadClass;
use serde::Deserialize;

/// The thread form's name, as written in the job.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FormName {
    /// Rectangular / square thread.
    Square,
    /// ISO 2904 trapezoidal, 30 degrees.
    Trapezoidal,
    /// ISO 68-1 metric, 60 degrees.
    IsoMetric,
    /// Unified (UN), 60 degrees.
    Unified,
    /// ACME, 29 degrees.
    Acme,
    /// Buttress (sawtooth): asymmetric flanks.
    Buttress,
    /// Any V or trapezoid with explicit flank angles.
    V,
}

impl FormName {
    /// The name as written in a job.
    pub fn name(self) -> &'static str {
        match self {
            FormName::Square => "square",
            FormName::Trapezoidal => "trapezoidal",
            FormName::IsoMetric => "iso-metric",
            FormName::Unified => "unified",
            FormName::Acme => "acme",
            FormName::Buttress => "buttress",
            FormName::V => "v",
        }
    }
}

/// Standard depth data of a form for a constant pitch `p`: (included angle, minor
/// diameter from major `d`, pitch diameter from `d`).
fn form_defaults(
    form: FormName,
    side: Side,
    d: f64,
    p: Option<f64>,
) -> (Option<f64>, Option<f64>, Option<f64>) {
    match (form, p) {
        (FormName::Square, _) => (Some(0.0), None, None),
        (FormName::Trapezoidal, Some(p)) => {
            // ISO 2904: h3 = 0.5P + ac, d2 = d - 0.5P.
            let ac = if p <= 1.5 {
                0.15
            } else if p <= 5.0 {
                0.25
            } else if p <= 12.0 {
                0.5
            } else {
                1.0
            };
            (
                Some(30.0),
                Some(d - 2.0 * (0.5 * p + ac)),
                Some(d - 0.5 * p),
            )
        }
        (FormName::Trapezoidal, None) => (Some(30.0), None, None),
        (FormName::IsoMetric | FormName::Unified, Some(p)) => {
            // ISO 68-1: d2 = d - 0.649519P; external design root d3 = d - 1.226869P,
            // internal minor D1 = D - 1.082532P.
            let minor = match side {
                Side::External => d - 1.226_869 * p,
                Side::Internal => d - 1.082_532 * p,
            };
            (Some(60.0), Some(minor), Some(d - 0.649_519 * p))
        }
        (FormName::IsoMetric | FormName::Unified, None) => (Some(60.0), None, None),
        (FormName::Acme, Some(p)) => (
            Some(29.0),
            Some(d - 2.0 * (0.5 * p + 0.254)),
            Some(d - 0.5 * p),
        ),
        (FormName::Acme, None) => (Some(29.0), None, None),
        (FormName::Buttress | FormName::V, _) => (None, None, None),
    }
}

/// A length for a message: at most 4 decimals, no trailing zeros, no 300-digit values.
fn fmt_mm(v: f64) -> String {
    if !v.is_finite() || v.abs() >= 1e9 {
        return format!("{v:.3e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// `[thread]` resolved: the ideal thread, its form, and the tolerance class's limits when
/// the drawing names one.
pub(super) fn resolve_thread(
    t: &RawThread,
    blank: &Blank,
    cx: &Ctx,
) -> Result<(ThreadSpec, FormName, Option<ThreadClass>), JobError> {
    let named = standard::named(t, cx)?;
    let side = named.side;
    let major = cx.positive("thread.major_diameter", named.major)?;
    let starts = named.starts;
    if starts == 0 || starts > 64 {
        return Err(cx.err("thread.starts", "expected 1 to 64 starts"));
    }
    let form = named.form;
    let mut class = named.class;
    // Pitch law: F = P1 - dP/2, K = dP gives P_n = P1 + (n-1) dP between whole turns.
    let (p1, dp, series_turns, constant) = match &named.pitch {
        RawPitch::Constant(p) => (cx.positive("thread.pitch", *p)?, 0.0, None, Some(*p)),
        RawPitch::Series(s) => {
            let p1 = cx.positive("thread.pitch.first", s.first)?;
            let dp = cx.finite("thread.pitch.increment", s.increment)?;
            let turns = match (s.last, s.turns) {
                (Some(last), None) => {
                    cx.positive("thread.pitch.last", last)?;
                    if dp == 0.0 {
                        return Err(cx.err("thread.pitch.increment", "expected a non-zero increment with `last` (use a number for constant pitch)"));
                    }
                    let n = (last - p1) / dp + 1.0;
                    if n < 1.0 - 1e-9 || (n - n.round()).abs() > 1e-6 {
                        return Err(cx.err("thread.pitch.last", format!("expected first + (n-1)*increment for a whole number of turns n; (last - first)/increment + 1 = {n}")));
                    }
                    n.round()
                }
                (None, Some(n)) => cx.positive("thread.pitch.turns", n)?,
                _ => {
                    return Err(cx.err("thread.pitch", "expected exactly one of `last` or `turns`"))
                }
            };
            (p1, dp, Some(turns), None)
        }
    };
    let turns = match (series_turns, t.length, t.turns) {
        (Some(n), None, None) => n,
        (Some(_), _, _) => {
            return Err(cx.err(
                "thread.turns",
                "the pitch series already gives the number of turns",
            ))
        }
        // Turns are revolutions of the pitch helix: a multi-start thread advances a lead
        // (starts x pitch) per turn.
        (None, Some(len), None) => cx.positive("thread.length", len)? / (p1 * starts as f64),
        (None, None, Some(n)) => cx.positive("thread.turns", n)?,
        (None, Some(_), Some(_)) => {
            return Err(cx.err("thread.turns", "expected `length` or `turns`, not both"))
        }
        (None, None, None) => {
            return Err(cx.err(
                "thread",
                "expected `length` (mm) or `turns` for a constant pitch",
            ))
        }
    };
    if turns > 100_000.0 {
        return Err(cx.err("thread", format!("{turns} turns: at most 100000")));
    }
    if turns < 1.0 {
        // A pitch far longer than the thread (`pitch = 1e4` over 72 mm) leaves nothing to
        // measure: no turn, no flank pair, an empty report.
        let key = match (series_turns, t.length) {
            (Some(_), _) => "thread.pitch",
            (None, Some(_)) => "thread.length",
            (None, None) => "thread.turns",
        };
        return Err(cx.err(
            key,
            format!("the thread has {turns:.4} turns (its length over the pitch {p1} mm): expected at least one"),
        ));
    }
    let law = LeadLaw {
        f: starts as f64 * (p1 - dp / 2.0),
        k: starts as f64 * dp,
    };
    for (n, key) in [
        (0.0, "thread.pitch.first"),
        (turns, "thread.pitch.increment"),
    ] {
        if law.lead(n) <= 0.0 {
            return Err(cx.err(
                key,
                format!(
                    "the lead law F + K*t = {} + {}*t is not positive at t = {n}",
                    law.f, law.k
                ),
            ));
        }
    }
    let (std_angle, std_minor, std_pitch) = match named.profile {
        Some((angle, minor, pitch_d)) => (Some(angle), Some(minor), Some(pitch_d)),
        None => form_defaults(form, side, major, constant),
    };
    let (left, right) = match (t.flank_angles, t.flank_angle, std_angle, form) {
        (Some([l, r]), None, _, FormName::V | FormName::Buttress) => (l, r),
        (Some(_), _, _, _) => return Err(cx.err("thread.flank_angles", "`flank_angles` is for the `v` and `buttress` forms; use `flank_angle` (included) for symmetric forms")),
        (None, Some(a), _, FormName::Trapezoidal | FormName::V | FormName::Acme) => (a / 2.0, a / 2.0),
        (None, Some(_), _, _) => return Err(cx.err("thread.flank_angle", "this form has a fixed flank angle")),
        (None, None, Some(a), _) => (a / 2.0, a / 2.0),
        (None, None, None, FormName::Buttress) => (3.0, 30.0),
        (None, None, None, _) => return Err(cx.err("thread.flank_angles", "expected [left, right] flank angles in degrees from the radial direction")),
    };
    let left_angle = cx.angle("thread.flank_angles", left, 0.0, 80.0)?;
    let right_angle = cx.angle("thread.flank_angles", right, 0.0, 80.0)?;
    let minor = match (t.minor_diameter, std_minor) {
        (Some(m), _) => cx.positive("thread.minor_diameter", m)?,
        // A class allows the internal thread's crest anywhere in its D1 limits: a tap-drill
        // bore above the basic minor diameter is the crest.
        (None, Some(m))
            if side == Side::Internal
                && class.is_some()
                && named.taper.is_none()
                && blank.bore > m =>
        {
            blank.bore
        }
        (None, Some(m)) => m,
        (None, None) => {
            return Err(cx.err(
                "thread.minor_diameter",
                "expected a minor diameter (no standard depth for this form and pitch)",
            ))
        }
    };
    if minor >= major {
        return Err(cx.err(
            "thread.minor_diameter",
            format!("expected less than major_diameter = {major}"),
        ));
    }
    let pitch_d = match (t.pitch_diameter, std_pitch) {
        (Some(p), _) => cx.positive("thread.pitch_diameter", p)?,
        (None, Some(p)) => p,
        (None, None) => 0.5 * (major + minor),
    };
    if pitch_d <= minor || pitch_d >= major {
        return Err(cx.err(
            "thread.pitch_diameter",
            format!("expected between the minor ({minor}) and major ({major}) diameters"),
        ));
    }
    // With a class, the crest may lie anywhere in its limits: a bar turned to the
    // external major diameter's, a bore drilled to the internal minor diameter's.
    let crest_limits = class.as_ref().map(|c| match side {
        Side::External => c.major_diameter,
        Side::Internal => c.minor_diameter,
    });
    let mut major = major;
    // A taper thread's crest is a cone: the blank (a cylinder) bounds it only on the
    // thread's face, where its radii are given.
    match (side, crest_limits) {
        (_, Some(_)) if named.taper.is_some() => {
            if side == Side::External && major > blank.diameter + 1e-9 {
                return Err(cx.err(
                    "blank.diameter",
                    format!(
                        "the blank ({} mm) is smaller than the major diameter of {} at its small end ({} mm)",
                        fmt_mm(blank.diameter),
                        class.as_ref().map_or("", |c| c.designation.as_str()),
                        fmt_mm(major)
                    ),
                ));
            }
            if side == Side::Internal && (blank.bore == 0.0 || major >= blank.diameter) {
                return Err(cx.err(
                    "blank.bore",
                    "an internal taper thread needs a bore and a blank larger than its major diameter at the face",
                ));
            }
        }
        (Side::External, Some(l)) if major > blank.diameter + 1e-9 => {
            if blank.diameter < l.min - 1e-9 {
                return Err(cx.err(
                    "blank.diameter",
                    format!(
                        "the blank ({} mm) is smaller than the least major diameter of {} ({} mm): expected a blank of at least that",
                        fmt_mm(blank.diameter),
                        class.as_ref().map_or("", |c| c.designation.as_str()),
                        fmt_mm(l.min)
                    ),
                ));
            }
            // The crest is the turned bar.
            major = blank.diameter;
        }
        (Side::External, None) if major > blank.diameter + 1e-9 => {
            return Err(cx.err(
                "thread.major_diameter",
                format!(
                    "an external thread must fit the blank: major {major} > blank diameter {}",
                    blank.diameter
                ),
            ));
        }
        (Side::Internal, Some(l)) if blank.bore == 0.0 || blank.bore > l.max + 1e-9 => {
            return Err(cx.err(
                "blank.bore",
                format!(
                    "an internal thread of {} needs a bore no larger than its greatest minor diameter D1 max = {} mm (blank.bore = {})",
                    class.as_ref().map_or("", |c| c.designation.as_str()),
                    fmt_mm(l.max),
                    fmt_mm(blank.bore)
                ),
            ));
        }
        (Side::Internal, None) if minor < blank.bore - 1e-9 || blank.bore == 0.0 => {
            return Err(cx.err("thread.minor_diameter", format!("an internal thread needs a bore no larger than its minor diameter (blank.bore = {})", blank.bore)));
        }
        (Side::Internal, _) if major >= blank.diameter => {
            return Err(cx.err(
                "thread.major_diameter",
                "an internal thread must stay inside the blank's outer diameter",
            ));
        }
        _ => {}
    }
    let (root_radius, crest_radius) = match side {
        Side::External => (minor / 2.0, major / 2.0),
        Side::Internal => (major / 2.0, minor / 2.0),
    };
    let width = match (&t.width, constant) {
        (
            Some(RawWidth {
                groove: Some(w),
                tooth: None,
            }),
            _,
        ) => WidthRule::Groove(cx.positive("thread.width.groove", *w)?),
        (
            Some(RawWidth {
                groove: None,
                tooth: Some(w),
            }),
            _,
        ) => WidthRule::Tooth(cx.positive("thread.width.tooth", *w)?),
        (Some(_), _) => {
            return Err(cx.err(
                "thread.width",
                "expected exactly one of { groove = .. } or { tooth = .. }",
            ))
        }
        (None, Some(p)) => WidthRule::Groove(p / 2.0),
        (None, None) => {
            return Err(cx.err(
                "thread.width",
                "a variable pitch needs `width = { groove = .. }` or `{ tooth = .. }`",
            ))
        }
    };
    let helix = Helix {
        z0: cx.finite("thread.z_start", t.z_start.unwrap_or(0.0))?,
        dir: -1.0,
        law,
        theta0: cx
            .finite("thread.start_angle", t.start_angle.unwrap_or(0.0))?
            .to_radians(),
        spin: match named.hand {
            HandName::Right => 1.0,
            HandName::Left => -1.0,
        },
    };
    let spec = ThreadSpec {
        side,
        root_radius,
        crest_radius,
        pitch_radius: pitch_d / 2.0,
        left_angle,
        right_angle,
        width,
        starts,
        helix,
        turns,
        outline: None,
        // The cones' reference: the thread's face (its given start, else the blank's front).
        taper: named.taper.map(|slope| crate::model::thread::Taper {
            slope,
            z_ref: t.z_start.unwrap_or(blank.z_front),
        }),
    };
    debug_assert_eq!(
        spec.hand(),
        if named.hand == HandName::Right {
            Hand::Right
        } else {
            Hand::Left
        }
    );
    // The drawing's thread must have something on the blank: a thread may start in front
    // of a face or run out through one (a through-threaded part, a program that starts a
    // pre-cut turn early), and what lies on the blank is compared; a thread wholly off the
    // stock could never be cut and would compare nothing. Without `z_start` the thread is
    // placed on the cut later (`analysis::place`), on the blank by construction.
    if t.z_start.is_some() {
        on_blank(&spec, blank, cx, t)?;
    }
    // Shapes that cannot exist.
    let hp = spec.pitch_height();
    let widen = spec.widening();
    let depth = spec.depth();
    let pitches = [
        spec.pitch_of_turn(1),
        spec.pitch_of_turn(turns.ceil().max(1.0) as i64),
    ];
    let (p_min, p_max) = (pitches[0].min(pitches[1]), pitches[0].max(pitches[1]));
    match width {
        WidthRule::Groove(w) => {
            if w - hp * widen < -1e-9 {
                return Err(cx.err("thread.width.groove", format!("the groove closes before the root: width {w} at the pitch line leaves {:.4} mm at the root", w - hp * widen)));
            }
            if w - hp * widen >= p_min {
                return Err(cx.err("thread.width.groove", format!("the groove's root ({:.4} mm) is wider than the smallest pitch ({p_min:.4} mm): no tooth is left", w - hp * widen)));
            }
        }
        WidthRule::Tooth(tw) => {
            if tw >= p_min {
                return Err(cx.err(
                    "thread.width.tooth",
                    format!(
                        "expected a tooth narrower than the first pitch ({p_min:.4} mm), got {tw}"
                    ),
                ));
            }
            if tw - (depth - hp) * widen < -1e-9 {
                return Err(cx.err("thread.width.tooth", "the tooth comes to a point below the crest: widen it or use a smaller flank angle"));
            }
            if p_min - tw - hp * widen < -1e-9 {
                return Err(cx.err(
                    "thread.width.tooth",
                    "the groove between the first teeth closes before the root",
                ));
            }
        }
    }
    let _ = p_max;
    // The GO gauge checks the length of engagement, and never more than the thread.
    if let Some(c) = class.as_mut() {
        let length = (spec.helix.z(turns) - spec.helix.z0).abs();
        c.engagement_length = c.engagement_length.min(length);
    }
    Ok((spec, form, class))
}

/// Whether any of the thread, from its first feature to its last with half a lead of
/// groove either side, lies on the blank; the error names the key to change.
pub(super) fn on_blank(
    spec: &ThreadSpec,
    blank: &Blank,
    cx: &Ctx,
    t: &RawThread,
) -> Result<(), JobError> {
    let law = spec.helix.law;
    let turns = spec.turns;
    let (z_first, z_last) = (spec.helix.z0, spec.helix.z(turns));
    let (b_lo, b_hi) = (blank.z_front - blank.length, blank.z_front);
    let slack = 0.5 * law.lead(0.0).max(law.lead(turns));
    let (t_lo, t_hi) = (z_first.min(z_last) - slack, z_first.max(z_last) + slack);
    if t_hi > b_lo && t_lo < b_hi {
        return Ok(());
    }
    let key = if t.z_start.is_some() {
        "thread.z_start"
    } else if t.length.is_some() {
        "thread.length"
    } else if t.turns.is_some() {
        "thread.turns"
    } else {
        "thread.pitch"
    };
    Err(cx.err(
        key,
        format!(
            "the thread runs from z {} to z {} (its first to its last turn), wholly off the blank (z {} to {}): nothing of it can be cut; expected a thread with at least part of a groove on the blank",
            fmt_mm(z_first),
            fmt_mm(z_last),
            fmt_mm(b_lo),
            fmt_mm(b_hi),
        ),
    ))
}
