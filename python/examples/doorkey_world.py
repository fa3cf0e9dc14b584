"""MiniGrid's DoorKey (``MiniGrid-DoorKey-5x5-v0``) as the world process of a
learnpnp run: partially observable, the agent sees an egocentric 7x7 view.

The atoms and actions are those of the DoorKey plan (plans/python/doorkey.py,
saved as plans/doorkey.pnml), which leaves open how to search for the key,
the door and the goal. From the repository's root::

    learnpnp-supervisor --world-cmd "python python/examples/doorkey_world.py" \\
        --plan plans/doorkey.pnml --algo q-learning --gamma 0.9 --episodes 200

``--record FILE`` appends one JSON line per episode the world served. Needs
the ``world`` extra and ``minigrid``: ``pip install './python[world]' minigrid``.
"""

import argparse
import pathlib
import sys

import gymnasium as gym
import minigrid  # noqa: F401  (registers the MiniGrid environments)

from learnpnp.world import RecordEpisodes, serve

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "plans" / "python"))
import doorkey  # noqa: E402  (the plan's atoms and actions)


def main():
    """Serves DoorKey-5x5 until the supervisor says stop."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", help="append each episode the world served to this file (JSON lines)")
    args = parser.parse_args()
    env = gym.make("MiniGrid-DoorKey-5x5-v0")
    if args.record:
        env = RecordEpisodes(env, args.record)
    try:
        serve(
            env,
            atoms=lambda observation: doorkey.atoms(env, observation),
            actions=doorkey.ACTIONS,
            atom_names=doorkey.atom_names(),
        )
    finally:
        env.close()


if __name__ == "__main__":
    main()
