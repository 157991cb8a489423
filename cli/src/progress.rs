//! Progress on stderr for long work, shown only when stderr is a terminal and `--quiet` is off:
//! a spinner naming the stage, and while frames are rendered a bar with frames done / total and
//! an estimate of the time left. `crmorph batch` counts pairs with the same bar, and gives each
//! pair a silent one that keeps its notes for the report.

use std::io::IsTerminal;
use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressStyle};

/// A stage-by-stage spinner that becomes a frame counter while frames are rendered (hidden when
/// not on a terminal or when quiet).
pub(crate) struct Progress {
    bar: ProgressBar,
    quiet: bool,
    /// Notes kept instead of printed (see [`Progress::capturing`]).
    captured: Option<Mutex<Vec<String>>>,
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
        Progress {
            bar,
            quiet,
            captured: None,
        }
    }

    /// A progress that shows nothing and keeps its notes for [`Progress::take_notes`]: one
    /// pair's of `crmorph batch`, whose notes go into the report.
    pub(crate) fn capturing() -> Self {
        Progress {
            bar: ProgressBar::hidden(),
            quiet: true,
            captured: Some(Mutex::new(Vec::new())),
        }
    }

    /// The notes kept so far (of a [`Progress::capturing`]), one line each, oldest first.
    pub(crate) fn take_notes(&self) -> Vec<String> {
        match &self.captured {
            Some(m) => std::mem::take(&mut *m.lock().unwrap_or_else(|e| e.into_inner())),
            None => Vec::new(),
        }
    }

    /// A one-line note for the user on stderr (what automatic mode did, for example), unless
    /// quiet; printed above the spinner. A capturing progress keeps it instead.
    pub(crate) fn note(&self, text: &str) {
        if let Some(m) = &self.captured {
            let text = crmorph::error::printable_line(text);
            m.lock().unwrap_or_else(|e| e.into_inner()).push(text);
            return;
        }
        if !self.quiet {
            let text = crmorph::error::printable_line(text);
            self.bar.suspend(|| eprintln!("note: {text}"));
        }
    }

    /// Names the stage now running.
    pub(crate) fn stage(&self, name: &str) {
        self.bar.set_message(name.to_string());
    }

    /// Switches to counting `total` frames: a bar with frames done / total, the elapsed time and
    /// the estimated time left, under the current stage's name. Frames are counted by the
    /// closure [`Progress::frame_counter`] returns.
    pub(crate) fn frames(&self, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(0);
        self.bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {msg} [{bar:30}] {pos}/{len} frames ({elapsed}, ETA {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        self.bar.reset_eta();
    }

    /// A closure that counts one finished frame each call, from any thread (for
    /// `Morph::on_frame`), and names the stage `then` once `at` frames are done (the encoding
    /// that follows the frames of a GIF, for example).
    pub(crate) fn frame_counter(&self, at: u64, then: &str) -> impl Fn() + Send + Sync + 'static {
        let (bar, then) = (self.bar.clone(), then.to_string());
        move || {
            bar.inc(1);
            if bar.position() == at {
                bar.set_message(then.clone());
            }
        }
    }

    /// Switches to counting `total` pairs of a batch, like [`Progress::frames`]; each call of
    /// [`Progress::frame_counter`]'s closure counts one pair.
    pub(crate) fn pairs(&self, total: u64) {
        self.bar.set_length(total);
        self.bar.set_position(0);
        self.bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {msg} [{bar:30}] {pos}/{len} pairs ({elapsed}, ETA {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        self.bar.reset_eta();
    }

    /// Back to the spinner, for the stages after the frames (encoding, writing).
    pub(crate) fn frames_done(&self) {
        self.bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} ({elapsed})").expect("valid template"),
        );
    }

    /// Removes the spinner.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
