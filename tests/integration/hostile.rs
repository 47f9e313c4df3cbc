//! Hostile input, class by class (issue 19): every malformed program or job gives an error
//! that names the file, line and column (or the job key) and what was expected, in every
//! dialect where the class applies; never a panic, a hang or a runaway allocation. The
//! library calls run under `catch_unwind` and a clock; the command line must exit 2.
//!
//! Classes: values out of range (overflow, NaN, huge literals, variables and R parameters
//! that do not exist, function domains); computed jumps; nesting; the number of moves;
//! allocation; what a control alarms on (zero feed, G76 P); job numbers; job type errors
//! (generated for every key of every scene); text encodings.

// An `NcError` carries every diagnostic of a program; the helpers pass it on as the
// library returns it.
#![allow(clippy::result_large_err)]

use crate::support::{scene_text, scenes};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};
use vpcut::{
    decode_program, interpret_with, DecimalPoint, Dialect, Limits, NcError, NcOptions, Settings,
    Source, Toolpath,
};

const F: Dialect = Dialect::Fanuc;
const G: Dialect = Dialect::Gsk980;
const S: Dialect = Dialect::Siemens802d;
const L: Dialect = Dialect::Linuxcnc;

/// The longest any one hostile case may take: a hang guard (a runaway loop must stop at a
/// limit, not run until the test harness is killed), not a speed target. A runaway case
/// runs up to the default move or block limit, some seconds on one core, and CI runs the
/// tests side by side, so the guard is generous; speed is the benchmarks' subject.
const BOUND: Duration = Duration::from_secs(60);

/// Interpret `text` as `P.NC` with `limits`: no panic, within [`BOUND`].
fn nc_with(dialect: Dialect, text: &str, limits: Limits) -> Result<Toolpath, NcError> {
    let src = Source {
        name: "P.NC".into(),
        text: text.into(),
    };
    // The programs here write plain numbers in mm (`G0 X50 Z5`): a FANUC/GSK machine with
    // calculator-type decimal-point input (standard input is `units_tests`' subject).
    let opts = NcOptions {
        limits,
        settings: Settings {
            decimal_point: DecimalPoint::Calculator,
            ..Settings::default()
        },
        ..NcOptions::default()
    };
    let t = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| {
        interpret_with(&src, dialect, &|_| None, &opts)
    }));
    let took = t.elapsed();
    let short: String = text.chars().take(60).collect();
    assert!(took < BOUND, "{dialect:?} {short:?}: took {took:?}");
    r.unwrap_or_else(|_| panic!("{dialect:?} {short:?}: panicked"))
}

fn nc(dialect: Dialect, text: &str) -> Result<Toolpath, NcError> {
    nc_with(dialect, text, Limits::default())
}

/// `text` fails in every dialect of `dialects` at `line` (and `col` when given), with a
/// message that contains `want`.
fn fails(dialects: &[Dialect], text: &str, line: usize, col: Option<usize>, want: &str) {
    for &d in dialects {
        let short: String = text.chars().take(60).collect();
        let e = match nc(d, text) {
            Ok(t) => panic!("{d:?} {short:?}: ran ({} moves)", t.moves.len()),
            Err(e) => e,
        };
        let shown = e.to_string();
        assert_eq!(e.file, "P.NC", "{d:?} {short:?}: {shown}");
        assert_eq!(e.line, line, "{d:?} {short:?}: {shown}");
        if let Some(c) = col {
            assert_eq!(e.col, c, "{d:?} {short:?}: {shown}");
        }
        assert!(
            e.message.contains(want),
            "{d:?} {short:?}: wanted {want:?} in {shown}"
        );
        crate::support::no_debug_text(&format!("{d:?} {short:?}"), &shown);
        assert!(shown.contains(&format!("P.NC:{line}:")), "{d:?}: {shown}");
        // A long line is shown cut around the column.
        assert!(shown.len() < 2000, "{d:?}: {} characters", shown.len());
    }
}

/// The end points of the moves of `text` in every dialect of `dialects`.
fn runs(dialects: &[Dialect], text: &str, ends: &[(f64, f64)]) {
    for &d in dialects {
        let t = nc(d, text).unwrap_or_else(|e| panic!("{d:?} {text:?}: {e}"));
        let got: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.x_dia, m.z)).collect();
        assert_eq!(got, ends, "{d:?} {text:?}");
    }
}

fn nines(n: usize) -> String {
    "9".repeat(n)
}

/// Class 1: Values: overflow, NaN, literals beyond any variable, variables and R parameters that
/// do not exist, function domains: refused where they are written, in every dialect.
#[test]
fn values_out_of_range_are_refused_where_they_are_written() {
    let fg = &[F, G];
    fails(
        fg,
        "#1=EXP[1000]\nG00 X#1\n",
        1,
        Some(4),
        "EXP of 1000 overflows",
    );
    fails(
        &[S],
        "R1=EXP(1000)\nG0 X=R1\n",
        1,
        Some(4),
        "EXP of 1000 overflows",
    );
    // LinuxCNC (as rs274) computes inf, and refuses it in the word.
    fails(
        &[L],
        "#1=EXP[1000]\nG0 X#1\n",
        2,
        Some(4),
        "the X word's value is inf",
    );
    // A literal of 309 nines.
    let big = nines(309);
    fails(fg, &format!("G00 X{big}\n"), 1, Some(6), "too large");
    fails(&[S], &format!("G0 X{big}\n"), 1, Some(5), "too large");
    fails(&[L], &format!("G0 X{big}\n"), 1, Some(4), "is inf");
    // A word beyond eight (FANUC) or nine (Siemens) digits.
    fails(
        fg,
        "#1=123456789\nG0 X#1\n",
        2,
        Some(4),
        "at most eight digits",
    );
    fails(
        &[S],
        "R1=1234567890\nG0 X=R1\n",
        2,
        Some(4),
        "at most nine digits",
    );
    // NaN is never a value: inf - inf stops at the first overflow.
    fails(
        fg,
        "#1=EXP[1000]-EXP[1000]\nG32 Z#1 F6.\n",
        1,
        Some(4),
        "overflows",
    );
    fails(
        &[S],
        "R1=EXP(1000)-EXP(1000)\nG33 Z=R1 K2\n",
        1,
        Some(4),
        "overflows",
    );
    // Products and sums beyond the variables' range (FANUC 1e47, alarm 111).
    fails(fg, "#1=EXP[100]*EXP[100]\n", 1, Some(12), "`*` overflows");
    fails(&[S], "R1=EXP(600)*EXP(600)\n", 1, Some(12), "`*` overflows");
    // Variables that do not exist, or are not modelled.
    fails(fg, "#1=#[0-5]\n", 1, Some(4), "#-5 does not exist");
    fails(fg, "#1=#5021\n", 1, Some(4), "system variable #5021");
    fails(fg, "#1=#50\n", 1, Some(4), "#50 does not exist");
    fails(fg, "#5021=1\n", 1, Some(1), "cannot be set");
    fails(fg, "#[#9]=1\n", 1, Some(1), "vacant");
    fails(&[S], "R99999=22\n", 1, Some(1), "R99999 does not exist");
    fails(&[S], "R1=R300\n", 1, Some(4), "R300 does not exist");
    // Function domains.
    fails(fg, "#1=LN[0]\n", 1, Some(4), "LN of 0");
    fails(&[S], "R1=LN(0)\n", 1, Some(4), "LN of 0");
    fails(&[L], "#1=LN[0]\n", 1, Some(4), "LN of 0");
    fails(fg, "#1=SQRT[-1]\n", 1, Some(4), "square root");
    fails(&[S], "R1=SQRT(-1)\n", 1, Some(4), "square root");
    fails(&[L], "#1=SQRT[-1]\n", 1, Some(4), "SQRT of -1");
    fails(fg, "#1=ASIN[2]\n", 1, Some(4), "ASIN of 2");
    fails(fg, "#1=ACOS[-2]\n", 1, Some(4), "ACOS of -2");
    fails(&[S], "R1=ACOS(2)\n", 1, Some(4), "ACOS of 2");
    fails(&[L], "#1=ASIN[2]\n", 1, Some(4), "ASIN of 2");
    fails(fg, "#1=1/0\n", 1, Some(6), "division by zero");
    fails(&[S], "R1=1/0\n", 1, Some(6), "division by zero");
    fails(&[L], "#1=[1/0]\n", 1, Some(6), "division by zero");
    // Macro A: the same domains and ranges.
    fails(fg, "G65 H21 P#100 Q-1\n", 1, None, "square root of -1");
    fails(
        fg,
        "#100=EXP[100]\nG65 H04 P#101 Q#100 R#100\n",
        2,
        None,
        "G65 H04 overflows",
    );
    fails(
        fg,
        "G65 H01 P#5021 Q1\n",
        1,
        Some(10),
        "system variable #5021",
    );
}

/// Class 2: A computed jump goes to the block its value names, in every form.
#[test]
fn computed_jumps_go_to_the_block_their_value_names() {
    let fg = &[F, G];
    let tail = "G0 X1 Z1\nN500 G0 X2 Z2\nN510 G0 X3 Z3\nM30\n";
    runs(
        fg,
        &format!("#1=500\nGOTO#1\n{tail}"),
        &[(2.0, 2.0), (3.0, 3.0)],
    );
    runs(fg, &format!("#1=500\nGOTO[#1+10]\n{tail}"), &[(3.0, 3.0)]);
    runs(
        fg,
        &format!("#2=510\nIF[1EQ1]GOTO#2\n{tail}"),
        &[(3.0, 3.0)],
    );
    runs(
        fg,
        &format!("#2=510\nIF[1EQ2]GOTO#2\n{tail}"),
        &[(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)],
    );
    // Macro A: `P#i` jumps to the block number that #i holds.
    runs(
        fg,
        &format!("G65 H01 P#1 Q510\nG65 H80 P#1\n{tail}"),
        &[(3.0, 3.0)],
    );
    runs(
        fg,
        &format!("G65 H01 P#1 Q500\nG65 H81 P#1 Q1 R1\n{tail}"),
        &[(2.0, 2.0), (3.0, 3.0)],
    );
    fails(
        fg,
        "#1=499\nGOTO#1\nN500 G0 X2 Z2\n",
        2,
        Some(5),
        "no block N499",
    );
    fails(fg, "GOTO#9\nN500 G0 X2 Z2\n", 1, Some(5), "vacant");
    fails(fg, "GOTO[1.5]\n", 1, Some(5), "expected a sequence number");
}

/// Class 3: Nesting: 100,000 brackets or signs stop at the nesting limit with a message, not a
/// stack overflow.
#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let n = 100_000;
    let deep = |open: &str, close: &str| format!("{}1{}", open.repeat(n), close.repeat(n));
    fails(
        &[F, G],
        &format!("#1={}\n", deep("[", "]")),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[F, G],
        &format!("G0 X{}\n", deep("[", "]")),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[F, G],
        &format!("#1={}1\n", "-".repeat(n)),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[F, G],
        &format!("#1={}1]\n", "#[".repeat(n)),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[S],
        &format!("R1={}\n", deep("(", ")")),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[S],
        &format!("R1={}1\n", "-".repeat(n)),
        1,
        None,
        "nests more than 100",
    );
    fails(
        &[L],
        &format!("#1={}\n", deep("[", "]")),
        1,
        None,
        "nested more than 100",
    );
    fails(
        &[L],
        &format!("#1={}1\n", "-".repeat(n)),
        1,
        None,
        "nested more than 100",
    );
}

/// Class 4: Moves: a loop that makes moves forever stops at the limit on moves, at the block,
/// long before the block limit or the memory; the G76 of 10,000 passes still runs.
#[test]
fn runaway_moves_stop_at_the_move_limit() {
    let limit = Limits::default().max_moves;
    let want = format!("more than {limit} moves");
    fails(&[F, G], "N10 G92 X38. Z-70. F6.\nGOTO10\n", 1, None, &want);
    let g32 = "G0 X40 Z5\nN10 G32 Z-70. F6.\nG0 X42\nZ5\nX40\nGOTO10\n";
    let e = nc(F, g32).unwrap_err();
    assert!(e.message.contains(&want) && e.line >= 2, "{e}");
    let siemens = "G0 X40 Z5\nLOOP:\nG33 Z-70 K6\nG0 X42\nZ5\nX40\nGOTOB LOOP\n";
    let e = nc(S, siemens).unwrap_err();
    assert!(e.message.contains(&want) && e.line >= 3, "{e}");
    let lcnc = "G0 X40 Z5 M3\no1 while [1]\nG33 Z-70 K6\nG0 X42\nZ5\nX40\no1 endwhile\n";
    let e = nc(L, lcnc).unwrap_err();
    assert!(e.message.contains(&want) && e.line >= 3, "{e}");
    // A smaller limit, as a job could set it: the block that passes it is named.
    let small = Limits {
        max_moves: 1000,
        ..Limits::default()
    };
    let e = nc_with(F, "N10 G0 X1\nG0 X2\nGOTO10\n", small).unwrap_err();
    assert_eq!(e.line, 1, "{e}");
    assert!(e.message.contains("more than 1000 moves"), "{e}");
    // One block of too many moves: LinuxCNC G76 spring passes.
    fails(
        &[L],
        "G7 M3\nG0 X22 Z5\nG76 P2 Z-20 I-1 J0.4 K1.5 H1000000000\n",
        3,
        Some(27),
        "more spring passes",
    );
    // The G76 bench (10,000 passes) is well inside the limit.
    let t = nc(
        F,
        "G0 X30 Z5\nG76 P010060 Q0 R0\nG76 X20 Z-20 P5000 Q50 F1\nM30\n",
    )
    .unwrap();
    assert!(
        t.moves.len() >= 30_000 && t.moves.len() < limit,
        "{}",
        t.moves.len()
    );
}

/// Class 6: What a control alarms on: a feed move without a feed or with F0; a G76 P that is not
/// six digits mm rr aa with a tool angle the control knows.
#[test]
fn feed_zero_and_g76_p_out_of_range_alarm() {
    fails(&[F, G], "G0 X50 Z5\nG01 X40. F0\n", 2, Some(10), "F0");
    fails(&[S, L], "G0 X50 Z5\nG1 X40 F0\n", 2, Some(8), "F0");
    fails(
        &[F, G, S, L],
        "G0 X50 Z5\nG1 X40\n",
        2,
        None,
        "without a feed",
    );
    fails(
        &[F, G],
        "G0 X0 Z0\nG03 X20 Z-10 R10\n",
        2,
        None,
        "without a feed",
    );
    fails(&[F, G], "G0 X60 Z5 F0\nG90 X50 Z-30\n", 2, None, "F0");
    // A feed set once is modal.
    runs(
        &[F, G, S],
        "G0 X50 Z5 F0.2\nG1 X40\n",
        &[(50.0, 5.0), (40.0, 5.0)],
    );
    let fg = &[F, G];
    fails(fg, "G76 P9999999 Q100 R0.1\n", 1, Some(5), "six digits");
    fails(fg, "G76 P010099 Q100 R0.1\n", 1, Some(5), "tool angle");
    // No finishing pass (`P00....`, as program generators write it) is a valid count
    // (issue 27: FANUC runs it).
    nc(F, "G76 P000060 Q100 R0.1\n").unwrap();
    fails(fg, "G76 P99999999999 Q100 R0.1\n", 1, Some(5), "P word");
    for a in [80, 60, 55, 30, 29, 0] {
        nc(F, &format!("G76 P0101{a:02} Q100 R0.1\n")).unwrap();
    }
}

/// Class 9: Encodings: a NUL byte and bytes that are not ASCII outside comments are named with
/// their code at line and column; a byte order mark is skipped; Latin-1 comments load.
#[test]
fn encodings_are_named_or_accepted() {
    let all = &[F, G, S, L];
    fails(all, "G0 X1\0 Z2\n", 1, Some(6), "a NUL byte (0x00)");
    fails(
        all,
        "G0 X1 Z2\nG0 X\u{7} Z1\n",
        2,
        Some(5),
        "a control character (0x07)",
    );
    let text = |b: &[u8]| decode_program(b.to_vec());
    fails(all, &text(b"G0 X1 \xB0 Z2\nM30\n"), 1, Some(7), "0xB0");
    // Columns count characters: the `a umlaut` of the comment is one.
    fails(&[F, G], &text(b"(\xE4) G0 X1 \xB0\n"), 1, Some(11), "0xB0");
    for d in [F, G, S, L] {
        let t = nc(d, "\u{feff}G0 X1 Z2\nM30\n").unwrap();
        assert_eq!(t.moves.len(), 1, "{d:?}");
        let comment: &[u8] = if d == S {
            b"G0 X1 Z2 ; GEWINDE \xD8 20\nM30\n"
        } else {
            b"G0 X1 Z2 (GEWINDE \xD8 20)\nM30\n"
        };
        let t = nc(d, &text(comment)).unwrap();
        assert_eq!(t.moves.len(), 1, "{d:?}");
    }
    // A UTF-8 BOM in the bytes is dropped, UTF-8 stays UTF-8.
    assert_eq!(text(b"\xEF\xBB\xBFG0 (\xC3\xA4)"), "G0 (\u{e4})");
}

// ---------------------------------------------------------------------------------------
// Jobs.

/// A line `key = value` of a job text: its dotted key (`tool[0].width`) and its value.
fn job_keys(text: &str) -> Vec<(usize, String, String)> {
    let mut table = String::new();
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if let Some(h) = t.strip_prefix("[[").and_then(|h| h.split_once("]]")) {
            let n = counts.entry(h.0.to_string()).or_insert(0);
            table = format!("{}[{n}]", h.0);
            *n += 1;
            continue;
        }
        if let Some(h) = t.strip_prefix('[').and_then(|h| h.split_once(']')) {
            table = h.0.to_string();
            continue;
        }
        if t.starts_with('#') {
            continue;
        }
        let Some((k, v)) = t.split_once('=') else {
            continue;
        };
        let k = k.trim();
        if k.is_empty() || !k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            continue;
        }
        // The value without a trailing comment.
        let v = v.trim();
        let v = if let Some(rest) = v.strip_prefix('"') {
            format!(
                "\"{}",
                &rest[..rest.find('"').map_or(rest.len(), |e| e + 1)]
            )
        } else {
            v.split('#').next().unwrap_or("").trim().to_string()
        };
        let open = v.matches(['[', '{']).count();
        let close = v.matches([']', '}']).count();
        if v.is_empty() || open != close {
            continue;
        }
        let key = if table.is_empty() {
            k.to_string()
        } else {
            format!("{table}.{k}")
        };
        out.push((i, key, v));
    }
    out
}

/// The job text with line `i` set to `key = value`.
fn set_line(text: &str, i: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let k = lines[i]
        .split_once('=')
        .map(|p| p.0.to_string())
        .unwrap_or_default();
    lines[i] = format!("{k}= {value}");
    lines.join("\n")
}

/// Read a job text: it must fail, without a panic, within the bound.
fn job_error(text: &str, what: &str) -> String {
    let t = Instant::now();
    let r = catch_unwind(|| vpcut::Job::from_toml(text, "job.toml"));
    assert!(t.elapsed() < BOUND, "{what}: took {:?}", t.elapsed());
    match r {
        Ok(Ok(_)) => panic!("{what}: the job was accepted"),
        Ok(Err(e)) => {
            let shown = e.to_string();
            crate::support::no_debug_text(what, &shown);
            shown
        }
        Err(_) => panic!("{what}: panicked"),
    }
}

const RUST_NAMES: [&str; 12] = [
    "u32",
    "u64",
    "usize",
    "f64",
    "f32",
    "i64",
    "untagged",
    "struct ",
    "enum ",
    "Raw",
    "sequence",
    "wanted string",
];

/// Class 8: Every key of every scene given a value of the wrong type: the error names the dotted
/// key and its line, and says what is expected in the job file's words.
#[test]
fn every_type_error_names_its_key_in_the_job_files_words() {
    let mut cases = 0;
    for scene in scenes() {
        let text = scene_text(&scene);
        for (i, key, value) in job_keys(&text) {
            let wrong = if value.starts_with('"') {
                "1.5"
            } else {
                "\"text\""
            };
            let what = format!("{scene}: {key} = {wrong}");
            let msg = job_error(&set_line(&text, i, wrong), &what);
            assert!(msg.contains(&format!("`{key}`")), "{what}: {msg}");
            assert!(
                crate::support::place(&msg).starts_with(&format!("job.toml:{}:", i + 1)),
                "{what}: {msg}"
            );
            assert!(msg.contains("expected"), "{what}: {msg}");
            for r in RUST_NAMES {
                assert!(!msg.contains(r), "{what}: {r:?} in {msg}");
            }
            cases += 1;
        }
    }
    assert!(cases > 300, "{cases}");
}

/// Class 7: Every number of every scene set to nan, inf or 1e300: the error names the key.
#[test]
fn every_number_must_be_finite_and_in_range() {
    let mut cases = 0;
    for scene in scenes() {
        let text = scene_text(&scene);
        for (i, key, value) in job_keys(&text) {
            if value.parse::<f64>().is_err() {
                continue;
            }
            for bad in ["nan", "inf", "-inf", "1e300", "-1e300"] {
                let what = format!("{scene}: {key} = {bad}");
                let msg = job_error(&set_line(&text, i, bad), &what);
                assert!(msg.contains(&format!("`{key}`")), "{what}: {msg}");
                assert!(
                    crate::support::place(&msg).starts_with(&format!("job.toml:{}:", i + 1)),
                    "{what}: {msg}"
                );
                for r in RUST_NAMES {
                    assert!(!msg.contains(r), "{what}: {r:?} in {msg}");
                }
                cases += 1;
            }
        }
    }
    assert!(cases > 500, "{cases}");
    // Keys that reached the passes unchecked before.
    let base = scene_text("iso-m20x2.5-radial");
    for (key, value) in [("z_from", "nan"), ("z_to", "inf"), ("origin_z", "nan")] {
        let text = base.replace("[process]", &format!("[process]\n{key} = {value}"));
        let msg = job_error(&text, key);
        assert!(msg.contains(&format!("`process.{key}`")), "{msg}");
    }
    // A pitch longer than the thread: no turn to cut or measure.
    let text = crate::support::with(&base, &[("thread", "pitch", "10000.0")]);
    let msg = job_error(&text, "pitch 1e4");
    assert!(
        msg.contains("`thread.length`") && msg.contains("at least one"),
        "{msg}"
    );
    // TOML nested 100,000 deep: the parser's limit, shown cut around the place.
    let deep = base.replace(
        "[simulation]",
        &format!(
            "[simulation]\nz_range = {}{}",
            "[".repeat(100_000),
            "]".repeat(100_000)
        ),
    );
    let msg = job_error(&deep, "deep z_range");
    assert!(
        crate::support::place(&msg).starts_with("job.toml:") && msg.len() < 1000,
        "{msg}"
    );
    for (table, key) in [("blank", "diameter"), ("thread", "pitch")] {
        let text = crate::support::with(&base, &[(table, key, "1e300")]);
        let msg = job_error(&text, key);
        assert!(msg.contains(&format!("`{table}.{key}`")), "{msg}");
        assert!(msg.contains("from -100000 to 100000"), "{msg}");
    }
}

// ---------------------------------------------------------------------------------------
// The command line: exit code 2 and the place, for a program and a job of each class.

fn tmp_dir() -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "vpcut-hostile-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Run the binary with `args` under a 2 GB address-space limit: (exit code, stderr).
fn vpcut_limited(dir: &std::path::Path, args: &str) -> (Option<i32>, String) {
    let bin = env!("CARGO_BIN_EXE_vpcut");
    let t = Instant::now();
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v 2000000; exec '{bin}' {args}"))
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        t.elapsed() < Duration::from_secs(120),
        "{args}: {:?}",
        t.elapsed()
    );
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !err.contains("panicked") && !err.contains("memory allocation"),
        "{args}: {err}"
    );
    crate::support::no_debug_text(args, &err);
    (out.status.code(), err)
}

#[test]
fn the_command_line_exits_2_naming_the_place() {
    let d = tmp_dir();
    let programs: [(&str, &[u8], &str, &str); 9] = [
        (
            "fanuc",
            b"#1=EXP[1000]\nG00 X#1\n",
            "--> P.NC:1:4\n",
            "overflows",
        ),
        (
            "fanuc",
            b"#1=499\nGOTO#1\nN500 G0 X2\n",
            "--> P.NC:2:5\n",
            "no block N499",
        ),
        ("siemens-802d", b"R99999=22\n", "--> P.NC:1:1\n", "R99999"),
        (
            "gsk980",
            b"N10 G92 X38. Z-70. F6.\nGOTO10\n",
            "--> P.NC:1:",
            "moves",
        ),
        (
            "linuxcnc",
            b"G0 X50 Z5\nG1 X40 F0\n",
            "--> P.NC:2:8\n",
            "F0",
        ),
        (
            "fanuc",
            b"G76 P9999999 Q100 R0.1\n",
            "--> P.NC:1:5\n",
            "six digits",
        ),
        (
            "fanuc",
            b"G0 X1\0 Z2\n",
            "--> P.NC:1:6\n",
            "NUL byte (0x00)",
        ),
        ("siemens-802d", b"G0 X1 \xB0 Z2\n", "--> P.NC:1:7\n", "0xB0"),
        (
            "siemens-840d",
            b"DEF REAL AB[2]\nG0 X=AB[2]\n",
            "--> P.NC:2:8\n",
            "out of range",
        ),
    ];
    for (dialect, bytes, at, want) in programs {
        std::fs::write(d.join("P.NC"), bytes).unwrap();
        let (code, err) = vpcut_limited(&d, &format!("toolpath P.NC --dialect {dialect}"));
        assert_eq!(code, Some(2), "{dialect} {at}: {err}");
        assert!(
            err.contains(at) && err.contains(want),
            "{dialect}: wanted {at} {want} in {err}"
        );
    }
    // A Latin-1 comment and a byte order mark read.
    std::fs::write(d.join("P.NC"), b"\xEF\xBB\xBFG0 X1 Z2 (\xD8 20)\nM30\n").unwrap();
    let (code, err) = vpcut_limited(&d, "toolpath P.NC --dialect fanuc");
    assert_eq!(code, Some(0), "{err}");
    // Jobs: a number out of range, a type error, memory that cannot be had.
    let base = crate::support::with(
        &scene_text("iso-m20x2.5-radial"),
        &[
            ("simulation", "angular_cells", "72"),
            ("simulation", "measure_generators", "1"),
        ],
    );
    let jobs = [
        (
            crate::support::with(&base, &[("blank", "diameter", "1e300")]),
            "`blank.diameter`",
        ),
        (
            crate::support::with(&base, &[("thread", "starts", "1.5")]),
            "`thread.starts`",
        ),
        (
            crate::support::with(&base, &[("thread", "pitch", "\"fast\"")]),
            "`thread.pitch`",
        ),
        (
            crate::support::with(&base, &[("simulation", "angular_cells", "3600.0")]),
            "`simulation.angular_cells`",
        ),
        (
            crate::support::with(
                &base,
                &[
                    ("simulation", "axial_spacing", "1e-6"),
                    ("simulation", "angular_cells", "3600"),
                ],
            ),
            "a run sweeps and compares",
        ),
    ];
    for (text, want) in jobs {
        std::fs::write(d.join("job.toml"), text).unwrap();
        let (code, err) = vpcut_limited(&d, "simulate job.toml -q --max-dexels 100000000000000");
        assert_eq!(code, Some(2), "{want}: {err}");
        assert!(err.contains(want), "wanted {want} in {err}");
        if want.starts_with('`') {
            assert!(err.contains("job.toml:"), "{err}");
        }
    }
    // A tiny measurement spacing is bounded: the run finishes.
    let text = crate::support::with(&base, &[("simulation", "measure_spacing", "1e-12")]);
    std::fs::write(d.join("job.toml"), text).unwrap();
    let (code, err) = vpcut_limited(&d, "simulate job.toml -q");
    assert_eq!(code, Some(0), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Okuma OSP-P (issue 27): every class of bad input above in the `okuma` dialect: values
/// out of range, runaway loops and calls, malformed words and statements: a clean error at
/// its line and column, within the bound, no panic.
#[test]
fn okuma_bad_input_stops_cleanly() {
    let o = &[Dialect::Okuma];
    fails(
        o,
        &format!("G00 X{}\n", nines(400)),
        1,
        Some(6),
        "not a number",
    );
    fails(
        o,
        "VC1=99999999*99999999*99999999\nG00 X=VC1\n",
        1,
        Some(5),
        "out of range",
    );
    fails(o, "VC1=SQRT[-4]\n", 1, Some(5), "out of its domain");
    fails(o, "VC1=1/[VC2]\n", 1, Some(6), "division by zero");
    fails(o, "N1 GOTO N1\n", 1, None, "more than");
    fails(
        o,
        "N1 CALL OSUB\nM02\nOSUB\nCALL OSUB\nRTS\n",
        4,
        None,
        "subprogram",
    );
    fails(o, "IF [1 EQ 1 N10\n", 1, None, "`]`");
    fails(
        o,
        "G00 X1 Z1\nG01 Z-5 F\n",
        2,
        Some(10),
        "expected a number",
    );
    fails(o, "G00 X10 Z0\nG33 X9 Z-10 F0\n", 2, None, "positive lead");
    fails(
        o,
        "G00 X10 Z0\nCALL OX Q-1\n",
        2,
        Some(9),
        "whole number of repeats",
    );
    // A loop that makes moves without end stops at the moves limit.
    let limits = Limits {
        max_moves: 1000,
        ..Limits::default()
    };
    let e = nc_with(Dialect::Okuma, "N1 G00 X10\nG00 X20\nGOTO N1\n", limits).unwrap_err();
    assert!(e.message.contains("moves"), "{e}");
}
