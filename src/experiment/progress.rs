//! How far a reproduction of several figures has come, and roughly how long
//! the rest will take: each domain family's seconds per episode (the grids
//! apart, every Keepaway experiment together: one simulator), measured on the
//! curves already run, times the episodes left. A family not run yet has no
//! rate, so the estimate is then a lower bound and says so.

use std::collections::HashMap;
use std::fmt;
use std::time::Duration;

use super::spec::{DomainSpec, ExperimentSpec};

/// The family whose measured rate estimates `spec`'s.
fn family(spec: &ExperimentSpec) -> &'static str {
    match spec.domain {
        DomainSpec::Keepaway { .. } => "keepaway",
        _ => spec.domain.name(),
    }
}

/// Episodes every run of `spec` plays: learning, evaluation and greedy ones.
pub(crate) fn episodes_of(spec: &ExperimentSpec) -> u64 {
    let p = &spec.protocol;
    let per_run = p.episodes + p.eval_points().len() as u64 * p.eval_episodes as u64 + p.greedy_episodes as u64;
    per_run * p.runs as u64 + spec.domain.replays() as u64
}

/// Seconds per episode, per domain family, measured so far.
#[derive(Debug, Clone, Default)]
pub struct Rates {
    measured: HashMap<&'static str, (f64, u64)>,
}

/// What is left: seconds, and the families not timed yet (then a lower bound).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Seconds left over the families with a rate.
    pub seconds: f64,
    /// Families still to run without a rate yet.
    pub(crate) untimed: Vec<&'static str>,
}

impl Rates {
    /// `spec` took `seconds`.
    pub fn record(&mut self, spec: &ExperimentSpec, seconds: f64) {
        let entry = self.measured.entry(family(spec)).or_insert((0.0, 0));
        entry.0 += seconds;
        entry.1 += episodes_of(spec);
    }

    /// The time `remaining` will take at the measured rates.
    pub fn estimate<'a>(&self, remaining: impl IntoIterator<Item = &'a ExperimentSpec>) -> Estimate {
        let mut seconds = 0.0;
        let mut untimed: Vec<&'static str> = Vec::new();
        for spec in remaining {
            let name = family(spec);
            match self.measured.get(name) {
                Some(&(s, n)) if n > 0 => seconds += s / n as f64 * episodes_of(spec) as f64,
                _ => {
                    if !untimed.contains(&name) {
                        untimed.push(name);
                    }
                }
            }
        }
        Estimate { seconds, untimed }
    }
}

/// A duration as `1h 02m`, `3m 05s` or `42s`.
pub fn clock(d: Duration) -> String {
    let s = d.as_secs();
    match (s / 3600, (s % 3600) / 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, min, sec) => format!("{min}m {sec:02}s"),
        (h, min, _) => format!("{h}h {min:02}m"),
    }
}

/// `about 3m 05s left`, or `at least 3m 05s left (keepaway-pass not timed yet)`.
impl fmt::Display for Estimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let left = clock(Duration::from_secs_f64(self.seconds.max(0.0)));
        if self.untimed.is_empty() {
            write!(f, "about {left} left")
        } else {
            write!(f, "at least {left} left ({} not timed yet)", self.untimed.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::presets;

    #[test]
    fn the_rest_is_estimated_from_the_rates_of_its_domains() {
        let curves: Vec<ExperimentSpec> = ["6.3", "7.3"]
            .iter()
            .flat_map(|id| presets::figure(id).expect("a preset").curves)
            .collect();
        let grid = &curves[0];
        assert_eq!(episodes_of(grid), 200 * (1000 + 51 * 20 + 100));
        let mut rates = Rates::default();
        let before = rates.estimate(&curves);
        assert_eq!(before.untimed, ["parr-russell", "keepaway"]);
        rates.record(grid, 10.0);
        let after = rates.estimate(&curves[1..]);
        // Three grid curves like the first one: 30 s; Keepaway still unknown.
        assert!((after.seconds - 30.0).abs() < 1e-9, "{after:?}");
        assert_eq!(after.to_string(), "at least 30s left (keepaway not timed yet)");
        rates.record(&curves[4], 100.0);
        // The next Keepaway curve (Soft-SoSMC) like the timed one: 100 s.
        assert_eq!(rates.estimate(&curves[5..6]).to_string(), "about 1m 40s left");
        assert_eq!(clock(Duration::from_secs(3725)), "1h 02m");
    }
}
