//! The terminal: standard output and error that a closed pipe cannot crash, colour that
//! honours `NO_COLOR` and appears only on a terminal, and progress spinners on standard
//! error for the stages that take a while.
//!
//! Nothing in the binary calls `print!`/`println!`/`eprintln!` directly: those panic with
//! "failed printing to stdout: Broken pipe" when the reader goes away
//! (`vpcut toolpath ... | head -1`). Here a closed standard output is remembered and every
//! later write is dropped, so the command finishes quietly with its own exit code.

use std::io::{IsTerminal as _, Write as _};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Write text to standard output. A closed pipe ends all further output quietly; other
/// errors (a full disk behind a redirection) are reported once on standard error.
pub(crate) fn out(s: &str) {
    let _ = out_bytes(s.as_bytes());
}

/// Write bytes to standard output (an output file named `-`). `Ok` when the reader went
/// away: that is the reader's choice, not a failure.
pub(crate) fn out_bytes(b: &[u8]) -> std::io::Result<()> {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    let mut o = std::io::stdout().lock();
    match o.write_all(b).and_then(|()| o.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        Err(e) => {
            STDOUT_CLOSED.store(true, Ordering::Relaxed);
            Err(e)
        }
    }
}

/// Write text to standard error; errors are ignored (there is nowhere left to say them).
pub(crate) fn err(s: &str) {
    let mut e = std::io::stderr().lock();
    let _ = e.write_all(s.as_bytes());
    let _ = e.flush();
}

/// Where text goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stream {
    /// Standard output.
    Stdout,
    /// Standard error.
    Stderr,
}

impl Stream {
    /// Write `s` there.
    pub(crate) fn write(self, s: &str) {
        match self {
            Stream::Stdout => out(s),
            Stream::Stderr => err(s),
        }
    }

    /// Whether colour is wanted there: a terminal, and `NO_COLOR` unset or empty
    /// (<https://no-color.org>).
    pub(crate) fn colour(self) -> bool {
        let tty = match self {
            Stream::Stdout => std::io::stdout().is_terminal(),
            Stream::Stderr => std::io::stderr().is_terminal(),
        };
        tty && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
    }
}

/// Paint `text` with `style` when `on`.
pub(crate) fn paint(on: bool, style: anstyle::Style, text: &str) -> String {
    if on {
        format!("{style}{text}{style:#}")
    } else {
        text.to_string()
    }
}

/// Red and bold: errors, fail verdicts, cells out of tolerance.
pub(crate) const RED: anstyle::Style = anstyle::AnsiColor::Red.on_default().bold();
/// Green and bold: pass verdicts.
pub(crate) const GREEN: anstyle::Style = anstyle::AnsiColor::Green.on_default().bold();
/// Yellow and bold: warnings.
pub(crate) const YELLOW: anstyle::Style = anstyle::AnsiColor::Yellow.on_default().bold();

/// `error: message` on standard error, `error:` in red on a terminal.
pub(crate) fn error(message: &str) {
    let on = Stream::Stderr.colour();
    err(&format!("{} {message}\n", paint(on, RED, "error:")));
}

/// Colour the `error:`/`warning:` words that start the diagnostics of jobs and programs
/// (`error: message`, then `--> file:line:col` and the source line) for standard error.
pub(crate) fn diagnostics(text: &str) -> String {
    if !Stream::Stderr.colour() {
        return text.to_string();
    }
    text.lines()
        .map(|l| {
            if let Some(rest) = l.strip_prefix("error:") {
                format!("{}{rest}", paint(true, RED, "error:"))
            } else if let Some(rest) = l.strip_prefix("warning:") {
                format!("{}{rest}", paint(true, YELLOW, "warning:"))
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + if text.ends_with('\n') { "\n" } else { "" }
}

/// Progress on standard error for the stages of a run: a spinner with the stage's name and
/// its elapsed time, only when standard error is a terminal and `-q` was not given. The
/// library does no IO; the stages are timed here around its calls.
pub(crate) struct Progress {
    on: bool,
}

impl Progress {
    /// Progress shown unless `quiet` or standard error is not a terminal.
    pub(crate) fn new(quiet: bool) -> Progress {
        Progress {
            on: !quiet && std::io::stderr().is_terminal(),
        }
    }

    /// Run `f` as the stage `name`: a spinner with the elapsed time while it runs, drawn
    /// only once the stage has taken half a second (quick stages leave no trace), cleared
    /// when it ends.
    pub(crate) fn stage<T>(&self, name: &str, f: impl FnOnce() -> T) -> T {
        if !self.on {
            return f();
        }
        let bar = indicatif::ProgressBar::hidden();
        bar.set_style(
            indicatif::ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                .expect("a valid template"),
        );
        bar.set_message(name.to_string());
        bar.enable_steady_tick(Duration::from_millis(120));
        let done = std::sync::Arc::new(AtomicBool::new(false));
        let show = {
            let (bar, done) = (bar.clone(), done.clone());
            std::thread::spawn(move || {
                let start = Instant::now();
                let delay = Duration::from_millis(500);
                while !done.load(Ordering::Acquire) {
                    let spent = start.elapsed();
                    if spent >= delay {
                        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                        return;
                    }
                    std::thread::park_timeout(delay - spent);
                }
            })
        };
        let out = f();
        done.store(true, Ordering::Release);
        show.thread().unpark();
        let _ = show.join();
        bar.finish_and_clear();
        out
    }
}

/// The report's summary for `stream`: coloured there when it is a terminal.
pub(crate) fn summary(report: &vpcut::Report, stream: Stream, wall_s: Option<f64>) -> String {
    let on = stream.colour();
    let paint = |tone: vpcut::Tone, text: &str| {
        let style = match tone {
            vpcut::Tone::Pass => GREEN,
            vpcut::Tone::Warning => YELLOW,
            _ => RED,
        };
        paint(true, style, text)
    };
    report.summary_with(&vpcut::SummaryStyle {
        paint: if on { Some(&paint) } else { None },
        wall_s,
    })
}
