//! One executor step of a 100-place plan, with no firing and with one firing.
//!
//! `cargo bench --bench executor_step`

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use learnpnp::condition::{AtomId, BitKnowledgeBase, KnowledgeBase};
use learnpnp::executor::{Action, Executor, RandomChooser, Registry, World};
use learnpnp::plan::{AllowedAtoms, PlanBuilder};
use learnpnp::rng::seeded;

struct Bench {
    kb: BitKnowledgeBase,
}

impl KnowledgeBase for Bench {
    fn holds(&self, atom: AtomId) -> bool {
        self.kb.holds(atom)
    }
}

impl World for Bench {}

/// An action that runs forever (its end transition waits on `finished`).
struct Forever;

impl Action<Bench> for Forever {
    fn finished(&self, _: &Bench) -> bool {
        false
    }
}

/// A ring of 50 actions: 100 places (an execution place and a connector each).
fn ring_of_actions() -> learnpnp::plan::Plan {
    let mut b = PlanBuilder::new("ring_actions");
    let first = b.initial_place("start");
    let mut from = first;
    for i in 0..49 {
        from = b.action(from, &format!("work_{i}")).done;
    }
    b.action_into(from, "work_49", first);
    b.build(AllowedAtoms::Open).expect("valid plan")
}

/// A ring of 100 places joined by unguarded transitions: every step fires one.
fn ring_of_transitions() -> learnpnp::plan::Plan {
    let mut b = PlanBuilder::new("ring_transitions");
    let first = b.initial_place("p0");
    let mut from = first;
    for i in 1..100 {
        let next = b.place(format!("p{i}"));
        b.transition(format!("t{i}"), &[(from, 1)], &[(next, 1)]);
        from = next;
    }
    b.transition("t0", &[(from, 1)], &[(first, 1)]);
    b.build(AllowedAtoms::Open).expect("valid plan")
}

fn bench(c: &mut Criterion) {
    let mut registry = Registry::new();
    registry.family("work", &[], |_| Forever);
    let mut world = Bench {
        kb: BitKnowledgeBase::new(1),
    };
    let mut chooser = RandomChooser::new(seeded(1));

    let plan = Arc::new(ring_of_actions());
    assert_eq!(plan.net().places().len(), 100);
    let mut exec = Executor::new(plan, &registry).expect("executor");
    exec.reset(&mut world, &mut chooser);
    exec.step(&mut world, &mut chooser).expect("step"); // start work_0
    c.bench_function("step_100_places_no_firing", |b| {
        b.iter(|| black_box(exec.step(&mut world, &mut chooser).expect("step")))
    });

    let plan = Arc::new(ring_of_transitions());
    assert_eq!(plan.net().places().len(), 100);
    let mut exec = Executor::new(plan, &registry).expect("executor");
    exec.reset(&mut world, &mut chooser);
    c.bench_function("step_100_places_one_firing", |b| {
        b.iter(|| black_box(exec.step(&mut world, &mut chooser).expect("step")))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
