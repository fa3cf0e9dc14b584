"""Keepaway for Python RL: the environments pass gymnasium's and PettingZoo's
own checks, and with the same seed play the episodes of the Rust in-process
experiment."""

import csv
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import api_test

import learnpnp  # noqa: F401  (registers learnpnp/KeepawayPass-v0)
from learnpnp.envs import KeepawayAECEnv, KeepawayPassEnv, KeepawayVectorEnv

TIMERS = ("real-time", "synchronous")


def rust_experiment(learnpnp_cli, out, seed, episodes, *options):
    """The returns of a `learnpnp experiment keepaway-fixed` of the hand-coded
    keepers (one run, no evaluation), with ``options`` added."""
    subprocess.run(
        [learnpnp_cli, "experiment", "keepaway-fixed", "--policy", "handcoded", "--seed", str(seed), "--runs", "1",
         "--episodes", str(episodes), "--eval-episodes", "0", "--greedy-episodes", "0", "--out", str(out), *options],
        capture_output=True, check=True,
    )
    with open(out / "episodes.csv") as f:
        return [float(row["return"]) for row in csv.DictReader(f)]


def play_handcoded(env, seed, episodes, skipped=True):
    """Durations of ``episodes`` episodes answered with the hand-coded choice
    (with those that ended before any decision, unless ``skipped`` is false);
    checks that each episode's rewards add up to its duration."""
    durations = []
    obs, info = env.reset(seed=seed)
    while len(durations) < episodes:
        if skipped:
            durations.extend(info["skipped_episodes"])
        total = info["seconds_before"]
        while True:
            obs, reward, terminated, truncated, info = env.step(info["handcoded_action"])
            assert env.observation_space.contains(obs) and not truncated
            total += reward
            if terminated:
                assert abs(total - info["episode_seconds"]) < 1e-9
                durations.append(info["episode_seconds"])
                break
        obs, info = env.reset()
    return durations[:episodes]


def play_handcoded_aec(aec, seed, episodes):
    """Durations of ``episodes`` episodes of the AEC keepers each answering as
    the hand-coded keepers would (with those that ended before any decision)."""
    aec.reset(seed=seed)
    durations = list(aec.infos[aec.agent_selection]["skipped_episodes"])
    while len(durations) < episodes:
        for agent in aec.agent_iter():
            obs, reward, terminated, truncated, info = aec.last()
            if terminated:
                aec.step(None)
                continue
            aec.step(info["handcoded_action"])
        durations.append(info["episode_seconds"])
        aec.reset()
        durations.extend(aec.infos[aec.agent_selection]["skipped_episodes"])
    return durations[:episodes]


def play_handcoded_vector(vec, seed, episodes):
    """Each copy's first ``episodes`` episode durations, answered with the
    hand-coded choice; checks the vector's next-step autoreset on the way."""
    n = vec.num_envs
    obs, info = vec.reset(seed=seed)
    assert obs.shape == (n, 13) and obs.dtype == np.float32
    ended = [[] for _ in range(n)]
    finished_last = np.zeros(n, dtype=bool)
    while min(len(e) for e in ended) < episodes:
        obs, rewards, terminated, truncated, info = vec.step(info["handcoded_action"])
        assert vec.observation_space.contains(obs)
        # The step after an episode's end starts the next one: no reward.
        assert np.all(rewards[finished_last] == 0.0) and not np.any(terminated[finished_last])
        for i in np.flatnonzero(terminated):
            ended[i].append(info["episode_seconds"][i])
        finished_last = terminated
    return [e[:episodes] for e in ended]


def test_pass_env_passes_gymnasiums_checker():
    check_env(KeepawayPassEnv(), skip_render_check=True)
    env = gym.make("learnpnp/KeepawayPass-v0", vision="quantised", field_length=25.0, field_width=25.0)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.action_space.n == 3 and env.observation_space.shape == (13,)


def test_aec_env_passes_pettingzoos_api_test():
    api_test(KeepawayAECEnv(), num_cycles=300)


def test_same_seed_same_episodes_as_the_rust_experiment(tmp_path, learnpnp_cli):
    seed, episodes = 7, 30
    expected = rust_experiment(learnpnp_cli, tmp_path / "fixed", seed, episodes)
    assert play_handcoded(KeepawayPassEnv(), seed, episodes) == expected
    # Three deciders answering as the hand-coded keepers would: the same episodes.
    assert play_handcoded_aec(KeepawayAECEnv(), seed, episodes) == expected


def test_each_server_timer_plays_its_own_reproducible_episodes(tmp_path, learnpnp_cli):
    # The soccer server's timer moves the framework players' sees (rcssserver's
    # real-time StandardTimer or synch_mode's SyncTimer, crates/keepaway/src/timing.rs):
    # with one seed, each timer repeats its episodes, the two differ, and each
    # is `learnpnp experiment --server-timer`'s.
    seed, episodes = 7, 30
    played = {}
    for timer in TIMERS:
        played[timer] = play_handcoded(KeepawayPassEnv(server_timer=timer), seed, episodes)
        assert play_handcoded(KeepawayPassEnv(server_timer=timer), seed, episodes) == played[timer]
        expected = rust_experiment(learnpnp_cli, tmp_path / timer, seed, episodes, "--server-timer", timer)
        assert played[timer] == expected, timer
    assert played["real-time"] != played["synchronous"]
    assert play_handcoded(KeepawayPassEnv(), seed, episodes) == played["real-time"], "real time is the default"
    # The option reaches every environment: gym.make, the AEC keepers, the
    # vector and gym.make_vec (whose copy 0 plays run 0, without the episodes
    # that ended before any decision).
    made = gym.make("learnpnp/KeepawayPass-v0", server_timer="synchronous")
    assert play_handcoded(made.unwrapped, seed, episodes) == played["synchronous"]
    assert play_handcoded_aec(KeepawayAECEnv(server_timer="synchronous"), seed, episodes) == played["synchronous"]
    few = 6
    decided = {t: play_handcoded(KeepawayPassEnv(server_timer=t), seed, few, skipped=False) for t in TIMERS}
    assert decided["real-time"] != decided["synchronous"]
    for vec in (
        KeepawayVectorEnv(2, server_timer="synchronous"),
        gym.make_vec("learnpnp/KeepawayPass-v0", num_envs=2, server_timer="synchronous"),
    ):
        assert play_handcoded_vector(vec, seed, few)[0] == decided["synchronous"]
    with pytest.raises(ValueError, match="server timer"):
        KeepawayPassEnv(server_timer="fast")


def test_vector_env_steps_copies_together_with_next_step_autoreset():
    n, seed, episodes = 8, 5, 6
    ended = play_handcoded_vector(KeepawayVectorEnv(n), seed, episodes)
    # Copy 0 plays run 0: the single environment's episodes (the vector does
    # not report episodes that ended before any decision).
    single = play_handcoded(KeepawayPassEnv(), seed, episodes, skipped=False)
    assert ended[0][:episodes] == single
    assert len({tuple(e[:episodes]) for e in ended}) == n, "each copy plays its own run"


def test_make_vec_builds_the_rust_stepped_batch():
    vec = gym.make_vec("learnpnp/KeepawayPass-v0", num_envs=3)
    assert isinstance(vec.unwrapped, KeepawayVectorEnv)
    obs, _ = vec.reset(seed=5)
    direct, _ = KeepawayVectorEnv(3).reset(seed=5)
    assert np.array_equal(obs, direct)


def test_the_gymnasium_environments_need_no_pettingzoo(tmp_path):
    # PettingZoo is optional: without it the gymnasium environments work and
    # the AEC environment says what to install.
    script = (
        "import sys; sys.modules['pettingzoo'] = None\n"
        "import learnpnp.envs as e\n"
        "e.KeepawayPassEnv().reset(seed=1); e.KeepawayVectorEnv(2).reset(seed=1)\n"
        "try:\n    e.KeepawayAECEnv\nexcept ImportError as err:\n    print(err)\n"
    )
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, cwd=tmp_path)
    out = run.stdout
    assert "KeepawayAECEnv needs PettingZoo" in out
