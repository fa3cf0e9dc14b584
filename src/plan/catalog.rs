//! The thesis's example plans, built with the operators (shipped as PNML in `plans/`).
//!
//! Each function returns the net; `tests/shipped_plans.rs` keeps the files in
//! `plans/` identical to these definitions.

use crate::net::{NetError, PetriNet};

use super::PlanBuilder;

/// Every catalogued plan with the file stem it ships under.
pub fn all() -> Result<Vec<(&'static str, PetriNet)>, NetError> {
    Ok(vec![
        ("football", football()?),
        ("choice_point", choice_point()?),
        ("penalty_kick_plain", penalty_kick_plain()?),
        ("penalty_kick_tree", penalty_kick_tree()?),
        ("penalty_kick_memory", penalty_kick_memory()?),
        ("loop_counter", loop_counter()?),
        ("environment_tracking", environment_tracking()?),
        ("parr_russell", parr_russell()?),
        ("sutton", sutton()?),
        ("keepaway_pass", keepaway_pass()?),
        ("keepaway_position", keepaway_position()?),
    ])
}

/// Figure 2.6: a football-playing robot. A sensing action tells whether the
/// ball is seen; each branch forks two parallel actions and joins them; the kick
/// ends normally or is interrupted when the ball is lost. No goal: it runs forever.
pub fn football() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("football");
    let start = b.initial_place("start");
    let look = b.sensing(start, "SeeBall", &["ballSeen", "not ballSeen"]);

    // Ball seen: approach it while tracking it, then kick.
    let branches = b.fork(look.outcomes[0], 2);
    let approach = b.action(branches[0], "GoToBall");
    let track = b.action(branches[1], "TrackBall");
    let near = b.join(&[approach.done, track.done]);
    let kick = b.action_into(near, "Kick", start);
    b.interrupt(&kick, "ballLost", start);

    // Ball not seen: turn the body and scan with the head until it is seen.
    let branches = b.fork(look.outcomes[1], 2);
    let turn = b.action(branches[0], "TurnBody");
    let scan = b.action(branches[1], "ScanHead");
    let found = b.join(&[turn.done, scan.done]);
    b.transition("back", &[(found, 1)], &[(start, 1)]);
    b.build_net()
}

/// Figure 5.1: a non-deterministic choice between two ordinary actions.
pub(crate) fn choice_point() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("choice_point");
    let start = b.initial_place("start");
    let goal = b.goal_place();
    b.action_into(start, "ActionA", goal);
    b.action_into(start, "ActionB", goal);
    b.build_net()
}

/// Figure 3.6: the penalty kick, plain. Both choices lead to the same Kick
/// marking, so one-step methods cannot tell them apart.
pub(crate) fn penalty_kick_plain() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("penalty_kick_plain");
    let start = b.initial_place("start");
    let ready = b.place("ready");
    b.action_into(start, "WalkStraight", ready);
    b.action_into(start, "Turn", ready);
    let goal = b.goal_place();
    b.action_into(ready, "Kick", goal);
    b.build_net()
}

/// Figure 5.3: the penalty kick as a tree: Kick is duplicated after each choice
/// (two execution places of one action), so the markings at Kick differ.
pub fn penalty_kick_tree() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("penalty_kick_tree");
    let start = b.initial_place("start");
    let goal = b.goal_place();
    let walk = b.action(start, "WalkStraight");
    b.action_into(walk.done, "Kick", goal);
    let turn = b.action(start, "Turn");
    b.action_into(turn.done, "Kick", goal);
    b.build_net()
}

/// Figure 5.4: the penalty kick with memory. Each choice's start also forks a
/// token into a memory place recording it, so the markings at Kick differ
/// without duplicating Kick; after the kick a join per branch removes the
/// memory token before the goal. (Two complementary memory places let the joins
/// stay deterministic: PNP has no inhibitor arcs to test an empty place.)
pub fn penalty_kick_memory() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("penalty_kick_memory");
    let start = b.initial_place("start");
    let ready = b.place("ready");
    let walked = b.memory_place("walked");
    let turned = b.memory_place("turned");
    let walk = b.action_into(start, "WalkStraight", ready);
    b.produce(walk.start, walked, 1);
    let turn = b.action_into(start, "Turn", ready);
    b.produce(turn.start, turned, 1);
    let kick = b.action(ready, "Kick");
    let goal = b.goal_place();
    b.transition("join", &[(kick.done, 1), (walked, 1)], &[(goal, 1)]);
    b.transition("join", &[(kick.done, 1), (turned, 1)], &[(goal, 1)]);
    b.build_net()
}

/// Figure 5.7: counting loop passes. A maze of binary junctions: at each
/// junction choose Left or Right; every pass adds a token to `passes`, so each
/// junction has its own marking (and value) without one place per junction.
/// The counter is unbounded by design.
pub fn loop_counter() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("loop_counter");
    let junction = b.initial_place("junction");
    let passes = b.memory_place("passes");
    let moved = b.place("moved");
    b.action_into(junction, "Left", moved);
    b.action_into(junction, "Right", moved);
    let next = b.transition("[not atExit]", &[(moved, 1)], &[(junction, 1)]);
    b.produce(next, passes, 1);
    let goal = b.goal_place();
    b.transition("[atExit]", &[(moved, 1)], &[(goal, 1)]);
    b.build_net()
}

/// Figure 5.9: four actions in a domain of two binary variables. A separate
/// environment-tracking part follows `x` and `y`; the procedural part has one
/// choice among the four actions, and each observation gives its own marking.
/// The plan begins with one step in which the trackers settle.
pub(crate) fn environment_tracking() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("environment_tracking");
    b.tracker("x");
    b.tracker("y");
    let choose = settle_then(&mut b, "choose");
    let acted = b.place("acted");
    for name in ["Action1", "Action2", "Action3", "Action4"] {
        b.action_into(choose, name, acted);
    }
    b.transition("[not done]", &[(acted, 1)], &[(choose, 1)]);
    let goal = b.goal_place();
    b.transition("[done]", &[(acted, 1)], &[(goal, 1)]);
    b.build_net()
}

/// The place `label`, reached from the initial place `start` by one transition:
/// environment trackers start in their `not_` place and settle during that
/// first step, so the first choice already sees the true observation.
fn settle_then(b: &mut PlanBuilder, label: &str) -> super::PlaceRef {
    let start = b.initial_place("start");
    let place = b.place(label);
    b.transition("begin", &[(start, 1)], &[(place, 1)]);
    place
}

/// The four moves of the grid worlds, in plan order.
pub(crate) const MOVES: [&str; 4] = ["MoveNorth", "MoveSouth", "MoveEast", "MoveWest"];

/// Figure 6.2: Parr and Russell's grid. An environment-tracking part follows
/// `WallLeft` and `WallRight`; the procedural part chooses one of four moves,
/// loops until `Terminal` holds, then reaches the goal.
pub fn parr_russell() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("parr_russell");
    b.tracker("WallLeft");
    b.tracker("WallRight");
    let choose = settle_then(&mut b, "choose");
    let moved = b.place("moved");
    for name in MOVES {
        b.action_into(choose, name, moved);
    }
    b.transition("[not Terminal]", &[(moved, 1)], &[(choose, 1)]);
    let goal = b.goal_place();
    b.transition("[Terminal]", &[(moved, 1)], &[(goal, 1)]);
    b.build_net()
}

/// The eight neighbour atoms of Sutton's grid, clockwise from north.
pub(crate) const NEIGHBOURS: [&str; 8] = [
    "BlockedN",
    "BlockedNE",
    "BlockedE",
    "BlockedSE",
    "BlockedS",
    "BlockedSW",
    "BlockedW",
    "BlockedNW",
];

/// Sutton's grid (thesis 6.4): eight trackers for the neighbouring cells and a
/// choice among the moves that do not run into an obstacle (each start is
/// guarded by its direction's neighbour being free).
pub fn sutton() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("sutton");
    for atom in NEIGHBOURS {
        b.tracker(atom);
    }
    let choose = settle_then(&mut b, "choose");
    let moved = b.place("moved");
    for (name, blocked) in MOVES.iter().zip(["BlockedN", "BlockedS", "BlockedE", "BlockedW"]) {
        b.guarded_action_into(choose, name, &format!("not {blocked}"), moved);
    }
    b.transition("[not AtGoal]", &[(moved, 1)], &[(choose, 1)]);
    let goal = b.goal_place();
    b.transition("[AtGoal]", &[(moved, 1)], &[(goal, 1)]);
    b.build_net()
}

/// The procedural part of thesis Figure 7.2 around `decide`: with the ball,
/// `ball` is marked; otherwise the keeper fastest to the ball intercepts and
/// the others support (through `support`). Every action ends back in `decide`.
fn keeper_procedure(b: &mut PlanBuilder, decide: super::PlaceRef, ball: super::PlaceRef, support: super::PlaceRef) {
    b.transition("[HasBall]", &[(decide, 1)], &[(ball, 1)]);
    let chase = b.place("chase");
    b.transition("[and (not HasBall) Fastest]", &[(decide, 1)], &[(chase, 1)]);
    b.action_into(chase, "Intercept", decide);
    b.transition("[and (not HasBall) (not Fastest)]", &[(decide, 1)], &[(support, 1)]);
}

/// The keeper decisions of the pass plan, in plan order.
pub(crate) const KEEPER_DECISIONS: [&str; 3] = ["Hold", "Pass1", "Pass2"];

/// Keepaway, learning the pass decision (thesis 7.2): the procedural part of
/// Figure 7.2 with a choice among Hold, Pass1 and Pass2 when the keeper has the
/// ball, and an environment-tracking part for the three binary features (the
/// lanes to the two teammates and the closest taker: 8 observations).
pub fn keepaway_pass() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("keepaway_pass");
    for atom in ["Lane1Open", "Lane2Open", "TakerFar"] {
        b.tracker(atom);
    }
    let decide = settle_then(&mut b, "decide");
    let ball = b.place("ball");
    let support = b.place("support");
    keeper_procedure(&mut b, decide, ball, support);
    for name in KEEPER_DECISIONS {
        b.action_into(ball, name, decide);
    }
    b.action_into(support, "GetOpen", decide);
    b.build_net()
}

/// The nine positioning points of thesis Figure 7.4, in plan order.
pub(crate) const POSITIONS: [&str; 9] = [
    "Corner1", "Corner2", "Corner3", "Corner4", "Centre", "Middle1", "Middle2", "Middle3", "Middle4",
];

/// Keepaway, learning where to stand (thesis 7.3): at the start of an episode
/// the keeper chooses one of nine points, recorded by a token in a memory
/// place `at<point>` (no state information); whenever it supports it goes to
/// that point. With the ball it follows the thesis's simple policy: hold while
/// the closest taker is far, else pass to the teammate with the safest lane.
pub fn keepaway_position() -> Result<PetriNet, NetError> {
    let mut b = PlanBuilder::new("keepaway_position");
    let start = b.initial_place("start");
    let decide = b.place("decide");
    let ball = b.place("ball");
    let support = b.place("support");
    for point in POSITIONS {
        let at = b.memory_place(format!("at{point}"));
        b.transition(format!("choose{point}"), &[(start, 1)], &[(at, 1), (decide, 1)]);
        let name = format!("GoTo{point}");
        let exec = b.place(format!("{name}.exec"));
        b.transition(format!("{name}.start"), &[(support, 1), (at, 1)], &[(exec, 1), (at, 1)]);
        b.transition(format!("{name}.end"), &[(exec, 1)], &[(decide, 1)]);
    }
    keeper_procedure(&mut b, decide, ball, support);
    let hold_exec = b.place("Hold.exec");
    b.transition("Hold.start [TakerFar]", &[(ball, 1)], &[(hold_exec, 1)]);
    b.transition("Hold.end", &[(hold_exec, 1)], &[(decide, 1)]);
    let pass_exec = b.place("PassSafest.exec");
    b.transition("PassSafest.start [not TakerFar]", &[(ball, 1)], &[(pass_exec, 1)]);
    b.transition("PassSafest.end", &[(pass_exec, 1)], &[(decide, 1)]);
    b.build_net()
}
