//! The thread placed on the cut (`analysis::place`) once the job's passes are known: a job
//! that does not fix `thread.z_start` has its ideal thread's first feature put where the
//! cut's grooves are, and a job that fixes it has the cut's offset from it measured
//! (constant lead). Jobs whose passes the thread itself generates (`[process]`) need no fit.

use super::Job;
use crate::analysis::place::{fit, Placement};
use crate::kernel::mill::mill_column;
use crate::kernel::sweep::{sweep_column, Column};
use crate::model::stock::Surface;
use crate::model::thread::Side;

impl Job {
    /// The cut of one free-standing column by the job's operation: the passes with their
    /// tools and the program's turning moves (lathe), or the mill's path (`q` holds
    /// `q - q_blank`, cut in place). The measurement generators cut the same way.
    pub(crate) fn cut_column(&self, q: &mut [f32], c: Column) {
        match &self.mill {
            Some(mj) => mill_column(q, c, &mj.path, &mj.cutters),
            None => {
                sweep_column(q, c, &self.passes, &self.tools);
                let (turned, q_floor) = match c.surface {
                    Surface::Outer => (&self.turning.outer, self.blank.bore / 2.0),
                    Surface::Inner => (&self.turning.inner, -self.blank.diameter / 2.0),
                };
                turned.clamp(q, c.z0, c.dz, c.q_blank, q_floor);
            }
        }
    }

    /// Place the thread on the cut (`fit`: `z_start` was not given) or measure the cut's
    /// offset from the given one (constant lead only: a variable-lead screw's is not
    /// needed and would cost a long column).
    pub(super) fn place(&mut self, fit_it: bool) {
        let thread = &self.thread;
        if !fit_it && thread.helix.law.k != 0.0 {
            return;
        }
        let b = &self.blank;
        let window = self
            .sim
            .z_range
            .unwrap_or((b.z_front - b.length, b.z_front));
        let q_blank = match thread.side {
            Side::External => b.diameter / 2.0,
            Side::Internal => -b.bore / 2.0,
        };
        if thread.side == Side::Internal && b.bore <= 0.0 {
            return;
        }
        let given = (!fit_it).then_some(thread.helix.z0);
        let cut = |q: &mut [f32], c: Column| self.cut_column(q, c);
        let found = fit(
            thread,
            &cut,
            q_blank,
            window,
            self.sim.measure_spacing,
            given,
        );
        self.placement = found;
        match found {
            Some(Placement { z_start, .. }) if fit_it => self.thread.helix.z0 = z_start,
            // Nothing of the thread's width at its pitch line: the thread is put at the
            // front face, where the comparison shows what the cut lacks.
            None if fit_it => self.thread.helix.z0 = window.1,
            _ => {}
        }
    }
}

/// The ideal thread moved to the middle of its class's zone (what the deviation colours
/// and the planner aim at): the flanks to the middle of the pitch-diameter zone, measured
/// at the same pitch line (the groove widens by the flanks' slopes times the radial move,
/// its root moves as far: the basic groove cut deeper; a root the job gives stays), a
/// basic crest to the middle of its diameter's zone (major outside, minor inside) where
/// both limits are set (a bar or bore inside the zone stays the crest). The root stays at the form's. A constant-lead, equal-groove thread only
/// (the classes' threads).
pub(super) fn zone_middle(
    thread: &mut crate::model::thread::ThreadSpec,
    class: &crate::model::tolerance::ThreadClass,
    root_given: bool,
) {
    use crate::model::thread::WidthRule;
    let WidthRule::Groove(w) = thread.width else {
        return;
    };
    if thread.helix.law.k != 0.0 {
        return;
    }
    let basic = class.basic_pitch_diameter;
    let Some(mid) = class.pitch_diameter.mid() else {
        return;
    };
    // Away from the material: external threads get smaller, internal ones larger.
    let away = match thread.side {
        Side::External => 0.5 * (basic - mid),
        Side::Internal => 0.5 * (mid - basic),
    };
    // The basic groove moved radially by `away` (deeper), as a deeper infeed cuts it: at
    // the same pitch line it is wider by `away` times the flanks' widening, and its root
    // (the same flat) lies `away` further into the part.
    thread.width = WidthRule::Groove(w + away * thread.widening());
    if !root_given {
        thread.root_radius -= thread.sense() * away;
    }
    let crest = match thread.side {
        Side::External => class.major_diameter,
        Side::Internal => class.minor_diameter,
    };
    // A bar or bore inside the zone is already the crest (`job::standard`); a basic crest
    // (the program turns it, or the blank is outside) goes to the zone's middle.
    let basic_crest = match thread.side {
        Side::External => class.basic_major,
        Side::Internal => class.basic_minor,
    };
    let at_basic = (2.0 * thread.crest_radius - basic_crest).abs() < 1e-9;
    if at_basic && crest.min.is_finite() && crest.max.is_finite() {
        thread.crest_radius = 0.25 * (crest.min + crest.max);
    }
}
