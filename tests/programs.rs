//! The paper's programs refuse an argument they do not take, with exit code 2, before they
//! compute or write anything; `--help` prints what they do and writes nothing.
//!
//! Every program here writes under a temporary output root (`JOINTWEAR_OUTPUT_ROOT`), never into
//! the checkout: its lock and outputs there collided with a second test run, or with a user's
//! `fig06` writing the checkout's figures; each test checks that it leaves the checkout as it
//! found it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::SystemTime;

fn crate_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// A temporary output root for the programs of one test, removed when dropped.
struct Root(PathBuf);

impl Root {
    /// An empty root; with `data`, holding a copy of the checkout's `data/` (what `--redraw`
    /// and the studies' records read back).
    fn new(name: &str, data: bool) -> Root {
        let dir =
            std::env::temp_dir().join(format!("jointwear-programs-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        if data {
            copy_dir(&crate_file("data"), &dir.join("data"));
            std::fs::create_dir_all(dir.join("figures")).unwrap();
        }
        Root(dir)
    }

    fn file(&self, path: &str) -> PathBuf {
        self.0.join(path)
    }

    /// `program` writing under this root.
    fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("JOINTWEAR_OUTPUT_ROOT", &self.0);
        c
    }

    /// The lock file of the paper's outputs under this root.
    fn lock(&self) -> PathBuf {
        self.file(".paper-outputs.lock")
    }

    /// The files under this root, with when each was last written.
    fn files(&self) -> Vec<(PathBuf, SystemTime)> {
        let mut files = Vec::new();
        let mut dirs = vec![self.0.clone()];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    dirs.push(path);
                } else {
                    files.push((path.clone(), modified(&path)));
                }
            }
        }
        files.sort();
        files
    }
}

impl Drop for Root {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// When `path` was last written.
fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// What the checkout holds where a paper program writes: `git status --ignored` (every file
/// added, changed or removed, ignored ones such as `.paper-outputs.lock` included) and when
/// each file of the crate root, `data/`, `data/golden/` and `figures/` was last written (a
/// file rewritten as it was, or written and removed again by git's measure, still shows).
fn checkout() -> (String, Vec<(PathBuf, SystemTime)>) {
    // (`--no-optional-locks`: a status that refreshes git's index would write the checkout.)
    let status = Command::new("git")
        .arg("-C")
        .arg(env!("CARGO_MANIFEST_DIR"))
        .args(["--no-optional-locks", "status", "--porcelain", "--ignored"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map_or_else(|| "not a git work tree".into(), |o| text(&o.stdout));
    let mut files = Vec::new();
    for dir in ["", "data", "data/golden", "figures"] {
        for entry in std::fs::read_dir(crate_file(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                files.push((path.clone(), modified(&path)));
            }
        }
    }
    files.sort();
    (status, files)
}

/// Runs `test` and checks that it left the checkout as it found it ([`checkout`]).
fn leaving_the_checkout_unchanged(test: impl FnOnce()) {
    let before = checkout();
    test();
    let after = checkout();
    assert_eq!(after.0, before.0, "git status of the checkout changed");
    assert_eq!(after.1, before.1, "a file of the checkout was written");
}

/// Runs `program` with `args` under an empty output root and checks that it wrote nothing.
fn run_writing_nothing(program: &str, args: &[&str]) -> (Output, PathBuf) {
    let root = Root::new(&format!("nothing-{}", args.join("")), false);
    let o = root.command(program).args(args).output().unwrap();
    assert_eq!(
        root.files(),
        [],
        "{program} {args:?} wrote: {}",
        text(&o.stdout)
    );
    (o, root.0.clone())
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

// Fails without the check: `fig06 --quick` and `fig06 --help` ran the full 32-member figure,
// rewrote figures/fig06.png and data/fig06.csv and exited 0.
#[test]
fn a_figure_program_refuses_an_argument_it_does_not_take() {
    leaving_the_checkout_unchanged(|| {
        let fig06 = env!("CARGO_BIN_EXE_fig06");
        let (o, _) = run_writing_nothing(fig06, &["--quick"]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
        let err = text(&o.stderr);
        assert!(
            err.contains("`--quick`") && err.contains("no arguments"),
            "{err}"
        );
        let (o, root) = run_writing_nothing(fig06, &["--help"]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        assert!(
            out.contains("Usage: fig06") && out.contains("data/fig06.csv"),
            "{out}"
        );
        let under = format!("(outputs under {}, JOINTWEAR_OUTPUT_ROOT)", root.display());
        assert!(out.contains(&under), "{out}");
    });
}

// Fails without the check: `report --al` (meant `--all`) ran the default report, rewrote
// paper.md with the slow studies' old results and exited 0.
#[test]
fn the_report_refuses_a_misspelt_flag() {
    leaving_the_checkout_unchanged(|| {
        let (o, _) = run_writing_nothing(env!("CARGO_BIN_EXE_report"), &["--al"]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
        let err = text(&o.stderr);
        assert!(
            err.contains("`--al`") && err.contains("one of --all"),
            "{err}"
        );
    });
}

// Fails without the check: `golden_record --help` re-recorded the golden statistics with the
// reason "--help".
// The checkout's data/golden/ensemble.toml, which the golden tests read, is written by no
// run here (`leaving_the_checkout_unchanged`), nor under a moved output root: golden_record
// records the checkout's, so it refuses to run with one.
#[test]
fn golden_record_takes_one_reason_and_help_records_nothing() {
    leaving_the_checkout_unchanged(|| {
        let program = env!("CARGO_BIN_EXE_golden_record");
        let (o, _) = run_writing_nothing(program, &["--help"]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        assert!(text(&o.stdout).contains("Usage: golden_record REASON"));
        for args in [&["--quick"][..], &[], &["a", "b"], &["a reason"]] {
            let (o, _) = run_writing_nothing(program, args);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o.stderr));
        }
        let (o, _) = run_writing_nothing(program, &["a reason"]);
        let err = text(&o.stderr);
        assert!(
            err.contains("JOINTWEAR_OUTPUT_ROOT") && err.contains("data/golden/ensemble.toml"),
            "{err}"
        );
    });
}

// The programs that claim the outputs run one after another, in one test: two tests running
// them at once would refuse each other.
#[test]
fn the_paper_programs_that_write_claim_the_outputs_in_turn() {
    leaving_the_checkout_unchanged(|| {
        let root = Root::new("claims", true);
        a_second_paper_program_is_refused_while_one_writes_the_outputs(&root);
        a_killed_programs_lock_is_taken_over_with_the_temporaries_it_left(&root);
        the_studies_say_which_root_they_write_into(&root);
        conflicting_flags_are_refused_before_the_outputs_are_claimed(&root);
        a_commands_folder_in_the_root_does_not_block_the_paper_programs(&root);
    });
}

// Fails without the check: a root that does not exist was written as if it did, its folders
// created, or refused later with an I/O error naming a file in it.
#[test]
fn a_moved_output_root_that_does_not_exist_is_refused() {
    leaving_the_checkout_unchanged(|| {
        let root = Root::new("missing", false);
        let missing = root.file("none");
        let o = Command::new(env!("CARGO_BIN_EXE_table3"))
            .env("JOINTWEAR_OUTPUT_ROOT", &missing)
            .output()
            .unwrap();
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("JOINTWEAR_OUTPUT_ROOT") && err.contains("an existing directory"),
            "{err}"
        );
        assert!(!missing.exists());
    });
}

// Fails without the claim: the second table3 ran beside the first and exited 0, both writing
// data/table3.csv; a figure program beside the report could leave its figure beside the other
// process's CSV.
fn a_second_paper_program_is_refused_while_one_writes_the_outputs(root: &Root) {
    let lock = root.lock();
    let table3 = env!("CARGO_BIN_EXE_table3");
    let first = root
        .command(table3)
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
    let o = root.command(table3).output().unwrap();
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
    // working directory, whatever root the program writes into.
    let out = text(&first.stdout);
    let wrote = format!("wrote data/table3.csv in {} from", root.0.display());
    assert!(out.contains(&wrote), "{out}");
    assert!(root.file("data/table3.csv").exists());
}

// Fails without the cleanup: the lock of a killed program (a process of this host that no
// longer runs: a pid beyond Linux's largest) was taken over without a word, and the
// temporaries it left in data/, figures/ and beside paper.md stayed there for good.
fn a_killed_programs_lock_is_taken_over_with_the_temporaries_it_left(root: &Root) {
    let lock = root.lock();
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
        std::fs::write(root.file(path), "x").unwrap();
    }
    let o = root.command(table3).output().unwrap();
    let err = text(&o.stderr);
    let taken: Vec<bool> = left.iter().map(|p| root.file(p).exists()).collect();
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
// working directory, whatever root they write into.
fn the_studies_say_which_root_they_write_into(root: &Root) {
    for (program, figure) in [
        (env!("CARGO_BIN_EXE_work_precision"), "work_precision"),
        (env!("CARGO_BIN_EXE_contact_law_wear"), "contact_law_wear"),
    ] {
        // Run elsewhere than the root, as a shared build would be.
        let o = root
            .command(program)
            .arg("--redraw")
            .current_dir(std::env::temp_dir())
            .output()
            .unwrap();
        let out = text(&o.stdout);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let line = format!(
            "redrew figures/{figure}.png from data/{figure}.csv in {}\n",
            root.0.display()
        );
        assert!(out.contains(&line), "{out}");
        assert!(root.file(&format!("figures/{figure}.png")).exists());
    }
}

// Fails without the check before the claim: `work_precision --redraw --rule` claimed the
// outputs first, so it took over the lock a killed program left, removing that program's
// temporaries, before refusing its own arguments (and, beside a live program, was refused for
// that program's claim instead of for its arguments).
fn conflicting_flags_are_refused_before_the_outputs_are_claimed(root: &Root) {
    let lock = root.lock();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let gone = format!("pid=4194305\nhost={}\ncommand=fig06\n", host.trim());
    std::fs::write(&lock, &gone).unwrap();
    let left = root.file("data/.fig06.tmp-4194305-0.csv");
    std::fs::write(&left, "x").unwrap();
    let o = root
        .command(env!("CARGO_BIN_EXE_work_precision"))
        .args(["--redraw", "--rule"])
        .output()
        .unwrap();
    // contact_law_wear ignored --table3 beside --redraw, exit 0.
    let law_wear = root
        .command(env!("CARGO_BIN_EXE_contact_law_wear"))
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
fn a_commands_folder_in_the_root_does_not_block_the_paper_programs(root: &Root) {
    std::fs::write(
        root.file("jointwear-manifest.txt"),
        "# jointwear run data/scenes/standard.toml --out .\n\
         # the files of this run; other files here are not from it\n",
    )
    .unwrap();
    // That command still writing there: its folder lock, held by this live process.
    let folder_lock = root.file(".jointwear.lock");
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
        let o = root
            .command(env!("CARGO_BIN_EXE_work_precision"))
            .arg("--redraw")
            .output()
            .unwrap();
        outcomes.push((o.status.code(), text(&o.stderr)));
    }
    let _ = std::fs::remove_file(&folder_lock);
    for (code, err) in outcomes {
        assert_eq!(code, Some(0), "{err}");
    }
    assert!(!root.lock().exists(), "released when it ends");
}

// Fails without the columns: data/benchmarks.csv held medians without saying when or on which
// machine criterion measured them, and the report compared medians of different hosts.
#[test]
fn the_benchmark_summary_names_when_and_where_each_bench_ran() {
    leaving_the_checkout_unchanged(|| {
        let root = Root::new("benchmarks", false);
        let estimates = r#"{"median":{"point_estimate":12.5,"confidence_interval":
            {"lower_bound":12.0,"upper_bound":13.0}},"median_abs_dev":{"point_estimate":0.25,
            "confidence_interval":{"lower_bound":0.2,"upper_bound":0.3}}}"#;
        let file = root.file("criterion/rhs/standard/new/estimates.json");
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(&file, estimates).unwrap();
        // 2026-01-02 03:04:05 UTC
        let when = SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_767_323_045);
        let f = std::fs::File::options().write(true).open(&file).unwrap();
        f.set_modified(when).unwrap();
        drop(f);
        let o = root
            .command(env!("CARGO_BIN_EXE_bench_summary"))
            .env("CRITERION_HOME", root.file("criterion"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
        let csv = std::fs::read_to_string(root.file("data/benchmarks.csv")).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "bench,median_ns,ci_low_ns,ci_high_ns,mad_ns,measured_utc,machine"
        );
        let row: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(
            &row[..6],
            [
                "rhs/standard",
                "12.5",
                "12",
                "13",
                "0.25",
                "2026-01-02 03:04 UTC"
            ]
        );
        assert!(row[6].ends_with(" threads)"), "{}", lines[1]);
    });
}
