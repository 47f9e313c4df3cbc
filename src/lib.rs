//! vpcut simulates CNC thread machining on a radial-dexel stock and tells whether the
//! passes cut the thread the drawing asks for.
//!
//! The pipeline, in reading order:
//!
//! 1. [`Job::from_toml`] reads a job (blank, thread, tools, passes or a pass generator,
//!    machine, simulation settings) into mm and radians; [`Job::from_toml_with`] then runs
//!    the program stage: the job's NC program through [`interpret`] (Siemens 802D, FANUC,
//!    GSK 980TDC, LinuxCNC), its thread moves made into passes (or a mill's moves into
//!    its path).
//! 2. [`simulate`] builds the blank as a [`Stock`] of radial dexels, sweeps every pass
//!    through it ([`sweep`]), compares the cut with the closed-form ideal thread
//!    ([`compare`]), measures leads and widths along generators ([`measure`]), runs the
//!    machine checks, and returns a [`Report`] with the stock.
//!
//! ```
//! let job = vpcut::Job::from_toml(r#"
//!     [blank]
//!     diameter = 20.0
//!     length = 30.0
//!     [thread]
//!     form = "iso-metric"
//!     major_diameter = 20.0
//!     pitch = 2.5
//!     length = 20.0
//!     [[tool]]
//!     id = 1
//!     kind = "threading"
//!     angle = 60.0
//!     tip_flat = 0.41666667
//!     [process]
//!     kind = "radial"
//!     tool = 1
//!     layers = 4
//!     [simulation]
//!     angular_cells = 90
//!     axial_spacing = 0.02
//!     measure_generators = 2
//! "#, "inline.toml").unwrap();
//! let out = vpcut::simulate(&job, &vpcut::SimOptions::default()).unwrap();
//! assert!(out.report.deviation.max_gouge_mm < 0.01);
//! ```

// The stages, lowest first (each uses only those before it; `tests/integration/tidy.rs`
// checks it): diag, model, kernel, nc, analysis, gen, toolpath, job, report, pipeline,
// output. See ARCHITECTURE.md. (rustfmt lists them alphabetically.)
mod analysis;
mod diag;
mod gen;
mod job;
mod kernel;
mod model;
// An `NcError` carries every diagnostic of a program (160 bytes); it is returned once per
// run, never in a loop, so boxing it would only make the API clumsier.
#[allow(clippy::result_large_err)]
mod nc;
mod output;
mod pipeline;
mod report;
mod toolpath;

pub use analysis::compare::{column_deviation, compare, Deviation, Extreme, Place, TurnDeviation};
pub use analysis::measure::{measure, MeasureConfig, TurnMeasure};
pub use analysis::place::Placement;
pub use gen::{plan, post};
pub use job::{FormName, Job, JobError, MillJob, SimConfig, DEFAULT_MAX_DEXELS};
pub use kernel::mill::{
    mill_column, sweep_mill, Cutter, CutterError, CutterSpec, MillPath, MillStats, Motion, MoveCut,
    PathMove, SAMPLING_BOUND_MM as MILL_SAMPLING_BOUND_MM,
};
pub use kernel::sweep::{sweep, sweep_column, Column, SweepStats};
pub use model::helix::{Hand, Helix, LeadLaw, Spindle};
pub use model::part::{Approach, PartError, PartProfile};
pub use model::pass::Pass;
pub use model::setup::{Blank, ChainLink, CycleTime, Machine, DEFAULT_RAPID_RATE};
pub use model::solid::{prism, Face, Solid, SolidError};
pub use model::standards::{
    class_for, parse as parse_designation, Designation, Engagement, Form as StandardForm, Series,
    Standard, StandardError,
};
pub use model::stock::{Grid, Stock, Surface};
pub use model::thread::{ColumnIdeal, Flank, Side, Taper, ThreadSpec, WidthRule};
pub use model::tolerance::{RootZone, SizeLimits, TaperGauge, ThreadClass, UnitSystem};
pub use model::tool::{linuxcnc_orientation, tip_direction};
pub use model::tool::{Body, DepthLimits, Edge, Reference, Tap, Tool};
pub use nc::{
    decode_program, interpret, interpret_partial, interpret_with, path_lead, to_csv, ArcGeometry,
    CompSide, DecimalPoint, Diagnostic, Dialect, Dwell, DwellTime, Feed, G76Params, GcodeSystem,
    InputIncrement, Limits, MillArc, MillKind, MillMove, MillSettings, Move, MoveKind, NcError,
    Nose, NoseData, NoseOffset, NoseRule, Options as NcOptions, Plane, PowerOn, Settings, Severity,
    Source, SpindleSpeed, ToolOffsets, Toolpath,
};
pub use output::glb::{from_glb, to_glb, GlbError};
pub use output::html::{finding_point, to_html, FindingPlace, HtmlPage, HtmlPicture};
pub use output::mesh::{build_scene, ideal_mesh, stock_mesh, toolpath, SceneOptions};
pub use output::plot::chart::band_colour;
pub use output::plot::developed::{developed_plot, developed_view, DevelopedPlot};
pub use output::plot::section::{section_view, trace_plot, trace_view, TraceMark, TracePlot};
pub use output::plot::{section_angle, section_profile, signed_deviation};
pub use output::render::{
    captions, encode_png, Captions, RenderError, RenderOptions, Renderer, ToolpathMode, View,
    SHADER,
};
pub use output::scene::{Focus, Legend, Mesh, PathKind, Polyline, Scene};
pub use output::stream::{simulate_meshed, Meshed};
pub use output::tool::tool_mesh;
pub use pipeline::{plan_grid, simulate, simulate_report, Outcome, SimError, SimOptions};
pub use report::{
    CycleTimeInfo, Extent, Finding, FindingCounts, FindingKind, GaugeElementInfo, GaugeInfo,
    GaugeLimits, InchThread, InchView, InputFile, LimitPair, OverWires, Painter, PlacementInfo,
    Range, Report, SummaryStyle, TaperInfo, Tone, ToolTime, TurnRow, Verdict, SCHEMA, VERSION,
};
