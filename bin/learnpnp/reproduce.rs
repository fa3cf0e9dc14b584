//! `learnpnp reproduce`: the thesis's figures from their presets.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp::atomic_file::write_atomic;
use learnpnp::experiment::output::{
    SummaryFile, bar, bar_axis, ci_text, greedy_text, score_axis, series, unit_suffix, with_unit, write_results,
};
use learnpnp::experiment::plot::{plot_bars, plot_curves};
use learnpnp::experiment::presets::{self, Figure, FigureKind};
use learnpnp::experiment::progress::{Rates, clock};
use learnpnp::experiment::report::summary_markdown;
use learnpnp::experiment::runner::run_experiment;

use super::experiment::default_threads;

#[derive(Args, Debug)]
pub struct ReproduceArgs {
    /// Figures to reproduce (e.g. 6.3 6.13); all when none is given.
    figures: Vec<String>,
    /// Directory for the results (one sub-directory per figure).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Override the number of runs of every curve (for a quick look).
    #[arg(long)]
    runs: Option<usize>,
}

impl Default for ReproduceArgs {
    fn default() -> Self {
        ReproduceArgs {
            figures: Vec::new(),
            out: PathBuf::from("out"),
            threads: None,
            runs: None,
        }
    }
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
    let threads = args.threads.unwrap_or_else(default_threads);
    let mut figures = selected(&args.figures)?;
    if figures.is_empty() {
        bail!("nothing to reproduce");
    }
    if let Some(runs) = args.runs {
        for spec in figures.iter_mut().flat_map(|f| f.curves.iter_mut()) {
            spec.protocol.runs = runs;
        }
    }
    let curves: usize = figures.iter().map(|f| f.curves.len()).sum();
    println!(
        "{} figure(s), {curves} curve(s) on {threads} worker threads into {}; each curve's full configuration \
         is in its directory's summary.json",
        figures.len(),
        args.out.display()
    );
    let started = Instant::now();
    let mut rates = Rates::default();
    let total = figures.len();
    let mut done: Vec<(Figure, Vec<SummaryFile>)> = Vec::new();
    for (k, figure) in figures.iter().enumerate() {
        let dir = args.out.join(format!("fig{}", figure.id));
        println!("Figure {} ({} of {total}): {}", figure.id, k + 1, figure.title);
        let mut summaries = Vec::new();
        let mut all = Vec::new();
        let mut bars = Vec::new();
        for (j, spec) in figure.curves.iter().enumerate() {
            let remaining = figures[k..].iter().flat_map(|f| &f.curves).skip(j);
            println!(
                "  [figure {} of {total}, curve {} of {}; {} elapsed, {}] {}",
                k + 1,
                j + 1,
                figure.curves.len(),
                clock(started.elapsed()),
                rates.estimate(remaining),
                spec.label
            );
            let output =
                run_experiment(spec, threads, true).with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
            rates.record(spec, output.wall_seconds);
            let curve_dir = dir.join(slug(&spec.label));
            let summary = write_results(&output, &curve_dir)?;
            let unit = spec.domain.score_unit();
            println!(
                "  {:<28} final {} (95% CI {})  greedy {}  {} runs {:.2} s  {:.0} episodes/s",
                spec.label,
                with_unit(summary.final_mean, unit),
                ci_text(&summary),
                greedy_text(&summary),
                spec.protocol.runs,
                summary.wall_seconds,
                summary.episodes_per_second
            );
            all.push(series(&output));
            bars.push(bar(&output));
            summaries.push(summary);
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
            (FigureKind::Bars, Some(first)) => plot_bars(
                &path,
                &title,
                &bar_axis(first),
                &unit_suffix(first.domain.score_unit()),
                &bars,
            ),
            _ => Ok(()),
        };
        drawn.with_context(|| format!("plotting {}", path.display()))?;
        done.push((figure.clone(), summaries));
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let path = args.out.join("summary.md");
    let listed: Vec<(&Figure, &[SummaryFile])> = done.iter().map(|(f, s)| (f, s.as_slice())).collect();
    write_atomic(&path, summary_markdown(&listed).as_bytes())?;
    println!(
        "summary table: {} ({} figures in {})",
        path.display(),
        done.len(),
        clock(started.elapsed())
    );
    Ok(())
}
