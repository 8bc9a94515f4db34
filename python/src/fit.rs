//! `fit` (issue 32): the measurements as a path or as named columns (a DataFrame's), the
//! parameters as `KEY[=LOW:HIGH]` strings; returns the report dict (fit.json) and the curves as
//! columns (fit.csv's), which `magbubble/__init__.py` turns into DataFrames.

use crate::convert::to_python;
use crate::{chain_error, value_error, worker, PyScene};
use magbubble::api::fit::{fit as api_fit, fit_attenuation as api_fit_attenuation, AttenuationFitRequest, Data, FitRequest, ParamSpec, Spectrum};
use magbubble::api::Monitor;
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit_attenuation, m)?)?;
    Ok(())
}

/// Fits `scene` to `path` (a CSV file) or `columns` (name → values); returns (report dict,
/// curve column names, curve columns).
#[pyfunction]
#[pyo3(signature = (scene, params, path = None, columns = None, starts = 1))]
#[allow(clippy::type_complexity)]
fn fit<'py>(
    py: Python<'py>,
    scene: &PyScene,
    params: Vec<String>,
    path: Option<PathBuf>,
    columns: Option<Vec<(String, Vec<f64>)>>,
    starts: usize,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>, Vec<Vec<f64>>)> {
    let specs = params.iter().map(|p| p.parse::<ParamSpec>()).collect::<anyhow::Result<Vec<_>>>().map_err(|e| chain_error(&e))?;
    let data = match (path, columns) {
        (Some(p), None) => Data::read(&p),
        (None, Some(c)) => Data::from_columns(c),
        _ => return Err(value_error("fit: give the data as a path or as columns")),
    }
    .map_err(|e| chain_error(&e))?;
    let mut request = FitRequest::new(data, specs);
    request.starts = starts;
    let sc = &scene.inner;
    let report = worker::run(py, None, |ctl| {
        api_fit(sc, &request, &Monitor { report: None, cancel: Some(ctl.flag()), bar: false })
    })?
    .map_err(|e| chain_error(&e))?;
    let mut names = vec!["t".to_string()];
    let mut cols = vec![report.t.clone()];
    for c in &report.curves {
        names.extend([format!("{}_data", c.name), format!("{}_model", c.name), format!("{}_residual", c.name)]);
        cols.extend([c.data.clone(), c.model.clone(), c.residual.clone()]);
    }
    Ok((to_python(py, &report)?, names, cols))
}

/// Fits `scene` to a measured attenuation spectrum, `path` (a CSV file) or `columns` (`f`,
/// `attenuation_db_per_cm`[, `sigma`]); `concentration` [bubbles/mL] for a scene without
/// `[population]`. Returns (report dict, ["f", "data", "model", "residual"], columns).
#[pyfunction]
#[pyo3(signature = (scene, params, path = None, columns = None, concentration = None, starts = 1))]
#[allow(clippy::type_complexity)]
fn fit_attenuation<'py>(
    py: Python<'py>,
    scene: &PyScene,
    params: Vec<String>,
    path: Option<PathBuf>,
    columns: Option<Vec<(String, Vec<f64>)>>,
    concentration: Option<f64>,
    starts: usize,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>, Vec<Vec<f64>>)> {
    let specs = params.iter().map(|p| p.parse::<ParamSpec>()).collect::<anyhow::Result<Vec<_>>>().map_err(|e| chain_error(&e))?;
    let data = match (path, columns) {
        (Some(p), None) => Spectrum::read(&p),
        (None, Some(c)) => Spectrum::from_columns(c),
        _ => return Err(value_error("fit: give the attenuation spectrum as a path or as columns")),
    }
    .map_err(|e| chain_error(&e))?;
    let mut request = AttenuationFitRequest::new(data, specs, concentration);
    request.starts = starts;
    let sc = &scene.inner;
    let report = worker::run(py, None, |ctl| {
        api_fit_attenuation(sc, &request, &Monitor { report: None, cancel: Some(ctl.flag()), bar: false })
    })?
    .map_err(|e| chain_error(&e))?;
    let names = ["f", "data", "model", "residual"].map(String::from).to_vec();
    let cols = match report.curves.first() {
        Some(c) => vec![report.t.clone(), c.data.clone(), c.model.clone(), c.residual.clone()],
        None => vec![Vec::new(); 4],
    };
    Ok((to_python(py, &report)?, names, cols))
}
