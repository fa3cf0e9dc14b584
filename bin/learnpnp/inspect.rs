//! Commands that inspect files: check, dot, convert, plot, values.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::analysis;
use learnpnp::dot::to_dot;
use learnpnp::experiment::plot::{Series, plot_curves, read_curve_csv};
use learnpnp::experiment::ranges::CountRange;
use learnpnp::learning::persist;
use learnpnp::plan::{Vocabulary, load_plan};
use learnpnp::pnml::{self, Dialect};
use learnpnp::result_dir::{self, Contents};
use learnpnp::schema;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The plan file (PNML), or a plan schema (.schema).
    plan: PathBuf,
    /// Most reachable markings to explore (at least 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = analysis::DEFAULT_LIMIT, value_parser = |s: &str| CountRange::new(1, u64::MAX).parse_usize(s))]
    limit: usize,
}

/// Exit 0: loads and passes; 1: loads and fails a check; 2: cannot be read.
pub fn check(args: &CheckArgs) -> ExitCode {
    if schema::is_schema_path(&args.plan) {
        return check_schema(args);
    }
    let plan = match load_plan(&args.plan, Vocabulary::Open) {
        Ok(plan) => plan,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let report = analysis::check(&plan, args.limit);
    print_report(&report, report.passed())
}

/// Prints a check report (a closed pipe is no error); exit 0 if it passed, 1 if not.
fn print_report(report: &dyn std::fmt::Display, passed: bool) -> ExitCode {
    match write!(std::io::stdout().lock(), "{report}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        _ if passed => ExitCode::SUCCESS,
        _ => ExitCode::from(1),
    }
}

/// A schema's checks (`schema::check_report`), with the same exit codes.
fn check_schema(args: &CheckArgs) -> ExitCode {
    let process = match schema::load_process(&args.plan, Vocabulary::Open) {
        Ok(process) => process,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let (report, passed) = schema::check_report(&process);
    print_report(&report, passed)
}

#[derive(Args, Debug)]
pub struct DotArgs {
    /// The plan file (PNML), or a plan schema (.schema: its process is drawn).
    plan: PathBuf,
}

pub fn dot(args: &DotArgs) -> Result<()> {
    if schema::is_schema_path(&args.plan) {
        let dot = schema::to_dot(&schema::load_process(&args.plan, Vocabulary::Open)?);
        write!(std::io::stdout().lock(), "{dot}")?;
        return Ok(());
    }
    let plan = load_plan(&args.plan, Vocabulary::Open)?;
    write!(std::io::stdout().lock(), "{}", to_dot(&plan))?;
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
            let mut label = label_of(dir);
            if let Contents::Results(m) = result_dir::contents(dir)?
                && !m.complete
            {
                eprintln!(
                    "note: {} is a partial result ({} of {} runs)",
                    dir.display(),
                    m.runs_completed,
                    m.runs_planned
                );
                label.push_str(&format!(" (partial: {} of {} runs)", m.runs_completed, m.runs_planned));
            }
            Ok(Series {
                label,
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
