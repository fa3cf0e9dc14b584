//! `learnpnp replay`: a game log as a self-contained HTML page.

use std::path::PathBuf;

use anyhow::{Context, Result};
use atomic_file::write_atomic;
use clap::Args;
use learnpnp_keepaway::rcg::GameLog;
use learnpnp_keepaway::replay::replay_page;

#[derive(Args, Debug)]
pub struct ReplayArgs {
    /// A RoboCup game log (text, ULG4 to ULG6), e.g. DIR/replays/episode-1.rcg.
    log: PathBuf,
    /// The page to write (default: the log's name with .html).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(args: &ReplayArgs) -> Result<()> {
    let log = GameLog::read_file(&args.log)?;
    let output = args.output.clone().unwrap_or_else(|| args.log.with_extension("html"));
    let title = args
        .log
        .file_name()
        .map_or_else(|| args.log.display().to_string(), |n| n.to_string_lossy().into_owned());
    let page = replay_page(&log, &title).context("encoding the log for the page")?;
    write_atomic(&output, page.as_bytes()).with_context(|| format!("writing {}", output.display()))?;
    let last = log.frames.last().map_or(0, |f| f.time);
    println!(
        "{}: {} shows (cycles {} to {last}), {} keeper notes; open {} in a browser",
        args.log.display(),
        log.frames.len(),
        log.frames.first().map_or(0, |f| f.time),
        log.notes.len(),
        output.display()
    );
    Ok(())
}
