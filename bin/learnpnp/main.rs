//! The `learnpnp` command line: check and convert plans, run experiments,
//! reproduce the thesis's figures. With no command it reproduces every figure
//! into `out/` on the thesis's parameters.

mod experiment;
mod inspect;
mod replay;
mod reproduce;
mod schema;

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
    Check(inspect::CheckArgs),
    /// Print a plan as Graphviz DOT.
    Dot(inspect::DotArgs),
    /// Convert a plan between the PNP editor's PNML and standard PNML.
    Convert(inspect::ConvertArgs),
    /// Run a learning experiment with the thesis's evaluation protocol.
    Experiment(Box<experiment::ExperimentArgs>),
    /// Reproduce figures of the thesis (all of them by default).
    Reproduce(reproduce::ReproduceArgs),
    /// Overlay the curves of several experiment directories in one SVG.
    Plot(inspect::PlotArgs),
    /// Print a saved value table as CSV.
    Values(inspect::ValuesArgs),
    /// Write a RoboCup game log (.rcg) as one self-contained HTML page to watch.
    Replay(replay::ReplayArgs),
    /// What a plan may use in every domain: actions, atoms, reward, episode end.
    Domains,
    /// What a plan may use in one domain (e.g. keepaway-pass).
    Domain(inspect::DomainArgs),
    /// Print the controllable process constructed from a plan schema (thesis chapter 3).
    Schema(schema::SchemaArgs),
}

fn main() -> ExitCode {
    // Like other command-line tools, stop quietly when the reader of our
    // output goes away (`learnpnp dot plan | head`) instead of panicking.
    #[cfg(unix)]
    // SAFETY: restoring the default action of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Check(args)) => return inspect::check(&args),
        Some(Command::Dot(args)) => inspect::dot(&args),
        Some(Command::Convert(args)) => inspect::convert(&args),
        Some(Command::Experiment(args)) => experiment::run(&args),
        Some(Command::Reproduce(args)) => reproduce::run(&args),
        Some(Command::Plot(args)) => inspect::plot(&args),
        Some(Command::Values(args)) => inspect::values(&args),
        Some(Command::Replay(args)) => replay::run(&args),
        Some(Command::Domains) => inspect::domains(),
        Some(Command::Domain(args)) => inspect::domain(&args),
        Some(Command::Schema(args)) => schema::run(&args),
        None => reproduce::run(&reproduce::ReproduceArgs::default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes, each cause once: errors that already quote their
/// source (`path: reason`) do not get it repeated.
fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    text
}
