"""``KeepawayPassEnv``: one learning keeper's pass decision as a gymnasium environment."""

from __future__ import annotations

from typing import Any, Dict, Optional, SupportsFloat, SupportsInt, Tuple

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from .. import _native
from .spaces import action_space, observation_space


class KeepawayPassEnv(gym.Env[NDArray[np.float32], SupportsInt]):
    """The pass decision of keeper 0; the other two keepers play ``others``.

    Options: ``vision`` (``framework``, the framework players' perception, by
    default; ``full-state`` or ``quantised``), ``others`` (the
    other keepers' fixed policy: ``handcoded``, the framework's, by default;
    ``threshold``, ``always-hold``, ``random``), ``field_length`` and
    ``field_width`` (metres, 20 x 20 by default), ``server_timer`` (the soccer
    server's timer, ``learnpnp experiment --server-timer``: ``real-time`` by
    default, or ``synchronous``; it moves the framework players' sees, so it
    changes nothing with the other visions). ``info`` carries
    ``handcoded_action`` (what the framework's hand-coded policy would choose
    at this decision); ``reset``'s info also ``seconds_before`` (played before
    the first decision) and ``skipped_episodes`` (durations of episodes that
    ended before any decision), and the last step's ``episode_seconds``.
    There is no render mode.
    """

    metadata: Dict[str, Any] = {"render_modes": []}

    def __init__(
        self,
        vision: str = "framework",
        others: str = "handcoded",
        field_length: float = 20.0,
        field_width: float = 20.0,
        render_mode: Optional[str] = None,
        server_timer: str = "real-time",
    ) -> None:
        if render_mode is not None:
            raise ValueError("KeepawayPassEnv has no render mode (record games with `learnpnp experiment --record`)")
        self.observation_space: gym.spaces.Box[np.float32] = observation_space(field_length, field_width)
        self.action_space: gym.spaces.Discrete[np.int64] = action_space()
        self._game = _native.KeepawayGame(1, 0, vision, others, field_length, field_width, server_timer)
        self._seeded = False
        #: The observation of the latest decision (the last one stays after the episode's end).
        self._last: NDArray[np.float32] = np.zeros(self.observation_space.shape, dtype=np.float32)

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[NDArray[np.float32], Dict[str, Any]]:
        """Starts an episode and returns its first decision's observation."""
        super().reset(seed=seed)
        if seed is not None:
            self._game.reseed(seed)
            self._seeded = True
        elif not self._seeded:
            self._game.reseed(int(self.np_random.integers(2**63)))
            self._seeded = True
        (_, state, handcoded), before, skipped = self._game.reset()
        self._last = np.asarray(state, dtype=np.float32)
        info: Dict[str, Any] = {"handcoded_action": handcoded, "seconds_before": before, "skipped_episodes": skipped}
        return self._last.copy(), info

    def step(self, action: SupportsInt) -> Tuple[NDArray[np.float32], SupportsFloat, bool, bool, Dict[str, Any]]:
        """Answers the decision and plays to the next one (or the episode's end)."""
        decision, seconds, episode_seconds = self._game.step(int(action))
        info: Dict[str, Any] = {}
        if decision is not None:
            _, state, info["handcoded_action"] = decision
            self._last = np.asarray(state, dtype=np.float32)
        else:
            info["episode_seconds"] = episode_seconds
        return self._last.copy(), float(seconds), decision is None, False, info
