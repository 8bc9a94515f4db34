//! Typed results to numpy arrays (moved, not copied) and the column lists that
//! `magbubble._util.frame` turns into a DataFrame.

use magbubble::api::table::{Column, Table};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// (name, kind, data) per column: kind `"int"` (int64 array), `"float"` (float64 array) or
/// `"text"` (data = (codes as a uint32 array, the distinct values)).
pub type Columns<'py> = Vec<(String, &'static str, Bound<'py, PyAny>)>;

/// A row-major `rows × width` buffer as a 2-D float64 array (the buffer is moved into numpy).
pub fn series_array(py: Python<'_>, values: Vec<f64>, rows: usize, width: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    PyArray1::from_vec(py, values).reshape([rows, width])
}

/// The columns of `table` as numpy arrays.
pub fn table_columns(py: Python<'_>, table: Table) -> PyResult<Columns<'_>> {
    let mut out = Vec::with_capacity(table.names.len());
    for (name, column) in table.names.into_iter().zip(table.columns) {
        let (kind, data): (&'static str, Bound<'_, PyAny>) = match column {
            Column::Int(v) => ("int", PyArray1::from_vec(py, v).into_any()),
            Column::Float(v) => ("float", PyArray1::from_vec(py, v).into_any()),
            Column::Text { codes, categories } => ("text", (PyArray1::from_vec(py, codes), categories).into_pyobject(py)?.into_any()),
        };
        out.push((name, kind, data));
    }
    Ok(out)
}

/// A typed result as Python dicts and lists (`pythonize`), with every mapping key a string, as
/// in the files the CLI writes (`initial.a = {2 = 1e-8}` is `{"2": 1e-08}`).
pub fn to_python<'py, T: serde::Serialize + ?Sized>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let obj = pythonize::pythonize(py, value)?;
    string_keys(&obj)?;
    Ok(obj)
}

/// Rewrites, in place, the non-string keys of every dict under `obj` as their `str()`.
fn string_keys(obj: &Bound<'_, PyAny>) -> PyResult<()> {
    use pyo3::types::{PyDict, PyList, PyString};
    if let Ok(dict) = obj.cast::<PyDict>() {
        let items: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)> = dict.iter().collect();
        let rename = items.iter().any(|(k, _)| !k.is_instance_of::<PyString>());
        if rename {
            dict.clear();
        }
        for (k, v) in items {
            string_keys(&v)?;
            if rename {
                let key = if k.is_instance_of::<PyString>() { k } else { k.str()?.into_any() };
                dict.set_item(key, v)?;
            }
        }
    } else if let Ok(list) = obj.cast::<PyList>() {
        for v in list.iter() {
            string_keys(&v)?;
        }
    }
    Ok(())
}
