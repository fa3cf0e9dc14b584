//! The `learnpnp` command line: check and convert plans, run experiments,
//! reproduce the thesis's figures. With no command it reproduces every figure
//! into `out/` on the thesis's parameters.

mod experiment;
mod generate;
mod inspect;
mod merge;
mod replay;
mod reproduce;
mod schema;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "learnpnp",
    version,
    about = "Reinforcement learning in plan space with Petri Net Plans"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Check a plan's structure: safety, minimality, effectiveness, dead markings.
    ///
    /// Each list of the report (places, choice points and their options,
    /// failures, notes, warnings) shows its count and its first 8 items;
    /// --verbose shows them all, --json prints the whole report as JSON.
    ///
    /// Exit status: 0 every check passed (or does not apply); 1 a check fails;
    /// 2 the plan cannot be read; 3 no check fails but one is inconclusive
    /// (the marking limit was reached, or an unbounded place is read), which
    /// is neither a pass nor a failure.
    Check(inspect::CheckArgs),
    /// Print a plan as Graphviz DOT.
    Dot(inspect::DotArgs),
    /// Convert a plan between the PNP editor's PNML and standard PNML.
    Convert(inspect::ConvertArgs),
    /// A plan from planners' plans: a linear plan (IPC plan file or PNPgen's
    /// line) as a sequence, k plans merged into choice points where they
    /// differ, or a conditional plan; execution rules added as interrupts.
    Generate(generate::GenerateArgs),
    /// Run a learning experiment with the thesis's evaluation protocol.
    Experiment(Box<experiment::ExperimentArgs>),
    /// Reproduce figures of the thesis (all of them by default).
    Reproduce(reproduce::ReproduceArgs),
    /// Combine the shards of an experiment or a reproduction (run with --shard I/N) into one result.
    Merge(merge::MergeArgs),
    /// Overlay the curves of several experiment directories in one SVG.
    Plot(inspect::PlotArgs),
    /// Print a saved value table as CSV.
    Values(inspect::ValuesArgs),
    /// Write a RoboCup game log (.rcg) as one self-contained HTML page to watch.
    Replay(replay::ReplayArgs),
    /// Serve the live view's page replaying an MCAP recording (from --record-mcap).
    View(view::ViewArgs),
    /// What a plan may use in every domain: actions, atoms, reward, episode end.
    Domains,
    /// What a plan may use in one domain (e.g. keepaway-pass).
    Domain(inspect::DomainArgs),
    /// Print the controllable process constructed from a plan schema (thesis chapter 3).
    Schema(schema::SchemaArgs),
}

/// An experiment stopped by a signal: its message, and the exit status
/// (128 + the signal's number).
#[derive(Debug)]
pub struct Interrupted {
    /// The exit status.
    pub status: u8,
    /// What was kept and how to continue.
    pub message: String,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Interrupted {}

/// An error and its causes on one line, each cause once: a cause whose text
/// its parent already shows (`path: error` wrapping `error`) is skipped.
fn describe(error: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in error.chain() {
        let part = cause.to_string();
        if !text.contains(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
    }
    text
}

/// Whether the error is a write to a closed pipe (`learnpnp values f | head`):
/// the reader has all it wanted, which is no failure.
fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error
        .chain()
        .filter_map(|c| c.downcast_ref::<std::io::Error>())
        .any(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Check(args)) => return inspect::check(&args),
        Some(Command::Dot(args)) => inspect::dot(&args),
        Some(Command::Convert(args)) => inspect::convert(&args),
        Some(Command::Generate(args)) => generate::run(&args),
        Some(Command::Experiment(args)) => experiment::run(&args),
        Some(Command::Reproduce(args)) => reproduce::run(&args),
        Some(Command::Merge(args)) => merge::run(&args),
        Some(Command::Plot(args)) => inspect::plot(&args),
        Some(Command::Values(args)) => inspect::values(&args),
        Some(Command::Replay(args)) => replay::run(&args),
        Some(Command::View(args)) => view::run(&args),
        Some(Command::Domains) => inspect::domains(),
        Some(Command::Domain(args)) => inspect::domain(&args),
        Some(Command::Schema(args)) => schema::run(&args),
        None => reproduce::run(&reproduce::ReproduceArgs::default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => match e.downcast_ref::<Interrupted>() {
            Some(interrupted) => {
                eprintln!("{interrupted}");
                ExitCode::from(interrupted.status)
            }
            None if is_broken_pipe(&e) => ExitCode::SUCCESS,
            None => {
                eprintln!("error: {}", describe(&e));
                ExitCode::from(2)
            }
        },
    }
}
