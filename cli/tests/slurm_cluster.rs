//! The Slurm job array of `docs/cluster/` run for real: the test starts a
//! one-node Slurm cluster of its own (munged, slurmctld and slurmd, every
//! file in a temporary directory, every port on this machine), submits
//! `slurm-array.sh` as an array of three shards and `slurm-merge.sh` as a job
//! depending on it, both unchanged but for their environment variables and
//! the array's size and CPUs on the sbatch command line, and checks that the
//! merged result is what one machine writes, file for file (the summary's
//! wall-clock figures aside, which the merge sums).
//!
//! Needs Debian's `slurm-wlm` and `munge` and root (the daemons run as root).
//! Without them the test says so and passes, unless `LEARNPNP_REQUIRE_SLURM`
//! is set, as `.ci/run` sets it after installing them. Every daemon, job
//! step and job process it started is killed, and its directory removed,
//! when it ends, also when it fails.

use std::collections::BTreeMap;
use std::fs;
use std::io::{Read, Write};
use std::net::TcpListener;
use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::util::{root, temp_dir, text};

/// The experiment `shards.rs` shards (a cheap one), as the scripts' variables.
const EXPERIMENT: [(&str, &str); 5] = [
    ("DOMAIN", "parr-russell"),
    ("ALGO", "sarsa-lambda"),
    ("RUNS", "5"),
    ("EPISODES", "200"),
    ("SEED", "9"),
];

/// The number of shards (the array's tasks).
const SHARDS: usize = 3;

/// The programs the cluster needs: its daemons and the clients the test uses.
const PROGRAMS: [&str; 6] = ["munged", "slurmctld", "slurmd", "sbatch", "scontrol", "sinfo"];

/// How long the node may take to come up idle.
const NODE_WAIT: Duration = Duration::from_secs(60);
/// How long the shards and the merge may take, from their submission (about
/// 10 s on two cores).
const JOBS_WAIT: Duration = Duration::from_secs(240);

/// Job states from which a job never completes.
const FAILED_STATES: [&str; 9] = [
    "FAILED",
    "CANCELLED",
    "TIMEOUT",
    "NODE_FAIL",
    "OUT_OF_MEMORY",
    "BOOT_FAIL",
    "DEADLINE",
    "PREEMPTED",
    "REVOKED",
];

/// The path of `program` on PATH or in the system directories (the daemons
/// are in /usr/sbin, which a user's PATH may lack).
fn find(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/bin", "/bin"].map(PathBuf::from))
        .map(|dir| dir.join(program))
        .find(|file| fs::metadata(file).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0))
}

/// Whether the test must run rather than be skipped.
fn required() -> bool {
    std::env::var_os("LEARNPNP_REQUIRE_SLURM").is_some_and(|v| !v.is_empty() && v != "0")
}

/// The programs' paths, or why the cluster cannot be started here.
fn programs() -> Result<BTreeMap<&'static str, PathBuf>, String> {
    // SAFETY: geteuid has no preconditions and cannot fail.
    if unsafe { libc::geteuid() } != 0 {
        return Err("not root (the Slurm and munge daemons run as root)".into());
    }
    let (found, missing): (Vec<_>, Vec<_>) = PROGRAMS.iter().map(|&p| (p, find(p))).partition(|(_, f)| f.is_some());
    if !missing.is_empty() {
        let names: Vec<_> = missing.iter().map(|(p, _)| *p).collect();
        return Err(format!(
            "{} not installed (Debian's slurm-wlm and munge)",
            names.join(", ")
        ));
    }
    Ok(found.into_iter().map(|(p, f)| (p, f.expect("found"))).collect())
}

/// This machine's short host name, as slurmctld and slurmd know it.
fn short_hostname() -> String {
    let name = fs::read_to_string("/proc/sys/kernel/hostname").expect("the host name (/proc/sys/kernel/hostname)");
    let short = name.trim().split('.').next().unwrap_or_default().to_string();
    assert!(!short.is_empty(), "this machine has no host name");
    short
}

/// Two consecutive TCP ports free on this machine, for slurmctld and slurmd:
/// from 17000 to 18799, starting at one derived from the process id so that
/// concurrent runs do not collide.
fn free_ports() -> (u16, u16) {
    let start = (std::process::id() % 900) as u16;
    (0..900u16)
        .map(|i| 17000 + 2 * ((start + i) % 900))
        .find(|&port| TcpListener::bind(("0.0.0.0", port)).is_ok() && TcpListener::bind(("0.0.0.0", port + 1)).is_ok())
        .map(|port| (port, port + 1))
        .expect("two free ports between 17000 and 18799")
}

/// The last `n` lines of `file` (or why it cannot be read).
fn tail(file: &Path, n: usize) -> String {
    match fs::read(file) {
        Ok(bytes) => {
            let all = text(&bytes);
            let lines: Vec<_> = all.lines().collect();
            lines[lines.len().saturating_sub(n)..].join("\n")
        }
        Err(e) => format!("({e})"),
    }
}

/// The pids of the processes whose environment holds `marker` (`NAME=value`),
/// this process aside.
fn marked_processes(marker: &str) -> Vec<i32> {
    let Ok(entries) = fs::read_dir("/proc") else {
        return Vec::new();
    };
    let me = std::process::id() as i32;
    entries
        .flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<i32>().ok())
        .filter(|&pid| pid != me)
        .filter(|pid| {
            fs::read(format!("/proc/{pid}/environ"))
                .is_ok_and(|env| env.split(|&b| b == 0).any(|v| v == marker.as_bytes()))
        })
        .collect()
}

/// Sends `signal` to `pid`.
fn signal(pid: i32, signal: i32) {
    // SAFETY: kill has no memory preconditions; a gone pid gives ESRCH.
    unsafe {
        libc::kill(pid, signal);
    }
}

/// A one-node Slurm cluster in a temporary directory: its daemons run until
/// it is dropped, which kills them and everything they started and removes
/// the directory.
struct Cluster {
    /// The temporary directory holding every file of the cluster.
    dir: PathBuf,
    /// Its `slurm.conf`.
    conf: PathBuf,
    /// The programs' paths.
    programs: BTreeMap<&'static str, PathBuf>,
    /// `NAME=value` in the environment of every process the cluster starts
    /// (daemons, job steps, jobs), by which they are found when it stops.
    marker: (String, String),
    /// The daemons, in the order started.
    daemons: Vec<(&'static str, Child)>,
}

impl Cluster {
    /// Writes the configuration and a munge key and starts munged,
    /// slurmctld and slurmd; the node is not necessarily up yet.
    fn start(programs: BTreeMap<&'static str, PathBuf>) -> Cluster {
        let dir = temp_dir("slurm");
        // munged requires its socket's directory to be searchable by all,
        // and no directory on the way writable by others.
        fs::set_permissions(&dir, fs::Permissions::from_mode(0o755)).expect("the directory's permissions");
        let at = dir.clone();
        let path = |name: &str| at.join(name).display().to_string();
        for sub in ["munge", "state", "spool"] {
            fs::create_dir_all(dir.join(sub)).expect("a directory of the cluster");
        }
        let mut key = [0u8; 128];
        fs::File::open("/dev/urandom")
            .and_then(|mut f| f.read_exact(&mut key))
            .expect("a munge key from /dev/urandom");
        fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o600)
            .open(dir.join("munge/munge.key"))
            .and_then(|mut f| f.write_all(&key))
            .expect("the munge key");

        let host = short_hostname();
        let (ctld_port, slurmd_port) = free_ports();
        let conf = dir.join("slurm.conf");
        let settings = format!(
            "# A one-node cluster of the slurm_cluster test: every file here, every address this machine's.
ClusterName=learnpnptest
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={socket}
StateSaveLocation={state}
SlurmdSpoolDir={spool}
SlurmctldPidFile={ctld_pid}
SlurmdPidFile={slurmd_pid}
SlurmctldLogFile={ctld_log}
SlurmdLogFile={slurmd_log}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
SwitchType=switch/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
ReturnToService=2
SlurmdParameters=config_overrides
TmpFS={tmp}
NodeName={host} NodeAddr=127.0.0.1 CPUs=2 RealMemory=256 State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
",
            socket = path("munge/munge.socket"),
            state = path("state"),
            spool = path("spool"),
            ctld_pid = path("slurmctld.pid"),
            slurmd_pid = path("slurmd.pid"),
            ctld_log = path("slurmctld.log"),
            slurmd_log = path("slurmd.log"),
            tmp = dir.display(),
        );
        fs::write(&conf, settings).expect("slurm.conf");

        let marker = ("LEARNPNP_SLURM_TEST".to_string(), dir.display().to_string());
        let mut cluster = Cluster {
            dir,
            conf,
            programs,
            marker,
            daemons: Vec::new(),
        };
        let munge = [
            "--foreground".to_string(),
            format!("--socket={}", path("munge/munge.socket")),
            format!("--key-file={}", path("munge/munge.key")),
            format!("--pid-file={}", path("munge/munged.pid")),
            format!("--seed-file={}", path("munge/munged.seed")),
            format!("--log-file={}", path("munge/munged.log")),
        ];
        cluster.spawn("munged", &munge);
        cluster.wait_for("munged's socket", Duration::from_secs(20), |c| {
            c.dir.join("munge/munge.socket").exists()
        });
        let conf = cluster.conf.display().to_string();
        cluster.spawn("slurmctld", &["-D".into(), "-f".into(), conf.clone()]);
        cluster.spawn("slurmd", &["-D".into(), "-f".into(), conf, "-N".into(), host]);
        cluster
    }

    /// Starts the daemon `name`, its output going to `NAME.out`.
    fn spawn(&mut self, name: &'static str, args: &[String]) {
        let out = fs::File::create(self.dir.join(format!("{name}.out"))).expect("a daemon's output file");
        let err = out.try_clone().expect("a daemon's output file");
        let child = self
            .command(name)
            .args(args)
            .stdin(Stdio::null())
            .stdout(out)
            .stderr(err)
            .spawn()
            .unwrap_or_else(|e| panic!("{name} does not start: {e}"));
        self.daemons.push((name, child));
    }

    /// A command running `program` against this cluster: its configuration,
    /// the marker, and no Slurm settings of the test's own environment.
    fn command(&self, program: &str) -> Command {
        let mut command = Command::new(&self.programs[program]);
        for (name, _) in std::env::vars_os() {
            let name = name.to_string_lossy();
            if name.starts_with("SLURM_") || name.starts_with("SBATCH_") || name.starts_with("SALLOC_") {
                command.env_remove(&*name);
            }
        }
        command
            .env("SLURM_CONF", &self.conf)
            .env(&self.marker.0, &self.marker.1)
            .current_dir(&self.dir);
        command
    }

    /// Runs the client `program` with `args`.
    fn client(&self, program: &str, args: &[&str]) -> Output {
        self.command(program)
            .args(args)
            .stdin(Stdio::null())
            .output()
            .unwrap_or_else(|e| panic!("{program} does not run: {e}"))
    }

    /// Panics with `what`, the daemons' and the jobs' logs.
    fn fail(&self, what: &str) -> ! {
        let mut report = format!("{what}\n");
        let mut files: Vec<PathBuf> = fs::read_dir(&self.dir)
            .map(|entries| entries.flatten().map(|e| e.path()).collect())
            .unwrap_or_default();
        // The daemons' output (`NAME.out`, which holds their log files' lines
        // and what comes before those open) and the jobs' logs.
        files.retain(|f| {
            let name = f.file_name().unwrap_or_default().to_string_lossy();
            name.ends_with(".out") || (name.starts_with("learnpnp-") && name.ends_with(".log"))
        });
        files.sort();
        for file in files {
            report += &format!("\n== {} (its end):\n{}\n", file.display(), tail(&file, 40));
        }
        panic!("{report}");
    }

    /// Waits up to `limit` for `ready`, failing with the logs when a daemon
    /// has exited or the time is up.
    fn wait_for(&mut self, what: &str, limit: Duration, mut ready: impl FnMut(&Cluster) -> bool) {
        let started = Instant::now();
        loop {
            if ready(self) {
                return;
            }
            let exited = self
                .daemons
                .iter_mut()
                .find_map(|(name, child)| Some((*name, child.try_wait().ok()??)));
            if let Some((name, status)) = exited {
                self.fail(&format!("{name} exited ({status}) while waiting for {what}"));
            }
            if started.elapsed() > limit {
                self.fail(&format!("no {what} after {} s", limit.as_secs()));
            }
            std::thread::sleep(Duration::from_millis(250));
        }
    }

    /// Submits `script` with `args` and the scripts' variables; the job's id.
    fn sbatch(&self, args: &[&str], script: &Path, vars: &[(&str, String)]) -> String {
        let mut command = self.command("sbatch");
        command.arg("--parsable").args(args).arg(script).stdin(Stdio::null());
        for (name, value) in vars {
            command.env(name, value);
        }
        let output = command.output().expect("sbatch runs");
        if !output.status.success() {
            self.fail(&format!(
                "sbatch {args:?} {}: {}",
                script.display(),
                text(&output.stderr)
            ));
        }
        let id = text(&output.stdout)
            .trim()
            .split(';')
            .next()
            .unwrap_or_default()
            .to_string();
        if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
            self.fail(&format!("sbatch printed no job id: {:?}", text(&output.stdout)));
        }
        id
    }

    /// The states of job `id`'s tasks (one for a job that is no array), and
    /// its reasons for pending.
    fn job_states(&self, id: &str) -> Vec<(String, String)> {
        let output = self.client("scontrol", &["show", "job", "-o", id]);
        let field = |line: &str, name: &str| {
            line.split_whitespace()
                .find_map(|f| f.strip_prefix(name))
                .unwrap_or_default()
                .to_string()
        };
        text(&output.stdout)
            .lines()
            .filter(|l| l.contains("JobState="))
            .map(|l| (field(l, "JobState="), field(l, "Reason=")))
            .collect()
    }

    /// Kills the processes of the cluster: the jobs and job steps first,
    /// then the daemons, each given a moment to stop.
    fn stop(&mut self) {
        let marker = format!("{}={}", self.marker.0, self.marker.1);
        let daemons: Vec<i32> = self.daemons.iter().map(|(_, c)| c.id() as i32).collect();
        for pid in marked_processes(&marker) {
            if !daemons.contains(&pid) {
                signal(pid, libc::SIGKILL);
            }
        }
        // slurmd and slurmctld before munged, which they talk to as they stop.
        for (_, child) in self.daemons.iter_mut().rev() {
            signal(child.id() as i32, libc::SIGTERM);
            let asked = Instant::now();
            while matches!(child.try_wait(), Ok(None)) && asked.elapsed() < Duration::from_secs(10) {
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        // Whatever a daemon started as it stopped.
        let asked = Instant::now();
        loop {
            let left = marked_processes(&marker);
            if left.is_empty() || asked.elapsed() > Duration::from_secs(10) {
                break;
            }
            for pid in left {
                signal(pid, libc::SIGKILL);
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        self.stop();
        let _ = fs::remove_dir_all(&self.dir);
    }
}

/// Every file under `dir`, by its path relative to `dir`.
fn files_under(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, files: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for entry in fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .flatten()
        {
            let path = entry.path();
            if path.is_dir() {
                walk(base, &path, files);
            } else {
                let bytes = fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                files.insert(path.strip_prefix(base).expect("under the base").to_path_buf(), bytes);
            }
        }
    }
    let mut files = BTreeMap::new();
    walk(dir, dir, &mut files);
    files
}

/// A summary without its wall-clock figures (as `shards.rs` compares them).
fn without_wall_clock(summary: &[u8]) -> String {
    text(summary)
        .lines()
        .filter(|l| !l.contains("wall_seconds") && !l.contains("per_second"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_slurm_array_of_shards_and_its_merge_job_write_what_one_machine_writes() {
    let programs = match programs() {
        Ok(programs) => programs,
        Err(why) => {
            assert!(
                !required(),
                "LEARNPNP_REQUIRE_SLURM is set but the Slurm cluster cannot start: {why}"
            );
            eprintln!(
                "skipped: {why}; the test starts a one-node Slurm cluster (set LEARNPNP_REQUIRE_SLURM=1 to fail instead)"
            );
            return;
        }
    };
    let started = Instant::now();
    let mut cluster = Cluster::start(programs);
    cluster.wait_for("idle node (sinfo)", NODE_WAIT, |c| {
        let output = c.client("sinfo", &["--noheader", "--format=%t"]);
        output.status.success() && text(&output.stdout).trim() == "idle"
    });
    eprintln!(
        "slurm_cluster: the node is up after {:.1} s",
        started.elapsed().as_secs_f64()
    );

    let out = cluster.dir.join("exp");
    let learnpnp = env!("CARGO_BIN_EXE_learnpnp");
    let mut vars: Vec<(&str, String)> = vec![
        ("LEARNPNP", learnpnp.to_string()),
        ("SHARDS", SHARDS.to_string()),
        ("OUT", out.display().to_string()),
    ];
    vars.extend(EXPERIMENT.iter().map(|&(name, value)| (name, value.to_string())));
    let scripts = root().join("docs/cluster");
    // Two tasks at a time on the node's two CPUs.
    let array = format!("--array=0-{}", SHARDS - 1);
    let shards = cluster.sbatch(&[&array, "--cpus-per-task=1"], &scripts.join("slurm-array.sh"), &vars);
    let after = format!("--dependency=afterok:{shards}");
    let merge = cluster.sbatch(
        &[&after, "--kill-on-invalid-dep=yes"],
        &scripts.join("slurm-merge.sh"),
        &vars,
    );

    let submitted = Instant::now();
    loop {
        let tasks = cluster.job_states(&shards);
        let merged = cluster.job_states(&merge);
        let all = tasks.iter().chain(&merged);
        if let Some((state, reason)) = all
            .clone()
            .find(|(s, r)| FAILED_STATES.contains(&s.as_str()) || r == "DependencyNeverSatisfied")
        {
            cluster.fail(&format!(
                "a job did not complete ({state}, {reason}): shards {tasks:?}, merge {merged:?}"
            ));
        }
        if merged.first().is_some_and(|(s, _)| s == "COMPLETED") {
            break;
        }
        if submitted.elapsed() > JOBS_WAIT {
            cluster.fail(&format!(
                "the jobs did not finish in {} s: shards {tasks:?}, merge {merged:?}",
                JOBS_WAIT.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    eprintln!(
        "slurm_cluster: shards and merge done after {:.1} s",
        started.elapsed().as_secs_f64()
    );

    // The same experiment on one machine, without Slurm.
    let whole = cluster.dir.join("whole");
    let mut args = vec!["experiment".to_string(), EXPERIMENT[0].1.to_string()];
    for (flag, &(_, value)) in ["--algo", "--runs", "--episodes", "--seed"]
        .iter()
        .zip(&EXPERIMENT[1..])
    {
        args.extend([flag.to_string(), value.to_string()]);
    }
    args.extend([
        "--threads".into(),
        "2".into(),
        "--out".into(),
        whole.display().to_string(),
    ]);
    let output = Command::new(learnpnp).args(&args).output().expect("learnpnp runs");
    assert!(output.status.success(), "learnpnp {args:?}: {}", text(&output.stderr));

    let (mut expected, mut got) = (files_under(&whole), files_under(&out));
    let summary = Path::new("summary.json");
    let (Some(a), Some(b)) = (expected.remove(summary), got.remove(summary)) else {
        cluster.fail("a summary.json is missing")
    };
    assert_eq!(without_wall_clock(&a), without_wall_clock(&b), "summary.json differs");
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        got.keys().collect::<Vec<_>>(),
        "the merged directory does not hold the one-machine run's files"
    );
    for (file, bytes) in &expected {
        assert!(&got[file] == bytes, "{} differs", file.display());
    }
    assert!(expected.len() >= 5, "the run wrote only {:?}", expected.keys());
    eprintln!(
        "slurm_cluster: {} files the same; {:.1} s in all",
        expected.len() + 1,
        started.elapsed().as_secs_f64()
    );
}
