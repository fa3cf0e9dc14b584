//! The Zenoh session joining a run's hosts: TCP endpoints given explicitly
//! (host A's bridge listens as a Zenoh router, so that what one host sends
//! reaches every other connected to it, a monitor included; the others
//! connect as clients), multicast and gossip scouting off, so that a bridge
//! talks to the endpoints it is given and to nothing else; a lost
//! connection is retried for as long as the run lasts.

use zenoh::{Config, Session, Wait};

use super::{BridgeError, zenoh_error};

/// Where a bridge listens and whom it connects to (`tcp/ADDRESS:PORT`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Endpoints {
    /// Endpoints to listen on.
    pub listen: Vec<String>,
    /// Endpoints to connect to.
    pub connect: Vec<String>,
}

/// Checks that every endpoint is TCP (the only transport built in).
fn tcp_only(endpoints: &[String]) -> Result<(), BridgeError> {
    match endpoints.iter().find(|e| !e.starts_with("tcp/")) {
        Some(e) => Err(BridgeError::Zenoh(format!(
            "endpoint '{e}': only tcp/ADDRESS:PORT endpoints are supported"
        ))),
        None => Ok(()),
    }
}

fn set(config: &mut Config, key: &str, value: &str) -> Result<(), BridgeError> {
    config
        .insert_json5(key, value)
        .map_err(|e| BridgeError::Zenoh(format!("config {key} = {value}: {e}")))
}

/// Opens the session on `endpoints`.
pub fn open(endpoints: &Endpoints) -> Result<Session, BridgeError> {
    tcp_only(&endpoints.listen)?;
    tcp_only(&endpoints.connect)?;
    let list = |v: &[String]| serde_json::to_string(v).unwrap_or_else(|_| "[]".into());
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
    // Wait at most a minute for the other host at start, and keep retrying
    // in the background after (and after a cut link).
    set(&mut config, "connect/timeout_ms", "60000")?;
    set(&mut config, "connect/exit_on_failure", "false")?;
    // Every message at once (not batched: a lock-step cycle waits for it),
    // and none dropped when the link is congested (the run counts on each).
    set(
        &mut config,
        "qos/publication",
        r#"[{ key_exprs: ["learnpnp/**"], config: { express: true, congestion_control: "block" } }]"#,
    )?;
    zenoh::open(config).wait().map_err(zenoh_error)
}
