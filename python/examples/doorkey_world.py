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

import gymnasium as gym
import minigrid  # noqa: F401  (registers the MiniGrid environments)

from _common import plan_module, serve_plan_world

doorkey = plan_module("doorkey")


def main():
    """Serves DoorKey-5x5 until the supervisor says stop."""
    serve_plan_world(__doc__.splitlines()[0], lambda: gym.make("MiniGrid-DoorKey-5x5-v0"), doorkey)


if __name__ == "__main__":
    main()
