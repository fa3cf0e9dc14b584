//! An agent's live feed on iceoryx2 (only in a run with a view): each agent
//! publishes its [`FeedEvent`](learnpnp_feed::FeedEvent)s, encoded as JSON in a byte slice behind a
//! [`FeedHeader`](shm_layouts::FeedHeader), on a service of its own ([`services::feed`](shm_layouts::services::feed)); the view
//! process reads them, checks every one and counts what it refuses.
//!
//! The sender never waits: the service overwrites the oldest record a slow
//! view has not read (safe overflow), a record larger than
//! [`MAX_FEED_BYTES`](shm_layouts::MAX_FEED_BYTES) or without a free sample is dropped, and the header's
//! sequence number lets the view count every record lost either way.

use std::fmt::Debug;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::node::Node;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::{AllocationStrategy, NodeBuilder, ServiceName, SignalHandlingMode, ipc_threadsafe};
use iceoryx2::service::port_factory::publish_subscribe;
use learnpnp_feed::{FeedEvent, FeedSink};
use shm_layouts::{FeedHeader, MAX_FEED_BYTES, PROTOCOL_VERSION, services};

use super::namespace::Namespace;
use super::protocol::{Rejection, Rejections};
use super::services::{Ipc, IpcError, fail};

/// The service variant of an agent's feed publisher: thread-safe ports, so
/// that the publisher is a [`FeedSink`] (`Send + Sync`); it shares the
/// services of [`Ipc`] (the same shared-memory layout).
pub type FeedIpc = ipc_threadsafe::Service;

/// Publishers: the agent, a restarted one whose predecessor iceoryx2 has not
/// yet cleaned up, a foreign one.
const FEED_PUBLISHERS: usize = 4;
/// Subscribers: the view, a restarted one, a diagnostic tool.
const FEED_SUBSCRIBERS: usize = 4;
/// Records a subscriber holds before the oldest is overwritten: a view that
/// reads every 20 ms keeps up with 12,800 records a second per agent.
const FEED_BUFFER: usize = 256;
/// Nodes on a feed service: the supervisor, the agent, the view, restarts.
const FEED_NODES: usize = 16;
/// The slice a publisher's samples start with; larger records make it
/// allocate larger ones (power of two), up to [`MAX_FEED_BYTES`].
const INITIAL_SLICE: usize = 4096;

/// A feed service's factory.
pub type FeedService<S> = publish_subscribe::PortFactory<S, [u8], FeedHeader>;

/// Opens (or creates) agent `a`'s feed service on `node`.
pub fn feed_service<S: iceoryx2::service::Service>(node: &Node<S>, a: usize) -> Result<FeedService<S>, IpcError> {
    let name = services::feed(a);
    let service_name = ServiceName::new(&name).map_err(fail(format!("service name {name}")))?;
    node.service_builder(&service_name)
        .publish_subscribe::<[u8]>()
        .user_header::<FeedHeader>()
        .max_publishers(FEED_PUBLISHERS)
        .max_subscribers(FEED_SUBSCRIBERS)
        .max_nodes(FEED_NODES)
        .history_size(0)
        .subscriber_max_buffer_size(FEED_BUFFER)
        .enable_safe_overflow(true)
        .open_or_create()
        .map_err(fail(format!("opening service {name}")))
}

/// The feed services of a run with a view, created by the supervisor (so
/// the limits are its own) and held open for the run's life.
pub struct FeedServices {
    _feeds: Vec<FeedService<Ipc>>,
}

impl FeedServices {
    /// Creates the feed service of each of `agents` agents on `node`.
    pub fn create(node: &Node<Ipc>, agents: usize) -> Result<Self, IpcError> {
        Ok(FeedServices {
            _feeds: (0..agents).map(|a| feed_service(node, a)).collect::<Result<_, _>>()?,
        })
    }
}

/// How often an agent sends its plan's shape again, so that a view that
/// starts (or is restarted) after the agent still draws the plan.
const PLAN_AGAIN: Duration = Duration::from_secs(1);

/// What a publisher keeps between records.
#[derive(Default)]
struct Encoding {
    /// The record being sent, as JSON (reused: no allocation per record).
    buffer: Vec<u8>,
    /// The plan's shape, encoded, and when it was last sent.
    plan: Option<(Vec<u8>, Instant)>,
}

/// An agent's feed publisher: a [`FeedSink`] that never waits. The plan's
/// shape, sent once by the agent, is sent again every second with
/// the records that follow.
pub struct FeedPublisher {
    publisher: Publisher<FeedIpc, [u8], FeedHeader>,
    agent: u32,
    run_id: u64,
    sequence: AtomicU64,
    dropped: AtomicU64,
    /// The encoder's buffer and the plan's shape.
    encoding: Mutex<Encoding>,
    _node: Node<FeedIpc>,
}

impl FeedPublisher {
    /// Agent `agent`'s publisher on run `run_id`'s feed service in `namespace`.
    pub fn open(namespace: &Namespace, agent: usize, run_id: u64) -> Result<Self, IpcError> {
        let config = namespace.config()?;
        let node_name = format!("feed-{agent}");
        let node = NodeBuilder::new()
            .name(
                &node_name
                    .as_str()
                    .try_into()
                    .map_err(fail(format!("node name {node_name}")))?,
            )
            .config(&config)
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<FeedIpc>()
            .map_err(fail(format!("creating node {node_name}")))?;
        let publisher = feed_service(&node, agent)?
            .publisher_builder()
            .initial_max_slice_len(INITIAL_SLICE)
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            .create()
            .map_err(fail(format!("publisher on {}", services::feed(agent))))?;
        Ok(FeedPublisher {
            publisher,
            agent: agent as u32,
            run_id,
            sequence: AtomicU64::new(0),
            dropped: AtomicU64::new(0),
            encoding: Mutex::new(Encoding::default()),
            _node: node,
        })
    }

    /// Records dropped here (too large, or no free sample).
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// Sends one encoded record; whether it went.
    fn send(&self, bytes: &[u8]) -> bool {
        let sequence = self.sequence.fetch_add(1, Ordering::Relaxed) + 1;
        if bytes.len() > MAX_FEED_BYTES {
            return false;
        }
        let Ok(mut sample) = self.publisher.loan_slice_uninit(bytes.len()) else {
            return false;
        };
        *sample.user_header_mut() = FeedHeader {
            version: PROTOCOL_VERSION,
            sender: self.agent,
            run_id: self.run_id,
            sequence,
        };
        sample.write_from_slice(bytes).send().is_ok()
    }

    /// Sends one encoded record, counting it if it was dropped.
    fn send_or_count(&self, bytes: &[u8]) {
        if !self.send(bytes) {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }
}

impl FeedSink for FeedPublisher {
    fn publish(&self, event: &FeedEvent) {
        let mut encoding = self.encoding.lock().unwrap_or_else(PoisonError::into_inner);
        let Encoding { buffer, plan } = &mut *encoding;
        buffer.clear();
        if serde_json::to_writer(&mut *buffer, event).is_err() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
            return;
        }
        self.send_or_count(buffer);
        if let FeedEvent::Plan(_) = event {
            *plan = Some((buffer.clone(), Instant::now()));
        } else if let Some((shape, sent)) = plan.as_mut()
            && sent.elapsed() >= PLAN_AGAIN
        {
            *sent = Instant::now();
            self.send_or_count(shape);
        }
    }
}

/// A record of an agent's feed that passed the checks.
#[derive(Debug, PartialEq)]
pub struct CheckedRecord<'a> {
    /// Its kind: the index of its channel in [`learnpnp_feed::CHANNELS`].
    pub kind: usize,
    /// What its channel carries, as the agent encoded it (the record
    /// without the kind's tag): a view passes it on without encoding it again.
    pub payload: &'a [u8],
    /// The record, read from the payload.
    pub event: FeedEvent,
}

/// Checks one record read from agent `agent`'s feed of run `run_id` (run
/// index `run`): the header (version, run, sender), the size, the JSON (the
/// compact form of a [`FeedEvent`], read in full into its record), and what
/// it says (a record an agent publishes, about itself in this run).
pub fn check_record<'a>(
    header: &FeedHeader,
    bytes: &'a [u8],
    agent: usize,
    run_id: u64,
    run: usize,
) -> Result<CheckedRecord<'a>, Rejection> {
    if header.version != PROTOCOL_VERSION {
        return Err(Rejection::Version);
    }
    if header.run_id != run_id {
        return Err(Rejection::Run);
    }
    if header.sender as usize != agent {
        return Err(Rejection::Sender);
    }
    if bytes.len() > MAX_FEED_BYTES {
        return Err(Rejection::Content);
    }
    let (kind, payload) = FeedEvent::split_json(bytes).ok_or(Rejection::Content)?;
    let event = FeedEvent::from_kind_payload(kind, payload).ok_or(Rejection::Content)?;
    let source = match &event {
        FeedEvent::Plan(r) => &r.source,
        FeedEvent::Marking(r) => &r.source,
        FeedEvent::Choice(r) => &r.source,
        FeedEvent::Reward(r) => &r.source,
        FeedEvent::Episode(r) => &r.source,
        FeedEvent::Curve(_) | FeedEvent::Health(_) | FeedEvent::Latency(_) => return Err(Rejection::Content),
    };
    if source.agent as usize != agent || source.run as usize != run {
        return Err(Rejection::Sender);
    }
    Ok(CheckedRecord { kind, payload, event })
}

/// What a view has read of the agents' feeds.
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FeedCounts {
    /// Records read and passed on.
    pub received: u64,
    /// Records refused (by reason).
    pub rejected: Rejections,
    /// Records lost: gaps in a publisher's sequence (dropped by the agent,
    /// or overwritten before the view read them).
    pub dropped: u64,
}

/// One agent's feed, as the view reads it.
struct AgentFeed {
    subscriber: Subscriber<Ipc, [u8], FeedHeader>,
    /// The publisher last read and its last sequence number.
    last: Option<(UniquePublisherId, u64)>,
}

/// The view's side: every agent's feed, read, checked and counted.
pub struct FeedReader {
    feeds: Vec<AgentFeed>,
    run_id: u64,
    run: usize,
    counts: FeedCounts,
}

/// The most records read from one agent's feed in one [`FeedReader::read`]
/// (so that one agent's flood does not starve the others).
const READ_BATCH: usize = 4 * FEED_BUFFER;

impl FeedReader {
    /// Subscribes on `node` to the feeds of `agents` agents of run `run_id` (run index `run`).
    pub fn open(node: &Node<Ipc>, agents: usize, run_id: u64, run: usize) -> Result<Self, IpcError> {
        let feeds = (0..agents)
            .map(|a| {
                let subscriber = feed_service(node, a)?
                    .subscriber_builder()
                    .create()
                    .map_err(fail(format!("subscriber on {}", services::feed(a))))?;
                Ok(AgentFeed { subscriber, last: None })
            })
            .collect::<Result<_, IpcError>>()?;
        Ok(FeedReader {
            feeds,
            run_id,
            run,
            counts: FeedCounts::default(),
        })
    }

    /// What has been read so far.
    pub fn counts(&self) -> &FeedCounts {
        &self.counts
    }

    /// Reads what has come on every feed, handing each record that passes
    /// the checks to `each`; refused and lost records are counted.
    pub fn read(&mut self, mut each: impl FnMut(FeedEvent)) -> Result<(), IpcError> {
        self.read_records(|record| each(record.event))
    }

    /// Reads what has come on every feed, handing each record that passes
    /// the checks, with its payload as the agent encoded it, to `each`;
    /// refused and lost records are counted.
    pub fn read_records(&mut self, mut each: impl FnMut(CheckedRecord<'_>)) -> Result<(), IpcError> {
        for (agent, feed) in self.feeds.iter_mut().enumerate() {
            for _ in 0..READ_BATCH {
                let Some(sample) = feed.subscriber.receive().map_err(fail("receiving a feed record"))? else {
                    break;
                };
                let header = *sample.user_header();
                match check_record(&header, sample.payload(), agent, self.run_id, self.run) {
                    Ok(record) => {
                        let origin = sample.origin();
                        match feed.last {
                            Some((last_origin, last)) if last_origin == origin => {
                                if header.sequence <= last {
                                    self.counts.rejected.count(Rejection::Sequence);
                                    continue;
                                }
                                self.counts.dropped += header.sequence - last - 1;
                            }
                            // A new publisher (the agent restarted): its count begins anew.
                            _ => {}
                        }
                        feed.last = Some((origin, header.sequence));
                        self.counts.received += 1;
                        each(record);
                    }
                    Err(why) => self.counts.rejected.count(why),
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipc::namespace::Namespace;
    use crate::ipc::services::node;
    use learnpnp_feed::{EpisodeEnd, RewardSample, Source};

    fn reward(agent: u32, step: u64) -> FeedEvent {
        FeedEvent::Reward(RewardSample {
            source: Source { run: 0, agent },
            episode: 1,
            step,
            reward: -0.5,
        })
    }

    #[test]
    fn records_cross_and_garbage_is_refused_and_counted() {
        let owner = Namespace::claim_unique().unwrap();
        let namespace = owner.namespace().clone();
        let supervisor = node(&namespace, "supervisor").unwrap();
        let _services = FeedServices::create(&supervisor, 2).unwrap();
        let view = node(&namespace, "view").unwrap();
        let mut reader = FeedReader::open(&view, 2, 7, 0).unwrap();
        let agent = FeedPublisher::open(&namespace, 1, 7).unwrap();
        agent.publish(&reward(1, 1));
        agent.publish(&FeedEvent::Episode(EpisodeEnd {
            source: Source { run: 0, agent: 1 },
            episode: 1,
            episode_return: 3.0,
            evaluation: false,
        }));
        // Too large: dropped by the sender, seen by the view as a gap.
        let huge = FeedEvent::Plan(learnpnp_feed::PlanShape {
            source: Source { run: 0, agent: 1 },
            plan: "x".repeat(MAX_FEED_BYTES),
            places: Vec::new(),
            transitions: Vec::new(),
        });
        agent.publish(&huge);
        assert_eq!(agent.dropped(), 1);
        agent.publish(&reward(1, 2));
        // Another agent's record on agent 1's service.
        agent.publish(&reward(0, 3));
        let mut read = Vec::new();
        reader.read(|e| read.push(e)).unwrap();
        assert_eq!(read, vec![reward(1, 1), read[1].clone(), reward(1, 2)]);
        assert_eq!(reader.counts().received, 3);
        assert_eq!(reader.counts().dropped, 1);
        assert_eq!(reader.counts().rejected.sender, 1);
        let header = FeedHeader {
            version: PROTOCOL_VERSION,
            sender: 0,
            run_id: 7,
            sequence: 1,
        };
        for (header, bytes, why) in [
            (FeedHeader { version: 9, ..header }, &b"{}"[..], Rejection::Version),
            (FeedHeader { run_id: 8, ..header }, &b"{}"[..], Rejection::Run),
            (FeedHeader { sender: 1, ..header }, &b"{}"[..], Rejection::Sender),
            (header, &b"\xff\x00garbage"[..], Rejection::Content),
            (
                header,
                &br#"{"Reward":{"source":{"run":0,"agent":0},"episode":1,"step":1,"reward":null}}"#[..],
                Rejection::Content,
            ),
        ] {
            assert_eq!(check_record(&header, bytes, 0, 7, 0), Err(why));
        }
        // A record as an agent writes it passes, its payload as it was written.
        let record = reward(0, 1);
        let bytes = serde_json::to_vec(&record).unwrap();
        let checked = check_record(&header, &bytes, 0, 7, 0).unwrap();
        assert_eq!(
            (checked.kind, checked.payload),
            (3, &record.payload_json().unwrap()[..])
        );
        assert_eq!(checked.event, record);
        // Well-formed JSON, but not as an agent writes a record.
        for bytes in [
            &br#" {"Reward":{}}"#[..],
            br#"{"Reward":{"source":{"run":0,"agent":0}}}"#,
        ] {
            assert_eq!(check_record(&header, bytes, 0, 7, 0), Err(Rejection::Content));
        }
        drop((agent, reader, view, _services, supervisor));
        owner.release().unwrap();
    }
}
