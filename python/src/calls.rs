//! The module's functions: each calls `magbubble::api` with typed arguments and converts the
//! typed result to Python directly — numbers to numpy arrays, tables to typed columns,
//! structured results (summaries, reports) to dicts with `pythonize` — which
//! `magbubble/__init__.py` wraps into DataFrames. No text format crosses in between.

use crate::convert::{series_array, table_columns, to_python, Columns};
use crate::{chain_error, value_error, worker, PyScene};
use magbubble::analysis::sweep::Shard;
use magbubble::api::coefficients::Field;
use magbubble::api::floquet::Variant;
use magbubble::api::stability::{Criterion, Family, FreqAxis, Modes, StabilityRequest};
use magbubble::api::sweep::{GridAxis, SweepRequest, SweepTable};
use magbubble::api::table::Table;
use magbubble::api::{self, Monitor};
use numpy::PyArray2;
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(floquet, m)?)?;
    m.add_function(wrap_pyfunction!(coefficients, m)?)?;
    m.add_function(wrap_pyfunction!(stability, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(response, m)?)?;
    Ok(())
}

/// The [`Monitor`] of a worker: progress to the calling thread, its cancel flag.
pub(crate) fn with_monitor<T>(ctl: &worker::Control, work: impl FnOnce(&Monitor) -> T) -> T {
    let report = |done: f64, total: f64| {
        ctl.set_total(total);
        ctl.set_done(done);
    };
    work(&Monitor { report: Some(&report), cancel: Some(ctl.flag()), bar: false })
}

/// Simulates `scene` (as `magbubble run`): (columns, rows × columns array, summary dict, echo),
/// echo = (echo.csv's columns, spectrum.csv's columns) with `[echo]`, else None.
/// `progress(t, duration)` is called every ~50 ms. A model that cannot be assembled raises
/// ValueError ("cannot simulate …", as the CLI); a blow-up or a failed integration is a status
/// in the summary, not an exception.
#[pyfunction]
#[pyo3(signature = (scene, progress = None))]
#[allow(clippy::type_complexity)]
fn run<'py>(
    py: Python<'py>,
    scene: &PyScene,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Vec<String>, Bound<'py, PyArray2<f64>>, Bound<'py, PyAny>, Option<(Columns<'py>, Columns<'py>)>)> {
    let sc = &scene.inner;
    let result = worker::run(py, progress.as_ref(), |ctl| with_monitor(ctl, |m| api::run::run(sc, m)))?;
    let mut r = result.map_err(|e| chain_error(&e))?;
    let summary = to_python(py, &r.outcome.summary)?;
    let echo = match r.outcome.echo.take() {
        Some(e) => Some((table_columns(py, e.echo)?, table_columns(py, e.spectrum)?)),
        None => None,
    };
    let array = series_array(py, r.values, r.outcome.rows as usize, r.outcome.columns.len())?;
    Ok((r.outcome.columns, array, summary, echo))
}

/// The linear response (as `magbubble response`): (response.csv's columns, natural frequency
/// [Hz], resonance frequency on the grid [Hz], damping rates by source [1/s] as a dict).
/// `freq`: "A:B:N[:log]" (as --freq) or a sequence of frequencies [Hz].
#[pyfunction]
#[allow(clippy::type_complexity)]
fn response<'py>(py: Python<'py>, scene: &PyScene, freq: Bound<'py, PyAny>) -> PyResult<(Columns<'py>, f64, f64, Bound<'py, PyAny>)> {
    let freqs = match freq.extract::<String>() {
        Ok(spec) => api::response::grid(&spec).map_err(|e| chain_error(&e))?,
        Err(_) => freq.extract::<Vec<f64>>().map_err(|_| value_error("freq: expected \"A:B:N[:log]\" or a sequence of frequencies [Hz]"))?,
    };
    let r = api::response::response(&scene.inner, &freqs).map_err(|e| chain_error(&e))?;
    let rates = to_python(py, &r.damping_rates_per_s)?;
    Ok((table_columns(py, api::response::table(&r))?, r.natural_frequency_hz, r.resonance_frequency_hz, rates))
}

/// Natural frequencies (`damped`: the damped spectrum) as a dict: what `modes` prints as JSON.
#[pyfunction]
#[pyo3(signature = (scene, kmax = None, damped = false))]
fn modes<'py>(py: Python<'py>, scene: &PyScene, kmax: Option<i64>, damped: bool) -> PyResult<Bound<'py, PyAny>> {
    // a negative kmax gets the library's message for a too small one (not OverflowError)
    let kmax = kmax.map(|k| usize::try_from(k).map_err(|_| value_error(format!("kmax = {k}: must be ≥ 2")))).transpose()?;
    let sc = &scene.inner;
    let m = worker::run(py, None, |_| api::modes::modes(sc, kmax, damped))?.map_err(|e| chain_error(&e))?;
    Ok(to_python(py, &m)?)
}

/// The Floquet report as a dict (`"status": "ok"`), or the status object (`"status": "error"`)
/// when the analysis fails (no periodic orbit, no shape modes …). A bad argument (`steps`,
/// `variant`) raises ValueError.
#[pyfunction]
#[pyo3(signature = (scene, steps = 400, variant = "orbit"))]
fn floquet<'py>(py: Python<'py>, scene: &PyScene, steps: usize, variant: &str) -> PyResult<Bound<'py, PyAny>> {
    let variant = match variant {
        "orbit" => Variant::Orbit,
        "paper" => Variant::Paper,
        other => return Err(value_error(format!("variant '{other}': expected 'orbit' or 'paper'"))),
    };
    let sc = &scene.inner;
    match worker::run(py, None, |_| api::floquet::floquet(sc, variant, steps))? {
        Ok(r) => Ok(to_python(py, &r)?),
        Err(f) if f.kind == "invalid_argument" => Err(chain_error(&f.error)),
        Err(f) => Ok(to_python(py, &f.report(sc.origin()))?),
    }
}

/// The generated coupling tables of `field` ("coil" or "dipole") up to mode `kmax`, as a dict.
#[pyfunction]
fn coefficients<'py>(py: Python<'py>, field: &str, kmax: usize) -> PyResult<Bound<'py, PyAny>> {
    let field = match field {
        "coil" => Field::Coil,
        "dipole" => Field::Dipole,
        other => return Err(value_error(format!("field '{other}': expected 'coil' or 'dipole'"))),
    };
    let c = api::coefficients::coefficients(field, kmax).map_err(|e| chain_error(&e))?;
    Ok(to_python(py, &c)?)
}

/// The frequency axis: a list of numbers [Hz] or the command line's text.
#[derive(FromPyObject)]
enum FreqArg {
    Text(String),
    List(Vec<f64>),
}

/// The family: `KEY=V1,V2` or (key, [values as `--set` text]).
#[derive(FromPyObject)]
enum FamilyArg {
    Text(String),
    Pair(String, Vec<String>),
}

/// One curve of [`stability`]: (family key, family value, file written, columns, points
/// computed, points resumed).
type Curve<'py> = (String, String, String, Columns<'py>, usize, usize);

/// A stability diagram into `out` (resumable: a rerun into the same `out` computes only the
/// missing points): every curve's rows as typed columns, and the lines about failed points.
/// Bad arguments raise ValueError before any work. On KeyboardInterrupt no point starts, the
/// points in flight are abandoned, and the interrupt is raised once the files hold only the
/// whole rows finished so far.
#[pyfunction]
#[pyo3(signature = (scene, freq, out, family = None, method = "floquet", vary = "drive.amplitude".to_string(),
    freq_key = None, range = (0.0, 1.0), tol = 1e-3, abs_tol = None, scan = 8, shard = None, progress = None,
    modes = "scene", cutoff_limit = None))]
#[allow(clippy::too_many_arguments)]
fn stability<'py>(
    py: Python<'py>,
    scene: &PyScene,
    freq: FreqArg,
    out: PathBuf,
    family: Option<FamilyArg>,
    method: &str,
    vary: String,
    freq_key: Option<String>,
    range: (f64, f64),
    tol: f64,
    abs_tol: Option<f64>,
    scan: usize,
    shard: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
    modes: &str,
    cutoff_limit: Option<usize>,
) -> PyResult<(Vec<Curve<'py>>, Vec<String>)> {
    // issue 31 part 5: the cutoff, parsed and checked by the library as for the CLI
    let modes = Modes::parse(modes, cutoff_limit).map_err(|e| chain_error(&e))?;
    let method = match method {
        "floquet" => Criterion::Floquet,
        "series" => Criterion::Series,
        other => return Err(value_error(format!("method '{other}': expected 'floquet' or 'series'"))),
    };
    let freq = match freq {
        FreqArg::Text(t) => FreqAxis::parse(&t),
        FreqArg::List(v) => FreqAxis::list(&v),
    }
    .map_err(|e| chain_error(&e))?;
    let family = match family {
        None => None,
        Some(FamilyArg::Text(t)) => Some(Family::parse(&t).map_err(|e| chain_error(&e))?),
        Some(FamilyArg::Pair(k, v)) => Some(Family::new(&k, v)),
    };
    let shard = match &shard {
        Some(s) => Shard::parse(s),
        None => Shard::from_env().map(|s| s.unwrap_or(Shard::ALL)),
    }
    .map_err(value_error)?;
    let req = StabilityRequest { freq, method, family, vary, freq_key, range, tol, abs_tol, scan, out, shard, modes };
    let sc = &scene.inner;
    api::stability::plan(sc, &req).map_err(|e| chain_error(&e))?;
    let result = worker::run(py, progress.as_ref(), |ctl| with_monitor(ctl, |m| api::stability::stability(sc, &req, m)))?;
    let output = result.map_err(|e| chain_error(&e))?;
    let mut curves = Vec::with_capacity(output.curves.len());
    for c in output.curves {
        let mut names = vec!["index".to_string()];
        names.extend(c.header);
        let rows: Vec<Vec<String>> = c
            .report
            .rows
            .into_iter()
            .map(|(i, fields)| std::iter::once(i.to_string()).chain(fields).collect())
            .collect();
        let table = Table::from_fields(names, rows.iter().map(Vec::as_slice));
        let path = c.path.display().to_string();
        curves.push((c.family.0, c.family.1, path, table_columns(py, table)?, c.report.computed, c.report.resumed));
    }
    Ok((curves, output.failed))
}

/// A grid of runs (`magbubble sweep`): `axes` are (key, values as `--set` text) or, with
/// `spec`, (key, [`START:STOP:N[:log]` or `V1,V2,…`]). The rows stream from the worker into
/// typed columns (no row is kept twice). Returns (columns, each row's series as (columns,
/// array) or None when asked for, computed, resumed, the file written or ""). Invalid keys or
/// values raise ValueError with the messages of `--set` before any run; KeyboardInterrupt
/// keeps the whole rows finished so far (resumable with `out`).
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
) -> PyResult<(Columns<'py>, Option<Vec<Option<SeriesOut<'py>>>>, usize, usize, String)> {
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
    let plan = api::sweep::plan(&scene.inner, &grid).map_err(|e| chain_error(&e.into()))?;
    let req = SweepRequest { out, shard: Some(shard), keep_series, return_series };
    let outcome = worker::run(py, progress.as_ref(), |ctl| {
        with_monitor(ctl, |m| {
            let mut table = SweepTable::new(&plan);
            api::sweep::sweep(&plan, &req, m, &mut |row| table.push(row)).map(|s| (s, table))
        })
    })?;
    let (summary, table) = outcome.map_err(|e| chain_error(&e.into()))?;
    let (table, series) = table.finish();
    let series = if return_series {
        let mut list = Vec::with_capacity(series.len());
        for s in series {
            list.push(match s {
                Some(s) => {
                    let (n, w) = (s.rows(), s.columns.len());
                    Some((s.columns, series_array(py, s.values, n, w)?))
                }
                None => None,
            });
        }
        Some(list)
    } else {
        None
    };
    let path = summary.path.map(|p| p.display().to_string()).unwrap_or_default();
    Ok((table_columns(py, table)?, series, summary.computed, summary.resumed, path))
}

/// A run's series: (columns, rows × columns array).
type SeriesOut<'py> = (Vec<String>, Bound<'py, PyArray2<f64>>);
