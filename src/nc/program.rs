//! Splitting a file into programs and blocks: comments, `%`, block skip, N numbers,
//! Siemens labels, and FANUC `O` numbers that start a new program.

use super::{Dialect, Source};
use std::collections::HashMap;

/// The text of a program file read as bytes: UTF-8 without a leading byte order mark;
/// a byte that is not part of valid UTF-8 is read as Latin-1 (controls and old editors
/// write comments such as `(GEWINDE Ø20)` in it), so such a file still loads and a byte
/// outside a comment is reported at its line and column with its value.
pub fn decode_program(bytes: Vec<u8>) -> String {
    let bytes = match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) => rest.to_vec(),
        None => bytes,
    };
    match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => {
            let bytes = e.into_bytes();
            let mut out = String::with_capacity(bytes.len() + bytes.len() / 8);
            for chunk in bytes.utf8_chunks() {
                out.push_str(chunk.valid());
                out.extend(chunk.invalid().iter().map(|&b| char::from(b)));
            }
            out
        }
    }
}

/// A program split into blocks.
#[derive(Debug)]
pub(super) struct Program {
    pub(super) name: String,
    /// Another name it is called by (`O0001` for the first program of `MAIN.NC`).
    pub(super) alias: Option<String>,
    /// (1-based line, original text, text without comments, upper-cased).
    pub(super) blocks: Vec<(usize, String, String)>,
    pub(super) labels: HashMap<String, usize>,
    pub(super) numbers: HashMap<u32, usize>,
}

fn strip_comment(line: &str, dialect: Dialect) -> String {
    let mut out = String::new();
    let mut depth = 0;
    let mut quoted = false;
    for c in line.chars() {
        match (dialect, c) {
            // A Siemens string (`MSG("A;B")`, `SET(";")`) may hold a `;`.
            (Dialect::Siemens802d, '"') => {
                quoted = !quoted;
                out.push(c);
            }
            (Dialect::Siemens802d, _) if quoted => out.push(c.to_ascii_uppercase()),
            (Dialect::Siemens802d, ';') => break,
            (Dialect::Fanuc, ';') if depth == 0 => break,
            (Dialect::Fanuc, '(') => depth += 1,
            (Dialect::Fanuc, ')') if depth > 0 => depth -= 1,
            _ if depth > 0 => {}
            _ => out.push(c.to_ascii_uppercase()),
        }
    }
    out.trim().to_string()
}

/// FANUC tape text: `;` outside a comment is the end of block (EOB, what FANUC screens and
/// ISO tapes print for LF), so one line may hold several blocks (`%;O1200;G0 X20;...`).
/// Each block becomes a line of its own that keeps its line number; the text before it on
/// the line is blanked to spaces so that columns stay those of the file. A `%` at the start
/// of a line (the tape start, as in `%O1200(THREAD)`) is blanked too.
fn split_eob(line: &str) -> Vec<String> {
    const PAD: usize = 160;
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut depth = 0;
    for (k, c) in line.chars().enumerate() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => {
                out.push(std::mem::take(&mut cur));
                // The next block starts after this `;`: blank what came before, so that
                // columns stay the file's (up to `PAD` characters: a hostile line of many
                // thousand blocks must not cost the square of its length; later blocks
                // count columns from their own start).
                let before = k + 1;
                if before <= PAD {
                    cur = " ".repeat(before);
                }
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur);
    out.into_iter()
        .map(|b| {
            let t = b.trim_start();
            match t.strip_prefix('%') {
                Some(rest) if !rest.trim().is_empty() => {
                    format!("{} {rest}", " ".repeat(b.len() - t.len()))
                }
                _ => b,
            }
        })
        .filter(|b| !b.trim().is_empty())
        .collect()
}

/// The programs of a file: for FANUC syntax each `O<number>` line starts a new program
/// (named `O<number>`, the first one also by the file's name); Siemens files hold one.
///
/// With `skip` (the block-skip switch on) blocks that start with `/` are left out; without
/// it the `/` (and an optional skip level 1..9 after it) is dropped and the block runs.
pub(super) fn load_programs(src: &Source, dialect: Dialect, skip: bool) -> Vec<Program> {
    // A byte order mark is no part of the program (editors on Windows write one).
    if let Some(rest) = src.text.strip_prefix('\u{feff}') {
        let src = Source {
            name: src.name.clone(),
            text: rest.to_string(),
        };
        return load_programs(&src, dialect, skip);
    }
    if dialect == Dialect::Linuxcnc {
        return super::linuxcnc::load(src);
    }
    let mut out = Vec::new();
    let mut name = src.name.clone();
    let mut alias: Option<String> = None;
    let mut lines: Vec<(usize, String)> = Vec::new();
    let split: Vec<(usize, String)> = src
        .text
        .lines()
        .enumerate()
        .flat_map(|(i, line)| {
            if dialect == Dialect::Fanuc {
                split_eob(line).into_iter().map(|b| (i, b)).collect()
            } else {
                vec![(i, line.to_string())]
            }
        })
        .collect();
    for (i, line) in split {
        let text = strip_comment(&line, dialect);
        let onum = text
            .strip_prefix('O')
            .filter(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
            .and_then(|r| r.parse::<u32>().ok());
        if dialect == Dialect::Fanuc {
            if let Some(n) = onum {
                let real = |l: &str| {
                    let t = strip_comment(l, dialect);
                    !t.is_empty() && t != "%"
                };
                if lines.iter().any(|(_, l)| real(l)) {
                    let mut p = load_program(&name, &lines, dialect, skip);
                    p.alias = alias.take();
                    out.push(p);
                    lines.clear();
                    name = format!("O{n}");
                } else {
                    alias = Some(format!("O{n}"));
                }
                continue;
            }
        }
        lines.push((i, line));
    }
    let mut p = load_program(&name, &lines, dialect, skip);
    p.alias = alias;
    out.push(p);
    out
}

fn load_program(name: &str, lines: &[(usize, String)], dialect: Dialect, skip: bool) -> Program {
    let mut blocks = Vec::new();
    let mut labels = HashMap::new();
    let mut numbers = HashMap::new();
    for (i, line) in lines {
        let (i, line) = (*i, line.as_str());
        let mut text = strip_comment(line, dialect);
        if let Some(rest) = text.strip_prefix('/') {
            if skip {
                continue;
            }
            let rest = match rest.as_bytes().first() {
                Some(b'1'..=b'9') => &rest[1..],
                _ => rest,
            };
            text = rest.trim_start().to_string();
        }
        if text.is_empty() || text == "%" {
            continue;
        }
        let idx = blocks.len();
        let mut rest = text.as_str();
        // N number.
        if let Some(r) = rest.strip_prefix('N') {
            let digits: String = r.chars().take_while(|c| c.is_ascii_digit()).collect();
            if !digits.is_empty() {
                if let Ok(n) = digits.parse() {
                    numbers.insert(n, idx);
                }
                rest = r[digits.len()..].trim_start();
            }
        }
        if dialect == Dialect::Siemens802d {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && rest[name.len()..].starts_with(':') {
                labels.insert(name, idx);
            }
        }
        blocks.push((i + 1, line.to_string(), text));
    }
    Program {
        name: name.to_string(),
        alias: None,
        blocks,
        labels,
        numbers,
    }
}
