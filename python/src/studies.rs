//! The accuracy studies (`magbubble accuracy`): what accuracy costs in time, from Python. Each
//! calls `magbubble::api::accuracy` with typed arguments and returns the typed report as a dict
//! (`pythonize`), which `magbubble/__init__.py` turns into DataFrames.

use crate::calls::with_monitor;
use crate::convert::to_python;
use crate::{chain_error, worker, PyScene};
use magbubble::api::accuracy;
use pyo3::prelude::*;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(accuracy_study, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy_critical, m)?)?;
    Ok(())
}

/// The work–precision study (`magbubble accuracy`): the report as a dict (the fields of
/// accuracy.json). `progress(done, total)` counts the study's simulations; KeyboardInterrupt
/// stops it before the next simulation. Bad `repeats`/`duration` raise ValueError before any
/// work.
#[pyfunction]
#[pyo3(signature = (scene, quick = false, repeats = None, duration = None, progress = None))]
fn accuracy_study<'py>(
    py: Python<'py>,
    scene: &PyScene,
    quick: bool,
    repeats: Option<usize>,
    duration: Option<f64>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let opts = accuracy::options(quick, repeats, duration).map_err(|e| chain_error(&e))?;
    let sc = &scene.inner;
    let report = worker::run(py, progress.as_ref(), |ctl| with_monitor(ctl, |m| accuracy::study(sc, &opts, m)))?
        .map_err(|e| chain_error(&e))?;
    Ok(to_python(py, &report)?)
}

/// The critical-ε_p study at `frequency_hz` (`magbubble accuracy --critical F`): the report as
/// a dict (the fields of critical.json).
#[pyfunction]
#[pyo3(signature = (scene, frequency_hz, quick = false))]
fn accuracy_critical<'py>(py: Python<'py>, scene: &PyScene, frequency_hz: f64, quick: bool) -> PyResult<Bound<'py, PyAny>> {
    let opts = accuracy::critical_options(frequency_hz, quick, None, None).map_err(|e| chain_error(&e))?;
    let sc = &scene.inner;
    let report = worker::run(py, None, |_| accuracy::critical(sc, &opts, &mut |_| {}))?.map_err(|e| chain_error(&e))?;
    Ok(to_python(py, &report)?)
}
