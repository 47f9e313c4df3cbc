//! Lengths in the user's units: every length a message or the summary gives is in mm, and
//! for an inch job ([`crate::Job::inch`]: an inch class or designation, an inch form, or a
//! program that cuts the thread in inches) the same length in inches beside it, and a
//! pitch or lead in threads per inch. The report's numbers stay in mm; [`InchThread`] gives
//! the thread's figures in inches.

use serde::Serialize;

/// Millimetres in an inch.
pub(crate) const MM_PER_INCH: f64 = 25.4;

/// How lengths read for a person.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Units {
    /// An inch job: inches (and TPI) beside mm.
    pub(crate) inch: bool,
}

impl Units {
    /// A length: `0.1270 mm`, or for an inch job `0.1270 mm (0.00500 in)`: `d` decimals in
    /// mm, one more in inches (0.0001 mm is 0.000004 in).
    pub(crate) fn len(self, v: f64, d: usize) -> String {
        if self.inch {
            format!("{v:.d$} mm ({:.e$} in)", v / MM_PER_INCH, e = d + 1)
        } else {
            format!("{v:.d$} mm")
        }
    }

    /// An axial position: `z -12.625`, or `z -12.625 (-0.4970 in)`.
    pub(crate) fn z(self, v: f64) -> String {
        if self.inch {
            format!("z {v:.3} ({:.4} in)", v / MM_PER_INCH)
        } else {
            format!("z {v:.3}")
        }
    }

    /// A pitch or a single-start thread's lead: `2.1167 mm`, or `2.1167 mm (0.08333 in,
    /// 12.000 TPI)`; `tpi` false (a multi-start lead) leaves out the threads per inch.
    pub(crate) fn pitch(self, v: f64, d: usize, tpi: bool) -> String {
        match (self.inch, tpi && v > 0.0) {
            (false, _) => format!("{v:.d$} mm"),
            (true, false) => self.len(v, d),
            (true, true) => format!(
                "{v:.d$} mm ({:.e$} in, {:.3} TPI)",
                v / MM_PER_INCH,
                MM_PER_INCH / v,
                e = d + 1
            ),
        }
    }
}

/// An inch thread's figures in inches (`thread.inch` in the report).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InchThread {
    /// Threads per inch (of the pitch).
    pub tpi: f64,
    /// Major diameter (in).
    pub major_diameter_in: f64,
    /// Pitch diameter (in).
    pub pitch_diameter_in: f64,
    /// Minor diameter (in).
    pub minor_diameter_in: f64,
    /// Depth of the thread, (major - minor) / 2 (in).
    pub depth_in: f64,
    /// Lead at the start (in per revolution).
    pub lead_in: f64,
}

impl InchThread {
    /// The figures of a thread of these diameters, pitch and lead (mm), rounded to 1e-6 in.
    pub(crate) fn of(major: f64, pitch_dia: f64, minor: f64, pitch: f64, lead: f64) -> InchThread {
        let i = |v: f64| crate::report::r6(v / MM_PER_INCH);
        InchThread {
            tpi: crate::report::r6(if pitch > 0.0 {
                MM_PER_INCH / pitch
            } else {
                0.0
            }),
            major_diameter_in: i(major),
            pitch_diameter_in: i(pitch_dia),
            minor_diameter_in: i(minor),
            depth_in: i((major - minor) / 2.0),
            lead_in: i(lead),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2-12 UN: P = 25.4 / 12 = 2.116667 mm, 0.083333 in; 13 TPI: 1.953846 mm.
    #[test]
    fn inches_and_threads_per_inch_beside_mm() {
        let mm = Units { inch: false };
        let inch = Units { inch: true };
        assert_eq!(mm.len(0.127, 4), "0.1270 mm");
        assert_eq!(inch.len(0.127, 4), "0.1270 mm (0.00500 in)");
        assert_eq!(inch.z(-12.7), "z -12.700 (-0.5000 in)");
        assert_eq!(mm.z(-12.7), "z -12.700");
        assert_eq!(
            inch.pitch(25.4 / 12.0, 4, true),
            "2.1167 mm (0.08333 in, 12.000 TPI)"
        );
        assert_eq!(
            inch.pitch(25.4 / 13.0, 4, true),
            "1.9538 mm (0.07692 in, 13.000 TPI)"
        );
        assert_eq!(inch.pitch(4.2333, 4, false), "4.2333 mm (0.16667 in)");
        let t = InchThread::of(50.8, 49.425, 48.203, 25.4 / 12.0, 25.4 / 12.0);
        assert_eq!(
            (t.tpi, t.major_diameter_in, t.lead_in),
            (12.0, 2.0, 0.083333)
        );
    }
}
