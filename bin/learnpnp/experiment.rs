//! `learnpnp experiment`: one domain, one algorithm, many runs.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::experiment::args::{DomainName, ExperimentOptions};
use learnpnp::experiment::output::{ci_text, greedy_text, replay_name, with_unit, write_results};
use learnpnp::experiment::runner::run_experiment;

#[derive(Args, Debug)]
pub struct ExperimentArgs {
    /// The domain.
    #[arg(value_enum)]
    domain: DomainName,
    #[command(flatten)]
    options: ExperimentOptions,
    /// Output directory.
    #[arg(long, default_value = "out/experiment")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

/// The default worker count: every core.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

pub fn run(args: &ExperimentArgs) -> Result<()> {
    let spec = args.options.spec(args.domain)?;
    let threads = args.threads.unwrap_or_else(default_threads);
    let configuration = serde_json::to_string_pretty(&spec).context("printing the configuration")?;
    println!(
        "configuration ({} worker threads; saved in {} with the results):\n{configuration}",
        threads,
        args.out.join("summary.json").display()
    );
    let output = run_experiment(&spec, threads, true).context("experiment failed")?;
    let summary = write_results(&output, &args.out).context("writing results")?;
    let unit = spec.domain.score_unit();
    println!(
        "{} on {}: final mean {}, 95% CI {}, greedy {}; {} runs in {:.2} s, {:.0} episodes/s; results in {}",
        spec.label,
        spec.domain.name(),
        with_unit(summary.final_mean, unit),
        ci_text(&summary),
        greedy_text(&summary),
        spec.protocol.runs,
        summary.wall_seconds,
        summary.episodes_per_second,
        args.out.display()
    );
    if spec.record > 0 {
        let first = args.out.join("replays").join(replay_name(0, spec.record));
        println!(
            "{} recorded episode(s) in {}; watch one with: learnpnp replay {} -o episode.html",
            spec.record,
            args.out.join("replays").display(),
            first.display()
        );
    }
    Ok(())
}
