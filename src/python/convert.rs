//! Values across the boundary: Python values to TOML values (a scene from a dict, a dotted
//! key's value, a sweep's values) and back, and `f64` series to the bytes the Python side views
//! as numpy arrays.

use super::SceneError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// The TOML value of a Python value: `bool`, `int` (and anything with `__index__`, such as
/// numpy integers), `float` (and anything with `__float__`, such as numpy floats), `str`,
/// lists and tuples as arrays, dicts with `str` keys as tables. `None` and other objects are a
/// [`SceneError`] naming `at`, the dotted key of the value.
pub fn to_toml(value: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| {
                SceneError::new_err(format!(
                    "invalid value for `{at}`: {value} (expected an integer within 64 bits)"
                ))
            });
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
                SceneError::new_err(format!(
                    "invalid key in `{at}`: {k} (expected a string: scene keys are names)"
                ))
            })?;
            let path = if at.is_empty() {
                key.clone()
            } else {
                format!("{at}.{key}")
            };
            table.insert(key, to_toml(&v, &path)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(i, v)| to_toml(&v?, &format!("{at}.{i}")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    // numpy scalars and arrays: an integer, a float, or a list of them
    if value.hasattr("tolist")? && !value.hasattr("keys")? {
        return to_toml(&value.call_method0("tolist")?, at);
    }
    if let Ok(i) = value.extract::<i64>() {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(x) = value.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    let kind = value.get_type().name()?;
    Err(SceneError::new_err(format!(
        "invalid value for `{at}`: {value} of type {kind} (expected a TOML value: a bool, int, \
         float, str, list or dict)"
    )))
}

/// The Python value of a TOML value: tables as dicts, arrays as lists, date-times as their
/// TOML text.
pub fn from_toml<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(items) => {
            let items = items
                .iter()
                .map(|v| from_toml(py, v))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, v) in t {
                d.set_item(k, from_toml(py, v)?)?;
            }
            d.into_any()
        }
    })
}

/// The native-endian bytes of `values`, which `numpy.frombuffer(b, dtype=float64)` reads back
/// bit for bit.
pub fn f64_bytes<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyBytes> {
    let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_ne_bytes()).collect();
    PyBytes::new(py, &bytes)
}
