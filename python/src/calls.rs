//! The module's functions: each calls the Rust library and hands back plain data (JSON text,
//! a float array, CSV fields) that `magbubble/__init__.py` wraps into dicts and DataFrames.

use crate::{chain_error, value_error, worker, PyScene};
use magbubble::analysis::stability::Variant;
use magbubble::cli::coefficients::{coefficients_json, FieldChoice};
use magbubble::cli::floquet::{error_json, floquet_json};
use magbubble::cli::modes::modes_json;
use magbubble::cli::run::summary;
use magbubble::output::series_header;
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
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
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
/// same `out` computes only the missing points. On KeyboardInterrupt no point starts, the points
/// in flight are abandoned, and the interrupt is raised once the CSV holds only the whole rows
/// finished so far.
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
        out: Some(out),
        plot: false,
        shard,
        set: overrides,
    };
    let total = points_of(&args).map_err(|e| chain_error(&e))?;
    let result = worker::run(py, progress.as_ref(), |ctl| {
        ctl.set_total(total as f64);
        let done = |_: usize, _: usize| ctl.add(1.0);
        let hooks = Hooks { cancel: Some(ctl.flag()), on_point: Some(&done), progress_bar: false };
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

/// One grid row: (CSV fields with the index first, the run's series as (columns, array) when
/// asked for).
type GridRowOut<'py> = (Vec<String>, Option<(Vec<String>, Bound<'py, PyArray2<f64>>)>);

/// `magbubble sweep SCENE --grid …` (analysis::grid): `axes` are (key, values as `--set`
/// text) or, with `spec`, (key, [`START:STOP:N[:log]` or `V1,V2,…`]). Returns (CSV header,
/// rows, computed, resumed, CSV path or ""). Invalid keys or values raise ValueError with the
/// messages of `--set` before any run; KeyboardInterrupt keeps the whole rows finished so far
/// (resumable with `out`).
#[pyfunction]
#[pyo3(signature = (scene, axes, out = None, shard = None, keep_series = false, return_series = false, progress = None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn sweep<'py>(
    py: Python<'py>,
    scene: &PyScene,
    axes: Vec<(String, Vec<String>, bool)>,
    out: Option<PathBuf>,
    shard: Option<String>,
    keep_series: bool,
    return_series: bool,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Vec<String>, Vec<GridRowOut<'py>>, usize, usize, String)> {
    use magbubble::analysis::grid::{plan_grid, run_grid, GridAxis, GridOptions};
    use magbubble::analysis::sweep::Shard;
    let mut grid = Vec::with_capacity(axes.len());
    for (key, values, spec) in &axes {
        let axis = if *spec {
            GridAxis::parse(&format!("{key}={}", values.join(","))).map_err(|e| chain_error(&e.into()))?
        } else {
            GridAxis::texts(key.as_str(), values)
        };
        grid.push(axis);
    }
    let shard = match &shard {
        Some(s) => Shard::parse(s).map_err(value_error)?,
        None => Shard::ALL,
    };
    let plan = plan_grid(&scene.template, &grid).map_err(|e| chain_error(&e.into()))?;
    let outcome = worker::run(py, progress.as_ref(), |ctl| {
        let on_run = |done: usize, total: usize| {
            ctl.set_total(total as f64);
            ctl.set_done(done as f64);
        };
        let options = GridOptions {
            out: out.as_deref(),
            shard: Some(shard),
            keep_series,
            return_series,
            cancel: Some(ctl.flag()),
            on_run: Some(&on_run),
            progress_bar: false,
        };
        run_grid(&plan, &options)
    })?;
    let outcome = outcome.map_err(|e| chain_error(&e.into()))?;
    let mut rows = Vec::with_capacity(outcome.rows.len());
    for mut row in outcome.rows {
        let mut fields = vec![row.index.to_string()];
        fields.extend(row.fields());
        let series = match row.series.take() {
            Some(s) => {
                let (n, w) = (s.rows(), s.columns.len());
                Some((s.columns, PyArray1::from_vec(py, s.values).reshape([n, w])?))
            }
            None => None,
        };
        rows.push((fields, series));
    }
    let csv = outcome.csv.map(|p| p.display().to_string()).unwrap_or_default();
    Ok((outcome.header, rows, outcome.computed, outcome.resumed, csv))
}
