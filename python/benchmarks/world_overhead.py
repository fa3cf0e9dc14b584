"""What serving a Python world through learnpnp costs per step: gymnasium's
Taxi-v4 served by the world kit (``python/examples/taxi_world.py``) to a Rust
agent process over iceoryx2, lock-step, against the same environment stepped
in a plain Python loop doing the world's own work (a step, then the plan's
atoms from the observation). Each figure is the median of ``--repeats`` runs.

    python python/benchmarks/world_overhead.py [--supervisor target/release/learnpnp-supervisor]
        [--episodes N] [--repeats R] [--wait hybrid]

The served figure is the run's lock-step cycles per second (every cycle: the
world publishes the snapshot, the agent steps its plan and answers, the world
steps Taxi); the plain loop's actions are random. The difference is the
overhead per step: shared memory both ways, the agent's executor and learner,
and the kit's bookkeeping.
"""

import argparse
import json
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import gymnasium as gym
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "plans" / "python"))
import taxi  # noqa: E402  (the plan's atoms)


def plain_steps_per_second(steps, seed=0):
    """Taxi stepped with random actions, atoms computed each step, as the world does."""
    env = gym.make("Taxi-v4")
    rng = np.random.default_rng(seed)
    actions = rng.integers(0, 6, size=steps)
    obs, _ = env.reset(seed=seed)
    start = time.perf_counter()
    for action in actions:
        obs, _, terminated, truncated, _ = env.step(int(action))
        taxi.atoms(env, obs)
        if terminated or truncated:
            obs, _ = env.reset()
    return steps / (time.perf_counter() - start)


def served(supervisor, episodes, wait):
    """One lock-step run of the Taxi world: its summary."""
    root = pathlib.Path(tempfile.mkdtemp(prefix="lpb", dir="/tmp"))
    try:
        world = f"{sys.executable} {ROOT / 'python' / 'examples' / 'taxi_world.py'}"
        command = [supervisor, "--world-cmd", world, "--plan", str(ROOT / "plans" / "taxi.pnml"),
                   "--algo", "q-learning", "--episodes", str(episodes), "--eval-every", str(episodes),
                   "--eval-episodes", "0", "--greedy-episodes", "0", "--wait", wait, "--out", str(root / "out")]
        subprocess.run(command, env={**os.environ, "LEARNPNP_IPC_DIR": str(root / "ipc")}, check=True,
                       capture_output=True)
        return json.loads((root / "out" / "summary.json").read_text())
    finally:
        shutil.rmtree(root, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--supervisor", default=str(ROOT / "target" / "release" / "learnpnp-supervisor"))
    parser.add_argument("--episodes", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--wait", default="hybrid")
    args = parser.parse_args()
    runs = [served(args.supervisor, args.episodes, args.wait) for _ in range(args.repeats)]
    served_rate = statistics.median(r["cycles_per_second"] for r in runs)
    cycles = statistics.median(r["cycles"] for r in runs)
    plain_rate = statistics.median(plain_steps_per_second(int(cycles)) for _ in range(args.repeats))
    trip = statistics.median(r["latency_us"]["p50"] for r in runs)
    floor = statistics.median(r["floor_us"]["p50"] for r in runs)
    print(f"Taxi-v4, {args.episodes} learning episodes ({cycles:.0f} steps), {args.wait} wait, median of {args.repeats}")
    print(f"  served to a Rust agent over shared memory: {served_rate:10.0f} steps/s ({1e6 / served_rate:6.1f} us/step)")
    print(f"  plain Python loop (step + atoms):          {plain_rate:10.0f} steps/s ({1e6 / plain_rate:6.1f} us/step)")
    print(f"  overhead per step: {1e6 / served_rate - 1e6 / plain_rate:.1f} us; "
          f"round trip p50 {trip:.1f} us against the iceoryx2 floor p50 {floor:.1f} us")


if __name__ == "__main__":
    main()
