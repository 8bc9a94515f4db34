//! Long calls: the Rust work runs on a worker thread with the GIL released, while the calling
//! (main) thread wakes every [`POLL`] to report progress to a Python callback and to run
//! Python's signal handlers (`Python::check_signals`). A KeyboardInterrupt (or an exception from
//! the callback) sets the cancel flag, which the Rust loop polls; the worker is joined before
//! the exception is raised, so nothing runs on after the call returns. No signal handler is
//! installed: Python's own SIGINT handler sets the flag that `check_signals` reads.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the calling thread wakes to report progress and check for signals.
const POLL: Duration = Duration::from_millis(50);

/// What the worker and the calling thread share.
pub struct Control {
    cancelled: AtomicBool,
    /// Progress as f64 bits (done, total): simulated seconds of a run, points of a sweep.
    done: AtomicU64,
    total: AtomicU64,
    finished: Mutex<bool>,
    wake: Condvar,
}

impl Control {
    fn new() -> Self {
        Control {
            cancelled: AtomicBool::new(false),
            done: AtomicU64::new(0f64.to_bits()),
            total: AtomicU64::new(f64::NAN.to_bits()),
            finished: Mutex::new(false),
            wake: Condvar::new(),
        }
    }

    /// The cancel flag itself (for the library's sweeps, which poll it).
    pub fn flag(&self) -> &AtomicBool {
        &self.cancelled
    }

    pub fn set_total(&self, total: f64) {
        self.total.store(total.to_bits(), Ordering::Relaxed);
    }

    pub fn set_done(&self, done: f64) {
        self.done.store(done.to_bits(), Ordering::Relaxed);
    }

    fn progress(&self) -> (f64, f64) {
        (f64::from_bits(self.done.load(Ordering::Relaxed)), f64::from_bits(self.total.load(Ordering::Relaxed)))
    }

    fn finish(&self) {
        *self.finished.lock().unwrap_or_else(|p| p.into_inner()) = true;
        self.wake.notify_all();
    }

    /// Waits up to [`POLL`] for the worker to finish; whether it has.
    fn wait(&self) -> bool {
        let guard = self.finished.lock().unwrap_or_else(|p| p.into_inner());
        let (guard, _) = self.wake.wait_timeout_while(guard, POLL, |f| !*f).unwrap_or_else(|p| p.into_inner());
        *guard
    }
}

/// Runs `work` on a worker thread, the GIL released; `progress(done, total)` (a Python
/// callable, optional) is called from this thread while it runs and once at the end.
/// A KeyboardInterrupt, or an exception raised by `progress`, cancels the work (through
/// [`Control::flag`], which the library polls) and is raised once the worker has stopped.
pub fn run<T, F>(py: Python<'_>, progress: Option<&Bound<'_, PyAny>>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&Control) -> T + Send,
{
    let control = Control::new();
    std::thread::scope(|scope| {
        let ctl = &control;
        let handle = scope.spawn(move || {
            let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(ctl)));
            ctl.finish();
            out
        });
        let mut pending: Option<PyErr> = None;
        loop {
            let finished = py.detach(|| control.wait());
            if pending.is_none() {
                let polled = report(progress, &control).and_then(|()| py.check_signals());
                if let Err(e) = polled {
                    control.cancelled.store(true, Ordering::Relaxed);
                    pending = Some(e);
                }
            }
            if finished {
                break;
            }
        }
        let out = py.detach(|| handle.join());
        if let Some(e) = pending {
            return Err(e);
        }
        match out {
            Ok(Ok(v)) => Ok(v),
            Ok(Err(panic)) | Err(panic) => Err(pyo3::exceptions::PyRuntimeError::new_err(format!(
                "internal error in magbubble: {}",
                panic_message(&panic)
            ))),
        }
    })
}

fn report(progress: Option<&Bound<'_, PyAny>>, control: &Control) -> PyResult<()> {
    if let Some(cb) = progress {
        let (done, total) = control.progress();
        cb.call1((done, total))?;
    }
    Ok(())
}

fn panic_message(p: &Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| p.downcast_ref::<String>().cloned()).unwrap_or_else(|| "a panic".into())
}
