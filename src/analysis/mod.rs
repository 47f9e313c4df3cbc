//! What the cut means: the deviation from the ideal thread ([`compare`]), measured leads and
//! widths ([`measure`]), what tool bodies cut past their edges ([`interference`]) and the
//! machine checks ([`checks`]). Reads the model and the kernels' stock; pure.

pub(crate) mod checks;
pub(crate) mod compare;
pub(crate) mod findings;
pub(crate) mod interference;
pub(crate) mod measure;
pub(crate) mod runs;
