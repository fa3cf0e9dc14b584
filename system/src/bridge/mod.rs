//! A run across hosts: each host's bridge (`learnpnp-bridge`) carries the
//! run's services between the host's iceoryx2 namespace and the other hosts
//! over Zenoh (TCP only, explicit endpoints, multicast scouting off).
//!
//! Host A runs the simulator or world, the supervisor and the local agents;
//! host B runs the remote agents under a supervisor of its own
//! (`learnpnp-supervisor remote`). For every service the remote agents use,
//! a bridge forwards what this host's processes publish (never what it
//! published itself) as the layout's raw bytes, keyed by the run's prefix and
//! the service's name and tagged with the type's name and the protocol
//! version ([`carry`]), and publishes what arrives into the local service,
//! where the receiving process validates it as it validates every message.
//! Host A's bridge answers host B's request for the run ([`remote::RunInfo`]);
//! at the end, host B's bridge ships the remote agents' checkpoints and
//! histograms to host A ([`remote::FileShipping`]), whose report covers the
//! whole run.

pub mod carry;
pub mod link;
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
    Ipc(#[from] crate::ipc::services::IpcError),
    /// The namespace is unusable.
    #[error(transparent)]
    Namespace(#[from] crate::ipc::namespace::NamespaceError),
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
}

/// A Zenoh error as a [`BridgeError`].
pub(crate) fn zenoh_error(e: impl std::fmt::Display) -> BridgeError {
    BridgeError::Zenoh(e.to_string())
}

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam::channel::Sender;
use iceoryx2::node::Node;
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Heartbeat, KeeperCommand, KeeperSnapshot, WorldCommand, WorldSnapshot,
    WorldVocabulary, services,
};
use zenoh::Session;

use carry::{Carrier, Carry, Direction, Moved, Route};
use link::Endpoints;
use remote::{FileShipping, RunInfo, fetch_run_info, serve_run_info};

use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{Role, Roster};
use crate::ipc::services::{Ipc, node, wake_name};
use crate::ipc::wait::WaitStrategy;

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
    /// Host A: the run's description to serve; a remote host: where to write
    /// the description it fetched.
    pub run_info: std::path::PathBuf,
    /// This host's work directory (host A: where shipped files go; a remote
    /// host: whose `outbox` is shipped).
    pub work_dir: std::path::PathBuf,
}

/// How long a remote host's bridge asks for the run before giving up.
pub const JOIN_TIMEOUT: Duration = Duration::from_secs(60);

/// The routes of the services of `info`'s run as `side` carries them.
fn routes(info: &RunInfo, side: Side) -> Vec<(Route, Payload)> {
    let here = |role: Role| match side {
        Side::Host => role.is_host() || !role.agent_index().is_some_and(|a| info.remote.contains(&a)),
        Side::Remote => role.agent_index().is_some_and(|a| info.remote.contains(&a)),
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
    let route = |service: String, point_to_point: bool, (direction, receivers): (Direction, Vec<String>)| Route {
        service,
        point_to_point,
        direction,
        receivers,
        roster,
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
        out.push((route(snapshot.0, true, down(wakes(&[agent]))), snapshot.1));
        out.push((route(command.0, true, up(wakes(&[host]))), command.1));
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
    out.push((
        route(services::AGENT_REPORT.into(), false, up(wakes(&[host]))),
        Payload::AgentReport,
    ));
    // Every host sees every process's heartbeats (a monitor on any host can
    // follow the whole run); the supervisors keep to their own processes'.
    out.push((
        route(services::HEARTBEAT.into(), false, (Direction::Both, Vec::new())),
        Payload::Heartbeat,
    ));
    let everyone: Vec<Role> = std::iter::once(host).chain(agents.iter().copied()).collect();
    out.push((
        route(services::CONTROL.into(), false, (Direction::Both, wakes(&everyone))),
        Payload::Control,
    ));
    out
}

/// The payload type of a carried service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Payload {
    KeeperSnapshot,
    KeeperCommand,
    EpisodeEvent,
    WorldSnapshot,
    WorldCommand,
    WorldVocabulary,
    AgentReport,
    Heartbeat,
    Control,
}

/// Opens the carrier of `route`.
fn carrier(
    node: &Node<Ipc>,
    session: &Session,
    prefix: &str,
    route: &Route,
    payload: Payload,
    wait: WaitStrategy,
    doorbell: &Sender<()>,
) -> Result<Box<dyn Carry>, BridgeError> {
    fn boxed<T: iceoryx2::prelude::ZeroCopySend + std::fmt::Debug + Copy + Send + 'static>(
        node: &Node<Ipc>,
        session: &Session,
        prefix: &str,
        route: &Route,
        wait: WaitStrategy,
        doorbell: &Sender<()>,
    ) -> Result<Box<dyn Carry>, BridgeError> {
        Ok(Box::new(Carrier::<T>::open(
            node, session, prefix, route, wait, doorbell,
        )?))
    }
    let open = match payload {
        Payload::KeeperSnapshot => boxed::<KeeperSnapshot>,
        Payload::KeeperCommand => boxed::<KeeperCommand>,
        Payload::EpisodeEvent => boxed::<EpisodeEvent>,
        Payload::WorldSnapshot => boxed::<WorldSnapshot>,
        Payload::WorldCommand => boxed::<WorldCommand>,
        Payload::WorldVocabulary => boxed::<WorldVocabulary>,
        Payload::AgentReport => boxed::<AgentReport>,
        Payload::Heartbeat => boxed::<Heartbeat>,
        Payload::Control => boxed::<Control>,
    };
    open(node, session, prefix, route, wait, doorbell)
}

/// What a bridge moved over its life.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Messages.
    pub messages: Moved,
    /// Files shipped or received.
    pub files: usize,
}

/// Yielding between polls for this long after the last message (a
/// lock-step cycle's next message comes within it), then waiting for an
/// arrival from the link (its doorbell) for at most [`IDLE_WAIT`] at a time.
const BUSY_FOR: Duration = Duration::from_millis(20);

/// The longest an idle bridge waits before it polls this host's services again.
const IDLE_WAIT: Duration = Duration::from_millis(1);

/// Runs a bridge until `stop` is set: joins the link, serves or fetches the
/// run's description, then carries the services and the files.
pub fn run(config: &BridgeConfig, stop: &AtomicBool) -> Result<Traffic, BridgeError> {
    let session = link::open(&config.endpoints)?;
    let (info, _queryable) = match config.side {
        Side::Host => {
            let info = RunInfo::read(&config.run_info)?;
            let queryable = serve_run_info(&session, &info)?;
            (info, Some(queryable))
        }
        Side::Remote => {
            let info = fetch_run_info(&session, JOIN_TIMEOUT)?;
            info.write(&config.run_info)?;
            (info, None)
        }
    };
    let namespace = Namespace::from_prefix(&config.ipc_prefix)?;
    let node = node(&namespace, "bridge")?;
    let (doorbell, rings) = crossbeam::channel::unbounded();
    let mut carriers = routes(&info, config.side)
        .iter()
        .map(|(route, payload)| carrier(&node, &session, &info.prefix, route, *payload, info.wait, &doorbell))
        .collect::<Result<Vec<_>, _>>()?;
    let mut files = match config.side {
        Side::Host => FileShipping::receiver(&session, &info.prefix, &config.work_dir)?,
        Side::Remote => FileShipping::sender(&session, &info.prefix, &config.work_dir)?,
    };
    let mut traffic = Traffic::default();
    let mut last = Instant::now();
    let mut last_files = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let mut moved = Moved::default();
        while rings.try_recv().is_ok() {}
        for carrier in &mut carriers {
            moved = moved.plus(carrier.pump()?);
        }
        if last_files.elapsed() >= Duration::from_millis(50) {
            traffic.files += files.pump(&session)?;
            last_files = Instant::now();
        }
        traffic.messages = traffic.messages.plus(moved);
        if moved.any() {
            last = Instant::now();
        } else if last.elapsed() < BUSY_FOR {
            std::thread::yield_now();
        } else {
            let _ = rings.recv_timeout(IDLE_WAIT);
        }
    }
    Ok(traffic)
}

/// The run's description a remote host's bridge wrote, once it has.
pub fn read_fetched(path: &Path) -> Option<RunInfo> {
    RunInfo::read(path).ok()
}
