"""Worlds no one here wrote, each served from a Python process by the world kit
and learned in plan space by a Rust agent process over shared memory
(``learnpnp-supervisor --world-cmd``): gymnasium's Taxi-v4 and MiniGrid's
DoorKey-5x5. The world records every episode it served (``--record``), an
account independent of the agent's.

Taxi is deterministic, so greedy episodes are judged exactly: no policy earns
more from a start state than the optimum (value iteration on gymnasium's own
table), so a greedy mean equal to the optimum's mean over the same start
states means the greedy policy was optimal from every one of them. Taxi's
registered reward_threshold (8) is above that optimum (7.93 on average over
the start states), so no policy reaches it in expectation; the tests assert
the optimum instead (as tests/test_taxi.py does in-process).
"""

import json
import os
import pathlib
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import taxi

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "python" / "examples"
GREEDY = 100

pytest.importorskip("iceoryx2")


def run_world(supervisor, sandbox, name, example, plan, *args):
    """Runs the supervisor with ``example`` as the world; returns the summary
    and the world's record of its episodes."""
    out, ipc, record = sandbox / name, sandbox / "ipc", sandbox / f"{name}.jsonl"
    world = f"{sys.executable} {EXAMPLES / example} --record {record}"
    command = [supervisor, "--world-cmd", world, "--plan", str(ROOT / "plans" / plan)]
    command += ["--out", str(out), "--floor-round-trips", "2000", "--greedy-episodes", str(GREEDY), *args]
    done = subprocess.run(
        command, env={**os.environ, "LEARNPNP_IPC_DIR": str(ipc)}, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"], summary
    left = [f for f in os.listdir("/dev/shm") if any(f.startswith(p) for p in summary["ipc_prefixes"])]
    assert left == [], left
    assert list(ipc.iterdir()) == []
    episodes = [json.loads(line) for line in record.read_text().splitlines()]
    return summary, [e for e in episodes if e["ended"]], out


TAXI = ("--algo", "q-learning", "--alpha", "0.1", "--epsilon", "0.1", "--episodes", "2000")
TAXI += ("--eval-every", "2000", "--eval-episodes", "0", "--wait", "hybrid")


def test_taxi_from_a_python_world_is_learned_to_the_optimum_and_a_seed_repeats(supervisor, sandbox):
    optimum = taxi.optimal_returns(gym.make("Taxi-v4"))
    for seed in ("1", "2", "3"):
        summary, episodes, out = run_world(supervisor, sandbox, f"taxi{seed}", "taxi_world.py", "taxi.pnml", *TAXI,
                                           "--seed", seed)
        greedy = episodes[-GREEDY:]
        assert len(episodes) == 2000 + GREEDY
        world_mean = np.mean([e["return"] for e in greedy])
        assert summary["experiment"]["final_greedy_mean"] == pytest.approx(world_mean), "the agent's and the world's accounts"
        best = np.mean([optimum[e["start"]] for e in greedy])
        print(f"Taxi over shared memory, seed {seed}: greedy {world_mean:.3f}, optimum over the same starts {best:.3f}; "
              f"round trip p50 {summary['latency_us']['p50']:.1f} us, floor p50 {summary['floor_us']['p50']:.1f} us")
        assert world_mean == pytest.approx(best), f"seed {seed}: greedy below the optimum from some start state"
        assert gym.spec("Taxi-v4").reward_threshold > optimum[np.flatnonzero(gym.make("Taxi-v4").unwrapped.initial_state_distrib)].mean()
    again, episodes_again, out_again = run_world(supervisor, sandbox, "taxi1-again", "taxi_world.py", "taxi.pnml", *TAXI,
                                                 "--seed", "1")
    first = (sandbox / "taxi1" / "episodes.csv").read_text()
    assert (out_again / "episodes.csv").read_text() == first, "the same seed plays the same episodes"
    assert (sandbox / "taxi1.jsonl").read_text() == (sandbox / "taxi1-again.jsonl").read_text()


def test_doorkey_from_a_python_world_reaches_the_goal_greedily(supervisor, sandbox):
    pytest.importorskip("minigrid")
    for seed in ("1", "2", "3"):
        summary, episodes, _ = run_world(supervisor, sandbox, f"doorkey{seed}", "doorkey_world.py", "doorkey.pnml",
                                         "--algo", "q-learning", "--gamma", "0.9", "--episodes", "200",
                                         "--eval-every", "200", "--eval-episodes", "0", "--wait", "hybrid",
                                         "--seed", seed)
        learning, greedy = episodes[:200], episodes[-GREEDY:]
        success = np.mean([e["terminated"] and e["return"] > 0 for e in greedy])
        steps = np.mean([e["steps"] for e in greedy])
        early = np.mean([e["steps"] for e in learning[:20]])
        print(f"DoorKey over shared memory, seed {seed}: greedy success {success:.0%} in {steps:.1f} steps "
              f"(first 20 learning episodes: {early:.1f} steps)")
        assert success >= 0.9, f"seed {seed}: {success:.0%} of greedy episodes reach the goal"
        assert steps <= 15, f"seed {seed}: greedy episodes take {steps:.1f} steps"


def guide_world():
    """The guide's twenty-line world (FrozenLake), as its page shows it."""
    text = (ROOT / "docs" / "guide" / "src" / "worlds.md").read_text()
    start = text.index("# my_world.py")
    return text[start : text.index("```", start)]


def test_the_guides_world_serves_frozenlake_and_its_plan_is_learned(supervisor, sandbox):
    import grid
    import learnpnp

    code = guide_world()
    assert len(code.strip().splitlines()) <= 22, "the guide promises about twenty lines"
    (sandbox / "my_world.py").write_text(code)
    grid.build("lake", 16, grid.LAKE_ACTIONS, {15}).save(str(sandbox / "lake.pnml"))
    out, ipc = sandbox / "lake", sandbox / "ipc"
    command = [supervisor, "--world-cmd", f"{sys.executable} my_world.py", "--plan", str(sandbox / "lake.pnml"),
               "--algo", "q-learning", "--episodes", "400", "--eval-every", "400", "--eval-episodes", "0",
               "--greedy-episodes", "10", "--out", str(out), "--floor-round-trips", "1000"]
    done = subprocess.run(command, cwd=sandbox, env={**os.environ, "LEARNPNP_IPC_DIR": str(ipc)},
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["experiment"]["final_greedy_mean"] == 1.0, "the greedy walk reaches the goal every time"
    episodes = (sandbox / "episodes.jsonl").read_text().splitlines()
    assert len(episodes) >= 410
    assert learnpnp.Plan.load(str(sandbox / "lake.pnml")).actions == list(grid.LAKE_ACTIONS)


LAKE_WORLD = """
import sys
import gymnasium as gym
from learnpnp.world import RecordEpisodes, serve
agents = int(sys.argv[1])
envs = [RecordEpisodes(gym.make("FrozenLake-v1", is_slippery=False), f"agent{a}.jsonl") for a in range(agents)]
serve(envs if agents > 1 else envs[0], atoms=lambda o: {f"at_{int(o)}"},
      atom_names=[f"at_{c}" for c in range(16)], actions=["left", "down", "right", "up"])
"""


def lake_run(supervisor, sandbox, name, agents, *args):
    import grid

    (sandbox / "lake_world.py").write_text(LAKE_WORLD)
    grid.build("lake", 16, grid.LAKE_ACTIONS, {15}).save(str(sandbox / "lake.pnml"))
    out, ipc = sandbox / name, sandbox / "ipc"
    command = [supervisor, "--world-cmd", f"{sys.executable} lake_world.py {agents}", "--plan",
               str(sandbox / "lake.pnml"), "--agents", str(agents), "--algo", "q-learning", "--out", str(out),
               "--floor-round-trips", "1000", *args]
    done = subprocess.run(command, cwd=sandbox, env={**os.environ, "LEARNPNP_IPC_DIR": str(ipc)},
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"], summary
    left = [f for f in os.listdir("/dev/shm") if any(f.startswith(p) for p in summary["ipc_prefixes"])]
    assert left == [] and list(ipc.iterdir()) == []
    return summary, out


def test_two_agents_each_in_its_own_environment_of_one_python_world(supervisor, sandbox):
    summary, out = lake_run(supervisor, sandbox, "two", 2, "--episodes", "400", "--eval-every", "400",
                            "--eval-episodes", "0", "--greedy-episodes", "10")
    assert summary["experiment"]["final_greedy_mean"] == 1.0
    for a in range(2):
        episodes = [json.loads(line) for line in (sandbox / f"agent{a}.jsonl").read_text().splitlines()]
        ended = [e for e in episodes if e["ended"]]
        assert len(ended) == 410, f"agent {a + 1}'s environment served every episode"
        assert all(e["return"] == 1.0 for e in ended[-10:]), f"agent {a + 1}'s greedy episodes reach the goal"
    assert (out / "runs" / "run-0" / "values-agent2.bin").exists()


def test_a_python_world_in_real_time_keeps_its_clock(supervisor, sandbox):
    summary, _ = lake_run(supervisor, sandbox, "realtime", 1, "--mode", "realtime", "--episodes", "2",
                          "--eval-every", "2", "--eval-episodes", "0", "--greedy-episodes", "0")
    print(f"FrozenLake in real time: {summary['cycles']} cycles, round trip p50 {summary['latency_us']['p50']:.0f} us, "
          f"floor p50 {summary['floor_us']['p50']:.0f} us, {summary['missed_deadlines']} missed deadlines")
    assert summary["cycles"] >= 2
    assert summary["cycles_per_second"] < 15, "one cycle every 100 ms"
