//! The latency benchmark: the system run once per configuration (each wait
//! strategy, idle and with a busy thread on every core) for a fixed time,
//! measuring side by side the bare iceoryx2 round trip of the snapshot payload
//! (the floor), the full snapshot-to-command round trip, and the agents'
//! compute time. It writes `.hgrm` and serialised histograms per
//! configuration, one percentile plot, a table with the ratios to the floor,
//! and `latency.json`.

use learnpnp::named::Named;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::json_error;
use crate::load::CpuLoad;
use learnpnp::experiment::result_dir::{Progress, ResultDir};
use learnpnp_system::ipc::wait::WaitStrategy;
use learnpnp_system::latency::plot::{ReferenceLine, percentile_plot};
use learnpnp_system::latency::{Latency, Percentiles};
use learnpnp_system::multiprocess::Clock;
use learnpnp_system::multiprocess::host::simulator::{FLOOR, ROUND_TRIP};
use learnpnp_system::multiprocess::supervisor::{
    Request, RunObserver, RunRecord, RunView, SupervisorConfig, SupervisorError, supervise_run,
};

/// One configuration of the benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Configuration {
    /// How processes wait.
    pub wait: WaitStrategy,
    /// A busy thread on every core beside the run.
    pub(crate) loaded: bool,
}

impl Configuration {
    /// Its name in files and tables: `yield-idle`, `block-loaded`, ...
    pub fn name(&self) -> String {
        format!("{}-{}", self.wait.name(), if self.loaded { "loaded" } else { "idle" })
    }
}

/// Percentiles of one histogram, and the median's ratio to the floor's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub(crate) struct Figures {
    /// Median, microseconds.
    pub(crate) p50: f64,
    /// 99th percentile.
    pub(crate) p99: f64,
    /// 99.9th percentile.
    pub(crate) p999: f64,
    /// Largest.
    pub max: f64,
    /// Values recorded.
    pub(crate) count: u64,
    /// p50 over the floor's p50 (of the same configuration).
    pub(crate) ratio_to_floor_p50: f64,
}

/// What one configuration measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct Measured {
    /// The bare round trip.
    pub floor: Figures,
    /// Snapshot to command, every keeper.
    pub(crate) roundtrip: Figures,
    /// The agents' compute time per cycle.
    pub(crate) compute: Figures,
    /// Cycles per second of the episode loop.
    pub(crate) cycles_per_second: f64,
    /// Real time: commands that missed their cycle.
    pub missed_deadlines: u64,
    /// Why the run ended early, if it did.
    pub(crate) failure: Option<String>,
}

/// Ends a configuration's run after a fixed time.
struct TimeLimit {
    limit: Duration,
    started: Instant,
}

impl RunObserver for TimeLimit {
    fn observe(&mut self, _view: &RunView<'_>) -> Vec<Request> {
        if self.started.elapsed() < self.limit {
            Vec::new()
        } else {
            vec![Request::Stop]
        }
    }
}

fn figures(h: &Latency, floor_p50: f64) -> Figures {
    let p: Percentiles = h.percentiles();
    Figures {
        p50: p.p50,
        p99: p.p99,
        p999: p.p999,
        max: p.max,
        count: h.count(),
        ratio_to_floor_p50: if floor_p50 > 0.0 { p.p50 / floor_p50 } else { 0.0 },
    }
}

/// The configurations: every strategy of `strategies`, idle then loaded.
pub fn configurations(strategies: &[WaitStrategy]) -> Vec<Configuration> {
    strategies
        .iter()
        .flat_map(|&wait| [false, true].map(|loaded| Configuration { wait, loaded }))
        .collect()
}

/// Runs `base` once per configuration for `seconds` each (its clock and
/// experiment; the wait strategy and load vary) and publishes the results in
/// `out`. Returns the table printed at the end.
pub fn bench_latency(
    base: &SupervisorConfig,
    configurations: &[Configuration],
    seconds: Duration,
    out: &mut ResultDir,
    stop: &AtomicBool,
) -> Result<String, SupervisorError> {
    let mut files = out.writer()?;
    let work = files.scratch_dir("configurations")?;
    let mut measured: BTreeMap<String, Measured> = BTreeMap::new();
    let mut shown: Vec<Latency> = Vec::new();
    for c in configurations {
        let config = SupervisorConfig {
            wait: c.wait,
            ..base.clone()
        };
        let load = c.loaded.then(CpuLoad::on_every_core);
        let mut limit = TimeLimit {
            limit: seconds,
            started: Instant::now(),
        };
        let record: RunRecord = supervise_run(&config, 0, &work.join(c.name()), stop, &mut limit)?;
        drop(load);
        let find = |name: &str| record.histograms.iter().find(|h| h.name() == name).cloned();
        let floor = find(FLOOR).unwrap_or_else(|| Latency::new(FLOOR));
        let roundtrip = find(ROUND_TRIP).unwrap_or_else(|| Latency::new(ROUND_TRIP));
        let mut compute = Latency::new("compute");
        for h in record.histograms.iter().filter(|h| h.name().starts_with("compute-")) {
            compute.merge(h)?;
        }
        let floor_p50 = floor.percentiles().p50;
        let totals = &record.sim.totals;
        measured.insert(
            c.name(),
            Measured {
                floor: figures(&floor, floor_p50),
                roundtrip: figures(&roundtrip, floor_p50),
                compute: figures(&compute, floor_p50),
                cycles_per_second: if totals.seconds > 0.0 {
                    totals.cycles as f64 / totals.seconds
                } else {
                    0.0
                },
                missed_deadlines: totals.missed_deadlines,
                failure: record.failure.clone(),
            },
        );
        for (kind, mut h) in [("floor", floor), ("roundtrip", roundtrip), ("compute", compute)] {
            let name = format!("{}-{kind}", c.name());
            files.add_text(&format!("latency/{name}.hgrm"), &h.to_hgrm())?;
            files.add_bytes(&format!("latency/{name}.hdr"), &h.to_bytes()?)?;
            if kind != "compute" {
                h = rename(
                    &h,
                    &format!("{} {}", c.name(), if kind == "floor" { "floor" } else { "round trip" }),
                )?;
                shown.push(h);
            }
        }
        if stop.load(std::sync::atomic::Ordering::Relaxed) {
            break;
        }
    }
    let json = serde_json::to_string_pretty(&measured).map_err(json_error("latency.json"))?;
    files.add_text("latency.json", &json)?;
    let refs: Vec<&Latency> = shown.iter().collect();
    let deadline = ReferenceLine {
        label: "deadline: 100 ms cycle".into(),
        micros: 100_000.0,
    };
    let title = format!(
        "{} mode: floor and round trip per wait strategy, idle and loaded",
        base.clock.name()
    );
    let svg = percentile_plot(&title, &refs, &[deadline])?;
    files.add_text("latency.svg", &svg)?;
    let table = table(base.clock, &measured);
    files.add_text("latency.txt", &table)?;
    let done = measured.len() as u64;
    files.commit(Progress {
        completed: done,
        planned: configurations.len() as u64,
    })?;
    Ok(table)
}

/// A copy of `h` under another name (for the plot's legend).
fn rename(h: &Latency, name: &str) -> Result<Latency, SupervisorError> {
    let mut renamed = Latency::new(name);
    renamed.merge(h)?;
    Ok(renamed)
}

fn table(clock: Clock, measured: &BTreeMap<String, Measured>) -> String {
    let mut text = format!(
        "{} mode, microseconds\n{:<16}{:>9}{:>9}{:>9}{:>10}{:>10}{:>8}{:>10}{:>10}{:>10}{:>8}\n",
        clock.name(),
        "configuration",
        "floor50",
        "rt p50",
        "rt p99",
        "rt p99.9",
        "rt max",
        "x floor",
        "comp p50",
        "comp p99",
        "cycles/s",
        "missed"
    );
    for (name, m) in measured {
        let _ = writeln!(
            text,
            "{name:<16}{:>9.1}{:>9.1}{:>9.1}{:>10.1}{:>10.1}{:>8.1}{:>10.2}{:>10.2}{:>10.0}{:>8}{}",
            m.floor.p50,
            m.roundtrip.p50,
            m.roundtrip.p99,
            m.roundtrip.p999,
            m.roundtrip.max,
            m.roundtrip.ratio_to_floor_p50,
            m.compute.p50,
            m.compute.p99,
            m.cycles_per_second,
            m.missed_deadlines,
            m.failure.as_deref().map(|f| format!("  ({f})")).unwrap_or_default()
        );
    }
    text
}
