//! The run's iceoryx2 services, each opened with explicit limits, and the
//! ports each process holds. Names, payloads and who publishes and subscribes
//! are documented in `shm_layouts/README.md`.

use std::fmt::Debug;

use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::prelude::{NodeBuilder, ServiceName, SignalHandlingMode, ZeroCopySend};
use iceoryx2::service::port_factory::{event, publish_subscribe};
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Heartbeat, KeeperCommand, KeeperSnapshot, NUM_KEEPERS, WorldCommand,
    WorldSnapshot, WorldVocabulary, services,
};

use super::namespace::Namespace;
use super::protocol::{Role, Roster};
use super::wait::WaitStrategy;

pub use super::port::{Ipc, IpcError, Pub, Sub, fail};

/// Sized for the run's processes plus restarts whose predecessor iceoryx2
/// has not yet cleaned up, and a diagnostic or foreign port or two.
const MAX_NODES: usize = 32;

/// A publish-subscribe service's limits.
#[derive(Debug, Clone, Copy)]
struct Limits {
    publishers: usize,
    subscribers: usize,
    /// Samples a subscriber holds before the oldest is overwritten.
    buffer: usize,
}

/// Data services between the simulator and one keeper: one of each side,
/// room for a restarted one and a foreign one; the buffer covers two
/// seconds of real-time cycles, for an agent that was stopped and catches up.
const POINT_TO_POINT: Limits = Limits {
    publishers: 4,
    subscribers: 4,
    buffer: 32,
};

/// Services every process publishes to or subscribes from.
const SHARED: Limits = Limits {
    publishers: 16,
    subscribers: 16,
    buffer: 256,
};

/// Opens (or creates) the publish-subscribe service `name` of `T`.
fn pubsub<T: ZeroCopySend + Debug + 'static>(
    node: &Node<Ipc>,
    name: &str,
    limits: Limits,
) -> Result<publish_subscribe::PortFactory<Ipc, T, ()>, IpcError> {
    let service_name = ServiceName::new(name).map_err(fail(format!("service name {name}")))?;
    node.service_builder(&service_name)
        .publish_subscribe::<T>()
        .max_publishers(limits.publishers)
        .max_subscribers(limits.subscribers)
        .max_nodes(MAX_NODES)
        .history_size(0)
        .subscriber_max_buffer_size(limits.buffer)
        .enable_safe_overflow(true)
        .open_or_create()
        .map_err(fail(format!("opening service {name}")))
}

/// Notifiers of a wake-up event: every sender to its process (a Keepaway run).
const WAKE_NOTIFIERS: usize = 16;

/// Notifiers of a wake-up event in a world run: up to two per agent (its
/// commands and its reports wake the world), the supervisor, restarts.
const WORLD_WAKE_NOTIFIERS: usize = 64;

/// Services every process of a world run publishes to or subscribes from:
/// room for the world, sixteen agents, the supervisor, restarted and foreign ones.
const WORLD_SHARED: Limits = Limits {
    publishers: 40,
    subscribers: 40,
    buffer: 256,
};

/// Opens (or creates) the event service that wakes `process`.
fn wake_service(node: &Node<Ipc>, process: &str) -> Result<event::PortFactory<Ipc>, IpcError> {
    wake_service_for(node, process, WAKE_NOTIFIERS)
}

/// Opens (or creates) the event service that wakes `process`, with room for
/// `notifiers` (an existing service may have more).
fn wake_service_for(node: &Node<Ipc>, process: &str, notifiers: usize) -> Result<event::PortFactory<Ipc>, IpcError> {
    let name = services::wake(process);
    let service_name = ServiceName::new(&name).map_err(fail(format!("service name {name}")))?;
    node.service_builder(&service_name)
        .event()
        .max_listeners(2)
        .max_notifiers(notifiers)
        .max_nodes(MAX_NODES)
        .open_or_create()
        .map_err(fail(format!("opening event service {name}")))
}

/// The wake-up service name of the simulator.
pub(crate) const SIM_PROCESS: &str = "sim";

/// The wake-up service name of keeper `k`'s agent.
pub(crate) fn keeper_process(k: usize) -> String {
    format!("keeper-{k}")
}

/// The wake-up service name of a world.
pub(crate) const WORLD_PROCESS: &str = "world";

/// The wake-up service name of a world's agent `a`.
pub fn agent_process(a: usize) -> String {
    format!("agent-{a}")
}

/// The wake-up service name of `role`'s process.
pub fn wake_name(role: Role) -> String {
    match role {
        Role::Simulator => SIM_PROCESS.to_string(),
        Role::Keeper(k) => keeper_process(k),
        Role::World => WORLD_PROCESS.to_string(),
        Role::Agent(a) => agent_process(a),
        Role::Bridge => "bridge".to_string(),
        Role::View => "view".to_string(),
    }
}

/// A node of the run in `namespace`, named `name`; signals are left to the program.
pub fn node(namespace: &Namespace, name: &str) -> Result<Node<Ipc>, IpcError> {
    let config = namespace.config()?;
    let node_name = name.try_into().map_err(fail(format!("node name {name}")))?;
    NodeBuilder::new()
        .name(&node_name)
        .config(&config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(fail(format!("creating node {name}")))
}

fn publisher<T: ZeroCopySend + Debug + 'static>(
    node: &Node<Ipc>,
    name: &str,
    limits: Limits,
) -> Result<Pub<T>, IpcError> {
    pubsub::<T>(node, name, limits)?
        .publisher_builder()
        .create()
        .map_err(fail(format!("publisher on {name}")))
}

fn subscriber<T: ZeroCopySend + Debug + 'static>(
    node: &Node<Ipc>,
    name: &str,
    limits: Limits,
) -> Result<Sub<T>, IpcError> {
    pubsub::<T>(node, name, limits)?
        .subscriber_builder()
        .create()
        .map_err(fail(format!("subscriber on {name}")))
}

fn listener(node: &Node<Ipc>, process: &str) -> Result<Listener<Ipc>, IpcError> {
    wake_service(node, process)?
        .listener_builder()
        .create()
        .map_err(fail(format!("listener of {process}")))
}

fn notifier(node: &Node<Ipc>, process: &str, notifiers: usize) -> Result<Notifier<Ipc>, IpcError> {
    wake_service_for(node, process, notifiers)?
        .notifier_builder()
        .create()
        .map_err(fail(format!("notifier of {process}")))
}

/// A publish-subscribe service's factory, held to keep the service open.
type Service<T> = publish_subscribe::PortFactory<Ipc, T, ()>;

/// Every service of a run, created by the supervisor before it starts the
/// processes (so the limits are its own) and kept open for the run's life.
pub enum RunServices {
    /// A Keepaway run's.
    Keepaway(KeepawayServices),
    /// A world run's.
    World(WorldServices),
}

impl RunServices {
    /// Creates every service of a run of `roster` on `node`.
    pub fn create(node: &Node<Ipc>, roster: Roster) -> Result<Self, IpcError> {
        Ok(match roster {
            Roster::Keepaway => RunServices::Keepaway(KeepawayServices::create(node)?),
            Roster::World { agents } => RunServices::World(WorldServices::create(node, agents)?),
        })
    }
}

/// A Keepaway run's services (the fields are held to keep them open).
pub struct KeepawayServices {
    _snapshots: Vec<Service<KeeperSnapshot>>,
    _commands: Vec<Service<KeeperCommand>>,
    _episode: Service<EpisodeEvent>,
    _agent_report: Service<AgentReport>,
    _heartbeat: Service<Heartbeat>,
    _control: Service<Control>,
    _floor_ping: Service<KeeperSnapshot>,
    _floor_pong: Service<KeeperCommand>,
    _wake_sim: event::PortFactory<Ipc>,
    _wake_keepers: Vec<event::PortFactory<Ipc>>,
}

impl KeepawayServices {
    /// Creates every service of a Keepaway run on `node`.
    pub(crate) fn create(node: &Node<Ipc>) -> Result<Self, IpcError> {
        let keepers = 0..NUM_KEEPERS;
        Ok(KeepawayServices {
            _snapshots: keepers
                .clone()
                .map(|k| pubsub(node, &services::snapshot(k), POINT_TO_POINT))
                .collect::<Result<_, _>>()?,
            _commands: keepers
                .clone()
                .map(|k| pubsub(node, &services::command(k), POINT_TO_POINT))
                .collect::<Result<_, _>>()?,
            _episode: pubsub(node, services::EPISODE, SHARED)?,
            _agent_report: pubsub(node, services::AGENT_REPORT, SHARED)?,
            _heartbeat: pubsub(node, services::HEARTBEAT, SHARED)?,
            _control: pubsub(node, services::CONTROL, SHARED)?,
            _floor_ping: pubsub(node, services::FLOOR_PING, POINT_TO_POINT)?,
            _floor_pong: pubsub(node, services::FLOOR_PONG, POINT_TO_POINT)?,
            _wake_sim: wake_service(node, SIM_PROCESS)?,
            _wake_keepers: keepers
                .map(|k| wake_service(node, &keeper_process(k)))
                .collect::<Result<_, _>>()?,
        })
    }
}

/// A world run's services (the fields are held to keep them open).
pub struct WorldServices {
    _snapshots: Vec<Service<WorldSnapshot>>,
    _commands: Vec<Service<WorldCommand>>,
    _vocabulary: Service<WorldVocabulary>,
    _agent_report: Service<AgentReport>,
    _heartbeat: Service<Heartbeat>,
    _control: Service<Control>,
    _floor_ping: Service<WorldSnapshot>,
    _floor_pong: Service<WorldCommand>,
    _wakes: Vec<event::PortFactory<Ipc>>,
}

impl WorldServices {
    /// Creates every service of a world run with `agents` agents on `node`.
    pub(crate) fn create(node: &Node<Ipc>, agents: usize) -> Result<Self, IpcError> {
        let roster = Roster::World { agents };
        Ok(WorldServices {
            _snapshots: (0..agents)
                .map(|a| pubsub(node, &services::world_snapshot(a), POINT_TO_POINT))
                .collect::<Result<_, _>>()?,
            _commands: (0..agents)
                .map(|a| pubsub(node, &services::world_command(a), POINT_TO_POINT))
                .collect::<Result<_, _>>()?,
            _vocabulary: pubsub(node, services::WORLD_VOCABULARY, WORLD_SHARED)?,
            _agent_report: pubsub(node, services::AGENT_REPORT, WORLD_SHARED)?,
            _heartbeat: pubsub(node, services::HEARTBEAT, WORLD_SHARED)?,
            _control: pubsub(node, services::CONTROL, WORLD_SHARED)?,
            _floor_ping: pubsub(node, services::WORLD_FLOOR_PING, POINT_TO_POINT)?,
            _floor_pong: pubsub(node, services::WORLD_FLOOR_PONG, POINT_TO_POINT)?,
            _wakes: roster
                .roles()
                .into_iter()
                .map(|role| wake_service_for(node, &wake_name(role), WORLD_WAKE_NOTIFIERS))
                .collect::<Result<_, _>>()?,
        })
    }
}

/// A publisher joined with the wake-up events of the processes that receive
/// what it sends: [`Outlet::send`] publishes, then notifies them (only if
/// their wait strategy blocks), in one call, as iceoryx2's example
/// publishers publish and then notify their listeners.
pub struct Outlet<T: ZeroCopySend + Debug + 'static> {
    publisher: Pub<T>,
    /// The receivers' wake-up events; empty when the receivers never block.
    wakes: Vec<Notifier<Ipc>>,
}

impl<T: ZeroCopySend + Debug + 'static> Outlet<T> {
    /// A publisher on service `name` that wakes `receivers` (wake-up service
    /// names) after each send if the run's processes wait with `wait`.
    fn open(
        node: &Node<Ipc>,
        name: &str,
        limits: Limits,
        receivers: &[String],
        wait: WaitStrategy,
    ) -> Result<Self, IpcError> {
        Self::open_with(node, name, limits, receivers, wait, WAKE_NOTIFIERS)
    }

    /// [`Outlet::open`], with room for `notifiers` on a wake-up service it creates.
    fn open_with(
        node: &Node<Ipc>,
        name: &str,
        limits: Limits,
        receivers: &[String],
        wait: WaitStrategy,
        notifiers: usize,
    ) -> Result<Self, IpcError> {
        let wakes = if wait.notifies() {
            receivers
                .iter()
                .map(|process| notifier(node, process, notifiers))
                .collect::<Result<_, _>>()?
        } else {
            Vec::new()
        };
        Ok(Outlet {
            publisher: publisher(node, name, limits)?,
            wakes,
        })
    }

    /// Publishes `value`, then wakes the receivers.
    pub fn send(&self, value: T) -> Result<(), IpcError> {
        send(&self.publisher, value)?;
        self.wake()
    }

    /// Publishes each of `values`, then wakes the receivers once.
    pub(crate) fn send_each(&self, values: impl IntoIterator<Item = T>) -> Result<(), IpcError> {
        for value in values {
            send(&self.publisher, value)?;
        }
        self.wake()
    }

    fn wake(&self) -> Result<(), IpcError> {
        for notifier in &self.wakes {
            notifier.notify().map_err(fail("notifying a wake-up event"))?;
        }
        Ok(())
    }
}

/// The wake-up service names of every keeper.
fn every_keeper() -> Vec<String> {
    (0..NUM_KEEPERS).map(keeper_process).collect()
}

/// The names of agent a's services, as functions of a: its snapshots, its
/// commands and its wake-up.
type AgentServices = (fn(usize) -> String, fn(usize) -> String, fn(usize) -> String);

/// A host process's ports for its agents, of snapshot payload `S` and
/// command payload `C` (the simulator's and a world's differ only in these).
pub struct HostPorts<S: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> {
    /// Snapshots to agent a (waking it).
    pub snapshots: Vec<Outlet<S>>,
    /// Commands from agent a.
    pub commands: Vec<Sub<C>>,
    /// Agents' reports.
    pub(crate) reports: Sub<AgentReport>,
    /// Heartbeats to the supervisor.
    pub heartbeat: Pub<Heartbeat>,
    /// The supervisor's commands.
    pub control: Sub<Control>,
    /// Wakes the host when it blocks.
    pub wake: Listener<Ipc>,
}

impl<S: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> HostPorts<S, C> {
    /// Opens the ports of host `process` (its wake-up service name) for
    /// `agents` agents on `node`: agent a's snapshots on service
    /// `snapshot(a)`, waking `agent(a)` if the run's processes wait with
    /// `wait`, and its commands on `command(a)`.
    fn open(
        node: &Node<Ipc>,
        process: &str,
        agents: usize,
        (snapshot, command, agent): AgentServices,
        wait: WaitStrategy,
    ) -> Result<Self, IpcError> {
        Ok(HostPorts {
            snapshots: (0..agents)
                .map(|a| Outlet::open(node, &snapshot(a), POINT_TO_POINT, &[agent(a)], wait))
                .collect::<Result<_, _>>()?,
            commands: (0..agents)
                .map(|a| subscriber(node, &command(a), POINT_TO_POINT))
                .collect::<Result<_, _>>()?,
            reports: subscriber(node, services::AGENT_REPORT, SHARED)?,
            heartbeat: publisher(node, services::HEARTBEAT, SHARED)?,
            control: subscriber(node, services::CONTROL, SHARED)?,
            wake: listener(node, process)?,
        })
    }
}

/// The simulator's ports.
pub struct SimPorts {
    /// Its keepers' snapshots and commands, their reports, the heartbeat,
    /// the supervisor's commands and its wake-up.
    pub host: HostPorts<KeeperSnapshot, KeeperCommand>,
    /// Episode events to every agent (waking them).
    pub episode: Outlet<EpisodeEvent>,
    /// Floor measurement pings to agent 0 (waking it).
    pub floor_ping: Outlet<KeeperSnapshot>,
    /// Floor measurement pongs from agent 0.
    pub floor_pong: Sub<KeeperCommand>,
}

impl SimPorts {
    /// Opens the simulator's ports on `node`, for processes that wait with `wait`.
    pub fn open(node: &Node<Ipc>, wait: WaitStrategy) -> Result<Self, IpcError> {
        let keepers: AgentServices = (services::snapshot, services::command, keeper_process);
        Ok(SimPorts {
            host: HostPorts::open(node, SIM_PROCESS, NUM_KEEPERS, keepers, wait)?,
            episode: Outlet::open(node, services::EPISODE, SHARED, &every_keeper(), wait)?,
            floor_ping: Outlet::open(node, services::FLOOR_PING, POINT_TO_POINT, &[keeper_process(0)], wait)?,
            floor_pong: subscriber(node, services::FLOOR_PONG, POINT_TO_POINT)?,
        })
    }
}

/// An agent's ports (keeper k).
pub struct AgentPorts {
    /// Its snapshots.
    pub snapshot: Sub<KeeperSnapshot>,
    /// Its commands (waking the simulator).
    pub command: Outlet<KeeperCommand>,
    /// Episode events.
    pub episode: Sub<EpisodeEvent>,
    /// Its reports to the simulator (waking it).
    pub report: Outlet<AgentReport>,
    /// Heartbeats to the supervisor.
    pub heartbeat: Pub<Heartbeat>,
    /// The supervisor's commands.
    pub control: Sub<Control>,
    /// Floor pings (agent 0 answers them).
    pub floor_ping: Sub<KeeperSnapshot>,
    /// Floor pongs (waking the simulator).
    pub floor_pong: Outlet<KeeperCommand>,
    /// Wakes this agent when it blocks.
    pub wake: Listener<Ipc>,
}

impl AgentPorts {
    /// Opens keeper `k`'s ports on `node`, for processes that wait with `wait`.
    pub fn open(node: &Node<Ipc>, k: usize, wait: WaitStrategy) -> Result<Self, IpcError> {
        let sim = [SIM_PROCESS.to_string()];
        Ok(AgentPorts {
            snapshot: subscriber(node, &services::snapshot(k), POINT_TO_POINT)?,
            command: Outlet::open(node, &services::command(k), POINT_TO_POINT, &sim, wait)?,
            episode: subscriber(node, services::EPISODE, SHARED)?,
            report: Outlet::open(node, services::AGENT_REPORT, SHARED, &sim, wait)?,
            heartbeat: publisher(node, services::HEARTBEAT, SHARED)?,
            control: subscriber(node, services::CONTROL, SHARED)?,
            floor_ping: subscriber(node, services::FLOOR_PING, POINT_TO_POINT)?,
            floor_pong: Outlet::open(node, services::FLOOR_PONG, POINT_TO_POINT, &sim, wait)?,
            wake: listener(node, &keeper_process(k))?,
        })
    }
}

/// A world's agent's ports (agent a).
pub(crate) struct WorldAgentPorts {
    /// Its snapshots.
    pub snapshot: Sub<WorldSnapshot>,
    /// Its commands (waking the world).
    pub command: Outlet<WorldCommand>,
    /// The world's vocabulary.
    pub vocabulary: Sub<WorldVocabulary>,
    /// Its readiness reports to the world (waking it).
    pub report: Outlet<AgentReport>,
    /// Heartbeats to the supervisor.
    pub heartbeat: Pub<Heartbeat>,
    /// The supervisor's commands.
    pub control: Sub<Control>,
    /// Agent 0: the supervisor's floor pings, and the pongs answering them
    /// (the supervisor polls without blocking).
    pub floor: Option<(Sub<WorldSnapshot>, Pub<WorldCommand>)>,
    /// Wakes this agent when it blocks.
    pub wake: Listener<Ipc>,
}

impl WorldAgentPorts {
    /// Opens agent `a`'s ports on `node`, for processes that wait with `wait`.
    pub(crate) fn open(node: &Node<Ipc>, a: usize, wait: WaitStrategy) -> Result<Self, IpcError> {
        let world = [WORLD_PROCESS.to_string()];
        Ok(WorldAgentPorts {
            snapshot: subscriber(node, &services::world_snapshot(a), POINT_TO_POINT)?,
            command: Outlet::open(node, &services::world_command(a), POINT_TO_POINT, &world, wait)?,
            vocabulary: subscriber(node, services::WORLD_VOCABULARY, SHARED)?,
            report: Outlet::open(node, services::AGENT_REPORT, SHARED, &world, wait)?,
            heartbeat: publisher(node, services::HEARTBEAT, SHARED)?,
            control: subscriber(node, services::CONTROL, SHARED)?,
            floor: if a == 0 {
                Some((
                    subscriber(node, services::WORLD_FLOOR_PING, POINT_TO_POINT)?,
                    publisher(node, services::WORLD_FLOOR_PONG, POINT_TO_POINT)?,
                ))
            } else {
                None
            },
            wake: listener(node, &agent_process(a))?,
        })
    }
}

/// A world's ports, for a world written in Rust (the Python world kit opens
/// the same services).
pub(crate) struct WorldPorts {
    /// Its agents' snapshots and commands, their readiness reports, the
    /// heartbeat, the supervisor's commands and its wake-up.
    pub host: HostPorts<WorldSnapshot, WorldCommand>,
    /// The vocabulary to every agent.
    pub vocabulary: Pub<WorldVocabulary>,
}

impl WorldPorts {
    /// Opens the ports of a world of `agents` agents on `node`, for processes that wait with `wait`.
    pub(crate) fn open(node: &Node<Ipc>, agents: usize, wait: WaitStrategy) -> Result<Self, IpcError> {
        let agent_services: AgentServices = (services::world_snapshot, services::world_command, agent_process);
        Ok(WorldPorts {
            host: HostPorts::open(node, WORLD_PROCESS, agents, agent_services, wait)?,
            vocabulary: publisher(node, services::WORLD_VOCABULARY, SHARED)?,
        })
    }
}

/// The supervisor's ports.
pub(crate) struct SupervisorPorts {
    /// Every process's heartbeats.
    pub(crate) heartbeats: Sub<Heartbeat>,
    /// Commands to the processes (waking every one of them).
    pub control: Outlet<Control>,
}

impl SupervisorPorts {
    /// Opens the supervisor's ports on `node` for a run of `roster`, whose
    /// processes wait with `wait`.
    pub(crate) fn open(node: &Node<Ipc>, wait: WaitStrategy, roster: Roster) -> Result<Self, IpcError> {
        let everyone: Vec<String> = roster.roles().into_iter().map(wake_name).collect();
        Ok(SupervisorPorts {
            heartbeats: subscriber(node, services::HEARTBEAT, SHARED)?,
            control: Outlet::open(node, services::CONTROL, SHARED, &everyone, wait)?,
        })
    }
}

/// The view process's ports beside the agents' feeds ([`super::feed`]): it
/// only reads.
pub(crate) struct ViewPorts {
    /// Every process's heartbeats.
    pub(crate) heartbeats: Sub<Heartbeat>,
}

impl ViewPorts {
    /// Opens the view's ports on `node`.
    pub(crate) fn open(node: &Node<Ipc>) -> Result<Self, IpcError> {
        Ok(ViewPorts {
            heartbeats: subscriber(node, services::HEARTBEAT, SHARED)?,
        })
    }
}

/// The wake-up service name of a remote host's floor echo process.
pub(crate) const FLOOR_ECHO_PROCESS: &str = "floor-echo";

/// The pinging side of a floor measurement: pings of the snapshot payload
/// `P` (waking the process that echoes them) and its echoes, of the command
/// payload `C`.
pub(crate) struct FloorPorts<P: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> {
    /// Pings to the echoing process (waking it).
    pub ping: Outlet<P>,
    /// Its echoes.
    pub pong: Sub<C>,
}

impl FloorPorts<WorldSnapshot, WorldCommand> {
    /// A world run's, echoed by agent 0, which waits with `wait`.
    pub(crate) fn world(node: &Node<Ipc>, wait: WaitStrategy) -> Result<Self, IpcError> {
        Ok(FloorPorts {
            ping: Outlet::open(
                node,
                services::WORLD_FLOOR_PING,
                POINT_TO_POINT,
                &[agent_process(0)],
                wait,
            )?,
            pong: subscriber(node, services::WORLD_FLOOR_PONG, POINT_TO_POINT)?,
        })
    }
}

impl<P: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> FloorPorts<P, C> {
    /// A remote host's own, echoed by its floor echo process, which waits with `wait`.
    pub(crate) fn host(node: &Node<Ipc>, wait: WaitStrategy) -> Result<Self, IpcError> {
        Ok(FloorPorts {
            ping: Outlet::open(
                node,
                services::HOST_FLOOR_PING,
                POINT_TO_POINT,
                &[FLOOR_ECHO_PROCESS.to_string()],
                wait,
            )?,
            pong: subscriber(node, services::HOST_FLOOR_PONG, POINT_TO_POINT)?,
        })
    }
}

/// The echoing side of a remote host's own floor measurement.
pub(crate) struct FloorEchoPorts<P: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> {
    /// The supervisor's pings.
    pub ping: Sub<P>,
    /// The echoes (the supervisor polls for them).
    pub pong: Pub<C>,
    /// Wakes the echo process when it blocks.
    pub wake: Listener<Ipc>,
}

impl<P: ZeroCopySend + Debug + 'static, C: ZeroCopySend + Debug + 'static> FloorEchoPorts<P, C> {
    /// Opens them on `node`.
    pub(crate) fn open(node: &Node<Ipc>) -> Result<Self, IpcError> {
        Ok(FloorEchoPorts {
            ping: subscriber(node, services::HOST_FLOOR_PING, POINT_TO_POINT)?,
            pong: publisher(node, services::HOST_FLOOR_PONG, POINT_TO_POINT)?,
            wake: listener(node, FLOOR_ECHO_PROCESS)?,
        })
    }
}

/// A bridge's ports on one service: a subscriber, to carry to the other
/// hosts what this host's processes publish, and an outlet, to publish here
/// (waking the receivers) what the other hosts sent.
pub struct BridgePorts<T: ZeroCopySend + Debug + 'static> {
    /// What this host's processes publish.
    pub subscriber: Sub<T>,
    /// What the other hosts sent, published here.
    pub outlet: Outlet<T>,
}

impl<T: ZeroCopySend + Debug + 'static> BridgePorts<T> {
    /// Opens them on service `name` of a run of `roster` (`point_to_point`:
    /// one publisher and one subscriber each side, else a service every
    /// process uses), with the limits the supervisor gives it (the bridge may
    /// create it first), waking `receivers` (wake-up service names) when the
    /// run's processes wait with `wait`.
    pub fn open(
        node: &Node<Ipc>,
        name: &str,
        point_to_point: bool,
        receivers: &[String],
        wait: WaitStrategy,
        roster: Roster,
    ) -> Result<Self, IpcError> {
        let (shared, notifiers) = match roster {
            Roster::Keepaway => (SHARED, WAKE_NOTIFIERS),
            Roster::World { .. } => (WORLD_SHARED, WORLD_WAKE_NOTIFIERS),
        };
        let limits = if point_to_point { POINT_TO_POINT } else { shared };
        Ok(BridgePorts {
            subscriber: subscriber(node, name, limits)?,
            outlet: Outlet::open_with(node, name, limits, receivers, wait, notifiers)?,
        })
    }

    /// Whether a sample came from this bridge's own outlet (not to be carried back).
    pub fn is_own(&self, origin: iceoryx2::identifiers::UniquePublisherId) -> bool {
        self.outlet.publisher.id() == origin
    }
}

/// Publishes `value` on `publisher`, written straight into a loaned
/// shared-memory sample.
pub(crate) fn send<T: ZeroCopySend + Debug + 'static>(publisher: &Pub<T>, value: T) -> Result<(), IpcError> {
    let sample = publisher.loan_uninit().map_err(fail("loaning a sample"))?;
    sample
        .write_payload(value)
        .send()
        .map(|_| ())
        .map_err(fail("sending a sample"))
}

/// Reads the next sample on `subscriber` in place (in shared memory, not
/// copied) with `read`, if there is one.
pub fn receive<T: ZeroCopySend + Debug + 'static, R>(
    subscriber: &Sub<T>,
    read: impl FnOnce(&T) -> R,
) -> Result<Option<R>, IpcError> {
    let sample = subscriber.receive().map_err(fail("receiving a sample"))?;
    Ok(sample.map(|s| read(&s)))
}
