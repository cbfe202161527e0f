//! Progress output: an indicatif bar and stage lines on stderr, or nothing at all.

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// The progress of a pipeline run.
pub struct Progress {
    bar: ProgressBar,
    on: bool,
}

impl Progress {
    /// A bar of `total` steps when `on`, else a silent one.
    pub fn new(on: bool, total: u64) -> Self {
        let bar = if on {
            let b = ProgressBar::new(total);
            b.set_style(
                ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {wide_msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            b.enable_steady_tick(Duration::from_millis(250));
            b
        } else {
            ProgressBar::hidden()
        };
        Progress { bar, on }
    }

    /// Prints a stage line (above the bar).
    pub fn say(&self, msg: impl AsRef<str>) {
        if self.on {
            self.bar.suspend(|| eprintln!("{}", msg.as_ref()));
        }
    }

    /// Sets what is being done.
    pub fn doing(&self, msg: impl Into<String>) {
        self.bar.set_message(msg.into());
    }

    /// One step done.
    pub fn done(&self) {
        self.bar.inc(1);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
