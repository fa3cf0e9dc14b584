//! Host A's access control (Zenoh's `access_control`, default deny), made
//! from the routes its bridge carries: host B's certificate may publish only
//! its own agents' keys (their commands, reports and heartbeats, its
//! supervisor's orders, its files) and subscribe only to what its agents and
//! supervisor need (their snapshots, the episode events, the heartbeats, host
//! A's orders, the files' acknowledgements), and ask for the run's
//! description; a monitor's certificate may only subscribe to the heartbeats
//! and the episode events. Subjects are certificates' common names
//! ([`learnpnp_system::hosts::certs`]), never Zenoh ids or interfaces (a Zenoh id is not
//! authenticated). What it denies is counted ([`super::refusals`](crate::refusals)).

use serde_json::{Value, json};
use shm_layouts::services;

use super::carry::{Direction, Route, Source, key};
use super::remote::{RUN_INFO_KEY, ack_key, file_key};
use learnpnp_system::hosts::certs::{HOST_B_NAME, MONITOR_NAME};
use learnpnp_system::hosts::shipped::ShippedFiles;

/// The keys of `route` that host B publishes on, those host A's bridge
/// subscribes to them by (announced to host B, whose publishers send only
/// where a subscriber is), and those host B subscribes to, as host A's
/// bridge carries it.
fn host_b_keys(prefix: &str, route: &Route) -> [Vec<String>; 3] {
    let base = key(prefix, &route.service);
    let (published, announced, subscribed) = match &route.source {
        Source::Single => (vec![base.clone()], vec![base.clone()], vec![base]),
        Source::BySender { accepted } => (
            accepted.iter().map(|s| format!("{base}/{s}")).collect(),
            vec![format!("{base}/*")],
            vec![format!("{base}/*")],
        ),
        // Host A's bridge names itself `this`, host B `other`.
        Source::ByHost { this, other } => (
            vec![format!("{base}/{other}")],
            vec![format!("{base}/{other}")],
            vec![format!("{base}/{this}")],
        ),
    };
    match route.direction {
        Direction::In => [published, announced, Vec::new()],
        Direction::Out => [Vec::new(), Vec::new(), subscribed],
        Direction::Both => [published, announced, subscribed],
    }
}

/// One rule: `messages` in `flow` on `keys` allowed.
fn rule(id: &str, messages: &[&str], flow: &str, keys: &[String]) -> Value {
    json!({
        "id": id,
        "messages": messages,
        "flows": [flow],
        "permission": "allow",
        "key_exprs": keys,
    })
}

/// Host A's `access_control` for the run whose prefix is `prefix`, its
/// bridge carrying `routes` and receiving `files` from host B.
pub(crate) fn host_a_policy(prefix: &str, routes: &[Route], files: &ShippedFiles) -> Value {
    let (mut published, mut announced, mut subscribed) = (Vec::new(), Vec::new(), Vec::new());
    for route in routes {
        let [p, a, s] = host_b_keys(prefix, route);
        published.extend(p);
        announced.extend(a);
        subscribed.extend(s);
    }
    published.extend(files.key_patterns().iter().map(|name| file_key(prefix, name)));
    announced.push(file_key(prefix, "*"));
    subscribed.push(ack_key(prefix, "*"));
    let run_info = vec![RUN_INFO_KEY.to_string()];
    // A monitor does not know the run's prefix (it cannot ask for the run).
    let watched = vec![
        key("*", &format!("{}/*", services::HEARTBEAT)),
        key("*", services::EPISODE),
    ];
    json!({
        "enabled": true,
        "default_permission": "deny",
        "rules": [
            rule("host-b-publishes", &["put"], "ingress", &published),
            // Host A tells host B where its publications are wanted.
            rule("host-b-publishes-to", &["declare_subscriber"], "egress", &announced),
            rule("host-b-subscribes", &["declare_subscriber"], "ingress", &subscribed),
            rule("host-b-receives", &["put"], "egress", &subscribed),
            rule("host-b-asks-for-the-run", &["query"], "ingress", &run_info),
            rule("host-b-is-told-the-run", &["reply", "declare_queryable"], "egress", &run_info),
            rule("monitor-subscribes", &["declare_subscriber"], "ingress", &watched),
            rule("monitor-receives", &["put"], "egress", &watched),
        ],
        "subjects": [
            { "id": "host-b", "cert_common_names": [HOST_B_NAME] },
            { "id": "monitor", "cert_common_names": [MONITOR_NAME] },
        ],
        "policies": [
            {
                "rules": [
                    "host-b-publishes",
                    "host-b-publishes-to",
                    "host-b-subscribes",
                    "host-b-receives",
                    "host-b-asks-for-the-run",
                    "host-b-is-told-the-run",
                ],
                "subjects": ["host-b"],
            },
            { "rules": ["monitor-subscribes", "monitor-receives"], "subjects": ["monitor"] },
        ],
    })
}
