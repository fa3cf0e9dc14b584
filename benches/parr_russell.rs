//! Parr and Russell's grid: one learning episode through the full plan executor
//! and learner, on one thread (episodes per second = 1 / time per episode).
//!
//! `cargo bench --bench parr_russell`

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use learnpnp::domains::Task;
use learnpnp::domains::parr_russell::{self, ParrRussell, ParrRussellConfig};
use learnpnp::experiment::defaults::default_learner;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::learning::EpisodeMode;
use learnpnp::rng::seeded;

fn bench(c: &mut Criterion) {
    let domain = DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    };
    let plan = Arc::new(parr_russell::default_plan().expect("plan"));
    let mut group = c.benchmark_group("parr_russell_episode");
    for algorithm in [Algorithm::EpsSosmc, Algorithm::SarsaLambda] {
        let learner = default_learner(algorithm, &domain).build(seeded(1));
        let mut task =
            ParrRussell::new(ParrRussellConfig::default(), Arc::clone(&plan), learner, seeded(2)).expect("task");
        // Past the initial phase and the early long episodes: the steady state of a run.
        for _ in 0..2000 {
            task.episode(EpisodeMode::Learn).expect("episode");
        }
        group.bench_function(algorithm.name(), |b| {
            b.iter(|| black_box(task.episode(EpisodeMode::Learn).expect("episode")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
