//! Thread standards: designations as drawings write them (`M30x2-6g`, `1/2-13 UNC-2B`,
//! `Tr40x14(P7)-8e`, `G1/2 A`, `1/2-14 NPT`), parsed into the thread they name
//! ([`Designation`]), and the limits of size of their tolerance class ([`ThreadClass`]).
//!
//! - `designation`: the parser (case and spaces as people write them; errors say what was
//!   expected, where);
//! - `iso965`: ISO 965-1 metric M (tables and formulas), ISO 261's coarse series;
//! - `unified`: ASME B1.1 Unified (series tables, formulas with B1.1's rounding);
//! - `trapezoidal`: ISO 2903 Tr and ASME B1.5 Acme (the published values vpcut has);
//! - `pipe`: NPT (ASME B1.20.1), G (ISO 228-1), R/Rc/Rp (ISO 7-1).
//!
//! Lengths are mm; an inch designation's sizes are converted exactly (25.4 mm/in).

mod designation;
mod iso965;
mod pipe;
mod trapezoidal;
mod unified;

#[cfg(test)]
mod parse_tests;
#[cfg(test)]
mod tests;

use crate::model::thread::Side;
use crate::model::tolerance::{ThreadClass, UnitSystem};

pub use designation::parse;
use iso965::MetricClass;
pub use unified::Series;
use unified::UnifiedClass;

/// Why a designation or a class cannot be read or has no limits in vpcut. The message says
/// what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct StandardError {
    /// What is wrong, in the drawing's words.
    pub message: String,
}

impl StandardError {
    fn new(message: impl Into<String>) -> StandardError {
        StandardError {
            message: message.into(),
        }
    }
}

/// The family of basic profile a designation names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// ISO 68-1 metric, 60°.
    IsoMetric,
    /// Unified (and NPT's) 60°.
    Unified,
    /// ISO 2904 trapezoidal, 30°.
    Trapezoidal,
    /// Acme, 29°.
    Acme,
    /// Whitworth, 55° (G, R, Rc, Rp).
    Whitworth,
}

/// The standard a designation belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    /// ISO metric (M), ISO 965.
    Metric,
    /// Unified inch, ASME B1.1.
    Unified(Series),
    /// ISO metric trapezoidal (Tr), ISO 2903.
    Trapezoidal,
    /// Acme, ASME B1.5.
    Acme,
    /// American taper pipe thread, ASME B1.20.1.
    Npt,
    /// Parallel pipe thread (G), ISO 228-1.
    PipeParallel,
    /// Taper pipe thread, ISO 7-1: external (R) or internal (Rc).
    PipeTaper {
        /// Rc rather than R.
        internal: bool,
    },
    /// Parallel internal pipe thread (Rp), ISO 7-1.
    PipeParallelInternal,
}

/// The length of engagement a metric designation names (ISO 965-1 §7: S, N, L or a length
/// in mm; N when none is written).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Engagement {
    /// Short (S).
    Short,
    /// Normal (N).
    Normal,
    /// Long (L).
    Long,
    /// An explicit length (mm).
    Length(f64),
}

/// A tolerance class as a designation writes it.
#[derive(Clone, Debug, PartialEq)]
enum ClassSpec {
    /// None written.
    None,
    /// ISO 965 (`6g`, `4h6h`, `6H`).
    Metric(MetricClass),
    /// ISO 965 fit (`6H/6g`): internal, external.
    MetricFit(MetricClass, MetricClass),
    /// ISO 2903 (`7e`, `8c`, `7H`): grade and position.
    Trapezoidal(u8, char),
    /// ISO 2903 fit (`7H/7e`).
    TrapezoidalFit((u8, char), (u8, char)),
    /// ASME B1.1 (`2A`).
    Unified(UnifiedClass),
    /// ASME B1.5 (`2G`).
    Acme(String),
    /// ISO 228-1 external class A or B.
    Pipe(char),
}

/// A thread as its designation names it: standard, basic size, pitch, starts, hand and
/// tolerance class.
#[derive(Clone, Debug, PartialEq)]
pub struct Designation {
    /// The designation normalised (`M30x2-6g`, `1/2-13 UNC-2B`, `Tr40x14(P7)-8e`).
    pub text: String,
    /// The standard.
    pub standard: Standard,
    /// Basic major diameter (mm); a taper pipe thread's at its gauge plane.
    pub major: f64,
    /// Pitch (mm): the axial distance between neighbouring threads.
    pub pitch: f64,
    /// Number of starts (lead = starts x pitch).
    pub starts: u32,
    /// A left-hand thread (`LH`).
    pub left_hand: bool,
    /// The length of engagement (metric; Normal elsewhere).
    pub engagement: Engagement,
    /// The tolerance class as written.
    class: ClassSpec,
    /// The designation was written without a lower-case letter: a position letter's case
    /// says nothing (ISO 965: lower case external, upper case internal).
    all_caps: bool,
    /// An inch or pipe size as written (`1 1/4`, `#10`), for the tables.
    size: String,
    /// Threads per inch of an inch designation.
    tpi: Option<f64>,
}

impl Designation {
    /// The family of the basic profile.
    pub fn form(&self) -> Form {
        match self.standard {
            Standard::Metric => Form::IsoMetric,
            Standard::Unified(_) | Standard::Npt => Form::Unified,
            Standard::Trapezoidal => Form::Trapezoidal,
            Standard::Acme => Form::Acme,
            _ => Form::Whitworth,
        }
    }

    /// Metric or inch.
    pub fn units(&self) -> UnitSystem {
        match self.standard {
            Standard::Unified(_) | Standard::Acme | Standard::Npt => UnitSystem::Inch,
            _ => UnitSystem::Metric,
        }
    }

    /// Taper on diameter per unit length (1/16 for NPT, R, Rc), else 0.
    pub fn taper(&self) -> f64 {
        match self.standard {
            Standard::Npt | Standard::PipeTaper { .. } => 1.0 / 16.0,
            _ => 0.0,
        }
    }

    /// Included flank angle of the basic profile (degrees).
    pub fn flank_angle_deg(&self) -> f64 {
        match self.form() {
            Form::IsoMetric | Form::Unified => 60.0,
            Form::Trapezoidal => 30.0,
            Form::Acme => 29.0,
            Form::Whitworth => 55.0,
        }
    }

    /// Whether a tolerance class is written (ISO 228-1's internal `G1/2` and NPT's
    /// designation are classes without letters: they count).
    pub fn has_class(&self) -> bool {
        !matches!(self.class, ClassSpec::None)
            || matches!(
                self.standard,
                Standard::PipeParallel | Standard::Npt | Standard::PipeTaper { .. }
            )
    }

    /// Whether the class is a fit (`6H/6g`): it names both threads.
    pub fn is_fit(&self) -> bool {
        matches!(
            self.class,
            ClassSpec::MetricFit(..) | ClassSpec::TrapezoidalFit(..)
        )
    }

    /// The side the designation itself says: the class's letters (ISO 965 and ISO 2903 by
    /// case, B1.1 by A/B, ISO 228-1 by a class letter or none), R external, Rc and Rp
    /// internal. None for a fit, NPT, Acme, a designation without class, and a class in
    /// capitals whose letter exists in both cases (`M30X2-6G`).
    pub fn implied_side(&self) -> Option<Side> {
        let by_case = |pos: char, external_only: &[char]| {
            if self.all_caps && !external_only.contains(&pos) {
                None
            } else if pos.is_ascii_uppercase() && !external_only.contains(&pos) {
                Some(Side::Internal)
            } else {
                Some(Side::External)
            }
        };
        match (&self.class, self.standard) {
            (ClassSpec::Metric(c), _) => by_case(c.pitch.1, &['E', 'F']),
            (ClassSpec::Trapezoidal(_, pos), _) => by_case(*pos, &['C', 'E']).or(
                // Tr's H has no lower-case twin among the external positions.
                (*pos == 'H').then_some(Side::Internal),
            ),
            (ClassSpec::Unified(c), _) => Some(if c.internal {
                Side::Internal
            } else {
                Side::External
            }),
            (ClassSpec::Pipe(_), _) => Some(Side::External),
            (ClassSpec::None, Standard::PipeParallel) => Some(Side::Internal),
            (_, Standard::PipeTaper { internal }) => Some(if internal {
                Side::Internal
            } else {
                Side::External
            }),
            (_, Standard::PipeParallelInternal) => Some(Side::Internal),
            _ => None,
        }
    }

    /// The limits of size of the class the designation names, for the thread on `side`
    /// (the job's `side`, when it gives one: it picks a fit's thread and reads a class in
    /// capitals). `None` when no class is written.
    pub fn class(&self, side: Option<Side>) -> Result<Option<ThreadClass>, StandardError> {
        let internal = |s: Side| s == Side::Internal;
        let t = &self.text;
        let fit_side = || {
            side.ok_or_else(|| {
                StandardError::new(format!(
                    "{t} is a fit (an internal and an external class): say which thread this is (its side)"
                ))
            })
        };
        let class = match (&self.class, self.standard) {
            (ClassSpec::None, Standard::PipeParallel) => pipe::g_limits(t, &self.size, None)?,
            (ClassSpec::None, Standard::Npt) => {
                pipe::npt_limits(t, &self.size, side.is_some_and(internal))?
            }
            (ClassSpec::None, Standard::PipeTaper { internal }) => {
                pipe::r_limits(t, &self.size, internal)?
            }
            (ClassSpec::None, _) => return Ok(None),
            (ClassSpec::Metric(c), _) => {
                let c = self.metric_case(*c, side)?;
                iso965::limits(t, self.major, self.pitch, self.starts, c, self.engagement)?
            }
            (ClassSpec::MetricFit(i, e), _) => {
                let c = if internal(fit_side()?) { *i } else { *e };
                let c = self.metric_case(c, side)?;
                iso965::limits(t, self.major, self.pitch, self.starts, c, self.engagement)?
            }
            (ClassSpec::Trapezoidal(g, pos), _) => {
                let pos = self.tr_case(*pos);
                trapezoidal::limits(t, self.major, self.pitch, self.starts, *g, pos, pos == 'H')?
            }
            (ClassSpec::TrapezoidalFit(i, e), _) => {
                let (g, pos) = if internal(fit_side()?) { *i } else { *e };
                trapezoidal::limits(t, self.major, self.pitch, self.starts, g, pos, pos == 'H')?
            }
            (ClassSpec::Unified(c), Standard::Unified(series)) => {
                let tpi = self.tpi.unwrap_or(25.4 / self.pitch);
                unified::limits(t, self.major / 25.4, tpi, self.starts, Some(series), *c)?
            }
            (ClassSpec::Unified(_), _) => {
                return Err(StandardError::new(format!(
                    "{t}: a B1.1 class belongs to a UN designation"
                )))
            }
            (ClassSpec::Acme(c), _) => trapezoidal::acme_limits(t, c)?,
            (ClassSpec::Pipe(c), _) => pipe::g_limits(t, &self.size, Some(*c))?,
        };
        Ok(Some(class))
    }

    /// A metric class as meant: a designation in capitals reads G and H by `side`.
    fn metric_case(
        &self,
        c: MetricClass,
        side: Option<Side>,
    ) -> Result<MetricClass, StandardError> {
        if !self.all_caps {
            return Ok(c);
        }
        let (p, q) = (c.pitch.1, c.crest.1);
        let external = if ['E', 'F'].contains(&p) {
            true
        } else {
            match side {
                Some(s) => s == Side::External,
                None => {
                    let lower = MetricClass {
                        pitch: (c.pitch.0, p.to_ascii_lowercase()),
                        crest: (c.crest.0, q.to_ascii_lowercase()),
                    };
                    return Err(StandardError::new(format!(
                        "{} is written in capitals: its class could be {} (internal) or {} (external); ISO 965 writes internal positions in upper case and external ones in lower case: write the class in its case or say the thread's side",
                        self.text,
                        c.text(),
                        lower.text()
                    )));
                }
            }
        };
        Ok(if external {
            MetricClass {
                pitch: (c.pitch.0, p.to_ascii_lowercase()),
                crest: (c.crest.0, q.to_ascii_lowercase()),
            }
        } else {
            c
        })
    }

    /// A Tr position as meant: C and E are external in any case (Tr has no internal C or
    /// E), H internal.
    fn tr_case(&self, pos: char) -> char {
        if pos == 'H' {
            pos
        } else {
            pos.to_ascii_lowercase()
        }
    }

    /// The basic pitch diameter (mm) of the profile.
    pub fn basic_pitch_diameter(&self) -> f64 {
        let p = self.pitch;
        match self.form() {
            Form::IsoMetric | Form::Unified => self.major - 0.649_519_052_838_329 * p,
            Form::Trapezoidal | Form::Acme => self.major - 0.5 * p,
            Form::Whitworth => self.major - pipe::whitworth_depth(p),
        }
    }

    /// The basic minor diameter (mm) of a Whitworth profile (its root and crest rounded:
    /// d − 2h, h = 0.640327P); the other forms' come from the job's form data.
    pub fn whitworth_minor(&self) -> f64 {
        self.major - 2.0 * pipe::whitworth_depth(self.pitch)
    }
}

/// The limits of size of `class` (`6g`, `2B`, `7e`) for a thread the designation does not
/// name in full (a size the tables may not list): `form`, basic major diameter and pitch in
/// mm. ISO 965-1's formulas off its tables; B1.1's formulas (the series placed by the
/// pitch, see `unified::engagement`).
pub fn class_for(
    form: Form,
    major: f64,
    pitch: f64,
    starts: u32,
    class: &str,
) -> Result<ThreadClass, StandardError> {
    let num = designation::fmt_num;
    match form {
        Form::IsoMetric => {
            let c = designation::metric_class(class)?;
            let text = format!("M{}x{}-{}", num(major), num(pitch), c.text());
            iso965::limits(&text, major, pitch, starts, c, Engagement::Normal)
        }
        Form::Unified => {
            let c = designation::unified_class(class)?;
            let (d, tpi) = (major / 25.4, 25.4 / pitch);
            let text = format!("{}-{} UN-{}", num(d), num(tpi), c.text());
            unified::limits(&text, d, tpi, starts, None, c)
        }
        Form::Trapezoidal => {
            let (g, pos) = designation::tr_class(class)?;
            let text = format!("Tr{}x{}-{g}{pos}", num(major), num(pitch * starts as f64));
            trapezoidal::limits(&text, major, pitch, starts, g, pos, pos == 'H')
        }
        Form::Acme => trapezoidal::acme_limits(&format!("ACME-{class}"), class),
        Form::Whitworth => Err(StandardError::new(
            "a Whitworth pipe thread's class comes with its designation (G1/2 A)",
        )),
    }
}
