//! Choice points: places whose output transitions can be executable together.

use crate::util::looking;
use learnpnp::analysis::{ChoicePoint, choice_points, explore, structural_choice_points};
use learnpnp::net::{PlaceId, TransitionId};
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder};

fn build(b: PlanBuilder) -> Plan {
    b.build(AllowedAtoms::Open).expect("test plan builds")
}

fn reachable(plan: &Plan) -> Vec<ChoicePoint> {
    choice_points(plan, &explore(plan, 1_000))
}

fn ids(ts: &[usize]) -> Vec<TransitionId> {
    ts.iter().copied().map(TransitionId::new).collect()
}

#[test]
fn the_choice_operator_is_a_choice_point() {
    let mut b = PlanBuilder::new("choice");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    for (i, out) in b.choice(init, 3).into_iter().enumerate() {
        b.action_into(out, &format!("A{i}"), goal);
    }
    let plan = build(b);
    let expected = vec![ChoicePoint {
        place: PlaceId::new(0),
        options: ids(&[0, 1, 2]),
    }];
    assert_eq!(reachable(&plan), expected);
    assert_eq!(structural_choice_points(&plan), expected);
}

#[test]
fn a_sensing_action_with_complementary_guards_is_no_choice_point() {
    let (mut b, exec, goal) = looking("sensing");
    b.transition("look.end [ballSeen]", &[(exec, 1)], &[(goal, 1)]);
    b.transition("look.end [not ballSeen]", &[(exec, 1)], &[(goal, 1)]);
    let plan = build(b);
    assert!(reachable(&plan).is_empty());
    assert!(structural_choice_points(&plan).is_empty());
}

#[test]
fn guards_that_can_hold_together_make_a_choice_point() {
    let mut b = PlanBuilder::new("overlap");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.transition("[a]", &[(init, 1)], &[(goal, 1)]);
    b.transition("[b]", &[(init, 1)], &[(goal, 1)]);
    b.transition("[and (not a) (not b)]", &[(init, 1)], &[(goal, 1)]);
    let plan = build(b);
    // [a] and [b] overlap; the third excludes both.
    assert_eq!(
        reachable(&plan),
        [ChoicePoint {
            place: PlaceId::new(0),
            options: ids(&[0, 1])
        }]
    );
}

#[test]
fn an_end_next_to_a_possible_interrupt_is_a_choice_point() {
    // `A.finished` and `obstacle` are independent: both may hold in one step.
    let mut b = PlanBuilder::new("interrupt");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    let a = b.action_into(init, "A", goal);
    b.transition("A.interrupt [obstacle]", &[(a.exec, 1)], &[(init, 1)]);
    let plan = build(b);
    let found = reachable(&plan);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].place, PlaceId::new(2));
}

#[test]
fn enough_tokens_for_both_is_no_choice_in_the_reachable_markings() {
    // Two tokens: both transitions fire together, nothing is chosen. The
    // structural variant cannot know that.
    let mut b = PlanBuilder::new("two_tokens");
    let init = b.initial_place("init");
    b.set_tokens(init, 2);
    let left = b.place("left");
    let right = b.place("right");
    b.transition("go_left", &[(init, 1)], &[(left, 1)]);
    b.transition("go_right", &[(init, 1)], &[(right, 1)]);
    b.transition("back", &[(left, 1), (right, 1)], &[(init, 2)]);
    let plan = build(b);
    let structural = structural_choice_points(&plan);
    assert_eq!(structural.len(), 1);
    // After one token left, a single token remains: then they compete.
    assert_eq!(reachable(&plan), structural);

    // Self-loops keep both tokens in place: the two never compete.
    let mut b = PlanBuilder::new("always_two");
    let init = b.initial_place("init");
    b.set_tokens(init, 2);
    b.transition("tick", &[(init, 1)], &[(init, 1)]);
    b.transition("tock", &[(init, 1)], &[(init, 1)]);
    let plan = build(b);
    assert!(reachable(&plan).is_empty());
    assert_eq!(structural_choice_points(&plan).len(), 1);
}

#[test]
fn a_place_that_is_never_marked_is_only_a_structural_choice_point() {
    let mut b = PlanBuilder::new("unmarked");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.transition("go", &[(init, 1)], &[(goal, 1)]);
    let island = b.place("island");
    b.choice(island, 2);
    let plan = build(b);
    assert!(reachable(&plan).is_empty());
    assert_eq!(structural_choice_points(&plan).len(), 1);
}
