//! A progress bar over simulated time, shown only when stderr is a terminal.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// Progress in simulated time; a no-op in a pipe or a file.
#[derive(Debug)]
pub struct Progress {
    bar: Option<ProgressBar>,
    end: f64,
    last: u64,
}

/// Resolution of the bar (ticks over the whole run).
const TICKS: u64 = 1000;

impl Progress {
    /// A bar for a run ending at `end` (same unit as [`Progress::set`]); hidden unless stderr is
    /// a terminal.
    pub fn new(end: f64, message: &str) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(TICKS);
            let style = ProgressStyle::with_template(
                "{msg} [{bar:40}] {percent:>3}% {elapsed} (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
            bar.set_style(style);
            bar.set_message(message.to_string());
            bar
        });
        Progress { bar, end, last: 0 }
    }

    /// Whether a bar is drawn.
    pub fn is_visible(&self) -> bool {
        self.bar.is_some()
    }

    /// Reports progress `t` out of `end`.
    pub fn set(&mut self, t: f64) {
        if let Some(bar) = &self.bar {
            let tick = ((t / self.end).clamp(0.0, 1.0) * TICKS as f64) as u64;
            if tick != self.last {
                self.last = tick;
                bar.set_position(tick);
            }
        }
    }

    /// Removes the bar.
    pub fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}

/// A fraction-done bar over a known number of runs (`accuracy`: its ladders' simulations),
/// shown only when stderr is a terminal, cleared when dropped.
#[derive(Debug)]
pub struct Counter(Option<ProgressBar>);

impl Counter {
    pub fn new(total: usize, message: &str) -> Self {
        Counter(std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(total as u64);
            let style = ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} runs {percent:>3}% {elapsed} (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
            bar.set_style(style);
            bar.set_message(message.to_string());
            bar
        }))
    }

    /// `done` of `total` runs finished (`total` may grow).
    pub fn set(&self, done: usize, total: usize) {
        if let Some(bar) = &self.0 {
            if bar.length() != Some(total as u64) {
                bar.set_length(total as u64);
            }
            bar.set_position(done as u64);
        }
    }
}

impl Drop for Counter {
    fn drop(&mut self) {
        if let Some(bar) = self.0.take() {
            bar.finish_and_clear();
        }
    }
}

/// An elapsed-time spinner for work whose length is not known in advance (`accuracy --critical`): shown
/// only when stderr is a terminal, cleared when dropped.
#[derive(Debug)]
pub struct Spinner(Option<ProgressBar>);

impl Spinner {
    pub fn new(message: &str) -> Self {
        Spinner(std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new_spinner();
            if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
                bar.set_style(style);
            }
            bar.set_message(message.to_string());
            bar.enable_steady_tick(std::time::Duration::from_millis(200));
            bar
        }))
    }
}

impl Spinner {
    /// Runs `f` (which prints to stdout) with the spinner line cleared, so the two do not mix.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.0 {
            Some(bar) => bar.suspend(f),
            None => f(),
        }
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        if let Some(bar) = self.0.take() {
            bar.finish_and_clear();
        }
    }
}
