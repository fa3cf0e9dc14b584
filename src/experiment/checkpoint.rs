//! The completed runs of an interrupted experiment, kept in its partial result
//! so that `--resume` continues without running them again.
//!
//! A partial result directory holds, besides the usual files computed over the
//! completed runs, [`CHECKPOINT`](crate::experiment::checkpoint::CHECKPOINT): the spec (as JSON text, compared exactly on
//! resume), the wall-clock seconds spent so far, and every completed
//! [`RunOutput`](crate::experiment::runner::RunOutput), bit for bit. Since run i depends only on the spec and i, the
//! runs still missing, run later, complete the same output an uninterrupted
//! experiment produces.
//!
//! The file is `LPNPRUNS` (8 bytes), the format version (`u32`), the CRC-32 of
//! the payload (`u32`), then the payload (bincode 2, serde, standard config),
//! integers little-endian.

use serde::{Deserialize, Serialize};

use super::runner::{Completed, ExperimentOutput, RunOutput};
use super::spec::{ExperimentError, ExperimentSpec};
use crate::experiment::result_dir::{Contents, ResultDir};
use crate::learning::persist::{decode_bounded, describe_decode_error};

/// The file of a partial result that holds its completed runs.
pub const CHECKPOINT: &str = "completed-runs.bin";

/// The first bytes of [`CHECKPOINT`].
const MAGIC: [u8; 8] = *b"LPNPRUNS";

/// The format version this build writes and reads.
/// 2: a run counts the actions of every episode it played (`RunOutput::actions_played`).
const FORMAT_VERSION: u32 = 2;

/// Bytes before the payload.
const HEADER_LEN: usize = 16;

#[derive(Serialize, Deserialize)]
struct Checkpoint {
    /// The spec as `serde_json::to_string` writes it.
    spec: String,
    wall_seconds: f64,
    runs: Vec<RunOutput>,
}

/// The bytes of [`CHECKPOINT`] for the runs `output` completed.
pub(crate) fn encode(output: &ExperimentOutput) -> Result<Vec<u8>, ExperimentError> {
    let checkpoint = Checkpoint {
        spec: spec_text(&output.spec)?,
        wall_seconds: output.wall_seconds,
        runs: output.runs.clone(),
    };
    let payload = bincode::serde::encode_to_vec(&checkpoint, bincode::config::standard())
        .map_err(|e| ExperimentError::Invalid(format!("cannot encode the completed runs: {e}")))?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

fn spec_text(spec: &ExperimentSpec) -> Result<String, ExperimentError> {
    serde_json::to_string(spec).map_err(|e| ExperimentError::Invalid(format!("cannot encode the spec: {e}")))
}

/// Where an experiment resumes from its output directory.
#[derive(Debug, Clone)]
pub enum ResumePoint {
    /// Nothing to resume: the directory holds no results.
    Fresh,
    /// An interrupted session of the same experiment: these runs are done.
    Partial(Completed),
    /// The same experiment, already complete.
    Complete,
}

/// What `dir` holds for an experiment of `spec` asked to resume: nothing,
/// its completed runs, or its complete results. Results of another
/// experiment, or of a version that kept no completed runs, are an error
/// naming the directory.
pub fn resume_point(dir: &ResultDir, spec: &ExperimentSpec) -> Result<ResumePoint, ExperimentError> {
    let invalid = |why: String| ExperimentError::Invalid(format!("{}: cannot resume: {why}", dir.path().display()));
    let manifest = match dir.contents()? {
        Contents::Empty => return Ok(ResumePoint::Fresh),
        Contents::Legacy => {
            return Err(invalid(
                "it holds results of an earlier version, which kept no completed runs; run without --resume to replace them"
                    .into(),
            ));
        }
        Contents::Results(manifest) => manifest,
    };
    let different = || invalid("it holds another experiment (different parameters or seed)".into());
    if manifest.complete {
        let summary: serde_json::Value = serde_json::from_slice(&dir.read("summary.json")?)
            .map_err(|e| invalid(format!("summary.json is not JSON: {e}")))?;
        let expected = serde_json::to_value(spec).map_err(|e| invalid(e.to_string()))?;
        return if summary.get("spec") == Some(&expected) {
            Ok(ResumePoint::Complete)
        } else {
            Err(different())
        };
    }
    let (text, completed) = read_completed(dir)?;
    if text != spec_text(spec)? {
        return Err(different());
    }
    Ok(ResumePoint::Partial(completed))
}

/// The completed runs a partial result in `dir` keeps, with its spec (the
/// JSON text it was written with): what `--resume` continues and
/// `learnpnp merge` combines. A missing, corrupt or foreign-format file is
/// an error naming the directory.
pub fn read_completed(dir: &ResultDir) -> Result<(String, Completed), ExperimentError> {
    let invalid = |why: String| ExperimentError::Invalid(format!("{}: {why}", dir.path().display()));
    let bytes = dir.read(CHECKPOINT)?;
    let corrupt = |why: String| invalid(format!("{CHECKPOINT} is corrupt: {why}"));
    let Some((header, payload)) = bytes.split_first_chunk::<HEADER_LEN>() else {
        return Err(corrupt("shorter than its header".into()));
    };
    let (magic, rest) = header.split_at(MAGIC.len());
    let (version, crc) = rest.split_at(4);
    if magic != MAGIC {
        return Err(corrupt("bad magic bytes".into()));
    }
    let version = u32::from_le_bytes(version.try_into().unwrap_or_default());
    if version != FORMAT_VERSION {
        return Err(invalid(format!(
            "{CHECKPOINT} has format {version}; this build reads format {FORMAT_VERSION}"
        )));
    }
    if u32::from_le_bytes(crc.try_into().unwrap_or_default()) != crc32fast::hash(payload) {
        return Err(corrupt("checksum mismatch".into()));
    }
    let (checkpoint, used) = decode_bounded::<Checkpoint>(payload).map_err(|e| corrupt(describe_decode_error(&e)))?;
    if used != payload.len() {
        return Err(corrupt(format!("{} byte(s) after the data", payload.len() - used)));
    }
    Ok((
        checkpoint.spec,
        Completed {
            runs: checkpoint.runs,
            wall_seconds: checkpoint.wall_seconds,
        },
    ))
}
