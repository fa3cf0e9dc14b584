"""Taxi-v4 learned in plan space (plans/python/taxi.py, after MAXQ's task graph).

Taxi is deterministic, so a greedy policy is measured exactly: its return from
every one of the 300 start states. Value iteration on gymnasium's own
transition table gives the optimum, 7.93 on average over the start states:
the registered threshold (8) is above what any policy earns in expectation, so
the test asserts the optimum itself, from every start state, on average over
10 seeds, and reports the episodes each learner needed beside flat tabular
Q-learning with the same step size and exploration.
"""

import gymnasium as gym
import numpy as np
import pytest

import learnpnp
import taxi

SEEDS = range(10)
EPISODES = 5000
EVAL_EVERY = 500
ALPHA, EPSILON = 0.1, 0.1


def start_states(env):
    return [int(s) for s in np.flatnonzero(env.unwrapped.initial_state_distrib)]


def greedy_returns_flat(table, q, starts, limit):
    """The flat greedy policy's return from each start, on the transition
    table (Taxi is deterministic: each entry has one outcome)."""
    out = []
    for s in starts:
        total = 0.0
        for _ in range(limit):
            _, s, r, done = table[s][int(np.argmax(q[s]))][0]
            total += r
            if done:
                break
        out.append(total)
    return np.array(out)


def learn_plan(env, seed, target, starts):
    """Learns in the plan until its greedy policy earns ``target`` from every
    start (checked every ``EVAL_EVERY`` episodes) or ``EPISODES`` pass; returns
    the greedy returns then and the episodes needed (None if never)."""
    agent = learnpnp.PlanAgent(taxi.build(), algo="q-learning", seed=seed, alpha=ALPHA, epsilon=EPSILON)
    env.reset(seed=seed)
    for episode in range(1, EPISODES + 1):
        learnpnp.run_episode(env, agent, lambda o: taxi.atoms(env, o), taxi.ACTIONS)
        if episode % EVAL_EVERY == 0:
            returns = taxi.greedy_returns(env, agent, starts)
            if np.allclose(returns, target):
                return returns, episode
    return returns, None


def learn_flat(env, seed, target, starts):
    """Flat tabular Q-learning on Taxi's 500 states, the same protocol, on
    gymnasium's transition table (one outcome per entry: what ``step`` does)."""
    rng = np.random.default_rng(seed)
    table, limit = env.unwrapped.P, env.spec.max_episode_steps
    weights = env.unwrapped.initial_state_distrib
    q = np.zeros((env.observation_space.n, env.action_space.n))
    for episode in range(1, EPISODES + 1):
        obs = int(rng.choice(len(weights), p=weights))
        for _ in range(limit):
            best = np.flatnonzero(q[obs] == q[obs].max())
            a = int(rng.integers(6)) if rng.random() < EPSILON else int(best[rng.integers(len(best))])
            _, nxt, r, term = table[obs][a][0]
            q[obs, a] += ALPHA * (r + (0.0 if term else q[nxt].max()) - q[obs, a])
            obs = nxt
            if term:
                break
        if episode % EVAL_EVERY == 0:
            returns = greedy_returns_flat(table, q, starts, limit)
            if np.allclose(returns, target):
                return returns, episode
    return returns, None


def test_taxi_learned_in_plan_space_is_optimal():
    env = taxi.StartFrom(gym.make("Taxi-v4"))
    starts = start_states(env)
    optimum = taxi.optimal_returns(env)[starts]
    assert env.spec.reward_threshold > optimum.mean(), "the threshold is above the optimum"
    plan_means, plan_needed, flat_needed = [], [], []
    for seed in SEEDS:
        returns, needed = learn_plan(env, seed, optimum, starts)
        plan_means.append(returns.mean())
        plan_needed.append(needed)
        flat_needed.append(learn_flat(env, seed, optimum, starts)[1])
    print(
        f"\nTaxi-v4: optimum {optimum.mean():.3f} (threshold {env.spec.reward_threshold}); "
        f"plan greedy mean {np.mean(plan_means):.3f}; episodes until optimal from every start "
        f"(checked every {EVAL_EVERY}): plan {plan_needed}, flat Q-learning {flat_needed}"
    )
    # Every seed's greedy policy within 0.05 of the optimum on average, and the
    # mean over seeds within 0.02 (at most 6 of 300 start states one step long).
    assert min(plan_means) >= optimum.mean() - 0.05
    assert np.mean(plan_means) >= optimum.mean() - 0.02
