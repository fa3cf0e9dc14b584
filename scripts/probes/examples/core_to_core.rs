//! How fast a cache line travels between CPU 0 and CPU 1: two threads, one
//! pinned to each, hand a shared counter back and forth for a while.
//!
//! ```sh
//! cargo run --release -p learnpnp-probes --example core_to_core -- [MILLISECONDS]
//! ```
//!
//! Prints the round trips a second and the mean round trip over MILLISECONDS
//! (1000 by default). The main job's lock-step hands its cycle between
//! processes on both CPUs through shared memory, so its speed follows this
//! figure; on a virtual machine it changes when the host moves the virtual
//! CPUs (`scripts/measure-speed-placement.py` samples both together).
//! A measurement program: it prints numbers and checks nothing.

use learnpnp_probes::args;

use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Result, bail};

/// Pins the calling thread to `cpu`.
fn pin_to(cpu: usize) -> Result<()> {
    // SAFETY: `set` is a plain bit set, zeroed and filled by libc's own
    // helpers, and handed to the kernel with its size; pid 0 is this thread.
    let ok = unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_ZERO(&mut set);
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) == 0
    };
    if !ok {
        bail!("cannot pin a thread to CPU {cpu}: {}", std::io::Error::last_os_error());
    }
    Ok(())
}

/// Bounces `turn` with the thread on CPU 1 for `length`; returns the round trips.
fn bounce(turn: &AtomicU64, done: &AtomicBool, length: Duration) -> u64 {
    let start = Instant::now();
    let mut trips = 0u64;
    // This side writes odd numbers, the other answers with the next even one.
    while start.elapsed() < length {
        for _ in 0..1024 {
            let mine = 2 * trips + 1;
            turn.store(mine, Ordering::Release);
            while turn.load(Ordering::Acquire) != mine + 1 {
                std::hint::spin_loop();
            }
            trips += 1;
        }
    }
    done.store(true, Ordering::Release);
    trips
}

fn run() -> Result<()> {
    let millis = args::positive_count("MILLISECONDS", 1000, "core_to_core [MILLISECONDS]")?;
    if std::thread::available_parallelism().map_or(1, usize::from) < 2 {
        bail!("this machine has one CPU: there is no other core to measure against");
    }
    let turn = Arc::new(AtomicU64::new(0));
    let done = Arc::new(AtomicBool::new(false));
    let (pinned_tx, pinned_rx) = std::sync::mpsc::channel();
    let answerer = {
        let (turn, done) = (Arc::clone(&turn), Arc::clone(&done));
        std::thread::spawn(move || {
            let pinned = pin_to(1);
            let failed = pinned.is_err();
            let _ = pinned_tx.send(pinned);
            if failed {
                return;
            }
            while !done.load(Ordering::Acquire) {
                let now = turn.load(Ordering::Acquire);
                if now % 2 == 1 {
                    turn.store(now + 1, Ordering::Release);
                } else {
                    std::hint::spin_loop();
                }
            }
        })
    };
    let ready = pinned_rx
        .recv()
        .map_err(|_| anyhow::anyhow!("the thread on CPU 1 ended before it was pinned"))
        .and_then(|pinned| pinned)
        .and_then(|()| pin_to(0));
    if let Err(e) = ready {
        done.store(true, Ordering::Release);
        let _ = answerer.join();
        return Err(e);
    }
    let start = Instant::now();
    let trips = bounce(&turn, &done, Duration::from_millis(millis));
    let seconds = start.elapsed().as_secs_f64();
    if answerer.join().is_err() {
        bail!("the thread on CPU 1 panicked");
    }
    println!(
        "CPU 0 <-> CPU 1: {:.0} round trips/s, {:.0} ns a round trip ({millis} ms)",
        trips as f64 / seconds,
        seconds * 1e9 / trips as f64
    );
    Ok(())
}

fn main() -> ExitCode {
    args::exit_code(run())
}
