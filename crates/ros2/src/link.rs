//! The world's Zenoh session, opened by the secure link's own code
//! (`learnpnp_bridge::link::open`): multicast scouting and gossip
//! off, only the endpoints the mapping names; with `tls`, mutual TLS over
//! QUIC with the run's certificates (`learnpnp-supervisor link-certs`).

use std::path::Path;

use learnpnp_bridge::link::{self, Endpoints, Security};
use learnpnp_system::hosts::certs::HostFiles;
use thiserror::Error;
use zenoh::Session;

use crate::mapping::ZenohSection;

/// The session cannot be opened.
#[derive(Debug, Error)]
pub enum LinkError {
    /// The certificate directory lacks a file.
    #[error("[zenoh] tls: {0}")]
    Certificates(String),
    /// Zenoh refused the configuration or the endpoints.
    #[error("[zenoh]: {0}")]
    Open(String),
}

/// Opens the session `zenoh` describes (relative `tls` paths start at `dir`).
pub fn open(zenoh: &ZenohSection, dir: &Path) -> Result<Session, LinkError> {
    let security = match &zenoh.tls {
        Some(tls) => {
            Security::MutualTls(HostFiles::in_dir(&dir.join(tls)).map_err(|e| LinkError::Certificates(e.to_string()))?)
        }
        None => Security::PlainTcp,
    };
    let endpoints = Endpoints {
        listen: zenoh.listen.clone(),
        connect: zenoh.connect.clone(),
    };
    link::open(&endpoints, &security, None).map_err(|e| LinkError::Open(e.to_string()))
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::sync::mpsc;
    use std::time::Duration;

    use learnpnp_system::hosts::certs::{self, CertRequest, HOST_A_DIR, HOST_B_DIR};

    use super::*;
    use crate::node::Node;
    use crate::types::{Registry, Value};

    fn section(listen: &[String], connect: &[String], tls: Option<&str>) -> ZenohSection {
        ZenohSection {
            connect: connect.to_vec(),
            listen: listen.to_vec(),
            tls: tls.map(Into::into),
        }
    }

    #[test]
    fn a_secure_world_talks_to_a_robot_over_mutual_tls_on_127_0_0_1() {
        let root = std::env::temp_dir().join(format!("learnpnp-ros2-tls-{}", std::process::id()));
        certs::make(
            &root,
            &CertRequest {
                host_a: vec!["127.0.0.1".into()],
                monitors: Vec::new(),
            },
        )
        .unwrap();
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let endpoint = vec![format!("quic/127.0.0.1:{port}")];
        let router = open(&section(&endpoint, &[], Some(HOST_A_DIR)), &root).unwrap();
        let world = open(&section(&[], &endpoint, Some(HOST_B_DIR)), &root).unwrap();
        std::fs::remove_dir_all(&root).unwrap();
        let registry = Arc::new(Registry::new());
        let robot = Node::new(router, Arc::clone(&registry), 0, "/", "robot").unwrap();
        let world = Node::new(world, Arc::clone(&registry), 0, "/", "learnpnp_world").unwrap();
        let (tx, rx) = mpsc::channel();
        let tx = std::sync::Mutex::new(tx);
        let _sub = world
            .subscribe("/at_end", "std_msgs/msg/Bool", move |r| {
                let _ = tx.lock().unwrap().send(r);
            })
            .unwrap();
        let publisher = robot.publisher("/at_end", "std_msgs/msg/Bool").unwrap();
        let got = (0..100).find_map(|_| {
            publisher
                .publish(&Value::fields([("data", Value::Bool(true))]))
                .unwrap();
            rx.recv_timeout(Duration::from_millis(100)).ok()
        });
        assert_eq!(got.unwrap().unwrap().value.get("data"), Some(&Value::Bool(true)));
    }

    #[test]
    fn missing_certificates_and_bad_endpoints_are_named() {
        let dir = std::env::temp_dir();
        let e = open(&section(&[], &["quic/127.0.0.1:9".into()], Some("no-such-dir")), &dir).unwrap_err();
        assert!(
            e.to_string().starts_with("[zenoh] tls: ") && e.to_string().contains("no-such-dir"),
            "{e}"
        );
        let e = open(&section(&[], &["udp/127.0.0.1:9".into()], None), &dir).unwrap_err();
        assert!(e.to_string().contains("udp/127.0.0.1:9"), "{e}");
    }
}
