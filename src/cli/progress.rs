//! Progress bars on stderr for long runs (the CLI only; the library never prints).
//!
//! A bar is drawn only when stderr is a terminal and the job is large enough to take more
//! than a moment; otherwise every call here does nothing, so pipes, files and CI logs stay
//! clean.

use std::io::{IsTerminal, Read};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Units done and in all of the job counted last ([`Progress::new`]), and their name, for
/// the message of an interrupted run ([`interrupted_message`]); shown or not.
static DONE: AtomicU64 = AtomicU64::new(0);
static TOTAL: AtomicU64 = AtomicU64::new(0);
static UNIT: Mutex<String> = Mutex::new(String::new());

/// What an interrupted run says (from a signal handler: nothing here blocks): how far the
/// job counted last had got, e.g. `"interrupted after 41200 of 100000 tables"`, or just
/// `"interrupted"` before any job was counted.
pub fn interrupted_message() -> String {
    let total = TOTAL.load(Ordering::SeqCst);
    let unit = UNIT.try_lock().map(|u| u.clone()).unwrap_or_default();
    if total == 0 || unit.is_empty() {
        return "interrupted".to_owned();
    }
    let done = DONE.load(Ordering::SeqCst).min(total);
    format!("interrupted after {done} of {total} {unit}")
}

/// A progress bar that may be hidden; it counts for [`interrupted_message`] either way.
pub struct Progress(ProgressBar);

impl Progress {
    /// A bar counting `total` units of `unit` (e.g. `"tables"`), labelled `what`; hidden
    /// unless stderr is a terminal and the job is `long` (the caller's judgement).
    pub fn new(what: &str, total: u64, unit: &str, long: bool) -> Progress {
        DONE.store(0, Ordering::SeqCst);
        TOTAL.store(total, Ordering::SeqCst);
        if let Ok(mut u) = UNIT.lock() {
            unit.clone_into(&mut u);
        }
        if !long || !std::io::stderr().is_terminal() {
            return Progress(ProgressBar::hidden());
        }
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        let template = format!(
            "{{msg}} [{{bar:32}}] {{human_pos}}/{{human_len}} {unit} ({{elapsed}}, ~{{eta}} left)"
        );
        bar.set_style(
            ProgressStyle::with_template(&template)
                .expect("the template is valid")
                .progress_chars("=> "),
        );
        bar.set_message(what.to_owned());
        Progress(bar)
    }

    /// A bar for reading `total` bytes (shown from 16 MiB up).
    pub fn bytes(what: &str, total: u64) -> Progress {
        if total < 16 << 20 || !std::io::stderr().is_terminal() {
            return Progress(ProgressBar::hidden());
        }
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:32}] {binary_bytes}/{binary_total_bytes} ({elapsed}, ~{eta} left)",
            )
            .expect("the template is valid")
            .progress_chars("=> "),
        );
        bar.set_message(what.to_owned());
        Progress(bar)
    }

    /// Counts `n` more units done.
    pub fn inc(&self, n: u64) {
        DONE.fetch_add(n, Ordering::SeqCst);
        self.0.inc(n);
    }

    /// Sets the units done.
    pub fn set(&self, done: u64) {
        DONE.store(done, Ordering::SeqCst);
        self.0.set_position(done);
    }

    /// A reader that advances the bar by the bytes read through it.
    pub fn wrap_read<R: Read>(&self, reader: R) -> impl Read {
        self.0.wrap_read(reader)
    }

    /// Removes the bar from the terminal.
    pub fn done(self) {
        self.0.finish_and_clear();
    }
}
