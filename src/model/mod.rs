//! The nouns of thread machining and their closed forms: the helix and its lead law, the
//! thread the drawing asks for, the tools and their solids, a pass, the dexel stock, and the
//! blank and machine a job names. Pure: no IO, no dependency on any other stage.

pub(crate) mod geom;
pub(crate) mod helix;
pub(crate) mod pass;
pub(crate) mod setup;
pub(crate) mod solid;
pub(crate) mod stock;
pub(crate) mod thread;
pub(crate) mod tool;
