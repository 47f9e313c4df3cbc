//! Okuma OSP-P thread cutting cycles as moves (pure): the fixed thread cutting cycles G31/G33
//! (constant lead) and G34 (variable lead), one pass a block, and the compound fixed thread
//! cutting cycle G71 (longitudinal), all its passes from one block.
//!
//! Sources: OSP-P200L programming manual 5238-E, section 7 "Fixed cycles": 2-1 "Fixed thread
//! cutting cycle: longitudinal (G31, G33)" (P-97: X the thread diameter of the pass, Z the
//! end, F the lead or F/J, I the radius difference of a taper, K the Z shift of the start,
//! C the phase of a multi-thread), the variable lead supplement (P-114 neighbourhood,
//! `D = n (F0 + n E / 2)`: E the lead change per revolution, continuous, see
//! `/work/shared/reference/controllers.md` 1.1) and the compound cycle's infeed patterns
//! (P-113/P-114: D the first cutting point, H the thread height, U the finishing allowance,
//! all diameters; B the tool angle; M32 single-edge, M33 zigzag, M34 reverse single-edge;
//! M73/M74/M75 the infeed patterns). Where the manual's text was not at hand the reading
//! chosen is said beside the code and in `docs/coverage/okuma.md`.

use super::expr::Fail;
use super::MoveKind;

/// A thread move's synchronisation: lead, lead change per revolution, spindle angle (deg).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Sync3 {
    pub(super) lead: f64,
    pub(super) change: f64,
    pub(super) angle: f64,
}

/// One move of a cycle: kind, start and end (diameter, z), and the sync of a thread move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CycleMove {
    pub(super) kind: MoveKind,
    pub(super) a: (f64, f64),
    pub(super) b: (f64, f64),
    pub(super) sync: Option<Sync3>,
}

/// One pass of a fixed thread cutting cycle from the start point `s` (diameter, z): to the
/// pass's start (Z first when the start is shifted by `k`, then X at `x + 2 i`, the taper's
/// start), the thread to (`x`, `z`), back out in X at rapid, back to `s` in Z: the moves of
/// the manual's figure (P-97: the starting point, the cutting start, the end, the
/// return). `shift` moves the whole pass along Z (the compound cycle's flank infeed).
pub(super) fn pass(
    s: (f64, f64),
    x: f64,
    z: f64,
    i: f64,
    k: f64,
    shift: f64,
    sync: Sync3,
) -> Vec<CycleMove> {
    let mut v = Vec::new();
    let rapid = |a, b| CycleMove {
        kind: MoveKind::Rapid,
        a,
        b,
        sync: None,
    };
    let z0 = s.1 + k + shift;
    let mut p = s;
    if z0 != p.1 {
        v.push(rapid(p, (p.0, z0)));
        p = (p.0, z0);
    }
    let start = (x + 2.0 * i, z0);
    v.push(rapid(p, start));
    let end = (x, z + shift);
    v.push(CycleMove {
        kind: MoveKind::Thread,
        a: start,
        b: end,
        sync: Some(sync),
    });
    v.push(rapid(end, (s.0, end.1)));
    v.push(rapid((s.0, end.1), s));
    v
}

/// How the compound cycle feeds in (5238-E P-113: M32 single-edge cutting along one flank,
/// M33 zigzag, M34 single-edge along the other flank).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Infeed {
    /// M32.
    Single,
    /// M33.
    Zigzag,
    /// M34.
    Reverse,
}

/// The infeed pattern (M73, M74, M75).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Pattern {
    /// M73: pattern 1.
    One,
    /// M74: pattern 2.
    Two,
    /// M75: patterns 3 and 4.
    Three,
}

/// At most this many passes a compound cycle may make (a limit, not a hang).
const MAX_PASSES: usize = 10_000;

/// The cutting points (depths below the crest, diameter values, as D, H and U are given)
/// of the compound cycle's passes, the finishing pass last.
///
/// - Pattern 1 (M73): the cutting point grows by D each pass (`n D`) until `H - U`, then
///   the finishing pass at H when U is given. Reading: the manual's pattern-1 figure shows
///   equal infeeds of D; its text was not retrieved (`docs/coverage/okuma.md`).
/// - Pattern 3 (M75 with M32/M34) when `D^2 >= H^2 - (H - U)^2`: the n-th pass at
///   `sqrt(n) D` (5238-E P-113, "the second path at cutting point sqrt(2) D, and the n-th
///   path at sqrt(n) D until the path reaches the cutting point of H - U(W). Finally, the
///   cutting tool is fed by U(W)"): constant area per pass.
/// - Pattern 4 (M75 when `D^2 < H^2 - (H - U)^2`), pattern 2 (M74) and pattern 3 with
///   zigzag (M33): the control's own optimisation or text not retrieved: refused.
pub(super) fn depths(
    d: f64,
    h: f64,
    u: f64,
    pattern: Pattern,
    infeed: Infeed,
) -> Result<Vec<f64>, String> {
    if !(d > 0.0 && h > 0.0 && u >= 0.0 && u < h) {
        return Err(format!(
            "G71 needs D (first cutting point) > 0, H (thread height) > 0 and 0 <= U (finishing allowance) < H, got D{d} H{h} U{u}"
        ));
    }
    let rough = h - u;
    let step: Box<dyn Fn(usize) -> f64> = match (pattern, infeed) {
        (Pattern::One, _) => Box::new(move |n| n as f64 * d),
        (Pattern::Three, Infeed::Single | Infeed::Reverse) => {
            if d * d < h * h - rough * rough {
                return Err(format!(
                    "G71 M75 with D{d}: D^2 < H^2 - (H - U)^2 selects infeed pattern 4, whose cutting points the control optimises itself (5238-E P-114): vpcut cannot reproduce them"
                ));
            }
            Box::new(move |n| (n as f64).sqrt() * d)
        }
        (Pattern::Three, Infeed::Zigzag) => {
            return Err(
                "G71 M75 with M33 (zigzag infeed pattern 3): the manual's odd-path cutting points are not reproduced by vpcut".into(),
            )
        }
        (Pattern::Two, _) => {
            return Err(
                "G71 M74 (infeed pattern 2) is not simulated: its cutting points are not documented in the sources vpcut follows".into(),
            )
        }
    };
    let mut v = Vec::new();
    let mut n = 1;
    loop {
        let c = step(n).min(rough);
        v.push(c);
        if c >= rough {
            break;
        }
        n += 1;
        if n > MAX_PASSES {
            return Err(format!("G71 would cut more than {MAX_PASSES} passes"));
        }
    }
    if u > 0.0 {
        v.push(h);
    }
    Ok(v)
}

/// The words of a G71 block, in mm and degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct G71 {
    /// X: the thread's root diameter at the end.
    pub(super) x: f64,
    /// Z: the thread's end.
    pub(super) z: f64,
    /// I: radius at the start minus radius at the end (taper).
    pub(super) i: f64,
    /// B: the tool angle (deg); 0 feeds in radially.
    pub(super) b: f64,
    /// D, H, U: diameters.
    pub(super) d: f64,
    pub(super) h: f64,
    pub(super) u: f64,
    /// F / J: the lead; E: its change per revolution.
    pub(super) lead: f64,
    pub(super) change: f64,
    /// Q: the number of threads (starts), each `360 / Q` deg further.
    pub(super) starts: u32,
    pub(super) infeed: Infeed,
    pub(super) pattern: Pattern,
}

/// The compound cycle's moves from the start point `s`: for each cutting point, a pass
/// (`pass`) at the crest diameter minus the cutting point (plus for an internal thread, X
/// beyond the start), shifted along Z by the radial depth times `tan(B/2)` towards the start
/// (M32; away with M34), for each start in turn at `360 k / Q` deg. The crest is `X + H`
/// (external: the root X lies inside the start) or `X - H` (internal).
pub(super) fn compound(s: (f64, f64), g: &G71) -> Result<Vec<CycleMove>, Fail> {
    let depths = depths(g.d, g.h, g.u, g.pattern, g.infeed).map_err(|m| (1, m))?;
    let inward = if g.x < s.0 { -1.0 } else { 1.0 };
    let crest = g.x - inward * g.h;
    let back = if g.z < s.1 { 1.0 } else { -1.0 };
    let half = (g.b / 2.0).to_radians().tan();
    let mut out = Vec::new();
    for &c in &depths {
        let x = crest + inward * c;
        let flank = c / 2.0 * half;
        let shift = match g.infeed {
            Infeed::Single => back * flank,
            Infeed::Reverse => -back * flank,
            Infeed::Zigzag => 0.0,
        };
        for k in 0..g.starts.max(1) {
            let sync = Sync3 {
                lead: g.lead,
                change: g.change,
                angle: 360.0 * f64::from(k) / f64::from(g.starts.max(1)),
            };
            out.extend(pass(s, x, g.z, g.i, 0.0, shift, sync));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_three_cuts_at_root_n_times_d_then_finishes() {
        // Hand derivation (5238-E P-113): H = 1.84, U = 0.1, D = 0.6 (diameters).
        // D^2 = 0.36 >= H^2 - (H - U)^2 = 3.3856 - 3.0276 = 0.358: pattern 3.
        // sqrt(n) 0.6: 0.6, 0.848528, 1.039230, 1.2, 1.341641, 1.469694, 1.587451,
        // 1.697056, n = 9: 1.8 >= 1.74 -> 1.74; then the finish at 1.84.
        let v = depths(0.6, 1.84, 0.1, Pattern::Three, Infeed::Single).unwrap();
        let want = [
            0.6, 0.848528, 1.039230, 1.2, 1.341641, 1.469694, 1.587451, 1.697056, 1.74, 1.84,
        ];
        assert_eq!(v.len(), want.len(), "{v:?}");
        for (g, w) in v.iter().zip(want) {
            assert!((g - w).abs() < 5e-7, "{v:?}");
        }
        // Pattern 4 when the first cut is smaller than the finishing one's area.
        let e = depths(0.5, 1.84, 0.1, Pattern::Three, Infeed::Single).unwrap_err();
        assert!(e.contains("pattern 4"), "{e}");
    }

    #[test]
    fn pattern_one_steps_by_d_without_finish_when_u_is_absent() {
        // n D: 0.4, 0.8, 1.2, 1.6, then 2.0 > 1.84 -> 1.84; no U, no finishing pass.
        let v = depths(0.4, 1.84, 0.0, Pattern::One, Infeed::Single).unwrap();
        let want = [0.4, 0.8, 1.2, 1.6, 1.84];
        assert_eq!(v.len(), want.len());
        for (g, w) in v.iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{v:?}");
        }
        for bad in [
            (0.0, 1.0, 0.0),
            (0.2, 0.0, 0.0),
            (0.2, 1.0, 1.0),
            (0.2, 1.0, -0.1),
        ] {
            assert!(depths(bad.0, bad.1, bad.2, Pattern::One, Infeed::Single).is_err());
        }
    }

    #[test]
    fn compound_passes_sit_on_the_flank_towards_the_start() {
        // External thread from (34, 5) to root X28.16 Z-30, H1.84, 60 deg tool, M32: the
        // pass with cutting point c is at X = 30 - c and Z shifted +c/2 tan 30 deg.
        let g = G71 {
            x: 28.16,
            z: -30.0,
            i: 0.0,
            b: 60.0,
            d: 0.6,
            h: 1.84,
            u: 0.1,
            lead: 2.0,
            change: 0.0,
            starts: 1,
            infeed: Infeed::Single,
            pattern: Pattern::Three,
        };
        let mv = compound((34.0, 5.0), &g).unwrap();
        let threads: Vec<&CycleMove> = mv.iter().filter(|m| m.kind == MoveKind::Thread).collect();
        assert_eq!(threads.len(), 10);
        let t = 30f64.to_radians().tan();
        for (m, c) in threads
            .iter()
            .zip(depths(0.6, 1.84, 0.1, Pattern::Three, Infeed::Single).unwrap())
        {
            assert!((m.a.0 - (30.0 - c)).abs() < 1e-12);
            assert!((m.a.1 - (5.0 + c / 2.0 * t)).abs() < 1e-12);
            assert!((m.b.1 - (-30.0 + c / 2.0 * t)).abs() < 1e-12);
        }
        // Every pass ends back at the start point.
        assert_eq!(mv.last().unwrap().b, (34.0, 5.0));
        // Internal: the crest is X - H, the passes go outwards; M34 shifts away.
        let gi = G71 {
            x: 31.84,
            infeed: Infeed::Reverse,
            ..g
        };
        let mv = compound((26.0, 5.0), &gi).unwrap();
        let first = mv.iter().find(|m| m.kind == MoveKind::Thread).unwrap();
        assert!((first.a.0 - 30.6).abs() < 1e-12);
        assert!((first.a.1 - (5.0 - 0.3 * t)).abs() < 1e-12);
    }
}
