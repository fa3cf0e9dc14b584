//! CDR as rmw_zenoh sends it (design.md, "Serialization/Deserialization":
//! CDR, so that data bridges to DDS unchanged): a 4-byte encapsulation
//! header (XCDR1 little-endian, `00 01 00 00`), then each primitive aligned
//! to its size counted from the end of the header (8 for 64-bit values),
//! strings as a `u32` length counting the terminating NUL, then the bytes and
//! the NUL, sequences as a `u32` count then the elements, fixed arrays as
//! their elements only.

use thiserror::Error;

/// The encapsulation header of little-endian plain CDR (XCDR1, `CDR_LE`).
pub(crate) const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// A payload that is not the CDR expected.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum CdrError {
    /// The payload is shorter than its encapsulation header.
    #[error("payload of {0} bytes has no CDR encapsulation header")]
    NoHeader(usize),
    /// The encapsulation is not little-endian plain CDR.
    #[error("encapsulation {0:02x} {1:02x} is not little-endian CDR (00 01)")]
    Encapsulation(u8, u8),
    /// The payload ends before a value.
    #[error("payload ends at byte {at} where {need} more bytes are needed")]
    Truncated {
        /// Offset in the body (after the header).
        at: usize,
        /// Bytes needed.
        need: usize,
    },
    /// A string without its NUL or not UTF-8.
    #[error("string at byte {0} is not NUL-terminated UTF-8")]
    BadString(usize),
    /// A boolean other than 0 or 1.
    #[error("boolean at byte {at} is {value}, not 0 or 1")]
    BadBool {
        /// Offset in the body.
        at: usize,
        /// The byte found.
        value: u8,
    },
    /// A bounded sequence or string longer than its bound.
    #[error("{what} at byte {at} has {count} elements, more than its bound {bound}")]
    OverBound {
        /// `sequence` or `string`.
        what: &'static str,
        /// Offset in the body.
        at: usize,
        /// The count found (a string's bytes without its NUL).
        count: usize,
        /// The type's bound.
        bound: usize,
    },
    /// A sequence longer than the payload could hold.
    #[error("sequence at byte {at} claims {count} elements")]
    BadLength {
        /// Offset in the body.
        at: usize,
        /// The count found.
        count: u32,
    },
}

/// Writes a CDR payload, header included.
#[derive(Debug, Clone)]
pub(crate) struct Writer {
    buf: Vec<u8>,
}

impl Default for Writer {
    fn default() -> Self {
        Self::new()
    }
}

impl Writer {
    /// An empty body after the little-endian header.
    pub fn new() -> Self {
        Self {
            buf: CDR_LE_HEADER.to_vec(),
        }
    }

    /// Pads the body to a multiple of `n` (alignment counts from after the header).
    pub(crate) fn align(&mut self, n: usize) {
        let body = self.buf.len() - CDR_LE_HEADER.len();
        let pad = (n - body % n) % n;
        self.buf.extend(std::iter::repeat_n(0u8, pad));
    }

    /// Writes a value's little-endian bytes aligned to their size.
    fn put<const N: usize>(&mut self, bytes: [u8; N]) {
        self.align(N);
        self.buf.extend_from_slice(&bytes);
    }

    /// A boolean (one byte).
    pub(crate) fn bool(&mut self, v: bool) {
        self.buf.push(u8::from(v));
    }
    /// One byte.
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }
    /// A signed byte.
    pub(crate) fn i8(&mut self, v: i8) {
        self.put(v.to_le_bytes());
    }
    /// A 16-bit signed integer.
    pub(crate) fn i16(&mut self, v: i16) {
        self.put(v.to_le_bytes());
    }
    /// A 16-bit unsigned integer.
    pub fn u16(&mut self, v: u16) {
        self.put(v.to_le_bytes());
    }
    /// A 32-bit signed integer.
    pub(crate) fn i32(&mut self, v: i32) {
        self.put(v.to_le_bytes());
    }
    /// A 32-bit unsigned integer.
    pub fn u32(&mut self, v: u32) {
        self.put(v.to_le_bytes());
    }
    /// A 64-bit signed integer.
    pub(crate) fn i64(&mut self, v: i64) {
        self.put(v.to_le_bytes());
    }
    /// A 64-bit unsigned integer.
    pub(crate) fn u64(&mut self, v: u64) {
        self.put(v.to_le_bytes());
    }
    /// A 32-bit float.
    pub(crate) fn f32(&mut self, v: f32) {
        self.put(v.to_le_bytes());
    }
    /// A 64-bit float.
    pub fn f64(&mut self, v: f64) {
        self.put(v.to_le_bytes());
    }
    /// A string: length with the NUL, bytes, NUL.
    pub fn string(&mut self, s: &str) {
        self.u32(u32::try_from(s.len() + 1).unwrap_or(u32::MAX));
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
    }
    /// The payload, header included.
    pub(crate) fn finish(self) -> Vec<u8> {
        self.buf
    }
}

/// Reads a CDR payload.
#[derive(Debug, Clone)]
pub(crate) struct Reader<'a> {
    body: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// Checks the header (little-endian plain CDR only) and reads the body.
    pub fn new(payload: &'a [u8]) -> Result<Self, CdrError> {
        if payload.len() < CDR_LE_HEADER.len() {
            return Err(CdrError::NoHeader(payload.len()));
        }
        if payload[..2] != CDR_LE_HEADER[..2] {
            return Err(CdrError::Encapsulation(payload[0], payload[1]));
        }
        Ok(Self {
            body: &payload[CDR_LE_HEADER.len()..],
            pos: 0,
        })
    }

    /// Skips to a multiple of `n`.
    fn align(&mut self, n: usize) {
        self.pos += (n - self.pos % n) % n;
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], CdrError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.body.len());
        match end {
            Some(end) => {
                let s = &self.body[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            None => Err(CdrError::Truncated { at: self.pos, need: n }),
        }
    }

    fn get<const N: usize>(&mut self) -> Result<[u8; N], CdrError> {
        self.align(N);
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }

    /// A boolean (0 or 1).
    pub(crate) fn bool(&mut self) -> Result<bool, CdrError> {
        let at = self.pos;
        match self.take(1)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            value => Err(CdrError::BadBool { at, value }),
        }
    }
    /// One byte.
    pub fn u8(&mut self) -> Result<u8, CdrError> {
        Ok(self.take(1)?[0])
    }
    /// A signed byte.
    pub(crate) fn i8(&mut self) -> Result<i8, CdrError> {
        Ok(i8::from_le_bytes(self.get()?))
    }
    /// A 16-bit signed integer.
    pub(crate) fn i16(&mut self) -> Result<i16, CdrError> {
        Ok(i16::from_le_bytes(self.get()?))
    }
    /// A 16-bit unsigned integer.
    pub fn u16(&mut self) -> Result<u16, CdrError> {
        Ok(u16::from_le_bytes(self.get()?))
    }
    /// A 32-bit signed integer.
    pub(crate) fn i32(&mut self) -> Result<i32, CdrError> {
        Ok(i32::from_le_bytes(self.get()?))
    }
    /// A 32-bit unsigned integer.
    pub fn u32(&mut self) -> Result<u32, CdrError> {
        Ok(u32::from_le_bytes(self.get()?))
    }
    /// A 64-bit signed integer.
    pub(crate) fn i64(&mut self) -> Result<i64, CdrError> {
        Ok(i64::from_le_bytes(self.get()?))
    }
    /// A 64-bit unsigned integer.
    pub(crate) fn u64(&mut self) -> Result<u64, CdrError> {
        Ok(u64::from_le_bytes(self.get()?))
    }
    /// A 32-bit float.
    pub(crate) fn f32(&mut self) -> Result<f32, CdrError> {
        Ok(f32::from_le_bytes(self.get()?))
    }
    /// A 64-bit float.
    pub fn f64(&mut self) -> Result<f64, CdrError> {
        Ok(f64::from_le_bytes(self.get()?))
    }
    /// A sequence's element count, checked against what is left (each element takes a byte at least).
    pub(crate) fn count(&mut self) -> Result<usize, CdrError> {
        let n = self.u32()?;
        let at = self.pos;
        if n as usize > self.body.len() - self.pos {
            return Err(CdrError::BadLength { at, count: n });
        }
        Ok(n as usize)
    }
    /// A bounded sequence's element count (`T[<=bound]`), refused when over its bound.
    pub(crate) fn bounded_count(&mut self, bound: usize) -> Result<usize, CdrError> {
        self.align(4);
        let at = self.pos;
        let count = self.count()?;
        if count > bound {
            return Err(CdrError::OverBound {
                what: "sequence",
                at,
                count,
                bound,
            });
        }
        Ok(count)
    }
    /// A bounded string (`string<=bound`, the bound in bytes), refused when over its bound.
    pub(crate) fn bounded_string(&mut self, bound: usize) -> Result<String, CdrError> {
        self.align(4);
        let at = self.pos;
        let s = self.string()?;
        if s.len() > bound {
            return Err(CdrError::OverBound {
                what: "string",
                at,
                count: s.len(),
                bound,
            });
        }
        Ok(s)
    }
    /// A string: length with the NUL, bytes, NUL.
    pub fn string(&mut self) -> Result<String, CdrError> {
        let at = self.pos;
        let n = self.count()?;
        let bytes = self.take(n)?;
        match bytes.split_last() {
            Some((0, text)) => String::from_utf8(text.to_vec()).map_err(|_| CdrError::BadString(at)),
            _ => Err(CdrError::BadString(at)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_string_is_its_length_with_the_nul_then_its_bytes() {
        let mut w = Writer::new();
        w.string("hi");
        assert_eq!(w.finish(), [0, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0]);
    }

    #[test]
    fn alignment_counts_from_the_end_of_the_header() {
        let mut w = Writer::new();
        w.u8(7);
        w.f64(1.0);
        let bytes = w.finish();
        assert_eq!(bytes.len(), 4 + 8 + 8);
        let mut r = Reader::new(&bytes).unwrap();
        assert_eq!(r.u8().unwrap(), 7);
        assert_eq!(r.f64().unwrap(), 1.0);
    }

    #[test]
    fn bad_payloads_are_named() {
        assert_eq!(Reader::new(&[0, 1]).unwrap_err(), CdrError::NoHeader(2));
        assert_eq!(Reader::new(&[0, 0, 0, 0]).unwrap_err(), CdrError::Encapsulation(0, 0));
        let mut r = Reader::new(&[0, 1, 0, 0, 1]).unwrap();
        assert!(matches!(r.i32(), Err(CdrError::Truncated { .. })));
        let mut r = Reader::new(&[0, 1, 0, 0, 2]).unwrap();
        assert_eq!(r.bool().unwrap_err(), CdrError::BadBool { at: 0, value: 2 });
        let mut r = Reader::new(&[0, 1, 0, 0, 200, 0, 0, 0, b'x']).unwrap();
        assert!(matches!(r.string(), Err(CdrError::BadLength { .. })));
        let mut r = Reader::new(&[0, 1, 0, 0, 3, 0, 0, 0, b'a', b'b', 0]).unwrap();
        assert_eq!(
            r.bounded_string(1).unwrap_err(),
            CdrError::OverBound {
                what: "string",
                at: 0,
                count: 2,
                bound: 1
            }
        );
        let mut r = Reader::new(&[0, 1, 0, 0, 2, 0, 0, 0, 7, 8]).unwrap();
        assert!(matches!(
            r.bounded_count(1),
            Err(CdrError::OverBound { count: 2, bound: 1, .. })
        ));
    }
}
