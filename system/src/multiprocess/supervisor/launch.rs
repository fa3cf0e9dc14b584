//! Starting the run's processes: where their binaries are, their command
//! lines, their logs, and the guarantee that they die with the supervisor
//! (`PR_SET_PDEATHSIG`) and are not hit by the terminal's Ctrl-C (their own
//! process group), so that the supervisor alone decides how they stop.

use learnpnp::named::Named;
use std::ffi::{OsStr, OsString};
use std::fs::File;
use std::io;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};

use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::Role;
use crate::multiprocess::RunContext;
use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec};
use learnpnp::rng::derive_seed;

/// The simulator's binary.
pub(crate) const SIM_BINARY: &str = "learnpnp-sim";

/// The agents' binary.
pub(crate) const AGENT_BINARY: &str = "learnpnp-agent";

/// The variables that give a world process its run (`shm_layouts/README.md`).
pub mod world_env {
    /// The run's iceoryx2 prefix.
    pub(crate) const PREFIX: &str = "LEARNPNP_IPC_PREFIX";
    /// The run's iceoryx2 root directory, ending in `/`.
    pub(crate) const ROOT: &str = "LEARNPNP_IPC_ROOT";
    /// The run id.
    pub(crate) const RUN_ID: &str = "LEARNPNP_RUN_ID";
    /// The run's index in the experiment (0-based; the agents' feed records carry it).
    pub const RUN: &str = "LEARNPNP_RUN";
    /// How many agents.
    pub const AGENTS: &str = "LEARNPNP_AGENTS";
    /// `lockstep` or `realtime`.
    pub(crate) const CLOCK: &str = "LEARNPNP_CLOCK";
    /// Real time: the cycle in milliseconds.
    pub(crate) const PERIOD_MS: &str = "LEARNPNP_PERIOD_MS";
    /// The wait strategy.
    pub(crate) const WAIT: &str = "LEARNPNP_WAIT";
    /// The world's seed for the run.
    pub const SEED: &str = "LEARNPNP_SEED";
}

/// Why a process cannot be started.
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    /// A binary is missing.
    #[error("{0} not found (build every binary: cargo build --release --bins)")]
    Missing(PathBuf),
    /// Cargo, to build the missing binaries, cannot be run.
    #[error("building {binaries} with cargo: {source}")]
    Cargo {
        /// The binaries it was to build.
        binaries: String,
        /// The error.
        source: io::Error,
    },
    /// Building the missing binaries failed.
    #[error("building {binaries} with cargo failed: {status}")]
    Build {
        /// The binaries it was to build.
        binaries: String,
        /// Cargo's exit status.
        status: ExitStatus,
    },
    /// The world's program does not exist.
    #[error("the world's program {program} does not exist ({hint})")]
    WorldMissing {
        /// The program, as the world's command names it.
        program: String,
        /// How to get it.
        hint: String,
    },
    /// Starting a process failed.
    #[error("starting {what}: {source}")]
    Spawn {
        /// The process.
        what: String,
        /// The error.
        source: io::Error,
    },
}

/// The bridge's binary (runs across hosts).
pub(crate) const BRIDGE_BINARY: &str = "learnpnp-bridge";

/// The view's binary (a run with a view; the package `learnpnp-view-process`).
pub(crate) const VIEW_BINARY: &str = "learnpnp-view";

/// The simulator's, the agents', the bridge's and the view's binaries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Binaries {
    /// `learnpnp-sim`.
    pub sim: PathBuf,
    /// `learnpnp-agent`.
    pub agent: PathBuf,
    /// `learnpnp-bridge`.
    pub bridge: PathBuf,
    /// `learnpnp-view`.
    pub view: PathBuf,
}

impl Binaries {
    /// The binaries in `dir` (the simulator's and the agents' must be there;
    /// the bridge's is looked for when a run crosses hosts: [`Binaries::bridge`]).
    pub(crate) fn in_dir(dir: &Path) -> Result<Self, LaunchError> {
        let binaries = Binaries {
            sim: dir.join(SIM_BINARY),
            agent: dir.join(AGENT_BINARY),
            bridge: dir.join(BRIDGE_BINARY),
            view: dir.join(VIEW_BINARY),
        };
        for path in [&binaries.sim, &binaries.agent] {
            if !path.is_file() {
                return Err(LaunchError::Missing(path.clone()));
            }
        }
        Ok(binaries)
    }

    /// The bridge's binary (the crate `learnpnp-bridge`), if it is there.
    pub fn bridge(&self) -> Result<&Path, LaunchError> {
        if self.bridge.is_file() {
            Ok(&self.bridge)
        } else {
            Err(LaunchError::Missing(self.bridge.clone()))
        }
    }

    /// The view's binary, if it is there.
    pub fn view(&self) -> Result<&Path, LaunchError> {
        if self.view.is_file() {
            Ok(&self.view)
        } else {
            Err(LaunchError::Missing(self.view.clone()))
        }
    }

    /// The binaries next to the running executable. Under `cargo run`, which
    /// builds only the binary it runs, the missing ones among those the run
    /// `needs` are built first, in one cargo invocation with the same cargo
    /// and profile; the others wait until a run needs them.
    pub fn beside_current_exe(needs: Needs) -> Result<Self, LaunchError> {
        let exe = std::env::current_exe().map_err(|source| LaunchError::Spawn {
            what: "locating the supervisor's executable".into(),
            source,
        })?;
        let dir = exe.parent().map(Path::to_path_buf).unwrap_or_default();
        // (binary, whether the run starts it)
        let binaries = [
            (SIM_BINARY, true),
            (AGENT_BINARY, true),
            (VIEW_BINARY, needs.view),
            (BRIDGE_BINARY, needs.bridge),
        ];
        let missing: Vec<&str> = binaries
            .into_iter()
            .filter(|&(binary, started)| started && !dir.join(binary).is_file())
            .map(|(binary, _)| binary)
            .collect();
        if !missing.is_empty() && std::env::var_os("CARGO").is_some() {
            build_with_cargo(&dir, &missing)?;
        }
        Self::in_dir(&dir)
    }
}

/// What a run starts besides the simulator and the agents, whose binaries
/// must then be there too.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Needs {
    /// The view's process (`--view`, `--record-mcap`, `--pnp-monitor`, `--view-jsonl`).
    pub view: bool,
    /// The bridge between hosts (a run across hosts).
    pub bridge: bool,
}

/// Builds the `missing` sibling binaries with the cargo that runs us (`cargo
/// run`), in the profile of the directory we run from. Cargo builds them in
/// the workspace's root, selecting them with `--bin` alone, as `cargo run`
/// there selected the supervisor: the same packages, so the same features,
/// and every dependency built for the supervisor is reused (naming their
/// packages with `-p` would resolve the features anew and rebuild most of them).
fn build_with_cargo(dir: &Path, missing: &[&str]) -> Result<(), LaunchError> {
    let binaries = missing.join(", ");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let root = workspace_root(&cargo).map_err(|source| LaunchError::Cargo {
        binaries: binaries.clone(),
        source,
    })?;
    let mut command = Command::new(&cargo);
    command.arg("build").current_dir(root);
    // `cargo run` gave us its package's variables; a build script that
    // watches one (ring's watches CARGO_MANIFEST_DIR) would run again, and
    // everything above it be rebuilt.
    for (name, _) in std::env::vars_os() {
        if is_package_variable(&name) {
            command.env_remove(name);
        }
    }
    for binary in missing {
        command.args(["--bin", binary]);
    }
    if dir.file_name().is_some_and(|n| n == "release") {
        command.arg("--release");
    }
    eprintln!(
        "building {binaries} (cargo run builds only the supervisor; the view and the bridge are built when a run asks for them)"
    );
    let status = command.status().map_err(|source| LaunchError::Cargo {
        binaries: binaries.clone(),
        source,
    })?;
    if status.success() {
        Ok(())
    } else {
        Err(LaunchError::Build { binaries, status })
    }
}

/// Whether `name` is one of the variables `cargo run` describes the running
/// binary's package with (not cargo's own settings, such as `CARGO_TARGET_DIR`).
fn is_package_variable(name: &OsStr) -> bool {
    name.to_str().is_some_and(|name| {
        name.starts_with("CARGO_PKG_")
            || matches!(
                name,
                "CARGO_MANIFEST_DIR" | "CARGO_MANIFEST_PATH" | "CARGO_CRATE_NAME" | "CARGO_BIN_NAME"
            )
    })
}

/// The workspace's root directory, as `cargo` locates it from the package
/// `cargo run` ran (its directory in `CARGO_MANIFEST_DIR`; else from ours).
fn workspace_root(cargo: &OsStr) -> io::Result<PathBuf> {
    let mut locate = Command::new(cargo);
    locate.args(["locate-project", "--workspace", "--message-format", "plain"]);
    if let Some(package) = std::env::var_os("CARGO_MANIFEST_DIR") {
        locate.current_dir(package);
    }
    let output = locate.stdin(Stdio::null()).stderr(Stdio::inherit()).output()?;
    if !output.status.success() {
        return Err(io::Error::other(format!(
            "cargo locate-project failed: {}",
            output.status
        )));
    }
    let manifest = PathBuf::from(String::from_utf8_lossy(&output.stdout).trim());
    manifest
        .parent()
        .map(Path::to_path_buf)
        .ok_or_else(|| io::Error::other(format!("no workspace root above {}", manifest.display())))
}

impl RunContext {
    /// The command-line arguments that give a child process this context.
    pub fn to_args(&self) -> Vec<OsString> {
        let mut args: Vec<OsString> = vec![
            "--run-id".into(),
            self.run_id.to_string().into(),
            "--run".into(),
            self.run.to_string().into(),
            "--ipc-prefix".into(),
            self.ipc_prefix.clone().into(),
            "--clock".into(),
            self.clock.name().into(),
            "--wait".into(),
            self.wait.name().into(),
            "--spec".into(),
        ];
        args.push(self.spec.clone().into());
        args.push("--work-dir".into());
        args.push(self.work_dir.clone().into());
        if self.feed {
            args.push("--feed".into());
        }
        args
    }
}

/// Gives process `pid` the real-time policy SCHED_FIFO at `priority` (1 to
/// 99): when woken it runs ahead of every normally scheduled process on its
/// core, and it yields its core only to real-time processes. Needs
/// CAP_SYS_NICE or an RLIMIT_RTPRIO (`ulimit -r`) of at least `priority`.
pub(crate) fn set_fifo_priority(pid: u32, priority: u8) -> io::Result<()> {
    let pid = libc::pid_t::try_from(pid).map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
    let param = libc::sched_param {
        sched_priority: i32::from(priority),
    };
    // SAFETY: `param` is a valid sched_param that outlives the call; the call
    // changes nothing but the target's scheduling. Children it forks start
    // normally scheduled again (SCHED_RESET_ON_FORK).
    let status = unsafe { libc::sched_setscheduler(pid, libc::SCHED_FIFO | libc::SCHED_RESET_ON_FORK, &param) };
    if status == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// A started process of the run.
#[derive(Debug)]
pub(crate) struct Process {
    child: Child,
}

impl Process {
    /// Its process id.
    pub(crate) fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Its exit status, if it has exited.
    pub(crate) fn exited(&mut self) -> io::Result<Option<ExitStatus>> {
        self.child.try_wait()
    }

    /// Kills it and every process it started (SIGKILL to its process group:
    /// a world started with `sh -c` may run as the shell's child) and reaps it.
    pub(crate) fn kill(&mut self) -> io::Result<ExitStatus> {
        if let Ok(group) = libc::pid_t::try_from(self.child.id()) {
            // SAFETY: killpg has no memory effects; the group is the child's own.
            unsafe { libc::killpg(group, libc::SIGKILL) };
        }
        // An already exited process makes kill fail; wait still reaps it.
        let _ = self.child.kill();
        self.child.wait()
    }

    /// Asks it to stop (SIGTERM) and waits up to `grace` for it to exit,
    /// then kills it as [`Process::kill`] does.
    pub(crate) fn stop(&mut self, grace: std::time::Duration) -> io::Result<ExitStatus> {
        if let Ok(pid) = libc::pid_t::try_from(self.child.id()) {
            // SAFETY: kill has no memory effects; the process is our child.
            unsafe { libc::kill(pid, libc::SIGTERM) };
        }
        let deadline = std::time::Instant::now() + grace;
        while std::time::Instant::now() < deadline {
            if let Some(status) = self.child.try_wait()? {
                return Ok(status);
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        self.kill()
    }

    /// Whether process `pid` runs in this process's group (it is this
    /// process, or one it started, such as the world a shell runs).
    pub(crate) fn leads(&self, pid: u32) -> bool {
        pid == self.child.id() || process_group(pid) == Some(self.child.id())
    }
}

/// The process group of process `pid`, from `/proc/<pid>/stat`.
fn process_group(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces.
    let after_name = &stat[stat.rfind(')')? + 1..];
    after_name.split_whitespace().nth(2)?.parse().ok()
}

/// The arguments naming agent `k` (0-based) of `role`'s kind and how often it
/// checkpoints: `--keeper K` or `--world-agent K` (1-based), `--checkpoint-every N`.
pub(crate) fn agent_args(role: Role, k: usize, checkpoint_every: u64) -> [OsString; 4] {
    let kind = if matches!(role, Role::Keeper(_)) {
        "--keeper"
    } else {
        "--world-agent"
    };
    [
        kind.into(),
        (k + 1).to_string().into(),
        "--checkpoint-every".into(),
        checkpoint_every.to_string().into(),
    ]
}

/// Starts `binary` as `role` with `args`, its output appended to `log`; it
/// gets its own process group and is killed when the supervisor dies.
pub(crate) fn spawn(binary: &Path, role: Role, args: &[OsString], log: &Path) -> Result<Process, LaunchError> {
    let mut command = Command::new(binary);
    command.args(args);
    spawn_command(command, role, &binary.display().to_string(), log)
}

/// Starts the world of `spec` (a [`DomainSpec::World`]) for `context`'s run,
/// telling it the real-time `period`
/// (directly, or with `sh -c` if a shell must read its command), in the
/// supervisor's working directory, with the run in its
/// environment (`shm_layouts/README.md`: the world process's environment).
pub(crate) fn spawn_world(
    spec: &ExperimentSpec,
    context: &RunContext,
    namespace: &Namespace,
    log: &Path,
    period: std::time::Duration,
) -> Result<Process, LaunchError> {
    let DomainSpec::World { command: line, plans } = &spec.domain else {
        return Err(LaunchError::Spawn {
            what: "the world".into(),
            source: io::Error::other(format!("the experiment is {}, not a world", spec.domain.name())),
        });
    };
    let seed = derive_seed(derive_seed(spec.seed, context.run as u64), WORLD_SEED_STREAM);
    let mut command = world_command(line);
    command
        .env(world_env::PREFIX, namespace.prefix())
        .env(world_env::ROOT, format!("{}/", namespace.root().display()))
        .env(world_env::RUN_ID, context.run_id.to_string())
        .env(world_env::RUN, context.run.to_string())
        .env(world_env::AGENTS, plans.len().to_string())
        .env(world_env::CLOCK, context.clock.name())
        .env(world_env::PERIOD_MS, period.as_millis().to_string())
        .env(world_env::WAIT, context.wait.name())
        .env(world_env::SEED, seed.to_string());
    let program = command.get_program().to_string_lossy().into_owned();
    spawn_command(command, Role::World, line, log).map_err(|e| match e {
        LaunchError::Spawn { source, .. } if source.kind() == io::ErrorKind::NotFound => LaunchError::WorldMissing {
            hint: build_hint(&program),
            program,
        },
        other => other,
    })
}

/// How to build `program` if it is one of this repository's worlds.
fn build_hint(program: &str) -> String {
    let name = Path::new(program).file_name().map(|n| n.to_string_lossy().into_owned());
    match name.as_deref() {
        Some("learnpnp-ros2-world") => "build it: cargo build --release --bin learnpnp-ros2-world".into(),
        Some("learnpnp-corridor") => "build it: cargo build --release --bin learnpnp-corridor".into(),
        _ => "check the world's command (--world-cmd)".into(),
    }
}

/// The process running `line`: a simple command (words only) is run
/// directly, so that the world is the supervisor's child (its pid the one
/// that is watched and killed); anything a shell must read runs with `sh -c`.
fn world_command(line: &str) -> Command {
    let simple = !line.contains(|c: char| "|&;<>()$`\\\"'*?[]#~=%{}!\n".contains(c));
    let mut words = line.split_whitespace();
    match (simple, words.next()) {
        (true, Some(program)) => {
            let mut command = Command::new(program);
            command.args(words);
            command
        }
        _ => {
            let mut command = Command::new("sh");
            command.arg("-c").arg(line);
            command
        }
    }
}

/// The stream of a run's seed the world's seed is drawn from (the run's task
/// stream, as an in-process domain's world draws from it).
const WORLD_SEED_STREAM: u64 = 2;

/// Starts `command` as `role` (described as `what`), its output appended to
/// `log`; it gets its own process group and is killed when the supervisor dies.
fn spawn_command(command: Command, role: Role, what: &str, log: &Path) -> Result<Process, LaunchError> {
    let child = spawn_child(command, &format!("{role} ({what})"), log)?;
    Ok(Process { child })
}

/// Starts `command` (described as `what` in errors) with its output
/// appended to `log`, in its own process group, killed when the supervisor dies.
fn spawn_child(mut command: Command, what: &str, log: &Path) -> Result<Child, LaunchError> {
    let fail = |source| LaunchError::Spawn {
        what: what.to_string(),
        source,
    };
    let out = File::options().create(true).append(true).open(log).map_err(fail)?;
    let err = out.try_clone().map_err(fail)?;
    let parent = std::process::id();
    command.stdin(Stdio::null()).stdout(out).stderr(err).process_group(0);
    // SAFETY: the closure only calls async-signal-safe functions (prctl, getppid).
    unsafe {
        command.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                return Err(io::Error::last_os_error());
            }
            // The supervisor may have died before the death signal was armed.
            if libc::getppid() as u32 != parent {
                return Err(io::Error::other("the supervisor is gone"));
            }
            Ok(())
        });
    }
    command.spawn().map_err(fail)
}

/// A supervisor's own short-lived helper process (a remote host's floor
/// echo), started as the run's processes are; killed with its group when
/// dropped, if it has not exited.
#[derive(Debug)]
pub(crate) struct Helper {
    child: Child,
}

impl Helper {
    /// Starts `binary` (described as `what`) with `args`, its output appended to `log`.
    pub(crate) fn spawn(binary: &Path, what: &str, args: &[OsString], log: &Path) -> Result<Self, LaunchError> {
        let mut command = Command::new(binary);
        command.args(args);
        Ok(Helper {
            child: spawn_child(command, what, log)?,
        })
    }

    /// Waits up to `timeout` for it to exit; its status, if it did.
    pub(crate) fn wait_for(&mut self, timeout: std::time::Duration) -> io::Result<Option<ExitStatus>> {
        let deadline = std::time::Instant::now() + timeout;
        loop {
            if let Some(status) = self.child.try_wait()? {
                return Ok(Some(status));
            }
            if std::time::Instant::now() >= deadline {
                return Ok(None);
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    }
}

impl Drop for Helper {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            if let Ok(group) = libc::pid_t::try_from(self.child.id()) {
                // SAFETY: killpg has no memory effects; the group is the child's own.
                unsafe { libc::killpg(group, libc::SIGKILL) };
            }
            let _ = self.child.wait();
        }
    }
}
