//! Damaged value files: every kind of damage gives its own error naming the
//! file, the file is never modified, and no bytes make `load` panic.

use std::fs;
use std::path::{Path, PathBuf};

use learnpnp::learning::persist::{
    FORMAT_VERSION, HEADER_LEN, Inconsistency, MAGIC, PersistError, PlanLabels, SavedEntry, SavedValues, load, save,
};
use proptest::prelude::*;

/// A fresh, empty directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("persist_corruption_{test}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn entry(plan: u16, tokens: &[u8], value: f64) -> SavedEntry {
    SavedEntry {
        plan,
        tokens: tokens.to_vec(),
        value,
        visits: 1,
    }
}

fn values() -> SavedValues {
    SavedValues {
        algorithm: "sosmc".into(),
        plans: vec![
            PlanLabels {
                name: "root".into(),
                places: vec!["start".into(), "a.exec".into(), "goal".into()],
            },
            PlanLabels {
                name: "sub".into(),
                places: vec!["x".into()],
            },
        ],
        entries: vec![
            entry(0, &[1, 0, 0], -1.5),
            entry(0, &[0, 1, 0], f64::NEG_INFINITY),
            entry(1, &[1], 2.0),
        ],
        identities: Vec::new(),
    }
}

/// The bytes of a value file holding `payload` (header fields given explicitly).
fn file_bytes(version: u32, payload: &[u8]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&version.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    bytes.extend_from_slice(payload);
    bytes
}

/// The bytes of a value file holding `values`, with no consistency check.
fn encoded(values: &SavedValues) -> Vec<u8> {
    let payload = bincode::serde::encode_to_vec(values, bincode::config::standard()).expect("encode");
    file_bytes(FORMAT_VERSION, &payload)
}

/// Writes `bytes` to `path`, loads it, checks the file is unchanged and that
/// the error names the file; returns the error.
fn load_err(path: &Path, bytes: &[u8]) -> PersistError {
    fs::write(path, bytes).expect("write");
    let err = load(path).expect_err("damaged file loads");
    assert_eq!(fs::read(path).expect("read back"), bytes, "load modified the file");
    let message = err.to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "the message does not name the file: {message}"
    );
    err
}

#[test]
fn the_reference_file_loads() {
    let dir = scratch("reference");
    let path = dir.join("v.bin");
    save(&path, &values()).expect("save");
    assert_eq!(fs::read(&path).expect("read"), encoded(&values()));
    assert_eq!(load(&path).expect("load"), values());
}

#[test]
fn a_flipped_payload_byte_fails_the_checksum() {
    let dir = scratch("flip");
    let path = dir.join("v.bin");
    let good = encoded(&values());
    for at in HEADER_LEN..good.len() {
        for bit in [0x01, 0x80] {
            let mut bytes = good.clone();
            bytes[at] ^= bit;
            let err = load_err(&path, &bytes);
            assert!(matches!(err, PersistError::Checksum { .. }), "byte {at}: {err:?}");
        }
    }
    // A damaged checksum field is caught the same way.
    let mut bytes = good.clone();
    bytes[HEADER_LEN - 1] ^= 0x10;
    let err = load_err(&path, &bytes);
    assert!(matches!(err, PersistError::Checksum { .. }), "{err:?}");
}

#[test]
fn a_truncated_file_is_reported_as_truncated() {
    let dir = scratch("truncate");
    let path = dir.join("v.bin");
    let good = encoded(&values());
    let full = good.len() as u64;
    for cut in [
        0,
        3,
        8,
        12,
        20,
        HEADER_LEN - 1,
        HEADER_LEN,
        HEADER_LEN + 1,
        good.len() - 1,
    ] {
        let err = load_err(&path, &good[..cut]);
        let expected = if cut < HEADER_LEN { HEADER_LEN as u64 } else { full };
        match err {
            PersistError::Truncated {
                expected: e, actual, ..
            } => {
                assert_eq!(e, expected, "cut at {cut}");
                assert_eq!(actual, cut as u64, "cut at {cut}");
            }
            other => panic!("cut at {cut}: {other:?}"),
        }
    }
}

#[test]
fn extra_bytes_after_the_payload_are_refused() {
    let dir = scratch("trailing");
    let path = dir.join("v.bin");
    let mut bytes = encoded(&values());
    bytes.extend_from_slice(b"xx");
    let err = load_err(&path, &bytes);
    assert!(matches!(err, PersistError::TrailingBytes { extra: 2, .. }), "{err:?}");
}

#[test]
fn a_file_without_the_magic_bytes_is_not_a_value_file() {
    let dir = scratch("magic");
    let path = dir.join("v.bin");
    let mut bytes = encoded(&values());
    bytes[0] = b'X';
    for damaged in [&bytes[..], b"hello", b"\x89PNG\r\n\x1a\n0000000000000000000000000"] {
        let err = load_err(&path, damaged);
        assert!(matches!(err, PersistError::NotAValueFile { .. }), "{err:?}");
        assert!(err.to_string().contains("not a learnpnp value file"), "{err}");
    }
}

#[test]
fn an_unknown_version_is_unsupported() {
    let dir = scratch("version");
    let path = dir.join("v.bin");
    let mut bytes = encoded(&values());
    bytes[8..12].copy_from_slice(&99u32.to_le_bytes());
    let err = load_err(&path, &bytes);
    assert!(
        matches!(
            err,
            PersistError::UnsupportedVersion {
                found: 99,
                supported: FORMAT_VERSION,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("version 99"), "{err}");
}

#[test]
fn a_payload_that_is_not_the_format_is_undecodable() {
    let dir = scratch("decode");
    let path = dir.join("v.bin");
    // A string length far beyond the payload.
    let err = load_err(&path, &file_bytes(FORMAT_VERSION, &[0xfc, 0xff, 0xff, 0xff, 0x7f]));
    assert!(matches!(err, PersistError::Decode { .. }), "{err:?}");
    // A string length of 2^62: refused without trying to allocate it.
    let mut huge = vec![0xfd];
    huge.extend_from_slice(&(1u64 << 62).to_le_bytes());
    let err = load_err(&path, &file_bytes(FORMAT_VERSION, &huge));
    assert!(matches!(err, PersistError::Decode { .. }), "{err:?}");
    let err = load_err(&path, &file_bytes(FORMAT_VERSION, &[]));
    assert!(matches!(err, PersistError::Decode { .. }), "{err:?}");
    // The algorithm's name is not UTF-8: said in words, not the decoder's debug text.
    let err = load_err(&path, &file_bytes(FORMAT_VERSION, &[2, 0xff, 0xfe]));
    let message = err.to_string();
    assert!(matches!(err, PersistError::Decode { .. }), "{err:?}");
    assert!(
        message.contains("not valid UTF-8") && !message.contains('{'),
        "{message}"
    );
    // A valid encoding followed by bytes the decoder does not use.
    let mut payload = bincode::serde::encode_to_vec(values(), bincode::config::standard()).expect("encode");
    payload.push(0);
    let err = load_err(&path, &file_bytes(FORMAT_VERSION, &payload));
    assert!(
        matches!(err, PersistError::PayloadTrailingBytes { unused: 1, .. }),
        "{err:?}"
    );
}

#[test]
fn inconsistent_payloads_are_refused() {
    let dir = scratch("inconsistent");
    let path = dir.join("v.bin");
    let cases = [
        (
            entry(2, &[1], 0.0),
            Inconsistency::UnknownPlan {
                entry: 3,
                plan: 2,
                plans: 2,
            },
        ),
        (
            entry(1, &[1, 0], 0.0),
            Inconsistency::WrongLength {
                entry: 3,
                plan: 1,
                name: "sub".into(),
                expected: 1,
                found: 2,
            },
        ),
        (
            entry(0, &[0, 1, 0], 4.0),
            Inconsistency::Duplicate {
                entry: 3,
                first: 1,
                plan: 0,
            },
        ),
    ];
    for (bad, expected) in cases {
        let mut v = values();
        v.entries.push(bad);
        let err = load_err(&path, &encoded(&v));
        match err {
            PersistError::Inconsistent { source, .. } => assert_eq!(source, expected),
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn a_missing_file_is_an_io_error() {
    let dir = scratch("missing");
    let path = dir.join("absent.bin");
    let err = load(&path).expect_err("missing");
    assert!(matches!(err, PersistError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains("absent.bin"), "{err}");
    assert!(!path.exists());
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let dir = scratch("random");
        let path = dir.join("v.bin");
        fs::write(&path, &bytes).expect("write");
        let _ = load(&path);
        prop_assert_eq!(fs::read(&path).expect("read"), bytes);
    }

    #[test]
    fn random_payloads_behind_a_valid_header_never_panic(
        payload in proptest::collection::vec(any::<u8>(), 0..200),
    ) {
        let dir = scratch("payload");
        let path = dir.join("v.bin");
        fs::write(&path, file_bytes(FORMAT_VERSION, &payload)).expect("write");
        if let Ok(v) = load(&path) {
            prop_assert!(v.validate().is_ok());
        }
    }

    #[test]
    fn mutated_valid_files_never_panic(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
        cut in any::<prop::sample::Index>(),
    ) {
        let dir = scratch("mutated");
        let path = dir.join("v.bin");
        let mut bytes = encoded(&values());
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let len = cut.index(bytes.len() + 1);
        bytes.truncate(len);
        fs::write(&path, &bytes).expect("write");
        if let Ok(v) = load(&path) {
            prop_assert!(v.validate().is_ok());
        }
    }
}

#[test]
fn errors_can_travel_across_threads() {
    fn thread_safe<T: std::error::Error + Send + Sync + 'static>() {}
    thread_safe::<PersistError>();
    thread_safe::<Inconsistency>();
}
