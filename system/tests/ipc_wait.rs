//! Waiting for a message: a pause never blocks longer than it was asked to.

use std::sync::mpsc;
use std::time::{Duration, Instant};

use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::services::{AgentPorts, RunServices, node};
use learnpnp_system::ipc::wait::{Idle, TIMED_WAIT_SLACK, WaitStrategy};

/// A blocking pause with no time left (a deadline just reached) returns at
/// once: iceoryx2 would take a zero socket timeout as no timeout at all.
#[test]
fn a_blocking_pause_with_no_time_left_returns() {
    let (done, finished) = mpsc::channel();
    // The ports live on the thread that uses them; the test waits for it with a limit.
    std::thread::spawn(move || {
        let owner = Namespace::claim_unique().unwrap();
        {
            let node = node(owner.namespace(), "waiter").unwrap();
            let _services = RunServices::create(&node, learnpnp_system::ipc::protocol::Roster::Keepaway).unwrap();
            let ports = AgentPorts::open(&node, 0, WaitStrategy::Block).unwrap();
            for strategy in [WaitStrategy::Block, WaitStrategy::Hybrid] {
                let mut idle = Idle::new(strategy);
                idle.pause(&ports.wake, Duration::ZERO).unwrap();
                idle.pause_until(&ports.wake, Instant::now() + TIMED_WAIT_SLACK / 2)
                    .unwrap();
                idle.pause_until(&ports.wake, Instant::now()).unwrap();
            }
        }
        owner.release().unwrap();
        done.send(()).unwrap();
    });
    assert!(
        finished.recv_timeout(Duration::from_secs(30)).is_ok(),
        "a pause with no time left blocked"
    );
}
