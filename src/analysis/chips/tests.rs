//! Chips and infeeds against the passes' own closed forms: radial infeed's chips are the
//! depth increments exactly, flank infeed's within the line model's bound, the first pass
//! its depth under the (turned) crest, a spring pass none; G76-style shifts at the flank's
//! angle rub, a modified flank infeed does not.

use super::*;
use crate::kernel::turn::{TurnCut, TurnPath, TurningTool};
use crate::model::helix::Spindle;
use crate::model::tool::{DepthLimits, Edge, Reference};
use crate::model::Rng;

fn v_tool(angle_deg: f64, flat: f64) -> Tool {
    let half = (angle_deg / 2.0).to_radians();
    Tool {
        id: 3,
        edge: Edge::Trapezoid {
            tip: flat,
            left_angle: half,
            right_angle: half,
        },
        reference: Reference::Tip,
        body: None,
        length: None,
        depth_per_pass: DepthLimits::default(),
    }
}

/// A pass of a 30 mm bar's external thread, lead 2, from z 5 to -30 shifted by `dz`, tip at
/// `depth` under r = 15.
fn pass(depth: f64, dz: f64, start_angle: f64) -> Pass {
    let x = 30.0 - 2.0 * depth;
    Pass {
        tool: 0,
        x_start: x,
        x_end: x,
        z_start: 5.0 + dz,
        z_end: -30.0 + dz,
        lead: 2.0,
        lead_change: 0.0,
        start_angle,
        spindle: Spindle::Cw,
    }
}

fn bar(turned: &Turned) -> Surface<'_> {
    Surface {
        sense: 1.0,
        q_blank: 15.0,
        q_floor: 0.0,
        z_span: (-60.0, 0.0),
        turned,
    }
}

#[test]
fn radial_infeed_chips_are_the_depth_increments_and_a_spring_pass_none() {
    // Random G92-like schedules: radial passes at increasing depths, the last repeated.
    let mut rng = Rng(23);
    let none = Turned::default();
    for case in 0..30 {
        let tool = v_tool(60.0, rng.range(0.01, 0.4));
        let n = 2 + case % 6;
        let mut depths: Vec<f64> = (0..n).map(|_| rng.range(0.02, 0.3)).collect();
        let mut acc = 0.0;
        for d in depths.iter_mut() {
            acc += *d;
            *d = acc;
        }
        depths.push(acc);
        let passes: Vec<Pass> = depths.iter().map(|&d| pass(d, 0.0, 0.0)).collect();
        let chips = pass_chips(&passes, std::slice::from_ref(&tool), bar(&none));
        let mut prev = 0.0;
        for (k, (c, &d)) in chips.iter().zip(&depths).enumerate() {
            assert!(
                (c.depth - (d - prev)).abs() < 1e-9,
                "case {case} pass {k}: {} vs {}",
                c.depth,
                d - prev
            );
            prev = d;
        }
    }
}

#[test]
fn flank_infeed_chips_are_the_depth_increments_within_the_line_models_bound() {
    // FANUC G76's schedule (controllers.md 2.3: k 1.30, dd 0.45, dmin 0.10, d 0.05) with
    // each pass shifted (k - d_n) tan 30 against the feed: the chips are the increments,
    // over by at most SPACING cot 30 (the old groove's lowest cell beside its tip stands
    // that far above the exact tip; the new tip is exact).
    let k: f64 = 1.3;
    let depths = [0.45, 0.636, 0.779, 0.9, 1.006, 1.106, 1.206, 1.25, 1.3, 1.3];
    let tool = v_tool(60.0, 0.0);
    let tan = 30f64.to_radians().tan();
    let passes: Vec<Pass> = depths
        .iter()
        .map(|&d| pass(d, (k - d) * tan, 0.0))
        .collect();
    let none = Turned::default();
    let chips = pass_chips(&passes, std::slice::from_ref(&tool), bar(&none));
    let bound = SPACING / tan + 1e-9;
    let mut prev = 0.0;
    for (c, &d) in chips.iter().zip(&depths) {
        assert!(
            c.depth >= d - prev - 1e-9 && c.depth <= d - prev + bound,
            "{} vs {}",
            c.depth,
            d - prev
        );
        prev = d;
    }
    assert_eq!(chips[9].depth, 0.0, "the spring pass cuts nothing");
}

#[test]
fn a_pass_in_the_air_cuts_no_chip() {
    // The bar ends at z 0: a pass from z 5 to z 1 never meets it.
    let none = Turned::default();
    let mut p = pass(0.5, 0.0, 0.0);
    p.z_end = 1.0;
    let chips = pass_chips(&[p], &[v_tool(60.0, 0.2)], bar(&none));
    assert_eq!(chips[0].depth, 0.0);
}

#[test]
fn the_first_chip_is_under_the_turned_crest_and_each_start_has_its_own() {
    // The bar turned to X29 (r 14.5) by a sharp turning tool: a first pass 0.7 under the
    // bar's 15 takes 0.2. A second start (half a turn on) begins under the crest again.
    let t = TurningTool::turning(1, 0.0, (0.0, 80f64.to_radians()), false);
    let turned = Turned {
        cuts: vec![TurnCut {
            tool: t,
            path: TurnPath::of_move(&t, 1.0, (10.0, 29.0), (-60.0, 29.0), None),
        }],
    };
    let tool = v_tool(60.0, 0.1);
    let passes = [
        pass(0.7, 0.0, 0.0),
        pass(1.0, 0.0, 0.0),
        pass(0.7, 0.0, std::f64::consts::PI),
    ];
    let chips = pass_chips(&passes, std::slice::from_ref(&tool), bar(&turned));
    let got: Vec<f64> = chips.iter().map(|c| c.depth).collect();
    for (g, w) in got.iter().zip([0.2, 0.3, 0.2]) {
        assert!((g - w).abs() < 1e-9, "{got:?}");
    }
}

fn blocks(n: usize) -> Vec<(usize, String, usize)> {
    (0..n).map(|i| (i, "O1.NC".to_string(), 9)).collect()
}

#[test]
fn an_infeed_beyond_the_flank_angle_rubs_the_trailing_edge_and_flank_infeed_does_not() {
    // G76 shifts (k - d_n) tan(a/2) against the feed (towards +z for shallower passes when
    // cutting towards -z): each deeper pass moves towards -z, so the +z (trailing) flank
    // follows the old wall. A 55 deg insert at a = 60: infeed 30 beyond its flank's 27.5,
    // the trailing edge is fed into the wall: a rub. a = 60 with a 60 deg insert: infeed
    // 30 = flank 30, the edge slides along the wall (pure flank infeed): none; a = 55 with
    // it: 27.5, none. Radial G92-style passes: none.
    let k = 1.3;
    let depths = [0.45, 0.7, 0.9, 1.1, 1.3];
    let run = |a_deg: f64, insert_deg: f64| {
        let tan = (a_deg / 2.0).to_radians().tan();
        let passes: Vec<Pass> = depths
            .iter()
            .map(|&d| pass(d, (k - d) * tan, 0.0))
            .collect();
        infeed_rubs(
            &passes,
            &[v_tool(insert_deg, 0.0)],
            &blocks(passes.len()),
            &[true; 5],
            1.0,
        )
    };
    let r = run(60.0, 55.0);
    assert_eq!(r.len(), 1, "one finding per block");
    assert_eq!(r[0].pass, 1);
    assert!(r[0].trailing);
    assert!((r[0].infeed.to_degrees() - 30.0).abs() < 1e-9);
    assert!((r[0].flank.to_degrees() - 27.5).abs() < 1e-9);
    assert!(run(60.0, 60.0).is_empty());
    assert!(run(55.0, 60.0).is_empty());
    assert!(run(0.0, 60.0).is_empty());
    // Shifted the other way (each deeper pass towards +z while cutting towards -z): the
    // -z, leading flank follows the wall.
    let tan = 30f64.to_radians().tan();
    let passes: Vec<Pass> = depths
        .iter()
        .map(|&d| pass(d, -(k - d) * tan, 0.0))
        .collect();
    let r = infeed_rubs(&passes, &[v_tool(55.0, 0.0)], &blocks(5), &[true; 5], 1.0);
    assert_eq!(r.len(), 1);
    assert!(!r[0].trailing);
    // Not a cycle's passes (a macro's G32 loop): not judged.
    let tan = 30f64.to_radians().tan();
    let passes: Vec<Pass> = depths
        .iter()
        .map(|&d| pass(d, (k - d) * tan, 0.0))
        .collect();
    let r = infeed_rubs(&passes, &[v_tool(55.0, 0.0)], &blocks(5), &[false; 5], 1.0);
    assert!(r.is_empty());
}
