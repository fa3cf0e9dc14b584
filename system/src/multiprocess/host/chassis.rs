//! The chassis both host processes run on (the Keepaway simulator,
//! [`super::sim_process`](crate::multiprocess::host::simulator), and a world
//! written in Rust, [`super::world_host`](crate::multiprocess::host::world)),
//! as the agents run on theirs ([`super::agent_chassis`](crate::multiprocess::agent::chassis)):
//! the heartbeat, the supervisor's orders (stop, an agent lost and its
//! replacement), the agents' readiness, the lost-agent protocol and the last
//! heartbeat of shutdown. What a host steps, what its heartbeat counts and
//! the messages of its world are its own.
//!
//! The lost-agent protocol: the supervisor restarts a lost agent, then names
//! the replacement's process ([`Order::KeeperLost`]); from then on the
//! agent is lost (its episode is discarded) and awaited until that process
//! says it is ready. The replacement may say so before the order is read:
//! its readiness is kept, and the order then finds it ready.

use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use shm_layouts::{AgentReport, Control, Heartbeat};

use crate::ipc::convert::{Rejection, Rejections, read_agent_report, read_control};
use crate::ipc::protocol::{AgentNews, Order, ProcessState, Role};
use crate::ipc::services::{Ipc, IpcError, Pub, Sub, receive};
use crate::ipc::wait::{Idle, MAX_BLOCK, WaitStrategy};
use crate::multiprocess::Pacemaker;

/// What every host process carries: its heartbeat, the run's stop, and
/// each agent's readiness and loss.
#[derive(Debug)]
pub(crate) struct HostChassis {
    run_id: u64,
    /// Who it is to the supervisor.
    role: Role,
    /// How it waits for messages.
    wait: WaitStrategy,
    /// The heartbeat and what it says.
    pub(crate) pacemaker: Pacemaker,
    /// Agents whose (replacement) process has not said it is ready.
    awaiting: Vec<bool>,
    /// Agents lost since [`HostChassis::clear_lost`].
    lost: Vec<bool>,
    /// The process id each agent's replacement will have (none before its first loss).
    expected: Vec<Option<u32>>,
    /// The process id of each agent's last readiness report.
    ready: Vec<Option<u32>>,
    /// The supervisor said stop (or the host found the run gone).
    stop: bool,
}

/// How a wait for the agents' readiness ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Readiness {
    /// Every agent is ready.
    Ready,
    /// The run stops.
    Stopped,
    /// These agents (0-based) were not ready in time.
    TimedOut(Vec<usize>),
}

/// A host process as its chassis's wait for the agents sees it.
pub(crate) trait Host {
    /// Why its housekeeping fails.
    type Error;
    /// Its chassis.
    fn chassis(&self) -> &HostChassis;
    /// One round of a wait for the agents: the heartbeat, the supervisor's
    /// orders, the agents' reports, and what else the host does meanwhile.
    fn await_round(&mut self) -> Result<(), Self::Error>;
    /// What wakes it.
    fn wake(&self) -> &Listener<Ipc>;
    /// A failure of shared memory, as the host reports it.
    fn failure(e: IpcError) -> Self::Error;
}

impl HostChassis {
    /// The chassis of a host as `role` in run `run_id`, waiting with `wait`,
    /// for `agents` agents, none of them ready yet.
    pub(crate) fn new(role: Role, run_id: u64, wait: WaitStrategy, agents: usize) -> Self {
        HostChassis {
            run_id,
            role,
            wait,
            pacemaker: Pacemaker::new(role, run_id),
            awaiting: vec![true; agents],
            lost: vec![false; agents],
            expected: vec![None; agents],
            ready: vec![None; agents],
            stop: false,
        }
    }

    /// Sends a heartbeat if one is due, then reads the supervisor's orders;
    /// refused messages are counted in `refused`. Whether a heartbeat was sent.
    pub(crate) fn keep(
        &mut self,
        heartbeat: &Pub<Heartbeat>,
        control: &Sub<Control>,
        refused: &mut Rejections,
    ) -> Result<bool, IpcError> {
        let beats = self.pacemaker.pulse.sequence;
        self.pacemaker.tick(heartbeat)?;
        let beat = self.pacemaker.pulse.sequence != beats;
        let (me, run_id) = (self.role, self.run_id);
        while let Some(order) = receive(control, |m| read_control(m, me, run_id))? {
            match order {
                Ok(Some(Order::Stop)) => self.stop = true,
                Ok(Some(Order::KeeperLost { keeper, pid })) if keeper < self.agents() => self.lose(keeper, pid),
                Ok(Some(Order::KeeperLost { .. })) => refused.count(Rejection::Content),
                Ok(Some(Order::Checkpoint | Order::SimulatorRestarted) | None) => {}
                Err(why) => refused.count(why),
            }
        }
        Ok(beat)
    }

    /// Reads the agents' reports: a readiness report ends the wait for its
    /// agent (only the replacement the supervisor named does, once one is
    /// named); any other news goes to `news` (an error: refused). Refused
    /// messages are counted in `refused`.
    pub(crate) fn read_reports(
        &mut self,
        reports: &Sub<AgentReport>,
        refused: &mut Rejections,
        mut news: impl FnMut(usize, AgentNews) -> Result<(), Rejection>,
    ) -> Result<(), IpcError> {
        let (run_id, agents) = (self.run_id, self.agents());
        while let Some(report) = receive(reports, |m| read_agent_report(m, run_id, agents))? {
            match report {
                Ok((a, AgentNews::Ready { pid })) => self.on_ready(a, pid),
                Ok((a, other)) => {
                    if let Err(why) = news(a, other) {
                        refused.count(why);
                    }
                }
                Err(why) => refused.count(why),
            }
        }
        Ok(())
    }

    /// Agent `a` is lost; its replacement is process `pid`.
    fn lose(&mut self, a: usize, pid: u32) {
        self.lost[a] = true;
        self.expected[a] = Some(pid);
        // The replacement may have said it is ready before this was read.
        self.awaiting[a] = self.ready[a] != Some(pid);
    }

    /// Process `pid` says agent `a` is ready: the wait for `a` ends unless
    /// another process is its named replacement.
    fn on_ready(&mut self, a: usize, pid: u32) {
        self.ready[a] = Some(pid);
        if self.expected[a].is_none_or(|p| p == pid) {
            self.awaiting[a] = false;
        }
    }

    /// How many agents the host has.
    pub(crate) fn agents(&self) -> usize {
        self.awaiting.len()
    }

    /// How the host waits for messages.
    pub(crate) fn wait(&self) -> WaitStrategy {
        self.wait
    }

    /// Whether the run stops.
    pub(crate) fn stopped(&self) -> bool {
        self.stop
    }

    /// The run stops, as the host found (its parent gone).
    pub(crate) fn stop(&mut self) {
        self.stop = true;
    }

    /// Whether every agent is ready.
    pub(crate) fn all_ready(&self) -> bool {
        !self.awaiting.contains(&true)
    }

    /// Whether agent `a` was lost.
    pub(crate) fn lost(&self, a: usize) -> bool {
        self.lost[a]
    }

    /// Whether an agent was lost.
    pub(crate) fn any_lost(&self) -> bool {
        self.lost.contains(&true)
    }

    /// Whether agent `a` was lost and its replacement is ready (it will not
    /// report the end of the episode it was lost in).
    pub(crate) fn replaced(&self, a: usize) -> bool {
        self.lost[a] && !self.awaiting[a]
    }

    /// Forgets the losses (a new episode begins).
    pub(crate) fn clear_lost(&mut self) {
        self.lost.fill(false);
    }

    /// Says `state` from the next heartbeat on.
    pub(crate) fn set_state(&mut self, state: ProcessState) {
        self.pacemaker.pulse.state = state;
    }

    /// Shutdown: says it is stopping in a heartbeat now.
    pub(crate) fn shut_down(&mut self, heartbeat: &Pub<Heartbeat>) -> Result<(), IpcError> {
        self.set_state(ProcessState::Stopping);
        self.pacemaker.beat(heartbeat)
    }
}

/// Waits until every agent of `host` is ready, the run stops, or (with a
/// `timeout`) the time is up, a round of the host's housekeeping at a time.
pub(crate) fn wait_ready<H: Host>(host: &mut H, timeout: Option<Duration>) -> Result<Readiness, H::Error> {
    let started = Instant::now();
    let mut idle = Idle::new(host.chassis().wait());
    loop {
        host.await_round()?;
        let chassis = host.chassis();
        if chassis.stopped() {
            return Ok(Readiness::Stopped);
        }
        if chassis.all_ready() {
            return Ok(Readiness::Ready);
        }
        if timeout.is_some_and(|t| started.elapsed() > t) {
            let missing = (0..chassis.agents()).filter(|&a| chassis.awaiting[a]).collect();
            return Ok(Readiness::TimedOut(missing));
        }
        idle.pause(host.wake(), MAX_BLOCK).map_err(H::failure)?;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chassis() -> HostChassis {
        HostChassis::new(Role::World, 7, WaitStrategy::Yield, 2)
    }

    #[test]
    fn every_agent_is_awaited_until_it_says_it_is_ready() {
        let mut host = chassis();
        host.on_ready(0, 100);
        assert!(!host.all_ready());
        host.on_ready(1, 101);
        assert!(host.all_ready());
        assert!(!host.any_lost());
    }

    #[test]
    fn a_lost_agent_is_awaited_until_its_named_replacement_is_ready() {
        let mut host = chassis();
        host.on_ready(0, 100);
        host.on_ready(1, 101);
        host.lose(1, 200);
        assert!(host.lost(1) && host.any_lost() && !host.all_ready() && !host.replaced(1));
        // The lost process, or another, does not end the wait.
        host.on_ready(1, 101);
        host.on_ready(1, 300);
        assert!(!host.all_ready());
        host.on_ready(1, 200);
        assert!(host.all_ready() && host.replaced(1));
        host.clear_lost();
        assert!(!host.any_lost() && !host.lost(1));
    }

    #[test]
    fn a_replacement_ready_before_the_order_is_read_is_ready() {
        let mut host = chassis();
        host.on_ready(0, 100);
        host.on_ready(1, 101);
        host.lose(1, 200);
        host.on_ready(1, 200);
        host.clear_lost();
        // Lost again: its replacement says it is ready before the order comes.
        host.on_ready(1, 201);
        assert!(host.all_ready());
        host.lose(1, 201);
        assert!(host.all_ready() && host.replaced(1));
    }
}
