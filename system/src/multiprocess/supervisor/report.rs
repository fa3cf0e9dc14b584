//! What a multi-process run writes: the experiment's own files (the learning
//! curve, `episodes.csv` with the in-process columns, the values), and the
//! system's figures: `summary.json`, the latency histograms (`.hgrm` text and
//! serialised), a percentile plot with the deadline and the iceoryx2 floor,
//! and a table for the terminal.

use learnpnp::named::Named;
use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::hosts::report::LinkReport;
use crate::ipc::convert::Rejections;
use crate::ipc::wait::WaitStrategy;
use crate::latency::plot::{ReferenceLine, percentile_plot};
use crate::latency::{Latency, Percentiles};
use crate::multiprocess::Clock;
use crate::multiprocess::agent::keeper::compute_histogram;
use crate::multiprocess::agent::world::WORLD_TURNAROUND;
use crate::multiprocess::floor_probe::REMOTE_HOST_FLOOR;
use crate::multiprocess::host::simulator::{AbortedEpisode, FLOOR, ROUND_TRIP, keeper_round_trip_histogram};
use crate::multiprocess::supervisor::config::{SupervisorConfig, SupervisorError, json_error};
use crate::multiprocess::supervisor::results::{ResumeCheck, RunRecord};
use crate::multiprocess::supervisor::watch::Fault;
use crate::multiprocess::view_process::ViewCounts;
use learnpnp::experiment::output::{SummaryFile, stage_results};
use learnpnp::experiment::result_dir::{Progress, ResultWriter};
use learnpnp::experiment::runner::ExperimentOutput;

/// The name of the merged compute time of every keeper.
const ALL_COMPUTE: &str = "compute";

/// `summary.json` of a multi-process run.
#[derive(Debug, Clone, Serialize)]
pub struct SystemSummary {
    /// Every run ended normally.
    pub complete: bool,
    /// Why not.
    pub failure: Option<String>,
    /// `lockstep` or `realtime`.
    pub mode: Clock,
    /// How processes waited.
    pub wait: WaitStrategy,
    /// How the simulator and the agents were scheduled (`normal`, `SCHED_FIFO 10`,
    /// or normal with the reason the real-time priority was refused).
    pub(crate) scheduling: String,
    /// Runs asked for.
    pub runs: usize,
    /// Runs that ended normally.
    pub runs_completed: usize,
    /// Learning episodes completed, over every run.
    pub episodes: u64,
    /// Episodes of every kind played (learning, evaluation, greedy; aborted ones included).
    pub(crate) episodes_played: u64,
    /// Cycles played.
    pub cycles: u64,
    /// Cycles per second of the episode loop.
    pub cycles_per_second: f64,
    /// Real time: commands that missed their cycle.
    pub missed_deadlines: u64,
    /// Real time: commands that arrived after their cycle.
    pub(crate) late_commands: u64,
    /// Real time: cycles whose work ran past their deadline (each counted,
    /// the next kept on the grid), by the process that keeps the cycle (the
    /// simulator, or the world: its incarnations summed), runs summed.
    pub late_cycles: BTreeMap<String, u64>,
    /// Agents restarted.
    pub restarts: u32,
    /// Every restarted agent resumed with exactly the values checkpointed before it was lost.
    pub(crate) values_survived: bool,
    /// Each agent restart and what it resumed with.
    pub(crate) resumes: Vec<ResumeCheck>,
    /// Episodes aborted because a keeper was lost.
    pub(crate) aborted_episodes: usize,
    /// The aborted episodes.
    pub(crate) aborted: Vec<AbortedEpisode>,
    /// Mean duration of the learning episodes, in seconds.
    pub mean_episode_seconds: f64,
    /// Snapshot-to-command round trip (every keeper, every cycle), microseconds.
    pub latency_us: Percentiles,
    /// Keepaway: each keeper's own round trip (`keeper 1`, ...; a keeper on
    /// another host's is the round trip across the link), microseconds.
    pub keeper_latency_us: BTreeMap<String, Percentiles>,
    /// The bare iceoryx2 round trip of the snapshot payload, measured in the same run.
    pub floor_us: Percentiles,
    /// The same on the host of the remote agents, measured there before they
    /// started (runs across hosts only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub remote_host_floor_us: Option<Percentiles>,
    /// The agents' compute time per cycle (executor and learner), microseconds.
    pub compute_us: Percentiles,
    /// A world run: the world's turnaround per cycle as its agents saw it,
    /// microseconds (see [`WORLD_TURNAROUND`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub world_turnaround_us: Option<Percentiles>,
    /// Median round trip as a multiple of the median floor.
    pub(crate) round_trip_over_floor_p50: f64,
    /// Messages from shared memory refused, by process and reason.
    pub(crate) rejected_messages: BTreeMap<String, Rejections>,
    /// Checkpoint writes that failed (the previous checkpoint kept).
    pub(crate) checkpoint_failures: u64,
    /// Faults and what was done about them.
    pub(crate) faults: Vec<Fault>,
    /// A run across hosts: how the link was protected, what host A's bridge
    /// carried and what it refused, by reason (runs summed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub link: Option<LinkReport>,
    /// A run with a view: the agents' feed records it read, refused (by
    /// reason) and lost (dropped by an agent or the view, or overwritten
    /// before it read them), runs summed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub view: Option<ViewCounts>,
    /// Files of the runs' iceoryx2 namespaces left after cleanup (0 expected).
    pub(crate) leftover_shm_files: usize,
    /// The runs' iceoryx2 prefixes.
    pub(crate) ipc_prefixes: Vec<String>,
    /// Wall-clock seconds of the whole launch.
    pub(crate) wall_seconds: f64,
    /// The experiment's figures (spec, final mean with its confidence interval, ...)
    /// when at least one run completed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub experiment: Option<SummaryFile>,
}

/// Every histogram of the launch, runs merged: round trip, floor, each
/// keeper's compute time, and all keepers' compute time.
pub(crate) fn merged_histograms(records: &[RunRecord]) -> Result<Vec<Latency>, SupervisorError> {
    let mut merged: Vec<Latency> = Vec::new();
    for record in records {
        for h in &record.histograms {
            match merged.iter_mut().find(|m| m.name() == h.name()) {
                Some(m) => m.merge(h)?,
                None => merged.push(h.clone()),
            }
        }
    }
    let mut compute = Latency::new(ALL_COMPUTE);
    for h in merged.iter().filter(|h| h.name().starts_with("compute-")) {
        compute.merge(h)?;
    }
    merged.push(compute);
    Ok(merged)
}

fn find<'a>(histograms: &'a [Latency], name: &str) -> Option<&'a Latency> {
    histograms.iter().find(|h| h.name() == name)
}

/// The summary of `records` (one per run started).
pub(crate) fn summarize(
    config: &SupervisorConfig,
    records: &[RunRecord],
    histograms: &[Latency],
    experiment: Option<SummaryFile>,
    wall_seconds: f64,
) -> SystemSummary {
    let percentiles = |name: &str| find(histograms, name).map(Latency::percentiles).unwrap_or_default();
    let (latency, floor) = (percentiles(ROUND_TRIP), percentiles(FLOOR));
    let seconds_per_cycle = crate::multiprocess::host::simulator::keepaway_config(&config.spec)
        .map(|c| c.simulator().server.cycle_seconds)
        .unwrap_or(0.1);
    let learning_cycles: u64 = records.iter().map(|r| r.sim.output.actions).sum();
    let learning_episodes: u64 = records.iter().map(|r| r.sim.totals.learning_episodes).sum();
    let loop_seconds: f64 = records.iter().map(|r| r.sim.totals.seconds).sum();
    let cycles: u64 = records.iter().map(|r| r.sim.totals.cycles).sum();
    let failure = records.iter().find_map(|r| r.failure.clone());
    let mut rejected: BTreeMap<String, Rejections> = BTreeMap::new();
    for record in records {
        for (process, r) in &record.rejected {
            let entry = rejected.entry(process.clone()).or_default();
            *entry = entry.plus(r);
        }
    }
    let mut late_cycles: BTreeMap<String, u64> = BTreeMap::new();
    for (process, late) in records.iter().flat_map(|r| &r.late_cycles) {
        *late_cycles.entry(process.clone()).or_default() += late;
    }
    SystemSummary {
        complete: failure.is_none()
            && records.len() == config.spec.protocol.runs
            && records.iter().all(|r| r.sim.complete),
        failure,
        mode: config.clock,
        wait: config.wait,
        scheduling: records.first().map(|r| r.scheduling.clone()).unwrap_or_default(),
        runs: config.spec.protocol.runs,
        runs_completed: records.iter().filter(|r| r.sim.complete).count(),
        episodes: learning_episodes,
        episodes_played: records.iter().map(|r| r.sim.output.episodes_run).sum::<u64>()
            + records.iter().map(|r| r.sim.totals.aborted.len() as u64).sum::<u64>(),
        cycles,
        cycles_per_second: if loop_seconds > 0.0 {
            cycles as f64 / loop_seconds
        } else {
            0.0
        },
        missed_deadlines: records.iter().map(|r| r.sim.totals.missed_deadlines).sum(),
        late_commands: records.iter().map(|r| r.sim.totals.late_commands).sum(),
        late_cycles,
        restarts: records.iter().map(|r| r.restarts).sum(),
        values_survived: records.iter().flat_map(|r| &r.resumes).all(|c| c.survived),
        resumes: records.iter().flat_map(|r| r.resumes.iter().cloned()).collect(),
        aborted_episodes: records.iter().map(|r| r.sim.totals.aborted.len()).sum(),
        aborted: records
            .iter()
            .flat_map(|r| r.sim.totals.aborted.iter().cloned())
            .collect(),
        mean_episode_seconds: if learning_episodes > 0 {
            learning_cycles as f64 * seconds_per_cycle / learning_episodes as f64
        } else {
            0.0
        },
        latency_us: latency,
        keeper_latency_us: (0..learnpnp_keepaway::world::NUM_KEEPERS)
            .filter_map(|k| {
                find(histograms, &keeper_round_trip_histogram(k))
                    .filter(|h| h.count() > 0)
                    .map(|h| (format!("keeper {}", k + 1), h.percentiles()))
            })
            .collect(),
        floor_us: floor,
        remote_host_floor_us: find(histograms, REMOTE_HOST_FLOOR)
            .filter(|h| h.count() > 0)
            .map(Latency::percentiles),
        compute_us: percentiles(ALL_COMPUTE),
        world_turnaround_us: find(histograms, WORLD_TURNAROUND)
            .filter(|h| h.count() > 0)
            .map(Latency::percentiles),
        round_trip_over_floor_p50: if floor.p50 > 0.0 { latency.p50 / floor.p50 } else { 0.0 },
        rejected_messages: rejected,
        checkpoint_failures: records.iter().map(|r| r.checkpoint_failures).sum(),
        faults: records.iter().flat_map(|r| r.faults.iter().cloned()).collect(),
        link: records.iter().filter_map(|r| r.link.clone()).reduce(|a, b| a.plus(&b)),
        view: records.iter().filter_map(|r| r.view.clone()).reduce(|a, b| a.add(&b)),
        leftover_shm_files: records.iter().map(|r| r.leftover_files).sum(),
        ipc_prefixes: records.iter().map(|r| r.prefix.clone()).collect(),
        wall_seconds,
        experiment,
    }
}

/// The latency table printed at the end of a run.
fn latency_table(histograms: &[Latency], summary: &SystemSummary) -> String {
    let mut text = format!(
        "{:<22}{:>10}{:>10}{:>10}{:>10}{:>10}{:>12}\n",
        "latency (µs)", "p50", "p90", "p99", "p99.9", "max", "count"
    );
    let keepers = 0..learnpnp_keepaway::world::NUM_KEEPERS;
    let rows = [(ROUND_TRIP.to_string(), "round trip".to_string())]
        .into_iter()
        .chain(
            keepers
                .clone()
                .map(|k| (keeper_round_trip_histogram(k), format!("  keeper {}", k + 1))),
        )
        .chain([
            (FLOOR.to_string(), "iceoryx2 floor".to_string()),
            (REMOTE_HOST_FLOOR.to_string(), "  on the remote host".to_string()),
            (ALL_COMPUTE.to_string(), "agent compute".to_string()),
        ])
        .chain(keepers.map(|k| (compute_histogram(k), format!("  keeper {}", k + 1))))
        .chain([(WORLD_TURNAROUND.to_string(), "world turnaround".to_string())]);
    for (name, label) in rows {
        if let Some(h) = find(histograms, &name).filter(|h| h.count() > 0) {
            let p = h.percentiles();
            let _ = writeln!(
                text,
                "{label:<22}{:>10.1}{:>10.1}{:>10.1}{:>10.1}{:>10.1}{:>12}",
                p.p50,
                p.p90,
                p.p99,
                p.p999,
                p.max,
                h.count()
            );
        }
    }
    let _ = writeln!(
        text,
        "round trip p50 = {:.1} x floor p50; {:.0} cycles/s; {} missed deadlines; {} restarts; {} aborted episodes",
        summary.round_trip_over_floor_p50,
        summary.cycles_per_second,
        summary.missed_deadlines,
        summary.restarts,
        summary.aborted_episodes
    );
    if summary.mode == Clock::Realtime {
        let _ = writeln!(text, "scheduling: {}", summary.scheduling);
    }
    text
}

/// A launch's summary and its histograms (runs merged).
#[derive(Debug, Clone)]
pub struct Report {
    /// What `summary.json` holds.
    pub summary: SystemSummary,
    /// Round trip, floor, compute per keeper and all keepers.
    pub(crate) histograms: Vec<Latency>,
}

impl Report {
    /// The latency table for the terminal.
    pub fn latency_table(&self) -> String {
        latency_table(&self.histograms, &self.summary)
    }
}

/// Writes the run's files into `files` and publishes them as one set: the
/// experiment's (when a run completed), `summary.json`, `latency/*.hgrm` and
/// `latency/*.hdr`, and `latency.svg`.
pub(crate) fn write_report(
    mut files: ResultWriter<'_>,
    config: &SupervisorConfig,
    records: &[RunRecord],
    wall_seconds: f64,
) -> Result<Report, SupervisorError> {
    let completed: Vec<&RunRecord> = records.iter().filter(|r| r.sim.complete).collect();
    let experiment = if completed.is_empty() {
        None
    } else {
        let mut runs: Vec<_> = completed.iter().map(|r| r.sim.output.clone()).collect();
        if let (Some(first), Some(record)) = (runs.first_mut(), completed.first()) {
            first.values = record.values.clone();
        }
        let mut spec = config.spec.clone();
        spec.protocol.runs = runs.len();
        let output = ExperimentOutput {
            eval_points: spec.protocol.eval_points(),
            spec,
            runs,
            wall_seconds,
        };
        Some(stage_results(&output, &mut files)?)
    };
    let histograms = merged_histograms(records)?;
    let summary = summarize(config, records, &histograms, experiment, wall_seconds);
    let json = serde_json::to_vec_pretty(&summary).map_err(json_error("summary.json"))?;
    files.add_bytes("summary.json", &json)?;
    for h in &histograms {
        files.add_bytes(&format!("latency/{}.hgrm", h.name()), h.to_hgrm().as_bytes())?;
        files.add_bytes(&format!("latency/{}.hdr", h.name()), &h.to_bytes()?)?;
    }
    // One line per histogram the processes recorded (not the merged compute).
    let shown: Vec<&Latency> = histograms.iter().filter(|h| h.name() != ALL_COMPUTE).collect();
    let mut references = vec![ReferenceLine {
        label: "deadline: 100 ms cycle".into(),
        micros: 100_000.0,
    }];
    if summary.floor_us.p50 > 0.0 {
        references.push(ReferenceLine {
            label: format!("iceoryx2 floor p50: {:.1} µs", summary.floor_us.p50),
            micros: summary.floor_us.p50,
        });
    }
    let title = format!(
        "{} on {}: {} mode, {} wait",
        config.spec.label,
        config.spec.domain.name(),
        config.clock.name(),
        config.wait.name()
    );
    let svg = percentile_plot(&title, &shown, &references)?;
    files.add_bytes("latency.svg", svg.as_bytes())?;
    files.commit(Progress {
        completed: summary.runs_completed as u64,
        planned: summary.runs as u64,
    })?;
    Ok(Report { summary, histograms })
}
