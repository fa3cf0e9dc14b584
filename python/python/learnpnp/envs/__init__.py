"""Keepaway 3 vs 2 for Python RL, on learnpnp's simulator.

- ``KeepawayPassEnv``: a gymnasium environment, registered as
  ``learnpnp/KeepawayPass-v0``: the pass decision of one learning keeper.
- ``KeepawayAECEnv``: the three keepers learning together (PettingZoo AEC).
- ``KeepawayVectorEnv``: N copies of ``KeepawayPassEnv`` stepped in one call.

Every environment plays the framework's keepers (Stone, Sutton and Kuhlmann's
keepaway): a learning keeper decides only when the ball is kickable for it
outside a pass, among hold (0), pass to the nearest teammate (1) and pass to the
second nearest (2). A step lasts until its next decision (a semi-Markov
decision); its reward is the seconds elapsed, so a return is the episode's
duration from the first decision on. The observation is the 13 state variables
of the keepaway papers, seen from the deciding keeper (distances in metres,
angles in degrees). With seed ``s`` an environment plays run 0 of a ``learnpnp
experiment`` of base seed ``s`` (copy ``i`` of a vector plays run ``i``).
``server_timer`` is ``learnpnp experiment --server-timer``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .single import KeepawayPassEnv
from .vector import KeepawayVectorEnv

if TYPE_CHECKING:
    from .aec import KeepawayAECEnv

__all__ = ["KeepawayAECEnv", "KeepawayPassEnv", "KeepawayVectorEnv"]


def __getattr__(name: str) -> Any:
    """``KeepawayAECEnv`` is imported on first use: it needs PettingZoo, an
    optional dependency (``pip install './python[pettingzoo]'``)."""
    if name == "KeepawayAECEnv":
        try:
            from .aec import KeepawayAECEnv
        except ImportError as missing:
            raise ImportError(
                "KeepawayAECEnv needs PettingZoo: pip install pettingzoo (or './python[pettingzoo]')"
            ) from missing
        return KeepawayAECEnv
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
