//! Post-processors: a [`Plan`] as an NC program for FANUC (flat, or a compact Macro B loop),
//! GSK 980TDC, Siemens 802D (R parameters and labels) and LinuxCNC (chained G33), and the
//! toolpath each program must give back when vpcut's own interpreter reads it.
//!
//! Every program: the tool, the spindle (M03/M04 so that the tool feeds away from the face)
//! at the plan's rpm, coolant, a safe start outside the part, then per pass a rapid to the
//! run-in point at the clearance diameter, a rapid in to the pass's diameter, the thread
//! move to the run-out, and a rapid out; at the end coolant and spindle off. Comments say
//! what each layer and block does. Words are written in the control's increments (0.001 mm,
//! 0.0001 mm/rev; macro tables and LinuxCNC's chain in 1e-6), which the plan is already in,
//! so the program re-reads to exactly the planned passes.
//!
//! - FANUC: `G32 Z F` for a constant lead, `G34 Z F K` for a variable one.
//! - FANUC Macro B: the layers in tables (`#500+l` diameter, `#600+l` first position,
//!   `#700+l` step, `#800+l` count, `#900+l` lead step; `#100+s`, `#110+s`, `#120+s` the runs)
//!   and three nested `WHILE` loops that compute each pass with `ROUND`, as the plan does.
//!   At most 99 layers and 9 starts.
//! - GSK 980TDC: `G32 Z F` or `G34 Z F R` (R the lead change; no J/K run-out: the tool
//!   retracts after the run-out).
//! - Siemens 802D: per layer and start R parameters and a `GOTOB` loop over the positions;
//!   `G33 Z K`, `G34 Z K F` (increasing) or `G35 Z K F` (decreasing), F unsigned.
//! - LinuxCNC has no G34: a variable lead becomes chained `G33 Z K` blocks, each a constant
//!   lead over `1/n` revolution with `n >= sqrt(|K| / (2 tol))`, so that the chord of the
//!   helix (`K/(8 n^2)` off it) stays within a quarter of the tolerance; the spindle phase runs
//!   on from block to block.

use crate::gen::plan::{quantize, Plan, TABLE};
use crate::model::helix::{LeadLaw, Spindle};
use crate::model::pass::Pass;
use crate::nc::Dialect;
use std::fmt::Write;

/// Which program to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Post {
    /// FANUC lathe, one block group per pass.
    Fanuc,
    /// FANUC lathe, Custom Macro B loops over the layer tables.
    FanucMacro,
    /// GSK 980TDC.
    Gsk980,
    /// Siemens 802D.
    Siemens802d,
    /// LinuxCNC (chained G33).
    Linuxcnc,
}

impl Post {
    /// The post for a dialect name (`fanuc`, `gsk980`, `siemens-802d`, `linuxcnc`;
    /// `siemens-840d` gets the 802D program, which the 840D runs unchanged); `macro_b` picks
    /// FANUC's macro version.
    pub fn from_name(name: &str, macro_b: bool) -> Option<Post> {
        Some(match (Dialect::from_name(name)?, macro_b) {
            (Dialect::Fanuc, false) => Post::Fanuc,
            (Dialect::Fanuc, true) => Post::FanucMacro,
            (Dialect::Gsk980, false) => Post::Gsk980,
            // The 840D runs the 802D's programs unchanged (a superset).
            (Dialect::Siemens802d | Dialect::Siemens840d, false) => Post::Siemens802d,
            (Dialect::Linuxcnc, false) => Post::Linuxcnc,
            _ => return None,
        })
    }

    /// The dialect its programs are read in.
    pub fn dialect(self) -> Dialect {
        match self {
            Post::Fanuc | Post::FanucMacro => Dialect::Fanuc,
            Post::Gsk980 => Dialect::Gsk980,
            Post::Siemens802d => Dialect::Siemens802d,
            Post::Linuxcnc => Dialect::Linuxcnc,
        }
    }
}

/// Why a plan cannot be written.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct PostError(String);

/// The passes a program of `post` gives back: the plan's, or for LinuxCNC their chains.
pub fn toolpath(plan: &Plan, post: Post) -> Vec<Pass> {
    let passes = plan.passes();
    match post {
        Post::Linuxcnc => passes.iter().flat_map(|p| chain(p, plan)).collect(),
        _ => passes,
    }
}

/// Chained constant-lead segments of `p`: vertices on its helix every `1/n` revolution.
fn chain(p: &Pass, plan: &Plan) -> Vec<Pass> {
    if p.lead_change == 0.0 {
        return vec![p.clone()];
    }
    let n = (p.lead_change.abs() / (2.0 * plan.tolerance))
        .sqrt()
        .ceil()
        .max(1.0);
    let revs = p.revolutions().unwrap_or(0.0);
    let h = p.helix();
    let mut ts: Vec<f64> = (0..)
        .map(|i| f64::from(i) / n)
        .take_while(|t| *t < revs - 1e-9)
        .collect();
    ts.push(revs);
    let mut out = Vec::with_capacity(ts.len());
    let mut z = p.z_start;
    // The spindle's angle past the index pulse; the part angle under the tool is minus
    // that with M03, plus with M04 (`toolpath::lathe_passes`).
    let sign = p.spindle.sign();
    let mut angle_deg = (-sign * p.start_angle).to_degrees();
    for w in ts.windows(2) {
        let z_next = if w[1] == revs {
            p.z_end
        } else {
            quantize(h.z(w[1]), TABLE)
        };
        let lead = quantize((z_next - z).abs() / (w[1] - w[0]), TABLE);
        out.push(Pass {
            x_start: p.x_start,
            x_end: p.x_end,
            z_start: z,
            z_end: z_next,
            lead,
            lead_change: 0.0,
            start_angle: -sign * angle_deg.to_radians(),
            ..p.clone()
        });
        // The phase runs on as the interpreter runs it (`nc::chain`).
        let t = LeadLaw::constant(lead)
            .revs_at((z_next - z).abs())
            .unwrap_or(0.0);
        angle_deg = (angle_deg + 360.0 * t).rem_euclid(360.0);
        z = z_next;
    }
    out
}

/// Write `plan` as a program for `post`. `tool_id` is the tool's number (T word), `name`
/// the job's name for the header.
pub fn post(plan: &Plan, tool_id: u32, name: &str, post: Post) -> Result<String, PostError> {
    let mut w = Writer {
        out: String::new(),
        post,
    };
    let passes = plan.passes();
    let variable = plan.lead_change != 0.0;
    let z_safe = passes
        .iter()
        .map(|p| p.z_start)
        .fold(f64::NEG_INFINITY, f64::max);
    let (spin_m, spin_word) = match plan.spindle {
        Spindle::Cw => (3, "cw"),
        Spindle::Ccw => (4, "ccw"),
    };
    let rpm = plan.rpm.round();
    let summary = format!(
        "{} layers, {} passes, {} start(s), lead change {:.4} mm/rev2; line check: leftover {:.4} mm, gouge {:.4} mm",
        plan.layers.len(),
        passes.len(),
        plan.runs.len(),
        plan.lead_change,
        plan.check.max_leftover,
        plan.check.max_gouge
    );
    match post {
        Post::Fanuc | Post::FanucMacro | Post::Gsk980 => {
            w.line("%");
            w.block("O1000", &format!("vpcut plan: {name}"));
            w.comment(&summary);
            w.block("G21 G99 G97 G40", "mm, feed per revolution, constant rpm");
            w.block(&format!("T{tool_id:02}{tool_id:02}"), "threading tool");
            w.block(
                &format!("M{spin_m:02} S{rpm}"),
                &format!("spindle {spin_word}, {rpm} rpm"),
            );
            w.block("M08", "coolant on");
        }
        Post::Siemens802d => {
            w.comment(&format!("vpcut plan: {name}"));
            w.comment(&summary);
            w.block("G90 G95 G71", "absolute, feed per revolution, mm");
            w.block(&format!("T{tool_id} D1"), "threading tool");
            w.block(
                &format!("M{spin_m} S{rpm}"),
                &format!("spindle {spin_word}, {rpm} rpm"),
            );
            w.block("M8", "coolant on");
            w.block(&format!("R20={}", f3(plan.clear_x)), "clearance diameter");
            w.block(&format!("R21={}", f3(plan.z_end)), "run-out end");
        }
        Post::Linuxcnc => {
            w.line("%");
            w.comment(&format!("vpcut plan: {name}"));
            w.comment(&summary);
            w.block("G7 G18 G21 G90", "diameter mode, XZ plane, mm, absolute");
            w.block(&format!("T{tool_id}"), "threading tool");
            w.block(
                &format!("M{spin_m} S{rpm}"),
                &format!("spindle {spin_word}, {rpm} rpm"),
            );
            w.block("M8", "coolant on");
        }
    }
    let g0 = if post == Post::Siemens802d {
        "G0"
    } else {
        "G00"
    };
    w.block(
        &format!("{g0} X{} Z{}", f3(plan.clear_x), f3(z_safe)),
        "safe start outside the part",
    );
    match post {
        Post::FanucMacro => macro_b(&mut w, plan, variable)?,
        Post::Siemens802d => siemens(&mut w, plan),
        _ => {
            let mut k = 0;
            for (l, layer) in plan.layers.iter().enumerate() {
                w.comment(&layer_comment(l, plan));
                for s in 0..plan.runs.len() {
                    for j in 0..layer.count {
                        let p = plan.pass(l, s, j);
                        k += 1;
                        w.block(&format!("{g0} Z{}", f3(p.z_start)), "run-in start");
                        w.block(&format!("{g0} X{}", f3(p.x_start)), "in to depth");
                        thread(&mut w, plan, &p, k, s)?;
                        w.block(&format!("{g0} X{}", f3(plan.clear_x)), "out");
                    }
                }
            }
        }
    }
    match post {
        Post::Siemens802d => {
            w.block("M9", "coolant off");
            w.block("M5", "spindle stop");
            w.block("M30", "end");
        }
        Post::Linuxcnc => {
            w.block("M9", "coolant off");
            w.block("M5", "spindle stop");
            w.block("M2", "end");
            w.line("%");
        }
        _ => {
            w.block("M09", "coolant off");
            w.block("M05", "spindle stop");
            w.block("M30", "end");
            w.line("%");
        }
    }
    Ok(w.out)
}

/// The thread block(s) of one pass.
fn thread(w: &mut Writer, plan: &Plan, p: &Pass, k: usize, s: usize) -> Result<(), PostError> {
    let what = format!("pass {k}, start {}", s + 1);
    let ze = f3(p.z_end);
    match w.post {
        Post::Fanuc | Post::FanucMacro if p.lead_change == 0.0 => w.block(
            &format!("G32 Z{ze} F{}", f4(p.lead)),
            &format!("thread, {what}"),
        ),
        Post::Fanuc | Post::FanucMacro => w.block(
            &format!("G34 Z{ze} F{} K{}", f4(p.lead), f4(p.lead_change)),
            &format!("variable lead thread, {what}"),
        ),
        Post::Gsk980 if p.lead_change == 0.0 => w.block(
            &format!("G32 Z{ze} F{}", f4(p.lead)),
            &format!("thread, {what}"),
        ),
        Post::Gsk980 => w.block(
            &format!("G34 Z{ze} F{} R{}", f4(p.lead), f4(p.lead_change)),
            &format!("variable lead thread, {what}"),
        ),
        // Siemens passes are written by `siemens`, in its loop.
        Post::Siemens802d => {}
        Post::Linuxcnc => {
            let segs = chain(p, plan);
            let n = segs.len();
            for (i, c) in segs.iter().enumerate() {
                let note = if n == 1 {
                    format!("thread, {what}")
                } else if i == 0 {
                    format!("variable lead as {n} chained G33, {what}")
                } else {
                    String::new()
                };
                w.block(&format!("G33 Z{} K{}", f6(c.z_end), f6(c.lead)), &note);
            }
        }
    }
    Ok(())
}

fn layer_comment(l: usize, plan: &Plan) -> String {
    let layer = &plan.layers[l];
    format!(
        "layer {} ({}): tip {:.4} mm below the crest at X{}, {} position(s) per start",
        l + 1,
        layer.role.name(),
        layer.depth,
        f3(layer.x),
        layer.count
    )
}

/// FANUC Custom Macro B: the layer and run tables, then three loops.
fn macro_b(w: &mut Writer, plan: &Plan, variable: bool) -> Result<(), PostError> {
    if plan.layers.len() > 99 {
        return Err(PostError(format!(
            "the Macro B version holds 99 layers in its tables (#500-#999); this plan has {}: write the flat version",
            plan.layers.len()
        )));
    }
    if plan.runs.len() > 9 {
        return Err(PostError(
            "the Macro B version holds 9 starts (#101-#129): write the flat version".into(),
        ));
    }
    w.comment("layer tables: #500+L diameter, #600+L first position, #700+L step, #800+L count, #900+L lead step");
    for (l, layer) in plan.layers.iter().enumerate() {
        let i = l + 1;
        w.block(
            &format!(
                "#{}={} #{}={} #{}={} #{}={} #{}={}",
                500 + i,
                f3(layer.x),
                600 + i,
                f6(layer.shift),
                700 + i,
                f6(layer.step),
                800 + i,
                layer.count,
                900 + i,
                f6(layer.lead_step)
            ),
            &layer_comment(l, plan),
        );
    }
    w.comment("runs: #100+S run-in z, #110+S lead there, #120+S far-family spread");
    for (s, run) in plan.runs.iter().enumerate() {
        let i = s + 1;
        w.block(
            &format!(
                "#{}={} #{}={} #{}={}",
                100 + i,
                f6(run.z),
                110 + i,
                f6(run.lead),
                120 + i,
                f6(run.spread)
            ),
            &format!("start {i}"),
        );
    }
    let thread = if variable {
        format!("G34 Z{} F#6 K{}", f3(plan.z_end), f4(plan.lead_change))
    } else {
        format!("G32 Z{} F#6", f3(plan.z_end))
    };
    w.block("#1=1", "layer");
    w.line(&format!("WHILE[#1LE{}]DO1", plan.layers.len()));
    w.block("#2=1", "start");
    w.line(&format!("WHILE[#2LE{}]DO2", plan.runs.len()));
    w.block("#3=0", "position");
    w.block("#4=#[800+#1]-1", "positions - 1 (at least 1)");
    w.line("IF[#4LT1]THEN#4=1");
    w.line("WHILE[#3LT#[800+#1]]DO3");
    w.block(
        "#5=ROUND[[#[100+#2]+#[600+#1]+#3*[#[700+#1]+#[120+#2]/#4]]*1000]/1000",
        "run-in start z",
    );
    w.block(
        "#6=ROUND[[#[110+#2]+#3*#[900+#1]]*10000]/10000",
        "lead there",
    );
    w.block("G00 Z#5", "run-in start");
    w.block("G00 X#[500+#1]", "in to depth");
    w.block(&thread, "thread");
    w.block(&format!("G00 X{}", f3(plan.clear_x)), "out");
    w.line("#3=#3+1");
    w.line("END3");
    w.line("#2=#2+1");
    w.line("END2");
    w.line("#1=#1+1");
    w.line("END1");
    Ok(())
}

/// Siemens 802D: R parameters per layer and start, a label loop over the positions.
fn siemens(w: &mut Writer, plan: &Plan) {
    let thread = if plan.lead_change == 0.0 {
        "G33 Z=R21 K=R9".to_string()
    } else if plan.lead_change > 0.0 {
        format!("G34 Z=R21 K=R9 F={}", f4(plan.lead_change))
    } else {
        format!("G35 Z=R21 K=R9 F={}", f4(-plan.lead_change))
    };
    for (l, layer) in plan.layers.iter().enumerate() {
        w.comment(&layer_comment(l, plan));
        w.block(
            &format!(
                "R1={} R2={} R3={} R4={} R5={} R7={}",
                f3(layer.x),
                f6(layer.shift),
                f6(layer.step),
                f6(layer.lead_step),
                layer.count,
                layer.count.saturating_sub(1).max(1)
            ),
            "diameter, first position, step, lead step, positions, steps",
        );
        for (s, run) in plan.runs.iter().enumerate() {
            w.block(
                &format!(
                    "R10={} R11={} R12={} R6=0",
                    f6(run.z),
                    f6(run.lead),
                    f6(run.spread)
                ),
                &format!(
                    "start {}: run-in z, lead there, spread; first position",
                    s + 1
                ),
            );
            let label = format!("LY{}S{}", l + 1, s + 1);
            w.line(&format!("{label}:"));
            w.block(
                "R8=ROUND((R10+R2+R6*(R3+R12/R7))*1000)/1000",
                "run-in start z",
            );
            w.block("R9=ROUND((R11+R6*R4)*10000)/10000", "lead there");
            w.block("G0 Z=R8", "run-in start");
            w.block("G0 X=R1", "in to depth");
            w.block(&thread, "thread");
            w.block("G0 X=R20", "out");
            w.line("R6=R6+1");
            w.block(&format!("IF R6<R5 GOTOB {label}"), "next position");
        }
    }
}

/// A program being written.
struct Writer {
    out: String,
    post: Post,
}

impl Writer {
    fn line(&mut self, s: &str) {
        self.out.push_str(s);
        self.out.push('\n');
    }

    /// A block with a comment in the dialect's syntax.
    fn block(&mut self, code: &str, note: &str) {
        if note.is_empty() {
            return self.line(code);
        }
        let _ = match self.post {
            Post::Siemens802d => writeln!(self.out, "{code} ; {note}"),
            Post::Fanuc | Post::FanucMacro | Post::Gsk980 => {
                writeln!(self.out, "{code} ({})", fanuc_comment(note))
            }
            Post::Linuxcnc => writeln!(self.out, "{code} ({})", note.replace(['(', ')'], "")),
        };
    }

    fn comment(&mut self, note: &str) {
        let _ = match self.post {
            Post::Siemens802d => writeln!(self.out, "; {note}"),
            Post::Fanuc | Post::FanucMacro | Post::Gsk980 => {
                writeln!(self.out, "({})", fanuc_comment(note))
            }
            Post::Linuxcnc => writeln!(self.out, "({})", note.replace(['(', ')'], "")),
        };
    }
}

/// FANUC comments: upper case, no nested parentheses.
fn fanuc_comment(s: &str) -> String {
    s.replace(['(', ')'], "").to_uppercase()
}

fn f3(v: f64) -> String {
    format!("{v:.3}")
}

fn f4(v: f64) -> String {
    format!("{v:.4}")
}

fn f6(v: f64) -> String {
    format!("{v:.6}")
}

/// A plan in words: its layers, passes, runs and check, for the terminal.
pub fn summary(plan: &Plan, post: Post) -> String {
    let passes = toolpath(plan, post).len();
    let planned = plan.passes().len();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "plan: {} layers, {planned} passes ({} start(s)){}",
        plan.layers.len(),
        plan.runs.len(),
        if passes != planned {
            format!(", written as {passes} chained blocks")
        } else {
            String::new()
        }
    );
    if let Some(n) = plan.seed002_passes {
        let _ = writeln!(
            s,
            "  seed 002's method over the same layers: {n} passes (R11 + 1 per layer)"
        );
    }
    let _ = writeln!(
        s,
        "  run-in {:.3} mm, run-out {:.3} mm past the thread, spindle {} {} rpm, lead change {} mm/rev^2",
        plan.run_in,
        plan.run_out,
        match plan.spindle {
            Spindle::Cw => "cw (M03)",
            Spindle::Ccw => "ccw (M04)",
        },
        plan.rpm,
        plan.lead_change
    );
    let _ = writeln!(
        s,
        "  line check (4 generators, 0.004 mm): leftover {:.4} mm, gouge {:.4} mm, thickest chip along the radius {:.4} mm (tolerance {} mm)",
        plan.check.max_leftover, plan.check.max_gouge, plan.check.max_chip, plan.tolerance
    );
    let _ = writeln!(s, "  layer  role     depth       X  positions");
    for (l, layer) in plan.layers.iter().enumerate() {
        let _ = writeln!(
            s,
            "  {:>5}  {:<7} {:>6.3} {:>8.3}  {:>9}",
            l + 1,
            layer.role.name(),
            layer.depth,
            layer.x,
            layer.count
        );
    }
    s
}

/// Where the passes a program gave back differ from the planned ones (beyond 1e-9 mm,
/// mm/rev or rad), or `None`.
pub fn differ(planned: &[Pass], read: &[Pass]) -> Option<String> {
    if planned.len() != read.len() {
        return Some(format!(
            "the program gives {} passes, the plan has {}",
            read.len(),
            planned.len()
        ));
    }
    for (i, (a, b)) in planned.iter().zip(read).enumerate() {
        let angle = (a.start_angle - b.start_angle).rem_euclid(std::f64::consts::TAU);
        let angle = angle.min(std::f64::consts::TAU - angle);
        let close = [
            (a.x_start, b.x_start),
            (a.x_end, b.x_end),
            (a.z_start, b.z_start),
            (a.z_end, b.z_end),
            (a.lead, b.lead),
            (a.lead_change, b.lead_change),
        ]
        .iter()
        .all(|(u, v)| (u - v).abs() <= 1e-9)
            && angle <= 1e-9
            && a.tool == b.tool
            && a.spindle == b.spindle;
        if !close {
            return Some(format!(
                "pass {}: planned {}; read {}",
                i + 1,
                pass_text(a),
                pass_text(b)
            ));
        }
    }
    None
}

/// A pass in the words of a program: its diameters, z span, lead, start angle, tool and
/// spindle direction.
fn pass_text(p: &Pass) -> String {
    let change = if p.lead_change != 0.0 {
        format!(" changing {:.6} per rev", p.lead_change)
    } else {
        String::new()
    };
    format!(
        "X{:.4} to X{:.4}, Z{:.4} to Z{:.4}, lead {:.6}{change}, start angle {:.3} deg, tool[{}], {}",
        p.x_start,
        p.x_end,
        p.z_start,
        p.z_end,
        p.lead,
        p.start_angle.to_degrees(),
        p.tool,
        match p.spindle {
            crate::model::helix::Spindle::Cw => "M03",
            crate::model::helix::Spindle::Ccw => "M04",
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::helix::Spindle;

    #[test]
    fn a_difference_is_said_in_a_programs_words() {
        let a = Pass {
            tool: 0,
            x_start: 27.546,
            x_end: 27.546,
            z_start: 5.0,
            z_end: -36.0,
            lead: 2.0,
            lead_change: 0.0,
            start_angle: 0.0,
            spindle: Spindle::Cw,
        };
        let b = Pass {
            lead: 2.1,
            ..a.clone()
        };
        let msg = differ(std::slice::from_ref(&a), &[b]).expect("a difference");
        assert_eq!(
            msg,
            "pass 1: planned X27.5460 to X27.5460, Z5.0000 to Z-36.0000, lead 2.000000, start angle 0.000 deg, tool[0], M03; read X27.5460 to X27.5460, Z5.0000 to Z-36.0000, lead 2.100000, start angle 0.000 deg, tool[0], M03"
        );
        assert_eq!(
            differ(std::slice::from_ref(&a), std::slice::from_ref(&a)),
            None
        );
    }
}
