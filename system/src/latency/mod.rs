//! Latency histograms of the multi-process system (HdrHistogram): recording,
//! merging, percentiles, the percentile-distribution text format (`.hgrm`),
//! the compact V2 serialisation, and a percentile plot ([`plot`](crate::latency::plot)).
//!
//! Values are recorded in nanoseconds with three significant digits and
//! reported in microseconds.

/// The percentile plot of latency histograms.
pub mod plot;

use std::fmt::Write as _;
use std::time::Duration;

use hdrhistogram::Histogram;
use hdrhistogram::serialization::{Deserializer, Serializer, V2Serializer};
use serde::{Deserialize, Serialize};

/// Longest latency a histogram holds (longer ones are recorded as this): an hour.
const HIGHEST_NS: u64 = 3_600_000_000_000;

/// Significant decimal digits of every histogram.
const SIGNIFICANT_DIGITS: u8 = 3;

/// Why a serialised histogram cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum LatencyError {
    /// The bytes are not a V2 histogram.
    #[error("histogram {name}: cannot decode: {detail}")]
    Decode {
        /// The histogram's name.
        name: String,
        /// The decoder's error.
        detail: String,
    },
    /// Serialising failed.
    #[error("histogram {name}: cannot encode: {detail}")]
    Encode {
        /// The histogram's name.
        name: String,
        /// The encoder's error.
        detail: String,
    },
    /// Histograms of different ranges cannot be merged.
    #[error("histogram {name}: cannot merge: {detail}")]
    Merge {
        /// The histogram's name.
        name: String,
        /// Why.
        detail: String,
    },
}

/// The percentiles a report quotes, in microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 90th percentile.
    pub(crate) p90: f64,
    /// 99th percentile.
    pub p99: f64,
    /// 99.9th percentile.
    pub p999: f64,
    /// The largest value.
    pub max: f64,
    /// The mean (what a rate of back-to-back round trips is the inverse of).
    pub mean: f64,
}

/// A named latency histogram.
#[derive(Debug, Clone)]
pub struct Latency {
    name: String,
    histogram: Histogram<u64>,
}

fn new_histogram() -> Histogram<u64> {
    Histogram::new_with_bounds(1, HIGHEST_NS, SIGNIFICANT_DIGITS).expect("constant bounds are valid")
}

impl Latency {
    /// An empty histogram called `name`.
    pub fn new(name: impl Into<String>) -> Self {
        Latency {
            name: name.into(),
            histogram: new_histogram(),
        }
    }

    /// Its name (also its file name).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Values recorded.
    pub fn count(&self) -> u64 {
        self.histogram.len()
    }

    /// Records one latency (beyond an hour: an hour; below a nanosecond: one).
    pub(crate) fn record(&mut self, latency: Duration) {
        let ns = u64::try_from(latency.as_nanos()).unwrap_or(u64::MAX);
        self.histogram.saturating_record(ns.clamp(1, HIGHEST_NS));
    }

    /// Adds every value of `other`.
    pub fn merge(&mut self, other: &Latency) -> Result<(), LatencyError> {
        self.histogram.add(&other.histogram).map_err(|e| LatencyError::Merge {
            name: self.name.clone(),
            detail: format!("{e:?}"),
        })
    }

    /// The value at `quantile` (0..=1), in microseconds.
    pub(crate) fn quantile_us(&self, quantile: f64) -> f64 {
        self.histogram.value_at_quantile(quantile) as f64 / 1000.0
    }

    /// p50, p90, p99, p99.9, max and mean in microseconds (zeros when empty).
    pub fn percentiles(&self) -> Percentiles {
        if self.histogram.is_empty() {
            return Percentiles::default();
        }
        Percentiles {
            p50: self.quantile_us(0.5),
            p90: self.quantile_us(0.9),
            p99: self.quantile_us(0.99),
            p999: self.quantile_us(0.999),
            max: self.histogram.max() as f64 / 1000.0,
            mean: self.histogram.mean() / 1000.0,
        }
    }

    /// The distribution as (quantile, microseconds) points, five per halving
    /// of the remaining tail: what percentile plots and `.hgrm` files list.
    pub(crate) fn distribution(&self) -> Vec<(f64, f64)> {
        self.histogram
            .iter_quantiles(5)
            .map(|v| (v.quantile_iterated_to(), v.value_iterated_to() as f64 / 1000.0))
            .collect()
    }

    /// HdrHistogram's percentile-distribution text (as its tools print and
    /// plot it), values in microseconds.
    pub fn to_hgrm(&self) -> String {
        let h = &self.histogram;
        let mut text = String::from("       Value     Percentile TotalCount 1/(1-Percentile)\n\n");
        let mut total = 0u64;
        for v in h.iter_quantiles(5) {
            total += v.count_since_last_iteration();
            let q = v.quantile_iterated_to();
            let value = v.value_iterated_to() as f64 / 1000.0;
            if q < 1.0 {
                let _ = writeln!(text, "{value:12.3} {q:2.12} {total:10} {:14.2}", 1.0 / (1.0 - q));
            } else {
                let _ = writeln!(text, "{value:12.3} {q:2.12} {total:10}");
            }
        }
        let (mean, stdev) = if h.is_empty() {
            (0.0, 0.0)
        } else {
            (h.mean() / 1000.0, h.stdev() / 1000.0)
        };
        let _ = writeln!(text, "#[Mean    = {mean:12.3}, StdDeviation   = {stdev:12.3}]");
        let _ = writeln!(
            text,
            "#[Max     = {:12.3}, Total count    = {:12}]",
            h.max() as f64 / 1000.0,
            h.len()
        );
        let sub_buckets = (2.0 * 10f64.powi(i32::from(SIGNIFICANT_DIGITS))).log2().ceil().exp2() as u64;
        let _ = writeln!(
            text,
            "#[Buckets = {:12}, SubBuckets     = {sub_buckets:12}]",
            h.buckets()
        );
        text
    }

    /// The compact V2 serialisation (HdrHistogram's own binary format).
    pub fn to_bytes(&self) -> Result<Vec<u8>, LatencyError> {
        let mut bytes = Vec::new();
        V2Serializer::new()
            .serialize(&self.histogram, &mut bytes)
            .map_err(|e| LatencyError::Encode {
                name: self.name.clone(),
                detail: e.to_string(),
            })?;
        Ok(bytes)
    }

    /// Reads a histogram serialised by [`Latency::to_bytes`].
    pub(crate) fn from_bytes(name: impl Into<String>, bytes: &[u8]) -> Result<Self, LatencyError> {
        let name = name.into();
        let decoded: Histogram<u64> =
            Deserializer::new()
                .deserialize(&mut &bytes[..])
                .map_err(|e| LatencyError::Decode {
                    name: name.clone(),
                    detail: format!("{e:?}"),
                })?;
        let mut histogram = new_histogram();
        histogram.add(&decoded).map_err(|e| LatencyError::Decode {
            name: name.clone(),
            detail: format!("{e:?}"),
        })?;
        Ok(Latency { name, histogram })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Latency {
        let mut l = Latency::new("roundtrip");
        for us in 1..=1000u64 {
            l.record(Duration::from_micros(us));
        }
        l
    }

    #[test]
    fn percentiles_in_microseconds() {
        let p = sample().percentiles();
        assert!((p.p50 - 500.0).abs() <= 1.0, "{p:?}");
        assert!((p.p99 - 990.0).abs() <= 1.0, "{p:?}");
        assert!((p.max - 1000.0).abs() <= 1.0, "{p:?}");
        assert_eq!(Latency::new("empty").percentiles(), Percentiles::default());
    }

    #[test]
    fn serialisation_round_trips() {
        let l = sample();
        let back = Latency::from_bytes("roundtrip", &l.to_bytes().unwrap()).unwrap();
        assert_eq!(back.count(), 1000);
        assert_eq!(back.percentiles(), l.percentiles());
        assert!(Latency::from_bytes("x", b"not a histogram").is_err());
    }

    #[test]
    fn merging_adds_counts() {
        let mut a = sample();
        a.merge(&sample()).unwrap();
        assert_eq!(a.count(), 2000);
    }

    #[test]
    fn hgrm_lists_the_distribution() {
        let text = sample().to_hgrm();
        assert!(text.starts_with("       Value     Percentile TotalCount 1/(1-Percentile)"));
        assert!(
            text.contains("#[Max     =     1000.447, Total count    =         1000]"),
            "{text}"
        );
        let last = text.lines().rfind(|l| !l.starts_with('#') && !l.is_empty()).unwrap();
        assert!(last.contains("1.000000000000       1000"), "{last}");
    }
}
