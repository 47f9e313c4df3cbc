//! The Siemens thread-cutting cycles CYCLE97 (802D and 840D) and CYCLE99 (840D sl), run as
//! the rapid and thread moves the cycle makes (`docs/job-format.md`, "Siemens thread
//! cycles"; SINUMERIK 802D/840D Cycles manuals, "Thread cutting - CYCLE97").
//!
//! `CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID, VARI,
//! NUMT, _VRT)`: the thread runs from `SPL` (diameter `DM1`) to `FPL` (`DM2`), lengthened by
//! the run-in `APP` before and the run-out `ROP` after along the same cone. `TDEP - FAL` is
//! cut in `NRC` roughing cuts (VARI 1/2: constant infeed, depth `n (TDEP - FAL) / NRC`;
//! VARI 3/4: constant cutting cross-section, depth `(TDEP - FAL) sqrt(n / NRC)`), then one
//! finishing cut at `TDEP` and `NID` idle passes there. VARI 1/3 external (infeed towards
//! the axis), 2/4 internal. `IANG`: infeed along a flank at that angle (> 0: one flank, < 0:
//! the flanks alternating), 0: radial; a cut at depth `d` stands back along Z by
//! `(TDEP - d) tan |IANG|` against the cutting direction (the same single-flank model as
//! vpcut's FANUC G76), so the last cut is the finished groove. Each cut: rapid to the
//! retract diameter at its start (`_VRT`, radius, default 1 mm, from the thread's diameter
//! at the run-in point), rapid infeed, thread move with lead `PIT` and start angle, rapid
//! retract at the run-out end; all cuts of one start, then the next: `NUMT` starts at
//! `NSP + k 360 / NUMT` degrees. At the end the tool is back at the start point (retract
//! diameter, run-in point). `MPIT` names an ISO coarse thread M3..M60 whose pitch is taken.
//!
//! `CYCLE99(_SPL, _SPD, _FPL, _FPD, _APP, _ROP, _TDEP, _FAL, _IANG, _NSP, _NRC, _NID, _PIT,
//! _VARI, _NUMTH, _VRT, ..)`: the same thread with the start and end points first and the
//! pitch later; `_VARI` 1..4 as CYCLE97's VARI. The 840D sl's coded `_VARI` (several
//! digits) and the parameters after `_VRT` are refused by name when set.
//!
//! `CYCLE84(RTP, RFP, SDIS, DP, DPR, DTB, SDAC, MPIT, PIT, POSS, SST, SST1)`, rigid tapping
//! on the spindle axis (X0): rapid to `RFP + SDIS`, tap to `DP` (or `RFP - DPR`) as a thread
//! move of lead |PIT| (or the ISO coarse pitch of |MPIT|; negative: a left-hand tap, the
//! spindle M4), back to `RFP + SDIS` with the spindle reversed, rapid to `RTP` (SINUMERIK
//! 802D/840D Cycles manuals, "Rigid tapping - CYCLE84").

use super::expr::Fail;
use super::lex::Cursor;
use super::{Interp, MoveKind, Program, Step, Sync};
use crate::model::helix::Spindle;

/// ISO coarse pitches by nominal diameter (ISO 261), for `MPIT` (M3..M60).
const ISO_COARSE: &[(u32, f64)] = &[
    (3, 0.5),
    (4, 0.7),
    (5, 0.8),
    (6, 1.0),
    (8, 1.25),
    (10, 1.5),
    (12, 1.75),
    (14, 2.0),
    (16, 2.0),
    (18, 2.5),
    (20, 2.5),
    (22, 2.5),
    (24, 3.0),
    (27, 3.0),
    (30, 3.5),
    (33, 3.5),
    (36, 4.0),
    (39, 4.0),
    (42, 4.5),
    (45, 4.5),
    (48, 5.0),
    (52, 5.0),
    (56, 5.5),
    (60, 5.5),
];

/// The most cuts one cycle call makes (passes times starts), so that a typo cannot fill
/// the memory.
const MAX_CUTS: u64 = 100_000;

/// A thread cycle's geometry and technology, in mm (diameters) and degrees, in the job's
/// frame.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ThreadCycle {
    /// Lead (mm per revolution along Z).
    pub(super) pit: f64,
    /// Thread start and end along Z.
    pub(super) spl: f64,
    pub(super) fpl: f64,
    /// Diameters at the start and end.
    pub(super) dm1: f64,
    pub(super) dm2: f64,
    /// Run-in and run-out paths (unsigned).
    pub(super) app: f64,
    pub(super) rop: f64,
    /// Thread depth and finishing allowance (radius, unsigned).
    pub(super) tdep: f64,
    pub(super) fal: f64,
    /// Infeed angle (deg; negative: alternating flanks).
    pub(super) iang: f64,
    /// Start angle of the first start (deg).
    pub(super) nsp: f64,
    /// Roughing cuts and idle passes.
    pub(super) nrc: u32,
    pub(super) nid: u32,
    /// Internal thread (VARI 2, 4).
    pub(super) internal: bool,
    /// Constant cutting cross-section (VARI 3, 4), else constant infeed depth.
    pub(super) constant_section: bool,
    /// Number of starts.
    pub(super) numt: u32,
    /// Retract distance (radius).
    pub(super) vrt: f64,
}

/// One move of a cycle: where to, and for a thread move its start angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Seg {
    pub(super) to: (f64, f64),
    pub(super) thread_angle: Option<f64>,
}

/// The depth (radius, below the thread's diameter) of every cut of one start: `nrc`
/// roughing cuts to `tdep - fal`, the finishing cut at `tdep`, `nid` idle passes at `tdep`.
pub(super) fn depths(tdep: f64, fal: f64, nrc: u32, constant_section: bool, nid: u32) -> Vec<f64> {
    let rough = tdep - fal;
    let n = f64::from(nrc);
    let mut out: Vec<f64> = (1..=nrc)
        .map(|i| {
            let i = f64::from(i);
            if constant_section {
                rough * (i / n).sqrt()
            } else {
                rough * i / n
            }
        })
        .collect();
    out.push(tdep);
    out.extend(std::iter::repeat_n(tdep, nid as usize));
    out
}

/// Every move of the cycle from the tool's position `from` (`docs` above).
pub(super) fn plan(t: &ThreadCycle) -> Vec<Seg> {
    let dir = (t.fpl - t.spl).signum();
    let za = t.spl - dir * t.app;
    let ze = t.fpl + dir * t.rop;
    let dia = |z: f64| t.dm1 + (t.dm2 - t.dm1) * (z - t.spl) / (t.fpl - t.spl);
    // Infeed direction of the diameter: towards the axis outside, away from it inside.
    let s = if t.internal { 1.0 } else { -1.0 };
    let retract = |z: f64| dia(z) - s * 2.0 * t.vrt;
    let tan = t.iang.abs().to_radians().tan();
    let cuts = depths(t.tdep, t.fal, t.nrc, t.constant_section, t.nid);
    let mut out = Vec::new();
    for k in 0..t.numt {
        let angle = (t.nsp + f64::from(k) * 360.0 / f64::from(t.numt)).rem_euclid(360.0);
        for (n, &d) in cuts.iter().enumerate() {
            let flank = if t.iang < 0.0 && n % 2 == 1 {
                -1.0
            } else {
                1.0
            };
            let shift = -dir * (t.tdep - d) * tan * flank;
            let (z0, z1) = (za + shift, ze + shift);
            out.push(Seg {
                to: (retract(za), z0),
                thread_angle: None,
            });
            out.push(Seg {
                to: (dia(za) + s * 2.0 * d, z0),
                thread_angle: None,
            });
            out.push(Seg {
                to: (dia(ze) + s * 2.0 * d, z1),
                thread_angle: Some(angle),
            });
            out.push(Seg {
                to: (retract(ze), z1),
                thread_angle: None,
            });
        }
    }
    out.push(Seg {
        to: (retract(za), za),
        thread_angle: None,
    });
    out
}

/// A cycle's arguments: values, `None` where left empty.
type Args = Vec<Option<f64>>;

impl Interp<'_> {
    /// `CYCLE97(..)`, `CYCLE99(..)`: the cursor after the name (`at`: the name's column).
    pub(super) fn thread_cycle(
        &mut self,
        c: &mut Cursor,
        prog: &Program,
        pc: usize,
        name: &str,
        at: usize,
    ) -> Result<Step, Fail> {
        let args = self.cycle_args(c, name)?;
        let t = match name {
            "CYCLE97" => self.cycle97(&args, at)?,
            "CYCLE99" => self.cycle99(&args, at)?,
            _ => unreachable!("called for CYCLE97 and CYCLE99"),
        };
        // Checked before the moves are made, so that they cannot fill the memory.
        let cuts = u64::from(t.numt) * (u64::from(t.nrc) + 1 + u64::from(t.nid));
        if cuts > MAX_CUTS {
            return Err((
                at,
                format!("{name} would make {cuts} cuts (at most {MAX_CUTS})"),
            ));
        }
        for s in plan(&t) {
            let from = (self.x, self.z);
            let (kind, sync) = match s.thread_angle {
                Some(angle) => (
                    MoveKind::Thread,
                    Some(Sync {
                        lead: t.pit,
                        change: 0.0,
                        angle,
                    }),
                ),
                None => (MoveKind::Rapid, None),
            };
            if from != s.to || sync.is_some() {
                self.emit(prog, pc, kind, from, s.to, sync);
            }
            (self.x, self.z) = s.to;
            if self.out.too_many_moves {
                break;
            }
        }
        Ok(Step::Next)
    }

    /// `CYCLE84(..)`, rigid tapping on the axis (the cursor after the name).
    pub(super) fn cycle84(
        &mut self,
        c: &mut Cursor,
        prog: &Program,
        pc: usize,
        at: usize,
    ) -> Result<Step, Fail> {
        let a = self.cycle_args(c, "CYCLE84")?;
        let v = |k: usize| a.get(k).copied().flatten();
        let (scale, ox, oz) = self.cycle_frame();
        let z = |p: f64| p * scale + oz;
        let err = |m: &str| Err((at, format!("CYCLE84: {m}")));
        let (Some(rtp), Some(rfp)) = (v(0), v(1)) else {
            return err("RTP and RFP (retract and reference planes) are needed");
        };
        let sdis = v(2).unwrap_or(0.0).abs();
        let dp = match (v(3), v(4)) {
            (Some(dp), _) => dp,
            (None, Some(dpr)) => rfp - dpr.abs(),
            (None, None) => return err("DP or DPR (the tapping depth) is needed"),
        };
        if dp == rfp {
            return err("the depth DP is at the reference plane RFP");
        }
        let (mpit, pit) = (v(7).unwrap_or(0.0), v(8).unwrap_or(0.0));
        let left = mpit < 0.0 || pit < 0.0;
        let lead = pitch("CYCLE84", pit.abs(), mpit.abs(), at)? * scale;
        if (self.x - ox).abs() > 1e-9 {
            return err("tapping off the spindle axis (X not 0) needs driven tools: not modelled");
        }
        // The safety distance lies on the side away from the depth.
        let dir = (z(dp) - z(rfp)).signum();
        let safe = z(rfp) - dir * sdis * scale;
        let x = self.x;
        let spindle = self.modal.spindle;
        let tap_in = if left { Spindle::Ccw } else { Spindle::Cw };
        let tap_out = if left { Spindle::Cw } else { Spindle::Ccw };
        let sync = Sync {
            lead,
            change: 0.0,
            angle: v(9).unwrap_or(0.0),
        };
        if self.z != safe {
            self.emit(prog, pc, MoveKind::Rapid, (x, self.z), (x, safe), None);
        }
        self.modal.spindle = tap_in;
        self.emit(
            prog,
            pc,
            MoveKind::Thread,
            (x, safe),
            (x, z(dp)),
            Some(sync),
        );
        self.modal.spindle = tap_out;
        // Back in the groove the way in cut: its phase counted the other way.
        let back = super::motion::tap_back(sync, (z(dp) - safe).abs() / lead);
        self.emit(
            prog,
            pc,
            MoveKind::Thread,
            (x, z(dp)),
            (x, safe),
            Some(back),
        );
        self.modal.spindle = spindle;
        if z(rtp) != safe {
            self.emit(prog, pc, MoveKind::Rapid, (x, safe), (x, z(rtp)), None);
        }
        self.z = z(rtp);
        Ok(Step::Next)
    }

    /// The arguments in brackets: expressions, empty where left out.
    fn cycle_args(&self, c: &mut Cursor, name: &str) -> Result<Args, Fail> {
        if !c.eat("(") {
            return c.err(format!("expected `(` after {name}"));
        }
        let mut out = Vec::new();
        if c.eat(")") {
            return Ok(out);
        }
        loop {
            c.ws();
            if matches!(c.peek(), Some(b',') | Some(b')')) {
                out.push(None);
            } else if c.peek() == Some(b'"') {
                return c.err(format!("{name}: a text argument is not modelled"));
            } else {
                out.push(Some(self.expr(c)?));
            }
            if c.eat(")") {
                break;
            }
            if !c.eat(",") {
                return c.err(format!("expected `,` or `)` in the arguments of {name}"));
            }
        }
        if !c.done() {
            return c.err(format!(
                "unexpected {} after {name}(..): a cycle call stands in a block of its own",
                c.here()
            ));
        }
        Ok(out)
    }

    /// Program units to mm, and a Z and a diameter of the active work offset to the job's
    /// frame.
    fn cycle_frame(&self) -> (f64, f64, f64) {
        let scale = if self.modal.inch { 25.4 } else { 1.0 };
        let (ox, oz) = self.frames.offsets[self.frames.work];
        (
            scale,
            ox + self.frames.g92_off.0,
            oz + self.frames.g92_off.1,
        )
    }

    fn cycle97(&self, a: &Args, at: usize) -> Result<ThreadCycle, Fail> {
        let v = |k: usize| a.get(k).copied().flatten().unwrap_or(0.0);
        if a.len() > 17 && a[17..].iter().any(|x| x.is_some_and(|x| x != 0.0)) {
            return Err((at, "CYCLE97: parameters after _VRT (the 840D sl's display modes and extensions) are not modelled".into()));
        }
        let (pit, mpit) = (v(0), v(1));
        let pit = pitch("CYCLE97", pit, mpit, at)?;
        let vari = v(14);
        self.thread_params(
            "CYCLE97",
            at,
            pit,
            [v(2), v(3), v(4), v(5), v(6), v(7), v(8), v(9), v(10), v(11)],
            (v(12), v(13), vari, v(15), v(16)),
        )
    }

    fn cycle99(&self, a: &Args, at: usize) -> Result<ThreadCycle, Fail> {
        let v = |k: usize| a.get(k).copied().flatten().unwrap_or(0.0);
        if a.len() > 16 && a[16..].iter().any(|x| x.is_some_and(|x| x != 0.0)) {
            return Err((at, "CYCLE99: parameters after _VRT (thread tables, _DMODE/_AMODE, the 840D sl's extensions) are not modelled: leave them empty or 0".into()));
        }
        let pit = v(12);
        if pit <= 0.0 {
            return Err((at, format!("CYCLE99: _PIT {pit}: the pitch must be positive (pitch as threads per inch or by table is not modelled)")));
        }
        let vari = v(13);
        if !(1.0..=4.0).contains(&vari) || vari.fract() != 0.0 {
            return Err((at, format!("CYCLE99: _VARI {vari}: the 840D sl's coded machining type is not modelled; vpcut runs _VARI 1..4 as CYCLE97's VARI (1/3 external, 2/4 internal; 1/2 constant infeed, 3/4 constant cross-section)")));
        }
        // (_SPL, _SPD, _FPL, _FPD) to CYCLE97's (SPL, FPL, DM1, DM2).
        self.thread_params(
            "CYCLE99",
            at,
            pit,
            [v(0), v(2), v(1), v(3), v(4), v(5), v(6), v(7), v(8), v(9)],
            (v(10), v(11), vari, v(14), v(15)),
        )
    }

    /// Checks and units: `g` = SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP (program
    /// units, degrees); `n` = NRC, NID, VARI, NUMT, _VRT.
    fn thread_params(
        &self,
        name: &str,
        at: usize,
        pit: f64,
        g: [f64; 10],
        n: (f64, f64, f64, f64, f64),
    ) -> Result<ThreadCycle, Fail> {
        let [spl, fpl, dm1, dm2, app, rop, tdep, fal, iang, nsp] = g;
        let (nrc, nid, vari, numt, vrt) = n;
        let err = |m: String| Err((at, format!("{name}: {m}")));
        if spl == fpl {
            return err(format!(
                "the thread's start and end are both at {spl} (SPL = FPL)"
            ));
        }
        if (dm2 - dm1).abs() / 2.0 > (fpl - spl).abs() {
            return err(
                "a taper steeper than 45 degrees (the lead would be along X) is not modelled"
                    .into(),
            );
        }
        if tdep <= 0.0 {
            return err(format!("TDEP {tdep}: the thread depth must be positive"));
        }
        if fal < 0.0 || fal >= tdep {
            return err(format!(
                "FAL {fal}: the finishing allowance must lie in 0..TDEP ({tdep})"
            ));
        }
        if iang.abs() >= 90.0 {
            return err(format!(
                "IANG {iang}: the infeed angle must lie within ±90 degrees"
            ));
        }
        let whole = |v: f64, what: &str, min: f64, max: f64| -> Result<u32, Fail> {
            if v.fract() != 0.0 || v < min || v > max {
                return Err((
                    at,
                    format!("{name}: {what} {v} must be a whole number from {min} to {max}"),
                ));
            }
            Ok(v as u32)
        };
        let nrc = whole(nrc, "NRC (roughing cuts)", 1.0, 1e5)?;
        let nid = whole(nid, "NID (idle passes)", 0.0, 1e5)?;
        let numt = whole(numt.max(1.0), "NUMT (starts)", 1.0, 1e5)?;
        // A coded VARI (the 840D sl's, 300103) is said as such below.
        let vari = whole(vari, "VARI", 1.0, 1e9)?;
        if vari > 4 {
            return err(format!(
                "VARI {vari}: the machining type is 1..4 (Siemens alarm 61002)"
            ));
        }
        if app < 0.0 || rop < 0.0 || vrt < 0.0 {
            return err("APP, ROP and _VRT are unsigned".into());
        }
        let (scale, ox, oz) = self.cycle_frame();
        Ok(ThreadCycle {
            pit: pit * scale,
            spl: spl * scale + oz,
            fpl: fpl * scale + oz,
            dm1: dm1 * scale + ox,
            dm2: dm2 * scale + ox,
            app: app * scale,
            rop: rop * scale,
            tdep: tdep * scale,
            fal: fal * scale,
            iang,
            nsp,
            nrc,
            nid,
            internal: vari == 2 || vari == 4,
            constant_section: vari >= 3,
            numt,
            // 1 mm when not programmed (whatever the units).
            vrt: if vrt > 0.0 { vrt * scale } else { 1.0 },
        })
    }
}

/// The pitch from `PIT` or the thread size `MPIT` (ISO coarse).
fn pitch(name: &str, pit: f64, mpit: f64, at: usize) -> Result<f64, Fail> {
    if mpit != 0.0 {
        let Some(&(_, p)) = ISO_COARSE.iter().find(|e| f64::from(e.0) == mpit) else {
            return Err((at, format!("{name}: MPIT {mpit} is not an ISO coarse thread size M3..M60 (Siemens alarm 61001)")));
        };
        if pit != 0.0 && (pit - p).abs() > 1e-9 {
            return Err((
                at,
                format!(
                    "{name}: PIT {pit} and MPIT {mpit} (pitch {p}) disagree (Siemens alarm 61001)"
                ),
            ));
        }
        return Ok(p);
    }
    if pit <= 0.0 {
        return Err((at, format!("{name}: PIT {pit}: the pitch must be positive, or name the thread size in MPIT (Siemens alarm 61001)")));
    }
    Ok(pit)
}
