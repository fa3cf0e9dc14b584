//! `learnpnp schema`: the controllable process constructed from a plan schema.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use learnpnp::plan::AllowedAtoms;
use learnpnp::schema;

#[derive(Args, Debug)]
pub struct SchemaArgs {
    /// The plan schema file (.schema).
    schema: PathBuf,
    /// Print the process as Graphviz DOT instead of a listing.
    #[arg(long)]
    dot: bool,
}

pub fn run(args: &SchemaArgs) -> Result<()> {
    let process = schema::load_process(&args.schema, AllowedAtoms::Open)?;
    let text = if args.dot {
        schema::to_dot(&process)
    } else {
        schema::describe(&process)
    };
    write!(std::io::stdout().lock(), "{text}")?;
    Ok(())
}
