//! `learnpnp-corridor`: a trivial world in its own process, written in Rust
//! on `learnpnp_system::multiprocess::world_host`, for tests and for
//! measuring the generic path's cost. Each agent walks its own corridor of
//! `LENGTH` cells from the first: `forward` or `back`, -1 a step until it is
//! at the end; the episode terminates when every agent is there, and is cut
//! short after `STEP_LIMIT` steps. Started by `learnpnp-supervisor
//! --world-cmd learnpnp-corridor --plan plans/corridor.pnml`.

use std::process::ExitCode;

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

    fn reset(&mut self, _seed: Option<u64>) {
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
    let mut world = Corridors {
        positions: vec![0; agents],
        steps: 0,
    };
    match serve(&mut world) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: learnpnp-corridor: {e}");
            ExitCode::FAILURE
        }
    }
}
