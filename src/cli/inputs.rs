//! Input files: read with messages that say why a file cannot be read (missing, a folder,
//! not UTF-8 and where), recorded with their SHA-256 for the report, and the map from an
//! NC program's name (`O2`) back to the file that holds it.

use anyhow::Context as _;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// Read a text file named by the user: `what` says what it is ("the job file").
pub(crate) fn read_text(path: &Path, what: &str) -> anyhow::Result<(String, Vec<u8>)> {
    let bytes = read_bytes(path, what)?;
    match std::str::from_utf8(&bytes) {
        Ok(s) => Ok((s.to_string(), bytes)),
        Err(e) => {
            let at = e.valid_up_to();
            let before = &bytes[..at];
            let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
            let col = at
                - before
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |p| p + 1)
                + 1;
            anyhow::bail!(
                "cannot read {what} {}: it is not UTF-8 text: byte 0x{:02X} at byte offset {at} (line {line}, column {col}); save it as UTF-8",
                path.display(),
                bytes[at]
            )
        }
    }
}

/// Read a file named by the user, saying why it cannot be read.
pub(crate) fn read_bytes(path: &Path, what: &str) -> anyhow::Result<Vec<u8>> {
    if path.as_os_str() == "-" {
        anyhow::bail!("{what} cannot be read from standard input: give its path");
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => {
            anyhow::bail!(
                "cannot read {what} {}: it is a folder, not a file",
                path.display()
            )
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            anyhow::bail!("cannot read {what} {}: no such file", path.display())
        }
        _ => {}
    }
    std::fs::read(path).with_context(|| format!("cannot read {what} {}", path.display()))
}

/// A program or model file read as text: the library's one rule ([`vpcut::decode_program`]:
/// a UTF-8 byte order mark dropped, bytes that are not UTF-8 read as Latin-1, as controls
/// and their editors write comments).
pub(crate) fn decode_program(bytes: &[u8]) -> String {
    vpcut::decode_program(bytes.to_vec())
}

/// One input file as the report lists it.
#[derive(Clone, Debug)]
pub(crate) struct Read {
    /// `job`, `program`, `tool`.
    pub(crate) role: &'static str,
    /// The path as the user would write it (the job's folder joined with the name).
    pub(crate) path: PathBuf,
    /// The name the job used for it.
    pub(crate) name: String,
    /// The bytes.
    pub(crate) bytes: Vec<u8>,
}

/// The files a job read, in order: the job file, then what its loader read beside it.
#[derive(Debug, Default)]
pub(crate) struct Inputs {
    files: RefCell<Vec<Read>>,
    /// The files the loader looked for and did not find (a subprogram searched for in
    /// several folders): a file there later may change the job's outcome.
    absent: RefCell<Vec<PathBuf>>,
    /// Program lookups made (`holder` calls): the tests count them.
    scans: std::cell::Cell<usize>,
}

impl Inputs {
    /// Record a file.
    pub(crate) fn add(&self, role: &'static str, path: PathBuf, name: String, bytes: Vec<u8>) {
        let mut f = self.files.borrow_mut();
        if !f.iter().any(|r| r.path == path) {
            f.push(Read {
                role,
                path,
                name,
                bytes,
            });
        }
    }

    /// A loader for `Job::from_toml_with`: files beside the job, recorded as they are read.
    /// Tool meshes (`.obj`) are `tool`s, everything else a `program`.
    pub(crate) fn loader<'a>(&'a self, dir: &'a Path) -> impl Fn(&str) -> Option<String> + 'a {
        move |name: &str| {
            let path = dir.join(name);
            let bytes = std::fs::metadata(&path)
                .is_ok_and(|m| m.is_file())
                .then(|| std::fs::read(&path).ok())
                .flatten();
            let Some(bytes) = bytes else {
                let mut absent = self.absent.borrow_mut();
                if !absent.contains(&path) {
                    absent.push(path);
                }
                return None;
            };
            let text = decode_program(&bytes);
            let role = if name.to_ascii_lowercase().ends_with(".obj") {
                "tool"
            } else {
                "program"
            };
            self.add(role, path, name.to_string(), bytes);
            Some(text)
        }
    }

    /// The file that holds the NC program `name` as diagnostics and moves name it: a file
    /// read under that name, or (FANUC) the file with an `O<n>` line for `O<n>`. Only its
    /// path and name are copied (a move's lookup must not copy the program's text: 200k
    /// moves of a 5 MB program did, quadratic). Each call counts in `scans`.
    fn holder(&self, name: &str) -> Option<(PathBuf, String)> {
        self.scans.set(self.scans.get() + 1);
        let files = self.files.borrow();
        let found = files.iter().find(|r| r.name == name).or_else(|| {
            let n: u32 = name.strip_prefix('O')?.parse().ok()?;
            files.iter().filter(|r| r.role == "program").find(|r| {
                decode_program(&r.bytes).lines().any(|l| {
                    let code = l.split(['(', ';']).next().unwrap_or("").trim();
                    code.strip_prefix(['O', 'o'])
                        .is_some_and(|d| !d.is_empty() && d.parse::<u32>().ok() == Some(n))
                })
            })
        });
        found.map(|r| (r.path.clone(), r.name.clone()))
    }

    /// The path of the file that holds program `name`, as the user would write it.
    pub(crate) fn program_file(&self, name: &str) -> Option<PathBuf> {
        self.holder(name).map(|r| r.0)
    }

    /// The name the job gives the file that holds program `name` (relative to the job).
    pub(crate) fn program_name(&self, name: &str) -> Option<String> {
        self.holder(name).map(|r| r.1)
    }

    /// Moves name their program (`O2`); rows name the file that holds it: each move's
    /// `file` becomes that file's name. Each distinct program is looked up once (a lookup
    /// may decode every program file), so this is linear in the moves.
    pub(crate) fn name_move_files(&self, moves: &mut [vpcut::Move]) {
        let mut names: std::collections::HashMap<String, Option<String>> =
            std::collections::HashMap::new();
        for m in moves {
            let name = names.entry(m.file.clone()).or_insert_with(|| {
                let p = self.program_file(&m.file)?;
                let file = p.file_name()?.to_string_lossy().into_owned();
                (file != m.file).then_some(file)
            });
            if let Some(n) = name {
                m.file.clone_from(n);
            }
        }
    }

    /// The paths of the files read.
    pub(crate) fn paths(&self) -> Vec<PathBuf> {
        self.files.borrow().iter().map(|r| r.path.clone()).collect()
    }

    /// The files read, for a record of `check --report-dir`: role, path as read, hash.
    pub(crate) fn hashed(&self) -> Vec<crate::cli::record::Hashed> {
        self.files
            .borrow()
            .iter()
            .map(|r| crate::cli::record::Hashed {
                role: r.role.to_string(),
                path: r.path.to_string_lossy().into_owned(),
                sha256: crate::cli::record::sha256(&r.bytes),
            })
            .collect()
    }

    /// The files looked for and not found, in order.
    pub(crate) fn absent(&self) -> Vec<PathBuf> {
        self.absent.borrow().clone()
    }

    /// The files for the report, with their hashes.
    pub(crate) fn report(&self) -> Vec<vpcut::InputFile> {
        self.files
            .borrow()
            .iter()
            .map(|r| vpcut::InputFile::new(r.role, r.name.clone(), &r.bytes))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_utf8_names_byte_line_and_column() {
        let d = std::env::temp_dir().join(format!("vpcut-inputs-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("j.toml");
        std::fs::write(&p, b"a = 1\nb = \"\xff\"\n").unwrap();
        let e = read_text(&p, "the job file").unwrap_err().to_string();
        assert!(
            e.contains("byte 0xFF at byte offset 11 (line 2, column 6)"),
            "{e}"
        );
        let e = read_text(&d, "the job file").unwrap_err().to_string();
        assert!(e.contains("it is a folder"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn latin1_programs_decode() {
        assert_eq!(decode_program(b"(caf\xe9)\nG0"), "(caf\u{e9})\nG0");
        assert_eq!(decode_program("(caf\u{e9})".as_bytes()), "(caf\u{e9})");
    }

    #[test]
    fn fanuc_subprograms_are_found_in_their_file() {
        let inputs = Inputs::default();
        inputs.add(
            "program",
            PathBuf::from("d/MAIN.NC"),
            "MAIN.NC".into(),
            b"O0001\nM98 P2\nM30\nO0002 (SUB)\nM99\n".to_vec(),
        );
        assert_eq!(inputs.program_file("O2"), Some(PathBuf::from("d/MAIN.NC")));
        assert_eq!(inputs.program_name("O2").as_deref(), Some("MAIN.NC"));
        assert_eq!(
            inputs.program_file("MAIN.NC"),
            Some(PathBuf::from("d/MAIN.NC"))
        );
        assert_eq!(inputs.program_file("O3"), None);
    }

    /// The toolpath rows' file names: one lookup per distinct program, whatever the number
    /// of moves (each lookup may decode every program file: a lookup per move made
    /// `vpcut toolpath` quadratic, 30 s for 100k blocks). An operation count, not a timing.
    #[test]
    fn move_files_are_named_with_one_lookup_per_program() {
        let inputs = Inputs::default();
        let mut text = b"O0001\nM98 P2\nM30\nO0002 (SUB)\nM99\n".to_vec();
        text.extend(std::iter::repeat_n(b'(', 100_000));
        inputs.add(
            "program",
            PathBuf::from("d/MAIN.NC"),
            "MAIN.NC".into(),
            text,
        );
        let mv = |file: &str| vpcut::Move {
            file: file.into(),
            line: 1,
            kind: vpcut::MoveKind::Rapid,
            x_start: 0.0,
            z_start: 0.0,
            x_dia: 1.0,
            z: 1.0,
            lead: None,
            lead_change: None,
            sync_angle_deg: None,
            chained: false,
            tool: None,
            tool_word: None,
            spindle: vpcut::Spindle::Cw,
            arc: None,
            speed: Default::default(),
            feed: None,
            cycle: false,
            nose: None,
        };
        let mut moves: Vec<vpcut::Move> = (0..30_000)
            .map(|k| mv(["O1", "O2", "MAIN.NC", "O9"][k % 4]))
            .collect();
        inputs.name_move_files(&mut moves);
        assert_eq!(inputs.scans.get(), 4, "one lookup per distinct program");
        let files: Vec<&str> = moves[..4].iter().map(|m| m.file.as_str()).collect();
        assert_eq!(files, ["MAIN.NC", "MAIN.NC", "MAIN.NC", "O9"]);
    }
}
