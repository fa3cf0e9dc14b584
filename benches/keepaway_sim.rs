//! Simulated keepaway cycles per second with the fixed procedure: hand-coded
//! keepers, framework takers, motion noise on, with the framework players'
//! perception (the default) and in full state; and, for comparison, the
//! physics and referee alone.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use learnpnp_keepaway::world::NUM_PLAYERS;
use learnpnp_keepaway::{BaselinePolicy, Command, Keepaway, KeepawayConfig, Simulator, VisionMode};
use std::hint::black_box;

/// Cycles simulated per benchmark iteration.
const CYCLES: u64 = 10_000;

fn run_cycles(game: &mut Keepaway, policy: &mut BaselinePolicy, n: u64) -> u64 {
    let mut ended = 0;
    for _ in 0..n {
        if game.step(policy).is_some() {
            ended += 1;
            game.reset();
        }
    }
    ended
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("keepaway");
    group.throughput(Throughput::Elements(CYCLES));
    for (name, vision) in [
        ("cycles_hand_coded_framework", VisionMode::Framework),
        ("cycles_hand_coded_full_state", VisionMode::FullState),
    ] {
        group.bench_function(name, |b| {
            let cfg = KeepawayConfig {
                vision,
                ..KeepawayConfig::default()
            };
            let mut game = match Keepaway::new(cfg, 42) {
                Ok(g) => g,
                Err(e) => panic!("configuration rejected: {e}"),
            };
            let mut policy = BaselinePolicy::HandCoded;
            b.iter(|| black_box(run_cycles(&mut game, &mut policy, CYCLES)));
        });
    }
    group.bench_function("cycles_physics_and_referee_only", |b| {
        // The same load without the agents: every player dashes, the ball rolls.
        let cfg = KeepawayConfig::default();
        let mut sim = match Simulator::new(cfg, 42) {
            Ok(s) => s,
            Err(e) => panic!("default configuration rejected: {e}"),
        };
        let cmds = [Command::Dash { power: 60.0 }; NUM_PLAYERS];
        b.iter(|| {
            let mut ended = 0u64;
            for _ in 0..CYCLES {
                if sim.step(black_box(&cmds)).is_some() {
                    ended += 1;
                    sim.reset();
                }
            }
            black_box(ended)
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
