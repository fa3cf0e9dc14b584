//! A ROS 2 node on a Zenoh session, as rmw_zenoh makes one (design.md,
//! "Nodes", "Publishers", "Subscriptions", "Service Clients"): a liveliness
//! token per entity, publications and requests under the data key with the
//! attachment, service calls as queries to a complete queryable.

use std::sync::Arc;
use std::sync::atomic::{AtomicI64, AtomicU64, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use learnpnp_system::multiprocess::host::world::Housekeeping;
use thiserror::Error;
use zenoh::Session;
use zenoh::Wait;
use zenoh::bytes::Encoding;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::{Publisher as ZPublisher, Subscriber};
use zenoh::query::QueryTarget;

use crate::keys::{Attachment, AttachmentError, Entity, EntityKind, Qos, gid_of, topic_key};
use crate::types::{Registry, TypeError, Value, dds_name};

/// A failure of the ROS 2 side.
#[derive(Debug, Error)]
pub enum Ros2Error {
    /// Zenoh refused an operation.
    #[error("zenoh: {0}")]
    Zenoh(String),
    /// A type or value error.
    #[error(transparent)]
    Type(#[from] TypeError),
    /// A service gave no reply in time.
    #[error("service '{service}' gave no reply within {ms} ms (is the robot's node running?)")]
    NoReply {
        /// The service.
        service: String,
        /// The wait.
        ms: u128,
    },
    /// A call given up before its reply or timeout: the run stops.
    #[error("service '{service}': the call was given up (the run stops)")]
    GivenUp {
        /// The service.
        service: String,
    },
    /// A reply refused (see [`Refusal`]).
    #[error("service '{service}': {refusal}")]
    Refused {
        /// The service.
        service: String,
        /// Why.
        refusal: Box<Refusal>,
    },
}

fn zenoh_error(e: impl std::fmt::Display) -> Ros2Error {
    Ros2Error::Zenoh(e.to_string())
}

/// Something a peer sent that is refused (counted, and the run goes on).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Refusal {
    /// A payload that does not decode as its type's CDR.
    #[error("malformed CDR on '{key}': {error}")]
    MalformedCdr {
        /// The key it came on.
        key: String,
        /// The decoding error.
        error: TypeError,
    },
    /// A message on the topic with another type name or type hash.
    #[error("wrong type on '{key}': expected {expected}")]
    WrongType {
        /// The key it came on.
        key: String,
        /// `<DDS type>/<hash>` expected.
        expected: String,
    },
    /// A missing or malformed attachment.
    #[error("bad attachment on '{key}': {error}")]
    BadAttachment {
        /// The key it came on.
        key: String,
        /// Why.
        error: String,
    },
}

/// A message as received.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Received {
    /// The decoded message.
    pub value: Value,
    /// Its attachment.
    pub(crate) attachment: Attachment,
}

/// Now in ns since the UNIX epoch.
pub(crate) fn now_ns() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
        .unwrap_or(0)
}

/// A ROS 2 node: its session, its name and its liveliness token.
pub struct Node {
    session: Session,
    registry: Arc<Registry>,
    domain: u32,
    zid: String,
    namespace: String,
    name: String,
    next_id: AtomicU64,
    _token: LivelinessToken,
}

/// Node ids start at 0 in a session (one node per session here); entity ids
/// follow (rmw_zenoh counts both in its context).
const NODE_ID: u64 = 0;

impl Node {
    /// Declares the node `name` in `namespace` on `session` (its `NN` token).
    pub fn new(
        session: Session,
        registry: Arc<Registry>,
        domain: u32,
        namespace: &str,
        name: &str,
    ) -> Result<Self, Ros2Error> {
        let zid = session.zid().to_string();
        let token = Entity {
            domain,
            zid: &zid,
            node_id: NODE_ID,
            id: NODE_ID,
            kind: EntityKind::Node,
            enclave: "",
            namespace,
            node: name,
            topic: None,
        }
        .token();
        let token = session.liveliness().declare_token(token).wait().map_err(zenoh_error)?;
        Ok(Node {
            session,
            registry,
            domain,
            zid,
            namespace: namespace.to_string(),
            name: name.to_string(),
            next_id: AtomicU64::new(NODE_ID + 1),
            _token: token,
        })
    }

    /// The types this node knows.
    pub fn registry(&self) -> &Arc<Registry> {
        &self.registry
    }

    /// The session.
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// A fully qualified name: relative names are put in the node's namespace.
    pub(crate) fn qualify(&self, name: &str) -> String {
        if name.starts_with('/') {
            name.to_string()
        } else if self.namespace == "/" {
            format!("/{name}")
        } else {
            format!("{}/{name}", self.namespace)
        }
    }

    /// The data key of `name` with type `type_name` and the entity's token.
    fn entity(&self, kind: EntityKind, name: &str, type_name: &str) -> Result<(String, String, String), Ros2Error> {
        let dds = dds_name(type_name)?;
        let hash = self.registry.type_hash(type_name)?;
        let fq = self.qualify(name);
        let token = Entity {
            domain: self.domain,
            zid: &self.zid,
            node_id: NODE_ID,
            id: self.next_id.fetch_add(1, Ordering::Relaxed),
            kind,
            enclave: "",
            namespace: &self.namespace,
            node: &self.name,
            topic: Some((&fq, &dds, &hash, Qos::keep_last(10))),
        }
        .token();
        Ok((topic_key(self.domain, &fq, &dds, &hash), format!("{dds}/{hash}"), token))
    }

    /// Declares an entity's liveliness token (rmw_zenoh's graph cache reads
    /// it), kept as long as the returned token lives.
    fn announce(&self, token: String) -> Result<zenoh::liveliness::LivelinessToken, Ros2Error> {
        self.session
            .liveliness()
            .declare_token(token)
            .wait()
            .map_err(zenoh_error)
    }

    /// A publisher of `type_name` messages on `topic` (its `MP` token).
    pub(crate) fn publisher(&self, topic: &str, type_name: &str) -> Result<Publisher, Ros2Error> {
        let (key, _, token) = self.entity(EntityKind::Publisher, topic, type_name)?;
        let gid = gid_of(&token);
        let token = self.announce(token)?;
        let publisher = self
            .session
            .declare_publisher(key)
            .encoding(Encoding::APPLICATION_CDR)
            .wait()
            .map_err(zenoh_error)?;
        Ok(Publisher {
            publisher,
            registry: Arc::clone(&self.registry),
            type_name: type_name.to_string(),
            sequence: AtomicI64::new(1),
            gid,
            _token: token,
        })
    }

    /// Subscribes to `topic` for `type_name` messages (its `MS` token). The
    /// subscriber listens to every type on the topic so that a message of
    /// another type or type hash is refused, not silently missed.
    pub(crate) fn subscribe<F>(&self, topic: &str, type_name: &str, on: F) -> Result<Subscription, Ros2Error>
    where
        F: Fn(Result<Received, Refusal>) + Send + Sync + 'static,
    {
        let (key, expected, token) = self.entity(EntityKind::Subscription, topic, type_name)?;
        let prefix = key.strip_suffix(&expected).unwrap_or(&key).to_string();
        let registry = Arc::clone(&self.registry);
        let type_name = type_name.to_string();
        let subscriber = self
            .session
            .declare_subscriber(format!("{prefix}*/*"))
            .callback(move |sample| {
                let key = sample.key_expr().as_str();
                let got = key.strip_prefix(prefix.as_str()).unwrap_or(key);
                let result = if got != expected {
                    Err(Refusal::WrongType {
                        key: key.to_string(),
                        expected: expected.clone(),
                    })
                } else {
                    decode(
                        &registry,
                        &type_name,
                        key,
                        &sample.payload().to_bytes(),
                        sample.attachment().map(|a| a.to_bytes()),
                    )
                };
                on(result);
            })
            .wait()
            .map_err(zenoh_error)?;
        // The token once the subscriber is there: a peer that sees it can publish to it.
        let token = self.announce(token)?;
        Ok(Subscription {
            _subscriber: subscriber,
            _token: token,
        })
    }

    /// A client of the service `service` of type `srv_type` (its `SC` token).
    pub(crate) fn client(&self, service: &str, srv_type: &str) -> Result<Client, Ros2Error> {
        let (key, _, token) = self.entity(EntityKind::ServiceClient, service, srv_type)?;
        let (request, response) = self.registry.service(srv_type)?;
        let (request, response) = (request.to_string(), response.to_string());
        let gid = gid_of(&token);
        let token = self.announce(token)?;
        Ok(Client {
            session: self.session.clone(),
            registry: Arc::clone(&self.registry),
            service: self.qualify(service),
            key,
            request,
            response,
            sequence: AtomicI64::new(1),
            gid,
            _token: token,
        })
    }
}

impl Node {
    /// Serves the service `service` of type `srv_type` (its `SS` token and a
    /// complete queryable, design.md "Service Servers"): `handler` answers
    /// each request; the reply's attachment carries the request's sequence
    /// number and GID with a new time. A request that does not decode, or
    /// has no attachment, is answered with an error and passed to `refused`.
    pub fn serve<H, R>(&self, service: &str, srv_type: &str, handler: H, refused: R) -> Result<Server, Ros2Error>
    where
        H: Fn(Value) -> Value + Send + Sync + 'static,
        R: Fn(Refusal) + Send + Sync + 'static,
    {
        let (key, _, token) = self.entity(EntityKind::ServiceServer, service, srv_type)?;
        let (request, response) = self.registry.service(srv_type)?;
        let (request, response) = (request.to_string(), response.to_string());
        let registry = Arc::clone(&self.registry);
        let reply_key = key.clone();
        let queryable = self
            .session
            .declare_queryable(key)
            .complete(true)
            .callback(move |query| {
                let payload = query.payload().map(|p| p.to_bytes().to_vec()).unwrap_or_default();
                let got = decode(
                    &registry,
                    &request,
                    &reply_key,
                    &payload,
                    query.attachment().map(|a| a.to_bytes()),
                );
                let answer = got.and_then(|got| {
                    let value = handler(got.value);
                    registry
                        .encode(&response, &value)
                        .map(|bytes| (bytes, got.attachment))
                        .map_err(|error| Refusal::MalformedCdr {
                            key: reply_key.clone(),
                            error,
                        })
                });
                match answer {
                    Ok((bytes, attachment)) => {
                        let attachment = Attachment {
                            timestamp_ns: now_ns(),
                            ..attachment
                        };
                        let _ = query
                            .reply(reply_key.clone(), bytes)
                            .encoding(Encoding::APPLICATION_CDR)
                            .attachment(attachment.to_bytes())
                            .wait();
                    }
                    Err(refusal) => {
                        let _ = query.reply_err(refusal.to_string()).wait();
                        refused(refusal);
                    }
                }
            })
            .wait()
            .map_err(zenoh_error)?;
        // The token once the queryable is there: a client that sees it can call.
        let token = self.announce(token)?;
        Ok(Server {
            _queryable: queryable,
            _token: token,
        })
    }
}

/// A service server and its token (dropping it undeclares both).
pub struct Server {
    _queryable: zenoh::query::Queryable<()>,
    _token: LivelinessToken,
}

/// Decodes a payload with its attachment.
fn decode(
    registry: &Registry,
    type_name: &str,
    key: &str,
    payload: &[u8],
    attachment: Option<std::borrow::Cow<'_, [u8]>>,
) -> Result<Received, Refusal> {
    let attachment = match attachment {
        None => Err(AttachmentError::Length(0)),
        Some(a) => Attachment::from_bytes(&a),
    }
    .map_err(|e| Refusal::BadAttachment {
        key: key.to_string(),
        error: e.to_string(),
    })?;
    let value = registry
        .decode(type_name, payload)
        .map_err(|error| Refusal::MalformedCdr {
            key: key.to_string(),
            error,
        })?;
    Ok(Received { value, attachment })
}

/// A publisher and its token.
pub(crate) struct Publisher {
    publisher: ZPublisher<'static>,
    registry: Arc<Registry>,
    type_name: String,
    sequence: AtomicI64,
    gid: [u8; 16],
    _token: LivelinessToken,
}

impl Publisher {
    /// Publishes `value` with the attachment.
    pub fn publish(&self, value: &Value) -> Result<(), Ros2Error> {
        let payload = self.registry.encode(&self.type_name, value)?;
        let attachment = Attachment {
            sequence: self.sequence.fetch_add(1, Ordering::Relaxed),
            timestamp_ns: now_ns(),
            gid: self.gid,
        };
        self.publisher
            .put(payload)
            .attachment(attachment.to_bytes())
            .wait()
            .map_err(zenoh_error)
    }
}

/// A subscription and its token (dropping it undeclares both).
pub(crate) struct Subscription {
    _subscriber: Subscriber<()>,
    _token: LivelinessToken,
}

/// A service client and its token.
pub(crate) struct Client {
    session: Session,
    registry: Arc<Registry>,
    service: String,
    key: String,
    request: String,
    response: String,
    sequence: AtomicI64,
    gid: [u8; 16],
    _token: LivelinessToken,
}

impl Client {
    /// Calls the service with `request`; the first reply within `timeout`.
    /// A reply that does not decode, or whose attachment does not carry this
    /// request's sequence number, is refused. The host's house is kept
    /// while the reply is awaited; the call is given up if the run stops.
    pub(crate) fn call(
        &self,
        request: &Value,
        timeout: Duration,
        house: &mut Housekeeping<'_>,
    ) -> Result<Value, Ros2Error> {
        let payload = self.registry.encode(&self.request, request)?;
        let sequence = self.sequence.fetch_add(1, Ordering::Relaxed);
        let attachment = Attachment {
            sequence,
            timestamp_ns: now_ns(),
            gid: self.gid,
        };
        // design.md, "Service Clients": target ALL_COMPLETE.
        let replies = self
            .session
            .get(self.key.as_str())
            .payload(payload)
            .encoding(Encoding::APPLICATION_CDR)
            .attachment(attachment.to_bytes())
            .target(QueryTarget::AllComplete)
            .timeout(timeout)
            .wait()
            .map_err(zenoh_error)?;
        let refused = |refusal| Ros2Error::Refused {
            service: self.service.clone(),
            refusal: Box::new(refusal),
        };
        loop {
            if !house.keep() {
                return Err(Ros2Error::GivenUp {
                    service: self.service.clone(),
                });
            }
            // The query's timeout closes the channel: Err once it has.
            let reply = match replies.recv_timeout(Housekeeping::EVERY) {
                Ok(Some(reply)) => reply,
                Ok(None) => continue,
                Err(_) => break,
            };
            let Ok(sample) = reply.result() else { continue };
            let key = sample.key_expr().as_str().to_string();
            let got = decode(
                &self.registry,
                &self.response,
                &key,
                &sample.payload().to_bytes(),
                sample.attachment().map(|a| a.to_bytes()),
            )
            .map_err(refused)?;
            if got.attachment.sequence != sequence {
                return Err(refused(Refusal::BadAttachment {
                    key,
                    error: format!(
                        "the reply carries sequence {} for request {sequence}",
                        got.attachment.sequence
                    ),
                }));
            }
            return Ok(got.value);
        }
        Err(Ros2Error::NoReply {
            service: self.service.clone(),
            ms: timeout.as_millis(),
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use std::sync::atomic::AtomicUsize;
    use std::sync::{Mutex, mpsc};

    use zenoh::Config;

    use super::*;

    /// A Zenoh config that contacts nothing but 127.0.0.1: peer mode,
    /// multicast scouting and gossip off, explicit endpoints.
    pub(crate) fn loopback(listen: Option<u16>, connect: Option<u16>) -> Config {
        let mut c = Config::default();
        let set = |c: &mut Config, k: &str, v: String| c.insert_json5(k, &v).unwrap();
        set(&mut c, "mode", "\"peer\"".into());
        set(&mut c, "scouting/multicast/enabled", "false".into());
        set(&mut c, "scouting/gossip/enabled", "false".into());
        let eps = |p: Option<u16>| match p {
            Some(p) => format!("[\"tcp/127.0.0.1:{p}\"]"),
            None => "[]".into(),
        };
        set(&mut c, "listen/endpoints", eps(listen));
        set(&mut c, "connect/endpoints", eps(connect));
        c
    }

    /// Two sessions linked on a free 127.0.0.1 port.
    pub(crate) fn loopback_pair() -> (Session, Session) {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let a = zenoh::open(loopback(Some(port), None)).wait().unwrap();
        let b = zenoh::open(loopback(None, Some(port))).wait().unwrap();
        (a, b)
    }

    #[test]
    fn subscriptions_refuse_wrong_types_malformed_cdr_and_missing_attachments() {
        let (a, b) = loopback_pair();
        let registry = Arc::new(Registry::new());
        let node = Node::new(a, Arc::clone(&registry), 0, "/", "world").unwrap();
        let (tx, rx) = mpsc::channel();
        let tx = Mutex::new(tx);
        let _sub = node
            .subscribe("/flag", "std_msgs/msg/Bool", move |r| {
                let _ = tx.lock().unwrap().send(r);
            })
            .unwrap();
        let talker = Node::new(b, Arc::clone(&registry), 0, "/", "talker").unwrap();
        let good = talker.publisher("flag", "std_msgs/msg/Bool").unwrap();
        let wrong = talker.publisher("flag", "std_msgs/msg/Int32").unwrap();
        let hash = registry.type_hash("std_msgs/msg/Bool").unwrap();
        let key = topic_key(0, "flag", "std_msgs::msg::dds_::Bool_", &hash);
        let raw = talker.session().declare_publisher(key).wait().unwrap();
        let attachment = Attachment {
            sequence: 1,
            timestamp_ns: 0,
            gid: [1; 16],
        };
        // Wait until the subscription is known: the first good message arrives.
        let first = (0..100).find_map(|_| {
            good.publish(&Value::fields([("data", Value::Bool(true))])).unwrap();
            rx.recv_timeout(Duration::from_millis(100)).ok()
        });
        assert_eq!(first.unwrap().unwrap().value.get("data"), Some(&Value::Bool(true)));
        while rx.try_recv().is_ok() {}
        wrong.publish(&Value::fields([("data", Value::Int(3))])).unwrap();
        raw.put(vec![0u8, 1, 0, 0, 9])
            .attachment(attachment.to_bytes())
            .wait()
            .unwrap();
        raw.put(vec![0u8, 1, 0, 0, 1]).wait().unwrap();
        let kinds = AtomicUsize::new(0);
        for _ in 0..3 {
            match rx.recv_timeout(Duration::from_secs(5)).unwrap() {
                Err(Refusal::WrongType { expected, .. }) => {
                    assert!(expected.starts_with("std_msgs::msg::dds_::Bool_/RIHS01_"));
                    kinds.fetch_or(1, Ordering::Relaxed);
                }
                Err(Refusal::MalformedCdr { error, .. }) => {
                    assert!(error.to_string().contains("not 0 or 1"), "{error}");
                    kinds.fetch_or(2, Ordering::Relaxed);
                }
                Err(Refusal::BadAttachment { .. }) => {
                    kinds.fetch_or(4, Ordering::Relaxed);
                }
                Ok(r) => panic!("accepted {r:?}"),
            }
        }
        assert_eq!(kinds.load(Ordering::Relaxed), 7);
    }
}
