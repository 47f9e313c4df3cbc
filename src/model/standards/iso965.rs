//! ISO 965-1 general purpose metric screw threads (M): the tolerance tables and their
//! formulas, the ISO 261 coarse series, and the limits of size of a class.
//!
//! The tables (ISO 965-1 Tables 1 to 6, µm) are shipped as the standard prints them; the
//! formulas of ISO 965-1 §13 are used only for a diameter and pitch the tables do not
//! list, with the actual diameter (FED-STD-H28/21B §5.1.3 example 3, M29x1.25: "since
//! table 12 does not include P = 1.25 for a 29 mm size, calculate ... Td2(4) = 0.63 x
//! 0.09 P^0.4 d^0.1"), unrounded. The tables were typed from the public copy in
//! `Bob-SpringMtTech/Engineering` Threads.py (`ThreadM`), each row checked against its
//! formula (the test `iso965_tables_follow_their_formulas`); that copy's typos are not
//! carried: es(e) and es(f) at P 0.75 and 1.75 lose their signs there, its f column
//! repeats e from P 0.5 up (f here is ISO 965-1's own, within 3 µm of −(30 + 11P) at every
//! pitch), Td2(4) for 180–355 mm, P 4 reads 198 (180: 0.63 x 280 = 176), Td2(9) for
//! 11.2–22.4 mm, P 1.25 reads 365 (265: 2 x 132) and Td2(9) for 45–90 mm, P 2 reads 335
//! (355: 2 x 180); and it leaves out TD2(6) for 0.99–1.4 mm, P 0.25, which the Yamawa tap
//! catalogue's ISO 965 comparison gives as 71 µm (M1x0.25 6H; 1.32 x 53 = 70).
//!
//! Limits are rounded to 0.001 mm, as ISO 965-2 and ASME B1.13M print them (FED-STD-H28/
//! 21B example 3: "28.16010 which is rounded to 28.160").

use super::{Engagement, StandardError};
use crate::model::tolerance::{RootZone, SizeLimits, ThreadClass, UnitSystem};
use std::f64::consts::PI;

/// The pitches of ISO 965-1 Tables 1, 3 and 4 (mm).
const PITCHES: [f64; 25] = [
    0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7, 0.75, 0.8, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0,
    3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 8.0,
];

/// ISO 965-1 Table 1: fundamental deviations (µm, magnitudes) per pitch of [`PITCHES`]:
/// EI of G (= |es| of g), |es| of e, |es| of f. H and h are 0.
const DEV_G: [u16; 25] = [
    17, 18, 18, 19, 19, 20, 20, 21, 22, 22, 24, 26, 28, 32, 34, 38, 42, 48, 53, 60, 63, 71, 75, 80,
    100,
];
const DEV_E: [u16; 25] = [
    0, 0, 0, 0, 0, 0, 50, 53, 56, 56, 60, 60, 63, 67, 71, 71, 80, 85, 90, 95, 100, 106, 112, 118,
    140,
];
const DEV_F: [u16; 25] = [
    0, 0, 0, 34, 34, 35, 36, 36, 38, 38, 38, 40, 42, 45, 48, 52, 58, 63, 70, 75, 80, 85, 90, 95,
    118,
];

/// ISO 965-1 Table 4: major-diameter tolerance Td of the external thread (µm) for grades
/// 4, 6 and 8, per pitch of [`PITCHES`]; 0 where the grade does not exist.
const TD: [[u16; 25]; 3] = [
    [
        36, 42, 48, 53, 60, 63, 67, 80, 90, 90, 95, 112, 132, 150, 170, 180, 212, 236, 265, 300,
        315, 335, 355, 375, 450,
    ],
    [
        56, 67, 75, 85, 95, 100, 106, 125, 140, 140, 150, 180, 212, 236, 265, 280, 335, 375, 425,
        475, 500, 530, 560, 600, 710,
    ],
    [
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 236, 280, 335, 375, 425, 450, 530, 600, 670, 750, 800, 850,
        900, 950, 1180,
    ],
];

/// ISO 965-1 Table 3: minor-diameter tolerance TD1 of the internal thread (µm) for grades
/// 4 to 8, per pitch of [`PITCHES`]; 0 where the grade does not exist.
const TD1: [[u16; 25]; 5] = [
    [
        38, 45, 53, 63, 71, 80, 90, 100, 112, 118, 125, 150, 170, 190, 212, 236, 280, 315, 355,
        375, 425, 450, 475, 500, 630,
    ],
    [
        0, 56, 67, 80, 90, 100, 112, 125, 140, 150, 160, 190, 212, 236, 265, 300, 355, 400, 450,
        475, 530, 560, 600, 630, 800,
    ],
    [
        0, 0, 85, 100, 112, 125, 140, 160, 180, 190, 200, 236, 265, 300, 335, 375, 450, 500, 560,
        600, 670, 710, 750, 800, 1000,
    ],
    [
        0, 0, 0, 0, 0, 0, 180, 200, 224, 236, 250, 300, 335, 375, 425, 475, 560, 630, 710, 750,
        850, 900, 950, 1000, 1250,
    ],
    [
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 315, 375, 425, 475, 530, 600, 710, 800, 900, 950, 1060, 1120,
        1180, 1250, 1600,
    ],
];

/// The basic major diameter ranges of ISO 965-1 (mm): over `RANGES[i]` up to and
/// including `RANGES[i + 1]`.
const RANGES: [f64; 10] = [0.99, 1.4, 2.8, 5.6, 11.2, 22.4, 45.0, 90.0, 180.0, 355.0];

/// One diameter range and pitch of ISO 965-1 Tables 2, 5 and 6.
struct SizeRow {
    /// Index into [`RANGES`].
    range: usize,
    /// Pitch (mm).
    p: f64,
    /// Table 6: Td2 (µm) for grades 3 to 9; 0 where the grade does not exist.
    td2: [u16; 7],
    /// Table 5: TD2 (µm) for grades 4 to 8; 0 where the grade does not exist.
    td2_int: [u16; 5],
    /// Table 2: the greatest short (S) and the least long (L) length of engagement (mm).
    le: [f64; 2],
}

const fn row(range: usize, p: f64, td2: [u16; 7], td2_int: [u16; 5], le: [f64; 2]) -> SizeRow {
    SizeRow {
        range,
        p,
        td2,
        td2_int,
        le,
    }
}

/// ISO 965-1 Tables 2, 5 and 6, one row per diameter range and pitch.
#[rustfmt::skip]
const SIZES: [SizeRow; 47] = [
    row(0, 0.2, [24, 30, 38, 48, 0, 0, 0], [40, 0, 0, 0, 0], [0.5, 1.4]),
    row(0, 0.25, [26, 34, 42, 53, 0, 0, 0], [45, 56, 71, 0, 0], [0.6, 1.7]),
    row(0, 0.3, [28, 36, 45, 56, 0, 0, 0], [48, 60, 75, 0, 0], [0.7, 2.0]),
    row(1, 0.2, [25, 32, 40, 50, 0, 0, 0], [42, 0, 0, 0, 0], [0.5, 1.5]),
    row(1, 0.25, [28, 36, 45, 56, 0, 0, 0], [48, 60, 0, 0, 0], [0.6, 1.9]),
    row(1, 0.35, [32, 40, 50, 63, 80, 0, 0], [53, 67, 85, 0, 0], [0.8, 2.6]),
    row(1, 0.4, [34, 42, 53, 67, 85, 0, 0], [56, 71, 90, 0, 0], [1.0, 3.0]),
    row(1, 0.45, [36, 45, 56, 71, 90, 0, 0], [60, 75, 95, 0, 0], [1.3, 3.8]),
    row(2, 0.35, [34, 42, 53, 67, 85, 0, 0], [56, 71, 90, 0, 0], [1.0, 3.0]),
    row(2, 0.5, [38, 48, 60, 75, 95, 0, 0], [63, 80, 100, 125, 0], [1.5, 4.5]),
    row(2, 0.6, [42, 53, 67, 85, 106, 0, 0], [71, 90, 112, 140, 0], [1.7, 5.0]),
    row(2, 0.7, [45, 56, 71, 90, 112, 0, 0], [75, 95, 118, 150, 0], [2.0, 6.0]),
    row(2, 0.75, [45, 56, 71, 90, 112, 0, 0], [75, 95, 118, 150, 0], [2.2, 6.7]),
    row(2, 0.8, [48, 60, 75, 95, 118, 150, 190], [80, 100, 125, 160, 200], [2.5, 7.5]),
    row(3, 0.75, [50, 63, 80, 100, 125, 0, 0], [85, 106, 132, 170, 0], [2.4, 7.1]),
    row(3, 1.0, [56, 71, 90, 112, 140, 180, 224], [95, 118, 150, 190, 236], [3.0, 9.0]),
    row(3, 1.25, [60, 75, 95, 118, 150, 190, 236], [100, 125, 160, 200, 250], [4.0, 12.0]),
    row(3, 1.5, [67, 85, 106, 132, 170, 212, 265], [112, 140, 180, 224, 280], [5.0, 15.0]),
    row(4, 1.0, [60, 75, 95, 118, 150, 190, 236], [100, 125, 160, 200, 250], [3.8, 11.0]),
    row(4, 1.25, [67, 85, 106, 132, 170, 212, 265], [112, 140, 180, 224, 280], [4.5, 13.0]),
    row(4, 1.5, [71, 90, 112, 140, 180, 224, 280], [118, 150, 190, 236, 300], [5.6, 16.0]),
    row(4, 1.75, [75, 95, 118, 150, 190, 236, 300], [125, 160, 200, 250, 315], [6.0, 18.0]),
    row(4, 2.0, [80, 100, 125, 160, 200, 250, 315], [132, 170, 212, 265, 335], [8.0, 24.0]),
    row(4, 2.5, [85, 106, 132, 170, 212, 265, 335], [140, 180, 224, 280, 355], [10.0, 30.0]),
    row(5, 1.0, [63, 80, 100, 125, 160, 200, 250], [106, 132, 170, 212, 0], [4.0, 12.0]),
    row(5, 1.5, [75, 95, 118, 150, 190, 236, 300], [125, 160, 200, 250, 315], [6.3, 19.0]),
    row(5, 2.0, [85, 106, 132, 170, 212, 265, 335], [140, 180, 224, 280, 335], [8.5, 25.0]),
    row(5, 3.0, [100, 125, 160, 200, 250, 315, 400], [170, 212, 265, 335, 425], [12.0, 36.0]),
    row(5, 3.5, [106, 132, 170, 212, 265, 335, 425], [180, 224, 280, 355, 450], [15.0, 45.0]),
    row(5, 4.0, [112, 140, 180, 224, 280, 355, 450], [190, 236, 300, 375, 475], [18.0, 53.0]),
    row(5, 4.5, [118, 150, 190, 236, 300, 375, 475], [200, 250, 315, 400, 500], [21.0, 63.0]),
    row(6, 1.5, [80, 100, 125, 160, 200, 250, 315], [132, 170, 212, 265, 335], [7.5, 22.0]),
    row(6, 2.0, [90, 112, 140, 180, 224, 280, 355], [150, 190, 236, 300, 375], [9.5, 28.0]),
    row(6, 3.0, [106, 132, 170, 212, 265, 335, 425], [180, 224, 280, 355, 450], [15.0, 45.0]),
    row(6, 4.0, [118, 150, 190, 236, 300, 375, 475], [200, 250, 315, 400, 500], [19.0, 56.0]),
    row(6, 5.0, [125, 160, 200, 250, 315, 400, 500], [212, 265, 335, 425, 530], [24.0, 71.0]),
    row(6, 5.5, [132, 170, 212, 265, 335, 425, 530], [224, 280, 355, 450, 560], [28.0, 85.0]),
    row(6, 6.0, [140, 180, 224, 280, 355, 450, 560], [236, 300, 375, 475, 600], [32.0, 95.0]),
    row(7, 2.0, [95, 118, 150, 190, 236, 300, 375], [160, 200, 250, 315, 400], [12.0, 36.0]),
    row(7, 3.0, [112, 140, 180, 224, 280, 355, 450], [190, 236, 300, 375, 475], [18.0, 53.0]),
    row(7, 4.0, [125, 160, 200, 250, 315, 400, 500], [212, 265, 335, 425, 530], [24.0, 71.0]),
    row(7, 6.0, [150, 190, 236, 300, 375, 475, 600], [250, 315, 400, 500, 630], [36.0, 106.0]),
    row(7, 8.0, [170, 212, 265, 335, 425, 530, 670], [280, 355, 450, 560, 710], [45.0, 132.0]),
    row(8, 3.0, [125, 160, 200, 250, 315, 400, 500], [212, 265, 335, 425, 530], [20.0, 60.0]),
    row(8, 4.0, [140, 180, 224, 280, 355, 450, 560], [236, 300, 375, 475, 600], [26.0, 80.0]),
    row(8, 6.0, [160, 200, 250, 315, 400, 500, 630], [265, 335, 425, 530, 670], [40.0, 118.0]),
    row(8, 8.0, [180, 224, 280, 355, 450, 560, 710], [300, 375, 475, 600, 750], [50.0, 150.0]),
];

/// ISO 261 Table 1: the coarse pitch of each nominal diameter (mm), first to third choice.
const COARSE: [(f64, f64); 40] = [
    (1.0, 0.25),
    (1.1, 0.25),
    (1.2, 0.25),
    (1.4, 0.3),
    (1.6, 0.35),
    (1.8, 0.35),
    (2.0, 0.4),
    (2.2, 0.45),
    (2.5, 0.45),
    (3.0, 0.5),
    (3.5, 0.6),
    (4.0, 0.7),
    (4.5, 0.75),
    (5.0, 0.8),
    (6.0, 1.0),
    (7.0, 1.0),
    (8.0, 1.25),
    (9.0, 1.25),
    (10.0, 1.5),
    (11.0, 1.5),
    (12.0, 1.75),
    (14.0, 2.0),
    (16.0, 2.0),
    (18.0, 2.5),
    (20.0, 2.5),
    (22.0, 2.5),
    (24.0, 3.0),
    (27.0, 3.0),
    (30.0, 3.5),
    (33.0, 3.5),
    (36.0, 4.0),
    (39.0, 4.0),
    (42.0, 4.5),
    (45.0, 4.5),
    (48.0, 5.0),
    (52.0, 5.0),
    (56.0, 5.5),
    (60.0, 5.5),
    (64.0, 6.0),
    (68.0, 6.0),
];

/// The ISO 261 coarse pitch of nominal diameter `d`, if it has one.
pub(super) fn coarse_pitch(d: f64) -> Option<f64> {
    COARSE
        .iter()
        .find(|(n, _)| (n - d).abs() < 1e-9)
        .map(|&(_, p)| p)
}

/// The nominal diameters of the coarse series, for messages.
pub(super) fn coarse_sizes() -> String {
    let first = COARSE.first().map_or(0.0, |c| c.0);
    let last = COARSE.last().map_or(0.0, |c| c.0);
    format!("M{first} to M{last}")
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

fn pitch_index(p: f64) -> Option<usize> {
    PITCHES.iter().position(|&q| same(q, p))
}

/// The range of ISO 965-1 that holds basic major diameter `d`.
fn range_of(d: f64) -> Option<usize> {
    (0..RANGES.len() - 1).find(|&i| d > RANGES[i] && d <= RANGES[i + 1] + 1e-9)
}

fn size_row(d: f64, p: f64) -> Option<&'static SizeRow> {
    let r = range_of(d)?;
    SIZES.iter().find(|s| s.range == r && same(s.p, p))
}

/// The geometric mean of a range's limits: the `d` of the formulas for a tabulated row.
#[cfg(test)]
fn range_mean(r: usize) -> f64 {
    (RANGES[r] * RANGES[r + 1]).sqrt()
}

// ---- ISO 965-1 §13: the formulas (µm; P and d in mm) ----

/// §13.1: the magnitude of the fundamental deviation of a position (G, e, f, g).
pub(super) fn deviation_formula(pos: char, p: f64) -> f64 {
    match pos {
        'e' => 50.0 + 11.0 * p,
        'f' => 30.0 + 11.0 * p,
        _ => 15.0 + 11.0 * p,
    }
}

/// §13.3: Td(6), the external major diameter's grade 6 tolerance.
pub(super) fn td6_formula(p: f64) -> f64 {
    180.0 * p.powf(2.0 / 3.0) - 3.15 / p.sqrt()
}

/// §13.3: TD1(6), the internal minor diameter's grade 6 tolerance.
pub(super) fn td1_6_formula(p: f64) -> f64 {
    if p < 1.0 {
        433.0 * p - 190.0 * p.powf(1.22)
    } else {
        230.0 * p.powf(0.7)
    }
}

/// §13.4: Td2(6), the external pitch diameter's grade 6 tolerance.
pub(super) fn td2_6_formula(p: f64, d: f64) -> f64 {
    90.0 * p.powf(0.4) * d.powf(0.1)
}

/// Grade factors of Td2 (grades 3 to 9).
pub(super) const TD2_FACTOR: [f64; 7] = [0.5, 0.63, 0.8, 1.0, 1.25, 1.6, 2.0];
/// Grade factors of TD2 over Td2(6) (grades 4 to 8).
pub(super) const TD2_INT_FACTOR: [f64; 5] = [0.85, 1.06, 1.32, 1.7, 2.12];
/// Grade factors of Td (grades 4, 6, 8).
pub(super) const TD_FACTOR: [f64; 3] = [0.63, 1.0, 1.6];
/// Grade factors of TD1 (grades 4 to 8).
pub(super) const TD1_FACTOR: [f64; 5] = [0.63, 0.8, 1.0, 1.25, 1.6];

/// A value of ISO 965-1's per-pitch tables, for the Tr tests: `e` the |es| of position e
/// (Table 1), `d` the major diameter's Td(4) (Table 4), µm; `None` where the table does
/// not list the pitch.
#[cfg(test)]
pub(super) fn table_value(what: char, p: f64) -> Option<f64> {
    let i = pitch_index(p)?;
    let v = match what {
        'e' => DEV_E[i],
        _ => TD[0][i],
    };
    (v > 0).then_some(v as f64)
}

/// Every tabulated value with its formula's, for the consistency test: (what, table µm,
/// formula µm).
#[cfg(test)]
pub(super) fn table_and_formula() -> Vec<(String, f64, f64)> {
    let mut out = Vec::new();
    for (i, &p) in PITCHES.iter().enumerate() {
        for (pos, col) in [('G', &DEV_G), ('e', &DEV_E), ('f', &DEV_F)] {
            if col[i] > 0 {
                out.push((
                    format!("es({pos}) P {p}"),
                    col[i] as f64,
                    deviation_formula(pos, p),
                ));
            }
        }
        for (g, f) in TD_FACTOR.iter().enumerate() {
            if TD[g][i] > 0 {
                let name = format!("Td({}) P {p}", [4, 6, 8][g]);
                out.push((name, TD[g][i] as f64, f * td6_formula(p)));
            }
        }
        for (g, f) in TD1_FACTOR.iter().enumerate() {
            if TD1[g][i] > 0 {
                let name = format!("TD1({}) P {p}", g + 4);
                out.push((name, TD1[g][i] as f64, f * td1_6_formula(p)));
            }
        }
    }
    for s in &SIZES {
        let d = range_mean(s.range);
        let (lo, hi) = (RANGES[s.range], RANGES[s.range + 1]);
        for (g, f) in TD2_FACTOR.iter().enumerate() {
            if s.td2[g] > 0 {
                let name = format!("Td2({}) d {lo}..{hi} P {}", g + 3, s.p);
                out.push((name, s.td2[g] as f64, f * td2_6_formula(s.p, d)));
            }
        }
        for (g, f) in TD2_INT_FACTOR.iter().enumerate() {
            if s.td2_int[g] > 0 {
                let name = format!("TD2({}) d {lo}..{hi} P {}", g + 4, s.p);
                out.push((name, s.td2_int[g] as f64, f * td2_6_formula(s.p, d)));
            }
        }
    }
    out
}

/// The lengths of engagement of every row with the formulas' (§13.2: S up to 2.24 P
/// d^0.2, L from 6.7 P d^0.2): (what, table mm, formula mm).
#[cfg(test)]
pub(super) fn engagement_and_formula() -> Vec<(String, f64, f64)> {
    SIZES
        .iter()
        .flat_map(|s| {
            let k = s.p * range_mean(s.range).powf(0.2);
            let name = format!("d {}..{} P {}", RANGES[s.range], RANGES[s.range + 1], s.p);
            [
                (format!("LE S {name}"), s.le[0], 2.24 * k),
                (format!("LE L {name}"), s.le[1], 6.7 * k),
            ]
        })
        .collect()
}

/// A value from a table or, off the table, from its formula (µm), and whether it came
/// from the table.
type Looked = (f64, bool);

/// The least pitch a grade of a per-pitch table exists for (the tables leave the finest
/// pitches out of the coarse grades); the formulas are not used below it.
fn least_pitch(col: &[u16; 25]) -> f64 {
    PITCHES[col.iter().position(|&v| v > 0).unwrap_or(0)]
}

/// The fundamental deviation of a position at pitch `p` (µm, signed: + for G, − for e f
/// g, 0 for H h).
fn deviation(pos: char, p: f64) -> Result<Looked, String> {
    if pos == 'H' || pos == 'h' {
        return Ok((0.0, true));
    }
    let (col, sign) = match pos {
        'G' => (&DEV_G, 1.0),
        'g' => (&DEV_G, -1.0),
        'e' => (&DEV_E, -1.0),
        'f' => (&DEV_F, -1.0),
        _ => {
            return Err(format!(
                "ISO 965-1 position `{pos}` is not in vpcut: expected e, f, g or h (external), G or H (internal)"
            ))
        }
    };
    if let Some(i) = pitch_index(p) {
        return match col[i] {
            0 => Err(format!(
                "ISO 965-1 Table 1 gives no position {pos} for pitch {p} mm (from {} mm)",
                least_pitch(col)
            )),
            v => Ok((sign * v as f64, true)),
        };
    }
    if p < least_pitch(col) {
        return Err(format!(
            "ISO 965-1 gives position {pos} only from pitch {} mm",
            least_pitch(col)
        ));
    }
    Ok((sign * deviation_formula(pos.to_ascii_lowercase(), p), false))
}

/// A per-pitch tolerance (Td or TD1) of grade index `g` (into `factors`).
fn per_pitch(
    table: &[[u16; 25]],
    factors: &[f64],
    g: usize,
    p: f64,
    grade6: fn(f64) -> f64,
    what: &str,
    grade: u8,
) -> Result<Looked, String> {
    let col = &table[g];
    if let Some(i) = pitch_index(p) {
        return match col[i] {
            0 => Err(format!(
                "ISO 965-1 gives no grade {grade} {what} for pitch {p} mm (from {} mm)",
                least_pitch(col)
            )),
            v => Ok((v as f64, true)),
        };
    }
    if p < least_pitch(col) {
        return Err(format!(
            "ISO 965-1 gives grade {grade} {what} only from pitch {} mm",
            least_pitch(col)
        ));
    }
    Ok((factors[g] * grade6(p), false))
}

/// A pitch-diameter tolerance (Td2 external, TD2 internal) of grade `grade`.
fn pitch_tolerance(internal: bool, grade: u8, d: f64, p: f64) -> Result<Looked, String> {
    let (lo, hi, factors) = if internal {
        (4u8, 8u8, &TD2_INT_FACTOR[..])
    } else {
        (3, 9, &TD2_FACTOR[..])
    };
    let what = if internal { "TD2" } else { "Td2" };
    if grade < lo || grade > hi {
        return Err(format!(
            "ISO 965-1 has no grade {grade} for the {} pitch diameter: expected {lo} to {hi}",
            if internal { "internal" } else { "external" }
        ));
    }
    let g = (grade - lo) as usize;
    let col = |s: &SizeRow| if internal { s.td2_int[g] } else { s.td2[g] };
    if let Some(s) = size_row(d, p) {
        return match col(s) {
            0 => Err(format!(
                "ISO 965-1 gives no grade {grade} {what} for M{d}x{p}: the grade is not defined for this pitch"
            )),
            v => Ok((v as f64, true)),
        };
    }
    // Off the table: the formula with the actual diameter, where the grade exists for the
    // pitch in some range.
    let least = SIZES
        .iter()
        .filter(|s| col(s) > 0)
        .map(|s| s.p)
        .fold(f64::INFINITY, f64::min);
    if p < least {
        return Err(format!(
            "ISO 965-1 gives grade {grade} {what} only from pitch {least} mm"
        ));
    }
    Ok((factors[g] * td2_6_formula(p, d), false))
}

/// An ISO 965-1 tolerance class as written: pitch diameter's grade and position, then the
/// crest diameter's (major for external, minor for internal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct MetricClass {
    /// Pitch diameter: grade 3..9 and position letter.
    pub(super) pitch: (u8, char),
    /// Crest diameter: grade and position letter.
    pub(super) crest: (u8, char),
}

impl MetricClass {
    /// Whether the class is an internal thread's (upper-case positions).
    pub(super) fn internal(&self) -> bool {
        self.pitch.1.is_ascii_uppercase()
    }

    /// The class as ISO 965-1 writes it (`6g`, `5g6g`).
    pub(super) fn text(&self) -> String {
        if self.pitch == self.crest {
            format!("{}{}", self.pitch.0, self.pitch.1)
        } else {
            format!(
                "{}{}{}{}",
                self.pitch.0, self.pitch.1, self.crest.0, self.crest.1
            )
        }
    }
}

fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// The length of engagement the GO gauge checks over: the group's longest length (S: the
/// S/N boundary; N: the N/L boundary), an explicit length, or infinite for L (the whole
/// thread; the job bounds it by the thread's length).
fn engagement_length(d: f64, p: f64, e: Engagement) -> f64 {
    let (s, l) = match size_row(d, p) {
        Some(r) => (r.le[0], r.le[1]),
        None => {
            let k = p * d.powf(0.2);
            (2.24 * k, 6.7 * k)
        }
    };
    match e {
        Engagement::Short => s,
        Engagement::Normal => l,
        Engagement::Long => f64::INFINITY,
        Engagement::Length(v) => v,
    }
}

/// The limits of size of M`d`x`p` in `class` (ISO 965-1), as `designation` names it.
pub(super) fn limits(
    designation: &str,
    d: f64,
    p: f64,
    starts: u32,
    class: MetricClass,
    engagement: Engagement,
) -> Result<ThreadClass, StandardError> {
    let err = |m: String| StandardError::new(m);
    if d <= RANGES[0] {
        return Err(err(format!(
            "ISO 965-1 covers basic major diameters over {} mm, got {d}",
            RANGES[0]
        )));
    }
    let internal = class.internal();
    if class.crest.1.is_ascii_uppercase() != internal {
        return Err(err(format!(
            "`{}`: the pitch and crest diameters' positions must both be lower case (external) or both upper case (internal)",
            class.text()
        )));
    }
    let h = 0.866_025_403_784_438_6 * p;
    let d2 = d - 0.649_519_052_838_329 * p;
    let d1 = d - 1.082_531_754_730_548 * p;
    let (pd_dev, t1) = deviation(class.pitch.1, p).map_err(err)?;
    let (cr_dev, t2) = deviation(class.crest.1, p).map_err(err)?;
    let (tp, t3) = pitch_tolerance(internal, class.pitch.0, d, p).map_err(err)?;
    let (tc, t4) = if internal {
        let g = class.crest.0;
        if !(4..=8).contains(&g) {
            return Err(err(format!(
                "ISO 965-1 has no grade {g} for the internal minor diameter: expected 4 to 8"
            )));
        }
        per_pitch(
            &TD1,
            &TD1_FACTOR,
            (g - 4) as usize,
            p,
            td1_6_formula,
            "TD1",
            g,
        )
        .map_err(err)?
    } else {
        let g = class.crest.0;
        let gi = match g {
            4 => 0,
            6 => 1,
            8 => 2,
            _ => {
                return Err(err(format!(
                    "ISO 965-1 has no grade {g} for the external major diameter: expected 4, 6 or 8"
                )))
            }
        };
        per_pitch(&TD, &TD_FACTOR, gi, p, td6_formula, "Td", g).map_err(err)?
    };
    let from_table = t1 && t2 && t3 && t4;
    let um = 1e-3;
    let (pitch_diameter, major_diameter, minor_diameter, root) = if internal {
        let d2min = d2 + pd_dev * um;
        let d1min = d1 + cr_dev * um;
        (
            SizeLimits::new(round3(d2min), round3(d2min + tp * um)),
            SizeLimits::new(round3(d + pd_dev * um), f64::INFINITY),
            SizeLimits::new(round3(d1min), round3(d1min + tc * um)),
            None,
        )
    } else {
        let d2max = d2 + pd_dev * um;
        let d2min = d2max - tp * um;
        let dmax = d + cr_dev * um;
        // ISO 965-1 §11: the external root contour, from the least-material profile's
        // fundamental triangle root apex (so d3 min = d2 min − H + 2 C_min, the
        // "rounded form" minimum of ASME B1.13M, and d3 max = d1 + es − 2y).
        let r_min = 0.125 * p;
        let t = tp * um;
        let y = r_min * (1.0 - (PI / 3.0 - (1.0 - t / (4.0 * r_min)).acos()).cos());
        let zone = RootZone {
            radius_min: r_min,
            truncation_min: 0.125 * p,
            truncation_max: h / 4.0 - y + t / 2.0,
        };
        (
            SizeLimits::new(round3(d2min), round3(d2max)),
            SizeLimits::new(round3(dmax - tc * um), round3(dmax)),
            SizeLimits::new(
                round3(d2min - h + 2.0 * zone.truncation_min),
                round3(d2min - h + 2.0 * zone.truncation_max),
            ),
            Some(zone),
        )
    };
    Ok(ThreadClass {
        designation: designation.to_string(),
        class: class.text(),
        units: UnitSystem::Metric,
        internal,
        basic_major: d,
        basic_pitch_diameter: d2,
        basic_minor: d1,
        pitch: p,
        starts,
        flank_angle: 60f64.to_radians(),
        taper: 0.0,
        pitch_diameter,
        major_diameter,
        minor_diameter,
        engagement_length: engagement_length(d, p, engagement),
        not_go_turns: 2.0,
        root,
        taper_gauge: None,
        source: if from_table {
            "ISO 965-1 tables".to_string()
        } else {
            "ISO 965-1 formulas (size or pitch not in its tables)".to_string()
        },
    })
}
