//! Interruption of the command line's runs without litter: temporary outputs are registered
//! here while they are written, and SIGINT, SIGTERM or SIGHUP removes them, says what it
//! removed and what stays (e.g. a sweep's finished rows), and exits with
//! [`INTERRUPTED_EXIT_CODE`]. The lock files of claimed outputs ([`claim`]) are released too.
//!
//! The handler holds the registry's lock until the process exits, so no temporary output can
//! start after it has cleaned up. A writer that registered its file just before the signal but
//! had not yet created it can still leave it behind: removal is best effort in that window of
//! microseconds.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Exit code of an interrupted program: 128 + SIGINT, the shells' convention.
pub const INTERRUPTED_EXIT_CODE: i32 = 130;

struct Registry {
    temporaries: Vec<PathBuf>,
    /// Lock files of claimed outputs ([`crate::io::lock`]), each with the folder its claim
    /// created, if it did: released without a word, the folder removed only if left empty.
    claims: Vec<(PathBuf, Option<PathBuf>)>,
    kept: Vec<String>,
    interrupted: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    temporaries: Vec::new(),
    claims: Vec::new(),
    kept: Vec::new(),
    interrupted: false,
});

/// The registry, also after a thread panicked while holding it (its data stay valid).
fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// A temporary file or directory, removed if the program is interrupted while this lives.
#[derive(Debug)]
pub struct Temporary {
    path: PathBuf,
}

/// Registers `path` as temporary until the returned guard drops; `None` once the program is
/// being interrupted (nothing new should start then).
pub fn temporary(path: &Path) -> Option<Temporary> {
    let mut r = registry();
    if r.interrupted {
        return None;
    }
    r.temporaries.push(path.to_path_buf());
    Some(Temporary {
        path: path.to_path_buf(),
    })
}

/// Registers the lock file `lock` of a claim, and the folder `created` the claim created, to
/// be released if the program is interrupted while the returned guard lives; `None` once the
/// program is being interrupted.
pub fn claim(lock: &Path, created: Option<&Path>) -> Option<Temporary> {
    let mut r = registry();
    if r.interrupted {
        return None;
    }
    r.claims
        .push((lock.to_path_buf(), created.map(Path::to_path_buf)));
    Some(Temporary {
        path: lock.to_path_buf(),
    })
}

impl Drop for Temporary {
    fn drop(&mut self) {
        let mut r = registry();
        if let Some(i) = r.temporaries.iter().rposition(|p| *p == self.path) {
            r.temporaries.swap_remove(i);
        } else if let Some(i) = r.claims.iter().rposition(|(p, _)| *p == self.path) {
            r.claims.swap_remove(i);
        }
    }
}

/// Releases every registered claim: for a program that exits on an error without returning
/// from `main` (whose [`crate::io::lock::Lock`]s then never drop), so that its locks do not
/// outlive it.
pub fn release_claims() {
    let mut r = registry();
    for (lock, created) in r.claims.drain(..) {
        super::lock::release(&lock, created.as_deref());
    }
}

/// Says, if the program is interrupted, that `what` stays (e.g. "finished cases stay in
/// sweep.csv").
pub fn keep(what: impl Into<String>) {
    registry().kept.push(what.into());
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP; call once, from `main`.
pub fn install() -> std::result::Result<(), String> {
    ctrlc::set_handler(on_signal).map_err(|e| format!("cannot install the signal handler: {e}"))
}

/// Removes the registered temporaries, says so, and exits.
fn on_signal() {
    let mut r = registry();
    r.interrupted = true;
    let mut removed = Vec::new();
    for path in &r.temporaries {
        let gone = if path.is_dir() {
            std::fs::remove_dir_all(path)
        } else {
            std::fs::remove_file(path)
        };
        if gone.is_ok() {
            removed.push(path.display().to_string());
        }
    }
    for (lock, created) in &r.claims {
        super::lock::release(lock, created.as_deref());
    }
    let mut message = match removed.len() {
        0 => "interrupted: no temporary outputs to remove".to_string(),
        n => format!(
            "interrupted: removed {n} temporary output(s): {}",
            removed.join(", ")
        ),
    };
    for k in &r.kept {
        message.push_str("; ");
        message.push_str(k);
    }
    eprintln!("\n{message}");
    // Exits with the lock held: no temporary output starts after the clean-up.
    std::process::exit(INTERRUPTED_EXIT_CODE);
}
