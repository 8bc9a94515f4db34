//! What every long call shares: a [`Monitor`] (progress reports and a cancel flag).

use std::sync::atomic::{AtomicBool, Ordering};

/// Progress and cancellation of a long call. `Monitor::default()` reports nothing and is
/// never cancelled. The CLI sets [`Monitor::bar`] (indicatif bars on a terminal) and a cancel
/// flag raised by SIGINT; the Python binding sets [`Monitor::report`] (read by the thread that
/// drives tqdm) and a flag raised on KeyboardInterrupt.
#[derive(Clone, Copy, Default)]
pub struct Monitor<'a> {
    /// `report(done, total)`: simulated seconds of a run, points of a sweep or a stability
    /// diagram. `total` may be NaN until known. Called from worker threads.
    pub report: Option<&'a (dyn Fn(f64, f64) + Sync)>,
    /// Polled by the work: once set, no new piece starts and the pieces in flight are abandoned.
    pub cancel: Option<&'a AtomicBool>,
    /// Draw the command line's progress bar on stderr (only when stderr is a terminal).
    pub bar: bool,
}

impl<'a> Monitor<'a> {
    /// Reports `done` of `total`.
    pub fn progress(&self, done: f64, total: f64) {
        if let Some(r) = self.report {
            r(done, total);
        }
    }

    /// Whether the caller asked the work to stop.
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// A progress callback counting pieces (sweep points) as `(done, total)` integers.
    pub fn counter(&self) -> impl Fn(usize, usize) + Sync + 'a {
        let report = self.report;
        move |done: usize, total: usize| {
            if let Some(r) = report {
                r(done as f64, total as f64);
            }
        }
    }
}

/// The error a call returns when its [`Monitor`] cancelled it before it finished (the
/// callers that resume, sweeps and stability diagrams, return their partial result instead).
#[derive(Debug, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;
