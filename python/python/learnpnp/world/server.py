"""``serve``: a gymnasium environment as the world process of a learnpnp run.

The protocol is the one of ``shm_layouts/README.md``, "A world in its own
process": heartbeats, the vocabulary while agents connect, their readiness,
then episodes of snapshots answered by commands (lock-step or real time),
each command checked and refused by reason when it is wrong.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from typing import (
    Any,
    Callable,
    Dict,
    Generic,
    Iterable,
    List,
    Mapping,
    Optional,
    Protocol,
    Sequence,
    Set,
    SupportsFloat,
    Tuple,
    TypeVar,
    Union,
    cast,
)

from .layouts import (
    MAX_ACTIONS,
    MAX_AGENTS,
    MAX_ATOMS,
    MAX_FLUENTS,
    NAME_LEN,
    NAMES_PER_PART,
    NO_ACTION,
    PROTOCOL_VERSION,
    SENDER_SUPERVISOR,
    SENDER_WORLD,
    ActionStatus,
    AgentReport,
    Control,
    ControlCommand,
    EpisodeStatus,
    Header,
    Heartbeat,
    Reject,
    Report,
    State,
    WorldCommand,
    WorldSnapshot,
    WorldVocabulary,
)
from .ports import WAIT_STRATEGIES, Idle, WorldError, WorldPorts, copy_of

_T = TypeVar("_T")
_Obs = TypeVar("_Obs")
_Obs_co = TypeVar("_Obs_co", covariant=True)

#: A command's action: its index (or ``NO_ACTION``) and its numeric arguments.
_Action = Tuple[int, Tuple[float, ...]]


class WorldEnv(Protocol[_Obs_co]):
    """What ``serve`` needs of an environment: gymnasium's ``reset`` and
    ``step`` (every ``gymnasium.Env`` has them)."""

    def reset(self, *, seed: Optional[int] = None) -> Tuple[_Obs_co, Dict[str, Any]]:
        """Starts an episode: its first observation and an info dict."""
        ...

    def step(self, action: Any, /) -> Tuple[_Obs_co, SupportsFloat, bool, bool, Any]:
        """Takes ``action``: observation, reward, terminated, truncated, info
        (a dict, whose ``action_status`` is read)."""
        ...


#: About how often the world publishes its heartbeat and, while it waits for
#: agents, its vocabulary.
ANNOUNCE_NS = 100_000_000

#: How long the world keeps its ports after its last (STOPPING) heartbeat.
STOPPING_LINGER_S = 0.05

#: ``info["action_status"]`` values a step may report (default ``"finished"``).
ACTION_STATUSES: Dict[str, int] = {
    "running": ActionStatus.RUNNING,
    "finished": ActionStatus.FINISHED,
    "failed": ActionStatus.FAILED,
}


@dataclass(frozen=True)
class RunSettings:
    """What the supervisor tells the world process through its environment."""

    prefix: str
    root: str
    run_id: int
    agents: int
    realtime: bool
    period_ns: int
    wait: str
    seed: int

    @classmethod
    def from_environment(cls, environ: Optional[Mapping[str, str]] = None) -> RunSettings:
        """Reads the ``LEARNPNP_*`` variables (``environ``: default ``os.environ``)."""
        environ = os.environ if environ is None else environ

        def variable(name: str, parse: Callable[[str], _T], expected: str) -> _T:
            text = environ.get(name)
            if text is None:
                raise WorldError(
                    f"{name} is not set: serve() runs in a world process started by "
                    "learnpnp-supervisor --world-cmd COMMAND"
                )
            try:
                return parse(text)
            except ValueError:
                raise WorldError(f"{name}={text!r}: expected {expected}") from None

        def natural(low: int, high: int) -> Callable[[str], int]:
            def parse(text: str) -> int:
                value = int(text, 10)
                if not low <= value <= high:
                    raise ValueError(text)
                return value

            return parse

        def one_of(choices: Tuple[str, ...]) -> Callable[[str], str]:
            def parse(text: str) -> str:
                if text not in choices:
                    raise ValueError(text)
                return text

            return parse

        def prefix(text: str) -> str:
            if not (text.startswith("lp") and text.replace("_", "").isalnum() and text.isascii() and len(text) <= 64):
                raise ValueError(text)
            return text

        def directory(text: str) -> str:
            if not text.endswith("/"):
                raise ValueError(text)
            return text

        u64 = natural(0, 2**64 - 1)
        clock = variable("LEARNPNP_CLOCK", one_of(("lockstep", "realtime")), "lockstep or realtime")
        period_ms = (
            variable("LEARNPNP_PERIOD_MS", natural(1, 3_600_000), "a period in milliseconds (1 or more)")
            if clock == "realtime"
            else 0
        )
        return cls(
            prefix=variable("LEARNPNP_IPC_PREFIX", prefix, "'lp' then letters, digits or '_'"),
            root=variable("LEARNPNP_IPC_ROOT", directory, "a directory ending in '/'"),
            run_id=variable("LEARNPNP_RUN_ID", u64, "a decimal u64"),
            agents=variable("LEARNPNP_AGENTS", natural(1, MAX_AGENTS), f"1 to {MAX_AGENTS} agents"),
            realtime=clock == "realtime",
            period_ns=period_ms * 1_000_000,
            wait=variable("LEARNPNP_WAIT", one_of(WAIT_STRATEGIES), " or ".join(WAIT_STRATEGIES)),
            seed=variable("LEARNPNP_SEED", u64, "a decimal u64"),
        )


def _checked_names(kind: str, given: Iterable[str], limit: int) -> Tuple[str, ...]:
    names = tuple(given)
    if len(names) > limit:
        raise WorldError(f"{len(names)} {kind}: a world has at most {limit}")
    for name in names:
        if not isinstance(name, str) or not name:
            raise WorldError(f"{kind}: {name!r} is not a name (a non-empty str)")
        if len(name.encode("utf-8")) > NAME_LEN:
            raise WorldError(f"{kind}: {name!r} is longer than {NAME_LEN} UTF-8 bytes")
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise WorldError(f"{kind}: named more than once: {', '.join(duplicates)}")
    return names


@dataclass(frozen=True)
class Vocabulary:
    """The world's names: atoms, fluents and actions, each in index order."""

    atoms: Tuple[str, ...]
    fluents: Tuple[str, ...]
    actions: Tuple[str, ...]

    @classmethod
    def checked(cls, atoms: Iterable[str], fluents: Iterable[str], actions: Iterable[str]) -> Vocabulary:
        """The vocabulary of these names, refused if a limit is exceeded."""
        checked_actions = _checked_names("actions", actions, MAX_ACTIONS)
        if not checked_actions:
            raise WorldError("a world has at least one action")
        return cls(
            _checked_names("atoms", atoms, MAX_ATOMS),
            _checked_names("fluents", fluents, MAX_FLUENTS),
            checked_actions,
        )

    def parts(self, header: Header, agents: int) -> List[WorldVocabulary]:
        """The ``WorldVocabulary`` messages that carry every name."""
        names = [*self.atoms, *self.fluents, *self.actions]
        count = math.ceil(len(names) / NAMES_PER_PART)
        parts = []
        for index in range(count):
            first = index * NAMES_PER_PART
            chunk = names[first : first + NAMES_PER_PART]
            part = WorldVocabulary(
                header=header,
                atoms=len(self.atoms),
                fluents=len(self.fluents),
                actions=len(self.actions),
                agents=agents,
                part=index,
                parts=count,
                first=first,
                count=len(chunk),
            )
            for slot, name in enumerate(chunk):
                encoded = name.encode("utf-8")
                part.names[slot][: len(encoded)] = list(encoded)
            parts.append(part)
        return parts


class _Slot(Generic[_Obs]):
    """One agent's environment and where it stands in the episode."""

    RUNNING, ENDED, DONE = "running", "ended", "done"

    #: The environment's latest observation (None before the first episode).
    observation: Optional[_Obs]
    #: ``RUNNING``, ``ENDED`` or ``DONE``.
    phase: str
    #: The steps taken in the episode.
    step: int
    #: An ``EpisodeStatus`` and an ``ActionStatus`` tag.
    episode_status: int
    action_status: int
    command: Optional[_Action]
    last_action: Optional[_Action]

    def __init__(self, env: WorldEnv[_Obs]) -> None:
        self.env = env
        #: The cycle of the last snapshot sent: the cycle its answer must carry.
        self.expected_cycle = 0
        #: The cycle of the agent's last command taken, and when it was read.
        self.answer_cycle, self.answer_received_ns = 0, 0
        self.begin(None)
        self.phase = self.DONE

    def begin(self, observation: Optional[_Obs]) -> None:
        """A new episode from ``observation``."""
        self.observation = observation
        self.phase = self.RUNNING
        self.step = 0
        #: Reward since the last snapshot sent.
        self.reward = 0.0
        self.episode_status = EpisodeStatus.RUNNING
        self.action_status = ActionStatus.NONE
        #: The command taken for ``expected_cycle``, if any.
        self.command = None
        #: The episode has just ended: its last snapshot is due.
        self.end_due = False
        #: Real time: the last action taken (index, args), repeated when a command misses its deadline.
        self.last_action = None

    def end(self, episode_status: int, action_status: int) -> None:
        """The episode has ended with ``episode_status``: its last snapshot is due."""
        self.phase, self.end_due = self.ENDED, True
        self.episode_status, self.action_status = episode_status, action_status


class _World(Generic[_Obs]):
    """The world process: its run, its environments and its counters."""

    def __init__(
        self,
        settings: RunSettings,
        vocabulary: Vocabulary,
        envs: Sequence[WorldEnv[_Obs]],
        atoms: Callable[[_Obs], Iterable[str]],
        fluents: Optional[Callable[[_Obs], Iterable[SupportsFloat]]],
        env_action: Callable[[int, Tuple[float, ...]], Any],
    ) -> None:
        self.settings = settings
        self.vocabulary = vocabulary
        self.slots = [_Slot(env) for env in envs]
        self.atoms = atoms
        self.fluents = fluents
        self.env_action = env_action
        self.atom_index = {name: i for i, name in enumerate(vocabulary.atoms)}
        self.ports = WorldPorts(settings.prefix, settings.root, settings.agents, settings.wait in ("block", "hybrid"))
        self.header = Header(version=PROTOCOL_VERSION, sender=SENDER_WORLD, run_id=settings.run_id)
        self.vocabulary_parts = vocabulary.parts(self.header, settings.agents)
        self.heartbeat = Heartbeat(header=self.header, pid=os.getpid(), state=State.STARTING)
        self.next_heartbeat_ns = 0
        self.next_vocabulary_ns = 0
        self.stop = False
        self.parent = os.getppid()
        #: Agents whose readiness the world waits for.
        self.awaiting: Set[int] = set(range(settings.agents))
        #: The process id the supervisor named for a lost agent's replacement.
        self.expected_pid: Dict[int, int] = {}
        #: The process id of each agent's last readiness report.
        self.ready_pid: Dict[int, int] = {}
        #: The agents lost during the episode in flight.
        self.lost: Set[int] = set()
        self.episode = 0
        self.cycle = 0

    # -- housekeeping: heartbeat, control, reports --------------------------------

    def reject(self, reason: int) -> None:
        """Counts one refused message."""
        self.heartbeat.rejected[reason] += 1

    def housekeeping(self) -> None:
        """The heartbeat if due, then the supervisor's commands and the agents' reports."""
        now = time.monotonic_ns()
        if now >= self.next_heartbeat_ns:
            self.send_heartbeat()
            self.next_heartbeat_ns = now + ANNOUNCE_NS
            if os.getppid() != self.parent:
                # The process that started the world (the supervisor, or the
                # shell it ran the command with) is gone: so is the run.
                self.stop = True
        while (sample := self.ports.control.receive()) is not None:
            self.apply_control(copy_of(sample, Control))
        while (sample := self.ports.reports.receive()) is not None:
            self.apply_report(copy_of(sample, AgentReport))

    def send_heartbeat(self) -> None:
        """Publishes the heartbeat now."""
        self.heartbeat.sequence += 1
        self.heartbeat.cycles = self.cycle
        self.ports.heartbeat.send_copy(self.heartbeat)

    def header_refusal(self, header: Header, sender_allowed: Callable[[int], bool]) -> Optional[int]:
        """Why a message with ``header`` is refused, or None."""
        if header.version != PROTOCOL_VERSION:
            return Reject.VERSION
        if header.run_id != self.settings.run_id:
            return Reject.RUN
        if not sender_allowed(header.sender):
            return Reject.SENDER
        return None

    def apply_control(self, msg: Control) -> None:
        """Acts on one of the supervisor's commands (STOP, KEEPER_LOST), refusing bad ones."""
        refusal = self.header_refusal(msg.header, lambda s: s == SENDER_SUPERVISOR)
        if refusal is None and msg.reserved != 0:
            refusal = Reject.CONTENT
        if refusal is not None:
            self.reject(refusal)
        elif msg.command == ControlCommand.STOP:
            self.stop = self.stop or msg.target in (ControlCommand.ALL, SENDER_WORLD)
        elif msg.command == ControlCommand.KEEPER_LOST and msg.target < self.settings.agents:
            agent = msg.target
            self.expected_pid[agent] = msg.pid
            self.lost.add(agent)
            # The replacement may have said it is ready before this was read.
            if self.ready_pid.get(agent) != msg.pid:
                self.awaiting.add(agent)
        elif msg.command not in (ControlCommand.CHECKPOINT, ControlCommand.SIM_RESTARTED):
            self.reject(Reject.CONTENT)

    def apply_report(self, msg: AgentReport) -> None:
        """Records an agent's readiness; an episode's end report needs nothing from the world."""
        refusal = self.header_refusal(msg.header, lambda s: s < self.settings.agents)
        if refusal is not None:
            self.reject(refusal)
            return
        valid = not any(msg.reserved) and (
            (msg.kind == Report.READY and msg.exploratory == 0)
            or (msg.kind == Report.ENDED and msg.exploratory in (0, 1))
        )
        if not valid:
            self.reject(Reject.CONTENT)
        elif msg.kind == Report.READY:
            agent = msg.header.sender
            self.ready_pid[agent] = msg.pid
            if self.expected_pid.get(agent, msg.pid) == msg.pid:
                self.awaiting.discard(agent)

    # -- commands -------------------------------------------------------------------

    def command_refusal(self, msg: WorldCommand, agent: int) -> Optional[int]:
        """Why agent ``agent``'s command is refused whatever its cycle, or None."""
        refusal = self.header_refusal(msg.header, lambda s: s == agent)
        if refusal is not None:
            return refusal
        in_range = msg.action < len(self.vocabulary.actions) or msg.action == NO_ACTION
        if msg.reserved != 0 or not in_range or not all(math.isfinite(a) for a in msg.args):
            return Reject.CONTENT
        return None

    def read_commands(self) -> None:
        """Takes every command that answers its agent's last snapshot; refuses the others."""
        for agent, slot in enumerate(self.slots):
            subscriber = self.ports.commands[agent]
            while (sample := subscriber.receive()) is not None:
                received_ns = time.monotonic_ns()
                msg = copy_of(sample, WorldCommand)
                refusal = self.command_refusal(msg, agent)
                if refusal is not None:
                    self.reject(refusal)
                    continue
                this_episode = msg.episode == self.episode
                awaited = slot.phase in (_Slot.RUNNING, _Slot.ENDED) and slot.command is None
                if this_episode and awaited and msg.cycle == slot.expected_cycle:
                    if slot.phase == _Slot.ENDED and msg.action != NO_ACTION:
                        self.reject(Reject.CONTENT)  # the end of an episode is acknowledged with NO_ACTION
                        continue
                    slot.command = (msg.action, tuple(msg.args))
                    slot.answer_cycle, slot.answer_received_ns = msg.cycle, received_ns
                elif not (self.settings.realtime and this_episode and msg.cycle < slot.expected_cycle):
                    self.reject(Reject.SEQUENCE)  # (in real time a late command is dropped, not refused)

    def drain_commands(self) -> None:
        """Drops the commands left from an episode that is over, refusing invalid ones."""
        for agent, subscriber in enumerate(self.ports.commands):
            while (sample := subscriber.receive()) is not None:
                refusal = self.command_refusal(copy_of(sample, WorldCommand), agent)
                if refusal is not None:
                    self.reject(refusal)

    # -- snapshots ------------------------------------------------------------------

    def snapshot(self, agent: int, slot: _Slot[_Obs], episode_status: int) -> WorldSnapshot:
        """Agent ``agent``'s snapshot of ``slot`` for the current cycle."""
        msg = WorldSnapshot(
            header=self.header,
            episode=self.episode,
            cycle=self.cycle,
            answer_cycle=slot.answer_cycle,
            answer_received_ns=slot.answer_received_ns,
            reward=slot.reward,
            agent=agent,
            step=slot.step,
            episode_status=episode_status,
            action_status=slot.action_status,
        )
        # Every episode begins with the environment's observation (None only before the first).
        observation = cast(_Obs, slot.observation)
        for name in self.atoms(observation):
            index = self.atom_index.get(name)
            if index is None:
                raise WorldError(f"atoms() returned {name!r}, which is not among atom_names")
            msg.atoms[index // 64] |= 1 << (index % 64)
        if self.fluents is not None:
            values = [float(v) for v in self.fluents(observation)]
            if len(values) != len(self.vocabulary.fluents):
                expected = len(self.vocabulary.fluents)
                raise WorldError(f"fluents() returned {len(values)} values for {expected} fluent_names")
            for i, value in enumerate(values):
                if not math.isfinite(value):
                    raise WorldError(f"fluents() returned {value} for {self.vocabulary.fluents[i]!r}: not finite")
                msg.fluents[i] = value
        msg.sent_ns = time.monotonic_ns()
        return msg

    def publish(self, aborted: bool = False) -> None:
        """Begins a cycle: a snapshot to every agent whose episode goes on or has just ended."""
        self.cycle += 1
        for agent, slot in enumerate(self.slots):
            if aborted or slot.phase == _Slot.RUNNING or slot.end_due:
                if not aborted:
                    slot.expected_cycle, slot.command, slot.end_due = self.cycle, None, False
                status = EpisodeStatus.ABORTED if aborted else slot.episode_status
                self.ports.send_snapshot(agent, self.snapshot(agent, slot, status))
                slot.reward = 0.0

    # -- the world's life -----------------------------------------------------------

    def run(self) -> None:
        """Serves the run until the supervisor says STOP."""
        try:
            self.housekeeping()
            while not self.stop:
                self.wait_ready()
                if not self.stop:
                    self.play_episode()
        finally:
            self.heartbeat.state = State.STOPPING
            self.send_heartbeat()
            # A sample still unread when its publisher goes is lost: give the
            # supervisor (which polls every 10 ms) time to read this last one.
            time.sleep(STOPPING_LINGER_S)
            self.ports.close()

    def wait_ready(self) -> None:
        """Announces the vocabulary until every awaited agent has said it is ready."""
        self.heartbeat.state = State.READY
        idle = Idle(self.settings.wait, self.ports.wake)
        while True:
            self.housekeeping()
            if self.stop or not self.awaiting:
                return
            now = time.monotonic_ns()
            if now >= self.next_vocabulary_ns:
                self.ports.send_vocabulary(self.vocabulary_parts)
                self.next_vocabulary_ns = now + ANNOUNCE_NS
            idle.pause()

    def reset(self, agent: int, slot: _Slot[_Obs]) -> None:
        """Resets ``slot``'s environment: with the run's seed (plus the agent) the first time."""
        seed = self.settings.seed + agent if self.episode == 1 else None
        observation, _info = slot.env.reset(seed=seed)
        slot.begin(observation)

    def play_episode(self) -> None:
        """One episode, from the reset to every agent's acknowledgement of its end
        (or to an agent's loss, or STOP)."""
        self.heartbeat.state = State.RUNNING
        self.drain_commands()
        self.lost.clear()
        self.episode += 1
        for agent, slot in enumerate(self.slots):
            self.reset(agent, slot)
        self.publish()
        deadline_ns = time.monotonic_ns() + self.settings.period_ns
        while True:
            outcome = self.collect(deadline_ns)
            if outcome == "answered" and self.settings.realtime:
                self.advance(missed_deadline=False)
                outcome = "ended" if self.episode_over() else self.sleep_until(deadline_ns)
            elif outcome in ("answered", "deadline"):
                self.advance(missed_deadline=outcome == "deadline")
                outcome = "ended" if self.episode_over() else "next"
            if outcome == "stop":
                return
            if outcome == "lost":
                self.abort()
                return
            if outcome == "ended":
                self.heartbeat.episodes += 1
                return
            self.publish()
            if self.settings.realtime:
                deadline_ns = self.next_deadline(deadline_ns)

    def next_deadline(self, deadline_ns: int) -> int:
        """Real time, once a cycle's snapshots are out: the next cycle's
        deadline on the episode's grid (cycle k ends at t0 + (k + 1) x period).
        A cycle whose work ran past that deadline is late: counted in the
        heartbeat, and the next deadline is the grid's next one ahead (the
        grid is kept; no cycle is squeezed in to catch up)."""
        period = self.settings.period_ns
        deadline_ns += period
        now = time.monotonic_ns()
        if now >= deadline_ns:
            self.heartbeat.late_cycles += 1
            deadline_ns += ((now - deadline_ns) // period + 1) * period
        return deadline_ns

    def abort(self) -> None:
        """An agent was lost: every agent is told the episode is discarded, and
        the world waits for each to say it is ready again (a lost one's
        replacement, with the process id the supervisor named)."""
        self.publish(aborted=True)
        self.heartbeat.aborted_episodes += 1
        self.awaiting.update(a for a in range(self.settings.agents) if a not in self.lost)

    def episode_over(self) -> bool:
        """Whether every agent has acknowledged the end of its episode."""
        return all(slot.phase == _Slot.DONE for slot in self.slots)

    def collect(self, deadline_ns: int) -> str:
        """Waits for the commands of the cycle. Returns ``"answered"`` (all in;
        in real time, acknowledgements of ended episodes may come later),
        ``"deadline"`` (real time: the running agents' deadline passed),
        ``"lost"`` (an agent was lost) or ``"stop"``."""
        idle = Idle(self.settings.wait, self.ports.wake)
        while True:
            self.read_commands()
            running = [s for s in self.slots if s.phase == _Slot.RUNNING]
            unanswered = [s for s in running if s.command is None]
            unacknowledged = [s for s in self.slots if s.phase == _Slot.ENDED and s.command is None]
            if not unanswered and (not unacknowledged or (self.settings.realtime and running)):
                return "answered"
            self.housekeeping()
            if self.stop:
                return "stop"
            if self.lost:
                return "lost"
            if self.settings.realtime and unanswered:
                if time.monotonic_ns() >= deadline_ns:
                    return "deadline"
                idle.pause_until(deadline_ns)
            else:
                idle.pause()

    def sleep_until(self, deadline_ns: int) -> str:
        """Real time: waits for the cycle's end, keeping the heartbeat and control.
        Returns ``"next"``, ``"lost"`` or ``"stop"``."""
        idle = Idle(self.settings.wait, self.ports.wake)
        while time.monotonic_ns() < deadline_ns:
            self.housekeeping()
            if self.stop:
                return "stop"
            if self.lost:
                return "lost"
            idle.pause_until(deadline_ns)
        return "next"

    def advance(self, missed_deadline: bool) -> None:
        """Steps every running environment with its command (real time: the
        last action again if the command missed its deadline); takes the
        acknowledgements of ended episodes."""
        for slot in self.slots:
            if slot.phase == _Slot.ENDED:
                if slot.command is not None:
                    slot.phase = _Slot.DONE
                continue
            if slot.phase != _Slot.RUNNING:
                continue
            if slot.command is None:
                if missed_deadline:
                    self.heartbeat.missed_deadlines += 1
                if slot.last_action is None:
                    continue  # the episode's first step: it waits a period
                action = slot.last_action
            else:
                action = slot.command
            if action[0] == NO_ACTION:  # the agent's plan has ended
                slot.end(EpisodeStatus.TRUNCATED, ActionStatus.NONE)
                continue
            observation, reward, terminated, truncated, info = slot.env.step(self.env_action(*action))
            reward = float(reward)
            if not math.isfinite(reward):
                raise WorldError(f"the environment returned the reward {reward}: not finite")
            slot.observation, slot.last_action = observation, action
            slot.reward += reward
            slot.step += 1
            slot.action_status = self.action_status(info)
            if terminated or truncated:
                slot.end(EpisodeStatus.TERMINATED if terminated else EpisodeStatus.TRUNCATED, slot.action_status)

    @staticmethod
    def action_status(info: Any) -> int:
        """The status of the action a step took, from ``info["action_status"]`` (default finished)."""
        name = info.get("action_status", "finished") if isinstance(info, dict) else "finished"
        if name not in ACTION_STATUSES:
            raise WorldError(f"info['action_status'] is {name!r}: expected one of {', '.join(ACTION_STATUSES)}")
        return ACTION_STATUSES[name]


def serve(
    env: Union[WorldEnv[_Obs], List[WorldEnv[_Obs]], Tuple[WorldEnv[_Obs], ...]],
    atoms: Callable[[_Obs], Iterable[str]],
    actions: Iterable[str],
    *,
    atom_names: Iterable[str],
    fluents: Optional[Callable[[_Obs], Iterable[SupportsFloat]]] = None,
    fluent_names: Iterable[str] = (),
    env_action: Optional[Callable[[int, Tuple[float, ...]], Any]] = None,
    environ: Optional[Mapping[str, str]] = None,
) -> None:
    """Serves ``env`` as the world process of a learnpnp run, until the supervisor says STOP.

    Run it as the run's world command (``learnpnp-supervisor --world-cmd
    'python my_world.py' --plan FILE``); the run comes from the ``LEARNPNP_*``
    environment variables (``environ``: default ``os.environ``).

    - ``env``: a gymnasium environment (``reset(seed=...)``, ``step(action)``
      with five results), or a list of them, one per agent (the run's
      ``LEARNPNP_AGENTS``): each agent then has its own environment and its own
      episode, and the world resets them all once every one has ended.
    - ``atoms(observation)``: the names of the atoms that hold (an iterable of str).
    - ``actions``: the environment's action names, in index order.
    - ``atom_names``: every atom ``atoms`` may name, in the vocabulary's order.
    - ``fluents(observation)``: optional, the numeric fluents (finite floats),
      one per name of ``fluent_names``.
    - ``env_action(index, args)``: optional, what ``env.step`` takes for the
      action ``index`` with the command's 4 numeric arguments; default: the index.

    A step's ``info["action_status"]`` may say ``"running"`` or ``"failed"``
    (default ``"finished"``). The first reset of agent ``a``'s environment uses
    the run's seed plus ``a``, later resets the environment's own generator.
    ``serve`` returns after STOP; closing ``env`` is the caller's. Raises
    ``WorldError`` for a bad argument or environment variable, or when the
    run's services cannot be opened.
    """
    vocabulary = Vocabulary.checked(atom_names, fluent_names, actions)
    if (fluents is None) != (not vocabulary.fluents):
        raise WorldError("fluents and fluent_names go together: give both or neither")
    settings = RunSettings.from_environment(environ)
    envs = list(env) if isinstance(env, (list, tuple)) else [env]
    if len(envs) != settings.agents:
        raise WorldError(
            f"LEARNPNP_AGENTS={settings.agents} but serve() was given {len(envs)} environment(s): "
            "pass one environment per agent as a list"
        )
    world = _World(settings, vocabulary, envs, atoms, fluents, env_action or (lambda index, args: index))
    world.run()
