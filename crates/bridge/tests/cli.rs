//! `learnpnp-bridge` as a supervisor starts it: a certificates directory
//! that is not there is refused, naming it, before any connection.

use std::process::Command;

const BRIDGE: &str = env!("CARGO_BIN_EXE_learnpnp-bridge");

#[test]
fn missing_certificates_are_refused_before_any_connection() {
    let dir = std::env::temp_dir().join(format!("learnpnp-bridge-cli-{}", std::process::id()));
    let certs = dir.join("no-such-certs");
    let out = Command::new(BRIDGE)
        .args([
            "--ipc-prefix",
            "lpbridgecli",
            "--side",
            "host",
            "--listen",
            "quic/127.0.0.1:9",
        ])
        .arg("--link-certs")
        .arg(&certs)
        .arg("--run-info")
        .arg(dir.join("run.json"))
        .arg("--work-dir")
        .arg(&dir)
        .output()
        .expect("the bridge runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("error: bridge:") && err.contains("no-such-certs"), "{err}");
    assert!(!dir.exists(), "the bridge made its work directory before refusing");
}
