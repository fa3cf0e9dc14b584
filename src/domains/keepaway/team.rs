//! The keepers of an episode, whoever decides for them: the [`KeeperTeam`]
//! interface, and [`LocalTeam`], plan-driven and fixed-policy keepers in this
//! process. Keeper processes behind shared memory implement the same interface
//! (`RemoteTeam`, in the simulator process of the `learnpnp-system` crate), so
//! both run the same episode loop.

use std::sync::Arc;

use super::agent::PlanKeeper;
use super::config::{KeepawayDomainConfig, KeepawayMode};
use crate::domains::TaskError;
use crate::learning::{EpisodeStart, Learner, StateKey};
use crate::plan::{Plan, catalog};
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::keeper::{KeeperMemory, keeper_command};
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::rcg::KeeperNote;
use learnpnp_keepaway::view::PlayerView;
use learnpnp_keepaway::world::NUM_KEEPERS;

/// The keepers' answer for one cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TeamStep {
    /// Keeper k's command at index k.
    Commands([Command; NUM_KEEPERS]),
    /// The episode cannot go on (a keeper was lost); it is discarded and played again.
    Aborted,
}

/// Who decides the keepers' commands in an episode.
pub trait KeeperTeam {
    /// A new episode begins; the learners are told how it is to be run.
    fn begin_episode(&mut self, start: EpisodeStart) -> Result<(), TaskError>;

    /// The commands for the cycle in which keeper k sees `views[k]`; each
    /// keeper is first credited `seconds_per_cycle` of reward (the time
    /// elapsed). `meanwhile` is the simulator's own work for the cycle (the
    /// takers' decisions), which does not depend on the keepers', in steps:
    /// each call does one and says whether more remain. The team runs them all,
    /// while its keepers think when they think elsewhere (between its polls
    /// for their commands); only a cycle that is not played skips them.
    fn act(
        &mut self,
        views: &[PlayerView; NUM_KEEPERS],
        seconds_per_cycle: f64,
        meanwhile: &mut dyn FnMut() -> bool,
    ) -> Result<TeamStep, TaskError>;

    /// The episode is over after `cycles` cycles: the learners update. Returns
    /// whether the first learning keeper's episode was exploratory.
    fn end_episode(&mut self, cycles: u32) -> Result<bool, TaskError>;

    /// Named values followed through a run (empty where the learners are elsewhere).
    fn traced_values(&self) -> Vec<(String, f64)>;

    /// The learners in this process.
    fn learners(&self) -> Vec<&dyn Learner>;

    /// Cycles in which a plan-driven keeper issued no command, over the run.
    fn idle_cycles(&self) -> u64;

    /// Starts or stops noting what the plan-driven keepers decide, for
    /// [`KeeperTeam::notes`] (off by default: it costs time). A team that
    /// cannot see its keepers' decisions ignores it.
    fn set_noting(&mut self, _on: bool) {}

    /// What each keeper is doing, at index k for keeper k: its current action
    /// and last choice. `None` where the team cannot know it (fixed-policy
    /// keepers, keepers in other processes).
    fn notes(&self) -> [Option<KeeperNote>; NUM_KEEPERS] {
        Default::default()
    }
}

/// The keepers in this process: the learning keepers execute the plan, the
/// others follow the mode's fixed policy (one policy object shared by them).
pub struct LocalTeam {
    sim_config: KeepawayConfig,
    keepers: Vec<PlanKeeper>,
    fixed: BaselinePolicy,
    memories: [KeeperMemory; NUM_KEEPERS],
    traced: Vec<(String, usize, StateKey)>,
}

impl LocalTeam {
    /// The team of `config`: `plan` drives the learning keepers (each with a
    /// learner from `learner`, called with the keeper's index); `fixed` decides
    /// for the others.
    pub fn new(
        config: &KeepawayDomainConfig,
        plan: Option<Arc<Plan>>,
        learner: &mut dyn FnMut(usize) -> Box<dyn Learner>,
        fixed: BaselinePolicy,
    ) -> Result<Self, TaskError> {
        let sim_config = config.simulator();
        let mut keepers = Vec::new();
        let mut traced = Vec::new();
        if let Some(plan) = plan.filter(|_| config.learning_keepers() > 0) {
            let registry = super::actions::registry(&sim_config);
            for k in 0..config.learning_keepers() {
                keepers.push(PlanKeeper::new(
                    Arc::clone(&plan),
                    &registry,
                    learner(k),
                    sim_config,
                    config.thresholds,
                )?);
                if config.mode == KeepawayMode::Position {
                    traced.extend(position_traces(&plan, k));
                }
            }
        }
        Ok(LocalTeam {
            sim_config,
            keepers,
            fixed,
            memories: [KeeperMemory::default(); NUM_KEEPERS],
            traced,
        })
    }
}

/// The values traced in the positioning experiment: keeper k's value of
/// standing at each of the thesis's points.
fn position_traces(plan: &Plan, k: usize) -> impl Iterator<Item = (String, usize, StateKey)> + '_ {
    catalog::POSITIONS.iter().filter_map(move |point| {
        let at = format!("at{point}");
        crate::domains::task::root_key(plan, &[&at, "decide"]).map(|key| (format!("keeper{}/{point}", k + 1), k, key))
    })
}

impl KeeperTeam for LocalTeam {
    fn begin_episode(&mut self, start: EpisodeStart) -> Result<(), TaskError> {
        self.memories = [KeeperMemory::default(); NUM_KEEPERS];
        for k in &mut self.keepers {
            k.begin_episode(start);
        }
        Ok(())
    }

    fn act(
        &mut self,
        views: &[PlayerView; NUM_KEEPERS],
        seconds_per_cycle: f64,
        meanwhile: &mut dyn FnMut() -> bool,
    ) -> Result<TeamStep, TaskError> {
        let mut commands = [Command::None; NUM_KEEPERS];
        for (k, (command, view)) in commands.iter_mut().zip(views).enumerate() {
            *command = match self.keepers.get_mut(k) {
                Some(keeper) => keeper.act(*view, seconds_per_cycle)?,
                None => keeper_command(view, &self.sim_config, &mut self.memories[k], &mut self.fixed),
            };
        }
        while meanwhile() {}
        Ok(TeamStep::Commands(commands))
    }

    fn end_episode(&mut self, _cycles: u32) -> Result<bool, TaskError> {
        for k in &mut self.keepers {
            k.end_episode();
        }
        Ok(self.keepers.first().is_some_and(|k| k.learner().exploratory()))
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        self.traced
            .iter()
            .map(|(name, k, key)| {
                (
                    name.clone(),
                    self.keepers[*k].learner().values().value_of(key.plan, &key.marking),
                )
            })
            .collect()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        self.keepers.iter().map(|k| k.learner()).collect()
    }

    fn idle_cycles(&self) -> u64 {
        self.keepers.iter().map(PlanKeeper::idle_cycles).sum()
    }

    fn set_noting(&mut self, on: bool) {
        for k in &mut self.keepers {
            k.set_noting(on);
        }
    }

    fn notes(&self) -> [Option<KeeperNote>; NUM_KEEPERS] {
        let mut notes: [Option<KeeperNote>; NUM_KEEPERS] = Default::default();
        for (k, (slot, keeper)) in notes.iter_mut().zip(&self.keepers).enumerate() {
            *slot = Some(keeper.note(k as u8 + 1));
        }
        notes
    }
}
