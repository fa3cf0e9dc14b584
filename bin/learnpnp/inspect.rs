//! Commands that inspect files and domains: check, dot, convert, plot, values, domains.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Args;
use learnpnp::analysis::{self, Outcome};
use learnpnp::domains::describe;
use learnpnp::dot::to_dot_with_values;
use learnpnp::experiment::output::score_axis;
use learnpnp::experiment::plot::{Reference, Series, plot_curves, read_curve_csv};
use learnpnp::experiment::ranges::CountRange;
use learnpnp::experiment::result_dir::{self, Contents};
use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec};
use learnpnp::learning::by_choice::{self, group_by_choice};
use learnpnp::learning::migrate;
use learnpnp::learning::persist::{self, SavedValues};
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::plan_file::load_plan;
use learnpnp::pnml::{self, Dialect};
use learnpnp::schema;

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The plan file (PNML), or a plan schema (.schema).
    plan: PathBuf,
    /// Most reachable markings to explore (at least 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = analysis::DEFAULT_LIMIT, value_parser = |s: &str| CountRange::new(1, u64::MAX).parse_usize(s))]
    limit: usize,
    /// Most memory, in MiB, the stored markings and edges may take with the
    /// checks' bookkeeping (at least 1); the limit reached is named in the report.
    #[arg(long, value_name = "MIB", allow_hyphen_values = true, default_value_t = analysis::MEMORY_LIMIT >> 20, value_parser = |s: &str| CountRange::new(1, 1 << 30).parse_usize(s))]
    memory: usize,
    /// Show every item of every list (by default each list shows its count
    /// and its first few items).
    #[arg(short, long, conflicts_with = "json")]
    verbose: bool,
    /// Print the whole report as JSON, for tools.
    #[arg(long)]
    json: bool,
}

/// How many items of each list the report shows without `--verbose`.
const SHOWN_ITEMS: usize = 8;

/// The exit status of `check`: the plan passes.
const PASSED: u8 = 0;
/// The exit status of `check`: the plan fails a check.
const FAILED: u8 = 1;
/// The exit status of `check`: an error (the plan cannot be read, or the
/// report cannot be written).
const UNREADABLE: u8 = 2;
/// The exit status of `check`: no check fails, but one is inconclusive.
const INCONCLUSIVE: u8 = 3;

/// Exit 0: loads and passes; 1: loads and fails a check; 2: cannot be read;
/// 3: loads, fails no check, but a check is inconclusive.
pub fn check(args: &CheckArgs) -> ExitCode {
    if schema::is_schema_path(&args.plan) {
        return check_schema(args);
    }
    let plan = match load_plan(&args.plan, AllowedAtoms::Open) {
        Ok(plan) => plan,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(UNREADABLE);
        }
    };
    let limits = analysis::Limits {
        markings: args.limit,
        memory: args.memory.saturating_mul(1 << 20),
    };
    let report = analysis::check_within(&plan, limits);
    let status = match report.outcome() {
        Outcome::Passed => PASSED,
        Outcome::Failed => FAILED,
        Outcome::Inconclusive => INCONCLUSIVE,
    };
    if args.json {
        print_report(&json_text(&report.to_json()), status)
    } else if args.verbose {
        print_report(&report, status)
    } else {
        print_report(&report.summary(SHOWN_ITEMS), status)
    }
}

/// `value` as pretty-printed JSON, one line after another.
fn json_text(value: &serde_json::Value) -> String {
    format!("{value:#}\n")
}

/// Prints a check report (a closed pipe is no error) and exits with `status`.
fn print_report(report: &dyn std::fmt::Display, status: u8) -> ExitCode {
    match write!(std::io::stdout().lock(), "{report}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: {e}");
            ExitCode::from(UNREADABLE)
        }
        _ => ExitCode::from(status),
    }
}

/// A schema's checks (`schema::check_report`), with the same exit codes (a
/// schema's checks are never inconclusive). Its report is printed whole, so
/// `--verbose` changes nothing; as JSON: `plan`, `result`, `passed`,
/// `failures` and `text`.
fn check_schema(args: &CheckArgs) -> ExitCode {
    let process = match schema::load_process(&args.plan, AllowedAtoms::Open) {
        Ok(process) => process,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(UNREADABLE);
        }
    };
    let (report, passed) = schema::check_report(&process);
    let status = if passed { PASSED } else { FAILED };
    if !args.json {
        return print_report(&report, status);
    }
    let outcome = if passed { Outcome::Passed } else { Outcome::Failed };
    let json = serde_json::json!({
        "plan": process.machines().first().map_or("", |m| m.plan().name()),
        "result": outcome.name(),
        "passed": passed,
        "failures": schema::check_failures(&report),
        "text": report,
    });
    print_report(&json_text(&json), status)
}

#[derive(Args, Debug)]
pub struct DotArgs {
    /// The plan file (PNML), or a plan schema (.schema: its process is drawn).
    plan: PathBuf,
    /// A value table learned on this plan (DIR/values.bin): each option of a
    /// choice point is labelled with its value and updates, the greedy one marked.
    #[arg(long, value_name = "FILE")]
    values: Option<PathBuf>,
    /// Most reachable markings to explore for the choice points, as check does (at least 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = analysis::DEFAULT_LIMIT, value_parser = |s: &str| CountRange::new(1, u64::MAX).parse_usize(s))]
    limit: usize,
}

/// A saved table, the previous good copy if the file is damaged (with a warning).
fn load_values(path: &Path) -> Result<SavedValues> {
    let (saved, problem) = persist::load_latest(path)?;
    if let Some(e) = problem {
        eprintln!("warning: {e}; using the previous good table");
    }
    Ok(saved)
}

pub fn dot(args: &DotArgs) -> Result<()> {
    if schema::is_schema_path(&args.plan) {
        if args.values.is_some() {
            anyhow::bail!("--values labels the choice points of a Petri Net Plan; give the plan, not a schema");
        }
        let dot = schema::to_dot(&schema::load_process(&args.plan, AllowedAtoms::Open)?);
        write!(std::io::stdout().lock(), "{dot}")?;
        return Ok(());
    }
    let plan = load_plan(&args.plan, AllowedAtoms::Open)?;
    for w in plan.warnings() {
        eprintln!("warning: {w}");
    }
    let learned = match &args.values {
        Some(path) => {
            let saved = load_values(path)?;
            Some(
                group_by_choice(&[&plan], &saved)
                    .with_context(|| format!("{} and {}", path.display(), args.plan.display()))?,
            )
        }
        None => None,
    };
    write!(
        std::io::stdout().lock(),
        "{}",
        to_dot_with_values(&plan, args.limit, learned.as_ref())
    )?;
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
    learnpnp::plan::Plan::from_net(net.clone(), AllowedAtoms::Open)
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

/// The experiment spec saved in `dir`'s summary.json, if it can be read.
fn spec_of(dir: &Path) -> Option<ExperimentSpec> {
    let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    serde_json::from_value(json["spec"].clone()).ok()
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
    // The axis and references of the experiments, when they all agree on them.
    let specs: Vec<Option<ExperimentSpec>> = args.dirs.iter().map(|d| spec_of(d)).collect();
    let known: Vec<&ExperimentSpec> = specs.iter().flatten().collect();
    let axis = match known.first() {
        Some(first) if known.len() == specs.len() && known.iter().all(|s| score_axis(s) == score_axis(first)) => {
            score_axis(first)
        }
        _ => "evaluation score (mean over runs, 95% CI)".to_string(),
    };
    let mut references: Vec<Reference> = Vec::new();
    for r in known.iter().filter_map(|s| s.domain.reference()) {
        if !references.contains(&r) {
            references.push(r);
        }
    }
    plot_curves(
        &args.output,
        &args.title,
        "learning episodes",
        &axis,
        &series,
        &references,
    )?;
    Ok(())
}

#[derive(Args, Debug)]
pub struct ValuesArgs {
    /// A value table saved by an experiment (values.bin).
    file: PathBuf,
    /// The plan the values were learned on, or a revision of it: the values
    /// are then carried over by name and what was kept, dropped and new is
    /// printed on standard error (default: the plan of the experiment, from
    /// summary.json next to the table).
    #[arg(long)]
    plan: Option<PathBuf>,
}

/// The plan of the experiment whose results directory holds `values`, from
/// its summary.json; `None` when there is none.
fn experiment_plan(values: &Path) -> Result<Option<Plan>> {
    let summary = values.with_file_name("summary.json");
    let Ok(text) = std::fs::read_to_string(&summary) else {
        return Ok(None);
    };
    let json: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{} is not JSON", summary.display()))?;
    // An experiment's summary holds its spec; the supervisor's (the main
    // job's) holds the experiment's summary, spec and all, under `experiment`.
    let spec = if json["spec"].is_null() {
        &json["experiment"]["spec"]
    } else {
        &json["spec"]
    };
    let domain: DomainSpec = serde_json::from_value(spec["domain"].clone()).with_context(|| {
        format!(
            "{}: no experiment domain in 'spec' (an experiment's) or 'experiment.spec' (the supervisor's)",
            summary.display()
        )
    })?;
    let plan = domain
        .load_plan()
        .with_context(|| format!("loading the plan named by {}", summary.display()))?;
    Ok(plan.map(|p| (*p).clone()))
}

pub fn values(args: &ValuesArgs) -> Result<()> {
    let saved = load_values(&args.file)?;
    let plan = match &args.plan {
        Some(path) => Some(load_plan(path, AllowedAtoms::Open)?),
        None => experiment_plan(&args.file)?,
    };
    let mut text = Vec::new();
    match plan {
        Some(plan) => {
            let (saved, report) = migrate::migrate(&saved, &plan.activation_plans())
                .with_context(|| format!("{}", args.file.display()))?;
            if !report.unchanged {
                eprintln!("{}: {report}", args.file.display());
            }
            let learned = group_by_choice(&[&plan], &saved).with_context(|| format!("{}", args.file.display()))?;
            by_choice::write_csv(&learned, &saved, &mut text)?;
        }
        None => {
            eprintln!(
                "warning: no plan for {} (give --plan PLAN): one row per marking, not grouped by choice point",
                args.file.display()
            );
            persist::write_csv(&saved, &mut text)?;
        }
    }
    std::io::stdout().lock().write_all(&text)?;
    Ok(())
}

#[derive(Args, Debug)]
pub struct DomainArgs {
    /// The domain's name, as `learnpnp experiment` takes it.
    name: String,
}

pub fn domains() -> Result<()> {
    let text: Vec<String> = describe::domains().iter().map(ToString::to_string).collect();
    write!(std::io::stdout().lock(), "{}", text.join("\n"))?;
    Ok(())
}

pub fn domain(args: &DomainArgs) -> Result<()> {
    let Some(d) = describe::domain(&args.name) else {
        let known: Vec<&str> = describe::domains().iter().map(|d| d.name).collect();
        anyhow::bail!("no domain '{}' (known: {})", args.name, known.join(", "));
    };
    write!(std::io::stdout().lock(), "{d}")?;
    Ok(())
}
