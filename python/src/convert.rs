//! Plain data across the boundary: JSON values (summaries, ratings, scene
//! files) to Python objects, Python values to TOML (scene overrides, study
//! plans), the series' vectors to NumPy arrays without a copy.

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::IntoPyObjectExt;
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A JSON value as plain Python data: dicts, lists, floats, ints, strings,
/// booleans and `None` (a non-finite number is `null` in JSON, so `None`).
pub(crate) fn json_to_py<'py>(
    py: Python<'py>,
    value: &serde_json::Value,
) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    match value {
        Value::Null => Ok(py.None().into_bound(py)),
        Value::Bool(b) => b.into_bound_py_any(py),
        Value::Number(n) => match (n.as_i64(), n.as_u64(), n.as_f64()) {
            (Some(i), _, _) => i.into_bound_py_any(py),
            (None, Some(u), _) => u.into_bound_py_any(py),
            (None, None, Some(x)) => x.into_bound_py_any(py),
            _ => Ok(py.None().into_bound(py)),
        },
        Value::String(s) => s.into_bound_py_any(py),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            Ok(list.into_any())
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, json_to_py(py, v)?)?;
            }
            Ok(dict.into_any())
        }
    }
}

/// A Python value as a TOML value: `bool`, `int`, `float`, `str`, lists
/// and tuples, dicts with string keys; NumPy scalars through `__index__`
/// and `__float__`. `what` names the value in errors.
pub(crate) fn py_to_toml(value: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        let i: i64 = value.extract().map_err(|_| {
            PyTypeError::new_err(format!("{what}: {value} does not fit a 64-bit integer"))
        })?;
        return Ok(toml::Value::Integer(i));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("{what}: a key {k} that is not a string"))
            })?;
            let inner = format!("{what}.{key}");
            table.insert(key, py_to_toml(&v, &inner)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(i, v)| py_to_toml(&v?, &format!("{what}[{i}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    // NumPy's integers and floats are not Python's.
    if value.hasattr("__index__")? {
        return Ok(toml::Value::Integer(value.extract()?));
    }
    if value.hasattr("__float__")? {
        return Ok(toml::Value::Float(value.extract()?));
    }
    Err(PyTypeError::new_err(format!(
        "{what}: {} is not a value a scene file holds (bool, int, float, str, list or dict)",
        value.get_type().name()?
    )))
}

/// A row-major `rows × width` block as a 2-D NumPy array that owns the
/// vector (no copy).
pub(crate) fn matrix<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    width: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let rows = data.len().checked_div(width).unwrap_or(0);
    let array = Array2::from_shape_vec((rows, width), data)
        .map_err(|e| PyRuntimeError::new_err(format!("series of {width} columns: {e}")))?;
    Ok(array.into_pyarray(py).into_any())
}

/// A vector as a 1-D NumPy array that owns it (no copy).
pub(crate) fn vector(py: Python<'_>, data: Vec<f64>) -> Bound<'_, PyAny> {
    data.into_pyarray(py).into_any()
}
