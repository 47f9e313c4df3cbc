//! A milling program's moves into the kernel's path in the part's frame, each with its
//! cutter and spindle speed.

use super::ProgramError;
use crate::kernel::mill::{Cutter, MillPath, Motion, PathMove};
use crate::nc::{MillKind, MillMove, Plane};

/// What the path needs of the job: its cutters, their tool numbers, the part's axis in the
/// job's frame and the job's spindle speed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MillSetup<'a> {
    /// The cutters, in the order of the job's tools.
    pub(crate) cutters: &'a [Cutter],
    /// Their tool numbers.
    pub(crate) ids: &'a [u32],
    /// The part axis (x, y) in the job frame.
    pub(crate) axis: [f64; 2],
    /// Spindle speed (rev/min) where the program gives none.
    pub(crate) rpm: f64,
}

/// The sampled path of `moves` in the part's frame, and the spindle speed of each move.
pub(crate) fn mill_path(
    moves: &[MillMove],
    setup: &MillSetup,
) -> Result<(MillPath, Vec<f64>), ProgramError> {
    let fail = |m: &MillMove, message: String| ProgramError::Move {
        file: m.file.clone(),
        line: m.line,
        message,
    };
    let axis = setup.axis;
    let mut path = Vec::with_capacity(moves.len());
    let mut rpms = Vec::with_capacity(moves.len());
    for m in moves {
        let cutter = match m.tool {
            Some(id) => setup.ids.iter().position(|&t| t == id),
            None if setup.cutters.len() == 1 => Some(0),
            None => None,
        }
        .ok_or_else(|| {
            fail(
                m,
                match m.tool {
                    Some(t) => {
                        let word = m
                            .tool_word
                            .as_deref()
                            .map_or_else(|| format!("T{t}"), str::to_string);
                        format!(
                            "milling with {}, which the job's [[tool]] list does not define",
                            super::tool_and_id(word, t)
                        )
                    }
                    None => "a milling move without a T word in a job with several cutters: select the cutter with a T word".to_string(),
                },
            )
        })?;
        let part = |p: [f64; 3]| [p[0] - axis[0], p[1] - axis[1], p[2]];
        let motion =
            match (m.kind, &m.arc) {
                (MillKind::Arc, Some(a)) if a.plane == Plane::Xy => Motion::Arc {
                    centre: [a.centre[0] - axis[0], a.centre[1] - axis[1]],
                    sweep: a.sweep,
                },
                (MillKind::Arc, _) => return Err(fail(
                    m,
                    "arcs outside the G17 (XY) plane are not simulated yet: the thread axis is Z"
                        .into(),
                )),
                _ => Motion::Line,
            };
        path.push(PathMove {
            start: part(m.start),
            end: part(m.end),
            motion,
            cutter,
        });
        rpms.push(m.spindle_rpm.unwrap_or(setup.rpm));
    }
    let path = MillPath::new(path, setup.cutters).map_err(|e| ProgramError::Samples(e.0))?;
    Ok((path, rpms))
}
