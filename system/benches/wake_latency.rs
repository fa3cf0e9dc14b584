//! Wake-up latency of a blocked process: iceoryx2's `WaitSet` against the
//! system's blocking wait (`Idle::pause` with `WaitStrategy::Block`: the
//! wake-up listener's `timed_wait`).
//!
//! A floor ping goes to an echo process and its pong comes back, each sent
//! through an `Outlet` (publish, then notify the receiver's wake-up event);
//! both processes block between polls, the same way in a round: on the
//! listener itself (`listener`), or on a `WaitSet` (one per process) the
//! listener is attached to, draining it in the callback (`waitset`). A round trip is two wake-ups.
//! The modes alternate over several rounds; the medians decide (see
//! `system/src/ipc/wait.rs`).
//!
//! `cargo bench -p learnpnp-system --bench wake_latency`

use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use iceoryx2::prelude::{CallbackProgression, SignalHandlingMode, WaitSet, WaitSetBuilder};
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::services::{AgentPorts, Ipc, RunServices, SimPorts, node, receive};
use learnpnp_system::ipc::wait::{Idle, MAX_BLOCK, WaitStrategy};
use learnpnp_system::multiprocess::host::simulator::{FLOOR_END, floor_ping, floor_pong};

/// The echo process's environment variable: `<prefix> <mode>`.
const ECHO: &str = "LEARNPNP_BENCH_WAKE";
const RUN_ID: u64 = 42;
const ROUNDS: usize = 3;
const ROUND_TRIPS: usize = 5_000;
const MODES: [&str; 2] = ["listener", "waitset"];

/// Blocks until `wake` is notified (or [`MAX_BLOCK`] has passed) on
/// `waitset` if there is one (`wake` attached to it), else on the listener
/// itself, then calls `poll` until it returns `Some`.
fn wait_for<R>(waitset: Option<&WaitSet<Ipc>>, wake: &Listener<Ipc>, mut poll: impl FnMut() -> Option<R>) -> R {
    let mut idle = Idle::new(WaitStrategy::Block);
    loop {
        if let Some(r) = poll() {
            return r;
        }
        match waitset {
            None => idle.pause(wake, MAX_BLOCK).expect("wait"),
            Some(waitset) => {
                waitset
                    .wait_and_process_once_with_timeout(
                        |_| {
                            let _ = wake.try_wait(|_| {});
                            CallbackProgression::Continue
                        },
                        MAX_BLOCK,
                    )
                    .expect("wait");
            }
        }
    }
}

/// A process's wait set (created once, as a process of the system would).
fn waitset() -> WaitSet<Ipc> {
    WaitSetBuilder::new()
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .expect("waitset")
}

/// The echo process: answers each ping with a pong, blocking in `mode` between them.
fn echo(prefix: &str, mode: &str) {
    let namespace = Namespace::from_prefix(prefix).expect("prefix");
    let node = node(&namespace, "echo").expect("node");
    let ports = AgentPorts::open(&node, 0, WaitStrategy::Block).expect("ports");
    let waitset = waitset();
    let guard = (mode == "waitset").then(|| waitset.attach_notification(&ports.wake).expect("attach"));
    let waitset = guard.as_ref().map(|_| &waitset);
    loop {
        let sequence = wait_for(waitset, &ports.wake, || {
            receive(&ports.floor_ping, |m| m.cycle_seq).expect("receive")
        });
        if sequence == FLOOR_END {
            return;
        }
        ports.floor_pong.send(floor_pong(RUN_ID, sequence)).expect("send");
    }
}

/// One round of `mode`: round trips in microseconds.
fn round(prefix: &str, ports: &SimPorts, mode: &str, sequence: &mut u64) -> Vec<f64> {
    let mut child = std::process::Command::new(std::env::current_exe().expect("exe"))
        .env(ECHO, format!("{prefix} {mode}"))
        .spawn()
        .expect("the echo process starts");
    // The echo process subscribes some time after it starts: ping until it answers.
    'connect: loop {
        *sequence += 1;
        ports.floor_ping.send(floor_ping(RUN_ID, *sequence)).expect("send");
        let sent = Instant::now();
        while sent.elapsed() < Duration::from_millis(10) {
            if receive(&ports.floor_pong, |m| m.cycle_seq).expect("receive") == Some(*sequence) {
                break 'connect;
            }
            std::thread::yield_now();
        }
    }
    let waitset = waitset();
    let guard = (mode == "waitset").then(|| waitset.attach_notification(&ports.host.wake).expect("attach"));
    let waitset = guard.as_ref().map(|_| &waitset);
    let mut micros = Vec::with_capacity(ROUND_TRIPS);
    for _ in 0..ROUND_TRIPS {
        *sequence += 1;
        let expected = *sequence;
        let sent = Instant::now();
        ports.floor_ping.send(floor_ping(RUN_ID, expected)).expect("send");
        wait_for(waitset, &ports.host.wake, || {
            (receive(&ports.floor_pong, |m| m.cycle_seq).expect("receive") == Some(expected)).then_some(())
        });
        micros.push(sent.elapsed().as_secs_f64() * 1e6);
    }
    ports.floor_ping.send(floor_ping(RUN_ID, FLOOR_END)).expect("send");
    child.wait().expect("the echo process ends");
    micros
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    if let Ok(echoed) = std::env::var(ECHO) {
        let (prefix, mode) = echoed.split_once(' ').expect("prefix and mode");
        echo(prefix, mode);
        return;
    }
    // `cargo test --benches` runs this with --bench absent: measure only when benchmarking.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    learnpnp_system::ipc::namespace::clean_stale().expect("cleaning what killed runs left");
    let owner = Namespace::claim_unique().expect("namespace");
    let prefix = owner.namespace().prefix().to_string();
    {
        let node = node(owner.namespace(), "bench").expect("node");
        let _services = RunServices::create(&node, learnpnp_system::ipc::protocol::Roster::Keepaway).expect("services");
        let ports = SimPorts::open(&node, WaitStrategy::Block).expect("ports");
        let mut sequence = 0;
        let mut all: Vec<Vec<f64>> = vec![Vec::new(); MODES.len()];
        let mut medians: Vec<Vec<f64>> = vec![Vec::new(); MODES.len()];
        for _ in 0..ROUNDS {
            for (m, mode) in MODES.iter().enumerate() {
                let mut micros = round(&prefix, &ports, mode, &mut sequence);
                micros.sort_by(f64::total_cmp);
                medians[m].push(percentile(&micros, 0.5));
                all[m].extend(micros);
            }
        }
        println!("wake-up round trip (two wake-ups), {ROUNDS} rounds x {ROUND_TRIPS}, alternating:");
        for (m, mode) in MODES.iter().enumerate() {
            let sorted = &mut all[m];
            sorted.sort_by(f64::total_cmp);
            let rounds: Vec<String> = medians[m].iter().map(|v| format!("{v:.1}")).collect();
            println!(
                "{mode:>9}: median {:.1} us (rounds: {}), p90 {:.1} us, p99 {:.1} us",
                percentile(sorted, 0.5),
                rounds.join(", "),
                percentile(sorted, 0.9),
                percentile(sorted, 0.99)
            );
        }
    }
    owner.release().expect("cleanup");
}
