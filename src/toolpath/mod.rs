//! The program stage: step 2 of loading a job, after the job file is parsed
//! (`crate::job`). It interprets the job's NC program ([`crate::nc`]) and turns the
//! interpreted moves into what the kernels cut:
//!
//! - on a lathe, every thread move into a [`Pass`], with the [`ChainLink`]s of continuous
//!   thread chains and the block each pass comes from ([`lathe_passes`]);
//! - on a lathe, every feed and arc move of a turning tool into a [`TurnCut`] of the
//!   surface it turns, and every rapid of one checked against the stock turned so far
//!   ([`lathe_turning`]);
//! - on a mill, the milling moves into the kernel's [`MillPath`] in the part's frame
//!   (`mill::mill_path`);
//! - a lathe program's cycle time from its moves and dwells (`cycle::cycle_time`);
//! - a tap's strokes (thread moves on the axis) into passes of its tooth (`tap`).
//!
//! It knows the job only through what it is given (the program to run, the tools or
//! cutters, the machine's axis and speed) and does no IO: the program's text and its
//! subprograms come from the caller's loader.

use crate::kernel::holder::{self, Mount};
use crate::kernel::turn::{Profile, TurnCut, TurnPath, Turned, TurningTool};
use crate::model::part::PartProfile;
use crate::model::pass::Pass;
use crate::model::setup::ChainLink;
use crate::model::tool::{Holder, Tap, Tool};
use crate::nc::{self, Dialect, MoveKind, NcError, Source, Toolpath};

mod cycle;
mod mill;
mod tap;
pub(crate) use cycle::cycle_time;
pub(crate) use mill::{mill_path, MillSetup};
pub(crate) use tap::TapFeed;

/// A program to run: the file the job names, its dialect and the interpreter's options.
#[derive(Clone, Debug)]
pub(crate) struct Program {
    /// The file, as the job names it (the loader's name for it).
    pub(crate) file: String,
    /// The control's dialect.
    pub(crate) dialect: Dialect,
    /// Strictness, limits and the machine's settings.
    pub(crate) options: nc::Options,
}

/// Why a program gives no passes or path.
#[derive(Debug)]
pub(crate) enum ProgramError {
    /// The loader has no text for the program file.
    Unreadable(String),
    /// The interpreter stopped.
    Nc(Box<NcError>),
    /// A move that cannot be cut; it names its block as a whole.
    Move {
        /// The program file.
        file: String,
        /// 1-based line of the block.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A milling path that needs more samples than the kernel takes.
    Samples(usize),
}

/// Read `program` (and its subprograms) through `load` and interpret it.
pub(crate) fn interpret(
    program: &Program,
    load: &dyn Fn(&str) -> Option<String>,
) -> Result<Toolpath, ProgramError> {
    let text = load(&program.file).ok_or_else(|| ProgramError::Unreadable(program.file.clone()))?;
    let main = Source {
        name: program.file.clone(),
        text,
    };
    let loader = |name: &str| {
        load(name).map(|text| Source {
            name: name.to_string(),
            text,
        })
    };
    nc::interpret_with(&main, program.dialect, &loader, &program.options)
        .map_err(|e| ProgramError::Nc(Box::new(e)))
}

/// What a lathe program gives: its passes, the joints of its thread chains (pass indices
/// counted from the program's first pass), each pass's thread block, and the warnings of
/// the blocks it leaves out.
#[derive(Debug, Default)]
pub(crate) struct LathePasses {
    /// The passes, in program order.
    pub(crate) passes: Vec<Pass>,
    /// The joints of continuous thread chains.
    pub(crate) links: Vec<ChainLink>,
    /// Each pass's thread block: file and 1-based line.
    pub(crate) blocks: Vec<(String, usize)>,
    /// Each pass's spindle speed as the program set it (rev/min; under G96 at the pass's
    /// smaller diameter, where it turns fastest), `None` where it set none.
    pub(crate) rpm: Vec<Option<f64>>,
    /// Each pass is a threading cycle's (`nc::Move::cycle`).
    pub(crate) cycle: Vec<bool>,
    /// Each pass's tool as the program wrote it (`nc::Move::tool_word`).
    pub(crate) tool_words: Vec<Option<String>>,
    /// Warnings about blocks as a whole (a tap's blocks without a tap tool), in program
    /// order.
    pub(crate) warnings: Vec<StageWarning>,
    /// The tap strokes whose feed is not the tap's pitch, one a block.
    pub(crate) tap_feeds: Vec<TapFeed>,
}

/// A warning of the program stage about a block as a whole (its column is 0).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StageWarning {
    /// The program file.
    pub(crate) file: String,
    /// 1-based line of the block.
    pub(crate) line: usize,
    /// What it is about.
    pub(crate) message: String,
    /// What to do about it.
    pub(crate) hint: String,
}

/// Turn a lathe program's thread moves into passes of `tools` (by the move's T number, or
/// the only tool). A chained move's sync angle already continues the previous move's phase
/// (`nc::chain`), so every pass is built the same way.
pub(crate) fn lathe_passes(
    moves: &[nc::Move],
    tools: &[Tool],
    turning: &[TurningTool],
    taps: &[Tap],
) -> Result<LathePasses, ProgramError> {
    let fail = |m: &nc::Move, message: String| ProgramError::Move {
        file: m.file.clone(),
        line: m.line,
        message,
    };
    let mut out = LathePasses::default();
    // Each tap's direction into the hole: that of its first stroke.
    let mut tap_dirs: std::collections::HashMap<u32, f64> = std::collections::HashMap::new();
    // A thread move that goes nowhere (a repeated block) cuts nothing.
    let goes = |m: &&nc::Move| m.z != m.z_start || m.x_dia != m.x_start;
    for m in moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .filter(goes)
    {
        // A thread move along the spindle axis is a tap's (G84, G33.1, G331/G332, CYCLE84,
        // G32 at X0): with a `kind = "tap"` tool its inward strokes become passes of the
        // tap's tooth (`tap`); without one, a threading tool's pass there would cut the
        // whole part away, so the block is left out with a warning (once a block).
        if m.x_start.abs() < 1e-9 && m.x_dia.abs() < 1e-9 {
            let Some(tap) = m.tool.and_then(|id| taps.iter().find(|t| t.id == id)) else {
                let seen = out
                    .warnings
                    .iter()
                    .any(|w| (w.file.as_str(), w.line) == (m.file.as_str(), m.line));
                if !seen {
                    out.warnings.push(StageWarning {
                        file: m.file.clone(),
                        line: m.line,
                        message: "tapping (a thread move along the spindle axis, X0) is not simulated with a tool that is not a tap (kind = \"tap\"): this block's moves cut nothing".into(),
                        hint: "give the tap as a [[tool]] with kind = \"tap\" (diameter, pitch, chamfer_length or chamfer_threads) and the T number the program selects".into(),
                    });
                }
                continue;
            };
            let dir = if m.z < m.z_start { -1.0 } else { 1.0 };
            let inward = *tap_dirs.entry(tap.id).or_insert(dir);
            if dir != inward {
                // The way out on the same helix cuts nothing more.
                continue;
            }
            let lead = m.lead.unwrap_or(0.0);
            if (lead - tap.pitch).abs() > tap::FEED_TOLERANCE
                && !out
                    .tap_feeds
                    .iter()
                    .any(|f| (f.file.as_str(), f.line) == (m.file.as_str(), m.line))
            {
                out.tap_feeds.push(TapFeed {
                    file: m.file.clone(),
                    line: m.line,
                    feed: lead,
                    pitch: tap.pitch,
                });
            }
            let tool = tools
                .iter()
                .position(|t| t.id == tap.id)
                .expect("a tap's tooth is in the tool list");
            for pass in tap::stroke_passes(m, tap, tool).map_err(|e| fail(m, e))? {
                out.blocks.push((m.file.clone(), m.line));
                out.rpm.push(m.speed.at(pass.x_end.abs()));
                out.cycle.push(m.cycle);
                out.tool_words
                    .push(m.tool_word.as_deref().map(str::to_string));
                out.passes.push(pass);
            }
            continue;
        }
        let tool = match m.tool {
            Some(id) => tools.iter().position(|t| t.id == id),
            None if tools.len() == 1 => Some(0),
            None => None,
        }
        .ok_or_else(|| match m.tool {
            None => fail(
                m,
                "a thread move without a T word in a job with several [[tool]]s: select the threading tool with a T word".into(),
            ),
            Some(t) => {
                let why = if turning.iter().any(|tt| tt.id == t) {
                    "a turning tool (kind = \"turning\"): threading needs a threading tool"
                } else {
                    "which the job's [[tool]] list does not define"
                };
                fail(m, format!("threading with {}, {why}", tool_and_id(m.tool_name(), t)))
            }
        })?;
        let angle = m.sync_angle_deg.unwrap_or(0.0).to_radians();
        let pass = Pass {
            tool,
            x_start: m.x_start,
            x_end: m.x_dia,
            z_start: m.z_start,
            z_end: m.z,
            lead: m.lead.unwrap_or(0.0),
            lead_change: m.lead_change.unwrap_or(0.0),
            // The thread starts `angle` past the index pulse; the part turns under the
            // tool, so the part angle under it is -angle with M03 and +angle with M04.
            start_angle: -m.spindle.sign() * angle,
            spindle: m.spindle,
        };
        if pass.lead <= 0.0 || pass.z_start == pass.z_end || pass.revolutions().is_none() {
            return Err(fail(m, format!("threading move to z = {}: the lead is not positive all the way (a real control alarms)", m.z)));
        }
        if m.chained {
            if let Some(prev) = out.passes.last() {
                out.links.push(ChainLink {
                    pass: out.passes.len(),
                    file: m.file.clone(),
                    line: m.line,
                    z: pass.z_start,
                    lead_before: prev.end_lead().unwrap_or(prev.lead),
                    change_before: prev.lead_change,
                    lead_after: pass.lead,
                    change_after: pass.lead_change,
                });
            }
        }
        out.blocks.push((m.file.clone(), m.line));
        out.rpm
            .push(m.speed.at(pass.x_start.abs().min(pass.x_end.abs())));
        out.cycle.push(m.cycle);
        out.tool_words
            .push(m.tool_word.as_deref().map(str::to_string));
        out.passes.push(pass);
    }
    Ok(out)
}

/// A tool as the program wrote it and, where that is not plainly the job's `[[tool]]` id,
/// the id the job must give it: `T0505 (id 5)`, `T="GEW" (id 1000: a tool named in the
/// program is numbered 1000, 1001, .. in the order first named)`, `T5`.
pub(crate) fn tool_and_id(word: String, id: u32) -> String {
    if word.starts_with("T=\"") {
        format!("{word} (id {id} in [[tool]]: tools named in the program are numbered 1000, 1001, .. in the order first named)")
    } else if word == format!("T{id}") {
        word
    } else {
        format!("{word} (id {id} in [[tool]])")
    }
}

/// How many times the blank's size a program's coordinates must exceed (or fall short
/// of) to be read as written for other units: two orders of magnitude. A tool change point
/// or a G53 machine position is often ten blank diameters away; a standard-input program
/// read as calculator-type (`X60640`) is a thousand.
const ORDERS: f64 = 100.0;

/// The hint of a program whose numbers are off the blank by orders of magnitude.
const UNITS_HINT: &str = "the program's numbers are likely read in the wrong units: check [program] decimal_point (\"standard\": X30 is 0.030 mm; \"calculator\": 30 mm), input_increment (0.001 or 0.0001 mm) and units (\"mm\" or \"inch\" at power-on)";

/// Warnings when a lathe program's coordinates are orders of magnitude off a blank of
/// diameter `diameter` over `z_span` (mm): the first move that ends more than [`ORDERS`]
/// times the blank's size away from it, and thread moves that all stay within a
/// hundredth of the blank's diameter from the axis (not taps on it). Either is what a
/// program read with the wrong decimal-point input, least input increment or units does.
pub(crate) fn scale_warnings(
    moves: &[nc::Move],
    diameter: f64,
    z_span: (f64, f64),
) -> Vec<StageWarning> {
    let mut out = Vec::new();
    let size = diameter.max(z_span.1 - z_span.0);
    let far = moves.iter().find(|m| {
        m.x_dia.abs() > ORDERS * diameter
            || m.z > z_span.1 + ORDERS * size
            || m.z < z_span.0 - ORDERS * size
    });
    if let Some(m) = far {
        out.push(StageWarning {
            file: m.file.clone(),
            line: m.line,
            message: format!(
                "this move ends at X{} Z{}, more than {ORDERS} times the blank's size ({diameter} mm diameter, {} mm long) away from it",
                round(m.x_dia),
                round(m.z),
                round(z_span.1 - z_span.0)
            ),
            hint: UNITS_HINT.into(),
        });
    }
    let threads: Vec<&nc::Move> = moves
        .iter()
        .filter(|m| m.kind == MoveKind::Thread)
        .filter(|m| m.x_start.abs() >= 1e-9 || m.x_dia.abs() >= 1e-9)
        .collect();
    let widest = threads
        .iter()
        .map(|m| m.x_start.abs().max(m.x_dia.abs()))
        .fold(0.0, f64::max);
    if let Some(m) = threads.first().filter(|_| widest < diameter / ORDERS) {
        out.push(StageWarning {
            file: m.file.clone(),
            line: m.line,
            message: format!(
                "every thread move lies within {} mm of the axis (diameter) of a blank {diameter} mm across: the thread is cut nowhere near the blank",
                round(widest)
            ),
            hint: UNITS_HINT.into(),
        });
    }
    out
}

/// A coordinate for a message (at most 4 decimals, no trailing zeros).
fn round(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// The stock one surface had before the program: the blank's signed radius `q_blank` over
/// the blank's axial span, and the floor no cut goes below (the other surface).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TurnStock {
    /// The blank's signed radius (`r` outside, `-r` in the bore).
    pub(crate) q_blank: f64,
    /// The lowest signed radius material can have (the bore, or minus the outside).
    pub(crate) q_floor: f64,
}

/// What a tool is for its moves that are not threading passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// A turning or boring insert (`kind = "turning"`).
    Turning,
    /// A square grooving insert: its feed moves cut grooves.
    Grooving,
    /// A threading insert: it cuts along the thread only; a feed move or a synchronised
    /// radial entry into material is a crash.
    Threading,
}

/// A tool of a lathe program: its shape as its moves sweep it, and its role.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LatheTool {
    /// The shape, driven as the program drives it.
    pub(crate) shape: TurningTool,
    /// What it is for.
    pub(crate) role: Role,
    /// What holds it (`[[tool]] holder`), if given.
    pub(crate) holder: Option<Holder>,
}

/// What a move that met material was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum HitKind {
    /// A rapid (G00, or a cycle's rapid).
    Rapid,
    /// A feed or arc move of a threading insert.
    Feed,
    /// A thread move of a threading insert that goes more into the part than along it (a
    /// synchronised radial entry).
    Entry,
    /// Any move whose tool's holder meets the stock as the move leaves it.
    Holder,
    /// Any move whose tool or holder meets the chuck or its jaws.
    Chuck,
}

/// A move that meets material left at its time and must not: a rapid of any tool, a feed
/// move or a synchronised radial entry of a threading insert.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RapidHit {
    /// The program file and 1-based line of the block.
    pub(crate) file: String,
    /// 1-based line.
    pub(crate) line: usize,
    /// How deep its tool's shape goes into the stock (mm, radial).
    pub(crate) depth: f64,
    /// Where (z, mm).
    pub(crate) z: f64,
    /// In the bore.
    pub(crate) internal: bool,
    /// The tool's id.
    pub(crate) tool: u32,
    /// The tool as the program wrote it (`Move::tool_name`).
    pub(crate) tool_name: String,
    /// The tool's role.
    pub(crate) role: Role,
    /// What the move was.
    pub(crate) kind: HitKind,
    /// How many moves of this kind of the block (a cycle makes many) met material; `depth`
    /// and `z` are the deepest's.
    pub(crate) moves: usize,
}

/// What a lathe program's moves that are not thread passes do.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LatheTurning {
    /// The feed and arc moves of external tools, in program order.
    pub(crate) outer: Turned,
    /// Those of boring bars and of an internal thread's inserts.
    pub(crate) inner: Turned,
    /// The block (file, 1-based line) of each of `outer`'s moves.
    pub(crate) outer_blocks: Vec<(String, usize)>,
    /// The block of each of `inner`'s moves.
    pub(crate) inner_blocks: Vec<(String, usize)>,
    /// The moves that meet material and must not.
    pub(crate) rapids: Vec<RapidHit>,
}

/// The moves of a lathe program that are not thread passes, in order, against the stock
/// as the moves before each left it (`outer`, and `inner` for a tube), over the blank's
/// span `z_span`, every `dz`:
///
/// - every feed and arc move of one of `tools` (by its T number, or the only tool) removes
///   that tool's shape along its path on the surface the tool cuts (turning, grooving, and
///   a threading insert's too: the part is what every tool left);
/// - every rapid of one of them that meets material is a [`RapidHit`], and so are a
///   threading insert's feed moves and synchronised radial entries (thread moves that go
///   further into the part than along it) that meet material. The rapid straight out
///   (along X, away from the part) from where a thread move ended is the threading cycle's
///   retract out of its own groove: the ring it marks at the thread's end is the thread's
///   run-out, as on the machine, and it is not a finding.
///
/// The stock is the turned profile (the feed moves' envelope); thread passes leave it as it
/// was: a helical groove narrower than its lead leaves the full radius at some angle of
/// every z, and the part turns under a rapid, so a rapid below the crest meets the crest.
/// Thread moves are the passes' ([`lathe_passes`]). The program's first move starts
/// wherever the machine happens to be (the interpreter starts at the work zero, which no
/// real machine does): it neither cuts nor is checked.
pub(crate) fn lathe_turning(
    moves: &[nc::Move],
    tools: &[LatheTool],
    outer: TurnStock,
    inner: Option<TurnStock>,
    z_span: (f64, f64),
    dz: f64,
    chuck: Option<&PartProfile>,
) -> LatheTurning {
    let mut out = LatheTurning::default();
    if tools.is_empty() {
        return out;
    }
    // The chuck where tools can reach the part: the blank's span and a metre beyond.
    let chuck = chuck.and_then(|c| Profile::outline(c, (z_span.0 - 1000.0, z_span.1 + 1000.0), dz));
    let mut outer_stock = Profile::new(z_span, dz, outer.q_blank, outer.q_floor);
    let mut inner_stock = inner.map(|s| Profile::new(z_span, dz, s.q_blank, s.q_floor));
    // Where the last thread move ended (diameter, z), while the next move may be the
    // retract out of its groove.
    let mut thread_end: Option<(f64, f64)> = None;
    for m in moves.iter().skip(1) {
        let after_thread = thread_end.take();
        let found = match m.tool {
            Some(id) => tools.iter().find(|t| t.shape.id == id),
            None if tools.len() == 1 => tools.first(),
            None => None,
        };
        let Some(&LatheTool {
            shape: tool,
            role,
            holder,
        }) = found
        else {
            continue;
        };
        let (turned, blocks, stock, sense) = if tool.internal {
            match inner_stock.as_mut() {
                Some(s) => (&mut out.inner, &mut out.inner_blocks, s, -1.0),
                None => continue,
            }
        } else {
            (&mut out.outer, &mut out.outer_blocks, &mut outer_stock, 1.0)
        };
        let arc = match (m.kind, &m.arc) {
            (MoveKind::Arc, Some(a)) => Some(((a.z_centre, a.x_centre_dia), a.clockwise)),
            _ => None,
        };
        let path = TurnPath::of_move(&tool, sense, (m.z_start, m.x_start), (m.z, m.x_dia), arc);
        let mut check = |stock: &Profile, shape: &TurningTool, path: &TurnPath, kind: HitKind| {
            if let Some(hit) = stock.rapid_depth(shape, path) {
                record(&mut out.rapids, m, &tool, role, kind, hit);
            }
        };
        let outward = sense * (m.x_dia - m.x_start) > 0.0;
        match m.kind {
            MoveKind::Feed | MoveKind::Arc => {
                if role == Role::Threading {
                    check(stock, &tool, &path, HitKind::Feed);
                }
                let cut = TurnCut { tool, path };
                stock.cut(&cut);
                turned.cuts.push(cut);
                blocks.push((m.file.clone(), m.line));
            }
            MoveKind::Rapid => {
                let retract =
                    after_thread == Some((m.x_start, m.z_start)) && m.z == m.z_start && outward;
                if !retract {
                    check(stock, &tool, &path, HitKind::Rapid);
                }
            }
            MoveKind::Thread => {
                let radial = (m.x_dia - m.x_start).abs() / 2.0;
                if role == Role::Threading && !outward && radial > (m.z - m.z_start).abs() {
                    check(stock, &tool, &path, HitKind::Entry);
                }
                thread_end = Some((m.x_dia, m.z));
            }
        }
        // The holder against the stock as this move leaves it, and the tool and its holder
        // against the chuck (outside).
        let sweeps = holder.map(|h| {
            let mount = Mount {
                id: tool.id,
                internal: tool.internal,
                tip_dz: match role {
                    Role::Turning => 0.0,
                    _ => tool_tip_dz(&tool, role),
                },
            };
            holder::sweeps(&h, mount, (m.z_start, m.x_start), (m.z, m.x_dia), arc)
        });
        for (shape, hp) in sweeps.iter().flatten() {
            check(stock, shape, hp, HitKind::Holder);
        }
        if let (Some(c), false) = (&chuck, tool.internal) {
            // The insert as a line up from its lowest point, two cells wide (its edges run
            // on without end in the stock's shapes; above the tip the holder stands for it).
            let tip = TurningTool {
                nose_radius: 0.0,
                flat: 2.0 * dz,
                lead_angle: 0.0,
                trail_angle: 0.0,
                anchor: (tool_tip_dz(&tool, role) - dz, 0.0),
                ..tool
            };
            let tip_path =
                TurnPath::of_move(&tip, sense, (m.z_start, m.x_start), (m.z, m.x_dia), arc);
            let mut worst = c.rapid_depth(&tip, &tip_path);
            for (shape, hp) in sweeps.iter().flatten() {
                if let Some(h) = c.rapid_depth(shape, hp) {
                    worst = Some(worst.map_or(h, |w: (f64, f64)| if h.0 > w.0 { h } else { w }));
                }
            }
            if let Some(hit) = worst {
                record(&mut out.rapids, m, &tool, role, HitKind::Chuck, hit);
            }
        }
    }
    out
}

/// The z of a tool's lowest point less the driven point's: a turning insert's nose
/// bottom (its centre's z: `r_n` after an imaginary tip of direction 3 or 2), an insert's
/// tip centre.
fn tool_tip_dz(tool: &TurningTool, role: Role) -> f64 {
    match role {
        Role::Turning => tool.anchor.0,
        _ => tool.anchor.0 + tool.flat / 2.0,
    }
}

/// Record a move of `tool` that meets material `hit = (depth, z)` deep: the moves of one
/// block and kind (a cycle's passes) are one hit, the deepest, with their count. Below the
/// report's rounding it is none (as milling's rapids).
fn record(
    hits: &mut Vec<RapidHit>,
    m: &nc::Move,
    tool: &TurningTool,
    role: Role,
    kind: HitKind,
    (depth, z): (f64, f64),
) {
    if depth < 5e-7 {
        return;
    }
    match hits
        .iter_mut()
        .rev()
        .take_while(|h| h.line == m.line && h.file == m.file)
        .find(|h| (h.tool, h.kind) == (tool.id, kind))
    {
        Some(h) => {
            h.moves += 1;
            if depth > h.depth {
                (h.depth, h.z) = (depth, z);
            }
        }
        None => hits.push(RapidHit {
            file: m.file.clone(),
            line: m.line,
            depth,
            z,
            internal: tool.internal,
            tool: tool.id,
            tool_name: m.tool_name(),
            role,
            kind,
            moves: 1,
        }),
    }
}
