//! The semantics of plan schemas (thesis 3.1.1) as the executor runs them:
//! actions end, start and keep running; events and conditions pick a
//! constituent; higher machines preempt lower ones; final states are
//! absorbing; sub-machines learn on their own and their reward accrues to the
//! calling state.

use crate::util::{LogWorld as Log, Timed, plain_sosmc};
use std::sync::Arc;

use learnpnp::condition::{AtomId, AtomTable, BitKnowledgeBase};
use learnpnp::executor::{Chooser, ExecError, Executor, PlanKey, Registry, Status};
use learnpnp::learning::{EpisodeStart, Learner, SoSmc};
use learnpnp::net::Marking;
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::rng::seeded;
use learnpnp::schema::{DecisionProcess, parse_schema};

const ATOMS: [&str; 8] = ["go", "tick", "stop", "close", "facing", "far", "e1", "e2"];

impl Log {
    fn new() -> Self {
        Log {
            kb: BitKnowledgeBase::new(ATOMS.len()),
            lines: Vec::new(),
            reward_per_step: 1.0,
        }
    }

    fn set(&mut self, atoms: &[&str]) {
        for (i, a) in ATOMS.iter().enumerate() {
            self.kb.set(AtomId(i as u32), atoms.contains(a));
        }
    }

    fn take_lines(&mut self) -> Vec<String> {
        std::mem::take(&mut self.lines)
    }
}

fn registry() -> Registry<Log> {
    let mut r = Registry::new();
    r.family("act", &[], Timed::new);
    r.family("keep", &[], Timed::new);
    r
}

fn plan(text: &str) -> Arc<Plan> {
    let atoms: AtomTable = ATOMS.into_iter().collect();
    let schema = parse_schema(text).unwrap_or_else(|e| panic!("{e}"));
    Arc::new(
        DecisionProcess::new(&schema, AllowedAtoms::Closed(&atoms))
            .unwrap()
            .into_plan(),
    )
}

/// A chooser that records what it is told and picks the options it is given.
struct Recorder {
    plans: Vec<Plan>,
    picks: Vec<usize>,
    lines: Vec<String>,
}

impl Recorder {
    fn new(plan: &Plan, picks: &[usize]) -> Self {
        Recorder {
            plans: plan.activation_plans().into_iter().cloned().collect(),
            picks: picks.iter().rev().copied().collect(),
            lines: Vec::new(),
        }
    }

    fn name(&self, plan: PlanKey, m: &Marking) -> String {
        self.plans[usize::from(plan.0)].describe(m)
    }

    fn take_lines(&mut self) -> Vec<String> {
        std::mem::take(&mut self.lines)
    }
}

impl Chooser for Recorder {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        let names: Vec<String> = options.iter().map(|o| self.name(plan, o)).collect();
        let line = format!(
            "choose {} at {} among {}",
            plan.0,
            self.name(plan, state),
            names.join(" | ")
        );
        self.lines.push(line);
        self.picks.pop().unwrap_or(0)
    }

    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        let line = format!("{} -> {} r={reward} t={elapsed}", plan.0, self.name(plan, marking));
        self.lines.push(line);
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        let line = format!("{} starts in {}", plan.0, self.name(plan, marking));
        self.lines.push(line);
    }
}

fn lines(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn actions_not_in_the_next_state_end_new_ones_start_common_ones_keep_running() {
    let plan = plan(
        "machine m
           initial a {act_1, keep_9}
           state b {keep_9, act_2}
           final done
           a -> b on act_1.finished
           b -> done on act_2.finished",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    exec.reset(&mut world, &mut chooser);
    assert_eq!(world.take_lines(), lines(&["start act_1", "start keep_9"]));
    assert_eq!(chooser.take_lines(), lines(&["0 starts in [a]"]));

    assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Running);
    assert_eq!(
        world.take_lines(),
        lines(&["step act_1", "step keep_9", "end act_1", "start act_2"])
    );
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [a, act_1.finished, {true}] r=1 t=1", "0 -> [b] r=0 t=0"])
    );

    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(world.take_lines(), lines(&["step keep_9", "step act_2"]));
    assert!(chooser.take_lines().is_empty());

    // The final state: everything ends, the machine has finished.
    assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Goal);
    assert_eq!(
        world.take_lines(),
        lines(&["step keep_9", "step act_2", "end keep_9", "end act_2"])
    );
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [b, act_2.finished, {true}] r=2 t=2", "0 -> [done] r=0 t=0"])
    );
    // Absorbing: nothing runs, nothing changes.
    for _ in 0..3 {
        assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Goal);
    }
    assert!(world.take_lines().is_empty() && chooser.take_lines().is_empty());
    assert_eq!(exec.take_pending().reward, 0.0);
}

#[test]
fn higher_machines_preempt_lower_ones() {
    let plan = plan(
        "machine top
           initial run {Sub}
           state next {Sub}
           state out
           run -> next on go
           next -> out on stop
         machine Sub
           initial s1 {keep_9}
           state s2 {keep_9}
           s1 -> s2 on tick
           s2 -> s1 on tick",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    exec.reset(&mut world, &mut chooser);
    chooser.take_lines();
    world.take_lines();

    // Only the sub-machine's event: it follows its edge.
    world.set(&["tick"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["1 -> [s1, tick, {true}] r=1 t=1", "1 -> [s2] r=0 t=0"])
    );
    world.take_lines();
    world.set(&[]);
    exec.step(&mut world, &mut chooser).unwrap();
    world.take_lines();
    // Both machines' events: the caller follows its edge and the sub-machine,
    // which runs in both states, keeps running without following its own.
    world.set(&["go", "tick"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [run, go, {true}] r=3 t=3", "0 -> [next] r=0 t=0"])
    );
    assert_eq!(world.take_lines(), lines(&["step keep_9"]));
    // The caller has nothing to follow: the sub-machine's turn. It did not
    // sense while preempted, so `tick`, false when it last sensed, has risen.
    world.set(&["tick"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["1 -> [s2, tick, {true}] r=3 t=3", "1 -> [s1] r=0 t=0"])
    );
    world.take_lines();
    // Leaving the states that run the sub-machine ends it.
    world.set(&["stop", "tick"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [next, stop, {true}] r=2 t=2", "0 -> [out] r=0 t=0"])
    );
    assert_eq!(world.take_lines(), lines(&["step keep_9", "end keep_9"]));
    exec.step(&mut world, &mut chooser).unwrap();
    assert!(world.take_lines().is_empty() && chooser.take_lines().is_empty());
}

#[test]
fn a_sub_machine_started_in_a_step_waits_for_the_next() {
    let plan = plan(
        "machine top
           initial idle
           state run {Sub}
           idle -> run on go
         machine Sub
           initial s
           state t {keep_9}
           s -> t",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    exec.reset(&mut world, &mut chooser);
    chooser.take_lines();
    world.set(&["go"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&[
            "0 -> [idle, go, {true}] r=1 t=1",
            "1 starts in [s]",
            "0 -> [run] r=0 t=0"
        ])
    );
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["1 -> [s, -, {true}] r=1 t=1", "1 -> [t] r=0 t=0"])
    );
}

#[test]
fn when_the_event_happens_and_no_condition_holds_the_state_loops() {
    let plan = plan(
        "machine m
           initial approach {keep_9}
           state punt {keep_9}
           state side
           approach -> punt on close [facing]
           approach -> side on close [far]",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    exec.reset(&mut world, &mut chooser);
    chooser.take_lines();
    world.take_lines();
    exec.step(&mut world, &mut chooser).unwrap();
    assert!(chooser.take_lines().is_empty(), "no event, no transition");
    world.set(&["close"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(chooser.take_lines(), lines(&["0 -> [approach] r=2 t=2"]));
    assert_eq!(world.take_lines(), lines(&["step keep_9", "step keep_9"]));
    // The event happened and is over: `close` holding on is no new event.
    world.set(&["close", "facing"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert!(chooser.take_lines().is_empty(), "no new event, no transition");
    world.set(&["facing"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert!(chooser.take_lines().is_empty());
    world.set(&["close", "facing"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [approach, close, {facing}] r=3 t=3", "0 -> [punt] r=0 t=0"])
    );
    assert_eq!(world.take_lines(), lines(&["step keep_9"; 3]), "keep_9 runs on");
}

/// Thesis 3.1.3 on the football robot (`plans/football_choice.schema`): in
/// `approach`, `closeToBall` happens while neither FacingGoal nor FarFromGoal
/// holds, so its edges cannot be followed; the robot stays close to the ball.
/// Events are instantaneous: that one is over, and when `ballLost` happens the
/// robot starts again (a level-triggered `closeToBall` would block it for ever).
/// An event that held when the state was entered happened before it.
#[test]
fn football_an_event_whose_guards_fail_does_not_block_ball_lost() {
    const FOOTBALL: [&str; 6] = [
        "BallSeen",
        "closeToBall",
        "FacingGoal",
        "FarFromGoal",
        "ballLost",
        "kickTerminated",
    ];
    let atoms: AtomTable = FOOTBALL.into_iter().collect();
    let plan = Arc::new(
        learnpnp::load_plan(
            &crate::util::shipped("football_choice.schema"),
            AllowedAtoms::Closed(&atoms),
        )
        .unwrap(),
    );
    let mut registry = Registry::new();
    for action in ["TurnBody", "ScanHead", "GoToBall", "TrackBall", "PuntKick", "SideKick"] {
        registry.action(action, &[], |n| Timed::new(&format!("{n}_1000")));
    }
    let mut exec = Executor::new(Arc::clone(&plan), &registry).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    let sees = |world: &mut Log, facts: &[&str]| {
        for (i, a) in FOOTBALL.iter().enumerate() {
            world.kb.set(AtomId(i as u32), facts.contains(a));
        }
    };
    // Entering `approach` with the ball already close: no event yet.
    sees(&mut world, &["BallSeen", "closeToBall", "FacingGoal"]);
    exec.reset(&mut world, &mut chooser);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(plan.describe(exec.marking()), "[approach]");
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        plan.describe(exec.marking()),
        "[approach]",
        "closeToBall happened before approach"
    );
    // closeToBall happens with no guard holding: it loops, and is over.
    sees(&mut world, &["BallSeen"]);
    exec.step(&mut world, &mut chooser).unwrap();
    sees(&mut world, &["BallSeen", "closeToBall"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(plan.describe(exec.marking()), "[approach]");
    chooser.take_lines();
    sees(&mut world, &["closeToBall", "ballLost"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(plan.describe(exec.marking()), "[start]", "ballLost is sensed");
    // Both events at once: one is perceived, the first whose guards hold.
    let mut exec = Executor::new(Arc::clone(&plan), &registry).unwrap();
    sees(&mut world, &["BallSeen"]);
    exec.reset(&mut world, &mut chooser);
    exec.step(&mut world, &mut chooser).unwrap();
    sees(&mut world, &["BallSeen", "closeToBall", "ballLost"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        plan.describe(exec.marking()),
        "[start]",
        "closeToBall's guards fail: ballLost is the event"
    );
}

#[test]
fn the_first_event_sensed_wins_and_the_empty_event_comes_last() {
    let text = "machine m
                  initial s
                  state a
                  state b
                  state c
                  s -> c [go]
                  s -> a on e1
                  s -> b on e2";
    let plan = plan(text);
    for (facts, entered) in [
        (&["go", "e1", "e2"][..], "[a]"),
        (&["go", "e2"][..], "[b]"),
        (&["go"][..], "[c]"),
    ] {
        let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
        let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
        exec.reset(&mut world, &mut chooser);
        world.set(facts);
        exec.step(&mut world, &mut chooser).unwrap();
        assert_eq!(plan.describe(exec.marking()), entered, "{facts:?}");
    }
}

#[test]
fn a_choice_offers_the_afterstates_of_the_options() {
    let plan = plan(
        "machine m
           initial approach {keep_9}
           state punt {act_1, keep_9}
           state side {act_2, keep_9}
           approach -> punt on close [facing]
           approach -> side on close [far]",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[1]));
    exec.reset(&mut world, &mut chooser);
    chooser.take_lines();
    world.take_lines();
    world.set(&["close", "facing", "far"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&[
            "0 -> [approach, close, {facing, far}] r=1 t=1",
            "choose 0 at [approach, close, {facing, far}] among [approach, close, {facing, far}: punt] | [approach, close, {facing, far}: side]",
            "0 -> [approach, close, {facing, far}: side] r=0 t=0",
        ])
    );
    assert_eq!(world.take_lines(), lines(&["step keep_9", "start act_2"]));
    // A constituent with one plan-action is no choice.
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    world.set(&[]);
    exec.reset(&mut world, &mut chooser);
    chooser.take_lines();
    world.set(&["close", "far"]);
    exec.step(&mut world, &mut chooser).unwrap();
    assert_eq!(
        chooser.take_lines(),
        lines(&["0 -> [approach, close, {far}] r=1 t=1", "0 -> [side] r=0 t=0"])
    );
}

/// A chooser answering `InvalidChoice`-worthy indices.
struct Wild;

impl Chooser for Wild {
    fn choose(&mut self, _: PlanKey, _: &Marking, options: &[Marking]) -> usize {
        options.len()
    }
}

#[test]
fn errors_name_the_machine() {
    let p = plan("machine m\n initial s {nothing}\n");
    match Executor::new(p, &registry()) {
        Err(ExecError::UnknownAction { plan, action, .. }) => {
            assert_eq!((plan.as_str(), action.as_str()), ("m", "nothing"))
        }
        other => panic!("{:?}", other.err()),
    }
    let p = plan("machine m\n initial s {keep_9}\n state t\n s -> t on keep_9.ready\n");
    assert!(matches!(
        Executor::new(p, &registry()),
        Err(ExecError::UndeclaredCondition { .. })
    ));
    let p = plan("machine m\n initial s\n state a\n state b\n s -> a, b\n");
    let mut exec = Executor::new(p, &registry()).unwrap();
    let mut world = Log::new();
    exec.reset(&mut world, &mut Wild);
    assert!(matches!(
        exec.step(&mut world, &mut Wild),
        Err(ExecError::InvalidChoice { index: 2, count: 2, .. })
    ));
}

const HIERARCHY: &str = "machine top
  initial run {Sub}
  final done
  final lost failed
  run -> done on Sub.finished
  run -> lost on Sub.failed
machine Sub
  initial s
  state quick {act_2}
  state slow {act_5}
  final f
  s -> quick, slow
  quick -> f on act_2.finished
  slow -> f on act_5.finished";

#[test]
fn a_sub_machines_reward_accrues_to_the_calling_state() {
    let plan = plan(HIERARCHY);
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[0]));
    exec.reset(&mut world, &mut chooser);
    let mut status = Status::Running;
    while status == Status::Running {
        status = exec.step(&mut world, &mut chooser).unwrap();
    }
    assert_eq!(status, Status::Goal);
    assert_eq!(
        chooser.take_lines(),
        lines(&[
            "0 starts in [run]",
            "1 starts in [s]",
            "1 -> [s, -, {true}] r=1 t=1",
            "choose 1 at [s, -, {true}] among [s, -, {true}: quick] | [s, -, {true}: slow]",
            "1 -> [s, -, {true}: quick] r=0 t=0",
            "1 -> [quick, act_2.finished, {true}] r=2 t=2",
            "1 -> [f] r=0 t=0",
            // The caller's state collected the four steps, the sub-machine's three included.
            "0 -> [run, Sub.finished, {true}] r=4 t=4",
            "0 -> [done] r=0 t=0",
        ])
    );
}

#[test]
fn each_machine_learns_on_its_own() {
    // Every step costs 1: in the sub-machine the quick action (2 steps) beats
    // the slow one (5 steps). The sub-machine's values are its own (plan key
    // 1), learned from the reward it collected; the root has no choice.
    let plan = plan(HIERARCHY);
    let config = plain_sosmc(10);
    let mut learner = SoSmc::new(config, seeded(3));
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let mut world = Log::new();
    world.reward_per_step = -1.0;
    for _ in 0..40 {
        learner.begin_episode(EpisodeStart::LEARN);
        exec.reset(&mut world, &mut learner);
        while exec.step(&mut world, &mut learner).unwrap() == Status::Running {}
        learner.end_episode(exec.take_pending());
    }
    let keys: Vec<(u16, String, f64)> = learner
        .values()
        .entries()
        .map(|(k, v, _)| {
            (
                k.plan.0,
                plan.activation_plans()[usize::from(k.plan.0)].describe(&k.marking),
                v,
            )
        })
        .collect();
    assert!(keys.iter().all(|(p, _, _)| *p == 1), "{keys:?}");
    let value = |name: &str| keys.iter().find(|(_, n, _)| n == name).map(|k| k.2).unwrap();
    // R_post-o in the sub-machine: the rest of the quick (2 steps) or slow (5 steps) action.
    assert_eq!(value("[s, -, {true}: quick]"), -2.0);
    assert_eq!(value("[s, -, {true}: slow]"), -5.0);
}

#[test]
fn a_failed_sub_machine_is_sensed_by_its_caller() {
    let plan = plan(
        "machine top
           initial run {Sub}
           final done
           final lost failed
           run -> done on Sub.finished
           run -> lost on Sub.failed
         machine Sub
           initial s {keep_9}
           final bad failed
           s -> bad on stop",
    );
    let mut exec = Executor::new(Arc::clone(&plan), &registry()).unwrap();
    let (mut world, mut chooser) = (Log::new(), Recorder::new(&plan, &[]));
    exec.reset(&mut world, &mut chooser);
    world.set(&["stop"]);
    assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Running);
    assert_eq!(exec.step(&mut world, &mut chooser).unwrap(), Status::Failed);
    assert_eq!(plan.describe(exec.marking()), "[lost]");
}
