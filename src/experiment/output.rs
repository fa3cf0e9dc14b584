//! Writing an experiment's results: CSV files, a JSON summary, SVG plots and
//! the learned values of run 0, published as one set in a
//! [`ResultDir`](crate::experiment::result_dir::ResultDir).

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::checkpoint;
use super::plot::{self, CurvePoint, Series};
use super::runner::ExperimentOutput;
use super::shard;
use super::spec::{ExperimentError, ExperimentSpec};
use super::stats::{Summary, summarize};
use crate::experiment::result_dir::{Progress, ResultDir, ResultWriter};
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
    /// `None` (`null`) where it does not apply (`greedy_not_applicable`).
    pub final_greedy_mean: Option<f64>,
    /// Its 95% confidence interval over runs.
    pub final_greedy_ci95: Option<[f64; 2]>,
    /// Wall-clock seconds for all runs.
    pub wall_seconds: f64,
    /// Episodes of every kind (learning, evaluation, greedy) executed.
    pub total_episodes: u64,
    /// `total_episodes / wall_seconds`.
    pub episodes_per_second: f64,
    /// Primitive actions (moves, cycles) of the learning episodes, per second
    /// of the whole wall time (evaluations included).
    pub actions_per_second: f64,
    /// Primitive actions of every episode played, of every kind (learning,
    /// evaluation, greedy, recorded; Keepaway: every simulated cycle), per
    /// second of wall time, in every domain; absent where the task does not
    /// count them (the multi-process runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cycles_per_second: Option<f64>,
    /// Whether every planned run completed; false for an interrupted
    /// experiment, whose figures are over the runs it completed.
    pub complete: bool,
    /// The runs the figures are over.
    pub runs_completed: usize,
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
pub(crate) fn greedy_not_applicable(spec: &ExperimentSpec) -> Option<&'static str> {
    if spec.domain.is_fixed_policy() {
        Some("n/a: a fixed policy learns nothing")
    } else if spec.protocol.greedy_episodes == 0 {
        Some("not measured (no greedy episode)")
    } else {
        None
    }
}

/// A score with its unit, e.g. `16.2 s` (four decimals without a unit).
pub(crate) fn with_unit(value: f64, unit: &str) -> String {
    if unit.is_empty() {
        format!("{value:.4}")
    } else {
        format!("{value:.2} {unit}")
    }
}

/// What a report says instead of a final score when no evaluation played an episode.
const NO_EVALUATION: &str = "no evaluation episodes";

/// What a report says instead of a confidence interval over one run (its
/// width would be zero, which says nothing about the spread).
const ONE_RUN: &str = "one run: no interval";

/// Whether the evaluations of `spec` measure anything: each plays
/// `eval_episodes` episodes, so with none there is no score (runs record 0),
/// unless the domain evaluates without episodes
/// (`DomainSpec::evaluates_without_episodes`: Sutton's grid).
fn evaluated(spec: &ExperimentSpec) -> bool {
    spec.protocol.eval_episodes > 0 || spec.domain.evaluates_without_episodes()
}

/// The final score's 95% confidence interval `low .. high` with its unit;
/// `None` over one run.
fn interval(summary: &SummaryFile) -> Option<String> {
    let unit = summary.spec.domain.score_unit();
    (summary.spec.protocol.runs > 1).then(|| {
        format!(
            "{} .. {}",
            with_unit(summary.final_ci95[0], unit),
            with_unit(summary.final_ci95[1], unit)
        )
    })
}

/// The final score's 95% confidence interval as text, with its unit, or why
/// there is none: `0.2400 .. 0.2860`, `one run: no interval` or `no evaluation
/// episodes` (a table cell; [`final_score_text`] is the whole phrase).
pub(crate) fn ci_text(summary: &SummaryFile) -> String {
    if evaluated(&summary.spec) {
        interval(summary).unwrap_or_else(|| ONE_RUN.to_string())
    } else {
        NO_EVALUATION.to_string()
    }
}

/// The mean final score with its unit, or `no evaluation episodes` when no
/// evaluation measured one (a table cell).
pub(crate) fn mean_text(summary: &SummaryFile) -> String {
    if evaluated(&summary.spec) {
        with_unit(summary.final_mean, summary.spec.domain.score_unit())
    } else {
        NO_EVALUATION.to_string()
    }
}

/// The final evaluation of `summary` as the lines reporting an experiment say
/// it: the mean with its unit and its 95% confidence interval over runs, or
/// what is known instead of an interval that would say nothing:
/// `final evaluation 0.2630 (95% CI 0.2400 .. 0.2860)`,
/// `final evaluation 15.55 s (one run: no interval)`, or
/// `no evaluation episodes` (the runs recorded no score). Only the text
/// changes: `summary.json` and the CSV files keep every number.
pub fn final_score_text(summary: &SummaryFile) -> String {
    if !evaluated(&summary.spec) {
        return NO_EVALUATION.to_string();
    }
    let mean = with_unit(summary.final_mean, summary.spec.domain.score_unit());
    match interval(summary) {
        Some(ci) => format!("final evaluation {mean} (95% CI {ci})"),
        None => format!("final evaluation {mean} ({ONE_RUN})"),
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
        cycles_per_second: output.actions_played().map(|n| n as f64 / wall),
        complete: output.is_complete(),
        runs_completed: output.runs.len(),
    }
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

/// Writes every result file of `output` into `dir` as one set (see
/// [`crate::experiment::result_dir`]: the previous set is replaced whole) and returns the
/// summary. The output of an interrupted experiment is written as a partial
/// result: its figures are over the completed runs, `summary.json` says
/// `"complete": false`, and [`checkpoint::CHECKPOINT`] keeps the runs for `--resume`.
pub fn write_results(output: &ExperimentOutput, dir: &mut ResultDir) -> Result<SummaryFile, ExperimentError> {
    write_shard_results(output, None, dir)
}

/// [`write_results`] for the runs of `shard` (when given): the runs are kept
/// ([`checkpoint::CHECKPOINT`]) even when the shard is the whole experiment,
/// and [`shard::SHARD_FILE`] names the shard, for `learnpnp merge`.
pub fn write_shard_results(
    output: &ExperimentOutput,
    shard: Option<&shard::ShardRecord>,
    dir: &mut ResultDir,
) -> Result<SummaryFile, ExperimentError> {
    write_shard_results_with(output, shard, dir, &[])
}

/// [`write_shard_results`] with further text files in the same set (such as
/// `migration.json`, what loading `--initial-values` into a revised plan did),
/// each as (name, contents).
pub fn write_shard_results_with(
    output: &ExperimentOutput,
    shard: Option<&shard::ShardRecord>,
    dir: &mut ResultDir,
    extra: &[(&str, String)],
) -> Result<SummaryFile, ExperimentError> {
    let mut files = dir.writer()?;
    let summary = stage_results(output, &mut files)?;
    for (name, text) in extra {
        files.add_text(name, text)?;
    }
    let json = serde_json::to_string_pretty(&summary).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
    files.add_text("summary.json", &json)?;
    if !output.is_complete() || shard.is_some() {
        files.add_bytes(checkpoint::CHECKPOINT, &checkpoint::encode(output)?)?;
    }
    if let Some(record) = shard {
        let json = serde_json::to_string_pretty(record).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
        files.add_text(shard::SHARD_FILE, &json)?;
    }
    files.commit(Progress {
        completed: output.runs.len() as u64,
        planned: output.spec.protocol.runs as u64,
    })?;
    Ok(summary)
}

/// Writes every result file of `output` but `summary.json` into `files`
/// (nothing is committed) and returns the summary: [`write_results`] writes it
/// as `summary.json`, a caller with a summary of its own (the multi-process
/// supervisor) embeds it there.
pub fn stage_results(output: &ExperimentOutput, files: &mut ResultWriter<'_>) -> Result<SummaryFile, ExperimentError> {
    let mut text = String::from("episode,mean,ci_low,ci_high,runs\n");
    for (episode, s) in curve(output) {
        let _ = writeln!(text, "{episode},{},{},{},{}", s.mean, s.ci_low, s.ci_high, s.n);
    }
    files.add_text("curve.csv", &text)?;

    let mut text = String::from("run,episode,score,greedy\n");
    for r in &output.runs {
        for (episode, score) in output.eval_points.iter().zip(&r.evals) {
            let _ = writeln!(text, "{},{episode},{score},{}", r.run, r.greedy);
        }
    }
    files.add_text("runs.csv", &text)?;

    if let Some(first) = output.first_run() {
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
        files.add_text("episodes.csv", &text)?;

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
            files.add_text("traces.csv", &text)?;
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
                plot::plot_scatter(&files.path_for(&file)?, &title, "learning episodes", &axis, series)
                    .map_err(|e| ExperimentError::Invalid(e.to_string()))?;
            }
        }

        for (agent, values) in first.values.iter().enumerate() {
            let name = if agent == 0 {
                "values.bin".to_string()
            } else {
                format!("values-agent{}.bin", agent + 1)
            };
            let bytes =
                persist::encode(Path::new(&name), values).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
            files.add_bytes(&name, &bytes)?;
        }

        for (i, log) in first.replays.iter().enumerate() {
            files.add_text(&format!("replays/{}", replay_name(i, first.replays.len())), log)?;
        }
    }

    let spec = &output.spec;
    let title = format!("{} on {}", spec.label, spec.domain.name());
    if spec.domain.is_fixed_policy() {
        // Nothing learns: one bar, not a curve over "learning" episodes.
        plot::plot_bars(
            &files.path_for("baseline.svg")?,
            &title,
            &bar_axis(spec),
            &unit_suffix(spec.domain.score_unit()),
            &[bar_of(&summary(output))],
        )
    } else {
        let references: Vec<plot::Reference> = spec.domain.reference().into_iter().collect();
        plot::plot_curves(
            &files.path_for("curve.svg")?,
            &title,
            "learning episodes",
            &score_axis(spec),
            &[series(output)],
            &references,
        )
    }
    .map_err(|e| ExperimentError::Invalid(e.to_string()))?;
    Ok(summary(output))
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

/// An experiment's final score as a bar: the mean over runs at the last
/// evaluation, with its 95% confidence interval.
pub fn bar_of(summary: &SummaryFile) -> plot::Bar {
    plot::Bar {
        label: summary.spec.label.clone(),
        mean: summary.final_mean,
        low: summary.final_ci95[0],
        high: summary.final_ci95[1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::options::{DomainName, ExperimentOptions};
    use crate::experiment::spec::Algorithm;

    /// The summary of `runs` runs in `domain` with `eval_episodes` episodes
    /// per evaluation, its figures made up (the interval is zero-wide over one run).
    fn made_up(domain: DomainName, runs: usize, eval_episodes: usize) -> SummaryFile {
        let spec = ExperimentOptions {
            algo: Some(Algorithm::SarsaLambda),
            runs: Some(runs),
            eval_episodes: Some(eval_episodes),
            ..ExperimentOptions::default()
        }
        .spec(domain)
        .expect("a valid experiment");
        let mean = 15.5512;
        SummaryFile {
            spec,
            final_mean: mean,
            final_ci95: if runs > 1 { [15.2, 15.9] } else { [mean, mean] },
            final_greedy_mean: Some(16.1),
            final_greedy_ci95: Some([16.0, 16.2]),
            wall_seconds: 1.0,
            total_episodes: 100,
            episodes_per_second: 100.0,
            actions_per_second: 1000.0,
            cycles_per_second: None,
            complete: true,
            runs_completed: runs,
        }
    }

    #[test]
    fn several_runs_give_the_mean_and_its_interval() {
        let s = made_up(DomainName::ParrRussell, 20, 20);
        assert_eq!(
            final_score_text(&s),
            "final evaluation 15.5512 (95% CI 15.2000 .. 15.9000)"
        );
        assert_eq!(
            (mean_text(&s), ci_text(&s)),
            ("15.5512".into(), "15.2000 .. 15.9000".into())
        );
        let s = made_up(DomainName::KeepawayPass, 4, 20);
        assert_eq!(
            final_score_text(&s),
            "final evaluation 15.55 s (95% CI 15.20 s .. 15.90 s)"
        );
    }

    #[test]
    fn one_run_gives_the_mean_and_no_interval() {
        let s = made_up(DomainName::KeepawayPass, 1, 20);
        assert_eq!(final_score_text(&s), "final evaluation 15.55 s (one run: no interval)");
        assert_eq!(ci_text(&s), "one run: no interval");
        assert_eq!(mean_text(&s), "15.55 s");
    }

    #[test]
    fn no_evaluation_episodes_give_no_score() {
        for runs in [1, 20] {
            let s = made_up(DomainName::ParrRussell, runs, 0);
            assert_eq!(final_score_text(&s), "no evaluation episodes");
            assert_eq!(ci_text(&s), "no evaluation episodes");
            assert_eq!(mean_text(&s), "no evaluation episodes");
        }
        // Sutton's grid evaluates the greedy policy, with no evaluation episode.
        let s = made_up(DomainName::Sutton, 20, 0);
        assert_eq!(
            final_score_text(&s),
            "final evaluation 15.5512 (95% CI 15.2000 .. 15.9000)"
        );
    }
}
