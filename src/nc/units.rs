//! How the words of a program become millimetres, and which program of a file runs: the
//! machine settings a program relies on without saying them.
//!
//! - **Decimal-point input** (FANUC parameter 3401#0 DPI; GSK 980TDc, Haas and the other
//!   FANUC-style controls read numbers the same way): a number written with a decimal point
//!   is in millimetres (inches under G20); one written without a point, at an address that
//!   takes a point (X, Z, U, W, R, I, K, ...), counts in the least input increment on a
//!   control in *standard* input (the factory setting: `X30` is 0.030 mm) and in
//!   millimetres on one set to *calculator-type* input (`X30` is 30 mm). A value that comes
//!   from a variable or an expression (`X#1`, `Z[#2+1]`) is always in millimetres (FANUC
//!   custom macro: "a constant without a point inside brackets counts as if it had one").
//!   Siemens and LinuxCNC have no such mode: their numbers are always in program units.
//! - Words that never take a point (G74..G76 P/Q, the threading start angle Q) count in
//!   their increment in both modes; a point on them is an alarm on the control and an error
//!   here.
//! - A thread lead (F, G34's K, GSK G34's R) written without a point in standard input has
//!   a unit that is a machine parameter of its own (FANUC 30i: 0.01 or 0.001 mm/rev; Haas
//!   setting 77): vpcut refuses it rather than guess, and says how to write it.
//! - **The least input increment** (increment system IS-B: 0.001 mm, 0.0001 in; IS-C:
//!   0.0001 mm, 0.00001 in).
//! - **Power-on modes**: inch or mm (G20/G21, Siemens G70/G71), feed per minute or per
//!   revolution (G98/G99, G94/G95), and diameter or radius programming of X.
//! - **The main program** of a FANUC/GSK file with several `O` programs ([`main_program`]).

use super::expr::Fail;
use super::program::Program;
use super::{Dialect, Interp, Words};

/// How a FANUC-style control reads a number written without a decimal point at an address
/// that takes one (FANUC parameter 3401#0 DPI).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DecimalPoint {
    /// DPI = 0, the factory setting: in the least input increment (`X30` = 0.030 mm).
    #[default]
    Standard,
    /// DPI = 1, "pocket calculator type": in millimetres or inches (`X30` = 30 mm).
    Calculator,
}

impl DecimalPoint {
    /// Parse `"standard"` or `"calculator"`.
    pub fn from_name(s: &str) -> Option<DecimalPoint> {
        match s {
            "standard" => Some(DecimalPoint::Standard),
            "calculator" => Some(DecimalPoint::Calculator),
            _ => None,
        }
    }

    /// The name used in jobs and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DecimalPoint::Standard => "standard",
            DecimalPoint::Calculator => "calculator",
        }
    }
}

/// The least input increment of a FANUC-style control (its increment system).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InputIncrement {
    /// IS-B: 0.001 mm, 0.0001 in (the common one).
    #[default]
    Micrometre,
    /// IS-C: 0.0001 mm, 0.00001 in.
    TenthMicrometre,
}

impl InputIncrement {
    /// From the increment in millimetres as the job writes it: 0.001 or 0.0001.
    pub fn from_mm(mm: f64) -> Option<InputIncrement> {
        if mm == 0.001 {
            Some(InputIncrement::Micrometre)
        } else if mm == 0.0001 {
            Some(InputIncrement::TenthMicrometre)
        } else {
            None
        }
    }

    /// One increment in millimetres (metric programs).
    pub fn mm(self) -> f64 {
        match self {
            InputIncrement::Micrometre => 0.001,
            InputIncrement::TenthMicrometre => 0.0001,
        }
    }

    /// One increment in inches (inch programs).
    pub fn inch(self) -> f64 {
        self.mm() / 10.0
    }
}

/// The modes the control is in when the program starts, which a program may rely on
/// without setting them (a machine set to inch at power-on runs an inch program without
/// G20).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PowerOn {
    /// Inch (G20; Siemens G70) at power-on, else mm.
    pub inch: bool,
    /// Feed per minute (G98 on FANUC/GSK lathes; G94) at power-on, else per revolution.
    pub per_minute: bool,
    /// X words are diameters (`Some(true)`) or radii (`Some(false)`); `None`: the
    /// dialect's usual (diameters on FANUC, GSK and Siemens lathes, radii on LinuxCNC, G8).
    pub diameter: Option<bool>,
}

/// A value written without a point reads as less than this many millimetres in standard
/// input while its digits say at least 1: it looks written for calculator-type input.
const SMALL_MM: f64 = 1.0;

/// A value written without a point reads as at least this many millimetres in
/// calculator-type input: it looks written for standard input (`X60640` for 60.640 mm).
const LARGE_MM: f64 = 10_000.0;

impl Interp<'_> {
    /// Millimetres per program unit: 25.4 under G20 (Siemens G70), else 1.
    pub(super) fn unit(&self) -> f64 {
        if self.modal.inch {
            25.4
        } else {
            1.0
        }
    }

    /// Millimetres of one least input increment in the current units.
    pub(super) fn increment_mm(&self) -> f64 {
        if self.modal.inch {
            self.cfg.increment.inch() * 25.4
        } else {
            self.cfg.increment.mm()
        }
    }

    /// Whether word `k` of `w` is a number written without a decimal point that a
    /// FANUC-style control in standard input reads in increments (not a variable or an
    /// expression; Siemens and LinuxCNC words never are).
    fn in_increments(&self, w: &Words, k: &str) -> bool {
        self.cfg.dialect == Dialect::Fanuc
            && self.cfg.decimal_point == DecimalPoint::Standard
            && w.plain.iter().any(|p| p == k)
    }

    /// Word `k` of `w` as a length in mm (a radius for X-derived cycle words; X itself is
    /// [`Interp::x_length`]): with a decimal point, from a variable, in calculator-type
    /// input and on Siemens and LinuxCNC in program units; written without a point in
    /// standard input, in the least input increment. The first axis word of a run whose
    /// plain digits look meant for the other input mode gets a warning that names the
    /// setting.
    pub(super) fn length(&mut self, w: &Words, k: &str) -> Option<f64> {
        let &(v, col) = w.vals.get(k)?;
        let plain = w.plain.iter().any(|p| p == k);
        let mm = if self.in_increments(w, k) {
            v * self.increment_mm()
        } else {
            v * self.unit()
        };
        if plain && v != 0.0 && self.cfg.dialect == Dialect::Fanuc && !self.out.units_noted {
            let axis = matches!(k, "X" | "Z" | "U" | "W" | "Y");
            let shown = format_plain(v);
            let note = match self.cfg.decimal_point {
                DecimalPoint::Standard if axis && mm.abs() < SMALL_MM && v.abs() >= 1.0 => Some((
                    format!(
                        "{k}{shown} has no decimal point: with standard decimal-point input (the factory setting) it is {} mm",
                        trim(mm)
                    ),
                    format!(
                        "if the program means {k}{shown}. ({shown} {}), the machine reads plain numbers as millimetres (calculator-type input): set decimal_point = \"calculator\" ([program] in the job, --decimal-point on `vpcut toolpath`)",
                        if self.modal.inch { "in" } else { "mm" }
                    ),
                )),
                DecimalPoint::Calculator if axis && mm.abs() >= LARGE_MM => Some((
                    format!(
                        "{k}{shown} has no decimal point: with calculator-type input it is {} mm",
                        trim(mm)
                    ),
                    format!(
                        "if it means {} mm in the least input increment, the machine uses standard decimal-point input: set decimal_point = \"standard\" ([program] in the job, --decimal-point on `vpcut toolpath`)",
                        trim(v * self.increment_mm())
                    ),
                )),
                _ => None,
            };
            if let Some((message, hint)) = note {
                self.out.units_noted = true;
                self.out.notes.push((col, message, hint));
            }
        }
        Some(mm)
    }

    /// An X or U word as a diameter in mm ([`Interp::length`], doubled in radius
    /// programming).
    pub(super) fn x_length(&mut self, w: &Words, k: &str) -> Option<f64> {
        let xs = if self.modal.diameter_mode { 1.0 } else { 2.0 };
        self.length(w, k).map(|v| v * xs)
    }

    /// A word that counts in the least input increment (FANUC G74..G76 `P`/`Q`: "never take
    /// a point"), in mm. Written with a decimal point it is read in program units with a
    /// warning: Haas and the FANUC-style controls of program generators accept
    /// `G76 X38.05 Z-40. P0.974 Q0.3` (issue 27), where a FANUC 0i alarms (PS0007, illegal
    /// use of decimal point). `what` names the code in the message.
    pub(super) fn increment_word(
        &mut self,
        w: &Words,
        k: &str,
        what: &str,
    ) -> Result<Option<f64>, Fail> {
        let Some(&(v, col)) = w.vals.get(k) else {
            return Ok(None);
        };
        if w.points.iter().any(|p| p == k) {
            let (unit, inc) = if self.modal.inch {
                ("in", self.cfg.increment.inch())
            } else {
                ("mm", self.cfg.increment.mm())
            };
            self.out.notes.push((
                col,
                format!("{what} {k}{v} has a decimal point: read as {v} {unit}, as the controls that accept the point here do (Haas, FANUC-style controls of program generators)"),
                format!("{what} {k} counts in the least input increment ({inc} {unit}) without a point; a FANUC 0i alarms on the point (PS0007, illegal use of decimal point)"),
            ));
            return Ok(Some(v * self.unit()));
        }
        Ok(Some(v * self.increment_mm()))
    }

    /// A word that counts in the least input increment unless written with a decimal point
    /// (then in program units), in either input mode: the one-block G76's `K`/`D` and the
    /// one-block G71/G72's `D`, as FANUC 0T and Haas write them (`D0140`, `K.0511`).
    pub(super) fn increment_or_units(&self, w: &Words, k: &str) -> Option<f64> {
        let v = w.vals.get(k)?.0;
        Some(if w.points.iter().any(|p| p == k) {
            v * self.unit()
        } else {
            v * self.increment_mm()
        })
    }

    /// A lead word (`F` of a thread block or cycle, FANUC G34's `K`, GSK G34's `R`, the
    /// tap's pitch) in mm/rev: in program units with a point, from a variable, in
    /// calculator-type input and on Siemens/LinuxCNC. Written without a point (and not 0)
    /// in standard input it is refused: its unit there is a machine parameter of its own
    /// (FANUC 30i: 0.01 or 0.001 mm/rev; Haas setting 77), which vpcut does not guess.
    pub(super) fn lead_word(&self, w: &Words, k: &str, what: &str) -> Result<Option<f64>, Fail> {
        let Some(&(v, col)) = w.vals.get(k) else {
            return Ok(None);
        };
        if self.in_increments(w, k) {
            self.plain_lead(v, col, what, k)?;
        }
        Ok(Some(v * self.unit()))
    }

    /// A lead `k` = `v` written without a decimal point (at column `col` of `what`): an
    /// error in standard decimal-point input on FANUC/GSK (unless it is 0), else fine.
    pub(super) fn plain_lead(&self, v: f64, col: usize, what: &str, k: &str) -> Result<(), Fail> {
        if v != 0.0
            && self.cfg.dialect == Dialect::Fanuc
            && self.cfg.decimal_point == DecimalPoint::Standard
        {
            let shown = format_plain(v);
            return Err((
                col,
                format!(
                    "{what} {k}{shown} has no decimal point: with standard decimal-point input the unit of a lead written without a point is a machine parameter (0.01, 0.001 or 0.0001 mm/rev), which vpcut does not guess; write {k}{shown}. for {shown} {}/rev, or, if the machine reads plain numbers as millimetres, set decimal_point = \"calculator\" ([program] in the job, --decimal-point on `vpcut toolpath`)",
                    if self.modal.inch { "in" } else { "mm" }
                ),
            ));
        }
        Ok(())
    }

    /// A G65 macro call's argument of address `letter` with value `v` (`plain`: written
    /// without a decimal point) as the local variable holds it, in program units. FANUC
    /// Custom Macro B, "Decimal point position of argument": "the units used for argument
    /// data passed without a decimal point correspond to the least input increment of each
    /// address". In standard input a plain number at a length address (X Y Z U V W I J K R)
    /// counts in the least input increment (`X50` passes 0.050), at an angle address (A B C)
    /// in 0.001 deg (0.0001 with IS-C); every other address (D E F M Q S T, whose increment is
    /// a machine matter or 1), every value with a point or from a variable, and every
    /// argument in calculator-type input, as written.
    pub(super) fn argument(&self, letter: u8, v: f64, plain: bool) -> f64 {
        if !plain || self.cfg.decimal_point == DecimalPoint::Calculator {
            return v;
        }
        match letter {
            b'X' | b'Y' | b'Z' | b'U' | b'V' | b'W' | b'I' | b'J' | b'K' | b'R' => {
                if self.modal.inch {
                    v * self.cfg.increment.inch()
                } else {
                    v * self.cfg.increment.mm()
                }
            }
            b'A' | b'B' | b'C' => v * self.cfg.increment.mm(),
            _ => v,
        }
    }

    /// The threading start angle `Q` of G32/G92/the one-block G76 in degrees: it counts in
    /// 0.001 deg and takes no decimal point (FANUC 30i-A lathe manual B-63944EN, G92: "Q_:
    /// Angle for shifting the threading start angle (Increment: 0.001 degrees, Valid
    /// setting range: 0 to 360 degrees)"; Haas G76: "Do not use a decimal point"). 0
    /// without one.
    pub(super) fn start_angle(&self, w: &Words, what: &str) -> Result<f64, Fail> {
        let Some(&(q, col)) = w.vals.get("Q") else {
            return Ok(0.0);
        };
        if w.points.iter().any(|p| p == "Q") {
            return Err((
                col,
                format!("{what} Q (the start angle) counts in 0.001 deg and takes no decimal point: Q{} is written Q{}", trim(q), trim(q * 1000.0)),
            ));
        }
        Ok(q / 1000.0)
    }
}

impl Interp<'_> {
    /// The end point of a cycle block's `X(U) Z(W)` (diameter, z) in the job's frame: X/Z
    /// absolute in the active work system (incremental under G91 in G-code systems B/C),
    /// U/W from the current point; a missing axis stays where it is.
    pub(super) fn cycle_end(&mut self, w: &Words) -> (f64, f64) {
        let (x0, z0) = (self.x, self.z);
        let (ox, oz) = self.frames.offsets[self.frames.work];
        let inc = self.modal.incremental;
        let x = match (self.x_length(w, "X"), self.x_length(w, "U")) {
            (Some(x), _) if inc => x0 + x,
            (Some(x), _) => x + ox,
            (None, Some(u)) => x0 + u,
            _ => x0,
        };
        let z = match (self.length(w, "Z"), self.length(w, "W")) {
            (Some(z), _) if inc => z0 + z,
            (Some(z), _) => z + oz,
            (None, Some(wv)) => z0 + wv,
            _ => z0,
        };
        (x, z)
    }

    /// A warning when a cycle's thread height `k` (mm, word `word` of `w`) is more than a
    /// quarter of the diameter `x` it is cut to: no standard thread is that deep (ISO
    /// metric coarse: 0.61 P with P at most d/6; trapezoidal: about d/8), so its numbers
    /// are most likely read in the wrong unit. The hint names the setting.
    pub(super) fn check_thread_height(&mut self, w: &Words, word: &str, k: f64, x: f64) {
        if x.abs() <= 0.0 || k <= x.abs() / 4.0 {
            return;
        }
        let Some(&(v, col)) = w.vals.get(word) else {
            return;
        };
        let plain = !w.points.iter().any(|p| p == word);
        let hint = if plain && self.cfg.increment == InputIncrement::Micrometre {
            format!(
                "{word}{} counts in the least input increment: on a machine whose increment is 0.0001 mm (IS-C) it is {} mm; set input_increment = 0.0001 ([program] in the job, --input-increment on `vpcut toolpath`)",
                trim(v),
                trim(k / 10.0)
            )
        } else {
            "check the thread height and the machine's units (decimal_point, input_increment and units of [program])".to_string()
        };
        self.out.notes.push((
            col,
            format!(
                "a thread {} mm deep cut to a diameter of {} mm: deeper than a quarter of its diameter, which no standard thread is",
                trim(k),
                trim(x.abs())
            ),
            hint,
        ));
    }
}

/// A lead finer than this (mm/rev) in a metric program that never selects its units reads
/// like inches: the finest standard thread pitch is 0.2 mm (ISO 261, M1), the finest common
/// inch lead 1/80 in = 0.3175 mm.
const FINE_LEAD_MM: f64 = 0.1;

impl Interp<'_> {
    /// The warning (once a run) at a thread move made since move `from` whose lead is
    /// under 0.1 mm/rev while the program runs in mm without having selected its units: an
    /// inch program on a machine that is in inch at power-on (`F0.0625` = 16 threads per
    /// inch read as 0.0625 mm).
    pub(super) fn check_inch_lead(&mut self, from: usize) {
        if self.out.inch_noted || self.modal.inch || self.modal.units_set {
            return;
        }
        let Some(lead) = self.out.moves[from.min(self.out.moves.len())..]
            .iter()
            .filter_map(|m| m.lead)
            .find(|&l| l > 0.0 && l < FINE_LEAD_MM)
        else {
            return;
        };
        self.out.inch_noted = true;
        self.out.notes.push((
            0,
            format!(
                "a lead of {} mm/rev, finer than any standard thread, in a program that never selects its units: read as inches it is {} in ({} threads per inch)",
                trim(lead),
                trim(lead),
                trim((1.0 / lead * 1000.0).round() / 1000.0)
            ),
            "if the machine is in inch at power-on, set units = \"inch\" ([program] in the job, --units on `vpcut toolpath`); the program can say it itself with G20 (Siemens G70)".into(),
        ));
    }
}

/// A value as written without a point (a whole number, or as it is).
fn format_plain(v: f64) -> String {
    trim(v)
}

/// A number without trailing zeros (`0.03`, `120`).
fn trim(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// Which program of a file with several (FANUC/GSK `O` numbers) is the main program: the
/// one `wanted` names (`Err` with the names there are when none is called so), else, as a
/// control is used, the first that ends the run (M30 or M02) and that no other program of
/// the file calls, else the first that no other calls, else the first. `names[i]` are the
/// names each program answers to (its `O` number and, for the first, the file's name);
/// `facts[i]` the programs it calls by a literal number and whether it has M30 or M02.
pub(super) fn main_program(
    names: &[Vec<String>],
    facts: &[(Vec<String>, bool)],
    wanted: Option<&str>,
) -> Result<usize, String> {
    if let Some(want) = wanted {
        let norm = normalise(want);
        return names
            .iter()
            .position(|ns| ns.iter().any(|n| normalise(n) == norm))
            .ok_or_else(|| {
                let all: Vec<String> = names
                    .iter()
                    .filter_map(|ns| ns.iter().find(|n| n.starts_with('O')).or(ns.first()))
                    .cloned()
                    .collect();
                format!(
                    "no program {want} in the file (it holds {})",
                    all.join(", ")
                )
            });
    }
    let called = |i: usize| {
        facts.iter().enumerate().any(|(j, (calls, _))| {
            j != i
                && calls
                    .iter()
                    .any(|c| names[i].iter().any(|n| normalise(n) == normalise(c)))
        })
    };
    let ends = |i: usize| facts[i].1;
    let n = names.len();
    Ok((0..n)
        .find(|&i| ends(i) && !called(i))
        .or_else(|| (0..n).find(|&i| !called(i)))
        .unwrap_or(0))
}

/// A program name compared as a control does: `O0100`, `O100` and `100` are one program.
fn normalise(name: &str) -> String {
    let t = name.trim();
    let digits = t
        .strip_prefix('O')
        .or_else(|| t.strip_prefix('o'))
        .unwrap_or(t);
    match digits.parse::<u64>() {
        Ok(n) => format!("O{n}"),
        Err(_) => t.to_ascii_uppercase(),
    }
}

/// The names a loaded program answers to: its own and its alias.
pub(super) fn names_of(p: &Program) -> Vec<String> {
    let mut v = vec![p.name.clone()];
    v.extend(p.alias.clone());
    v
}
