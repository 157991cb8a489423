//! Progress on stderr for long work, shown only when stderr is a terminal and `--quiet` is off.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};

/// A stage-by-stage spinner (hidden when not on a terminal or when quiet).
pub(crate) struct Progress {
    bar: ProgressBar,
    quiet: bool,
}

impl Progress {
    /// A spinner that is visible only if `quiet` is off and stderr is a terminal.
    pub(crate) fn new(quiet: bool) -> Self {
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let b = ProgressBar::new_spinner();
            b.set_style(
                ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                    .expect("valid template"),
            );
            b.enable_steady_tick(std::time::Duration::from_millis(120));
            b
        };
        Progress { bar, quiet }
    }

    /// A one-line note for the user on stderr (what automatic mode did, for example), unless
    /// quiet; printed above the spinner.
    pub(crate) fn note(&self, text: &str) {
        if !self.quiet {
            self.bar.suspend(|| eprintln!("note: {text}"));
        }
    }

    /// Names the stage now running.
    pub(crate) fn stage(&self, name: &str) {
        self.bar.set_message(name.to_string());
    }

    /// Removes the spinner.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
