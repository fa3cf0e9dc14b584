//! `learnpnp experiment`: one domain, one algorithm, many runs.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::experiment::checkpoint::{ResumePoint, resume_point};
use learnpnp::experiment::options::{DomainName, ExperimentOptions};
use learnpnp::experiment::output::{SummaryFile, final_score_text, greedy_text, replay_name, write_shard_results_with};
use learnpnp::experiment::ranges;
use learnpnp::experiment::result_dir::{Contents, ResultDir};
use learnpnp::experiment::runner::{Completed, ExperimentOutput, RunOptions, run_experiment};
use learnpnp::experiment::shard::{Shard, ShardRecord};
use learnpnp::experiment::spec::ExperimentSpec;
use learnpnp::feed::FeedSink;
use learnpnp_flags::args::named;
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_flags::view::ViewFlags;
use learnpnp_view::{View, ViewError, ViewOptions};

use super::Interrupted;

#[derive(Args, Debug)]
pub struct ExperimentArgs {
    /// The domain.
    #[arg(value_parser = named::<DomainName>())]
    domain: DomainName,
    #[command(flatten)]
    options: ExperimentOptions,
    /// Output directory (replaced as a whole when the experiment ends; refused
    /// if another experiment is writing there).
    #[arg(long, default_value = "out/experiment")]
    out: PathBuf,
    /// Continue the interrupted experiment whose partial result is in --out
    /// (same parameters): only the missing runs are run, and the final
    /// numbers are those of an uninterrupted experiment.
    #[arg(long)]
    resume: bool,
    /// Worker threads (default: all cores; 1 to 256).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::THREADS.parse_usize(s))]
    threads: Option<usize>,
    /// Play only shard I of N (0-based: the runs r with r % N == I, each with
    /// the seeds the whole experiment gives it), for `learnpnp merge` to combine.
    #[arg(long)]
    shard: Option<Shard>,
    #[command(flatten)]
    view: ViewFlags,
}

/// The default worker count: every core.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// How an experiment written into a result directory ended.
pub enum Finished {
    /// Every run completed; the results are written.
    Complete {
        /// The summary written.
        summary: Box<SummaryFile>,
        /// The output it summarises.
        output: Box<ExperimentOutput>,
    },
    /// The directory already held the complete results (with `--resume`).
    AlreadyComplete,
}

/// Runs `spec` (continuing a partial result in `dir` when `resume`; only
/// `shard`'s runs when one is given; publishing to `feed` when given) and
/// writes its results into `dir`. A
/// signal stops it: the completed runs are written as a partial result and
/// [`Interrupted`] is returned.
pub fn run_into(
    spec: &ExperimentSpec,
    dir: &mut ResultDir,
    resume: bool,
    threads: usize,
    interrupt: &Interrupt,
    shard: Option<Shard>,
    feed: Option<&Arc<dyn FeedSink>>,
) -> Result<Finished> {
    let completed = if resume {
        match resume_point(dir, spec)? {
            ResumePoint::Fresh => Completed::default(),
            ResumePoint::Partial(completed) => {
                eprintln!(
                    "{}: resuming with {} of {} runs done",
                    dir.path().display(),
                    completed.runs.len(),
                    spec.protocol.runs
                );
                completed
            }
            ResumePoint::Complete => return Ok(Finished::AlreadyComplete),
        }
    } else {
        if let Contents::Results(m) = dir.contents()?
            && !m.complete
        {
            eprintln!(
                "note: replacing the partial result in {} ({} of {} runs; --resume would continue it)",
                dir.path().display(),
                m.runs_completed,
                m.runs_planned
            );
        }
        Completed::default()
    };
    let planned = spec.protocol.runs;
    let record = shard.map(|shard| ShardRecord {
        shard,
        runs: shard.runs(planned),
    });
    let options = RunOptions {
        threads,
        progress: true,
        stop: Some(interrupt.flag()),
        only: record.as_ref().map(|r| r.runs.as_slice()),
        feed,
    };
    let migration = initial_values_migration(spec)?;
    let output = run_experiment(spec, options, completed).context("experiment failed")?;
    if output.runs.is_empty() {
        return Err(Interrupted {
            status: interrupt.exit_status(),
            message: format!(
                "interrupted before any run completed; {} is unchanged",
                dir.path().display()
            ),
        }
        .into());
    }
    let extra: Vec<(&str, String)> = migration.into_iter().map(|text| ("migration.json", text)).collect();
    let summary = write_shard_results_with(&output, record.as_ref(), dir, &extra).context("writing results")?;
    let complete = match &record {
        Some(record) => output.runs.len() == record.runs.len(),
        None => output.is_complete(),
    };
    if !complete {
        return Err(Interrupted {
            status: interrupt.exit_status(),
            message: format!(
                "interrupted: {} of {planned} runs completed, kept in {} as a partial result; \
                 the same command with --resume continues it",
                output.runs.len(),
                dir.path().display()
            ),
        }
        .into());
    }
    if let Some(record) = &record {
        eprintln!(
            "shard {} complete: run(s) {:?} of {planned} in {}; combine the shards with learnpnp merge OUT DIR...",
            record.shard,
            record.runs,
            dir.path().display()
        );
    }
    Ok(Finished::Complete {
        summary: Box::new(summary),
        output: Box::new(output),
    })
}

/// What loading `--initial-values` into the experiment's plan does, printed
/// on standard error when a table is carried into a revised plan; returns
/// `migration.json`'s text then (one object per table: `path` and the report),
/// `None` when every table was learned on this very plan.
fn initial_values_migration(spec: &ExperimentSpec) -> Result<Option<String>> {
    if spec.initial_values.is_empty() {
        return Ok(None);
    }
    let plan = spec.domain.load_plan().context("loading the plan")?;
    let tables = spec
        .migrate_initial_values(plan.as_deref())
        .context("loading --initial-values")?;
    if tables.iter().all(|(_, _, report)| report.unchanged) {
        return Ok(None);
    }
    let mut json = Vec::new();
    for (path, _, report) in &tables {
        eprintln!("{}: {report}", path.display());
        json.push(serde_json::json!({ "path": path, "report": report.to_json() }));
    }
    Ok(Some(serde_json::to_string_pretty(&json)?))
}

pub fn run(args: &ExperimentArgs) -> Result<()> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let spec = args.options.spec(args.domain)?;
    // Checked and locked before any work.
    let mut dir = ResultDir::open(&args.out)?;
    let threads = args.threads.unwrap_or_else(default_threads);
    let configuration = serde_json::to_string_pretty(&spec).context("printing the configuration")?;
    println!(
        "configuration ({threads} worker threads; saved in {} with the results):\n{configuration}",
        args.out.join("summary.json").display()
    );
    let view = start_view(&args.view).context("starting the view")?.map(Arc::new);
    let feed = view.clone().map(|v| v as Arc<dyn FeedSink>);
    let finished = run_into(
        &spec,
        &mut dir,
        args.resume,
        threads,
        &interrupt,
        args.shard,
        feed.as_ref(),
    );
    drop(feed);
    if let Some(view) = view.and_then(Arc::into_inner) {
        let dropped = view.dropped();
        view.close().context("closing the view")?;
        if dropped > 0 {
            eprintln!("view: {dropped} records dropped (the view could not keep up)");
        }
    }
    match finished? {
        Finished::AlreadyComplete => println!(
            "{} already holds the complete results of this experiment; nothing to do",
            args.out.display()
        ),
        Finished::Complete { .. } if args.shard.is_some() => {}
        Finished::Complete { summary, .. } => {
            println!(
                "{} on {}: {}, greedy {}; {} runs in {:.2} s, {:.0} episodes/s; results in {}",
                spec.label,
                spec.domain.name(),
                final_score_text(&summary),
                greedy_text(&summary),
                spec.protocol.runs,
                summary.wall_seconds,
                summary.episodes_per_second,
                args.out.display()
            );
            let replays = spec.domain.replays();
            if replays > 0 {
                let first = args.out.join("replays").join(replay_name(0, replays));
                println!(
                    "{} recorded episode(s) in {}; watch one with: learnpnp replay {} -o episode.html",
                    replays,
                    args.out.join("replays").display(),
                    first.display()
                );
            }
        }
    }
    Ok(())
}

/// Starts the view `flags` ask for in this process (`None` when none is),
/// and says on standard error where it is served.
fn start_view(flags: &ViewFlags) -> Result<Option<View>, ViewError> {
    if !flags.asked() {
        return Ok(None);
    }
    let view = View::start(ViewOptions {
        address: flags.view,
        record_mcap: flags.record_mcap.clone(),
        pnp_monitor: flags.pnp_monitor,
        ..ViewOptions::default()
    })?;
    if let Some(address) = view.address() {
        eprintln!("view: http://{address}/ (Foxglove: ws://{address})");
    }
    if let Some(address) = view.pnp_monitor_address() {
        eprintln!("PNP monitor line: tcp://{address}");
    }
    Ok(Some(view))
}
