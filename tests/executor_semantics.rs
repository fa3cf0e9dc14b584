//! The executor's operational semantics (thesis 5.3) on small plans built in code.

use crate::util::{LogWorld as Log, Timed};
use std::sync::Arc;

use learnpnp::condition::{AtomId, AtomTable, BitKnowledgeBase};
use learnpnp::executor::{Chooser, ExecError, Executor, PlanKey, RandomChooser, Registry, Status};
use learnpnp::net::Marking;
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder};
use learnpnp::rng::seeded;

fn registry() -> Registry<Log> {
    let mut r = Registry::new();
    r.family("act", &["begun"], Timed::new);
    r
}

/// Records what the executor told it; picks a fixed option.
#[derive(Default)]
struct Recorder {
    pick: usize,
    choices: Vec<(PlanKey, Marking, Vec<Marking>)>,
    transitions: Vec<(PlanKey, Marking, f64, u32)>,
}

impl Chooser for Recorder {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        self.choices.push((plan, state.clone(), options.to_vec()));
        self.pick
    }
    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        self.transitions.push((plan, marking.clone(), reward, elapsed));
    }
}

fn run(exec: &mut Executor<Log>, world: &mut Log, chooser: &mut impl Chooser, max: usize) -> (Status, usize) {
    exec.reset(world, chooser);
    for i in 1..=max {
        let s = exec.step(world, chooser).unwrap();
        if s != Status::Running {
            return (s, i);
        }
    }
    (Status::Running, max)
}

#[test]
fn sequence_runs_actions_in_order_and_reaches_the_goal() {
    let mut b = PlanBuilder::new("seq");
    let init = b.initial_place("init");
    let a = b.action(init, "act_a_2");
    let goal = b.goal_place();
    b.action_into(a.done, "act_b_1", goal);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let mut exec = Executor::new(plan, &registry()).unwrap();
    let mut world = Log::default();
    let mut rec = Recorder::default();
    let (status, steps) = run(&mut exec, &mut world, &mut rec, 20);
    assert_eq!(status, Status::Goal);
    // step 1: start a; 2: a steps; 3: a steps, finished, ends; 4: start b; 5: b steps, ends -> goal.
    assert_eq!(steps, 5);
    assert_eq!(
        world.lines,
        [
            "start act_a_2",
            "step act_a_2",
            "step act_a_2",
            "end act_a_2",
            "start act_b_1",
            "step act_b_1",
            "end act_b_1"
        ]
    );
    assert!(rec.choices.is_empty());
    // Elapsed steps between marking changes: 1, 2, 1, 1.
    let elapsed: Vec<u32> = rec.transitions.iter().map(|t| t.3).collect();
    assert_eq!(elapsed, [1, 2, 1, 1]);
    // Stepping after the goal does nothing.
    assert_eq!(exec.step(&mut world, &mut rec).unwrap(), Status::Goal);
    assert_eq!(world.lines.len(), 7);
}

#[test]
fn choice_offers_the_next_markings_and_follows_the_pick() {
    let mut b = PlanBuilder::new("choice");
    let init = b.initial_place("init");
    let options = b.choice_of_actions(init, &["act_left_1", "act_right_1"]);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    for pick in 0..2 {
        let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
        let mut world = Log::default();
        let mut rec = Recorder {
            pick,
            ..Recorder::default()
        };
        exec.reset(&mut world, &mut rec);
        exec.step(&mut world, &mut rec).unwrap();
        assert_eq!(rec.choices.len(), 1);
        let (key, state, opts) = &rec.choices[0];
        assert_eq!(*key, PlanKey::ROOT);
        assert_eq!(state, &plan.initial_marking());
        assert_eq!(opts.len(), 2);
        for (i, o) in opts.iter().enumerate() {
            assert_eq!(
                o.get(plan_place(&plan, &format!("act_{}_1.exec", ["left", "right"][i]))),
                1
            );
            assert_eq!(o.total(), 1);
        }
        assert_eq!(exec.marking(), &opts[pick]);
        assert_eq!(world.lines, [format!("start {}", options[pick].name)]);
    }
}

fn plan_place(plan: &Plan, label: &str) -> learnpnp::net::PlaceId {
    plan.net().places_labelled(label).next().unwrap()
}

#[test]
fn transitions_enabled_by_this_step_wait_for_the_next() {
    // init -> t1 -> p -> t2 -> goal: two steps, not one.
    let mut b = PlanBuilder::new("chain");
    let init = b.initial_place("init");
    let mid = b.place("mid");
    let goal = b.goal_place();
    b.transition("t1", &[(init, 1)], &[(mid, 1)]);
    b.transition("t2", &[(mid, 1)], &[(goal, 1)]);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let mut exec = Executor::new(plan, &registry()).unwrap();
    let (status, steps) = run(&mut exec, &mut Log::default(), &mut RandomChooser::new(seeded(1)), 10);
    assert_eq!((status, steps), (Status::Goal, 2));
}

#[test]
fn non_conflicting_transitions_fire_together_and_appear_in_every_option() {
    // A choice at `c` while an unguarded tracker transition fires elsewhere.
    let mut atoms = AtomTable::new();
    let wall = atoms.intern("wall");
    let mut b = PlanBuilder::new("free");
    let c = b.initial_place("c");
    b.choice(c, 3);
    let tracker = b.tracker("wall");
    let plan = Arc::new(b.build(AllowedAtoms::Closed(&atoms)).unwrap());
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let mut world = Log {
        kb: BitKnowledgeBase::new(1),
        ..Log::default()
    };
    world.kb.set(wall, true);
    let mut rec = Recorder {
        pick: 2,
        ..Recorder::default()
    };
    exec.reset(&mut world, &mut rec);
    exec.step(&mut world, &mut rec).unwrap();
    let (_, _, opts) = &rec.choices[0];
    assert_eq!(opts.len(), 3);
    let holds = plan_place(&plan, "wall");
    assert!(opts.iter().all(|o| o.get(holds) == 1 && o.total() == 2));
    assert_eq!(exec.marking(), &opts[2]);
    let _ = tracker;
}

#[test]
fn guards_read_the_knowledge_base_and_sensing_takes_the_true_branch() {
    let atoms: AtomTable = ["ballSeen"].into_iter().collect();
    let mut b = PlanBuilder::new("sense");
    let init = b.initial_place("init");
    let sensing = b.sensing(init, "act_look_1", &["ballSeen", "not ballSeen"]);
    let seen = b.place("seen goal");
    let unseen = b.place("unseen fail");
    b.transition("", &[(sensing.outcomes[0], 1)], &[(seen, 1)]);
    b.transition("", &[(sensing.outcomes[1], 1)], &[(unseen, 1)]);
    let plan = Arc::new(b.build(AllowedAtoms::Closed(&atoms)).unwrap());
    for (truth, expected) in [(true, Status::Goal), (false, Status::Failed)] {
        let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
        let mut world = Log {
            kb: BitKnowledgeBase::new(1),
            ..Log::default()
        };
        world.kb.set(AtomId(0), truth);
        let (status, _) = run(&mut exec, &mut world, &mut RandomChooser::new(seeded(3)), 10);
        assert_eq!(status, expected);
    }
}

#[test]
fn interrupt_preempts_the_normal_end() {
    let atoms: AtomTable = ["obstacle"].into_iter().collect();
    let mut b = PlanBuilder::new("interrupt");
    let init = b.initial_place("init");
    let go = b.action(init, "act_go_5");
    let recover = b.place("recover");
    b.interrupt(&go, "obstacle", recover);
    let plan = Arc::new(b.build(AllowedAtoms::Closed(&atoms)).unwrap());
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let mut world = Log {
        kb: BitKnowledgeBase::new(1),
        ..Log::default()
    };
    let mut chooser = RandomChooser::new(seeded(0));
    exec.reset(&mut world, &mut chooser);
    exec.step(&mut world, &mut chooser).unwrap();
    exec.step(&mut world, &mut chooser).unwrap();
    world.kb.set(AtomId(0), true);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        world.lines,
        ["start act_go_5", "step act_go_5", "step act_go_5", "interrupt act_go_5"]
    );
    assert_eq!(exec.marking().get(plan_place(&plan, "recover")), 1);
}

#[test]
fn declared_internal_conditions_are_bound_and_checked() {
    let mut b = PlanBuilder::new("internal");
    let init = b.initial_place("init");
    let go = b.action(init, "act_go_5");
    let early = b.place("early goal");
    b.transition("act_go_5.end [act_go_5.begun]", &[(go.exec, 1)], &[(early, 1)]);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (status, steps) = run(&mut exec, &mut Log::default(), &mut RandomChooser::new(seeded(0)), 20);
    assert_eq!((status, steps), (Status::Goal, 2));

    let mut b = PlanBuilder::new("undeclared");
    let init = b.initial_place("init");
    let go = b.action(init, "act_go_5");
    let out = b.place("");
    b.transition("[act_go_5.blocked]", &[(go.exec, 1)], &[(out, 1)]);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let err = Executor::new(plan, &registry()).err().unwrap();
    assert!(
        matches!(err, ExecError::UndeclaredCondition { ref condition, .. } if condition == "blocked"),
        "{err}"
    );
    assert!(err.to_string().contains("begun"));
}

#[test]
fn unknown_actions_are_refused() {
    let mut b = PlanBuilder::new("unknown");
    let init = b.initial_place("init");
    b.action(init, "fly");
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let err = Executor::new(plan, &registry()).err().unwrap();
    assert!(err.to_string().contains("'fly'"), "{err}");
}

fn sub_plan(name: &str, inner: &str) -> Plan {
    let mut b = PlanBuilder::new(name);
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.action_into(init, inner, goal);
    b.build(AllowedAtoms::Open).unwrap()
}

#[test]
fn sub_plans_run_as_actions_and_report_under_their_own_key() {
    let mut reg = registry();
    let key = reg.sub_plan(Arc::new(sub_plan("fetch", "act_grab_2")));
    let mut b = PlanBuilder::new("main");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.action_into(init, "fetch", goal);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let mut exec = Executor::new(plan, &reg).unwrap();
    let mut world = Log {
        reward_per_step: 1.0,
        ..Log::default()
    };
    let mut rec = Recorder::default();
    let (status, steps) = run(&mut exec, &mut world, &mut rec, 20);
    assert_eq!(status, Status::Goal);
    // 1 start fetch; 2 (fresh sub-plan waits) sub fires: start grab; 3 grab steps;
    // 4 grab steps, sub ends grab -> sub goal; 5 main ends fetch -> goal.
    assert_eq!(steps, 5);
    assert_eq!(
        world.lines,
        [
            "start act_grab_2",
            "step act_grab_2",
            "step act_grab_2",
            "end act_grab_2"
        ]
    );
    let sub: Vec<_> = rec.transitions.iter().filter(|t| t.0 == key).collect();
    assert_eq!(sub.len(), 2);
    // The root saw: start (1 step), then the end after 4 more steps, 4 reward.
    let root: Vec<_> = rec
        .transitions
        .iter()
        .filter(|t| t.0 == PlanKey::ROOT)
        .map(|t| (t.2, t.3))
        .collect();
    assert_eq!(root, [(1.0, 1), (4.0, 4)]);
}

#[test]
fn a_higher_interrupt_preempts_the_sub_plan_and_ends_its_subtree() {
    let atoms: AtomTable = ["alarm"].into_iter().collect();
    let mut reg = registry();
    reg.sub_plan(Arc::new(sub_plan("patrol", "act_walk_9")));
    let mut b = PlanBuilder::new("main");
    let init = b.initial_place("init");
    let patrol = b.call(init, "patrol");
    let safe = b.place("safe goal");
    b.interrupt(&patrol, "alarm", safe);
    let plan = Arc::new(b.build(AllowedAtoms::Closed(&atoms)).unwrap());
    let mut exec = Executor::new(plan, &reg).unwrap();
    let mut world = Log {
        kb: BitKnowledgeBase::new(1),
        ..Log::default()
    };
    let mut chooser = RandomChooser::new(seeded(0));
    exec.reset(&mut world, &mut chooser);
    for _ in 0..3 {
        exec.step(&mut world, &mut chooser).unwrap();
    }
    world.kb.set(AtomId(0), true);
    assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Goal);
    assert_eq!(
        world.lines,
        [
            "start act_walk_9",
            "step act_walk_9",
            "step act_walk_9",
            "interrupt act_walk_9"
        ]
    );
}

#[test]
fn recursive_sub_plans_are_refused() {
    let mut reg = registry();
    reg.sub_plan(Arc::new(sub_plan("loop", "loop")));
    let plan = Arc::new(sub_plan("main", "loop"));
    let err = Executor::new(plan, &reg).err().unwrap();
    assert!(matches!(err, ExecError::RecursiveSubPlan { .. }), "{err}");
}

#[test]
fn memory_place_makes_the_markings_after_a_choice_differ() {
    // Thesis Figure 5.4: a fork on one branch leaves a memory token, a join removes it.
    let mut b = PlanBuilder::new("memory");
    let init = b.initial_place("init");
    let mem = b.memory_place("turned");
    let walk = b.action(init, "act_walk_1");
    let turn = b.action(init, "act_turn_1");
    b.produce(turn.start, mem, 1);
    let kick_from = b.place("ready");
    b.transition("", &[(walk.done, 1)], &[(kick_from, 1)]);
    b.transition("", &[(turn.done, 1)], &[(kick_from, 1)]);
    let kick = b.action(kick_from, "act_kick_1");
    let goal = b.goal_place();
    b.transition("", &[(kick.done, 1)], &[(goal, 1)]);
    let plan = Arc::new(b.build(AllowedAtoms::Open).unwrap());
    let mut kick_markings = Vec::new();
    for pick in 0..2 {
        let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
        let mut rec = Recorder {
            pick,
            ..Recorder::default()
        };
        let (status, _) = run(&mut exec, &mut Log::default(), &mut rec, 30);
        // Goal markings only constrain places labelled goal: the memory token stays.
        assert_eq!(status, Status::Goal);
        let kick_exec = plan_place(&plan, "act_kick_1.exec");
        let m = rec
            .transitions
            .iter()
            .map(|t| &t.1)
            .find(|m| m.get(kick_exec) == 1)
            .unwrap()
            .clone();
        kick_markings.push(m);
    }
    assert_ne!(kick_markings[0], kick_markings[1]);
}
