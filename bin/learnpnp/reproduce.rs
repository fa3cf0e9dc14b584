//! `learnpnp reproduce`: the thesis's figures from their presets.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp::atomic_file::write_atomic;
use learnpnp::experiment::output::{series, write_results};
use learnpnp::experiment::plot::plot_curves;
use learnpnp::experiment::presets::{self, Figure, FigureKind};
use learnpnp::experiment::runner::run_experiment;
use learnpnp::result_dir::ResultDir;

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
    let figures = selected(&args.figures)?;
    if figures.is_empty() {
        bail!("nothing to reproduce");
    }
    // Every result directory is checked and locked before any work.
    let mut plans = Vec::new();
    for figure in figures {
        let dir = args.out.join(format!("fig{}", figure.id));
        let mut curves = Vec::new();
        for mut spec in figure.curves.clone() {
            if let Some(runs) = args.runs {
                spec.protocol.runs = runs;
            }
            let curve_dir = ResultDir::open(dir.join(slug(&spec.label)))?;
            curves.push((spec, curve_dir));
        }
        plans.push((figure, dir, curves));
    }
    let mut table = String::from(
        "| figure | curve | final mean | 95% CI | greedy mean | runs | seconds |\n|---|---|---|---|---|---|---|\n",
    );
    for (figure, dir, curves) in plans {
        println!("Figure {}: {}", figure.id, figure.title);
        let mut all = Vec::new();
        for (spec, mut curve_dir) in curves {
            let output = run_experiment(&spec, threads, true)
                .with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
            let summary = write_results(&output, &mut curve_dir)?;
            println!(
                "  {:<28} final {:>9.4} [{:.4}, {:.4}]  greedy {:>9.4}  {:>4} runs {:>7.2} s  {:>9.0} episodes/s",
                spec.label,
                summary.final_mean,
                summary.final_ci95[0],
                summary.final_ci95[1],
                summary.final_greedy_mean,
                spec.protocol.runs,
                summary.wall_seconds,
                summary.episodes_per_second
            );
            let _ = writeln!(
                table,
                "| {} | {} | {:.4} | [{:.4}, {:.4}] | {:.4} | {} | {:.2} |",
                figure.id,
                spec.label,
                summary.final_mean,
                summary.final_ci95[0],
                summary.final_ci95[1],
                summary.final_greedy_mean,
                spec.protocol.runs,
                summary.wall_seconds
            );
            all.push(series(&output));
        }
        if figure.kind == FigureKind::Curves {
            let path = dir.join("figure.svg");
            plot_curves(
                &path,
                &format!("Figure {}: {}", figure.id, figure.title),
                "learning episodes",
                "evaluation return (mean, 95% CI)",
                &all,
            )
            .with_context(|| format!("plotting {}", path.display()))?;
        }
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let path = args.out.join("summary.md");
    write_atomic(&path, table.as_bytes())?;
    println!("summary table: {}", path.display());
    Ok(())
}
