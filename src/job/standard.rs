//! `[thread] designation` and `class`: the drawing's thread as its designation names it
//! (`M30x2-6g`, `1/2-13 UNC-2B`), read by `model::standards` into the keys it fills (form,
//! major diameter, pitch, starts, hand, side) and the tolerance class's limits. Keys given
//! beside a designation must agree with it: a contradiction is an error naming both.
//! `class` alone gives the limits for the explicit form, major diameter and pitch (the
//! standards' formulas where their tables do not list the size).

use super::ctx::Ctx;
use super::forms::FormName;
use super::schema::{HandName, RawPitch, RawThread, SideName};
use super::JobError;
use crate::model::standards::{self, Designation, Form, Standard};
use crate::model::thread::Side;
use crate::model::tolerance::ThreadClass;

/// The `[thread]` keys a designation or a class fills, resolved: what `forms` builds the
/// thread from.
pub(super) struct Named {
    /// The form.
    pub(super) form: FormName,
    /// Basic major diameter (mm).
    pub(super) major: f64,
    /// The pitch law as the keys give it.
    pub(super) pitch: RawPitch,
    /// Number of starts.
    pub(super) starts: u32,
    /// Hand.
    pub(super) hand: HandName,
    /// Which surface.
    pub(super) side: Side,
    /// The basic profile where the job's forms have none (Whitworth G, Rp): included
    /// angle (degrees), minor and pitch diameters (mm).
    pub(super) profile: Option<(f64, f64, f64)>,
    /// The tolerance class's limits.
    pub(super) class: Option<ThreadClass>,
    /// A taper thread's slope (radius per mm of z, signed; its radii above are at the
    /// thread's face).
    pub(super) taper: Option<f64>,
}

fn side_of(s: SideName) -> Side {
    match s {
        SideName::External => Side::External,
        SideName::Internal => Side::Internal,
    }
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::External => "external",
        Side::Internal => "internal",
    }
}

/// A number for a message: at most 4 decimals, no trailing zeros.
fn num(v: f64) -> String {
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The job's form for a standard's profile family.
fn form_name(f: Form) -> FormName {
    match f {
        Form::IsoMetric => FormName::IsoMetric,
        Form::Unified => FormName::Unified,
        Form::Trapezoidal => FormName::Trapezoidal,
        Form::Acme => FormName::Acme,
        Form::Whitworth => FormName::V,
    }
}

/// The `[thread]` keys resolved from `designation`, `class` and the keys beside them.
pub(super) fn named(t: &RawThread, cx: &Ctx) -> Result<Named, JobError> {
    match &t.designation {
        Some(text) => designated(t, text, cx),
        None => explicit(t, cx),
    }
}

/// Without a designation: the keys as given (form, major diameter and pitch required),
/// and `class`'s limits.
fn explicit(t: &RawThread, cx: &Ctx) -> Result<Named, JobError> {
    let form = t.form.ok_or_else(|| {
        cx.err(
            "thread.form",
            "missing: expected `form` (the thread's form) or a `designation` (M30x2-6g, 1/2-13 UNC-2B)",
        )
    })?;
    let major = t.major_diameter.ok_or_else(|| {
        cx.err(
            "thread.major_diameter",
            "missing: expected `major_diameter` (mm) or a `designation`",
        )
    })?;
    let pitch = t.pitch.clone().ok_or_else(|| {
        cx.err(
            "thread.pitch",
            "missing: expected `pitch` (mm, or a series table) or a `designation`",
        )
    })?;
    let starts = t.starts.unwrap_or(1);
    let mut side = t.side.map_or(Side::External, side_of);
    let class = match &t.class {
        None => None,
        Some(text) => {
            let key = "thread.class";
            let std_form = match form {
                FormName::IsoMetric => Form::IsoMetric,
                FormName::Unified => Form::Unified,
                FormName::Trapezoidal => Form::Trapezoidal,
                FormName::Acme => Form::Acme,
                _ => {
                    return Err(cx.err(
                        key,
                        format!(
                            "a tolerance class is for the iso-metric, unified, trapezoidal and acme forms, not `{}`; for another thread give its `designation` (G1/2 A)",
                            form.name()
                        ),
                    ))
                }
            };
            let RawPitch::Constant(p) = pitch else {
                return Err(cx.err(key, "a tolerance class needs a constant `pitch`"));
            };
            let major = cx.positive("thread.major_diameter", major)?;
            let p = cx.positive("thread.pitch", p)?;
            if !(1..=64).contains(&starts) {
                return Err(cx.err("thread.starts", "expected 1 to 64 starts"));
            }
            let c = standards::class_for(std_form, major, p, starts, text)
                .map_err(|e| cx.err(key, e.message))?;
            let class_side = if c.internal {
                Side::Internal
            } else {
                Side::External
            };
            if let Some(s) = t.side.map(side_of).filter(|&s| s != class_side) {
                return Err(cx.err(
                    "thread.side",
                    format!(
                        "`side = \"{}\"` contradicts `class = \"{text}\"`, an {} class",
                        side_name(s),
                        side_name(class_side)
                    ),
                ));
            }
            side = class_side;
            Some(c)
        }
    };
    Ok(Named {
        form,
        major,
        pitch,
        starts,
        hand: t.hand.unwrap_or_default(),
        side,
        profile: None,
        class,
        taper: None,
    })
}

/// With a designation: its keys, each key beside it checked against it.
fn designated(t: &RawThread, text: &str, cx: &Ctx) -> Result<Named, JobError> {
    let key = "thread.designation";
    let d = standards::parse(text).map_err(|e| cx.err(key, e.message))?;
    if t.class.is_some() {
        return Err(cx.err(
            "thread.class",
            format!(
                "`class` and `designation = \"{}\"` both give the class: write it in the designation (M30x2-6g)",
                d.text
            ),
        ));
    }
    let form = form_name(d.form());
    let contradiction = |k: &str, given: String, says: String| {
        cx.err(
            &format!("thread.{k}"),
            format!(
                "`{k} = {given}` contradicts `designation = \"{}\"`, which gives {says}",
                d.text
            ),
        )
    };
    if let Some(f) = t.form.filter(|&f| f != form) {
        return Err(contradiction(
            "form",
            format!("\"{}\"", f.name()),
            format!("the form `{}`", form.name()),
        ));
    }
    if let Some(m) = t
        .major_diameter
        .filter(|m| (m - d.major).abs() > 1e-6 * d.major.max(1.0))
    {
        return Err(contradiction(
            "major_diameter",
            num(m),
            format!("{} mm", num(d.major)),
        ));
    }
    match &t.pitch {
        Some(RawPitch::Constant(p)) if (p - d.pitch).abs() > 1e-9 * d.pitch.max(1.0) => {
            return Err(contradiction(
                "pitch",
                num(*p),
                format!("a pitch of {} mm", num(d.pitch)),
            ))
        }
        Some(RawPitch::Series(_)) => {
            return Err(cx.err(
                "thread.pitch",
                format!(
                    "a pitch series contradicts `designation = \"{}\"`, a constant pitch of {} mm",
                    d.text,
                    num(d.pitch)
                ),
            ))
        }
        _ => {}
    }
    if let Some(n) = t.starts.filter(|&n| n != d.starts) {
        return Err(contradiction(
            "starts",
            n.to_string(),
            format!("{} start{}", d.starts, if d.starts == 1 { "" } else { "s" }),
        ));
    }
    let hand = if d.left_hand {
        HandName::Left
    } else {
        HandName::Right
    };
    if let Some(h) = t.hand.filter(|&h| h != hand) {
        let name = |h: HandName| if h == HandName::Left { "left" } else { "right" };
        return Err(contradiction(
            "hand",
            format!("\"{}\"", name(h)),
            format!(
                "a {}-hand thread{}",
                name(hand),
                if d.left_hand { " (LH)" } else { " (no LH)" }
            ),
        ));
    }
    let angle = d.flank_angle_deg();
    if let Some(a) = t.flank_angle.filter(|a| (a - angle).abs() > 1e-9) {
        return Err(contradiction(
            "flank_angle",
            num(a),
            format!("an included angle of {} degrees", num(angle)),
        ));
    }
    let given_side = t.side.map(side_of);
    let implied = d.implied_side();
    if let (Some(s), Some(i)) = (given_side, implied) {
        if s != i {
            let hint = if d.standard == Standard::PipeParallel && i == Side::Internal {
                " (ISO 228-1 writes an external thread with its class: G1/2 A or G1/2 B)"
            } else {
                ""
            };
            return Err(contradiction(
                "side",
                format!("\"{}\"", side_name(s)),
                format!("an {} thread{hint}", side_name(i)),
            ));
        }
    }
    if d.is_fit() && given_side.is_none() {
        return Err(cx.err(
            key,
            format!(
                "`{}` is a fit (an internal and an external class): give `side = \"internal\"` or `side = \"external\"` for the thread this job cuts",
                d.text
            ),
        ));
    }
    let side = implied.or(given_side).unwrap_or(Side::External);
    let class = class_of(&d, given_side, cx)?;
    if let Some(c) = &class {
        if c.internal != (side == Side::Internal) {
            return Err(contradiction(
                "side",
                format!("\"{}\"", side_name(side)),
                format!(
                    "the class {} of an {} thread",
                    c.class,
                    side_name(if c.internal {
                        Side::Internal
                    } else {
                        Side::External
                    })
                ),
            ));
        }
    }
    let mut profile = (d.form() == Form::Whitworth)
        .then(|| (angle, d.whitworth_minor(), d.basic_pitch_diameter()));
    let mut major = d.major;
    // A taper thread: its basic diameters at the thread's face (the cones' reference),
    // from the gauge plane's (1:16 on the diameter: an external thread's small end is its
    // face, an internal one's large end).
    let taper = match class.as_ref().and_then(|c| c.taper_gauge.map(|g| (c, g))) {
        Some((c, g)) => {
            let sign = if side == Side::Internal { 1.0 } else { -1.0 };
            let shift = sign * c.taper * g.gauge_plane;
            major = c.basic_major + shift;
            profile = Some((angle, c.basic_minor + shift, c.basic_pitch_diameter + shift));
            Some(sign * 0.5 * c.taper)
        }
        None => None,
    };
    Ok(Named {
        form,
        major,
        pitch: RawPitch::Constant(d.pitch),
        starts: d.starts,
        hand,
        side,
        profile,
        class,
        taper,
    })
}

/// The designation's class for the job's side.
fn class_of(
    d: &Designation,
    side: Option<Side>,
    cx: &Ctx,
) -> Result<Option<ThreadClass>, JobError> {
    if d.standard == Standard::PipeParallelInternal {
        // ISO 7-1's Rp: no limits vpcut can give (see `model::standards::pipe`).
        return Ok(None);
    }
    d.class(side)
        .map_err(|e| cx.err("thread.designation", e.message))
}
