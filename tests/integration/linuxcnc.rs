//! LinuxCNC conformance: G33 and G76 thread moves against LinuxCNC's own interpreter.
//!
//! `tests/data/linuxcnc/*.canon` are rs274's canonical calls for the `*.ngc` beside them
//! (see that folder's README: lengths are scaled by 1000 so rs274's 4 printed decimals give
//! 1e-7 mm). Every synchronised feed (`STRAIGHT_FEED` after `START_SPEED_FEED_SYNC`) must
//! equal one of vpcut's thread moves to 1e-6 mm, in order.

use crate::support::root;
use vpcut::{interpret, Dialect, Limits, MoveKind, Source};

/// (x_start radius, z_start, x_end radius, z_end, pitch) of every synchronised feed, in mm.
fn canon_threads(text: &str) -> Vec<[f64; 5]> {
    let nums = |line: &str| -> Vec<f64> {
        let inner = &line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()];
        inner
            .split(',')
            .map(|s| s.trim().parse().unwrap())
            .collect()
    };
    let mut out = Vec::new();
    let (mut x, mut z) = (0.0, 0.0);
    let mut pitch: Option<f64> = None;
    for line in text.lines() {
        if line.contains("START_SPEED_FEED_SYNC(") {
            pitch = Some(nums(line)[0]);
        } else if line.contains("STOP_SPEED_FEED_SYNCH") {
            pitch = None;
        } else if line.contains("STRAIGHT_TRAVERSE(") || line.contains("STRAIGHT_FEED(") {
            let v = nums(line);
            if let (Some(p), true) = (pitch, line.contains("STRAIGHT_FEED(")) {
                out.push([
                    x / 1000.0,
                    z / 1000.0,
                    v[0] / 1000.0,
                    v[2] / 1000.0,
                    p / 1000.0,
                ]);
            }
            (x, z) = (v[0], v[2]);
        }
    }
    out
}

#[test]
fn g33_and_g76_match_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc");
    let mut checked = 0;
    for name in [
        "g33-g7",
        "g76-g7-external-r2-q29.5-h1",
        "g76-g8-external-r1",
        "g76-g7-internal-r1.5-q30-h2",
    ] {
        let ngc = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
        let want = canon_threads(&canon);
        assert!(
            !want.is_empty(),
            "{name}: no synchronised feeds in the reference"
        );
        let src = Source {
            name: format!("{name}.ngc"),
            text: ngc,
        };
        let moves = interpret(&src, Dialect::Linuxcnc, &|_| None, Limits::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let got: Vec<[f64; 5]> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .map(|m| {
                [
                    m.x_start / 2000.0,
                    m.z_start / 1000.0,
                    m.x_dia / 2000.0,
                    m.z / 1000.0,
                    m.lead.unwrap() / 1000.0,
                ]
            })
            .collect();
        assert_eq!(got.len(), want.len(), "{name}: pass count");
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            for c in 0..5 {
                assert!(
                    (g[c] - w[c]).abs() < 1e-6,
                    "{name} pass {k} field {c}: {g:?} vs LinuxCNC {w:?}"
                );
            }
        }
        checked += got.len();
    }
    assert_eq!(checked, 2 + 16 + 9 + 25);
}

/// G76 with entry and exit tapers (E2 L3): per pass a synchronised radial move in the air,
/// the entry taper, the pass and the exit taper, fed per path length. vpcut keeps the three
/// cutting segments with the axial lead P and the spindle phase at which each starts; both
/// are computed here from rs274's geometry alone.
#[test]
fn g76_tapers_match_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc");
    let ngc = std::fs::read_to_string(dir.join("g76-g7-external-taper-e2-l3.ngc")).unwrap();
    let canon = std::fs::read_to_string(dir.join("g76-g7-external-taper-e2-l3.canon")).unwrap();
    let src = Source {
        name: "t.ngc".into(),
        text: ngc,
    };
    let moves = interpret(&src, Dialect::Linuxcnc, &|_| None, Limits::default()).unwrap();
    let got: Vec<&vpcut::Move> = moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect();
    // rs274: 16 passes x (radial + entry + straight + exit) synchronised feeds.
    let feeds = canon_threads(&canon);
    assert_eq!(feeds.len(), 64);
    assert_eq!(got.len(), 48);
    let mut g = got.iter();
    let mut revs = 0.0;
    for f in &feeds {
        let [xa, za, xb, zb, p] = *f;
        let path = (xb - xa).hypot(zb - za);
        if (zb - za).abs() < 1e-9 {
            // The radial move starts the synchronised sequence of a pass.
            revs = path / p;
            continue;
        }
        let m = g.next().unwrap();
        for (a, b) in [
            (m.x_start / 2000.0, xa),
            (m.z_start / 1000.0, za),
            (m.x_dia / 2000.0, xb),
            (m.z / 1000.0, zb),
        ] {
            assert!((a - b).abs() < 1e-6, "{m:?} vs {f:?}");
        }
        let axial = p * (zb - za).abs() / path;
        assert!(
            (m.lead.unwrap() / 1000.0 - axial).abs() < 1e-6,
            "lead {:?} vs {axial}",
            m.lead
        );
        let phase = (revs * 360.0f64).rem_euclid(360.0);
        assert!(
            (m.sync_angle_deg.unwrap() - phase).abs() < 1e-3,
            "phase {:?} vs {phase}",
            m.sync_angle_deg
        );
        revs += path / p;
    }
}
