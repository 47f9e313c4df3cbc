//! Where passes come from when the job does not list them: the pass generators
//! ([`process`]), the planner ([`plan`]) and the post-processors that write a plan as an NC
//! program in a controller's dialect ([`post`]).

pub mod plan;
pub mod post;
pub(crate) mod process;
