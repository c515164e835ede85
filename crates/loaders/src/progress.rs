//! A progress bar for long loads and sweeps (the tool's `stress` and `bench`) that never
//! pollutes logs.
//!
//! The bar is drawn on stderr, and only when stderr is a terminal: under CI, with stderr
//! redirected to a file or piped, it is hidden and costs nothing. Stdout is never touched, so
//! tables and CSV printed there stay clean either way.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A counter from 0 to a known total with a one-line bar on stderr when it is a terminal.
///
/// `Progress` is `Send + Sync` and its methods take `&self`, so one bar can be shared by worker
/// threads. Dropping it without [`finish`](Progress::finish) leaves the last drawn state.
///
/// ```
/// use ellipsoid_splat_loaders::Progress;
/// let progress = Progress::new(3, "stress");
/// for case in ["near", "far", "flat"] {
///     // ... run the case ...
///     progress.inc(case);
/// }
/// progress.finish();
/// ```
#[derive(Debug, Clone)]
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// A bar for `total` steps labelled `what` (e.g. `"stress"`): drawn on stderr if that is a
    /// terminal, hidden otherwise.
    pub fn new(total: u64, what: &str) -> Self {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        Self::with_target(total, what, target)
    }

    /// A bar that is never drawn, whatever stderr is (for tests and `--quiet`).
    pub fn hidden(total: u64, what: &str) -> Self {
        Self::with_target(total, what, ProgressDrawTarget::hidden())
    }

    fn with_target(total: u64, what: &str, target: ProgressDrawTarget) -> Self {
        let bar = ProgressBar::with_draw_target(Some(total), target);
        // The template is a constant, so it always parses; fall back to indicatif's default
        // rather than panic should that ever change.
        if let Ok(style) = ProgressStyle::with_template(
            "{prefix:.bold} [{bar:32.cyan/blue}] {pos}/{len} {elapsed_precise} (eta {eta}) {wide_msg}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(what.to_string());
        // Redraw on a timer too, so elapsed time and ETA move during a long step.
        if !bar.is_hidden() {
            bar.enable_steady_tick(Duration::from_millis(250));
        }
        Self { bar }
    }

    /// Counts one finished step and shows `message` (e.g. the case just done) beside the bar.
    pub fn inc(&self, message: &str) {
        self.bar.set_message(message.to_string());
        self.bar.inc(1);
    }

    /// Steps counted so far.
    pub fn position(&self) -> u64 {
        self.bar.position()
    }

    /// Whether the bar is being drawn (stderr is a terminal and this is not [`hidden`]).
    ///
    /// [`hidden`]: Progress::hidden
    pub fn is_visible(&self) -> bool {
        !self.bar.is_hidden()
    }

    /// Stops the bar and leaves its final state (with a `done` message) on the terminal.
    pub fn finish(&self) {
        self.bar.finish_with_message("done");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_while_hidden() {
        let p = Progress::hidden(4, "test");
        assert!(!p.is_visible());
        for i in 0..4 {
            p.inc(&format!("case {i}"));
        }
        assert_eq!(p.position(), 4);
        p.finish();
        // Shared between threads.
        let p = Progress::hidden(8, "threads");
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| (0..4).for_each(|_| p.inc("x")));
            }
        });
        assert_eq!(p.position(), 8);
        p.finish();
    }
}
