//! Atomic outputs (CSV tables and figures), and the crate's one CSV writer and reader.
//!
//! Every output is written to a temporary file in the same directory and renamed into place,
//! so a failed run never leaves a half-written CSV or PNG behind: the target either keeps its
//! previous content or receives the complete new one. The temporary is flushed to the disk
//! (`fsync`) before the rename and the directory after it, so that a power loss cannot leave
//! the new name on an empty or partial file, nor lose the rename of a file reported written;
//! the files of one run's folder ([`write_outputs`]) share one flush of the folder, after
//! their complete manifest (a flush costs milliseconds: 31 of them were a third of a run).
//!
//! Every CSV table of the crate is written here ([`write_csv`], [`write_rows`],
//! [`write_table`], [`GrowingTable`]) and read here ([`read_csv`], [`read_rows`],
//! [`parse_rows`]), in one dialect.

use std::cell::RefCell;
use std::ffi::OsString;
use std::fs::{self, File};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::io::interrupt;
use crate::{Error, Result};

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Distinguishes the temporary names of one process.
static TEMPORARY_COUNT: AtomicU64 = AtomicU64::new(0);

/// `tag-<pid>-<n>`: a part of a file name no other process, and no other call of this
/// process, uses.
fn unique_tag(tag: &str) -> String {
    let n = TEMPORARY_COUNT.fetch_add(1, Ordering::Relaxed);
    format!("{tag}-{}-{n}", std::process::id())
}

/// Hidden temporary sibling of `path`, unique to this process and call, that keeps the
/// extension (`dir/.name.tmp-<pid>-<n>.png` for `dir/name.png`), so writers that pick the
/// format from the extension still work and two processes never write the same temporary.
fn temp_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or(path.as_os_str());
    let mut name = OsString::from(".");
    name.push(stem);
    name.push(".");
    name.push(unique_tag("tmp"));
    if let Some(ext) = path.extension() {
        name.push(".");
        name.push(ext);
    }
    path.with_file_name(name)
}

/// The output stem and the writing process's id of a temporary file name of [`temp_path`]
/// (`.<stem>.tmp-<pid>-<n>` with an optional extension), read from the right (a stem may
/// itself hold `.tmp-`); None for any other name.
pub(crate) fn temporary_of(name: &str) -> Option<(&str, u32)> {
    let (stem, tag) = name.strip_prefix('.')?.rsplit_once(".tmp-")?;
    let (pid, rest) = tag.split_once('-')?;
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    let ext = &rest[digits..];
    let tail = ext.is_empty() || ext.strip_prefix('.').is_some_and(|e| !e.contains('.'));
    let pid_digits = !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit());
    if stem.is_empty() || digits == 0 || !tail || !pid_digits {
        return None;
    }
    Some((stem, pid.parse().ok()?))
}

/// Writes `path` atomically: creates the parent directory, lets `write` produce the content
/// at a temporary path next to `path`, then renames it into place. On failure the temporary
/// file is removed and `path` is left untouched. Inside [`write_outputs`], a file of its
/// folder is listed in the folder's manifest before it is renamed into place.
pub fn write_atomic(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    // A file of the folder a write of outputs is under way in: that write flushes the folder
    // once, with its final manifest.
    let batched = WRITING.with_borrow(|w| {
        w.as_ref()
            .is_some_and(|w| path.parent() == Some(w.dir.as_path()))
    });
    let flush = if batched {
        Flush::Data
    } else {
        Flush::DataAndFolder
    };
    replace(path, write, flush, || {
        WRITING.with_borrow_mut(|w| w.as_mut().map_or(Ok(()), |w| w.announce(path)))
    })
}

/// What [`replace`] flushes to the disk (`fsync`) so that a power loss keeps the file.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Flush {
    /// Nothing: the incomplete manifest of a write of outputs, which guards against an
    /// interrupted program, not a power loss (the complete one is flushed).
    Nothing,
    /// The file's content before the rename: a file of a write of outputs, whose folder is
    /// flushed once, with the complete manifest.
    Data,
    /// The content before the rename and the folder after it, so that the rename survives
    /// too.
    DataAndFolder,
}

/// [`write_atomic`], calling `before_rename` once the content is complete, before `path` is
/// replaced; its failure leaves `path` untouched as well.
fn replace(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<()>,
    flush: Flush,
    before_rename: impl FnOnce() -> Result<()>,
) -> Result<()> {
    if path.file_name().is_none() {
        return Err(io_error(
            path,
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "output path has no file name",
            ),
        ));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir_synced(dir)?;
    }
    let tmp = temp_path(path);
    // Registered while it exists, so that an interrupted program removes it.
    let _registered = interrupt::temporary(&tmp).ok_or_else(|| {
        io_error(
            path,
            std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted"),
        )
    })?;
    // A failure to write the temporary is a failure to write `path`: it names the output.
    let result = write(&tmp)
        .map_err(|e| match e {
            Error::Io { path: p, source } if p == tmp => io_error(path, source),
            e => e,
        })
        .and_then(|()| match flush {
            Flush::Nothing => Ok(()),
            _ => sync(&tmp).map_err(|e| io_error(path, e)),
        })
        .and_then(|()| before_rename())
        .and_then(|()| fs::rename(&tmp, path).map_err(|e| io_error(path, e)))
        .and_then(|()| match flush {
            Flush::DataAndFolder => sync_dir(path),
            _ => Ok(()),
        });
    if result.is_err() {
        // Best effort: the writer may have failed before creating the file.
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Flushes the file or directory at `path` to the disk (`fsync`): without it a file renamed
/// into place can be empty after a power loss, its data not yet written when the rename was.
fn sync(path: &Path) -> std::io::Result<()> {
    sync_file(&File::open(path)?, path)
}

/// Flushes `file`, open at `path`, to the disk (`path` is only recorded, in tests).
#[cfg_attr(not(test), allow(unused_variables))]
fn sync_file(file: &File, path: &Path) -> std::io::Result<()> {
    file.sync_all()?;
    #[cfg(test)]
    SYNCED.with_borrow_mut(|s| s.push(path.to_path_buf()));
    Ok(())
}

/// Flushes the directory of `path`, which was just renamed into it, so that the rename
/// itself survives a power loss. Unix only: elsewhere a directory cannot be opened as a file.
fn sync_dir(path: &Path) -> Result<()> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let dir = dir.unwrap_or(Path::new("."));
    if cfg!(unix) {
        sync(dir).map_err(|e| io_error(dir, e))?;
    }
    Ok(())
}

/// Creates the directory `dir` and its missing ancestors, each one created flushed into its
/// parent (`fsync` of the parent): without that a power loss can lose a new output folder,
/// and with it every file flushed into it. Nothing is flushed for a directory that exists.
pub fn create_dir_synced(dir: &Path) -> Result<()> {
    if dir.is_dir() {
        return Ok(());
    }
    let missing: Vec<&Path> = dir
        .ancestors()
        .filter(|d| !d.as_os_str().is_empty())
        .take_while(|d| !d.exists())
        .collect();
    fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    // Outermost first: each new directory's entry into the one that held it.
    missing.iter().rev().try_for_each(|d| sync_dir(d))
}

#[cfg(test)]
thread_local! {
    /// The paths this thread's [`sync`] flushed, in order (tests check what was flushed).
    static SYNCED: RefCell<Vec<PathBuf>> = const { RefCell::new(Vec::new()) };
}

/// 64-bit FNV-1a of `bytes`: a stable hash (the standard library's may change between
/// releases) for fingerprints and checksums of the files this crate writes.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// File listing the outputs of the last run written into a folder.
pub const MANIFEST: &str = "jointwear-manifest.txt";

/// How the name of a sweep file's last column starts: the column that names its sweep
/// (`crate::sweep::file`).
pub const SWEEP_COLUMN_PREFIX: &str = "jointwear sweep ";

/// Longest header line of a sweep file looked for ([`sweep_file_in`]): a sweep's header is at
/// most 64 KiB (`crate::sweep::file::MAX_SWEEP_FILE_BYTES`).
const MAX_SWEEP_HEADER_BYTES: u64 = 65536;

/// A sweep file in `dir`, if there is one: a regular file whose first line's last column
/// names a sweep ([`SWEEP_COLUMN_PREFIX`]). Only the first line of each file is read, at most
/// 64 KiB of it; what cannot be read is no sweep file. A command that writes a manifest into
/// `dir` must leave such a file alone: a sweep refuses a file beside a manifest, so a killed
/// or interrupted sweep's finished cases could no longer be resumed there.
pub fn sweep_file_in(dir: &Path) -> Option<PathBuf> {
    let header_names_a_sweep = |path: &Path| {
        let mut head = Vec::new();
        let read =
            File::open(path).and_then(|f| f.take(MAX_SWEEP_HEADER_BYTES).read_to_end(&mut head));
        let head = String::from_utf8_lossy(&head[..read.unwrap_or(0)]);
        let first = head.lines().next().unwrap_or_default();
        first
            .rsplit(',')
            .next()
            .is_some_and(|c| c.starts_with(SWEEP_COLUMN_PREFIX))
    };
    let entries = fs::read_dir(dir).ok()?;
    // (The first by name, so that a refusal names the same file every time.)
    entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        // Not a temporary of a sweep's file (a killed sweep leaves its own beside the file):
        // no sweep resumes from it, and named first ('.' sorts before letters) the refusal
        // told the user to move it instead of the file.
        .filter(|e| temporary_of(&e.file_name().to_string_lossy()).is_none())
        .map(|e| e.path())
        .filter(|p| header_names_a_sweep(p))
        .min()
}

/// The second line of the manifest of a write that has not completed.
const INCOMPLETE: &str = "# INCOMPLETE: the write of this run was interrupted or failed; the \
                          files below are its own and the previous run's, which the next \
                          complete write into this folder removes";

/// The second line of the manifest of a complete write.
const COMPLETE: &str = "# the files of this run; other files here are not from it";

thread_local! {
    /// The [`write_outputs`] under way on this thread, to which [`write_atomic`] announces
    /// its files.
    static WRITING: RefCell<Option<Writing>> = const { RefCell::new(None) };
}

/// A write of outputs into a folder under way ([`write_outputs`]).
struct Writing {
    dir: PathBuf,
    /// The manifest's first line.
    title: String,
    /// Whether a file name is one the program writes into output folders.
    owned: fn(&str) -> bool,
    /// The names its manifest lists: the previous write's, then this one's as they come.
    listed: Vec<String>,
    /// This write's names, in the order first written.
    written: Vec<String>,
    /// Whether the manifest says yet that the write is incomplete.
    marked: bool,
}

impl Writing {
    /// Lists `path`, about to be written, in the incomplete manifest first when it is a new
    /// file of the folder, so that no file of the program is ever in the folder unlisted: an
    /// interrupted write leaves every file it wrote or replaced to the next one to remove.
    fn announce(&mut self, path: &Path) -> Result<()> {
        if path.parent() != Some(self.dir.as_path()) {
            return Ok(());
        }
        let name = path.file_name().and_then(|n| n.to_str());
        let Some(name) = name.filter(|n| (self.owned)(n)) else {
            // A writer's name missing from the folder's names would never be removed.
            return Err(Error::invalid(
                "output file",
                path.display(),
                "one of the names output folders hold (the list of their writers' files)",
            ));
        };
        if !self.written.iter().any(|n| n == name) {
            self.written.push(name.to_owned());
        }
        if self.marked && self.listed.iter().any(|n| n == name) {
            return Ok(());
        }
        if !self.listed.iter().any(|n| n == name) {
            self.listed.push(name.to_owned());
        }
        self.marked = true;
        self.save(INCOMPLETE, &self.listed, Flush::Nothing)
    }

    /// Replaces the manifest, atomically, by one headed by the title and `status` that lists
    /// `names`, flushed as `flush` says.
    fn save(&self, status: &str, names: &[String], flush: Flush) -> Result<()> {
        let mut text = format!("# {}\n{status}\n", self.title);
        for n in names {
            text.push_str(n);
            text.push('\n');
        }
        let manifest = self.dir.join(MANIFEST);
        replace(
            &manifest,
            |tmp| fs::write(tmp, &text).map_err(|e| io_error(tmp, e)),
            flush,
            || Ok(()),
        )
    }
}

/// The file names the manifest of `dir` lists (none without a manifest), each one that
/// `owned` says the program writes into output folders; any other line but a comment (`#`)
/// or an empty one is an error: the manifest was edited, or is not this program's, and a
/// rerun would remove what it lists. Never a dot-file, a checkpoint, a lock or a file
/// outside `dir`, whatever the manifest says.
pub fn read_manifest(dir: &Path, owned: fn(&str) -> bool) -> Result<Vec<String>> {
    let manifest = dir.join(MANIFEST);
    let Some(text) = manifest_text(dir)? else {
        return Ok(Vec::new());
    };
    let mut names = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.is_empty() {
            continue;
        }
        if !owned(line) {
            return Err(Error::invalid(
                format!("line {} of {}", i + 1, manifest.display()),
                line,
                "the name of a file this program writes into an output folder: the manifest \
                 was edited or is not this program's, and a new run into the folder removes \
                 the files it lists (remove the line, or the manifest to leave every file \
                 here alone)",
            ));
        }
        names.push(line.to_owned());
    }
    Ok(names)
}

/// The title at the top of the manifest of `dir` (the command line of the write that made
/// it, as [`write_outputs`] was given it, control characters escaped), None without a
/// manifest or without a title line (`# ` first).
pub fn manifest_title(dir: &Path) -> Result<Option<String>> {
    let text = manifest_text(dir)?;
    let first = text.as_deref().and_then(|t| t.lines().next());
    Ok(first.and_then(|l| l.strip_prefix("# ")).map(str::to_owned))
}

/// Largest manifest read back (bytes): its lines are a command line, which the system bounds
/// (2 MiB of arguments on Linux by default), and the names of a folder's files, at most 100
/// bytes each. A larger file is not a manifest, and reading it whole would only fill the
/// memory (one linked to `/dev/zero` did).
const MAX_MANIFEST_BYTES: u64 = 64 << 20;

/// The text of the manifest of `dir`, None if there is none; a regular file of at most
/// [`MAX_MANIFEST_BYTES`] ([`read_bounded_text`]: a FIFO in its place made a run wait).
fn manifest_text(dir: &Path) -> Result<Option<String>> {
    let manifest = dir.join(MANIFEST);
    let why = "a command line and the names of a folder's files";
    match read_bounded_text(&manifest, MAX_MANIFEST_BYTES, "a manifest", why) {
        Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => Ok(None),
        read => read.map(Some),
    }
}

/// `title` on one line: its control characters (a line break) escaped, so that no text of a
/// title (a scene's, a `--set` value) becomes a line of the manifest.
fn one_line(title: &str) -> String {
    title
        .chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Writes the outputs of one run into `dir` so that old and new outputs never mix and no
/// output is ever left unlisted: `write` writes through [`write_atomic`] on this thread;
/// before it replaces the first file, the folder's [`MANIFEST`] is replaced by one marked
/// incomplete that lists the previous write's files, and each new file is added to it before
/// it appears; then the files of the previous write this one did not rewrite are removed, and
/// the manifest, headed by `title`, lists this write's files alone. An interrupted or failed
/// write thus leaves a manifest listing every file it and the one before wrote, which the
/// next write removes. Only names `owned` accepts, the names of the program's outputs, are
/// ever written or removed ([`read_manifest`]); files this program did not write are left
/// alone.
pub fn write_outputs<T>(
    dir: &Path,
    title: &str,
    owned: fn(&str) -> bool,
    write: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let writing = Writing {
        dir: dir.to_path_buf(),
        title: one_line(title),
        owned,
        listed: read_manifest(dir, owned)?,
        written: Vec::new(),
        marked: false,
    };
    WRITING.with_borrow_mut(|w| *w = Some(writing));
    let result = write();
    let writing = WRITING.with_borrow_mut(Option::take);
    let value = result?;
    // Taken by a write of outputs nested in this one, which would have listed this one's
    // files in its own folder's manifest.
    let writing = writing.ok_or_else(|| {
        Error::invalid(
            "output folder",
            dir.display(),
            "one folder written at a time on a thread",
        )
    })?;
    for stale in (writing.listed.iter()).filter(|n| !writing.written.contains(n)) {
        let path = dir.join(stale);
        if path.is_file() {
            fs::remove_file(&path).map_err(|e| io_error(&path, e))?;
        }
    }
    // Its folder flushed after the complete manifest's rename: with it every rename and
    // removal of this write survives a power loss (each file's content was flushed before).
    writing.save(COMPLETE, &writing.written, Flush::DataAndFolder)?;
    Ok(value)
}

/// Why `dir` cannot become a directory of outputs, if it cannot: it must be a writable
/// directory, or be creatable (its nearest existing ancestor is a writable directory).
/// Nothing is created but a probe file, removed at once.
fn unwritable_dir(dir: &Path) -> Option<String> {
    // The parent of a relative one-component path is "", the working directory.
    let existing = dir
        .ancestors()
        .map(|a| {
            if a.as_os_str().is_empty() {
                Path::new(".")
            } else {
                a
            }
        })
        .find(|a| a.exists())
        .unwrap_or(Path::new("."));
    if !existing.is_dir() {
        return Some(format!("{} is an existing file", existing.display()));
    }
    let probe = existing.join(format!(".jointwear-write-test-{}", std::process::id()));
    let opened = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe);
    match opened {
        Ok(_) => {
            let _ = fs::remove_file(&probe);
            None
        }
        Err(e) => Some(format!("{} cannot be written: {e}", existing.display())),
    }
}

/// Checks, before any work is done, that `dir` can receive the outputs of a run (see
/// `unwritable_dir`); `option` names the setting in the error (e.g. `--out`), which is bad
/// input ([`Error::Invalid`]). An empty path is refused: it names no folder, and its files
/// went into the working directory (Python's `save("")`).
pub fn check_output_dir(option: &str, dir: &Path) -> Result<()> {
    if dir.as_os_str().is_empty() {
        return Err(Error::invalid(
            option,
            "\"\"",
            "a folder's path (an empty one would write into the working directory)",
        ));
    }
    // (Only from Python: a command line cannot hold one. It failed later as an I/O error.)
    if dir.as_os_str().as_encoded_bytes().contains(&0) {
        return Err(Error::invalid(
            option,
            dir.display(),
            "a folder's path without a NUL character, which no file name can hold",
        ));
    }
    match unwritable_dir(dir) {
        None => Ok(()),
        Some(why) => Err(Error::invalid(
            option,
            dir.display(),
            format!("a directory that can be created and written ({why})"),
        )),
    }
}

/// Like [`check_output_dir`] for an output file: `file` must not be a directory, and its
/// directory must be writable or creatable.
pub fn check_output_file(option: &str, file: &Path) -> Result<()> {
    let why = if file.is_dir() || file.file_name().is_none() {
        Some("it is a directory".to_string())
    } else {
        unwritable_dir(file.parent().unwrap_or(Path::new(".")))
    };
    match why {
        None => Ok(()),
        Some(why) => Err(Error::invalid(
            option,
            file.display(),
            format!("a file in a directory that can be created and written ({why})"),
        )),
    }
}

/// The text of the file at `path`, a regular file of at most `limit` bytes: a `what` (`a
/// scene file`), which may hold that much because `why` (said when it holds more). Anything
/// else is refused before it is read, so that a device (`/dev/zero`) or a FIFO cannot make
/// the reader wait or fill the memory; the read itself is bounded too, in case the file grows
/// after the check.
pub fn read_bounded_text(path: &Path, limit: u64, what: &str, why: &str) -> Result<String> {
    let refuse = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let too_large = |bytes: u64| {
        refuse(format!(
            "{bytes} bytes or more, beyond the {limit} bytes {what} may hold ({why}; likely \
             cause: not {what})"
        ))
    };
    let meta = fs::metadata(path).map_err(|e| io_error(path, e))?;
    if !meta.is_file() {
        return Err(refuse(format!(
            "not a regular file (a directory, device or FIFO), which {what} is"
        )));
    }
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::new();
    File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(|e| io_error(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| refuse(format!("not UTF-8 text: {e}")))
}

/// Writes `text` to `path`, atomically (a sidecar `README.txt`, say).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_bytes(path, text.as_bytes())
}

/// Writes `bytes` to `path`, atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |tmp| {
        fs::write(tmp, bytes).map_err(|e| io_error(tmp, e))
    })
}

/// Writes `value` to `path` as pretty-printed JSON, atomically. Floats are written with the
/// fewest significant digits that parse back to the identical `f64` (serde_json's format);
/// NaN and infinities, which JSON cannot hold, become `null`.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    text.push('\n');
    write_text(path, &text)
}

/// Writes `value` as compact JSON into a new file at `path`, flushed: a failure of the file
/// system (a full disk) is an [`Error::Io`] naming the file, never a parse error.
pub fn write_json_file(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    serde_json::to_writer(&mut w, value).map_err(|e| {
        if e.is_io() {
            io_error(path, e.into())
        } else {
            Error::Parse {
                path: path.to_path_buf(),
                message: format!("cannot be written as JSON: {e}"),
            }
        }
    })?;
    // An error of the last buffered bytes shows only here (dropping would lose it).
    w.flush().map_err(|e| io_error(path, e))
}

// ---------------------------------------------------------------------------------------------
// CSV: every table the crate writes goes through `csv_writer`, every one it reads through
// `csv_reader`, so that all share one dialect.

/// The writer of every CSV table: the `csv` crate's dialect (comma separated, fields quoted only
/// where needed, `\n` line ends), every record as long as the first.
fn csv_writer<W: Write>(sink: W) -> csv::Writer<W> {
    csv::WriterBuilder::new().from_writer(sink)
}

/// The reader of every CSV table, in the dialect of [`csv_writer`]; `flexible` takes rows of
/// any length (the caller picks the complete ones), otherwise another length is an error.
fn csv_reader<R: Read>(source: R, flexible: bool) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .flexible(flexible)
        .from_reader(source)
}

fn csv_error(path: &Path, err: csv::Error) -> Error {
    let message = err.to_string();
    match err.into_kind() {
        csv::ErrorKind::Io(source) => io_error(path, source),
        _ => Error::Parse {
            path: path.to_path_buf(),
            message,
        },
    }
}

/// `x` as the shortest decimal text that parses back to the identical `f64`: plain (`0.72`,
/// `1500`, `-0.25`) or in e-notation (`1.25e-9`, `2e5`, `-3e-3`), whichever has fewer characters,
/// plain on a tie. Both of Rust's float formats print the same fewest significant digits that
/// round-trip; plain alone would spell `1e-300` with 300 zeros, e-notation alone a time of
/// 0.72 s as `7.2e-1`. NaN and infinities are written `NaN`, `inf` and `-inf`. Every number
/// of every CSV the crate writes is formatted here.
pub fn number(x: f64) -> String {
    let mut text = String::new();
    push_number(&mut text, x);
    text
}

/// [`number`]`(x)`, or an empty field for NaN: what a CSV writes for a value that was not
/// measured (nothing recorded, no finite member), never the text `NaN`.
pub fn number_or_empty(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        number(x)
    }
}

/// Appends [`number`]`(x)` to `out`. Formats once, in e-notation, and spells the plain form
/// from its digits and exponent when that is not longer: a recorded run writes millions of
/// numbers, and formatting each twice into two fresh strings was a sixth of its instructions.
pub fn push_number(out: &mut String, x: f64) {
    use std::fmt::Write as _;
    let start = out.len();
    // Writing into a String cannot fail.
    let _ = write!(out, "{x:e}");
    if !x.is_finite() {
        return;
    }
    // `{:e}` of a finite f64: an optional `-`, one digit, an optional `.` and more digits, `e`
    // and a decimal exponent; at most 17 significant digits.
    let sci = &out.as_bytes()[start..];
    let sign = usize::from(sci[0] == b'-');
    let e_at = sci.iter().rposition(|&b| b == b'e').unwrap_or(sci.len());
    let mut digits = [0u8; 17];
    let mut n = 0;
    for &b in sci[sign..e_at].iter().filter(|b| b.is_ascii_digit()) {
        digits[n] = b;
        n += 1;
    }
    let e: i64 = (out[start + e_at + 1..].parse()).unwrap_or_default();
    let n_len = n as i64;
    let plain_len = if e < 0 {
        n_len + 1 - e // "0.", then −e − 1 zeros and the digits
    } else if e >= n_len - 1 {
        e + 1 // the digits, then zeros
    } else {
        n_len + 1 // the digits with a point among them
    };
    if ((sci.len() - sign) as i64) < plain_len {
        return;
    }
    out.truncate(start + sign);
    let digits = std::str::from_utf8(&digits[..n]).unwrap_or_default();
    if e < 0 {
        out.push_str("0.");
        out.extend(std::iter::repeat_n('0', (-e - 1) as usize));
        out.push_str(digits);
    } else if e >= n_len - 1 {
        out.push_str(digits);
        out.extend(std::iter::repeat_n('0', (e - n_len + 1) as usize));
    } else {
        let (int, frac) = digits.split_at(e as usize + 1);
        out.push_str(int);
        out.push('.');
        out.push_str(frac);
    }
}

/// Writes equally long `columns` under `header` as CSV, atomically. Numbers are written by
/// [`number`]: the shortest text that parses back to the identical `f64`.
pub fn write_csv(path: &Path, header: &[&str], columns: &[&[f64]]) -> Result<()> {
    let field = |what: &str| format!("{} {what}", path.display());
    if header.len() != columns.len() {
        return Err(Error::invalid(
            field("header"),
            format!("{} names", header.len()),
            format!("one name per column ({} columns)", columns.len()),
        ));
    }
    let rows = columns.first().map_or(0, |c| c.len());
    if let Some((i, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != rows) {
        return Err(Error::invalid(
            field(&format!("column `{}`", header[i])),
            format!("{} values", c.len()),
            format!("{rows} values, like column `{}`", header[0]),
        ));
    }
    // Each number is formatted into one reused buffer and handed to the writer as a field:
    // no string per number or vector per row.
    let mut field = String::new();
    write_records(path, None, header, |w| {
        for row in 0..rows {
            for c in columns {
                field.clear();
                push_number(&mut field, c[row]);
                w.write_field(&field)?;
            }
            w.write_record(None::<&[u8]>)?;
        }
        Ok(())
    })
}

/// Writes text rows under `header` as CSV, atomically (for tables with text columns).
pub fn write_rows(
    path: &Path,
    header: &[impl AsRef<str>],
    rows: impl IntoIterator<Item = Vec<String>>,
) -> Result<()> {
    write_table(path, None, header, rows)
}

/// Like [`write_rows`], with `first_line` (e.g. a `#` line naming what the table holds) written
/// as is before the header.
pub fn write_table(
    path: &Path,
    first_line: Option<&str>,
    header: &[impl AsRef<str>],
    rows: impl IntoIterator<Item = Vec<String>>,
) -> Result<()> {
    write_records(path, first_line, header, |w| {
        rows.into_iter()
            .try_for_each(|record| w.write_record(&record))
    })
}

/// Writes `first_line` (if any) and `header`, then the records `body` writes, atomically.
fn write_records(
    path: &Path,
    first_line: Option<&str>,
    header: &[impl AsRef<str>],
    body: impl FnOnce(&mut csv::Writer<File>) -> csv::Result<()>,
) -> Result<()> {
    write_atomic(path, |tmp| {
        let mut file = File::create(tmp).map_err(|e| io_error(tmp, e))?;
        if let Some(line) = first_line {
            file.write_all(format!("{line}\n").as_bytes())
                .map_err(|e| io_error(tmp, e))?;
        }
        let mut w = csv_writer(file);
        w.write_record(header.iter().map(AsRef::as_ref))
            .map_err(|e| csv_error(tmp, e))?;
        body(&mut w).map_err(|e| csv_error(tmp, e))?;
        w.flush().map_err(|e| io_error(tmp, e))
    })
}

/// A CSV table that grows a row at a time (a sweep's results as its cases finish): written
/// atomically with its first rows by [`GrowingTable::create`], then appended to by
/// [`GrowingTable::append`], each row in a single write that is flushed to the disk at once, so that rows
/// appended from parallel threads never interleave and an interrupted program keeps every row
/// appended before.
#[derive(Debug)]
pub struct GrowingTable {
    path: PathBuf,
    file: Mutex<File>,
}

impl GrowingTable {
    /// Writes the table at `path` as [`write_table`] does, then opens it for appending.
    pub fn create(
        path: &Path,
        first_line: Option<&str>,
        header: &[impl AsRef<str>],
        rows: impl IntoIterator<Item = Vec<String>>,
    ) -> Result<GrowingTable> {
        write_table(path, first_line, header, rows)?;
        let file = fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| io_error(path, e))?;
        Ok(GrowingTable {
            path: path.to_path_buf(),
            file: Mutex::new(file),
        })
    }

    /// Appends `row` (one CSV record, in the dialect of [`write_rows`]) in a single write.
    pub fn append(&self, row: &[String]) -> Result<()> {
        let failed = |e: String| Error::invalid("CSV row", row.join(","), e);
        let mut w = csv_writer(Vec::new());
        w.write_record(row).map_err(|e| failed(e.to_string()))?;
        let line = w.into_inner().map_err(|e| failed(e.to_string()))?;
        let mut file = self.file.lock().unwrap_or_else(|e| e.into_inner());
        // Flushed to the disk: a finished row must survive a power loss too.
        file.write_all(&line)
            .and_then(|()| sync_file(&file, &self.path))
            .map_err(|e| io_error(&self.path, e))
    }

    /// The table's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Reads any CSV as text: returns the header and the rows.
pub fn read_rows(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    read_table(path, file, false)
}

/// Reads CSV text of the file at `path` (e.g. what follows a first line [`write_table`] wrote)
/// as [`read_rows`] does, except that rows may have any length: the caller picks the complete
/// ones.
pub fn parse_rows(path: &Path, text: &str) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    read_table(path, text.as_bytes(), true)
}

/// The header and the rows of the CSV `source` (the file at `path`).
fn read_table<R: Read>(
    path: &Path,
    source: R,
    flexible: bool,
) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r = csv_reader(source, flexible);
    let header = r
        .headers()
        .map_err(|e| csv_error(path, e))?
        .iter()
        .map(str::to_owned)
        .collect();
    let rows = r
        .records()
        .map(|rec| {
            rec.map(|rec| rec.iter().map(str::to_owned).collect())
                .map_err(|e| csv_error(path, e))
        })
        .collect::<Result<Vec<Vec<String>>>>()?;
    Ok((header, rows))
}

/// Reads a CSV written by [`write_csv`]: returns the header and the columns.
pub fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>)> {
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    let mut r = csv_reader(file, false);
    let header: Vec<String> = r
        .headers()
        .map_err(|e| csv_error(path, e))?
        .iter()
        .map(str::to_owned)
        .collect();
    let mut columns = vec![Vec::new(); header.len()];
    for (line, record) in r.records().enumerate() {
        let record = record.map_err(|e| csv_error(path, e))?;
        for (column, field) in columns.iter_mut().zip(record.iter()) {
            let value = field.trim().parse().map_err(|_| Error::Parse {
                path: path.to_path_buf(),
                message: format!("data row {}: `{field}` is not a number", line + 1),
            })?;
            column.push(value);
        }
    }
    Ok((header, columns))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_is_fnv1a_so_fingerprints_agree_across_builds() {
        // The published FNV-1a 64 test vectors.
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// An atomic write flushes its temporary to the disk before renaming it into place and
    /// the directory after, so that a power loss leaves neither an empty file under the new
    /// name nor the rename lost. Would fail without either `fsync`.
    #[test]
    fn a_committed_output_is_flushed_before_and_after_its_rename() {
        let dir = std::env::temp_dir().join(format!("jointwear-synced-{}", std::process::id()));
        let path = dir.join("a.csv");
        // (A folder this write creates is flushed too: a_new_output_folder_is_flushed_….)
        fs::create_dir_all(&dir).unwrap();
        SYNCED.with_borrow_mut(Vec::clear);
        write_text(&path, "x\n").unwrap();
        let synced = SYNCED.with_borrow_mut(std::mem::take);
        assert_eq!(synced.len(), 2, "{synced:?}");
        let file = synced[0].file_name().and_then(|n| n.to_str()).unwrap();
        assert_eq!(temporary_of(file).map(|(stem, _)| stem), Some("a"));
        assert_eq!(synced[1], dir);
        assert_eq!(fs::read_to_string(&path).unwrap(), "x\n");
        // An appended row (a sweep's finished case) is flushed as it is written.
        let table = GrowingTable::create(&path, None, &["a"], []).unwrap();
        SYNCED.with_borrow_mut(Vec::clear);
        table.append(&["1".into()]).unwrap();
        assert_eq!(SYNCED.with_borrow_mut(std::mem::take), [path.as_path()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A run's folder of outputs is flushed once, after its complete manifest, and each file's
    /// content before its rename; the incomplete manifest, which guards against an interrupted
    /// program, is not flushed. Would fail with every rename followed by a flush of the folder
    /// (three more) or the incomplete manifest flushed (two more).
    #[test]
    fn a_folder_of_outputs_is_flushed_once_after_its_manifest() {
        let dir = std::env::temp_dir().join(format!("jointwear-batched-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        SYNCED.with_borrow_mut(Vec::clear);
        write_outputs(
            &dir,
            "test",
            |_| true,
            || {
                write_text(&dir.join("a.csv"), "a\n")?;
                write_text(&dir.join("b.csv"), "b\n")
            },
        )
        .unwrap();
        let synced = SYNCED.with_borrow_mut(std::mem::take);
        let stem = |p: &PathBuf| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            temporary_of(name).map(|(stem, _)| stem.to_owned())
        };
        let stems: Vec<Option<String>> = synced[..3].iter().map(stem).collect();
        let want = ["a", "b", "jointwear-manifest"].map(|s| Some(s.to_owned()));
        assert_eq!(stems, want, "{synced:?}");
        assert_eq!(synced[3..], [dir.as_path()], "{synced:?}");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A write into a folder that does not exist creates it flushed into its parent, each new
    /// level, so that a power loss cannot lose the folder of the files flushed into it. Would
    /// fail with the folder made by a bare `create_dir_all` (only the file's folder flushed).
    #[test]
    fn a_new_output_folder_is_flushed_into_its_parent() {
        let dir = std::env::temp_dir().join(format!("jointwear-new-dir-{}", std::process::id()));
        let path = dir.join("a").join("b.csv");
        SYNCED.with_borrow_mut(Vec::clear);
        write_text(&path, "x\n").unwrap();
        let synced = SYNCED.with_borrow_mut(std::mem::take);
        fs::remove_dir_all(&dir).unwrap();
        let parent = dir.parent().unwrap().to_path_buf();
        assert_eq!(synced[..2], [parent, dir.clone()], "{synced:?}");
        assert_eq!(synced.len(), 4, "{synced:?}");
        assert_eq!(synced[3], dir.join("a"));
    }

    /// A sweep file beside a temporary of its own, which a killed sweep leaves, is the one
    /// named. Would fail with the temporary named, first by name.
    #[test]
    fn the_sweep_file_named_in_a_folder_is_not_a_temporary() {
        let dir = std::env::temp_dir().join(format!("jointwear-sweep-in-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let header = format!("case,a,{SWEEP_COLUMN_PREFIX}fingerprint=0\n0,1,\n");
        fs::write(dir.join(".s.tmp-123-1.csv"), &header).unwrap();
        assert_eq!(sweep_file_in(&dir), None);
        fs::write(dir.join("s.csv"), &header).unwrap();
        let found = sweep_file_in(&dir);
        fs::remove_dir_all(&dir).unwrap();
        assert_eq!(found, Some(dir.join("s.csv")));
    }

    /// A full disk is a write error naming the file. Would fail with the error of
    /// `serde_json::to_writer` passed on as a parse error, or with the final flush left to
    /// `BufWriter`'s drop (which ignores its error).
    #[test]
    fn a_full_disk_is_a_write_error_naming_the_file() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return; // not Linux
        }
        let big = vec![1.5_f64; 10_000];
        for value in [&big[..], &big[..1]] {
            match write_json_file(full, &value) {
                Err(Error::Io { path, source }) => {
                    assert_eq!(path, full);
                    assert_eq!(source.raw_os_error(), Some(28), "ENOSPC: {source}");
                }
                other => panic!("{other:?}"),
            }
        }
    }

    /// A write of outputs lists every file of the folder's previous write and each of its
    /// own before it appears, under a manifest marked incomplete; a failed write keeps it, and
    /// the next complete write removes what it does not rewrite. Would fail with the manifest
    /// removed first and written at the end (the previous write's b.csv, and c.csv, never
    /// removed), or with a title's line break written as one.
    #[test]
    fn every_output_is_listed_before_it_is_in_the_folder() {
        let dir = std::env::temp_dir().join(format!("jointwear-listed-{}", std::process::id()));
        let owned: fn(&str) -> bool = |n| n.ends_with(".csv");
        let write = |name: &str| write_text(&dir.join(name), name);
        let names = || read_manifest(&dir, owned).unwrap();
        let text = || fs::read_to_string(dir.join(MANIFEST)).unwrap();
        write_outputs(&dir, "first", owned, || write("a.csv").and(write("b.csv"))).unwrap();
        assert_eq!(names(), ["a.csv", "b.csv"]);
        let stopped = write_outputs(&dir, "second\nc.csv\r", owned, || {
            write("c.csv")?;
            assert!(text().starts_with(&format!("# second\\nc.csv\\r\n{INCOMPLETE}\n")));
            assert_eq!(names(), ["a.csv", "b.csv", "c.csv"]);
            // Not an output: refused, never in the folder.
            assert!(write("notes.txt").is_err());
            assert!(!dir.join("notes.txt").exists());
            Err::<(), _>(Error::Cancelled)
        });
        assert!(matches!(stopped, Err(Error::Cancelled)));
        assert_eq!(names(), ["a.csv", "b.csv", "c.csv"]);
        write_outputs(&dir, "third", owned, || write("a.csv")).unwrap();
        assert_eq!(text(), format!("# third\n{COMPLETE}\na.csv\n"));
        assert!(!dir.join("b.csv").exists() && !dir.join("c.csv").exists());
        // A line the program would not write is refused, naming it, and nothing is removed.
        fs::write(dir.join(MANIFEST), "# edited\na.csv\nnotes.txt\n").unwrap();
        let e = write_outputs(&dir, "fourth", owned, || write("d.csv")).unwrap_err();
        assert!(e.to_string().contains("line 3 of"), "{e}");
        assert!(dir.join("a.csv").exists() && !dir.join("d.csv").exists());
        fs::remove_dir_all(&dir).unwrap();
    }

    /// The bytes of the one CSV dialect: sweep files (tests/sweeps.rs) depend on them.
    #[test]
    fn tables_are_written_grown_and_read_in_one_dialect() {
        let dir = std::env::temp_dir().join(format!("jointwear-output-{}", std::process::id()));
        let path = dir.join("table.csv");
        let header = ["case", "value", "error"];
        let kept = vec![vec!["0".to_string(), "1e0".into(), String::new()]];
        let table = GrowingTable::create(&path, Some("# a table"), &header, kept).unwrap();
        let quoted = ["1".to_string(), "a,b".into(), "say \"no\"".into()];
        table.append(&quoted).unwrap();
        table
            .append(&["2".to_string(), "-".into(), String::new()])
            .unwrap();
        drop(table);
        let text = fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "# a table\ncase,value,error\n0,1e0,\n1,\"a,b\",\"say \"\"no\"\"\"\n2,-,\n"
        );
        let (head, rows) = parse_rows(&path, text.split_once('\n').unwrap().1).unwrap();
        assert_eq!(head, header);
        assert_eq!(rows[1], quoted);
        write_rows(&path, &header, rows.clone()).unwrap();
        assert_eq!(read_rows(&path).unwrap(), (head, rows));
        // A cut last row is read as it is (its reader picks the complete rows); a table that
        // is not flexible refuses it.
        assert_eq!(parse_rows(&path, "a,b\n1,2\n3").unwrap().1[1], ["3"]);
        fs::write(&path, "a,b\n1,2\n3").unwrap();
        assert!(matches!(read_rows(&path), Err(Error::Parse { .. })));
        fs::remove_dir_all(&dir).unwrap();
    }

    /// Numbers are the shortest text that round-trips. Would fail on `{:e}` alone (`7.2e-1`),
    /// on `{}` alone (`1e-300` as 302 characters) or on a rounding format (`{:.6e}` loses bits).
    #[test]
    fn numbers_are_the_shortest_text_that_round_trips() {
        for (x, text) in [
            (0.72, "0.72"),
            (1500.0, "1500"),
            (2e5, "2e5"),
            (1.25e-9, "1.25e-9"),
            (-0.003, "-3e-3"),
            (0.01, "0.01"),
            (-0.25, "-0.25"),
            (0.0, "0"),
            (-0.0, "-0"),
            (1e-300, "1e-300"),
            (f64::MAX, "1.7976931348623157e308"),
            (0.1 + 0.2, "0.30000000000000004"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(number(x), text, "{x:e}");
        }
        let check = |x: f64| {
            if x.is_nan() {
                return;
            }
            let text = number(x);
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{text}"
            );
            // The definition spelled out: the shorter of Rust's two formats, plain on a tie.
            let (plain, sci) = (x.to_string(), format!("{x:e}"));
            assert_eq!(text, if sci.len() < plain.len() { sci } else { plain });
        };
        // Every bit pattern class round-trips: subnormals, tiny, huge, negative, random bits.
        let mut bits = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..100_000 {
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            // Raw bits are mostly huge or tiny (e-notation wins); also numbers of the sizes
            // a table holds, where the plain form wins, and round ones, where zeros decide.
            let ordinary =
                (bits >> 11) as f64 / (1u64 << 53) as f64 * 10f64.powi((bits % 40) as i32 - 15);
            let round = ((bits >> 40) % 100_000) as f64 * 10f64.powi((bits % 30) as i32 - 12);
            for x in [f64::from_bits(bits), ordinary, -round] {
                check(x);
            }
        }
        for x in [
            5e-324,
            2.2250738585072014e-308,
            123456789.0,
            0.001,
            1e21,
            1e-7,
        ] {
            assert_eq!(number(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
        }
    }
}
