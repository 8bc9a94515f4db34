//! The module's functions: each calls the Rust library and hands back plain data (JSON text,
//! a float array, CSV fields) that `magbubble/__init__.py` wraps into dicts and DataFrames.

use crate::{chain_error, value_error, worker, PyScene};
use magbubble::analysis::stability::Variant;
use magbubble::cli::coefficients::{coefficients_json, FieldChoice};
use magbubble::cli::floquet::{error_json, floquet_json};
use magbubble::cli::modes::modes_json;
use magbubble::cli::run::{series_header, summary};
use magbubble::cli::stability::{points_of, run_with, Hooks, MethodArg, StabilityArgs};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(floquet, m)?)?;
    m.add_function(wrap_pyfunction!(coefficients, m)?)?;
    m.add_function(wrap_pyfunction!(stability, m)?)?;
    Ok(())
}

/// The payload of the unwind that stops a run when the caller cancels (KeyboardInterrupt):
/// `simulate`'s observer cannot return a stop, so it unwinds to the worker's `catch_unwind`
/// (pure Rust frames only; `resume_unwind` runs no panic hook, so nothing is printed).
struct Cancelled;

type RunOutput = (Vec<f64>, usize, String);

/// Simulates `scene` (as `magbubble run`): (header, rows × columns array, summary.json text).
/// `progress(t, duration)` is called every ~50 ms. A model that cannot be assembled raises
/// ValueError ("cannot simulate …", as the CLI); a blow-up or a failed integration is a status
/// in the summary, not an exception.
#[pyfunction]
#[pyo3(signature = (scene, progress = None))]
fn run<'py>(
    py: Python<'py>,
    scene: &PyScene,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Vec<String>, Bound<'py, PyArray2<f64>>, String)> {
    let sc = scene.template.scene().clone();
    let header = series_header(&sc);
    let width = header.len() - 1;
    let file = scene.template.origin().to_string();
    let overrides = scene.overrides.clone();
    let out: Result<RunOutput, anyhow::Error> = worker::run(py, progress.as_ref(), |ctl| {
        ctl.set_total(sc.run.duration);
        let mut data = Vec::new();
        let mut rows = 0usize;
        let mut bad_row = None;
        let result = magbubble::model::simulate(&sc, &mut |t, row| {
            if ctl.cancelled() {
                std::panic::resume_unwind(Box::new(Cancelled));
            }
            if row.len() != width {
                bad_row.get_or_insert((t, row.len()));
                return;
            }
            data.push(t);
            data.extend_from_slice(row);
            rows += 1;
            ctl.set_done(t);
        });
        let report = result.map_err(|e| anyhow::Error::new(e).context(format!("cannot simulate {file}")))?;
        if let Some((t, len)) = bad_row {
            anyhow::bail!("internal error: the model gave a row of {len} values at t = {t:e} s, expected {width}");
        }
        let text = serde_json::to_string(&summary(&report, &sc, rows as u64, &file, &overrides))?;
        Ok((data, rows, text))
    })?;
    let (data, rows, text) = out.map_err(|e| chain_error(&e))?;
    let array = PyArray1::from_vec(py, data).reshape([rows, width + 1])?;
    Ok((header, array, text))
}

/// `modes --json` (`damped`: `modes --damped --json`) as JSON text.
#[pyfunction]
#[pyo3(signature = (scene, kmax = None, damped = false))]
fn modes(py: Python<'_>, scene: &PyScene, kmax: Option<usize>, damped: bool) -> PyResult<String> {
    let label = scene.template.origin().to_string();
    let sc = scene.template.scene();
    let v = worker::run(py, None, |_| modes_json(sc, kmax, damped, &label))?.map_err(|e| chain_error(&e))?;
    Ok(v.to_string())
}

/// `floquet --json` as JSON text: the report (`"status": "ok"`), or the CLI's status object
/// (`"status": "error"`) when the analysis fails (no periodic orbit, no shape modes …).
/// A bad argument (`steps`, `variant`) raises ValueError.
#[pyfunction]
#[pyo3(signature = (scene, steps = 400, variant = "orbit"))]
fn floquet(py: Python<'_>, scene: &PyScene, steps: usize, variant: &str) -> PyResult<String> {
    let variant = match variant {
        "orbit" => Variant::Orbit,
        "paper" => Variant::Paper,
        other => return Err(value_error(format!("variant '{other}': expected 'orbit' or 'paper'"))),
    };
    let file = scene.template.origin().to_string();
    let sc = scene.template.scene().clone();
    let result = worker::run(py, None, |_| floquet_json(&file, &scene.overrides, variant, steps, || Ok(sc)))?;
    match result {
        Ok(v) => Ok(v.to_string()),
        Err(("invalid_argument" | "scene", e)) => Err(chain_error(&e)),
        Err((kind, e)) => Ok(error_json(kind, &e, &file).to_string()),
    }
}

/// `coefficients --field FIELD --kmax KMAX --json` (pretty JSON text).
#[pyfunction]
fn coefficients(field: &str, kmax: usize) -> PyResult<String> {
    let choice = match field {
        "coil" => FieldChoice::Coil,
        "dipole" => FieldChoice::Dipole,
        other => return Err(value_error(format!("field '{other}': expected 'coil' or 'dipole'"))),
    };
    coefficients_json(choice, kmax).map_err(|e| chain_error(&e))
}

/// One curve of [`stability`]: (family key, family value, CSV path, header without `index`,
/// rows (index, fields), points computed, points resumed).
type Curve = (String, String, String, Vec<String>, Vec<(usize, Vec<String>)>, usize, usize);

/// `magbubble stability SCENE --freq FREQ … --out OUT` (arguments as the CLI's, validated by
/// it): every curve's CSV rows, and the lines about failed points. Resumable: a rerun into the
/// same `out` computes only the missing points. On KeyboardInterrupt the points not yet
/// computed are written as error rows (which a rerun computes again) and the interrupt is
/// raised once the CSV is complete.
#[pyfunction]
#[pyo3(signature = (scene, freq, out, overrides = Vec::new(), family = None, method = "floquet", vary = "drive.amplitude".to_string(),
    freq_key = None, range = "0:1".to_string(), tol = 1e-3, abs_tol = None, scan = 8, shard = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn stability<'py>(
    py: Python<'py>,
    scene: PathBuf,
    freq: String,
    out: PathBuf,
    overrides: Vec<String>,
    family: Option<String>,
    method: &str,
    vary: String,
    freq_key: Option<String>,
    range: String,
    tol: f64,
    abs_tol: Option<f64>,
    scan: usize,
    shard: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Vec<Curve>, Vec<String>)> {
    let method = match method {
        "floquet" => MethodArg::Floquet,
        "series" => MethodArg::Series,
        other => return Err(value_error(format!("method '{other}': expected 'floquet' or 'series'"))),
    };
    let args = StabilityArgs {
        scene,
        freq,
        method,
        family,
        vary,
        freq_key,
        range,
        tol,
        abs_tol,
        scan,
        out,
        plot: false,
        shard,
        set: overrides,
    };
    let total = points_of(&args).map_err(|e| chain_error(&e))?;
    let result = worker::run(py, progress.as_ref(), |ctl| {
        ctl.set_total(total as f64);
        let cancelled = || ctl.cancelled();
        let done = || ctl.add_one();
        let hooks = Hooks { cancelled: &cancelled, point_done: &done, progress_bar: false };
        run_with(&args, &hooks)
    })?;
    let output = result.map_err(|e| chain_error(&e))?;
    let curves = output
        .curves
        .into_iter()
        .map(|c| {
            (c.family.0, c.family.1, c.csv.display().to_string(), c.header, c.report.rows, c.report.computed, c.report.resumed)
        })
        .collect();
    Ok((curves, output.failed))
}
