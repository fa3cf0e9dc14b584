//! `learnpnp experiment`: one domain, one algorithm, many runs.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::experiment::args::{DomainName, ExperimentOptions};
use learnpnp::experiment::output::write_results;
use learnpnp::experiment::runner::run_experiment;
use learnpnp::result_dir::ResultDir;

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
    // Checked and locked before any work.
    let mut dir = ResultDir::open(&args.out)?;
    let threads = args.threads.unwrap_or_else(default_threads);
    let output = run_experiment(&spec, threads, true).context("experiment failed")?;
    let summary = write_results(&output, &mut dir).context("writing results")?;
    println!(
        "{} on {}: final mean {:.4} (95% CI {:.4} .. {:.4}), greedy {:.4}; {} runs in {:.2} s, {:.0} episodes/s; results in {}",
        spec.label,
        spec.domain.name(),
        summary.final_mean,
        summary.final_ci95[0],
        summary.final_ci95[1],
        summary.final_greedy_mean,
        spec.protocol.runs,
        summary.wall_seconds,
        summary.episodes_per_second,
        args.out.display()
    );
    Ok(())
}
