//! Running the runs of an experiment in parallel, reproducibly.
//!
//! Run i draws every random number from seeds derived from the base seed and
//! i, so results are identical whatever the number of threads.

use crate::named::Named;
use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use crossbeam::channel;
use serde::{Deserialize, Serialize};

use super::spec::{ExperimentError, ExperimentSpec};
use crate::domains::{EpisodeOutcome, Task};
use crate::feed::{FeedSink, Source};
use crate::learning::persist::SavedValues;
use crate::learning::{EpisodeMode, Learner, WatchedLearner};
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
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunOutput {
    /// The run's index (its seeds derive from it).
    pub run: usize,
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
    /// Primitive actions (moves, cycles) of the learning episodes.
    pub actions: u64,
    /// Primitive actions (moves, Keepaway's cycles) of every episode the run
    /// played, of every kind ([`Task::actions_played`]); `None` where the
    /// task does not count them.
    #[serde(default)]
    pub actions_played: Option<u64>,
    /// Game logs (`.rcg` text) of the recorded episodes (run 0 only).
    pub replays: Vec<String>,
}

/// What an experiment produced: every run, or, when it was stopped, the runs
/// it completed.
#[derive(Debug, Clone)]
pub struct ExperimentOutput {
    /// What was run.
    pub spec: ExperimentSpec,
    /// Learning episodes at each evaluation point.
    pub eval_points: Vec<u64>,
    /// The completed runs, in run order.
    pub runs: Vec<RunOutput>,
    /// Wall-clock seconds (over every session of a resumed experiment).
    pub wall_seconds: f64,
}

impl ExperimentOutput {
    /// Episodes of every kind executed over all runs.
    pub fn total_episodes(&self) -> u64 {
        self.runs.iter().map(|r| r.episodes_run).sum()
    }

    /// Primitive actions over all runs.
    pub(crate) fn total_actions(&self) -> u64 {
        self.runs.iter().map(|r| r.actions).sum()
    }

    /// Primitive actions of every episode over all runs, if every run counted them.
    pub(crate) fn actions_played(&self) -> Option<u64> {
        self.runs.iter().map(|r| r.actions_played).sum()
    }

    /// Whether every planned run completed.
    pub fn is_complete(&self) -> bool {
        self.runs.len() == self.spec.protocol.runs
    }

    /// Run 0, which records episodes, traces and values, if it completed.
    pub(crate) fn first_run(&self) -> Option<&RunOutput> {
        self.runs.iter().find(|r| r.run == 0)
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
    run_task_rng(spec.seed, run)
}

/// The random stream of run `run`'s task in an experiment of base seed `seed`.
pub fn run_task_rng(seed: u64, run: usize) -> SimRng {
    seeded(derive_seed(derive_seed(seed, run as u64), 2))
}

/// Runs run `run` of `spec` with the plan already loaded; `None` if `stop`
/// said so before it finished (checked before every learning episode). With
/// a `feed`, every learner of a plan is watched and the curve is published.
pub(crate) fn run_one(
    spec: &ExperimentSpec,
    plan: Option<Arc<Plan>>,
    initial: &[SavedValues],
    run: usize,
    feed: Option<&Arc<dyn FeedSink>>,
    progress: impl FnMut(u64),
    stop: impl Fn() -> bool,
) -> Result<Option<RunOutput>, ExperimentError> {
    let mut learner = |agent: usize| {
        let learner = learner_for(spec, run, agent, initial.get(agent));
        match (feed, plan.as_deref()) {
            (Some(sink), Some(plan)) => {
                let source = Source {
                    run: run as u32,
                    agent: agent as u32,
                };
                Box::new(WatchedLearner::new(learner, plan, source, sink.clone()))
            }
            _ => learner,
        }
    };
    let mut task = spec.domain.task(plan.clone(), &mut learner, task_rng(spec, run))?;
    if let Some(sink) = feed {
        task = Box::new(super::watched::WatchedTask::new(task, run, sink.clone()));
    }
    let mut out = RunOutput::default();
    if !run_protocol(spec, task.as_mut(), run, true, &mut out, progress, stop)? {
        return Ok(None);
    }
    if run == 0 {
        let plans: Vec<&Plan> = plan.as_deref().map(Plan::activation_plans).unwrap_or_default();
        out.values = task
            .learners()
            .iter()
            .map(|l| SavedValues::new(spec.algorithm.name(), l.values(), &plans))
            .collect();
    }
    Ok(Some(out))
}

/// The protocol of one run on `task`, whatever runs it (in this process or
/// with keepers in other processes): evaluations every `eval_every` learning
/// episodes, then the greedy score. Results accumulate in `out` (whose `run`
/// is set) as they come, so an interrupted run keeps what it completed.
/// Run 0 also keeps every learning episode in `out.episodes`, unless
/// `keep_episodes` is false (a long-running process that journals its
/// episodes elsewhere keeps its memory flat). Returns false if `stop` said so
/// (checked before every learning episode) before the protocol ended.
pub fn run_protocol(
    spec: &ExperimentSpec,
    task: &mut dyn Task,
    run: usize,
    keep_episodes: bool,
    out: &mut RunOutput,
    mut progress: impl FnMut(u64),
    stop: impl Fn() -> bool,
) -> Result<bool, ExperimentError> {
    let p = spec.protocol;
    let first = run == 0;
    out.run = run;
    let eval_cost = p.eval_episodes as u64;
    let played_before = task.actions_played();
    out.evals.push(task.evaluate(p.eval_episodes)?);
    out.episodes_run += eval_cost;
    let mut since_report = 0;
    for episode in 1..=p.episodes {
        if stop() {
            return Ok(false);
        }
        let outcome = task.episode(EpisodeMode::Learn)?;
        out.episodes_run += 1;
        out.actions += u64::from(outcome.actions);
        if first && keep_episodes {
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
        out.replays = task.replays()?;
    }
    out.actions_played = played_before.zip(task.actions_played()).map(|(a, b)| b - a);
    Ok(true)
}

/// How the runs of an experiment are executed.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// Worker threads (at least one is used, and no more than there are runs).
    pub threads: usize,
    /// Draw a progress bar when standard error is a terminal.
    pub progress: bool,
    /// Once set (by a signal handler, say), no run starts and the runs in
    /// progress are abandoned: the experiment returns the runs completed so far.
    pub stop: Option<&'a AtomicBool>,
    /// Play only these runs (a shard's, [`super::shard::Shard::runs`]); all when `None`.
    pub only: Option<&'a [usize]>,
    /// Where the live feed goes (a view): every learner is watched
    /// ([`WatchedLearner`]) and the curve published; nothing is when `None`.
    pub feed: Option<&'a Arc<dyn FeedSink>>,
}

impl std::fmt::Debug for RunOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("threads", &self.threads)
            .field("progress", &self.progress)
            .field("stop", &self.stop)
            .field("only", &self.only)
            .field("feed", &self.feed.is_some())
            .finish()
    }
}

/// Runs completed in an earlier session of the same experiment (read back
/// from a partial result), which are not run again.
#[derive(Debug, Clone, Default)]
pub struct Completed {
    /// The runs, each with its index.
    pub runs: Vec<RunOutput>,
    /// Wall-clock seconds the earlier sessions took.
    pub wall_seconds: f64,
}

/// Runs every run of `spec` not in `completed`, on `options.threads` threads.
/// Run i draws from seeds derived from the base seed and i alone, so the
/// output is the same whatever the threads, and whether the experiment ran in
/// one session or was stopped and resumed.
pub fn run_experiment(
    spec: &ExperimentSpec,
    options: RunOptions<'_>,
    completed: Completed,
) -> Result<ExperimentOutput, ExperimentError> {
    spec.validate()?;
    let plan = spec.domain.load_plan()?;
    let initial = spec.load_initial_values(plan.as_deref())?;
    let start = Instant::now();
    let planned = spec.protocol.runs;
    let mut results: Vec<Option<RunOutput>> = vec![None; planned];
    for run in completed.runs {
        let index = run.run;
        match results.get_mut(index) {
            Some(slot @ None) => *slot = Some(run),
            _ => {
                return Err(ExperimentError::Invalid(format!(
                    "completed run {index} is out of range or repeated (the experiment has {planned} runs)"
                )));
            }
        }
    }
    let todo: Vec<usize> = (0..planned)
        .filter(|&i| results[i].is_none() && options.only.is_none_or(|only| only.contains(&i)))
        .collect();
    let next = AtomicUsize::new(0);
    let abort = AtomicBool::new(false);
    let stopped = || abort.load(Ordering::Relaxed) || options.stop.is_some_and(|s| s.load(Ordering::Relaxed));
    let (tx, rx) = channel::unbounded::<Result<Option<RunOutput>, ExperimentError>>();
    let (ptx, prx) = channel::unbounded::<u64>();
    let threads = options.threads.clamp(1, todo.len().max(1));
    let bar = if options.progress && std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(spec.protocol.episodes * todo.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} episodes ({eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar.set_message(spec.label.clone());
        Some(bar)
    } else {
        None
    };
    let mut failure = None;
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let (tx, ptx, next, plan, initial, todo, stopped) =
                (tx.clone(), ptx.clone(), &next, plan.clone(), &initial, &todo, &stopped);
            scope.spawn(move || {
                while !stopped() {
                    let Some(&run) = todo.get(next.fetch_add(1, Ordering::Relaxed)) else {
                        break;
                    };
                    let result = run_one(
                        spec,
                        plan.clone(),
                        initial,
                        run,
                        options.feed,
                        |n| {
                            let _ = ptx.send(n);
                        },
                        stopped,
                    );
                    let _ = tx.send(result);
                }
            });
        }
        drop(tx);
        drop(ptx);
        loop {
            channel::select! {
                recv(prx) -> n => if let (Ok(n), Some(bar)) = (n, &bar) { bar.inc(n) },
                recv(rx) -> r => match r {
                    Ok(Ok(Some(out))) => {
                        let index = out.run;
                        results[index] = Some(out);
                    }
                    Ok(Ok(None)) => {}
                    Ok(Err(e)) => {
                        abort.store(true, Ordering::Relaxed);
                        failure.get_or_insert(e);
                    }
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
    Ok(ExperimentOutput {
        spec: spec.clone(),
        eval_points: spec.protocol.eval_points(),
        runs: results.into_iter().flatten().collect(),
        wall_seconds: completed.wall_seconds + start.elapsed().as_secs_f64(),
    })
}
