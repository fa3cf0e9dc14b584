//! Parr and Russell's grid: one learning episode through the full plan executor
//! and learner, on one thread (episodes per second = 1 / time per episode),
//! with the Petri Net Plan and with the equivalent plan schema.
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
use learnpnp::named::Named;
use learnpnp::plan::AllowedAtoms;
use learnpnp::plan_file::load_plan;
use learnpnp::rng::seeded;

fn bench(c: &mut Criterion) {
    let domain = DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    };
    let net = Arc::new(parr_russell::default_plan().expect("plan"));
    let schema_file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("plans/parr_russell.schema");
    let schema = Arc::new(load_plan(&schema_file, AllowedAtoms::Closed(&parr_russell::atoms())).expect("schema"));
    let mut group = c.benchmark_group("parr_russell_episode");
    let runs = [
        (Algorithm::EpsSosmc, &net, ""),
        (Algorithm::SarsaLambda, &net, ""),
        (Algorithm::EpsSosmc, &schema, "/schema"),
    ];
    for (algorithm, plan, suffix) in runs {
        let learner = default_learner(algorithm, &domain).build(seeded(1));
        let mut task =
            ParrRussell::new(ParrRussellConfig::default(), Arc::clone(plan), learner, seeded(2)).expect("task");
        // Past the initial phase and the early long episodes: the steady state of a run.
        for _ in 0..2000 {
            task.episode(EpisodeMode::Learn).expect("episode");
        }
        group.bench_function(format!("{}{suffix}", algorithm.name()), |b| {
            b.iter(|| black_box(task.episode(EpisodeMode::Learn).expect("episode")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
