//! Keepaway with every keeper executing a plan and learning (the positioning
//! experiment: three plan keepers, two takers; the pass experiment: one), in
//! one process on one thread, with the framework players' perception (the
//! default) and, for the positioning experiment, in full state.
//! Reported per 10,000 simulated cycles: cycles per second = 10,000 / time.
//!
//! `cargo bench --bench keepaway_plans`

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use learnpnp::domains::Task;
use learnpnp::domains::keepaway::{KeepawayDomainConfig, KeepawayMode, KeepawayTask};
use learnpnp::experiment::defaults::default_learner;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::learning::EpisodeMode;
use learnpnp::rng::{derive_seed, seeded};
use learnpnp_keepaway::VisionMode;
use std::sync::Arc;

const CYCLES: u64 = 10_000;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("keepaway_plans");
    for (name, mode, vision) in [
        (
            "three_plan_keepers_learning_positions",
            KeepawayMode::Position,
            VisionMode::Framework,
        ),
        (
            "one_plan_keeper_learning_passes",
            KeepawayMode::Pass,
            VisionMode::Framework,
        ),
        (
            "three_plan_keepers_learning_positions_full_state",
            KeepawayMode::Position,
            VisionMode::FullState,
        ),
    ] {
        let config = KeepawayDomainConfig {
            vision,
            ..KeepawayDomainConfig::for_mode(mode)
        };
        let domain = DomainSpec::Keepaway { config, plan: None };
        let spec = default_learner(Algorithm::SoftSosmc, &domain);
        let plan = Arc::new(config.default_plan().expect("plan").expect("learning mode"));
        let mut learner = |i: usize| spec.build(seeded(derive_seed(1, i as u64)));
        let mut task = KeepawayTask::new(config, Some(plan), &mut learner, seeded(2)).expect("task");
        group.bench_function(name, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let mut cycles = 0;
                    let start = Instant::now();
                    while cycles < CYCLES {
                        cycles += u64::from(task.episode(EpisodeMode::Learn).expect("episode").actions);
                    }
                    // Scale to exactly CYCLES cycles.
                    total += start.elapsed().mul_f64(CYCLES as f64 / cycles as f64);
                }
                total
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
