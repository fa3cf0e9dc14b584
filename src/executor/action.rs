//! What the executor runs: actions in a world that answers conditions and pays rewards.

use crate::condition::KnowledgeBase;

/// The world as a plan's executor sees it: a knowledge base to ask, and the
/// reward collected since it was last asked.
pub trait World: KnowledgeBase {
    /// The reward collected since the previous call (the executor asks once per step).
    fn take_reward(&mut self) -> f64 {
        0.0
    }
}

/// A durative action of a plan.
///
/// The executor calls the lifecycle functions when transitions carrying them
/// fire, calls [`Action::step`] once per executor step while the action's
/// execution place is marked, and asks [`Action::finished`] / [`Action::failed`]
/// / [`Action::condition`] for the guards that wait on it.
pub trait Action<W>: Send {
    /// A new episode begins: forget any state from the previous one.
    fn reset(&mut self) {}
    /// The action starts.
    fn start(&mut self, _world: &mut W) {}
    /// One executor step while the action runs.
    fn step(&mut self, _world: &mut W) {}
    /// The action ends normally.
    fn end(&mut self, _world: &mut W) {}
    /// The action is interrupted.
    fn interrupt(&mut self, _world: &mut W) {}
    /// The action resumes after an interrupt.
    fn resume(&mut self, _world: &mut W) {}
    /// The action is ended as failed.
    fn fail(&mut self, _world: &mut W) {}
    /// Whether it has finished (the implicit wait of `A.end`).
    fn finished(&self, world: &W) -> bool;
    /// Whether it has failed (the implicit wait of `A.fail`).
    fn failed(&self, _world: &W) -> bool {
        false
    }
    /// Declared internal condition number `index` (in the order given at registration).
    fn condition(&self, _index: usize, _world: &W) -> bool {
        false
    }
}

/// An action that acts once, in its first step, and is then finished (a grid
/// move, a choice, a reward paid): `act` runs on the world in that step.
pub struct OneStep<F> {
    act: F,
    done: bool,
}

impl<F> OneStep<F> {
    /// The action running `act` in its first step.
    pub fn new(act: F) -> Self {
        OneStep { act, done: false }
    }
}

impl<W, F: FnMut(&mut W) + Send> Action<W> for OneStep<F> {
    fn reset(&mut self) {
        self.done = false;
    }
    fn start(&mut self, _: &mut W) {
        self.done = false;
    }
    fn step(&mut self, world: &mut W) {
        if !self.done {
            (self.act)(world);
            self.done = true;
        }
    }
    fn finished(&self, _: &W) -> bool {
        self.done
    }
}
