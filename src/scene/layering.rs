//! Reading scene files: `extends` chains and `[overrides]` (see the module documentation of
//! [`crate::scene`]), dotted keys for sweeps, and the paths of the shipped scenes.

use super::{SceneFile, MAX_SCENE_BYTES};
use crate::io::output::read_bounded_text;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// How deep `extends` chains may go (a cycle would otherwise recurse forever).
const MAX_EXTENDS_DEPTH: usize = 8;

pub(super) fn read_table(path: &Path, depth: usize) -> Result<toml::Table> {
    parse_table(&read_scene_text(path)?, path, depth)
}

/// The text of the scene file at `path`: a regular file of at most [`MAX_SCENE_BYTES`]
/// ([`read_bounded_text`]).
fn read_scene_text(path: &Path) -> Result<String> {
    read_bounded_text(
        path,
        MAX_SCENE_BYTES,
        "a scene file",
        "1 MiB; the largest shipped scene is a few kB",
    )
}

/// Parses a scene document and resolves its `extends` and `[overrides]`.
pub(super) fn parse_table(text: &str, path: &Path, depth: usize) -> Result<toml::Table> {
    let parse_error = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let table: toml::Table = toml::from_str(text).map_err(|e| parse_error(e.to_string()))?;
    resolve_table(table, path, depth)
}

/// Resolves the `extends` and `[overrides]` of a parsed scene document (`path`: its file, for
/// messages and to find the base).
fn resolve_table(mut table: toml::Table, path: &Path, depth: usize) -> Result<toml::Table> {
    let parse_error = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let Some(base) = table.remove("extends") else {
        if table.contains_key("overrides") {
            return Err(parse_error(
                "`overrides` needs `extends = \"base.toml\"`".into(),
            ));
        }
        return Ok(table);
    };
    let base = base
        .as_str()
        .ok_or_else(|| parse_error("`extends` must be a file name".into()))?;
    if depth >= MAX_EXTENDS_DEPTH {
        return Err(parse_error(format!(
            "`extends` chains deeper than {MAX_EXTENDS_DEPTH} (a cycle?)"
        )));
    }
    let base_path = path.parent().unwrap_or(Path::new(".")).join(base);
    // A base that cannot be read is this scene's error: name the scene that refers to it.
    let mut merged = read_table(&base_path, depth + 1).map_err(|e| match e {
        Error::Io { path: p, source } => parse_error(format!(
            "`extends = \"{base}\"`: cannot read {}: {source}",
            p.display()
        )),
        e => e,
    })?;
    let overrides = match table.remove("overrides") {
        Some(toml::Value::Table(o)) => o,
        Some(_) => {
            return Err(parse_error(
                "`overrides` must be a table of dotted keys".into(),
            ))
        }
        None => toml::Table::new(),
    };
    merged.extend(table);
    let mut doc = toml::Value::Table(merged);
    for (key, value) in overrides {
        set_dotted(&mut doc, &key, value).map_err(|e| parse_error(format!("override: {e}")))?;
    }
    match doc {
        toml::Value::Table(t) => Ok(t),
        _ => unreachable!("a scene document is a table"),
    }
}

/// Path of a shipped scene, `data/scenes/<name>.toml`, relative to the crate root.
pub fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/scenes")
        .join(format!("{name}.toml"))
}

/// Sets the value at a dotted `key` of a scene document: table keys by name, array elements
/// by a 0-based number (`clearance.0.clearance_mm`, `driver.speed_rpm`). Every part but the
/// last must exist; the last may add a key to a table (an unknown key is then rejected when
/// the document is converted by [`SceneFile::from_document`]).
pub fn set_dotted(doc: &mut toml::Value, key: &str, value: toml::Value) -> Result<()> {
    // The value that failed is the key's part `at`, not the value set.
    let bad = |at: &str, what: &str, expected: String| {
        Error::invalid(key, format!("`{at}` {what}"), expected)
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut node = doc;
    for (i, part) in parts.iter().enumerate() {
        let last = i + 1 == parts.len();
        node = match node {
            toml::Value::Table(table) if last => {
                table.insert(part.to_string(), value);
                return Ok(());
            }
            toml::Value::Table(table) => {
                if !table.contains_key(*part) {
                    let keys: Vec<&str> = table.keys().map(String::as_str).collect();
                    let expected = format!("one of the keys {}", keys.join(", "));
                    return Err(bad(part, "is no key there", expected));
                }
                &mut table[*part]
            }
            toml::Value::Array(items) => {
                let len = items.len();
                let slot = part
                    .parse::<usize>()
                    .ok()
                    .and_then(|k| items.get_mut(k))
                    .ok_or_else(|| {
                        bad(
                            part,
                            "is no element there",
                            format!("an array index in [0, {len})"),
                        )
                    })?;
                if last {
                    *slot = value;
                    return Ok(());
                }
                slot
            }
            _ => {
                return Err(bad(
                    part,
                    "follows a value",
                    "a table or an array before it".into(),
                ))
            }
        };
    }
    Err(Error::invalid(key, "empty", "a dotted key"))
}

/// The driver's speed (r/min) in a scene document, where it is a number.
fn driver_speed_rpm(doc: &toml::Value) -> Option<f64> {
    match doc.get("driver")?.get("speed_rpm")? {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(n) => Some(*n as f64),
        _ => None,
    }
}

/// A note for the user when setting `value` at `key` of `doc` (as `--set` or Python's `set`)
/// turns the driver the other way than `doc` does, or None. A scene calibrated in one sense of
/// rotation wears elsewhere in the other (the standard scene's deepest wear moves from 185.5 to
/// 175.5 deg), and a speed given without its sign is the likely cause.
pub fn reversal_note(doc: &toml::Value, key: &str, value: &toml::Value) -> Option<String> {
    let mut varied = doc.clone();
    set_dotted(&mut varied, key, value.clone()).ok()?;
    let (from, to) = (driver_speed_rpm(doc)?, driver_speed_rpm(&varied)?);
    (from * to < 0.0).then(|| {
        format!(
            "{key} = {value} reverses the driver: the scene turns it at {from} r/min (positive \
             is counter-clockwise), and the wear depends on the sense; give the speed the \
             scene's sign to keep it"
        )
    })
}

impl SceneFile {
    /// Reads a scene file (resolving `extends`) without validating its values, so that it
    /// can be varied before [`SceneFile::build`].
    pub fn read(path: impl AsRef<Path>) -> Result<SceneFile> {
        let path = path.as_ref();
        SceneFile::from_document(SceneFile::read_document(path)?, path)
    }

    /// Parses scene text; `path` is used in error messages and to resolve `extends`.
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
        SceneFile::from_document(toml::Value::Table(parse_table(text, path, 0)?), path)
    }

    /// Reads a scene file as a TOML document (with `extends` resolved), to be varied with
    /// [`set_dotted`].
    pub fn read_document(path: impl AsRef<Path>) -> Result<toml::Value> {
        read_table(path.as_ref(), 0).map(toml::Value::Table)
    }

    /// Resolves the `extends` and `[overrides]` of a scene document built in memory (the
    /// Python bindings' scenes from a dict), as [`SceneFile::read_document`] does for a file:
    /// `path` names the document in messages, and a relative `extends` is found beside it.
    pub fn resolve_document(doc: toml::Value, path: &Path) -> Result<toml::Value> {
        match doc {
            toml::Value::Table(t) => resolve_table(t, path, 0).map(toml::Value::Table),
            other => Err(Error::Parse {
                path: path.to_path_buf(),
                message: format!("a scene is a table of keys, not a {}", other.type_str()),
            }),
        }
    }

    /// Converts a (varied) scene document; `path` is only used in error messages.
    pub fn from_document(doc: toml::Value, path: &Path) -> Result<SceneFile> {
        doc.try_into().map_err(|e: toml::de::Error| Error::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }
}
