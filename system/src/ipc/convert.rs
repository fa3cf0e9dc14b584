//! Between the in-process types (the protocol's are in [`super::protocol`](crate::ipc::protocol))
//! and their shared-memory layouts (`shm_layouts`), validating everything read: a message from shared memory
//! is untrusted until it has passed here (protocol version, run, sender, ids
//! in range, finite numbers, known tags). A refused message is counted by
//! [`Rejection`](crate::ipc::convert::Rejection) reason and never applied.

use shm_layouts::{
    AgentReport, BallLayout, Control, EpisodeEvent, Header, Heartbeat, KeeperCommand, KeeperSnapshot, PROTOCOL_VERSION,
    PlayerLayout, SENDER_SIMULATOR, SENDER_SUPERVISOR, command, control, episode, forced, mode, report, state,
};

use learnpnp::learning::{EpisodeMode, EpisodeStart};
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::geometry::Vec2;
use learnpnp_keepaway::view::{PlayerId, PlayerView, SeenBall, SeenPlayer};
use learnpnp_keepaway::world::{NUM_KEEPERS, NUM_PLAYERS};

use super::protocol::{AgentNews, CommandReading, EpisodeNews, Order, ProcessState, Pulse, Role, Roster, SnapshotMeta};

const _: () = assert!(shm_layouts::NUM_KEEPERS == NUM_KEEPERS && shm_layouts::NUM_PLAYERS == NUM_PLAYERS);

pub use super::protocol::{Rejection, Rejections};

/// Checks a header: this protocol, this run, one of the allowed senders.
fn check_header(header: &Header, run_id: u64, allowed: impl Fn(u32) -> bool) -> Result<(), Rejection> {
    if header.version != PROTOCOL_VERSION {
        return Err(Rejection::Version);
    }
    if header.run_id != run_id {
        return Err(Rejection::Run);
    }
    if !allowed(header.sender) {
        return Err(Rejection::Sender);
    }
    Ok(())
}

fn finite(values: &[f64]) -> Result<(), Rejection> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Rejection::Content)
    }
}

fn mode_tag(m: EpisodeMode) -> u8 {
    match m {
        EpisodeMode::Learn => mode::LEARN,
        EpisodeMode::Evaluate => mode::EVALUATE,
        EpisodeMode::Greedy => mode::GREEDY,
    }
}

fn forced_tag(f: Option<bool>) -> u8 {
    match f {
        None => forced::NONE,
        Some(true) => forced::EXPLORE,
        Some(false) => forced::EXPLOIT,
    }
}

fn read_start(mode_tag: u8, forced_tag: u8) -> Result<EpisodeStart, Rejection> {
    let mode = match mode_tag {
        mode::LEARN => EpisodeMode::Learn,
        mode::EVALUATE => EpisodeMode::Evaluate,
        mode::GREEDY => EpisodeMode::Greedy,
        _ => return Err(Rejection::Content),
    };
    let exploratory = match forced_tag {
        forced::NONE => None,
        forced::EXPLORE => Some(true),
        forced::EXPLOIT => Some(false),
        _ => return Err(Rejection::Content),
    };
    Ok(EpisodeStart { mode, exploratory })
}

fn vec(v: Vec2) -> [f64; 2] {
    [v.x, v.y]
}

fn unvec(a: [f64; 2]) -> Vec2 {
    Vec2 { x: a[0], y: a[1] }
}

/// The snapshot of `view` (keeper `view.me`) for run `run_id`.
pub fn snapshot(view: &PlayerView, meta: &SnapshotMeta, run_id: u64) -> KeeperSnapshot {
    KeeperSnapshot {
        header: Header::new(SENDER_SIMULATOR, run_id),
        episode: meta.episode,
        cycle_seq: meta.cycle_seq,
        reward: meta.reward,
        cycle: view.cycle,
        me: view.me.index() as u32,
        mode: mode_tag(meta.start.mode),
        forced_exploration: forced_tag(meta.start.exploratory),
        reserved: [0; 6],
        ball: BallLayout {
            pos: vec(view.ball.pos),
            vel: vec(view.ball.vel),
        },
        players: view.players.map(|p| PlayerLayout {
            pos: vec(p.pos),
            vel: vec(p.vel),
            body: p.body,
        }),
    }
}

/// Reads a snapshot received on keeper `keeper`'s service.
pub fn read_snapshot(
    msg: &KeeperSnapshot,
    keeper: usize,
    run_id: u64,
) -> Result<(SnapshotMeta, PlayerView), Rejection> {
    check_header(&msg.header, run_id, |s| s == SENDER_SIMULATOR)?;
    if msg.me as usize != keeper {
        return Err(Rejection::Content);
    }
    let me = PlayerId::keeper(keeper).ok_or(Rejection::Content)?;
    let start = read_start(msg.mode, msg.forced_exploration)?;
    finite(&[msg.reward])?;
    finite(&msg.ball.pos)?;
    finite(&msg.ball.vel)?;
    for p in &msg.players {
        finite(&p.pos)?;
        finite(&p.vel)?;
        finite(&[p.body])?;
    }
    let view = PlayerView {
        cycle: msg.cycle,
        me,
        ball: SeenBall {
            pos: unvec(msg.ball.pos),
            vel: unvec(msg.ball.vel),
        },
        players: msg.players.map(|p| SeenPlayer {
            pos: unvec(p.pos),
            vel: unvec(p.vel),
            body: p.body,
        }),
    };
    let meta = SnapshotMeta {
        episode: msg.episode,
        cycle_seq: msg.cycle_seq,
        reward: msg.reward,
        start,
    };
    Ok((meta, view))
}

/// Keeper `keeper`'s command answering `(episode, cycle_seq)`.
pub fn command_message(reading: &CommandReading, keeper: usize, run_id: u64) -> KeeperCommand {
    let (kind, arg0, arg1) = match reading.command {
        Command::None => (command::NONE, 0.0, 0.0),
        Command::Kick { power, direction } => (command::KICK, power, direction),
        Command::Dash { power } => (command::DASH, power, 0.0),
        Command::Turn { moment } => (command::TURN, moment, 0.0),
    };
    KeeperCommand {
        header: Header::new(keeper as u32, run_id),
        episode: reading.episode,
        cycle_seq: reading.cycle_seq,
        kind,
        flags: if reading.idle { command::FLAG_IDLE } else { 0 },
        arg0,
        arg1,
    }
}

/// Reads a command received on keeper `keeper`'s service.
pub fn read_command(msg: &KeeperCommand, keeper: usize, run_id: u64) -> Result<CommandReading, Rejection> {
    check_header(&msg.header, run_id, |s| s as usize == keeper)?;
    finite(&[msg.arg0, msg.arg1])?;
    if msg.flags & !command::FLAG_IDLE != 0 {
        return Err(Rejection::Content);
    }
    let command = match msg.kind {
        command::NONE => Command::None,
        command::KICK => Command::Kick {
            power: msg.arg0,
            direction: msg.arg1,
        },
        command::DASH => Command::Dash { power: msg.arg0 },
        command::TURN => Command::Turn { moment: msg.arg0 },
        _ => return Err(Rejection::Content),
    };
    Ok(CommandReading {
        episode: msg.episode,
        cycle_seq: msg.cycle_seq,
        command,
        idle: msg.flags & command::FLAG_IDLE != 0,
    })
}

/// The event of `news` about episode `episode`.
pub(crate) fn episode_event(episode_seq: u64, news: EpisodeNews, run_id: u64) -> EpisodeEvent {
    let (kind, start, cycles, seconds) = match news {
        EpisodeNews::Begin(start) => (episode::BEGIN, start, 0, 0.0),
        EpisodeNews::End { cycles, seconds } => (episode::END, EpisodeStart::LEARN, cycles, seconds),
        EpisodeNews::Abort { cycles } => (episode::ABORT, EpisodeStart::LEARN, cycles, 0.0),
    };
    EpisodeEvent {
        header: Header::new(SENDER_SIMULATOR, run_id),
        episode: episode_seq,
        kind,
        mode: mode_tag(start.mode),
        forced_exploration: forced_tag(start.exploratory),
        reserved: [0; 2],
        cycles,
        reserved2: 0,
        seconds,
    }
}

/// Reads an episode event: its episode and what happens.
pub(crate) fn read_episode_event(msg: &EpisodeEvent, run_id: u64) -> Result<(u64, EpisodeNews), Rejection> {
    check_header(&msg.header, run_id, |s| s == SENDER_SIMULATOR)?;
    finite(&[msg.seconds])?;
    let news = match msg.kind {
        episode::BEGIN => EpisodeNews::Begin(read_start(msg.mode, msg.forced_exploration)?),
        episode::END => EpisodeNews::End {
            cycles: msg.cycles,
            seconds: msg.seconds,
        },
        episode::ABORT => EpisodeNews::Abort { cycles: msg.cycles },
        _ => return Err(Rejection::Content),
    };
    Ok((msg.episode, news))
}

/// Keeper `keeper`'s report.
pub(crate) fn agent_report(news: AgentNews, keeper: usize, run_id: u64) -> AgentReport {
    let (kind, episode, pid, exploratory) = match news {
        AgentNews::Ready { pid } => (report::READY, 0, pid, false),
        AgentNews::Ended { episode, exploratory } => (report::ENDED, episode, 0, exploratory),
    };
    AgentReport {
        header: Header::new(keeper as u32, run_id),
        episode,
        kind,
        pid,
        exploratory: u8::from(exploratory),
        reserved: [0; 7],
    }
}

/// Reads a report from one of `agents` agents: the agent that sent it and what it says.
pub(crate) fn read_agent_report(
    msg: &AgentReport,
    run_id: u64,
    agents: usize,
) -> Result<(usize, AgentNews), Rejection> {
    check_header(&msg.header, run_id, |s| (s as usize) < agents)?;
    let news = match (msg.kind, msg.exploratory) {
        (report::READY, 0) => AgentNews::Ready { pid: msg.pid },
        (report::ENDED, e @ (0 | 1)) => AgentNews::Ended {
            episode: msg.episode,
            exploratory: e == 1,
        },
        _ => return Err(Rejection::Content),
    };
    Ok((msg.header.sender as usize, news))
}

/// The heartbeat carrying `pulse`.
pub fn heartbeat(pulse: &Pulse, run_id: u64) -> Heartbeat {
    Heartbeat {
        header: Header::new(pulse.role.sender(), run_id),
        pid: pulse.pid,
        state: match pulse.state {
            ProcessState::Starting => state::STARTING,
            ProcessState::Ready => state::READY,
            ProcessState::Running => state::RUNNING,
            ProcessState::Stopping => state::STOPPING,
        },
        sequence: pulse.sequence,
        episodes: pulse.episodes,
        cycles: pulse.cycles,
        rejected: pulse.rejected.to_array(),
        missed_deadlines: pulse.missed_deadlines,
        aborted_episodes: pulse.aborted_episodes,
        checkpoints: pulse.checkpoints,
        checkpoint_failures: pulse.checkpoint_failures,
        late_cycles: pulse.late_cycles,
    }
}

/// Reads a heartbeat from one of `roster`'s processes.
pub(crate) fn read_heartbeat(msg: &Heartbeat, run_id: u64, roster: Roster) -> Result<Pulse, Rejection> {
    check_header(&msg.header, run_id, |s| roster.role_of(s).is_some())?;
    let role = roster.role_of(msg.header.sender).ok_or(Rejection::Sender)?;
    let state = match msg.state {
        state::STARTING => ProcessState::Starting,
        state::READY => ProcessState::Ready,
        state::RUNNING => ProcessState::Running,
        state::STOPPING => ProcessState::Stopping,
        _ => return Err(Rejection::Content),
    };
    Ok(Pulse {
        role,
        pid: msg.pid,
        state,
        sequence: msg.sequence,
        episodes: msg.episodes,
        cycles: msg.cycles,
        rejected: Rejections::from_array(msg.rejected),
        missed_deadlines: msg.missed_deadlines,
        aborted_episodes: msg.aborted_episodes,
        checkpoints: msg.checkpoints,
        checkpoint_failures: msg.checkpoint_failures,
        late_cycles: msg.late_cycles,
    })
}

/// The control message of `order` for `target` (`None`: everyone).
pub(crate) fn control_message(order: Order, target: Option<Role>, sequence: u64, run_id: u64) -> Control {
    let (command, target, pid) = match order {
        Order::Stop => (control::STOP, target.map_or(control::ALL, Role::sender), 0),
        Order::Checkpoint => (control::CHECKPOINT, target.map_or(control::ALL, Role::sender), 0),
        Order::SimulatorRestarted => (control::SIM_RESTARTED, control::ALL, 0),
        Order::KeeperLost { keeper, pid } => (control::KEEPER_LOST, keeper as u32, pid),
    };
    Control {
        header: Header::new(SENDER_SUPERVISOR, run_id),
        command,
        target,
        sequence,
        pid,
        reserved: 0,
    }
}

/// The most agents a run of `me`'s kind has (a world checks its own number).
fn agents_of(me: Role) -> usize {
    match me {
        Role::Simulator | Role::Keeper(_) => NUM_KEEPERS,
        Role::World | Role::Agent(_) | Role::Bridge | Role::View => shm_layouts::MAX_AGENTS,
    }
}

/// Reads a control message as `me` receives it: `None` if it is for someone else.
pub(crate) fn read_control(msg: &Control, me: Role, run_id: u64) -> Result<Option<Order>, Rejection> {
    check_header(&msg.header, run_id, |s| s == SENDER_SUPERVISOR)?;
    let for_me = msg.target == control::ALL || msg.target == me.sender();
    match msg.command {
        control::STOP if for_me => Ok(Some(Order::Stop)),
        control::CHECKPOINT if for_me => Ok(Some(Order::Checkpoint)),
        control::KEEPER_LOST if (msg.target as usize) < agents_of(me) => {
            Ok(me.is_host().then_some(Order::KeeperLost {
                keeper: msg.target as usize,
                pid: msg.pid,
            }))
        }
        control::SIM_RESTARTED if msg.target == control::ALL => {
            Ok((!me.is_host()).then_some(Order::SimulatorRestarted))
        }
        control::STOP | control::CHECKPOINT => Ok(None),
        _ => Err(Rejection::Content),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> PlayerView {
        let mut players = [SeenPlayer::default(); NUM_PLAYERS];
        for (i, p) in players.iter_mut().enumerate() {
            p.pos = Vec2 { x: i as f64, y: -1.5 };
            p.vel = Vec2 { x: 0.25, y: 0.0 };
            p.body = 30.0 * i as f64;
        }
        PlayerView {
            cycle: 17,
            me: PlayerId::keeper(1).unwrap(),
            ball: SeenBall {
                pos: Vec2 { x: 3.0, y: 4.0 },
                vel: Vec2 { x: -0.5, y: 0.125 },
            },
            players,
        }
    }

    const META: SnapshotMeta = SnapshotMeta {
        episode: 4,
        cycle_seq: 99,
        reward: 0.1,
        start: EpisodeStart::EVALUATE,
    };

    #[test]
    fn snapshot_round_trip_is_exact() {
        let msg = snapshot(&view(), &META, 7);
        assert_eq!(read_snapshot(&msg, 1, 7), Ok((META, view())));
    }

    #[test]
    fn snapshot_refusals() {
        let good = snapshot(&view(), &META, 7);
        let mut m = good;
        m.header.version = 9;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Version));
        assert_eq!(read_snapshot(&good, 1, 8), Err(Rejection::Run));
        let mut m = good;
        m.header.sender = 1;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Sender));
        assert_eq!(
            read_snapshot(&good, 2, 7),
            Err(Rejection::Content),
            "another keeper's view"
        );
        let mut m = good;
        m.players[3].vel[1] = f64::NAN;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Content));
        let mut m = good;
        m.mode = 3;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Content));
        let mut m = good;
        m.forced_exploration = 200;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Content));
        let mut m = good;
        m.reward = f64::INFINITY;
        assert_eq!(read_snapshot(&m, 1, 7), Err(Rejection::Content));
    }

    #[test]
    fn commands_round_trip_and_refusals() {
        for command in [
            Command::None,
            Command::Kick {
                power: 55.5,
                direction: -12.0,
            },
            Command::Dash { power: 100.0 },
            Command::Turn { moment: 33.0 },
        ] {
            let reading = CommandReading {
                episode: 3,
                cycle_seq: 12,
                command,
                idle: command == Command::None,
            };
            let msg = command_message(&reading, 2, 5);
            assert_eq!(read_command(&msg, 2, 5), Ok(reading));
            assert_eq!(
                read_command(&msg, 0, 5),
                Err(Rejection::Sender),
                "keeper 3's command on keeper 1's service"
            );
        }
        let reading = CommandReading {
            episode: 3,
            cycle_seq: 12,
            command: Command::Dash { power: 1.0 },
            idle: false,
        };
        let mut m = command_message(&reading, 0, 5);
        m.arg0 = f64::NAN;
        assert_eq!(read_command(&m, 0, 5), Err(Rejection::Content));
        let mut m = command_message(&reading, 0, 5);
        m.kind = 4;
        assert_eq!(read_command(&m, 0, 5), Err(Rejection::Content));
        let mut m = command_message(&reading, 0, 5);
        m.flags = 6;
        assert_eq!(read_command(&m, 0, 5), Err(Rejection::Content));
    }

    #[test]
    fn episode_events_round_trip() {
        for news in [
            EpisodeNews::Begin(EpisodeStart::GREEDY),
            EpisodeNews::Begin(EpisodeStart {
                mode: EpisodeMode::Learn,
                exploratory: Some(true),
            }),
            EpisodeNews::End {
                cycles: 140,
                seconds: 14.0,
            },
            EpisodeNews::Abort { cycles: 3 },
        ] {
            let msg = episode_event(9, news, 1);
            assert_eq!(read_episode_event(&msg, 1), Ok((9, news)));
        }
        let mut m = episode_event(9, EpisodeNews::Abort { cycles: 1 }, 1);
        m.kind = 0;
        assert_eq!(read_episode_event(&m, 1), Err(Rejection::Content));
    }

    #[test]
    fn reports_heartbeats_and_control_round_trip() {
        let news = AgentNews::Ended {
            episode: 5,
            exploratory: true,
        };
        assert_eq!(read_agent_report(&agent_report(news, 2, 3), 3, 3), Ok((2, news)));
        let ready = AgentNews::Ready { pid: 4242 };
        assert_eq!(read_agent_report(&agent_report(ready, 0, 3), 3, 3), Ok((0, ready)));
        let mut m = agent_report(news, 2, 3);
        m.header.sender = 3;
        assert_eq!(read_agent_report(&m, 3, 3), Err(Rejection::Sender));

        let pulse = Pulse {
            role: Role::Keeper(1),
            pid: 42,
            state: ProcessState::Running,
            sequence: 8,
            episodes: 2,
            cycles: 300,
            rejected: Rejections {
                content: 4,
                ..Rejections::default()
            },
            missed_deadlines: 0,
            aborted_episodes: 0,
            checkpoints: 1,
            checkpoint_failures: 0,
            late_cycles: 7,
        };
        assert_eq!(read_heartbeat(&heartbeat(&pulse, 3), 3, Roster::Keepaway), Ok(pulse));

        let stop = control_message(Order::Stop, None, 1, 3);
        assert_eq!(read_control(&stop, Role::Keeper(0), 3), Ok(Some(Order::Stop)));
        let checkpoint = control_message(Order::Checkpoint, Some(Role::Keeper(2)), 2, 3);
        assert_eq!(read_control(&checkpoint, Role::Keeper(0), 3), Ok(None));
        assert_eq!(
            read_control(&checkpoint, Role::Keeper(2), 3),
            Ok(Some(Order::Checkpoint))
        );
        let order = Order::KeeperLost { keeper: 1, pid: 77 };
        let lost = control_message(order, None, 3, 3);
        assert_eq!(read_control(&lost, Role::Simulator, 3), Ok(Some(order)));
        assert_eq!(read_control(&lost, Role::Keeper(1), 3), Ok(None));
        let restarted = control_message(Order::SimulatorRestarted, None, 4, 3);
        assert_eq!(
            read_control(&restarted, Role::Keeper(2), 3),
            Ok(Some(Order::SimulatorRestarted))
        );
        assert_eq!(read_control(&restarted, Role::Simulator, 3), Ok(None));
    }
}
