//! Choosing among options by their values: greedy, epsilon-greedy, softmax.

use rand::RngExt;
use serde::{Deserialize, Serialize};

use crate::rng::SimRng;

/// A parameter that changes linearly from `start` to `end` over `over` units
/// (episodes or decisions, as its user says), then stays at `end`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// Value at 0.
    pub start: f64,
    /// Value from `over` on.
    pub end: f64,
    /// Length of the ramp (0: always `end`).
    pub(crate) over: u64,
}

impl Schedule {
    /// A constant.
    pub const fn constant(value: f64) -> Self {
        Schedule {
            start: value,
            end: value,
            over: 0,
        }
    }

    /// A linear ramp.
    pub(crate) const fn linear(start: f64, end: f64, over: u64) -> Self {
        Schedule { start, end, over }
    }

    /// The value after `t` units.
    #[inline]
    pub fn at(&self, t: u64) -> f64 {
        if t >= self.over {
            self.end
        } else {
            self.start + (self.end - self.start) * (t as f64 / self.over as f64)
        }
    }
}

/// How a choice is drawn from option values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Strategy {
    /// Always a best option (ties broken at random).
    Greedy,
    /// A uniformly random option with probability epsilon, else greedy.
    EpsilonGreedy(f64),
    /// Softmax (Boltzmann) with temperature tau, thesis eq. 1.8: an option
    /// with no estimate (negative infinity) has weight e^(-inf/tau) = 0.
    Softmax(f64),
    /// Softmax with temperature tau in which an option with no estimate
    /// weighs like the best estimated one: its upper bound is unknown, so it
    /// is as promising as anything seen (SoSMC's `--unestimated as-best`).
    SoftmaxUnestimatedAsBest(f64),
}

/// An exploration rule whose parameter follows a schedule (over decisions or episodes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Exploration {
    /// Always greedy (e.g. with optimistic initial values).
    Greedy,
    /// epsilon-greedy with a scheduled epsilon.
    EpsilonGreedy(Schedule),
    /// Softmax with a scheduled temperature.
    Softmax(Schedule),
}

impl Exploration {
    /// The strategy after `t` units of the schedule.
    pub fn at(&self, t: u64) -> Strategy {
        match self {
            Exploration::Greedy => Strategy::Greedy,
            Exploration::EpsilonGreedy(s) => Strategy::EpsilonGreedy(s.at(t)),
            Exploration::Softmax(s) => Strategy::Softmax(s.at(t)),
        }
    }

    /// The strategy after `t` units of the schedule, or greedy throughout for
    /// a learner told to exploit (`greedy`).
    pub(crate) fn unless_greedy(&self, greedy: bool, t: u64) -> Strategy {
        if greedy { Strategy::Greedy } else { self.at(t) }
    }
}

/// The indices of the best values (ties included).
pub(crate) fn best_indices(values: &[f64], out: &mut Vec<usize>) {
    out.clear();
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    out.extend(
        values
            .iter()
            .enumerate()
            .filter(|(_, v)| **v == max || (v.is_nan() && max.is_nan()))
            .map(|(i, _)| i),
    );
    if out.is_empty() {
        out.extend(0..values.len());
    }
}

/// A greedy index, ties broken uniformly at random.
pub(crate) fn greedy(values: &[f64], rng: &mut SimRng, scratch: &mut Vec<usize>) -> usize {
    best_indices(values, scratch);
    scratch[rng.random_range(0..scratch.len())]
}

/// Whether `index` is among the best values.
pub(crate) fn is_greedy(values: &[f64], index: usize) -> bool {
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    values[index] == max
}

/// Draws an index by `strategy`.
pub(crate) fn select(strategy: Strategy, values: &[f64], rng: &mut SimRng, scratch: &mut Vec<usize>) -> usize {
    match strategy {
        Strategy::Greedy => greedy(values, rng, scratch),
        Strategy::EpsilonGreedy(eps) => {
            if rng.random::<f64>() < eps {
                rng.random_range(0..values.len())
            } else {
                greedy(values, rng, scratch)
            }
        }
        Strategy::Softmax(tau) => softmax(values, tau, 0.0, rng, scratch),
        Strategy::SoftmaxUnestimatedAsBest(tau) => softmax(values, tau, 1.0, rng, scratch),
    }
}

/// A softmax draw; an option without an estimate (negative infinity) has
/// weight `unestimated` (relative to the best estimated option's 1). With no
/// estimate at all the draw is uniform; a temperature of zero is greedy.
fn softmax(values: &[f64], tau: f64, unestimated: f64, rng: &mut SimRng, scratch: &mut Vec<usize>) -> usize {
    let max = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !max.is_finite() {
        return rng.random_range(0..values.len());
    }
    if tau <= 0.0 {
        return greedy(values, rng, scratch);
    }
    let weight = |v: f64| {
        if v.is_finite() {
            ((v - max) / tau).exp()
        } else {
            unestimated
        }
    };
    let total: f64 = values.iter().map(|&v| weight(v)).sum();
    let mut draw = rng.random::<f64>() * total;
    for (i, &v) in values.iter().enumerate() {
        draw -= weight(v);
        if draw <= 0.0 {
            return i;
        }
    }
    greedy(values, rng, scratch)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::seeded;

    #[test]
    fn schedules_ramp_then_hold() {
        let s = Schedule::linear(0.2, 0.0, 100);
        assert_eq!(s.at(0), 0.2);
        assert!((s.at(50) - 0.1).abs() < 1e-12);
        assert_eq!(s.at(100), 0.0);
        assert_eq!(s.at(1000), 0.0);
        assert_eq!(Schedule::constant(3.0).at(7), 3.0);
    }

    #[test]
    fn greedy_breaks_ties_among_the_best() {
        let mut rng = seeded(1);
        let mut scratch = Vec::new();
        let mut seen = [0; 3];
        for _ in 0..200 {
            seen[greedy(&[1.0, 3.0, 3.0], &mut rng, &mut scratch)] += 1;
        }
        assert_eq!(seen[0], 0);
        assert!(seen[1] > 50 && seen[2] > 50);
        assert!(is_greedy(&[1.0, 3.0, 3.0], 2) && !is_greedy(&[1.0, 3.0, 3.0], 0));
    }

    #[test]
    fn softmax_prefers_higher_values_and_weighs_missing_estimates_as_asked() {
        let mut rng = seeded(2);
        let mut scratch = Vec::new();
        let n = 4000;
        let values = [0.0, 1.0, f64::NEG_INFINITY];
        let mut as_best = [0; 3];
        let mut eq_1_8 = [0; 3];
        for _ in 0..n {
            as_best[select(Strategy::SoftmaxUnestimatedAsBest(1.0), &values, &mut rng, &mut scratch)] += 1;
            eq_1_8[select(Strategy::Softmax(1.0), &values, &mut rng, &mut scratch)] += 1;
        }
        // As the best: weights 1/e, 1, 1: P(1) = P(2) = e / (1 + 2e) = 0.422.
        for i in [1, 2] {
            let p = as_best[i] as f64 / n as f64;
            assert!((p - 0.422).abs() < 0.03, "{i}: {p}");
        }
        // Eq. 1.8: weights 1/e, 1, 0: P(1) = e / (1 + e) = 0.731, never 2.
        assert_eq!(eq_1_8[2], 0);
        let p = eq_1_8[1] as f64 / n as f64;
        assert!((p - 0.731).abs() < 0.03, "{p}");
        // No estimate at all: uniform, either way.
        for strategy in [Strategy::Softmax(0.1), Strategy::SoftmaxUnestimatedAsBest(0.1)] {
            let mut uniform = [0; 2];
            for _ in 0..n {
                uniform[select(strategy, &[f64::NEG_INFINITY; 2], &mut rng, &mut scratch)] += 1;
            }
            assert!((uniform[0] as f64 / n as f64 - 0.5).abs() < 0.03);
        }
    }

    #[test]
    fn epsilon_greedy_explores_at_the_rate() {
        let mut rng = seeded(3);
        let mut scratch = Vec::new();
        let n = 4000;
        let off = (0..n)
            .filter(|_| select(Strategy::EpsilonGreedy(0.4), &[5.0, 0.0], &mut rng, &mut scratch) == 1)
            .count();
        // Off-greedy with probability eps / 2 = 0.2.
        let p = off as f64 / n as f64;
        assert!((p - 0.2).abs() < 0.03, "{p}");
    }
}
