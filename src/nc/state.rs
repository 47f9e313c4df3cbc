//! The interpreter's state, grouped by what it is about: the run's fixed settings, the
//! programs, the tool's position, modal state (motion, units, feed, spindle), coordinate
//! frames, threading cycles' modal state, the FANUC/Siemens variable stores (LinuxCNC's
//! live in `linuxcnc::Lcnc`), the output, and the milling state.

use super::{linuxcnc, mill, Dialect, GcodeSystem, Limits, Move, Options, Program, Source};
use crate::model::helix::Spindle;
use std::collections::HashMap;

/// Interpreter state, grouped by what it is about. (Named `Interp`: the crate's `machine`
/// is the machine tool's settings.)
pub(super) struct Interp<'l> {
    /// What the run was started with; fixed for the run.
    pub(super) cfg: Config,
    /// Programs known by name and the loader that finds more beside the main file.
    pub(super) progs: Programs<'l>,
    /// Where the tool is: diameter (mm).
    pub(super) x: f64,
    /// Where the tool is: z (mm).
    pub(super) z: f64,
    /// Modal state of motion, units, feed and spindle.
    pub(super) modal: Modal,
    /// Work offsets, G92 offsets and reference points.
    pub(super) frames: Frames,
    /// Threading cycles' modal state and continuous threading.
    pub(super) thread: ThreadState,
    /// FANUC `#` variables and Siemens R parameters.
    pub(super) vars: Vars,
    /// What the run has made so far.
    pub(super) out: Output,
    /// LinuxCNC named parameters, call levels and O-word tables.
    pub(super) lc: linuxcnc::Lcnc,
    /// A FANUC milling program's codes, addresses and state (`Settings::mill`).
    pub(super) mill: Option<mill::MillState>,
}

/// The run's fixed settings.
pub(super) struct Config {
    /// Syntax family (FANUC for GSK too).
    pub(super) dialect: Dialect,
    /// GSK 980TDC semantics for G34.
    pub(super) gsk: bool,
    /// Siemens 840D: the 802D syntax and its additions (`siemens_840d`).
    pub(super) s840: bool,
    /// The blocks (program, line) the static check refused, where a partial run
    /// (`interpret_partial`) stops.
    pub(super) stop_at: std::collections::HashSet<(String, usize)>,
    /// FANUC lathe G-code system (codes are translated to system A when read).
    pub(super) system: GcodeSystem,
    /// Unknown words and codes are errors.
    pub(super) strict: bool,
    /// Skip blocks that start with `/`.
    pub(super) block_skip: bool,
    /// Limits on executed blocks, moves and nesting.
    pub(super) limits: Limits,
    /// A FANUC milling program (`Settings::mill`).
    pub(super) milling: bool,
    /// How FANUC/GSK numbers without a decimal point are read.
    pub(super) decimal_point: super::DecimalPoint,
    /// The least input increment.
    pub(super) increment: super::InputIncrement,
    /// The tool offsets the job defines (`Settings::tool_offsets`).
    pub(super) offsets: Option<super::ToolOffsets>,
    /// LinuxCNC's subroutine folders (`Settings::subroutine_path`).
    pub(super) subroutine_path: Vec<String>,
    /// The noses' radii and tip directions (`Settings::noses`).
    pub(super) noses: super::NoseData,
}

/// The programs of a run.
pub(super) struct Programs<'l> {
    /// Finds a file beside the main one by name.
    pub(super) loader: &'l dyn Fn(&str) -> Option<Source>,
    /// Programs by the names they are called by.
    pub(super) by_name: HashMap<String, std::rc::Rc<Program>>,
}

/// Modal state: motion mode, units, X mode, feed, spindle and tool.
#[derive(Clone)]
pub(super) struct Modal {
    /// Active motion G code (0, 1, 2, 3, 32, ...).
    pub(super) motion: u32,
    /// Incremental moves (G91 on LinuxCNC and G-code systems B/C).
    pub(super) incremental: bool,
    /// Inch units (G20).
    pub(super) inch: bool,
    /// X words are diameters (G7; always on FANUC/GSK/Siemens lathes), else radii (G8).
    pub(super) diameter_mode: bool,
    /// G99 feed per revolution (else G98 per minute).
    pub(super) per_rev: bool,
    /// The modal feed F (`None` before any F).
    pub(super) feed: Option<f64>,
    /// The modal F was written without a decimal point (FANUC/GSK): a tap's pitch taken
    /// from it is refused in standard decimal-point input (`Interp::lead_word`).
    pub(super) feed_plain: bool,
    /// The program selected the units itself (G20/G21, G70/G71): a lead that looks like
    /// inches then gets no warning about the power-on units.
    pub(super) units_set: bool,
    /// G96 constant surface speed (else G97 rpm).
    pub(super) css: bool,
    /// The last S value (rev/min under G97; the surface speed under G96, in m/min or, in
    /// inch mode, ft/min).
    pub(super) speed: Option<f64>,
    /// The clamp on G96's spindle speed (FANUC/GSK `G50 S`, Siemens `LIMS=`, LinuxCNC
    /// `G96 D`), rev/min.
    pub(super) speed_max: Option<f64>,
    /// The active tool offset number (FANUC/GSK T0305: 5; Siemens D5); 0 or `None`: none.
    pub(super) offset: Option<u32>,
    /// Active tool number.
    pub(super) tool: Option<u32>,
    /// The tool's T word as written (`Move::tool_word`), without the D.
    pub(super) tool_t: Option<String>,
    /// The tool as `Move::tool_word` gives it (the T word, with Siemens' D in force).
    pub(super) tool_word: Option<std::sync::Arc<str>>,
    /// Spindle direction.
    pub(super) spindle: Spindle,
    /// Tool nose radius compensation (`nose`): G41/G42 and LinuxCNC's `D`; `None` (G40).
    pub(super) nose: Option<(super::CompSide, Option<u32>)>,
    /// LinuxCNC G41.1/G42.1: the radius (mm) and tip direction the block gave (`D` / 2,
    /// orientation `L`), used instead of the tool table's.
    pub(super) nose_dynamic: Option<(f64, u8)>,
    /// SINUMERIK G450 (transition circles at outer corners; G451: intersections).
    pub(super) nose_arc: bool,
    /// SINUMERIK KONT (else NORM): the approach and retraction of compensation.
    pub(super) nose_kont: bool,
}

/// Coordinate frames: work offsets, G92 offsets, reference points.
pub(super) struct Frames {
    /// Work offsets G54..G59 (and LinuxCNC's G59.1..G59.3).
    pub(super) offsets: [(f64, f64); 9],
    /// The active work offset (0 = G54).
    pub(super) work: usize,
    /// LinuxCNC G92 offset (diameter, z; mm) added to the work offset; (0, 0) when none.
    pub(super) g92_off: (f64, f64),
    /// The G28 reference point (diameter, z): the job's, else the machine zero (0, 0).
    pub(super) reference: (f64, f64),
    /// FANUC's second reference point (G30 P2) and LinuxCNC's G30 home at the start.
    pub(super) reference2: (f64, f64),
}

/// Threading cycles' modal state.
pub(super) struct ThreadState {
    /// G76 parameters set by its first block.
    pub(super) g76: G76Setup,
    /// Modal G92 target z, lead and taper R (radius, start minus end).
    pub(super) g92: Option<(f64, f64, f64)>,
    /// Thread chamfer length in leads (FANUC parameter 5130; G76 P rr sets it).
    pub(super) chamfer: f64,
    /// Thread chamfering switched on (M23) or off (M24).
    pub(super) chamfer_on: bool,
    /// Modal G90/G94 cutting cycle: (G code, target of the axis a repeat block leaves out,
    /// taper R).
    pub(super) cycle90: Option<(u32, f64, f64)>,
    /// GSK modal thread run-out: J (short axis, signed, radius) and K (long axis, `None` =
    /// as long as |J|), in mm.
    pub(super) runout: (Option<f64>, Option<f64>),
    /// GSK G92/G76 run-out `(K, |J|)` in mm (`fanuc::thread_pullout`), modal.
    pub(super) cycle_runout: Option<(f64, f64)>,
    /// Spindle angle (deg) where the last thread block's move ended, and its Z direction,
    /// while the next thread block would continue it without a re-sync; `None` once
    /// anything else moved.
    pub(super) chain_end: Option<(f64, f64)>,
    /// The multiple repetitive cycles' (G70..G75) first-block data.
    pub(super) cycles: super::cycles::CycleSetup,
    /// FANUC/GSK rigid tapping (M29, G84).
    pub(super) tap: TapState,
}

/// FANUC/GSK rigid tapping's modal state (`fanuc::g84`).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct TapState {
    /// M29 given: the next G84 taps rigidly (the spindle position-synchronised).
    pub(super) rigid: bool,
    /// While G84 is modal: the initial level (the Z where the cycle began).
    pub(super) initial: Option<f64>,
    /// The modal R (from the initial level to the R point, mm, signed) and hole bottom Z.
    pub(super) r: Option<f64>,
    /// The modal hole bottom (Z, mm in the job's frame).
    pub(super) bottom: Option<f64>,
    /// The group-01 motion before G84 (G80 restores it).
    pub(super) before: u32,
    /// G-code systems B/C: G99 returns to the R point (G98, the default: initial level).
    pub(super) to_r: bool,
    /// Siemens 840D: the last G331's way in (its sync and revolutions), so that the G332
    /// after it comes back in the same groove.
    pub(super) g331: Option<(super::Sync, f64)>,
}

/// FANUC and Siemens variable stores (LinuxCNC's are in [`linuxcnc::Lcnc`]).
pub(super) struct Vars {
    /// FANUC common variables (#100.., #500..); a missing entry is null (vacant).
    pub(super) common: HashMap<u32, f64>,
    /// FANUC local variables #1..#33, one level per G65 macro call; missing = null.
    pub(super) locals: Vec<HashMap<u32, f64>>,
    /// Siemens R parameters.
    pub(super) r: HashMap<u32, f64>,
    /// Siemens 840D user variables, `PROC` arguments, tool names.
    pub(super) s840: super::siemens_vars::S840State,
}

/// What the run has made and counted.
pub(super) struct Output {
    /// The moves in execution order.
    pub(super) moves: Vec<Move>,
    /// A block tried to record more than `limits.max_moves` moves (the rest were dropped).
    pub(super) too_many_moves: bool,
    /// Blocks executed.
    pub(super) blocks: u64,
    /// Warnings of the block being run: (column, message).
    pub(super) pending: Vec<(usize, String)>,
    /// Warnings of the block being run with their own hint: (column, message, hint).
    pub(super) notes: Vec<(usize, String, String)>,
    /// A warning that plain numbers look meant for the other decimal-point input was given
    /// (once a run).
    pub(super) units_noted: bool,
    /// A warning that a lead looks like inches was given (once a run).
    pub(super) inch_noted: bool,
    /// The dwells (G04) so far.
    pub(super) dwells: Vec<super::Dwell>,
    /// The tool offset (X diameter, Z) the last move ended with: the next move starts
    /// there and absorbs a change, as the control applies an offset with the next motion.
    pub(super) applied: (f64, f64),
    /// A threading cycle's block is running (its thread moves are marked).
    pub(super) cycle: bool,
    /// A cycle whose moves run with the nose radius compensation's vector held is running.
    pub(super) nose_hold: bool,
    /// A thread move was made in inch units (`Toolpath::inch`).
    pub(super) inch_threads: bool,
}

/// FANUC G76 first-block data (modal): finishing count, chamfer, tool angle (deg),
/// minimum cut and finishing allowance (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct G76Setup {
    pub(super) m: u32,
    pub(super) r: u32,
    pub(super) a: f64,
    pub(super) dmin: f64,
    pub(super) d: f64,
    /// A first block has run: the values are the program's, not the parameters'.
    pub(super) given: bool,
}

impl<'l> Interp<'l> {
    /// The state at the start of a run of `dialect`'s syntax family (`gsk` for GSK 980TDC).
    pub(super) fn new(
        dialect: Dialect,
        gsk: bool,
        loader: &'l dyn Fn(&str) -> Option<Source>,
        opts: &Options,
    ) -> Interp<'l> {
        Interp {
            cfg: Config {
                dialect,
                gsk,
                s840: false,
                stop_at: Default::default(),
                system: opts.settings.gcode_system,
                strict: opts.strict,
                block_skip: opts.settings.block_skip,
                limits: opts.limits,
                milling: opts.settings.mill.is_some(),
                decimal_point: opts.settings.decimal_point,
                increment: opts.settings.input_increment,
                offsets: opts.settings.tool_offsets.clone(),
                subroutine_path: opts.settings.subroutine_path.clone(),
                noses: opts.settings.noses.clone(),
            },
            progs: Programs {
                loader,
                by_name: HashMap::new(),
            },
            x: 0.0,
            z: 0.0,
            modal: Modal {
                motion: 0,
                incremental: false,
                inch: opts.settings.power_on.inch,
                diameter_mode: opts
                    .settings
                    .power_on
                    .diameter
                    .unwrap_or(dialect != Dialect::Linuxcnc),
                per_rev: !opts.settings.power_on.per_minute,
                feed: None,
                feed_plain: false,
                units_set: false,
                css: false,
                speed: None,
                speed_max: None,
                offset: None,
                tool: None,
                tool_t: None,
                tool_word: None,
                spindle: Spindle::Cw,
                nose: None,
                nose_dynamic: None,
                nose_arc: true,
                nose_kont: false,
            },
            frames: Frames {
                offsets: {
                    let mut o = [(0.0, 0.0); 9];
                    o[..6].copy_from_slice(&opts.settings.work_offsets);
                    o
                },
                work: 0,
                g92_off: (0.0, 0.0),
                reference: opts.settings.reference_point.unwrap_or((0.0, 0.0)),
                reference2: opts.settings.second_reference_point.unwrap_or((0.0, 0.0)),
            },
            thread: ThreadState {
                g76: G76Setup {
                    m: opts.settings.g76.finish_passes,
                    r: 0,
                    a: opts.settings.g76.tool_angle,
                    dmin: opts.settings.g76.min_cut,
                    d: opts.settings.g76.finish_allowance,
                    given: false,
                },
                g92: None,
                chamfer: opts.settings.thread_chamfer,
                chamfer_on: true,
                cycle90: None,
                runout: (None, None),
                cycle_runout: None,
                chain_end: None,
                cycles: Default::default(),
                tap: Default::default(),
            },
            vars: Vars {
                common: HashMap::new(),
                locals: vec![HashMap::new()],
                r: HashMap::new(),
                s840: Default::default(),
            },
            out: Output {
                moves: Vec::new(),
                too_many_moves: false,
                blocks: 0,
                pending: Vec::new(),
                notes: Vec::new(),
                units_noted: false,
                inch_noted: false,
                inch_threads: false,
                dwells: Vec::new(),
                applied: (0.0, 0.0),
                cycle: false,
                nose_hold: false,
            },
            lc: Default::default(),
            mill: opts.settings.mill.clone().map(mill::MillState::new),
        }
    }
}
