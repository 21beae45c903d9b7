//! The command line of the paper's programs (figures, Table 3, the report, the studies): each
//! takes a few flags and nothing else, and refuses anything else (and flags that exclude each
//! other, [`one_flag`]) before it claims, computes or writes.
//! An argument a program ignored ran it as if it had not been given: `fig06 --help` rewrote the
//! figure and exited 0, `report --al` (meant `--all`) left the slow studies' last results in
//! `paper.md` and said nothing.
//!
//! A program that runs then claims the crate's outputs ([`claim_outputs`]): `figures/`,
//! `data/` and `paper.md` are written by one paper program at a time, as `jointwear`'s commands
//! claim their `--out` folders. Two at once (two figure programs, the report and a figure
//! program, a study and the report that redraws its figure) each wrote their files atomically
//! but in any order, so a figure could end up beside another process's CSV, both exit 0. A
//! `jointwear` command whose `--out` lies among these outputs, or Python's `save` into them,
//! holds the same claim ([`crate::io::paper_claim`]).

use crate::error::exit_on_error;
use crate::io::interrupt;
use crate::io::lock::Lock;
use crate::io::paper_claim::{
    claim_paper_outputs, output_root, output_root_moved, OUTPUT_ROOT_VAR, PAPER_OUTPUTS,
};
use crate::{Error, Result};

/// A flag a program takes, and what it does (for `--help`).
pub type Flag = (&'static str, &'static str);

/// What a program's command line asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Asked {
    /// `-h` or `--help`: the usage, nothing run.
    Help,
    /// Run, with these of the program's flags given.
    Run(Vec<&'static str>),
}

/// Reads `args` (the arguments after the program's name) against the program's `flags`: an
/// argument that is none of them (nor `-h`, `--help`) is an error naming it and the flags.
pub fn parse(args: impl IntoIterator<Item = String>, flags: &[Flag]) -> Result<Asked> {
    let mut given = Vec::new();
    for arg in args {
        if arg == "-h" || arg == "--help" {
            return Ok(Asked::Help);
        }
        let Some(&(flag, _)) = flags.iter().find(|(f, _)| *f == arg) else {
            let allowed = if flags.is_empty() {
                "no arguments (--help for what the program does)".to_string()
            } else {
                let names: Vec<&str> = flags.iter().map(|(f, _)| *f).collect();
                format!("one of {} (--help for what each does)", names.join(", "))
            };
            return Err(Error::invalid(
                "command-line argument",
                format!("`{arg}`"),
                allowed,
            ));
        };
        if !given.contains(&flag) {
            given.push(flag);
        }
    }
    Ok(Asked::Run(given))
}

/// The usage `--help` prints: what `program` does and its flags.
pub fn usage(program: &str, about: &str, flags: &[Flag]) -> String {
    let chosen = if output_root_moved() {
        OUTPUT_ROOT_VAR
    } else {
        "the crate this program was built from"
    };
    let mut text = format!(
        "{about}\n(outputs under {}, {chosen})\n\nUsage: {program}",
        output_root().display()
    );
    for (flag, _) in flags {
        text.push_str(&format!(" [{flag}]"));
    }
    for (flag, does) in flags {
        text.push_str(&format!("\n  {flag}  {does}"));
    }
    text
}

/// `done` (`wrote data/x.csv`, `redrew figures/x.png from data/x.csv`: paths under the crate
/// root) with the root named, as a program's line says it: a program built in one checkout
/// writes into that checkout wherever it runs, so "wrote data/x.csv" alone reads as relative
/// to the working directory.
pub fn in_root(done: &str) -> String {
    format!("{done} in {}", output_root().display())
}

/// A paper program's claim of the crate's outputs, with the flags it was given; released
/// when it drops.
#[must_use = "the outputs are claimed while this lives: bind it for the whole of `main`"]
#[derive(Debug)]
pub struct Claimed {
    /// The program's flags given on its command line.
    pub flags: Vec<&'static str>,
    _lock: Lock,
}

/// A paper program's claim of the outputs ([`claim_paper_outputs`]), with the interrupt
/// handler installed and the claim's notes printed on stderr; prints an error and exits 2
/// while another process writes them.
pub fn claim_outputs() -> Lock {
    if let Err(e) = interrupt::install() {
        eprintln!("note: {e}: an interrupt leaves the outputs' lock behind");
    }
    exit_on_error(claim_paper_outputs(
        PAPER_OUTPUTS,
        "figures/, data/ and paper.md",
    ))
    .noted()
}

/// `asked`, unless it runs with more than one of `flags`: an error naming those given.
fn at_most_one(asked: Asked, flags: &[Flag]) -> Result<Asked> {
    match &asked {
        Asked::Run(given) if given.len() > 1 => {
            let names: Vec<&str> = flags.iter().map(|(f, _)| *f).collect();
            Err(Error::invalid(
                "command-line arguments",
                given.join(" "),
                format!("at most one of {}", names.join(", ")),
            ))
        }
        _ => Ok(asked),
    }
}

/// The `flags` given to this program, and its claim of the outputs ([`claim_outputs`]):
/// prints its usage and exits 0 on `--help`; prints an error and exits 2 on any other argument
/// or while another paper program writes the outputs. The first call of a program's `main`.
pub fn flags(program: &str, about: &str, flags: &[Flag]) -> Claimed {
    claimed(program, about, flags, parse(program_args(), flags))
}

/// [`flags`] for a program whose flags each choose one part of its work instead of the
/// whole (`work_precision --redraw`, `--rule`): two or more are an error, refused as any bad
/// argument is, before the outputs are claimed. Refused after the claim, `--redraw --rule`
/// took over a killed program's lock, removing its temporaries, or was refused for another
/// program's claim rather than for its arguments.
pub fn one_flag(program: &str, about: &str, flags: &[Flag]) -> Claimed {
    let asked = parse(program_args(), flags).and_then(|asked| at_most_one(asked, flags));
    claimed(program, about, flags, asked)
}

/// What `asked` says, with the claim of the outputs: the usage and exit 0 on `--help`, an
/// error and exit 2 on an argument error, before anything is claimed.
fn claimed(program: &str, about: &str, flags: &[Flag], asked: Result<Asked>) -> Claimed {
    match exit_on_error(asked) {
        Asked::Help => {
            println!("{}", usage(program, about, flags));
            std::process::exit(0)
        }
        Asked::Run(given) => Claimed {
            flags: given,
            _lock: claim_outputs(),
        },
    }
}

/// Reads the arguments of a program that takes one text, a reason (`golden_record "REASON"`):
/// `None` for `-h` or `--help`; an error for no text, a blank one, a flag or more than one
/// (`golden_record --help` recorded the golden statistics with the reason "--help").
pub fn parse_reason(args: impl IntoIterator<Item = String>) -> Result<Option<String>> {
    let args: Vec<String> = args.into_iter().collect();
    match args.as_slice() {
        [a] if a == "-h" || a == "--help" => Ok(None),
        [reason] if !reason.starts_with('-') && !reason.trim().is_empty() => {
            Ok(Some(reason.clone()))
        }
        _ => Err(Error::invalid(
            "REASON",
            format!("{args:?}"),
            "one argument, why it is run, not blank and not beginning with `-`",
        )),
    }
}

/// The reason given to this program ([`parse_reason`]): prints its usage and exits 0 on
/// `--help`; prints an error and exits 2 on anything but one reason.
pub fn reason(program: &str, about: &str) -> String {
    exit_on_error(parse_reason(program_args())).unwrap_or_else(|| {
        println!("{} REASON", usage(program, about, &[]));
        std::process::exit(0)
    })
}

/// This program's arguments after its name, as text.
fn program_args() -> impl Iterator<Item = String> {
    std::env::args_os()
        .skip(1)
        .map(|a| a.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    const ALL: &[Flag] = &[("--all", "rerun the slow studies")];

    #[test]
    fn a_program_runs_only_with_its_own_flags() {
        assert_eq!(parse(args(&[]), &[]).unwrap(), Asked::Run(vec![]));
        assert_eq!(
            parse(args(&["--all", "--all"]), ALL).unwrap(),
            Asked::Run(vec!["--all"])
        );
        assert_eq!(parse(args(&["--help"]), &[]).unwrap(), Asked::Help);
        assert_eq!(parse(args(&["--all", "-h"]), ALL).unwrap(), Asked::Help);
        let e = parse(args(&["--al"]), ALL).unwrap_err().to_string();
        assert!(e.contains("`--al`") && e.contains("one of --all"), "{e}");
        let e = parse(args(&["--quick"]), &[]).unwrap_err().to_string();
        assert!(e.contains("`--quick`") && e.contains("no arguments"), "{e}");
        assert_eq!(
            crate::error::exit_code(&parse(args(&["x"]), &[]).unwrap_err()),
            2
        );
    }

    #[test]
    fn flags_that_each_choose_a_part_of_the_work_are_given_one_at_a_time() {
        const PARTS: &[Flag] = &[("--redraw", "redraw"), ("--rule", "rule")];
        let one = |a: &[&str]| parse(args(a), PARTS).and_then(|asked| at_most_one(asked, PARTS));
        assert_eq!(
            one(&["--rule", "--rule"]).unwrap(),
            Asked::Run(vec!["--rule"])
        );
        assert_eq!(one(&["--redraw", "--rule", "-h"]).unwrap(), Asked::Help);
        let e = one(&["--rule", "--redraw"]).unwrap_err();
        assert_eq!(crate::error::exit_code(&e), 2);
        let e = e.to_string();
        assert!(e.contains("--rule --redraw") && e.contains("at most one of --redraw, --rule"));
    }

    #[test]
    fn a_reason_is_one_text_that_is_not_a_flag() {
        assert_eq!(
            parse_reason(args(&["a physics fix"])).unwrap(),
            Some("a physics fix".to_string())
        );
        assert_eq!(parse_reason(args(&["--help"])).unwrap(), None);
        for bad in [&[][..], &["--quick"], &["  "], &["a", "b"]] {
            assert!(parse_reason(args(bad)).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn the_usage_names_every_flag_and_what_it_does() {
        let u = usage("report", "Writes paper.md.", ALL);
        assert_eq!(
            u,
            format!(
                "Writes paper.md.\n(outputs under {}, the crate this program was built \
                 from)\n\nUsage: report [--all]\n  --all  rerun the slow studies",
                env!("CARGO_MANIFEST_DIR")
            )
        );
    }
}
