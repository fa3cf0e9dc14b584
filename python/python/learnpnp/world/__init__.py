"""The world kit: any environment as the world process of a learnpnp run.

A run started with ``learnpnp-supervisor --world-cmd COMMAND --plan FILE`` has
one world process (COMMAND) and one learning agent process per agent, which
exchange snapshots and commands through iceoryx2 shared memory. ``serve``
makes a gymnasium environment that world::

    import gymnasium as gym
    from learnpnp.world import serve

    env = gym.make("FrozenLake-v1", is_slippery=False)
    serve(env, atoms=lambda obs: {f"at_{obs}"}, atom_names=[f"at_{s}" for s in range(16)],
          actions=["left", "down", "right", "up"])

The message types (``WorldSnapshot``, ``WorldCommand``, ...) mirror
``shm_layouts`` for programs that speak the protocol themselves. Needs the
iceoryx2 package (``pip install iceoryx2==0.10.0``, or the ``world`` extra).
"""

from . import layouts
from .layouts import *  # noqa: F403 (the constants and message types, as layouts lists them)
from .ports import WorldError
from .record import RecordEpisodes
from .server import RunSettings, serve

__all__ = ["RecordEpisodes", "RunSettings", "WorldError", "serve"]
__all__ += layouts.__all__
