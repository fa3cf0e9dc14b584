//! Commands that inspect files: check, dot, convert, plot, values.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::analysis;
use learnpnp::dot::to_dot;
use learnpnp::experiment::plot::{Series, plot_curves, read_curve_csv};
use learnpnp::learning::persist;
use learnpnp::plan::{Vocabulary, load_plan};
use learnpnp::pnml::{self, Dialect};

/// Writes `text` to standard output; a reader that closed the pipe (`| head`) is no error.
pub fn print_out(text: &str) -> std::io::Result<()> {
    use std::io::Write as _;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The plan file (PNML).
    plan: PathBuf,
    /// Most reachable markings to explore.
    #[arg(long, default_value_t = 100_000)]
    limit: usize,
}

/// Exit 0: loads and passes; 1: loads and fails a check; 2: cannot be read.
pub fn check(args: &CheckArgs) -> ExitCode {
    let plan = match load_plan(&args.plan, Vocabulary::Open) {
        Ok(plan) => plan,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let report = analysis::check(&plan, args.limit);
    if let Err(e) = print_out(&report.to_string()) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

#[derive(Args, Debug)]
pub struct DotArgs {
    /// The plan file (PNML).
    plan: PathBuf,
}

pub fn dot(args: &DotArgs) -> Result<()> {
    let plan = load_plan(&args.plan, Vocabulary::Open)?;
    for w in plan.warnings() {
        eprintln!("warning: {w}");
    }
    print_out(&to_dot(&plan))?;
    Ok(())
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The plan file (either dialect).
    plan: PathBuf,
    /// The dialect to write: jarp (the PNP editor) or standard (ISO/IEC 15909-2).
    #[arg(long)]
    to: Dialect,
    /// Output file.
    #[arg(short, long)]
    output: PathBuf,
}

pub fn convert(args: &ConvertArgs) -> Result<()> {
    let net = pnml::read_file(&args.plan)?;
    // Refuse to convert something that is not a valid plan.
    learnpnp::plan::Plan::from_net(net.clone(), Vocabulary::Open)
        .with_context(|| format!("{} is not a valid plan", args.plan.display()))?;
    pnml::write_file(&net, args.to, &args.output)?;
    Ok(())
}

#[derive(Args, Debug)]
pub struct PlotArgs {
    /// Experiment directories (each with curve.csv and summary.json).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// The SVG to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Title of the plot.
    #[arg(long, default_value = "learning curves")]
    title: String,
}

fn label_of(dir: &std::path::Path) -> String {
    let from_summary = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .and_then(|v| v["spec"]["label"].as_str().map(str::to_string));
    from_summary.unwrap_or_else(|| dir.display().to_string())
}

pub fn plot(args: &PlotArgs) -> Result<()> {
    let series = args
        .dirs
        .iter()
        .map(|dir| {
            Ok(Series {
                label: label_of(dir),
                points: read_curve_csv(&dir.join("curve.csv"))?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    plot_curves(
        &args.output,
        &args.title,
        "learning episodes",
        "evaluation return (mean, 95% CI)",
        &series,
    )?;
    Ok(())
}

#[derive(Args, Debug)]
pub struct ValuesArgs {
    /// A value table saved by an experiment (values.bin).
    file: PathBuf,
}

pub fn values(args: &ValuesArgs) -> Result<()> {
    let (saved, problem) = persist::load_latest(&args.file)?;
    if let Some(e) = problem {
        eprintln!("warning: {e}; showing the previous good table");
    }
    let stdout = std::io::stdout();
    persist::write_csv(&saved, &mut stdout.lock())?;
    Ok(())
}
