//! Integration tests: one binary, a module per area.

/// Shared helpers: load scenes, tweak their settings, run them.
mod support;

/// Tool bodies behind the edge: interference against closed forms.
mod bodies;
/// The command line: exit codes, error messages, atomic outputs.
mod cli;
/// Issue 27: the coverage tables in `docs/coverage/` against the NC corpus.
mod coverage;
/// Issue 28: programs that crash on the machine fail at their block; their fixes pass.
mod crashes;
/// Issue 28: cycle times against derivations by hand.
mod cycle_time;
/// `[thread] designation` and `class`: scenes rewritten with designations, contradictions.
mod designations;
/// The docs against the code: every job key documented, README's commands run.
mod docs;
/// The gauges' verdict (GO/NOT GO, functional diameter) against hand derivations, and its
/// independence of where the cut starts.
mod gauging;
/// The glTF export against closed forms, the dexel data, the report and itself.
mod gltf;
/// The scenes' reports against reviewed goldens and hand-derived expectations.
mod goldens;
/// Issue 28: tool holders, boring bars and the chuck against closed-form clearances.
mod holders;
/// Hostile input, class by class: clean errors naming the place, never a panic or a hang.
mod hostile;
/// The HTML report: self-contained, the report's rows, the passes of the findings.
mod html;
/// Same answer whatever the thread count; left and right hands mirror each other.
mod invariance;
/// Issue 27: LinuxCNC's G70/G71/G72 against rs274 reference output.
mod lcnc_g7x;
/// LinuxCNC conformance against rs274 reference output.
mod linuxcnc;
/// Thread milling: thread counts, sampling bound, job errors.
mod milling;
/// NC programs as data: `tests/data/nc/<dialect>/*.nc` against their reviewed `*.moves`.
mod nc_data;
/// Lathe tool nose radius compensation (G41/G42) against rs274, move for move.
mod nose;
/// Okuma OSP-P programs through jobs: a whole part program cut and gauged.
mod okuma;
/// Geometry against independent oracles: closed forms, finer grids, hand-computed passes.
mod oracle;
/// Output files all or nothing, symlinks, `-`, closed pipes, CI formats, `vpcut check`.
mod outputs;
/// Issue 26: the drawn part's chamfers in the ideal thread, against closed forms.
mod part_outline;
/// Issue 29: every picture, the page and the model's extras against the report.
mod pictures;
/// `vpcut plan`: planned screws round-trip through every dialect and simulate clean.
mod plan;
/// The pictures that need no GPU against the report and the exact cut.
mod plots;
/// NC programs against the pass generators that transcribe the same methods.
mod programs;
/// Issue 17: a corpus of threading programs in the style of real ones runs end to end.
mod real_programs;
/// The headless renderer: shader validity, pixel geometry, determinism, golden pictures.
mod render;
/// Bad input never panics.
mod robust;
/// Issue 29: every finding at its NC block or job key; SARIF's physical locations.
mod sources;
/// `--gltf` alone: the model meshed as the columns stream, the full grid's bytes.
mod streamed_mesh;
mod streaming;
/// Issue 26: taper threads' gauge stand-off against a closed form.
mod taper;
/// Taps: tapping strokes cut the internal thread and its chamfer cone; the feed's finding.
mod taps;
/// Project hygiene: module docs, scenes and goldens in one-to-one correspondence.
mod tidy;
/// A new user's trials: shop programs from a drawing's words, their findings as classes.
mod trials;
/// No false PASS: randomized clean cuts pass, short defects fail on their turn and flank.
mod trust;
/// The whole lathe program cuts the stock: turned profiles against hand derivations, rapids
/// into material.
mod turning;
/// Issue 29: messages in the user's words: inch jobs in inches and TPI, tools as the
/// program writes them.
mod words;
