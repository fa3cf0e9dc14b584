//! Every type that crosses a process boundary in learnpnp's multi-process
//! system, as it lies in iceoryx2 shared memory.
//!
//! The simulator process, one agent process per keeper and the supervisor
//! exchange these messages zero-copy. Each type is `#[repr(C)]`, contains only
//! fixed-size plain data (integers, floats, arrays; enumerations as integer
//! tags, so that any bit pattern a foreign process writes is a valid value to
//! read and reject), carries a [`Header`] with [`PROTOCOL_VERSION`], and has a
//! stable `type_name` so that binaries built separately agree on it. The tests
//! pin every size, alignment and field offset.
//!
//! Nothing here validates: a message read from shared memory is untrusted
//! until learnpnp's `ipc::convert` has checked it (version, run, sender, ids
//! in range, finite numbers, known tags). The services, their limits and who
//! publishes and subscribes are documented in `shm_layouts/README.md` and
//! named by [`services`].

#![deny(missing_docs)]

use iceoryx2::prelude::ZeroCopySend;

/// The version of this protocol; a message with another version is rejected.
pub const PROTOCOL_VERSION: u32 = 2;

/// Keepers in Keepaway 3 vs 2 (one agent process each).
pub const NUM_KEEPERS: usize = 3;

/// Players on the field: the keepers (global indices `0..3`), then the two takers.
pub const NUM_PLAYERS: usize = 5;

/// The `sender` of the simulator's messages.
pub const SENDER_SIMULATOR: u32 = 100;

/// The `sender` of the supervisor's messages.
pub const SENDER_SUPERVISOR: u32 = 200;

/// Begins every message: who sent it, in which run, in which protocol version.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::Header")]
#[repr(C)]
pub struct Header {
    /// [`PROTOCOL_VERSION`] of the sender.
    pub version: u32,
    /// A keeper index (`0..NUM_KEEPERS`), [`SENDER_SIMULATOR`] or [`SENDER_SUPERVISOR`].
    pub sender: u32,
    /// The run this message belongs to (chosen by the supervisor at launch).
    pub run_id: u64,
}

impl Header {
    /// A header of this protocol version.
    pub const fn new(sender: u32, run_id: u64) -> Self {
        Header {
            version: PROTOCOL_VERSION,
            sender,
            run_id,
        }
    }
}

/// The ball as seen: global position and velocity (m, m/cycle).
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[type_name("learnpnp::BallLayout")]
#[repr(C)]
pub struct BallLayout {
    /// Position `[x, y]`.
    pub pos: [f64; 2],
    /// Velocity `[x, y]`.
    pub vel: [f64; 2],
}

/// A player as seen: global position, velocity and body direction (degrees).
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[type_name("learnpnp::PlayerLayout")]
#[repr(C)]
pub struct PlayerLayout {
    /// Position `[x, y]`.
    pub pos: [f64; 2],
    /// Velocity `[x, y]`.
    pub vel: [f64; 2],
    /// Body direction, degrees.
    pub body: f64,
}

/// Tags of an episode's mode ([`KeeperSnapshot::mode`], [`EpisodeEvent::mode`]).
pub mod mode {
    /// Values learn from the episode.
    pub const LEARN: u8 = 0;
    /// Values frozen, behaviour as while learning.
    pub const EVALUATE: u8 = 1;
    /// Values frozen, every choice greedy.
    pub const GREEDY: u8 = 2;
}

/// Tags of the forced-exploration flag of an episode.
pub mod forced {
    /// The learner decides by its own rule.
    pub const NONE: u8 = 0;
    /// The episode is forced exploratory.
    pub const EXPLORE: u8 = 1;
    /// The episode is forced not to explore.
    pub const EXPLOIT: u8 = 2;
}

/// One keeper's knowledge-base snapshot for one cycle: what it perceives and
/// the reward since its previous snapshot. Simulator to agent, on
/// [`services::snapshot`]; also the payload of the floor measurement's ping.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::KeeperSnapshot")]
#[repr(C)]
pub struct KeeperSnapshot {
    /// Sender [`SENDER_SIMULATOR`].
    pub header: Header,
    /// The episode this cycle belongs to: a sequence number over the run's
    /// episodes of every kind (aborted ones included), from 1.
    pub episode: u64,
    /// The cycle's sequence number over the run, from 1; the command answering
    /// this snapshot carries it back.
    pub cycle_seq: u64,
    /// Reward since the previous snapshot (seconds of possession).
    pub reward: f64,
    /// Cycles since the episode started (the view's cycle).
    pub cycle: u32,
    /// The viewer's global player index (a keeper: equal to the service's keeper).
    pub me: u32,
    /// The episode's mode: a [`mode`] tag.
    pub mode: u8,
    /// The episode's forced-exploration flag: a [`forced`] tag.
    pub forced_exploration: u8,
    /// Zero.
    pub reserved: [u8; 6],
    /// The ball.
    pub ball: BallLayout,
    /// Every player by global index (keepers, then takers); entry `me` is the viewer.
    pub players: [PlayerLayout; NUM_PLAYERS],
}

/// Tags of a command's kind ([`KeeperCommand::kind`]).
pub mod command {
    /// Do nothing this cycle.
    pub const NONE: u32 = 0;
    /// Kick: `arg0` power, `arg1` direction relative to the body (degrees).
    pub const KICK: u32 = 1;
    /// Dash: `arg0` power.
    pub const DASH: u32 = 2;
    /// Turn: `arg0` moment (degrees).
    pub const TURN: u32 = 3;
    /// [`super::KeeperCommand::flags`] bit: the plan acted in no way this cycle.
    pub const FLAG_IDLE: u32 = 1;
}

/// A keeper's body command for one cycle, answering one snapshot. Agent to
/// simulator, on [`services::command`]; also the floor measurement's pong.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::KeeperCommand")]
#[repr(C)]
pub struct KeeperCommand {
    /// Sender: the keeper index.
    pub header: Header,
    /// The snapshot's episode.
    pub episode: u64,
    /// The snapshot's cycle sequence number.
    pub cycle_seq: u64,
    /// A [`command`] tag.
    pub kind: u32,
    /// [`command::FLAG_IDLE`] or zero.
    pub flags: u32,
    /// First argument (power or moment).
    pub arg0: f64,
    /// Second argument (kick direction), zero otherwise.
    pub arg1: f64,
}

/// Tags of an [`EpisodeEvent`].
pub mod episode {
    /// An episode begins: learners are told its mode.
    pub const BEGIN: u32 = 1;
    /// The episode ended normally: learners update, then acknowledge.
    pub const END: u32 = 2;
    /// The episode is discarded (a keeper was lost): learners drop it.
    pub const ABORT: u32 = 3;
}

/// An episode begins, ends or is aborted. Simulator to every agent, on [`services::EPISODE`].
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::EpisodeEvent")]
#[repr(C)]
pub struct EpisodeEvent {
    /// Sender [`SENDER_SIMULATOR`].
    pub header: Header,
    /// The episode's sequence number.
    pub episode: u64,
    /// An [`episode`] tag.
    pub kind: u32,
    /// The episode's mode: a [`mode`] tag.
    pub mode: u8,
    /// The forced-exploration flag: a [`forced`] tag.
    pub forced_exploration: u8,
    /// Zero.
    pub reserved: [u8; 2],
    /// Cycles played (end and abort).
    pub cycles: u32,
    /// Zero.
    pub reserved2: u32,
    /// The episode's duration in seconds (end).
    pub seconds: f64,
}

/// Tags of an [`AgentReport`].
pub mod report {
    /// The agent is connected and ready for an episode (after a start or restart).
    pub const READY: u32 = 1;
    /// The agent has ended the episode (learned, checkpointed if due).
    pub const ENDED: u32 = 2;
}

/// An agent's answer at an episode boundary. Agent to simulator, on [`services::AGENT_REPORT`].
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::AgentReport")]
#[repr(C)]
pub struct AgentReport {
    /// Sender: the keeper index.
    pub header: Header,
    /// The episode ended ([`report::ENDED`]); 0 for [`report::READY`].
    pub episode: u64,
    /// A [`report`] tag.
    pub kind: u32,
    /// The agent's process id (which incarnation of the keeper is ready).
    pub pid: u32,
    /// 1 if the episode explored, else 0.
    pub exploratory: u8,
    /// Zero.
    pub reserved: [u8; 7],
}

/// Tags of a [`Heartbeat`]'s state.
pub mod state {
    /// Loading its plan and values.
    pub const STARTING: u32 = 1;
    /// Connected, waiting for the run to begin.
    pub const READY: u32 = 2;
    /// Playing episodes.
    pub const RUNNING: u32 = 3;
    /// Stopping (final checkpoint, writing its files).
    pub const STOPPING: u32 = 4;
}

/// Indices of [`Heartbeat::rejected`]: why messages from shared memory were refused.
pub mod reject {
    /// Another protocol version.
    pub const VERSION: usize = 0;
    /// Another run's id.
    pub const RUN: usize = 1;
    /// A sender that may not publish on this service (e.g. another keeper's command).
    pub const SENDER: usize = 2;
    /// An id or tag out of range, or a number that is not finite.
    pub const CONTENT: usize = 3;
    /// Out of sequence: a stale or future episode or cycle.
    pub const SEQUENCE: usize = 4;
    /// How many reasons there are.
    pub const COUNT: usize = 5;
}

/// A process is alive, and what it has done. Every simulator and agent process
/// to the supervisor, on [`services::HEARTBEAT`], about every 100 ms.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::Heartbeat")]
#[repr(C)]
pub struct Heartbeat {
    /// Sender: a keeper index or [`SENDER_SIMULATOR`].
    pub header: Header,
    /// The process id.
    pub pid: u32,
    /// A [`state`] tag.
    pub state: u32,
    /// Heartbeats sent by this process, from 1.
    pub sequence: u64,
    /// Simulator: learning episodes completed in the run. Agent: episodes ended.
    pub episodes: u64,
    /// Cycles played (simulator) or acted on (agent).
    pub cycles: u64,
    /// Messages refused, by [`reject`] reason.
    pub rejected: [u64; reject::COUNT],
    /// Simulator (real time): commands that missed their cycle.
    pub missed_deadlines: u64,
    /// Simulator: episodes aborted because a keeper was lost.
    pub aborted_episodes: u64,
    /// Agent: checkpoints written.
    pub checkpoints: u64,
    /// Agent: checkpoint writes that failed (the previous one kept).
    pub checkpoint_failures: u64,
    /// Simulator or world (real time): cycles whose work ran past their
    /// deadline (each counted, the next kept on the grid).
    pub late_cycles: u64,
}

/// Tags of a [`Control`] command.
pub mod control {
    /// Stop: the simulator ends the run; agents checkpoint and exit.
    pub const STOP: u32 = 1;
    /// Agents checkpoint their values now.
    pub const CHECKPOINT: u32 = 2;
    /// To the simulator: keeper `target` was lost; abort the episode and wait
    /// for its replacement (process [`super::Control::pid`]).
    pub const KEEPER_LOST: u32 = 3;
    /// To the agents: the simulator was restarted; drop the episode in
    /// progress and say you are ready again.
    pub const SIM_RESTARTED: u32 = 4;
    /// [`super::Control::target`] of a command for every process.
    pub const ALL: u32 = u32::MAX;
}

/// A command of the supervisor. Supervisor to every process, on [`services::CONTROL`].
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::Control")]
#[repr(C)]
pub struct Control {
    /// Sender [`SENDER_SUPERVISOR`].
    pub header: Header,
    /// A [`control`] tag.
    pub command: u32,
    /// A keeper index, [`SENDER_SIMULATOR`], or [`control::ALL`].
    pub target: u32,
    /// The supervisor's command counter, from 1.
    pub sequence: u64,
    /// [`control::KEEPER_LOST`]: the replacement's process id; zero otherwise.
    pub pid: u32,
    /// Zero.
    pub reserved: u32,
}

/// The most bytes of one encoded feed record (a [`FeedHeader`]'s payload): a
/// record that does not fit is dropped by its sender and counted.
pub const MAX_FEED_BYTES: usize = 64 * 1024;

/// The header of one record of an agent's live feed, on
/// [`services::feed`]: the payload is a byte slice holding one record of the
/// `learnpnp-feed` crate (`FeedEvent`) encoded as JSON, at most
/// [`MAX_FEED_BYTES`] long.
#[derive(Debug, Clone, Copy, PartialEq, Default, ZeroCopySend)]
#[type_name("learnpnp::FeedHeader")]
#[repr(C)]
pub struct FeedHeader {
    /// [`PROTOCOL_VERSION`] of the sender.
    pub version: u32,
    /// The agent (0-based) whose feed this is.
    pub sender: u32,
    /// The run this record belongs to.
    pub run_id: u64,
    /// Records this publisher has tried to send, from 1 (a gap is a record
    /// lost: dropped by the sender or overwritten before it was read).
    pub sequence: u64,
}

/// The most atoms a world has: [`WorldSnapshot::atoms`] is a bitset of this many bits.
pub const MAX_ATOMS: usize = 256;

/// The most numeric fluents a world has ([`WorldSnapshot::fluents`]).
pub const MAX_FLUENTS: usize = 16;

/// The most numeric arguments an action takes ([`WorldCommand::args`]).
pub const MAX_ARGS: usize = 4;

/// The most actions a world has (an action's index is below it).
pub const MAX_ACTIONS: usize = 256;

/// The most agents a world serves (agent indices `0..MAX_AGENTS`).
pub const MAX_AGENTS: usize = 16;

/// The bytes of a name in a [`WorldVocabulary`] (UTF-8, padded with zeros;
/// a name of exactly this length has no terminating zero).
pub const NAME_LEN: usize = 32;

/// Names carried by one [`WorldVocabulary`] message.
pub const NAMES_PER_PART: usize = 16;

/// The `sender` of a world's messages: a world takes the simulator's place.
pub const SENDER_WORLD: u32 = SENDER_SIMULATOR;

/// [`WorldCommand::action`] of a command that names no action: the plan has
/// ended, or the agent acknowledges the snapshot that ended an episode.
pub const NO_ACTION: u32 = u32::MAX;

/// Tags of [`WorldSnapshot::episode_status`].
pub mod episode_status {
    /// The episode goes on: the agent answers with its next action.
    pub const RUNNING: u8 = 0;
    /// The episode reached a terminal state (gymnasium's `terminated`).
    pub const TERMINATED: u8 = 1;
    /// The episode was cut short (gymnasium's `truncated`, a step limit).
    pub const TRUNCATED: u8 = 2;
    /// The episode is discarded (an agent was lost): agents forget it and
    /// say they are ready again.
    pub const ABORTED: u8 = 3;
}

/// Tags of [`WorldSnapshot::action_status`]: what became of the action the
/// agent's previous command started.
pub mod action_status {
    /// No action in progress (the first snapshot of an episode).
    pub const NONE: u8 = 0;
    /// It goes on (a durative action).
    pub const RUNNING: u8 = 1;
    /// It ended normally.
    pub const FINISHED: u8 = 2;
    /// It failed.
    pub const FAILED: u8 = 3;
}

/// One agent's knowledge-base snapshot of a world in its own process: what
/// holds, the fluents, the reward since the previous snapshot, the episode's
/// and the action's status. World to agent `agent`, on [`services::world_snapshot`].
/// Every snapshot is answered by one [`WorldCommand`] carrying its `cycle`.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::WorldSnapshot")]
#[repr(C)]
pub struct WorldSnapshot {
    /// Sender [`SENDER_WORLD`].
    pub header: Header,
    /// The episode, numbered from 1 by the world process (a restarted world
    /// numbers afresh).
    pub episode: u64,
    /// The snapshot's sequence number over the world process's life, from 1,
    /// increasing (the same for every agent in one step of the world).
    pub cycle: u64,
    /// `CLOCK_MONOTONIC` in nanoseconds when the world published it.
    pub sent_ns: u64,
    /// The cycle of this agent's last command the world took (0: none yet).
    pub answer_cycle: u64,
    /// `CLOCK_MONOTONIC` in nanoseconds when the world read that command.
    pub answer_received_ns: u64,
    /// Reward since the previous snapshot (finite).
    pub reward: f64,
    /// The agent this snapshot is for.
    pub agent: u32,
    /// Steps of the world since the episode began (0 in its first snapshot).
    pub step: u32,
    /// An [`episode_status`] tag.
    pub episode_status: u8,
    /// An [`action_status`] tag.
    pub action_status: u8,
    /// Zero.
    pub reserved: [u8; 6],
    /// The truth of the atoms: atom `i` holds if bit `i % 64` of word `i / 64`
    /// is set; bits beyond the vocabulary's atoms are zero.
    pub atoms: [u64; MAX_ATOMS / 64],
    /// The numeric fluents (finite); those beyond the vocabulary's are zero.
    pub fluents: [f64; MAX_FLUENTS],
}

/// An agent's answer to one [`WorldSnapshot`]: the action to run, by its
/// index in the world's vocabulary, and its arguments. Agent to world, on
/// [`services::world_command`].
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::WorldCommand")]
#[repr(C)]
pub struct WorldCommand {
    /// Sender: the agent's index.
    pub header: Header,
    /// The snapshot's episode.
    pub episode: u64,
    /// The snapshot's cycle.
    pub cycle: u64,
    /// Nanoseconds the agent took from reading the snapshot to sending this.
    pub compute_ns: u64,
    /// The action's index in the vocabulary's actions, or [`NO_ACTION`].
    pub action: u32,
    /// Zero.
    pub reserved: u32,
    /// The action's numeric arguments (finite; zero when unused).
    pub args: [f64; MAX_ARGS],
}

/// Part of a world's vocabulary: the names of its atoms, fluents and actions,
/// in that order, [`NAMES_PER_PART`] to a message. World to every agent, on
/// [`services::WORLD_VOCABULARY`], repeated while the world waits for its agents.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("learnpnp::WorldVocabulary")]
#[repr(C)]
pub struct WorldVocabulary {
    /// Sender [`SENDER_WORLD`].
    pub header: Header,
    /// The world's atoms (at most [`MAX_ATOMS`]).
    pub atoms: u32,
    /// Its fluents (at most [`MAX_FLUENTS`]).
    pub fluents: u32,
    /// Its actions (at most [`MAX_ACTIONS`]).
    pub actions: u32,
    /// The agents it serves (1 to [`MAX_AGENTS`]).
    pub agents: u32,
    /// This message's index, from 0.
    pub part: u32,
    /// How many messages the vocabulary takes.
    pub parts: u32,
    /// The index of this message's first name in the list atoms, fluents, actions.
    pub first: u32,
    /// Names in this message (at most [`NAMES_PER_PART`]).
    pub count: u32,
    /// The names, zero-padded; entries beyond `count` are zero.
    pub names: [[u8; NAME_LEN]; NAMES_PER_PART],
}

/// The names of the services, relative to the run's iceoryx2 prefix (which
/// isolates runs from each other).
pub mod services {
    /// Simulator to every agent: [`super::EpisodeEvent`].
    pub const EPISODE: &str = "learnpnp/episode";
    /// Every agent to the simulator: [`super::AgentReport`].
    pub const AGENT_REPORT: &str = "learnpnp/agent-report";
    /// Every process to the supervisor: [`super::Heartbeat`].
    pub const HEARTBEAT: &str = "learnpnp/heartbeat";
    /// Supervisor to every process: [`super::Control`].
    pub const CONTROL: &str = "learnpnp/control";
    /// Floor measurement, simulator to agent 0: [`super::KeeperSnapshot`].
    pub const FLOOR_PING: &str = "learnpnp/floor/ping";
    /// Floor measurement, agent 0 to simulator: [`super::KeeperCommand`].
    pub const FLOOR_PONG: &str = "learnpnp/floor/pong";

    /// Simulator to keeper `k`: [`super::KeeperSnapshot`].
    pub fn snapshot(k: usize) -> String {
        format!("learnpnp/keeper/{k}/snapshot")
    }

    /// Keeper `k` to the simulator: [`super::KeeperCommand`].
    pub fn command(k: usize) -> String {
        format!("learnpnp/keeper/{k}/command")
    }

    /// A world to every agent: [`super::WorldVocabulary`].
    pub const WORLD_VOCABULARY: &str = "learnpnp/world/vocabulary";
    /// Floor measurement of a world run, supervisor to agent 0: [`super::WorldSnapshot`].
    pub const WORLD_FLOOR_PING: &str = "learnpnp/world/floor/ping";
    /// Floor measurement of a world run, agent 0 to supervisor: [`super::WorldCommand`].
    pub const WORLD_FLOOR_PONG: &str = "learnpnp/world/floor/pong";

    /// A remote host's own floor, its supervisor to its echo process: the
    /// run's snapshot payload ([`super::KeeperSnapshot`] or
    /// [`super::WorldSnapshot`]). Never carried between hosts.
    pub const HOST_FLOOR_PING: &str = "learnpnp/host/floor/ping";
    /// A remote host's own floor, the echo process to its supervisor: the
    /// run's command payload ([`super::KeeperCommand`] or [`super::WorldCommand`]).
    pub const HOST_FLOOR_PONG: &str = "learnpnp/host/floor/pong";

    /// A world to agent `a`: [`super::WorldSnapshot`].
    pub fn world_snapshot(a: usize) -> String {
        format!("learnpnp/world/agent/{a}/snapshot")
    }

    /// Agent `a` to its world: [`super::WorldCommand`].
    pub fn world_command(a: usize) -> String {
        format!("learnpnp/world/agent/{a}/command")
    }

    /// Agent `a`'s live feed to the view process: a byte slice with a
    /// [`super::FeedHeader`] (only in a run that has a view).
    pub fn feed(a: usize) -> String {
        format!("learnpnp/feed/agent/{a}")
    }

    /// The event service that wakes a blocked process (`sim`, `keeper-0`,
    /// `world`, `agent-0`, ...).
    pub fn wake(process: &str) -> String {
        format!("learnpnp/wake/{process}")
    }
}

#[cfg(test)]
mod tests {
    use core::mem::{align_of, offset_of, size_of};

    use super::*;

    #[test]
    fn header_layout() {
        assert_eq!((size_of::<Header>(), align_of::<Header>()), (16, 8));
        assert_eq!(offset_of!(Header, version), 0);
        assert_eq!(offset_of!(Header, sender), 4);
        assert_eq!(offset_of!(Header, run_id), 8);
    }

    #[test]
    fn seen_object_layouts() {
        assert_eq!((size_of::<BallLayout>(), align_of::<BallLayout>()), (32, 8));
        assert_eq!(offset_of!(BallLayout, pos), 0);
        assert_eq!(offset_of!(BallLayout, vel), 16);
        assert_eq!((size_of::<PlayerLayout>(), align_of::<PlayerLayout>()), (40, 8));
        assert_eq!(offset_of!(PlayerLayout, pos), 0);
        assert_eq!(offset_of!(PlayerLayout, vel), 16);
        assert_eq!(offset_of!(PlayerLayout, body), 32);
    }

    #[test]
    fn snapshot_layout() {
        assert_eq!((size_of::<KeeperSnapshot>(), align_of::<KeeperSnapshot>()), (288, 8));
        assert_eq!(offset_of!(KeeperSnapshot, header), 0);
        assert_eq!(offset_of!(KeeperSnapshot, episode), 16);
        assert_eq!(offset_of!(KeeperSnapshot, cycle_seq), 24);
        assert_eq!(offset_of!(KeeperSnapshot, reward), 32);
        assert_eq!(offset_of!(KeeperSnapshot, cycle), 40);
        assert_eq!(offset_of!(KeeperSnapshot, me), 44);
        assert_eq!(offset_of!(KeeperSnapshot, mode), 48);
        assert_eq!(offset_of!(KeeperSnapshot, forced_exploration), 49);
        assert_eq!(offset_of!(KeeperSnapshot, reserved), 50);
        assert_eq!(offset_of!(KeeperSnapshot, ball), 56);
        assert_eq!(offset_of!(KeeperSnapshot, players), 88);
    }

    #[test]
    fn command_layout() {
        assert_eq!((size_of::<KeeperCommand>(), align_of::<KeeperCommand>()), (56, 8));
        assert_eq!(offset_of!(KeeperCommand, header), 0);
        assert_eq!(offset_of!(KeeperCommand, episode), 16);
        assert_eq!(offset_of!(KeeperCommand, cycle_seq), 24);
        assert_eq!(offset_of!(KeeperCommand, kind), 32);
        assert_eq!(offset_of!(KeeperCommand, flags), 36);
        assert_eq!(offset_of!(KeeperCommand, arg0), 40);
        assert_eq!(offset_of!(KeeperCommand, arg1), 48);
    }

    #[test]
    fn episode_event_layout() {
        assert_eq!((size_of::<EpisodeEvent>(), align_of::<EpisodeEvent>()), (48, 8));
        assert_eq!(offset_of!(EpisodeEvent, episode), 16);
        assert_eq!(offset_of!(EpisodeEvent, kind), 24);
        assert_eq!(offset_of!(EpisodeEvent, mode), 28);
        assert_eq!(offset_of!(EpisodeEvent, forced_exploration), 29);
        assert_eq!(offset_of!(EpisodeEvent, reserved), 30);
        assert_eq!(offset_of!(EpisodeEvent, cycles), 32);
        assert_eq!(offset_of!(EpisodeEvent, reserved2), 36);
        assert_eq!(offset_of!(EpisodeEvent, seconds), 40);
    }

    #[test]
    fn agent_report_layout() {
        assert_eq!((size_of::<AgentReport>(), align_of::<AgentReport>()), (40, 8));
        assert_eq!(offset_of!(AgentReport, episode), 16);
        assert_eq!(offset_of!(AgentReport, kind), 24);
        assert_eq!(offset_of!(AgentReport, pid), 28);
        assert_eq!(offset_of!(AgentReport, exploratory), 32);
        assert_eq!(offset_of!(AgentReport, reserved), 33);
    }

    #[test]
    fn heartbeat_layout() {
        assert_eq!((size_of::<Heartbeat>(), align_of::<Heartbeat>()), (128, 8));
        assert_eq!(offset_of!(Heartbeat, pid), 16);
        assert_eq!(offset_of!(Heartbeat, state), 20);
        assert_eq!(offset_of!(Heartbeat, sequence), 24);
        assert_eq!(offset_of!(Heartbeat, episodes), 32);
        assert_eq!(offset_of!(Heartbeat, cycles), 40);
        assert_eq!(offset_of!(Heartbeat, rejected), 48);
        assert_eq!(offset_of!(Heartbeat, missed_deadlines), 88);
        assert_eq!(offset_of!(Heartbeat, aborted_episodes), 96);
        assert_eq!(offset_of!(Heartbeat, checkpoints), 104);
        assert_eq!(offset_of!(Heartbeat, checkpoint_failures), 112);
        assert_eq!(offset_of!(Heartbeat, late_cycles), 120);
    }

    #[test]
    fn control_layout() {
        assert_eq!((size_of::<Control>(), align_of::<Control>()), (40, 8));
        assert_eq!(offset_of!(Control, command), 16);
        assert_eq!(offset_of!(Control, target), 20);
        assert_eq!(offset_of!(Control, sequence), 24);
        assert_eq!(offset_of!(Control, pid), 32);
        assert_eq!(offset_of!(Control, reserved), 36);
    }

    #[test]
    fn world_snapshot_layout() {
        assert_eq!((size_of::<WorldSnapshot>(), align_of::<WorldSnapshot>()), (240, 8));
        assert_eq!(offset_of!(WorldSnapshot, header), 0);
        assert_eq!(offset_of!(WorldSnapshot, episode), 16);
        assert_eq!(offset_of!(WorldSnapshot, cycle), 24);
        assert_eq!(offset_of!(WorldSnapshot, sent_ns), 32);
        assert_eq!(offset_of!(WorldSnapshot, answer_cycle), 40);
        assert_eq!(offset_of!(WorldSnapshot, answer_received_ns), 48);
        assert_eq!(offset_of!(WorldSnapshot, reward), 56);
        assert_eq!(offset_of!(WorldSnapshot, agent), 64);
        assert_eq!(offset_of!(WorldSnapshot, step), 68);
        assert_eq!(offset_of!(WorldSnapshot, episode_status), 72);
        assert_eq!(offset_of!(WorldSnapshot, action_status), 73);
        assert_eq!(offset_of!(WorldSnapshot, reserved), 74);
        assert_eq!(offset_of!(WorldSnapshot, atoms), 80);
        assert_eq!(offset_of!(WorldSnapshot, fluents), 112);
    }

    #[test]
    fn world_command_layout() {
        assert_eq!((size_of::<WorldCommand>(), align_of::<WorldCommand>()), (80, 8));
        assert_eq!(offset_of!(WorldCommand, header), 0);
        assert_eq!(offset_of!(WorldCommand, episode), 16);
        assert_eq!(offset_of!(WorldCommand, cycle), 24);
        assert_eq!(offset_of!(WorldCommand, compute_ns), 32);
        assert_eq!(offset_of!(WorldCommand, action), 40);
        assert_eq!(offset_of!(WorldCommand, reserved), 44);
        assert_eq!(offset_of!(WorldCommand, args), 48);
    }

    #[test]
    fn world_vocabulary_layout() {
        assert_eq!((size_of::<WorldVocabulary>(), align_of::<WorldVocabulary>()), (560, 8));
        assert_eq!(offset_of!(WorldVocabulary, header), 0);
        assert_eq!(offset_of!(WorldVocabulary, atoms), 16);
        assert_eq!(offset_of!(WorldVocabulary, fluents), 20);
        assert_eq!(offset_of!(WorldVocabulary, actions), 24);
        assert_eq!(offset_of!(WorldVocabulary, agents), 28);
        assert_eq!(offset_of!(WorldVocabulary, part), 32);
        assert_eq!(offset_of!(WorldVocabulary, parts), 36);
        assert_eq!(offset_of!(WorldVocabulary, first), 40);
        assert_eq!(offset_of!(WorldVocabulary, count), 44);
        assert_eq!(offset_of!(WorldVocabulary, names), 48);
    }

    #[test]
    fn feed_header_layout() {
        assert_eq!((size_of::<FeedHeader>(), align_of::<FeedHeader>()), (24, 8));
        assert_eq!(offset_of!(FeedHeader, version), 0);
        assert_eq!(offset_of!(FeedHeader, sender), 4);
        assert_eq!(offset_of!(FeedHeader, run_id), 8);
        assert_eq!(offset_of!(FeedHeader, sequence), 16);
    }

    /// A type's size and its fields' offsets, as `layouts.json` lists them.
    macro_rules! layout {
        ($t:ty, $($field:ident),+) => {
            (
                stringify!($t),
                size_of::<$t>(),
                vec![$((stringify!($field), offset_of!($t, $field))),+],
            )
        };
    }

    /// `layouts.json` as these types make it: every type's size and field
    /// offsets, and the limits, for programs in other languages to check
    /// their own mirrors against (the Python world kit's test does).
    fn layouts_json() -> String {
        let types = [
            layout!(Header, version, sender, run_id),
            layout!(
                WorldSnapshot,
                header,
                episode,
                cycle,
                sent_ns,
                answer_cycle,
                answer_received_ns,
                reward,
                agent,
                step,
                episode_status,
                action_status,
                reserved,
                atoms,
                fluents
            ),
            layout!(WorldCommand, header, episode, cycle, compute_ns, action, reserved, args),
            layout!(
                WorldVocabulary,
                header,
                atoms,
                fluents,
                actions,
                agents,
                part,
                parts,
                first,
                count,
                names
            ),
            layout!(AgentReport, header, episode, kind, pid, exploratory, reserved),
            layout!(
                Heartbeat,
                header,
                pid,
                state,
                sequence,
                episodes,
                cycles,
                rejected,
                missed_deadlines,
                aborted_episodes,
                checkpoints,
                checkpoint_failures,
                late_cycles
            ),
            layout!(Control, header, command, target, sequence, pid, reserved),
        ];
        let mut out = String::from("{\n  \"protocol_version\": ");
        out += &format!("{PROTOCOL_VERSION},\n  \"limits\": {{");
        let limits = [
            ("MAX_ATOMS", MAX_ATOMS),
            ("MAX_FLUENTS", MAX_FLUENTS),
            ("MAX_ARGS", MAX_ARGS),
            ("MAX_ACTIONS", MAX_ACTIONS),
            ("MAX_AGENTS", MAX_AGENTS),
            ("NAME_LEN", NAME_LEN),
            ("NAMES_PER_PART", NAMES_PER_PART),
        ];
        let limits: Vec<String> = limits.iter().map(|(n, v)| format!("\"{n}\": {v}")).collect();
        out += &limits.join(", ");
        out += "},\n  \"types\": {\n";
        let types: Vec<String> = types
            .iter()
            .map(|(name, size, fields)| {
                let fields: Vec<String> = fields.iter().map(|(f, o)| format!("\"{f}\": {o}")).collect();
                format!(
                    "    \"{name}\": {{\"size\": {size}, \"offsets\": {{{}}}}}",
                    fields.join(", ")
                )
            })
            .collect();
        out += &types.join(",\n");
        out += "\n  }\n}\n";
        out
    }

    #[test]
    fn layouts_json_is_current() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/layouts.json");
        let expected = layouts_json();
        let found = std::fs::read_to_string(path).unwrap_or_default();
        assert!(
            found == expected,
            "{path} is not what the layouts are; it should read:\n{expected}"
        );
    }

    #[test]
    fn type_names_are_stable() {
        use iceoryx2::prelude::ZeroCopySend;
        // SAFETY: type_name only reads the derive's constant.
        let names = unsafe {
            [
                KeeperSnapshot::type_name(),
                KeeperCommand::type_name(),
                EpisodeEvent::type_name(),
                AgentReport::type_name(),
                Heartbeat::type_name(),
                Control::type_name(),
                WorldSnapshot::type_name(),
                WorldCommand::type_name(),
                WorldVocabulary::type_name(),
                FeedHeader::type_name(),
            ]
        };
        assert_eq!(
            names,
            [
                "learnpnp::KeeperSnapshot",
                "learnpnp::KeeperCommand",
                "learnpnp::EpisodeEvent",
                "learnpnp::AgentReport",
                "learnpnp::Heartbeat",
                "learnpnp::Control",
                "learnpnp::WorldSnapshot",
                "learnpnp::WorldCommand",
                "learnpnp::WorldVocabulary",
                "learnpnp::FeedHeader",
            ]
        );
    }
}
