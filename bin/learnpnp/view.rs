//! `learnpnp view`: the live view's page replaying a recording.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_view::{View, ViewOptions};

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// The MCAP recording to replay (written by `learnpnp experiment --record-mcap`).
    recording: PathBuf,
    /// Where to serve the page (port 0 picks a free port; another interface
    /// than loopback only when given).
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8765")]
    view: SocketAddr,
}

/// Serves the page, with the recording at `/recording.mcap`, until a signal.
pub fn run(args: &ViewArgs) -> Result<()> {
    if !args.recording.is_file() {
        bail!("{}: no such recording", args.recording.display());
    }
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let view = View::start(ViewOptions {
        address: Some(args.view),
        replay: Some(args.recording.clone()),
        ..ViewOptions::default()
    })
    .context("starting the view")?;
    if let Some(address) = view.address() {
        println!(
            "replaying {} at http://{address}/ (the file is at /recording.mcap); Ctrl-C stops",
            args.recording.display()
        );
    }
    while !interrupt.flag().load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(100));
    }
    view.close().context("closing the view")?;
    Ok(())
}
