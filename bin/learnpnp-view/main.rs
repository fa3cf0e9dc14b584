//! `learnpnp-view`: the view of a multi-process run (started by
//! `learnpnp-supervisor --view`, which passes every argument). Read-only: it
//! reads the agents' live feeds and the heartbeats on the run's iceoryx2
//! services and serves them with the `learnpnp-view` crate's server (the
//! page and the Foxglove WebSocket protocol, an MCAP recording, PNP's
//! monitor line); SIGTERM or Ctrl-C ends it with its last counts written
//! and its recording closed.

use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};

use anyhow::{Context, Result};
use clap::Parser;
use learnpnp_feed::{FeedEvent, FeedSink, KINDS};
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_system::child_args::RunContextArgs;
use learnpnp_system::multiprocess::{RunContext, view_process};
use learnpnp_view::{View, ViewOptions};

/// The view of a run: the agents' live feeds and every process's health.
#[derive(Parser)]
#[command(name = "learnpnp-view", version)]
struct Args {
    #[command(flatten)]
    context: RunContextArgs,
    /// Serve the page and the Foxglove WebSocket protocol on this address (port 0: any free port).
    #[arg(long)]
    listen: Option<SocketAddr>,
    /// Record every channel to this MCAP file.
    #[arg(long)]
    record_mcap: Option<PathBuf>,
    /// Write PNP's monitor line to TCP clients on this address.
    #[arg(long)]
    pnp_monitor: Option<SocketAddr>,
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

    /// The line of the record as serde writes it (`{"Kind":payload}`), without decoding it.
    fn publish_payload(&self, kind: usize, payload: &[u8]) {
        let Some(tag) = KINDS.get(kind) else {
            return;
        };
        let mut file = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let _ = write!(file, "{{\"{tag}\":")
            .and_then(|()| file.write_all(payload))
            .and_then(|()| file.write_all(b"}\n"))
            .and_then(|()| file.flush());
    }
}

/// Every sink the view hands its records to.
struct Sinks(Vec<Arc<dyn FeedSink>>);

impl FeedSink for Sinks {
    fn publish(&self, event: &FeedEvent) {
        for sink in &self.0 {
            sink.publish(event);
        }
    }

    fn publish_payload(&self, kind: usize, payload: &[u8]) {
        for sink in &self.0 {
            sink.publish_payload(kind, payload);
        }
    }
}

fn run(args: Args) -> Result<()> {
    // Off the learners' path: this thread and every thread started from it
    // (the feed's reader, the server's) wake without preempting a learner.
    learnpnp_view::run_in_background();
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let context = RunContext::from(args.context);
    let mut sinks: Vec<Arc<dyn FeedSink>> = Vec::new();
    let view = if args.listen.is_some() || args.record_mcap.is_some() || args.pnp_monitor.is_some() {
        let view = View::start(ViewOptions {
            address: args.listen,
            record_mcap: args.record_mcap.clone(),
            pnp_monitor: args.pnp_monitor,
            ..ViewOptions::default()
        })
        .context("starting the view's server")?;
        if let Some(address) = view.address() {
            eprintln!("view: http://{address}/ (Foxglove: ws://{address})");
        }
        if let Some(address) = view.pnp_monitor_address() {
            eprintln!("PNP monitor line: tcp://{address}");
        }
        let view = Arc::new(view);
        sinks.push(view.clone());
        Some(view)
    } else {
        None
    };
    if let Some(path) = &args.jsonl {
        let file = File::options()
            .create(true)
            .append(true)
            .open(path)
            .with_context(|| format!("opening {}", path.display()))?;
        sinks.push(Arc::new(JsonLines(Mutex::new(BufWriter::new(file)))));
    }
    let sinks = Sinks(sinks);
    let dropped = || view.as_ref().map_or(0, |v| v.dropped());
    let counts = view_process::run(&context, &sinks, &dropped, interrupt.flag())?;
    drop(sinks);
    if let Some(view) = view.and_then(Arc::into_inner) {
        view.close().context("closing the view")?;
    }
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
