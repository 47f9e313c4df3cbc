//! What the cut means: the deviation from the ideal thread ([`compare`]), measured leads and
//! widths ([`measure`]), what tool bodies cut past their edges ([`interference`]), the
//! machine checks ([`checks`]), the insert's limits pass by pass ([`chips`]) and the
//! finished part's contour against every cut ([`contour`]). Reads the model and the kernels' stock; pure.

pub(crate) mod checks;
pub(crate) mod chips;
pub(crate) mod compare;
pub(crate) mod contour;
pub(crate) mod findings;
pub(crate) mod gauge;
pub(crate) mod interference;
pub(crate) mod measure;
pub(crate) mod place;
pub(crate) mod runs;

/// A small deterministic generator for the analysis tests (64-bit LCG, the high bits).
#[cfg(test)]
pub(crate) struct Lcg(pub(crate) u64);

#[cfg(test)]
impl Lcg {
    /// The next value in [0, 1).
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
