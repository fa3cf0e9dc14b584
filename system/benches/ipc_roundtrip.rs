//! The snapshot/command round trip between two processes over iceoryx2, as
//! the multi-process system does it, against the bare transport:
//!
//! - `bare`: a snapshot-sized sample out, a command-sized sample back (the
//!   run's floor measurement);
//! - `validated`: a keeper's `PlayerView` converted into a snapshot, read and
//!   validated by the other process, answered with a command that is read and
//!   validated in turn (the simulator's and agent's work per cycle, without
//!   the keeper's thinking).
//!
//! Both processes poll and yield between polls (the lock-step default). The
//! echoing process is this bench binary, started again with
//! `LEARNPNP_BENCH_ECHO` set to the namespace's prefix.
//!
//! `cargo bench --bench ipc_roundtrip`

use std::time::{Duration, Instant};

use criterion::Criterion;
use learnpnp::learning::EpisodeStart;
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::perception::perceive;
use learnpnp_keepaway::simulator::Simulator;
use learnpnp_keepaway::view::PlayerId;
use learnpnp_system::ipc::convert::{command_message, read_command, read_snapshot, snapshot};
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::protocol::{CommandReading, SnapshotMeta};
use learnpnp_system::ipc::services::{AgentPorts, RunServices, SimPorts, node, receive};
use learnpnp_system::ipc::wait::WaitStrategy;
use learnpnp_system::multiprocess::host::simulator::{FLOOR_END, floor_ping, floor_pong};

const ECHO: &str = "LEARNPNP_BENCH_ECHO";
const RUN_ID: u64 = 42;

/// The other process: answers pings on the floor services raw, and
/// snapshots of keeper 1 with a validated command, until the end marker.
fn echo(prefix: &str) {
    let namespace = Namespace::from_prefix(prefix).expect("prefix");
    let node = node(&namespace, "echo").expect("node");
    let ports = AgentPorts::open(&node, 0, WaitStrategy::Yield).expect("ports");
    loop {
        if let Some(sequence) = receive(&ports.floor_ping, |m| m.cycle_seq).expect("receive") {
            if sequence == FLOOR_END {
                return;
            }
            ports.floor_pong.send(floor_pong(RUN_ID, sequence)).expect("send");
            continue;
        }
        if let Some(reading) = receive(&ports.snapshot, |m| read_snapshot(m, 0, RUN_ID)).expect("receive") {
            let (meta, view) = reading.expect("a valid snapshot");
            let answer = CommandReading {
                episode: meta.episode,
                cycle_seq: meta.cycle_seq,
                command: Command::Dash { power: view.ball.pos.x },
                idle: false,
            };
            ports.command.send(command_message(&answer, 0, RUN_ID)).expect("send");
            continue;
        }
        std::thread::yield_now();
    }
}

fn bench(c: &mut Criterion) {
    learnpnp_system::ipc::namespace::clean_stale().expect("cleaning what killed runs left");
    let owner = Namespace::claim_unique().expect("namespace");
    let prefix = owner.namespace().prefix().to_string();
    let node = node(owner.namespace(), "bench").expect("node");
    let _services = RunServices::create(&node, learnpnp_system::ipc::protocol::Roster::Keepaway).expect("services");
    let ports = SimPorts::open(&node, WaitStrategy::Yield).expect("ports");
    let mut child = std::process::Command::new(std::env::current_exe().expect("exe"))
        .env(ECHO, &prefix)
        .spawn()
        .expect("the echo process starts");

    let config = KeepawayConfig::default();
    let sim = Simulator::new(config, 7).expect("simulator");
    let view = perceive(sim.field(), PlayerId::keeper(0).expect("keeper"), &config);
    // The echo process subscribes some time after it starts: ping until it answers.
    let mut sequence = 0u64;
    'connect: loop {
        ports.floor_ping.send(floor_ping(RUN_ID, sequence)).expect("send");
        let sent = Instant::now();
        while sent.elapsed() < Duration::from_millis(10) {
            if receive(&ports.floor_pong, |m| m.cycle_seq).expect("receive") == Some(sequence) {
                break 'connect;
            }
            std::thread::yield_now();
        }
    }
    let mut group = c.benchmark_group("ipc_roundtrip");
    group.bench_function("bare", |b| {
        b.iter_custom(|iters| {
            let started = Instant::now();
            for _ in 0..iters {
                sequence += 1;
                ports.floor_ping.send(floor_ping(RUN_ID, sequence)).expect("send");
                while receive(&ports.floor_pong, |m| m.cycle_seq).expect("receive") != Some(sequence) {
                    std::thread::yield_now();
                }
            }
            started.elapsed()
        })
    });
    group.bench_function("validated", |b| {
        b.iter_custom(|iters| {
            let started = Instant::now();
            for _ in 0..iters {
                sequence += 1;
                let meta = SnapshotMeta {
                    episode: 1,
                    cycle_seq: sequence,
                    reward: 0.1,
                    start: EpisodeStart::LEARN,
                };
                ports.host.snapshots[0]
                    .send(snapshot(&view, &meta, RUN_ID))
                    .expect("send");
                loop {
                    match receive(&ports.host.commands[0], |m| read_command(m, 0, RUN_ID)).expect("receive") {
                        Some(Ok(c)) if c.cycle_seq == sequence => break,
                        Some(_) => {}
                        None => std::thread::yield_now(),
                    }
                }
            }
            started.elapsed()
        })
    });
    group.finish();
    ports.floor_ping.send(floor_ping(RUN_ID, FLOOR_END)).expect("send");
    let _ = child.wait();
    drop(ports);
    drop(_services);
    drop(node);
    owner.release().expect("cleanup");
}

fn main() {
    if let Ok(prefix) = std::env::var(ECHO) {
        echo(&prefix);
        return;
    }
    let mut criterion = Criterion::default()
        .configure_from_args()
        .measurement_time(Duration::from_secs(5));
    bench(&mut criterion);
    criterion.final_summary();
}
