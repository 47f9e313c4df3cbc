//! The setting of a job that is not the thread or the tools: the blank, the machine's data
//! for the checks, and the joints of continuous thread chains a program makes.

use crate::model::helix::Spindle;

/// The blank.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blank {
    /// Outer diameter (mm).
    pub diameter: f64,
    /// Bore diameter (mm), 0 = solid.
    pub bore: f64,
    /// Length (mm).
    pub length: f64,
    /// z of the right (front) face; the bar extends toward -z.
    pub z_front: f64,
}

/// Machine data for the checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Machine {
    /// Spindle speed during threading (rev/min).
    pub spindle_rpm: f64,
    /// Maximum axis feed (mm/min), if known.
    pub max_feed: Option<f64>,
    /// Axis acceleration (mm/s^2), if known.
    pub acceleration: Option<f64>,
    /// Spindle direction.
    pub spindle: Spindle,
    /// The rapid traverse rate (mm/min), if given (the cycle time's rapids; see
    /// [`DEFAULT_RAPID_RATE`]).
    pub rapid_rate: Option<f64>,
}

/// The rapid rate the cycle time takes when the job gives none (mm/min): a small CNC
/// lathe's; the report says when it was assumed.
pub const DEFAULT_RAPID_RATE: f64 = 10_000.0;

/// A program's cycle time, split by what the machine does, and by tool.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CycleTime {
    /// Rapids (s).
    pub rapid: f64,
    /// Feed and arc moves (s).
    pub feed: f64,
    /// Threading moves (s).
    pub thread: f64,
    /// Waits: each thread move's wait for the spindle's one-rev signal (half a revolution
    /// on average) and the dwells (s).
    pub wait: f64,
    /// Per tool (its T number; `None` before any), in the order of first use (s).
    pub by_tool: Vec<(Option<u32>, f64)>,
    /// Each of `by_tool`'s tools as the program first wrote it (`T0606`), `None` before
    /// any T word.
    pub tool_words: Vec<Option<String>>,
    /// The rapid rate used (mm/min).
    pub rapid_rate: f64,
    /// Whether it is the job's (else [`DEFAULT_RAPID_RATE`]).
    pub rapid_rate_given: bool,
}

impl CycleTime {
    /// The whole cycle (s).
    pub fn total(&self) -> f64 {
        self.rapid + self.feed + self.thread + self.wait
    }
}

/// A program's thread move that continues the previous one without a re-sync (a chained
/// move of the program): where it is, and the lead law on both sides of the
/// joint. The `thread_chain` machine check compares them.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainLink {
    /// Index of the chained pass in the job's passes.
    pub pass: usize,
    /// Program file of its block.
    pub file: String,
    /// Line of its block.
    pub line: usize,
    /// z of the joint (mm).
    pub z: f64,
    /// Lead the previous pass ended with (mm/rev).
    pub lead_before: f64,
    /// Lead change per revolution of the previous pass (mm/rev^2).
    pub change_before: f64,
    /// Start lead of the chained pass (mm/rev).
    pub lead_after: f64,
    /// Its lead change per revolution (mm/rev^2).
    pub change_after: f64,
}
