//! ISO 2903 metric trapezoidal (Tr) tolerance classes, and ASME B1.5 Acme's.
//!
//! ISO 2903's limits are in tables that are not public (ISO 2903-2:2025, DIN 103-8); its
//! §11 formulas were not found either. The Tr fundamental deviations are not ISO 965-1's
//! beyond P 5 (Tr44x12-7e: es = −160 µm, where ISO 965-1's e formula gives −182), and its
//! Td2 values are not always the ISO 965-1 formula's rounding (Tr10x2-7e: 190 µm where
//! 1.25 x 90 P^0.4 d^0.1 = 182.6 rounds to 180). So vpcut carries the values it found
//! published, each with its source below, and refuses every other class with a message
//! that says so rather than invent one: external classes of single-start threads whose
//! deviation, pitch-diameter tolerance and major-diameter tolerance are all listed. The
//! minor diameter of the external thread follows from those as Td3 = 1.25 Td2 + |es|
//! (every published row below, e.g. Tr10x2-8c: Td3 = 445 = 1.25 x 236 + 150). Internal
//! classes (7H 8H 9H) and multi-start threads (ISO 2903 §10 widens their tolerances) are
//! refused: no public value was found.
//!
//! ASME B1.5 Acme (2G, 3G, 4G): the tolerance formulas of B1.5 Tables 3 to 7 were not
//! found in a public source; the classes are refused the same way.

use super::StandardError;
use crate::model::tolerance::{SizeLimits, ThreadClass, UnitSystem};

/// The diameter ranges (mm) of ISO 2903, as ISO 965-1's: over `RANGES[i]` up to and
/// including `RANGES[i + 1]`.
const RANGES: [f64; 8] = [5.6, 11.2, 22.4, 45.0, 90.0, 180.0, 355.0, 640.0];

/// Published fundamental deviations of the external pitch diameter: (position, pitch mm,
/// |es| µm).
/// - e, P 1.5 to 5: engineersedge.com "External ISO Metric Trapezoidal Screw Threads Table
///   Chart Sizes TR8 - TR315" (TR8x1.5 7e: d2 7.183 = 7.250 − 0.067; TR10x2: 8.929;
///   TR12x3: 10.415; TR16x4: 13.905) and transdev.co.uk "Trapezoidal Screw Specifications"
///   (Tr 22x5 7e: d2 19.394 = 19.5 − 0.106).
/// - e, P 12: Tr44x12-7e, es = −160 µm (the exam solution cited in thread-gauging.md §1.2).
/// - c, P 2: obliczenia.icad.pl trapezoidal example, Tr10x2-8c: es = −150 µm.
const DEVIATIONS: [(char, f64, u16); 7] = [
    ('e', 1.5, 67),
    ('e', 2.0, 71),
    ('e', 3.0, 85),
    ('e', 4.0, 95),
    ('e', 5.0, 106),
    ('e', 12.0, 160),
    ('c', 2.0, 150),
];

/// Published pitch-diameter tolerances of the external thread: (range index, pitch mm,
/// grade, Td2 µm). Grade 7 from the 7e rows of engineersedge.com (TR8x1.5: 7.183 − 7.013
/// = 170; TR10x2: 190; TR11x3: 212; TR12x2: 200; TR12x3: 224; TR16x4: 265) and
/// transdev.co.uk (Tr 22x5: 280; Tr 24x5: 300; Tr 25x3: 250), engineersedge.com TR320x5
/// (375) and Tr44x12-7e (425); grade 8 from icad.pl Tr10x2-8c (236).
const PITCH_TOLERANCES: [(usize, f64, u8, u16); 12] = [
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

/// Published major-diameter tolerances of the external thread (always grade 4, position
/// h): (pitch mm, Td µm): engineersedge.com (TR8x1.5: 8.000 − 7.850 = 150; TR10x2: 180;
/// TR11x3: 236; TR16x4: 300; TR320x5: 335), the same as ISO 965-1's Td(4).
const MAJOR_TOLERANCES: [(f64, u16); 5] =
    [(1.5, 150), (2.0, 180), (3.0, 236), (4.0, 300), (5.0, 335)];

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

/// The limits of size of Tr`d`x`lead` with pitch `p` and `starts` starts in class
/// `grade``pos`, where vpcut has the published values.
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
            "no public value of ISO 2903's internal class {class} was found"
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
    let Some(range) = (0..RANGES.len() - 1).find(|&i| d > RANGES[i] && d <= RANGES[i + 1] + 1e-9)
    else {
        return refuse(format!("{d} mm is outside ISO 2903's diameters"));
    };
    let es = DEVIATIONS
        .iter()
        .find(|(c, q, _)| *c == pos && same(*q, p))
        .map(|t| t.2 as f64);
    let td2 = PITCH_TOLERANCES
        .iter()
        .find(|(r, q, g, _)| *r == range && same(*q, p) && *g == grade)
        .map(|t| t.3 as f64);
    let td = MAJOR_TOLERANCES
        .iter()
        .find(|(q, _)| same(*q, p))
        .map(|t| t.1 as f64);
    let (Some(es), Some(td2), Some(td)) = (es, td2, td) else {
        let mut missing = Vec::new();
        if es.is_none() {
            missing.push(format!("the deviation of {pos} for pitch {p} mm"));
        }
        if td2.is_none() {
            missing.push(format!(
                "Td2({grade}) for {} to {} mm and pitch {p} mm",
                RANGES[range],
                RANGES[range + 1]
            ));
        }
        if td.is_none() {
            missing.push(format!("Td(4) for pitch {p} mm"));
        }
        return refuse(format!("no public value of {}", missing.join(", ")));
    };
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
        source: "ISO 2903 values as published (engineersedge.com, transdev.co.uk, icad.pl)"
            .to_string(),
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
