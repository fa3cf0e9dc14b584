//! `learnpnp-bridge`: a run across hosts: each host's bridge (the binary
//! `learnpnp-bridge`, which the host's supervisor starts) carries the
//! run's services between the host's iceoryx2 namespace and the other hosts
//! over Zenoh (TLS with mutual authentication by the run's private CA,
//! explicit endpoints, multicast scouting off: [`link`], and
//! [`learnpnp_system::hosts::certs`]).
//!
//! Host A runs the simulator or world, the supervisor and the local agents;
//! host B runs the remote agents under a supervisor of its own
//! (`learnpnp-supervisor remote`). For every service the remote agents use,
//! a bridge forwards what this host's processes publish (never what it
//! published itself) as the layout's raw bytes, keyed by the run's prefix and
//! the service's name and tagged with the type's name and the protocol
//! version ([`carry`]), and publishes what arrives into the local service,
//! where the receiving process validates it as it validates every message.
//! Host A's bridge answers host B's request for the run ([`learnpnp_system::hosts::run_info::RunInfo`]);
//! at the end, host B's bridge ships the remote agents' checkpoints and
//! histograms to host A ([`remote::FileShipping`]), whose report covers the
//! whole run.
//!
//! Nothing that arrives is trusted for being authenticated: host A's access
//! control ([`access`]) admits host B to its own agents' keys only, and each
//! bridge takes from the link only the senders and orders the route carries
//! and the files the run expects, counting what it refuses ([`refusals`]).

#![deny(missing_docs)]

/// Host A's access control, made from the routes its bridge carries.
pub mod access;
/// Host B's reports of lost agents, weighed against host A's own view.
pub(crate) mod agents_lost;
/// One service carried between hosts as the layout's raw bytes.
pub mod carry;
/// The Zenoh session joining a run's hosts.
pub mod link;
/// What a bridge refused, by reason.
pub mod refusals;
/// What the hosts of a run tell each other besides the services.
pub mod remote;

use std::path::PathBuf;

/// Why a bridge fails.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// Zenoh failed.
    #[error("zenoh: {0}")]
    Zenoh(String),
    /// Shared memory failed.
    #[error(transparent)]
    Ipc(#[from] learnpnp_system::ipc::services::IpcError),
    /// The namespace is unusable.
    #[error(transparent)]
    Namespace(#[from] learnpnp_system::ipc::namespace::NamespaceError),
    /// A file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The run's description cannot be had or read.
    #[error("the run: {0}")]
    RunInfo(String),
    /// The host's certificates are unusable.
    #[error(transparent)]
    Certs(#[from] learnpnp_system::hosts::certs::CertError),
    /// The run's description file cannot be read or written.
    #[error(transparent)]
    RunInfoFile(#[from] RunInfoError),
    /// Host B refused host A's certificate: it will not change by waiting.
    #[error(
        "host A's certificate was refused at the TLS handshake {count} times ({reason}): \
         it is not of this run's CA, or not for the address connected to"
    )]
    Handshake {
        /// Refusals so far.
        count: u64,
        /// Why the last was refused.
        reason: String,
    },
}

/// A Zenoh error as a [`BridgeError`].
pub(crate) fn zenoh_error(e: impl std::fmt::Display) -> BridgeError {
    BridgeError::Zenoh(e.to_string())
}

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use shm_layouts::services;

use agents_lost::RemoteAgents;
use carry::{Direction, Expected, Moved, Payload, RemoteOrders, Route, Sending, Source};
use learnpnp_system::hosts::report::{AgentLost, LinkReport, RefusedFile};
use learnpnp_system::hosts::run_info::{RunInfo, RunInfoError};
use learnpnp_system::hosts::shipped::ShippedFiles;
use learnpnp_system::hosts::{JOIN_TIMEOUT, PLAIN_TCP_WARNING};
use link::{Endpoints, Security};
use refusals::ZenohRefusals;
use remote::{FileShipping, fetch_run_info, serve_run_info};

use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::protocol::{Role, Roster};
use learnpnp_system::ipc::services::{node, wake_name};

/// Which host a bridge serves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Host A: the simulator or world, the supervisor and the local agents.
    Host,
    /// A host of remote agents.
    Remote,
}

/// A bridge's settings.
#[derive(Debug, Clone)]
pub struct BridgeConfig {
    /// This host's iceoryx2 prefix (under `LEARNPNP_IPC_DIR`).
    pub ipc_prefix: String,
    /// Which host.
    pub side: Side,
    /// The link's endpoints.
    pub endpoints: Endpoints,
    /// How the link is protected.
    pub security: Security,
    /// Host A: the run's description to serve; a remote host: where to write
    /// the description it fetched.
    pub run_info: std::path::PathBuf,
    /// This host's work directory (host A: where shipped files go; a remote
    /// host: whose `outbox` is shipped).
    pub work_dir: std::path::PathBuf,
}

/// Host A's name in the keys of a service keyed by host.
const HOST_A: &str = "host-a";

/// Host B's name in the keys of a service keyed by host.
const HOST_B: &str = "host-b";

/// The routes of the services of `info`'s run as `side` carries them.
fn routes(info: &RunInfo, side: Side) -> Vec<(Route, Payload)> {
    let remote = |role: Role| role.agent_index().is_some_and(|a| info.remote.contains(&a));
    let here = |role: Role| match side {
        Side::Host => role.is_host() || !remote(role),
        Side::Remote => remote(role),
    };
    let wakes = |roles: &[Role]| -> Vec<String> { roles.iter().filter(|r| here(**r)).map(|r| wake_name(*r)).collect() };
    let roster = info.roster;
    let host = roster.host();
    let agents: Vec<Role> = (0..roster.agents()).map(|a| roster.agent(a)).collect();
    // From the host to the agents, or back.
    let down = |receivers: Vec<String>| match side {
        Side::Host => (Direction::Out, Vec::new()),
        Side::Remote => (Direction::In, receivers),
    };
    let up = |receivers: Vec<String>| match side {
        Side::Host => (Direction::In, receivers),
        Side::Remote => (Direction::Out, Vec::new()),
    };
    // The senders of the processes on the other hosts.
    let there: Vec<u32> = std::iter::once(host)
        .chain(agents.iter().copied())
        .filter(|r| !here(*r))
        .map(Role::sender)
        .collect();
    let expected = Expected {
        run_id: info.run_id,
        roster,
        agent: None,
    };
    // Host A's bridge fans out to every subscriber: droppable (see Sending).
    let sending = match side {
        Side::Host => Sending::Droppable,
        Side::Remote => Sending::Blocking,
    };
    let route = |service: String, point_to_point: bool, (direction, receivers): (Direction, Vec<String>)| Route {
        service,
        point_to_point,
        direction,
        source: Source::Single,
        orders: None,
        receivers,
        expected,
        sending,
    };
    let agents_route = |a: usize, service: String, way: (Direction, Vec<String>)| Route {
        expected: Expected {
            agent: Some(a),
            ..expected
        },
        ..route(service, true, way)
    };
    let mut out = Vec::new();
    for &a in &info.remote {
        let agent = roster.agent(a);
        let (snapshot, command, ping, pong) = match roster {
            Roster::Keepaway => (
                (services::snapshot(a), Payload::KeeperSnapshot),
                (services::command(a), Payload::KeeperCommand),
                (services::FLOOR_PING.to_string(), Payload::KeeperSnapshot),
                (services::FLOOR_PONG.to_string(), Payload::KeeperCommand),
            ),
            Roster::World { .. } => (
                (services::world_snapshot(a), Payload::WorldSnapshot),
                (services::world_command(a), Payload::WorldCommand),
                (services::WORLD_FLOOR_PING.to_string(), Payload::WorldSnapshot),
                (services::WORLD_FLOOR_PONG.to_string(), Payload::WorldCommand),
            ),
        };
        out.push((agents_route(a, snapshot.0, down(wakes(&[agent]))), snapshot.1));
        out.push((agents_route(a, command.0, up(wakes(&[host]))), command.1));
        if a == 0 {
            // The floor is measured with agent 0, wherever it is.
            out.push((route(ping.0, true, down(wakes(&[agent]))), ping.1));
            out.push((route(pong.0, true, up(wakes(&[host]))), pong.1));
        }
    }
    let remote_agents: Vec<Role> = agents
        .iter()
        .copied()
        .filter(|r| here(*r) || side == Side::Host)
        .collect();
    let announcements = match roster {
        Roster::Keepaway => (services::EPISODE.to_string(), Payload::EpisodeEvent),
        Roster::World { .. } => (services::WORLD_VOCABULARY.to_string(), Payload::WorldVocabulary),
    };
    out.push((
        route(announcements.0, false, down(wakes(&remote_agents))),
        announcements.1,
    ));
    let by_sender = Source::BySender {
        accepted: there.clone(),
    };
    out.push((
        Route {
            source: by_sender.clone(),
            ..route(services::AGENT_REPORT.into(), false, up(wakes(&[host])))
        },
        Payload::AgentReport,
    ));
    // Every host sees every process's heartbeats (a monitor on any host can
    // follow the whole run); the supervisors keep to their own processes'.
    out.push((
        Route {
            source: by_sender,
            // Fanned out by host A's router to monitors too, from either host.
            sending: Sending::Background,
            ..route(services::HEARTBEAT.into(), false, (Direction::Both, Vec::new()))
        },
        Payload::Heartbeat,
    ));
    let everyone: Vec<Role> = std::iter::once(host).chain(agents.iter().copied()).collect();
    let (this, other, orders) = match side {
        Side::Host => (
            HOST_A,
            HOST_B,
            Some(RemoteOrders {
                agents: info.remote.iter().map(|&a| roster.agent(a).sender()).collect(),
                host: host.sender(),
            }),
        ),
        Side::Remote => (HOST_B, HOST_A, None),
    };
    out.push((
        Route {
            source: Source::ByHost { this, other },
            orders,
            ..route(services::CONTROL.into(), false, (Direction::Both, wakes(&everyone)))
        },
        Payload::Control,
    ));
    out
}

/// What a bridge moved over its life.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Messages.
    pub messages: Moved,
    /// Files shipped or received.
    pub files: usize,
    /// The files refused (the first [`MAX_LISTED`](learnpnp_system::hosts::report::MAX_LISTED)).
    pub refused_files: Vec<RefusedFile>,
    /// Host A: host B's reports of lost agents, and what became of each.
    pub agents_lost: Vec<AgentLost>,
}

/// Yielding between polls for this long after the last message (a
/// lock-step cycle's next message comes within it), then waiting for an
/// arrival from the link (its doorbell) for at most [`IDLE_WAIT`] at a time.
const BUSY_FOR: Duration = Duration::from_millis(20);

/// The longest an idle bridge waits before it polls this host's services again.
const IDLE_WAIT: Duration = Duration::from_millis(1);

/// How often the bridge rewrites its [`LinkReport`] when something changed.
const REPORT_EVERY: Duration = Duration::from_secs(1);

/// A bridge's [`LinkReport`]: what earlier bridges of this host reported
/// (a restarted bridge adds to it) plus this one's traffic and refusals.
struct Reporting<'a> {
    dir: &'a Path,
    earlier: LinkReport,
    zenoh: &'a ZenohRefusals,
    written: Option<LinkReport>,
    at: Instant,
    /// The traffic last written.
    traffic: Traffic,
}

impl<'a> Reporting<'a> {
    fn new(dir: &'a Path, security: &Security, zenoh: &'a ZenohRefusals) -> Self {
        let mut earlier = LinkReport::read(dir).unwrap_or_default();
        earlier.security = security.name().to_string();
        earlier.warning = (security == &Security::PlainTcp).then(|| PLAIN_TCP_WARNING.to_string());
        Reporting {
            dir,
            earlier,
            zenoh,
            written: None,
            at: Instant::now(),
            traffic: Traffic::default(),
        }
    }

    fn report(&self, traffic: &Traffic) -> LinkReport {
        let (tls_handshake, access_denied) = self.zenoh.counts();
        let mut refused = traffic.messages.refused;
        refused.tls_handshake += tls_handshake;
        refused.access_denied += access_denied;
        self.earlier.plus(&LinkReport {
            security: self.earlier.security.clone(),
            warning: self.earlier.warning.clone(),
            sent: traffic.messages.sent,
            received: traffic.messages.received,
            files: traffic.files as u64,
            stop_requests: traffic.messages.stop_requests,
            refused,
            lost: traffic.messages.lost,
            refused_files: traffic.refused_files.clone(),
            agents_lost: traffic.agents_lost.clone(),
            host_b: None,
        })
    }

    /// Writes the report if it changed (`now`: whenever due, else at most
    /// every [`REPORT_EVERY`]).
    fn write(&mut self, traffic: &Traffic, now: bool) -> Result<(), BridgeError> {
        if !now && self.at.elapsed() < REPORT_EVERY {
            return Ok(());
        }
        self.at = Instant::now();
        self.traffic.clone_from(traffic);
        let report = self.report(traffic);
        if self.written.as_ref() == Some(&report) {
            return Ok(());
        }
        report.write(self.dir).map_err(|source| BridgeError::Io {
            path: self.dir.join(learnpnp_system::hosts::report::LINK_REPORT_FILE),
            source,
        })?;
        self.written = Some(report);
        Ok(())
    }
}

/// Host B gives up joining once host A's certificate was refused this often.
const HANDSHAKE_TRIES: u64 = 3;

/// Host B: opens the session, giving up once host A's certificate has been
/// refused [`HANDSHAKE_TRIES`] times (waiting will not change it).
fn open_remote(config: &BridgeConfig, zenoh: &ZenohRefusals) -> Result<zenoh::Session, BridgeError> {
    let (tx, rx) = crossbeam::channel::bounded(1);
    let (endpoints, security) = (config.endpoints.clone(), config.security.clone());
    std::thread::spawn(move || {
        let _ = tx.send(link::open(&endpoints, &security, None));
    });
    loop {
        match rx.recv_timeout(Duration::from_millis(100)) {
            Ok(opened) => return opened,
            Err(crossbeam::channel::RecvTimeoutError::Timeout) => {
                let (count, _) = zenoh.counts();
                if count >= HANDSHAKE_TRIES {
                    let reason = zenoh.last_handshake_refusal().unwrap_or_default();
                    return Err(BridgeError::Handshake { count, reason });
                }
            }
            Err(crossbeam::channel::RecvTimeoutError::Disconnected) => {
                return Err(zenoh_error("opening the link failed without a word"));
            }
        }
    }
}

/// Runs a bridge until `stop` is set: joins the link, serves or fetches the
/// run's description, then carries the services and the files; keeps its
/// [`LinkReport`] in the work directory, counting what Zenoh refused as
/// `zenoh` saw it (also when it fails).
pub fn run(config: &BridgeConfig, zenoh: &ZenohRefusals, stop: &AtomicBool) -> Result<Traffic, BridgeError> {
    let mut reporting = Reporting::new(&config.work_dir, &config.security, zenoh);
    reporting.write(&Traffic::default(), true)?;
    let carried = carry_until_stopped(config, &mut reporting, stop);
    if carried.is_err() {
        // What was refused before the failure (a refused certificate) stays counted.
        let traffic = reporting.traffic.clone();
        reporting.write(&traffic, true)?;
    }
    carried
}

/// [`run`]'s work, reported through `reporting`.
fn carry_until_stopped(
    config: &BridgeConfig,
    reporting: &mut Reporting<'_>,
    stop: &AtomicBool,
) -> Result<Traffic, BridgeError> {
    let zenoh = reporting.zenoh;
    if config.security == Security::PlainTcp {
        eprintln!("bridge: warning: {PLAIN_TCP_WARNING}");
    }
    let (session, info, _queryable) = match config.side {
        Side::Host => {
            let info = RunInfo::read(&config.run_info)?;
            let policy = match config.security {
                Security::MutualTls(_) => {
                    let routes: Vec<Route> = routes(&info, Side::Host).into_iter().map(|(r, _)| r).collect();
                    Some(access::host_a_policy(&info.prefix, &routes, &ShippedFiles::of(&info)))
                }
                Security::PlainTcp => None,
            };
            let session = link::open(&config.endpoints, &config.security, policy.as_ref())?;
            let queryable = serve_run_info(&session, &info)?;
            (session, info, Some(queryable))
        }
        Side::Remote => {
            let session = open_remote(config, zenoh)?;
            let info = fetch_run_info(&session, JOIN_TIMEOUT)?;
            info.write(&config.run_info)?;
            (session, info, None)
        }
    };
    let namespace = Namespace::from_prefix(&config.ipc_prefix)?;
    let node = node(&namespace, "bridge")?;
    let (doorbell, rings) = crossbeam::channel::unbounded();
    let mut carriers = routes(&info, config.side)
        .iter()
        .map(|(route, payload)| payload.opener()(&node, &session, &info.prefix, route, info.wait, &doorbell))
        .collect::<Result<Vec<_>, _>>()?;
    let mut files = match config.side {
        Side::Host => FileShipping::receiver(&session, &info, &config.work_dir)?,
        Side::Remote => FileShipping::sender(&session, &info.prefix, &config.work_dir)?,
    };
    let mut traffic = Traffic::default();
    let mut agents = RemoteAgents::default();
    let mut last = Instant::now();
    let mut last_files = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let mut moved = Moved::default();
        while rings.try_recv().is_ok() {}
        for carrier in &mut carriers {
            moved = moved.plus(carrier.pump(&mut agents)?);
        }
        if last_files.elapsed() >= Duration::from_millis(50) {
            traffic.files += files.pump(&session, &mut moved.refused)?;
            if let FileShipping::Receiver(reception) = &files {
                traffic.refused_files.clone_from(&reception.quarantine.refused);
            }
            traffic.agents_lost.clone_from(&agents.events);
            last_files = Instant::now();
            reporting.write(&traffic, false)?;
        }
        traffic.messages = traffic.messages.plus(moved);
        if moved.stop_requests > 0 {
            eprintln!("bridge: the other host asked to stop the run");
            reporting.write(&traffic, true)?;
        }
        if moved.any() || agents.holding() {
            last = Instant::now();
        } else if last.elapsed() < BUSY_FOR {
            std::thread::yield_now();
        } else {
            let _ = rings.recv_timeout(IDLE_WAIT);
        }
    }
    if let FileShipping::Receiver(reception) = &files {
        traffic.refused_files.clone_from(&reception.quarantine.refused);
    }
    traffic.agents_lost.clone_from(&agents.events);
    reporting.write(&traffic, true)?;
    Ok(traffic)
}

/// The run's description a remote host's bridge wrote, once it has.
pub fn read_fetched(path: &Path) -> Option<RunInfo> {
    RunInfo::read(path).ok()
}
