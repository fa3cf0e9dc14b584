//! `learnpnp-corridor`: a trivial world in its own process, written in Rust
//! on `learnpnp_system::multiprocess::world_host`, for tests and for
//! measuring the generic path's cost. Each agent walks its own corridor of
//! `LENGTH` cells from the first: `forward` or `back`, -1 a step until it is
//! at the end; the episode terminates when every agent is there, and is cut
//! short after `STEP_LIMIT` steps. Started by `learnpnp-supervisor
//! --world-cmd learnpnp-corridor --plan plans/corridor.pnml`.
//!
//! `learnpnp-corridor --answer-ms MIN-MAX` plays a robot that answers each
//! step in MIN to MAX milliseconds (uniform, seeded by the run's seed): in
//! real time the world's log ends with the cycle it kept (cycles, seconds,
//! rate, late cycles), which is how the cadence is measured against a robot.

use std::process::ExitCode;
use std::time::Duration;

use learnpnp_system::ipc::world::{ActionStatus, Vocabulary};
use learnpnp_system::multiprocess::world_host::{Observation, ServedWorld, StepResult, serve};

/// Cells of a corridor.
const LENGTH: u32 = 5;

/// Steps after which an episode is cut short.
const STEP_LIMIT: u32 = 30;

/// Action indices.
const FORWARD: usize = 0;

/// Every agent's corridor.
#[derive(Debug, Default)]
struct Corridors {
    positions: Vec<u32>,
    steps: u32,
    /// A robot's answer time, if it plays one.
    answer: Option<AnswerTime>,
}

/// A robot's answer time: uniform in `min..=max` milliseconds (xorshift64*).
#[derive(Debug)]
struct AnswerTime {
    min: u64,
    max: u64,
    state: u64,
}

impl AnswerTime {
    /// Parses `MIN-MAX` (milliseconds).
    fn parse(text: &str) -> Result<Self, String> {
        let bad = || format!("--answer-ms: '{text}' is not MIN-MAX in milliseconds (e.g. 5-20)");
        let (min, max) = text.split_once('-').ok_or_else(bad)?;
        let (min, max): (u64, u64) = (min.parse().map_err(|_| bad())?, max.parse().map_err(|_| bad())?);
        if min > max || max > 60_000 {
            return Err(bad());
        }
        Ok(AnswerTime { min, max, state: 1 })
    }

    /// The next answer time.
    fn draw(&mut self) -> Duration {
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        let r = self.state.wrapping_mul(0x2545_F491_4F6C_DD1D);
        Duration::from_millis(self.min + r % (self.max - self.min + 1))
    }
}

impl Corridors {
    fn at_end(&self, agent: usize) -> bool {
        self.positions[agent] + 1 == LENGTH
    }
}

impl ServedWorld for Corridors {
    fn vocabulary(&self) -> Vocabulary {
        Vocabulary {
            atoms: vec!["at_end".into()],
            fluents: vec!["position".into()],
            actions: vec!["forward".into(), "back".into()],
            agents: 1,
        }
    }

    fn reset(&mut self, seed: Option<u64>) {
        if let (Some(answer), Some(seed)) = (&mut self.answer, seed) {
            answer.state = seed | 1;
        }
        self.steps = 0;
        self.positions.iter_mut().for_each(|p| *p = 0);
    }

    fn observe(&self, agent: usize) -> Observation {
        Observation {
            atoms: if self.at_end(agent) { vec![0] } else { Vec::new() },
            fluents: vec![f64::from(self.positions[agent])],
        }
    }

    fn step(&mut self, actions: &[Option<usize>]) -> Vec<StepResult> {
        if self.positions.len() != actions.len() {
            self.positions = vec![0; actions.len()];
        }
        self.steps += 1;
        if let Some(answer) = &mut self.answer {
            std::thread::sleep(answer.draw());
        }
        actions
            .iter()
            .enumerate()
            .map(|(agent, action)| {
                if self.at_end(agent) {
                    return StepResult {
                        reward: 0.0,
                        action: ActionStatus::None,
                    };
                }
                let p = &mut self.positions[agent];
                match action {
                    Some(FORWARD) => *p = (*p + 1).min(LENGTH - 1),
                    Some(_) => *p = p.saturating_sub(1),
                    None => {}
                }
                StepResult {
                    reward: -1.0,
                    action: ActionStatus::Finished,
                }
            })
            .collect()
    }

    fn terminated(&self) -> bool {
        (0..self.positions.len()).all(|a| self.at_end(a))
    }

    fn truncated(&self) -> bool {
        self.steps >= STEP_LIMIT
    }
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let agents = std::env::var(learnpnp_system::multiprocess::supervisor::world_env::AGENTS)
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(1);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let answer = match args.as_slice() {
        [] => None,
        [flag, range] if flag == "--answer-ms" => match AnswerTime::parse(range) {
            Ok(answer) => Some(answer),
            Err(e) => {
                eprintln!("error: learnpnp-corridor: {e}");
                return ExitCode::FAILURE;
            }
        },
        _ => {
            eprintln!("error: learnpnp-corridor: usage: learnpnp-corridor [--answer-ms MIN-MAX]");
            return ExitCode::FAILURE;
        }
    };
    let mut world = Corridors {
        positions: vec![0; agents],
        steps: 0,
        answer,
    };
    match serve(&mut world) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: learnpnp-corridor: {e}");
            ExitCode::FAILURE
        }
    }
}
