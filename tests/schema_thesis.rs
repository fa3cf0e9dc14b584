//! The thesis's chapter 3 on plan schemas: the football robot's construction
//! (Figures 3.1 - 3.5), the penalty kick's non-Markovian reward (Figures 3.6
//! and 3.7), and a schema learning exactly as the equivalent Petri Net Plan.

use crate::util::{plain_sosmc, shipped};
use std::sync::Arc;

use learnpnp::condition::{Expr, parse_condition};
use learnpnp::domains::Task;
use learnpnp::domains::parr_russell::{self, ParrRussell, ParrRussellConfig};
use learnpnp::domains::penalty_kick::{PenaltyKick, PenaltyKickConfig};
use learnpnp::executor::PlanKey;
use learnpnp::experiment::defaults::default_learner;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::learning::{EpisodeMode, Exploration, Learner, Schedule, Scope, SoSmc, Target, TdConfig, TdLearner};
use learnpnp::net::{Marking, PlaceId};
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::plan_file::load_plan;
use learnpnp::rng::{derive_seed, seeded};
use learnpnp::schema::{
    DecisionProcess, DecisionState, MachineProcess, ProcessTransition, condition_constituents, parse_schema,
    read_schema,
};

fn process(name: &str) -> DecisionProcess {
    DecisionProcess::new(
        &read_schema(&shipped(&format!("{name}.schema"))).unwrap(),
        AllowedAtoms::Open,
    )
    .unwrap()
}

fn atoms(names: &[&str]) -> Vec<Expr> {
    names.iter().map(|n| parse_condition(n).unwrap()).collect()
}

/// The process state of `mp` whose name is `label`.
fn state(mp: &MachineProcess, label: &str) -> usize {
    (0..mp.states().len())
        .find(|&i| mp.label(i) == label)
        .unwrap_or_else(|| panic!("no state {label}"))
}

#[test]
fn figure_3_4_constituents_of_close_to_ball() {
    // C_cnd({GoToBall, TrackBall}, closeToBall) with FacingGoal and FarFromGoal:
    // only FacingGoal, only FarFromGoal, both; "none holds" is the loop.
    let (masks, loops) = condition_constituents(&atoms(&["FacingGoal", "FarFromGoal"]), Some("closeToBall")).unwrap();
    assert_eq!(masks, [0b01, 0b10, 0b11]);
    assert!(loops);

    let p = process("football_choice");
    let mp = &p.machines()[0];
    let approach = mp.machine().state_named("approach").unwrap();
    assert_eq!(mp.machine().states()[approach].actions, ["GoToBall", "TrackBall"]);
    let group = mp
        .groups(approach)
        .iter()
        .find(|g| g.event.as_deref() == Some("closeToBall"))
        .unwrap();
    assert_eq!(group.conditions, atoms(&["FacingGoal", "FarFromGoal"]));
    let names: Vec<&str> = group.constituents.iter().map(|c| mp.label(c.state)).collect();
    assert_eq!(
        names,
        [
            "[approach, closeToBall, {FacingGoal}]",
            "[approach, closeToBall, {FarFromGoal}]",
            "[approach, closeToBall, {FacingGoal, FarFromGoal}]",
        ]
    );
    assert!(group.loops);
}

#[test]
fn figure_3_5_the_choice_point_as_a_process() {
    // Figure 3.4: the choice point of Figure 3.2 on its own.
    let schema = parse_schema(
        "machine choice_point
           initial approach {GoToBall, TrackBall}
           state punt {PuntKick, TrackBall}
           state side {SideKick, TrackBall}
           approach -> punt on closeToBall [FacingGoal]
           approach -> side on closeToBall [FarFromGoal]",
    )
    .unwrap();
    let p = DecisionProcess::new(&schema, AllowedAtoms::Open).unwrap();
    let mp = &p.machines()[0];
    let (approach, punt, side) = (0, 1, 2);
    let fg = state(mp, "[approach, closeToBall, {FacingGoal}]");
    let ffg = state(mp, "[approach, closeToBall, {FarFromGoal}]");
    let both = state(mp, "[approach, closeToBall, {FacingGoal, FarFromGoal}]");

    // The states of Figure 3.5 (b): three action states (first and last
    // layer) and three constituent states (the middle layer).
    let action_states: Vec<usize> = (0..mp.states().len())
        .filter(|&i| matches!(mp.states()[i], DecisionState::Action { .. }))
        .collect();
    assert_eq!(action_states, [approach, punt, side]);
    let mut constituents: Vec<usize> = (0..mp.states().len())
        .filter(|&i| matches!(mp.states()[i], DecisionState::Constituent { .. }))
        .collect();
    constituents.sort_unstable();
    assert_eq!(constituents, [fg, ffg, both]);

    // Its edges: closeToBall from the action state to each constituent, the
    // loop when none holds (Figure 3.5 (a)), then one plan-action per enabled
    // action node, two from the state where both hold.
    let edges: Vec<(usize, usize, &str)> = mp
        .transitions()
        .into_iter()
        .map(|t| match t {
            ProcessTransition::Event { state, group, to } => {
                assert_eq!(mp.groups(state)[group].event.as_deref(), Some("closeToBall"));
                (state, to, "event")
            }
            ProcessTransition::Loop { state, .. } => (state, state, "loop"),
            ProcessTransition::PlanAction { from, action } => (from, action.target, "plan-action"),
        })
        .collect();
    assert_eq!(
        edges,
        [
            (approach, fg, "event"),
            (approach, ffg, "event"),
            (approach, both, "event"),
            (approach, approach, "loop"),
            (fg, punt, "plan-action"),
            (ffg, side, "plan-action"),
            (both, punt, "plan-action"),
            (both, side, "plan-action"),
        ]
    );
    let choices: Vec<usize> = mp.choice_states().map(|c| c.state).collect();
    assert_eq!(choices, [both]);
    let counts = mp.counts();
    assert_eq!((counts.action_states, counts.constituent_states), (3, 3));
    assert_eq!((counts.events, counts.loops, counts.plan_actions), (3, 1, 4));
    assert_eq!((counts.choice_states, counts.options), (1, 2));
}

#[test]
fn figure_3_1_an_if_statement_is_no_choice() {
    // The leftmost state: [BallSeen] and [not BallSeen] exclude each other, so
    // exactly one holds: two constituents, no loop, nothing to learn.
    let p = process("football");
    let mp = &p.machines()[0];
    let start = mp.machine().state_named("start").unwrap();
    assert!(mp.machine().states()[start].actions.is_empty());
    let groups = mp.groups(start);
    assert_eq!(groups.len(), 1);
    assert_eq!(groups[0].event, None);
    assert_eq!(groups[0].constituents.len(), 2);
    assert!(!groups[0].loops);
    assert_eq!(mp.choice_states().count(), 0);
    for c in &groups[0].constituents {
        assert_eq!(c.plan_actions.len(), 1);
    }
}

#[test]
fn figure_3_3_kick_is_a_machine_with_the_choice() {
    let p = process("football");
    assert_eq!(p.machines().len(), 2);
    let top = &p.machines()[0];
    let kick = top.machine().state_named("kick").unwrap();
    let called: Vec<Option<usize>> = top
        .state_actions(kick)
        .iter()
        .map(|&a| top.actions()[a].machine)
        .collect();
    assert_eq!(called, [Some(1), None], "Kick is machine 1, TrackBall primitive");
    let sub = &p.machines()[1];
    assert_eq!(sub.name(), "Kick");
    // The choice between the kicks moved into the sub-machine.
    let choices: Vec<&str> = sub.choice_states().map(|c| sub.label(c.state)).collect();
    assert_eq!(choices, ["[choose, -, {FacingGoal, FarFromGoal}]"]);
    // ballLost ends the procedure from either kick.
    for name in ["punt", "side"] {
        let s = sub.machine().state_named(name).unwrap();
        let events: Vec<&str> = sub.groups(s).iter().filter_map(|g| g.event.as_deref()).collect();
        assert_eq!(events, ["kickTerminated", "ballLost"]);
    }
}

/// A penalty-kick run of `schema` with `learner`, after `episodes` learning
/// episodes: the values of the two options of the first choice and the greedy return.
fn kick(schema: &str, learner: Box<dyn Learner>, episodes: usize) -> (f64, f64, f64) {
    let plan = Arc::new(load_plan(&shipped(&format!("{schema}.schema")), AllowedAtoms::Open).unwrap());
    let mut task = PenaltyKick::new(PenaltyKickConfig::default(), Arc::clone(&plan), learner).unwrap();
    for _ in 0..episodes {
        task.episode(EpisodeMode::Learn).unwrap();
    }
    let value = |label: &str| {
        let place = plan
            .net()
            .places_labelled(label)
            .next()
            .unwrap_or_else(|| panic!("{label}"));
        let mut m = Marking::empty(plan.net().places().len());
        m.set(place, 1);
        task.learners()[0].values().value_of(PlanKey::ROOT, &m)
    };
    let walk = value("[start, -, {true}: walk]");
    let turn = value("[start, -, {true}: turn]");
    let greedy = task.greedy_score(10).unwrap();
    (walk, turn, greedy)
}

fn one_step_q_learning(seed: u64) -> Box<dyn Learner> {
    let config = TdConfig {
        gamma: 1.0,
        alpha: 0.02,
        lambda: 0.0,
        target: Target::Max,
        scope: Scope::Markings,
        exploration: Exploration::EpsilonGreedy(Schedule::constant(1.0)),
        initial_value: 0.0,
        consistent: false,
    };
    Box::new(TdLearner::new(config, seeded(seed)))
}

const SEEDS: u64 = 10;

#[test]
fn figure_3_6_one_step_q_learning_values_both_first_choices_equally() {
    // Q-learning on every state of the process, behaving uniformly at random
    // (it learns off-policy, and neither option's value lags behind): both
    // options lead, through states without reward, to the one Kick state,
    // whose value averages scoring (10) and missing (0). With a step size of
    // 0.02 over 2000 episodes the noise of an estimate is about 0.1 (measured:
    // the largest difference over these seeds is 0.19), against the 10 that
    // separates the options' true values.
    let mut walk_wins = 0;
    for seed in 0..SEEDS {
        let (walk, turn, greedy) = kick("penalty_kick", one_step_q_learning(seed), 2000);
        assert!((walk - turn).abs() < 0.5, "seed {seed}: walk {walk}, turn {turn}");
        for v in [walk, turn] {
            assert!((v - 5.0).abs() < 1.5, "seed {seed}: {v} is not the average of 10 and 0");
        }
        walk_wins += u32::from(greedy == 10.0);
    }
    // The greedy policy is a coin toss between the two.
    assert!(
        (1..SEEDS as u32).contains(&walk_wins),
        "WalkStraight greedy in {walk_wins} of {SEEDS} runs"
    );
}

#[test]
fn figure_3_6_sosmc_learns_to_walk_straight() {
    // First-visit returns credit each option with what followed it.
    let config = plain_sosmc(20);
    for seed in 0..SEEDS {
        let (walk, turn, greedy) = kick("penalty_kick", Box::new(SoSmc::new(config, seeded(seed))), 100);
        assert_eq!((walk, turn), (10.0, 0.0), "seed {seed}");
        assert_eq!(greedy, 10.0, "seed {seed}");
    }
}

#[test]
fn figure_3_7_the_restructured_schema_lets_q_learning_learn() {
    for seed in 0..SEEDS {
        let (walk, turn, greedy) = kick("penalty_kick_restructured", one_step_q_learning(seed), 2000);
        assert!(walk > 9.0 && turn < 1.0, "seed {seed}: walk {walk}, turn {turn}");
        assert_eq!(greedy, 10.0, "seed {seed}");
    }
}

/// The greedy move (index into the moves) in each of the four observations
/// (wall west, wall east), and every episode's return.
fn grid_run(
    plan: Plan,
    options: impl Fn(bool, bool) -> Vec<Marking>,
    algorithm: Algorithm,
    seed: u64,
) -> (Vec<usize>, Vec<f64>) {
    let domain = DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    };
    let learner = default_learner(algorithm, &domain).build(seeded(derive_seed(seed, 1)));
    let plan = Arc::new(plan);
    let mut task = ParrRussell::new(
        ParrRussellConfig::default(),
        plan,
        learner,
        seeded(derive_seed(seed, 2)),
    )
    .unwrap();
    let returns: Vec<f64> = (0..600)
        .map(|_| task.episode(EpisodeMode::Learn).unwrap().ret)
        .collect();
    let values = task.learners()[0].values();
    let policy = [(false, false), (false, true), (true, false), (true, true)]
        .into_iter()
        .map(|(west, east)| {
            let v: Vec<f64> = options(west, east)
                .iter()
                .map(|m| values.value_of(PlanKey::ROOT, m))
                .collect();
            (0..v.len()).fold(0, |best, i| if v[i] > v[best] { i } else { best })
        })
        .collect();
    (policy, returns)
}

const MOVES: [&str; 4] = ["MoveNorth", "MoveSouth", "MoveEast", "MoveWest"];

#[test]
fn a_schema_and_the_equivalent_plan_learn_the_same_policy_with_the_same_seed() {
    // Parr and Russell's grid: plans/parr_russell.pnml (Figure 6.2) and
    // plans/parr_russell.schema offer the same four moves in the same four
    // observations, in the same order; with the same seeds every decision
    // and every move's outcome coincide.
    let net_plan = || parr_russell::default_plan().unwrap();
    let net_options = |west: bool, east: bool| -> Vec<Marking> {
        let plan = net_plan();
        let net = plan.net();
        let marked = |label: &str| net.places_labelled(label).next().unwrap();
        MOVES
            .iter()
            .map(|m| {
                let mut k = Marking::empty(net.places().len());
                k.set(marked(if west { "WallLeft" } else { "not_WallLeft" }), 1);
                k.set(marked(if east { "WallRight" } else { "not_WallRight" }), 1);
                k.set(marked(&format!("{m}.exec")), 1);
                k
            })
            .collect()
    };
    let atoms = parr_russell::atoms();
    let schema_plan = || load_plan(&shipped("parr_russell.schema"), AllowedAtoms::Closed(&atoms)).unwrap();
    let schema_options = |west: bool, east: bool| -> Vec<Marking> {
        let plan = schema_plan();
        let observation = format!(
            "{}, {}",
            if west { "WallLeft" } else { "not WallLeft" },
            if east { "WallRight" } else { "not WallRight" }
        );
        ["north", "south", "east", "west"]
            .iter()
            .map(|m| {
                let label = format!("[choose, -, {{{observation}}}: {m}]");
                let place = plan
                    .net()
                    .places_labelled(&label)
                    .next()
                    .unwrap_or_else(|| panic!("{label}"));
                let mut k = Marking::empty(plan.net().places().len());
                k.set(PlaceId::new(place.index()), 1);
                k
            })
            .collect()
    };
    for algorithm in [Algorithm::EpsSosmc, Algorithm::SarsaLambda] {
        for seed in 0..3 {
            let (net_policy, net_returns) = grid_run(net_plan(), net_options, algorithm, seed);
            let (schema_policy, schema_returns) = grid_run(schema_plan(), schema_options, algorithm, seed);
            assert_eq!(
                net_returns, schema_returns,
                "{algorithm:?}, seed {seed}: the runs differ"
            );
            assert_eq!(net_policy, schema_policy, "{algorithm:?}, seed {seed}");
        }
    }
}

/// The penalty kick's schema variants (`--variant schema`, `schema-restructured`,
/// the `reproduce 3.6 / 3.7` presets) are the shipped schema files.
#[test]
fn the_kick_schema_variants_are_the_shipped_files() {
    use learnpnp::domains::penalty_kick::{self, Variant};
    use learnpnp::learning::persist::PlanLabels;
    for (variant, file) in [
        (Variant::Schema, "penalty_kick.schema"),
        (Variant::SchemaRestructured, "penalty_kick_restructured.schema"),
    ] {
        let built = penalty_kick::plan(variant).unwrap();
        let shipped = learnpnp::load_plan(&crate::util::shipped(file), learnpnp::AllowedAtoms::Open).unwrap();
        assert!(built.schema_process().is_some(), "{file}: a schema's process");
        assert_eq!(PlanLabels::of(&built), PlanLabels::of(&shipped), "{file}");
    }
}
