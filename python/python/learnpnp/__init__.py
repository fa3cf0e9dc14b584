"""learnpnp: reinforcement learning in plan space, from Python.

A designer writes a behaviour as a Petri Net Plan (loaded with ``Plan.load`` or
built with ``PlanBuilder``) and leaves some choices open; a ``PlanAgent`` runs the
plan in any environment the caller steps and learns which option pays best.

>>> import learnpnp
>>> b = learnpnp.PlanBuilder("doors")
>>> start, goal = b.initial_place("start"), b.goal_place()
>>> _ = b.action_into(start, "left", goal), b.action_into(start, "right", goal)
>>> agent = learnpnp.PlanAgent(b.build(), algo="q-learning", seed=1)
>>> agent.act(set()) in ("left", "right")
True
"""

from __future__ import annotations

from ._native import (
    ALGORITHMS,
    PARAMETERS,
    ActionNet,
    Place,
    Plan,
    PlanAgent,
    PlanBuilder,
    PlanCheckError,
    PlanFileError,
    PlanStalledError,
    SensingNet,
    Tracker,
    Transition,
)
from .loop import run_episode

try:  # gymnasium is a dependency; registering costs nothing until make().
    import gymnasium as _gymnasium

    _gymnasium.register(
        id="learnpnp/KeepawayPass-v0",
        entry_point="learnpnp.envs:KeepawayPassEnv",
        # gym.make_vec builds the Rust-stepped batch, not copies in Python.
        vector_entry_point="learnpnp.envs:KeepawayVectorEnv",
    )
except ImportError:  # pragma: no cover
    pass

__all__ = [
    "ALGORITHMS",
    "PARAMETERS",
    "ActionNet",
    "Place",
    "Plan",
    "PlanAgent",
    "PlanBuilder",
    "PlanCheckError",
    "PlanFileError",
    "PlanStalledError",
    "SensingNet",
    "Tracker",
    "Transition",
    "run_episode",
]
