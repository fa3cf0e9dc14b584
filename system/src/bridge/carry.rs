//! One service carried between hosts: what this host's processes publish on
//! it goes out over Zenoh as the layout's raw bytes, tagged with the type's
//! name and the protocol version; what arrives is checked against that tag
//! and its size and published here, where the receiving process validates
//! it as it validates every message (the bridge trusts nothing it carries).

use std::fmt::Debug;
use std::mem::size_of;

use crossbeam::channel::{Receiver, Sender, unbounded};
use iceoryx2::node::Node;
use iceoryx2::prelude::ZeroCopySend;
use zenoh::pubsub::{Publisher, Subscriber};
use zenoh::sample::Locality;
use zenoh::{Session, Wait};

use super::{BridgeError, zenoh_error};
use crate::ipc::services::{BridgePorts, Ipc, fail};
use crate::ipc::wait::WaitStrategy;

/// Which way a service is carried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// From this host to the others.
    Out,
    /// From the others to this host.
    In,
    /// Both ways (the supervisors' commands).
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

/// What one poll of a carried service moved.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Moved {
    /// Messages sent to the other hosts.
    pub sent: u64,
    /// Messages received and published here.
    pub received: u64,
    /// Messages received and refused (another type, protocol version or size).
    pub refused: u64,
}

impl Moved {
    /// Whether anything moved.
    pub fn any(&self) -> bool {
        self.sent + self.received + self.refused > 0
    }

    /// The sum.
    pub fn plus(self, other: Moved) -> Moved {
        Moved {
            sent: self.sent + other.sent,
            received: self.received + other.received,
            refused: self.refused + other.refused,
        }
    }
}

/// A carried service, whatever its payload.
pub trait Carry {
    /// Moves what is waiting, both ways.
    fn pump(&mut self) -> Result<Moved, BridgeError>;
}

/// One message that arrived: its bytes and its tag.
struct Arrival {
    payload: Vec<u8>,
    tag: Vec<u8>,
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

/// One service of `T`, carried.
pub struct Carrier<T: ZeroCopySend + Debug + Copy + 'static> {
    ports: BridgePorts<T>,
    tag: Vec<u8>,
    publisher: Option<Publisher<'static>>,
    inbox: Option<Receiver<Arrival>>,
    _subscriber: Option<Subscriber<()>>,
}

/// Where and how a service is carried.
#[derive(Debug, Clone)]
pub struct Route {
    /// The service's name.
    pub service: String,
    /// One publisher and one subscriber (a keeper's or agent's own service).
    pub point_to_point: bool,
    /// Which way.
    pub direction: Direction,
    /// The wake-up services of the processes here that receive it.
    pub receivers: Vec<String>,
    /// The run's processes (the service's limits follow from them).
    pub roster: crate::ipc::protocol::Roster,
}

impl<T: ZeroCopySend + Debug + Copy + Send + 'static> Carrier<T> {
    /// Carries `route` of the run whose prefix is `prefix` (the Zenoh keys)
    /// between `node`'s namespace and `session`.
    /// Each arrival rings `doorbell`, to wake the bridge's loop.
    pub fn open(
        node: &Node<Ipc>,
        session: &Session,
        prefix: &str,
        route: &Route,
        wait: WaitStrategy,
        doorbell: &Sender<()>,
    ) -> Result<Self, BridgeError> {
        let ports = BridgePorts::open(
            node,
            &route.service,
            route.point_to_point,
            &route.receivers,
            wait,
            route.roster,
        )?;
        let key = key(prefix, &route.service);
        let publisher = if route.direction.sends() {
            Some(session.declare_publisher(key.clone()).wait().map_err(zenoh_error)?)
        } else {
            None
        };
        let (inbox, subscriber) = if route.direction.receives() {
            let (tx, rx) = unbounded();
            let doorbell = doorbell.clone();
            let subscriber = session
                .declare_subscriber(key)
                .allowed_origin(Locality::Remote)
                .callback(move |sample| {
                    let arrival = Arrival {
                        payload: sample.payload().to_bytes().into_owned(),
                        tag: sample
                            .attachment()
                            .map(|a| a.to_bytes().into_owned())
                            .unwrap_or_default(),
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
        Ok(Carrier {
            ports,
            tag: tag_of::<T>(),
            publisher,
            inbox,
            _subscriber: subscriber,
        })
    }
}

impl<T: ZeroCopySend + Debug + Copy + Send + 'static> Carry for Carrier<T> {
    fn pump(&mut self) -> Result<Moved, BridgeError> {
        let mut moved = Moved::default();
        if let Some(publisher) = &self.publisher {
            while let Some(sample) = self.ports.subscriber.receive().map_err(fail("receiving a sample"))? {
                if self.ports.is_own(sample.origin()) {
                    continue; // it came from the other hosts: not carried back
                }
                let value: &T = &sample;
                // SAFETY: every layout of shm_layouts is repr(C) with explicit
                // reserved fields in place of padding (their tests pin every
                // offset), so all size_of::<T>() bytes are initialised.
                let bytes = unsafe { std::slice::from_raw_parts((value as *const T).cast::<u8>(), size_of::<T>()) };
                publisher
                    .put(bytes.to_vec())
                    .attachment(self.tag.clone())
                    .wait()
                    .map_err(zenoh_error)?;
                moved.sent += 1;
            }
        }
        if let Some(inbox) = &self.inbox {
            while let Ok(arrival) = inbox.try_recv() {
                if arrival.tag != self.tag || arrival.payload.len() != size_of::<T>() {
                    moved.refused += 1;
                    continue;
                }
                // SAFETY: the bytes are size_of::<T>() long, and every bit
                // pattern is a valid value of a shm_layouts type (integers,
                // floats and arrays of them only; tags are integers): the
                // receiving process validates the contents.
                let value: T = unsafe { std::ptr::read_unaligned(arrival.payload.as_ptr().cast::<T>()) };
                self.ports.outlet.send(value)?;
                moved.received += 1;
            }
        }
        Ok(moved)
    }
}
