"""A ROS 2 robot as the world: a corridor robot written with zenoh-ros2-sdk
(an implementation of rmw_zenoh's wire format no one here wrote,
``ros2/corridor_robot.py``) is learned in plan space through
``learnpnp-supervisor --ros2 MAPPING`` (the world ``learnpnp-ros2-world MAPPING``), the mapping
being ``ros2/corridor.toml``. The robot's message definitions are shipped in
``ros2/msgs``: nothing is downloaded.

Every Zenoh session contacts only 127.0.0.1: this test's router listens on a
free port there with multicast scouting and gossip off, and the robot and the
world connect to it alone.

The corridor has five cells and costs -1 a step, so the best return is -4
(four steps forward); the greedy episodes after learning must all earn it.
A robot that sends a malformed CDR payload and a message under a wrong type
hash gets both refused and counted, and the run goes on to the optimum.

The plan's state reaches the same independent peer as ROS 2 topics, as
PNPros published it: the robot subscribes with zenoh-ros2-sdk to
``/learnpnp/agent1/pnp/currentActivePlaces``, ``.../runningActions`` and
``.../choices``, which the world republishes from the agent's live feed.
"""

import json
import os
import pathlib
import re
import socket
import subprocess
import sys
import time

import pytest

zenoh = pytest.importorskip("zenoh")
pytest.importorskip("zenoh_ros2_sdk")

ROOT = pathlib.Path(__file__).resolve().parents[2]
HERE = pathlib.Path(__file__).resolve().parent / "ros2"
GREEDY = 5


@pytest.fixture
def ros2_world(built_beside):
    """The `learnpnp-ros2-world` built beside the supervisor."""
    return built_beside("learnpnp-ros2-world")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def router():
    """A Zenoh router on 127.0.0.1 (rmw_zenohd's role): its port."""
    port = free_port()
    conf = zenoh.Config()
    conf.insert_json5("mode", '"router"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/gossip/enabled", "false")
    conf.insert_json5("listen/endpoints", f'["tcp/127.0.0.1:{port}"]')
    conf.insert_json5("connect/endpoints", "[]")
    session = zenoh.open(conf)
    yield port
    session.close()


def start_robot(port, sandbox, *args):
    robot = subprocess.Popen(
        [sys.executable, str(HERE / "corridor_robot.py"), "--port", str(port), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "TMPDIR": str(sandbox)},
    )
    line = robot.stdout.readline()
    assert line.strip() == "ready", robot.stderr.read()
    return robot


def stop(robot):
    robot.terminate()
    try:
        robot.wait(timeout=10)
    except subprocess.TimeoutExpired:
        robot.kill()
        robot.wait()


def mapping(sandbox, port, name, timeout_ms=None):
    text = (HERE / name).read_text()
    if timeout_ms is not None:
        text = text.replace("timeout_ms = 5000", f"timeout_ms = {timeout_ms}")
    text = text.replace("tcp/127.0.0.1:7447", f"tcp/127.0.0.1:{port}")
    text = text.replace('file = "msgs/', f'file = "{HERE}/msgs/')
    path = sandbox / name
    path.write_text(text)
    return path


def learn(supervisor, sandbox, port, name, seed, mapping_name="corridor.toml", episodes=150, extra=(), timeout_ms=None):
    out, ipc = sandbox / name, sandbox / "ipc"
    plan = str(ROOT / "plans" / "ros2" / "corridor.pnml")
    command = [supervisor, "--ros2", str(mapping(sandbox, port, mapping_name, timeout_ms)), "--plan", plan]
    command += ["--algo", "q-learning", "--episodes", str(episodes), "--eval-every", str(episodes)]
    command += ["--eval-episodes", "0", "--greedy-episodes", str(GREEDY), "--seed", seed, "--out", str(out)]
    command += ["--floor-round-trips", "200", *extra]
    done = subprocess.run(
        command, env={**os.environ, "LEARNPNP_IPC_DIR": str(ipc)}, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"], summary
    left = [f for f in os.listdir("/dev/shm") if any(f.startswith(p) for p in summary["ipc_prefixes"])]
    assert left == [], left
    # The world's last report line in its log: its refusals and counts.
    log = (out / "runs" / "run-0" / "world.log").read_text().splitlines()
    counts = [line for line in log if line.startswith("learnpnp-ros2-world: {")]
    assert counts, log[-5:]
    return summary, json.loads(counts[-1].split(": ", 1)[1])


def test_a_ros2_corridor_robot_is_learned_to_the_optimum_and_bad_messages_are_refused(
    supervisor, ros2_world, sandbox, router
):
    echoed = sandbox / "plan_state.jsonl"
    robot = start_robot(router, sandbox, "--faults", "3", "--plan-state", str(echoed))
    try:
        summary, counts = learn(supervisor, sandbox, router, "corridor", "1")
    finally:
        stop(robot)
    assert summary["experiment"]["final_greedy_mean"] == -4.0, "the greedy walk goes straight forward"
    assert counts["malformed_cdr"] == 1, counts
    assert counts["wrong_type"] == 1, counts
    assert counts["timeouts"] == 0, counts
    assert counts["steps"] >= 150 * 4, counts
    assert counts["resets"] >= 150 + GREEDY, counts
    check_plan_state(echoed, counts["plan_state"])


def check_plan_state(echoed, counts):
    """What the robot received of the agent's plan state, against the plan's
    own labels (read from its PNML here) and the world's counts."""
    pnml = (ROOT / "plans" / "ros2" / "corridor.pnml").read_text()
    places = set(re.findall(r"<place id=[^>]*>.*?<name>\s*<value>([^<]*)</value>", pnml, re.S))
    actions = {p[: -len(".exec")] for p in places if p.endswith(".exec")}
    assert actions == {"forward", "back"}, places
    transitions = set(re.findall(r"<transition id=[^>]*>.*?<name>\s*<value>([^<]*)</value>", pnml, re.S))
    got = {"currentActivePlaces": [], "runningActions": [], "choices": []}
    for line in echoed.read_text().splitlines():
        message = json.loads(line)
        if message["topic"] in got:
            got[message["topic"]].append(message["data"])
    assert got["currentActivePlaces"], counts
    for data in got["currentActivePlaces"]:
        assert data and set(data.split(",")) <= places, data
    # The markings are sampled where the learner sees them (at most 30 a
    # second): the actions' names when any runs, empty otherwise.
    assert abs(len(got["runningActions"]) - len(got["currentActivePlaces"])) <= 1, got
    assert {a for data in got["runningActions"] for a in data.split(",") if a} <= actions, got
    choices = [json.loads(data) for data in got["choices"]]
    assert choices, counts
    for choice in choices:
        # Each option is named by the transition that leads to it, as `learnpnp values` names it.
        names = [o["name"] for o in choice["options"]]
        assert set(names) <= transitions, (choice, transitions)
        assert choice["choice"] in places and choice["chosen"] in names, choice
        assert all(o["value"] is None or isinstance(o["value"], float) for o in choice["options"]), choice
    # Once learned, the options have values, and going forward is worth more than going back.
    last = [c for c in choices if all(o["value"] is not None for o in c["options"])][-1]
    value = {o["name"]: o["value"] for o in last["options"]}
    assert value["forward.start"] > value["back.start"], last
    assert counts["unreadable"] is None, counts
    assert counts["feed"]["received"] > 0, counts
    assert sum(counts["feed"]["rejected"].values()) == 0, counts
    assert counts["republished"]["choices"] >= len(choices), counts
    assert counts["republished"]["refused"] == counts["republished"]["failed"] == 0, counts


def test_plan_actions_as_ros2_action_goals_run_to_their_results_on_an_sdk_robot(
    supervisor, ros2_world, sandbox, router
):
    """The same corridor, each move a goal of the ROS 2 action /corridor/move
    whose server the robot makes of zenoh-ros2-sdk's service servers and
    publishers (the SDK has no actions), the synthesized types' hashes by
    rosbags: every goal is accepted and runs to its result (a hash that
    differed from the world's would put the robot's services on other keys,
    and every goal would time out), its feedback and statuses are taken, and
    the agent still learns the optimum. The robot's one malformed payload,
    one wrong type hash and one goal status action_msgs does not define are
    each refused and counted. The robot holds its fifth goal: the world's
    get_result times out (1 s here), the world cancels the goal through
    _action/cancel_goal, the robot cancels it, and the run goes on."""
    robot = start_robot(router, sandbox, "--action", "--faults", "3", "--stall", "5")
    try:
        summary, counts = learn(supervisor, sandbox, router, "action", "2", "corridor_action.toml", timeout_ms=1000)
    finally:
        stop(robot)
    assert robot.stdout.read().split() == ["canceled", "1"], "the held goal is canceled by the world"
    assert summary["experiment"]["final_greedy_mean"] == -4.0, "the greedy walk goes straight forward"
    for refusal in ("goals_rejected", "bad_attachment"):
        assert counts[refusal] == 0, counts
    for refusal in ("unknown_action_status", "wrong_type", "malformed_cdr"):
        assert counts[refusal] == 1, counts
    # The held goal: its get_result times out, and the action fails: a failed
    # action waits for no answer after it (the move the robot never made).
    assert counts["timeouts"] == 1, counts
    assert counts["failed_actions"] == 1, counts
    assert counts["steps"] >= 150 * 4, counts
    # One feedback message a goal; the last ones may still be on their way when the world stops.
    assert counts["steps"] - 3 <= counts["feedback"] <= counts["steps"] - 1, counts


def test_in_real_time_the_robot_is_commanded_at_its_rate_and_latencies_are_recorded(
    supervisor, ros2_world, sandbox, router
):
    """The supervisor's real-time mode with the world's cycle the robot's
    rate (--world-period-ms 50: a 20 Hz robot): the robot, which logs the
    wall-clock time of each command it gets, is commanded once a cycle (the
    median gap between its commands is the period, within scheduling
    jitter), the run writes its latency histograms, and each action the
    robot is commanded in an episode shows on the plan's ``runningActions``
    in that episode."""
    period_ms = 50
    log = sandbox / "commands.log"
    timeline = sandbox / "plan_state.jsonl"
    robot = start_robot(router, sandbox, "--log", str(log), "--plan-state", str(timeline))
    try:
        extra = ("--mode", "realtime", "--world-period-ms", str(period_ms))
        summary, counts = learn(supervisor, sandbox, router, "realtime", "3", episodes=3, extra=extra)
    finally:
        stop(robot)
    assert summary["mode"] == "realtime", summary
    times = [int(line) for line in log.read_text().split()]
    assert len(times) >= 20, times
    gaps_ms = sorted((b - a) / 1e6 for a, b in zip(times, times[1:]))
    median = gaps_ms[len(gaps_ms) // 2]
    assert 0.9 * period_ms <= median <= 1.3 * period_ms, gaps_ms
    assert 0.6 * 1000 / period_ms <= summary["cycles_per_second"] <= 1.05 * 1000 / period_ms, summary
    assert counts["timeouts"] == 0, counts
    latency = sandbox / "realtime" / "latency"
    for histogram in ("roundtrip", "world-turnaround", "compute", "floor"):
        assert (latency / f"{histogram}.hgrm").stat().st_size > 0, histogram
    assert summary["latency_us"]["p50"] > 0, summary
    check_running_actions(timeline)


def check_running_actions(timeline):
    """Every action the robot was commanded in an episode, it saw on
    ``runningActions`` in the same episode (the robot's timeline cut at its
    resets): the plan's state shows the action a robot is executing."""
    episodes = []
    for line in timeline.read_text().splitlines():
        message = json.loads(line)
        if message["topic"] == "reset":
            episodes.append({"commanded": set(), "shown": set()})
        elif episodes and message["topic"] == "command":
            episodes[-1]["commanded"].add(message["data"])
        elif episodes and message["topic"] == "runningActions":
            episodes[-1]["shown"].update(a for a in message["data"].split(",") if a)
    played = [e for e in episodes if e["commanded"]]
    # 3 learning episodes and the greedy ones, each of 4 moves at least.
    assert len(played) >= 3 + GREEDY, episodes
    for episode in played:
        assert episode["commanded"] <= episode["shown"], (episode, episodes)


def ros2_world_pids(marker):
    """The `learnpnp-ros2-world` processes whose command line names `marker`."""
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                argv = (pathlib.Path("/proc") / entry / "cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if argv and argv[0].endswith(b"learnpnp-ros2-world") and any(marker.encode() in a for a in argv):
                pids.append(int(entry))
    return pids


def test_a_killed_ros2_world_is_restarted_and_the_robot_is_still_learned(supervisor, ros2_world, sandbox, router):
    """The ROS 2 world restarts as any world does: killed mid-run, the
    supervisor starts another, which reconnects to the robot, and the agent
    still learns the optimum."""
    robot = start_robot(router, sandbox, "--log", str(sandbox / "commands.log"))
    name, episodes = "restarted", 600
    out, ipc = sandbox / name, sandbox / "ipc"
    plan = str(ROOT / "plans" / "ros2" / "corridor.pnml")
    mapping_file = mapping(sandbox, router, "corridor.toml")
    command = [supervisor, "--ros2", str(mapping_file), "--plan", plan, "--algo", "q-learning"]
    command += ["--episodes", str(episodes), "--eval-every", str(episodes), "--eval-episodes", "0"]
    command += ["--greedy-episodes", str(GREEDY), "--seed", "4", "--out", str(out), "--floor-round-trips", "200"]
    run = subprocess.Popen(
        command,
        env={**os.environ, "LEARNPNP_IPC_DIR": str(ipc)},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        log = sandbox / "commands.log"
        deadline = time.time() + 60
        # Killed once the robot has been commanded for a while.
        while not (log.exists() and len(log.read_text().split()) >= 200):
            assert time.time() < deadline and run.poll() is None, "the run never commanded the robot"
            time.sleep(0.05)
        pids = ros2_world_pids(str(mapping_file))
        assert len(pids) == 1, pids
        os.kill(pids[0], 9)
        _, stderr = run.communicate(timeout=120)
    finally:
        if run.poll() is None:
            run.kill()
        stop(robot)
    assert run.returncode == 0, stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"], summary
    assert summary["restarts"] >= 1, summary
    assert summary["experiment"]["final_greedy_mean"] == -4.0, summary
    left = [f for f in os.listdir("/dev/shm") if any(f.startswith(p) for p in summary["ipc_prefixes"])]
    assert left == [], left
