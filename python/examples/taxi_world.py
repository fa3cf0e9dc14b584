"""gymnasium's Taxi-v4 as the world process of a learnpnp run.

The atoms and actions are those of the Taxi plan (plans/python/taxi.py, saved
as plans/taxi.pnml), so that plan fits this world. From the repository's root::

    learnpnp-supervisor --world-cmd "python python/examples/taxi_world.py" \\
        --plan plans/taxi.pnml --algo q-learning --episodes 2000

(the supervisor sets the LEARNPNP_* variables). ``--record FILE`` appends one
JSON line per episode the world served (``learnpnp.world.RecordEpisodes``).
Needs the ``world`` extra: ``pip install './python[world]'``.
"""

import gymnasium as gym

from _common import plan_module, serve_plan_world

taxi = plan_module("taxi")


def main():
    """Serves Taxi-v4 until the supervisor says stop."""
    serve_plan_world(__doc__.splitlines()[0], lambda: gym.make("Taxi-v4"), taxi)


if __name__ == "__main__":
    main()
