//! Exclusive claims of outputs: a run's folder or a sweep's file belongs to one process while
//! it writes, so that two runs never mix their files.
//!
//! A claim is a lock file beside the output, created with `O_EXCL` (it exists or it does not:
//! one process wins), holding the holder's process id, host and command line. A second writer
//! is refused with an error naming them. A lock whose holder is no longer alive on this host
//! (a process killed with SIGKILL cannot remove it) is stale: it is taken over, with a message.
//! The lock is removed when its [`Lock`] drops, and by the interrupt handler
//! ([`crate::io::interrupt`]) on SIGINT, SIGTERM or SIGHUP, with the folder the claim created
//! if nothing was written into it.
//!
//! Whether a holder lives is told by `/proc/<pid>` on this host; a lock of another host (a
//! shared file system) is never taken over, as its holder cannot be seen from here.

use crate::io::interrupt;
use crate::{Error, Result};
use std::ffi::OsString;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the lock file of an output folder, inside it.
pub const FOLDER_LOCK: &str = ".jointwear.lock";

/// A held claim; dropping it releases the claim (removes the lock file).
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
    /// The folder the claim created, removed with the lock if nothing was written into it.
    created: Option<PathBuf>,
    _registered: Option<interrupt::Temporary>,
}

impl Drop for Lock {
    fn drop(&mut self) {
        release(&self.path, self.created.as_deref());
    }
}

/// Removes the lock file `lock` and the folder its claim `created`, if nothing was written
/// into it: on drop and on an interrupt.
pub(crate) fn release(lock: &Path, created: Option<&Path>) {
    // Best effort: a lock left behind is stale and taken over by the next writer.
    let _ = fs::remove_file(lock);
    if let Some(dir) = created {
        // Fails, as it should, unless the folder is empty.
        let _ = fs::remove_dir(dir);
    }
}

impl Lock {
    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Claims the output folder `dir` (creating it) for this process; `option` names the setting
/// that chose it (e.g. `--out`) in the error of a folder another process is writing.
pub fn claim_folder(option: &str, dir: &Path) -> Result<Lock> {
    let created = (!dir.exists()).then(|| dir.to_path_buf());
    fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let lock = claim(option, dir, &dir.join(FOLDER_LOCK), created.as_deref());
    if lock.is_err() {
        if let Some(dir) = &created {
            let _ = fs::remove_dir(dir);
        }
    }
    lock
}

/// Claims the output file `file` (e.g. a sweep's CSV) for this process through the lock file
/// `.<name>.lock` beside it, creating its folder.
pub fn claim_file(option: &str, file: &Path) -> Result<Lock> {
    let mut name = OsString::from(".");
    name.push(file.file_name().unwrap_or(file.as_os_str()));
    name.push(".lock");
    let lock = file.with_file_name(name);
    if let Some(dir) = lock.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).map_err(|source| Error::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    claim(option, file, &lock, None)
}

/// This host's name, as lock files record it.
fn host() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The content of this process's lock file.
fn holder_text() -> String {
    let command: Vec<String> = std::env::args().collect();
    format!(
        "pid={}\nhost={}\ncommand={}\n",
        std::process::id(),
        host(),
        command.join(" ")
    )
}

/// The value of `key` in a lock file's `text`.
fn field<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
}

/// Whether the holder recorded in `text` is certainly gone: a process of this host that no
/// longer runs. An unreadable or foreign lock is not judged stale.
fn stale(text: &str) -> bool {
    let pid = field(text, "pid").and_then(|p| p.parse::<u32>().ok());
    let here = field(text, "host") == Some(host().as_str());
    let proc = Path::new("/proc");
    match pid {
        Some(pid) if here && proc.is_dir() => !proc.join(pid.to_string()).exists(),
        _ => false,
    }
}

/// The holder recorded in `text`, for messages.
fn describe(text: &str) -> String {
    let get = |k| field(text, k).unwrap_or("?");
    format!(
        "process {} on host {} (`{}`)",
        get("pid"),
        get("host"),
        get("command")
    )
}

/// Creates `lock` exclusively for this process, taking over a stale one; the output `target`
/// and the `option` that chose it name a refusal.
fn claim(option: &str, target: &Path, lock: &Path, created: Option<&Path>) -> Result<Lock> {
    let io = |source| Error::Io {
        path: lock.to_path_buf(),
        source,
    };
    let text = holder_text();
    // Two attempts: the second after taking over a stale lock.
    for _ in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut file) => {
                let registered = interrupt::claim(lock, created);
                let lock = Lock {
                    path: lock.to_path_buf(),
                    created: created.map(Path::to_path_buf),
                    _registered: registered,
                };
                file.write_all(text.as_bytes())
                    .and_then(|()| file.sync_all())
                    .map_err(io)?;
                return Ok(lock);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                let held = fs::read_to_string(lock).unwrap_or_default();
                if !stale(&held) {
                    return Err(Error::invalid(
                        option,
                        target.display(),
                        format!(
                            "an output no other run is writing: it is claimed by {} (lock \
                             file {}); wait for that run, choose another {option}, or remove \
                             the lock file if that process is gone",
                            describe(&held),
                            lock.display()
                        ),
                    ));
                }
                take_over(lock, &held).map_err(io)?;
                eprintln!(
                    "note: taking over {}: its holder, {}, no longer runs",
                    lock.display(),
                    describe(&held)
                );
            }
            Err(e) => return Err(io(e)),
        }
    }
    Err(Error::invalid(
        option,
        target.display(),
        format!(
            "an output no other run is claiming: {} was claimed again while its stale lock \
             was taken over",
            lock.display()
        ),
    ))
}

/// Removes the stale lock `lock` whose content was `held`. It is first moved aside under a
/// name of this process and removed only if it still holds `held`: a lock another process
/// created after it was judged stale is put back (the next `create_new` then refuses).
fn take_over(lock: &Path, held: &str) -> std::io::Result<()> {
    let aside = crate::io::output::unique_sibling(lock, "stale");
    if fs::rename(lock, &aside).is_err() {
        // Another process moved it first.
        return Ok(());
    }
    let moved = fs::read_to_string(&aside).unwrap_or_default();
    if moved != held {
        // Fails if yet another lock appeared meanwhile; that one then holds the claim.
        let _ = fs::hard_link(&aside, lock);
    }
    fs::remove_file(&aside)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_claim_is_refused_naming_the_holder_and_a_stale_one_taken_over() {
        let dir = std::env::temp_dir().join(format!("jointwear-lock-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        // A folder the claim created goes with it, if left empty.
        drop(claim_folder("--out", &dir).unwrap());
        assert!(!dir.exists());
        fs::create_dir_all(&dir).unwrap();
        let first = claim_folder("--out", &dir).unwrap();
        let held = fs::read_to_string(first.path()).unwrap();
        assert!(held.starts_with(&format!("pid={}\n", std::process::id())));
        let e = claim_folder("--out", &dir).unwrap_err().to_string();
        assert!(
            e.contains(&format!("process {}", std::process::id())),
            "{e}"
        );
        assert!(e.contains(FOLDER_LOCK), "{e}");
        drop(first);
        assert!(!dir.join(FOLDER_LOCK).exists());
        // A holder of this host that is gone (pid beyond Linux's largest, 2^22): taken over.
        let gone = format!("pid=4194305\nhost={}\ncommand=x\n", host());
        assert!(stale(&gone));
        fs::write(dir.join(FOLDER_LOCK), &gone).unwrap();
        let taken = claim_folder("--out", &dir).unwrap();
        assert_eq!(fs::read_to_string(taken.path()).unwrap(), held);
        // Another host's holder is never judged gone.
        assert!(!stale("pid=4194305\nhost=elsewhere.invalid\ncommand=x\n"));
        drop(taken);
        fs::remove_dir_all(&dir).unwrap();
    }
}
