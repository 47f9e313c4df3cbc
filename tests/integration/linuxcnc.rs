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

/// Programs whose every synchronised feed is one vpcut thread move, with the pass count.
const PLAIN: [(&str, usize); 11] = [
    ("g33-g7", 2),
    ("g76-g7-external-r2-q29.5-h1", 16),
    ("g76-g8-external-r1", 9),
    ("g76-g7-internal-r1.5-q30-h2", 25),
    // O-words: a while loop calling o<pass> with depths 300, 566, 693, 800, 894, 980,
    // 1058, 1131, 1200, 1265, 1327, 1386, 1442, 1497, 1534 (hand: 400 sqrt(n), rounded,
    // the first pass 300, the last clamped to 1534) and 2 spring passes from a repeat.
    ("oword-g33-loop", 15 + 2),
    // o200 called for n = 1, 3, 5 (continue skips even n, break at 6): G76 K800 H0,
    // K1200 H1, K1600 H1 with J250 R1.5 gives 5+1, 10+1+1, 16+1+1 passes (hand:
    // 250 n^(2/3) < K), then 2 passes of the external o<spring_pass> (spring_pass.ngc).
    ("oword-sub-g76", 6 + 12 + 18 + 2),
    // 150 random expressions (all operators and functions, numbered and named parameters),
    // each value the X of a G33 pass: vpcut's evaluator against rs274's.
    ("oword-expressions", 150),
    // Random programs of nested if/elseif/else, while, do, repeat, break, continue and sub
    // calls with return values (a seeded generator); each G33 pass's X records the state.
    ("oword-random-flow-21", 54),
    ("oword-random-flow-23", 25),
    ("oword-random-flow-72", 24),
    ("oword-random-flow-44", 21),
];

/// Reads the subroutine files beside the programs (rs274 finds them in its working folder).
fn beside(name: &str) -> Option<Source> {
    let path = root().join("tests/data/linuxcnc").join(name);
    std::fs::read_to_string(path).ok().map(|text| Source {
        name: name.to_string(),
        text,
    })
}

#[test]
fn g33_and_g76_match_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc");
    for (name, passes) in PLAIN {
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
        let moves = interpret(&src, Dialect::Linuxcnc, &beside, Limits::default())
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
        assert_eq!(want.len(), passes, "{name}: rs274's pass count");
        assert_eq!(got.len(), want.len(), "{name}: pass count");
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            for c in 0..5 {
                assert!(
                    (g[c] - w[c]).abs() < 1e-6,
                    "{name} pass {k} field {c}: {g:?} vs LinuxCNC {w:?}"
                );
            }
        }
    }
}

/// G76 with tapers: L3 (entry and exit, E2), L1 (entry only, E2) and L2 (exit only, E1.5,
/// internal, G8). Per pass rs274 feeds, synchronised: with an entry taper a radial move in
/// the air and the taper, then the pass, then with an exit taper the taper out, fed per path
/// length. vpcut keeps the cutting segments with the axial lead P and the spindle phase at
/// which each starts; both are computed here from rs274's geometry alone.
#[test]
fn g76_tapers_match_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc");
    // (file, rs274 synchronised feeds, vpcut thread moves): 16 passes x (radial, entry,
    // pass, exit) for L3; 16 x (radial, entry, pass) for L1; 17 x (pass, exit) for L2
    // (hand: 150 n^(2/3) < 900 for n <= 14, then K once and H2).
    for (name, n_feeds, n_moves) in [
        ("g76-g7-external-taper-e2-l3", 64, 48),
        ("g76-g7-external-taper-e2-l1", 48, 32),
        ("g76-g8-internal-taper-e1.5-l2", 34, 34),
    ] {
        let ngc = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
        let src = Source {
            name: "t.ngc".into(),
            text: ngc,
        };
        let moves = interpret(&src, Dialect::Linuxcnc, &|_| None, Limits::default()).unwrap();
        let got: Vec<&vpcut::Move> = moves
            .iter()
            .filter(|m| m.kind == MoveKind::Thread)
            .collect();
        let feeds = canon_threads(&canon);
        assert_eq!(feeds.len(), n_feeds, "{name}");
        assert_eq!(got.len(), n_moves, "{name}");
        let mut g = got.iter();
        let mut revs = 0.0;
        let mut last_end = [f64::NAN; 2];
        for f in &feeds {
            let [xa, za, xb, zb, p] = *f;
            if (xa - last_end[0]).abs() > 1e-9 || (za - last_end[1]).abs() > 1e-9 {
                // A pass's synchronised sequence starts here (after a rapid).
                revs = 0.0;
            }
            last_end = [xb, zb];
            let path = (xb - xa).hypot(zb - za);
            if (zb - za).abs() < 1e-9 {
                // The radial move in the air before an entry taper.
                revs += path / p;
                continue;
            }
            let m = g.next().unwrap();
            for (a, b) in [
                (m.x_start / 2000.0, xa),
                (m.z_start / 1000.0, za),
                (m.x_dia / 2000.0, xb),
                (m.z / 1000.0, zb),
            ] {
                assert!((a - b).abs() < 1e-6, "{name}: {m:?} vs {f:?}");
            }
            let axial = p * (zb - za).abs() / path;
            assert!(
                (m.lead.unwrap() / 1000.0 - axial).abs() < 1e-6,
                "{name}: lead {:?} vs {axial}",
                m.lead
            );
            let phase = (revs * 360.0f64).rem_euclid(360.0);
            assert!(
                (m.sync_angle_deg.unwrap() - phase).abs() < 1e-3,
                "{name}: phase {:?} vs {phase}",
                m.sync_angle_deg
            );
            revs += path / p;
        }
    }
}

/// Every move rs274 makes (rapids, synchronised radial moves, threads), each from where the
/// one before ended: vpcut lists the same moves for G33 and G76 (issue 17: the cycles'
/// rapids, the radial move of an entry taper, and where G76 leaves the tool). rs274's
/// zero-length traverses are left out, as vpcut leaves them out.
#[test]
fn every_move_of_g33_and_g76_matches_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc");
    let names = [
        "g33-g7",
        "g76-g7-external-r2-q29.5-h1",
        "g76-g8-external-r1",
        "g76-g7-internal-r1.5-q30-h2",
        "g76-g7-external-taper-e2-l3",
        "g76-g7-external-taper-e2-l1",
        "g76-g8-internal-taper-e1.5-l2",
        "oword-sub-g76",
        // G91: the G76 Z counts from the current Z (rs274).
        "g76-g91-incremental",
    ];
    for name in names {
        let ngc = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
        let mut want: Vec<[f64; 4]> = Vec::new();
        let (mut x, mut z) = (0.0, 0.0);
        for line in canon.lines() {
            if !(line.contains("STRAIGHT_TRAVERSE(") || line.contains("STRAIGHT_FEED(")) {
                continue;
            }
            let inner = &line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()];
            let v: Vec<f64> = inner
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect();
            if (v[0], v[2]) != (x, z) {
                want.push([x / 1000.0, z / 1000.0, v[0] / 1000.0, v[2] / 1000.0]);
            }
            (x, z) = (v[0], v[2]);
        }
        let src = Source {
            name: format!("{name}.ngc"),
            text: ngc,
        };
        let moves = interpret(&src, Dialect::Linuxcnc, &beside, Limits::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let got: Vec<[f64; 4]> = moves
            .iter()
            .map(|m| {
                [
                    m.x_start / 2000.0,
                    m.z_start / 1000.0,
                    m.x_dia / 2000.0,
                    m.z / 1000.0,
                ]
            })
            .collect();
        assert_eq!(got.len(), want.len(), "{name}: move count");
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            for c in 0..4 {
                assert!(
                    (g[c] - w[c]).abs() < 1e-6,
                    "{name} move {k}: {g:?} vs LinuxCNC {w:?}"
                );
            }
        }
    }
}

/// One motion of rs274's canon output, in mm: traverse or feed, start and end (X a radius),
/// and for a synchronised feed the distance per revolution along the path.
#[derive(Debug)]
pub(crate) struct CanonMove {
    pub(crate) rapid: bool,
    pub(crate) from: [f64; 2],
    pub(crate) to: [f64; 2],
    /// An arc's centre (X a radius, z) and whether it turns clockwise (G2: rs274's
    /// rotation -1 in the XZ plane).
    pub(crate) arc: Option<([f64; 2], bool)>,
    path_lead: Option<f64>,
    /// Revolutions of the spindle since the synchronised motion began (the phase at the
    /// move's start): 0 after a traverse; continuous over back-to-back synchronised feeds.
    revs: f64,
    /// The spindle turns clockwise (M03) during the move: the last START_SPINDLE_*, the
    /// other way on a rigid tap's way back.
    cw: bool,
}

/// Every non-zero motion of a canon file. Lengths are divided by `scale` (the program's
/// scaling, see `random/gen.py`) and inches are converted to mm.
pub(crate) fn canon_moves(text: &str, scale: f64) -> Vec<CanonMove> {
    let mut out = Vec::new();
    let (mut x, mut z) = (0.0, 0.0);
    let mut mm = 1.0;
    let mut pitch: Option<f64> = None;
    let mut revs = 0.0;
    let mut cw = true;
    // rs274 prints points in the current frame: the work offset and G92 (radius, program
    // units) are added back so points are machine points, as vpcut's are.
    let (mut g5x, mut g92) = ([0.0; 2], [0.0; 2]);
    for line in text.lines() {
        let args = || -> Vec<f64> {
            let inner = &line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()];
            inner
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect()
        };
        if line.contains("SET_G5X_OFFSET(") {
            let v = args();
            g5x = [v[1], v[3]];
        } else if line.contains("SET_G92_OFFSET(") {
            let v = args();
            g92 = [v[0], v[2]];
        } else if line.contains("ARC_FEED(") {
            // In the XZ plane: first end Z, second end X, then the centre's Z and X, and
            // the rotation (-1 for G2).
            let v = args();
            let xb = (v[1] + g5x[0] + g92[0]) * mm / scale;
            let zb = (v[0] + g5x[1] + g92[1]) * mm / scale;
            let xc = (v[3] + g5x[0] + g92[0]) * mm / scale;
            let zc = (v[2] + g5x[1] + g92[1]) * mm / scale;
            out.push(CanonMove {
                rapid: false,
                from: [x, z],
                to: [xb, zb],
                arc: Some(([xc, zc], v[4] < 0.0)),
                path_lead: None,
                revs: 0.0,
                cw,
            });
            (x, z) = (xb, zb);
        } else if line.contains("START_SPINDLE_CLOCKWISE(") {
            cw = true;
        } else if line.contains("START_SPINDLE_COUNTERCLOCKWISE(") {
            cw = false;
        } else if line.contains("RIGID_TAP(") {
            // LinuxCNC manual, G33.1: from the current point, at an index pulse, a move
            // synchronised at the pitch to the end point; the spindle reverses and the tap
            // comes back along the same line, still synchronised, to the start; the spindle
            // is restored and a last unsynchronised move places the tool at the start
            // (rs274's next position). The spindle's overtravel is machine dynamics (left
            // out). The way back starts at the phase the way in ended at.
            let v = args();
            let xb = (v[0] + g5x[0] + g92[0]) * mm / scale;
            let zb = (v[2] + g5x[1] + g92[1]) * mm / scale;
            let p = pitch.expect("RIGID_TAP inside START_SPEED_FEED_SYNC");
            let path = (xb - x).hypot(zb - z);
            if path > 0.0 {
                out.push(CanonMove {
                    rapid: false,
                    from: [x, z],
                    to: [xb, zb],
                    arc: None,
                    path_lead: Some(p),
                    revs: 0.0,
                    cw,
                });
                out.push(CanonMove {
                    rapid: false,
                    from: [xb, zb],
                    to: [x, z],
                    arc: None,
                    path_lead: Some(p),
                    revs: path / p,
                    cw: !cw,
                });
            }
            revs = 0.0;
        } else if line.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)") {
            mm = 25.4;
        } else if line.contains("USE_LENGTH_UNITS(CANON_UNITS_MM)") {
            mm = 1.0;
        } else if line.contains("START_SPEED_FEED_SYNC(") {
            pitch = Some(args()[0] * mm / scale);
        } else if line.contains("STOP_SPEED_FEED_SYNCH") {
            pitch = None;
        } else if line.contains("STRAIGHT_TRAVERSE(") || line.contains("STRAIGHT_FEED(") {
            let v = args();
            let xb = (v[0] + g5x[0] + g92[0]) * mm / scale;
            let zb = (v[2] + g5x[1] + g92[1]) * mm / scale;
            let rapid = line.contains("STRAIGHT_TRAVERSE(");
            if rapid {
                revs = 0.0;
            }
            // rs274 makes every move, even of no length, where vpcut leaves those out; a
            // move shorter than the print's resolution (1e-4 x the scale) is one of those.
            if (xb - x).hypot(zb - z) > 5e-7 * scale / 1000.0 * mm {
                let path_lead = if rapid { None } else { pitch };
                out.push(CanonMove {
                    rapid,
                    from: [x, z],
                    to: [xb, zb],
                    arc: None,
                    path_lead,
                    revs,
                    cw,
                });
                if let Some(p) = path_lead {
                    revs += (xb - x).hypot(zb - z) / p;
                }
            }
            (x, z) = (xb, zb);
        }
    }
    out
}

/// The reference programs of `dir` (`NAME.ngc` beside rs274's `NAME.canon`), sorted by
/// name: the program as a source, rs274's moves and the scale its lengths were written in
/// (x10000 for G20 programs, else x1000).
fn reference_programs(dir: &std::path::Path) -> Vec<(String, Source, Vec<CanonMove>, f64)> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            name.strip_suffix(".ngc").map(str::to_string)
        })
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let ngc = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
            let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
            let scale = if ngc.contains("G20") { 10000.0 } else { 1000.0 };
            let want = canon_moves(&canon, scale);
            let src = Source {
                name: format!("{name}.ngc"),
                text: ngc,
            };
            (name, src, want, scale)
        })
        .collect()
}

/// Whether a move's start and end (radii and z, unscaled) are rs274's to 1e-6.
fn ends_match(m: &vpcut::Move, w: &CanonMove, scale: f64) -> bool {
    let got = [
        m.x_start / 2.0 / scale,
        m.z_start / scale,
        m.x_dia / 2.0 / scale,
        m.z / scale,
    ];
    let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
    (0..4).all(|c| (got[c] - exp[c]).abs() <= 1e-6)
}

/// Issue 17's proof: seeded random programs (`tests/data/linuxcnc/random/gen.py`, seed 17):
/// 64 G76 cycles (taper modes L0..L3 in turn with E, Q, H, R, I/J/K, internal and external,
/// G7 and G8, G20 and G21, towards -Z and +Z) and 32 programs of straight and tapered G33
/// blocks and chains (absolute and G91). vpcut must make rs274's motions move for move:
/// rapids as rapids, feeds as feed or thread moves, every start and end to 1e-6 mm; every
/// synchronised move's leads (rs274 syncs the distance along the path: the z lead is that
/// times |dz| / path; vpcut's `lead` is the z lead) and the spindle phase at which it
/// starts (0 after a rapid; continued over back-to-back synchronised moves).
#[test]
fn random_g76_and_g33_match_linuxcnc_move_for_move() {
    let programs = reference_programs(&root().join("tests/data/linuxcnc/random"));
    let count = |p: &str| programs.iter().filter(|(n, ..)| n.starts_with(p)).count();
    assert!(
        count("g76-") >= 60 && count("g33-") >= 30,
        "random programs missing"
    );
    let mut failures = Vec::new();
    let (mut n_moves, mut n_threads) = (0, 0);
    for (name, src, want, scale) in &programs {
        let scale = *scale;
        let moves = match interpret(src, Dialect::Linuxcnc, &|_| None, Limits::default()) {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        if moves.len() != want.len() {
            failures.push(format!(
                "{name}: {} moves, rs274 {}",
                moves.len(),
                want.len()
            ));
            continue;
        }
        for (k, (m, w)) in moves.iter().zip(want).enumerate() {
            n_moves += 1;
            let mut bad = !ends_match(m, w, scale);
            bad |= (m.kind == MoveKind::Rapid) != w.rapid;
            if let Some(p) = w.path_lead {
                let path = (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1]);
                let dz = (w.to[1] - w.from[1]).abs();
                if dz > 0.0 {
                    n_threads += 1;
                    bad |= m.kind != MoveKind::Thread;
                    let z_lead = p * dz / path;
                    bad |= m.lead.is_none_or(|l| (l / scale - z_lead).abs() > 1e-6);
                    let phase = (w.revs * 360.0).rem_euclid(360.0);
                    bad |= m.sync_angle_deg.is_none_or(|a| {
                        let d = (a - phase).rem_euclid(360.0);
                        d.min(360.0 - d) > 1e-3
                    });
                } else {
                    // A synchronised radial move (G76's entry taper): no z, no thread.
                    bad |= m.kind != MoveKind::Feed;
                }
            } else {
                bad |= m.kind == MoveKind::Thread;
            }
            if bad {
                failures.push(format!("{name} move {k}: {m:?}\n   vs rs274 {w:?}"));
                break;
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} programs differ from rs274:\n{}",
        failures.len(),
        programs.len(),
        failures.join("\n")
    );
    assert!(n_moves > 3000 && n_threads > 1500, "{n_moves} {n_threads}");
}

/// Issue 17's corpus, LinuxCNC part: every `tests/data/nc/linuxcnc/corpus-*.nc` (whole shop
/// programs in the styles `CORPUS.md` there names) against rs274's canon kept in
/// `tests/data/linuxcnc/corpus/` (made with its `tool.tbl`: tools with zero offsets, as
/// vpcut's tools), move for move: rapids as rapids, feeds and arcs as feed, arc or thread
/// moves, every start and end to rs274's print resolution (4 decimals of the program's unit:
/// 5e-5 mm, 1.27e-3 mm in inch), every synchronised move a thread move with rs274's
/// distance per revolution along the path (6 decimals) and the z lead that makes. Moves of
/// no length are left out on both sides (rs274 prints every traverse, even after G92 made
/// it one of no length), and vpcut's moves shorter than two print steps where they match
/// none of rs274's (they print as no move).
#[test]
fn corpus_matches_linuxcnc_move_for_move() {
    let dir = root().join("tests/data/nc/linuxcnc");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            let stem = name.strip_suffix(".nc")?;
            stem.starts_with("corpus-").then(|| stem.to_string())
        })
        .collect();
    names.sort();
    assert!(names.len() >= 16, "{} corpus programs", names.len());
    let mut failures = Vec::new();
    for name in &names {
        let nc = std::fs::read_to_string(dir.join(format!("{name}.nc"))).unwrap();
        let canon_path = root().join(format!("tests/data/linuxcnc/corpus/{name}.canon"));
        let canon = std::fs::read_to_string(&canon_path).unwrap();
        let inch = canon.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)");
        let unit = if inch { 25.4 } else { 1.0 };
        let want = canon_moves(&canon, 1.0);
        let src = Source {
            name: format!("{name}.nc"),
            text: nc,
        };
        let moves = interpret(&src, Dialect::Linuxcnc, &|_| None, Limits::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let moves: Vec<&vpcut::Move> = moves
            .iter()
            .filter(|m| m.x_dia != m.x_start || m.z != m.z_start)
            .collect();
        let want: Vec<&CanonMove> = want
            .iter()
            .filter(|w| (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1]) > 0.6e-4 * unit)
            .collect();
        let tol = 0.51e-4 * unit;
        let same = |m: &vpcut::Move, w: &CanonMove| -> bool {
            let got = [m.x_start / 2.0, m.z_start, m.x_dia / 2.0, m.z];
            let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
            let mut bad = (0..4).any(|c| (got[c] - exp[c]).abs() > tol);
            bad |= (m.kind == MoveKind::Rapid) != w.rapid;
            match w.path_lead {
                // A synchronised radial move (G76's entry taper): a feed, no thread.
                Some(_) if (w.to[1] - w.from[1]).abs() < tol => bad |= m.kind != MoveKind::Feed,
                Some(p) => {
                    bad |= m.kind != MoveKind::Thread;
                    bad |= vpcut::path_lead(m).is_none_or(|l| (l - p).abs() > 0.51e-6 * unit);
                }
                None => bad |= m.kind == MoveKind::Thread,
            }
            !bad
        };
        // A move of vpcut's shorter than two print steps may print as none (a G7x cycle
        // makes such moves): it is passed over where it matches nothing.
        let tiny =
            |m: &vpcut::Move| ((m.x_dia - m.x_start) / 2.0).hypot(m.z - m.z_start) < 2e-4 * unit;
        let (mut i, mut j) = (0, 0);
        while i < moves.len() || j < want.len() {
            match (moves.get(i), want.get(j)) {
                (Some(m), Some(w)) if same(m, w) => (i, j) = (i + 1, j + 1),
                (Some(m), _) if tiny(m) => i += 1,
                (m, w) => {
                    failures.push(format!(
                        "{name} move {i}: {m:?}\n   vs rs274's move {j}: {w:?}"
                    ));
                    break;
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} corpus programs differ from rs274:\n{}",
        failures.len(),
        names.len(),
        failures.join("\n")
    );
}

/// Issue 17: LinuxCNC's rigid tapping `G33.1` against rs274 (`tests/data/linuxcnc/rigid-tap/`,
/// scaled as `random/`: x1000 in mm, x10000 in inch): 7 programs (pitches 0.8 to 2.5 mm and
/// 1/20 in, depths of whole and broken turns, G20/G21, G7/G8, M03 and M04, towards -Z and
/// +Z, a work offset, modal G33.1 repeated, G33 threads before and after, off the axis and
/// along a slope). Every motion move for move, each `RIGID_TAP` as its two synchronised
/// moves (see `canon_moves`): ends to 1e-6 mm, z lead K |dz| / path, the spindle direction
/// (reversed on the way back) and the spindle phase: 0 at the index pulse on the way in;
/// on the way back the spindle, turned `path / K` revolutions, counts its angle past the
/// index the other way: `-360 path / K` mod 360.
#[test]
fn rigid_tapping_matches_linuxcnc() {
    let programs = reference_programs(&root().join("tests/data/linuxcnc/rigid-tap"));
    assert!(programs.len() >= 7, "{} programs", programs.len());
    let mut n_taps = 0;
    for (name, src, want, scale) in &programs {
        let scale = *scale;
        let moves = interpret(src, Dialect::Linuxcnc, &|_| None, Limits::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(moves.len(), want.len(), "{name}: {moves:#?}\n{want:#?}");
        for (k, (m, w)) in moves.iter().zip(want).enumerate() {
            let at = format!("{name} move {k}: {m:?}\n   vs rs274 {w:?}");
            assert!(ends_match(m, w, scale), "{at}");
            assert_eq!(m.kind == MoveKind::Rapid, w.rapid, "{at}");
            match w.path_lead {
                Some(p) => {
                    let path = (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1]);
                    let dz = (w.to[1] - w.from[1]).abs();
                    assert_eq!(m.kind, MoveKind::Thread, "{at}");
                    let lead = m.lead.unwrap() / scale;
                    assert!((lead - p * dz / path).abs() < 1e-9, "{at}");
                    assert_eq!(m.spindle == vpcut::Spindle::Cw, w.cw, "{at}");
                    // No G33 here continues another synchronised move: a phase past 0 is a
                    // tap's way back, counted the other way.
                    let phase = (-w.revs * 360.0).rem_euclid(360.0);
                    let d = (m.sync_angle_deg.unwrap() - phase).rem_euclid(360.0);
                    assert!(d.min(360.0 - d) < 1e-6, "{at}");
                    if w.revs > 0.0 {
                        n_taps += 1;
                    }
                }
                None => assert_ne!(m.kind, MoveKind::Thread, "{at}"),
            }
        }
    }
    assert_eq!(n_taps, 9);
}

/// Issue 27: `return`/`endsub` inside nested `if`/`while`/`do`/`repeat` blocks, against
/// rs274 (`tests/data/linuxcnc/flow/`: hand-written cases and 24 seeded random programs of
/// `gen.py`, references by `regen.sh`). Where rs274 runs a program, every move is its move
/// (kind, start and end to its 4 printed decimals); where it stops (`NAME.err`), vpcut
/// refuses it too, with rs274's words (the text before the quote: "duplicate O-word
/// label", "undefined O-word label", "not in a subroutine definition") at rs274's line or
/// naming it.
#[test]
fn return_inside_blocks_matches_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc/flow");
    let programs = reference_programs(&dir);
    assert!(programs.len() >= 30, "{} programs", programs.len());
    let (mut n_errors, mut n_moves) = (0, 0);
    let mut failures = Vec::new();
    for (name, src, _, _) in &programs {
        let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
        let want = canon_moves(&canon, 1.0);
        let loader = |file: &str| -> Option<Source> {
            let text = std::fs::read_to_string(dir.join(file)).ok()?;
            Some(Source {
                name: file.to_string(),
                text,
            })
        };
        let got = interpret(src, Dialect::Linuxcnc, &loader, Limits::default());
        if let Ok(err) = std::fs::read_to_string(dir.join(format!("{name}.err"))) {
            n_errors += 1;
            let first = err.lines().next().unwrap();
            let (line, text) = first.split_once(": ").unwrap();
            let line: usize = line.parse().unwrap();
            let words = text.split([':', '-']).next().unwrap().trim();
            match got {
                Ok(_) => failures.push(format!("{name}: runs, rs274 stops: {first}")),
                Err(e) => {
                    let at = e.line == line || e.message.contains(&format!("line {line}"));
                    if !at || !e.message.contains(words) {
                        failures.push(format!("{name}: {e}\n   vs rs274 {first}"));
                    }
                }
            }
            continue;
        }
        let moves = match got {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let moves: Vec<&vpcut::Move> = moves
            .iter()
            .filter(|m| m.x_dia != m.x_start || m.z != m.z_start)
            .collect();
        let want: Vec<&CanonMove> = want
            .iter()
            .filter(|w| (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1]) > 0.6e-4)
            .collect();
        if moves.len() != want.len() {
            failures.push(format!(
                "{name}: {} moves, rs274 {}",
                moves.len(),
                want.len()
            ));
            continue;
        }
        for (k, (m, w)) in moves.iter().zip(&want).enumerate() {
            n_moves += 1;
            let got = [m.x_start / 2.0, m.z_start, m.x_dia / 2.0, m.z];
            let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
            let bad = (0..4).any(|c| (got[c] - exp[c]).abs() > 0.51e-4)
                || (m.kind == MoveKind::Rapid) != w.rapid;
            if bad {
                failures.push(format!("{name} move {k}: {m:?}\n   vs rs274 {w:?}"));
                break;
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} programs differ from rs274:\n{}",
        failures.len(),
        programs.len(),
        failures.join("\n")
    );
    assert!(n_errors >= 6 && n_moves > 500, "{n_errors} {n_moves}");
}

/// Issue 27: `o<name> call` files found through the INI's SUBROUTINE_PATH, against rs274
/// run with that INI (`tests/data/linuxcnc/subpath/`: `rs274 -i rs274.ini -g main.ngc
/// main.canon`). The folders are read from the same `rs274.ini`; the program's own folder
/// comes first (`beside.ngc` over `lib1/beside.ngc`), then the folders in order (`lib1`'s
/// spring pass over `lib2`'s). Every move is rs274's; without the path the call is an
/// error that names the file it looked for.
#[test]
fn subroutine_path_matches_linuxcnc() {
    let dir = root().join("tests/data/linuxcnc/subpath");
    let ini = std::fs::read_to_string(dir.join("rs274.ini")).unwrap();
    let path: Vec<String> = ini
        .lines()
        .find_map(|l| l.trim().strip_prefix("SUBROUTINE_PATH"))
        .unwrap()
        .trim_start_matches([' ', '='])
        .split(':')
        .map(|s| s.trim().to_string())
        .collect();
    assert_eq!(path.len(), 3);
    let canon = std::fs::read_to_string(dir.join("main.canon")).unwrap();
    let want = canon_moves(&canon, 1.0);
    let src = Source {
        name: "main.ngc".into(),
        text: std::fs::read_to_string(dir.join("main.ngc")).unwrap(),
    };
    let loader = |file: &str| -> Option<Source> {
        let text = std::fs::read_to_string(dir.join(file)).ok()?;
        Some(Source {
            name: file.to_string(),
            text,
        })
    };
    let mut opts = vpcut::NcOptions::default();
    opts.settings.subroutine_path = path;
    let moves = vpcut::interpret_with(&src, Dialect::Linuxcnc, &loader, &opts)
        .unwrap_or_else(|e| panic!("{e}"))
        .moves;
    let moves: Vec<&vpcut::Move> = moves
        .iter()
        .filter(|m| m.x_dia != m.x_start || m.z != m.z_start)
        .collect();
    let want: Vec<&CanonMove> = want
        .iter()
        .filter(|w| (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1]) > 0.6e-4)
        .collect();
    assert_eq!(moves.len(), want.len());
    assert!(want.len() >= 18 && want.iter().filter(|w| w.path_lead.is_some()).count() == 4);
    for (k, (m, w)) in moves.iter().zip(&want).enumerate() {
        let got = [m.x_start / 2.0, m.z_start, m.x_dia / 2.0, m.z];
        let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
        assert!(
            (0..4).all(|c| (got[c] - exp[c]).abs() <= 0.51e-4),
            "move {k}: {m:?} vs rs274 {w:?}"
        );
        assert_eq!(m.kind == MoveKind::Rapid, w.rapid, "move {k}");
        assert_eq!(
            m.kind == MoveKind::Thread,
            w.path_lead.is_some(),
            "move {k}"
        );
    }
    let e = interpret(&src, Dialect::Linuxcnc, &loader, Limits::default()).unwrap_err();
    assert!(
        e.message.contains("o<pass> not found") && e.message.contains("pass.ngc"),
        "{e}"
    );
    assert_eq!(e.line, 8, "{e}");
}

/// `[program] subroutine_path` in a job: the folders reach the interpreter; a non-LinuxCNC
/// dialect or an empty entry is an error naming the key.
#[test]
fn job_subroutine_path_key() {
    let job = |dialect: &str, path: &str| {
        format!(
            "[blank]\ndiameter = 24.0\nlength = 40.0\nz_front = 0.0\n\n[thread]\nside = \"external\"\nform = \"iso-metric\"\nmajor_diameter = 24.0\npitch = 1.5\nturns = 10\nz_start = 0.0\n\n[[tool]]\nid = 1\nkind = \"threading\"\nangle = 60.0\ntip_flat = 0.1875\nreference = \"tip\"\n\n[program]\nfile = \"main.ngc\"\ndialect = \"{dialect}\"\nsubroutine_path = {path}\n"
        )
    };
    let main = "G18 G21 G7 G95\nG0 X26 Z5 S300 M3\no<pass> call [22.2]\nM2\n";
    let pass = "o<pass> sub\nG0 X#1 Z5\nG33 Z-15 K1.5\nG0 X26\nG0 Z5\no<pass> endsub\n";
    let load = |f: &str| match f {
        "main.ngc" => Some(main.to_string()),
        "macros/pass.ngc" => Some(pass.to_string()),
        _ => None,
    };
    let ok = vpcut::Job::from_toml_with(&job("linuxcnc", "[\"macros\"]"), "job.toml", &load);
    let ok = ok.unwrap_or_else(|e| panic!("{e}"));
    drop(ok);
    for (dialect, path, says) in [
        ("fanuc", "[\"macros\"]", "a LinuxCNC setting"),
        ("linuxcnc", "[\"\"]", "entry 1 is empty"),
        ("linuxcnc", "[]", "o<pass> not found"),
    ] {
        let err = vpcut::Job::from_toml_with(&job(dialect, path), "job.toml", &load)
            .err()
            .unwrap_or_else(|| panic!("{dialect} {path}: no error"))
            .to_string();
        assert!(err.contains(says), "{dialect} {path}: {err}");
    }
}

/// The G and M codes, with their numbers, that a LinuxCNC line runs (comments, named
/// parameters and O-word lines left out), and whether it has an `L2`/`L20` word (G10).
fn codes_of(line: &str) -> Vec<String> {
    let mut text = String::new();
    let mut depth = 0;
    for ch in line.chars() {
        match ch {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            _ if depth == 0 => text.push(ch.to_ascii_uppercase()),
            _ => {}
        }
    }
    let t: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if t.starts_with('O') {
        return Vec::new();
    }
    let b = t.as_bytes();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < b.len() {
        if b[i] == b'#' && b.get(i + 1) == Some(&b'<') {
            i = t[i..].find('>').map_or(b.len(), |k| i + k + 1);
            continue;
        }
        let letter = b[i];
        let after_word = i == 0 || !b[i - 1].is_ascii_alphabetic();
        let mut j = i + 1;
        while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
            j += 1;
        }
        if matches!(letter, b'G' | b'M' | b'L') && after_word && j > i + 1 {
            if let Ok(v) = t[i + 1..j].parse::<f64>() {
                out.push(format!("{}{}", letter as char, v));
            }
        }
        i = j.max(i + 1);
    }
    let l = out.iter().find(|c| c.starts_with('L')).cloned();
    let mut codes: Vec<String> = out.into_iter().filter(|c| !c.starts_with('L')).collect();
    if let (Some(l), true) = (l, codes.iter().any(|c| c == "G10")) {
        codes.push(format!("G10 {l}"));
    }
    codes
}

/// Issue 27: `docs/coverage/linuxcnc.md` lists every G and M code of the LinuxCNC
/// reference; every code it calls "simulated" is run by some program of
/// `tests/data/nc/linuxcnc` (whose moves the corpus and data tests compare), and every
/// O-word construct it calls "simulated" stands in one.
#[test]
fn coverage_table_is_exercised() {
    let table = std::fs::read_to_string(root().join("docs/coverage/linuxcnc.md")).unwrap();
    let dir = root().join("tests/data/nc/linuxcnc");
    let mut used = std::collections::BTreeSet::new();
    let mut owords = std::collections::BTreeSet::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "nc") {
            for line in std::fs::read_to_string(&path).unwrap().lines() {
                used.extend(codes_of(line));
                let t = line.trim().to_ascii_lowercase();
                if t.starts_with('o') {
                    owords.extend(t.split_whitespace().nth(1).map(str::to_string));
                }
            }
        }
    }
    assert!(codes_of("G0 X#<g1> (G2) M3 ; G4").eq(&["G0", "M3"]));
    assert!(codes_of("G10 L20 P2 X1").eq(&["G10", "G10 L20"]));
    let (mut simulated, mut rows, mut missing) = (0, 0, Vec::new());
    for line in table.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 5
            || cells[1] == "code"
            || cells[1] == "construct"
            || cells[1].starts_with("---")
        {
            continue;
        }
        rows += 1;
        let (code, status) = (cells[1], cells[2]);
        assert!(
            ["simulated", "accepted", "warning", "refused"].contains(&status),
            "{line}"
        );
        if status != "simulated" {
            continue;
        }
        simulated += 1;
        let is_code = code.starts_with('G') || code.starts_with('M');
        let found = if is_code {
            let norm = match code.split_once(' ') {
                Some((g, l)) => format!("{} {}", g, l),
                None => {
                    let v: f64 = code[1..].parse().unwrap();
                    format!("{}{}", &code[..1], v)
                }
            };
            used.contains(&norm)
        } else {
            match code {
                "sub" | "endsub" | "call" | "return" | "while" | "do" | "if" | "repeat"
                | "break" | "continue" => owords.contains(code),
                // Checked by the programs' own tests (parameters, expressions, comments,
                // external files: `oword-*`, `subpath/`).
                _ => true,
            }
        };
        if !found {
            missing.push(code.to_string());
        }
    }
    assert!(
        rows > 140 && simulated > 55,
        "{rows} rows, {simulated} simulated"
    );
    assert!(
        missing.is_empty(),
        "simulated in docs/coverage/linuxcnc.md but run by no program of tests/data/nc/linuxcnc: {missing:?}"
    );
}
