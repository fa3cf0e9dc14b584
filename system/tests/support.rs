//! What the end-to-end tests of every package share: a sandbox per test (its
//! result and iceoryx2 namespace directories, checked clean and removed), the
//! binaries cargo built, and helpers over processes and results. A package's
//! test binary includes it with `#[path]`, as it includes `tests/util.rs`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::output::write_results;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::named::Named;
use learnpnp_flags::args::parse_experiment_flags;
use learnpnp_system::ipc::namespace::{Namespace, SHM_DIR};
use learnpnp_system::multiprocess::supervisor::{IDENTITY_FILE, run_work_dir};
use serde_json::Value;
use shm_layouts::{EpisodeEvent, Header, SENDER_SIMULATOR};

use crate::util::{run_quietly, text};

/// A binary of the workspace that cargo built beside this test's binary
/// (`target/<profile>/`; test binaries sit in its `deps/`). `cargo test
/// --workspace` builds every package's binaries before any test runs; a test
/// never builds one itself.
pub(crate) fn workspace_binary(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    let dir = exe
        .parent()
        .and_then(Path::parent)
        .expect("a test binary in target/<profile>/deps");
    let path = dir.join(name);
    assert!(
        path.is_file(),
        "{} is missing: run the tests with `cargo test --workspace`, which builds it",
        path.display()
    );
    path
}

/// The supervisor: this package's own binary when it is the system crate's.
pub(crate) fn supervisor_binary() -> PathBuf {
    option_env!("CARGO_BIN_EXE_learnpnp-supervisor")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_binary("learnpnp-supervisor"))
}

/// A short lock-step Keepaway run (150 episodes, evaluated every 50) with its
/// seed and learner; without them, its first 8 arguments.
pub(crate) const SHORT: [&str; 12] = [
    "--episodes",
    "150",
    "--eval-every",
    "50",
    "--eval-episodes",
    "3",
    "--greedy-episodes",
    "3",
    "--seed",
    "5",
    "--algo",
    "soft-sosmc",
];

/// A test's directories: results, and iceoryx2 namespaces (kept short:
/// unix socket paths are).
pub(crate) struct Sandbox {
    root: PathBuf,
    ipc: PathBuf,
}

impl Sandbox {
    pub(crate) fn new(name: &str) -> Self {
        let root = std::env::temp_dir().join(format!("learnpnp-mp-{name}-{}", std::process::id()));
        let ipc = PathBuf::from(format!("/tmp/lpt{}-{name}", std::process::id()));
        for dir in [&root, &ipc] {
            let _ = fs::remove_dir_all(dir);
            fs::create_dir_all(dir).unwrap();
        }
        Sandbox { root, ipc }
    }

    pub(crate) fn ipc(&self) -> PathBuf {
        self.ipc.clone()
    }

    pub(crate) fn out(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    pub(crate) fn supervisor(&self, out: &str, args: &[&str]) -> Command {
        let mut command = Command::new(supervisor_binary());
        command
            .arg("--out")
            .arg(self.out(out))
            .args(["--floor-round-trips", "2000"])
            .args(args)
            .env("LEARNPNP_IPC_DIR", self.ipc())
            .stdin(Stdio::null());
        command
    }

    /// Checks that the namespaces of `prefixes` left nothing, that the
    /// namespace directory is empty and that no process of this test lives.
    pub(crate) fn assert_clean(&self, prefixes: &[String]) {
        for prefix in prefixes {
            let left: Vec<String> = fs::read_dir(SHM_DIR)
                .unwrap()
                .flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with(prefix.as_str()))
                .collect();
            assert!(left.is_empty(), "{SHM_DIR} still holds {left:?}");
        }
        let left: Vec<_> = fs::read_dir(self.ipc()).unwrap().flatten().map(|e| e.path()).collect();
        assert!(left.is_empty(), "the namespace directory still holds {left:?}");
        assert!(
            wait_until(Duration::from_secs(5), || pids_with(&self.root.to_string_lossy())
                .is_empty()),
            "processes of this test are still running: {:?}",
            pids_with(&self.root.to_string_lossy())
        );
    }
}

impl Drop for Sandbox {
    fn drop(&mut self) {
        for pid in pids_with(&self.root.to_string_lossy()) {
            // SAFETY: kill has no memory effects.
            unsafe { libc::kill(pid, libc::SIGKILL) };
        }
        // A test that failed half-way leaves its runs' shared memory behind:
        // remove every namespace of the sandbox once its processes are gone.
        wait_until(Duration::from_secs(5), || {
            pids_with(&self.root.to_string_lossy()).is_empty()
        });
        for entry in fs::read_dir(&self.ipc).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if entry.path().is_dir()
                && let Ok(namespace) = Namespace::at(&self.ipc, &format!("{name}_"))
            {
                let _ = namespace.remove_all();
            }
        }
        let _ = fs::remove_dir_all(&self.root);
        let _ = fs::remove_dir_all(&self.ipc);
    }
}

pub(crate) fn summary(out: &Path) -> Value {
    let path = out.join("summary.json");
    serde_json::from_str(&fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

pub(crate) fn prefixes(summary: &Value) -> Vec<String> {
    summary["ipc_prefixes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap().to_string())
        .collect()
}

pub(crate) fn wait_until(limit: Duration, mut done: impl FnMut() -> bool) -> bool {
    let started = Instant::now();
    while started.elapsed() < limit {
        if done() {
            return true;
        }
        sleep(Duration::from_millis(20));
    }
    done()
}

/// Processes whose command line contains every one of `parts`.
pub(crate) fn pids_with_all(parts: &[&str]) -> Vec<i32> {
    let mut pids = Vec::new();
    for entry in fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<i32>() else {
            continue;
        };
        let Ok(cmdline) = fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = cmdline.split(|&b| b == 0).map(text).collect();
        let line = args.join(" ");
        if pid != std::process::id() as i32 && parts.iter().all(|p| line.contains(p)) {
            pids.push(pid);
        }
    }
    pids
}

pub(crate) fn pids_with(part: &str) -> Vec<i32> {
    pids_with_all(&[part])
}

pub(crate) fn kill(pid: i32, signal: i32) {
    // SAFETY: kill has no memory effects.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0, "kill {pid}");
}

/// Stops process `pid` (SIGSTOP) and waits until every thread of it has
/// stopped: a thread running on another core at the signal may still make a
/// call (its checkpoint writer, a rename) before the stop reaches it.
pub(crate) fn stop(pid: i32) {
    kill(pid, libc::SIGSTOP);
    let stopped = || {
        fs::read_dir(format!("/proc/{pid}/task")).is_ok_and(|tasks| {
            tasks.flatten().all(|task| {
                fs::read_to_string(task.path().join("stat")).is_ok_and(|stat| {
                    // The state follows the command name, which is in parentheses.
                    stat.rsplit_once(')')
                        .is_some_and(|(_, rest)| matches!(rest.trim_start().chars().next(), Some('T' | 't')))
                })
            })
        })
    };
    assert!(wait_until(Duration::from_secs(10), stopped), "{pid} did not stop");
}

pub(crate) fn finish(child: Child) -> Output {
    child.wait_with_output().expect("the supervisor runs")
}

/// Episode 1's event of this kind from run `run_id`'s simulator, every other field zero.
pub(crate) fn first_episode_event(run_id: u64, kind: u32) -> EpisodeEvent {
    EpisodeEvent {
        header: Header::new(SENDER_SIMULATOR, run_id),
        episode: 1,
        kind,
        mode: 0,
        forced_exploration: 0,
        reserved: [0; 2],
        cycles: 0,
        reserved2: 0,
        seconds: 0.0,
    }
}

/// The same experiment in one process, written as `learnpnp experiment` writes it.
pub(crate) fn in_process(domain: &str, algo: &str, seed: &str, protocol: &[&str], out: &Path) {
    let mut flags = vec!["--algo", algo, "--runs", "1", "--seed", seed];
    flags.extend_from_slice(protocol);
    let domain = DomainName::from_name(domain).expect("a domain");
    let spec = parse_experiment_flags(&flags)
        .expect("valid flags")
        .spec(domain)
        .expect("a spec");
    let output = run_quietly(&spec, 2);
    write_results(&output, &mut ResultDir::open(out).expect("a result directory")).expect("results written");
}

/// Waits for `child`, the supervisor of `sandbox`'s run `system` (keepaway-position,
/// Soft-SoSMC, `seed`, `protocol`), and checks that it succeeded and played the
/// episodes of the same experiment in one process: `episodes.csv`, `curve.csv`
/// and `values.bin` byte-identical.
pub(crate) fn assert_plays_in_process(child: Child, sandbox: &Sandbox, seed: &str, protocol: &[&str]) {
    let output = finish(child);
    assert!(output.status.success(), "{}", text(&output.stderr));
    in_process(
        "keepaway-position",
        "soft-sosmc",
        seed,
        protocol,
        &sandbox.out("inproc"),
    );
    assert_same_files(
        &sandbox.out("system"),
        &sandbox.out("inproc"),
        &["episodes.csv", "curve.csv", "values.bin"],
    );
}

/// The identity of run 0 of `out` (its prefix and id), once it exists.
pub(crate) fn identity(out: &Path) -> (String, u64) {
    let path = || run_work_dir(out, 0).join(IDENTITY_FILE);
    assert!(wait_until(Duration::from_secs(60), || path().exists()));
    let identity: Value = serde_json::from_str(&fs::read_to_string(path()).unwrap()).unwrap();
    (
        identity["ipc_prefix"].as_str().unwrap().to_string(),
        identity["run_id"].as_u64().unwrap(),
    )
}

pub(crate) fn assert_same_files(a: &Path, b: &Path, files: &[&str]) {
    for file in files {
        let (x, y) = (fs::read(a.join(file)).unwrap(), fs::read(b.join(file)).unwrap());
        assert!(x == y, "{file} differs between {} and {}", a.display(), b.display());
    }
}

/// A foreign process's port on the run's services.
pub(crate) fn foreign_node(sandbox: &Sandbox, prefix: &str) -> Node<ipc::Service> {
    let namespace = Namespace::at(&sandbox.ipc(), prefix).unwrap();
    learnpnp_system::ipc::services::node(&namespace, "foreign").unwrap()
}
