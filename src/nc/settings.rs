//! What a program cannot say about the machine it runs on ([`Settings`], set by the job's
//! `[program]` and `[machine]`), and FANUC G76's parameters ([`G76Params`]).

use super::{DecimalPoint, GcodeSystem, InputIncrement, MillSettings, NoseData, PowerOn};

/// What a program cannot say about the machine it runs on: set by the job (`[program]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Thread chamfer (pull-out) length of G92 and G76 in leads: FANUC parameter 5130
    /// (in 0.1 L there). G76 `P(mmrraa)` overwrites it with `rr`/10, as on FANUC. 0 = none.
    pub thread_chamfer: f64,
    /// Work offsets G54..G59: (X as a diameter, Z) of each work zero in the job's frame.
    pub work_offsets: [(f64, f64); 6],
    /// Skip blocks that start with `/` (the block-skip switch on); false runs them.
    pub block_skip: bool,
    /// The reference point G28 returns to: (X as a diameter, Z) in the job's frame (machine
    /// coordinates). `None`: the machine zero (0, 0), as a control whose reference point is
    /// at its machine zero (LinuxCNC's #5161/#5163 start at 0 too).
    pub reference_point: Option<(f64, f64)>,
    /// The second reference point FANUC/GSK `G30` (P2) goes to, and LinuxCNC's G30 home
    /// (#5181/#5183) at the start: (X as a diameter, Z) in machine coordinates. `None`:
    /// the machine zero.
    pub second_reference_point: Option<(f64, f64)>,
    /// A milling machine's settings: when set, FANUC programs are read as milling programs
    /// and their moves come out as [`Toolpath::mill`].
    pub mill: Option<MillSettings>,
    /// FANUC/GSK lathe G-code system (A, B or C; [`GcodeSystem`]).
    pub gcode_system: GcodeSystem,
    /// Whether the job or the command line named the G-code system. When not, a FANUC
    /// lathe program that shows system B or C (G90/G91, G94/G95 as modes, and nothing of
    /// system A) is read in that system, with a warning (`detect`).
    pub gcode_system_named: bool,
    /// How a FANUC/GSK number without a decimal point is read ([`DecimalPoint`]).
    pub decimal_point: DecimalPoint,
    /// The least input increment of FANUC/GSK words without a decimal point
    /// ([`InputIncrement`]).
    pub input_increment: InputIncrement,
    /// The modes the control is in when the program starts ([`PowerOn`]).
    pub power_on: PowerOn,
    /// The main program of a file that holds several (FANUC/GSK `O` numbers), by name
    /// (`O1000`); `None`: the one the control would run (the first that ends in M30/M02
    /// and that no other calls).
    pub main: Option<String>,
    /// The tool offsets by number (FANUC/GSK T0305 calls number 5, Siemens D5): the shift
    /// (X as a diameter, Z) of the tool's point from where the program drives it,
    /// geometry and wear together. `None`: the job gives no offsets, and every offset is
    /// taken as zero; with a table, calling a number it lacks is a warning at the block.
    pub tool_offsets: Option<ToolOffsets>,
    /// What a FANUC/GSK two-block G76 uses when the program leaves its first block out:
    /// the control's parameters (FANUC No. 5142, 5143, 5140, 5141).
    pub g76: G76Params,
    /// LinuxCNC: the folders searched, in order, for the file `name.ngc` of an
    /// `o<name> call` that the program's file does not define, after the program's own
    /// folder (the INI's `[RS274NGC] SUBROUTINE_PATH`, as `Interp::find_ngc_file` searches
    /// it: the first folder that has the file wins). Names as the loader reads them
    /// (relative to the job's folder).
    pub subroutine_path: Vec<String>,
    /// Tool nose radius compensation's radius and tip direction: by tool number (`tool`,
    /// the job's turning tools), and by offset number where the offset page says (`offset`).
    pub noses: NoseData,
    /// Siemens: the machine's definition files (GUD and macro `.DEF` files, cycle `.SPF`
    /// files), read through the loader before the program (`siemens_defs`).
    pub definitions: Vec<String>,
}

/// Tool offsets by number: the shift (X as a diameter, Z) of the tool's point.
pub type ToolOffsets = std::collections::BTreeMap<u32, (f64, f64)>;

/// The FANUC/GSK G76 first block's values as the control's parameters hold them (FANUC
/// 0i/30i lathe parameters: No. 5142 finishing passes, 5143 tool angle, 5140 minimum cut,
/// 5141 finishing allowance; the chamfer is No. 5130, [`Settings::thread_chamfer`]). A
/// first block overwrites them for the rest of the run, as on the control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct G76Params {
    /// Finishing passes at the full depth, `m` (1 to 99).
    pub finish_passes: u32,
    /// Tool angle `a` (deg): the infeed runs at half of it.
    pub tool_angle: f64,
    /// Minimum cut `dmin` (mm, radius).
    pub min_cut: f64,
    /// Finishing allowance `d` (mm, radius).
    pub finish_allowance: f64,
}

impl Default for G76Params {
    /// vpcut's defaults: one finishing pass, 60 deg, no minimum cut, no allowance.
    fn default() -> G76Params {
        G76Params {
            finish_passes: 1,
            tool_angle: 60.0,
            min_cut: 0.0,
            finish_allowance: 0.0,
        }
    }
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            thread_chamfer: 0.0,
            work_offsets: [(0.0, 0.0); 6],
            block_skip: true,
            reference_point: None,
            second_reference_point: None,
            mill: None,
            gcode_system: GcodeSystem::A,
            gcode_system_named: false,
            decimal_point: DecimalPoint::Standard,
            input_increment: InputIncrement::Micrometre,
            power_on: PowerOn::default(),
            main: None,
            tool_offsets: None,
            g76: G76Params::default(),
            subroutine_path: Vec::new(),
            noses: NoseData::default(),
            definitions: Vec::new(),
        }
    }
}

#[cfg(test)]
impl Settings {
    /// The default settings but calculator-type decimal-point input: the machine the unit
    /// tests' programs are written for where they write plain numbers in millimetres (`X60
    /// Z8`), as vpcut read every program before standard input became the default (issue
    /// 30). `units_tests` tests both inputs.
    pub(crate) fn in_mm() -> Settings {
        Settings {
            decimal_point: DecimalPoint::Calculator,
            ..Settings::default()
        }
    }
}
