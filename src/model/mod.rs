//! The nouns of thread machining and their closed forms: the helix and its lead law, the
//! thread the drawing asks for, the tools and their solids, a pass, the dexel stock, and the
//! blank and machine a job names, a thread's tolerance class as a drawing names it, and the
//! finished part's contour as drawn. Pure: no IO, no dependency on any other stage.

pub(crate) mod clip;
pub(crate) mod geom;
pub(crate) mod helix;
pub(crate) mod part;
pub(crate) mod pass;
pub(crate) mod setup;
pub(crate) mod solid;
pub(crate) mod standards;
pub(crate) mod stock;
pub(crate) mod thread;
pub(crate) mod tolerance;
pub(crate) mod tool;

/// A small deterministic generator for tests (xorshift64*).
#[cfg(test)]
pub(crate) struct Rng(pub(crate) u64);

#[cfg(test)]
impl Rng {
    /// The next value in [0, 1).
    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A value in [a, b).
    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}
