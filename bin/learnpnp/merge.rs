//! `learnpnp merge OUT DIR...`: the shards of an experiment (`learnpnp
//! experiment ... --shard I/N`) or of a reproduction (`learnpnp reproduce
//! --shard I/N`) combined into what one machine would have written.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use learnpnp::experiment::output::write_results;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::shard::{SHARD_FILE, merge};

use super::reproduce::{self, REPRODUCE_SHARD_FILE, ReproduceArgs, ReproduceShard};

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Where the merged results go (replaced as a whole, as an experiment's).
    out: PathBuf,
    /// The shards' output directories, one per shard, in any order.
    #[arg(required = true)]
    shards: Vec<PathBuf>,
}

/// The directories under `root` holding a shard's result, relative to it.
fn curve_dirs(root: &Path) -> Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    let mut pending = vec![PathBuf::new()];
    while let Some(relative) = pending.pop() {
        let dir = root.join(&relative);
        if dir.join(SHARD_FILE).is_file() {
            found.push(relative);
            continue;
        }
        for entry in std::fs::read_dir(&dir).with_context(|| format!("reading {}", dir.display()))? {
            let entry = entry?;
            let name = entry.file_name();
            if entry.file_type()?.is_dir() && !name.to_string_lossy().starts_with('.') {
                pending.push(relative.join(name));
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Merges one experiment's shards into `out`.
fn merge_experiment(out: &Path, shards: &[PathBuf]) -> Result<()> {
    let output = merge(shards)?;
    let mut dir = ResultDir::open(out)?;
    write_results(&output, &mut dir).with_context(|| format!("writing {}", out.display()))?;
    Ok(())
}

pub fn run(args: &MergeArgs) -> Result<()> {
    let first = &args.shards[0];
    if first.join(SHARD_FILE).is_file() {
        merge_experiment(&args.out, &args.shards)?;
        println!("{} shards merged into {}", args.shards.len(), args.out.display());
        return Ok(());
    }
    let record_path = first.join(REPRODUCE_SHARD_FILE);
    let Ok(text) = std::fs::read(&record_path) else {
        bail!(
            "{}: neither an experiment's shard ({SHARD_FILE}) nor a reproduction's ({REPRODUCE_SHARD_FILE})",
            first.display()
        );
    };
    let record: ReproduceShard =
        serde_json::from_slice(&text).with_context(|| format!("{} is not a shard record", record_path.display()))?;
    for other in &args.shards[1..] {
        let path = other.join(REPRODUCE_SHARD_FILE);
        let theirs: ReproduceShard = serde_json::from_slice(
            &std::fs::read(&path).with_context(|| format!("{}: not a reproduction's shard", other.display()))?,
        )
        .with_context(|| format!("{} is not a shard record", path.display()))?;
        if (theirs.figures.as_slice(), theirs.runs) != (record.figures.as_slice(), record.runs) {
            bail!(
                "{} and {} are shards of different reproductions (figures or runs differ)",
                first.display(),
                other.display()
            );
        }
    }
    let curves = curve_dirs(first)?;
    for curve in &curves {
        let shards: Vec<PathBuf> = args.shards.iter().map(|s| s.join(curve)).collect();
        merge_experiment(&args.out.join(curve), &shards).with_context(|| format!("curve {}", curve.display()))?;
    }
    println!(
        "{} curve(s) of {} shards merged into {}; drawing the figures",
        curves.len(),
        args.shards.len(),
        args.out.display()
    );
    reproduce::run(&ReproduceArgs::of_merged(&record, args.out.clone()))
}
