//! Exclusive claims of outputs: a run's folder or a sweep's file belongs to one process while
//! it writes, so that two runs never mix their files; so do outputs kept elsewhere, through a
//! name that stands for them ([`claim_name`]: the paper's).
//!
//! A claim is a lock file beside the output, created with `O_EXCL` (it exists or it does not:
//! one process wins), holding the holder's process id, host, start time and command line. A
//! second writer is refused with an error naming them. A lock whose holder is no longer alive
//! on this host (a process killed with SIGKILL cannot remove it) is stale: it is taken over,
//! with a message, by exactly one of the processes that find it so at once (the one that
//! claims the takeover marker `<lock>.takeover-<pid>` beside it), which also removes the hidden
//! temporary files that holder left beside the lock in the middle of a write (unless its id is
//! another process's now, whose files of that id cannot be told from the holder's).
//! The lock is removed when its [`Lock`] drops, and by the interrupt handler
//! ([`crate::io::interrupt`]) on SIGINT, SIGTERM or SIGHUP, with the folder the claim created
//! if nothing was written into it.
//!
//! Whether a holder lives is told by `/proc/<pid>` on this host and, as an id is given again
//! to later processes, by the start time in `/proc/<pid>/stat`: a process of that id started
//! at another time than the lock records is not its holder (a holder killed long ago kept its
//! lock alive once another process had its id), and a holder that has ended but is not yet
//! reaped by its parent (a zombie) is gone. A lock written before start times were
//! recorded is judged by its id alone. A lock of another host (a shared file system) is never
//! taken over, as its holder cannot be seen from here; nor is one cut short or edited, which
//! cannot tell whether its holder runs: the refusal says why.

use crate::io::interrupt;
use crate::io::output::{create_dir_synced, read_bounded_text, temporary_of, MANIFEST};
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
    /// The outermost folder the claim created, removed with the lock, with those below it down
    /// to the output folder, if nothing was written into them.
    created: Option<PathBuf>,
    _registered: Option<interrupt::Temporary>,
    /// What the claim did that its user should hear of ([`Lock::notes`]).
    notes: Vec<String>,
    /// The process id of the gone holder whose stale lock the claim took over, if it did and
    /// no other process has that id now ([`Lock::taken_from`]).
    taken_from: Option<u32>,
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
    if let (Some(created), Some(dir)) = (created, lock.parent()) {
        remove_created(dir, created);
    }
}

/// Removes the folder `dir` and its ancestors up to `created` (the outermost one a claim
/// created), each only if empty: the first that is not stops it.
fn remove_created(dir: &Path, created: &Path) {
    for d in dir.ancestors() {
        // Fails, as it should, unless the folder is empty.
        if fs::remove_dir(d).is_err() || d == created {
            break;
        }
    }
}

/// Prints a claim's `notes` ([`Lock::notes`]) on stderr, as the programs show them.
pub fn print_notes(notes: &[String]) {
    for note in notes {
        eprintln!("note: {note}");
    }
}

impl Lock {
    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What claiming it did that its user should hear of, each without a `note: ` prefix: a
    /// stale lock taken over, the temporary files its gone holder left removed. The caller
    /// shows them where its user sees them: the program on stderr, Python on its
    /// `sys.stderr` (a notebook's, which the process's stderr does not reach).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The lock, its notes ([`Lock::notes`]) printed on stderr as the programs show them
    /// ([`print_notes`]).
    pub fn noted(self) -> Lock {
        print_notes(&self.notes);
        self
    }

    /// The process id of the gone holder whose stale lock this claim took over, if it did:
    /// the temporaries that holder left elsewhere than beside the lock are its claimer's to
    /// remove ([`remove_temporaries_of`]). None if another process has that id now: that
    /// process's temporaries of that id cannot be told from the holder's.
    pub fn taken_from(&self) -> Option<u32> {
        self.taken_from
    }

    /// Adds `notes` to what its user should hear of ([`Lock::notes`]): what its claimer did
    /// on taking it, such as removing temporaries elsewhere.
    pub(crate) fn note(&mut self, notes: impl IntoIterator<Item = String>) {
        self.notes.extend(notes);
    }
}

/// Claims the output folder `dir` (creating it) for this process; `option` names the setting
/// that chose it (e.g. `--out`) in the error of a folder another process is writing. A folder
/// into which a sweep is writing its file ([`claim_file`]'s live lock is in it) is refused too:
/// the run's outputs could replace the sweep's file. (Each side checks for the other after it
/// has claimed, so of a run and a sweep that start at once, one sees the other's lock.) The
/// claim of a name beside it ([`claim_name`]: the paper's outputs' in a crate's root) does not
/// refuse it, as no file is written at that name.
pub fn claim_folder(option: &str, dir: &Path) -> Result<Lock> {
    // The outermost folder the claim creates: `--out out/standard/longlife` in a fresh
    // checkout creates out/ too, and a refused command must not leave it behind.
    let created = (dir.ancestors())
        .filter(|d| !d.as_os_str().is_empty())
        .take_while(|d| !d.exists())
        .last()
        .map(Path::to_path_buf);
    create_dir_synced(dir)?;
    let lock = claim(option, dir, &dir.join(FOLDER_LOCK), created.as_deref()).and_then(|lock| {
        match live_file_claim(dir) {
            // (Dropping the lock releases the claim and the folder it created.)
            Some((file_lock, held)) => Err(Error::invalid(
                option,
                dir.display(),
                format!(
                    "a folder in which no other process claims a file: {} claims one there \
                     (a sweep's output) for {}, which this command's outputs could replace; \
                     wait for that process, or choose another {option}",
                    file_lock.display(),
                    describe(&held)
                ),
            )),
            None => Ok(lock),
        }
    });
    if lock.is_err() {
        if let Some(created) = &created {
            remove_created(dir, created);
        }
    }
    lock
}

/// A lock of [`claim_file`] in `dir` whose holder may still run, and its content (not one of
/// [`claim_name`], which says so: [`NAME_CLAIM`]).
fn live_file_claim(dir: &Path) -> Option<(PathBuf, String)> {
    let entries = fs::read_dir(dir).ok()?;
    entries.flatten().find_map(|e| {
        let name = e.file_name().into_string().ok()?;
        let file_lock = name.starts_with('.') && name.ends_with(".lock") && name != FOLDER_LOCK;
        file_lock
            .then(|| live_holder(&e.path()))?
            .filter(|held| field(held, "claims") != Some(NAME_CLAIM))
            .map(|held| (e.path(), held))
    })
}

/// The content of the lock file `lock` if its holder may still run (not [`gone`]); None if it
/// cannot be read as a lock ([`read_lock`]).
fn live_holder(lock: &Path) -> Option<String> {
    read_lock(lock).ok().filter(|held| gone(held).is_none())
}

/// Largest lock file read (bytes): it holds its holder's id, host and start time and its
/// command line, whose arguments the system bounds (2 MiB on Linux by default).
const MAX_LOCK_BYTES: u64 = 64 << 20;

/// The text of the lock file `lock`, a regular file of at most [`MAX_LOCK_BYTES`]
/// ([`read_bounded_text`]): a FIFO in its place made a claim wait for a writer.
fn read_lock(lock: &Path) -> Result<String> {
    let why = "its holder's id, host, start time and command line";
    read_bounded_text(lock, MAX_LOCK_BYTES, "a lock file", why)
}

/// Claims the output file `file` (e.g. a sweep's CSV) for this process through the lock file
/// `.<name>.lock` beside it, creating its folder. A file in the output folder of another
/// command (one that holds a [`MANIFEST`] or a folder lock) is refused: that command's next
/// write there may replace it, or it one of that command's outputs (a sweep's `--out
/// <ensemble folder>/summary.json` replaced the ensemble's summary, which the folder's
/// manifest still listed, and was lost itself to the ensemble still running, both exit 0).
pub fn claim_file(option: &str, file: &Path) -> Result<Lock> {
    let claimed = claim_at(option, file, None)?;
    // (Checked after the claim, as [`claim_folder`] checks for this lock after its own.)
    let lock = claimed.path();
    let dir = lock.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = dir.unwrap_or(Path::new("."));
    // A folder lock its process left (killed, or a crashed node) owns nothing.
    let owner = [dir.join(MANIFEST), dir.join(FOLDER_LOCK)]
        .into_iter()
        .find(|p| p != lock && p.exists() && (p.ends_with(MANIFEST) || live_holder(p).is_some()));
    match owner {
        None => Ok(claimed),
        Some(owner) => Err(Error::invalid(
            option,
            file.display(),
            format!(
                "a file outside the output folders of other commands: {} holds {}, so it is the \
                 output folder of `run`, `run --ensemble`, `longlife` or Python's `save` (a \
                 manifest), or `check` or `animate` is drawing there (a live folder lock), whose \
                 writes there may replace this file, or this file one of their outputs; likely \
                 cause: an {option} naming a file in such a folder (give a file in a folder of \
                 its own)",
                dir.display(),
                owner.file_name().unwrap_or_default().to_string_lossy()
            ),
        )),
    }
}

/// Claims `name`, a path no command writes, for this process through the lock file
/// `.<name>.lock` beside it, creating its folder: the claim of outputs kept elsewhere (the
/// paper's, [`crate::io::paper_claim`], whose lock lies in the crate root). Unlike
/// [`claim_file`], a manifest or folder lock beside it does not refuse it: no output is
/// written at `name`, so the command whose folder that is can neither replace it nor have one
/// of its outputs replaced by it ([`claim_file`] is this claim, then that check).
pub fn claim_name(option: &str, name: &Path) -> Result<Lock> {
    claim_at(option, name, Some(NAME_CLAIM))
}

/// What the lock of [`claim_name`] records as the kind of its claim (`claims=`): a name no
/// command writes, which [`claim_folder`] does not take for a file in its folder.
const NAME_CLAIM: &str = "name";

/// The claim of `name` through `.<name>.lock` beside it, creating its folder, its lock
/// recording `kind` ([`holder_text`]): [`claim_name`] and [`claim_file`]'s.
fn claim_at(option: &str, name: &Path, kind: Option<&str>) -> Result<Lock> {
    let mut lock_name = OsString::from(".");
    lock_name.push(name.file_name().unwrap_or(name.as_os_str()));
    lock_name.push(".lock");
    let lock = name.with_file_name(lock_name);
    if let Some(dir) = lock.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir_synced(dir)?;
    }
    claim_nested(option, name, &lock, None, kind, 0)
}

/// This host's name, as lock files record it.
fn host() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// The content of this process's lock file: its id, host, start time ([`start_time`], left
/// out where it cannot be read), the kind of its claim if it is not a folder's or a file's
/// (`claims=`, [`NAME_CLAIM`]) and command line, last, as it may hold line breaks (an
/// argument's). Its command line is read lossily: an argument that is not UTF-8 (a folder's
/// name) made `std::env::args` panic as a claim was taken.
fn holder_text(kind: Option<&str>) -> String {
    let command: Vec<String> = (std::env::args_os())
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let pid = std::process::id();
    let start = start_time(pid).map_or(String::new(), |t| format!("start={t}\n"));
    let kind = kind.map_or(String::new(), |k| format!("claims={k}\n"));
    format!(
        "pid={pid}\nhost={}\n{start}{kind}command={}\n",
        host(),
        command.join(" ")
    )
}

/// When process `pid` of this host started, in clock ticks after boot (field 22 of
/// `/proc/<pid>/stat`): with its id, it tells that process from a later one given the same
/// id. None if it cannot be read (the process has ended, or no `/proc`).
fn start_time(pid: u32) -> Option<u64> {
    stat_start(&fs::read_to_string(format!("/proc/{pid}/stat")).ok()?)
}

/// The fields of a `/proc/<pid>/stat` line after the command name, from the third (the
/// state) on: the name is in parentheses and may itself hold spaces and parentheses (hence
/// after the last `)`).
fn stat_fields(stat: &str) -> impl Iterator<Item = &str> {
    let after_name = stat.rsplit_once(')').map_or("", |(_, after)| after);
    after_name.split_whitespace()
}

/// The start time in a `/proc/<pid>/stat` line: its 22nd field, the 20th after the command
/// name ([`stat_fields`]).
fn stat_start(stat: &str) -> Option<u64> {
    stat_fields(stat).nth(19)?.parse().ok()
}

/// The value of `key` in a lock file's `text`: from the lines before its command line (which
/// comes last, [`holder_text`], and may hold any text), or the command line's first line.
fn field<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    for line in text.lines() {
        let (k, value) = line.split_once('=')?;
        if k == key {
            return Some(value);
        }
        if k == "command" {
            return None;
        }
    }
    None
}

/// What makes the lock file `text` other than [`holder_text`] writes one, if anything: one cut
/// short (its holder was killed while writing it, or is writing it now; it ends with its
/// command line and a line break), edited, or not this program's. Such a lock cannot tell
/// whether its holder runs, so it is never judged stale; the refusal says why.
fn flaw(text: &str) -> Option<String> {
    let start = field(text, "start");
    if text.is_empty() {
        Some("it is empty".into())
    } else if field(text, "command").is_none() || !text.ends_with('\n') {
        Some("it is cut short or edited: it does not end with its holder's command line".into())
    } else if field(text, "pid")
        .and_then(|p| p.parse::<u32>().ok())
        .is_none()
    {
        Some("its `pid` is missing or not a process id".into())
    } else if field(text, "host").is_none_or(str::is_empty) {
        Some("its `host` is missing".into())
    } else if start.is_some_and(|t| t.parse::<u64>().is_err()) {
        Some(format!(
            "its `start` ({}) is not a start time",
            start.unwrap_or_default()
        ))
    } else {
        None
    }
}

/// How the holder that a lock records is known to be gone ([`gone`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Gone {
    /// No process of its id runs on this host: the temporaries of that id are its own.
    Ended,
    /// A process of its id runs, but started at another time than the lock records: the id
    /// was given again to a later process, whose temporaries of that id cannot be told from
    /// the ones the holder left.
    Reused,
}

impl Gone {
    /// How a note says it of the holder.
    fn says(self) -> &'static str {
        match self {
            Gone::Ended => "no longer runs",
            Gone::Reused => {
                "no longer runs (its process id is another process's now, started at another \
                 time than the lock records; that id's temporary files are left alone, as they \
                 may be that process's)"
            }
        }
    }
}

/// Whether, and how, the holder recorded in the lock file `text` is certainly gone: a process
/// of this host that no longer runs (or has ended and waits to be reaped, [`ended`]), or whose
/// id a process started at another time has now.
/// A lock of another host, a flawed one ([`flaw`]) or one whose holder may still run is not
/// judged stale; nor is a lock without a start time (written before they were recorded) whose
/// id a process has, nor one whose process's start time cannot be read.
fn gone(text: &str) -> Option<Gone> {
    let proc = Path::new("/proc");
    if flaw(text).is_some() || field(text, "host") != Some(host().as_str()) || !proc.is_dir() {
        return None;
    }
    let pid: u32 = field(text, "pid")?.parse().ok()?;
    let Ok(stat) = fs::read_to_string(proc.join(format!("{pid}/stat"))) else {
        // (Read again: a process that ended between the two reads is gone.)
        return (!proc.join(pid.to_string()).exists()).then_some(Gone::Ended);
    };
    if ended(&stat, pid) {
        return Some(Gone::Ended);
    }
    let recorded: u64 = field(text, "start")?.parse().ok()?;
    (stat_start(&stat)? != recorded).then_some(Gone::Reused)
}

/// Whether the process `pid` whose `/proc/<pid>/stat` line is `stat` has ended and only waits
/// to be reaped by its parent (a zombie, state `Z`, or dead, `X`, with no other thread left):
/// a holder killed and not yet waited for, which keeps its entry and start time until then.
/// Its id is no other process's until then, so the temporaries of that id are its own.
fn ended(stat: &str, pid: u32) -> bool {
    let state = stat_fields(stat).next();
    // (A thread group's leader that ended while its other threads run shows as a zombie too.)
    let threads = fs::read_dir(format!("/proc/{pid}/task")).map_or(0, Iterator::count);
    matches!(state, Some("Z" | "X")) && threads <= 1
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

/// How many takeovers may nest: a takeover claims a marker ([`take_over`]), and a marker left
/// by a holder killed in the middle of its takeover is itself taken over, and so on. Each level
/// needs a kill within a takeover's microseconds; three is beyond any real history.
const MAX_TAKEOVERS: u32 = 3;

/// Creates `lock` exclusively for this process, taking over a stale one; the output `target`
/// and the `option` that chose it name a refusal.
fn claim(option: &str, target: &Path, lock: &Path, created: Option<&Path>) -> Result<Lock> {
    claim_nested(option, target, lock, created, None, 0)
}

/// [`claim`] of a lock recording `kind` ([`holder_text`]) within `depth` takeovers.
fn claim_nested(
    option: &str,
    target: &Path,
    lock: &Path,
    created: Option<&Path>,
    kind: Option<&str>,
    depth: u32,
) -> Result<Lock> {
    let io = |source| Error::Io {
        path: lock.to_path_buf(),
        source,
    };
    let text = holder_text(kind);
    // The content of a stale lock this process took over, and how its holder was gone.
    let mut taken: Option<(String, Gone)> = None;
    let mut notes = Vec::new();
    // Two attempts: the second after taking over a stale lock.
    for _ in 0..2 {
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(lock)
        {
            Ok(mut file) => {
                let registered = interrupt::claim(lock, created);
                let mut claimed = Lock {
                    path: lock.to_path_buf(),
                    created: created.map(Path::to_path_buf),
                    _registered: registered,
                    notes,
                    taken_from: None,
                };
                file.write_all(text.as_bytes())
                    .and_then(|()| file.sync_all())
                    .map_err(io)?;
                if let Some((held, Gone::Ended)) = &taken {
                    // (A takeover marker of a folder's lock starts with the lock's name.)
                    let folder = (lock.file_name().and_then(|n| n.to_str()))
                        .is_some_and(|n| n.starts_with(FOLDER_LOCK));
                    let stem = target.file_stem().and_then(|s| s.to_str());
                    claimed.taken_from = field(held, "pid").and_then(|p| p.parse().ok());
                    let dir = lock.parent().filter(|d| !d.as_os_str().is_empty());
                    let removed = claimed.taken_from.and_then(|pid| {
                        let dir = dir.unwrap_or(Path::new("."));
                        remove_temporaries_of(dir, pid, if folder { None } else { stem })
                    });
                    claimed.notes.extend(removed);
                }
                return Ok(claimed);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                // (One removed since, or unreadable, reads as empty: a flawed lock, refused
                // below. One that is no regular file, or too large, is no lock of this program.)
                let held = match read_lock(lock) {
                    Err(e @ Error::Parse { .. }) => return Err(e),
                    read => read.unwrap_or_default(),
                };
                let Some(how) = gone(&held) else {
                    let why = flaw(&held).map_or(String::new(), |flaw| {
                        format!(", which cannot tell whether its holder runs: {flaw}")
                    });
                    return Err(Error::invalid(
                        option,
                        target.display(),
                        format!(
                            "an output no other run is writing: it is claimed by {} (lock \
                             file {}{why}); wait for that run, choose another {option}, or \
                             remove the lock file if that process is gone",
                            describe(&held),
                            lock.display()
                        ),
                    ));
                };
                if take_over(option, target, lock, &held, depth, &mut notes)? {
                    notes.push(format!(
                        "taking over {}: its holder, {}, {}",
                        lock.display(),
                        describe(&held),
                        how.says()
                    ));
                    taken = Some((held, how));
                }
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

/// Removes the temporary files ([`crate::io::output`]'s hidden `.<stem>.tmp-<pid>-<n>` files)
/// in `dir` that the gone holder of a taken-over lock, process `pid`, left when it was killed
/// in the middle of a write, and says which: beside a folder's lock, every one in the folder
/// (the folder was the holder's alone); beside a file's lock, only the claimed file's
/// (`stem`), as the folder may hold other outputs. No process of that id runs on this host
/// (a takeover from an id that another process has now removes none), so no file of that id
/// is being written here. Best effort, as their content is never read: a file that cannot be
/// removed stays. Returns the note naming those removed, if any.
pub fn remove_temporaries_of(dir: &Path, pid: u32, stem: Option<&str>) -> Option<String> {
    let entries = fs::read_dir(dir).ok()?;
    let left = |name: &str| {
        temporary_of(name).is_some_and(|(s, p)| p == pid && stem.is_none_or(|stem| s == stem))
    };
    let mut removed: Vec<String> = entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            (left(&name) && fs::remove_file(e.path()).is_ok()).then_some(name)
        })
        .collect();
    (!removed.is_empty()).then(|| {
        removed.sort();
        format!(
            "removed {} temporary file(s) that process {pid} left unfinished in {}: {}",
            removed.len(),
            dir.display(),
            removed.join(", ")
        )
    })
}

/// Removes the stale lock `lock` whose content was `held`, if it still holds it; returns
/// whether this process removed it. Of the processes that judged it stale, only the one that
/// claims the marker `<lock>.takeover-<pid of the gone holder>` may remove it, and only after
/// reading it again under that claim: a lock is only ever removed by its holder or under
/// that marker, so what it reads then stays until it removes it, and a late taker finds the
/// winner's lock instead. The others are refused, naming the taker. `depth` counts the nested
/// takeovers of markers ([`MAX_TAKEOVERS`]); the notes of the marker's claim go to `notes`.
fn take_over(
    option: &str,
    target: &Path,
    lock: &Path,
    held: &str,
    depth: u32,
    notes: &mut Vec<String>,
) -> Result<bool> {
    if depth >= MAX_TAKEOVERS {
        return Err(Error::invalid(
            option,
            target.display(),
            format!(
                "an output whose stale lock can be taken over: {} and {MAX_TAKEOVERS} nested \
                 takeover markers beside it were all left by processes that no longer run; \
                 remove them",
                lock.display()
            ),
        ));
    }
    let mut name = lock.as_os_str().to_owned();
    name.push(format!(".takeover-{}", field(held, "pid").unwrap_or("?")));
    let marker = claim_nested(option, target, Path::new(&name), None, None, depth + 1)?;
    notes.extend_from_slice(marker.notes());
    let now = read_lock(lock).unwrap_or_default();
    if now != held || gone(&now).is_none() {
        // Taken over and released, or claimed afresh, since it was read.
        return Ok(false);
    }
    fs::remove_file(lock).map_err(|source| Error::Io {
        path: lock.to_path_buf(),
        source,
    })?;
    Ok(true)
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
        // So do the folders it created above it (a refused `longlife --until NaN` left out/
        // and out/standard/ in the working directory), and no folder that existed.
        drop(claim_folder("--out", &dir.join("a").join("b")).unwrap());
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
        let ended = format!("pid=4194305\nhost={}\ncommand=x\n", host());
        assert_eq!(gone(&ended), Some(Gone::Ended));
        fs::write(dir.join(FOLDER_LOCK), &ended).unwrap();
        let taken = claim_folder("--out", &dir).unwrap();
        assert_eq!(fs::read_to_string(taken.path()).unwrap(), held);
        drop(taken);
        // The temporary files the gone holder left mid-write go with its lock; another
        // process's temporaries, and names that only look alike, stay.
        let left = [".wear.tmp-4194305-3.csv", ".checkpoint.tmp-4194305-12"];
        let others = [
            format!(".wear.tmp-{}-1.csv", std::process::id()),
            ".wear.tmp-41943050-1.csv".into(),
            ".wear.tmp-4194305-x.csv".into(),
            // a live process's temporary of an output named `x.tmp-4194305-1.csv`
            format!(".x.tmp-4194305-1.tmp-{}-0.csv", std::process::id()),
            "wear.tmp-4194305-2.csv".into(),
            "wear.csv".into(),
        ];
        for name in left
            .iter()
            .copied()
            .chain(others.iter().map(String::as_str))
        {
            fs::write(dir.join(name), "x").unwrap();
        }
        fs::write(dir.join(FOLDER_LOCK), &ended).unwrap();
        let taken = claim_folder("--out", &dir).unwrap();
        for name in left {
            assert!(!dir.join(name).exists(), "{name} left behind");
        }
        for name in &others {
            assert!(dir.join(name).exists(), "{name} removed");
            fs::remove_file(dir.join(name)).unwrap();
        }
        drop(taken);
        // Of a file's lock (a sweep's), only that file's temporaries go: the folder may hold
        // other outputs.
        let file = dir.join("s.csv");
        let (own, other) = (".s.tmp-4194305-2.csv", ".t.tmp-4194305-1.csv");
        for name in [own, other] {
            fs::write(dir.join(name), "x").unwrap();
        }
        fs::write(dir.join(".s.csv.lock"), &ended).unwrap();
        let taken = claim_file("--out", &file).unwrap();
        assert!(!dir.join(own).exists() && dir.join(other).exists());
        fs::remove_file(dir.join(other)).unwrap();
        // Another host's holder is never judged gone.
        assert_eq!(
            gone("pid=4194305\nhost=elsewhere.invalid\ncommand=x\n"),
            None
        );
        drop(taken);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn three_racing_takers_of_a_stale_lock_leave_one_holder() {
        let dir = std::env::temp_dir().join(format!("jointwear-race-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let ended = format!("pid=4194305\nhost={}\ncommand=x\n", host());
        // Checked to fail: the former takeover (move the lock aside, put back one that was not
        // the stale one) left two holders in 6 of 2000 such rounds; 500 rounds (about 10 s)
        // catch that with a probability of 78 %.
        for round in 0..500 {
            fs::write(dir.join(FOLDER_LOCK), &ended).unwrap();
            let barrier = std::sync::Barrier::new(3);
            let claims: Vec<Result<Lock>> = std::thread::scope(|s| {
                let takers: Vec<_> = (0..3)
                    .map(|_| {
                        s.spawn(|| {
                            barrier.wait();
                            claim_folder("--out", &dir)
                        })
                    })
                    .collect();
                takers.into_iter().map(|t| t.join().unwrap()).collect()
            });
            let holders = claims.iter().filter(|c| c.is_ok()).count();
            assert_eq!(holders, 1, "round {round}: {claims:?}");
            // The losers were refused, naming a holder; no marker is left behind.
            drop(claims);
            assert_eq!(fs::read_dir(&dir).unwrap().count(), 0, "round {round}");
        }
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_start_time_is_read_after_the_last_parenthesis_of_the_command_name() {
        // A command name may hold spaces and parentheses; fields 3 to 21, then 22: 4242.
        let fields: Vec<String> = (3..=21).map(|i| i.to_string()).collect();
        let stat = format!("77 (a) b (c)) {} 4242 23 24\n", fields.join(" "));
        assert_eq!(stat_start(&stat), Some(4242));
        assert_eq!(stat_start("77 (a) b"), None);
        assert_eq!(stat_start("77 (x) S 1 2"), None);
        // This process's, as its lock records it.
        let me = start_time(std::process::id()).expect("this host has /proc");
        assert!(holder_text(None).contains(&format!("\nstart={me}\ncommand=")));
    }

    // Fails without telling a name's claim from a file's: a folder holding the live claim of
    // a name no command writes (the paper's outputs' lock in a crate's root) was refused to a
    // run, check or Python's save "as this command's outputs could replace" a file never
    // written, while that folder's command beside a running paper program was not.
    #[test]
    fn a_folder_is_not_refused_for_the_claim_of_a_name_beside_it() {
        let dir = std::env::temp_dir().join(format!("jointwear-name-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let name = claim_name("paper outputs", &dir.join("paper-outputs")).unwrap();
        let folder = claim_folder("--out", &dir).unwrap();
        drop(folder);
        drop(name);
        // A file's claim still refuses it.
        let file = claim_file("--out", &dir.join("sweep.csv")).unwrap();
        let e = claim_folder("--out", &dir).unwrap_err().to_string();
        assert!(e.contains(".sweep.csv.lock"), "{e}");
        drop(file);
        fs::remove_dir_all(&dir).unwrap();
    }

    // Fails without reading the holder's state: a holder killed but not yet waited for by its
    // parent (a zombie, as a notebook's killed subprocess stays until it is reaped) kept its
    // lock alive, refusing every writer, as its /proc entry and start time remain.
    #[test]
    fn a_lock_whose_holder_was_killed_but_not_reaped_is_stale() {
        let mut child = std::process::Command::new("sleep")
            .arg("60")
            .spawn()
            .unwrap();
        let pid = child.id();
        let start = start_time(pid).unwrap();
        let held = format!("pid={pid}\nhost={}\nstart={start}\ncommand=x\n", host());
        assert_eq!(gone(&held), None, "it runs");
        child.kill().unwrap();
        // Not waited for: a zombie until then.
        let zombie = (0..200).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(10));
            fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|s| {
                s.rsplit_once(')')
                    .is_some_and(|(_, r)| r.trim_start().starts_with('Z'))
            })
        });
        assert!(zombie);
        assert_eq!(gone(&held), Some(Gone::Ended));
        // A lock of an earlier version, without a start time, too.
        let earlier = format!("pid={pid}\nhost={}\ncommand=x\n", host());
        assert_eq!(gone(&earlier), Some(Gone::Ended));
        child.wait().unwrap();
        assert_eq!(gone(&held), Some(Gone::Ended));
    }

    // Fails without the start time: a lock whose holder was killed long ago stayed alive, and
    // refused every writer, once another process had been given its process id.
    #[test]
    fn a_lock_whose_process_id_another_process_has_now_is_taken_over() {
        let dir = std::env::temp_dir().join(format!("jointwear-reused-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let (pid, host) = (std::process::id(), host());
        let me = start_time(pid).unwrap();
        let lock = |start: &str| format!("pid={pid}\nhost={host}\n{start}command=x\n");
        // This process's id (it runs), recorded with another start time: a gone holder whose
        // id was given again. This process's temporaries of that id stay.
        let reused = lock(&format!("start={}\n", me + 1));
        assert_eq!(gone(&reused), Some(Gone::Reused));
        let mine = format!(".wear.tmp-{pid}-1.csv");
        fs::write(dir.join(&mine), "x").unwrap();
        fs::write(dir.join(FOLDER_LOCK), &reused).unwrap();
        let taken = claim_folder("--out", &dir).unwrap();
        assert_eq!(taken.taken_from(), None);
        let note = taken.notes().join("\n");
        assert!(
            note.contains("taking over") && note.contains("another process's now"),
            "{note}"
        );
        assert!(dir.join(&mine).exists(), "{note}");
        drop(taken);
        // The same start time, or none (a lock of an earlier version): its holder runs.
        for held in [lock(&format!("start={me}\n")), lock("")] {
            assert_eq!(gone(&held), None, "{held}");
            fs::write(dir.join(FOLDER_LOCK), &held).unwrap();
            let e = claim_folder("--out", &dir).unwrap_err().to_string();
            assert!(e.contains(&format!("claimed by process {pid}")), "{e}");
            assert!(!e.contains("cannot tell"), "{e}");
        }
        // A lock cut short or edited cannot tell whether its holder runs: refused, saying why,
        // even where its process has ended.
        let ended = format!("pid=4194305\nhost={host}\ncommand=x\n");
        for (held, why) in [
            (String::new(), "it is empty"),
            (ended[..ended.len() - 1].to_string(), "cut short"),
            (format!("pid=4194305\nhost={host}\nstart=12"), "cut short"),
            (ended.replace("4194305", "x"), "`pid`"),
            (ended.replace(&format!("host={host}"), "host="), "`host`"),
            (
                format!("pid={pid}\nhost={host}\nstart=1e3\ncommand=x\n"),
                "`start` (1e3)",
            ),
        ] {
            assert_eq!(gone(&held), None, "{held}");
            fs::write(dir.join(FOLDER_LOCK), &held).unwrap();
            let e = claim_folder("--out", &dir).unwrap_err().to_string();
            assert!(
                e.contains("cannot tell whether its holder runs") && e.contains(why),
                "{e}"
            );
            assert_eq!(fs::read_to_string(dir.join(FOLDER_LOCK)).unwrap(), held);
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}
