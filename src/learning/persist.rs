//! Saving and loading learned value tables, safely.
//!
//! A value file is a small header followed by a checksummed payload (all
//! integers little-endian):
//!
//! | offset | size | content                                                   |
//! |-------:|-----:|-----------------------------------------------------------|
//! | 0      | 8    | magic bytes [`MAGIC`](crate::learning::persist::MAGIC) (`LPNPVAL\0`)                       |
//! | 8      | 4    | format version, `u32` ([`FORMAT_VERSION`](crate::learning::persist::FORMAT_VERSION))                |
//! | 12     | 8    | payload length in bytes, `u64`                            |
//! | 20     | 4    | CRC-32 (IEEE) of the payload, `u32`                       |
//! | 24     | n    | payload: bincode 2 (serde, standard config) of [`SavedValues`](crate::learning::persist::SavedValues) |
//!
//! The file must be exactly header plus payload long. Markings are stored as
//! plain token vectors together with the place labels of every plan, so a file
//! can be listed ([`write_csv`](crate::learning::persist::write_csv)) without the plans that produced it, and checked
//! for consistency when it is read back.
//!
//! Version 2 (this build's) adds, per plan, the identity of every place and the
//! choice points with their options ([`PlanIdentity`](crate::learning::persist::PlanIdentity): names a designer
//! controls, see [`super::migrate`](crate::learning::migrate)), so that values can be carried into a
//! revised plan. Version 1 files (no identities) are still read: their
//! [`SavedValues::identities`](crate::learning::persist::SavedValues::identities) is empty.
//!
//! [`save`](crate::learning::persist::save) never leaves a half-written file behind: it writes a temporary file
//! in the same directory, syncs it and renames it over the target; the previous
//! table, if it was a valid value file, is kept as `<path>.prev` first.
//! [`load`](crate::learning::persist::load) never modifies anything, and [`load_latest`](crate::learning::persist::load_latest) falls back to the
//! `.prev` copy when the main file is unusable.

use std::collections::{BTreeSet, HashMap};
use std::ffi::OsString;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{StateKey, ValueTable};
use crate::analysis::{structural_choice_points, transition_name};
use crate::executor::PlanKey;
use crate::net::Marking;
use crate::plan::Plan;

/// The first eight bytes of every value file.
pub const MAGIC: [u8; 8] = *b"LPNPVAL\0";

/// The format version this build writes (and the newest it reads).
pub const FORMAT_VERSION: u32 = 2;

/// The oldest format version this build reads (version 1: no place identities).
pub(crate) const OLDEST_VERSION: u32 = 1;

/// Bytes before the payload: magic, version, payload length, checksum.
pub const HEADER_LEN: usize = 24;

/// A value table in a form that outlives the process: plan and place names
/// plus every entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedValues {
    /// The learner that produced the values (free text, e.g. `sosmc`).
    pub algorithm: String,
    /// The plans of the activation tree; the index is the [`PlanKey`].
    pub plans: Vec<PlanLabels>,
    /// Every entry of the table, in the table's id order.
    pub entries: Vec<SavedEntry>,
    /// One per plan (same order as `plans`): the places' identities and the
    /// choice points, to carry the values into a revised plan; empty in a
    /// version 1 file.
    pub identities: Vec<PlanIdentity>,
}

/// What a plan's places and choices are, by names a designer controls (see
/// [`place_keys`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanIdentity {
    /// One key per place, in place order: its name, qualified by the places
    /// leading to it where names repeat.
    pub(crate) keys: Vec<String>,
    /// The choice points, in place order.
    pub choices: Vec<SavedChoice>,
}

/// A choice point and its options, by name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedChoice {
    /// The choice point's place key.
    pub(crate) place: String,
    /// The names (labels, or ids when blank) of the transitions it chooses among, sorted.
    pub options: Vec<String>,
}

/// A version 1 payload: [`SavedValues`] without identities.
#[derive(Deserialize)]
struct SavedValuesV1 {
    algorithm: String,
    plans: Vec<PlanLabels>,
    entries: Vec<SavedEntry>,
}

/// The names of one plan and of its places.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanLabels {
    /// The plan's name.
    pub name: String,
    /// One name per place, in place order: the label, or the place id when the
    /// label is empty (as [`Plan::describe`] does).
    pub places: Vec<String>,
}

/// One entry of a saved table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedEntry {
    /// The plan (index into [`SavedValues::plans`]).
    pub plan: u16,
    /// Token count of every place of that plan.
    pub tokens: Vec<u8>,
    /// The value; negative infinity means "no estimate yet".
    pub value: f64,
    /// Updates of the entry so far.
    pub visits: u64,
}

/// Why a [`SavedValues`] does not describe a table: the entry at fault and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Inconsistency {
    /// An entry names a plan that is not listed.
    #[error("entry {entry} refers to plan {plan}, but only {plans} plan(s) are listed")]
    UnknownPlan {
        /// Index of the entry.
        entry: usize,
        /// The plan it names.
        plan: u16,
        /// How many plans are listed.
        plans: usize,
    },
    /// An entry's token vector does not match its plan's places.
    #[error("entry {entry} has {found} token count(s), but plan {plan} ('{name}') has {expected} place(s)")]
    WrongLength {
        /// Index of the entry.
        entry: usize,
        /// Its plan.
        plan: u16,
        /// The plan's name.
        name: String,
        /// Places of the plan.
        expected: usize,
        /// Token counts in the entry.
        found: usize,
    },
    /// A plan's identity does not fit its places, or not every plan has one.
    #[error("plan {plan} has {found} place key(s) for {expected} place(s), or the identities do not match the plans")]
    WrongIdentity {
        /// The plan at fault.
        plan: usize,
        /// Its places.
        expected: usize,
        /// Its keys.
        found: usize,
    },
    /// Two entries have the same plan and marking.
    #[error("entry {entry} repeats the marking of entry {first} (plan {plan})")]
    Duplicate {
        /// Index of the second entry.
        entry: usize,
        /// Index of the first one.
        first: usize,
        /// Their plan.
        plan: u16,
    },
}

/// A value file that cannot be saved or loaded; the message starts with its path.
#[derive(Debug, thiserror::Error)]
pub enum PersistError {
    /// Reading, writing or renaming failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// The file does not start with [`MAGIC`].
    #[error("{path}: not a learnpnp value file (bad magic bytes)")]
    NotAValueFile {
        /// The file.
        path: PathBuf,
    },
    /// The file was written in a format version this build does not read.
    #[error(
        "{path}: unsupported value file version {found} (this build reads versions {OLDEST_VERSION} to {supported})"
    )]
    UnsupportedVersion {
        /// The file.
        path: PathBuf,
        /// The version in the file.
        found: u32,
        /// The version this build reads.
        supported: u32,
    },
    /// The file is shorter than its header or than the payload it announces.
    #[error("{path}: truncated value file ({actual} bytes, expected {expected})")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Bytes the file should have (at least).
        expected: u64,
        /// Bytes it has.
        actual: u64,
    },
    /// The file is longer than header plus announced payload.
    #[error("{path}: {extra} unexpected byte(s) after the payload")]
    TrailingBytes {
        /// The file.
        path: PathBuf,
        /// Bytes beyond the payload.
        extra: u64,
    },
    /// The payload does not match its checksum.
    #[error("{path}: checksum mismatch (stored {stored:#010x}, computed {computed:#010x}); the file is corrupt")]
    Checksum {
        /// The file.
        path: PathBuf,
        /// The checksum in the header.
        stored: u32,
        /// The checksum of the payload read.
        computed: u32,
    },
    /// The payload passed its checksum but cannot be decoded.
    #[error("{path}: undecodable payload: {}", describe_decode_error(error))]
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's error.
        error: bincode::error::DecodeError,
    },
    /// The payload decodes to fewer bytes than announced.
    #[error("{path}: undecodable payload: {unused} byte(s) left over after decoding")]
    PayloadTrailingBytes {
        /// The file.
        path: PathBuf,
        /// Payload bytes not consumed by the decoder.
        unused: usize,
    },
    /// The values cannot be encoded.
    #[error("{path}: cannot encode the values: {source}")]
    Encode {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        source: bincode::error::EncodeError,
    },
    /// The payload decodes but does not describe a table (or the values to
    /// save do not).
    #[error("{path}: inconsistent values: {source}")]
    Inconsistent {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: Inconsistency,
    },
}

impl PlanLabels {
    /// The names of `plan` and of its places.
    pub fn of(plan: &Plan) -> Self {
        PlanLabels {
            name: plan.name().to_string(),
            places: plan
                .net()
                .places()
                .iter()
                .map(|p| {
                    if p.label.is_empty() {
                        p.id.clone()
                    } else {
                        p.label.clone()
                    }
                })
                .collect(),
        }
    }

    /// A marking as text: the names of its marked places joined by spaces,
    /// `name*n` for a place with `n > 1` tokens, `-` when nothing is marked.
    /// Token counts beyond the listed places are named `#<index>`.
    pub fn describe(&self, tokens: &[u8]) -> String {
        describe_tokens(tokens, |i| self.places.get(i))
    }
}

/// Tokens as `name name*n ...` (`name*n` for a place with `n > 1` tokens, `-`
/// when nothing is marked), each place named by `name_of` (`#<index>` where it
/// has no name).
pub(crate) fn describe_tokens<'a>(tokens: &[u8], name_of: impl Fn(usize) -> Option<&'a String>) -> String {
    let parts: Vec<String> = tokens
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(i, &n)| {
            let name = name_of(i).cloned().unwrap_or_else(|| format!("#{i}"));
            if n == 1 { name } else { format!("{name}*{n}") }
        })
        .collect();
    if parts.is_empty() {
        "-".to_string()
    } else {
        parts.join(" ")
    }
}

impl SavedValues {
    /// The contents of `table`, learned by `algorithm`, over `plans` (indexed by
    /// [`PlanKey`]: the root plan first, sub-plans in registration order).
    ///
    /// Nothing is checked here; [`SavedValues::validate`] (also run by [`save`])
    /// reports keys whose plan is missing from `plans` or whose marking does not
    /// fit the plan.
    pub fn new(algorithm: impl Into<String>, table: &ValueTable, plans: &[&Plan]) -> Self {
        SavedValues {
            algorithm: algorithm.into(),
            plans: plans.iter().map(|p| PlanLabels::of(p)).collect(),
            identities: plans.iter().map(|p| identity_of(p)).collect(),
            entries: table
                .entries()
                .map(|(key, value, visits)| SavedEntry {
                    plan: key.plan.0,
                    tokens: key.marking.tokens().to_vec(),
                    value,
                    visits,
                })
                .collect(),
        }
    }

    /// A table holding every entry (values and visit counts exactly as saved,
    /// ids in entry order) whose new entries start at `initial_value`. Of
    /// entries repeating a key (which [`SavedValues::validate`] refuses, and
    /// [`load`] never returns) the last one wins.
    pub fn to_table(&self, initial_value: f64) -> ValueTable {
        let mut table = ValueTable::new(initial_value);
        for e in &self.entries {
            table.insert(
                StateKey {
                    plan: PlanKey(e.plan),
                    marking: Marking::from_tokens(e.tokens.clone()),
                },
                e.value,
                e.visits,
            );
        }
        table
    }

    /// Checks that every entry names a listed plan, fits its places, and that no
    /// (plan, marking) appears twice.
    pub fn validate(&self) -> Result<(), Inconsistency> {
        if !self.identities.is_empty() {
            for (plan, labels) in self.plans.iter().enumerate() {
                let found = self.identities.get(plan).map_or(0, |i| i.keys.len());
                if found != labels.places.len() {
                    return Err(Inconsistency::WrongIdentity {
                        plan,
                        expected: labels.places.len(),
                        found,
                    });
                }
            }
            if self.identities.len() != self.plans.len() {
                return Err(Inconsistency::WrongIdentity {
                    plan: self.plans.len(),
                    expected: 0,
                    found: 0,
                });
            }
        }
        let mut seen: HashMap<(u16, &[u8]), usize> = HashMap::with_capacity(self.entries.len());
        for (entry, e) in self.entries.iter().enumerate() {
            let Some(plan) = self.plans.get(usize::from(e.plan)) else {
                return Err(Inconsistency::UnknownPlan {
                    entry,
                    plan: e.plan,
                    plans: self.plans.len(),
                });
            };
            if e.tokens.len() != plan.places.len() {
                return Err(Inconsistency::WrongLength {
                    entry,
                    plan: e.plan,
                    name: plan.name.clone(),
                    expected: plan.places.len(),
                    found: e.tokens.len(),
                });
            }
            if let Some(&first) = seen.get(&(e.plan, e.tokens.as_slice())) {
                return Err(Inconsistency::Duplicate {
                    entry,
                    first,
                    plan: e.plan,
                });
            }
            seen.insert((e.plan, e.tokens.as_slice()), entry);
        }
        Ok(())
    }
}

/// The file kept next to `path` holding the previous valid table: `<path>.prev`.
pub fn prev_path(path: &Path) -> PathBuf {
    let mut name = OsString::from(path.as_os_str());
    name.push(".prev");
    PathBuf::from(name)
}

/// Saves `values` to `path` atomically.
///
/// The values are checked first ([`SavedValues::validate`]); nothing is written
/// if they are inconsistent. If `path` already holds a valid value file, its
/// bytes are first installed (atomically) as `<path>.prev`; an unreadable or
/// corrupt file at `path` is simply replaced, so `.prev` keeps the last good
/// table. The new file is then written to a temporary file in the same
/// directory, synced, and renamed over `path`: at every moment `path` holds
/// either the old or the new complete file. If keeping `.prev` fails, the new
/// table is not written and the error names the `.prev` file.
pub fn save(path: &Path, values: &SavedValues) -> Result<(), PersistError> {
    let bytes = encode(path, values)?;
    let previous = fs::read(path).ok().filter(|old| parse(path, old).is_ok());
    if let Some(old) = previous {
        let prev = prev_path(path);
        atomic_file::write_atomic(&prev, &old).map_err(|source| PersistError::Io { path: prev, source })?;
    }
    atomic_file::write_atomic(path, &bytes).map_err(|source| PersistError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The bytes of a value file holding `values` (for writers that place the
/// file themselves, such as a result directory); `path` names the file in
/// errors. The values are checked first ([`SavedValues::validate`]).
pub(crate) fn encode(path: &Path, values: &SavedValues) -> Result<Vec<u8>, PersistError> {
    values.validate().map_err(|source| PersistError::Inconsistent {
        path: path.to_path_buf(),
        source,
    })?;
    let payload =
        bincode::serde::encode_to_vec(values, bincode::config::standard()).map_err(|source| PersistError::Encode {
            path: path.to_path_buf(),
            source,
        })?;
    let mut bytes = Vec::with_capacity(HEADER_LEN + payload.len());
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

/// Reads the value file at `path`, checking magic, version, length, checksum
/// and consistency. Never modifies the file, and never panics, whatever it holds.
pub fn load(path: &Path) -> Result<SavedValues, PersistError> {
    let bytes = fs::read(path).map_err(|source| PersistError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse(path, &bytes)
}

/// Reads a value file's `bytes` (called `path` in errors), checking magic,
/// version, length, checksum and consistency, as [`load`] does: for bytes
/// that arrive otherwise than from a file (a value file shipped between hosts).
pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<SavedValues, PersistError> {
    parse(path, bytes)
}

/// Reads `path`, or, if it cannot be used (missing, unreadable or corrupt),
/// `<path>.prev` together with the error that made `path` unusable, so callers
/// can report the problem and continue with the last good table.
///
/// When `.prev` cannot be used either, the error about `path` is returned.
pub fn load_latest(path: &Path) -> Result<(SavedValues, Option<PersistError>), PersistError> {
    match load(path) {
        Ok(values) => Ok((values, None)),
        Err(error) => match load(&prev_path(path)) {
            Ok(values) => Ok((values, Some(error))),
            Err(_) => Err(error),
        },
    }
}

/// Decodes the bytes of a value file read from `path`.
fn parse(path: &Path, bytes: &[u8]) -> Result<SavedValues, PersistError> {
    let path_buf = || path.to_path_buf();
    let magic_len = bytes.len().min(MAGIC.len());
    if bytes[..magic_len] != MAGIC[..magic_len] {
        return Err(PersistError::NotAValueFile { path: path_buf() });
    }
    let Some((header, rest)) = bytes.split_first_chunk::<HEADER_LEN>() else {
        return Err(PersistError::Truncated {
            path: path_buf(),
            expected: HEADER_LEN as u64,
            actual: bytes.len() as u64,
        });
    };
    let (_, header) = header.split_at(MAGIC.len());
    let (version, header) = split_u32(header);
    let (length, header) = split_u64(header);
    let (stored, _) = split_u32(header);
    if !(OLDEST_VERSION..=FORMAT_VERSION).contains(&version) {
        return Err(PersistError::UnsupportedVersion {
            path: path_buf(),
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    let available = rest.len() as u64;
    if available < length {
        return Err(PersistError::Truncated {
            path: path_buf(),
            expected: (HEADER_LEN as u64).saturating_add(length),
            actual: bytes.len() as u64,
        });
    }
    if available > length {
        return Err(PersistError::TrailingBytes {
            path: path_buf(),
            extra: available - length,
        });
    }
    let computed = crc32fast::hash(rest);
    if computed != stored {
        return Err(PersistError::Checksum {
            path: path_buf(),
            stored,
            computed,
        });
    }
    let decoded = if version == 1 {
        decode_bounded::<SavedValuesV1>(rest).map(|(v, used)| {
            let values = SavedValues {
                algorithm: v.algorithm,
                plans: v.plans,
                entries: v.entries,
                identities: Vec::new(),
            };
            (values, used)
        })
    } else {
        decode_bounded::<SavedValues>(rest)
    };
    let (values, used) = decoded.map_err(|error| PersistError::Decode {
        path: path_buf(),
        error,
    })?;
    if used != rest.len() {
        return Err(PersistError::PayloadTrailingBytes {
            path: path_buf(),
            unused: rest.len().saturating_sub(used),
        });
    }
    values.validate().map_err(|source| PersistError::Inconsistent {
        path: path_buf(),
        source,
    })?;
    Ok(values)
}

/// Decodes a bincode payload, bounding what the decoder may allocate.
///
/// bincode allocates a string's bytes before reading them, so a corrupt length
/// could ask for exabytes. Its byte limit counts every claim (a string's
/// length, the in-memory size of every number), which for a valid payload is at
/// most eight times its encoded size; the limit is the smallest of a few fixed
/// tiers above that (a limit is a compile-time constant), so a bogus length
/// fails with `LimitExceeded` instead of allocating more than a small multiple
/// of the file. Payloads beyond 256 MiB are decoded without a limit.
pub(crate) fn decode_bounded<T: serde::de::DeserializeOwned>(
    payload: &[u8],
) -> Result<(T, usize), bincode::error::DecodeError> {
    fn limited<T: serde::de::DeserializeOwned, const LIMIT: usize>(
        payload: &[u8],
    ) -> Result<(T, usize), bincode::error::DecodeError> {
        bincode::serde::decode_from_slice(payload, bincode::config::standard().with_limit::<LIMIT>())
    }
    let claims = payload.len().saturating_mul(8).saturating_add(4096);
    if claims <= 1 << 16 {
        limited::<T, { 1 << 16 }>(payload)
    } else if claims <= 1 << 20 {
        limited::<T, { 1 << 20 }>(payload)
    } else if claims <= 1 << 24 {
        limited::<T, { 1 << 24 }>(payload)
    } else if claims <= 1 << 28 {
        limited::<T, { 1 << 28 }>(payload)
    } else if claims <= 1 << 31 {
        limited::<T, { 1 << 31 }>(payload)
    } else {
        limited::<T, { usize::MAX }>(payload)
    }
}

/// What a bincode decoding error means, in words (bincode's own message is
/// its debug representation).
pub(crate) fn describe_decode_error(error: &bincode::error::DecodeError) -> String {
    use bincode::error::DecodeError as E;
    match error {
        E::UnexpectedEnd { additional } => format!("the data ends {additional} byte(s) too early"),
        E::LimitExceeded => "a length is larger than the file can hold".to_string(),
        E::InvalidIntegerType { .. } | E::OutsideUsizeRange(_) => "a number is out of range".to_string(),
        E::UnexpectedVariant { type_name, found, .. } => format!("unknown variant {found} of {type_name}"),
        E::Utf8 { .. } => "a text is not valid UTF-8".to_string(),
        E::InvalidCharEncoding(_) => "a character is not valid".to_string(),
        E::InvalidBooleanValue(b) => format!("{b} is not a boolean"),
        E::ArrayLengthMismatch { required, found } => {
            format!("a list has {found} element(s) where {required} are required")
        }
        E::Other(message) => (*message).to_string(),
        E::OtherString(message) => message.clone(),
        _ => "the data does not have the expected structure".to_string(),
    }
}

/// Splits a little-endian `u32` off the front of a header slice of known length.
fn split_u32(bytes: &[u8]) -> (u32, &[u8]) {
    let mut word = [0; 4];
    let (head, rest) = bytes.split_at(4);
    word.copy_from_slice(head);
    (u32::from_le_bytes(word), rest)
}

/// Splits a little-endian `u64` off the front of a header slice of known length.
fn split_u64(bytes: &[u8]) -> (u64, &[u8]) {
    let mut word = [0; 8];
    let (head, rest) = bytes.split_at(8);
    word.copy_from_slice(head);
    (u64::from_le_bytes(word), rest)
}

/// One entry of a saved table as `learnpnp values` lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct ValueRow {
    /// The plan's name.
    pub plan: String,
    /// The names of its marked places (see [`PlanLabels::describe`]).
    pub marking: String,
    /// The value; negative infinity means "no estimate yet".
    pub value: f64,
    /// Updates of the entry so far.
    pub visits: u64,
}

/// The entries of `values`, sorted by plan index, then marking text; refused
/// when the values are inconsistent (see [`SavedValues::validate`]).
pub fn rows(values: &SavedValues) -> Result<Vec<ValueRow>, Inconsistency> {
    values.validate()?;
    let mut rows: Vec<(u16, ValueRow)> = values
        .entries
        .iter()
        .map(|e| {
            let plan = values.plans.get(usize::from(e.plan));
            let row = ValueRow {
                plan: plan.map_or_else(String::new, |p| p.name.clone()),
                marking: plan.map_or_else(String::new, |p| p.describe(&e.tokens)),
                value: e.value,
                visits: e.visits,
            };
            (e.plan, row)
        })
        .collect();
    rows.sort_by(|a, b| (a.0, &a.1.marking).cmp(&(b.0, &b.1.marking)));
    Ok(rows.into_iter().map(|(_, row)| row).collect())
}

/// Lists `values` as CSV: `plan,marking,value,visits`, one row per entry
/// (the [`rows`]).
///
/// `value` is printed exactly (the shortest text that reads back to the same
/// number, e.g. `0.5`, `3.0`, `1e-300`; `-inf` for no estimate). Fields with
/// commas, quotes or line breaks are quoted. Inconsistent values are refused
/// with [`io::ErrorKind::InvalidData`].
pub fn write_csv(values: &SavedValues, out: &mut impl Write) -> io::Result<()> {
    let rows = rows(values).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))?;
    writeln!(out, "plan,marking,value,visits")?;
    for row in rows {
        writeln!(
            out,
            "{},{},{:?},{}",
            csv_field(&row.plan),
            csv_field(&row.marking),
            row.value,
            row.visits
        )?;
    }
    Ok(())
}

/// Quotes a CSV field when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}
/// Rounds of qualification by predecessors while keys repeat.
pub const REFINE_ROUNDS: usize = 4;

/// The key of every place of `plan`, in place order (the rule in [`super::migrate`]).
pub fn place_keys(plan: &Plan) -> Vec<String> {
    let names = PlanLabels::of(plan).places;
    let incidence = plan.incidence();
    let mut preds: Vec<Vec<usize>> = vec![Vec::new(); names.len()];
    for t in incidence.transition_ids() {
        for out in incidence.outputs(t) {
            for input in incidence.inputs(t) {
                preds[out.place.index()].push(input.place.index());
            }
        }
    }
    for p in &mut preds {
        p.sort_unstable();
        p.dedup();
    }
    let mut keys = names.clone();
    for _ in 0..REFINE_ROUNDS {
        let counts = counts(&keys);
        if counts.values().all(|&n| n == 1) {
            break;
        }
        let next: Vec<String> = keys
            .iter()
            .enumerate()
            .map(|(p, key)| {
                if counts[key.as_str()] == 1 {
                    return key.clone();
                }
                let context: BTreeSet<&str> = preds[p].iter().map(|&q| keys[q].as_str()).collect();
                format!("{}<{}>", names[p], context.into_iter().collect::<Vec<_>>().join(","))
            })
            .collect();
        if next == keys {
            break;
        }
        keys = next;
    }
    keys
}

/// How often each key occurs.
pub(super) fn counts(keys: &[String]) -> HashMap<&str, usize> {
    let mut counts = HashMap::with_capacity(keys.len());
    for k in keys {
        *counts.entry(k.as_str()).or_insert(0) += 1;
    }
    counts
}

/// The identity of `plan` as a value file stores it: the place keys and the
/// choice points with their options' names.
pub(crate) fn identity_of(plan: &Plan) -> PlanIdentity {
    let keys = place_keys(plan);
    let choices = structural_choice_points(plan)
        .into_iter()
        .map(|c| {
            let mut options: Vec<String> = c
                .options
                .iter()
                .map(|&t| transition_name(plan, t).to_string())
                .collect();
            options.sort();
            SavedChoice {
                place: keys[c.place.index()].clone(),
                options,
            }
        })
        .collect();
    PlanIdentity { keys, choices }
}
