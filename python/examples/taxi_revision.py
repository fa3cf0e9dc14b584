"""Revise Taxi's plan and keep what was learned (issue 39).

Learns Taxi-v4 in ``plans/python/taxi.py``'s plan (or in a revision of it),
saves the values, then learns in a revised plan from scratch and from the
migrated values (``PlanAgent.load(path, revised)``), over several seeds:
episodes until the greedy policy is optimal from every start state (checked
every ``--every`` episodes), as ``python/tests/test_taxi.py`` measures it.

Revisions (``--revision``):
- ``remove``: the wrong subtask's option removed (no Get when the passenger is
  aboard, no Put when not): learned in the full plan, loaded into the pruned one;
- ``add``: the reverse, learned in the pruned plan, loaded into the full plan,
  where the wrong subtask is a new option at the root.

    python python/examples/taxi_revision.py --revision remove --seeds 5
"""

import argparse
import os
import sys
import tempfile

import gymnasium as gym
import numpy as np

import learnpnp

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "plans", "python"))
import taxi  # noqa: E402

ALPHA, EPSILON = 0.1, 0.1


def pruned():
    """taxi.build() without the wrong subtask's option: the root chooses no
    more, Get when the passenger waits, Put when aboard."""
    b = learnpnp.PlanBuilder("taxi")
    root = b.initial_place("root")
    subtasks = {}
    for aboard, sensed_name, subtask in (("not carrying", "empty", "get"), ("carrying", "full", "put")):
        sensed = b.place(f"root_{sensed_name}")
        b.transition(f"[{aboard}]", [(root, 1)], [(sensed, 1)])
        place = b.place(f"{subtask}_{sensed_name}")
        b.transition(f"choose_{subtask}", [(sensed, 1)], [(place, 1)])
        subtasks[subtask] = place
    for site in taxi.SITES:
        nav = taxi._navigate(b, f"get_{site}", "pickup", root)
        b.transition(f"[waiting_{site}]", [(subtasks["get"], 1)], [(nav, 1)])
    for site in taxi.SITES:
        nav = taxi._navigate(b, f"put_{site}", "dropoff", root)
        b.transition(f"[dest_{site}]", [(subtasks["put"], 1)], [(nav, 1)])
    return b.build(atoms=taxi.atom_names())


def learn(env, agent, seed, episodes, every, target, starts):
    """Learns until the greedy policy earns ``target`` from every start;
    returns the episodes needed (None if not within ``episodes``)."""
    env.reset(seed=seed)
    if target is not None and np.allclose(taxi.greedy_returns(env, agent, starts), target):
        return 0
    for episode in range(1, episodes + 1):
        learnpnp.run_episode(env, agent, lambda o: taxi.atoms(env, o), taxi.ACTIONS)
        if target is not None and episode % every == 0 and np.allclose(taxi.greedy_returns(env, agent, starts), target):
            return episode
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revision", choices=("remove", "add"), default="remove")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--source-episodes", type=int, default=1500)
    parser.add_argument("--episodes", type=int, default=5000)
    parser.add_argument("--every", type=int, default=100)
    args = parser.parse_args()
    before, after = (taxi.build, pruned) if args.revision == "remove" else (pruned, taxi.build)
    env = taxi.StartFrom(gym.make("Taxi-v4"))
    starts = [int(s) for s in np.flatnonzero(env.unwrapped.initial_state_distrib)]
    target = taxi.optimal_returns(env)[starts]
    scratch, migrated = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(args.seeds):
            source = learnpnp.PlanAgent(before(), algo="q-learning", seed=seed, alpha=ALPHA, epsilon=EPSILON)
            learn(env, source, 1000 + seed, args.source_episodes, args.every, None, starts)
            path = os.path.join(tmp, f"values{seed}.bin")
            source.save(path)
            fresh = learnpnp.PlanAgent(after(), algo="q-learning", seed=seed, alpha=ALPHA, epsilon=EPSILON)
            scratch.append(learn(env, fresh, seed, args.episodes, args.every, target, starts))
            loaded = learnpnp.PlanAgent.load(path, after(), seed=seed, alpha=ALPHA, epsilon=EPSILON)
            report = loaded.migration
            migrated.append(learn(env, loaded, seed, args.episodes, args.every, target, starts))
            print(
                f"seed {seed}: kept {report['kept']}, dropped {len(report['dropped'])}, "
                f"new options {len(report['new_options'])}, changed choices {len(report['changed_choices'])}; "
                f"episodes to optimal: scratch {scratch[-1]}, migrated {migrated[-1]}",
                flush=True,
            )
    print(f"revision {args.revision}: source {args.source_episodes} episodes; scratch {scratch}; migrated {migrated}")


if __name__ == "__main__":
    main()
