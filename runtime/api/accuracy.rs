//! `accuracy`: work–precision of every integrator on a scene (issue 6; method in
//! [`crate::analysis::accuracy`]), or with a drive frequency the error of the critical ε_p
//! against its cost (issue 13 part 5; [`crate::analysis::critical_accuracy`]).

use super::common::Monitor;
use super::scene::Scene;
pub use crate::analysis::accuracy::{AccuracyOptions, AccuracyReport, MIN_WORK_RATIO};
use crate::analysis::accuracy::{accuracy_study_with, planned_runs};
pub use crate::analysis::critical_accuracy::{CriticalAccuracyOptions, CriticalAccuracyReport, CriticalRung};
use anyhow::Context;

/// The time-series study: reference, one ladder per method, the mode and grid ladders.
/// Progress counts the study's simulations (the command line's bar on a terminal).
pub fn study(scene: &Scene, opts: &AccuracyOptions, monitor: &Monitor) -> anyhow::Result<AccuracyReport> {
    let sc = scene.scene();
    let bar = monitor.bar.then(|| crate::output::Counter::new(planned_runs(sc, opts), "accuracy study"));
    let report = accuracy_study_with(sc, opts, &|done, total| {
        if let Some(b) = &bar {
            b.set(done, total);
        }
        monitor.progress(done as f64, total as f64);
    })
    .context("accuracy study")?;
    drop(bar);
    Ok(report)
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
