//! The job file's raw schema: what serde reads from the TOML, before any value is checked.
//! Every table denies unknown keys; defaults are the documented ones (`docs/job-format.md`).

use super::forms::FormName;
use super::{keys, mill};
use crate::gen::process;
use serde::Deserialize;
use std::fmt;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawJob {
    pub(super) name: Option<String>,
    pub(super) blank: RawBlank,
    pub(super) thread: RawThread,
    #[serde(default)]
    pub(super) tool: Vec<RawTool>,
    #[serde(default)]
    pub(super) pass: Vec<RawPass>,
    pub(super) process: Option<RawProcess>,
    pub(super) program: Option<RawProgram>,
    #[serde(default)]
    pub(super) machine: RawMachine,
    #[serde(default)]
    pub(super) simulation: RawSimulation,
    pub(super) part: Option<RawPart>,
}

/// `[part]`: the finished part's contours as drawn, `[z, d]` points in the order of z.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPart {
    pub(super) profile: Option<Vec<[f64; 2]>>,
    pub(super) bore_profile: Option<Vec<[f64; 2]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProgram {
    pub(super) file: String,
    pub(super) dialect: String,
    /// Unknown words and codes are errors, not warnings.
    #[serde(default)]
    pub(super) strict: bool,
    /// Thread chamfer (pull-out) of G92/G76 in leads (FANUC parameter 5130 / 10).
    #[serde(default)]
    pub(super) thread_chamfer: f64,
    /// Work offsets `G54`..`G59` = { x = diameter, z }.
    #[serde(default)]
    pub(super) work_offsets: std::collections::BTreeMap<String, RawOffset>,
    /// Skip blocks that start with `/` (the operator's block-skip switch).
    #[serde(default = "yes")]
    pub(super) block_skip: bool,
    /// Where G28 goes: { x = diameter, z } in the job's frame.
    pub(super) reference_point: Option<RawPoint>,
    /// FANUC/GSK lathe G-code system: "A" (default), "B" or "C".
    pub(super) gcode_system: Option<String>,
    /// Where FANUC/GSK G30 (and LinuxCNC's G30 at the start) goes: { x = diameter, z }.
    pub(super) second_reference_point: Option<RawPoint>,
    /// FANUC/GSK decimal-point input: "standard" (the default) or "calculator".
    pub(super) decimal_point: Option<String>,
    /// The least input increment in mm: 0.001 (the default) or 0.0001.
    pub(super) input_increment: Option<f64>,
    /// Units at power-on: "mm" (the default) or "inch".
    pub(super) units: Option<String>,
    /// Feed at power-on: "per-revolution" (the default) or "per-minute".
    pub(super) feed_mode: Option<String>,
    /// X words: "diameter" or "radius" (default: the dialect's).
    pub(super) x_mode: Option<String>,
    /// The main program of a file that holds several: "O1000".
    pub(super) main: Option<String>,
    /// LinuxCNC: folders searched for `o<name> call` files (the INI's SUBROUTINE_PATH).
    #[serde(default)]
    pub(super) subroutine_path: Vec<String>,
    /// Siemens: the machine's definition files (GUD, macro and cycle files).
    #[serde(default)]
    pub(super) definitions: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPoint {
    pub(super) x: f64,
    pub(super) z: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawOffset {
    #[serde(default)]
    pub(super) x: f64,
    pub(super) y: Option<f64>,
    #[serde(default)]
    pub(super) z: f64,
}

fn yes() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBlank {
    pub(super) diameter: f64,
    #[serde(default)]
    pub(super) bore: f64,
    pub(super) length: f64,
    #[serde(default)]
    pub(super) z_front: f64,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum SideName {
    #[default]
    External,
    Internal,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum HandName {
    #[default]
    Right,
    Left,
}

/// `pitch = 6.0` or `pitch = { first, increment, last | turns }`.
#[derive(Clone)]
pub(super) enum RawPitch {
    Constant(f64),
    Series(RawSeries),
}

impl<'de> Deserialize<'de> for RawPitch {
    /// A number or a table, told apart by what the file holds; any other value is an error
    /// that says both forms (an untagged enum would only say that nothing matched).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Pitch;
        impl<'de> serde::de::Visitor<'de> for Pitch {
            type Value = RawPitch;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a pitch in mm or a table `{ first = .., increment = .., last = .. }` (or `turns = ..` for `last`)")
            }
            fn visit_f64<E>(self, v: f64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<RawPitch, E> {
                Ok(RawPitch::Constant(v as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<RawPitch, A::Error> {
                RawSeries::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(RawPitch::Series)
            }
        }
        d.deserialize_any(Pitch)
    }
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSeries {
    pub(super) first: f64,
    pub(super) increment: f64,
    pub(super) last: Option<f64>,
    pub(super) turns: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWidth {
    pub(super) groove: Option<f64>,
    pub(super) tooth: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawThread {
    /// The drawing's designation (`M30x2-6g`, `1/2-13 UNC-2B`): form, size, pitch, starts,
    /// hand, side and tolerance class; the keys beside it must agree with it.
    pub(super) designation: Option<String>,
    /// A tolerance class (`6g`, `2B`, `7e`) for the explicit form, diameter and pitch.
    pub(super) class: Option<String>,
    /// Default `external`, or the designation's.
    pub(super) side: Option<SideName>,
    /// Required without a designation.
    pub(super) form: Option<FormName>,
    pub(super) flank_angle: Option<f64>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) flank_angles: Option<[f64; 2]>,
    /// Required without a designation.
    pub(super) major_diameter: Option<f64>,
    pub(super) minor_diameter: Option<f64>,
    pub(super) pitch_diameter: Option<f64>,
    /// Default `right`, or the designation's.
    pub(super) hand: Option<HandName>,
    /// Default 1, or the designation's.
    pub(super) starts: Option<u32>,
    pub(super) z_start: Option<f64>,
    pub(super) start_angle: Option<f64>,
    /// Required without a designation.
    pub(super) pitch: Option<RawPitch>,
    pub(super) length: Option<f64>,
    pub(super) turns: Option<f64>,
    pub(super) width: Option<RawWidth>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) pitch_diameter_limits: Option<[f64; 2]>,
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum ToolKind {
    Grooving,
    Threading,
    Trapezoidal,
    Mesh,
    ThreadMill,
    Turning,
    Tap,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum RefName {
    #[default]
    Center,
    Left,
    Right,
    Tip,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTool {
    pub(super) id: u32,
    pub(super) kind: ToolKind,
    pub(super) width: Option<f64>,
    pub(super) angle: Option<f64>,
    pub(super) tip_flat: Option<f64>,
    pub(super) nose_radius: Option<f64>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) edge_angles: Option<[f64; 2]>,
    pub(super) tip_direction: Option<u32>,
    pub(super) side: Option<SideName>,
    pub(super) tip_width: Option<f64>,
    pub(super) flank_angle: Option<f64>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) flank_angles: Option<[f64; 2]>,
    pub(super) reference: Option<RefName>,
    pub(super) length: Option<f64>,
    pub(super) file: Option<String>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) mesh_origin: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) mesh_axes: Option<[String; 3]>,
    pub(super) mesh_units: Option<String>,
    pub(super) mesh_body: Option<bool>,
    pub(super) cutter: Option<mill::CutterName>,
    pub(super) diameter: Option<f64>,
    pub(super) pitch: Option<f64>,
    pub(super) teeth: Option<u32>,
    pub(super) tooth_depth: Option<f64>,
    pub(super) first_tooth: Option<f64>,
    pub(super) shank_diameter: Option<f64>,
    pub(super) neck: Option<f64>,
    pub(super) flutes: Option<u32>,
    pub(super) drill_diameter: Option<f64>,
    pub(super) point_angle: Option<f64>,
    pub(super) chamfer_diameter: Option<f64>,
    pub(super) chamfer_length: Option<f64>,
    pub(super) chamfer_threads: Option<f64>,
    pub(super) h: Option<u32>,
    pub(super) d: Option<u32>,
    pub(super) d_value: Option<f64>,
    pub(super) thickness: Option<f64>,
    pub(super) side_clearance_left: Option<f64>,
    pub(super) side_clearance_right: Option<f64>,
    pub(super) front_clearance: Option<f64>,
    pub(super) inclination: Option<f64>,
    pub(super) max_depth_per_pass: Option<f64>,
    pub(super) min_depth_per_pass: Option<f64>,
    pub(super) holder: Option<RawHolder>,
}

/// `[[tool]] holder`: a shank (`left`, `right`, `clearance`) or a boring bar (`diameter`,
/// `reach`, `front`, `length`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHolder {
    pub(super) kind: HolderKind,
    pub(super) left: Option<f64>,
    pub(super) right: Option<f64>,
    pub(super) clearance: Option<f64>,
    pub(super) diameter: Option<f64>,
    pub(super) reach: Option<f64>,
    pub(super) front: Option<f64>,
    pub(super) length: Option<f64>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum HolderKind {
    Shank,
    Bar,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPass {
    pub(super) tool: u32,
    pub(super) x: f64,
    pub(super) x_end: Option<f64>,
    pub(super) z_start: f64,
    pub(super) z_end: f64,
    pub(super) lead: f64,
    #[serde(default)]
    pub(super) lead_change: f64,
    #[serde(default)]
    pub(super) start_angle: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProcess {
    pub(super) kind: process::Kind,
    pub(super) tool: u32,
    pub(super) layers: Option<u32>,
    pub(super) depths: Option<Vec<f64>>,
    #[serde(default)]
    pub(super) schedule: process::Schedule,
    pub(super) layer_depth: Option<f64>,
    #[serde(default)]
    pub(super) method: process::AxialMethod,
    pub(super) z_from: Option<f64>,
    pub(super) z_to: Option<f64>,
    pub(super) origin_z: Option<f64>,
    pub(super) root_width: Option<f64>,
    pub(super) max_depth: Option<f64>,
    pub(super) min_depth: Option<f64>,
    pub(super) infeed: Option<crate::gen::plan::Infeed>,
    pub(super) finish_passes: Option<u32>,
    pub(super) spring_passes: Option<u32>,
    pub(super) finish_allowance: Option<f64>,
}

#[derive(Deserialize, Clone, Copy, Default, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(super) enum SpindleName {
    #[default]
    Cw,
    Ccw,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMachine {
    #[serde(default)]
    pub(super) kind: mill::MachineKind,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) axis: Option<[f64; 2]>,
    pub(super) home_z: Option<f64>,
    #[serde(default = "default_rpm")]
    pub(super) spindle_rpm: f64,
    pub(super) max_feed: Option<f64>,
    pub(super) acceleration: Option<f64>,
    pub(super) rapid_rate: Option<f64>,
    #[serde(default)]
    pub(super) spindle: SpindleName,
    /// Tool offsets by number: `offsets.5 = { x = .., z = .., wear_x = .., wear_z = .. }`.
    pub(super) offsets: Option<std::collections::BTreeMap<String, RawToolOffset>>,
    /// FANUC parameter 5142: G76's finishing passes without a first block.
    pub(super) g76_finish_passes: Option<u32>,
    /// FANUC parameter 5143: G76's tool angle (deg).
    pub(super) g76_tool_angle: Option<f64>,
    /// FANUC parameter 5140: G76's minimum cut (mm).
    pub(super) g76_min_cut: Option<f64>,
    /// FANUC parameter 5141: G76's finishing allowance (mm).
    pub(super) g76_finish_allowance: Option<f64>,
    /// The chuck and its jaws as a contour `[[z, d], ...]` (they turn with the part).
    pub(super) chuck: Option<Vec<[f64; 2]>>,
}

/// One tool offset: the geometry's deviation and the wear (mm; x a diameter).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawToolOffset {
    #[serde(default)]
    pub(super) x: f64,
    #[serde(default)]
    pub(super) z: f64,
    #[serde(default)]
    pub(super) wear_x: f64,
    #[serde(default)]
    pub(super) wear_z: f64,
    /// The nose radius R (tool nose radius compensation); left out: the tool's.
    pub(super) r: Option<f64>,
    #[serde(default)]
    pub(super) wear_r: f64,
    /// The imaginary tip direction T (0 to 9); left out: the tool's.
    pub(super) t: Option<u32>,
}

fn default_rpm() -> f64 {
    200.0
}

impl Default for RawMachine {
    fn default() -> Self {
        RawMachine {
            kind: mill::MachineKind::Lathe,
            axis: None,
            home_z: None,
            spindle_rpm: default_rpm(),
            max_feed: None,
            acceleration: None,
            rapid_rate: None,
            spindle: SpindleName::Cw,
            offsets: None,
            g76_finish_passes: None,
            g76_tool_angle: None,
            g76_min_cut: None,
            g76_finish_allowance: None,
            chuck: None,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSimulation {
    #[serde(default = "default_spacing")]
    pub(super) axial_spacing: f64,
    #[serde(default = "default_cells")]
    pub(super) angular_cells: usize,
    #[serde(default = "default_tolerance")]
    pub(super) tolerance: f64,
    #[serde(default, deserialize_with = "keys::fixed")]
    pub(super) z_range: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "keys::count")]
    pub(super) max_dexels: Option<u64>,
    #[serde(default = "default_measure_spacing")]
    pub(super) measure_spacing: f64,
    #[serde(default = "default_generators")]
    pub(super) measure_generators: usize,
}

fn default_spacing() -> f64 {
    0.01
}
fn default_cells() -> usize {
    3600
}
fn default_tolerance() -> f64 {
    0.01
}
fn default_measure_spacing() -> f64 {
    0.0005
}
fn default_generators() -> usize {
    12
}

impl Default for RawSimulation {
    fn default() -> Self {
        RawSimulation {
            axial_spacing: default_spacing(),
            angular_cells: default_cells(),
            tolerance: default_tolerance(),
            z_range: None,
            max_dexels: None,
            measure_spacing: default_measure_spacing(),
            measure_generators: default_generators(),
        }
    }
}
