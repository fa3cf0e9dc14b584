//! The k best plans of a planner merged into one Petri Net Plan whose choice
//! points are where they differ.
//!
//! The plans are merged by their common prefixes (a trie of actions): from
//! the initial place, the plans' first actions are the options of a choice
//! point, each option the start of its action (`move_a_b.start`); after an
//! action, the plans that went on alike share it, and they part again where
//! their next actions differ. Where one plan ends and another goes on, the
//! option of ending is the transition `finish`. Every plan ends in the one
//! goal place.
//!
//! Tails are not shared: two plans that reach the same action sequence after
//! different prefixes keep their own copies, because a plan file says what
//! was done, not the state it left, and only a shared state makes a shared
//! tail safe. So the paths of the merged plan from `init` to `goal` are
//! exactly the input plans (duplicates merged), and the learner's marking
//! says which prefix it followed.

use super::{GenerateError, GeneratedPlan, PlanStep};
use crate::plan::PlaceRef;

/// A node of the trie: the plans ending here, and the branches going on.
#[derive(Debug, Default)]
struct Node {
    ends: bool,
    next: Vec<(PlanStep, Node)>,
}

impl Node {
    fn insert(&mut self, steps: &[PlanStep]) {
        let Some((first, rest)) = steps.split_first() else {
            self.ends = true;
            return;
        };
        let i = self.next.iter().position(|(s, _)| s == first).unwrap_or_else(|| {
            self.next.push((first.clone(), Node::default()));
            self.next.len() - 1
        });
        self.next[i].1.insert(rest);
    }
}

impl GeneratedPlan {
    /// The plans merged by their common prefixes (duplicates merged, order of
    /// first appearance kept for the options). One plan gives its sequence.
    pub fn merged(name: &str, plans: &[Vec<PlanStep>]) -> Result<Self, GenerateError> {
        if plans.is_empty() {
            return Err(GenerateError::NoPlans);
        }
        let mut root = Node::default();
        for p in plans {
            root.insert(p);
        }
        let mut plan = GeneratedPlan::new(name);
        let init = plan.init;
        plan.grow(init, &root);
        Ok(plan)
    }

    /// The branches of `node` from place `at`.
    fn grow(&mut self, at: PlaceRef, node: &Node) {
        let goal = self.goal;
        if node.ends {
            self.builder.transition("finish", &[(at, 1)], &[(goal, 1)]);
        }
        for (step, child) in &node.next {
            if child.next.is_empty() {
                self.step(at, step, Some(goal), true);
            } else {
                let after = self.step(at, step, None, true);
                self.grow(after, child);
            }
        }
    }
}
