"""ctypes mirrors of the shared-memory messages of a world in its own process.

Each class lies in memory exactly as its Rust twin in ``shm_layouts/src/lib.rs``
(sizes and offsets are checked against ``shm_layouts/layouts.json`` by the
tests), and its ``type_name()`` is the Rust ``type_name``, so that iceoryx2
connects Python ports to the Rust ones. Tags are plain integers, as in Rust:
anything read from shared memory may hold any bit pattern and is checked
before it is used. Each structure annotates its fields with the Python
types ctypes gives them (``_fields_`` gives the C types).
"""

from __future__ import annotations

import ctypes
from typing import Tuple, Type

#: What ``learnpnp.world`` re-exports: the constants and the message types.
__all__ = [
    "MAX_ACTIONS",
    "MAX_AGENTS",
    "MAX_ARGS",
    "MAX_ATOMS",
    "MAX_FLUENTS",
    "MESSAGE_TYPES",
    "NAME_LEN",
    "NAMES_PER_PART",
    "NO_ACTION",
    "PROTOCOL_VERSION",
    "SENDER_SUPERVISOR",
    "SENDER_WORLD",
    "ActionStatus",
    "AgentReport",
    "Control",
    "ControlCommand",
    "EpisodeStatus",
    "Header",
    "Heartbeat",
    "Reject",
    "Report",
    "State",
    "WorldCommand",
    "WorldSnapshot",
    "WorldVocabulary",
]

#: The version of the protocol; a message with another version is refused.
PROTOCOL_VERSION = 2
#: The ``sender`` of a world's messages (the simulator's).
SENDER_WORLD = 100
#: The ``sender`` of the supervisor's messages.
SENDER_SUPERVISOR = 200
#: ``WorldCommand.action`` naming no action: the plan has ended, or the agent
#: acknowledges the snapshot that ended an episode.
NO_ACTION = 0xFFFF_FFFF

#: Atoms of a world (bits of ``WorldSnapshot.atoms``).
MAX_ATOMS = 256
#: Numeric fluents of a world.
MAX_FLUENTS = 16
#: Numeric arguments of an action.
MAX_ARGS = 4
#: Actions of a world.
MAX_ACTIONS = 256
#: Agents a world serves.
MAX_AGENTS = 16
#: Bytes of a name (UTF-8, zero-padded).
NAME_LEN = 32
#: Names in one ``WorldVocabulary`` message.
NAMES_PER_PART = 16


class EpisodeStatus:
    """Tags of ``WorldSnapshot.episode_status``."""

    RUNNING = 0
    TERMINATED = 1
    TRUNCATED = 2
    ABORTED = 3


class ActionStatus:
    """Tags of ``WorldSnapshot.action_status``: what became of the last action."""

    NONE = 0
    RUNNING = 1
    FINISHED = 2
    FAILED = 3


class State:
    """Tags of ``Heartbeat.state``."""

    STARTING = 1
    READY = 2
    RUNNING = 3
    STOPPING = 4


class Reject:
    """Indices of ``Heartbeat.rejected``: why a message was refused."""

    VERSION = 0
    RUN = 1
    SENDER = 2
    CONTENT = 3
    SEQUENCE = 4
    COUNT = 5


class ControlCommand:
    """Tags of ``Control.command``, and the target of a command for everyone."""

    STOP = 1
    CHECKPOINT = 2
    KEEPER_LOST = 3
    SIM_RESTARTED = 4
    ALL = 0xFFFF_FFFF


class Report:
    """Tags of ``AgentReport.kind``."""

    READY = 1
    ENDED = 2


_u8, _u32, _u64, _f64 = ctypes.c_uint8, ctypes.c_uint32, ctypes.c_uint64, ctypes.c_double


class Header(ctypes.Structure):
    """Begins every message: protocol version, sender, run id."""

    version: int
    sender: int
    run_id: int

    _fields_ = [("version", _u32), ("sender", _u32), ("run_id", _u64)]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::Header"


class WorldSnapshot(ctypes.Structure):
    """One agent's knowledge-base snapshot: world to agent ``agent``."""

    header: Header
    episode: int
    cycle: int
    sent_ns: int
    answer_cycle: int
    answer_received_ns: int
    reward: float
    agent: int
    step: int
    episode_status: int
    action_status: int
    reserved: ctypes.Array[ctypes.c_uint8]
    atoms: ctypes.Array[ctypes.c_uint64]
    fluents: ctypes.Array[ctypes.c_double]

    _fields_ = [
        ("header", Header),
        ("episode", _u64),
        ("cycle", _u64),
        ("sent_ns", _u64),
        ("answer_cycle", _u64),
        ("answer_received_ns", _u64),
        ("reward", _f64),
        ("agent", _u32),
        ("step", _u32),
        ("episode_status", _u8),
        ("action_status", _u8),
        ("reserved", _u8 * 6),
        ("atoms", _u64 * (MAX_ATOMS // 64)),
        ("fluents", _f64 * MAX_FLUENTS),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::WorldSnapshot"


class WorldCommand(ctypes.Structure):
    """An agent's answer to one snapshot: an action index (or ``NO_ACTION``) and its arguments."""

    header: Header
    episode: int
    cycle: int
    compute_ns: int
    action: int
    reserved: int
    args: ctypes.Array[ctypes.c_double]

    _fields_ = [
        ("header", Header),
        ("episode", _u64),
        ("cycle", _u64),
        ("compute_ns", _u64),
        ("action", _u32),
        ("reserved", _u32),
        ("args", _f64 * MAX_ARGS),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::WorldCommand"


class WorldVocabulary(ctypes.Structure):
    """One part of the world's names (atoms, then fluents, then actions)."""

    header: Header
    atoms: int
    fluents: int
    actions: int
    agents: int
    part: int
    parts: int
    first: int
    count: int
    names: ctypes.Array[ctypes.Array[ctypes.c_uint8]]

    _fields_ = [
        ("header", Header),
        ("atoms", _u32),
        ("fluents", _u32),
        ("actions", _u32),
        ("agents", _u32),
        ("part", _u32),
        ("parts", _u32),
        ("first", _u32),
        ("count", _u32),
        ("names", (_u8 * NAME_LEN) * NAMES_PER_PART),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::WorldVocabulary"


class AgentReport(ctypes.Structure):
    """An agent is ready (its pid) or has ended an episode."""

    header: Header
    episode: int
    kind: int
    pid: int
    exploratory: int
    reserved: ctypes.Array[ctypes.c_uint8]

    _fields_ = [
        ("header", Header),
        ("episode", _u64),
        ("kind", _u32),
        ("pid", _u32),
        ("exploratory", _u8),
        ("reserved", _u8 * 7),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::AgentReport"


class Heartbeat(ctypes.Structure):
    """A process is alive, with its counters."""

    header: Header
    pid: int
    state: int
    sequence: int
    episodes: int
    cycles: int
    rejected: ctypes.Array[ctypes.c_uint64]
    missed_deadlines: int
    aborted_episodes: int
    checkpoints: int
    checkpoint_failures: int
    late_cycles: int

    _fields_ = [
        ("header", Header),
        ("pid", _u32),
        ("state", _u32),
        ("sequence", _u64),
        ("episodes", _u64),
        ("cycles", _u64),
        ("rejected", _u64 * Reject.COUNT),
        ("missed_deadlines", _u64),
        ("aborted_episodes", _u64),
        ("checkpoints", _u64),
        ("checkpoint_failures", _u64),
        ("late_cycles", _u64),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::Heartbeat"


class Control(ctypes.Structure):
    """A command of the supervisor."""

    header: Header
    command: int
    target: int
    sequence: int
    pid: int
    reserved: int

    _fields_ = [
        ("header", Header),
        ("command", _u32),
        ("target", _u32),
        ("sequence", _u64),
        ("pid", _u32),
        ("reserved", _u32),
    ]

    @staticmethod
    def type_name() -> str:
        """The Rust type's name."""
        return "learnpnp::Control"


#: Every message type whose layout ``shm_layouts/layouts.json`` lists.
MESSAGE_TYPES: Tuple[Type[ctypes.Structure], ...] = (
    Header,
    WorldSnapshot,
    WorldCommand,
    WorldVocabulary,
    AgentReport,
    Heartbeat,
    Control,
)
