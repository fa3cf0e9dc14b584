"""Keepaway decision steps per second from Python, beside the Rust simulator
playing the same episodes in-process and gymnasium's CartPole-v1 stepped in the
same Python loop. Every figure comes from this one run; each is the median of
``--repeats`` timings.

    python python/benchmarks/keepaway_speed.py [--decisions N] [--repeats R]

Each learning keeper's action is the hand-coded policy's choice (reported in
``info``), so the Python and Rust loops play the same episodes.
"""

import argparse
import statistics
import time

import gymnasium as gym
import numpy as np

from learnpnp import _native
from learnpnp.envs import KeepawayPassEnv, KeepawayVectorEnv


def timed(run, repeats):
    """Median steps per second of ``run()``, which returns the steps it took."""
    rates = []
    for _ in range(repeats):
        start = time.perf_counter()
        steps = run()
        rates.append(steps / (time.perf_counter() - start))
    return statistics.median(rates)


def rust(decisions):
    game = _native.KeepawayGame(1, 7)
    game.play_handcoded(decisions)
    return decisions


def single(decisions):
    env = KeepawayPassEnv()
    obs, info = env.reset(seed=7)
    for _ in range(decisions):
        obs, reward, terminated, truncated, info = env.step(info["handcoded_action"])
        if terminated:
            obs, info = env.reset()
    return decisions


def vector(decisions, copies=64):
    env = KeepawayVectorEnv(copies)
    obs, info = env.reset(seed=7)
    steps = decisions // copies
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(info["handcoded_action"])
    return steps * copies


def cartpole(steps):
    env = gym.make("CartPole-v1")
    env.reset(seed=7)
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(0 if np.random.random() < 0.5 else 1)
        if terminated or truncated:
            env.reset()
    return steps


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--decisions", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    n, r = args.decisions, args.repeats
    figures = {
        "Rust in-process (no Python)": timed(lambda: rust(n), r),
        "KeepawayPassEnv, one env": timed(lambda: single(n), r),
        "KeepawayVectorEnv, 64 copies": timed(lambda: vector(n), r),
        "CartPole-v1 (gymnasium), one env": timed(lambda: cartpole(n), r),
    }
    base = figures["Rust in-process (no Python)"]
    print(f"{'loop':36} {'steps/s':>12} {'x Rust':>8}")
    for name, rate in figures.items():
        print(f"{name:36} {rate:12,.0f} {rate / base:8.2f}")


if __name__ == "__main__":
    main()
