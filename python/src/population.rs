//! Populations (issue 33): `population`, `attenuation` and `merge` over `magbubble::api`,
//! converted to typed columns (no text format crosses); `magbubble/__init__.py` wraps them.

use crate::convert::{table_columns, Columns};
use crate::{chain_error, value_error, worker, PyScene};
use magbubble::analysis::sweep::{self, Shard};
use magbubble::api::attenuation::{attenuation as run_attenuation, AttenuationRequest};
use magbubble::api::population::{population as run_population, PopulationRequest};
use magbubble::api::stability::FreqAxis;
use magbubble::api::table::Table;
use magbubble::api::Monitor;
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(population, m)?)?;
    m.add_function(wrap_pyfunction!(attenuation, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    Ok(())
}

fn freq_axis(freq: FreqArg) -> PyResult<FreqAxis> {
    match freq {
        FreqArg::Text(t) => FreqAxis::parse(&t),
        FreqArg::List(v) => FreqAxis::list(&v),
    }
    .map_err(|e| chain_error(&e))
}

fn shard_arg(shard: &Option<String>) -> PyResult<Shard> {
    match shard {
        Some(s) => Shard::parse(s),
        None => Shard::from_env().map(|s| s.unwrap_or(Shard::ALL)),
    }
    .map_err(value_error)
}

fn monitored<T>(ctl: &worker::Control, work: impl FnOnce(&Monitor) -> T) -> T {
    let report = |done: f64, total: f64| {
        ctl.set_total(total);
        ctl.set_done(done);
    };
    work(&Monitor { report: Some(&report), cancel: Some(ctl.flag()), bar: false })
}

#[derive(FromPyObject)]
enum FreqArg {
    Text(String),
    List(Vec<f64>),
}

/// (points CSV, computed, resumed, bins columns or None, (frequency_hz, eps_p,
/// fraction_unstable) or None, failed line or None, multi-window lines).
type PopulationResult<'py> = (String, usize, usize, Option<Columns<'py>>, Option<(Vec<f64>, Vec<f64>, Vec<f64>)>, Option<String>, Vec<String>);

/// A population map into `out` (resumable, shardable): the tables once every point is there.
#[pyfunction]
#[pyo3(signature = (scene, freq, out, range = (0.0, 1.0), eps_points = 101, tol = 1e-3, abs_tol = None, scan = 8,
    window_check = true, shard = None, progress = None))]
#[allow(clippy::too_many_arguments)]
fn population<'py>(
    py: Python<'py>,
    scene: &PyScene,
    freq: FreqArg,
    out: PathBuf,
    range: (f64, f64),
    eps_points: usize,
    tol: f64,
    abs_tol: Option<f64>,
    scan: usize,
    window_check: bool,
    shard: Option<String>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<PopulationResult<'py>> {
    let req = PopulationRequest { freq: freq_axis(freq)?, range, eps_points, tol, abs_tol, scan, window_check, out, shard: shard_arg(&shard)? };
    let sc = &scene.inner;
    magbubble::api::population::plan(sc, &req).map_err(|e| chain_error(&e))?;
    let o = worker::run(py, progress.as_ref(), |ctl| monitored(ctl, |m| run_population(sc, &req, m)))?.map_err(|e| chain_error(&e))?;
    let (bins, fraction, multi) = match o.tables {
        Some(t) => {
            let names = ["frequency_hz", "radius", "weight", "critical_eps_p", "mode", "outcome", "windows", "note"].map(String::from).to_vec();
            let table = Table::from_fields(names, t.bins.iter().map(|r| &r[..]));
            let f = (t.fraction.iter().map(|r| r.0).collect(), t.fraction.iter().map(|r| r.1).collect(), t.fraction.iter().map(|r| r.2).collect());
            (Some(table_columns(py, table)?), Some(f), t.multi_window)
        }
        None => (None, None, Vec::new()),
    };
    Ok((o.points_csv.display().to_string(), o.report.computed, o.report.resumed, bins, fraction, o.failed, multi))
}

/// (points CSV, computed, resumed, (frequency_hz, attenuation_db_per_cm, backscatter_per_m_sr)
/// or None, failed line or None).
type AttenuationResult = (String, usize, usize, Option<(Vec<f64>, Vec<f64>, Vec<f64>)>, Option<String>);

/// A population's attenuation spectrum into `out` (resumable, shardable).
#[pyfunction]
#[pyo3(signature = (scene, freq, out, shard = None, progress = None))]
fn attenuation<'py>(py: Python<'py>, scene: &PyScene, freq: FreqArg, out: PathBuf, shard: Option<String>, progress: Option<Bound<'py, PyAny>>) -> PyResult<AttenuationResult> {
    let req = AttenuationRequest { freq: freq_axis(freq)?, out, shard: shard_arg(&shard)? };
    let sc = &scene.inner;
    magbubble::api::attenuation::plan(sc, &req).map_err(|e| chain_error(&e))?;
    let o = worker::run(py, progress.as_ref(), |ctl| monitored(ctl, |m| run_attenuation(sc, &req, m)))?.map_err(|e| chain_error(&e))?;
    let cols = o.points.map(|p| {
        (p.iter().map(|x| x.frequency_hz).collect(), p.iter().map(|x| x.attenuation_db_per_cm).collect(), p.iter().map(|x| x.backscatter_per_m_sr).collect())
    });
    Ok((o.points_csv.display().to_string(), o.report.computed, o.report.resumed, cols, o.failed))
}

/// `magbubble merge`: joins shard CSVs (each with its `.meta.json`) into `out`; returns the
/// number of points.
#[pyfunction]
fn merge(inputs: Vec<PathBuf>, out: PathBuf) -> PyResult<usize> {
    sweep::merge(&inputs, &out).map(|m| m.total).map_err(value_error)
}
