//! `magbubble._magbubble`: the private extension module of the Python package `magbubble`
//! (python/magbubble). Everything here calls the library API `magbubble::api` — the one the
//! command line calls — with typed arguments, and converts its typed results to Python
//! directly (numpy arrays, typed columns, dicts); the Python package wraps them into pandas
//! DataFrames and dicts (docs/python.md).

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod calls;
mod convert;
mod studies;
mod population; // issue 33
mod fit;
mod worker;

use magbubble::api;

/// A validated scene (TOML tree + resolved parameters). Made by `Scene.load(path)` or
/// `Scene.from_toml(text)`; `with_set` returns a new one.
#[pyclass(name = "Scene", module = "magbubble._magbubble", frozen)]
#[derive(Clone)]
pub struct PyScene {
    pub(crate) inner: api::Scene,
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file (TOML) with `key=value` overrides (as `--set`), in one
    /// validation as the CLI does. ValueError with every problem (key, value, reason), the
    /// message the CLI prints after `error: `.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = Vec::new()))]
    fn load(path: std::path::PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        Ok(PyScene { inner: api::Scene::load(&path, &overrides).map_err(value_error)? })
    }

    /// Validates a scene given as TOML text; `origin` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(text: &str, origin: &str) -> PyResult<Self> {
        Ok(PyScene { inner: api::Scene::from_toml(text, origin, &[] as &[String]).map_err(value_error)? })
    }

    /// A new scene with `key=value` overrides (the strings `--set` takes), validated.
    fn with_set(&self, overrides: Vec<String>) -> PyResult<Self> {
        Ok(PyScene { inner: self.inner.with_overrides(&overrides).map_err(value_error)? })
    }

    /// The scene as TOML text (overrides applied); `Scene.from_toml` reads it back.
    fn to_toml(&self) -> PyResult<String> {
        self.inner.to_toml().map_err(|e| PyRuntimeError::new_err(format!("cannot write the scene as TOML: {e}")))
    }

    /// Every resolved parameter (defaults applied, SI units) as a dict.
    fn resolved<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::to_python(py, self.inner.scene())
    }

    /// The file the scene was read from (or the origin given to `from_toml`).
    #[getter]
    fn origin(&self) -> &str {
        self.inner.origin()
    }

    /// The overrides applied since the file, as `key=value` strings.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.inner.overrides().to_vec()
    }

    fn __repr__(&self) -> String {
        if self.inner.overrides().is_empty() {
            format!("Scene({:?})", self.inner.origin())
        } else {
            format!("Scene({:?}, overrides={:?})", self.inner.origin(), self.inner.overrides())
        }
    }
}

/// A ValueError with the message the CLI prints after `error: `.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A ValueError with an anyhow error's whole chain, as the CLI prints it (`error: …` then one
/// `caused by:` line per cause that adds something).
pub(crate) fn chain_error(e: &anyhow::Error) -> PyErr {
    let top = e.to_string();
    let mut text = top.clone();
    let mut shown = top;
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if shown.contains(&c) {
            continue;
        }
        text.push_str("\n  caused by: ");
        text.push_str(&c);
        shown = c;
    }
    PyValueError::new_err(text)
}

#[pymodule]
fn _magbubble(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScene>()?;
    calls::register(m)?;
    studies::register(m)?;
    population::register(m)?; // issue 33
    fit::register(m)?;
    m.add("KMAX", magbubble::coefficients::KMAX)?;
    Ok(())
}
