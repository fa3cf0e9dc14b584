//! Stopping long work on Ctrl-C or SIGTERM without losing what is done.
//!
//! [`Interrupt::install`] registers handlers for SIGINT and SIGTERM (Unix). The
//! first signal only sets a flag ([`Interrupt::flag`]), which long loops check
//! (the experiment runner stops starting runs and abandons the ones in
//! progress), so the caller can write what was completed. A second signal
//! ends the process at once with the conventional status 128 + signal number,
//! for a user who does not want to wait.

use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

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
        for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            // Registered first, so it sees the flag as the previous signal left it.
            signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, interrupt.flag.clone())?;
            signal_hook::flag::register_usize(signal, interrupt.signal.clone(), signal as usize)?;
            signal_hook::flag::register(signal, interrupt.flag.clone())?;
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
