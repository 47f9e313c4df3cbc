//! Issue 27: the coverage tables (`docs/coverage/*.md`) say what vpcut does with every code
//! of each control's manual. A code whose status is `simulated` must be exercised by some
//! program of the dialect's corpus folders in `tests/data/nc` (the oracle is the corpus
//! itself: the programs' text, comments left out), and one that says `simulated, no corpus
//! program yet` must not be (then the table is out of date: say `simulated`).

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every program text of the folders, upper-case, comments (`(..)` and from `;`) left out.
fn corpus(folders: &[&str]) -> String {
    let mut all = String::new();
    for f in folders {
        let dir = root().join("tests/data/nc").join(f);
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("entry").path())
            .filter(|p| {
                let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
                !matches!(ext, "moves" | "md")
            })
            .collect();
        files.sort();
        for p in files {
            let text = std::fs::read_to_string(&p).unwrap_or_default();
            for line in text.lines() {
                let mut depth = 0;
                for ch in line.chars() {
                    match ch {
                        '(' => depth += 1,
                        ')' if depth > 0 => depth -= 1,
                        ';' if depth == 0 => break,
                        _ if depth > 0 => {}
                        c => all.push(c.to_ascii_uppercase()),
                    }
                }
                all.push('\n');
            }
        }
    }
    all
}

/// Whether `code` (`G71`, `G07.1`, `M3`, `WHILE`, `R1`, `CYCLE97`, `G65 H`) occurs in
/// `text`: a G/M code as a word (leading zeros free: `G1` is `G01`, not `G10`), anything
/// else as a word of its own.
fn uses(text: &str, code: &str) -> bool {
    let b = text.as_bytes();
    let word_start = |i: usize| i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
    let gm = code.len() > 1
        && matches!(code.as_bytes()[0], b'G' | b'M')
        && code[1..].bytes().all(|c| c.is_ascii_digit() || c == b'.');
    if gm {
        let (letter, number) = (code.as_bytes()[0], code[1..].trim_start_matches('0'));
        let want: f64 = if number.is_empty() {
            0.0
        } else {
            number.parse().expect("number")
        };
        let mut i = 0;
        while i < b.len() {
            if b[i] == letter && word_start(i) {
                let mut j = i + 1;
                while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                    j += 1;
                }
                if let Ok(v) = text[i + 1..j].parse::<f64>() {
                    if v == want {
                        return true;
                    }
                }
                i = j.max(i + 1);
            } else {
                i += 1;
            }
        }
        return false;
    }
    // `G65 H`: Macro A (G65 with an H word).
    if code == "G65 H" {
        return text.lines().any(|l| uses(l, "G65") && l.contains('H'));
    }
    let c = code.as_bytes();
    (0..b.len()).any(|i| {
        b[i..].starts_with(c)
            && word_start(i)
            && b.get(i + c.len()).is_none_or(|n| {
                !(n.is_ascii_alphabetic() || *n == b'_') || c.last().is_some_and(u8::is_ascii_digit)
            })
    })
}

/// The rows of a table: (first column without backticks, status).
fn rows(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells[1].trim_matches('`').to_string(), cells[2].to_string())
        })
        .collect()
}

#[test]
fn every_simulated_code_of_the_coverage_tables_is_exercised_by_the_corpus() {
    let tables: [(&str, &[&str]); 4] = [
        ("fanuc-lathe.md", &["fanuc"]),
        ("fanuc-mill.md", &["fanuc-mill"]),
        ("gsk.md", &["gsk"]),
        ("siemens.md", &["siemens", "siemens-840d"]),
    ];
    let statuses = [
        "simulated",
        "simulated, no corpus program yet",
        "no motion",
        "moves only",
        "ignored with warning",
        "refused",
    ];
    let mut problems = Vec::new();
    let mut simulated = 0;
    for (table, folders) in tables {
        let text = corpus(folders);
        let rows = rows(&root().join("docs/coverage").join(table));
        assert!(rows.len() > 20, "{table}: {} rows", rows.len());
        for (code, status) in rows {
            if !statuses.contains(&status.as_str()) {
                problems.push(format!("{table}: `{code}`: unknown status `{status}`"));
            }
            // The first code of a range (`G55..G59`) stands for it.
            let first = code.split("..").next().unwrap_or(&code).to_string();
            let found = uses(&text, &first);
            if status == "simulated" {
                simulated += 1;
                if !found {
                    problems.push(format!(
                        "{table}: `{code}` says simulated, but no program in {folders:?} uses it"
                    ));
                }
            }
            if status == "simulated, no corpus program yet" && found {
                problems.push(format!(
                    "{table}: `{code}` is used by a program in {folders:?} now: say simulated"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(simulated > 100, "{simulated} simulated codes");
}

/// The matcher itself, on cases written by hand.
#[test]
fn the_corpus_matcher_reads_codes_as_words() {
    for (text, code, want) in [
        ("G01 X1.\n", "G1", true),
        ("G1 X1.\n", "G01", true),
        ("G10 P1\n", "G1", false),
        ("G71 U1.\n", "G7", false),
        ("G07.1 C1.\n", "G7.1", true),
        ("N10 G00X1.\n", "G0", true),
        ("MSG(\"X\")\n", "M", false),
        ("M3 S100\n", "M03", true),
        ("M30\n", "M3", false),
        ("WHILE[#1LT3]DO1\n", "WHILE", true),
        ("ENDWHILE\n", "WHILE", false),
        ("R1=2\n", "R1", true),
        ("R10=2\n", "R1", true),
        ("CYCLE97(1)\n", "CYCLE97", true),
        ("G65 H01 P#100 Q5\n", "G65 H", true),
        ("G65 P9010 X1.\n", "G65 H", false),
        ("TEST=1\n", "TEST=1", true),
    ] {
        assert_eq!(uses(text, code), want, "{code} in {text:?}");
    }
}
