//! Failures of the command line: the message printed on stderr and the exit code.
//!
//! Owns how an error becomes a failure. Every exit code comes from the crate's one map,
//! [`jointwear::error::exit_code`] (2 for bad input, 1 for a failure while running); the one
//! rule this program adds on top of it, that an input file which cannot be read is bad input
//! too, lives in [`code`] alone.

use jointwear::error::exit_code;
use jointwear::Error;
use std::path::Path;
use std::process::ExitCode;

/// A failure to report: the message and the exit code.
pub struct Failure {
    code: u8,
    message: String,
}

/// The result of a subcommand.
pub type CliResult<T> = std::result::Result<T, Failure>;

/// The exit code of `e` ([`exit_code`]). With `input` (`e` arose reading the command's input,
/// a scene or a shard file), a file that cannot be read counts as one that cannot be parsed:
/// bad input.
fn code(e: &Error, input: bool) -> u8 {
    match e {
        Error::Io { path, source } if input => exit_code(&Error::Parse {
            path: path.clone(),
            message: source.to_string(),
        }),
        e => exit_code(e),
    }
}

impl Failure {
    /// A library error, prefixed with the file it concerns unless the message names it.
    pub fn from(path: &Path, e: Error) -> Failure {
        Failure::new(path, e, false)
    }

    /// Like [`Failure::from`] for an error while reading the command's input (a scene): a
    /// file that cannot be read is bad input too (exit code 2).
    pub fn input(path: &Path, e: Error) -> Failure {
        Failure::new(path, e, true)
    }

    fn new(path: &Path, e: Error, input: bool) -> Failure {
        let code = code(&e, input);
        let message = match e {
            Error::Invalid { .. } | Error::Integration { .. } | Error::Validity { .. } => {
                format!("{}: {e}", path.display())
            }
            _ => e.to_string(),
        };
        Failure { code, message }
    }

    /// A failure while running that is no single library error (cases of a sweep failed,
    /// each with its own error in the sweep file): the code [`exit_code`] gives every error
    /// that is not bad input.
    pub fn running(message: String) -> Failure {
        // Any error but bad input maps to that code; a failed case is usually an integration
        // failure.
        let failed_case = Error::Integration {
            time: f64::NAN,
            cause: message.clone(),
        };
        Failure {
            code: exit_code(&failed_case),
            message,
        }
    }

    /// Prints the message on stderr and returns the exit code.
    pub fn report(self) -> ExitCode {
        eprintln!("error: {}", self.message);
        ExitCode::from(self.code)
    }
}
