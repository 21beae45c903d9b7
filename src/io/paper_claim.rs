//! The claim of the paper's outputs, `figures/`, `data/` and `paper.md` of the crate this was
//! built from (or of the directory [`OUTPUT_ROOT_VAR`] names): held by each paper program
//! while it writes them (`jointwear::paper::program`), and by a `jointwear` command or
//! Python's `save` whose output lies among them, so that none writes there while another does. Outside the paper feature too: a build without it still writes into a
//! checkout whose paper programs may run.
//!
//! Its lock lies in the crate root, which may also be a command's output folder (`jointwear
//! run … --out .` there leaves its manifest): that does not refuse the claim
//! ([`claim_name`]; as a sweep file's claim, it made every paper program exit 2), as such a
//! command writes and removes only its own files in the root, never `paper.md` nor anything in
//! `figures/` or `data/` (a command whose output lies there takes this claim too).

use crate::io::lock::{claim_name, remove_temporaries_of, Lock};
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The environment variable that moves the generated outputs out of the checkout: the
/// directory under which the paper programs write and read back `figures/`, `data/` and
/// `paper.md`, and claim them, in place of the crate root. For a test or a scratch run beside
/// the checkout's own programs, which it then never collides with; their inputs (scenes, the
/// paper's values) are still read from the checkout.
pub const OUTPUT_ROOT_VAR: &str = "JOINTWEAR_OUTPUT_ROOT";

/// The root of the generated outputs: the crate the program was built from, wherever it runs
/// (a program built in one checkout writes into that checkout, so it says where), or the
/// directory [`OUTPUT_ROOT_VAR`] names (made absolute when first asked).
pub fn output_root() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| match std::env::var_os(OUTPUT_ROOT_VAR) {
        Some(dir) => std::path::absolute(&dir).unwrap_or_else(|_| dir.into()),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")),
    })
}

/// Whether [`OUTPUT_ROOT_VAR`] moved the outputs out of the crate root.
pub fn output_root_moved() -> bool {
    std::env::var_os(OUTPUT_ROOT_VAR).is_some()
}

/// The name, never written, whose lock (`.paper-outputs.lock` beside it, in the crate root)
/// claims the crate's outputs for one paper program.
pub fn outputs_claim_target() -> PathBuf {
    output_root().join("paper-outputs")
}

/// What a paper program's refusal names as the setting that chose its outputs.
pub(crate) const PAPER_OUTPUTS: &str = "paper outputs";

/// The folders the paper programs write into, under [`output_root`], each with the stem of
/// the only output whose temporaries there are theirs (`None`: every file there is).
const OUTPUT_DIRS: [(&str, Option<&str>); 4] = [
    ("", Some("paper")),
    ("figures", None),
    ("data", None),
    ("data/golden", None),
];

/// Claims `figures/`, `data/` and `paper.md` for this process until the returned lock drops
/// (also released on an interrupt, if the process installed the handler, and by
/// [`crate::error::exit_on_error`]); refused, naming the process that holds them and `option`
/// with its `value` (what chose these outputs), while another process writes them. A claim
/// that takes over the lock of a killed process removes the temporary files that process left
/// in the outputs' folders in the middle of a write (unless another process has its id now,
/// [`Lock::taken_from`]); its notes ([`Lock::notes`]) say so, for
/// the caller to show where its user sees them.
pub fn claim_paper_outputs(option: &str, value: &str) -> Result<Lock> {
    if output_root_moved() && !output_root().is_dir() {
        return Err(Error::invalid(
            OUTPUT_ROOT_VAR,
            output_root().display(),
            "an existing directory, under which the paper's outputs are written in place of \
             the checkout's (create it, or unset the variable to write into the checkout)",
        ));
    }
    let mut lock = claim_name(option, &outputs_claim_target()).map_err(|e| match e {
        // the claim's message, which names the holder, said of these outputs
        Error::Invalid { expected, .. } => Error::invalid(
            option,
            value,
            expected
                .replacen(
                    "an output no other run is writing",
                    "outputs no other program is writing (the paper's: figures/, data/ and \
                     paper.md)",
                    1,
                )
                // (a paper program cannot choose other outputs; a command can)
                .replacen(&format!(", choose another {PAPER_OUTPUTS}"), "", 1),
        ),
        e => e,
    })?;
    if let Some(pid) = lock.taken_from() {
        let removed = (OUTPUT_DIRS.iter())
            .filter_map(|(dir, stem)| remove_temporaries_of(&output_root().join(dir), pid, *stem));
        lock.note(removed.collect::<Vec<_>>());
    }
    Ok(lock)
}

/// The claim of the paper's outputs ([`claim_paper_outputs`]) for a command of the
/// `jointwear` program, or Python's `save`, whose `option` names `path`, when that is one of
/// them: `paper.md`, or in `figures/` or `data/` under [`output_root`] (the README's `check …
/// --out figures`; for Python, of the checkout the package was built from). A
/// paper program writing there at the same time could replace its files (a sweep's `--out
/// data/table3.csv`) or it theirs. `None` for any other path.
pub fn claim_if_paper_output(option: &str, path: &Path) -> Result<Option<Lock>> {
    let root = resolved(output_root());
    let path = resolved(path);
    let ours = ["figures", "data"]
        .iter()
        .any(|dir| path.starts_with(root.join(dir)))
        || path == root.join("paper.md");
    ours.then(|| claim_paper_outputs(option, &path.display().to_string()))
        .transpose()
}

/// The claims of a command's output `out`, a folder or a file, until they drop: the paper's
/// outputs if `out` lies among them ([`claim_if_paper_output`]), then `out` itself by `claim`
/// ([`crate::io::lock::claim_folder`] or [`crate::io::lock::claim_file`]), in that order for
/// every writer (the program's commands, Python's `save`). `noted` hears each claim's notes
/// as it is taken, so that those of the first are heard though the second is refused.
pub fn claim_output(
    option: &str,
    out: &Path,
    claim: fn(&str, &Path) -> Result<Lock>,
    noted: &mut dyn FnMut(&[String]),
) -> Result<(Option<Lock>, Lock)> {
    let paper = claim_if_paper_output(option, out)?;
    if let Some(lock) = &paper {
        noted(lock.notes());
    }
    let own = claim(option, out)?;
    noted(own.notes());
    Ok((paper, own))
}

/// `path` made absolute, with symbolic links resolved as far as it exists.
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    // The names below the longest part that exists, innermost first.
    let mut names = Vec::new();
    let mut head = absolute.as_path();
    loop {
        if let Ok(real) = head.canonicalize() {
            return names.iter().rev().fold(real, |p, name| p.join(name));
        }
        match (head.parent(), head.file_name()) {
            (Some(parent), Some(name)) => {
                names.push(name);
                head = parent;
            }
            _ => return absolute,
        }
    }
}
