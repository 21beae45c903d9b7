//! Values across the boundary: Python values to TOML values (a scene from a dict, a dotted
//! key's value, a sweep's values) and back, and `f64` series to the bytes the Python side views
//! as numpy arrays.

use super::SceneError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Deepest nesting of dicts and lists in a scene from Python: the deepest shipped scene
/// nests 4 levels, and the TOML reader of scene files stops at about 80. Deeper input (a list
/// nested 100 000 deep) used to overflow the stack and kill the interpreter.
pub const MAX_NESTING: usize = 64;

/// The TOML value of a Python value: `bool`, `int` (and anything with `__index__`, such as
/// numpy integers), `float` (and anything with `__float__`, such as numpy floats), `str`,
/// lists and tuples as arrays, dicts with `str` keys as tables. `None` and other objects, a
/// dict or list that contains itself and nesting deeper than [`MAX_NESTING`] are a
/// [`SceneError`] naming `at`, the dotted key of the value.
pub fn to_toml(value: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    to_toml_within(value, at, &mut Vec::new())
}

/// [`to_toml`] of a value inside the containers `path` (their addresses, outermost first).
fn to_toml_within(
    value: &Bound<'_, PyAny>,
    at: &str,
    path: &mut Vec<usize>,
) -> PyResult<toml::Value> {
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
    let container = value.is_instance_of::<PyDict>()
        || value.is_instance_of::<PyList>()
        || value.is_instance_of::<PyTuple>();
    if container {
        let address = value.as_ptr() as usize;
        if path.contains(&address) {
            return Err(SceneError::new_err(format!(
                "invalid value for `{at}`: a {} that contains itself (expected nested dicts \
                 and lists that end in values)",
                value.get_type().name()?
            )));
        }
        if path.len() == MAX_NESTING {
            // The first parts of the key name where it goes deep; all 64 would be noise.
            let start: Vec<&str> = at.split('.').take(8).collect();
            return Err(SceneError::new_err(format!(
                "invalid value for `{}…`: nested deeper than {MAX_NESTING} dicts and lists \
                 (a scene nests a few)",
                start.join(".")
            )));
        }
        path.push(address);
        let converted = containers_to_toml(value, at, path);
        path.pop();
        return converted;
    }
    // numpy scalars and arrays: an integer, a float, or a list of them
    if value.hasattr("tolist")? && !value.hasattr("keys")? {
        return to_toml_within(&value.call_method0("tolist")?, at, path);
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

/// The TOML table or array of a dict, list or tuple inside the containers `path`.
fn containers_to_toml(
    value: &Bound<'_, PyAny>,
    at: &str,
    path: &mut Vec<usize>,
) -> PyResult<toml::Value> {
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                SceneError::new_err(format!(
                    "invalid key in `{at}`: {k} (expected a string: scene keys are names)"
                ))
            })?;
            let key_path = if at.is_empty() {
                key.clone()
            } else {
                format!("{at}.{key}")
            };
            table.insert(key, to_toml_within(&v, &key_path, path)?);
        }
        return Ok(toml::Value::Table(table));
    }
    let items = value
        .try_iter()?
        .enumerate()
        .map(|(i, v)| to_toml_within(&v?, &format!("{at}.{i}"), path))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(toml::Value::Array(items))
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
