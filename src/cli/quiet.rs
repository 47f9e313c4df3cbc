//! The GPU stack's own chatter kept off a successful run's standard error: the Vulkan
//! loader and its drivers (libwayland through Mesa's WSI) print `error: XDG_RUNTIME_DIR is
//! invalid or not set in the environment.` while the renderer starts on a machine without a
//! desktop session, though nothing failed. [`gpu_quiet`] runs the start with file
//! descriptor 2 pointed at a temporary file and passes on every other line it caught.

use std::io::{Read as _, Seek as _, Write as _};

/// The lines the GPU stack prints that say nothing about the run.
const NOISE: [&str; 1] = ["XDG_RUNTIME_DIR is invalid or not set in the environment"];

/// Whether a caught line is noise.
fn noise(line: &str) -> bool {
    NOISE.iter().any(|n| line.contains(n))
}

/// An anonymous scratch file: created in the temporary directory and unlinked at once.
#[cfg(unix)]
fn scratch() -> Option<std::fs::File> {
    let path = std::env::temp_dir().join(format!(
        ".vpcut-stderr-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create_new(true)
        .open(&path)
        .ok()?;
    let _ = std::fs::remove_file(&path);
    Some(file)
}

/// Run `f` (the renderer's start) with standard error caught; the caught lines but the
/// noise go to standard error afterwards. Where the catch cannot be set up, `f` runs as is.
#[cfg(unix)]
pub(crate) fn gpu_quiet<T>(f: impl FnOnce() -> T) -> T {
    use std::os::fd::AsRawFd as _;
    let _ = std::io::stderr().flush();
    let Some(mut caught) = scratch() else {
        return f();
    };
    // SAFETY: dup/dup2/close on descriptor 2 and on descriptors this function owns.
    let saved = unsafe { libc::dup(2) };
    if saved < 0 {
        return f();
    }
    if unsafe { libc::dup2(caught.as_raw_fd(), 2) } < 0 {
        unsafe { libc::close(saved) };
        return f();
    }
    let out = f();
    let _ = std::io::stderr().flush();
    unsafe {
        libc::dup2(saved, 2);
        libc::close(saved);
    }
    let mut text = String::new();
    if caught.rewind().is_ok() && caught.read_to_string(&mut text).is_ok() {
        let kept: String = text.split_inclusive('\n').filter(|l| !noise(l)).collect();
        if !kept.is_empty() {
            let _ = std::io::stderr().write_all(kept.as_bytes());
        }
    }
    out
}

/// Elsewhere the start runs as is.
#[cfg(not(unix))]
pub(crate) fn gpu_quiet<T>(f: impl FnOnce() -> T) -> T {
    f()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_session_message_is_noise() {
        assert!(noise(
            "error: XDG_RUNTIME_DIR is invalid or not set in the environment.\n"
        ));
        assert!(!noise("error: no adapter\n"));
    }
}
