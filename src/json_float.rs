//! Serde for an `f64` that may be infinite (a pessimistic initial value of
//! negative infinity): JSON has no infinities and would write `null`, so
//! they are written as the strings `"inf"` and `"-inf"` and read back from
//! them (or from a plain number). Use as `#[serde(with = "crate::json_float")]`.

use serde::{Deserialize, Deserializer, Serializer};

/// Writes `value`: a number when finite, `"inf"`, `"-inf"` or `"NaN"` otherwise.
pub(crate) fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    if value.is_finite() {
        serializer.serialize_f64(*value)
    } else if value.is_nan() {
        serializer.serialize_str("NaN")
    } else if *value > 0.0 {
        serializer.serialize_str("inf")
    } else {
        serializer.serialize_str("-inf")
    }
}

/// Reads a number, or one of the strings [`serialize`] writes.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum NumberOrName {
        Number(f64),
        Name(String),
    }
    match NumberOrName::deserialize(deserializer)? {
        NumberOrName::Number(v) => Ok(v),
        NumberOrName::Name(name) => match name.as_str() {
            "inf" | "+inf" | "infinity" => Ok(f64::INFINITY),
            "-inf" | "-infinity" => Ok(f64::NEG_INFINITY),
            "NaN" | "nan" => Ok(f64::NAN),
            other => Err(serde::de::Error::custom(format!(
                "expected a number, \"inf\" or \"-inf\", found \"{other}\""
            ))),
        },
    }
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Holder {
        #[serde(with = "super")]
        value: f64,
    }

    #[test]
    fn infinities_round_trip_through_json() {
        for value in [f64::NEG_INFINITY, f64::INFINITY, 0.0, -4.5] {
            let json = serde_json::to_string(&Holder { value }).unwrap();
            assert_eq!(serde_json::from_str::<Holder>(&json).unwrap(), Holder { value });
        }
        assert_eq!(
            serde_json::to_string(&Holder {
                value: f64::NEG_INFINITY
            })
            .unwrap(),
            r#"{"value":"-inf"}"#
        );
        assert!(serde_json::from_str::<Holder>(r#"{"value":"lots"}"#).is_err());
        assert!(serde_json::from_str::<Holder>(r#"{"value":null}"#).is_err());
    }
}
