//! FANUC milling programs (machining centres, FANUC 0i-MF G codes): the public nouns of a
//! milling toolpath and their interpretation.
//!
//! A milling job's program runs through the same FANUC front end as a lathe program
//! (blocks, Macro A/B, subprograms, limits); with [`MillSettings`] in the interpreter's
//! settings its motion words are read as a mill reads them: X/Y/Z radii in the active
//! work system, G90/G91 absolute/incremental, G17/G18/G19 planes, G02/G03 with I/J/K or R
//! and a linear axis (helical interpolation), G43/G49 tool length and G41/G42/G40 cutter
//! radius compensation with D registers. Out come [`MillMove`]s: the path of the tool
//! tip's centre in the job's frame.
//!
//! - this module: the public milling nouns ([`MillMove`], [`MillSettings`], planes, sides);
//! - `blocks`: FANUC machining-centre blocks (XYZ, planes, helical arcs, G43/G49, G41/G42
//!   recorded as programmed) into programmed moves;
//! - `comp`: cutter radius compensation of the programmed moves (a pure pass).

mod blocks;
mod comp;
#[cfg(test)]
mod tests;

pub(super) use blocks::MillState;
pub(super) use comp::{compensate, intersections, Offset};

use crate::model::helix::Spindle;

/// The plane of circular interpolation and of cutter radius compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    /// G17: XY, normal +Z.
    Xy,
    /// G18: ZX, normal +Y.
    Zx,
    /// G19: YZ, normal +X.
    Yz,
}

/// The side of the contour the tool runs on under cutter radius compensation, looking
/// along the direction of travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompSide {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// What a milling move does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MillKind {
    /// G00.
    Rapid,
    /// G01.
    Feed,
    /// G02/G03, with [`MillMove::arc`].
    Arc,
}

/// The circle of a milling arc: the tool centre's path, possibly helical.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MillArc {
    /// Centre in the job frame; its coordinate along the plane's normal is the start's.
    pub centre: [f64; 3],
    /// Radius of the tool centre's circle (mm).
    pub radius: f64,
    /// Signed sweep (rad): positive is counter-clockwise seen from the plane's positive
    /// normal (G03), negative clockwise (G02). A full circle is `+-2 pi`.
    pub sweep: f64,
    /// Plane of the circle; the coordinate along its normal moves linearly with the
    /// angle (helical interpolation).
    pub plane: Plane,
}

/// One interpreted milling move.
#[derive(Clone, Debug, PartialEq)]
pub struct MillMove {
    /// File of the block.
    pub file: String,
    /// 1-based line of the block.
    pub line: usize,
    /// Kind.
    pub kind: MillKind,
    /// Tool tip centre at the start (job frame, mm), after work offsets, tool length and
    /// cutter radius compensation.
    pub start: [f64; 3],
    /// Tool tip centre at the end.
    pub end: [f64; 3],
    /// The tool centre's circle (arcs).
    pub arc: Option<MillArc>,
    /// The programmed contour's end point (before radius compensation), job frame.
    pub programmed_end: [f64; 3],
    /// Programmed feed (mm/min) of feed and arc moves.
    pub feed: Option<f64>,
    /// Spindle speed (rev/min), if an S word was given.
    pub spindle_rpm: Option<f64>,
    /// Spindle direction, `None` while it is stopped.
    pub spindle: Option<Spindle>,
    /// Active tool number.
    pub tool: Option<u32>,
    /// The tool as the program wrote it (`T1`), `None` before any T word.
    pub tool_word: Option<std::sync::Arc<str>>,
    /// Cutter radius compensation in force during the move: side and radius (mm).
    pub comp: Option<(CompSide, f64)>,
}

/// What a milling program cannot say about the machine: set by the job.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct MillSettings {
    /// Work offsets G54..G59: where each work zero lies in the job's frame (x, y, z).
    pub work_offsets: [[f64; 3]; 6],
    /// D registers: (number, radius in mm).
    pub radius_offsets: Vec<(u32, f64)>,
    /// H registers that hold the tool's length: under G43 with one of them the tip
    /// follows the programmed Z.
    pub length_offsets: Vec<u32>,
    /// z where the tool tip comes from before its first known Z position (the tool
    /// starts above the part).
    pub home_z: f64,
}
