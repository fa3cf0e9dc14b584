//! What a message carried from another host must hold before a bridge
//! publishes it here: the checks the receiving process makes (protocol
//! version, run, sender, kinds and tags, finite numbers), made once more at
//! the link, so that a refusal of something the other host sent is counted
//! as the link's ([`LinkRefusals`](crate::hosts::report::LinkRefusals)) and is a fault of the
//! run, not only a process's rejected message. The receiving process still
//! checks everything itself.

use shm_layouts::{AgentReport, Control, Heartbeat, KeeperCommand, SENDER_SUPERVISOR, WorldCommand, control};

use crate::ipc::convert::{Rejection, read_agent_report, read_command, read_heartbeat};
use crate::ipc::protocol::{AgentNews, Role, Roster};
use crate::ipc::world::read_world_command;

/// Keeper `keeper`'s command, as the simulator would read it.
pub fn keeper_command(msg: &KeeperCommand, keeper: usize, run_id: u64) -> Result<(), Rejection> {
    read_command(msg, keeper, run_id).map(|_| ())
}

/// Agent `agent`'s command, as a world would read it (its actions' number
/// is the world's to check).
pub fn world_command(msg: &WorldCommand, agent: usize, run_id: u64) -> Result<(), Rejection> {
    read_world_command(msg, agent, run_id, usize::MAX).map(|_| ())
}

/// An agent's report: the agent (0-based), and the process id when it says
/// the agent is ready.
pub fn agent_report(msg: &AgentReport, run_id: u64, roster: Roster) -> Result<(usize, Option<u32>), Rejection> {
    let (agent, news) = read_agent_report(msg, run_id, roster.agents())?;
    Ok(match news {
        AgentNews::Ready { pid } => (agent, Some(pid)),
        AgentNews::Ended { .. } => (agent, None),
    })
}

/// A heartbeat: the process's role and id.
pub fn heartbeat(msg: &Heartbeat, run_id: u64, roster: Roster) -> Result<(Role, u32), Rejection> {
    read_heartbeat(msg, run_id, roster).map(|pulse| (pulse.role, pulse.pid))
}

/// A supervisor's order, whoever it is for (the bridge checks what the
/// other host may order).
pub fn control(msg: &Control, run_id: u64) -> Result<(), Rejection> {
    let header = &msg.header;
    if header.version != shm_layouts::PROTOCOL_VERSION {
        return Err(Rejection::Version);
    }
    if header.run_id != run_id {
        return Err(Rejection::Run);
    }
    if header.sender != SENDER_SUPERVISOR {
        return Err(Rejection::Sender);
    }
    match msg.command {
        control::STOP | control::CHECKPOINT | control::KEEPER_LOST | control::SIM_RESTARTED => Ok(()),
        _ => Err(Rejection::Content),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shm_layouts::{Header, command};

    fn command(kind: u32, arg0: f64) -> KeeperCommand {
        KeeperCommand {
            header: Header::new(2, 7),
            episode: 1,
            cycle_seq: 1,
            kind,
            flags: 0,
            arg0,
            arg1: 0.0,
        }
    }

    #[test]
    fn a_command_is_checked_as_the_simulator_checks_it() {
        assert_eq!(keeper_command(&command(command::DASH, 50.0), 2, 7), Ok(()));
        assert_eq!(keeper_command(&command(command::DASH, 50.0), 2, 8), Err(Rejection::Run));
        assert_eq!(
            keeper_command(&command(command::DASH, 50.0), 1, 7),
            Err(Rejection::Sender)
        );
        assert_eq!(
            keeper_command(&command(command::DASH, f64::NAN), 2, 7),
            Err(Rejection::Content)
        );
        assert_eq!(keeper_command(&command(99, 0.0), 2, 7), Err(Rejection::Content));
    }

    #[test]
    fn an_order_must_come_from_a_supervisor_and_be_known() {
        let order = Control {
            header: Header::new(SENDER_SUPERVISOR, 7),
            command: control::KEEPER_LOST,
            target: 2,
            sequence: 1,
            pid: 42,
            reserved: 0,
        };
        assert_eq!(control(&order, 7), Ok(()));
        assert_eq!(control(&Control { command: 77, ..order }, 7), Err(Rejection::Content));
        assert_eq!(
            control(
                &Control {
                    header: Header::new(2, 7),
                    ..order
                },
                7
            ),
            Err(Rejection::Sender)
        );
    }
}
