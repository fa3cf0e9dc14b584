//! Experiments sharded across machines, with no scheduler of our own: shard
//! `I/N` of an experiment plays the runs `r` with `r % N == I` (0-based `I`,
//! as a Slurm array's task id or a Kubernetes indexed Job's completion index
//! count), each with the seeds the whole experiment gives it (run `r` depends
//! only on the spec and `r`). A shard writes a partial result that keeps its
//! runs bit for bit ([`super::checkpoint`](crate::experiment::checkpoint)) and [`SHARD_FILE`](crate::experiment::shard::SHARD_FILE); [`merge`](crate::experiment::shard::merge)
//! combines the shards' runs into the output one machine would have
//! produced, written by the same code ([`super::output::write_results`](crate::experiment::output::write_results)).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::checkpoint::read_completed;
use super::runner::ExperimentOutput;
use super::spec::{ExperimentError, ExperimentSpec};
use crate::experiment::result_dir::{Contents, ResultDir};

/// The file of a shard's result naming the shard.
pub const SHARD_FILE: &str = "shard.json";

/// One share of an experiment's runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which share, from 0.
    pub index: usize,
    /// How many shares.
    pub count: usize,
}

impl FromStr for Shard {
    type Err = String;

    /// Reads `I/N` (0 <= I < N).
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = || format!("'{text}' is not a shard I/N with 0 <= I < N (e.g. 0/4)");
        let (index, count) = text.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            index.trim().parse().map_err(|_| bad())?,
            count.trim().parse().map_err(|_| bad())?,
        );
        if index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// The runs of an experiment of `planned` runs this shard plays.
    pub fn runs(&self, planned: usize) -> Vec<usize> {
        (self.index..planned).step_by(self.count).collect()
    }
}

/// What [`SHARD_FILE`] says.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardRecord {
    /// The shard.
    pub shard: Shard,
    /// The runs it plays.
    pub runs: Vec<usize>,
}

/// Why shards cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// No directory was given.
    #[error("no shard to merge")]
    Nothing,
    /// A directory holds no shard's result.
    #[error("{0}: not a shard's result (no {SHARD_FILE}; run it with learnpnp experiment ... --shard I/N)")]
    NotAShard(PathBuf),
    /// Two shards of different experiments.
    #[error("{first} and {other} are shards of different experiments (their parameters or seeds differ)")]
    DifferentExperiments {
        /// The first shard.
        first: PathBuf,
        /// The other.
        other: PathBuf,
    },
    /// Shards of different splits.
    #[error("{first} is shard {a} and {other} is shard {b}: the experiment was split differently")]
    DifferentSplits {
        /// The first shard.
        first: PathBuf,
        /// Its shard.
        a: Shard,
        /// The other.
        other: PathBuf,
        /// Its shard.
        b: Shard,
    },
    /// The same shard twice.
    #[error("shard {shard} is given twice: {first} and {other}")]
    Duplicate {
        /// The shard.
        shard: Shard,
        /// Where it is.
        first: PathBuf,
        /// Where it is again.
        other: PathBuf,
    },
    /// Shards missing.
    #[error("shard(s) {missing} of {count} missing: every shard is needed")]
    Missing {
        /// The missing shards' indices, comma-separated.
        missing: String,
        /// How many shards the experiment has.
        count: usize,
    },
    /// A shard that did not complete its runs.
    #[error("{dir}: shard {shard} is partial: run(s) {missing} missing (continue it with --resume)")]
    Partial {
        /// The shard's directory.
        dir: PathBuf,
        /// The shard.
        shard: Shard,
        /// The runs it lacks, comma-separated.
        missing: String,
    },
    /// A shard's files cannot be read.
    #[error(transparent)]
    Unreadable(#[from] ExperimentError),
    /// A shard's file is not what it should be.
    #[error("{dir}: {SHARD_FILE}: {detail}")]
    BadShardFile {
        /// The shard's directory.
        dir: PathBuf,
        /// What is wrong.
        detail: String,
    },
}

/// One shard as read.
struct ReadShard {
    dir: PathBuf,
    record: ShardRecord,
    spec_text: String,
    output: super::runner::Completed,
}

fn read_shard(path: &Path) -> Result<ReadShard, MergeError> {
    let dir = ResultDir::open(path).map_err(ExperimentError::from)?;
    if !matches!(dir.contents().map_err(ExperimentError::from)?, Contents::Results(_)) {
        return Err(MergeError::NotAShard(path.to_path_buf()));
    }
    let text = dir
        .read(SHARD_FILE)
        .map_err(|_| MergeError::NotAShard(path.to_path_buf()))?;
    let record: ShardRecord = serde_json::from_slice(&text).map_err(|e| MergeError::BadShardFile {
        dir: path.to_path_buf(),
        detail: e.to_string(),
    })?;
    let (spec_text, output) = read_completed(&dir)?;
    Ok(ReadShard {
        dir: path.to_path_buf(),
        record,
        spec_text,
        output,
    })
}

fn list(values: impl IntoIterator<Item = usize>) -> String {
    values.into_iter().map(|v| v.to_string()).collect::<Vec<_>>().join(", ")
}

/// Combines the shards' results in `dirs` (in any order) into the output
/// the whole experiment would have produced on one machine; the wall-clock
/// seconds are the shards' sum. Refuses, saying why, shards of different
/// experiments or splits, a missing or repeated shard, and a partial one.
pub fn merge(dirs: &[PathBuf]) -> Result<ExperimentOutput, MergeError> {
    let shards = dirs.iter().map(|d| read_shard(d)).collect::<Result<Vec<_>, _>>()?;
    let first = shards.first().ok_or(MergeError::Nothing)?;
    let count = first.record.shard.count;
    let mut by_index: BTreeMap<usize, &ReadShard> = BTreeMap::new();
    for shard in &shards {
        if shard.spec_text != first.spec_text {
            return Err(MergeError::DifferentExperiments {
                first: first.dir.clone(),
                other: shard.dir.clone(),
            });
        }
        if shard.record.shard.count != count {
            return Err(MergeError::DifferentSplits {
                first: first.dir.clone(),
                a: first.record.shard,
                other: shard.dir.clone(),
                b: shard.record.shard,
            });
        }
        if let Some(earlier) = by_index.insert(shard.record.shard.index, shard) {
            return Err(MergeError::Duplicate {
                shard: shard.record.shard,
                first: earlier.dir.clone(),
                other: shard.dir.clone(),
            });
        }
    }
    let missing: Vec<usize> = (0..count).filter(|i| !by_index.contains_key(i)).collect();
    if !missing.is_empty() {
        return Err(MergeError::Missing {
            missing: list(missing),
            count,
        });
    }
    let spec = ExperimentSpec::from_json(&first.spec_text)?;
    let mut runs = Vec::with_capacity(spec.protocol.runs);
    let mut wall_seconds = 0.0;
    for shard in by_index.values() {
        let expected = shard.record.shard.runs(spec.protocol.runs);
        let have: Vec<usize> = shard.output.runs.iter().map(|r| r.run).collect();
        let lacking: Vec<usize> = expected.iter().copied().filter(|r| !have.contains(r)).collect();
        if !lacking.is_empty() || have.iter().any(|r| !expected.contains(r)) {
            return Err(MergeError::Partial {
                dir: shard.dir.clone(),
                shard: shard.record.shard,
                missing: list(lacking),
            });
        }
        runs.extend(shard.output.runs.iter().cloned());
        wall_seconds += shard.output.wall_seconds;
    }
    runs.sort_by_key(|r| r.run);
    Ok(ExperimentOutput {
        eval_points: spec.protocol.eval_points(),
        spec,
        runs,
        wall_seconds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_split_the_runs_between_them() {
        let shards: Vec<Shard> = (0..3).map(|i| format!("{i}/3").parse().unwrap()).collect();
        let mut all: Vec<usize> = shards.iter().flat_map(|s| s.runs(10)).collect();
        all.sort();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
        assert_eq!(shards[1].runs(10), vec![1, 4, 7]);
        for bad in ["3/3", "1", "a/2", "1/0", "-1/2"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
