//! How the generic path's cost grows with the agents: the corridor world
//! (`learnpnp-corridor`, a trivial world in Rust) run lock-step with 1, 2, 4,
//! ... agents, each run measuring its cycles per second, the round trip from
//! a snapshot's publication to the world's reading of its command, and the
//! bare iceoryx2 round trip of the same payload (the floor) on the same
//! machine just before, with what a cycle spends above it (the agents'
//! compute, the world's turnaround). Writes `bench-world.csv`, `bench-world.svg` and the
//! runs' own reports (`agents-N/`), and returns the table.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::AtomicBool;

use plotters::prelude::*;
use serde::Serialize;

use learnpnp::experiment::plot::{FONT, PLOT_SIZE, colour};
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::spec::DomainSpec;
use learnpnp_system::latency::plot::PlotFailure;
use learnpnp_system::multiprocess::supervisor::{Progress, SupervisorConfig, SupervisorError, supervise};

/// One run of the benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WorldFigures {
    /// Agents in the run.
    pub agents: usize,
    /// Lock-step cycles (world steps) per second.
    pub(crate) cycles_per_second: f64,
    /// Round trip, median, microseconds.
    pub(crate) round_trip_p50: f64,
    /// Round trip, 99th percentile.
    pub(crate) round_trip_p99: f64,
    /// The floor's median.
    pub(crate) floor_p50: f64,
    /// The floor's mean (its back-to-back round trips per second are the inverse).
    pub(crate) floor_mean: f64,
    /// A cycle's mean duration (1 / cycles per second) over the floor's mean:
    /// lock-step cycles per second against bare round trips per second.
    pub(crate) cycle_over_floor: f64,
    /// The agents' compute time per cycle (executor and learner), median.
    pub(crate) compute_p50: f64,
    /// The world's turnaround (reading a command to publishing the next
    /// snapshot), median.
    pub(crate) world_p50: f64,
}

/// A column of the table and the CSV: its header, its CSV name, its width
/// and decimals in the table, its decimals in the CSV, and its value.
type Column = (
    &'static str,
    &'static str,
    usize,
    usize,
    usize,
    fn(&WorldFigures) -> f64,
);

/// The benchmark's columns.
const COLUMNS: [Column; 9] = [
    ("agents", "agents", 7, 0, 0, |f| f.agents as f64),
    ("cycles/s", "cycles_per_second", 14, 0, 1, |f| f.cycles_per_second),
    ("round trip p50", "round_trip_p50_us", 16, 1, 2, |f| f.round_trip_p50),
    ("round trip p99", "round_trip_p99_us", 16, 1, 2, |f| f.round_trip_p99),
    ("floor p50", "floor_p50_us", 12, 1, 2, |f| f.floor_p50),
    ("floor mean", "floor_mean_us", 12, 2, 3, |f| f.floor_mean),
    ("cycle / floor", "cycle_over_floor", 16, 2, 3, |f| f.cycle_over_floor),
    ("compute p50", "compute_p50_us", 14, 2, 3, |f| f.compute_p50),
    ("world p50", "world_turnaround_p50_us", 12, 2, 3, |f| f.world_p50),
];

/// Runs `base` (a world run whose command is the corridor) with each of
/// `agents`, writing each run's report under `out/agents-N`, then the table.
pub fn bench_world(
    base: &SupervisorConfig,
    agents: &[usize],
    out: &Path,
    stop: &AtomicBool,
) -> Result<(String, Vec<WorldFigures>), SupervisorError> {
    let mut figures = Vec::new();
    for &n in agents {
        let mut config = base.clone();
        if let DomainSpec::World { plans, .. } = &mut config.spec.domain {
            let plan = plans[0].clone();
            *plans = vec![plan; n];
        }
        let mut dir = ResultDir::open(out.join(format!("agents-{n}")))?;
        let report = supervise(&config, &mut dir, stop, &mut Progress(|_, _| {}))?;
        let s = &report.summary;
        let cycle_us = if s.cycles_per_second > 0.0 {
            1e6 / s.cycles_per_second
        } else {
            0.0
        };
        figures.push(WorldFigures {
            agents: n,
            cycles_per_second: s.cycles_per_second,
            round_trip_p50: s.latency_us.p50,
            round_trip_p99: s.latency_us.p99,
            floor_p50: s.floor_us.p50,
            floor_mean: s.floor_us.mean,
            cycle_over_floor: if s.floor_us.mean > 0.0 {
                cycle_us / s.floor_us.mean
            } else {
                0.0
            },
            compute_p50: s.compute_us.p50,
            world_p50: s.world_turnaround_us.map_or(0.0, |p| p.p50),
        });
    }
    let mut table = String::new();
    let mut csv = String::new();
    for (header, name, width, ..) in COLUMNS {
        let _ = write!(table, "{header:>width$}");
        let _ = write!(csv, "{}{name}", if csv.is_empty() { "" } else { "," });
    }
    for f in &figures {
        table.push('\n');
        csv.push('\n');
        for (i, (_, _, width, decimals, csv_decimals, value)) in COLUMNS.into_iter().enumerate() {
            let _ = write!(table, "{:>width$.decimals$}", value(f));
            let _ = write!(csv, "{}{:.csv_decimals$}", if i == 0 { "" } else { "," }, value(f));
        }
    }
    table.push('\n');
    csv.push('\n');
    let write = |name: &str, bytes: &[u8]| {
        let path = out.join(name);
        atomic_file::write_atomic(&path, bytes).map_err(|source| SupervisorError::Io { path, source })
    };
    write("bench-world.csv", csv.as_bytes())?;
    write("bench-world.svg", plot(&figures)?.as_bytes())?;
    Ok((table, figures))
}

/// A panel's title, its axis unit and its points (agents, value).
type Series = (&'static str, &'static str, Vec<(f64, f64)>);

/// Cycles per second and the round trip's median against the agents, side by side.
fn plot(figures: &[WorldFigures]) -> Result<String, PlotFailure> {
    let fail = |e: &dyn std::fmt::Display| PlotFailure::new("the world benchmark's plot", e);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (PLOT_SIZE.0, PLOT_SIZE.1)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        let panels = root.split_evenly((1, 2));
        let most = figures.iter().map(|f| f.agents).max().unwrap_or(1) as f64;
        let series: [Series; 2] = [
            (
                "lock-step cycles per second",
                "cycles/s",
                figures.iter().map(|f| (f.agents as f64, f.cycles_per_second)).collect(),
            ),
            (
                "round trip p50 (µs)",
                "µs",
                figures.iter().map(|f| (f.agents as f64, f.round_trip_p50)).collect(),
            ),
        ];
        for (i, (panel, (title, unit, points))) in panels.iter().zip(series).enumerate() {
            let top = points.iter().map(|&(_, y)| y).fold(0.0, f64::max) * 1.1 + 1e-9;
            let mut chart = ChartBuilder::on(panel)
                .caption(title, (FONT, 16))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(60)
                .build_cartesian_2d((1.0..most.max(2.0)).log_scale(), 0.0..top)
                .map_err(|e| fail(&e))?;
            chart
                .configure_mesh()
                .x_desc("agents")
                .y_desc(unit)
                .label_style((FONT, 12))
                .draw()
                .map_err(|e| fail(&e))?;
            let style = colour(i).stroke_width(2);
            chart
                .draw_series(LineSeries::new(points.clone(), style))
                .map_err(|e| fail(&e))?;
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 3, colour(i).filled())))
                .map_err(|e| fail(&e))?;
        }
        root.present().map_err(|e| fail(&e))?;
    }
    Ok(svg)
}
