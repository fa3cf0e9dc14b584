"""gymnasium's Taxi-v4 as the world process of a learnpnp run.

The atoms and actions are those of the Taxi plan (plans/python/taxi.py, saved
as plans/taxi.pnml), so that plan fits this world. From the repository's root::

    learnpnp-supervisor --world-cmd "python python/examples/taxi_world.py" \\
        --plan plans/taxi.pnml --algo q-learning --episodes 2000

(the supervisor sets the LEARNPNP_* variables). ``--record FILE`` appends one
JSON line per episode the world served (``learnpnp.world.RecordEpisodes``).
Needs the ``world`` extra: ``pip install './python[world]'``.
"""

import argparse
import pathlib
import sys

import gymnasium as gym

from learnpnp.world import RecordEpisodes, serve

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "plans" / "python"))
import taxi  # noqa: E402  (the plan's atoms and actions)


def main():
    """Serves Taxi-v4 until the supervisor says stop."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", help="append each episode the world served to this file (JSON lines)")
    args = parser.parse_args()
    env = gym.make("Taxi-v4")
    if args.record:
        env = RecordEpisodes(env, args.record)
    try:
        serve(
            env,
            atoms=lambda observation: taxi.atoms(env, observation),
            actions=taxi.ACTIONS,
            atom_names=taxi.atom_names(),
        )
    finally:
        env.close()


if __name__ == "__main__":
    main()
