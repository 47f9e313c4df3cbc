//! LinuxCNC M70..M73: the modal state saved in a call level and restored, as rs274
//! 2.9.0~pre1 does it (`Interp::save_settings`, `restore_settings`, `gen_settings`,
//! `gen_m_codes`; LinuxCNC manual "M70", "M71", "M72", "M73").
//!
//! M70 saves the state in the current call level, M73 too and marks it to be restored
//! when the subroutine returns (not in the main program), M71 forgets it, M72 restores it
//! (an error when none is saved). What is saved and restored: units (restored first), the
//! feed and the spindle speed (restored as rs274 writes them back: `F%.1f`, `S%.0f`, so F0.25
//! comes back as F0.2), the plane, cutter compensation, G90/G91, the feed mode, the work
//! offset, G43/G49, G98/G99, G96/G97, G90.1/G91.1, G7/G8, G92.2/G92.3, and the spindle,
//! coolant and override M codes. The motion mode is not restored (rs274: "a real bad idea").
//! A state whose value equals the current one is left alone, as rs274 generates code only
//! for the differences.

use super::expr::Fail;
use super::Interp;
use crate::model::helix::Spindle;

/// The state M70/M73 save.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Modes {
    inch: bool,
    feed: f64,
    speed: f64,
    plane: u32,
    ccomp: u32,
    incremental: bool,
    feed_mode: u32,
    work: usize,
    tool_offset: bool,
    retract_r: bool,
    css: bool,
    ijk_absolute: bool,
    diameter: bool,
    g92_on: bool,
    spindle_on: bool,
    spindle: Spindle,
    mist: bool,
    flood: bool,
    overrides: (bool, bool),
    adaptive_feed: bool,
    feed_hold: bool,
}

/// A call level's saved state: valid (M70/M73, not M71) and restored on return (M73).
#[derive(Clone, Debug)]
pub(super) struct Context {
    modes: Modes,
    valid: bool,
    restore_on_return: bool,
}

impl Interp<'_> {
    fn lc_modes(&self) -> Modes {
        let st = &self.lc.st;
        Modes {
            inch: self.modal.inch,
            feed: self.modal.feed.unwrap_or(0.0),
            speed: self.modal.speed.unwrap_or(0.0),
            plane: st.plane,
            ccomp: st.ccomp,
            incremental: self.modal.incremental,
            feed_mode: st.feed_mode,
            work: self.frames.work,
            tool_offset: st.tool_offset,
            retract_r: st.retract_r,
            css: self.modal.css,
            ijk_absolute: st.ijk_absolute,
            diameter: self.modal.diameter_mode,
            g92_on: st.g92_on,
            spindle_on: st.spindle_on,
            spindle: self.modal.spindle,
            mist: st.mist,
            flood: st.flood,
            overrides: (st.feed_override, st.speed_override),
            adaptive_feed: st.adaptive_feed,
            feed_hold: st.feed_hold,
        }
    }

    /// M70..M73 (`m`) in the block being run.
    pub(super) fn lc_m7x(&mut self, m: u32) -> Result<(), Fail> {
        let depth = self.lc_depth();
        match m {
            70 | 73 => {
                let modes = self.lc_modes();
                let c = self.lc.contexts.entry(depth).or_insert(Context {
                    modes: modes.clone(),
                    valid: true,
                    restore_on_return: false,
                });
                c.modes = modes;
                c.valid = true;
                // rs274: an M73 in the main program saves, with nothing to return to.
                c.restore_on_return |= m == 73 && depth > 0;
            }
            71 => {
                if let Some(c) = self.lc.contexts.get_mut(&depth) {
                    c.valid = false;
                }
            }
            _ => {
                let saved =
                    match self.lc.contexts.get(&depth) {
                        Some(c) if c.valid => c.modes.clone(),
                        _ => return Err((
                            1,
                            "Cannot restore context from invalid stack frame - missing M70/M73?"
                                .into(),
                        )),
                    };
                self.lc_restore(&saved);
            }
        }
        Ok(())
    }

    /// A new call level starts without a saved state.
    pub(super) fn lc_context_enter(&mut self, depth: usize) {
        self.lc.contexts.remove(&depth);
    }

    /// At the `endsub`/`return` of the current level: its M73 state comes back.
    pub(super) fn lc_context_leave(&mut self) {
        let depth = self.lc_depth();
        if let Some(c) = self.lc.contexts.remove(&depth) {
            if c.valid && c.restore_on_return {
                self.lc_restore(&c.modes);
            }
        }
    }

    /// Bring back `saved` where it differs from now, as rs274's generated code does.
    fn lc_restore(&mut self, saved: &Modes) {
        let now = self.lc_modes();
        self.modal.inch = saved.inch;
        if saved.feed != now.feed {
            // rs274 writes the feed back as `F%.1f`.
            let f: f64 = format!("{:.1}", saved.feed).parse().unwrap_or(saved.feed);
            self.modal.feed = Some(f);
        }
        if saved.speed != now.speed {
            let s: f64 = format!("{:.0}", saved.speed).parse().unwrap_or(saved.speed);
            self.modal.speed = Some(s);
        }
        self.modal.incremental = saved.incremental;
        self.modal.per_rev = saved.feed_mode == 95;
        self.frames.work = saved.work;
        self.modal.css = saved.css;
        self.modal.diameter_mode = saved.diameter;
        if saved.g92_on != now.g92_on {
            // G92.3 applies the stored offsets again, G92.2 suspends them.
            self.frames.g92_off = if saved.g92_on {
                self.lc.st.g92_params
            } else {
                (0.0, 0.0)
            };
        }
        if (saved.spindle_on, saved.spindle) != (now.spindle_on, now.spindle) {
            // An M3/M4/M5: the next thread block waits for the index pulse again.
            self.thread.chain_end = None;
            if saved.spindle_on {
                self.modal.spindle = saved.spindle;
            }
        }
        let st = &mut self.lc.st;
        st.plane = saved.plane;
        st.ccomp = saved.ccomp;
        st.feed_mode = saved.feed_mode;
        st.tool_offset = saved.tool_offset;
        st.retract_r = saved.retract_r;
        st.ijk_absolute = saved.ijk_absolute;
        st.g92_on = saved.g92_on;
        st.spindle_on = saved.spindle_on;
        st.mist = saved.mist;
        st.flood = saved.flood;
        (st.feed_override, st.speed_override) = saved.overrides;
        st.adaptive_feed = saved.adaptive_feed;
        st.feed_hold = saved.feed_hold;
    }
}
