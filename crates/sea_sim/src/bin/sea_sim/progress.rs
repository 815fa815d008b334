//! Progress on stderr for long runs: a bar on a terminal, a line every few seconds otherwise.

use crate::common::say;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Progress of a run on stderr: a bar on a terminal, periodic lines otherwise, or nothing.
pub(crate) enum Progress {
    Bar(indicatif::ProgressBar),
    Lines { last: Option<Instant> },
    Quiet,
}

/// Wall time between two plain progress lines.
pub(crate) const LINE_INTERVAL: Duration = Duration::from_secs(2);

impl Progress {
    /// The right kind for this stderr; `duration_s` is the simulated time to reach.
    pub(crate) fn new(quiet: bool, duration_s: f64) -> Self {
        if quiet {
            return Progress::Quiet;
        }
        if !std::io::stderr().is_terminal() {
            return Progress::Lines { last: None };
        }
        let bar = indicatif::ProgressBar::with_draw_target(
            Some((duration_s * 1000.0).max(1.0) as u64),
            indicatif::ProgressDrawTarget::stderr(),
        );
        let style = indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {msg} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
        Progress::Bar(bar.with_style(style))
    }

    /// Simulated time `t_s` of `total_s` reached.
    pub(crate) fn update(&mut self, t_s: f64, total_s: f64) {
        match self {
            Progress::Bar(bar) => {
                bar.set_position((t_s * 1000.0) as u64);
                bar.set_message(format!("t = {t_s:.2} / {total_s:.2} s"));
            }
            Progress::Lines { last } => {
                if last.is_none_or(|l| l.elapsed() >= LINE_INTERVAL) {
                    *last = Some(Instant::now());
                    say(format_args!("sea-sim: t = {t_s:6.2} / {total_s:.2} s"));
                }
            }
            Progress::Quiet => {}
        }
    }

    /// Removes the bar.
    pub(crate) fn finish(&self) {
        if let Progress::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}
