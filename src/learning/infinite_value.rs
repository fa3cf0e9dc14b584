//! Serde for a value that may be infinite, such as the pessimistic initial
//! value negative infinity ("no estimate yet").
//!
//! JSON has no infinity (serde_json would write `null` and then refuse to read
//! it back), so human-readable formats write a finite value as a number and an
//! infinite one as the string `"-inf"` or `"inf"`; they read either. Binary
//! formats (bincode) keep the plain number. NaN is refused on reading.
//! Use with `#[serde(with = "crate::learning::infinite_value")]`.

use serde::de::{self, Deserializer, Unexpected, Visitor};
use serde::ser::Serializer;

/// Writes `value` (see the module documentation).
pub fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    if !serializer.is_human_readable() || value.is_finite() || value.is_nan() {
        serializer.serialize_f64(*value)
    } else if *value > 0.0 {
        serializer.serialize_str("inf")
    } else {
        serializer.serialize_str("-inf")
    }
}

/// Reads a value written by [`serialize`].
pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    struct ValueVisitor;

    impl Visitor<'_> for ValueVisitor {
        type Value = f64;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a number, \"-inf\" or \"inf\"")
        }

        fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
            if v.is_nan() {
                Err(E::invalid_value(Unexpected::Float(v), &self))
            } else {
                Ok(v)
            }
        }

        fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
            Ok(v as f64)
        }

        fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
            Ok(v as f64)
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<f64, E> {
            match v {
                "-inf" => Ok(f64::NEG_INFINITY),
                "inf" | "+inf" => Ok(f64::INFINITY),
                _ => Err(E::invalid_value(Unexpected::Str(v), &self)),
            }
        }
    }

    if deserializer.is_human_readable() {
        deserializer.deserialize_any(ValueVisitor)
    } else {
        deserializer.deserialize_f64(ValueVisitor)
    }
}

#[cfg(test)]
mod tests {
    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Holder {
        #[serde(with = "super")]
        v: f64,
    }

    #[test]
    fn infinities_round_trip_through_json_and_bincode() {
        for v in [f64::NEG_INFINITY, f64::INFINITY, 0.1, -4.0, 1e300] {
            let json = serde_json::to_string(&Holder { v }).unwrap();
            assert_eq!(serde_json::from_str::<Holder>(&json).unwrap(), Holder { v }, "{json}");
            let bin = bincode::serde::encode_to_vec(Holder { v }, bincode::config::standard()).unwrap();
            let (back, _): (Holder, usize) =
                bincode::serde::decode_from_slice(&bin, bincode::config::standard()).unwrap();
            assert_eq!(back, Holder { v });
        }
        assert_eq!(
            serde_json::to_string(&Holder { v: f64::NEG_INFINITY }).unwrap(),
            r#"{"v":"-inf"}"#
        );
        assert!(serde_json::from_str::<Holder>(r#"{"v":"nan"}"#).is_err());
        assert!(serde_json::from_str::<Holder>(r#"{"v":null}"#).is_err());
        assert_eq!(serde_json::from_str::<Holder>(r#"{"v":3}"#).unwrap(), Holder { v: 3.0 });
    }
}
