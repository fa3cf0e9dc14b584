//! A keeper driven by a plan, with a learner at its choice points.

use std::sync::Arc;

use crate::analysis::option_label;
use crate::executor::{Chooser, ExecError, Executor, PlanKey, Registry};
use crate::learning::{EpisodeStart, Learner};
use crate::net::Marking;
use crate::plan::Plan;
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::features::FeatureThresholds;
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::rcg::{ChoiceNote, KeeperNote, OptionNote};
use learnpnp_keepaway::view::PlayerView;

use super::world::KeeperWorld;

/// Most executor steps a keeper takes in one cycle before it must have acted.
/// A decision needs about four (end the last action, read the situation, choose,
/// act); a plan that thinks longer without acting sends no command that cycle.
pub const MAX_STEPS_PER_CYCLE: u32 = 16;

/// A keeper executing a plan: each cycle it perceives, then steps its plan
/// until an action has issued the cycle's command.
pub struct PlanKeeper {
    plan: Arc<Plan>,
    executor: Executor<KeeperWorld>,
    learner: Box<dyn Learner>,
    world: KeeperWorld,
    idle_cycles: u64,
    /// Whether choices are noted for [`PlanKeeper::note`] (off: it costs time).
    noting: bool,
    /// The cycle being played.
    cycle: u32,
    /// The last choice of the root plan this episode, while noting.
    last_choice: Option<ChoiceNote>,
    /// The actions that issued the last command, while noting.
    acting: String,
}

/// A learner whose root-plan choices are written down: the options, named by
/// their transitions, with their values when the choice was made.
struct Noting<'a> {
    learner: &'a mut dyn Learner,
    plan: &'a Plan,
    cycle: u32,
    last: &'a mut Option<ChoiceNote>,
}

impl Chooser for Noting<'_> {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        let chosen = self.learner.choose(plan, state, options);
        if plan == PlanKey::ROOT {
            let values = self.learner.values();
            *self.last = Some(ChoiceNote {
                cycle: self.cycle,
                at: self.plan.describe(state),
                options: options
                    .iter()
                    .map(|next| OptionNote {
                        name: option_label(self.plan, state, next),
                        value: values.value_of(plan, next),
                        visits: values.find(plan, next).map_or(0, |id| values.visits(id)),
                    })
                    .collect(),
                chosen,
            });
        }
        chosen
    }

    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        self.learner.transition(plan, marking, reward, elapsed);
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        self.learner.plan_started(plan, marking);
    }
}

impl PlanKeeper {
    /// A keeper running `plan` with actions from `registry` and `learner` at its choices.
    pub fn new(
        plan: Arc<Plan>,
        registry: &Registry<KeeperWorld>,
        learner: Box<dyn Learner>,
        config: KeepawayConfig,
        thresholds: FeatureThresholds,
    ) -> Result<Self, ExecError> {
        Ok(PlanKeeper {
            executor: Executor::new(Arc::clone(&plan), registry)?,
            plan,
            learner,
            world: KeeperWorld::new(config, thresholds),
            idle_cycles: 0,
            noting: false,
            cycle: 0,
            last_choice: None,
            acting: String::new(),
        })
    }

    /// A new episode: the learner is told, the plan restarts.
    pub fn begin_episode(&mut self, start: EpisodeStart) {
        self.learner.begin_episode(start);
        self.last_choice = None;
        self.acting.clear();
        self.world.reset();
        self.executor.reset(&mut self.world, self.learner.as_mut());
    }

    /// One cycle: perceive `view` (crediting `elapsed_seconds` of reward), think
    /// until an action issues a command, and return it.
    pub fn act(&mut self, view: PlayerView, elapsed_seconds: f64) -> Result<Command, ExecError> {
        self.cycle = view.cycle;
        self.acting.clear();
        self.world.perceive(view, elapsed_seconds);
        for _ in 0..MAX_STEPS_PER_CYCLE {
            if self.noting {
                // Actions act at the start of a step: those marked now issue its command.
                let acting = self.running_actions();
                let mut chooser = Noting {
                    learner: self.learner.as_mut(),
                    plan: &self.plan,
                    cycle: self.cycle,
                    last: &mut self.last_choice,
                };
                self.executor.step(&mut self.world, &mut chooser)?;
                if self.world.command().is_some() {
                    self.acting = acting;
                }
            } else {
                self.executor.step(&mut self.world, self.learner.as_mut())?;
            }
            if self.world.command().is_some() {
                break;
            }
        }
        Ok(self.world.command().unwrap_or_else(|| {
            self.idle_cycles += 1;
            Command::None
        }))
    }

    /// The episode is over: the learner gets the reward after the last marking change.
    pub fn end_episode(&mut self) {
        self.learner.end_episode(self.executor.take_pending());
    }

    /// The learner.
    pub fn learner(&self) -> &dyn Learner {
        self.learner.as_ref()
    }

    /// Starts or stops noting choices for [`PlanKeeper::note`].
    pub(crate) fn set_noting(&mut self, on: bool) {
        self.noting = on;
        self.last_choice = None;
    }

    /// The actions whose execution places are marked, joined by `, `.
    fn running_actions(&self) -> String {
        let plan = self.executor.plan();
        let names: Vec<&str> = self
            .executor
            .marking()
            .marked()
            .filter_map(|(p, _)| plan.exec_action(p))
            .map(|a| plan.action(a).name.as_str())
            .fold(Vec::new(), |mut names, name| {
                if !names.contains(&name) {
                    names.push(name);
                }
                names
            });
        names.join(", ")
    }

    /// What this keeper (uniform number `keeper`) did in the last cycle while
    /// noting: the actions that issued its command (`-` for none), and its
    /// last choice this episode.
    pub(crate) fn note(&self, keeper: u8) -> KeeperNote {
        KeeperNote {
            keeper,
            action: if self.acting.is_empty() {
                "-".to_string()
            } else {
                self.acting.clone()
            },
            choice: self.last_choice.clone(),
        }
    }

    /// Cycles in which the plan issued no command (a sign of a plan that never acts).
    pub fn idle_cycles(&self) -> u64 {
        self.idle_cycles
    }
}
