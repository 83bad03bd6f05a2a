//! Progress bars on stderr for long runs (the CLI only; the library never prints).
//!
//! A bar is drawn only when stderr is a terminal and the job is large enough to take more
//! than a moment; otherwise every call here does nothing, so pipes, files and CI logs stay
//! clean.

use std::io::{IsTerminal, Read};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar that may be hidden.
pub struct Progress(ProgressBar);

impl Progress {
    /// A bar counting `total` units of `unit` (e.g. `"tables"`), labelled `what`; hidden
    /// unless stderr is a terminal and the job is `long` (the caller's judgement).
    pub fn new(what: &str, total: u64, unit: &str, long: bool) -> Progress {
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
        self.0.inc(n);
    }

    /// Sets the units done.
    pub fn set(&self, done: u64) {
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
