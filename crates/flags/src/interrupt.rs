//! Stopping long work on Ctrl-C or SIGTERM without losing what is done.
//!
//! [`Interrupt::install`](crate::interrupt::Interrupt::install) registers handlers for SIGINT and SIGTERM (Unix). The
//! first signal only sets a flag ([`Interrupt::flag`](crate::interrupt::Interrupt::flag)), which long loops check
//! (the experiment runner stops starting runs and abandons the ones in
//! progress), so the caller can write what was completed. A second signal
//! ends the process at once with the conventional status 128 + signal number,
//! for a user who does not want to wait; signals less than [`SECOND_SIGNAL_AFTER`](crate::interrupt::SECOND_SIGNAL_AFTER)
//! apart count as one, because `timeout` (and some service managers) send
//! the same signal to the process and then to its whole process group.

use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::Duration;

/// How long after the first signal another one counts as a second signal.
pub const SECOND_SIGNAL_AFTER: Duration = Duration::from_secs(1);

/// The flag that the first SIGINT or SIGTERM sets, and which signal it was.
#[derive(Debug, Clone)]
pub struct Interrupt {
    flag: Arc<AtomicBool>,
    signal: Arc<AtomicUsize>,
}

impl Interrupt {
    /// Installs the handlers (see the module documentation).
    pub fn install() -> io::Result<Interrupt> {
        let interrupt = Interrupt {
            flag: Arc::new(AtomicBool::new(false)),
            signal: Arc::new(AtomicUsize::new(0)),
        };
        #[cfg(unix)]
        {
            // Monotonic nanoseconds (plus one, so that 0 means "none yet") of the first signal.
            let first = Arc::new(AtomicU64::new(0));
            for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
                let (flag, which, first) = (interrupt.flag.clone(), interrupt.signal.clone(), first.clone());
                let handler = move || {
                    let now = monotonic_nanos().saturating_add(1);
                    match first.compare_exchange(0, now, Ordering::SeqCst, Ordering::SeqCst) {
                        Ok(_) => {
                            which.store(signal as usize, Ordering::SeqCst);
                            flag.store(true, Ordering::SeqCst);
                        }
                        Err(then) if now.saturating_sub(then) >= SECOND_SIGNAL_AFTER.as_nanos() as u64 => {
                            signal_hook::low_level::exit(128 + signal)
                        }
                        Err(_) => {}
                    }
                };
                // SAFETY: the handler only reads the monotonic clock
                // (clock_gettime is async-signal-safe), touches atomics and
                // calls `_exit`; it allocates nothing and takes no lock.
                unsafe { signal_hook::low_level::register(signal, handler)? };
            }
        }
        Ok(interrupt)
    }

    /// Set once a signal asked to stop.
    pub fn flag(&self) -> &AtomicBool {
        &self.flag
    }

    /// Whether a signal asked to stop.
    pub fn requested(&self) -> bool {
        self.flag.load(Ordering::SeqCst)
    }

    /// The exit status for the signal received: 128 + its number (130 for
    /// Ctrl-C, 143 for SIGTERM), or 130 if none was recorded.
    pub fn exit_status(&self) -> u8 {
        match self.signal.load(Ordering::SeqCst) {
            0 => 130,
            s => u8::try_from(128 + s).unwrap_or(130),
        }
    }
}

/// The monotonic clock in nanoseconds, read in an async-signal-safe way.
#[cfg(unix)]
fn monotonic_nanos() -> u64 {
    let mut now = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `now` is a valid timespec for clock_gettime to write.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut now) };
    (now.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(now.tv_nsec as u64)
}
