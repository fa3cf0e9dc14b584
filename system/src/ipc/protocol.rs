//! The protocol's own types: who the run's processes are ([`Role`](crate::ipc::protocol::Role)), what
//! their messages say once read ([`SnapshotMeta`](crate::ipc::protocol::SnapshotMeta), [`CommandReading`](crate::ipc::protocol::CommandReading),
//! [`EpisodeNews`](crate::ipc::protocol::EpisodeNews), [`AgentNews`](crate::ipc::protocol::AgentNews), [`Pulse`](crate::ipc::protocol::Pulse)) and the supervisor's orders
//! ([`Order`](crate::ipc::protocol::Order)). Their shared-memory layouts are the `shm_layouts` crate;
//! [`super::convert`](crate::ipc::convert) converts between the two, validating what it reads.

use serde::{Deserialize, Serialize};
use shm_layouts::SENDER_SIMULATOR;

use learnpnp::learning::EpisodeStart;
use learnpnp_keepaway::command::Command;
use shm_layouts::reject;

/// What a snapshot says besides the view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnapshotMeta {
    /// The episode's sequence number.
    pub episode: u64,
    /// The cycle's sequence number.
    pub cycle_seq: u64,
    /// Reward since the previous snapshot.
    pub reward: f64,
    /// How the episode is run.
    pub start: EpisodeStart,
}

/// A command as read from shared memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandReading {
    /// The episode it belongs to.
    pub episode: u64,
    /// The cycle it answers.
    pub cycle_seq: u64,
    /// The command.
    pub command: Command,
    /// The plan issued no command this cycle.
    pub idle: bool,
}

/// What happens to an episode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EpisodeNews {
    /// It begins, run as `start` says.
    Begin(EpisodeStart),
    /// It ended after `cycles` cycles, lasting `seconds`.
    End {
        /// Cycles played.
        cycles: u32,
        /// Its duration.
        seconds: f64,
    },
    /// It is discarded after `cycles` cycles.
    Abort {
        /// Cycles played.
        cycles: u32,
    },
}

/// An agent's report at an episode boundary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AgentNews {
    /// Connected and ready for an episode: the process with this id.
    Ready {
        /// The agent's process id.
        pid: u32,
    },
    /// Episode `episode` ended.
    Ended {
        /// The episode.
        episode: u64,
        /// It explored.
        exploratory: bool,
    },
}

/// The `sender` a bridge or a view would have: none of the run's messages
/// carries it (the bridge forwards the other processes' messages as they
/// are, the view sends none).
pub(crate) const SENDER_BRIDGE: u32 = 300;

/// Who a process of the run is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Role {
    /// The Keepaway simulator.
    Simulator,
    /// Keeper k's agent.
    Keeper(usize),
    /// A world in its own process.
    World,
    /// Agent a of a world.
    Agent(usize),
    /// The host's bridge to the run's other hosts (it sends no message of its own).
    Bridge,
    /// The run's view (it only reads).
    View,
}

impl Role {
    /// The header's sender of this role.
    pub fn sender(self) -> u32 {
        match self {
            Role::Simulator | Role::World => SENDER_SIMULATOR,
            Role::Keeper(k) | Role::Agent(k) => k as u32,
            Role::Bridge | Role::View => SENDER_BRIDGE,
        }
    }

    /// Whether this role hosts the run's episodes (the simulator or the world).
    pub fn is_host(self) -> bool {
        matches!(self, Role::Simulator | Role::World)
    }

    /// The learner's index of an agent role (`None` for a host).
    pub fn agent_index(self) -> Option<usize> {
        match self {
            Role::Keeper(k) | Role::Agent(k) => Some(k),
            Role::Simulator | Role::World | Role::Bridge | Role::View => None,
        }
    }
}

impl std::fmt::Display for Role {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Role::Simulator => write!(f, "simulator"),
            Role::Keeper(k) => write!(f, "keeper {}", k + 1),
            Role::World => write!(f, "world"),
            Role::Agent(a) => write!(f, "agent {}", a + 1),
            Role::Bridge => write!(f, "bridge"),
            Role::View => write!(f, "view"),
        }
    }
}

/// The processes a run has: Keepaway's simulator and three keepers, or a
/// world in its own process and its agents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Roster {
    /// The Keepaway simulator and its keepers.
    Keepaway,
    /// A world and `agents` agents.
    World {
        /// How many agents.
        agents: usize,
    },
}

impl Roster {
    /// The processes of a run of `domain`: a world's and its agents, or Keepaway's.
    pub(crate) fn of(domain: &learnpnp::experiment::spec::DomainSpec) -> Self {
        match domain {
            learnpnp::experiment::spec::DomainSpec::World { plans, .. } => Roster::World { agents: plans.len() },
            _ => Roster::Keepaway,
        }
    }

    /// How many agent processes.
    pub fn agents(self) -> usize {
        match self {
            Roster::Keepaway => shm_layouts::NUM_KEEPERS,
            Roster::World { agents } => agents,
        }
    }

    /// The host: the simulator or the world.
    pub fn host(self) -> Role {
        match self {
            Roster::Keepaway => Role::Simulator,
            Roster::World { .. } => Role::World,
        }
    }

    /// Agent `k`'s role.
    pub fn agent(self, k: usize) -> Role {
        match self {
            Roster::Keepaway => Role::Keeper(k),
            Roster::World { .. } => Role::Agent(k),
        }
    }

    /// Every role, the host first.
    pub(crate) fn roles(self) -> Vec<Role> {
        std::iter::once(self.host())
            .chain((0..self.agents()).map(|k| self.agent(k)))
            .collect()
    }

    /// The role of a header's sender, if it is one of the run's processes.
    pub(crate) fn role_of(self, sender: u32) -> Option<Role> {
        match sender {
            SENDER_SIMULATOR => Some(self.host()),
            k if (k as usize) < self.agents() => Some(self.agent(k as usize)),
            _ => None,
        }
    }
}

/// A process's state as its heartbeat says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProcessState {
    /// Loading.
    Starting,
    /// Connected, waiting.
    Ready,
    /// Playing.
    Running,
    /// Stopping.
    Stopping,
}

/// What a heartbeat reports (the counters are the process's totals so far).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pulse {
    /// Who sent it.
    pub(crate) role: Role,
    /// Its process id.
    pub pid: u32,
    /// Its state.
    pub state: ProcessState,
    /// Its heartbeat counter.
    pub(crate) sequence: u64,
    /// Simulator: learning episodes done. Agent: episodes ended.
    pub episodes: u64,
    /// Cycles played or acted on.
    pub cycles: u64,
    /// Messages it refused.
    pub rejected: Rejections,
    /// Simulator: commands that missed their cycle.
    pub missed_deadlines: u64,
    /// Simulator: episodes aborted.
    pub(crate) aborted_episodes: u64,
    /// Agent: checkpoints written.
    pub(crate) checkpoints: u64,
    /// Agent: checkpoint writes that failed.
    pub checkpoint_failures: u64,
    /// Simulator or world (real time): cycles whose work ran past their deadline.
    pub late_cycles: u64,
}

/// A supervisor's command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Order {
    /// End the run.
    Stop,
    /// Checkpoint now.
    Checkpoint,
    /// The simulator was restarted (to the agents): drop the episode in
    /// progress and say you are ready.
    SimulatorRestarted,
    /// Keeper `keeper` was lost (to the simulator); process `pid` replaces it.
    KeeperLost {
        /// The keeper.
        keeper: usize,
        /// Its replacement's process id.
        pid: u32,
    },
}

/// Why a message was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejection {
    /// Another protocol version.
    Version,
    /// Another run.
    Run,
    /// A sender that may not publish this message here.
    Sender,
    /// An id or tag out of range, or a number that is not finite.
    Content,
    /// A stale or future episode or cycle.
    Sequence,
}

impl Rejection {
    /// Its index in [`Rejections`] and in the heartbeat's counters.
    pub fn index(self) -> usize {
        match self {
            Rejection::Version => reject::VERSION,
            Rejection::Run => reject::RUN,
            Rejection::Sender => reject::SENDER,
            Rejection::Content => reject::CONTENT,
            Rejection::Sequence => reject::SEQUENCE,
        }
    }
}

/// Refused messages, counted by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rejections {
    /// Another protocol version.
    pub version: u64,
    /// Another run.
    pub run: u64,
    /// A sender not allowed on the service.
    pub sender: u64,
    /// Ids out of range, unknown tags, numbers that are not finite.
    pub(crate) content: u64,
    /// Out of sequence.
    pub(crate) sequence: u64,
}

impl Rejections {
    /// Counts one refusal.
    pub(crate) fn count(&mut self, why: Rejection) {
        let slot = match why {
            Rejection::Version => &mut self.version,
            Rejection::Run => &mut self.run,
            Rejection::Sender => &mut self.sender,
            Rejection::Content => &mut self.content,
            Rejection::Sequence => &mut self.sequence,
        };
        *slot += 1;
    }

    /// Adds `other`'s refusals to these.
    pub(crate) fn add(&mut self, other: &Rejections) {
        for (slot, more) in [
            (&mut self.version, other.version),
            (&mut self.run, other.run),
            (&mut self.sender, other.sender),
            (&mut self.content, other.content),
            (&mut self.sequence, other.sequence),
        ] {
            *slot += more;
        }
    }

    /// All refusals.
    pub fn total(&self) -> u64 {
        self.to_array().iter().sum()
    }

    /// As the heartbeat carries them (indexed by `shm_layouts::reject`).
    pub fn to_array(&self) -> [u64; reject::COUNT] {
        let mut a = [0; reject::COUNT];
        a[reject::VERSION] = self.version;
        a[reject::RUN] = self.run;
        a[reject::SENDER] = self.sender;
        a[reject::CONTENT] = self.content;
        a[reject::SEQUENCE] = self.sequence;
        a
    }

    /// From the heartbeat's array.
    pub(crate) fn from_array(a: [u64; reject::COUNT]) -> Self {
        Rejections {
            version: a[reject::VERSION],
            run: a[reject::RUN],
            sender: a[reject::SENDER],
            content: a[reject::CONTENT],
            sequence: a[reject::SEQUENCE],
        }
    }

    /// The sum, reason by reason.
    pub(crate) fn plus(&self, other: &Rejections) -> Rejections {
        let (a, b) = (self.to_array(), other.to_array());
        Rejections::from_array(std::array::from_fn(|i| a[i] + b[i]))
    }
}
