//! CPU load beside a run: busy threads that compete with the run's processes
//! for the cores (chaos soaks and latency benchmarks measure the deadlines
//! under it).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

/// Busy threads, one per core asked for, spinning until dropped.
#[derive(Debug)]
pub(crate) struct CpuLoad {
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

impl CpuLoad {
    /// Starts `threads` busy threads.
    pub(crate) fn start(threads: usize) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let threads = (0..threads)
            .map(|_| {
                let stop = Arc::clone(&stop);
                std::thread::spawn(move || {
                    let mut x = 0u64;
                    while !stop.load(Ordering::Relaxed) {
                        for _ in 0..10_000 {
                            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
                        }
                    }
                })
            })
            .collect();
        CpuLoad { stop, threads }
    }

    /// Threads spinning.
    pub(crate) fn threads(&self) -> usize {
        self.threads.len()
    }

    /// One busy thread per core of this machine.
    pub(crate) fn on_every_core() -> Self {
        Self::start(std::thread::available_parallelism().map_or(2, |n| n.get()))
    }
}

impl Drop for CpuLoad {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for thread in self.threads.drain(..) {
            let _ = thread.join();
        }
    }
}
