//! One service carried between hosts: what this host's processes publish on
//! it goes out over Zenoh as the layout's raw bytes, tagged with the type's
//! name and the protocol version; what arrives is checked against that tag,
//! its size, its key's sender and (for the supervisors' orders) what the
//! other host may order, and only then published here, where the receiving
//! process validates it as it validates every message. Whatever fails a
//! check is refused and counted by reason ([`LinkRefusals`](learnpnp_system::hosts::report::LinkRefusals)).
//!
//! A service several processes publish on (heartbeats, agents' reports) is
//! keyed by sender (`.../learnpnp/heartbeat/2`), so that host A's access
//! control can let host B publish its own agents' keys and no other; the
//! supervisors' orders are keyed by host (`.../learnpnp/control/host-b`).

use std::collections::BTreeMap;
use std::fmt::Debug;
use std::mem::size_of;
use std::time::Instant;

use crossbeam::channel::{Receiver, Sender, unbounded};
use iceoryx2::node::Node;
use iceoryx2::prelude::ZeroCopySend;
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Header, Heartbeat, KeeperCommand, KeeperSnapshot, WorldCommand, WorldSnapshot,
    WorldVocabulary, control,
};
use zenoh::pubsub::{Publisher, Subscriber};
use zenoh::qos::{CongestionControl, Priority};
use zenoh::sample::Locality;
use zenoh::{Session, Wait};

use super::agents_lost::{Decision, RemoteAgents, Seen};
use super::{BridgeError, zenoh_error};
use learnpnp_system::hosts::inbound;
use learnpnp_system::hosts::report::LinkRefusals;
use learnpnp_system::ipc::convert::Rejection;
use learnpnp_system::ipc::protocol::Roster;
use learnpnp_system::ipc::services::{BridgePorts, Ipc, fail};
use learnpnp_system::ipc::wait::WaitStrategy;

/// Which way a service is carried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Direction {
    /// From this host to the others.
    Out,
    /// From the others to this host.
    In,
    /// Both ways (heartbeats, the supervisors' orders).
    Both,
}

impl Direction {
    fn sends(self) -> bool {
        matches!(self, Direction::Out | Direction::Both)
    }

    fn receives(self) -> bool {
        matches!(self, Direction::In | Direction::Both)
    }
}

/// How a service's Zenoh keys name who sent a message, and whom a bridge
/// takes messages from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Source {
    /// One key: one publisher (a keeper's snapshots and commands, the episode
    /// events), whose receiver checks the sender.
    Single,
    /// A key per sender (`KEY/SENDER`, the header's sender); what arrives is
    /// taken from the `accepted` senders only (the other hosts' processes),
    /// its header naming the same sender as its key.
    BySender {
        /// The senders whose messages may arrive.
        accepted: Vec<u32>,
    },
    /// A key per host (`KEY/HOST`): this host sends on its own, takes
    /// messages from the other's only.
    ByHost {
        /// This host's name in keys.
        this: &'static str,
        /// The other host's.
        other: &'static str,
    },
}

/// What the other host may order this one's processes (host A's bridge,
/// about host B's supervisor): that one of its own agents was lost and
/// restarted, and that the run stop (host B was stopped).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RemoteOrders {
    /// The other host's agents (0-based): `KEEPER_LOST` may name them only.
    pub agents: Vec<u32>,
    /// The sender of this host's simulator or world: `STOP` may go to it only.
    pub host: u32,
}

impl RemoteOrders {
    /// Whether `command` for `target` may come from the other host.
    fn admits(&self, command: u32, target: u32) -> bool {
        match command {
            control::KEEPER_LOST => self.agents.contains(&target),
            control::STOP => target == self.host,
            _ => false,
        }
    }
}

/// What one poll of a carried service moved.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Moved {
    /// Messages sent to the other hosts.
    pub sent: u64,
    /// Messages received and published here.
    pub received: u64,
    /// Orders to stop the run received from the other host (and passed on).
    pub(crate) stop_requests: u64,
    /// Messages received and refused, by reason.
    pub refused: LinkRefusals,
    /// Messages of the other host's that never arrived (gaps in a key's sequence numbers).
    pub lost: u64,
}

impl Moved {
    /// Whether anything moved.
    pub(crate) fn any(&self) -> bool {
        self.sent + self.received + self.refused.total() + self.lost > 0
    }

    /// The sum.
    pub(crate) fn plus(self, other: Moved) -> Moved {
        Moved {
            sent: self.sent + other.sent,
            received: self.received + other.received,
            stop_requests: self.stop_requests + other.stop_requests,
            refused: self.refused.plus(&other.refused),
            lost: self.lost + other.lost,
        }
    }

    /// Counts a message refused for `why`, as the receiving process would have.
    fn refuse(&mut self, why: Rejection) {
        let refused = &mut self.refused;
        match why {
            Rejection::Version => refused.wrong_type += 1,
            Rejection::Run => refused.wrong_run += 1,
            Rejection::Sender => refused.wrong_sender += 1,
            Rejection::Content | Rejection::Sequence => refused.bad_content += 1,
        }
    }
}

/// A carried service, whatever its payload.
pub(crate) trait Carry {
    /// Moves what is waiting, both ways; what arrives from host B's agents
    /// goes into `agents` (host A weighs host B's reports of lost agents by it).
    fn pump(&mut self, agents: &mut RemoteAgents) -> Result<Moved, BridgeError>;
}

/// What a route's messages from the other host must hold beyond their type and size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Expected {
    /// The run's id.
    pub run_id: u64,
    /// The run's processes.
    pub roster: Roster,
    /// The agent whose service it is (a keeper's commands), if one's.
    pub agent: Option<usize>,
}

/// A layout the bridge carries: every one begins with a [`Header`].
pub(crate) trait Carried: ZeroCopySend + Debug + Copy + Send + 'static {
    /// The message's header.
    fn header(&self) -> &Header;

    /// A supervisor's order: its command and target.
    fn order(&self) -> Option<(u32, u32)> {
        None
    }

    /// The process id an order names (`KEEPER_LOST`: the replacement's).
    fn pid_named(&self) -> u32 {
        0
    }

    /// Checks what the receiving process would refuse in a message from
    /// the other host (the messages host B sends host A; the others are
    /// checked by their receivers only), and what it shows of an agent.
    fn check(&self, _expected: &Expected) -> Result<Seen, Rejection> {
        Ok(Seen::Nothing)
    }
}

impl Carried for KeeperCommand {
    fn header(&self) -> &Header {
        &self.header
    }

    fn check(&self, expected: &Expected) -> Result<Seen, Rejection> {
        let keeper = expected.agent.ok_or(Rejection::Sender)?;
        inbound::keeper_command(self, keeper, expected.run_id).map(|()| Seen::Nothing)
    }
}

impl Carried for WorldCommand {
    fn header(&self) -> &Header {
        &self.header
    }

    fn check(&self, expected: &Expected) -> Result<Seen, Rejection> {
        let agent = expected.agent.ok_or(Rejection::Sender)?;
        inbound::world_command(self, agent, expected.run_id).map(|()| Seen::Nothing)
    }
}

impl Carried for AgentReport {
    fn header(&self) -> &Header {
        &self.header
    }

    fn check(&self, expected: &Expected) -> Result<Seen, Rejection> {
        Ok(match inbound::agent_report(self, expected.run_id, expected.roster)? {
            (agent, Some(pid)) => Seen::Ready { agent, pid },
            (_, None) => Seen::Nothing,
        })
    }
}

impl Carried for Heartbeat {
    fn header(&self) -> &Header {
        &self.header
    }

    fn check(&self, expected: &Expected) -> Result<Seen, Rejection> {
        let (role, pid) = inbound::heartbeat(self, expected.run_id, expected.roster)?;
        Ok(role
            .agent_index()
            .map_or(Seen::Nothing, |agent| Seen::Beat { agent, pid }))
    }
}

/// Implements [`Carried`] for the layouts that are only a header and a body,
/// checked by their receivers only, and defines [`Payload`], one variant per
/// carried layout (those, and those with checks of their own), with the
/// opening of a carrier of each.
macro_rules! carried {
    ($($t:ident),*; $($checked:ident),*) => {
        $(impl Carried for $t {
            fn header(&self) -> &Header {
                &self.header
            }
        })*

        /// The payload type of a carried service.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub(crate) enum Payload {
            $($t,)*
            $($checked,)*
        }

        impl Payload {
            /// How a carrier of this payload is opened.
            pub(crate) fn opener(self) -> Opener {
                match self {
                    $(Payload::$t => Carrier::<$t>::open,)*
                    $(Payload::$checked => Carrier::<$checked>::open,)*
                }
            }
        }
    };
}

carried!(
    KeeperSnapshot,
    EpisodeEvent,
    WorldSnapshot,
    WorldVocabulary;
    KeeperCommand,
    WorldCommand,
    AgentReport,
    Heartbeat,
    Control
);

/// Opens the carrier of a route for one payload (see [`Payload::opener`]).
pub(crate) type Opener =
    fn(&Node<Ipc>, &Session, &str, &Route, WaitStrategy, &Sender<()>) -> Result<Box<dyn Carry>, BridgeError>;

impl Carried for Control {
    fn header(&self) -> &Header {
        &self.header
    }

    fn order(&self) -> Option<(u32, u32)> {
        Some((self.command, self.target))
    }

    fn pid_named(&self) -> u32 {
        self.pid
    }

    fn check(&self, expected: &Expected) -> Result<Seen, Rejection> {
        inbound::control(self, expected.run_id).map(|()| Seen::Nothing)
    }
}

/// One message that arrived: its bytes, its tag and its key's last chunk.
struct Arrival {
    payload: Vec<u8>,
    tag: Vec<u8>,
    last_chunk: String,
}

/// The Zenoh key of service `service` of the run whose prefix is `prefix`.
pub fn key(prefix: &str, service: &str) -> String {
    format!("learnpnp/{}/{service}", prefix.trim_end_matches('_'))
}

/// The tag a message of `T` carries: its type name and the protocol version.
fn tag_of<T: ZeroCopySend>() -> Vec<u8> {
    // SAFETY: type_name only reads the derive's constant.
    let name = unsafe { <T as ZeroCopySend>::type_name() };
    format!("{name};{}", shm_layouts::PROTOCOL_VERSION).into_bytes()
}

/// Where and how a service is carried.
#[derive(Debug, Clone)]
pub(crate) struct Route {
    /// The service's name.
    pub service: String,
    /// One publisher and one subscriber (a keeper's or agent's own service).
    pub(crate) point_to_point: bool,
    /// Which way.
    pub(crate) direction: Direction,
    /// How keys name senders, and whose messages are taken.
    pub(crate) source: Source,
    /// The orders the other host may give (the supervisors' orders, on host A).
    pub(crate) orders: Option<RemoteOrders>,
    /// The wake-up services of the processes here that receive it.
    pub(crate) receivers: Vec<String>,
    /// What its messages from the other host must hold (the roster also
    /// sets the service's limits).
    pub(crate) expected: Expected,
    /// How what this host sends on it meets a congested link (see [`Sending`]).
    pub(crate) sending: Sending,
}

/// How a route's messages are put on the link. Host A's bridge is the
/// link's router: what it sends (and what host B sends that the router may
/// pass to other subscribers, the heartbeats) is fanned out to every
/// subscriber the access control admits, so a subscriber that stops reading
/// must lose its own messages rather than block the router: such routes
/// are droppable (Zenoh's congestion control `drop`, per destination queue,
/// after [`WAIT_BEFORE_DROP`]); a loss on the real host's queue shows as a
/// gap in the sequence numbers its bridge counts. What only host A's bridge
/// receives (host B's commands, reports, orders and files) blocks instead:
/// nothing of it may be lost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sending {
    /// Never dropped: the caller waits for room on the link.
    Blocking,
    /// Dropped for a destination whose queue stays full.
    Droppable,
    /// Droppable, on the lowest data priority (heartbeats: their queue
    /// never holds up the lock-step's messages).
    Background,
}

/// How long a droppable message waits for room in a destination's queue
/// before it is dropped for that destination (microseconds, Zenoh's
/// `wait_before_drop`); later ones are dropped at once until the queue
/// drains.
pub(crate) const WAIT_BEFORE_DROP: &str = "10000";

/// One service of `T`, carried.
pub(crate) struct Carrier<T: Carried> {
    ports: BridgePorts<T>,
    tag: Vec<u8>,
    base: String,
    source: Source,
    orders: Option<RemoteOrders>,
    expected: Expected,
    sending: Sending,
    /// The publishers, by the last chunk of their key ("" for [`Source::Single`]),
    /// with the sequence number of the last message each sent.
    publishers: BTreeMap<String, (Publisher<'static>, u64)>,
    /// The sequence number each key of the other host's is expected to send next.
    next_seq: BTreeMap<String, u64>,
    /// Orders held until host A's view agrees (`KEEPER_LOST` from host B).
    held: Vec<T>,
    sends: bool,
    session: Session,
    inbox: Option<Receiver<Arrival>>,
    _subscriber: Option<Subscriber<()>>,
}

impl<T: Carried> Carrier<T> {
    /// Carries `route` of the run whose prefix is `prefix` (the Zenoh keys)
    /// between `node`'s namespace and `session`.
    /// Each arrival rings `doorbell`, to wake the bridge's loop. Boxed: the
    /// loop holds the carriers of every payload alike.
    pub(crate) fn open(
        node: &Node<Ipc>,
        session: &Session,
        prefix: &str,
        route: &Route,
        wait: WaitStrategy,
        doorbell: &Sender<()>,
    ) -> Result<Box<dyn Carry>, BridgeError> {
        let ports = BridgePorts::open(
            node,
            &route.service,
            route.point_to_point,
            &route.receivers,
            wait,
            route.expected.roster,
        )?;
        let base = key(prefix, &route.service);
        let (inbox, subscriber) = if route.direction.receives() {
            let listen_on = match &route.source {
                Source::Single => base.clone(),
                Source::BySender { .. } => format!("{base}/*"),
                Source::ByHost { other, .. } => format!("{base}/{other}"),
            };
            let (tx, rx) = unbounded();
            let doorbell = doorbell.clone();
            let subscriber = session
                .declare_subscriber(listen_on)
                .allowed_origin(Locality::Remote)
                .callback(move |sample| {
                    let key = sample.key_expr().as_str();
                    let arrival = Arrival {
                        payload: sample.payload().to_bytes().into_owned(),
                        tag: sample
                            .attachment()
                            .map(|a| a.to_bytes().into_owned())
                            .unwrap_or_default(),
                        last_chunk: key.rsplit('/').next().unwrap_or_default().to_string(),
                    };
                    // The bridge is gone when the channel is: nothing to deliver to.
                    let _ = tx.send(arrival);
                    let _ = doorbell.send(());
                })
                .wait()
                .map_err(zenoh_error)?;
            (Some(rx), Some(subscriber))
        } else {
            (None, None)
        };
        Ok(Box::new(Carrier::<T> {
            ports,
            tag: tag_of::<T>(),
            base,
            source: route.source.clone(),
            orders: route.orders.clone(),
            expected: route.expected,
            sending: route.sending,
            publishers: BTreeMap::new(),
            next_seq: BTreeMap::new(),
            held: Vec::new(),
            sends: route.direction.sends(),
            session: session.clone(),
            inbox,
            _subscriber: subscriber,
        }))
    }

    /// The publisher for `value`'s key, declared on first use, and the
    /// sequence number of its next message.
    fn publisher(&mut self, value: &T) -> Result<(&Publisher<'static>, u64), BridgeError> {
        let chunk = match &self.source {
            Source::Single => String::new(),
            Source::BySender { .. } => value.header().sender.to_string(),
            Source::ByHost { this, .. } => (*this).to_string(),
        };
        if !self.publishers.contains_key(&chunk) {
            let key = if chunk.is_empty() {
                self.base.clone()
            } else {
                format!("{}/{chunk}", self.base)
            };
            let (congestion, priority) = match self.sending {
                Sending::Blocking => (CongestionControl::Block, Priority::Data),
                Sending::Droppable => (CongestionControl::Drop, Priority::Data),
                Sending::Background => (CongestionControl::Drop, Priority::DataLow),
            };
            let publisher = self
                .session
                .declare_publisher(key)
                .express(true)
                .congestion_control(congestion)
                .priority(priority)
                .wait()
                .map_err(zenoh_error)?;
            self.publishers.insert(chunk.clone(), (publisher, 0));
        }
        let (publisher, seq) = self
            .publishers
            .get_mut(&chunk)
            .ok_or_else(|| zenoh_error("no publisher"))?;
        *seq += 1;
        Ok((publisher, *seq))
    }

    /// Checks what arrived; the message if it may be published here.
    fn admit(&mut self, arrival: &Arrival, moved: &mut Moved, agents: &mut RemoteAgents) -> Option<T> {
        let seq = match split_tag(&arrival.tag, &self.tag) {
            Some(seq) => seq,
            None => {
                moved.refused.wrong_type += 1;
                return None;
            }
        };
        if arrival.payload.len() != size_of::<T>() {
            moved.refused.wrong_size += 1;
            return None;
        }
        if let Some(seq) = seq {
            moved.lost += gap(&mut self.next_seq, &arrival.last_chunk, seq);
        }
        // SAFETY: the bytes are size_of::<T>() long, and every bit pattern
        // is a valid value of a shm_layouts type (integers, floats and arrays
        // of them only; tags are integers): the receiving process validates
        // the contents.
        let value: T = unsafe { std::ptr::read_unaligned(arrival.payload.as_ptr().cast::<T>()) };
        if let Source::BySender { accepted } = &self.source {
            let Some(sender) = arrival.last_chunk.parse::<u32>().ok().filter(|s| accepted.contains(s)) else {
                moved.refused.wrong_key += 1;
                return None;
            };
            if value.header().sender != sender {
                moved.refused.wrong_sender += 1;
                return None;
            }
        }
        let seen = match value.check(&self.expected) {
            Ok(seen) => seen,
            Err(why) => {
                moved.refuse(why);
                return None;
            }
        };
        agents.see(seen, Instant::now());
        if let (Some(orders), Some((command, target))) = (&self.orders, value.order()) {
            if !orders.admits(command, target) {
                moved.refused.forbidden_order += 1;
                return None;
            }
            if command == control::STOP {
                moved.stop_requests += 1;
            }
            if command == control::KEEPER_LOST {
                // Host A's own view must agree first (see agents_lost).
                agents.hold(target as usize, value.pid_named(), Instant::now());
                self.held.push(value);
                return None;
            }
        }
        Some(value)
    }

    /// Publishes the held orders host A's view now agrees with; counts
    /// those it refuses.
    fn release(&mut self, agents: &mut RemoteAgents, moved: &mut Moved) -> Result<(), BridgeError> {
        for (agent, pid, decision) in agents.decide(Instant::now()) {
            let Some(i) = self
                .held
                .iter()
                .position(|v| v.order().map(|(_, t)| t as usize) == Some(agent) && v.pid_named() == pid)
            else {
                continue;
            };
            let value = self.held.remove(i);
            match decision {
                Decision::Pass => {
                    eprintln!(
                        "bridge: host B reported agent {} lost, replaced by process {pid}: passed on",
                        agent + 1
                    );
                    self.ports.outlet.send(value)?;
                    moved.received += 1;
                }
                Decision::Refuse => {
                    eprintln!(
                        "bridge: refused host B's report that agent {} was lost (process {pid})",
                        agent + 1
                    );
                    moved.refused.forbidden_order += 1;
                }
            }
        }
        Ok(())
    }
}

/// The messages of key `chunk` that never came before the one numbered
/// `seq` (a gap in its sequence numbers; a lower number than expected is the
/// other bridge restarted, counting from 1 again); `next` holds the number
/// each key is expected to send next.
fn gap(next: &mut BTreeMap<String, u64>, chunk: &str, seq: u64) -> u64 {
    let expected = next.entry(chunk.to_string()).or_insert(seq);
    let lost = seq.saturating_sub(*expected);
    *expected = seq + 1;
    lost
}

/// The sequence number in an arrival's tag (`TYPE;VERSION;SEQ`): `None`
/// for an unknown type or version, `Some(None)` for a tag without one.
fn split_tag(arrival: &[u8], tag: &[u8]) -> Option<Option<u64>> {
    if arrival == tag {
        return Some(None);
    }
    let rest = arrival.strip_prefix(tag)?.strip_prefix(b";")?;
    let seq = std::str::from_utf8(rest).ok()?.parse::<u64>().ok()?;
    Some(Some(seq))
}

impl<T: Carried> Carry for Carrier<T> {
    fn pump(&mut self, agents: &mut RemoteAgents) -> Result<Moved, BridgeError> {
        let mut moved = Moved::default();
        if self.sends {
            while let Some(sample) = self.ports.subscriber.receive().map_err(fail("receiving a sample"))? {
                if self.ports.is_own(sample.origin()) {
                    continue; // it came from the other hosts: not carried back
                }
                let value: T = *sample;
                drop(sample);
                // SAFETY: every layout of shm_layouts is repr(C) with explicit
                // reserved fields in place of padding (their tests pin every
                // offset), so all size_of::<T>() bytes are initialised.
                let bytes = unsafe { std::slice::from_raw_parts((&value as *const T).cast::<u8>(), size_of::<T>()) };
                let mut tag = self.tag.clone();
                let (publisher, seq) = self.publisher(&value)?;
                tag.extend_from_slice(format!(";{seq}").as_bytes());
                publisher
                    .put(bytes.to_vec())
                    .attachment(tag)
                    .wait()
                    .map_err(zenoh_error)?;
                moved.sent += 1;
            }
        }
        if let Some(inbox) = &self.inbox {
            let arrivals: Vec<Arrival> = inbox.try_iter().collect();
            for arrival in arrivals {
                if let Some(value) = self.admit(&arrival, &mut moved, agents) {
                    self.ports.outlet.send(value)?;
                    moved.received += 1;
                }
            }
        }
        if !self.held.is_empty() {
            self.release(agents, &mut moved)?;
        }
        Ok(moved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tag_is_the_type_and_version_with_a_sequence_number_or_without() {
        let tag = b"learnpnp::Heartbeat;1";
        assert_eq!(split_tag(b"learnpnp::Heartbeat;1", tag), Some(None));
        assert_eq!(split_tag(b"learnpnp::Heartbeat;1;42", tag), Some(Some(42)));
        for other in [
            &b"learnpnp::Heartbeat;2;42"[..],
            b"learnpnp::Control;1;42",
            b"learnpnp::Heartbeat;1;",
            b"learnpnp::Heartbeat;1;x",
            b"learnpnp::Heartbeat;1;-1",
            b"",
        ] {
            assert_eq!(split_tag(other, tag), None, "{}", String::from_utf8_lossy(other));
        }
    }

    #[test]
    fn gaps_in_a_keys_sequence_numbers_are_messages_lost() {
        let mut next = BTreeMap::new();
        assert_eq!(gap(&mut next, "2", 5), 0, "the first number heard starts the count");
        assert_eq!(gap(&mut next, "2", 6), 0);
        assert_eq!(gap(&mut next, "2", 9), 2, "7 and 8 never came");
        assert_eq!(gap(&mut next, "0", 1), 0, "each key counts for itself");
        assert_eq!(gap(&mut next, "2", 1), 0, "a restarted bridge counts from 1 again");
        assert_eq!(gap(&mut next, "2", 3), 1);
    }

    #[test]
    fn host_b_may_order_its_own_agents_lost_and_the_run_stopped_only() {
        let orders = RemoteOrders {
            agents: vec![2],
            host: shm_layouts::SENDER_SIMULATOR,
        };
        assert!(orders.admits(control::KEEPER_LOST, 2));
        assert!(!orders.admits(control::KEEPER_LOST, 0), "another host's keeper");
        assert!(orders.admits(control::STOP, shm_layouts::SENDER_SIMULATOR));
        assert!(!orders.admits(control::STOP, control::ALL), "every process");
        assert!(!orders.admits(control::STOP, 0), "a keeper of host A");
        assert!(!orders.admits(control::CHECKPOINT, 2));
        assert!(!orders.admits(control::SIM_RESTARTED, control::ALL));
    }
}
