//! A scene variant: a scene document with values changed by dotted key, as `jointwear run
//! --set KEY=VALUE --rotations N` and Python's `Scene.set` make it, with one set of rules for
//! both: what a change of `run.rotations` cuts, the fingerprint a checkpoint carries, and what
//! a run folder says about where its scene came from ([`Origin`]).

use crate::io::output::fnv1a;
use crate::scene::{set_dotted, SceneFile};
use crate::simulation::folder::Origin;
use crate::simulation::Scene;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The key whose change may cut others ([`Variant::set`] with `cut`).
const ROTATIONS: &str = "run.rotations";

/// Fingerprint of a scene document (`extends` resolved) and changes to it: each change's key
/// and its values as written, in order. A checkpoint and a sweep file carry it, so that they
/// are resumed only with the scene and changes that made them.
pub fn fingerprint<'a>(
    doc: &toml::Value,
    changes: impl IntoIterator<Item = (&'a str, &'a [String])>,
) -> String {
    let mut text = doc.to_string();
    for (key, values) in changes {
        // Unit separators: no key or value can run into the next.
        text.push_str(&format!("\u{1f}{key}={}", values.join("\u{1e}")));
    }
    format!("{:016x}", fnv1a(text.as_bytes()))
}

/// `jointwear run SCENE`, the start of the command line of a run of the scene at `path`.
pub fn run_command(path: &Path) -> String {
    format!("jointwear run {}", shell_word(&path.display().to_string()))
}

/// `word` as one word of a POSIX shell's command line that the shell reads back as `word`:
/// as it is when no character of it means anything to a shell, else in single quotes (a
/// quote inside as `'\''`). A value typed unquoted loses its TOML quotes (`title="a b"`)
/// and with them the fingerprint of the changes, and a bracket is a pattern
/// (`run.wear_snapshots=[1]`).
pub fn shell_word(word: &str) -> std::borrow::Cow<'_, str> {
    let plain = |b: u8| b.is_ascii_alphanumeric() || b"%+,-./:=@_".contains(&b);
    if !word.is_empty() && word.bytes().all(plain) {
        word.into()
    } else {
        format!("'{}'", word.replace('\'', r"'\''")).into()
    }
}

/// The words of the command line `line` as a POSIX shell splits them: the inverse of
/// [`shell_word`] (single quotes, a backslash outside quotes), and double quotes as lines
/// recorded before words were quoted hold them (`--set title="a b"`). `None` if a quote is
/// not closed.
pub fn shell_words(line: &str) -> Option<Vec<String>> {
    let mut words = Vec::new();
    // The word being read, if one has begun (`''` is a word, empty).
    let mut word: Option<String> = None;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            ' ' | '\t' | '\n' => words.extend(word.take()),
            '\'' => {
                let w = word.get_or_insert_with(String::new);
                loop {
                    match chars.next()? {
                        '\'' => break,
                        c => w.push(c),
                    }
                }
            }
            '"' => {
                let w = word.get_or_insert_with(String::new);
                loop {
                    match chars.next()? {
                        '"' => break,
                        '\\' => match chars.next()? {
                            c @ ('"' | '\\' | '$' | '`') => w.push(c),
                            c => w.extend(['\\', c]),
                        },
                        c => w.push(c),
                    }
                }
            }
            '\\' => word.get_or_insert_with(String::new).push(chars.next()?),
            c => word.get_or_insert_with(String::new).push(c),
        }
    }
    words.extend(word);
    Some(words)
}

/// A TOML value as written on the command line; a bare word that is not TOML is a string.
pub fn parse_value(text: &str) -> toml::Value {
    text.parse()
        .unwrap_or_else(|_| toml::Value::String(text.to_string()))
}

/// The canonical spelling of the dotted `key` into `doc` (`clearance.0` for `clearance.00`),
/// by which a key given twice is found ([`Variant::set`], [`crate::sweep::canonical_sets`]);
/// parts past where the document ends are kept as written (setting them fails with its own
/// message).
pub fn canonical_key(doc: &toml::Value, key: &str) -> String {
    let mut node = Some(doc);
    let parts: Vec<String> = key
        .split('.')
        .map(|part| match node {
            Some(toml::Value::Array(items)) => match part.parse::<usize>() {
                Ok(k) => {
                    node = items.get(k);
                    k.to_string()
                }
                Err(_) => {
                    node = None;
                    part.to_string()
                }
            },
            Some(toml::Value::Table(table)) => {
                node = table.get(part);
                part.to_string()
            }
            _ => {
                node = None;
                part.to_string()
            }
        })
        .collect();
    parts.join(".")
}

/// A change asked for, as text ([`Variant::state`]): the key, the value as written, and
/// whether it cuts (`--rotations`).
pub type Change = (String, String, bool);

/// One change asked for.
#[derive(Clone, Debug, PartialEq)]
struct Asked {
    key: String,
    /// The value as written (the command line's text, or the TOML of a Python value), one
    /// value as the slice [`fingerprint`] takes.
    text: [String; 1],
    /// A change of `run.rotations` that cuts the snapshots and recorded rotations
    /// (`--rotations`, Python's `set`), not a plain `--set`.
    cut: bool,
}

/// A scene document as read, and the changes made to it in order.
#[derive(Clone, Debug)]
pub struct Variant {
    path: PathBuf,
    /// The document as read or built, before any change: what a reversal of the driver is
    /// noted against and what the fingerprint hashes.
    loaded: toml::Value,
    /// The document with every change applied.
    doc: toml::Value,
    asked: Vec<Asked>,
    /// Every change made, as `[key, value]`: the ones asked for and what they cut.
    changes: Vec<(String, String)>,
}

impl Variant {
    /// The scene file at `path` (`extends` resolved), unchanged.
    pub fn read(path: &Path) -> Result<Variant> {
        Ok(Variant::new(SceneFile::read_document(path)?, path))
    }

    /// A scene document (`extends` resolved) that `path` names in messages, unchanged.
    pub fn new(doc: toml::Value, path: &Path) -> Variant {
        Variant {
            path: path.to_path_buf(),
            loaded: doc.clone(),
            doc,
            asked: Vec::new(),
            changes: Vec::new(),
        }
    }

    /// Sets `value` (written `text`) at the dotted `key`, all or nothing: a key the scene file
    /// cannot have or a value of the wrong type is an error and leaves the variant as it was
    /// (a value out of range is refused by [`Variant::build`]). With `cut`, a change of
    /// `run.rotations` to N also drops the wear snapshots past N and cuts
    /// `run.record_rotations` to N, unless they were set before: it returns those cuts. A key
    /// asked before, under any spelling, replaces that change: the variant is the one asked
    /// each key once, with its last value (but a cutting `run.rotations` after plain ones,
    /// the program's `--rotations` over its `--set run.rotations`, keeps them as it asked).
    pub fn set(
        &mut self,
        key: &str,
        value: toml::Value,
        text: &str,
        cut: bool,
    ) -> Result<Vec<(String, toml::Value)>> {
        // A key asked again replaces its earlier value: the variant is made again from the
        // document as read without it, so that each key is asked once and the command line
        // makes the same document (the program refuses a key given twice, and an earlier
        // `run.rotations` would have cut what a later one keeps).
        let again = canonical_key(&self.loaded, key);
        let (earlier, others): (Vec<&Asked>, Vec<&Asked>) =
            (self.asked.iter()).partition(|a| canonical_key(&self.loaded, &a.key) == again);
        // Except the program's `--rotations` over its `--set run.rotations`, which it has
        // always asked after it, overriding it (tests/cli.rs): its command line holds both, and
        // so does the fingerprint of a checkpoint written with both, which it must resume.
        // Neither cut, so the cuts are those of the `--rotations` alone.
        let overrides = cut && key == ROTATIONS && earlier.iter().all(|a| !a.cut);
        if !earlier.is_empty() && !overrides {
            let mut fresh = Variant::new(self.loaded.clone(), &self.path);
            for a in others {
                fresh.set(&a.key, parse_value(&a.text[0]), &a.text[0], a.cut)?;
            }
            let cuts = fresh.set(key, value, text, cut)?;
            *self = fresh;
            return Ok(cuts);
        }
        let mut doc = self.doc.clone();
        set_dotted(&mut doc, key, value)?;
        let mut file = SceneFile::from_document(doc.clone(), &self.path)?;
        let mut cuts = Vec::new();
        let cut = cut && key == ROTATIONS;
        if cut {
            let set = |k: &str| self.asked.iter().any(|a| a.key == k);
            cuts = file.run.cut_to(file.run.rotations, set);
            for (k, v) in &cuts {
                set_dotted(&mut doc, k, v.clone())?;
            }
        }
        self.doc = doc;
        self.asked.push(Asked {
            key: key.to_string(),
            text: [text.to_string()],
            cut,
        });
        self.changes.push((key.to_string(), text.to_string()));
        (self.changes).extend(cuts.iter().map(|(k, v)| (k.clone(), v.to_string())));
        Ok(cuts)
    }

    /// The scene as changed, validated and in SI units.
    pub fn build(&self) -> Result<Scene> {
        SceneFile::from_document(self.doc.clone(), &self.path)?.build()
    }

    /// This variant named by `path` instead, a file that holds its document as read
    /// ([`Variant::state`]): its fingerprint is the same, its command line and origin name
    /// `path` (a scene built from a dict, saved with a run's folder).
    pub fn named(&self, path: &Path) -> Variant {
        Variant {
            path: path.to_path_buf(),
            ..self.clone()
        }
    }

    /// The document with every change applied.
    pub fn document(&self) -> &toml::Value {
        &self.doc
    }

    /// The document as read, before any change.
    pub fn loaded(&self) -> &toml::Value {
        &self.loaded
    }

    /// The path that names the scene.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The changes asked for in the order the program asks its options: the plain ones
    /// (`--set`) in the order asked, then the cutting one (`--rotations`), which the program
    /// applies after every `--set`. The document is the same in either order (a cut spares the
    /// keys set before it, and a key set after it replaces the cut value), so the fingerprint
    /// and command line of Python's `set("run.rotations", n)` followed by other keys are those
    /// of a run of that command line.
    fn in_program_order(&self) -> impl Iterator<Item = &Asked> {
        (self.asked.iter().filter(|a| !a.cut)).chain(self.asked.iter().filter(|a| a.cut))
    }

    /// The [`fingerprint`] of the scene as read and the changes asked for, in the program's
    /// order: every plain change (`--set`) before the cutting one (`--rotations`).
    pub fn fingerprint(&self) -> String {
        fingerprint(
            &self.loaded,
            (self.in_program_order()).map(|a| (a.key.as_str(), a.text.as_slice())),
        )
    }

    /// The command line that makes this variant: `jointwear run SCENE`, then `--set KEY=VALUE`
    /// per change in the order asked and `--rotations N` for a cutting change of
    /// `run.rotations` last, as the program applies them, each word as a shell reads it back
    /// ([`shell_word`]).
    pub fn command(&self) -> String {
        let mut command = run_command(&self.path);
        for a in self.in_program_order() {
            let (option, word) = if a.cut {
                ("--rotations", a.text[0].clone())
            } else {
                ("--set", format!("{}={}", a.key, a.text[0]))
            };
            command.push_str(&format!(" {option} {}", shell_word(&word)));
        }
        command
    }

    /// What a run folder of this variant says about its scene.
    pub fn origin(&self) -> Origin {
        Origin {
            path: self.path.display().to_string(),
            fingerprint: self.fingerprint(),
            changes: self.changes.clone(),
            command: self.command(),
        }
    }

    /// The variant as text that [`Variant::restore`] makes it again, identical: the document
    /// as read (TOML), and per change asked for its key, value as written and `cut`. For a
    /// copy in another process (Python's executors).
    pub fn state(&self) -> Result<(String, Vec<Change>)> {
        let loaded = toml::to_string(&self.loaded).map_err(|e| Error::Parse {
            path: self.path.clone(),
            message: format!("cannot be written as TOML: {e}"),
        })?;
        let asked = (self.asked.iter())
            .map(|a| (a.key.clone(), a.text[0].clone(), a.cut))
            .collect();
        Ok((loaded, asked))
    }

    /// The variant of [`Variant::state`], named by `path`: the changes are made again, each
    /// value read by [`parse_value`].
    pub fn restore(path: &Path, loaded: &str, asked: &[Change]) -> Result<Variant> {
        let parse = |message: String| Error::Parse {
            path: path.to_path_buf(),
            message,
        };
        let doc = loaded
            .parse::<toml::Table>()
            .map_err(|e| parse(e.to_string()))?;
        let mut variant = Variant::new(toml::Value::Table(doc), path);
        for (key, text, cut) in asked {
            variant.set(key, parse_value(text), text, *cut)?;
        }
        Ok(variant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::scene_path;

    /// Every word [`shell_word`] writes is read back whole, whatever it holds; fails if a
    /// quoted word is split at its spaces or keeps its quotes.
    #[test]
    fn shell_words_reads_back_what_shell_word_writes() {
        let words = [
            "jointwear",
            "/a dir/it's.toml",
            "title=\"x --member 3 --seed 1\"",
            "run.wear_snapshots=[1]",
            "",
            "a\\b\"c$d",
        ];
        let line: Vec<_> = words.iter().map(|w| shell_word(w)).collect();
        assert_eq!(shell_words(&line.join(" ")).unwrap(), words);
        // A line recorded before words were quoted.
        assert_eq!(
            shell_words(r#"jointwear run a.toml --set title="a \"b\" c""#).unwrap(),
            ["jointwear", "run", "a.toml", "--set", r#"title=a "b" c"#]
        );
        assert_eq!(shell_words("run --set title=it's"), None);
    }

    /// Fails if a cut is applied to a key set before, if the command forgets `--rotations`, or
    /// if a restored copy differs from the original in any part.
    #[test]
    fn rotations_cut_what_was_not_set_and_a_restored_copy_is_identical() {
        let mut v = Variant::read(&scene_path("standard")).unwrap();
        let snapshots = toml::Value::Array(vec![1.into()]);
        v.set("run.wear_snapshots", snapshots, "[1]", true).unwrap();
        let cuts = v.set(ROTATIONS, 1.into(), "1", true).unwrap();
        assert_eq!(cuts, [("run.record_rotations".to_string(), 1.into())]);
        assert_eq!(v.build().unwrap().run.record_rotations, 1);
        assert!(v
            .command()
            .ends_with(" --set 'run.wear_snapshots=[1]' --rotations 1"));
        assert!(v.set("run.rotatons", 2.into(), "2", true).is_err());
        let (loaded, asked) = v.state().unwrap();
        let copy = Variant::restore(v.path(), &loaded, &asked).unwrap();
        assert_eq!(copy.document(), v.document());
        assert_eq!(copy.origin(), v.origin());
    }

    /// A variant made as Python's `set` makes it, `run.rotations` before other keys, has the
    /// fingerprint and command line of the program's run of that command line, which asks
    /// every `--set` before `--rotations`. Failed with the changes in the order asked: the
    /// command `--rotations 1 --set run.record_rotations=0` and another fingerprint than its
    /// run's.
    #[test]
    fn rotations_set_first_makes_the_fingerprint_of_its_command_line() {
        let path = scene_path("standard");
        let mut python = Variant::read(&path).unwrap();
        python.set(ROTATIONS, 1.into(), "1", true).unwrap();
        python
            .set("run.record_rotations", 0.into(), "0", true)
            .unwrap();
        let mut program = Variant::read(&path).unwrap();
        program
            .set("run.record_rotations", 0.into(), "0", false)
            .unwrap();
        program.set(ROTATIONS, 1.into(), "1", true).unwrap();
        assert_eq!(python.document(), program.document());
        assert_eq!(python.command(), program.command());
        assert_eq!(python.fingerprint(), program.fingerprint());
        assert!(program
            .command()
            .ends_with(" --set run.record_rotations=0 --rotations 1"));
    }

    /// The program's `--set run.rotations=5 --rotations 3` keeps both changes, the fingerprint
    /// of a checkpoint written with them before a key set again was replaced, and the command
    /// line that the program runs. Failed with the `--set` replaced: fingerprint of
    /// `--rotations 3` alone, and `run --resume` refused that checkpoint.
    #[test]
    fn rotations_over_a_set_of_rotations_keep_both_as_the_program_asked_them() {
        let path = scene_path("standard");
        let mut v = Variant::read(&path).unwrap();
        v.set(ROTATIONS, 5.into(), "5", false).unwrap();
        v.set(ROTATIONS, 3.into(), "3", true).unwrap();
        let (five, three) = (["5".to_string()], ["3".to_string()]);
        let both = [(ROTATIONS, &five[..]), (ROTATIONS, &three[..])];
        assert_eq!(v.fingerprint(), fingerprint(v.loaded(), both));
        assert!(v
            .command()
            .ends_with(" --set run.rotations=5 --rotations 3"));
        assert_eq!(v.build().unwrap().run.rotations, 3);
        // and a further cutting change replaces both
        v.set(ROTATIONS, 2.into(), "2", true).unwrap();
        assert!(
            v.command().ends_with(".toml --rotations 2"),
            "{}",
            v.command()
        );
    }

    /// A key set twice (Python's `set`) is asked once, with its last value: the program
    /// refuses a key given twice, so a command line naming both would not run again. Failed
    /// before: the command held `--set clearance.0.clearance_mm=0.03 --set
    /// clearance.00.clearance_mm=0.05`, and a second `run.rotations` kept the first's cut.
    #[test]
    fn a_key_set_again_replaces_its_earlier_value() {
        let path = scene_path("standard");
        let mut v = Variant::read(&path).unwrap();
        v.set("clearance.0.clearance_mm", 0.03.into(), "0.03", false)
            .unwrap();
        v.set(ROTATIONS, 1.into(), "1", true).unwrap();
        v.set("clearance.00.clearance_mm", 0.05.into(), "0.05", false)
            .unwrap();
        v.set(ROTATIONS, 40.into(), "40", true).unwrap();
        let mut once = Variant::read(&path).unwrap();
        once.set("clearance.00.clearance_mm", 0.05.into(), "0.05", false)
            .unwrap();
        once.set(ROTATIONS, 40.into(), "40", true).unwrap();
        assert_eq!(v.document(), once.document());
        assert_eq!(v.origin(), once.origin());
        assert!(
            v.command()
                .ends_with(" --set clearance.00.clearance_mm=0.05 --rotations 40"),
            "{}",
            v.command()
        );
        // and a failed change leaves the variant as it was
        assert!(v.set(ROTATIONS, "x".into(), "x", true).is_err());
        assert_eq!(v.origin(), once.origin());
    }
}
