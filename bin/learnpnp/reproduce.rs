//! `learnpnp reproduce`: the thesis's figures from their presets.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp::atomic_file::write_atomic;
use learnpnp::experiment::output::series;
use learnpnp::experiment::plot::{Series, plot_curves, read_curve_csv};
use learnpnp::experiment::presets::{self, Figure, FigureKind};
use learnpnp::experiment::ranges;
use learnpnp::interrupt::Interrupt;
use learnpnp::result_dir::ResultDir;

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
}

impl Default for ReproduceArgs {
    fn default() -> Self {
        ReproduceArgs {
            figures: Vec::new(),
            out: PathBuf::from("out"),
            threads: None,
            runs: None,
            resume: false,
        }
    }
}

/// The figures of a curve in the summary table.
struct Row {
    final_mean: f64,
    ci: [f64; 2],
    greedy: f64,
    seconds: f64,
}

/// The row and series of a curve whose complete results `dir` already holds.
fn read_back(dir: &ResultDir, label: &str) -> Result<(Row, Series)> {
    let summary: serde_json::Value = serde_json::from_slice(&dir.read("summary.json")?)
        .with_context(|| format!("{}: summary.json is not JSON", dir.path().display()))?;
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
    let row = Row {
        final_mean: number(&summary["final_mean"]),
        ci: [number(&summary["final_ci95"][0]), number(&summary["final_ci95"][1])],
        greedy: number(&summary["final_greedy_mean"]),
        seconds: number(&summary["wall_seconds"]),
    };
    let points = read_curve_csv(&dir.path().join("curve.csv"))?;
    Ok((
        row,
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
    for figure in figures {
        let dir = args.out.join(format!("fig{}", figure.id));
        let mut curves = Vec::new();
        for mut spec in figure.curves.clone() {
            if let Some(runs) = args.runs {
                spec.protocol.runs = runs;
            }
            spec.validate()
                .with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
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
            let finished = run_into(&spec, &mut curve_dir, args.resume, threads, &interrupt)
                .with_context(|| format!("figure {}: {}", figure.id, spec.label))?;
            let (row, curve, note) = match finished {
                Finished::Complete { summary, output } => (
                    Row {
                        final_mean: summary.final_mean,
                        ci: summary.final_ci95,
                        greedy: summary.final_greedy_mean,
                        seconds: summary.wall_seconds,
                    },
                    series(&output),
                    format!("{:>9.0} episodes/s", summary.episodes_per_second),
                ),
                Finished::AlreadyComplete => {
                    let (row, curve) = read_back(&curve_dir, &spec.label)?;
                    (row, curve, "(already complete)".to_string())
                }
            };
            println!(
                "  {:<28} final {:>9.4} [{:.4}, {:.4}]  greedy {:>9.4}  {:>4} runs {:>7.2} s  {note}",
                spec.label, row.final_mean, row.ci[0], row.ci[1], row.greedy, spec.protocol.runs, row.seconds,
            );
            let _ = writeln!(
                table,
                "| {} | {} | {:.4} | [{:.4}, {:.4}] | {:.4} | {} | {:.2} |",
                figure.id,
                spec.label,
                row.final_mean,
                row.ci[0],
                row.ci[1],
                row.greedy,
                spec.protocol.runs,
                row.seconds
            );
            all.push(curve);
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
