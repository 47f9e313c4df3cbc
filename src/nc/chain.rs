//! Continuous threading and the GSK 980TDC thread run-out.
//!
//! **Thread chains.** On FANUC and GSK (GSK 980TDi manual §3.23: "If the current block is
//! for thread and the next block is the same, the system does not test the spindle encoder
//! signal ... continuous thread machining") and on LinuxCNC (its trajectory planner waits
//! for the index only when the spindle is not already synchronised) a thread block that
//! directly follows a thread block does not wait for the one-rev signal: the spindle phase
//! runs on. vpcut marks such a move `chained` and gives it, as sync angle, the spindle angle
//! at which the previous thread move ended (`angle + 360 x revolutions`); a Q/SF start
//! angle on a continued block is ignored. The lead law of a chained block is what the block
//! programs (F, K/R), so a block that re-programs it jumps the lead at the joint: the
//! `thread_chain` machine check reports that. Readings chosen: any recorded move that is
//! not a thread move (a rapid, a feed, a threading cycle), a tool change and an M03/M04/M05
//! break the chain, and so does a block that reverses the Z direction (the axis stops and
//! turns: not a continuation); blocks without motion (macro statements, subprogram calls
//! and returns, modal words) do not.
//! Threading cycles (G92, G76) always re-sync; LinuxCNC's G76 entry/exit tapers carry
//! their own phase (`linuxcnc.rs`).
//!
//! **GSK run-out J/K** (GSK 980TDi manual §3.23 on G32/G34; seed 000's own list of rules):
//! "J: Movement in the short axis in thread run-out ... with sign; if the short axis is X,
//! its value is specified with the radius; J is modal. K: Length in the long axis in thread
//! run-out ... no direction; K is modal." J (or J and K) never given: no run-out; K
//! omitted with J: K = |J|; J = 0: none; J != 0 with K = 0: K = |J|. Both words stay in
//! force for later thread blocks until re-programmed (the manual calls them modal; seed 000
//! says so for continuous thread blocks in particular).
//!
//! Reading chosen: **the run-out lies inside the block**. The long axis travels to the
//! programmed end; over its last K the short axis moves J as well, so the block ends at
//! `(X_end + 2J, Z_end)` (X a diameter). Evidence: the GSK928TE manual's example
//! `G00 Z100 X20; G33 W-40 K3 I5 U6.2 P2` ends at "(Z60, X31.20)", the programmed end plus
//! the run-out, and D.Electron's "the final programmed point is never overcome". The
//! run-out segment stays spindle-synchronised: same lead law continuing, no re-sync. It is
//! recorded as a second thread move (a taper) whose start lead is the lead reached at the
//! split and whose phase continues. Only blocks whose long axis is Z take a run-out here
//! (a face thread's run-out is refused with an error).

use super::expr::Fail;
use super::{Interp, MoveKind, Program, Sync, Words};

/// A point of the tool path: (diameter, z) in mm.
type Point = (f64, f64);

/// Why a GSK thread run-out cannot split its block.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(super) enum RunoutError {
    /// The block's long axis is X.
    #[error(
        "thread run-out (J/K) on a block whose long axis is X (a face thread) is not supported yet"
    )]
    FaceThread,
    /// K reaches back past the block's start.
    #[error("thread run-out K = {k} mm is not shorter than the block's travel in Z ({travel} mm)")]
    NotShorter {
        /// The run-out's length along Z (mm).
        k: f64,
        /// The block's travel in Z (mm).
        travel: f64,
    },
}

/// Where a run-out splits a thread block from `start` to `end` (diameter, z) whose long
/// axis is Z: the split point on the programmed line `k` before the end, and the run-out's
/// end point `(x_end + 2j, z_end)`. `Err` says why not.
pub(super) fn runout_split(
    start: Point,
    end: Point,
    j: f64,
    k: f64,
) -> Result<(Point, Point), RunoutError> {
    let dz = end.1 - start.1;
    if (end.0 - start.0).abs() / 2.0 > dz.abs() {
        return Err(RunoutError::FaceThread);
    }
    if k >= dz.abs() {
        return Err(RunoutError::NotShorter {
            k,
            travel: dz.abs(),
        });
    }
    let z_split = end.1 - dz.signum() * k;
    let x_split = start.0 + (end.0 - start.0) * (z_split - start.1) / dz;
    Ok(((x_split, z_split), (end.0 + 2.0 * j, end.1)))
}

impl Interp<'_> {
    /// The GSK modal run-out after this block's J/K words: `(j, k)` in mm when there is
    /// one (`k` resolved: K = |J| when omitted or 0).
    fn gsk_runout(&mut self, w: &Words) -> Option<(f64, f64)> {
        let j = self.length(w, "J");
        let k = self.length(w, "K");
        match (j, k) {
            (Some(j), None) => self.thread.runout = (Some(j), None),
            (j, Some(k)) => self.thread.runout = (j.or(self.thread.runout.0), Some(k.abs())),
            (None, None) => {}
        }
        match self.thread.runout {
            (Some(j), k) if j != 0.0 => Some((j, k.filter(|&k| k != 0.0).unwrap_or(j.abs()))),
            _ => None,
        }
    }

    /// Record the move of a thread block (G32/G33/G34 of every dialect) from the current
    /// position to `end`: continue the phase of a chain, split off the GSK run-out, leave the
    /// chain open for the next block, and move the machine to the block's end.
    pub(super) fn thread_block(
        &mut self,
        w: &Words,
        prog: &Program,
        pc: usize,
        end: Point,
        mut sync: Sync,
    ) -> Result<(), Fail> {
        let start = (self.x, self.z);
        let dir = (end.1 - start.1).signum();
        let chained = self.thread.chain_end.filter(|c| c.1 == dir).map(|c| c.0);
        if let Some(angle) = chained {
            sync.angle = angle;
        }
        let runout = if self.cfg.gsk {
            self.gsk_runout(w)
        } else {
            None
        };
        let col = |k: &str| w.vals.get(k).map_or(1, |v| v.1);
        let mut segments = vec![(start, end, sync)];
        if let Some((j, k)) = runout {
            let (split, stop) =
                runout_split(start, end, j, k).map_err(|e| (col("K"), e.to_string()))?;
            let rest = sync.after(split.1 - start.1).ok_or((
                1,
                "the lead would reach zero before the thread run-out (a real control alarms)"
                    .to_string(),
            ))?;
            segments = vec![(start, split, sync), (split, stop, rest)];
        }
        let mut end_angle = None;
        for (i, &(a, b, s)) in segments.iter().enumerate() {
            self.emit(prog, pc, MoveKind::Thread, a, b, Some(s));
            if let Some(m) = self.out.moves.last_mut() {
                m.chained = i > 0 || chained.is_some();
            }
            end_angle = s.after(b.1 - a.1).map(|s| s.angle);
        }
        let last = segments.last().map_or(end, |s| s.1);
        self.x = last.0;
        self.z = last.1;
        self.thread.chain_end = end_angle.map(|a| (a, dir));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{interpret_with, Dialect, Move, MoveKind, Options, Settings, Source};
    use super::runout_split;

    fn threads(text: &str, dialect: Dialect) -> Vec<Move> {
        let src = Source {
            name: "T.NC".into(),
            text: text.into(),
        };
        interpret_with(
            &src,
            dialect,
            &|_| None,
            &Options {
                settings: Settings::in_mm(),
                ..Options::default()
            },
        )
        .map(|t| t.moves)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .collect()
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    /// Closed form: the split lies K before the end on the programmed line (linear in z for
    /// a taper); the run-out ends 2J (diameter) off the programmed end, in either feed
    /// direction.
    #[test]
    fn runout_split_geometry() {
        let (s, e) = runout_split((49.8, 8.0), (49.8, -70.0), 1.0, 2.0).unwrap();
        assert_eq!((s, e), ((49.8, -68.0), (51.8, -70.0)));
        // Taper 40 -> 44 over 40 mm: at z = -36 the line is at 40 + 4 * 36/40 = 43.6.
        let (s, e) = runout_split((40.0, 0.0), (44.0, -40.0), -0.5, 4.0).unwrap();
        assert!(close(s.0, 43.6) && close(s.1, -36.0), "{s:?}");
        assert_eq!(e, (43.0, -40.0));
        // Feeding toward +z the split is K below the end.
        let (s, _) = runout_split((20.0, -30.0), (20.0, 0.0), 1.0, 3.0).unwrap();
        assert_eq!(s, (20.0, -3.0));
        assert!(runout_split((20.0, 0.0), (20.0, -2.0), 1.0, 2.0)
            .unwrap_err()
            .to_string()
            .contains("not shorter"));
        assert!(runout_split((20.0, 0.0), (60.0, -2.0), 1.0, 1.0)
            .unwrap_err()
            .to_string()
            .contains("long axis is X"));
    }

    /// Seed 000's O0002 with its run-out: from X60 Z8, U-10.2 then G34 Z-70 F4 J1 K2 R1 ends
    /// at X + 2 (J = 1 radius), so U10 leaves the tool 1.8 mm further out each time:
    /// X = 49.8 + 1.8 k. Lead at the split (76 mm of travel): L^2 = F^2 + 2Rs = 16 + 152,
    /// t = L - F = sqrt(168) - 4 revolutions, so the run-out starts at spindle angle
    /// 360 t mod 360 with lead sqrt(168).
    #[test]
    fn seed000_o0002_runout_drifts_out() {
        let text = "O0001\nN40 G00 X60 Z8 M03\nN50 M98 P250002\nN90 M30\n\
                    O0002\nN10 G00 U-10.2\nN20 G34 Z-70 F4 J1 K2 R1\nN30 G0 U10\nN40 G00 Z8\nN50 M99\n";
        let t = threads(text, Dialect::Gsk980);
        assert_eq!(t.len(), 50);
        let l = 168f64.sqrt();
        let angle = (360.0 * (l - 4.0)).rem_euclid(360.0);
        for (k, pair) in t.chunks(2).enumerate() {
            let x = 49.8 + 1.8 * k as f64;
            let (a, b) = (&pair[0], &pair[1]);
            assert!(close(a.x_start, x) && close(a.x_dia, x), "{k}: {a:?}");
            assert_eq!((a.z_start, a.z, a.chained), (8.0, -68.0, false));
            assert_eq!(
                (a.lead, a.lead_change, a.sync_angle_deg),
                (Some(4.0), Some(1.0), Some(0.0))
            );
            assert!(close(b.x_start, x) && close(b.x_dia, x + 2.0), "{k}: {b:?}");
            assert_eq!((b.z_start, b.z, b.chained), (-68.0, -70.0, true));
            assert!(close(b.lead.unwrap(), l) && close(b.sync_angle_deg.unwrap(), angle));
            assert_eq!(b.line, a.line);
        }
    }

    /// The modal rules of seed 000's list: no J ever: none; J alone: K = J; omitted: the
    /// previous J/K; K0: K = J; J0: none, also with K; a negative J runs out inward.
    #[test]
    fn runout_modal_rules() {
        let blocks = [
            ("G32 Z-10 F2", None),
            ("G32 Z-10 F2 J0.5", Some((1.0, 0.5))),
            ("G32 Z-10 F2", Some((1.0, 0.5))),
            ("G32 Z-10 F2 J0.5 K0", Some((1.0, 0.5))),
            ("G32 Z-10 F2 K3", Some((1.0, 3.0))),
            ("G32 Z-10 F2", Some((1.0, 3.0))),
            ("G34 Z-10 F2 R0.1", Some((1.0, 3.0))),
            ("G32 Z-10 F2 J-1 K1", Some((-2.0, 1.0))),
            ("G32 Z-10 F2 J0", None),
            ("G32 Z-10 F2 K2", None),
        ];
        let mut text = String::from("G0 X20 Z0\n");
        for (b, _) in &blocks {
            text.push_str(&format!("G0 X20 Z0\n{b}\n"));
        }
        let t = threads(&text, Dialect::Gsk980);
        let mut i = 0;
        for (b, want) in blocks {
            match want {
                None => {
                    assert_eq!((t[i].x_dia, t[i].z), (20.0, -10.0), "{b}");
                    i += 1;
                }
                Some((dx, k)) => {
                    assert_eq!((t[i].x_dia, t[i].z), (20.0, -10.0 + k), "{b}");
                    assert_eq!((t[i + 1].x_dia, t[i + 1].z), (20.0 + dx, -10.0), "{b}");
                    assert!(t[i + 1].chained && !t[i].chained, "{b}");
                    i += 2;
                }
            }
        }
        assert_eq!(i, t.len());
    }

    /// Two chained blocks: the second starts at the spindle angle where the first ended
    /// (360 x revolutions, mod 360) and ignores its Q; a rapid, a tool change or a spindle
    /// command between them starts a new chain at the block's own Q.
    #[test]
    fn chained_blocks_continue_the_phase() {
        // F2 over 7 mm: 3.5 revolutions, 1260 deg -> 180.
        let t = threads(
            "G0 X20 Z0\nG32 Z-7 F2\nG32 Z-20 F2 Q90000\n",
            Dialect::Fanuc,
        );
        assert_eq!((t[0].chained, t[0].sync_angle_deg), (false, Some(0.0)));
        assert_eq!((t[1].chained, t[1].sync_angle_deg), (true, Some(180.0)));
        // G34 F4 K1 over 12 mm: t = sqrt(16 + 24) - 4.
        let t = threads(
            "G0 X20 Z0\nG34 Z-12 F4 K1\n#1=1\nG34 Z-30 F6.325 K1\n",
            Dialect::Fanuc,
        );
        let want = (360.0 * (40f64.sqrt() - 4.0)).rem_euclid(360.0);
        assert!(
            t[1].chained && close(t[1].sync_angle_deg.unwrap(), want),
            "{t:?}"
        );
        // Reversing the Z direction is no continuation either.
        let t = threads(
            "G0 X20 Z0\nG32 Z-7 F2\nG32 X19 Z0 F2 Q90000\n",
            Dialect::Fanuc,
        );
        assert_eq!((t[1].chained, t[1].sync_angle_deg), (false, Some(90.0)));
        for between in ["G0 X21", "T0202", "M04", "G1 Z-7.5"] {
            let text = format!("G0 X20 Z0\nG32 Z-7 F2\n{between}\nG32 Z-20 F2 Q90000\n");
            let t = threads(&text, Dialect::Fanuc);
            assert_eq!(
                (t[1].chained, t[1].sync_angle_deg),
                (false, Some(90.0)),
                "{between}"
            );
        }
        // A threading cycle re-syncs every pass.
        let t = threads(
            "G0 X30 Z3\nG32 Z-1 F1.5\nG92 X29 Z-20 F1.5\n",
            Dialect::Fanuc,
        );
        assert!(!t[1].chained);
        // LinuxCNC's planner keeps the sync of consecutive G33 moves too (K is the pitch).
        let t = threads(
            "G7 M3\nG0 X20 Z0\nG33 Z-7 K2\nG33 X24 Z-9 K2\n",
            Dialect::Linuxcnc,
        );
        assert_eq!((t[1].chained, t[1].sync_angle_deg), (true, Some(180.0)));
    }

    /// A run-out too long for its block or on a face thread is an error at the K word.
    #[test]
    fn runout_errors_name_the_word() {
        let src = Source {
            name: "T.NC".into(),
            text: "G0 X50 Z5\nG34 Z3 F4 J1 K2 R1\n".into(),
        };
        let e = interpret_with(
            &src,
            Dialect::Gsk980,
            &|_| None,
            &Options {
                settings: Settings::in_mm(),
                ..Options::default()
            },
        )
        .map(|t| t.moves)
        .unwrap_err();
        assert_eq!((e.line, e.col), (2, 14), "{e}");
        assert!(e.message.contains("not shorter"), "{e}");
        // F1 reaches lead 0 after 10 revolutions, 5 mm: never at the split (23 mm).
        let src = Source {
            name: "T.NC".into(),
            text: "G0 X50 Z5\nG34 Z-20 F1 J1 K2 R-0.1\n".into(),
        };
        let e = interpret_with(
            &src,
            Dialect::Gsk980,
            &|_| None,
            &Options {
                settings: Settings::in_mm(),
                ..Options::default()
            },
        )
        .map(|t| t.moves)
        .unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("lead would reach zero"), "{e}");
    }
}
