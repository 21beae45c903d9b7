//! Atomic outputs (CSV tables and figures).
//!
//! Every output is written to a temporary file in the same directory and renamed into place,
//! so a failed run never leaves a half-written CSV or PNG behind: the target either keeps its
//! previous content or receives the complete new one.

use std::cell::RefCell;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};

use crate::{interrupt, Error, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

fn io_error(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Hidden temporary sibling of `path` that keeps the extension (`dir/.name.tmp.png` for
/// `dir/name.png`), so writers that pick the format from the extension still work.
fn temp_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or(path.as_os_str());
    let mut name = OsString::from(".");
    name.push(stem);
    name.push(".tmp");
    if let Some(ext) = path.extension() {
        name.push(".");
        name.push(ext);
    }
    path.with_file_name(name)
}

/// Writes `path` atomically: creates the parent directory, lets `write` produce the content
/// at a temporary path next to `path`, then renames it into place. On failure the temporary
/// file is removed and `path` is left untouched.
pub fn write_atomic(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
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
        fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    }
    let tmp = temp_path(path);
    // Registered while it exists, so that an interrupted program removes it.
    let _registered = interrupt::temporary(&tmp).ok_or_else(|| {
        io_error(
            path,
            std::io::Error::new(std::io::ErrorKind::Interrupted, "interrupted"),
        )
    })?;
    let result = write(&tmp).and_then(|()| fs::rename(&tmp, path).map_err(|e| io_error(path, e)));
    match result {
        Ok(()) => WRITTEN.with_borrow_mut(|w| w.iter_mut().for_each(|w| w.push(path.into()))),
        // Best effort: the writer may have failed before creating the file.
        Err(_) => {
            let _ = fs::remove_file(&tmp);
        }
    }
    result
}

thread_local! {
    /// The files [`write_atomic`] wrote on this thread while [`write_outputs`] collects them.
    static WRITTEN: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

/// File listing the outputs of the last complete run written into a folder.
pub const MANIFEST: &str = "jointwear-manifest.txt";

/// The file names a folder's manifest lists (none without a manifest). Only plain names are
/// taken: a manifest never makes this program touch anything outside its folder.
fn manifest_files(dir: &Path) -> Vec<String> {
    let text = fs::read_to_string(dir.join(MANIFEST)).unwrap_or_default();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty() && *l != MANIFEST)
        .filter(|l| Path::new(l).file_name() == Some(std::ffi::OsStr::new(l)))
        .map(str::to_owned)
        .collect()
}

/// Writes the outputs of one run into `dir` so that old and new outputs never mix: the
/// previous run's manifest is removed first (a folder without one holds an interrupted or
/// failed write), `write` writes through [`write_atomic`] on this thread, the files of the
/// previous run it did not rewrite are removed, and a new [`MANIFEST`] headed by `title`
/// lists this run's files. Files this program did not write are left alone.
pub fn write_outputs<T>(dir: &Path, title: &str, write: impl FnOnce() -> Result<T>) -> Result<T> {
    let previous = manifest_files(dir);
    let manifest = dir.join(MANIFEST);
    if manifest.exists() {
        fs::remove_file(&manifest).map_err(|e| io_error(&manifest, e))?;
    }
    WRITTEN.with_borrow_mut(|w| *w = Some(Vec::new()));
    let result = write();
    let written = WRITTEN.with_borrow_mut(Option::take).unwrap_or_default();
    let value = result?;
    let mut names: Vec<String> = Vec::new();
    for p in written.iter().filter(|p| p.parent() == Some(dir)) {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        if let Some(n) = name.filter(|n| !names.contains(n)) {
            names.push(n);
        }
    }
    for stale in previous.iter().filter(|p| !names.contains(p)) {
        let path = dir.join(stale);
        if path.is_file() {
            fs::remove_file(&path).map_err(|e| io_error(&path, e))?;
        }
    }
    let mut text =
        format!("# {title}\n# the files of this run; other files here are not from it\n");
    for n in &names {
        text.push_str(n);
        text.push('\n');
    }
    write_atomic(&manifest, |tmp| {
        fs::write(tmp, &text).map_err(|e| io_error(tmp, e))
    })?;
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
/// [`unwritable_dir`]); `option` names the setting in the error (e.g. `--out`), which is bad
/// input ([`Error::Invalid`]).
pub fn check_output_dir(option: &str, dir: &Path) -> Result<()> {
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

/// Writes equally long `columns` under `header` as CSV, atomically. Numbers are written in the
/// shortest form that parses back to the identical `f64` (e.g. `1.25e-9`).
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
    write_rows(
        path,
        header,
        (0..rows).map(|row| columns.iter().map(|c| format!("{:e}", c[row])).collect()),
    )
}

/// Writes text rows under `header` as CSV, atomically (for tables with text columns).
pub fn write_rows(
    path: &Path,
    header: &[impl AsRef<str>],
    rows: impl IntoIterator<Item = Vec<String>>,
) -> Result<()> {
    write_atomic(path, |tmp| {
        let mut w = csv::Writer::from_path(tmp).map_err(|e| csv_error(tmp, e))?;
        w.write_record(header.iter().map(AsRef::as_ref))
            .map_err(|e| csv_error(tmp, e))?;
        for record in rows {
            w.write_record(&record).map_err(|e| csv_error(tmp, e))?;
        }
        w.flush().map_err(|e| io_error(tmp, e))
    })
}

/// Reads any CSV as text: returns the header and the rows.
pub fn read_rows(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r = csv::Reader::from_path(path).map_err(|e| csv_error(path, e))?;
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
    let mut r = csv::Reader::from_path(path).map_err(|e| csv_error(path, e))?;
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

/// A progress bar of `len` `unit`s on stderr (hidden when stderr is not a terminal).
pub fn progress_bar(len: u64, unit: &str) -> ProgressBar {
    let style = ProgressStyle::with_template(&format!(
        "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {unit} (eta {{eta}})"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr()).with_style(style)
}
