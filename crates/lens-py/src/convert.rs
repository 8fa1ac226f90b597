//! JSON reports to Python objects: objects become dicts, strings, numbers,
//! booleans and null themselves, and a list of numbers a numpy array
//! (float64, or int64 where every entry is an integer), a list of equal
//! lists of numbers a 2-D array. A list holding `null` (a vignetted ray's
//! value) stays a list, its `None`s where the JSON has null.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// `v` as a Python object.
pub fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => array(py, items)?,
        Value::Object(map) => {
            let d = PyDict::new(py);
            for (k, v) in map {
                d.set_item(k, to_py(py, v)?)?;
            }
            d.into_any()
        }
    })
}

/// A JSON list: a numpy array where it is numbers (or equal lists of
/// numbers), else a list.
fn array<'py>(py: Python<'py>, items: &[Value]) -> PyResult<Bound<'py, PyAny>> {
    if !items.is_empty() {
        if let Some(ints) = items.iter().map(Value::as_i64).collect::<Option<Vec<i64>>>() {
            if items.iter().all(|v| v.as_f64().is_some_and(|_| !v.is_f64())) {
                return Ok(PyArray1::from_vec(py, ints).into_any());
            }
        }
        if let Some(floats) = numbers(items) {
            return Ok(PyArray1::from_vec(py, floats).into_any());
        }
        let rows: Option<Vec<Vec<f64>>> = items.iter().map(|r| r.as_array().and_then(|r| numbers(r))).collect();
        if let Some(rows) = rows {
            let width = rows[0].len();
            if width > 0 && rows.iter().all(|r| r.len() == width) {
                let flat: Vec<f64> = rows.concat();
                if let Ok(a) = Array2::from_shape_vec((rows.len(), width), flat) {
                    return Ok(a.into_pyarray(py).into_any());
                }
            }
        }
    }
    let list = PyList::empty(py);
    for v in items {
        list.append(to_py(py, v)?)?;
    }
    Ok(list.into_any())
}

/// The list as floats, if every entry is a number.
fn numbers(items: &[Value]) -> Option<Vec<f64>> {
    if items.is_empty() {
        return None;
    }
    items.iter().map(Value::as_f64).collect()
}
