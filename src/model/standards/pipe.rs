//! Pipe threads: NPT (ASME B1.20.1, taper 1:16), G (ISO 228-1, parallel, Whitworth 55°)
//! and R, Rc, Rp (ISO 7-1, taper 1:16 and parallel internal, Whitworth 55°).
//!
//! - NPT: the pitch diameter at the pipe's end E0 = D − (0.05D + 1.1)/n, at the hand-tight
//!   plane E1 = E0 + 0.0625 L1 (engineersedge.com "Pipe thread pitch diameter formulas");
//!   L1 per size from B1.20.1 Table 2 (as unifiedalloys.com "Pipe Threads" reproduces it,
//!   E1 to 5 decimals: every row is the formula's to 1e-5 in). The thread is gauged by an
//!   L1 gauge flush within ±1 turn, ±p axially, so ±p/16 on the diameter at the gauge
//!   plane (thread-gauging.md §1.2).
//! - G: the basic diameters of ISO 228-1 Table 1 (engineeringhardware.com, haustechnik-
//!   versand.com: d and D1) and the Whitworth form, h = 0.640327P. Its tolerances per
//!   size group: the external major diameter's Td (oekopan.at "Gewindemaße": G1/2 20.67 to
//!   20.96 mm, Td = 0.284; G1/8 0.214; G1/4 and 3/8 0.250; G1 to 2 0.360; G2 1/2 and 3
//!   0.434); the pitch diameter's TD2 (internal, +) and class A's Td2 (−) are half of it, class
//!   B's all of it (ring-plug-thread-gages.com "Class A vs B": "Class-B has twice the
//!   product tolerance of the Class-A"; ISO 228-1 Table 1's 0.107/0.125/0.142/0.180/
//!   0.217 mm); the internal minor diameter's TD1 is ISO 228-1 Table 1's
//!   (0.282/0.445/0.541/0.640/0.640 mm, not found in a second public source).
//! - R, Rc, Rp: the basic diameters at the gauge plane are ISO 228-1's (Mechanical
//!   Engineer's Pocket Book 4.1.38, ISO pipe threads tapered: 1/8 9.728/9.147/8.566 mm).
//!   ISO 7-1's gauge lengths and the tolerances of the gauge plane's position (in turns)
//!   from two public copies ([`R_GAUGE`]): an R or Rc designation names a class gauged by
//!   its stand-off. Rp (parallel internal) names none: its diametral tolerance was found in
//!   one copy only.

use super::StandardError;
use crate::model::tolerance::{SizeLimits, TaperGauge, ThreadClass, UnitSystem};

/// ASME B1.20.1 Table 2: (size as written, outside diameter D in, threads per inch n, L1 in).
const NPT: [(&str, f64, f64, f64); 16] = [
    ("1/16", 0.3125, 27.0, 0.160),
    ("1/8", 0.405, 27.0, 0.1615),
    ("1/4", 0.540, 18.0, 0.2278),
    ("3/8", 0.675, 18.0, 0.240),
    ("1/2", 0.840, 14.0, 0.320),
    ("3/4", 1.050, 14.0, 0.339),
    ("1", 1.315, 11.5, 0.400),
    ("1 1/4", 1.660, 11.5, 0.420),
    ("1 1/2", 1.900, 11.5, 0.420),
    ("2", 2.375, 11.5, 0.436),
    ("2 1/2", 2.875, 8.0, 0.682),
    ("3", 3.500, 8.0, 0.766),
    ("3 1/2", 4.000, 8.0, 0.821),
    ("4", 4.500, 8.0, 0.844),
    ("5", 5.563, 8.0, 0.937),
    ("6", 6.625, 8.0, 0.958),
];

/// ISO 228-1 Table 1: (size, threads per inch, major diameter mm, tolerance group).
const G: [(&str, f64, f64, usize); 24] = [
    ("1/16", 28.0, 7.723, 0),
    ("1/8", 28.0, 9.728, 0),
    ("1/4", 19.0, 13.157, 1),
    ("3/8", 19.0, 16.662, 1),
    ("1/2", 14.0, 20.955, 2),
    ("5/8", 14.0, 22.911, 2),
    ("3/4", 14.0, 26.441, 2),
    ("7/8", 14.0, 30.201, 2),
    ("1", 11.0, 33.249, 3),
    ("1 1/8", 11.0, 37.897, 3),
    ("1 1/4", 11.0, 41.910, 3),
    ("1 1/2", 11.0, 47.803, 3),
    ("1 3/4", 11.0, 53.746, 3),
    ("2", 11.0, 59.614, 3),
    ("2 1/4", 11.0, 65.710, 4),
    ("2 1/2", 11.0, 75.184, 4),
    ("2 3/4", 11.0, 81.534, 4),
    ("3", 11.0, 87.884, 4),
    ("3 1/2", 11.0, 100.330, 4),
    ("4", 11.0, 113.030, 4),
    ("4 1/2", 11.0, 125.730, 4),
    ("5", 11.0, 138.430, 4),
    ("5 1/2", 11.0, 151.130, 4),
    ("6", 11.0, 163.830, 4),
];

/// ISO 228-1 per tolerance group (mm): the external major diameter's Td and the internal
/// minor diameter's TD1. TD2 = Td2(A) = Td/2, Td2(B) = Td.
const G_TOLERANCES: [(f64, f64); 5] = [
    (0.214, 0.282),
    (0.250, 0.445),
    (0.284, 0.541),
    (0.360, 0.640),
    (0.434, 0.640),
];

/// ISO 7-1 sizes: those of ISO 228-1 less 5/8, 7/8, 1 1/8, 1 3/4, 2 1/4, 2 3/4, 3 1/2,
/// 4 1/2 and 5 1/2.
const R_SIZES: [&str; 15] = [
    "1/16", "1/8", "1/4", "3/8", "1/2", "3/4", "1", "1 1/4", "1 1/2", "2", "2 1/2", "3", "4", "5",
    "6",
];

/// ISO 7-1 Table 1 per size of [`R_SIZES`]: the gauge length (mm, from the small end of the
/// external thread to its gauge plane), and the tolerances of the gauge plane's position in
/// turns: external ±T1/2, internal ±T2/2. From a public copy of EN 10226-1:2004 Table 1
/// (a thread calculator's `families/bspt/data.js`: gauge length; T1/2 0.9/1.3/1.8/2.3/3.5
/// mm; T2/2 1.1/1.7/2.3/2.9/3.5 mm), in turns as BS 21:1985 Table 2 gives them
/// (indazoo/MCAD `fasteners/threads.scad` `BSP_data`: gauge length 4 3/8 .. 12 3/8 turns,
/// ±1 turn up to size 2 and ±1 1/2 turns from 2 1/2, T2/2 1 1/4 and 1 1/2 turns); each
/// mm value is the turns times the pitch to 0.1 mm (the test
/// `iso7_gauge_lengths_and_tolerances_agree`).
pub(super) const R_GAUGE: [(f64, f64, f64); 15] = [
    (4.0, 1.0, 1.25),
    (4.0, 1.0, 1.25),
    (6.0, 1.0, 1.25),
    (6.4, 1.0, 1.25),
    (8.2, 1.0, 1.25),
    (9.5, 1.0, 1.25),
    (10.4, 1.0, 1.25),
    (12.7, 1.0, 1.25),
    (12.7, 1.0, 1.25),
    (15.9, 1.0, 1.25),
    (17.5, 1.5, 1.5),
    (20.6, 1.5, 1.5),
    (25.4, 1.5, 1.5),
    (28.6, 1.5, 1.5),
    (28.6, 1.5, 1.5),
];

/// The Whitworth form's thread height h = 2H/3 = 0.640327P (H = 0.960491P), to 0.001 mm
/// as ISO 228-1 Table 1 prints it (G1: h 1.479, d1 = 33.249 − 2.958 = 30.291; unrounded
/// 30.292).
pub(super) fn whitworth_depth(p: f64) -> f64 {
    round3(0.640_327 * p)
}

/// An NPT size: (outside diameter in, threads per inch, L1 in).
pub(super) fn npt_size(size: &str) -> Option<(f64, f64, f64)> {
    NPT.iter()
        .find(|s| s.0 == size)
        .map(|&(_, d, n, l1)| (d, n, l1))
}

/// A G (ISO 228-1) size: (threads per inch, major diameter mm, tolerance group).
pub(super) fn g_size(size: &str) -> Option<(f64, f64, usize)> {
    G.iter()
        .find(|s| s.0 == size)
        .map(|&(_, n, d, g)| (n, d, g))
}

/// Whether ISO 7-1 has `size`.
pub(super) fn r_size(size: &str) -> bool {
    R_SIZES.contains(&size)
}

/// The sizes of a table, for messages.
pub(super) fn sizes(kind: char) -> String {
    let list: Vec<&str> = match kind {
        'N' => NPT.iter().map(|s| s.0).collect(),
        'G' => G.iter().map(|s| s.0).collect(),
        _ => R_SIZES.to_vec(),
    };
    list.join(", ")
}

/// NPT: E0 and E1 (in) of a size.
pub(super) fn npt_e0_e1(d: f64, n: f64, l1: f64) -> (f64, f64) {
    let e0 = d - (0.05 * d + 1.1) / n;
    (e0, e0 + 0.0625 * l1)
}

/// The NPT class of `size` (ASME B1.20.1): the pitch diameter at the hand-tight (gauge)
/// plane L1 from the small end, ±1 turn of the L1 gauge. `engagement_length` is L1, the
/// gauge plane's distance from the small end; major and minor are not limited separately
/// (B1.20.1 limits the truncation instead).
pub(super) fn npt_limits(
    designation: &str,
    size: &str,
    internal: bool,
) -> Result<ThreadClass, StandardError> {
    let (d, n, l1) =
        npt_size(size).ok_or_else(|| StandardError::new(format!("{size} is not an NPT size")))?;
    let (_, e1) = npt_e0_e1(d, n, l1);
    let p = 1.0 / n;
    let mm = |v: f64| v * 25.4;
    let turn = p / 16.0;
    Ok(ThreadClass {
        designation: designation.to_string(),
        class: String::new(),
        units: UnitSystem::Inch,
        internal,
        basic_major: mm(e1 + 0.8 * p),
        basic_pitch_diameter: mm(e1),
        basic_minor: mm(e1 - 0.8 * p),
        pitch: mm(p),
        starts: 1,
        flank_angle: 60f64.to_radians(),
        taper: 1.0 / 16.0,
        pitch_diameter: SizeLimits::new(mm(e1 - turn), mm(e1 + turn)),
        major_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
        minor_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
        engagement_length: mm(l1),
        // A taper thread's gauge checks its stand-off (±1 turn), there is no NOT GO.
        not_go_turns: 0.0,
        root: None,
        // The L1 ring's gauge plane lies L1 from the pipe's end; the L1 plug's notch is
        // flush with the fitting's face.
        taper_gauge: Some(TaperGauge {
            gauge_plane: if internal { 0.0 } else { mm(l1) },
            length: mm(l1),
            tolerance_turns: 1.0,
        }),
        source: "ASME B1.20.1 (E1 from its formulas, L1 from its Table 2)".to_string(),
    })
}

/// The ISO 7-1 class of `size`: R (external) or Rc (internal, `internal`). The basic
/// diameters at the gauge plane are ISO 228-1's (the major diameter of `G` and the
/// Whitworth form); the gauge plane lies the gauge length from an external thread's small
/// end, and half a pitch behind an internal thread's face (ISO 7-1 §3.3 note 4); the gauge
/// may stand ±T1/2 (external) or ±T2/2 (internal) turns off it. ISO 7-1 limits no diameter
/// separately.
pub(super) fn r_limits(
    designation: &str,
    size: &str,
    internal: bool,
) -> Result<ThreadClass, StandardError> {
    let i = R_SIZES
        .iter()
        .position(|s| *s == size)
        .ok_or_else(|| StandardError::new(format!("R{size} is not an ISO 7-1 size")))?;
    let (n, d, _) =
        g_size(size).ok_or_else(|| StandardError::new(format!("{size} has no ISO 228-1 size")))?;
    let p = 25.4 / n;
    let h = whitworth_depth(p);
    let (gauge_length, t1, t2) = R_GAUGE[i];
    let turns = if internal { t2 } else { t1 };
    let e = d - h;
    let dev = turns * p / 16.0;
    Ok(ThreadClass {
        designation: designation.to_string(),
        class: String::new(),
        units: UnitSystem::Metric,
        internal,
        basic_major: d,
        basic_pitch_diameter: e,
        basic_minor: d - 2.0 * h,
        pitch: p,
        starts: 1,
        flank_angle: 55f64.to_radians(),
        taper: 1.0 / 16.0,
        pitch_diameter: SizeLimits::new(e - dev, e + dev),
        major_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
        minor_diameter: SizeLimits::new(f64::NEG_INFINITY, f64::INFINITY),
        engagement_length: gauge_length,
        not_go_turns: 0.0,
        root: None,
        taper_gauge: Some(TaperGauge {
            gauge_plane: if internal { 0.5 * p } else { gauge_length },
            length: gauge_length,
            tolerance_turns: turns,
        }),
        source: "ISO 7-1 Table 1 (gauge lengths and their tolerances in turns, as EN 10226-1 and BS 21 print them); ISO 228-1's diameters at the gauge plane".to_string(),
    })
}

fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// The G class of `size` (ISO 228-1): external A or B, or internal (`class` None).
pub(super) fn g_limits(
    designation: &str,
    size: &str,
    class: Option<char>,
) -> Result<ThreadClass, StandardError> {
    let (n, d, group) = g_size(size)
        .ok_or_else(|| StandardError::new(format!("G{size} is not an ISO 228-1 size")))?;
    let p = 25.4 / n;
    let d2 = d - whitworth_depth(p);
    let d1 = d - 2.0 * whitworth_depth(p);
    let (td, td1) = G_TOLERANCES[group];
    let (internal, pitch_diameter, major, minor) = match class {
        None => (
            true,
            SizeLimits::new(round3(d2), round3(d2 + td / 2.0)),
            SizeLimits::new(d, f64::INFINITY),
            SizeLimits::new(round3(d1), round3(d1 + td1)),
        ),
        Some(c) => {
            let t = if c == 'A' { td / 2.0 } else { td };
            (
                false,
                SizeLimits::new(round3(d2 - t), round3(d2)),
                SizeLimits::new(round3(d - td), d),
                SizeLimits::new(f64::NEG_INFINITY, round3(d1)),
            )
        }
    };
    Ok(ThreadClass {
        designation: designation.to_string(),
        class: class.map(String::from).unwrap_or_default(),
        units: UnitSystem::Metric,
        internal,
        basic_major: d,
        basic_pitch_diameter: d2,
        basic_minor: d1,
        pitch: p,
        starts: 1,
        flank_angle: 55f64.to_radians(),
        taper: 0.0,
        pitch_diameter,
        major_diameter: major,
        minor_diameter: minor,
        // ISO 228-1 sets no length of engagement: the GO gauge checks the whole thread
        // (the job bounds it by the thread's length); NOT GO as ISO 1502 (2 turns).
        engagement_length: f64::INFINITY,
        not_go_turns: 2.0,
        root: None,
        taper_gauge: None,
        source: "ISO 228-1 Table 1".to_string(),
    })
}
