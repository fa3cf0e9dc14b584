//! Simulated keepaway cycles per second with the fixed procedure: hand-coded
//! keepers, framework takers, full-state vision, motion noise on.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use learnpnp::keepaway::{BaselinePolicy, Keepaway, KeepawayConfig};
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
    group.bench_function("cycles_hand_coded_full_state", |b| {
        let cfg = KeepawayConfig::default();
        let mut game = match Keepaway::new(cfg, 42) {
            Ok(g) => g,
            Err(e) => panic!("default configuration rejected: {e}"),
        };
        let mut policy = BaselinePolicy::HandCoded;
        b.iter(|| black_box(run_cycles(&mut game, &mut policy, CYCLES)));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
