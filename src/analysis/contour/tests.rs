//! The part's contour against cuts whose depths are derived by hand: a thread run into a
//! shoulder, one ending short of it (its flank still reaches), one ending in a relief
//! groove, a diameter turned oversize and a chamfer never turned.

use super::*;
use crate::model::helix::{Helix, LeadLaw, Spindle};
use crate::model::thread::{Side, WidthRule};
use crate::model::tool::{DepthLimits, Edge, Reference};

const ROOT: f64 = 15.0 - 0.613435 * 2.0;

/// M30x2 from z -1 (groove centres at -1 - 2k), 18 turns.
fn m30() -> ThreadSpec {
    ThreadSpec {
        side: Side::External,
        root_radius: ROOT,
        crest_radius: 15.0,
        pitch_radius: 14.350481,
        left_angle: 30f64.to_radians(),
        right_angle: 30f64.to_radians(),
        width: WidthRule::Groove(1.0),
        starts: 1,
        helix: Helix {
            z0: -1.0,
            dir: -1.0,
            law: LeadLaw { f: 2.0, k: 0.0 },
            theta0: 0.0,
            spin: 1.0,
        },
        turns: 18.0,
        outline: None,
        taper: None,
    }
}

/// A 60 deg insert with the d3 root flat P/6, driven by its tip.
fn insert() -> Tool {
    Tool {
        id: 3,
        edge: Edge::Trapezoid {
            tip: 1.0 / 3.0,
            left_angle: 30f64.to_radians(),
            right_angle: 30f64.to_radians(),
        },
        reference: Reference::Tip,
        body: None,
        length: None,
        depth_per_pass: DepthLimits::default(),
    }
}

fn pass(x: f64, z_end: f64) -> Pass {
    Pass {
        tool: 0,
        x_start: x,
        x_end: x,
        z_start: 5.0,
        z_end,
        lead: 2.0,
        lead_change: 0.0,
        start_angle: 0.0,
        spindle: Spindle::Cw,
    }
}

/// A needle of a tool (no nose, both edges radial: its cut is its path exactly) driven
/// along `path` (z, x) points: the contour turned as drawn, without a tool's own shape.
fn turned(path: &[(f64, f64)]) -> Turned {
    let t = TurningTool::turning(1, 0.0, (0.0, 0.0), false);
    Turned {
        cuts: path
            .windows(2)
            .map(|w| TurnCut {
                tool: t,
                path: TurnPath::of_move(&t, 1.0, w[0], w[1], None),
            })
            .collect(),
    }
}

/// Issue 28's second part: a chamfer d26 -> d30 over z 0..-2, d30 to the D36 shoulder at
/// z -42, D36 to -60.
fn shaft() -> PartProfile {
    PartProfile::from_diameters(&[
        [0.0, 26.0],
        [-2.0, 30.0],
        [-42.0, 30.0],
        [-42.0, 36.0],
        [-60.0, 36.0],
    ])
    .unwrap()
}

fn run(
    profile: &PartProfile,
    turned: &Turned,
    passes: &[Pass],
    compared: Option<(f64, f64)>,
) -> (Vec<PartGouge>, Vec<PartLeftover>) {
    let thread = m30();
    check(&Surface {
        profile,
        sense: 1.0,
        q_blank: 18.0,
        q_floor: 0.0,
        turned,
        thread: Some((&thread, compared)),
        passes,
        tools: &[insert()],
        dz: 0.01,
        z_span: (-1000.0, 1000.0),
        tolerance: 0.01,
    })
}

/// The shaft turned as drawn from the 36 bar: the chamfer, d30 to the shoulder, its face.
fn shaft_turned() -> Turned {
    turned(&[
        (1.0, 26.0),
        (0.0, 26.0),
        (-2.0, 30.0),
        (-42.0, 30.0),
        (-42.0, 37.0),
    ])
}

#[test]
fn a_thread_run_into_the_shoulder_gouges_it_by_the_root_depth() {
    // Passes to z -45 at X29, X28.2 and the root X27.546: each runs 3 mm into the D36
    // shoulder (from z -42), its tip 18 - x/2 under the shoulder's radius: 3.5, 3.9 and
    // 18 - 13.773 = 4.227 mm. The turning moves cut the contour exactly: no gouge, no
    // leftover.
    let passes = [pass(29.0, -45.0), pass(28.2, -45.0), pass(27.546, -45.0)];
    let (g, l) = run(&shaft(), &shaft_turned(), &passes, Some((-38.0, 0.0)));
    assert!(l.is_empty(), "{l:?}");
    assert_eq!(g.len(), 3, "{g:?}");
    for (g, x) in g.iter().zip([29.0, 28.2, 27.546]) {
        assert!((g.depth - (18.0 - x / 2.0)).abs() < 1e-9, "{g:?}");
        assert!(g.z < -42.0 && g.z >= -45.0 - 1.0 / 6.0, "{g:?}");
        assert_eq!(g.floor, 18.0);
    }
    assert_eq!(g[2].by, Cutter::Pass(2));
}

#[test]
fn a_thread_ending_short_of_the_shoulder_still_digs_in_with_its_flank() {
    // Ending at z -41.5 at X27.546 (r 13.773), the insert's -z flank beyond its tip flat
    // (1/6 each side) stands (u - 1/6) cot 30 above the tip at u from the tip's centre: at
    // the shoulder's face (u = 0.5) 13.773 + (1/3) cot 30 = 14.350, 3.650 under the
    // face's 18 (deeper in the shoulder it rises: the face is the worst). Ending at -40.5:
    // 13.773 + (1.5 - 1/6) cot 30 = 16.082, 1.918 deep. Ending at -38.5: 19.546, over the
    // shoulder, no gouge (its run-out in the thread's section, to the root, is the
    // thread's).
    let cot = 1.0 / 30f64.to_radians().tan();
    let face = |end: f64| 27.546 / 2.0 + ((end + 42.0).abs() - 1.0 / 6.0) * cot;
    assert!((face(-41.5) - 14.350350).abs() < 1e-6);
    for (end, want) in [
        (-41.5, Some(18.0 - face(-41.5))),
        (-40.5, Some(18.0 - face(-40.5))),
        (-38.5, None),
    ] {
        let (g, _) = run(
            &shaft(),
            &shaft_turned(),
            &[pass(27.546, end)],
            Some((-38.0, 0.0)),
        );
        match want {
            Some(d) => {
                assert_eq!(g.len(), 1, "{end}: {g:?}");
                assert!((g[0].depth - d).abs() < 1e-6, "{end}: {g:?} vs {d}");
                assert!((g[0].z + 42.0).abs() < 1e-6, "{g:?}");
            }
            None => assert!(g.is_empty(), "{end}: {g:?}"),
        }
    }
}

#[test]
fn a_relief_groove_takes_the_run_out_and_an_oversize_diameter_is_leftover() {
    // A relief groove d26.5 over z -38..-40, then the D36 face. A thread at the root
    // (r 13.773) ending at z -38.8 runs out in the groove (its tip over the groove's
    // bottom 13.25), but 1.2 mm before the face its -z flank stands only
    // 13.773 + (1.2 - 1/6) cot 30 = 15.563 high there, under the face's 18: the groove is
    // too narrow for that run-out, a gouge of 2.437. Ending at -37.0, 3 mm before the face,
    // the flank stands at 13.773 + (3 - 1/6) cot 30 = 18.681 there: clear.
    let profile = PartProfile::from_diameters(&[
        [0.0, 30.0],
        [-38.0, 30.0],
        [-38.0, 26.5],
        [-40.0, 26.5],
        [-40.0, 36.0],
        [-60.0, 36.0],
    ])
    .unwrap();
    let t = turned(&[
        (1.0, 30.0),
        (-38.0, 30.0),
        (-38.0, 26.5),
        (-40.0, 26.5),
        (-40.0, 37.0),
    ]);
    let (g, l) = run(&profile, &t, &[pass(27.546, -38.8)], Some((-36.0, 0.0)));
    let cot = 1.0 / 30f64.to_radians().tan();
    let at_face = 27.546 / 2.0 + (1.2 - 1.0 / 6.0) * cot;
    assert_eq!(g.len(), 1, "{g:?}");
    assert!((g[0].depth - (18.0 - at_face)).abs() < 1e-6, "{g:?}");
    assert!((g[0].z + 40.0).abs() < 1e-6, "{g:?}");
    assert!(l.is_empty(), "{l:?}");
    assert!(ROOT + (3.0 - 1.0 / 6.0) * cot > 18.0);
    let (g, _) = run(&profile, &t, &[pass(27.546, -37.0)], Some((-36.0, 0.0)));
    assert!(g.is_empty(), "{g:?}");

    // Turned to X30.5 instead of X30: 0.25 mm leftover along the whole turned stretch of
    // the section (outside the compared span), and nowhere the program did not turn.
    let t = turned(&[
        (1.0, 30.5),
        (-38.0, 30.5),
        (-38.0, 26.5),
        (-40.0, 26.5),
        (-40.0, 37.0),
    ]);
    let (_, l) = run(&profile, &t, &[], Some((-36.0, 0.0)));
    assert!(!l.is_empty());
    for r in &l {
        assert!((r.height - 0.25).abs() < 1e-9, "{r:?}");
        assert!(r.span.1 <= -36.0 || r.span.0 >= 0.0, "{r:?}");
    }
}

#[test]
fn a_chamfer_never_turned_is_leftover_by_its_depth() {
    // The shaft turned straight to X30 from the face: the chamfer (r 13 at the face to 15
    // at z -2) is left standing 15 - r(z), 2 mm at the face.
    let t = turned(&[(1.0, 30.0), (-42.0, 30.0), (-42.0, 37.0)]);
    let (g, l) = run(&shaft(), &t, &[], Some((-38.0, -1.0)));
    assert!(g.is_empty(), "{g:?}");
    assert_eq!(l.len(), 1, "{l:?}");
    assert!(
        (l[0].height - 2.0).abs() < 1e-6 && l[0].z.abs() < 1e-6,
        "{l:?}"
    );
    assert!((l[0].span.0 + 1.0).abs() < 0.011, "{l:?}");
}
