//! The Zenoh session joining a run's hosts. By default an encrypted link
//! with mutual authentication: every host presents a certificate of the
//! run's private CA ([`learnpnp_system::hosts::certs`]) and trusts no other root; host B
//! verifies that host A's certificate names the address it connects to;
//! host A's router admits each peer only to the keys its certificate's
//! common name may use ([`super::access`](crate::access)). Plain TCP (no encryption, no
//! authentication, no access control) only when asked for by name
//! ([`Security::PlainTcp`](crate::link::Security::PlainTcp)).
//!
//! The encrypted link is Zenoh's QUIC transport (TLS 1.3 inside QUIC, set
//! up by the same `transport/link/tls` settings: root CA, listen and connect
//! certificates, `enable_mtls`, `verify_name_on_connect`), not its `tls/`
//! transport: zenoh 1.10.2's TLS link reads and writes one rustls stream
//! from two tasks at once (eclipse-zenoh/zenoh#2557, open), and the
//! lock-step exchange, traffic both ways every cycle, lost messages within
//! seconds and crashed a bridge (an invalid opcode in its transmit thread).
//!
//! Endpoints are given explicitly (host A's bridge listens as a Zenoh
//! router, so that what one host sends reaches every other connected to it,
//! a monitor included; the others connect as clients), multicast and gossip
//! scouting are off, so that a bridge talks to the endpoints it is given and
//! to nothing else; a lost connection is retried for as long as the run lasts.

use zenoh::{Config, Session, Wait};

use super::{BridgeError, zenoh_error};
use learnpnp_system::hosts::certs::HostFiles;

/// Where a bridge listens and whom it connects to (`quic/ADDRESS:PORT`, or
/// `tcp/ADDRESS:PORT` with [`Security::PlainTcp`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Endpoints {
    /// Endpoints to listen on.
    pub listen: Vec<String>,
    /// Endpoints to connect to.
    pub connect: Vec<String>,
}

/// How the link protects the run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Security {
    /// TLS, both ends authenticated by the run's private CA.
    MutualTls(HostFiles),
    /// Plain TCP: anyone who reaches the port can read the run and take it over.
    PlainTcp,
}

impl Security {
    /// The endpoints' scheme.
    fn scheme(&self) -> &'static str {
        match self {
            Security::MutualTls(_) => "quic/",
            Security::PlainTcp => "tcp/",
        }
    }

    /// A name for reports: `mutual-tls-quic` or `plain-tcp`.
    pub fn name(&self) -> &'static str {
        match self {
            Security::MutualTls(_) => "mutual-tls-quic",
            Security::PlainTcp => "plain-tcp",
        }
    }
}

/// Checks that every endpoint has the scheme of `security`.
fn check_scheme(endpoints: &[String], security: &Security) -> Result<(), BridgeError> {
    let scheme = security.scheme();
    match endpoints.iter().find(|e| !e.starts_with(scheme)) {
        Some(e) if security == &Security::PlainTcp => Err(BridgeError::Zenoh(format!(
            "endpoint '{e}': with --insecure-plain-tcp only tcp/ADDRESS:PORT endpoints are supported"
        ))),
        Some(e) => Err(BridgeError::Zenoh(format!(
            "endpoint '{e}': the link is TLS with mutual authentication, give quic/ADDRESS:PORT \
             (or --insecure-plain-tcp with tcp/ADDRESS:PORT to give up encryption and authentication)"
        ))),
        None => Ok(()),
    }
}

/// A QUIC endpoint on one stream (`?multistream=0`): by default Zenoh's QUIC
/// link opens a stream per priority, its declarations on one and the data on
/// another, so that a message can overtake the declaration of the key it is
/// sent under, and the receiver drops it. A run counts on every message (a
/// keeper lost, announced on a key declared at that moment, was lost so and
/// stalled a lock-step run): one stream keeps them in order, as TCP does.
/// Set on host A's listener, it is what every peer negotiates.
fn one_stream(endpoint: &str, security: &Security) -> String {
    match security {
        Security::MutualTls(_) if !endpoint.contains('?') => format!("{endpoint}?multistream=0"),
        _ => endpoint.to_string(),
    }
}

fn set(config: &mut Config, key: &str, value: &str) -> Result<(), BridgeError> {
    config
        .insert_json5(key, value)
        .map_err(|e| BridgeError::Zenoh(format!("config {key} = {value}: {e}")))
}

/// A JSON string.
fn quoted(s: &str) -> String {
    serde_json::Value::String(s.to_string()).to_string()
}

/// Opens the session on `endpoints` with `security`; host A's bridge passes
/// its access control (`access_control`, a JSON object: [`super::access`]).
pub fn open(
    endpoints: &Endpoints,
    security: &Security,
    access_control: Option<&serde_json::Value>,
) -> Result<Session, BridgeError> {
    check_scheme(&endpoints.listen, security)?;
    check_scheme(&endpoints.connect, security)?;
    let list = |v: &[String]| {
        let v: Vec<String> = v.iter().map(|e| one_stream(e, security)).collect();
        serde_json::to_string(&v).unwrap_or_else(|_| "[]".into())
    };
    let mut config = Config::default();
    let mode = if endpoints.listen.is_empty() {
        "\"client\""
    } else {
        "\"router\""
    };
    set(&mut config, "mode", mode)?;
    set(&mut config, "scouting/multicast/enabled", "false")?;
    set(&mut config, "scouting/gossip/enabled", "false")?;
    set(&mut config, "listen/endpoints", &list(&endpoints.listen))?;
    set(&mut config, "connect/endpoints", &list(&endpoints.connect))?;
    if let Security::MutualTls(files) = security {
        let path = |p: &std::path::Path| quoted(&p.display().to_string());
        let tls = "transport/link/tls";
        set(&mut config, &format!("{tls}/root_ca_certificate"), &path(&files.ca))?;
        set(&mut config, &format!("{tls}/enable_mtls"), "true")?;
        if !endpoints.listen.is_empty() {
            set(&mut config, &format!("{tls}/listen_certificate"), &path(&files.cert))?;
            set(&mut config, &format!("{tls}/listen_private_key"), &path(&files.key))?;
        }
        if !endpoints.connect.is_empty() {
            set(&mut config, &format!("{tls}/connect_certificate"), &path(&files.cert))?;
            set(&mut config, &format!("{tls}/connect_private_key"), &path(&files.key))?;
            set(&mut config, &format!("{tls}/verify_name_on_connect"), "true")?;
        }
        // A certificate that expires during a run closes its link.
        set(&mut config, &format!("{tls}/close_link_on_expiration"), "true")?;
    }
    if let Some(acl) = access_control {
        set(&mut config, "access_control", &acl.to_string())?;
    }
    // Wait at most a minute for the other host at start, and keep retrying
    // in the background after (and after a cut link).
    set(&mut config, "connect/timeout_ms", "60000")?;
    set(&mut config, "connect/exit_on_failure", "false")?;
    // Each publisher says how it meets a congested link (see
    // carry::Sending): droppable where host A's router fans out, blocking
    // where only host A's bridge receives; every message at once (express).
    // Room for a burst of messages per priority and destination before a
    // droppable one waits at all (16 batches, the most Zenoh allows: a
    // message sent at once takes a batch to itself).
    let queue = "transport/link/tx/queue";
    set(&mut config, &format!("{queue}/size/data"), "16")?;
    set(&mut config, &format!("{queue}/size/data_low"), "16")?;
    set(
        &mut config,
        &format!("{queue}/congestion_control/drop/wait_before_drop"),
        super::carry::WAIT_BEFORE_DROP,
    )?;
    zenoh::open(config).wait().map_err(zenoh_error)
}
