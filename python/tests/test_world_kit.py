"""learnpnp.world.serve() end to end, with no Rust: the test creates a private
iceoryx2 namespace and the run's services with the supervisor's limits, starts
a world serving a small corridor in a subprocess (this file run as a script),
and plays the supervisor and the agent with the kit's ctypes types.

Run as a script, this file is that world (the ``LEARNPNP_*`` variables say
which run).
"""

import ctypes
import glob
import math
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import time

import gymnasium as gym
import iceoryx2 as iox
import pytest

from learnpnp import world
from learnpnp.world import ActionStatus, ControlCommand, EpisodeStatus, Reject, State

HERE = os.path.dirname(os.path.abspath(__file__))
LENGTH = 20
ATOMS = [f"at_{i}" for i in range(LENGTH)]
FLUENTS = ["progress"]
ACTIONS = ["left", "right"]
LEFT, RIGHT = 0, 1
SEED = 12345
RUN_ID = 0xC0FFEE_0000_0001
READY_PID = 4242
TIMEOUT_S = 5.0
#: Set (milliseconds) in the world's environment, its first step takes that long.
SLOW_FIRST_STEP = "LEARNPNP_TEST_SLOW_FIRST_STEP_MS"


class Corridor(gym.Env):
    """A corridor of LENGTH cells, entered in its first half at random; the last cell pays 1 and ends it."""

    observation_space = gym.spaces.Discrete(LENGTH)
    action_space = gym.spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.position = int(self.np_random.integers(0, LENGTH // 2))
        return self.position, {}

    def step(self, action):
        slow_ms = int(os.environ.pop(SLOW_FIRST_STEP, "0"))
        if slow_ms:
            time.sleep(slow_ms / 1000)
        self.position = min(max(self.position + (1 if action == RIGHT else -1), 0), LENGTH - 1)
        done = self.position == LENGTH - 1
        return self.position, float(done), done, False, {}


def serve_corridor():
    """This file as a script: the corridor served as the run's world."""
    world.serve(
        Corridor(),
        atoms=lambda position: {f"at_{position}"},
        actions=ACTIONS,
        atom_names=ATOMS,
        fluents=lambda position: [position / (LENGTH - 1)],
        fluent_names=FLUENTS,
    )


def start_positions(count):
    """The corridor's first ``count`` starts with the run's seed, as the world draws them."""
    env = Corridor()
    return [env.reset(seed=SEED if i == 0 else None)[0] for i in range(count)]


# -- the supervisor's and agent 0's side -------------------------------------------

POINT_TO_POINT = dict(publishers=4, subscribers=4, buffer=32)
SHARED = dict(publishers=16, subscribers=16, buffer=256)


def run_environment(prefix, root, clock, wait, period_ms=0):
    """The ``LEARNPNP_*`` variables of a run of one agent."""
    return dict(
        LEARNPNP_IPC_PREFIX=prefix,
        LEARNPNP_IPC_ROOT=root,
        LEARNPNP_RUN_ID=str(RUN_ID),
        LEARNPNP_AGENTS="1",
        LEARNPNP_CLOCK=clock,
        LEARNPNP_PERIOD_MS=str(period_ms),
        LEARNPNP_WAIT=wait,
        LEARNPNP_SEED=str(SEED),
    )


def received(sample, payload):
    """A copy of a sample's payload."""
    return payload.from_buffer_copy(ctypes.string_at(sample.payload_ptr, ctypes.sizeof(payload)))


class Run:
    """A private namespace, the run's services as the supervisor creates them,
    and the ports of the supervisor and of agent 0."""

    def __init__(self):
        self.prefix = f"lpt{secrets.token_hex(4)}_"
        self.root = tempfile.mkdtemp(prefix="lpt") + "/"
        self.config = iox.config.default()
        self.config.global_cfg.prefix = iox.FileName.new(self.prefix)
        self.config.global_cfg.root_path = iox.Path.new(self.root)
        self.node = (
            iox.NodeBuilder.new()
            .config(self.config)
            .signal_handling_mode(iox.SignalHandlingMode.Disabled)
            .create(iox.ServiceType.Ipc)
        )
        self.services = []
        self.vocabulary = self.subscriber("learnpnp/world/vocabulary", world.WorldVocabulary, SHARED)
        self.snapshots = self.subscriber("learnpnp/world/agent/0/snapshot", world.WorldSnapshot, POINT_TO_POINT)
        self.commands = self.publisher("learnpnp/world/agent/0/command", world.WorldCommand, POINT_TO_POINT)
        self.reports = self.publisher("learnpnp/agent-report", world.AgentReport, SHARED)
        self.heartbeats = self.subscriber("learnpnp/heartbeat", world.Heartbeat, SHARED)
        self.control = self.publisher("learnpnp/control", world.Control, SHARED)
        self.wake_world = self.event("learnpnp/wake/world").notifier_builder().create()
        self.wake_agent = self.event("learnpnp/wake/agent-0").listener_builder().create()
        self.process = None
        self.last_heartbeat = None
        self.control_sequence = 0

    def pubsub(self, name, payload, limits):
        service = (
            self.node.service_builder(iox.ServiceName.new(name))
            .publish_subscribe(payload)
            .max_publishers(limits["publishers"])
            .max_subscribers(limits["subscribers"])
            .max_nodes(32)
            .history_size(0)
            .subscriber_max_buffer_size(limits["buffer"])
            .enable_safe_overflow(True)
            .create()
        )
        self.services.append(service)
        return service

    def publisher(self, name, payload, limits):
        return self.pubsub(name, payload, limits).publisher_builder().create()

    def subscriber(self, name, payload, limits):
        return self.pubsub(name, payload, limits).subscriber_builder().create()

    def event(self, name):
        service = (
            self.node.service_builder(iox.ServiceName.new(name))
            .event()
            .max_listeners(2)
            .max_notifiers(16)
            .max_nodes(32)
            .create()
        )
        self.services.append(service)
        return service

    def start_world(self, clock, wait, period_ms=0, **more):
        self.process = subprocess.Popen(
            [sys.executable, __file__],
            env={**os.environ, **run_environment(self.prefix, self.root, clock, wait, period_ms), **more},
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    def poll(self, receive, what, timeout=TIMEOUT_S):
        """Polls ``receive`` until it returns something."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            value = receive()
            if value is not None:
                return value
            if self.process is not None and self.process.poll() is not None:
                code, stderr = self.process.returncode, self.process.stderr.read()
                pytest.fail(f"the world exited ({code}) waiting for {what}:\n{stderr}")
            time.sleep(0.0005)
        pytest.fail(f"no {what} within {timeout} s")

    def receive(self, subscriber, payload):
        sample = subscriber.receive()
        return None if sample is None else received(sample, payload)

    def vocabulary_names(self):
        """Every name of the vocabulary, once all its parts have come."""
        parts = {}
        while True:
            part = self.poll(lambda: self.receive(self.vocabulary, world.WorldVocabulary), "vocabulary")
            parts[part.part] = part
            if len(parts) == part.parts:
                break
        names = []
        for index in range(len(parts)):
            part = parts[index]
            assert (part.first, part.header.sender, part.header.run_id) == (len(names), world.SENDER_WORLD, RUN_ID)
            names += [bytes(part.names[i]).rstrip(b"\0").decode() for i in range(part.count)]
            assert not any(any(part.names[i]) for i in range(part.count, world.NAMES_PER_PART))
        assert (part.atoms, part.fluents, part.actions, part.agents) == (LENGTH, 1, 2, 1)
        return names

    def snapshot(self):
        return self.poll(lambda: self.receive(self.snapshots, world.WorldSnapshot), "snapshot")

    def no_snapshot_for(self, seconds):
        time.sleep(seconds)
        assert self.receive(self.snapshots, world.WorldSnapshot) is None

    def heartbeat(self, after_s=0.25):
        """The newest heartbeat, read ``after_s`` from now (heartbeats come every 100 ms)."""
        time.sleep(after_s)
        while (beat := self.receive(self.heartbeats, world.Heartbeat)) is not None:
            self.last_heartbeat = beat
        return self.last_heartbeat

    def command(self, snapshot, action, **changes):
        """Answers ``snapshot`` with ``action``; ``changes`` spoil the command's fields."""
        header = world.Header(version=world.PROTOCOL_VERSION, sender=0, run_id=RUN_ID)
        msg = world.WorldCommand(
            header=header, episode=snapshot.episode, cycle=snapshot.cycle, compute_ns=1000, action=action
        )
        for field, value in changes.items():
            target = msg.header if field in ("version", "sender", "run_id") else msg
            if field == "args":
                msg.args[:] = value
            else:
                setattr(target, field, value)
        self.commands.send_copy(msg)
        self.wake_world.notify()

    def report_ready(self, pid, sender=0):
        header = world.Header(version=world.PROTOCOL_VERSION, sender=sender, run_id=RUN_ID)
        self.reports.send_copy(world.AgentReport(header=header, kind=world.Report.READY, pid=pid))
        self.wake_world.notify()

    def order(self, command, target=ControlCommand.ALL, pid=0, run_id=RUN_ID):
        self.control_sequence += 1
        header = world.Header(version=world.PROTOCOL_VERSION, sender=world.SENDER_SUPERVISOR, run_id=run_id)
        order = world.Control(header=header, command=command, target=target, sequence=self.control_sequence, pid=pid)
        self.control.send_copy(order)
        self.wake_world.notify()

    def stop_world(self):
        """STOP; the world must say it is stopping, exit 0 and leave no dead node behind."""
        self.order(ControlCommand.STOP)
        states, end = [], time.monotonic() + TIMEOUT_S
        while self.process.poll() is None and time.monotonic() < end:
            # Read while the world lives: a sample whose publisher is gone is lost.
            while (beat := self.receive(self.heartbeats, world.Heartbeat)) is not None:
                states.append(beat.state)
            time.sleep(0.002)
        try:
            code = self.process.wait(timeout=0.1)
        except subprocess.TimeoutExpired:
            pytest.fail("the world did not stop within 5 s")
        assert code == 0, self.process.stderr.read()
        assert states and states[-1] == State.STOPPING
        nodes = iox.Node.list(iox.ServiceType.Ipc, self.config)
        assert len(nodes) == 1 and isinstance(nodes[0], iox.NodeState.Alive), "the world removed its node"

    def close(self):
        """Stops the world if it runs, releases every port, and removes the namespace."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        for port in (self.wake_agent, self.wake_world, self.control, self.heartbeats, self.reports):
            port.delete()
        for port in (self.commands, self.snapshots, self.vocabulary):
            port.delete()
        self.services.clear()
        self.node = None
        for path in glob.glob(f"/dev/shm/{self.prefix}*"):
            os.remove(path)
        shutil.rmtree(self.root)


@pytest.fixture
def run():
    before = set(glob.glob("/dev/shm/lpt*"))
    run = Run()
    try:
        yield run
    finally:
        run.close()
    assert glob.glob(f"/dev/shm/{run.prefix}*") == []
    assert set(glob.glob("/dev/shm/lpt*")) <= before
    assert not os.path.exists(run.root)


def atoms_of(snapshot):
    """The names of the atoms a snapshot says hold."""
    return {ATOMS[i] for i in range(256) if snapshot.atoms[i // 64] >> (i % 64) & 1}


def test_lockstep_episodes_refusals_loss_and_stop(run):
    starts = start_positions(3)
    run.start_world("lockstep", "block")
    assert run.vocabulary_names() == ATOMS + FLUENTS + ACTIONS
    assert run.heartbeat().state == State.READY
    run.no_snapshot_for(0.05)  # not before the agent is ready
    run.report_ready(READY_PID)

    first = run.snapshot()
    header = first.header
    assert (header.version, header.sender, header.run_id) == (world.PROTOCOL_VERSION, world.SENDER_WORLD, RUN_ID)
    assert (first.episode, first.cycle, first.step, first.agent) == (1, 1, 0, 0)
    assert (first.episode_status, first.action_status, first.reward) == (EpisodeStatus.RUNNING, ActionStatus.NONE, 0.0)
    assert atoms_of(first) == {f"at_{starts[0]}"}
    assert first.fluents[0] == pytest.approx(starts[0] / (LENGTH - 1)) and not any(first.fluents[1:])
    assert (first.answer_cycle, first.answer_received_ns, bytes(first.reserved)) == (0, 0, bytes(6))
    assert run.wake_agent.try_wait(), "the world wakes a blocking agent after each snapshot"

    # Refused commands, each counted by its reason and none applied.
    expected = [0] * Reject.COUNT
    for spoil, reason in [
        (dict(version=world.PROTOCOL_VERSION + 1), Reject.VERSION),
        (dict(run_id=RUN_ID + 1), Reject.RUN),
        (dict(sender=1), Reject.SENDER),
        (dict(action=len(ACTIONS)), Reject.CONTENT),
        (dict(args=[0.0, math.nan, 0.0, 0.0]), Reject.CONTENT),
        (dict(args=[math.inf, 0.0, 0.0, 0.0]), Reject.CONTENT),
        (dict(reserved=1), Reject.CONTENT),
        (dict(cycle=first.cycle + 5), Reject.SEQUENCE),
        (dict(episode=2), Reject.SEQUENCE),
    ]:
        run.command(first, spoil.pop("action", RIGHT), **spoil)
        expected[reason] += 1
    run.report_ready(READY_PID, sender=7)
    expected[Reject.SENDER] += 1
    run.order(ControlCommand.STOP, run_id=RUN_ID + 1)
    expected[Reject.RUN] += 1
    run.no_snapshot_for(0.05)

    sent_ns = time.monotonic_ns()
    run.command(first, RIGHT)
    second = run.snapshot()
    assert (second.episode, second.cycle, second.step) == (1, 2, 1)
    assert atoms_of(second) == {f"at_{starts[0] + 1}"}, "exactly one step: no refused command was applied"
    assert (second.action_status, second.episode_status) == (ActionStatus.FINISHED, EpisodeStatus.RUNNING)
    assert second.reward == 0.0
    assert second.answer_cycle == first.cycle
    assert sent_ns <= second.answer_received_ns <= second.sent_ns <= time.monotonic_ns()

    # Walk to the end: TERMINATED with the reward, then held until acknowledged.
    snapshot = second
    while snapshot.episode_status == EpisodeStatus.RUNNING:
        run.command(snapshot, RIGHT)
        snapshot = run.snapshot()
    assert (snapshot.episode_status, snapshot.reward) == (EpisodeStatus.TERMINATED, 1.0)
    assert snapshot.step == LENGTH - 1 - starts[0]
    assert atoms_of(snapshot) == {f"at_{LENGTH - 1}"}
    run.no_snapshot_for(0.05)
    run.command(snapshot, world.NO_ACTION)

    # Episode 2 (the world's own generator): the plan ends it with NO_ACTION.
    snapshot = run.snapshot()
    assert (snapshot.episode, snapshot.step, snapshot.episode_status) == (2, 0, EpisodeStatus.RUNNING)
    assert atoms_of(snapshot) == {f"at_{starts[1]}"}
    run.command(snapshot, LEFT)
    snapshot = run.snapshot()
    run.command(snapshot, world.NO_ACTION)
    ended = run.snapshot()
    assert (ended.episode, ended.step) == (2, 1)
    assert (ended.episode_status, ended.action_status) == (EpisodeStatus.TRUNCATED, ActionStatus.NONE)
    run.command(ended, RIGHT)  # an end is acknowledged with NO_ACTION only
    expected[Reject.CONTENT] += 1
    run.no_snapshot_for(0.05)
    run.command(ended, world.NO_ACTION)
    third = run.snapshot()
    assert (third.episode, third.step, atoms_of(third)) == (3, 0, {f"at_{starts[2]}"})

    beat = run.heartbeat()
    assert (beat.header.sender, beat.pid, beat.state) == (world.SENDER_WORLD, run.process.pid, State.RUNNING)
    assert (list(beat.rejected), beat.episodes, beat.cycles, beat.missed_deadlines) == (expected, 2, third.cycle, 0)

    # The agent is lost: ABORTED, then a new episode once its replacement (pid 777) is ready.
    run.order(ControlCommand.KEEPER_LOST, target=0, pid=777)
    aborted = run.snapshot()
    assert (aborted.episode, aborted.cycle, aborted.episode_status) == (3, third.cycle + 1, EpisodeStatus.ABORTED)
    run.report_ready(READY_PID)  # the lost process's readiness does not count
    run.vocabulary_names()  # announced again meanwhile
    run.no_snapshot_for(0.1)
    run.report_ready(777)
    fourth = run.snapshot()
    assert (fourth.episode, fourth.step, fourth.episode_status) == (4, 0, EpisodeStatus.RUNNING)
    assert run.heartbeat().aborted_episodes == 1

    run.stop_world()


def test_realtime_waits_a_period_repeats_the_last_action_and_drops_late_commands(run):
    period_ms = 40
    start = start_positions(1)[0]
    run.start_world("realtime", "hybrid", period_ms)
    run.vocabulary_names()
    run.report_ready(READY_PID)

    first = run.snapshot()
    second = run.snapshot()  # unanswered at the episode's first step: the world waited a period
    assert (second.cycle, second.step, atoms_of(second)) == (first.cycle + 1, 0, {f"at_{start}"})
    assert (second.sent_ns - first.sent_ns) / 1e6 == pytest.approx(period_ms, abs=15)
    run.command(second, RIGHT)
    third = run.snapshot()
    assert (third.step, atoms_of(third)) == (1, {f"at_{start + 1}"})
    assert (third.sent_ns - second.sent_ns) / 1e6 == pytest.approx(period_ms, abs=15)
    fourth = run.snapshot()  # unanswered: the last action again
    assert (fourth.step, atoms_of(fourth)) == (2, {f"at_{start + 2}"})
    run.command(third, LEFT)  # late: dropped, not refused
    fifth = run.snapshot()
    assert (fifth.step, atoms_of(fifth)) == (3, {f"at_{start + 3}"})

    beat = run.heartbeat(after_s=0.15)
    assert list(beat.rejected) == [0] * Reject.COUNT
    assert beat.missed_deadlines >= 3
    run.stop_world()


def test_realtime_a_late_cycle_is_counted_and_the_next_keeps_the_grid(run):
    period_ms = 100
    run.start_world("realtime", "hybrid", period_ms, **{SLOW_FIRST_STEP: str(period_ms * 5 // 2)})
    run.vocabulary_names()
    run.report_ready(READY_PID)
    first = run.snapshot()
    second = run.snapshot()  # unanswered at the episode's first step
    run.command(second, RIGHT)
    run.snapshot()  # its step took two periods and a half: a late cycle
    later = [run.snapshot() for _ in range(3)]  # unanswered: the last action again
    # Cycle k still ends at t0 + (k + 1) x period: the late cycle moved no deadline.
    for snapshot in later:
        offset_ms = (snapshot.sent_ns - first.sent_ns) % (period_ms * 1_000_000) / 1e6
        assert min(offset_ms, period_ms - offset_ms) < period_ms / 4, offset_ms
    beat = run.heartbeat(after_s=0.15)
    assert beat.late_cycles >= 1
    run.stop_world()


def test_clear_errors_before_any_shared_memory():
    def serve(environ, **changes):
        arguments = dict(atoms=lambda p: {f"at_{p}"}, actions=ACTIONS, atom_names=ATOMS, environ=environ)
        arguments.update(changes)
        world.serve(Corridor(), **arguments)

    good = run_environment("lpt0_", "/nonexistent/", "lockstep", "spin")
    with pytest.raises(world.WorldError, match="LEARNPNP_RUN_ID is not set"):
        serve({k: v for k, v in good.items() if k != "LEARNPNP_RUN_ID"})
    with pytest.raises(world.WorldError, match="LEARNPNP_SEED='-1': expected a decimal u64"):
        serve({**good, "LEARNPNP_SEED": "-1"})
    with pytest.raises(world.WorldError, match="LEARNPNP_WAIT='sleep'"):
        serve({**good, "LEARNPNP_WAIT": "sleep"})
    with pytest.raises(world.WorldError, match="LEARNPNP_PERIOD_MS"):
        serve({**good, "LEARNPNP_CLOCK": "realtime", "LEARNPNP_PERIOD_MS": "fast"})
    with pytest.raises(world.WorldError, match="LEARNPNP_AGENTS=2 but serve.. was given 1 environment"):
        serve({**good, "LEARNPNP_AGENTS": "2"})
    with pytest.raises(world.WorldError, match="257 atoms: a world has at most 256"):
        serve(good, atom_names=[f"a{i}" for i in range(257)])
    with pytest.raises(world.WorldError, match="longer than 32 UTF-8 bytes"):
        serve(good, actions=["left", "é" * 17])
    with pytest.raises(world.WorldError, match="fluents and fluent_names go together"):
        serve(good, fluent_names=["x"])


def test_a_world_outside_a_run_fails_clearly_and_leaves_nothing():
    prefix = f"lpt{secrets.token_hex(4)}_"
    root = tempfile.mkdtemp(prefix="lpt") + "/"
    environ = run_environment(prefix, root, "lockstep", "spin")
    try:
        with pytest.raises(world.WorldError, match="cannot open the run's service"):
            world.serve(Corridor(), atoms=lambda p: set(), actions=ACTIONS, atom_names=ATOMS, environ=environ)
        # Only iceoryx2's management segment of the prefix outlives a node (a run's cleanup removes it).
        assert [p.endswith(".global_mgmt") for p in glob.glob(f"/dev/shm/{prefix}*")] == [True]
    finally:
        for path in glob.glob(f"/dev/shm/{prefix}*"):
            os.remove(path)
        shutil.rmtree(root)
    assert glob.glob(f"/dev/shm/{prefix}*") == []


def test_import_learnpnp_needs_no_iceoryx2_and_the_kit_says_how_to_get_it():
    blocked = "import sys; sys.modules['iceoryx2'] = None; "

    def python(code):  # run from here, so that the installed learnpnp is imported
        return subprocess.run([sys.executable, "-c", blocked + code], capture_output=True, text=True, cwd=HERE)

    plain = python("import learnpnp")
    assert plain.returncode == 0, plain.stderr
    kit = python("import learnpnp.world")
    assert kit.returncode != 0 and "pip install iceoryx2==0.10.0" in kit.stderr


if __name__ == "__main__":
    serve_corridor()
