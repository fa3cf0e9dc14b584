//! Keepaway for Python RL: the simulator paused at the deciding keepers' pass
//! decisions (`learnpnp::domains::keepaway::PassDecisions`), one game or a
//! batch stepped in one call.

use learnpnp::domains::keepaway::{Decision, FixedPolicy, KeepawayDomainConfig, KeepawayMode, PassDecisions, Stop};
use learnpnp::experiment::runner::run_task_rng;
use learnpnp::named::Named;
use learnpnp_keepaway::{KeepawayConfig, KeeperAction, ServerTimer, VisionMode};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::value_error;

/// The state variables per decision.
const STATE_VARS: usize = 13;

/// The settings a game is made from.
#[derive(Clone, Copy)]
struct Settings {
    config: KeepawayConfig,
    deciders: usize,
    others: FixedPolicy,
}

impl Settings {
    fn new(
        deciders: usize,
        vision: &str,
        others: &str,
        field_length: f64,
        field_width: f64,
        server_timer: &str,
    ) -> PyResult<Self> {
        if !(1..=3).contains(&deciders) {
            return Err(value_error(format!("deciders {deciders}: it must be 1, 2 or 3")));
        }
        let mut config = KeepawayConfig {
            vision: VisionMode::from_name(vision).map_err(value_error)?,
            timer: ServerTimer::from_name(server_timer).map_err(value_error)?,
            ..KeepawayConfig::default()
        };
        config.region.length = field_length;
        config.region.width = field_width;
        config.validate().map_err(value_error)?;
        Ok(Settings {
            config,
            deciders,
            others: FixedPolicy::from_name(others).map_err(value_error)?,
        })
    }

    /// The game of run `run` of an experiment of base seed `seed`.
    fn game(&self, seed: u64, run: usize) -> PyResult<PassDecisions> {
        let others = KeepawayDomainConfig::for_mode(KeepawayMode::Fixed(self.others));
        PassDecisions::new(
            self.config,
            self.deciders,
            |s| others.baseline(s),
            run_task_rng(seed, run),
        )
        .map_err(value_error)
    }
}

fn action(index: i64) -> PyResult<KeeperAction> {
    usize::try_from(index)
        .ok()
        .and_then(KeeperAction::from_index)
        .ok_or_else(|| {
            value_error(format!(
                "action {index}: it must be 0 (hold), 1 (pass to the nearest teammate) or 2 (the second nearest)"
            ))
        })
}

type DecisionTuple = (usize, [f64; STATE_VARS], usize);

fn decision_tuple(d: &Decision) -> DecisionTuple {
    (d.keeper, d.state, d.handcoded.index())
}

/// One Keepaway 3 vs 2 game paused at pass decisions (the core of
/// `learnpnp.envs.KeepawayPassEnv` and `KeepawayAECEnv`).
///
/// `KeepawayGame(deciders, seed, vision, others, field_length, field_width,
/// server_timer)`: keepers `0..deciders` decide from outside, the others play
/// the fixed policy `others` (`handcoded`, `threshold`, `always-hold`,
/// `random`); `server_timer` (`real-time` or `synchronous`) is `learnpnp
/// experiment --server-timer`. Seed `s` plays run 0 of a `learnpnp
/// experiment` of base seed `s`.
#[pyclass(module = "learnpnp")]
pub struct KeepawayGame {
    settings: Settings,
    game: PassDecisions,
}

#[pymethods]
impl KeepawayGame {
    #[new]
    #[pyo3(signature = (deciders = 1, seed = 0, vision = "framework", others = "handcoded", field_length = 20.0, field_width = 20.0, server_timer = "real-time"))]
    fn new(
        deciders: usize,
        seed: u64,
        vision: &str,
        others: &str,
        field_length: f64,
        field_width: f64,
        server_timer: &str,
    ) -> PyResult<Self> {
        let settings = Settings::new(deciders, vision, others, field_length, field_width, server_timer)?;
        Ok(KeepawayGame {
            game: settings.game(seed, 0)?,
            settings,
        })
    }

    /// Starts the game anew from `seed` (the same episodes as a new game of that seed).
    fn reseed(&mut self, seed: u64) -> PyResult<()> {
        self.game = self.settings.game(seed, 0)?;
        Ok(())
    }

    /// Starts an episode: `((keeper, state, handcoded), seconds_before, skipped)`,
    /// the first decision, the seconds played before it, and the durations of
    /// episodes that ended before any decision.
    fn reset(&mut self) -> (DecisionTuple, f64, Vec<f64>) {
        let start = self.game.reset();
        (decision_tuple(&start.decision), start.seconds_before, start.skipped)
    }

    /// Plays `decisions` decisions in Rust alone, each answered with the
    /// hand-coded choice, new episodes started as they end: the in-process
    /// speed a Python loop is measured against. Returns the episodes ended.
    fn play_handcoded(&mut self, py: Python<'_>, decisions: u64) -> u64 {
        py.detach(|| {
            let mut decision = self.game.reset().decision;
            let mut episodes = 0;
            for _ in 0..decisions {
                match self.game.step(decision.handcoded).0 {
                    Stop::Decide(next) => decision = next,
                    Stop::Ended { .. } => {
                        episodes += 1;
                        decision = self.game.reset().decision;
                    }
                }
            }
            episodes
        })
    }

    /// Answers the pending decision with `action` (0 hold, 1 and 2 the
    /// passes): `(decision or None at the end, seconds since the previous
    /// decision, the episode's duration or None while it goes on)`.
    fn step(&mut self, action_index: i64) -> PyResult<(Option<DecisionTuple>, f64, Option<f64>)> {
        let (stop, seconds) = self.game.step(action(action_index)?);
        Ok(match stop {
            Stop::Decide(d) => (Some(decision_tuple(&d)), seconds, None),
            Stop::Ended { seconds: total } => (None, seconds, Some(total)),
        })
    }
}

/// N games of one decider stepped together (the core of
/// `learnpnp.envs.KeepawayVectorEnv`): game i plays run i of a `learnpnp
/// experiment` of base seed `seed`; the options are `KeepawayGame`'s. Arrays
/// cross as bytes (numpy reads them without a copy): states as float32 N x 13,
/// actions as int64.
#[pyclass(module = "learnpnp")]
pub struct KeepawayBatch {
    settings: Settings,
    games: Vec<PassDecisions>,
    ended: Vec<bool>,
    pending: Vec<Decision>,
}

impl KeepawayBatch {
    fn states(&self) -> Vec<f32> {
        self.pending.iter().flat_map(|d| d.state.map(|v| v as f32)).collect()
    }
}

#[pymethods]
impl KeepawayBatch {
    #[new]
    #[pyo3(signature = (n, seed = 0, vision = "framework", others = "handcoded", field_length = 20.0, field_width = 20.0, server_timer = "real-time"))]
    fn new(
        n: usize,
        seed: u64,
        vision: &str,
        others: &str,
        field_length: f64,
        field_width: f64,
        server_timer: &str,
    ) -> PyResult<Self> {
        if n == 0 {
            return Err(value_error("a batch needs at least one game"));
        }
        let settings = Settings::new(1, vision, others, field_length, field_width, server_timer)?;
        let games = (0..n).map(|i| settings.game(seed, i)).collect::<PyResult<Vec<_>>>()?;
        Ok(KeepawayBatch {
            settings,
            ended: vec![false; n],
            pending: Vec::with_capacity(n),
            games,
        })
    }

    /// Restarts every game from `seed`.
    fn reseed(&mut self, seed: u64) -> PyResult<()> {
        self.games = (0..self.games.len())
            .map(|i| self.settings.game(seed, i))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(())
    }

    /// Starts an episode in every game: `(states, handcoded)`, the states as
    /// bytes of float32 N x 13 and the hand-coded policy's choices.
    fn reset<'py>(&mut self, py: Python<'py>) -> (Bound<'py, PyBytes>, Vec<usize>) {
        self.pending = self.games.iter_mut().map(|g| g.reset().decision).collect();
        self.ended.iter_mut().for_each(|e| *e = false);
        let handcoded = self.pending.iter().map(|d| d.handcoded.index()).collect();
        (PyBytes::new(py, &f32_bytes(&self.states())), handcoded)
    }

    /// Answers every game's decision with `actions` (bytes of int64, one per
    /// game) and plays each to its next decision. A game whose episode ended
    /// at the previous step starts a new one instead (its action ignored,
    /// reward 0: gymnasium's next-step autoreset). Returns `(states, rewards,
    /// terminated, handcoded, durations)`: durations hold an ended episode's
    /// length, 0 elsewhere.
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: &[u8],
    ) -> PyResult<(Bound<'py, PyBytes>, Vec<f64>, Vec<bool>, Vec<usize>, Vec<f64>)> {
        let n = self.games.len();
        if actions.len() != n * 8 {
            return Err(value_error(format!(
                "{} bytes of actions for {n} games: it must be {}",
                actions.len(),
                n * 8
            )));
        }
        let indices: Vec<i64> = actions
            .chunks_exact(8)
            .map(|c| i64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect();
        let chosen = indices.iter().map(|&i| action(i)).collect::<PyResult<Vec<_>>>()?;
        let (mut rewards, mut terminated, mut durations) = (vec![0.0; n], vec![false; n], vec![0.0; n]);
        py.detach(|| {
            for i in 0..n {
                if self.ended[i] {
                    self.pending[i] = self.games[i].reset().decision;
                    self.ended[i] = false;
                    continue;
                }
                let (stop, seconds) = self.games[i].step(chosen[i]);
                rewards[i] = seconds;
                if let Stop::Ended { seconds: total } = stop {
                    terminated[i] = true;
                    durations[i] = total;
                    self.ended[i] = true;
                } else if let Stop::Decide(d) = stop {
                    self.pending[i] = d;
                }
            }
        });
        let handcoded = self.pending.iter().map(|d| d.handcoded.index()).collect();
        // A game that ended keeps its last decision's state as its final observation.
        Ok((
            PyBytes::new(py, &f32_bytes(&self.states())),
            rewards,
            terminated,
            handcoded,
            durations,
        ))
    }
}

/// The bytes of `values` in native endianness, as numpy's float32 reads them.
fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_ne_bytes()).collect()
}
