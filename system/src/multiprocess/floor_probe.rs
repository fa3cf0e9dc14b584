//! The iceoryx2 floor: the bare round trip of a run's snapshot payload,
//! answered at once with its command payload, measured on the same machine
//! in the same run as the real round trips.
//!
//! - A world run's: between the supervisor and agent 0. Lock-step: back to
//!   back before the world starts; real time: one ping each cycle, side by
//!   side with the run. (A Keepaway run's simulator measures its own floor
//!   with keeper 0.)
//! - A remote host's own (`learnpnp-supervisor remote`): between its
//!   supervisor and a `learnpnp-agent --floor-echo` process it starts, back
//!   to back before its agents start, on services the bridge never carries.
//!   Its histogram ([`REMOTE_HOST_FLOOR`](crate::multiprocess::floor_probe::REMOTE_HOST_FLOOR)) is shipped to host A with the
//!   agents' and shown in host A's report.

use std::fmt::Debug;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use iceoryx2::node::Node;
use iceoryx2::prelude::ZeroCopySend;
use shm_layouts::{KeeperCommand, KeeperSnapshot, WorldCommand, WorldSnapshot};

use super::host::simulator::{FLOOR, FLOOR_END, histogram_file};
use super::supervisor::config::SupervisorError;
use super::{ProcessError, RunContext};
use crate::ipc::protocol::Roster;
use crate::ipc::services::{FloorEchoPorts, FloorPorts, Ipc, IpcError, node, receive, send};
use crate::ipc::wait::{Idle, MAX_BLOCK, WaitStrategy};
use crate::latency::Latency;

/// The histogram of a remote host's own floor.
pub const REMOTE_HOST_FLOOR: &str = "floor-remote-host";

/// The payloads of a run's floor measurement: its snapshot (the ping) and
/// its command (the echo).
pub(crate) trait FloorPayload {
    /// The snapshot payload.
    type Ping: ZeroCopySend + Debug + 'static;
    /// The command payload.
    type Pong: ZeroCopySend + Debug + 'static;
    /// Ping `sequence` of run `run_id`.
    fn ping(run_id: u64, sequence: u64) -> Self::Ping;
    /// The sequence a ping carries, if it is run `run_id`'s.
    fn ping_sequence(ping: &Self::Ping, run_id: u64) -> Option<u64>;
    /// The echo of ping `sequence` of run `run_id`.
    fn pong(run_id: u64, sequence: u64) -> Self::Pong;
    /// The sequence an echo carries, if it is run `run_id`'s.
    fn pong_sequence(pong: &Self::Pong, run_id: u64) -> Option<u64>;
}

/// A Keepaway run's payloads.
pub(crate) struct KeepawayFloor;

impl FloorPayload for KeepawayFloor {
    type Ping = KeeperSnapshot;
    type Pong = KeeperCommand;
    fn ping(run_id: u64, sequence: u64) -> KeeperSnapshot {
        super::host::simulator::floor_ping(run_id, sequence)
    }
    fn ping_sequence(ping: &KeeperSnapshot, run_id: u64) -> Option<u64> {
        (ping.header.run_id == run_id).then_some(ping.cycle_seq)
    }
    fn pong(run_id: u64, sequence: u64) -> KeeperCommand {
        super::host::simulator::floor_pong(run_id, sequence)
    }
    fn pong_sequence(pong: &KeeperCommand, run_id: u64) -> Option<u64> {
        (pong.header.run_id == run_id).then_some(pong.cycle_seq)
    }
}

/// A world run's payloads.
pub(crate) struct WorldFloor;

impl FloorPayload for WorldFloor {
    type Ping = WorldSnapshot;
    type Pong = WorldCommand;
    fn ping(run_id: u64, sequence: u64) -> WorldSnapshot {
        crate::ipc::world::floor_ping(run_id, sequence)
    }
    fn ping_sequence(ping: &WorldSnapshot, run_id: u64) -> Option<u64> {
        (ping.header.run_id == run_id).then_some(ping.cycle)
    }
    fn pong(run_id: u64, sequence: u64) -> WorldCommand {
        crate::ipc::world::floor_pong(run_id, sequence)
    }
    fn pong_sequence(pong: &WorldCommand, run_id: u64) -> Option<u64> {
        (pong.header.run_id == run_id).then_some(pong.cycle)
    }
}

/// How long the first echo may take: agent 0 loads its plan before it answers.
const FIRST_ECHO_TIMEOUT: Duration = Duration::from_secs(30);

/// How long a later echo may take before the measurement gives up.
const ECHO_TIMEOUT: Duration = Duration::from_secs(2);

/// The pinging side of a floor measurement.
pub(crate) struct FloorProbe<F: FloorPayload> {
    ports: FloorPorts<F::Ping, F::Pong>,
    run_id: u64,
    histogram: Latency,
    work_dir: PathBuf,
    sequence: u64,
    last_ping: Option<Instant>,
    /// Real time: the world's cycle (one ping each).
    period: Duration,
}

impl FloorProbe<WorldFloor> {
    /// A world run's, with agent 0 (which waits with `wait`), on `node`;
    /// the histogram goes to `work_dir`.
    pub(crate) fn world(
        node: &Node<Ipc>,
        wait: WaitStrategy,
        run_id: u64,
        work_dir: &Path,
        period: Duration,
    ) -> Result<Self, SupervisorError> {
        Ok(FloorProbe {
            ports: FloorPorts::world(node, wait)?,
            run_id,
            histogram: Latency::new(FLOOR),
            work_dir: work_dir.to_path_buf(),
            sequence: 0,
            last_ping: None,
            period,
        })
    }
}

impl<F: FloorPayload> FloorProbe<F> {
    /// A remote host's own, with its echo process (which waits with `wait`),
    /// on `node`; the histogram ([`REMOTE_HOST_FLOOR`]) goes to `work_dir`.
    pub(crate) fn host(
        node: &Node<Ipc>,
        wait: WaitStrategy,
        run_id: u64,
        work_dir: &Path,
    ) -> Result<Self, SupervisorError> {
        Ok(FloorProbe {
            ports: FloorPorts::host(node, wait)?,
            run_id,
            histogram: Latency::new(REMOTE_HOST_FLOOR),
            work_dir: work_dir.to_path_buf(),
            sequence: 0,
            last_ping: None,
            period: Duration::ZERO,
        })
    }

    /// Tells the echoing process the measurement is over.
    pub(crate) fn end(&mut self) -> Result<(), SupervisorError> {
        self.ports.ping.send(F::ping(self.run_id, FLOOR_END))?;
        Ok(())
    }

    fn ping(&mut self) -> Result<(u64, Instant), SupervisorError> {
        self.sequence += 1;
        let sent = Instant::now();
        self.ports.ping.send(F::ping(self.run_id, self.sequence))?;
        Ok((self.sequence, sent))
    }

    /// Whether the echo of ping `sequence` has come (older echoes are dropped).
    fn echoed(&self, sequence: u64) -> Result<bool, SupervisorError> {
        let run_id = self.run_id;
        while let Some(echo) = receive(&self.ports.pong, |m| F::pong_sequence(m, run_id))? {
            if echo == Some(sequence) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Lock-step: `round_trips` pings back to back, each waited for by
    /// yielding between polls; gives up (keeping what it measured) when an
    /// echo does not come.
    pub(crate) fn measure(&mut self, round_trips: usize) -> Result<(), SupervisorError> {
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

    /// Waits for the echoing process to answer at all (agent 0 loads its plan first), pinging
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
    pub(crate) fn sample(&mut self) -> Result<(), SupervisorError> {
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
    pub(crate) fn save(&self) -> Result<(), SupervisorError> {
        let path = histogram_file(&self.work_dir, self.histogram.name());
        let bytes = self.histogram.to_bytes()?;
        atomic_file::write_atomic(&path, &bytes).map_err(|source| SupervisorError::Io { path, source })
    }
}

/// Echoes a remote host's floor pings until the end marker, or until the
/// supervisor falls silent (none within [`FIRST_ECHO_TIMEOUT`] of the start,
/// or [`ECHO_TIMEOUT`] after the last).
fn echo<F: FloorPayload>(node: &Node<Ipc>, context: &RunContext) -> Result<(), IpcError> {
    let ports = FloorEchoPorts::<F::Ping, F::Pong>::open(node)?;
    let run_id = context.run_id;
    let (started, mut last) = (Instant::now(), None::<Instant>);
    let mut idle = Idle::new(context.wait);
    loop {
        match receive(&ports.ping, |m| F::ping_sequence(m, run_id))? {
            Some(Some(FLOOR_END)) => return Ok(()),
            Some(Some(sequence)) => {
                send(&ports.pong, F::pong(run_id, sequence))?;
                last = Some(Instant::now());
                idle = Idle::new(context.wait);
            }
            // Another run's ping: not answered.
            Some(None) => {}
            None => {
                let silent = match last {
                    Some(t) => t.elapsed() > ECHO_TIMEOUT,
                    None => started.elapsed() > FIRST_ECHO_TIMEOUT,
                };
                if silent {
                    return Ok(());
                }
                idle.pause(&ports.wake, MAX_BLOCK)?;
            }
        }
    }
}

/// The floor echo process of a remote host (`learnpnp-agent --floor-echo`):
/// echoes its supervisor's pings with the run's payloads until told to stop.
pub fn run_echo(context: &RunContext) -> Result<(), ProcessError> {
    let spec = context.load_spec()?;
    let namespace = context.namespace()?;
    let node = node(&namespace, "floor-echo")?;
    match Roster::of(&spec.domain) {
        Roster::Keepaway => echo::<KeepawayFloor>(&node, context)?,
        Roster::World { .. } => echo::<WorldFloor>(&node, context)?,
    }
    Ok(())
}
