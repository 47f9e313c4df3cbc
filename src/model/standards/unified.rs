//! ASME B1.1 Unified inch screw threads (UN, UNC, UNF, UNEF, UNS): the standard series'
//! threads per inch and the limits of size of classes 1A, 2A, 3A, 1B, 2B, 3B by the B1.1
//! formulas (§5.8: allowance, major, pitch and minor diameter tolerances; §5.1: the length
//! of engagement per series).
//!
//! The limits are computed the way B1.1-2019 Tables 3 to 6 work them (reproduced in
//! Machinery's Handbook 31st ed., "External/Internal Inch Screw Thread Calculations" for
//! 1/2-28 UNEF-2A/2B and 19/64-36 UNS-2A/2B): pitch to 8 decimals, basic major to 4,
//! thread heights (0.64951905P, 1.08253175P) to 6, the allowance (0.3 x the 2A pitch
//! diameter tolerance) to 4, the tolerances unrounded, and every limit to 4 decimal places
//! (the minor diameter of classes 1B and 2B from #6 (0.138 in) up to 3), half to even.
//! The published tables follow that rule to the last digit (the test
//! `unified_limits_are_the_published_ones`), except the 2B minor diameter maximum of #1-64,
//! #1-72 and #2-64, which B1.1 prints 0.0001 in above its own formula, and of #10-24
//! (0.156 where the formula gives 0.155): those are left as the formula gives them.

use super::{StandardError, UnitSystem};
use crate::model::tolerance::{SizeLimits, ThreadClass};

/// A Unified series as a designation names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Series {
    /// Coarse (UNC).
    Coarse,
    /// Fine (UNF).
    Fine,
    /// Extra fine (UNEF).
    ExtraFine,
    /// Constant pitch (UN: 4, 6, 8, 12, 16, 20, 28 or 32 threads per inch).
    Constant,
    /// Special (UNS).
    Special,
}

impl Series {
    /// The series' letters (`UNC`).
    pub fn name(self) -> &'static str {
        match self {
            Series::Coarse => "UNC",
            Series::Fine => "UNF",
            Series::ExtraFine => "UNEF",
            Series::Constant => "UN",
            Series::Special => "UNS",
        }
    }
}

/// One size of a standard series: (basic major diameter, in; threads per inch; the size as
/// written).
type Size = (f64, f64, &'static str);

/// ASME B1.1 Table 1 (as efunda's "Unified Screw Threads, Standard Series" and Machinery's
/// Handbook reproduce it): the coarse series.
const UNC: [Size; 33] = [
    (0.073, 64.0, "#1"),
    (0.086, 56.0, "#2"),
    (0.099, 48.0, "#3"),
    (0.112, 40.0, "#4"),
    (0.125, 40.0, "#5"),
    (0.138, 32.0, "#6"),
    (0.164, 32.0, "#8"),
    (0.190, 24.0, "#10"),
    (0.216, 24.0, "#12"),
    (0.25, 20.0, "1/4"),
    (0.3125, 18.0, "5/16"),
    (0.375, 16.0, "3/8"),
    (0.4375, 14.0, "7/16"),
    (0.5, 13.0, "1/2"),
    (0.5625, 12.0, "9/16"),
    (0.625, 11.0, "5/8"),
    (0.75, 10.0, "3/4"),
    (0.875, 9.0, "7/8"),
    (1.0, 8.0, "1"),
    (1.125, 7.0, "1 1/8"),
    (1.25, 7.0, "1 1/4"),
    (1.375, 6.0, "1 3/8"),
    (1.5, 6.0, "1 1/2"),
    (1.75, 5.0, "1 3/4"),
    (2.0, 4.5, "2"),
    (2.25, 4.5, "2 1/4"),
    (2.5, 4.0, "2 1/2"),
    (2.75, 4.0, "2 3/4"),
    (3.0, 4.0, "3"),
    (3.25, 4.0, "3 1/4"),
    (3.5, 4.0, "3 1/2"),
    (3.75, 4.0, "3 3/4"),
    (4.0, 4.0, "4"),
];

/// ASME B1.1 Table 1: the fine series.
const UNF: [Size; 24] = [
    (0.060, 80.0, "#0"),
    (0.073, 72.0, "#1"),
    (0.086, 64.0, "#2"),
    (0.099, 56.0, "#3"),
    (0.112, 48.0, "#4"),
    (0.125, 44.0, "#5"),
    (0.138, 40.0, "#6"),
    (0.164, 36.0, "#8"),
    (0.190, 32.0, "#10"),
    (0.216, 28.0, "#12"),
    (0.25, 28.0, "1/4"),
    (0.3125, 24.0, "5/16"),
    (0.375, 24.0, "3/8"),
    (0.4375, 20.0, "7/16"),
    (0.5, 20.0, "1/2"),
    (0.5625, 18.0, "9/16"),
    (0.625, 18.0, "5/8"),
    (0.75, 16.0, "3/4"),
    (0.875, 14.0, "7/8"),
    (1.0, 12.0, "1"),
    (1.125, 12.0, "1 1/8"),
    (1.25, 12.0, "1 1/4"),
    (1.375, 12.0, "1 3/8"),
    (1.5, 12.0, "1 1/2"),
];

/// ASME B1.1 Table 1: the extra-fine series.
const UNEF: [Size; 25] = [
    (0.216, 32.0, "#12"),
    (0.25, 32.0, "1/4"),
    (0.3125, 32.0, "5/16"),
    (0.375, 32.0, "3/8"),
    (0.4375, 28.0, "7/16"),
    (0.5, 28.0, "1/2"),
    (0.5625, 24.0, "9/16"),
    (0.625, 24.0, "5/8"),
    (0.6875, 24.0, "11/16"),
    (0.75, 20.0, "3/4"),
    (0.8125, 20.0, "13/16"),
    (0.875, 20.0, "7/8"),
    (0.9375, 20.0, "15/16"),
    (1.0, 20.0, "1"),
    (1.0625, 18.0, "1 1/16"),
    (1.125, 18.0, "1 1/8"),
    (1.1875, 18.0, "1 3/16"),
    (1.25, 18.0, "1 1/4"),
    (1.3125, 18.0, "1 5/16"),
    (1.375, 18.0, "1 3/8"),
    (1.4375, 18.0, "1 7/16"),
    (1.5, 18.0, "1 1/2"),
    (1.5625, 18.0, "1 9/16"),
    (1.625, 18.0, "1 5/8"),
    (1.6875, 18.0, "1 11/16"),
];

/// The threads per inch of the constant-pitch series (B1.1 §3: 4-UN to 32-UN).
const CONSTANT: [f64; 8] = [4.0, 6.0, 8.0, 12.0, 16.0, 20.0, 28.0, 32.0];

fn table(series: Series) -> &'static [Size] {
    match series {
        Series::Coarse => &UNC,
        Series::Fine => &UNF,
        Series::ExtraFine => &UNEF,
        Series::Constant | Series::Special => &[],
    }
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// The series' threads per inch for basic major diameter `d` (in), if it lists the size.
pub(super) fn series_tpi(series: Series, d: f64) -> Option<f64> {
    table(series).iter().find(|s| same(s.0, d)).map(|s| s.1)
}

/// Checks that `d`-`tpi` belongs to `series`; the message says what the series has.
pub(super) fn check_series(series: Series, d: f64, tpi: f64, size: &str) -> Result<(), String> {
    match series {
        Series::Special => Ok(()),
        Series::Constant => {
            if CONSTANT.iter().any(|&t| same(t, tpi)) {
                Ok(())
            } else {
                Err(format!(
                    "{tpi} threads per inch is not a constant-pitch UN series (4, 6, 8, 12, 16, 20, 28 or 32); a special pitch is UNS"
                ))
            }
        }
        _ => match series_tpi(series, d) {
            Some(t) if same(t, tpi) => Ok(()),
            Some(t) => Err(format!(
                "{size} {} has {t} threads per inch (ASME B1.1 Table 1), not {tpi}",
                series.name()
            )),
            None => {
                let t = table(series);
                Err(format!(
                    "{size} is not a size of the {} series (ASME B1.1 Table 1: {} to {})",
                    series.name(),
                    t.first().map_or("", |s| s.2),
                    t.last().map_or("", |s| s.2)
                ))
            }
        },
    }
}

/// B1.1 §5.1: the length of engagement the pitch diameter tolerance is based on (in): the
/// basic major diameter for UNC, UNF and 4-, 6-, 8-UN; nine pitches for UNEF, 12-UN and
/// finer, and UNS. A size given without its series (a `class` key) is placed by its pitch:
/// in UNC or UNF, or 4, 6 or 8 threads per inch, as the former.
pub(super) fn engagement(series: Option<Series>, d: f64, tpi: f64) -> f64 {
    let major = match series {
        Some(Series::Coarse | Series::Fine) => true,
        Some(Series::Constant) => tpi <= 8.0,
        Some(Series::ExtraFine | Series::Special) => false,
        None => {
            [Series::Coarse, Series::Fine]
                .iter()
                .any(|&s| series_tpi(s, d).is_some_and(|t| same(t, tpi)))
                || [4.0, 6.0, 8.0].iter().any(|&t| same(t, tpi))
        }
    };
    if major {
        d
    } else {
        9.0 / tpi
    }
}

/// Round half to even at `n` decimals (a tie within 1e-9 of the last unit).
pub(super) fn round_even(x: f64, n: i32) -> f64 {
    let s = x * 10f64.powi(n);
    let f = s.floor();
    let r = if (s - f - 0.5).abs() < 1e-6 {
        if f % 2.0 == 0.0 {
            f
        } else {
            f + 1.0
        }
    } else {
        s.round()
    };
    r / 10f64.powi(n)
}

/// A Unified class: 1, 2 or 3, external (A) or internal (B).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct UnifiedClass {
    /// 1, 2 or 3.
    pub(super) grade: u8,
    /// B (internal) rather than A.
    pub(super) internal: bool,
}

impl UnifiedClass {
    pub(super) fn text(&self) -> String {
        format!("{}{}", self.grade, if self.internal { 'B' } else { 'A' })
    }
}

/// The limits of size, in inches, of a Unified thread: (pitch diameter, major, minor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct InchLimits {
    pub(super) pitch: (f64, f64),
    pub(super) major: (f64, f64),
    pub(super) minor: (f64, f64),
    pub(super) engagement: f64,
}

/// B1.1 §5.8 and Tables 3 to 6: the limits of `d`-`tpi` (basic major diameter in inches)
/// in `class`.
pub(super) fn inch_limits(
    d: f64,
    tpi: f64,
    series: Option<Series>,
    class: UnifiedClass,
) -> InchLimits {
    let p = round_even(1.0 / tpi, 8);
    let d = round_even(d, 4);
    let le = engagement(series, d, tpi);
    // §5.8.1(c): the class 2A pitch diameter tolerance.
    let t = 0.0015 * (d.cbrt() + le.sqrt() + 10.0 * p.powf(2.0 / 3.0));
    let addendum2 = round_even(0.649_519_05 * p, 6);
    let height2 = round_even(1.082_531_75 * p, 6);
    if !class.internal {
        let allowance = if class.grade == 3 {
            0.0
        } else {
            round_even(0.3 * t, 4)
        };
        let dmax = d - allowance;
        let td = if class.grade == 1 { 0.090 } else { 0.060 } * p.powf(2.0 / 3.0);
        let td2 = t * [1.5, 1.0, 0.75][(class.grade - 1) as usize];
        let d2max = round_even(dmax - addendum2, 4);
        InchLimits {
            pitch: (round_even(d2max - td2, 4), d2max),
            major: (round_even(dmax - td, 4), round_even(dmax, 4)),
            minor: (f64::NEG_INFINITY, round_even(dmax - height2, 4)),
            engagement: le,
        }
    } else {
        let d1min = round_even(d - height2, 6);
        // §5.8.2(c): the minor diameter tolerance.
        let first = 0.05 * p.powf(2.0 / 3.0) + 0.03 * p / d - 0.002;
        let td1 = if class.grade < 3 {
            if d < 0.25 {
                first.min(0.394 * p).max(0.25 * p - 0.4 * p * p)
            } else if tpi >= 4.0 {
                0.25 * p - 0.4 * p * p
            } else {
                0.15 * p
            }
        } else {
            let least = if tpi >= 13.0 {
                0.23 * p - 1.5 * p * p
            } else {
                0.120 * p
            };
            first.min(0.394 * p).max(least)
        };
        let places = if class.grade < 3 && d >= 0.138 - 1e-9 {
            3
        } else {
            4
        };
        let d2min = round_even(d - addendum2, 4);
        let td2 = t * [1.95, 1.3, 0.975][(class.grade - 1) as usize];
        InchLimits {
            pitch: (d2min, round_even(d2min + td2, 4)),
            major: (d, f64::INFINITY),
            minor: (round_even(d1min, places), round_even(d1min + td1, places)),
            engagement: le,
        }
    }
}

/// The limits of size of a Unified thread in `class`, as `designation` names it (mm).
pub(super) fn limits(
    designation: &str,
    d: f64,
    tpi: f64,
    starts: u32,
    series: Option<Series>,
    class: UnifiedClass,
) -> Result<ThreadClass, StandardError> {
    if !(1..=3).contains(&class.grade) {
        return Err(StandardError::new(format!(
            "ASME B1.1 has classes 1A, 2A, 3A, 1B, 2B and 3B, not {}",
            class.text()
        )));
    }
    let l = inch_limits(d, tpi, series, class);
    let mm = |v: f64| v * 25.4;
    let range = |(a, b): (f64, f64)| SizeLimits::new(mm(a), mm(b));
    let p = 1.0 / tpi;
    Ok(ThreadClass {
        designation: designation.to_string(),
        class: class.text(),
        units: UnitSystem::Inch,
        internal: class.internal,
        basic_major: mm(d),
        basic_pitch_diameter: mm(d - 0.649_519_052_838_329 * p),
        basic_minor: mm(d - 1.082_531_754_730_548 * p),
        pitch: mm(p),
        starts,
        flank_angle: 60f64.to_radians(),
        taper: 0.0,
        pitch_diameter: range(l.pitch),
        major_diameter: range(l.major),
        minor_diameter: range(l.minor),
        engagement_length: mm(l.engagement),
        not_go_turns: 3.0,
        root: None,
        taper_gauge: None,
        source: "ASME B1.1 formulas".to_string(),
    })
}
