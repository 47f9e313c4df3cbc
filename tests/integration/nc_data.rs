//! NC programs as data: every `tests/data/nc/<dialect>/*.nc` runs through the public
//! interpreter and its moves, warnings or error must equal the reviewed `*.moves` beside it.
//!
//! The `.moves` format (one item a line, numbers rounded to 6 decimals; see
//! `tests/data/nc/README.md`): leading `#` lines are the file's header (where the expected
//! values come from; kept when blessing), then lathe moves
//! `L<line> <kind> X<x0> Z<z0> -> X<x1> Z<z1>` with `lead=`, `change=`, `sync=`, `chained`,
//! `tool=`, `ccw` and an arc's `centre=X..,Z.. cw|ccw` where they apply; milling moves
//! `L<line> <kind> (x,y,z) -> (x,y,z)` with `prog=`, `feed=`, `tool=`, `comp=`, an arc's
//! `centre=`, `r=`, `sweep=`, `plane=`, `spindle=`; `warning L<line>:<col> <message>`; a failed run's
//! `error L<line>:<col> <message>` and after it the other errors and warnings the static
//! check found, one a line. `VPCUT_BLESS=1` rewrites the files (header kept): review
//! the difference against the header's source before committing it.

use crate::support::{blessing, root};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use vpcut::{
    interpret_with, DecimalPoint, Dialect, InputIncrement, MillMove, MillSettings, Move, MoveKind,
    NcOptions, Settings, Severity, Source, Spindle, Toolpath,
};

/// The dialect folders and what they run as.
const DIALECTS: [(&str, Dialect, bool); 7] = [
    ("fanuc", Dialect::Fanuc, false),
    ("gsk", Dialect::Gsk980, false),
    ("siemens", Dialect::Siemens802d, false),
    ("siemens-840d", Dialect::Siemens840d, false),
    ("linuxcnc", Dialect::Linuxcnc, false),
    ("fanuc-mill", Dialect::Fanuc, true),
    ("okuma", Dialect::Okuma, false),
];

/// The milling machine of `fanuc-mill`: G54's work zero at (100, 50, -10), G57's at the
/// job's origin; H10 a length offset; D60 = 5 mm, D61 = 9 mm; the tool comes from z = 100.
fn mill_settings() -> MillSettings {
    let mut work_offsets = [[0.0; 3]; 6];
    work_offsets[0] = [100.0, 50.0, -10.0];
    MillSettings {
        work_offsets,
        radius_offsets: vec![(60, 5.0), (61, 9.0)],
        length_offsets: vec![10],
        home_z: 100.0,
    }
}

/// The machine settings a program is written for, from its `.moves` header's
/// `# settings: key = value, ...` line (the `[program]` keys of a job: `decimal_point`,
/// `input_increment`, `units`, `feed_mode`, `x_mode`, `main`; `nose`, the turning tools'
/// nose radii and tip directions; and `definitions` as names separated by spaces), over
/// `base`.
fn header_settings(header: &str, mut base: Settings) -> Settings {
    for line in header.lines() {
        let Some(rest) = line
            .trim_start_matches('#')
            .trim()
            .strip_prefix("settings:")
        else {
            continue;
        };
        for pair in rest.split(',') {
            let (k, v) = pair.split_once('=').expect("settings: key = value");
            let (k, v) = (k.trim(), v.trim().trim_matches('"'));
            match k {
                "decimal_point" => base.decimal_point = DecimalPoint::from_name(v).expect(v),
                "input_increment" => {
                    base.input_increment = InputIncrement::from_mm(v.parse().expect(v)).expect(v)
                }
                "units" => base.power_on.inch = v == "inch",
                "feed_mode" => base.power_on.per_minute = v == "per-minute",
                "x_mode" => base.power_on.diameter = Some(v == "diameter"),
                "main" => base.main = Some(v.to_string()),
                // Tool nose radius compensation's tools: `nose = "1:0.8:3 2:0.4:2"` (tool,
                // nose radius, tip direction), as a job's turning tools give them.
                "nose" => {
                    for t in v.split_whitespace() {
                        let f: Vec<&str> = t.split(':').collect();
                        let tool = f[0].parse().expect(t);
                        let nose = (f[1].parse().expect(t), f[2].parse().expect(t));
                        base.noses.tool.insert(tool, nose);
                    }
                }
                "definitions" => {
                    base.definitions = v.split_whitespace().map(str::to_string).collect()
                }
                _ => panic!("unknown setting `{k}` in a .moves header"),
            }
        }
    }
    base
}

/// A number rounded to 6 decimals, trailing zeros dropped (`-0` reads `0`).
fn num(v: f64) -> String {
    let s = format!("{:.6}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

fn lathe_move(out: &mut String, m: &Move) {
    let kind = match m.kind {
        MoveKind::Rapid => "rapid",
        MoveKind::Feed => "feed",
        MoveKind::Thread => "thread",
        MoveKind::Arc => "arc",
    };
    let _ = write!(
        out,
        "L{} {kind} X{} Z{} -> X{} Z{}",
        m.line,
        num(m.x_start),
        num(m.z_start),
        num(m.x_dia),
        num(m.z)
    );
    if let Some(l) = m.lead {
        let _ = write!(out, " lead={}", num(l));
    }
    if let Some(c) = m.lead_change {
        let _ = write!(out, " change={}", num(c));
    }
    if let Some(a) = m.sync_angle_deg {
        let _ = write!(out, " sync={}", num(a));
    }
    if m.chained {
        out.push_str(" chained");
    }
    if let Some(a) = m.arc {
        let _ = write!(
            out,
            " centre=X{},Z{} {}",
            num(a.x_centre_dia),
            num(a.z_centre),
            if a.clockwise { "cw" } else { "ccw" }
        );
    }
    if let Some(t) = m.tool {
        let _ = write!(out, " tool={t}");
    }
    if m.spindle == Spindle::Ccw {
        out.push_str(" ccw");
    }
    if let Some(n) = m.nose {
        let side = match n.side {
            vpcut::CompSide::Left => "G41",
            vpcut::CompSide::Right => "G42",
        };
        let _ = write!(out, " nose={side}:{}:{}", num(n.radius), n.tip);
    }
    out.push('\n');
}

fn point(p: [f64; 3]) -> String {
    format!("({},{},{})", num(p[0]), num(p[1]), num(p[2]))
}

fn mill_move(out: &mut String, m: &MillMove) {
    let kind = format!("{:?}", m.kind).to_lowercase();
    let _ = write!(
        out,
        "L{} {kind} {} -> {}",
        m.line,
        point(m.start),
        point(m.end)
    );
    if m.programmed_end != m.end {
        let _ = write!(out, " prog={}", point(m.programmed_end));
    }
    if let Some(a) = m.arc {
        let _ = write!(
            out,
            " centre={} r={} sweep={} plane={:?}",
            point(a.centre),
            num(a.radius),
            num(a.sweep),
            a.plane
        );
    }
    if let Some(f) = m.feed {
        let _ = write!(out, " feed={}", num(f));
    }
    if let Some(t) = m.tool {
        let _ = write!(out, " tool={t}");
    }
    match m.spindle {
        Some(Spindle::Cw) => {}
        Some(Spindle::Ccw) => out.push_str(" spindle=ccw"),
        None => out.push_str(" spindle=off"),
    }
    if let Some((side, r)) = m.comp {
        let _ = write!(out, " comp={:?}:{}", side, num(r));
    }
    out.push('\n');
}

/// The body of a `.moves` file for one run.
fn render(result: &Result<Toolpath, Box<vpcut::NcError>>) -> String {
    let mut out = String::new();
    match result {
        Ok(t) => {
            for m in &t.moves {
                lathe_move(&mut out, m);
            }
            for m in &t.mill {
                mill_move(&mut out, m);
            }
            for w in &t.warnings {
                let _ = writeln!(out, "warning L{}:{} {}", w.line, w.col, w.message);
            }
        }
        Err(e) => {
            let _ = writeln!(out, "error L{}:{} {}", e.line, e.col, e.message);
            // The static check's other findings, in line order.
            for d in &e.others {
                let severity = match d.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                };
                let _ = writeln!(out, "{severity} L{}:{} {}", d.line, d.col, d.message);
            }
        }
    }
    out
}

/// The `.nc` files of a folder (Okuma's `.MIN` main programs too), sorted.
fn programs(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "nc" || x == "MIN"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Run every program of the data with the settings of its `.moves` header: (folder,
/// file name, folder path, the program's text, the result).
fn run_all(mut each: impl FnMut(&str, &str, &Path, &str, &Result<Toolpath, Box<vpcut::NcError>>)) {
    let base = root().join("tests/data/nc");
    for (folder, dialect, mill) in DIALECTS {
        let dir = base.join(folder);
        for path in programs(&dir) {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&path).unwrap();
            let main = Source {
                name: name.clone(),
                text: text.clone(),
            };
            let loader = |n: &str| {
                std::fs::read_to_string(dir.join(n))
                    .ok()
                    .map(|text| Source {
                        name: n.to_string(),
                        text,
                    })
            };
            let old = std::fs::read_to_string(path.with_extension("moves")).unwrap_or_default();
            let header: String = old
                .lines()
                .take_while(|l| l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect();
            let opts = NcOptions {
                settings: header_settings(
                    &header,
                    Settings {
                        mill: mill.then(mill_settings),
                        ..Settings::default()
                    },
                ),
                ..NcOptions::default()
            };
            let result = interpret_with(&main, dialect, &loader, &opts).map_err(Box::new);
            each(folder, &name, &dir, &text, &result);
        }
    }
}

/// Issue 29: tools as the program writes them. Every move of every program of the data
/// that has a tool carries its T word as written (`T0202`, `T="THREAD_55" D1`, Okuma's
/// `T030303`): each word of it (`T..`, `D..`) stands in the program or a file beside it as
/// a word of its own, and its number is the move's tool (FANUC and GSK: the code over 100;
/// Okuma: the middle pair of six digits or the last pair of four; a Siemens name: 1000 and
/// up). That is what every message naming a tool prints (`Move::tool_name`).
#[test]
fn every_tool_is_named_as_the_program_writes_it() {
    // The word `w` stands alone in `text` (upper case, not inside a longer word).
    let stands = |text: &str, w: &str| {
        let t = text.to_uppercase();
        let w = w.to_uppercase();
        t.match_indices(&w).any(|(i, _)| {
            let before = t[..i].chars().next_back();
            let after = t[i + w.len()..].chars().next();
            !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
                && !after.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
        })
    };
    let (mut named, mut programs_with_tools) = (0, 0);
    let mut failures = Vec::new();
    run_all(|folder, name, dir, text, result| {
        let Ok(tp) = result else { return };
        // The program and the files beside it that a call may read.
        let mut texts = vec![text.to_string()];
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x != "moves" && x != "md") {
                texts.push(std::fs::read_to_string(&p).unwrap_or_default());
            }
        }
        let lathe = tp
            .moves
            .iter()
            .map(|m| (m.line, m.tool, m.tool_word.clone()));
        let mill = tp
            .mill
            .iter()
            .map(|m| (m.line, m.tool, m.tool_word.clone()));
        let mut any = false;
        for (line, tool, word) in lathe.chain(mill) {
            let Some(tool) = tool else {
                if word.is_some() {
                    failures.push(format!(
                        "{folder}/{name}:{line}: a word {word:?} without a tool"
                    ));
                }
                continue;
            };
            any = true;
            let Some(word) = word else {
                failures.push(format!(
                    "{folder}/{name}:{line}: tool {tool} without its word"
                ));
                continue;
            };
            named += 1;
            for part in word.split(' ') {
                if !texts.iter().any(|t| stands(t, part)) {
                    failures.push(format!("{folder}/{name}:{line}: `{part}` of `{word}` is not written in the program"));
                }
            }
            let t = word.split(' ').next().unwrap();
            let number = match t.strip_prefix("T=") {
                Some(_) => tool >= 1000,
                None => {
                    let n: u32 = t[1..].parse().unwrap_or(u32::MAX);
                    let digits = t.len() - 1;
                    match folder {
                        "fanuc" | "gsk" if n >= 100 => n / 100 == tool,
                        "okuma" if digits == 6 => (n / 100) % 100 == tool,
                        "okuma" => n % 100 == tool,
                        _ => n == tool,
                    }
                }
            };
            if !number {
                failures.push(format!(
                    "{folder}/{name}:{line}: `{word}` is not tool {tool}"
                ));
            }
        }
        programs_with_tools += usize::from(any);
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        programs_with_tools >= 60,
        "{programs_with_tools} programs with tools"
    );
    eprintln!("{named} moves of {programs_with_tools} programs name their tool as written");
}

#[test]
fn nc_programs_give_their_reviewed_moves() {
    let base = root().join("tests/data/nc");
    let mut failures = Vec::new();
    let mut count = 0;
    for (folder, dialect, mill) in DIALECTS {
        let dir = base.join(folder);
        for path in programs(&dir) {
            count += 1;
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let main = Source {
                name: name.clone(),
                text: std::fs::read_to_string(&path).unwrap(),
            };
            // Subprograms are the files beside the program (`O0100.nc`, `SUB.SPF`).
            let loader = |n: &str| {
                std::fs::read_to_string(dir.join(n))
                    .ok()
                    .map(|text| Source {
                        name: n.to_string(),
                        text,
                    })
            };
            let expect_path = path.with_extension("moves");
            let old = std::fs::read_to_string(&expect_path).unwrap_or_default();
            let header: String = old
                .lines()
                .take_while(|l| l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect();
            let opts = NcOptions {
                settings: header_settings(
                    &header,
                    Settings {
                        mill: mill.then(mill_settings),
                        ..Settings::default()
                    },
                ),
                ..NcOptions::default()
            };
            let result = interpret_with(&main, dialect, &loader, &opts).map_err(Box::new);
            let got = render(&result);
            let body: String = old
                .lines()
                .skip_while(|l| l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect();
            if blessing() {
                std::fs::write(&expect_path, format!("{header}{got}")).unwrap();
                continue;
            }
            if header.is_empty() {
                failures.push(format!(
                    "{folder}/{name}: the .moves file has no header saying where its values come from"
                ));
            }
            if body != got {
                failures.push(format!(
                    "{folder}/{name}: moves differ from {}\n--- expected\n{body}--- got\n{got}",
                    expect_path.display()
                ));
            }
        }
    }
    assert!(count >= 20, "only {count} NC data programs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The 840D is a superset of the 802D: every 802D program of the data (and the seed's
/// MYAAA.MPF) makes the same moves read as `siemens-840d`.
#[test]
fn siemens_802d_programs_make_the_same_moves_on_the_840d() {
    let mut dirs = vec![root().join("tests/data/nc/siemens")];
    dirs.push(root().join("scenes/seed002-siemens-equal-tooth"));
    let mut compared = 0;
    for dir in dirs {
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "nc" || x == "MPF"))
            .collect();
        files.sort();
        for path in files {
            let main = Source {
                name: path.file_name().unwrap().to_string_lossy().into_owned(),
                text: std::fs::read_to_string(&path).unwrap(),
            };
            let loader = |n: &str| {
                std::fs::read_to_string(dir.join(n))
                    .ok()
                    .map(|text| Source {
                        name: n.to_string(),
                        text,
                    })
            };
            let opts = NcOptions::default();
            let Ok(a) = interpret_with(&main, Dialect::Siemens802d, &loader, &opts) else {
                continue;
            };
            let b = interpret_with(&main, Dialect::Siemens840d, &loader, &opts)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert_eq!(a.moves, b.moves, "{}", path.display());
            compared += 1;
        }
    }
    assert!(compared >= 6, "only {compared} programs compared");
}

/// Issue 17's corpus: whole shop programs (`corpus-*.nc` in the dialect folders), at least
/// 40 of them. Each is named in its folder's `CORPUS.md` (with the public sources its
/// features come from), every `CORPUS.md` row names a program that exists, and each runs
/// from its first block to its last: its reviewed `.moves` holds no error and at least one
/// thread move (the moves themselves are checked by `nc_programs_give_their_reviewed_moves`).
#[test]
fn corpus_programs_are_listed_and_run_to_their_threads() {
    let mut total = 0;
    for (folder, _, _) in DIALECTS {
        let dir = root().join("tests/data/nc").join(folder);
        let corpus: Vec<String> = programs(&dir)
            .into_iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .filter(|n| n.starts_with("corpus-"))
            .collect();
        if corpus.is_empty() {
            continue;
        }
        let index = std::fs::read_to_string(dir.join("CORPUS.md"))
            .unwrap_or_else(|_| panic!("{folder}: corpus programs but no CORPUS.md"));
        for name in &corpus {
            let stem = name.trim_end_matches(".nc").trim_end_matches(".MIN");
            assert!(
                index.contains(&format!("`{name}`")) || index.contains(&format!("`{stem}`")),
                "{folder}/{name} is not listed in {folder}/CORPUS.md"
            );
            let moves = std::fs::read_to_string(dir.join(name).with_extension("moves")).unwrap();
            let body: Vec<&str> = moves.lines().filter(|l| !l.starts_with('#')).collect();
            assert!(
                !body.iter().any(|l| l.starts_with("error ")),
                "{folder}/{name} does not run to its end"
            );
            assert!(
                body.iter().any(|l| l.contains(" thread ")),
                "{folder}/{name} makes no thread move"
            );
        }
        for listed in index.lines().filter_map(|l| {
            let l = l.strip_prefix("| `")?;
            let listed = &l[..l.find('`')?];
            Some(if listed.ends_with(".nc") || listed.ends_with(".MIN") {
                listed.to_string()
            } else {
                format!("{listed}.nc")
            })
        }) {
            assert!(
                corpus.contains(&listed),
                "{folder}/CORPUS.md lists `{listed}`, which is not a corpus program there"
            );
        }
        total += corpus.len();
    }
    assert!(
        total >= 40,
        "the corpus holds {total} programs, fewer than 40"
    );
}
