//! Plan files on disk: reading with the path in every error, writing atomically.

use std::fs;
use std::io;
use std::path::Path;

use super::error::PnmlFileError;
use super::{Dialect, parse, write};
use crate::net::PetriNet;

/// Reads a plan file in either dialect (see [`parse`]).
///
/// The fallback plan name is the file name up to its first '.'
/// (`plans/fetch.box.pnml` gives `fetch`). The bytes are read as UTF-8, or as
/// ISO-8859-1 (which JARP declares) when they are not valid UTF-8.
pub fn read_file(path: &Path) -> Result<PetriNet, PnmlFileError> {
    let bytes = fs::read(path).map_err(|error| PnmlFileError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    let text = decode(bytes);
    parse(&text, &fallback_name(path)).map_err(|error| PnmlFileError::Pnml {
        path: path.to_path_buf(),
        error,
    })
}

/// Writes the net to `path` in `dialect` (see [`write`](fn@write)), atomically: the text
/// goes to a temporary file in the same directory, which then replaces `path`.
/// An error message names the path.
pub fn write_file(net: &PetriNet, dialect: Dialect, path: &Path) -> io::Result<()> {
    atomic_file::write_atomic(path, write(net, dialect).as_bytes())
        .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))
}

/// The file name up to its first '.'.
fn fallback_name(path: &Path) -> String {
    let name = path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
    name.split_once('.').map_or(name.as_ref(), |(stem, _)| stem).to_string()
}

/// UTF-8 if valid, ISO-8859-1 otherwise (every byte is a code point there).
fn decode(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| e.into_bytes().into_iter().map(char::from).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fallback_name_is_the_file_name_up_to_its_first_dot() {
        assert_eq!(fallback_name(Path::new("plans/fetch.box.pnml")), "fetch");
        assert_eq!(fallback_name(Path::new("plan")), "plan");
        assert_eq!(fallback_name(Path::new("/a.b/c.pnml")), "c");
    }

    #[test]
    fn decodes_latin1_when_not_utf8() {
        assert_eq!(decode(b"caf\xe9".to_vec()), "café");
        assert_eq!(decode("café".as_bytes().to_vec()), "café");
    }
}
