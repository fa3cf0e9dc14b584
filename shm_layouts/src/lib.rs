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
pub const PROTOCOL_VERSION: u32 = 1;

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

    /// The event service that wakes a blocked process (`sim`, `keeper-0`, ...).
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
        assert_eq!((size_of::<Heartbeat>(), align_of::<Heartbeat>()), (120, 8));
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
            ]
        );
    }
}
