//! Real time on the wall clock, for every process that keeps a cycle (the
//! simulator and a world in its own process): cycles on absolute deadlines,
//! and a sleep that keeps the heartbeat going.
//!
//! Cycle k of a [`Cadence`] ends at `t0 + (k + 1) × period`, whatever the
//! cycle's work took: the time a cycle spends stepping the world or waiting
//! for a robot's answer is taken from the cycle, not added to it, so the
//! rate is `1 / period` over a run. A cycle whose work ran past its deadline
//! is late: it is counted, and the next cycle ends on the next deadline of
//! the grid still ahead (the grid is kept; no cycle is squeezed in to catch
//! up).

use std::time::{Duration, Instant};

use crate::multiprocess::HEARTBEAT_EVERY;

/// The longest a [`sleep_until`] (or a world's wait for its robot) sleeps
/// between two calls of its housekeeping: half a heartbeat, so that a
/// heartbeat is never later than half its interval for a sleep.
pub(crate) const SLEEP_SLICE: Duration = Duration::from_millis(HEARTBEAT_EVERY.as_millis() as u64 / 2);

/// Cycles of `period` on absolute deadlines from a start.
#[derive(Debug, Clone)]
pub(crate) struct Cadence {
    period: Duration,
    start: Instant,
    /// The cycle under way (0 from the start).
    cycle: u64,
    /// Cycles ended.
    ended: u64,
    /// Cycles whose work ran past their deadline.
    late: u64,
    /// Whether the cycle under way is late.
    overran: bool,
}

impl Cadence {
    /// Cycles of `period` from now.
    pub(crate) fn new(period: Duration) -> Self {
        Cadence {
            period: period.max(Duration::from_nanos(1)),
            start: Instant::now(),
            cycle: 0,
            ended: 0,
            late: 0,
            overran: false,
        }
    }

    /// When cycle `k` ends: `start + (k + 1) × period`.
    fn end_of(&self, k: u64) -> Instant {
        let nanos = self.period.as_nanos().saturating_mul(u128::from(k) + 1);
        self.start + Duration::from_nanos(u64::try_from(nanos).unwrap_or(u64::MAX))
    }

    /// When the cycle under way ends.
    pub(crate) fn deadline(&self) -> Instant {
        self.end_of(self.cycle)
    }

    /// Called once the cycle's work is done (the world stepped and its
    /// snapshot published, before the commands are collected): the cycle
    /// is late if its deadline has passed.
    pub(crate) fn worked(&mut self) {
        self.overran |= Instant::now() > self.deadline();
    }

    /// Ends the cycle under way: the next one ends a period after its
    /// deadline or, if that too is past, on the next deadline of the grid
    /// ahead (the cycle was late: counted).
    pub(crate) fn next(&mut self) {
        self.cycle += 1;
        self.ended += 1;
        let now = Instant::now();
        if now >= self.deadline() {
            self.overran = true;
            let elapsed = now.duration_since(self.start).as_nanos() / self.period.as_nanos();
            self.cycle = u64::try_from(elapsed).unwrap_or(u64::MAX);
        }
        self.late += u64::from(std::mem::take(&mut self.overran));
    }

    /// Cycles ended.
    pub(crate) fn cycles(&self) -> u64 {
        self.ended
    }

    /// Cycles whose work ran past their deadline.
    pub(crate) fn late(&self) -> u64 {
        self.late
    }

    /// Seconds since the start.
    pub(crate) fn seconds(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// Sleeps until `deadline`, calling `housekeeping` (the heartbeat, the
/// supervisor's orders) before each slice of at most half a heartbeat
/// interval: a process asleep in its cycle is never silent.
pub(crate) fn sleep_until<E>(deadline: Instant, mut housekeeping: impl FnMut() -> Result<(), E>) -> Result<(), E> {
    loop {
        housekeeping()?;
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Ok(());
        }
        std::thread::sleep(left.min(SLEEP_SLICE));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deadlines_are_on_the_grid_and_a_late_cycle_is_counted_and_skips_to_the_grid() {
        let mut cadence = Cadence::new(Duration::from_millis(5));
        let t0 = cadence.start;
        assert_eq!(cadence.deadline(), t0 + Duration::from_millis(5));
        cadence.next();
        // Whether or not the test was slow, the deadline stays on the grid.
        let offset = cadence.deadline().duration_since(t0).as_nanos();
        assert_eq!(offset % 5_000_000, 0);
        let late = cadence.late();
        // The cycle's work runs past its deadline.
        std::thread::sleep(Duration::from_millis(12));
        cadence.worked();
        cadence.next();
        assert_eq!(
            cadence.late(),
            late + 1,
            "a cycle whose work overran its deadline is late, once"
        );
        assert!(cadence.deadline() > Instant::now(), "the next deadline is ahead");
        assert_eq!(cadence.deadline().duration_since(t0).as_nanos() % 5_000_000, 0);
        assert_eq!(cadence.cycles(), 2);
    }

    #[test]
    fn a_sleep_keeps_house_at_least_every_half_heartbeat() {
        let mut calls = 0;
        let deadline = Instant::now() + HEARTBEAT_EVERY * 2;
        sleep_until::<()>(deadline, || {
            calls += 1;
            Ok(())
        })
        .unwrap();
        assert!(Instant::now() >= deadline);
        // Before the first slice and after the last, at least.
        assert!(calls >= 2, "{calls}");
    }
}
