//! The iceoryx2 floor of a world run: the bare round trip of the snapshot
//! payload between the supervisor and agent 0 (which echoes each ping at
//! once), measured on the same machine in the same run as the world's round
//! trips. Lock-step: back to back before the world starts; real time: one
//! ping each cycle, side by side with the run. (A Keepaway run's simulator
//! measures its own floor.)

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use iceoryx2::node::Node;

use super::sim_process::{FLOOR, histogram_file};
use super::supervisor::SupervisorError;
use crate::ipc::services::{FloorPorts, Ipc, receive};
use crate::ipc::wait::WaitStrategy;
use crate::ipc::world::floor_ping;
use crate::latency::Latency;

/// How long the first echo may take: agent 0 loads its plan before it answers.
const FIRST_ECHO_TIMEOUT: Duration = Duration::from_secs(30);

/// How long a later echo may take before the measurement gives up.
const ECHO_TIMEOUT: Duration = Duration::from_secs(2);

/// The supervisor's side of the floor measurement.
pub struct FloorProbe {
    ports: FloorPorts,
    run_id: u64,
    histogram: Latency,
    work_dir: PathBuf,
    sequence: u64,
    last_ping: Option<Instant>,
    /// Real time: the world's cycle (one ping each).
    period: Duration,
}

impl FloorProbe {
    /// Opens the measurement's ports on `node` for a run whose agents wait
    /// with `wait`; the histogram goes to `work_dir`.
    pub fn open(
        node: &Node<Ipc>,
        wait: WaitStrategy,
        run_id: u64,
        work_dir: &Path,
        period: Duration,
    ) -> Result<Self, SupervisorError> {
        Ok(FloorProbe {
            ports: FloorPorts::open(node, wait)?,
            run_id,
            histogram: Latency::new(FLOOR),
            work_dir: work_dir.to_path_buf(),
            sequence: 0,
            last_ping: None,
            period,
        })
    }

    fn ping(&mut self) -> Result<(u64, Instant), SupervisorError> {
        self.sequence += 1;
        let sent = Instant::now();
        self.ports.ping.send(floor_ping(self.run_id, self.sequence))?;
        Ok((self.sequence, sent))
    }

    /// Whether the echo of ping `sequence` has come (older echoes are dropped).
    fn echoed(&self, sequence: u64) -> Result<bool, SupervisorError> {
        let run_id = self.run_id;
        while let Some(echo) = receive(&self.ports.pong, |m| (m.header.run_id == run_id).then_some(m.cycle))? {
            if echo == Some(sequence) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Lock-step: `round_trips` pings back to back, each waited for by
    /// yielding between polls; gives up (keeping what it measured) when an
    /// echo does not come.
    pub fn measure(&mut self, round_trips: usize) -> Result<(), SupervisorError> {
        if !self.first_echo()? {
            return self.save();
        }
        for _ in 0..round_trips {
            let (sequence, sent) = self.ping()?;
            while !self.echoed(sequence)? {
                if sent.elapsed() > ECHO_TIMEOUT {
                    return self.save();
                }
                std::thread::yield_now();
            }
            self.histogram.record(sent.elapsed());
        }
        self.save()
    }

    /// Waits for agent 0 to answer at all (it loads its plan first), pinging
    /// every few milliseconds: a ping sent before its subscriber exists is
    /// lost. Not recorded. False if it never answers.
    fn first_echo(&mut self) -> Result<bool, SupervisorError> {
        let started = Instant::now();
        while started.elapsed() < FIRST_ECHO_TIMEOUT {
            let (sequence, sent) = self.ping()?;
            while sent.elapsed() < Duration::from_millis(5) {
                if self.echoed(sequence)? {
                    return Ok(true);
                }
                std::thread::sleep(Duration::from_micros(200));
            }
        }
        Ok(false)
    }

    /// Real time: once a cycle, one ping, waited for (yielding) until its
    /// echo comes or a tenth of a cycle has passed; the supervisor's loop
    /// does nothing else meanwhile.
    pub fn sample(&mut self) -> Result<(), SupervisorError> {
        if self.last_ping.is_some_and(|t| t.elapsed() < self.period) {
            return Ok(());
        }
        self.last_ping = Some(Instant::now());
        let (sequence, sent) = self.ping()?;
        while sent.elapsed() < self.period / 10 {
            if self.echoed(sequence)? {
                self.histogram.record(sent.elapsed());
                return Ok(());
            }
            std::thread::yield_now();
        }
        Ok(())
    }

    /// Writes the histogram into the run's work directory.
    pub fn save(&self) -> Result<(), SupervisorError> {
        let path = histogram_file(&self.work_dir, self.histogram.name());
        let bytes = self.histogram.to_bytes()?;
        learnpnp::atomic_file::write_atomic(&path, &bytes).map_err(|source| SupervisorError::Io { path, source })
    }
}
