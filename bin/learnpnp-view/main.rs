//! `learnpnp-view`: the view of a multi-process run (started by
//! `learnpnp-supervisor --view`, which passes every argument). Read-only: it
//! reads the agents' live feeds and the heartbeats on the run's iceoryx2
//! services and serves them; SIGTERM or Ctrl-C ends it with its last counts
//! written.

use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

use anyhow::{Context, Result};
use clap::Parser;
use learnpnp_cli::interrupt::Interrupt;
use learnpnp_feed::{FeedEvent, FeedSink};
use learnpnp_system::child_args::RunContextArgs;
use learnpnp_system::multiprocess::{RunContext, view_process};

/// The view of a run: the agents' live feeds and every process's health.
#[derive(Parser)]
#[command(name = "learnpnp-view", version)]
struct Args {
    #[command(flatten)]
    context: RunContextArgs,
    /// Also write every record served as a line of JSON to FILE.
    #[arg(long)]
    jsonl: Option<PathBuf>,
}

/// Every record as a line of JSON in a file, flushed as it is written.
struct JsonLines(Mutex<BufWriter<File>>);

impl FeedSink for JsonLines {
    fn publish(&self, event: &FeedEvent) {
        let Ok(line) = serde_json::to_string(event) else {
            return;
        };
        let mut file = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        // A full disk loses lines, not the view.
        let _ = writeln!(file, "{line}").and_then(|()| file.flush());
    }
}

/// Every sink the view hands its records to.
struct Sinks(Vec<Box<dyn FeedSink>>);

impl FeedSink for Sinks {
    fn publish(&self, event: &FeedEvent) {
        for sink in &self.0 {
            sink.publish(event);
        }
    }
}

fn run(args: Args) -> Result<()> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let context = RunContext::from(args.context);
    let mut sinks: Vec<Box<dyn FeedSink>> = Vec::new();
    if let Some(path) = &args.jsonl {
        let file = File::options()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("opening {}", path.display()))?;
        sinks.push(Box::new(JsonLines(Mutex::new(BufWriter::new(file)))));
    }
    let sinks = Sinks(sinks);
    let counts = view_process::run(&context, &sinks, &|| 0, interrupt.flag())?;
    eprintln!(
        "learnpnp-view: {} feed records served, {} refused, {} lost",
        counts.feed.received,
        counts.feed.rejected.total(),
        counts.dropped()
    );
    Ok(())
}

fn main() -> ExitCode {
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Warn);
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "error: learnpnp-view: {e:#}");
            ExitCode::FAILURE
        }
    }
}
