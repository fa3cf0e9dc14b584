//! Garbage on a run's services, published as a foreign process would: what
//! chaos soaks inject ([`Garbage::every_kind`](crate::garbage::Garbage::every_kind)) and what the tests send to
//! check that every process refuses and counts it.

use std::fmt::Debug;
use std::time::Duration;

use iceoryx2::node::Node;
use iceoryx2::prelude::{ServiceName, ZeroCopySend};
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Header, KeeperCommand, KeeperSnapshot, MAX_AGENTS, MAX_ARGS, MAX_FLUENTS,
    NAME_LEN, NAMES_PER_PART, NO_ACTION, NUM_KEEPERS, PROTOCOL_VERSION, SENDER_SIMULATOR, SENDER_SUPERVISOR,
    SENDER_WORLD, WorldCommand, WorldSnapshot, WorldVocabulary, services,
};

use learnpnp_system::ipc::services::{Ipc, IpcError, Pub, fail};
use learnpnp_system::multiprocess::host::simulator::floor_ping;

/// Messages to publish on a run's services, by service (empty: none there).
#[derive(Debug, Clone, Default)]
pub struct Garbage {
    /// On keeper k's command service.
    pub commands: [Vec<KeeperCommand>; NUM_KEEPERS],
    /// On keeper k's snapshot service.
    pub snapshots: [Vec<KeeperSnapshot>; NUM_KEEPERS],
    /// On the episode events' service.
    pub episode: Vec<EpisodeEvent>,
    /// On the agents' reports' service.
    pub reports: Vec<AgentReport>,
    /// On the supervisor's control service.
    pub control: Vec<Control>,
    /// A world run: snapshots on agent a's service (index a).
    pub(crate) world_snapshots: Vec<Vec<WorldSnapshot>>,
    /// A world run: commands on agent a's service (index a).
    pub(crate) world_commands: Vec<Vec<WorldCommand>>,
    /// A world run: vocabulary parts.
    pub vocabulary: Vec<WorldVocabulary>,
}

/// How many subscribers a service's garbage reached (the fewest over its messages).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Delivered {
    /// The service.
    pub service: String,
    /// Subscribers reached.
    pub subscribers: usize,
}

/// Publishes `values` on the existing service `service` (a foreign process
/// creates nothing); returns the publisher, which holds the samples, and the
/// subscribers reached.
fn burst<T: ZeroCopySend + Debug + Copy + 'static>(
    node: &Node<Ipc>,
    service: &str,
    values: &[T],
    delivered: &mut Vec<Delivered>,
) -> Result<Option<Pub<T>>, IpcError> {
    if values.is_empty() {
        return Ok(None);
    }
    let name = ServiceName::new(service).map_err(fail(format!("service name {service}")))?;
    let publisher = node
        .service_builder(&name)
        .publish_subscribe::<T>()
        .open()
        .map_err(fail(format!("opening service {service}")))?
        .publisher_builder()
        .create()
        .map_err(fail(format!("publisher on {service}")))?;
    let mut subscribers = usize::MAX;
    for v in values {
        let reached = publisher.send_copy(*v).map_err(fail(format!("sending on {service}")))?;
        subscribers = subscribers.min(reached);
    }
    delivered.push(Delivered {
        service: service.to_string(),
        subscribers,
    });
    Ok(Some(publisher))
}

impl Garbage {
    /// Garbage of every kind on every service of run `run_id`: a wrong
    /// protocol version, NaN, unknown tags, ids out of range, a keeper's
    /// command on another's service.
    pub fn every_kind(run_id: u64) -> Self {
        let command = KeeperCommand {
            header: Header::new(0, run_id),
            episode: 0,
            cycle_seq: 0,
            kind: 0,
            flags: 0,
            arg0: 0.0,
            arg1: 0.0,
        };
        let mut snapshot = floor_ping(run_id, 0);
        snapshot.players[2].vel[1] = f64::NAN;
        let mut garbage = Garbage::default();
        for k in 0..NUM_KEEPERS {
            garbage.commands[k] = vec![
                KeeperCommand {
                    header: Header {
                        version: PROTOCOL_VERSION + 7,
                        ..command.header
                    },
                    ..command
                },
                KeeperCommand {
                    kind: 1,
                    arg0: f64::NAN,
                    header: Header::new(k as u32, run_id),
                    ..command
                },
                KeeperCommand {
                    header: Header::new(((k + 1) % NUM_KEEPERS) as u32, run_id),
                    ..command
                },
                KeeperCommand {
                    kind: 77,
                    header: Header::new(k as u32, run_id),
                    ..command
                },
            ];
            garbage.snapshots[k] = vec![
                KeeperSnapshot {
                    me: k as u32,
                    ..snapshot
                },
                KeeperSnapshot { me: 9, ..snapshot },
            ];
        }
        Garbage {
            episode: vec![EpisodeEvent {
                header: Header::new(SENDER_SIMULATOR, run_id),
                episode: 0,
                kind: 99,
                mode: 0,
                forced_exploration: 0,
                reserved: [0; 2],
                cycles: 0,
                reserved2: 0,
                seconds: f64::NAN,
            }],
            reports: vec![AgentReport {
                header: Header::new(42, run_id),
                episode: 0,
                kind: 2,
                pid: 0,
                exploratory: 7,
                reserved: [0; 7],
            }],
            control: vec![Control {
                header: Header::new(SENDER_SUPERVISOR, run_id),
                command: 55,
                target: u32::MAX,
                sequence: 0,
                pid: 0,
                reserved: 0,
            }],
            ..garbage
        }
    }

    /// Garbage on a world run's services with `agents` agents, as the world
    /// tests and chaos soaks publish it: on each agent's snapshot service, a
    /// snapshot of another run, one from another sender, three whose content
    /// is wrong (a NaN fluent, an atom beyond any vocabulary's first 192, an
    /// unknown episode status) and a well-formed one out of sequence (cycle
    /// 1, older than any an agent under way has taken); on each agent's
    /// command service, a command from another agent, two whose content is
    /// wrong (an action index beyond the vocabulary, NaN arguments) and one
    /// of another run; a vocabulary part of no whole.
    pub fn every_world_kind(run_id: u64, agents: usize) -> Self {
        Garbage {
            world_snapshots: (0..agents).map(|a| world_snapshots(run_id, a)).collect(),
            world_commands: (0..agents).map(|a| world_commands(run_id, a)).collect(),
            vocabulary: vec![WorldVocabulary {
                header: Header::new(SENDER_WORLD, run_id),
                atoms: 1,
                fluents: 1,
                actions: 2,
                agents: 1,
                part: 0,
                parts: 7,
                first: 0,
                count: 4,
                names: [[0; NAME_LEN]; NAMES_PER_PART],
            }],
            ..Garbage::default()
        }
    }

    /// Publishes the garbage on the services of `node`'s run and keeps the
    /// publishers (whose memory holds the samples) for `hold`, for the
    /// subscribers to read it; returns what each service's garbage reached.
    pub fn publish(&self, node: &Node<Ipc>, hold: Duration) -> Result<Vec<Delivered>, IpcError> {
        let mut delivered = Vec::new();
        let mut commands = Vec::new();
        let mut snapshots = Vec::new();
        for k in 0..NUM_KEEPERS {
            commands.push(burst(node, &services::command(k), &self.commands[k], &mut delivered)?);
            snapshots.push(burst(node, &services::snapshot(k), &self.snapshots[k], &mut delivered)?);
        }
        let episode = burst(node, services::EPISODE, &self.episode, &mut delivered)?;
        let reports = burst(node, services::AGENT_REPORT, &self.reports, &mut delivered)?;
        let control = burst(node, services::CONTROL, &self.control, &mut delivered)?;
        let mut world_snapshots = Vec::new();
        for (a, values) in self.world_snapshots.iter().enumerate() {
            world_snapshots.push(burst(node, &services::world_snapshot(a), values, &mut delivered)?);
        }
        let mut world_commands = Vec::new();
        for (a, values) in self.world_commands.iter().enumerate() {
            world_commands.push(burst(node, &services::world_command(a), values, &mut delivered)?);
        }
        let vocabulary = burst(node, services::WORLD_VOCABULARY, &self.vocabulary, &mut delivered)?;
        std::thread::sleep(hold);
        drop((commands, snapshots, episode, reports, control));
        drop((world_snapshots, world_commands, vocabulary));
        Ok(delivered)
    }
}

/// The garbage snapshots of [`Garbage::every_world_kind`] for agent `a`.
fn world_snapshots(run_id: u64, a: usize) -> Vec<WorldSnapshot> {
    let good = WorldSnapshot {
        header: Header::new(SENDER_WORLD, run_id),
        episode: 1,
        cycle: 1,
        sent_ns: 0,
        answer_cycle: 0,
        answer_received_ns: 0,
        reward: 0.0,
        agent: a as u32,
        step: 0,
        episode_status: 0,
        action_status: 0,
        reserved: [0; 6],
        atoms: [0; 4],
        fluents: [0.0; MAX_FLUENTS],
    };
    let mut other_run = good;
    other_run.header.run_id = run_id ^ 1;
    let mut other_sender = good;
    other_sender.header.sender = 3;
    let mut nan = good;
    nan.fluents[0] = f64::NAN;
    let mut beyond = good;
    beyond.atoms[3] = 1;
    let mut unknown_status = good;
    unknown_status.episode_status = 9;
    vec![other_run, other_sender, nan, beyond, unknown_status, good]
}

/// The garbage commands of [`Garbage::every_world_kind`] on agent `a`'s service.
fn world_commands(run_id: u64, a: usize) -> Vec<WorldCommand> {
    let good = WorldCommand {
        header: Header::new(a as u32, run_id),
        episode: 1,
        cycle: 1,
        compute_ns: 0,
        action: NO_ACTION,
        reserved: 0,
        args: [0.0; MAX_ARGS],
    };
    let mut other_agent = good;
    other_agent.header.sender = (a as u32 + 1) % MAX_AGENTS as u32;
    let mut beyond = good;
    beyond.action = 9999;
    let mut nan = good;
    nan.args = [f64::NAN; MAX_ARGS];
    let mut other_run = good;
    other_run.header.run_id = run_id.wrapping_add(1);
    vec![other_agent, beyond, nan, other_run]
}
