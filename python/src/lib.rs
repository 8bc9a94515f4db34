//! `magbubble._magbubble`: the private extension module of the Python package `magbubble`
//! (python/magbubble). Everything here calls the Rust library: scenes are loaded and validated
//! by `scene::SceneTemplate` (the `--set` path), the JSON of `modes`, `floquet` and
//! `coefficients` is built by the same functions the CLI prints, stability diagrams go through
//! `cli::stability::run_with` (resumable CSVs). The Python package turns the results into
//! pandas DataFrames and dicts (docs/python.md).

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod calls;
mod worker;

use magbubble::scene::SceneTemplate;

/// A validated scene (TOML tree + resolved parameters). Made by `Scene.load(path)` or
/// `Scene.from_toml(text)`; `with_overrides` returns a new one.
#[pyclass(name = "Scene", module = "magbubble._magbubble", frozen)]
#[derive(Clone)]
pub struct PyScene {
    pub(crate) template: SceneTemplate,
    /// The `--set` overrides applied since the file or text (as `key=value` strings).
    pub(crate) overrides: Vec<String>,
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file (TOML) with `key=value` overrides (as `--set`), in one
    /// validation as the CLI does. ValueError with every problem (key, value, reason), the
    /// message the CLI prints after `error: `.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = Vec::new()))]
    fn load(path: std::path::PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        let template = SceneTemplate::load(&path, &overrides).map_err(value_error)?;
        Ok(PyScene { template, overrides })
    }

    /// Validates a scene given as TOML text; `origin` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(text: &str, origin: &str) -> PyResult<Self> {
        let template = SceneTemplate::from_str(text, origin, &[] as &[String]).map_err(value_error)?;
        Ok(PyScene { template, overrides: Vec::new() })
    }

    /// A new scene with `key=value` overrides (the strings `--set` takes), validated.
    fn with_set(&self, overrides: Vec<String>) -> PyResult<Self> {
        let template = self.template.with_overrides(&overrides).map_err(value_error)?;
        let mut all = self.overrides.clone();
        all.extend(overrides);
        Ok(PyScene { template, overrides: all })
    }

    /// The scene as TOML text (overrides applied); `Scene.from_toml` reads it back.
    fn to_toml(&self) -> PyResult<String> {
        self.template.to_toml().map_err(|e| PyRuntimeError::new_err(format!("cannot write the scene as TOML: {e}")))
    }

    /// Every resolved parameter (defaults applied, SI units) as JSON text.
    fn resolved_json(&self) -> PyResult<String> {
        serde_json::to_string(self.template.scene()).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// The file the scene was read from (or the origin given to `from_toml`).
    #[getter]
    fn origin(&self) -> &str {
        self.template.origin()
    }

    /// The overrides applied since the file, as `key=value` strings.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.overrides.clone()
    }

    fn __repr__(&self) -> String {
        if self.overrides.is_empty() {
            format!("Scene({:?})", self.template.origin())
        } else {
            format!("Scene({:?}, overrides={:?})", self.template.origin(), self.overrides)
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
    m.add("KMAX", magbubble::coefficients::KMAX)?;
    Ok(())
}
