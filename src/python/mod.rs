//! The Python bindings (feature `python`): the native module `jointwear._native` of the Python
//! package `jointwear` (`python/jointwear/`, built by maturin from `pyproject.toml`).
//!
//! Owns the boundary between Python and the library: a scene document that Python loads,
//! builds from a dict and varies by dotted keys ([`scene::Document`]); the conversion of
//! Python values to TOML values and of results to Python objects ([`convert`]); and the map of
//! library errors to Python exceptions ([`to_py_err`]). Uses [`crate::scene`] (reading,
//! `extends`, dotted keys, validation), [`crate::simulation`] (runs and ensembles),
//! [`crate::sweep`] (cases, summaries, ensemble statistics) and [`crate::analysis`]; nothing
//! in the library uses it.
//!
//! Rules of the boundary:
//! * every library error becomes a Python exception whose message is the one the `jointwear`
//!   program prints after `error: ` for the same input: [`SceneError`] (a `ValueError`) for what
//!   the program calls bad input (exit code 2), [`SimulationError`] (a `RuntimeError`) for a
//!   failure while running (exit code 1), both chosen by the crate's one map,
//!   [`crate::error::exit_code`]; no input reaches a panic;
//! * the GIL is released while a run, an ensemble or a sweep computes, so other Python threads
//!   go on;
//! * numbers cross as they are: series as the native-endian bytes of their `f64`s, which the
//!   Python side views as numpy arrays, so a run from Python is bit for bit the run of the
//!   program.

pub mod convert;
pub mod scene;

use crate::error::exit_code;
use crate::Error;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::Path;

create_exception!(
    jointwear,
    SceneError,
    PyValueError,
    "A scene that cannot be read, parsed, validated or assembled (the `jointwear` program's \
     bad input, exit code 2); the message is the program's."
);

create_exception!(
    jointwear,
    SimulationError,
    PyRuntimeError,
    "A failure while running (integration, a validity limit reached during the run; the \
     `jointwear` program's exit code 1); the message is the program's."
);

/// The Python exception of library error `e` about the scene `path`, with the message the
/// `jointwear` program prints for it: invalid values, integration failures and validity stops
/// prefixed with the scene's path, the others naming their file themselves. `input`: `e` arose reading the
/// scene, so a file that cannot be read is bad input, as in the program.
pub fn to_py_err(path: &Path, e: Error, input: bool) -> PyErr {
    let bad_input = exit_code(&e) == 2 || (input && matches!(e, Error::Io { .. }));
    let message = match e {
        Error::Invalid { .. } | Error::Integration { .. } | Error::Validity { .. } => {
            format!("{}: {e}", path.display())
        }
        _ => e.to_string(),
    };
    if bad_input {
        SceneError::new_err(message)
    } else {
        SimulationError::new_err(message)
    }
}

/// The native module `jointwear._native`: the [`scene::Document`] and [`scene::Folder`]
/// classes and the two exceptions.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::Document>()?;
    m.add_class::<scene::Folder>()?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
