//! The insert's limits, pass by pass: the radial depth each threading pass cuts (its chip)
//! against the insert's `depth_per_pass`, and a threading cycle's infeed angle against the
//! insert's flanks.
//!
//! **Chip depth.** A pass's radial chip is how much deeper its tip runs than the deepest
//! material it removes: the tip's radius against the lowest point of the stock the pass
//! cuts into, on the stock the passes before it (and the turned profile) left, wherever
//! its tip is in the material and was one revolution before (the first revolution into
//! the part meets the earlier passes' groove as a ramp from nothing at the part's face:
//! with flank infeed up to twice the infeed there; that is the pass entering the part, not
//! its infeed). With radial
//! infeed that is the depth increment; with flank infeed (G76's `a/2`), where the tip moves
//! sideways onto the old leading flank, it is still the depth increment (the old tip lies
//! under the new trailing flank, the deepest point the new pass touches); the first pass's
//! chip is its depth under the crest. The stock is a line model ([`LineModel`]): four
//! generators, every pass's edge profile placed at each of its crossings of a generator in
//! program order, cells [`SPACING`] apart; the new tip is exact, and the only
//! discretisation is that the old groove's lowest cell stands up to `SPACING cot(flank)`
//! above its exact bottom: a flank infeed's chip comes out over by at most that (0.0035 mm
//! for 60 deg), a flat-tipped insert's radial infeed's exactly.
//!
//! **Infeed angle.** Two passes of one threading cycle's block (G76, CYCLE97, LinuxCNC
//! G76) on the same helix, the second deeper by `dr` and shifted along z by `dz`, infeed at
//! `atan(|dz| / dr)` from the radial. The flank on the side away from the shift runs along
//! the wall the pass before cut: at an infeed angle equal to that flank's angle the edge
//! slides along the wall, its clearance behind it (pure flank infeed, FANUC G76 with `a`
//! the insert's angle: the usual use, not flagged; Sandvik Coromant's threading guide
//! prefers a modified flank infeed 3 to 5 deg under the flank angle); beyond it the edge is
//! fed into the wall past its clearance and rubs: a warning at the block.

use crate::analysis::checks::MachineIssue;
use crate::analysis::findings::FindingKind;
use crate::kernel::turn::{Turned, TurningTool};
use crate::model::pass::Pass;
use crate::model::tool::Tool;
use std::f64::consts::TAU;

/// The line model's axial spacing (mm).
pub(crate) const SPACING: f64 = 0.002;

/// Generators of the line model, equally spaced from angle 0.
const GENERATORS: usize = 4;

/// The chip of one pass: its radial depth (mm) and where its tip cut it deepest (z, mm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Chip {
    /// Radial depth (mm); 0 when the pass cut nothing (in the air, or a spring pass).
    pub(crate) depth: f64,
    /// z of the tip there (mm).
    pub(crate) z: f64,
}

/// The surface the passes cut and the stock on it before them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface<'a> {
    /// 1 outside, -1 in the bore (`q = sense r`).
    pub(crate) sense: f64,
    /// The blank's `q`.
    pub(crate) q_blank: f64,
    /// The lowest `q` material can have.
    pub(crate) q_floor: f64,
    /// The blank's axial span (no material beyond it).
    pub(crate) z_span: (f64, f64),
    /// The program's turned profile on it.
    pub(crate) turned: &'a Turned,
}

/// The radial chip of every pass, in order ([`Chip`]), on the line model.
pub(crate) fn pass_chips(passes: &[Pass], tools: &[Tool], s: Surface) -> Vec<Chip> {
    let mut chips = vec![Chip::default(); passes.len()];
    let Some(model) = LineModel::new(passes, tools, s) else {
        return chips;
    };
    for g in 0..GENERATORS {
        let theta = TAU * g as f64 / GENERATORS as f64;
        let mut old = model.initial(s);
        for (p, chip) in passes.iter().zip(chips.iter_mut()) {
            let c = model.cut(&mut old, p, &tools[p.tool], theta, s);
            if c.depth > chip.depth {
                *chip = c;
            }
        }
    }
    chips
}

/// The cells of the line model: `z0 + j SPACING`, over the passes' spans and the tools'
/// reach beside them.
struct LineModel {
    z0: f64,
    n: usize,
}

impl LineModel {
    fn new(passes: &[Pass], tools: &[Tool], s: Surface) -> Option<LineModel> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in passes {
            let tool = &tools[p.tool];
            let reach = (s.q_blank - s.sense * p.x_start / 2.0)
                .abs()
                .max((s.q_blank - s.sense * p.x_end / 2.0).abs());
            let (vl, vr) = tool.span(reach);
            let off = tool.reference_offset();
            lo = lo.min(p.z_start.min(p.z_end) - off + vl);
            hi = hi.max(p.z_start.max(p.z_end) - off + vr);
        }
        if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
            return None;
        }
        // A bound on the work: a line longer than 4 m (2e6 cells) is not modelled.
        let n = ((hi - lo) / SPACING).ceil() as usize + 1;
        (n <= 2_000_000).then_some(LineModel { z0: lo, n })
    }

    /// The stock on a generator before the passes: the blank as the turning moves left it.
    fn initial(&self, s: Surface) -> Vec<f64> {
        let col = s
            .turned
            .profile(self.n, self.z0, SPACING, s.q_blank, s.q_floor);
        col.iter()
            .enumerate()
            .map(|(j, &v)| {
                let z = self.z0 + SPACING * j as f64;
                if (s.z_span.0..=s.z_span.1).contains(&z) {
                    s.q_blank + f64::from(v)
                } else {
                    s.q_floor
                }
            })
            .collect()
    }

    /// Cut `old` with pass `p` of `tool` on the generator at `theta`; its chip there.
    fn cut(&self, old: &mut [f64], p: &Pass, tool: &Tool, theta: f64, s: Surface) -> Chip {
        let Some(revs) = p.revolutions() else {
            return Chip::default();
        };
        let helix = p.helix();
        let off = tool.reference_offset();
        let kernel = tool.kernel();
        let mut chip = Chip::default();
        let mut in_before = false;
        for t in helix.crossings(theta, 0.0, revs) {
            let z = helix.z(t);
            let c = z - off;
            let q_tip = s.sense * p.radius_at(z);
            let (vl, vr) = tool.span((s.q_blank - q_tip).max(0.0) + 1e-9);
            let a = ((c + vl - self.z0) / SPACING).floor().max(0.0) as usize;
            let b = ((((c + vr - self.z0) / SPACING).ceil()).max(0.0) as usize + 1).min(self.n);
            // The lowest old point the pass removes material at, where its tip is in the
            // material and was a revolution before: the first revolution into the part
            // (beside its face, or after a groove) meets the groove the passes before cut
            // as a ramp from nothing, not their infeed.
            let j_tip = ((c - self.z0) / SPACING).round();
            let was_in = std::mem::replace(
                &mut in_before,
                (j_tip >= 0.0 && (j_tip as usize) < self.n)
                    && old[j_tip as usize] > s.q_floor + 1e-9,
            );
            let mut deepest = f64::INFINITY;
            let mut tip_in = false;
            for (j, q) in old.iter_mut().enumerate().take(b).skip(a) {
                let new = q_tip + kernel.height(self.z0 + SPACING * j as f64 - c);
                if new < *q - 1e-9 {
                    deepest = deepest.min(*q);
                    tip_in |= j as f64 == j_tip;
                    *q = new.max(s.q_floor);
                }
            }
            if tip_in && was_in && deepest - q_tip > chip.depth {
                chip = Chip {
                    depth: deepest - q_tip,
                    z,
                };
            }
        }
        chip
    }
}

/// A threading cycle's infeed that makes a flank's edge rub: the block's first such pair
/// of passes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct InfeedRub {
    /// The deeper pass of the pair (index).
    pub(crate) pass: usize,
    /// The infeed angle from the radial (rad).
    pub(crate) infeed: f64,
    /// The angle of the flank that follows the wall (rad, from the radial).
    pub(crate) flank: f64,
    /// The flank that rubs is the trailing one (on the side away from the feed), else the
    /// leading one.
    pub(crate) trailing: bool,
}

/// Every threading cycle block's infeed that rubs a flank: consecutive passes of one
/// cycle block (`blocks[i]`, `cycle[i]`), tool and helix (lead, lead change, start angle,
/// direction), the second deeper and shifted alike at both ends.
pub(crate) fn infeed_rubs(
    passes: &[Pass],
    tools: &[Tool],
    blocks: &[(usize, String, usize)],
    cycle: &[bool],
    sense: f64,
) -> Vec<InfeedRub> {
    // Each pass's block, by pass index (passes without one, listed in the job: none).
    let mut of_pass: Vec<Option<(&String, usize)>> = vec![None; passes.len()];
    for b in blocks {
        if let Some(slot) = of_pass.get_mut(b.0) {
            *slot = Some((&b.1, b.2));
        }
    }
    let block = |i: usize| of_pass[i];
    let mut out: Vec<InfeedRub> = Vec::new();
    let mut flagged: Vec<(&String, usize)> = Vec::new();
    for i in 1..passes.len() {
        let (a, b) = (&passes[i - 1], &passes[i]);
        if !(cycle.get(i - 1).copied().unwrap_or(false) && cycle.get(i).copied().unwrap_or(false)) {
            continue;
        }
        let (Some(ba), Some(bb)) = (block(i - 1), block(i)) else {
            continue;
        };
        let same = ba == bb
            && a.tool == b.tool
            && a.lead == b.lead
            && a.lead_change == b.lead_change
            && a.start_angle == b.start_angle
            && a.spindle == b.spindle
            && (a.z_end - a.z_start).signum() == (b.z_end - b.z_start).signum();
        if !same || flagged.contains(&bb) {
            continue;
        }
        let dr = sense * (a.x_start - b.x_start) / 2.0;
        let dz = b.z_start - a.z_start;
        let parallel = ((b.z_end - a.z_end) - dz).abs() < 1e-9
            && (sense * (a.x_end - b.x_end) / 2.0 - dr).abs() < 1e-9;
        if dr <= 1e-9 || !parallel || dz.abs() >= a.lead / 2.0 {
            continue;
        }
        let infeed = (dz.abs() / dr).atan();
        // The flank away from the shift follows the old wall: the +z flank when the pass
        // moved towards -z.
        let shape = TurningTool::insert(&tools[a.tool], sense < 0.0);
        let (flank, plus_side) = if dz < 0.0 {
            (shape.trail_angle, true)
        } else {
            (shape.lead_angle, false)
        };
        // Beyond the flank by more than a micro-radian (the rounding of the shifts).
        if infeed > flank + 1e-6 {
            let feed_towards_minus = a.z_end < a.z_start;
            out.push(InfeedRub {
                pass: i,
                infeed,
                flank,
                trailing: plus_side == feed_towards_minus,
            });
            flagged.push(bb);
        }
    }
    out
}

/// The passes whose chip is over the insert's `max` (an error: the insert breaks) or, where
/// the pass cut something, under its `min` (a warning: it rubs rather than cuts).
/// `names` gives each pass's tool as the program wrote it (`T0202`).
pub(crate) fn depth_issues(
    passes: &[Pass],
    tools: &[Tool],
    chips: &[Chip],
    names: &dyn Fn(usize) -> String,
) -> Vec<MachineIssue> {
    let mut out = Vec::new();
    for (i, (p, c)) in passes.iter().zip(chips).enumerate() {
        let tool = &tools[p.tool];
        let limits = tool.depth_per_pass;
        let issue = |error: bool, limit: f64| MachineIssue {
            kind: FindingKind::DepthPerPass,
            error,
            pass: i,
            z: c.z,
            value: c.depth,
            limit,
            message: if error {
                format!(
                    "pass {}: a radial chip of {:.4} mm, over the {limit} mm that the insert of {} stands ([[tool]] max_depth_per_pass)",
                    i + 1,
                    c.depth,
                    names(i)
                )
            } else {
                format!(
                    "pass {}: a radial chip of {:.4} mm, under the {limit} mm the insert of {} needs to cut rather than rub ([[tool]] min_depth_per_pass)",
                    i + 1,
                    c.depth,
                    names(i)
                )
            },
        };
        if let Some(max) = limits.max.filter(|&m| c.depth > m + 1e-9) {
            out.push(issue(true, max));
        } else if let Some(min) = limits.min.filter(|&m| c.depth > 1e-6 && c.depth < m - 1e-9) {
            out.push(issue(false, min));
        }
    }
    out
}

/// The infeeds that rub, as warnings.
pub(crate) fn rub_issues(passes: &[Pass], rubs: &[InfeedRub]) -> Vec<MachineIssue> {
    rubs.iter()
        .map(|r| MachineIssue {
            kind: FindingKind::InfeedAngle,
            error: false,
            pass: r.pass,
            z: passes[r.pass].z_start,
            value: r.infeed.to_degrees(),
            limit: r.flank.to_degrees(),
            message: format!(
                "pass {}: the cycle's infeed runs {:.2} deg from the radial, beyond the {} flank's {:.2} deg: that edge is fed into the flank the pass before cut and rubs (an infeed at most the flank angle, better 3 to 5 deg under it, keeps it off)",
                r.pass + 1,
                r.infeed.to_degrees(),
                if r.trailing { "trailing" } else { "leading" },
                r.flank.to_degrees(),
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests;
