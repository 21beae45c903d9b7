//! Sweeps on a real cluster: README's Slurm job array, submitted to a single-node Slurm cluster
//! started on this machine (Debian's `slurm-wlm` and `munge`), gives shards whose merge is the
//! one-machine sweep bit for bit (up to the wall times).
//!
//! Skipped, saying why on stderr, where the programs are missing or the test is not root
//! (slurmd runs jobs as their user). `.ci/run` installs them. The cluster lives in a temporary
//! folder (its slurm.conf, munge key and socket, state, spool and logs) and its daemons are
//! stopped at the end, also when the test fails.

mod common;

use common::*;
use std::fs;
use std::io::{Read, Write};
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

/// The programs the cluster needs.
const PROGRAMS: [&str; 7] = [
    "munged",
    "slurmctld",
    "slurmd",
    "sinfo",
    "sbatch",
    "scancel",
    "bash",
];

/// The polls of the cluster's state, every [`POLL`]: a guard against a hang (a node that never
/// comes up, a job that never runs), not the measure of the test, which takes about 5 s.
const POLLS: u32 = 1200;
const POLL: Duration = Duration::from_millis(250);

/// `name`'s path on PATH or in the system folders a root shell has on it.
fn program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/bin", "/bin"].map(PathBuf::from))
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// The reason to skip, if any.
fn skip_reason() -> Option<String> {
    let missing: Vec<&str> = PROGRAMS
        .into_iter()
        .filter(|p| program(p).is_none())
        .collect();
    if !missing.is_empty() {
        return Some(format!(
            "{} not found (Debian: apt-get install slurm-wlm munge)",
            missing.join(", ")
        ));
    }
    let uid = fs::metadata("/proc/self").map(|m| m.uid());
    (uid.ok() != Some(0)).then(|| "not root: slurmd runs its jobs as their user".into())
}

/// A free TCP port of this machine (for slurmctld and slurmd).
fn free_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    listener.local_addr().unwrap().port()
}

/// A single-node Slurm cluster in `dir`; dropping it cancels its jobs and stops its daemons.
struct Cluster {
    dir: PathBuf,
    /// munged, slurmctld, slurmd, in the order started.
    daemons: Vec<Child>,
}

impl Cluster {
    /// Starts munged, slurmctld and slurmd with their files in `dir`, and waits for the node.
    fn start(dir: &Path) -> Cluster {
        // munged refuses a socket folder that others cannot traverse or may write to.
        fs::set_permissions(dir, fs::Permissions::from_mode(0o755)).unwrap();
        // munged's key: random bytes only its owner may read (what `mungekey --create` writes).
        let key = dir.join("munge.key");
        let mut random = vec![0u8; 1024];
        fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut random))
            .unwrap();
        fs::write(&key, random).unwrap();
        fs::set_permissions(&key, fs::Permissions::from_mode(0o400)).unwrap();
        for d in ["state", "spool"] {
            fs::create_dir(dir.join(d)).unwrap();
        }
        let mut cluster = Cluster {
            dir: dir.to_path_buf(),
            daemons: Vec::new(),
        };
        let socket = dir.join("munge.sock");
        let f = |name: &str| format!("{}", dir.join(name).display());
        cluster.spawn(
            "munged",
            &[
                "--foreground",
                &format!("--socket={}", socket.display()),
                &format!("--key-file={}", key.display()),
                &format!("--pid-file={}", f("munged.pid")),
                &format!("--seed-file={}", f("munged.seed")),
            ],
        );
        // slurmctld's first request to munged must find its socket.
        cluster.poll("munged's socket", || socket.exists());
        let conf = dir.join("slurm.conf");
        fs::write(
            &conf,
            format!(
                "ClusterName=jointwear\n\
                 SlurmctldHost=localhost(127.0.0.1)\n\
                 SlurmctldPort={}\n\
                 SlurmdPort={}\n\
                 SlurmUser=root\n\
                 SlurmdUser=root\n\
                 AuthType=auth/munge\n\
                 AuthInfo=socket={}\n\
                 CredType=cred/munge\n\
                 StateSaveLocation={}\n\
                 SlurmdSpoolDir={}\n\
                 SlurmctldPidFile={}\n\
                 SlurmdPidFile={}\n\
                 SlurmctldLogFile={}\n\
                 SlurmdLogFile={}\n\
                 MailProg=/bin/true\n\
                 ProctrackType=proctrack/linuxproc\n\
                 TaskPlugin=task/none\n\
                 JobAcctGatherType=jobacct_gather/none\n\
                 AccountingStorageType=accounting_storage/none\n\
                 SelectType=select/cons_tres\n\
                 SelectTypeParameters=CR_CPU\n\
                 MpiDefault=none\n\
                 ReturnToService=2\n\
                 SlurmdParameters=config_overrides\n\
                 NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n\
                 PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n",
                free_port(),
                free_port(),
                socket.display(),
                f("state"),
                f("spool"),
                f("slurmctld.pid"),
                f("slurmd.pid"),
                f("slurmctld.log"),
                f("slurmd.log"),
            ),
        )
        .unwrap();
        let conf = format!("{}", conf.display());
        cluster.spawn("slurmctld", &["-D", "-f", &conf]);
        cluster.spawn("slurmd", &["-D", "-f", &conf, "-N", "localhost"]);
        cluster.poll("the node idle", || {
            let o = cluster.command("sinfo").args(["-h", "-o", "%t"]).output();
            o.is_ok_and(|o| stdout(&o).trim() == "idle")
        });
        cluster
    }

    /// Starts daemon `name` with `args` in the foreground, its output in `<name>.out`.
    fn spawn(&mut self, name: &str, args: &[&str]) {
        let out = fs::File::create(self.dir.join(format!("{name}.out"))).unwrap();
        let child = Command::new(program(name).unwrap())
            .args(args)
            .stdin(Stdio::null())
            .stdout(out.try_clone().unwrap())
            .stderr(out)
            .spawn()
            .unwrap();
        self.daemons.push(child);
    }

    /// A command of this cluster (`SLURM_CONF` set, no Slurm variables of an enclosing job),
    /// run in its folder with the built `jointwear` first on PATH.
    fn command(&self, name: &str) -> Command {
        let mut c = Command::new(program(name).unwrap());
        for (k, _) in std::env::vars_os() {
            if k.to_string_lossy().starts_with("SLURM_") {
                c.env_remove(k);
            }
        }
        let bin = Path::new(env!("CARGO_BIN_EXE_jointwear")).parent().unwrap();
        let path = std::env::var_os("PATH").unwrap_or_default();
        let path = std::env::join_paths(
            std::iter::once(bin.to_path_buf()).chain(std::env::split_paths(&path)),
        )
        .unwrap();
        c.env("SLURM_CONF", self.dir.join("slurm.conf"))
            .env("PATH", path)
            .current_dir(&self.dir);
        c
    }

    /// Runs `script` with bash (stopping at the first failure) in the cluster's folder, and
    /// returns its output; fails the test, with the daemons' logs, if it does not end.
    fn bash(&self, script: &str) -> Output {
        let child = self
            .command("bash")
            .args(["-euo", "pipefail", "-c", script])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let id = child.id();
        let mut child = Some(child);
        self.poll(&format!("the end of `{script}`"), || {
            child
                .as_mut()
                .is_some_and(|c| c.try_wait().unwrap().is_some())
        });
        let o = child.take().unwrap().wait_with_output().unwrap();
        assert!(
            o.status.success(),
            "`{script}` (pid {id}) failed: {}{}\n{}",
            stdout(&o),
            stderr(&o),
            self.logs()
        );
        o
    }

    /// Waits until `done`, at most [`POLLS`] times [`POLL`]; fails with the logs if never.
    fn poll(&self, what: &str, mut done: impl FnMut() -> bool) {
        for _ in 0..POLLS {
            if done() {
                return;
            }
            std::thread::sleep(POLL);
        }
        panic!("no {what} after {POLLS} polls\n{}", self.logs());
    }

    /// The daemons' output and logs, for a failure's message.
    fn logs(&self) -> String {
        let names = [
            "munged.out",
            "slurmctld.out",
            "slurmctld.log",
            "slurmd.out",
            "slurmd.log",
        ];
        names
            .iter()
            .map(|n| {
                let text = fs::read_to_string(self.dir.join(n)).unwrap_or_default();
                format!("--- {n}:\n{text}")
            })
            .collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        if self.daemons.len() == 3 {
            // Jobs of a failed test would outlive slurmd in their slurmstepd.
            let _ = self.command("scancel").arg("--user=root").output();
        }
        for child in self.daemons.iter_mut().rev() {
            let _ = Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .status();
            // Ten seconds to shut down, then SIGKILL: never a daemon left behind.
            let ended = (0..100).any(|_| {
                std::thread::sleep(Duration::from_millis(100));
                child.try_wait().is_ok_and(|s| s.is_some())
            });
            if !ended {
                let _ = child.kill();
                let _ = child.wait();
            }
        }
    }
}

/// The README's code block that starts with `first_line` (without its fences).
fn readme_block(first_line: &str) -> String {
    let readme =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let start = readme
        .find(&format!("```sh\n{first_line}"))
        .unwrap_or_else(|| panic!("README has no block starting with `{first_line}`"));
    let block = &readme[start + "```sh\n".len()..];
    block[..block.find("```").unwrap()].to_string()
}

/// `text` with each `(from, to)` replaced (each `from` must occur).
fn replaced(mut text: String, replacements: &[(&str, &str)]) -> String {
    for (from, to) in replacements {
        assert!(
            text.contains(from),
            "README's block lacks `{from}`:\n{text}"
        );
        text = text.replace(from, to);
    }
    text
}

/// A sweep file's lines, each row without its wall time (the only field that may differ
/// between two runs of a case).
fn without_wall_time(path: &Path) -> Vec<String> {
    let text = fs::read_to_string(path).unwrap();
    // the sweep's id is the name of the header's last column
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let wall = header
        .split(',')
        .position(|h| h == "wall_time_s")
        .expect("a wall_time_s column");
    let mut out = vec![header.to_string()];
    out.extend(lines.map(|l| {
        let mut fields: Vec<&str> = l.split(',').collect();
        fields.remove(wall);
        fields.join(",")
    }));
    out
}

#[test]
fn readme_job_array_on_slurm_merges_into_the_one_machine_sweep() {
    if let Some(reason) = skip_reason() {
        // Straight to stderr: the test harness captures `eprintln!` of a passing test.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED cluster::readme_job_array_on_slurm_merges_into_the_one_machine_sweep: {reason}"
        );
        return;
    }
    let dir = temp_dir("cluster", "array");
    let cluster = Cluster::start(&dir);
    short_standard(&dir, "scene.toml", 1, &[]);
    // README's array, cut to 4 one-rotation cases over 3 tasks of 1 CPU (the node has 2).
    let script = replaced(
        readme_block("#!/bin/bash"),
        &[
            ("--array=1-20", "--array=1-3"),
            ("--cpus-per-task=8", "--cpus-per-task=1"),
            ("=0.01,0.02,0.05,0.1,0.2 ", "=0.02,0.1 "),
            ("=-500,-1000,-1500,-2000,-3000 ", "=-2000 "),
            ("=0.5,0.7,0.9", "=0.5,0.9"),
        ],
    );
    fs::write(dir.join("sweep.sbatch"), &script).unwrap();
    let submit_and_merge = readme_block("sbatch --wait sweep.sbatch");
    cluster.bash(&submit_and_merge);
    let shards = || -> Vec<String> {
        (1..=3)
            .map(|task| fs::read_to_string(dir.join(format!("shards/shard-{task}.csv"))).unwrap())
            .collect()
    };
    let first = shards();
    for (task, shard) in (1..).zip(&first) {
        let header = shard.lines().next().unwrap_or_default();
        assert!(
            header.starts_with("case,") && header.contains(",jointwear sweep fingerprint="),
            "{shard}"
        );
        assert!(header.contains(&format!(" shard={task}/3 ")), "{shard}");
    }
    // Submitted again (as after a time limit), the array's --resume runs no case twice: the
    // shards keep their rows, wall times included (without --resume every case runs again).
    cluster.bash(&submit_and_merge);
    assert_eq!(shards(), first);
    // The same sweep on this machine: README's command without its shard.
    let command = script[script.find("jointwear sweep").unwrap()..].replace("\\\n", " ");
    let one_machine = replaced(
        command,
        &[(
            "--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT --resume --out shards/shard-$SLURM_ARRAY_TASK_ID.csv",
            "--out whole.csv",
        )],
    );
    cluster.bash(&one_machine);
    drop(cluster);

    let (merged, whole) = (
        without_wall_time(&dir.join("sweep.csv")),
        without_wall_time(&dir.join("whole.csv")),
    );
    // Checked to fail: the one-machine sweep with restitution 0.5,0.7 differs from row 1 on.
    assert_eq!(merged, whole);
    assert!(
        whole[0].ends_with(" shard=1/1 cases=4 total=4"),
        "{}",
        whole[0]
    );
    assert_eq!(whole.len(), 1 + 4);
    // Every case ran, none failed: the error column is empty; the id column after it holds
    // the row's label check (`label-` and 16 hex digits).
    assert!(
        whole[1..].iter().all(|r| {
            let (rest, check) = r.rsplit_once(',').unwrap_or_default();
            let hash = check.strip_prefix("label-").unwrap_or_default();
            rest.ends_with(',') && hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit())
        }),
        "{whole:?}"
    );
    fs::remove_dir_all(&dir).unwrap();
}
