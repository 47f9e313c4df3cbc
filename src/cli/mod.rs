//! The binary's own modules (not part of the library): output files written all or nothing,
//! input files read with good messages, the terminal (closed pipes, colour, progress) and
//! the CI formats, the HTML report, counts as they are written (`--max-dexels 4e8`), and the
//! `toolpath` command, `check` (its table, `--shard`, the records of `--report-dir` and
//! `--changed-since`), and the GPU stack's chatter kept off standard error.

pub(crate) mod check;
pub(crate) mod ci;
pub(crate) mod count;
pub(crate) mod html;
pub(crate) mod inputs;
pub(crate) mod output;
pub(crate) mod quiet;
pub(crate) mod record;
pub(crate) mod shard;
pub(crate) mod term;
pub(crate) mod toolpath;
