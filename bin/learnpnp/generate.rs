//! `learnpnp generate`: a Petri Net Plan from planners' plans (`learnpnp::generate`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp::analysis::{self, Outcome};
use learnpnp::condition::AtomTable;
use learnpnp::generate::GeneratedPlan;
use learnpnp::generate::linear::parse_linear_plan;
use learnpnp::generate::rules::parse_rules;
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::pnml::{self, Dialect};

#[derive(Args, Debug)]
pub struct GenerateArgs {
    /// Linear plans: IPC plan files (one `(action arg ...)` a line, as
    /// planners write them) or PNPgen's line (`a|30; b; c`). Several plans
    /// (a planner's k best) merge into one plan with a choice point wherever
    /// they differ.
    #[arg(required_unless_present = "conditional", conflicts_with = "conditional")]
    plans: Vec<PathBuf>,
    /// A conditional plan in PNPgen's form (states, actions, edges labelled
    /// by sensing outcomes) instead of linear plans.
    #[arg(long, value_name = "FILE")]
    conditional: Option<PathBuf>,
    /// Execution rules (`*if* COND *during* ACTION *do* RECOVERY`, one a
    /// line), added as interrupts with their recovery branches.
    #[arg(long, value_name = "FILE")]
    rules: Option<PathBuf>,
    /// The atoms the world has, comma-separated: a rule's condition may test
    /// only these (by default any atom).
    #[arg(long, value_delimiter = ',')]
    atoms: Option<Vec<String>>,
    /// The plan's name (by default the first file's name up to its first '.').
    #[arg(long)]
    name: Option<String>,
    /// The PNML file to write (by default the plan is printed).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The dialect to write: jarp (the PNP editor) or standard (ISO/IEC 15909-2).
    #[arg(long, default_value_t = Dialect::Jarp)]
    to: Dialect,
}

fn read(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))
}

/// The file's name up to its first '.'.
fn stem(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    name.split('.').next().unwrap_or("plan").to_string()
}

pub fn run(args: &GenerateArgs) -> Result<()> {
    let first = args
        .conditional
        .as_ref()
        .or(args.plans.first())
        .context("no plan given")?;
    let name = args.name.clone().unwrap_or_else(|| stem(first));
    let mut generated = match &args.conditional {
        Some(path) => GeneratedPlan::conditional(&name, &read(path)?).with_context(|| path.display().to_string())?,
        None => {
            let plans = args
                .plans
                .iter()
                .map(|p| parse_linear_plan(&read(p)?).with_context(|| p.display().to_string()))
                .collect::<Result<Vec<_>>>()?;
            GeneratedPlan::merged(&name, &plans)?
        }
    };
    let atoms: Option<AtomTable> = args.atoms.as_ref().map(|a| a.iter().map(String::as_str).collect());
    if let Some(path) = &args.rules {
        let rules = parse_rules(&read(path)?).with_context(|| path.display().to_string())?;
        generated
            .apply_rules(&rules, atoms.as_ref())
            .with_context(|| path.display().to_string())?;
    }
    let net = generated.into_net()?;
    let plan = Plan::from_net(net.clone(), AllowedAtoms::Open).context("the generated plan")?;
    let report = analysis::check(&plan, analysis::DEFAULT_LIMIT);
    match &args.output {
        Some(path) => {
            pnml::write_file(&net, args.to, path).with_context(|| format!("writing {}", path.display()))?;
            eprintln!(
                "{}: plan '{}', {} actions, {} choice points",
                path.display(),
                plan.name(),
                plan.actions().len(),
                report.choice_points.len()
            );
        }
        None => print!("{}", pnml::write(&net, args.to)),
    }
    // Every generated plan should pass (a `fail_plan` rule's recovery ends in
    // the declared failure end, which `check` accepts); if one does not, the
    // plan is written and the report shown.
    if report.outcome() != Outcome::Passed {
        bail!("the generated plan does not pass the checks:\n{}", report.summary(8));
    }
    Ok(())
}
