//! Errors of the library: bad input names the field, the value and the valid range;
//! numerical failures name the simulated time and the cause.

use std::fmt;
use std::path::PathBuf;

/// Every failure the library reports. None of them is a panic.
#[derive(Debug)]
pub enum Error {
    /// A scene value outside its valid range (or missing / not a number).
    Invalid {
        /// Dotted path of the field, e.g. `joints.clearance[0].clearance_mm`.
        field: String,
        /// The offending value as written.
        value: String,
        /// The valid range or the rule it breaks.
        expected: String,
    },
    /// A file that could not be parsed (TOML syntax, unknown key, wrong type).
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// A file that could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The integrator failed (step size underflow, non-finite state, step limit).
    Integration {
        /// Simulated time of the failure (s).
        time: f64,
        /// What went wrong, with the likely cause.
        cause: String,
    },
    /// A run stopped where its model stops describing the mechanism (a worn bearing too steep
    /// for the paper's gap, [`crate::simulation::MAX_ECCENTRICITY_SLOPE`]). A run writes
    /// nothing then, as for any failure; a long-life prediction stops there and keeps what it
    /// predicted.
    Validity {
        /// Simulated time of the stop (s).
        time: f64,
        /// The clearance joint, in the mechanism's order.
        joint: usize,
        /// What left the model, by how much, and what stays within it.
        cause: String,
    },
    /// Rendering a figure failed.
    Plot {
        /// The figure file.
        path: PathBuf,
        /// The renderer's message.
        message: String,
    },
    /// The caller asked the computation to stop ([`crate::io::progress::Progress::cancelled`]).
    Cancelled,
    /// Results saved by an earlier run (a study's CSVs under `data/`) that do not come from
    /// what would compute them now, or whose record of what did is missing: read as they are,
    /// they would pass for this checkout's.
    Stale {
        /// Each such result: its files, what differs and the command that remakes it.
        results: Vec<String>,
    },
}

/// How the message of an [`Error::Validity`] begins, for a reader of saved messages (a
/// study's failure column) that tells such stops from failures.
pub const LEFT_MODEL: &str = "the run left its model";

/// Library-wide result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// The error with ` (context)` appended to a bad value's field or to a parse message, so
    /// that it names where the value came from (a `--set`, a sweep case); others unchanged.
    pub fn in_context(self, context: &str) -> Error {
        match self {
            Error::Invalid {
                field,
                value,
                expected,
            } => Error::Invalid {
                field: format!("{field} ({context})"),
                value,
                expected,
            },
            Error::Parse { path, message } => Error::Parse {
                path,
                message: format!("{} ({context})", message.trim_end()),
            },
            e => e,
        }
    }

    /// The error of a run with `what: ` put before its cause (the ensemble member, the case
    /// it ran), for the failures while running that carry one; others unchanged.
    pub fn in_run(self, what: &str) -> Error {
        match self {
            Error::Integration { time, cause } => Error::Integration {
                time,
                cause: format!("{what}: {cause}"),
            },
            Error::Validity { time, joint, cause } => Error::Validity {
                time,
                joint,
                cause: format!("{what}: {cause}"),
            },
            e => e,
        }
    }

    /// Shorthand for a validation error.
    pub fn invalid(
        field: impl Into<String>,
        value: impl fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Error::Invalid {
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}

/// Exit code of a program that stops on `error`: 2 for bad input (a scene value, a file
/// that cannot be parsed, saved results that are not this checkout's), 1 for a failure while
/// running, 130 when cancelled. The one map every program uses.
pub fn exit_code(error: &Error) -> u8 {
    match error {
        Error::Invalid { .. } | Error::Parse { .. } | Error::Stale { .. } => 2,
        Error::Cancelled => crate::io::interrupt::INTERRUPTED_EXIT_CODE as u8,
        _ => 1,
    }
}

/// Unwraps `result` or prints the error, releases the program's claims of its outputs and
/// exits with [`exit_code`]: the `main` of the figure and study programs.
pub fn exit_on_error<T>(result: Result<T>) -> T {
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        crate::io::interrupt::release_claims();
        std::process::exit(exit_code(&e).into())
    })
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Invalid {
                field,
                value,
                expected,
            } => {
                write!(
                    f,
                    "invalid value for `{field}`: {value} (expected {expected})"
                )
            }
            Error::Parse { path, message } => {
                // toml's messages end with a line break: the message is one of several lines.
                let message = message.trim_end();
                write!(f, "cannot parse {}: {message}", path.display())
            }
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Integration { time, cause } => {
                write!(f, "integration failed at t = {time:.6e} s: {cause}")
            }
            Error::Validity { time, cause, .. } => {
                write!(
                    f,
                    "{LEFT_MODEL} at t = {time:.6e} s: {cause}; fewer rotations or a \
                     smaller k/H stay within it, `jointwear longlife` tells how many rotations \
                     reach it"
                )
            }
            Error::Plot { path, message } => {
                write!(f, "cannot render {}: {message}", path.display())
            }
            Error::Cancelled => write!(f, "cancelled before it finished"),
            Error::Stale { results } => {
                write!(
                    f,
                    "results saved by earlier runs do not come from what this checkout would \
                     compute them from, and are not used:"
                )?;
                results.iter().try_for_each(|r| write!(f, "\n  - {r}"))
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}
