//! Running the runs of an experiment in parallel, reproducibly.
//!
//! Run i draws every random number from seeds derived from the base seed and
//! i, so results are identical whatever the number of threads.

use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use crossbeam::channel;
use serde::{Deserialize, Serialize};

use super::spec::{ExperimentError, ExperimentSpec};
use crate::domains::{EpisodeOutcome, Task};
use crate::learning::persist::SavedValues;
use crate::learning::{EpisodeMode, Learner};
use crate::plan::Plan;
use crate::rng::{SimRng, derive_seed, seeded};

/// One learning episode of run 0, as `episodes.csv` lists it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EpisodeRecord {
    /// Learning episode number (1-based).
    pub episode: u64,
    /// What it earned.
    pub outcome: EpisodeOutcome,
}

/// What one run produced.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RunOutput {
    /// The evaluation score at each evaluation point.
    pub evals: Vec<f64>,
    /// The greedy policy's mean return at the end.
    pub greedy: f64,
    /// Every learning episode (run 0 only).
    pub episodes: Vec<EpisodeRecord>,
    /// Traced values after every learning episode (run 0 only).
    pub traces: Vec<(u64, Vec<(String, f64)>)>,
    /// The learned values of each learning agent at the end (run 0 only).
    pub values: Vec<SavedValues>,
    /// Episodes of every kind this run executed.
    pub episodes_run: u64,
    /// Primitive actions (moves, cycles) over those episodes.
    pub actions: u64,
    /// Game logs (`.rcg` text) of the recorded episodes (run 0 only).
    pub replays: Vec<String>,
}

/// What an experiment produced.
#[derive(Debug, Clone)]
pub struct ExperimentOutput {
    /// What was run.
    pub spec: ExperimentSpec,
    /// Learning episodes at each evaluation point.
    pub eval_points: Vec<u64>,
    /// One output per run, in run order.
    pub runs: Vec<RunOutput>,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
}

impl ExperimentOutput {
    /// Episodes of every kind executed over all runs.
    pub fn total_episodes(&self) -> u64 {
        self.runs.iter().map(|r| r.episodes_run).sum()
    }

    /// Primitive actions over all runs.
    pub fn total_actions(&self) -> u64 {
        self.runs.iter().map(|r| r.actions).sum()
    }
}

/// The learner of agent `agent` in run `run`, starting from `initial` if given.
/// Agent 0 draws from stream 1 of the run's seed, further agents from streams
/// 100 + i: every process of a multi-process run builds the same learners.
pub fn learner_for(spec: &ExperimentSpec, run: usize, agent: usize, initial: Option<&SavedValues>) -> Box<dyn Learner> {
    let seed = derive_seed(spec.seed, run as u64);
    let stream = if agent == 0 { 1 } else { 100 + agent as u64 };
    let mut learner = spec.learner.build(seeded(derive_seed(seed, stream)));
    if let Some(saved) = initial {
        let start = saved.to_table(learner.values().initial_value());
        *learner.values_mut() = start;
    }
    learner
}

/// The random stream of run `run`'s task (its world and fixed policies).
pub fn task_rng(spec: &ExperimentSpec, run: usize) -> SimRng {
    seeded(derive_seed(derive_seed(spec.seed, run as u64), 2))
}

/// Runs one run of `spec` with the plan already loaded.
pub fn run_one(
    spec: &ExperimentSpec,
    plan: Option<Arc<Plan>>,
    initial: &[SavedValues],
    run: usize,
    progress: impl FnMut(u64),
) -> Result<RunOutput, ExperimentError> {
    let mut learner = |agent: usize| learner_for(spec, run, agent, initial.get(agent));
    let mut task = spec.domain.task(plan.clone(), &mut learner, task_rng(spec, run))?;
    let mut out = RunOutput::default();
    run_protocol(spec, task.as_mut(), run, &mut out, progress)?;
    if run == 0 {
        let plans: Vec<&Plan> = plan.as_deref().map(Plan::activation_plans).unwrap_or_default();
        out.values = task
            .learners()
            .iter()
            .map(|l| SavedValues::new(spec.algorithm.name(), l.values(), &plans))
            .collect();
    }
    Ok(out)
}

/// The protocol of one run on `task`, whatever runs it (in this process or
/// with keepers in other processes): evaluations every `eval_every` learning
/// episodes, then the greedy score. Results accumulate in `out` as they come,
/// so an interrupted run keeps what it completed.
pub fn run_protocol(
    spec: &ExperimentSpec,
    task: &mut dyn Task,
    run: usize,
    out: &mut RunOutput,
    mut progress: impl FnMut(u64),
) -> Result<(), ExperimentError> {
    let p = spec.protocol;
    let first = run == 0;
    let eval_cost = p.eval_episodes as u64;
    out.evals.push(task.evaluate(p.eval_episodes)?);
    out.episodes_run += eval_cost;
    let mut since_report = 0;
    for episode in 1..=p.episodes {
        let outcome = task.episode(EpisodeMode::Learn)?;
        out.episodes_run += 1;
        out.actions += u64::from(outcome.actions);
        if first {
            out.episodes.push(EpisodeRecord { episode, outcome });
        }
        if first && p.trace_interval() > 0 && episode % p.trace_interval() == 0 {
            let traced = task.traced_values();
            if !traced.is_empty() {
                out.traces.push((episode, traced));
            }
        }
        if episode % p.eval_every == 0 {
            out.evals.push(task.evaluate(p.eval_episodes)?);
            out.episodes_run += eval_cost;
        }
        since_report += 1;
        if since_report == 256 {
            progress(since_report);
            since_report = 0;
        }
    }
    progress(since_report);
    out.greedy = task.greedy_score(p.greedy_episodes)?;
    out.episodes_run += p.greedy_episodes as u64;
    if first {
        // Played last, so that recording changes no result of the run.
        out.replays = task.record(spec.record)?;
    }
    Ok(())
}

/// Runs every run of `spec` on `threads` threads; a progress bar is drawn on a
/// terminal when `progress` is set.
pub fn run_experiment(
    spec: &ExperimentSpec,
    threads: usize,
    progress: bool,
) -> Result<ExperimentOutput, ExperimentError> {
    spec.protocol.validate()?;
    let plan = spec.domain.load_plan()?;
    let initial = spec.load_initial_values(plan.as_deref())?;
    let start = Instant::now();
    let runs = spec.protocol.runs;
    let next = AtomicUsize::new(0);
    let (tx, rx) = channel::unbounded::<Result<(usize, RunOutput), ExperimentError>>();
    let (ptx, prx) = channel::unbounded::<u64>();
    let threads = threads.clamp(1, runs);
    let bar = if progress && std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(spec.protocol.episodes * runs as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} episodes ({eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar.set_message(spec.label.clone());
        Some(bar)
    } else {
        None
    };
    let mut results: Vec<Option<RunOutput>> = vec![None; runs];
    let mut failure = None;
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let (tx, ptx, next, plan, initial) = (tx.clone(), ptx.clone(), &next, plan.clone(), &initial);
            scope.spawn(move || {
                loop {
                    let run = next.fetch_add(1, Ordering::Relaxed);
                    if run >= runs {
                        break;
                    }
                    let result = run_one(spec, plan.clone(), initial, run, |n| {
                        let _ = ptx.send(n);
                    });
                    let failed = result.is_err();
                    let _ = tx.send(result.map(|r| (run, r)));
                    if failed {
                        next.store(runs, Ordering::Relaxed);
                        break;
                    }
                }
            });
        }
        drop(tx);
        drop(ptx);
        let mut done = 0;
        while done < runs && failure.is_none() {
            channel::select! {
                recv(prx) -> n => if let (Ok(n), Some(bar)) = (n, &bar) { bar.inc(n) },
                recv(rx) -> r => match r {
                    Ok(Ok((i, out))) => { results[i] = Some(out); done += 1; }
                    Ok(Err(e)) => failure = Some(e),
                    Err(_) => break,
                },
            }
        }
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if let Some(e) = failure {
        return Err(e);
    }
    let runs = results
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| ExperimentError::Invalid("a run did not finish".into()))?;
    Ok(ExperimentOutput {
        spec: spec.clone(),
        eval_points: spec.protocol.eval_points(),
        runs,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}
