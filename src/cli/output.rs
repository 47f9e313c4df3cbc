//! Output files, all or nothing: every output path is checked before the work starts (its
//! folder exists and takes a new file, it is not a folder, two outputs are not the same file,
//! no output overwrites an input), every file is written to a temporary beside its final
//! target, and the temporaries are renamed into place only when all of them were written.
//! A run that fails at any point leaves every existing file as it was.
//!
//! A symbolic link is followed: the temporary is made next to the link's final target and
//! renamed there, so the link keeps pointing at fresh data. A device or a FIFO
//! (`/dev/stdout`, a named pipe) is written directly, never replaced. `-` is standard output.

use crate::cli::term;
use anyhow::Context as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// An output that has been checked and has a place to go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Slot(usize);

enum Dest {
    /// Standard output: the bytes, written last.
    Stdout(Vec<u8>),
    /// A device, FIFO or socket file: written in place when all else succeeded.
    Direct { path: PathBuf, bytes: Vec<u8> },
    /// A regular file (or a new one): a temporary in the target's folder, renamed over it.
    Replace {
        target: PathBuf,
        tmp: PathBuf,
        file: Option<File>,
        permissions: Option<std::fs::Permissions>,
    },
}

struct Entry {
    /// The path as the user gave it, for messages.
    shown: PathBuf,
    dest: Dest,
    written: bool,
}

/// The outputs of one run.
pub(crate) struct Outputs {
    entries: Vec<Entry>,
    /// Files that must not be written over (the job, its programs).
    inputs: Vec<PathBuf>,
    /// Folders this run created (outermost first), removed again if it fails.
    created: Vec<PathBuf>,
    done: bool,
}

/// What an output may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Allow {
    /// A file only.
    File,
    /// A file, or `-` for standard output.
    FileOrStdout,
}

impl Outputs {
    /// No outputs yet; `inputs` are files no output may replace.
    pub(crate) fn new(inputs: &[&Path]) -> Outputs {
        Outputs {
            entries: Vec::new(),
            inputs: inputs.iter().filter_map(|p| identity(p)).collect(),
            created: Vec::new(),
            done: false,
        }
    }

    /// Whether some output goes to standard output (the human summary must not).
    pub(crate) fn uses_stdout(&self) -> bool {
        self.entries
            .iter()
            .any(|e| matches!(e.dest, Dest::Stdout(_)))
    }

    /// Check the output `path` given to `flag` and prepare its temporary.
    pub(crate) fn file(&mut self, path: &Path, flag: &str, allow: Allow) -> anyhow::Result<Slot> {
        let shown = path.to_path_buf();
        if path.as_os_str() == "-" {
            if allow != Allow::FileOrStdout {
                anyhow::bail!("{flag} cannot write to standard output (`-`): give a file");
            }
            if self.uses_stdout() {
                anyhow::bail!("{flag} -: only one output can go to standard output");
            }
            return Ok(self.push(shown, Dest::Stdout(Vec::new())));
        }
        let cannot =
            |why: String| anyhow::anyhow!("cannot write {} ({flag}): {why}", path.display());
        if path.as_os_str().is_empty() {
            return Err(cannot("an empty path".into()));
        }
        let (target, meta) = resolve(path).map_err(|e| cannot(e.to_string()))?;
        if path.file_name().is_none() || target.file_name().is_none() {
            return Err(cannot("that is a folder, not a file name".into()));
        }
        let dir = parent(&target);
        match std::fs::metadata(&dir) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(cannot(format!("{} is not a folder", dir.display()))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(cannot(format!(
                    "the folder {} does not exist",
                    dir.display()
                )))
            }
            Err(e) => return Err(cannot(format!("{}: {e}", dir.display()))),
        }
        let id = identity(&target);
        if let Some(id) = &id {
            if self.inputs.contains(id) {
                return Err(cannot("that is an input of this run".into()));
            }
            if let Some(other) = self
                .entries
                .iter()
                .find(|e| e.identity().as_ref() == Some(id))
            {
                return Err(cannot(format!(
                    "{} is written there too",
                    other.shown.display()
                )));
            }
        }
        let in_place = target.starts_with("/dev") || target.starts_with("/proc");
        let dest = match meta {
            Some(m) if m.is_dir() => return Err(cannot("it is a folder".into())),
            Some(m) if !m.is_file() || in_place => {
                if is_socket(&m) {
                    return Err(cannot("it is a socket".into()));
                }
                check_writable(&target).map_err(|e| cannot(e.to_string()))?;
                Dest::Direct {
                    path: target,
                    bytes: Vec::new(),
                }
            }
            m => {
                let (tmp, file) = temporary(&dir, &target).map_err(|e| cannot(e.to_string()))?;
                Dest::Replace {
                    target,
                    tmp,
                    file: Some(file),
                    permissions: m.map(|m| m.permissions()),
                }
            }
        };
        Ok(self.push(shown, dest))
    }

    /// Refuse outputs that would replace one of `inputs` (the programs a job read, known
    /// only once it has been read; still before any work).
    pub(crate) fn protect(&mut self, inputs: &[PathBuf]) -> anyhow::Result<()> {
        for p in inputs {
            let Some(id) = identity(p) else { continue };
            if let Some(e) = self
                .entries
                .iter()
                .find(|e| e.identity().as_ref() == Some(&id))
            {
                anyhow::bail!(
                    "cannot write {}: that is an input of this run ({})",
                    e.shown.display(),
                    p.display()
                );
            }
            self.inputs.push(id);
        }
        Ok(())
    }

    /// Check a folder of outputs (`--renders`, `--plots`): it is a folder, or it can be
    /// made (then it is made now, and removed again if the run fails).
    pub(crate) fn folder(&mut self, dir: &Path, flag: &str) -> anyhow::Result<()> {
        let cannot =
            |why: String| anyhow::anyhow!("cannot write into {} ({flag}): {why}", dir.display());
        if dir.as_os_str() == "-" {
            return Err(cannot("a folder cannot be standard output".into()));
        }
        match std::fs::metadata(dir) {
            Ok(m) if m.is_dir() => return Ok(()),
            Ok(_) => return Err(cannot("it is not a folder".into())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(cannot(e.to_string())),
        }
        // The folders to make, outermost first.
        let mut missing = Vec::new();
        let mut p = dir.to_path_buf();
        while !p.as_os_str().is_empty() && std::fs::symlink_metadata(&p).is_err() {
            missing.push(p.clone());
            match p.parent() {
                Some(q) => p = q.to_path_buf(),
                None => break,
            }
        }
        missing.reverse();
        for m in missing {
            std::fs::create_dir(&m).map_err(|e| cannot(format!("{}: {e}", m.display())))?;
            self.created.push(m);
        }
        Ok(())
    }

    fn push(&mut self, shown: PathBuf, dest: Dest) -> Slot {
        self.entries.push(Entry {
            shown,
            dest,
            written: false,
        });
        Slot(self.entries.len() - 1)
    }

    /// Write an output's bytes (to its temporary; standard output and devices are written
    /// at `commit`).
    pub(crate) fn put(&mut self, slot: Slot, bytes: &[u8]) -> anyhow::Result<()> {
        let e = &mut self.entries[slot.0];
        let shown = e.shown.display().to_string();
        match &mut e.dest {
            Dest::Stdout(b) | Dest::Direct { bytes: b, .. } => b.extend_from_slice(bytes),
            Dest::Replace { file, .. } => {
                // Written whole, synced and closed: a run of many outputs (`check
                // --report-dir`, a record a job) holds no more open files than it writes
                // at once.
                let mut f = file.take().expect("an open temporary: one put a slot");
                f.write_all(bytes)
                    .and_then(|()| f.flush())
                    .and_then(|()| f.sync_all())
                    .with_context(|| format!("cannot write {shown}"))?;
            }
        }
        e.written = true;
        Ok(())
    }

    /// Put every written output in place; returns the paths written, as the user gave them.
    /// Standard output comes last.
    pub(crate) fn commit(mut self) -> anyhow::Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for e in &mut self.entries {
            if !e.written {
                continue;
            }
            let cannot =
                |err: std::io::Error| anyhow::anyhow!("cannot write {}: {err}", e.shown.display());
            match &mut e.dest {
                Dest::Stdout(_) => continue,
                Dest::Direct { path, bytes } => {
                    // Appending: `/dev/stdout` redirected to a file keeps what is there.
                    let mut f = std::fs::OpenOptions::new()
                        .append(true)
                        .open(&*path)
                        .map_err(cannot)?;
                    match f.write_all(bytes).and_then(|()| f.flush()) {
                        Ok(()) => {}
                        Err(err) if err.kind() == std::io::ErrorKind::BrokenPipe => {}
                        Err(err) => return Err(cannot(err)),
                    }
                }
                Dest::Replace {
                    target,
                    tmp,
                    file,
                    permissions,
                } => {
                    // `put` synced and closed it.
                    debug_assert!(file.is_none());
                    if let Some(p) = permissions.take() {
                        // Keep the mode of the file it replaces; failing that is no error.
                        let _ = std::fs::set_permissions(&*tmp, p);
                    }
                    std::fs::rename(&*tmp, &*target).map_err(cannot)?;
                    // Renamed: nothing to clean up any more.
                    tmp.clear();
                }
            }
            written.push(e.shown.clone());
        }
        self.created.clear();
        self.done = true;
        for e in &mut self.entries {
            if let (true, Dest::Stdout(b)) = (e.written, &e.dest) {
                term::out_bytes(b).context("cannot write to standard output")?;
            }
        }
        Ok(written)
    }
}

impl Entry {
    fn identity(&self) -> Option<PathBuf> {
        match &self.dest {
            // `/dev/null` may take several outputs.
            Dest::Stdout(_) | Dest::Direct { .. } => None,
            Dest::Replace { target, .. } => identity(target),
        }
    }
}

impl Drop for Outputs {
    /// A run that did not commit removes its temporaries and the folders it made.
    fn drop(&mut self) {
        for e in &mut self.entries {
            if let Dest::Replace { tmp, file, .. } = &mut e.dest {
                drop(file.take());
                if !tmp.as_os_str().is_empty() {
                    let _ = std::fs::remove_file(&*tmp);
                }
            }
        }
        if !self.done {
            for d in self.created.iter().rev() {
                let _ = std::fs::remove_dir(d);
            }
        }
    }
}

/// The folder a path is in (`.` for a bare name).
fn parent(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Follow symbolic links to the final target (which may not exist yet); its metadata when
/// it exists. A regular file resolves to its canonical path; anything else that exists
/// (a device, a FIFO, `/dev/stdout` whose link goes through `/proc/self/fd` to a pipe)
/// stays the path given, to be opened as it is.
fn resolve(path: &Path) -> std::io::Result<(PathBuf, Option<std::fs::Metadata>)> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && !path.starts_with("/dev") && !path.starts_with("/proc") => {
            return Ok((std::fs::canonicalize(path)?, Some(m)));
        }
        Ok(m) if m.is_file() => {
            // `/dev/stdout` redirected to a file: write through the descriptor, do not
            // rename over what the shell opened.
            return Ok((path.to_path_buf(), Some(m)));
        }
        Ok(m) => return Ok((path.to_path_buf(), Some(m))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(e),
    }
    // A new file, or a link to one that does not exist yet: follow the links by hand.
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let t = std::fs::read_link(&p)?;
                p = if t.is_absolute() {
                    t
                } else {
                    parent(&p).join(t)
                };
            }
            Ok(m) => return Ok((p, Some(m))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((p, None)),
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// A path's identity for comparing outputs with each other and with inputs: the canonical
/// folder and the file name (the file itself may not exist yet).
fn identity(p: &Path) -> Option<PathBuf> {
    let (t, _) = resolve(p).ok()?;
    let dir = std::fs::canonicalize(parent(&t)).ok()?;
    Some(dir.join(t.file_name()?))
}

/// A new temporary file in `dir` for `target`: created exclusively, so it proves the folder
/// takes new files.
fn temporary(dir: &Path, target: &Path) -> std::io::Result<(PathBuf, File)> {
    static N: AtomicUsize = AtomicUsize::new(0);
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    loop {
        let tmp = dir.join(format!(
            ".{name}.vpcut-{}-{}.tmp",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(unix)]
fn is_socket(m: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt as _;
    m.file_type().is_socket()
}

#[cfg(not(unix))]
fn is_socket(_: &std::fs::Metadata) -> bool {
    false
}

/// Whether a device or FIFO can be opened for writing (without opening it: a FIFO would
/// wait for its reader).
#[cfg(target_os = "linux")]
fn check_writable(p: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt as _;
    let c = std::ffi::CString::new(p.as_os_str().as_bytes())
        .map_err(|_| std::io::Error::other("a path with a NUL byte"))?;
    // SAFETY: `c` is a valid NUL-terminated string that outlives the call.
    if unsafe { libc::access(c.as_ptr(), libc::W_OK) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(not(target_os = "linux"))]
fn check_writable(p: &Path) -> std::io::Result<()> {
    if std::fs::metadata(p)?.permissions().readonly() {
        Err(std::io::Error::from(std::io::ErrorKind::PermissionDenied))
    } else {
        Ok(())
    }
}
