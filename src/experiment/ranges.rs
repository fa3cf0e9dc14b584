//! The valid range of every numeric experiment parameter.
//!
//! The same ranges are checked where a flag is parsed (the value parsers of
//! the command line's experiment flags, so every entry point refuses
//! `--alpha 5` before any work) and by
//! [`ExperimentSpec::validate`](crate::experiment::spec::ExperimentSpec::validate) (specs
//! read from files). Every message states the valid range.

use crate::learning::Schedule;

/// An interval of real numbers; NaN is never in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RealRange {
    /// Lower end (may be negative infinity: no bound).
    pub(crate) low: f64,
    /// Whether `low` itself is excluded.
    pub(crate) low_open: bool,
    /// Upper end (may be infinity: no bound, but infinity itself excluded).
    pub(crate) high: f64,
    /// Whether `high` itself is excluded.
    pub(crate) high_open: bool,
}

impl RealRange {
    /// `[low, high]`.
    pub(crate) const fn closed(low: f64, high: f64) -> Self {
        RealRange {
            low,
            low_open: false,
            high,
            high_open: false,
        }
    }

    /// `(low, high]`.
    pub const fn above(low: f64, high: f64) -> Self {
        RealRange {
            low,
            low_open: true,
            high,
            high_open: false,
        }
    }

    /// Whether `value` is in the range.
    pub fn contains(&self, value: f64) -> bool {
        let above_low = if self.low_open {
            value > self.low
        } else {
            value >= self.low
        };
        let below_high = if self.high_open || self.high.is_infinite() {
            value < self.high
        } else {
            value <= self.high
        };
        above_low && below_high
    }

    /// The range in words: "a number from 0 (excluded) to 1".
    pub fn describe(&self) -> String {
        let excluded = |open: bool| if open { " (excluded)" } else { "" };
        match (self.low.is_finite(), self.high.is_finite()) {
            (true, true) => format!(
                "a number from {}{} to {}{}",
                self.low,
                excluded(self.low_open),
                self.high,
                excluded(self.high_open)
            ),
            (true, false) if self.low_open => format!("a finite number above {}", self.low),
            (true, false) => format!("a finite number of at least {}", self.low),
            (false, true) => format!("a number up to {}{}", self.high, excluded(self.high_open)),
            (false, false) => "a finite number".to_string(),
        }
    }

    /// `value` if in range, else why not.
    pub fn check(&self, value: f64) -> Result<f64, String> {
        in_range(value, self.contains(value), || self.describe())
    }

    /// Parses `text` as a number in the range (for flags).
    pub fn parse(&self, text: &str) -> Result<f64, String> {
        self.check(read(text, "a number", || self.describe())?)
    }

    /// Checks both ends of a schedule (a ramp stays between them).
    pub fn check_schedule(&self, schedule: &Schedule) -> Result<(), String> {
        self.check(schedule.start)?;
        self.check(schedule.end)?;
        Ok(())
    }
}

/// `value` if `fits`, else why not: `range` gives the range in words.
fn in_range<T: std::fmt::Display>(value: T, fits: bool, range: impl FnOnce() -> String) -> Result<T, String> {
    if fits {
        Ok(value)
    } else {
        Err(format!("{value} is out of range: it must be {}", range()))
    }
}

/// `text` read as `noun` (what a `T` is in words), else why not: `range`
/// gives the range in words.
fn read<T: std::str::FromStr>(text: &str, noun: &str, range: impl FnOnce() -> String) -> Result<T, String> {
    text.trim()
        .parse::<T>()
        .map_err(|_| format!("'{text}' is not {noun}: it must be {}", range()))
}

/// An interval of whole numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CountRange {
    /// Smallest valid value.
    pub(crate) low: u64,
    /// Largest valid value.
    pub(crate) high: u64,
}

impl CountRange {
    /// `[low, high]`.
    pub const fn new(low: u64, high: u64) -> Self {
        CountRange { low, high }
    }

    /// The range in words: "a whole number from 1 to 256".
    pub fn describe(&self) -> String {
        if self.high == u64::MAX {
            format!("a whole number of at least {}", self.low)
        } else {
            format!("a whole number from {} to {}", self.low, self.high)
        }
    }

    /// `value` if in range, else why not.
    pub fn check(&self, value: u64) -> Result<u64, String> {
        in_range(value, (self.low..=self.high).contains(&value), || self.describe())
    }

    /// Parses `text` as a whole number in the range (for flags).
    pub fn parse(&self, text: &str) -> Result<u64, String> {
        self.check(read(text, "a whole number", || self.describe())?)
    }

    /// Parses into a `usize` (the range fits one on every supported platform).
    pub fn parse_usize(&self, text: &str) -> Result<usize, String> {
        let value = self.parse(text)?;
        usize::try_from(value).map_err(|_| format!("{value} is too large for this machine"))
    }

    /// Parses into a `u32` (the range must fit one).
    pub fn parse_u32(&self, text: &str) -> Result<u32, String> {
        let value = self.parse(text)?;
        u32::try_from(value).map_err(|_| format!("{value} is out of range: it must be {}", self.describe()))
    }
}

/// Discount per executor step.
pub const GAMMA: RealRange = RealRange::closed(0.0, 1.0);
/// Step sizes: TD's alpha, SoSMC's constant step, MCESP's smallest step.
pub const STEP: RealRange = RealRange::above(0.0, 1.0);
/// Eligibility trace decay.
pub const LAMBDA: RealRange = RealRange::closed(0.0, 1.0);
/// Exploration probability of epsilon-greedy choices.
pub const EPSILON: RealRange = RealRange::closed(0.0, 1.0);
/// Softmax temperature.
pub const TEMPERATURE: RealRange = RealRange::above(0.0, f64::INFINITY);
/// An epsilon or a temperature, before the algorithm says which (the spec's
/// validation then checks the one it is).
pub const EXPLORATION: RealRange = RealRange::closed(0.0, f64::INFINITY);
/// A return level (SoSMC's threshold rule).
pub(crate) const RETURN: RealRange = RealRange::closed(f64::NEG_INFINITY, f64::INFINITY);
/// Keepaway distances, in metres (the largest field is about 105 m long).
pub const DISTANCE: RealRange = RealRange::closed(0.0, 200.0);

/// Independent runs of an experiment.
pub const RUNS: CountRange = CountRange::new(1, 100_000);
/// Learning episodes per run.
pub const EPISODES: CountRange = CountRange::new(1, 1_000_000_000);
/// Episodes of an evaluation or of the final greedy evaluation (0: none, or
/// the domain's own, e.g. every start cell of Sutton's grid).
pub const EVAL_EPISODES: CountRange = CountRange::new(0, 1_000_000);
/// Any whole number: seeds, episode counts such as SoSMC's initial phase,
/// the interval between recordings of traced values (0: never).
pub const WHOLE: CountRange = CountRange::new(0, u64::MAX);
/// Actions after which a grid episode is cut.
pub const MAX_ACTIONS: CountRange = CountRange::new(1, u32::MAX as u64);
/// MCESP: episodes per explored pair.
pub const STAGE_LENGTH: CountRange = CountRange::new(1, u64::MAX);
/// SoSMC's threshold rule: exploiting episodes in the mean; `every:N` exploration.
pub(crate) const WINDOW: CountRange = CountRange::new(1, 1_000_000_000);
/// Worker threads.
pub const THREADS: CountRange = CountRange::new(1, 256);
/// Episodes recorded as game logs (each is a few hundred kilobytes).
pub const RECORD: CountRange = CountRange::new(0, 1000);

/// The learning episodes between evaluations of a run of `episodes` episodes:
/// at least one, at most the run (a longer interval would only evaluate the
/// initial policy).
pub fn eval_every(episodes: u64) -> CountRange {
    CountRange::new(1, episodes.max(1))
}

/// The value of unseen markings: a finite number, or negative infinity (no
/// estimate yet: the first return replaces it).
pub(crate) fn check_initial_value(value: f64) -> Result<f64, String> {
    if value.is_finite() || value == f64::NEG_INFINITY {
        Ok(value)
    } else {
        Err(format!("{value} is out of range: it must be a finite number or -inf"))
    }
}

/// Parses an initial value (`-inf` accepted).
pub fn parse_initial_value(text: &str) -> Result<f64, String> {
    let value = text
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("'{text}' is not a number: it must be a finite number or -inf"))?;
    check_initial_value(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_say_what_is_valid() {
        assert_eq!(STEP.parse("0.5"), Ok(0.5));
        assert_eq!(STEP.parse("1"), Ok(1.0));
        for bad in ["0", "5", "NaN", "-1", "inf"] {
            let e = STEP.parse(bad).unwrap_err();
            assert!(e.contains("from 0 (excluded) to 1"), "{bad}: {e}");
        }
        assert!(STEP.parse("x").unwrap_err().contains("not a number"));
        assert_eq!(TEMPERATURE.describe(), "a finite number above 0");
        assert!(TEMPERATURE.parse("inf").is_err() && TEMPERATURE.parse("0").is_err());
        assert_eq!(TEMPERATURE.parse("1e6"), Ok(1e6));
        assert!(RETURN.parse("NaN").is_err() && RETURN.parse("inf").is_err());
        assert_eq!(RETURN.describe(), "a finite number");
        assert_eq!(THREADS.describe(), "a whole number from 1 to 256");
        assert!(THREADS.parse("0").unwrap_err().contains("from 1 to 256"));
        assert!(THREADS.parse("-1").unwrap_err().contains("not a whole number"));
        assert_eq!(WHOLE.describe(), "a whole number of at least 0");
        assert_eq!(eval_every(100).check(100), Ok(100));
        assert!(eval_every(100).check(101).unwrap_err().contains("from 1 to 100"));
        assert_eq!(parse_initial_value("-inf"), Ok(f64::NEG_INFINITY));
        assert!(parse_initial_value("inf").is_err() && parse_initial_value("nan").is_err());
        assert!(MAX_ACTIONS.parse_u32("0").is_err());
        assert_eq!(MAX_ACTIONS.parse_u32("4294967295"), Ok(u32::MAX));
    }
}
