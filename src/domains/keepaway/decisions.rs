//! Keepaway with the pass decisions of some keepers taken from outside: the
//! environment behind the Python `KeepawayPassEnv` (one decider) and the
//! three-keeper PettingZoo environment (three).
//!
//! Every keeper plays the framework's keeper (`keeper_command`: intercept, get
//! open, hold or pass when the ball is kickable, a pass kicked to its end);
//! the deciding keepers' choice among hold and the two passes, asked whenever
//! the ball is kickable for them outside a pass, comes from the caller, the
//! other keepers' from a fixed policy. Play stops at such a decision and
//! resumes, in the same cycle, when the caller answers: a step is the time
//! until the next decision (a semi-Markov decision, as in Stone, Sutton and
//! Kuhlmann's keepaway). Each cycle is the simulator's [`Game`] cycle, the one
//! [`KeepawayTask`](super::KeepawayTask) plays, so a caller that answers as a
//! fixed policy would plays the episodes of that policy's `keepaway-fixed` run.

use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::game::{Cycle, Game};
use learnpnp_keepaway::keeper::{KeeperAction, KeeperMemory, KeeperPolicy, keeper_command};
use learnpnp_keepaway::params::{ConfigError, KeepawayConfig};
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::state_vars::StateVars;
use learnpnp_keepaway::view::PlayerView;
use learnpnp_keepaway::world::NUM_KEEPERS;

use super::task::RunSeeds;
use crate::rng::SimRng;

/// A keeper's decision to make: who, and the 13 state variables it sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decision {
    /// The keeper (0, 1 or 2).
    pub keeper: usize,
    /// Stone, Sutton and Kuhlmann's 13 state variables, from the keeper's view
    /// (distances in metres, angles in degrees).
    pub state: [f64; 13],
    /// What the framework's hand-coded policy would choose here.
    pub handcoded: KeeperAction,
}

/// Where play stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// A keeper must decide.
    Decide(Decision),
    /// The episode ended, after this many seconds in all.
    Ended {
        /// The episode's duration.
        seconds: f64,
    },
}

/// How an episode started.
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// Its first decision.
    pub decision: Decision,
    /// The seconds played before it.
    pub seconds_before: f64,
    /// The durations of the episodes that ended before any decision (played
    /// through and discarded, in order).
    pub skipped: Vec<f64>,
}

/// A cycle stopped in its keepers' stage: the game's cycle and the keepers'
/// commands decided so far.
#[derive(Clone, Copy)]
struct Paused {
    cycle: Cycle,
    keepers: [Command; NUM_KEEPERS],
    next_keeper: usize,
}

/// A keeper policy that answers with a given action, or notes that it was
/// asked (a probe: the answer is then discarded).
struct Asked {
    answer: Option<KeeperAction>,
    asked: Option<Decision>,
    keeper: usize,
}

impl KeeperPolicy for Asked {
    fn decide(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> KeeperAction {
        if let Some(answer) = self.answer {
            return answer;
        }
        // Without the state variables (too little seen) the framework's
        // policies hold; so does a decider, without being asked.
        if let Some(state) = StateVars::from_view(view) {
            self.asked = Some(Decision {
                keeper: self.keeper,
                state: state.to_array(),
                handcoded: BaselinePolicy::HandCoded.decide(view, cfg),
            });
        }
        KeeperAction::Hold
    }
}

/// Keepaway 3 vs 2 paused at the deciding keepers' decisions.
pub struct PassDecisions {
    game: Game,
    deciders: usize,
    others: BaselinePolicy,
    keepers: [KeeperMemory; NUM_KEEPERS],
    paused: Option<Paused>,
    cycles_since_stop: u32,
}

impl PassDecisions {
    /// Keepers `0..deciders` decide from outside, the others by `others`; the
    /// simulator and `others` draw from the seeds of `rng` as a Keepaway
    /// run's task does ([`RunSeeds`]).
    pub fn new(
        config: KeepawayConfig,
        deciders: usize,
        others: impl FnOnce(u64) -> BaselinePolicy,
        mut rng: SimRng,
    ) -> Result<Self, ConfigError> {
        let seeds = RunSeeds::draw(&mut rng);
        Ok(PassDecisions {
            game: Game::new(config, seeds.simulator)?,
            deciders: deciders.min(NUM_KEEPERS),
            others: others(seeds.fixed_policy),
            keepers: [KeeperMemory::default(); NUM_KEEPERS],
            paused: None,
            cycles_since_stop: 0,
        })
    }

    /// The simulator's configuration.
    pub fn config(&self) -> &KeepawayConfig {
        self.game.simulator().config()
    }

    /// Starts a new episode and plays to its first decision (episodes that end
    /// before any decision are played through and listed).
    pub fn reset(&mut self) -> Start {
        let mut skipped = Vec::new();
        loop {
            self.game.reset();
            self.keepers = [KeeperMemory::default(); NUM_KEEPERS];
            self.paused = None;
            self.cycles_since_stop = 0;
            match self.play(None) {
                Stop::Decide(decision) => {
                    return Start {
                        decision,
                        seconds_before: self.take_seconds(),
                        skipped,
                    };
                }
                Stop::Ended { seconds } => skipped.push(seconds),
            }
        }
    }

    /// Answers the pending decision with `action` and plays to the next
    /// decision or the episode's end; also returns the seconds played since
    /// the previous stop. Without a pending decision (after the end), plays
    /// nothing and returns the end again.
    pub fn step(&mut self, action: KeeperAction) -> (Stop, f64) {
        if self.paused.is_none() {
            return (
                Stop::Ended {
                    seconds: self.game.simulator().episode_seconds(),
                },
                0.0,
            );
        }
        let stop = self.play(Some(action));
        (stop, self.take_seconds())
    }

    /// The seconds played since the previous stop, counted from now on anew.
    fn take_seconds(&mut self) -> f64 {
        f64::from(std::mem::take(&mut self.cycles_since_stop)) * self.config().server.cycle_seconds
    }

    /// Plays cycles until a decision or the episode's end; `answer` completes
    /// the decision the current cycle stopped at.
    fn play(&mut self, mut answer: Option<KeeperAction>) -> Stop {
        let cfg = *self.config();
        loop {
            let mut paused = self.paused.take().unwrap_or_else(|| Paused {
                cycle: self.game.views(),
                keepers: [Command::None; NUM_KEEPERS],
                next_keeper: 0,
            });
            while paused.next_keeper < NUM_KEEPERS {
                let k = paused.next_keeper;
                let view = &paused.cycle.views[k];
                paused.keepers[k] = if k < self.deciders {
                    let mut memory = self.keepers[k];
                    let mut policy = Asked {
                        answer: answer.take(),
                        asked: None,
                        keeper: k,
                    };
                    let command = keeper_command(view, &cfg, &mut memory, &mut policy);
                    if let Some(decision) = policy.asked {
                        self.paused = Some(paused);
                        return Stop::Decide(decision);
                    }
                    self.keepers[k] = memory;
                    command
                } else {
                    keeper_command(view, &cfg, &mut self.keepers[k], &mut self.others)
                };
                paused.next_keeper += 1;
            }
            let commands = self.game.commands(paused.cycle, paused.keepers);
            self.cycles_since_stop += 1;
            if self.game.step(&commands).is_some() {
                return Stop::Ended {
                    seconds: self.game.simulator().episode_seconds(),
                };
            }
        }
    }
}
