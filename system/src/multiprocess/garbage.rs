//! Garbage on a run's services, published as a foreign process would: what
//! chaos soaks inject ([`Garbage::every_kind`]) and what the tests send to
//! check that every process refuses and counts it.

use std::fmt::Debug;
use std::time::Duration;

use iceoryx2::node::Node;
use iceoryx2::prelude::{ServiceName, ZeroCopySend};
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Header, KeeperCommand, KeeperSnapshot, NUM_KEEPERS, PROTOCOL_VERSION,
    SENDER_SIMULATOR, SENDER_SUPERVISOR, WorldCommand, WorldSnapshot, WorldVocabulary, services,
};

use super::sim_process::floor_ping;
use crate::ipc::services::{Ipc, IpcError, Pub, fail};

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
    pub world_snapshots: Vec<Vec<WorldSnapshot>>,
    /// A world run: commands on agent a's service (index a).
    pub world_commands: Vec<Vec<WorldCommand>>,
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
