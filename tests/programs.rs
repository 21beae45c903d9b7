//! The paper's programs refuse an argument they do not take, with exit code 2, before they
//! compute or write anything; `--help` prints what they do and writes nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::SystemTime;

fn crate_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// When `path` was last written.
fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Runs `program` with `args` and checks that none of `outputs` was written.
fn run_writing_nothing(program: &str, args: &[&str], outputs: &[&str]) -> Output {
    let before: Vec<SystemTime> = outputs.iter().map(|p| modified(&crate_file(p))).collect();
    let o = Command::new(program).args(args).output().unwrap();
    for (path, t) in outputs.iter().zip(before) {
        assert_eq!(
            modified(&crate_file(path)),
            t,
            "{program} {args:?} wrote {path}: {}",
            String::from_utf8_lossy(&o.stdout)
        );
    }
    o
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

// Fails without the check: `fig06 --quick` and `fig06 --help` ran the full 32-member figure,
// rewrote figures/fig06.png and data/fig06.csv and exited 0.
#[test]
fn a_figure_program_refuses_an_argument_it_does_not_take() {
    let fig06 = env!("CARGO_BIN_EXE_fig06");
    let outputs = ["figures/fig06.png", "data/fig06.csv"];
    let o = run_writing_nothing(fig06, &["--quick"], &outputs);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("`--quick`") && err.contains("no arguments"),
        "{err}"
    );
    let o = run_writing_nothing(fig06, &["--help"], &outputs);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(
        out.contains("Usage: fig06") && out.contains("data/fig06.csv"),
        "{out}"
    );
    assert!(out.contains(env!("CARGO_MANIFEST_DIR")), "{out}");
}

// Fails without the check: `report --al` (meant `--all`) ran the default report, rewrote
// paper.md with the slow studies' old results and exited 0.
#[test]
fn the_report_refuses_a_misspelt_flag() {
    let o = run_writing_nothing(env!("CARGO_BIN_EXE_report"), &["--al"], &["paper.md"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("`--al`") && err.contains("one of --all"),
        "{err}"
    );
}

// Fails without the check: `golden_record --help` re-recorded the golden statistics with the
// reason "--help".
#[test]
fn golden_record_takes_one_reason_and_help_records_nothing() {
    let program = env!("CARGO_BIN_EXE_golden_record");
    let golden = ["data/golden/ensemble.toml"];
    let o = run_writing_nothing(program, &["--help"], &golden);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("Usage: golden_record REASON"));
    for args in [&["--quick"][..], &[], &["a", "b"]] {
        let o = run_writing_nothing(program, args, &golden);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o.stderr));
    }
}

/// The lock file of the paper's outputs.
fn paper_lock() -> PathBuf {
    crate_file(".paper-outputs.lock")
}

// The programs that claim the outputs run one after another, in one test: two tests running
// them at once would refuse each other.
#[test]
fn the_paper_programs_that_write_claim_the_outputs_in_turn() {
    a_second_paper_program_is_refused_while_one_writes_the_outputs();
    a_killed_programs_lock_is_taken_over_with_the_temporaries_it_left();
    the_studies_say_which_checkout_they_write_into();
    conflicting_flags_are_refused_before_the_outputs_are_claimed();
    a_commands_folder_in_the_crate_root_does_not_block_the_paper_programs();
}

// Fails without the claim: the second table3 ran beside the first and exited 0, both writing
// data/table3.csv; a figure program beside the report could leave its figure beside the other
// process's CSV.
fn a_second_paper_program_is_refused_while_one_writes_the_outputs() {
    let lock = paper_lock();
    let table3 = env!("CARGO_BIN_EXE_table3");
    let first = Command::new(table3)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // The first's own lock, not one a killed program left, which the first takes over.
    let held = format!("pid={}\n", first.id());
    let claimed = || std::fs::read_to_string(&lock).is_ok_and(|t| t.starts_with(&held));
    let clock = std::time::Instant::now();
    while !claimed() && clock.elapsed().as_secs() < 30 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(claimed(), "the first program claims the outputs");
    let clock = std::time::Instant::now();
    let o = Command::new(table3).output().unwrap();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("figures/, data/ and paper.md")
            && err.contains(&format!("process {}", first.id()))
            && err.contains("table3"),
        "{err}"
    );
    assert!(clock.elapsed().as_secs() < 5, "refused at once");
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success());
    assert!(!lock.exists(), "released when the first ends");
    // Fails without the root in the line: "wrote data/table3.csv" read as relative to the
    // working directory, whatever checkout the program was built in and writes into.
    let out = text(&first.stdout);
    let root = env!("CARGO_MANIFEST_DIR");
    assert!(
        out.contains(&format!("wrote data/table3.csv in {root} from")),
        "{out}"
    );
}

// Fails without the cleanup: the lock of a killed program (a process of this host that no
// longer runs: a pid beyond Linux's largest) was taken over without a word, and the
// temporaries it left in data/, figures/ and beside paper.md stayed there for good.
fn a_killed_programs_lock_is_taken_over_with_the_temporaries_it_left() {
    let lock = paper_lock();
    let table3 = env!("CARGO_BIN_EXE_table3");
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    std::fs::write(
        &lock,
        format!("pid=4194305\nhost={}\ncommand=fig06\n", host.trim()),
    )
    .unwrap();
    let left = [
        "data/.fig06.tmp-4194305-0.csv",
        "figures/.fig06.tmp-4194305-1.png",
        ".paper.tmp-4194305-2.md",
    ];
    for path in left {
        std::fs::write(crate_file(path), "x").unwrap();
    }
    let o = Command::new(table3).output().unwrap();
    let err = text(&o.stderr);
    let taken: Vec<bool> = left.iter().map(|p| crate_file(p).exists()).collect();
    for path in left {
        let _ = std::fs::remove_file(crate_file(path));
    }
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("note: taking over") && err.contains("process 4194305"),
        "{err}"
    );
    assert_eq!(taken, [false; 3], "{err}");
    assert!(!lock.exists(), "released when the taker ends");
}

// Fails without the root in their lines: the studies said "wrote data/x.csv" (here the
// redraws, which are quick, "redrew figures/x.png from data/x.csv"), read as relative to the
// working directory, whatever checkout they were built in and write into.
fn the_studies_say_which_checkout_they_write_into() {
    let root = env!("CARGO_MANIFEST_DIR");
    for (program, figure) in [
        (env!("CARGO_BIN_EXE_work_precision"), "work_precision"),
        (env!("CARGO_BIN_EXE_contact_law_wear"), "contact_law_wear"),
    ] {
        // Run elsewhere than the checkout, as a shared build would be.
        let o = Command::new(program)
            .arg("--redraw")
            .current_dir(std::env::temp_dir())
            .output()
            .unwrap();
        let out = text(&o.stdout);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let line = format!("redrew figures/{figure}.png from data/{figure}.csv in {root}\n");
        assert!(out.contains(&line), "{out}");
    }
}

// Fails without the check before the claim: `work_precision --redraw --rule` claimed the
// outputs first, so it took over the lock a killed program left, removing that program's
// temporaries, before refusing its own arguments (and, beside a live program, was refused for
// that program's claim instead of for its arguments).
fn conflicting_flags_are_refused_before_the_outputs_are_claimed() {
    let lock = paper_lock();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let gone = format!("pid=4194305\nhost={}\ncommand=fig06\n", host.trim());
    std::fs::write(&lock, &gone).unwrap();
    let left = crate_file("data/.fig06.tmp-4194305-0.csv");
    std::fs::write(&left, "x").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_work_precision"))
        .args(["--redraw", "--rule"])
        .output()
        .unwrap();
    // contact_law_wear ignored --table3 beside --redraw, exit 0.
    let law_wear = Command::new(env!("CARGO_BIN_EXE_contact_law_wear"))
        .args(["--redraw", "--table3"])
        .output()
        .unwrap();
    let (held, kept) = (std::fs::read_to_string(&lock), left.exists());
    let _ = std::fs::remove_file(&lock);
    let _ = std::fs::remove_file(&left);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("at most one of --redraw, --rule"), "{err}");
    assert!(!err.contains("taking over"), "{err}");
    assert_eq!(held.ok(), Some(gone), "the lock it found is left as it was");
    assert!(kept, "the temporary beside it is left as it was");
    let err = text(&law_wear.stderr);
    assert_eq!(law_wear.status.code(), Some(2), "{err}");
    assert!(err.contains("at most one of --redraw, --table3"), "{err}");
}

// Fails without the claim of a name: the paper claim was a sweep file's claim, which refuses a
// folder holding another command's manifest or live folder lock, so the manifest that
// `jointwear run … --out .` leaves in the crate root made every paper program exit 2. That
// command writes only its own files there, never paper.md nor into figures/ or data/ (a
// command whose --out is there claims the paper's outputs too).
fn a_commands_folder_in_the_crate_root_does_not_block_the_paper_programs() {
    let manifest = crate_file("jointwear-manifest.txt");
    // (A checkout's own manifest, from such a run, is left to it.)
    let ours = !manifest.exists();
    if ours {
        std::fs::write(
            &manifest,
            "# jointwear run data/scenes/standard.toml --out .\n\
             # the files of this run; other files here are not from it\n",
        )
        .unwrap();
    }
    // That command still writing there: its folder lock, held by this live process.
    let folder_lock = crate_file(".jointwear.lock");
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let held = format!(
        "pid={}\nhost={}\ncommand=jointwear run x --out .\n",
        std::process::id(),
        host.trim()
    );
    let mut outcomes = Vec::new();
    for live in [false, true] {
        if live {
            std::fs::write(&folder_lock, &held).unwrap();
        }
        let o = Command::new(env!("CARGO_BIN_EXE_work_precision"))
            .arg("--redraw")
            .output()
            .unwrap();
        outcomes.push((o.status.code(), text(&o.stderr)));
    }
    let _ = std::fs::remove_file(&folder_lock);
    if ours {
        std::fs::remove_file(&manifest).unwrap();
    }
    for (code, err) in outcomes {
        assert_eq!(code, Some(0), "{err}");
    }
    assert!(!paper_lock().exists(), "released when it ends");
}
