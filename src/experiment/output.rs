//! Writing an experiment's results: CSV files, a JSON summary, SVG plots and
//! the learned values of run 0.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::plot::{self, CurvePoint, Series};
use super::runner::ExperimentOutput;
use super::spec::{ExperimentError, ExperimentSpec};
use super::stats::{Summary, summarize};
use crate::atomic_file::write_atomic;
use crate::learning::persist;

/// One named series of (episode, value) points.
type Scatter = (String, Vec<(f64, f64)>);

/// The figures of `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SummaryFile {
    /// The full configuration, seed included.
    pub spec: ExperimentSpec,
    /// Mean evaluation score at the last evaluation point.
    pub final_mean: f64,
    /// Its 95% confidence interval over runs.
    pub final_ci95: [f64; 2],
    /// Mean return of each run's greedy policy at the end, averaged over runs;
    /// `None` (`null`) where it does not apply ([`greedy_not_applicable`]).
    pub final_greedy_mean: Option<f64>,
    /// Its 95% confidence interval over runs.
    pub final_greedy_ci95: Option<[f64; 2]>,
    /// Wall-clock seconds for all runs.
    pub wall_seconds: f64,
    /// Episodes of every kind (learning, evaluation, greedy) executed.
    pub total_episodes: u64,
    /// `total_episodes / wall_seconds`.
    pub episodes_per_second: f64,
    /// Primitive actions (moves, cycles) per second over learning episodes.
    pub actions_per_second: f64,
    /// Keepaway: simulated cycles per second over learning episodes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycles_per_second: Option<f64>,
}

/// The file name of recorded episode `i` (0-based) of `count`:
/// `episode-1.rcg`, or `episode-01.rcg` ... when there are ten or more.
pub fn replay_name(i: usize, count: usize) -> String {
    let width = count.to_string().len();
    format!("episode-{:0width$}.rcg", i + 1)
}

/// The curve: mean and 95% CI over runs at each evaluation point.
pub fn curve(output: &ExperimentOutput) -> Vec<(u64, Summary)> {
    output
        .eval_points
        .iter()
        .enumerate()
        .map(|(i, &episode)| {
            let samples: Vec<f64> = output.runs.iter().filter_map(|r| r.evals.get(i).copied()).collect();
            (episode, summarize(&samples))
        })
        .collect()
}

/// Why an experiment has no greedy score, if it has none: a fixed policy
/// learns nothing to be greedy about, and a protocol may play no greedy episode.
pub fn greedy_not_applicable(spec: &ExperimentSpec) -> Option<&'static str> {
    if spec.domain.is_fixed_policy() {
        Some("n/a: a fixed policy learns nothing")
    } else if spec.protocol.greedy_episodes == 0 {
        Some("not measured (no greedy episode)")
    } else {
        None
    }
}

/// A score with its unit, e.g. `16.2 s` (four decimals without a unit).
pub fn with_unit(value: f64, unit: &str) -> String {
    if unit.is_empty() {
        format!("{value:.4}")
    } else {
        format!("{value:.2} {unit}")
    }
}

/// The final score's 95% confidence interval as text, with its unit, or why there is none.
pub fn ci_text(summary: &SummaryFile) -> String {
    let unit = summary.spec.domain.score_unit();
    if summary.spec.protocol.runs < 2 {
        "n/a (one run)".to_string()
    } else {
        format!(
            "{} .. {}",
            with_unit(summary.final_ci95[0], unit),
            with_unit(summary.final_ci95[1], unit)
        )
    }
}

/// The greedy score of `summary` as text: the value with its unit, or why it does not apply.
pub fn greedy_text(summary: &SummaryFile) -> String {
    match (summary.final_greedy_mean, greedy_not_applicable(&summary.spec)) {
        (Some(mean), None) => with_unit(mean, summary.spec.domain.score_unit()),
        (_, Some(why)) => why.to_string(),
        (None, None) => "n/a".to_string(),
    }
}

/// The vertical axis of a learning curve over `runs` runs: what is measured,
/// its unit, and whether a mean and interval are drawn.
pub fn score_axis(spec: &ExperimentSpec) -> String {
    let unit = spec.domain.score_unit();
    let name = if unit.is_empty() {
        format!("evaluation {}", spec.domain.score_name())
    } else {
        format!("{} ({unit}), evaluation", spec.domain.score_name())
    };
    if spec.protocol.runs > 1 {
        format!("{name}: mean of {} runs, 95% CI", spec.protocol.runs)
    } else {
        format!("{name}: one run")
    }
}

/// The summary of an experiment.
pub fn summary(output: &ExperimentOutput) -> SummaryFile {
    let last = curve(output).last().map(|(_, s)| *s).unwrap_or_else(|| summarize(&[]));
    let greedy: Vec<f64> = output.runs.iter().map(|r| r.greedy).collect();
    let greedy = summarize(&greedy);
    let greedy_applies = greedy_not_applicable(&output.spec).is_none();
    let total = output.total_episodes();
    let wall = output.wall_seconds.max(1e-9);
    SummaryFile {
        spec: output.spec.clone(),
        final_mean: last.mean,
        final_ci95: [last.ci_low, last.ci_high],
        final_greedy_mean: greedy_applies.then_some(greedy.mean),
        final_greedy_ci95: greedy_applies.then_some([greedy.ci_low, greedy.ci_high]),
        wall_seconds: output.wall_seconds,
        total_episodes: total,
        episodes_per_second: total as f64 / wall,
        actions_per_second: output.total_actions() as f64 / wall,
        cycles_per_second: matches!(output.spec.domain, crate::experiment::spec::DomainSpec::Keepaway { .. })
            .then(|| output.total_actions() as f64 / wall),
    }
}

fn write_text(path: &Path, text: &str) -> Result<(), ExperimentError> {
    write_atomic(path, text.as_bytes()).map_err(|source| ExperimentError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The curve as a plottable series.
pub fn series(output: &ExperimentOutput) -> Series {
    Series {
        label: output.spec.label.clone(),
        points: curve(output)
            .into_iter()
            .map(|(x, s)| CurvePoint {
                x: x as f64,
                mean: s.mean,
                low: s.ci_low,
                high: s.ci_high,
            })
            .collect(),
    }
}

/// Writes every result file of `output` into `dir` (created if needed) and returns the summary.
pub fn write_results(output: &ExperimentOutput, dir: &Path) -> Result<SummaryFile, ExperimentError> {
    let io = |path: PathBuf| move |source| ExperimentError::Io { path, source };
    std::fs::create_dir_all(dir).map_err(io(dir.to_path_buf()))?;

    let mut text = String::from("episode,mean,ci_low,ci_high,runs\n");
    for (episode, s) in curve(output) {
        let _ = writeln!(text, "{episode},{},{},{},{}", s.mean, s.ci_low, s.ci_high, s.n);
    }
    write_text(&dir.join("curve.csv"), &text)?;

    let mut text = String::from("run,episode,score,greedy\n");
    for (run, r) in output.runs.iter().enumerate() {
        for (episode, score) in output.eval_points.iter().zip(&r.evals) {
            let _ = writeln!(text, "{run},{episode},{score},{}", r.greedy);
        }
    }
    write_text(&dir.join("runs.csv"), &text)?;

    if let Some(first) = output.runs.first() {
        let mut text = String::from("episode,return,actions,steps,exploratory\n");
        for e in &first.episodes {
            let o = e.outcome;
            let _ = writeln!(
                text,
                "{},{},{},{},{}",
                e.episode,
                o.ret,
                o.actions,
                o.steps,
                u8::from(o.exploratory)
            );
        }
        write_text(&dir.join("episodes.csv"), &text)?;

        if !first.traces.is_empty() {
            let mut text = String::from("episode,name,value\n");
            let mut by_name: Vec<Scatter> = Vec::new();
            for (episode, values) in &first.traces {
                for (name, v) in values {
                    let _ = writeln!(text, "{episode},{name},{v}");
                    match by_name.iter_mut().find(|(n, _)| n == name) {
                        Some((_, points)) => points.push((*episode as f64, *v)),
                        None => by_name.push((name.clone(), vec![(*episode as f64, *v)])),
                    }
                }
            }
            write_text(&dir.join("traces.csv"), &text)?;
            for (_, points) in &mut by_name {
                points.retain(|(_, v)| v.is_finite());
            }
            // Names `agent/option` get one plot per agent (`traces-agent.svg`).
            let mut groups: Vec<(Option<String>, Vec<Scatter>)> = Vec::new();
            for (name, points) in by_name {
                let (group, label) = match name.split_once('/') {
                    Some((g, l)) => (Some(g.to_string()), l.to_string()),
                    None => (None, name),
                };
                match groups.iter_mut().find(|(g, _)| *g == group) {
                    Some((_, series)) => series.push((label, points)),
                    None => groups.push((group, vec![(label, points)])),
                }
            }
            for (group, series) in &groups {
                let (file, title) = match group {
                    Some(g) => (
                        format!("traces-{g}.svg"),
                        format!("{}: values of {g}'s options (run 0)", output.spec.label),
                    ),
                    None => (
                        "traces.svg".to_string(),
                        format!("{}: values of the traced options (run 0)", output.spec.label),
                    ),
                };
                let axis = match output.spec.domain.score_unit() {
                    "" => "value".to_string(),
                    unit => format!(
                        "value: expected {} still to come ({unit})",
                        output.spec.domain.score_name()
                    ),
                };
                plot::plot_scatter(&dir.join(file), &title, "learning episodes", &axis, series)
                    .map_err(|e| ExperimentError::Invalid(e.to_string()))?;
            }
        }

        for (agent, values) in first.values.iter().enumerate() {
            let name = if agent == 0 {
                "values.bin".to_string()
            } else {
                format!("values-agent{}.bin", agent + 1)
            };
            persist::save(&dir.join(name), values).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
        }

        if !first.replays.is_empty() {
            let replays = dir.join("replays");
            std::fs::create_dir_all(&replays).map_err(io(replays.clone()))?;
            for (i, log) in first.replays.iter().enumerate() {
                write_text(&replays.join(replay_name(i, first.replays.len())), log)?;
            }
        }
    }

    let summary = summary(output);
    let json = serde_json::to_string_pretty(&summary).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
    write_text(&dir.join("summary.json"), &json)?;

    let spec = &output.spec;
    let title = format!("{} on {}", spec.label, spec.domain.name());
    if spec.domain.is_fixed_policy() {
        // Nothing learns: one bar, not a curve over "learning" episodes.
        plot::plot_bars(
            &dir.join("baseline.svg"),
            &title,
            &bar_axis(spec),
            &unit_suffix(spec.domain.score_unit()),
            &[bar(output)],
        )
    } else {
        let references: Vec<plot::Reference> = spec.domain.reference().into_iter().collect();
        plot::plot_curves(
            &dir.join("curve.svg"),
            &title,
            "learning episodes",
            &score_axis(spec),
            &[series(output)],
            &references,
        )
    }
    .map_err(|e| ExperimentError::Invalid(e.to_string()))?;
    Ok(summary)
}

/// The vertical axis of a bar chart of fixed policies like `spec`.
pub fn bar_axis(spec: &ExperimentSpec) -> String {
    let unit = spec.domain.score_unit();
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" ({unit})")
    };
    format!(
        "mean {}{unit}, {} episodes per run, 95% CI over {} runs",
        spec.domain.score_name(),
        spec.protocol.eval_episodes,
        spec.protocol.runs
    )
}

/// A unit written after a number on a chart (` s`), or nothing.
pub fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}

/// The experiment's final score as a bar: the mean over runs at the last
/// evaluation, with its 95% confidence interval.
pub fn bar(output: &ExperimentOutput) -> plot::Bar {
    let last = curve(output).last().map(|(_, s)| *s).unwrap_or_else(|| summarize(&[]));
    plot::Bar {
        label: output.spec.label.clone(),
        mean: last.mean,
        low: last.ci_low,
        high: last.ci_high,
    }
}
