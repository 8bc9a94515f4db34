//! `accuracy`: work–precision of every integrator on a scene (issue 6; method in
//! [`crate::analysis::accuracy`]), or with a drive frequency the error of the critical ε_p
//! against its cost (issue 13 part 5; [`crate::analysis::critical_accuracy`]).

use super::common::Monitor;
use super::scene::Scene;
pub use crate::analysis::accuracy::{AccuracyOptions, AccuracyReport, MIN_WORK_RATIO};
use crate::analysis::accuracy::{accuracy_study_cancellable, planned_runs, AccuracyError};
pub use crate::analysis::critical_accuracy::{CriticalAccuracyOptions, CriticalAccuracyReport, CriticalRung};
use anyhow::Context;

/// The time-series study: reference, one ladder per method, the mode and grid ladders.
/// Progress counts the study's simulations (the command line's bar on a terminal); the
/// monitor's cancel flag stops it before the next simulation ([`super::common::Cancelled`]).
pub fn study(scene: &Scene, opts: &AccuracyOptions, monitor: &Monitor) -> anyhow::Result<AccuracyReport> {
    let sc = scene.scene();
    let bar = monitor.bar.then(|| crate::output::Counter::new(planned_runs(sc, opts), "accuracy study"));
    let progress = |done: usize, total: usize| {
        if let Some(b) = &bar {
            b.set(done, total);
        }
        monitor.progress(done as f64, total as f64);
    };
    let report = match accuracy_study_cancellable(sc, opts, &progress, monitor.cancel) {
        Err(AccuracyError::Cancelled) => return Err(super::common::Cancelled.into()),
        r => r.context("accuracy study")?,
    };
    drop(bar);
    Ok(report)
}

/// The time-series study's options: [`AccuracyOptions::quick`] or [`AccuracyOptions::full`],
/// with `repeats` (≥ 1) and `duration` (> 0 s) when given (the CLI's --quick, --repeats,
/// --duration; Python's `quick`, `repeats`, `duration`).
pub fn options(quick: bool, repeats: Option<usize>, duration: Option<f64>) -> anyhow::Result<AccuracyOptions> {
    let mut opts = if quick { AccuracyOptions::quick() } else { AccuracyOptions::full() };
    if let Some(r) = repeats {
        anyhow::ensure!(r > 0, "--repeats = 0: need at least one run per setting");
        opts.repeats = r;
    }
    if let Some(d) = duration {
        anyhow::ensure!(d.is_finite() && d > 0.0, "--duration = {d}: must be a positive time in seconds");
        opts.duration = Some(d);
    }
    Ok(opts)
}

/// The critical-ε_p study's options at `frequency_hz` (quick or full); `repeats` and
/// `duration` have no meaning there and are refused.
pub fn critical_options(frequency_hz: f64, quick: bool, repeats: Option<usize>, duration: Option<f64>) -> anyhow::Result<CriticalAccuracyOptions> {
    check_frequency(frequency_hz)?;
    anyhow::ensure!(duration.is_none(), "--duration has no meaning with --critical (a Floquet study has no simulated time)");
    anyhow::ensure!(repeats.is_none(), "--repeats has no meaning with --critical (each search runs once; its wall time is reported)");
    Ok(if quick { CriticalAccuracyOptions::quick(frequency_hz) } else { CriticalAccuracyOptions::full(frequency_hz) })
}

/// Refuses a drive frequency that is not finite and > 0.
pub fn check_frequency(frequency_hz: f64) -> anyhow::Result<()> {
    anyhow::ensure!(
        frequency_hz.is_finite() && frequency_hz > 0.0,
        "--critical {frequency_hz}: the drive frequency must be finite and > 0 Hz"
    );
    Ok(())
}

/// The critical-ε_p study at `opts.frequency_hz`: every search's row is handed to `on_rung`
/// as it ends (the reference searches first).
pub fn critical(scene: &Scene, opts: &CriticalAccuracyOptions, on_rung: &mut dyn FnMut(&CriticalRung)) -> anyhow::Result<CriticalAccuracyReport> {
    check_frequency(opts.frequency_hz)?;
    anyhow::ensure!(scene.scene().drive.is_some(), "{}: --critical needs a [drive] section (ε_p is the varied quantity)", scene.origin());
    crate::analysis::critical_accuracy::critical_accuracy(scene.scene(), opts, on_rung).context("critical-ε_p accuracy study")
}
