//! `learnpnp-corridor`: a trivial world in its own process, written in Rust
//! on `learnpnp_system::multiprocess::host::world`, for tests and for
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
//!
//! `--stall-ms MS` plays a robot that takes MS milliseconds to answer the
//! first step of the world process, the world keeping house while it waits
//! (as a ROS 2 world waits for its robot): it lives through a stall longer
//! than the heartbeat timeout. `--hang-ms MS` blocks the first step MS
//! milliseconds without keeping house: a hung world, which the supervisor
//! kills as silent.

use std::process::ExitCode;
use std::time::{Duration, Instant};

use learnpnp_system::ipc::world::{ActionStatus, Vocabulary};
use learnpnp_system::multiprocess::host::world::{Housekeeping, Observation, ServedWorld, StepResult, serve};

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
    /// The first step's stall or hang, if it plays one (taken by the first step).
    first_step: Option<FirstStep>,
}

/// How the first step of the world process blocks.
#[derive(Debug, Clone, Copy)]
struct FirstStep {
    /// For how long.
    wait: Duration,
    /// Whether the world keeps house while it waits (a stall) or not (a hang).
    keeping_house: bool,
}

impl FirstStep {
    /// Blocks for the step's wait, keeping house in slices if it may.
    fn block(self, house: &mut Housekeeping<'_>) {
        let until = Instant::now() + self.wait;
        if !self.keeping_house {
            std::thread::sleep(self.wait);
            return;
        }
        while house.keep() {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return;
            }
            std::thread::sleep(left.min(Housekeeping::EVERY));
        }
    }
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

    fn reset(&mut self, seed: Option<u64>, _house: &mut Housekeeping<'_>) {
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

    fn step(&mut self, actions: &[Option<usize>], house: &mut Housekeeping<'_>) -> Vec<StepResult> {
        if self.positions.len() != actions.len() {
            self.positions = vec![0; actions.len()];
        }
        self.steps += 1;
        if let Some(answer) = &mut self.answer {
            std::thread::sleep(answer.draw());
        }
        if let Some(first) = self.first_step.take() {
            first.block(house);
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

/// The robot's answer time and the first step's block, from the arguments.
fn parse(args: &[String]) -> Result<(Option<AnswerTime>, Option<FirstStep>), String> {
    const USAGE: &str = "usage: learnpnp-corridor [--answer-ms MIN-MAX] [--stall-ms MS | --hang-ms MS]";
    let mut answer = None;
    let mut first_step = None;
    for pair in args.chunks(2) {
        let [flag, value] = pair else {
            return Err(USAGE.into());
        };
        let wait = || {
            value
                .parse()
                .map(Duration::from_millis)
                .map_err(|_| format!("{flag}: '{value}' is not a number of milliseconds"))
        };
        match flag.as_str() {
            "--answer-ms" => answer = Some(AnswerTime::parse(value)?),
            "--stall-ms" | "--hang-ms" if first_step.is_none() => {
                first_step = Some(FirstStep {
                    wait: wait()?,
                    keeping_house: flag == "--stall-ms",
                });
            }
            _ => return Err(USAGE.into()),
        }
    }
    Ok((answer, first_step))
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let agents = std::env::var(learnpnp_system::multiprocess::supervisor::world_env::AGENTS)
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(1);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (answer, first_step) = match parse(&args) {
        Ok(parsed) => parsed,
        Err(e) => {
            eprintln!("error: learnpnp-corridor: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut world = Corridors {
        positions: vec![0; agents],
        steps: 0,
        answer,
        first_step,
    };
    match serve(&mut world) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: learnpnp-corridor: {e}");
            ExitCode::FAILURE
        }
    }
}
