//! Host B's reports that one of its agents was lost (`KEEPER_LOST`, naming
//! the agent and its replacement's process id), weighed by host A's bridge
//! against what it has seen of host B's agents itself ([`RemoteAgents`](crate::agents_lost::RemoteAgents)):
//! their heartbeats and their readiness reports, which all pass through it.
//!
//! A report is passed on to the simulator or world (which then aborts the
//! episode and waits for the replacement) only when host A's own view
//! agrees: the replacement, a process that was not the agent in service,
//! reported ready, or the agent in service has been silent for
//! [`SILENT_AFTER`](crate::agents_lost::SILENT_AFTER). A report naming the agent in service, or a process
//! that never reports ready while the agent in service keeps beating for
//! [`HOLD_AT_MOST`](crate::agents_lost::HOLD_AT_MOST), is refused (counted as a forbidden order). Every
//! report is listed in host A's link report with what became of it.

use std::collections::{BTreeMap, BTreeSet};
use std::time::{Duration, Instant};

use learnpnp_system::hosts::report::{AgentLost, MAX_LISTED};

/// An agent whose heartbeats stopped this long ago is gone (heartbeats come
/// every 100 ms).
pub(crate) const SILENT_AFTER: Duration = Duration::from_millis(600);

/// The longest a report waits for host A's view to agree before it is refused.
pub(crate) const HOLD_AT_MOST: Duration = Duration::from_secs(2);

/// What a message from host B shows of its agents.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Seen {
    /// Nothing about an agent.
    Nothing,
    /// Agent `agent` (0-based) beat, as process `pid`.
    Beat {
        /// The agent.
        agent: usize,
        /// Its process.
        pid: u32,
    },
    /// Agent `agent` reported ready, as process `pid`.
    Ready {
        /// The agent.
        agent: usize,
        /// Its process.
        pid: u32,
    },
}

/// What host A's bridge has seen of one remote agent.
#[derive(Debug, Default)]
struct AgentView {
    /// The process host A takes for the agent: the first seen, then each
    /// replacement passed on.
    in_service: Option<u32>,
    /// When each of its processes last beat.
    last_beat: BTreeMap<u32, Instant>,
    /// The processes that reported ready.
    ready: BTreeSet<u32>,
}

/// A report waiting for host A's view to agree.
#[derive(Debug, Clone, Copy)]
struct Held {
    agent: usize,
    pid: u32,
    since: Instant,
}

/// What became of a held report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Decision {
    /// Pass it on.
    Pass,
    /// Refuse it.
    Refuse,
}

/// Host B's agents as host A's bridge has seen them, and its reports of lost
/// agents waiting to be weighed.
#[derive(Debug, Default)]
pub(crate) struct RemoteAgents {
    agents: BTreeMap<usize, AgentView>,
    held: Vec<Held>,
    /// Every report and what became of it (the first [`MAX_LISTED`]).
    pub(crate) events: Vec<AgentLost>,
}

impl RemoteAgents {
    /// Takes in what a message from host B showed.
    pub(crate) fn see(&mut self, seen: Seen, now: Instant) {
        match seen {
            Seen::Nothing => {}
            Seen::Beat { agent, pid } => {
                let view = self.agents.entry(agent).or_default();
                view.in_service.get_or_insert(pid);
                view.last_beat.insert(pid, now);
            }
            Seen::Ready { agent, pid } => {
                let view = self.agents.entry(agent).or_default();
                view.in_service.get_or_insert(pid);
                view.ready.insert(pid);
            }
        }
    }

    /// Holds host B's report that `agent` was lost, replaced by process `pid`.
    pub(crate) fn hold(&mut self, agent: usize, pid: u32, now: Instant) {
        self.held.push(Held { agent, pid, since: now });
    }

    /// Whether reports are waiting.
    pub(crate) fn holding(&self) -> bool {
        !self.held.is_empty()
    }

    /// Weighs the held reports: those decided, in the order they came, with
    /// the agent and process they name; the others stay held.
    pub(crate) fn decide(&mut self, now: Instant) -> Vec<(usize, u32, Decision)> {
        let mut decided = Vec::new();
        let mut still = Vec::new();
        for held in std::mem::take(&mut self.held) {
            match self.verdict(&held, now) {
                Some((decision, why)) => {
                    if decision == Decision::Pass {
                        self.agents.entry(held.agent).or_default().in_service = Some(held.pid);
                    }
                    if self.events.len() < MAX_LISTED {
                        self.events.push(AgentLost {
                            agent: held.agent + 1,
                            pid: held.pid,
                            accepted: decision == Decision::Pass,
                            why,
                        });
                    }
                    decided.push((held.agent, held.pid, decision));
                }
                None => still.push(held),
            }
        }
        self.held = still;
        decided
    }

    /// What to do with `held` now, and why; `None` to wait.
    fn verdict(&self, held: &Held, now: Instant) -> Option<(Decision, String)> {
        let empty = AgentView::default();
        let view = self.agents.get(&held.agent).unwrap_or(&empty);
        let name = held.agent + 1;
        if view.in_service == Some(held.pid) {
            return Some((
                Decision::Refuse,
                format!("process {} is agent {name}'s in service, not a replacement", held.pid),
            ));
        }
        if view.ready.contains(&held.pid) {
            return Some((Decision::Pass, format!("its replacement {} reported ready", held.pid)));
        }
        let silent = match view.in_service.and_then(|pid| view.last_beat.get(&pid)) {
            Some(beat) => now.saturating_duration_since(*beat),
            None => Duration::MAX,
        };
        if silent >= SILENT_AFTER {
            let since = if silent == Duration::MAX {
                "never heard".to_string()
            } else {
                format!("silent for {} ms", silent.as_millis())
            };
            let old = view
                .in_service
                .map_or_else(|| "its process".to_string(), |p| format!("process {p}"));
            return Some((Decision::Pass, format!("agent {name}'s {old} was {since}")));
        }
        if now.saturating_duration_since(held.since) >= HOLD_AT_MOST {
            return Some((
                Decision::Refuse,
                format!(
                    "agent {name}'s process {} still beats and {} never reported ready within {} s",
                    view.in_service.unwrap_or_default(),
                    held.pid,
                    HOLD_AT_MOST.as_secs()
                ),
            ));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(t: Instant, n: u64) -> Instant {
        t + Duration::from_millis(n)
    }

    #[test]
    fn a_report_naming_the_live_agent_is_refused_at_once() {
        let t = Instant::now();
        let mut agents = RemoteAgents::default();
        agents.see(Seen::Ready { agent: 2, pid: 100 }, t);
        agents.see(Seen::Beat { agent: 2, pid: 100 }, t);
        agents.hold(2, 100, ms(t, 10));
        assert_eq!(agents.decide(ms(t, 10)), vec![(2, 100, Decision::Refuse)]);
        assert!(!agents.events[0].accepted);
    }

    #[test]
    fn a_made_up_replacement_is_refused_while_the_agent_beats() {
        let t = Instant::now();
        let mut agents = RemoteAgents::default();
        agents.see(Seen::Beat { agent: 2, pid: 100 }, t);
        agents.hold(2, 777, t);
        for step in 1..20 {
            agents.see(Seen::Beat { agent: 2, pid: 100 }, ms(t, step * 100));
            assert!(agents.decide(ms(t, step * 100)).is_empty(), "step {step}");
        }
        agents.see(Seen::Beat { agent: 2, pid: 100 }, ms(t, 2000));
        assert_eq!(agents.decide(ms(t, 2000)), vec![(2, 777, Decision::Refuse)]);
    }

    #[test]
    fn a_real_replacement_passes_once_it_is_ready_or_the_agent_is_silent() {
        let t = Instant::now();
        let mut agents = RemoteAgents::default();
        agents.see(Seen::Beat { agent: 2, pid: 100 }, t);
        agents.hold(2, 200, ms(t, 50));
        assert!(agents.decide(ms(t, 60)).is_empty());
        agents.see(Seen::Ready { agent: 2, pid: 200 }, ms(t, 70));
        assert_eq!(agents.decide(ms(t, 70)), vec![(2, 200, Decision::Pass)]);
        // Replayed later, it names the agent now in service.
        agents.hold(2, 200, ms(t, 5000));
        assert_eq!(agents.decide(ms(t, 5000)), vec![(2, 200, Decision::Refuse)]);
        // The next loss: the agent in service (200) falls silent.
        agents.see(Seen::Beat { agent: 2, pid: 200 }, ms(t, 6000));
        agents.hold(2, 300, ms(t, 6100));
        assert!(agents.decide(ms(t, 6200)).is_empty());
        assert_eq!(agents.decide(ms(t, 6700)), vec![(2, 300, Decision::Pass)]);
    }
}
