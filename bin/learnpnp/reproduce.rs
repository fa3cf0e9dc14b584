//! `learnpnp reproduce`: the thesis's figures from their presets.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use atomic_file::write_atomic;
use clap::Args;
use learnpnp::experiment::output::{
    SummaryFile, bar_axis, bar_of, final_score_text, greedy_text, score_axis, series, unit_suffix,
};
use learnpnp::experiment::plot::{Series, plot_bars, plot_curves, read_curve_csv};
use learnpnp::experiment::presets::{self, Figure, FigureKind};
use learnpnp::experiment::progress::{Rates, clock};
use learnpnp::experiment::ranges;
use learnpnp::experiment::report::summary_markdown;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::shard::Shard;
use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec};
use learnpnp::experiment::verdict::verdict_markdown;
use learnpnp_flags::args::named;
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_keepaway::params::RefereeRule;
use serde::{Deserialize, Serialize};

use super::experiment::{Finished, default_threads, run_into};

#[derive(Args, Debug)]
pub struct ReproduceArgs {
    /// Figures to reproduce (e.g. 6.3 6.13); all when none is given.
    figures: Vec<String>,
    /// Directory for the results (one sub-directory per figure).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Worker threads (default: all cores; 1 to 256).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::THREADS.parse_usize(s))]
    threads: Option<usize>,
    /// Override the number of runs of every curve (for a quick look; 1 to 100000).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::RUNS.parse_usize(s))]
    runs: Option<usize>,
    /// Continue an interrupted reproduction: curves already complete are kept,
    /// a partial curve continues where it stopped.
    #[arg(long)]
    resume: bool,
    /// Play only shard I of N of every curve (0-based; see `learnpnp
    /// experiment --shard`); `learnpnp merge OUT DIR...` combines the shards
    /// and draws the figures.
    #[arg(long)]
    shard: Option<Shard>,
    /// Keepaway figures: the referee's turnover rule, rcssserver-11 (the
    /// default, 4 cycles of taker possession) or rcssserver-9.4.5 (5 cycles).
    #[arg(long, value_parser = named::<RefereeRule>())]
    referee: Option<RefereeRule>,
    /// Keepaway figures: the distance d (m) at which the fixed keepers pass and
    /// the learner's closest-taker feature flips (default: the text-fixed d,
    /// `DEFAULT_HOLD_THRESHOLD`; 5 for the framework's radius used before issue 56).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    keepaway_threshold: Option<f64>,
}

/// The file of a reproduction's shard naming what it reproduced, for `learnpnp merge`.
pub const REPRODUCE_SHARD_FILE: &str = "reproduce-shard.json";

/// What [`REPRODUCE_SHARD_FILE`] says.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReproduceShard {
    /// The shard.
    pub shard: Shard,
    /// The figures reproduced (all when empty).
    pub figures: Vec<String>,
    /// The runs override, if any.
    pub runs: Option<usize>,
    /// The Keepaway referee override, if any.
    #[serde(default)]
    pub referee: Option<RefereeRule>,
    /// The Keepaway threshold override, if any.
    #[serde(default)]
    pub keepaway_threshold: Option<f64>,
}

impl Default for ReproduceArgs {
    fn default() -> Self {
        ReproduceArgs {
            figures: Vec::new(),
            out: PathBuf::from("out"),
            threads: None,
            runs: None,
            resume: false,
            shard: None,
            referee: None,
            keepaway_threshold: None,
        }
    }
}

impl ReproduceArgs {
    /// Draws the figures (and writes the summary) of merged shards in `out`:
    /// a resumed reproduction in which every curve is already complete.
    pub fn of_merged(record: &ReproduceShard, out: PathBuf) -> Self {
        ReproduceArgs {
            figures: record.figures.clone(),
            out,
            runs: record.runs,
            referee: record.referee,
            keepaway_threshold: record.keepaway_threshold,
            resume: true,
            ..ReproduceArgs::default()
        }
    }
}

/// The summary and series of a curve whose complete results `dir` already holds.
fn read_back(dir: &ResultDir, label: &str) -> Result<(SummaryFile, Series)> {
    let v: serde_json::Value = serde_json::from_slice(&dir.read("summary.json")?)
        .with_context(|| format!("{}: summary.json is not JSON", dir.path().display()))?;
    let spec: ExperimentSpec = serde_json::from_value(v["spec"].clone())
        .with_context(|| format!("{}: summary.json has no experiment spec", dir.path().display()))?;
    // JSON writes non-finite numbers as null.
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
    let pair = |v: &serde_json::Value| [number(&v[0]), number(&v[1])];
    let summary = SummaryFile {
        spec,
        final_mean: number(&v["final_mean"]),
        final_ci95: pair(&v["final_ci95"]),
        final_greedy_mean: v["final_greedy_mean"].as_f64(),
        final_greedy_ci95: v["final_greedy_ci95"].is_array().then(|| pair(&v["final_greedy_ci95"])),
        wall_seconds: number(&v["wall_seconds"]),
        total_episodes: v["total_episodes"].as_u64().unwrap_or(0),
        episodes_per_second: number(&v["episodes_per_second"]),
        actions_per_second: number(&v["actions_per_second"]),
        cycles_per_second: v["cycles_per_second"].as_f64(),
        complete: v["complete"].as_bool().unwrap_or(true),
        runs_completed: v["runs_completed"].as_u64().unwrap_or(0) as usize,
    };
    let points = read_curve_csv(&dir.path().join("curve.csv"))?;
    Ok((
        summary,
        Series {
            label: label.to_string(),
            points,
        },
    ))
}

fn slug(label: &str) -> String {
    let mut s: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    while s.contains("--") {
        s = s.replace("--", "-");
    }
    s.trim_matches('-').to_string()
}

fn selected(names: &[String]) -> Result<Vec<Figure>> {
    if names.is_empty() {
        return Ok(presets::figures());
    }
    names
        .iter()
        .map(|n| {
            presets::figure(n).with_context(|| {
                let known: Vec<&str> = presets::figures().iter().map(|f| f.id).collect();
                format!("no preset for figure '{n}' (known: {})", known.join(", "))
            })
        })
        .collect()
}

pub fn run(args: &ReproduceArgs) -> Result<()> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let threads = args.threads.unwrap_or_else(default_threads);
    let figures = selected(&args.figures)?;
    if figures.is_empty() {
        bail!("nothing to reproduce");
    }
    // Every result directory is checked and locked before any work.
    let mut plans = Vec::new();
    for mut figure in figures {
        let dir = args.out.join(format!("fig{}", figure.id));
        let mut dirs = Vec::new();
        for spec in &mut figure.curves {
            if let Some(runs) = args.runs {
                spec.protocol.runs = runs;
            }
            if let DomainSpec::Keepaway { config, .. } = &mut spec.domain {
                if let Some(referee) = args.referee {
                    config.referee = referee;
                }
                if let Some(d) = args.keepaway_threshold {
                    config.hold_threshold = d;
                    config.thresholds.closest_taker = d;
                }
            }
            spec.validate()
                .with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
            dirs.push(ResultDir::open(dir.join(slug(&spec.label)))?);
        }
        plans.push((figure, dir, dirs));
    }
    let total = plans.len();
    let curves: usize = plans.iter().map(|(f, _, _)| f.curves.len()).sum();
    println!(
        "{total} figure(s), {curves} curve(s) on {threads} worker threads into {}; each curve's full \
         configuration is in its directory's summary.json",
        args.out.display()
    );
    let started = Instant::now();
    let mut rates = Rates::default();
    let mut done: Vec<(Figure, Vec<SummaryFile>)> = Vec::new();
    for k in 0..plans.len() {
        let (head, tail) = plans.split_at_mut(k + 1);
        let later: Vec<&ExperimentSpec> = tail.iter().flat_map(|(f, _, _)| f.curves.iter()).collect();
        let (figure, dir, dirs) = &mut head[k];
        let figure = figure.clone();
        println!("Figure {} ({} of {total}): {}", figure.id, k + 1, figure.title);
        let mut summaries = Vec::new();
        let mut all = Vec::new();
        for (j, (spec, curve_dir)) in figure.curves.iter().zip(dirs.iter_mut()).enumerate() {
            let estimate = rates.estimate(figure.curves[j..].iter().chain(later.iter().copied()));
            println!(
                "  [figure {} of {total}, curve {} of {}; {} elapsed, {estimate}] {}",
                k + 1,
                j + 1,
                figure.curves.len(),
                clock(started.elapsed()),
                spec.label
            );
            let finished = run_into(spec, curve_dir, args.resume, threads, &interrupt, args.shard, None)
                .with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
            if args.shard.is_some() {
                // A shard's curve is a share of the runs: merged, then drawn.
                continue;
            }
            let (summary, curve, note) = match finished {
                Finished::Complete { summary, output } => {
                    rates.record(spec, summary.wall_seconds);
                    let note = format!("{:.0} episodes/s", summary.episodes_per_second);
                    (*summary, series(&output), note)
                }
                Finished::AlreadyComplete => {
                    let (summary, curve) = read_back(curve_dir, &spec.label)?;
                    (summary, curve, "(already complete)".to_string())
                }
            };
            println!(
                "  {:<28} {}  greedy {}  {} runs {:.2} s  {note}",
                spec.label,
                final_score_text(&summary),
                greedy_text(&summary),
                spec.protocol.runs,
                summary.wall_seconds,
            );
            all.push(curve);
            summaries.push(summary);
        }
        if args.shard.is_some() {
            continue;
        }
        let title = format!("Figure {}: {}", figure.id, figure.title);
        let path = dir.join("figure.svg");
        let drawn = match (figure.kind, figure.curves.first()) {
            (FigureKind::Curves, Some(first)) => {
                let references: Vec<_> = first.domain.reference().into_iter().collect();
                plot_curves(
                    &path,
                    &title,
                    "learning episodes",
                    &score_axis(first),
                    &all,
                    &references,
                )
            }
            (FigureKind::Bars, Some(first)) => {
                let bars: Vec<_> = summaries.iter().map(bar_of).collect();
                plot_bars(
                    &path,
                    &title,
                    &bar_axis(first),
                    &unit_suffix(first.domain.score_unit()),
                    &bars,
                )
            }
            _ => Ok(()),
        };
        drawn.with_context(|| format!("plotting {}", path.display()))?;
        done.push((figure, summaries));
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    if let Some(shard) = args.shard {
        let record = ReproduceShard {
            shard,
            figures: args.figures.clone(),
            runs: args.runs,
            referee: args.referee,
            keepaway_threshold: args.keepaway_threshold,
        };
        let path = args.out.join(REPRODUCE_SHARD_FILE);
        write_atomic(&path, &serde_json::to_vec_pretty(&record)?)?;
        println!(
            "shard {shard} of every curve in {}; combine the shards with learnpnp merge OUT DIR...",
            args.out.display()
        );
        return Ok(());
    }
    let path = args.out.join("summary.md");
    let listed: Vec<(&Figure, &[SummaryFile])> = done.iter().map(|(f, s)| (f, s.as_slice())).collect();
    write_atomic(&path, summary_markdown(&listed).as_bytes())?;
    let verdicts = verdict_markdown(&listed);
    if verdicts.lines().count() > 2 {
        println!("\nThe thesis's claims, checked (also in summary.md):\n\n{verdicts}");
    }
    println!(
        "summary table: {} ({} figures in {})",
        path.display(),
        done.len(),
        clock(started.elapsed())
    );
    Ok(())
}
