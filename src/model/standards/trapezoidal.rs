//! ISO 2903 metric trapezoidal (Tr) tolerance classes, and ASME B1.5 Acme's.
//!
//! ISO 2903's limits are in tables that are not public (ISO 2903-2:2025, DIN 103-4 and
//! -8); its §11 formulas were not found either. vpcut carries each value only where two
//! independent public sources agree on it (a copy of a table and a published limit of
//! size, or a copy of a table and the ISO 965-1 rule ISO 2903 is built on), and refuses
//! the rest with a message that says so rather than invent one:
//!
//! - **Fundamental deviations of the external pitch diameter** (ISO 2903 Table 1, c and
//!   e): a public copy of the whole table (a Polish Tr tolerance calculator,
//!   "Tolerancje gwintów trapezowych Tr wg ISO 2903 (DIN 103)", odchyłki zasadnicze, P 1.5
//!   to 44) agrees with every published limit found: e at P 1.5 to 5 (engineersedge.com
//!   "External ISO Metric Trapezoidal Screw Threads Table Chart Sizes TR8 - TR315", TR8x1.5
//!   7e d2 7.183 = 7.250 − 0.067 ...; transdev.co.uk "Trapezoidal Screw Specifications",
//!   Tr 22x5 7e: 19.394 = 19.5 − 0.106), e at P 12 (Tr44x12-7e, es = −160 µm, the exam
//!   solution cited in thread-gauging.md §1.2) and c at P 2 (obliczenia.icad.pl,
//!   Tr10x2-8c: −150 µm); and at P 6 and 7 with ISO 965-1's e (its Table 1: 118 at P 6;
//!   its formula −(50 + 11P) = −127 at P 7, 125 in the R40 series). From P 8 on the copy's
//!   e departs from ISO 965-1's (132 against 140 at P 8; 160 against 182 at P 12, the
//!   latter confirmed by the exam), so ISO 965-1 cannot check it there: those pitches, and
//!   c beyond P 2, are refused.
//! - **Pitch-diameter tolerance Td2** of grades 7, 8 and 9: ISO 965-1's rule, Td2(6) =
//!   90 P^0.4 d^0.1 (d the geometric mean of the diameter range) rounded to the R40
//!   series, times 1.25, 1.6 or 2.0, rounded to R40 again (a value halfway between two
//!   R40 numbers going up). This reproduces every published Td2 found (all 12 rows of
//!   `PITCH_TOLERANCES_PUBLISHED` in the tests, three sources, where rounding the product of the
//!   unrounded Td2(6) instead gives 160 for Tr8x1.5-7e's published 170 and 180 for
//!   Tr10x2-7e's 190).
//! - **Major-diameter tolerance Td** (always grade 4, position h): the public copy's
//!   Table 4, equal to ISO 965-1's Td(4) table where that lists the pitch (P ≤ 8) and to
//!   its formula 0.63 (180 P^(2/3) − 3.15 P^(−1/2)) in the R40 series beyond; engineersedge
//!   and transdev print the same at P 1.5 to 5.
//! - The minor diameter of the external thread: Td3 = 1.25 Td2 + |es| (every published
//!   row, e.g. Tr10x2-8c: Td3 = 445 = 1.25 x 236 + 150).
//!
//! Internal classes (7H 8H 9H) are refused: their TD2 (the copy's 1.32 Td2) was not found
//! published anywhere to check it against. Multi-start threads too (ISO 2903 §10 widens
//! their tolerances by factors not found in a public source).
//!
//! ASME B1.5 Acme (2G, 3G, 4G): the tolerance formulas of B1.5 Tables 3 to 7 were not
//! found in a public source (searched: code, vendor pages, handbook excerpts); the classes
//! are refused the same way.

use super::StandardError;
use crate::model::tolerance::{SizeLimits, ThreadClass, UnitSystem};

/// The diameter ranges (mm) of ISO 2903, as ISO 965-1's: over `RANGES[i]` up to and
/// including `RANGES[i + 1]`.
const RANGES: [f64; 8] = [5.6, 11.2, 22.4, 45.0, 90.0, 180.0, 355.0, 640.0];

/// The pitches of ISO 2903 Table 1 (mm).
pub(super) const PITCHES: [f64; 22] = [
    1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 12.0, 14.0, 16.0, 18.0, 20.0, 22.0, 24.0,
    28.0, 32.0, 36.0, 40.0, 44.0,
];

/// The fundamental deviations of the external pitch diameter vpcut ships: (position, pitch
/// mm, |es| µm), each from the public copy of ISO 2903 Table 1 and checked against a
/// second source (see the module's documentation and the test
/// `trapezoidal_deviations_agree_with_a_second_source`).
pub(super) const DEVIATIONS: [(char, f64, u16); 9] = [
    ('e', 1.5, 67),
    ('e', 2.0, 71),
    ('e', 3.0, 85),
    ('e', 4.0, 95),
    ('e', 5.0, 106),
    ('e', 6.0, 118),
    ('e', 7.0, 125),
    ('e', 12.0, 160),
    ('c', 2.0, 150),
];

/// ISO 2903 Table 4 as the public copy prints it: the major-diameter tolerance Td of the
/// external thread (grade 4, µm) per pitch of [`PITCHES`].
pub(super) const MAJOR_TOLERANCES: [u16; 22] = [
    150, 180, 236, 300, 335, 375, 425, 450, 500, 530, 600, 670, 710, 800, 850, 900, 950, 1060,
    1120, 1250, 1320, 1400,
];

/// Published pitch-diameter tolerances of the external thread, the checks of
/// [`td2`]: (range index, pitch mm, grade, Td2 µm). Grade 7 from the 7e rows of
/// engineersedge.com (TR8x1.5: 7.183 − 7.013 = 170; TR10x2: 190; TR11x3: 212; TR12x2:
/// 200; TR12x3: 224; TR16x4: 265) and transdev.co.uk (Tr 22x5: 280; Tr 24x5: 300;
/// Tr 25x3: 250), engineersedge.com TR320x5 (375) and Tr44x12-7e (425); grade 8 from
/// icad.pl Tr10x2-8c (236).
#[cfg(test)]
pub(super) const PITCH_TOLERANCES_PUBLISHED: [(usize, f64, u8, u16); 12] = [
    (0, 1.5, 7, 170),
    (0, 2.0, 7, 190),
    (0, 3.0, 7, 212),
    (1, 2.0, 7, 200),
    (1, 3.0, 7, 224),
    (1, 4.0, 7, 265),
    (1, 5.0, 7, 280),
    (2, 3.0, 7, 250),
    (2, 5.0, 7, 300),
    (2, 12.0, 7, 425),
    (5, 5.0, 7, 375),
    (0, 2.0, 8, 236),
];

/// The R40 series of preferred numbers (ISO 3), one decade.
const R40: [f64; 40] = [
    100.0, 106.0, 112.0, 118.0, 125.0, 132.0, 140.0, 150.0, 160.0, 170.0, 180.0, 190.0, 200.0,
    212.0, 224.0, 236.0, 250.0, 265.0, 280.0, 300.0, 315.0, 335.0, 355.0, 375.0, 400.0, 425.0,
    450.0, 475.0, 500.0, 530.0, 560.0, 600.0, 630.0, 670.0, 710.0, 750.0, 800.0, 850.0, 900.0,
    950.0,
];

/// `v` (> 0) rounded to the nearest number of the R40 series (of any decade); halfway
/// between two, the greater.
pub(super) fn r40(v: f64) -> f64 {
    let decade = 10f64.powf((v / 100.0).log10().floor());
    let mut best = f64::NAN;
    for k in [decade / 10.0, decade, decade * 10.0] {
        for &n in R40.iter().chain([1000.0].iter()) {
            let c = n * k;
            let (d, db) = ((c - v).abs(), (best - v).abs());
            if best.is_nan() || d < db - 1e-9 * v || ((d - db).abs() <= 1e-9 * v && c > best) {
                best = c;
            }
        }
    }
    best
}

/// Td2 (µm) of grade `grade` for pitch `p` in diameter range `range` (see the module's
/// documentation).
pub(super) fn td2(range: usize, p: f64, grade: u8) -> f64 {
    let d = (RANGES[range] * RANGES[range + 1]).sqrt();
    let k = match grade {
        7 => 1.25,
        8 => 1.6,
        _ => 2.0,
    };
    r40(k * r40(90.0 * p.powf(0.4) * d.powf(0.1)))
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// ISO 2904: the crest clearance a_c of pitch `p`.
pub(super) fn crest_clearance(p: f64) -> f64 {
    if p <= 1.5 {
        0.15
    } else if p <= 5.0 {
        0.25
    } else if p <= 12.0 {
        0.5
    } else {
        1.0
    }
}

fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// The diameter range index of `d`, if ISO 2903 has it.
pub(super) fn range_of(d: f64) -> Option<usize> {
    (0..RANGES.len() - 1).find(|&i| d > RANGES[i] && d <= RANGES[i + 1] + 1e-9)
}

/// The limits of size of Tr`d`x`lead` with pitch `p` and `starts` starts in class
/// `grade``pos`, where vpcut has the values.
#[allow(clippy::too_many_arguments)]
pub(super) fn limits(
    designation: &str,
    d: f64,
    p: f64,
    starts: u32,
    grade: u8,
    pos: char,
    internal: bool,
) -> Result<ThreadClass, StandardError> {
    let class = format!("{grade}{pos}");
    let refuse = |why: String| {
        Err(StandardError::new(format!(
            "the limits of {designation} are not in vpcut: {why}; ISO 2903's tables are not public and vpcut does not invent them (give the designation without its class for the basic profile)"
        )))
    };
    if internal || pos.is_ascii_uppercase() {
        return refuse(format!(
            "no public value of ISO 2903's internal class {class} was found to check its copy against"
        ));
    }
    if !matches!(class.as_str(), "7e" | "8e" | "8c" | "9c") {
        return Err(StandardError::new(format!(
            "ISO 2903 recommends the external classes 7e, 8e, 8c and 9c and the internal 7H, 8H and 9H, not {class}"
        )));
    }
    if starts > 1 {
        return refuse(format!(
            "ISO 2903 §10 widens the tolerances of a {starts}-start thread by factors not found in a public source"
        ));
    }
    let Some(range) = range_of(d) else {
        return refuse(format!("{d} mm is outside ISO 2903's diameters"));
    };
    let Some(ip) = PITCHES.iter().position(|&q| same(q, p)) else {
        return refuse(format!(
            "{p} mm is not a pitch of ISO 2903 Table 1 (1.5 to 44 mm)"
        ));
    };
    let Some(es) = DEVIATIONS
        .iter()
        .find(|(c, q, _)| *c == pos && same(*q, p))
        .map(|t| t.2 as f64)
    else {
        let have: Vec<String> = DEVIATIONS
            .iter()
            .filter(|t| t.0 == pos)
            .map(|t| super::designation::fmt_num(t.1))
            .collect();
        return refuse(format!(
            "the fundamental deviation {pos} for pitch {p} mm was found in one public copy of ISO 2903 Table 1 only, with no second source to check it (vpcut has {pos} for pitches {} mm)",
            have.join(", ")
        ));
    };
    let td2 = td2(range, p, grade);
    let td = MAJOR_TOLERANCES[ip] as f64;
    let um = 1e-3;
    let d2 = d - 0.5 * p;
    let d3 = d - 2.0 * (0.5 * p + crest_clearance(p));
    let d2max = d2 - es * um;
    let td3 = 1.25 * td2 + es;
    Ok(ThreadClass {
        designation: designation.to_string(),
        class,
        units: UnitSystem::Metric,
        internal: false,
        basic_major: d,
        basic_pitch_diameter: d2,
        basic_minor: d - p,
        pitch: p,
        starts,
        flank_angle: 30f64.to_radians(),
        taper: 0.0,
        pitch_diameter: SizeLimits::new(round3(d2max - td2 * um), round3(d2max)),
        major_diameter: SizeLimits::new(round3(d - td * um), d),
        minor_diameter: SizeLimits::new(round3(d3 - td3 * um), round3(d3)),
        // ISO 2903 §8's length groups are not public either: the GO gauge checks the
        // whole thread (the job bounds it by the thread's length).
        engagement_length: f64::INFINITY,
        not_go_turns: 2.0,
        root: None,
        taper_gauge: None,
        source: "ISO 2903: Table 1 and 4 values checked against published limits; Td2 by ISO 965-1's rule (R40), checked against published limits".to_string(),
    })
}

/// ASME B1.5 Acme classes: refused (see the module's documentation).
pub(super) fn acme_limits(designation: &str, class: &str) -> Result<ThreadClass, StandardError> {
    if !matches!(class, "2G" | "3G" | "4G" | "2C" | "3C" | "4C" | "5C" | "6C") {
        return Err(StandardError::new(format!(
            "ASME B1.5 has the general-purpose classes 2G, 3G, 4G and the centralizing 2C to 6C, not {class}"
        )));
    }
    Err(StandardError::new(format!(
        "the limits of {designation} are not in vpcut: no public source of ASME B1.5's Acme tolerance formulas was found, and vpcut does not invent them (give the designation without its class for the basic profile)"
    )))
}
