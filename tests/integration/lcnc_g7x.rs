//! Issue 27: LinuxCNC's lathe cycles G70, G71/G71.1/G71.2 and G72/G72.1/G72.2 against
//! rs274's own output (`tests/data/linuxcnc/g7x/`: seeded random contours of `gen.py`,
//! hand-written cases and every error rs274 gives on a cycle's block or contour; references
//! by `regen.sh`).

use crate::linuxcnc::{canon_moves, CanonMove};
use crate::support::root;
use vpcut::{interpret, Dialect, Limits, MoveKind, Source};

/// Whether vpcut's move `m` is rs274's `w` to `tol` (mm): kind, ends, an arc's centre and
/// sense.
fn same(m: &vpcut::Move, w: &CanonMove, tol: f64) -> bool {
    let got = [m.x_start / 2.0, m.z_start, m.x_dia / 2.0, m.z];
    let exp = [w.from[0], w.from[1], w.to[0], w.to[1]];
    if (0..4).any(|c| (got[c] - exp[c]).abs() > tol) {
        return false;
    }
    match (m.kind, &w.arc) {
        (MoveKind::Rapid, None) => w.rapid,
        (MoveKind::Feed, None) => !w.rapid,
        (MoveKind::Arc, Some((c, cw))) => m.arc.is_some_and(|a| {
            (a.x_centre_dia / 2.0 - c[0]).abs() <= tol
                && (a.z_centre - c[1]).abs() <= tol
                && a.clockwise == *cw
        }),
        _ => false,
    }
}

/// Every program of the folder: where rs274 runs it, vpcut makes its moves, move for move
/// (rapids as rapids, feeds as feeds, arcs as arcs about rs274's centre in rs274's sense,
/// every start and end and centre to rs274's print resolution: 4 decimals of the program's
/// unit, 0.51e-4 mm or 0.51e-4 in; moves that print as no move are left out on both
/// sides, as are vpcut's moves shorter than two print steps that rs274 prints as none).
/// Where rs274 stops (`NAME.err`: its message, then the line it stopped at), vpcut refuses
/// the program with rs274's message at that line (or, for a contour subroutine that is
/// not there, at the cycle's line that rs274's message names, or naming the line rs274
/// made up); where rs274 crashes or never ends, vpcut says so.
#[test]
fn g70_g71_g72_match_linuxcnc_move_for_move() {
    let dir = root().join("tests/data/linuxcnc/g7x");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            name.strip_suffix(".ngc").map(str::to_string)
        })
        .collect();
    names.sort();
    let loader = |file: &str| -> Option<Source> {
        let text = std::fs::read_to_string(dir.join(file)).ok()?;
        Some(Source {
            name: file.to_string(),
            text,
        })
    };
    let mut failures = Vec::new();
    let (mut n_run, mut n_err, mut n_moves, mut n_arcs) = (0, 0, 0, 0);
    let mut codes_run = std::collections::BTreeSet::new();
    for name in &names {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let src = Source {
            name: format!("{name}.ngc"),
            text: text.clone(),
        };
        let got = interpret(&src, Dialect::Linuxcnc, &loader, Limits::default());
        if let Ok(err) = std::fs::read_to_string(dir.join(format!("{name}.err"))) {
            n_err += 1;
            let mut lines = err.lines();
            let message = lines.next().unwrap();
            let at = lines.next().unwrap_or("").trim();
            let e = match got {
                Ok(_) => {
                    failures.push(format!("{name}: runs, rs274 stops: {message}"));
                    continue;
                }
                Err(e) => e,
            };
            let says = if message.starts_with("rs274 crashed") {
                "reads past its segment list"
            } else if message.starts_with("rs274 loops for ever") {
                "loops for ever"
            } else {
                message
            };
            let there = e.snippet.trim().eq_ignore_ascii_case(at)
                || message.ends_with(&format!("from line: {}", e.line))
                || e.message.contains(at)
                || at.is_empty();
            if !e.message.contains(says) || !there {
                failures.push(format!("{name}: {e}\n   vs rs274: {message} at `{at}`"));
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
        n_run += 1;
        for code in ["G70", "G71.1", "G71.2", "G72.1", "G72.2", "G71 ", "G72 "] {
            if text.contains(code) {
                codes_run.insert(code.trim());
            }
        }
        let canon = std::fs::read_to_string(dir.join(format!("{name}.canon"))).unwrap();
        let unit = if canon.contains("USE_LENGTH_UNITS(CANON_UNITS_INCHES)") {
            25.4
        } else {
            1.0
        };
        let (tol, tiny) = (0.51e-4 * unit, 2e-4 * unit);
        let want: Vec<CanonMove> = canon_moves(&canon, 1.0)
            .into_iter()
            .filter(|w| w.from != w.to)
            .collect();
        let len = |m: &vpcut::Move| ((m.x_dia - m.x_start) / 2.0).hypot(m.z - m.z_start);
        let (mut i, mut j) = (0, 0);
        let mut bad = None;
        while i < moves.len() || j < want.len() {
            match (moves.get(i), want.get(j)) {
                (Some(m), Some(w)) if same(m, w, tol) => {
                    n_moves += 1;
                    n_arcs += usize::from(m.kind == MoveKind::Arc);
                    i += 1;
                    j += 1;
                }
                (Some(m), _) if len(m) < tiny => i += 1,
                _ => {
                    bad = Some(format!(
                        "{name}: move {i} {:?}\n   vs rs274's move {j} {:?}",
                        moves.get(i),
                        want.get(j)
                    ));
                    break;
                }
            }
        }
        failures.extend(bad);
    }
    assert!(
        failures.is_empty(),
        "{} of {} programs differ from rs274:\n{}",
        failures.len(),
        names.len(),
        failures.join("\n")
    );
    // The set covers every cycle that runs, and errors of every kind.
    assert_eq!(
        codes_run.len(),
        7,
        "cycles run by the programs: {codes_run:?}"
    );
    assert!(
        n_run >= 70 && n_err >= 50 && n_moves > 4500 && n_arcs > 500,
        "{n_run} programs run, {n_err} errors, {n_moves} moves, {n_arcs} arcs"
    );
}
