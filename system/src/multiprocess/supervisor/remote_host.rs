//! A host of remote agents (`learnpnp-supervisor remote`): it joins a run
//! that host A's supervisor started with `--remote-agents`, over the link its
//! bridge opens. It claims a namespace of its own, starts the bridge (which
//! fetches the run's description from host A), creates the run's services
//! here, starts the remote agents with the run's id, and watches them:
//! an agent that dies or falls silent is restarted from its checkpoint, and
//! host A's simulator or world is told (`KEEPER_LOST`, carried by the
//! bridge). When host A stops the run, the agents checkpoint and exit; their
//! checkpoints and histograms are shipped to host A for its report, and
//! everything this host created in shared memory is removed.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitStatus;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::hosts::JOIN_TIMEOUT;
use crate::hosts::report::LINK_REPORT_FILE;
use crate::hosts::report::LinkReport;
use crate::hosts::run_info::{OUTBOX, RunInfo};
use crate::hosts::shipped::HOST_B_LINK_REPORT;
use crate::ipc::convert::{control_message, read_heartbeat};
use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{Order, Role, Roster};
use crate::ipc::services::{Ipc, RunServices, SupervisorPorts, node, receive};
use crate::multiprocess::RunContext;
use crate::multiprocess::agent::chassis::checkpoint_name;
use crate::multiprocess::floor_probe::{FloorPayload, FloorProbe, KeepawayFloor, WorldFloor};
use crate::multiprocess::supervisor::config::{EXIT_CANNOT_RESUME, SupervisorError, json_error};
use crate::multiprocess::supervisor::hand_off::BRIDGE_STOP_GRACE;
use crate::multiprocess::supervisor::launch::{Binaries, Helper, Process, agent_args, spawn};
use crate::multiprocess::supervisor::watch::Fault;
use iceoryx2::node::Node;
use learnpnp::experiment::spec::ExperimentSpec;

/// How a remote host runs.
#[derive(Debug, Clone)]
pub struct RemoteConfig {
    /// Host A's bridge (`quic/ADDRESS:PORT`).
    pub connect: Vec<String>,
    /// Host B's certificates (made by `learnpnp-supervisor link-certs`);
    /// `None`: plain TCP, which gives up encryption and authentication.
    pub link_certs: Option<PathBuf>,
    /// The agents' and the bridge's binaries.
    pub binaries: Binaries,
    /// A process silent for this long is taken as hung and killed.
    pub heartbeat_timeout: Duration,
    /// Restarts of one agent (or of the bridge) before the host gives up.
    pub max_restarts: u32,
}

/// How long the remote host waits for host A to acknowledge its files.
pub(crate) const SHIPPING_TIMEOUT: Duration = Duration::from_secs(30);

/// What a remote host did (its `summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct RemoteSummary {
    /// The run joined.
    pub run_id: u64,
    /// Host A's prefix (the run's name on the link).
    pub run_prefix: String,
    /// This host's iceoryx2 prefix.
    pub(crate) ipc_prefix: String,
    /// The agents run here (1-based, as reports name them).
    pub agents: Vec<usize>,
    /// Processes restarted here.
    pub restarts: u32,
    /// Faults and what was done, in order.
    pub(crate) faults: Vec<Fault>,
    /// Every file was delivered to host A.
    pub shipped: bool,
    /// Why the host gave up, if it did.
    pub(crate) failure: Option<String>,
    /// Files of this host's namespace left after cleanup (0 unless cleanup failed).
    pub(crate) leftover_shm_files: usize,
    /// How the link was protected, what this host's bridge carried and refused.
    pub link: LinkReport,
    /// Wall-clock seconds.
    pub(crate) wall_seconds: f64,
}

/// The remote host's processes and what it knows of them.
struct Host<'a> {
    config: &'a RemoteConfig,
    namespace: &'a Namespace,
    work_dir: PathBuf,
    context: Option<RunContext>,
    info: Option<RunInfo>,
    processes: BTreeMap<Role, Process>,
    last_heard: BTreeMap<Role, Instant>,
    restarts: BTreeMap<Role, u32>,
    done: Vec<usize>,
    faults: Vec<Fault>,
    started: Instant,
    control_sequence: u64,
}

impl Drop for Host<'_> {
    fn drop(&mut self) {
        for process in self.processes.values_mut() {
            let _ = process.kill();
        }
    }
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SupervisorError + '_ {
    move |source| SupervisorError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl Host<'_> {
    fn log(&self, role: Role) -> PathBuf {
        self.work_dir.join(match role {
            Role::Keeper(k) => format!("keeper{}.log", k + 1),
            Role::Agent(a) => format!("agent{}.log", a + 1),
            _ => "bridge.log".to_string(),
        })
    }

    fn fault(&mut self, kind: String, outcome: String) {
        self.faults.push(Fault {
            run: self.info.as_ref().map_or(0, |i| i.run),
            seconds: self.started.elapsed().as_secs_f64(),
            kind,
            outcome,
        });
    }

    fn start_bridge(&mut self) -> Result<(), SupervisorError> {
        let mut args: Vec<OsString> = vec![
            "--ipc-prefix".into(),
            self.namespace.prefix().into(),
            "--side".into(),
            "remote".into(),
            "--run-info".into(),
            self.work_dir.join(super::hand_off::RUN_INFO_FILE).into(),
            "--work-dir".into(),
            self.work_dir.clone().into(),
        ];
        for endpoint in &self.config.connect {
            args.push("--connect".into());
            args.push(endpoint.into());
        }
        match &self.config.link_certs {
            Some(dir) => args.extend(["--link-certs".into(), dir.clone().into_os_string()]),
            None => args.push("--insecure-plain-tcp".into()),
        }
        let process = spawn(
            self.config.binaries.bridge()?,
            Role::Bridge,
            &args,
            &self.log(Role::Bridge),
        )?;
        self.processes.insert(Role::Bridge, process);
        Ok(())
    }

    fn start_agent(&mut self, role: Role, resume: bool) -> Result<(), SupervisorError> {
        let (Some(context), Some(info), Some(k)) = (&self.context, &self.info, role.agent_index()) else {
            return Ok(());
        };
        let mut args = context.to_args();
        if resume {
            args.push("--resume".into());
        }
        args.extend(agent_args(role, k, info.checkpoint_every));
        let process = spawn(&self.config.binaries.agent, role, &args, &self.log(role))?;
        self.processes.insert(role, process);
        self.last_heard.insert(role, Instant::now());
        Ok(())
    }

    /// This host's own iceoryx2 floor, before its agents start: its
    /// supervisor pings a floor echo process (`learnpnp-agent --floor-echo`)
    /// with the run's payloads, back to back; the histogram
    /// ([`super::floor_probe::REMOTE_HOST_FLOOR`]) is shipped to host A with the agents' files.
    fn measure_floor(&mut self, node: &Node<Ipc>, info: &RunInfo) -> Result<(), SupervisorError> {
        let Some(context) = &self.context else {
            return Ok(());
        };
        let mut args = context.to_args();
        args.push("--floor-echo".into());
        let log = self.work_dir.join("floor-echo.log");
        let mut echo = Helper::spawn(&self.config.binaries.agent, "the floor echo", &args, &log)?;
        let rounds = info.floor_round_trips;
        let measured = match info.roster {
            Roster::Keepaway => measure::<KeepawayFloor>(node, context, rounds),
            Roster::World { .. } => measure::<WorldFloor>(node, context, rounds),
        };
        // The echo exits at the end marker; dropping it kills it otherwise.
        echo.wait_for(Duration::from_secs(2)).map_err(io_error(&log))?;
        measured
    }

    /// Waits for the bridge to fetch the run's description; `None` on stop.
    fn await_run(&mut self, stop: &AtomicBool) -> Result<Option<RunInfo>, SupervisorError> {
        let path = self.work_dir.join(super::hand_off::RUN_INFO_FILE);
        let deadline = Instant::now() + JOIN_TIMEOUT + Duration::from_secs(5);
        while Instant::now() < deadline && !stop.load(Ordering::Relaxed) {
            if let Ok(info) = RunInfo::read(&path) {
                return Ok(Some(info));
            }
            if let Some(status) = self.exited(Role::Bridge)? {
                return Err(SupervisorError::Bridge(format!(
                    "the bridge exited before the run was found: {status:?} ({})",
                    fs::read_to_string(self.log(Role::Bridge)).unwrap_or_default().trim()
                )));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        if stop.load(Ordering::Relaxed) {
            return Ok(None);
        }
        Err(SupervisorError::Bridge(format!(
            "no run found on {} within {} s",
            self.config.connect.join(", "),
            JOIN_TIMEOUT.as_secs()
        )))
    }

    fn exited(&mut self, role: Role) -> Result<Option<ExitStatus>, SupervisorError> {
        match self.processes.get_mut(&role) {
            Some(process) => {
                let status = process.exited().map_err(io_error(Path::new("waitpid")))?;
                if status.is_some() {
                    self.processes.remove(&role);
                }
                Ok(status)
            }
            None => Ok(None),
        }
    }

    /// Counts a restart of `role`; an error once there were too many.
    fn count_restart(&mut self, role: Role, what: &str) -> Result<(), SupervisorError> {
        let restarts = self.restarts.entry(role).or_default();
        *restarts += 1;
        if *restarts > self.config.max_restarts {
            return Err(SupervisorError::Bridge(format!(
                "{what}, {restarts} times: this host gives up"
            )));
        }
        Ok(())
    }

    /// Restarts agent `role` from its checkpoint and tells host A.
    fn restart_agent(&mut self, role: Role, what: String, ports: &SupervisorPorts) -> Result<(), SupervisorError> {
        self.count_restart(role, &what)?;
        self.namespace.remove_dead_nodes()?;
        self.start_agent(role, true)?;
        let (Some(k), Some(info)) = (role.agent_index(), &self.info) else {
            return Ok(());
        };
        let pid = self.processes.get(&role).map_or(0, Process::pid);
        self.control_sequence += 1;
        let order = Order::KeeperLost { keeper: k, pid };
        let message = control_message(order, Some(info.roster.host()), self.control_sequence, info.run_id);
        ports.control.send(message)?;
        self.fault(what, format!("restarted from its checkpoint {}", checkpoint_name(k)));
        Ok(())
    }

    /// Watches the agents until every one has ended (host A stopped the run).
    fn watch(&mut self, ports: &SupervisorPorts, stop: &AtomicBool) -> Result<(), SupervisorError> {
        let Some(info) = self.info.clone() else {
            return Ok(());
        };
        let mut asked_to_stop = false;
        loop {
            while let Some(reading) = receive(&ports.heartbeats, |m| read_heartbeat(m, info.run_id, info.roster))? {
                if let Ok(pulse) = reading
                    && self.processes.get(&pulse.role).is_some_and(|p| p.leads(pulse.pid))
                {
                    self.last_heard.insert(pulse.role, Instant::now());
                }
            }
            if stop.load(Ordering::Relaxed) && !asked_to_stop {
                // This host stopped: so does the run (host A ends it).
                asked_to_stop = true;
                self.control_sequence += 1;
                let message = control_message(
                    Order::Stop,
                    Some(info.roster.host()),
                    self.control_sequence,
                    info.run_id,
                );
                ports.control.send(message)?;
                self.fault(
                    "stop requested (signal)".into(),
                    "host A is asked to end the run".into(),
                );
            }
            let roles: Vec<Role> = self.processes.keys().copied().collect();
            for role in roles {
                let Some(status) = self.exited(role)? else { continue };
                let what = format!("{role} exited: {status:?}");
                match role.agent_index() {
                    Some(k) if status.success() => self.done.push(k),
                    Some(_) if status.code() == Some(EXIT_CANNOT_RESUME) => {
                        return Err(SupervisorError::Bridge(format!("{what}: it cannot resume")));
                    }
                    Some(_) => self.restart_agent(role, what, ports)?,
                    None => {
                        self.count_restart(role, &what)?;
                        self.start_bridge()?;
                        self.fault(what, "restarted; the link is joined again".into());
                    }
                }
            }
            let timeout = self.config.heartbeat_timeout;
            let hung: Vec<Role> = self
                .last_heard
                .iter()
                .filter(|(r, t)| self.processes.contains_key(r) && t.elapsed() > timeout)
                .map(|(r, _)| *r)
                .collect();
            for role in hung {
                if let Some(mut process) = self.processes.remove(&role) {
                    let _ = process.kill();
                    self.restart_agent(
                        role,
                        format!("{role} silent for {} s: killed", timeout.as_secs()),
                        ports,
                    )?;
                }
            }
            if self.done.len() == info.remote.len() {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Puts the agents' checkpoints and histograms into the outbox and waits
    /// until host A has acknowledged them all; returns whether it did.
    fn ship(&mut self) -> Result<bool, SupervisorError> {
        let outbox = self.work_dir.join(OUTBOX);
        fs::create_dir_all(&outbox).map_err(io_error(&outbox))?;
        let remote: Vec<usize> = self.info.as_ref().map(|i| i.remote.clone()).unwrap_or_default();
        let mut names: Vec<String> = remote.iter().map(|&k| checkpoint_name(k)).collect();
        for entry in fs::read_dir(&self.work_dir)
            .map_err(io_error(&self.work_dir))?
            .flatten()
        {
            let name = entry.file_name().to_string_lossy().into_owned();
            // Histograms, and a world agent's result (host A's report reads agent 1's).
            if name.ends_with(".hdr") || (name.starts_with("agent") && name.ends_with(".json")) {
                names.push(name);
            }
        }
        let mut shipped: Vec<(String, String)> = names.into_iter().map(|n| (n.clone(), n)).collect();
        // This host's link counts, for host A's report (as they stand now:
        // its bridge rewrites them within a second of a change).
        shipped.push((LINK_REPORT_FILE.to_string(), HOST_B_LINK_REPORT.to_string()));
        for (name, as_name) in shipped {
            let from = self.work_dir.join(&name);
            if let Ok(bytes) = fs::read(&from) {
                let to = outbox.join(&as_name);
                atomic_file::write_atomic(&to, &bytes).map_err(io_error(&to))?;
            }
        }
        let deadline = Instant::now() + SHIPPING_TIMEOUT;
        loop {
            let waiting = fs::read_dir(&outbox)
                .map_err(io_error(&outbox))?
                .flatten()
                .any(|e| !e.file_name().to_string_lossy().starts_with('.'));
            if !waiting {
                return Ok(true);
            }
            if Instant::now() > deadline {
                return Ok(false);
            }
            if let Some(status) = self.exited(Role::Bridge)? {
                self.fault(
                    format!("the bridge exited: {status:?}"),
                    "restarted to ship the files".into(),
                );
                self.start_bridge()?;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// Joins the run host A's bridge serves on `config.connect`, runs its remote
/// agents here until host A ends the run, ships their files to host A, and
/// writes this host's `summary.json` into `work_dir`.
pub fn join(config: &RemoteConfig, work_dir: &Path, stop: &AtomicBool) -> Result<RemoteSummary, SupervisorError> {
    fs::create_dir_all(work_dir).map_err(io_error(work_dir))?;
    let owner = Namespace::claim_unique()?;
    let namespace = owner.namespace().clone();
    let mut host = Host {
        config,
        namespace: &namespace,
        work_dir: work_dir.to_path_buf(),
        context: None,
        info: None,
        processes: BTreeMap::new(),
        last_heard: BTreeMap::new(),
        restarts: BTreeMap::new(),
        done: Vec::new(),
        faults: Vec::new(),
        started: Instant::now(),
        control_sequence: 0,
    };
    let outcome = run_here(&mut host, stop);
    let shipped = match &outcome {
        Ok(true) => host.ship(),
        _ => Ok(false),
    };
    if let Some(mut bridge) = host.processes.remove(&Role::Bridge) {
        // Asked to stop, it writes its last link report.
        let _ = bridge.stop(BRIDGE_STOP_GRACE);
    }
    for process in host.processes.values_mut() {
        let _ = process.kill();
    }
    host.processes.clear();
    let released = owner.release();
    let mut summary = RemoteSummary {
        run_id: host.info.as_ref().map_or(0, |i| i.run_id),
        run_prefix: host.info.as_ref().map(|i| i.prefix.clone()).unwrap_or_default(),
        ipc_prefix: namespace.prefix().to_string(),
        agents: host
            .info
            .as_ref()
            .map(|i| i.remote.iter().map(|k| k + 1).collect())
            .unwrap_or_default(),
        restarts: host.restarts.values().sum(),
        faults: std::mem::take(&mut host.faults),
        shipped: *shipped.as_ref().unwrap_or(&false),
        failure: outcome.as_ref().err().map(ToString::to_string),
        leftover_shm_files: 0,
        wall_seconds: host.started.elapsed().as_secs_f64(),
        link: LinkReport::read(work_dir).unwrap_or_default(),
    };
    released?;
    summary.leftover_shm_files = namespace.files().len();
    let path = work_dir.join("summary.json");
    let json = serde_json::to_vec_pretty(&summary).map_err(json_error("summary.json"))?;
    atomic_file::write_atomic(&path, &json).map_err(io_error(&path))?;
    shipped?;
    outcome?;
    Ok(summary)
}

/// `round_trips` of a host's floor with payloads `F`, then the end marker.
fn measure<F: FloorPayload>(node: &Node<Ipc>, context: &RunContext, round_trips: usize) -> Result<(), SupervisorError> {
    let mut probe = FloorProbe::<F>::host(node, context.wait, context.run_id, &context.work_dir)?;
    probe.measure(round_trips)?;
    probe.end()
}

/// The remote host's run: the bridge, the run's services, the agents, until
/// they end; false if it was stopped before the run was found.
fn run_here(host: &mut Host<'_>, stop: &AtomicBool) -> Result<bool, SupervisorError> {
    host.start_bridge()?;
    let Some(info) = host.await_run(stop)? else {
        return Ok(false);
    };
    let spec: ExperimentSpec =
        serde_json::from_value(info.spec.clone()).map_err(json_error("the run's experiment spec"))?;
    let spec_path = host.work_dir.join("spec.json");
    let json = serde_json::to_vec_pretty(&spec).map_err(json_error("the experiment spec"))?;
    atomic_file::write_atomic(&spec_path, &json).map_err(io_error(&spec_path))?;
    let node = node(host.namespace, "supervisor")?;
    let _services = RunServices::create(&node, info.roster)?;
    let ports = SupervisorPorts::open(&node, info.wait, info.roster)?;
    host.context = Some(RunContext {
        run_id: info.run_id,
        run: info.run,
        ipc_prefix: host.namespace.prefix().to_string(),
        clock: info.clock,
        wait: info.wait,
        spec: spec_path,
        work_dir: host.work_dir.clone(),
        // A remote host's agents publish no feed: the view reads this host's services only.
        feed: false,
    });
    host.info = Some(info.clone());
    host.measure_floor(&node, &info)?;
    for &k in &info.remote {
        host.start_agent(info.roster.agent(k), false)?;
    }
    host.watch(&ports, stop)?;
    Ok(true)
}
