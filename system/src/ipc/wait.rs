//! How a process waits for a message that has not arrived yet.
//!
//! iceoryx2 subscribers have no blocking receive: a process polls, and between
//! polls it spins, yields its core, or blocks on an iceoryx2 event that the
//! sender notifies. On a machine with fewer cores than busy processes, pure
//! spinning starves the process being waited for, and a blocking wake-up costs
//! tens of microseconds; the figures that chose the default are in
//! docs/results/RESULTS.md (multi-process system).
//!
//! A blocking pause waits on the process's wake-up listener itself
//! (`Listener::timed_wait`), not on an iceoryx2 `WaitSet`: the process waits
//! on one event only, so the `WaitSet`'s extra epoll wait buys nothing
//! (measured in RESULTS.md, "Wait strategies").

use std::time::{Duration, Instant};

use iceoryx2::port::listener::{Listener, ListenerWaitError};
use serde::{Deserialize, Serialize};

use super::port::{Ipc, IpcError, fail};

/// A waiting process's behaviour between polls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WaitStrategy {
    /// Poll without pause: lowest latency while every process has a core of its own.
    Spin,
    /// Poll, yielding the core between polls.
    Yield,
    /// Block on the process's wake-up event until a sender notifies it.
    Block,
    /// Yield between polls for a while (`HYBRID_YIELD`), then block.
    Hybrid,
}

impl WaitStrategy {
    /// Whether senders must notify the receiver's wake-up event after sending.
    pub(crate) fn notifies(self) -> bool {
        matches!(self, WaitStrategy::Block | WaitStrategy::Hybrid)
    }
}

learnpnp::named::impl_named!(
    WaitStrategy,
    "wait strategy",
    [
        Spin => "spin",
        Yield => "yield",
        Block => "block",
        Hybrid => "hybrid",
    ]
);

/// How long [`WaitStrategy::Hybrid`] yields before it blocks: a little longer
/// than a lock-step cycle's round trip, so that a busy run never blocks and an
/// idle process soon stops taking turns on the cores.
pub(crate) const HYBRID_YIELD: Duration = Duration::from_micros(200);

/// The longest a blocked process sleeps before it looks again (for its
/// heartbeat, the supervisor's commands and deadlines).
pub const MAX_BLOCK: Duration = Duration::from_millis(20);

/// How much later than asked a blocking pause may return. iceoryx2's
/// listener times out through a socket receive timeout, which the kernel
/// counts in scheduler ticks (4 ms at the common HZ=250), so a timed wait can
/// overshoot by a tick or two. A wait that must end on time blocks only until
/// this long before its end ([`Idle::pause_until`]).
pub const TIMED_WAIT_SLACK: Duration = Duration::from_millis(10);

/// One wait: call [`Idle::pause`] each time a poll found nothing.
#[derive(Debug)]
pub struct Idle {
    strategy: WaitStrategy,
    since: Option<Instant>,
}

impl Idle {
    /// A wait that begins now.
    pub fn new(strategy: WaitStrategy) -> Self {
        Idle { strategy, since: None }
    }

    /// Pauses once between two polls; a blocking pause returns when `wake` is
    /// notified or after about `limit` (at most [`MAX_BLOCK`], and possibly
    /// [`TIMED_WAIT_SLACK`] late). A zero `limit` only yields: a zero socket
    /// timeout would mean no timeout at all.
    pub fn pause(&mut self, wake: &Listener<Ipc>, limit: Duration) -> Result<(), IpcError> {
        if limit.is_zero() {
            std::thread::yield_now();
            return Ok(());
        }
        let since = *self.since.get_or_insert_with(Instant::now);
        match self.strategy {
            WaitStrategy::Spin => std::hint::spin_loop(),
            WaitStrategy::Yield => std::thread::yield_now(),
            WaitStrategy::Hybrid if since.elapsed() < HYBRID_YIELD => std::thread::yield_now(),
            WaitStrategy::Block | WaitStrategy::Hybrid => match wake.timed_wait(|_| {}, limit.min(MAX_BLOCK)) {
                // A signal (SIGCONT after a stop, SIGTERM) ends the wait early:
                // the caller polls again and sees any stop it asked for.
                Ok(_) | Err(ListenerWaitError::InterruptSignal) => {}
                Err(e) => return Err(fail("waiting on the wake-up event")(e)),
            },
        }
        Ok(())
    }

    /// Pauses once, returning by `deadline`: a blocking pause blocks only
    /// while the deadline is more than [`TIMED_WAIT_SLACK`] away; in the last
    /// stretch it yields.
    pub fn pause_until(&mut self, wake: &Listener<Ipc>, deadline: Instant) -> Result<(), IpcError> {
        let left = deadline.saturating_duration_since(Instant::now());
        self.pause(wake, left.saturating_sub(TIMED_WAIT_SLACK))
    }
}
