//! The cutting kernels: a pass's tool swept through the dexel stock column by column
//! ([`sweep`], with the tool body behind the edge in [`body`]), thread milling
//! ([`mill`]) and the axisymmetric stock removal of turning moves ([`turn`]). They read the model and write stock; nothing else.

pub(crate) mod body;
pub(crate) mod holder;
pub(crate) mod mill;
pub(crate) mod sweep;
pub(crate) mod turn;
