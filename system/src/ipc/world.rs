//! The protocol of a world in its own process (`shm_layouts/README.md`, "A
//! world in its own process"): what its messages say once read
//! ([`WorldView`](crate::ipc::world::WorldView), [`WorldOrder`](crate::ipc::world::WorldOrder), [`Vocabulary`](crate::ipc::world::Vocabulary)), and their conversion to
//! and from the layouts, validating everything read. A refused message is
//! counted by [`Rejection`](crate::ipc::convert::Rejection) reason and never applied.

use shm_layouts::{
    Header, MAX_ACTIONS, MAX_AGENTS, MAX_ARGS, MAX_ATOMS, MAX_FLUENTS, NAME_LEN, NAMES_PER_PART, NO_ACTION,
    SENDER_SUPERVISOR, SENDER_WORLD, WorldCommand, WorldSnapshot, WorldVocabulary, action_status, episode_status,
};

use super::convert::Rejection;

/// Words of the atoms' bitset.
pub(crate) const ATOM_WORDS: usize = MAX_ATOMS / 64;

/// What happens to the episode, as a snapshot says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EpisodeStatus {
    /// It goes on.
    Running,
    /// It reached a terminal state.
    Terminated,
    /// It was cut short.
    Truncated,
    /// It is discarded.
    Aborted,
}

impl EpisodeStatus {
    /// Whether the episode ended normally (the agent learns from it).
    pub(crate) fn ended(self) -> bool {
        matches!(self, EpisodeStatus::Terminated | EpisodeStatus::Truncated)
    }
}

/// What became of the action the agent's previous command started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionStatus {
    /// No action in progress.
    None,
    /// It goes on.
    Running,
    /// It ended normally.
    Finished,
    /// It failed.
    Failed,
}

/// A snapshot as an agent reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldView {
    /// The episode.
    pub episode: u64,
    /// The world's cycle.
    pub(crate) cycle: u64,
    /// When the world published it (`CLOCK_MONOTONIC` ns).
    pub(crate) sent_ns: u64,
    /// The cycle of the agent's last command the world took, and when it read it.
    pub(crate) answered: Option<(u64, u64)>,
    /// Reward since the previous snapshot.
    pub reward: f64,
    /// Steps since the episode began.
    pub step: u32,
    /// The episode's status.
    pub(crate) episode_status: EpisodeStatus,
    /// The action's status.
    pub(crate) action_status: ActionStatus,
    /// The atoms that hold, as a bitset.
    pub atoms: [u64; ATOM_WORDS],
    /// The fluents.
    pub fluents: [f64; MAX_FLUENTS],
}

impl WorldView {
    /// Whether world atom `index` holds.
    pub(crate) fn holds(&self, index: usize) -> bool {
        self.atoms[index / 64] >> (index % 64) & 1 == 1
    }
}

/// A command as the world reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldOrder {
    /// The episode it belongs to.
    pub episode: u64,
    /// The cycle it answers.
    pub(crate) cycle: u64,
    /// The agent's compute time, ns.
    pub(crate) compute_ns: u64,
    /// The action's index in the vocabulary, or `None`.
    pub action: Option<usize>,
    /// Its arguments.
    pub args: [f64; MAX_ARGS],
}

/// A world's names: what agents check their plans against.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Vocabulary {
    /// The atoms, in bit order.
    pub atoms: Vec<String>,
    /// The fluents.
    pub fluents: Vec<String>,
    /// The actions, in index order.
    pub actions: Vec<String>,
    /// The agents the world serves.
    pub agents: usize,
}

/// Why a vocabulary cannot be announced.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum VocabularyError {
    /// More names of a kind than the layouts carry.
    #[error("{count} {kind} (at most {limit})")]
    TooMany {
        /// Atoms, fluents, actions or agents.
        kind: &'static str,
        /// How many were given.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// A name that does not fit its field or is empty.
    #[error("name '{0}' is empty or longer than {NAME_LEN} bytes")]
    BadName(String),
    /// A name given twice.
    #[error("name '{0}' appears twice")]
    Duplicate(String),
}

impl Vocabulary {
    /// Checks the vocabulary against the layouts' limits.
    pub fn validate(&self) -> Result<(), VocabularyError> {
        let limits = [
            ("atoms", self.atoms.len(), MAX_ATOMS),
            ("fluents", self.fluents.len(), MAX_FLUENTS),
            ("actions", self.actions.len(), MAX_ACTIONS),
            ("agents", self.agents, MAX_AGENTS),
        ];
        for (kind, count, limit) in limits {
            if count > limit || (kind == "agents" && count == 0) {
                return Err(VocabularyError::TooMany { kind, count, limit });
            }
        }
        let mut seen = std::collections::HashSet::new();
        for name in self.names() {
            if name.is_empty() || name.len() > NAME_LEN || name.contains('\0') {
                return Err(VocabularyError::BadName(name.clone()));
            }
            if !seen.insert(name) {
                return Err(VocabularyError::Duplicate(name.clone()));
            }
        }
        Ok(())
    }

    fn names(&self) -> impl Iterator<Item = &String> {
        self.atoms.iter().chain(&self.fluents).chain(&self.actions)
    }

    /// The messages announcing it (call [`Vocabulary::validate`] first).
    pub fn parts(&self, run_id: u64) -> Vec<WorldVocabulary> {
        let names: Vec<&String> = self.names().collect();
        let parts = names.len().div_ceil(NAMES_PER_PART).max(1);
        (0..parts)
            .map(|part| {
                let first = part * NAMES_PER_PART;
                let chunk = &names[first.min(names.len())..(first + NAMES_PER_PART).min(names.len())];
                let mut fields = [[0u8; NAME_LEN]; NAMES_PER_PART];
                for (field, name) in fields.iter_mut().zip(chunk) {
                    field[..name.len()].copy_from_slice(name.as_bytes());
                }
                WorldVocabulary {
                    header: Header::new(SENDER_WORLD, run_id),
                    atoms: self.atoms.len() as u32,
                    fluents: self.fluents.len() as u32,
                    actions: self.actions.len() as u32,
                    agents: self.agents as u32,
                    part: part as u32,
                    parts: parts as u32,
                    first: first as u32,
                    count: chunk.len() as u32,
                    names: fields,
                }
            })
            .collect()
    }
}

/// Checks a header: this protocol, this run, the expected sender.
fn check_header(header: &Header, run_id: u64, sender: u32) -> Result<(), Rejection> {
    if header.version != shm_layouts::PROTOCOL_VERSION {
        return Err(Rejection::Version);
    }
    if header.run_id != run_id {
        return Err(Rejection::Run);
    }
    if header.sender != sender {
        return Err(Rejection::Sender);
    }
    Ok(())
}

/// Collects a vocabulary's parts as they come, checking each.
#[derive(Debug, Default)]
pub(crate) struct VocabularyReader {
    shape: Option<[u32; 5]>,
    names: Vec<Option<String>>,
}

impl VocabularyReader {
    /// Takes one part; returns the vocabulary once every part has come.
    pub(crate) fn read(&mut self, msg: &WorldVocabulary, run_id: u64) -> Result<Option<Vocabulary>, Rejection> {
        check_header(&msg.header, run_id, SENDER_WORLD)?;
        let total = msg.atoms as usize + msg.fluents as usize + msg.actions as usize;
        let within = msg.atoms as usize <= MAX_ATOMS
            && msg.fluents as usize <= MAX_FLUENTS
            && msg.actions as usize <= MAX_ACTIONS
            && (1..=MAX_AGENTS).contains(&(msg.agents as usize))
            && msg.parts as usize == total.div_ceil(NAMES_PER_PART).max(1)
            && msg.part < msg.parts
            && msg.first as usize == msg.part as usize * NAMES_PER_PART
            && msg.count as usize == total.saturating_sub(msg.first as usize).min(NAMES_PER_PART);
        if !within {
            return Err(Rejection::Content);
        }
        let mut names = Vec::with_capacity(msg.count as usize);
        for (i, field) in msg.names.iter().enumerate() {
            let len = field.iter().position(|&b| b == 0).unwrap_or(NAME_LEN);
            if i >= msg.count as usize {
                if field.iter().any(|&b| b != 0) {
                    return Err(Rejection::Content);
                }
                continue;
            }
            if len == 0 || field[len..].iter().any(|&b| b != 0) {
                return Err(Rejection::Content);
            }
            names.push(
                std::str::from_utf8(&field[..len])
                    .map_err(|_| Rejection::Content)?
                    .to_string(),
            );
        }
        let shape = [msg.atoms, msg.fluents, msg.actions, msg.agents, msg.parts];
        if self.shape != Some(shape) {
            // The first part, or a world that announces another vocabulary.
            self.shape = Some(shape);
            self.names = vec![None; total];
        }
        for (slot, name) in self.names[msg.first as usize..].iter_mut().zip(names) {
            *slot = Some(name);
        }
        if self.names.iter().any(Option::is_none) {
            return Ok(None);
        }
        let names: Vec<String> = self.names.iter().flatten().cloned().collect();
        let (atoms, rest) = names.split_at(msg.atoms as usize);
        let (fluents, actions) = rest.split_at(msg.fluents as usize);
        Ok(Some(Vocabulary {
            atoms: atoms.to_vec(),
            fluents: fluents.to_vec(),
            actions: actions.to_vec(),
            agents: msg.agents as usize,
        }))
    }
}

/// The snapshot of `view` for agent `agent`.
pub(crate) fn world_snapshot(view: &WorldView, agent: usize, run_id: u64) -> WorldSnapshot {
    let (answer_cycle, answer_received_ns) = view.answered.unwrap_or((0, 0));
    WorldSnapshot {
        header: Header::new(SENDER_WORLD, run_id),
        episode: view.episode,
        cycle: view.cycle,
        sent_ns: view.sent_ns,
        answer_cycle,
        answer_received_ns,
        reward: view.reward,
        agent: agent as u32,
        step: view.step,
        episode_status: match view.episode_status {
            EpisodeStatus::Running => episode_status::RUNNING,
            EpisodeStatus::Terminated => episode_status::TERMINATED,
            EpisodeStatus::Truncated => episode_status::TRUNCATED,
            EpisodeStatus::Aborted => episode_status::ABORTED,
        },
        action_status: match view.action_status {
            ActionStatus::None => action_status::NONE,
            ActionStatus::Running => action_status::RUNNING,
            ActionStatus::Finished => action_status::FINISHED,
            ActionStatus::Failed => action_status::FAILED,
        },
        reserved: [0; 6],
        atoms: view.atoms,
        fluents: view.fluents,
    }
}

/// Reads a snapshot received on agent `agent`'s service from a world of
/// `atoms` atoms and `fluents` fluents.
pub(crate) fn read_world_snapshot(
    msg: &WorldSnapshot,
    agent: usize,
    run_id: u64,
    atoms: usize,
    fluents: usize,
) -> Result<WorldView, Rejection> {
    check_header(&msg.header, run_id, SENDER_WORLD)?;
    let episode_status = match msg.episode_status {
        episode_status::RUNNING => EpisodeStatus::Running,
        episode_status::TERMINATED => EpisodeStatus::Terminated,
        episode_status::TRUNCATED => EpisodeStatus::Truncated,
        episode_status::ABORTED => EpisodeStatus::Aborted,
        _ => return Err(Rejection::Content),
    };
    let action_status = match msg.action_status {
        action_status::NONE => ActionStatus::None,
        action_status::RUNNING => ActionStatus::Running,
        action_status::FINISHED => ActionStatus::Finished,
        action_status::FAILED => ActionStatus::Failed,
        _ => return Err(Rejection::Content),
    };
    let atoms_beyond = msg.atoms.iter().enumerate().any(|(w, &word)| {
        let used = atoms.saturating_sub(w * 64).min(64);
        let mask = if used == 64 { u64::MAX } else { (1u64 << used) - 1 };
        word & !mask != 0
    });
    let fluents_ok = msg.fluents[..fluents].iter().all(|f| f.is_finite())
        && msg.fluents[fluents..].iter().all(|&f| f.to_bits() == 0);
    let valid = msg.agent as usize == agent
        && msg.reserved == [0; 6]
        && !atoms_beyond
        && fluents_ok
        && msg.reward.is_finite()
        && msg.episode > 0
        && msg.cycle > 0;
    if !valid {
        return Err(Rejection::Content);
    }
    Ok(WorldView {
        episode: msg.episode,
        cycle: msg.cycle,
        sent_ns: msg.sent_ns,
        answered: (msg.answer_cycle > 0).then_some((msg.answer_cycle, msg.answer_received_ns)),
        reward: msg.reward,
        step: msg.step,
        episode_status,
        action_status,
        atoms: msg.atoms,
        fluents: msg.fluents,
    })
}

/// Agent `agent`'s command `order`.
pub(crate) fn world_command(order: &WorldOrder, agent: usize, run_id: u64) -> WorldCommand {
    WorldCommand {
        header: Header::new(agent as u32, run_id),
        episode: order.episode,
        cycle: order.cycle,
        compute_ns: order.compute_ns,
        action: order.action.map_or(NO_ACTION, |a| a as u32),
        reserved: 0,
        args: order.args,
    }
}

/// Reads a command received on agent `agent`'s service by a world of `actions` actions.
pub(crate) fn read_world_command(
    msg: &WorldCommand,
    agent: usize,
    run_id: u64,
    actions: usize,
) -> Result<WorldOrder, Rejection> {
    check_header(&msg.header, run_id, agent as u32)?;
    let action = match msg.action {
        NO_ACTION => None,
        a if (a as usize) < actions => Some(a as usize),
        _ => return Err(Rejection::Content),
    };
    if msg.reserved != 0 || !msg.args.iter().all(|a| a.is_finite()) {
        return Err(Rejection::Content);
    }
    Ok(WorldOrder {
        episode: msg.episode,
        cycle: msg.cycle,
        compute_ns: msg.compute_ns,
        action,
        args: msg.args,
    })
}

/// The supervisor's floor ping `sequence`: the snapshot payload, zeroed.
pub(crate) fn floor_ping(run_id: u64, sequence: u64) -> WorldSnapshot {
    let view = WorldView {
        episode: 1,
        cycle: sequence,
        sent_ns: 0,
        answered: None,
        reward: 0.0,
        step: 0,
        episode_status: EpisodeStatus::Running,
        action_status: ActionStatus::None,
        atoms: [0; ATOM_WORDS],
        fluents: [0.0; MAX_FLUENTS],
    };
    WorldSnapshot {
        header: Header::new(SENDER_SUPERVISOR, run_id),
        ..world_snapshot(&view, 0, run_id)
    }
}

/// Agent 0's answer to floor ping `sequence`.
pub(crate) fn floor_pong(run_id: u64, sequence: u64) -> WorldCommand {
    let order = WorldOrder {
        episode: 1,
        cycle: sequence,
        compute_ns: 0,
        action: None,
        args: [0.0; MAX_ARGS],
    };
    world_command(&order, 0, run_id)
}

/// Now on `CLOCK_MONOTONIC`, in nanoseconds: the clock every process of a
/// host shares (Python's `time.monotonic_ns()`).
pub(crate) fn monotonic_ns() -> u64 {
    let mut now = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `now` is a valid timespec the call writes.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut now) };
    now.tv_sec as u64 * 1_000_000_000 + now.tv_nsec as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vocabulary() -> Vocabulary {
        Vocabulary {
            atoms: (0..70).map(|i| format!("atom{i}")).collect(),
            fluents: vec!["speed".into()],
            actions: vec!["left".into(), "right".into()],
            agents: 2,
        }
    }

    fn view() -> WorldView {
        let mut atoms = [0; ATOM_WORDS];
        atoms[0] = 0b101;
        atoms[1] = 1 << 5; // atom 69
        let mut fluents = [0.0; MAX_FLUENTS];
        fluents[0] = 2.5;
        WorldView {
            episode: 3,
            cycle: 40,
            sent_ns: 123,
            answered: Some((39, 120)),
            reward: -1.0,
            step: 7,
            episode_status: EpisodeStatus::Running,
            action_status: ActionStatus::Finished,
            atoms,
            fluents,
        }
    }

    #[test]
    fn vocabulary_round_trip_in_any_order() {
        let v = vocabulary();
        v.validate().unwrap();
        let parts = v.parts(9);
        assert_eq!(parts.len(), 5, "73 names, 16 to a part");
        let mut reader = VocabularyReader::default();
        let mut got = None;
        for part in parts.iter().rev() {
            got = reader.read(part, 9).unwrap();
        }
        assert_eq!(got, Some(v));
    }

    #[test]
    fn vocabulary_refusals() {
        let parts = vocabulary().parts(9);
        let mut reader = VocabularyReader::default();
        assert_eq!(reader.read(&parts[0], 8), Err(Rejection::Run));
        let mut m = parts[0];
        m.header.sender = 1;
        assert_eq!(reader.read(&m, 9), Err(Rejection::Sender));
        let mut m = parts[4];
        m.names[15][0] = b'x';
        assert_eq!(reader.read(&m, 9), Err(Rejection::Content), "a name beyond count");
        let mut m = parts[0];
        m.names[0] = [0xff; NAME_LEN];
        assert_eq!(reader.read(&m, 9), Err(Rejection::Content), "not UTF-8");
        let mut m = parts[0];
        m.atoms = 300;
        assert_eq!(reader.read(&m, 9), Err(Rejection::Content));
        let long = Vocabulary {
            atoms: vec!["x".repeat(NAME_LEN + 1)],
            ..vocabulary()
        };
        assert!(matches!(long.validate(), Err(VocabularyError::BadName(_))));
    }

    #[test]
    fn snapshot_round_trip_and_refusals() {
        let msg = world_snapshot(&view(), 1, 5);
        assert_eq!(read_world_snapshot(&msg, 1, 5, 70, 1), Ok(view()));
        assert_eq!(read_world_snapshot(&msg, 0, 5, 70, 1), Err(Rejection::Content));
        assert_eq!(
            read_world_snapshot(&msg, 1, 5, 69, 1),
            Err(Rejection::Content),
            "atom 69 beyond a vocabulary of 69"
        );
        let mut m = msg;
        m.fluents[0] = f64::NAN;
        assert_eq!(read_world_snapshot(&m, 1, 5, 70, 1), Err(Rejection::Content));
        let mut m = msg;
        m.fluents[3] = 1.0;
        assert_eq!(read_world_snapshot(&m, 1, 5, 70, 1), Err(Rejection::Content));
        let mut m = msg;
        m.episode_status = 4;
        assert_eq!(read_world_snapshot(&m, 1, 5, 70, 1), Err(Rejection::Content));
        let mut m = msg;
        m.header.version = shm_layouts::PROTOCOL_VERSION + 1;
        assert_eq!(read_world_snapshot(&m, 1, 5, 70, 1), Err(Rejection::Version));
        assert!(view().holds(69) && view().holds(2) && !view().holds(1));
    }

    #[test]
    fn command_round_trip_and_refusals() {
        let order = WorldOrder {
            episode: 3,
            cycle: 40,
            compute_ns: 77,
            action: Some(1),
            args: [0.5, 0.0, 0.0, 0.0],
        };
        let msg = world_command(&order, 1, 5);
        assert_eq!(read_world_command(&msg, 1, 5, 2), Ok(order));
        assert_eq!(read_world_command(&msg, 0, 5, 2), Err(Rejection::Sender));
        assert_eq!(read_world_command(&msg, 1, 5, 1), Err(Rejection::Content));
        let mut m = msg;
        m.args[2] = f64::INFINITY;
        assert_eq!(read_world_command(&m, 1, 5, 2), Err(Rejection::Content));
        let none = WorldOrder { action: None, ..order };
        assert_eq!(read_world_command(&world_command(&none, 1, 5), 1, 5, 2), Ok(none));
    }
}
