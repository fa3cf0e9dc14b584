"""``KeepawayVectorEnv``: N copies of ``KeepawayPassEnv`` stepped in one call."""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space
from numpy.typing import ArrayLike, NDArray

from .. import _native
from .spaces import action_space, observation_space


class KeepawayVectorEnv(VectorEnv[NDArray[np.float32], ArrayLike, NDArray[Any]]):
    """``num_envs`` Keepaway games of one learning keeper, stepped together in
    Rust (no Python loop per copy) into numpy arrays. Copy ``i`` plays run
    ``i`` of a ``learnpnp experiment`` of the reset's base seed. Autoreset is
    gymnasium's next-step mode: the step after an episode ends starts the
    next one in that copy (its action ignored, reward 0); an ended copy's
    observation is its last decision's. ``infos`` carries ``handcoded_action``
    and ``episode_seconds`` (0 where no episode ended). Options as
    ``KeepawayPassEnv``.
    """

    metadata: Dict[str, Any] = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_envs: int,
        vision: str = "framework",
        others: str = "handcoded",
        field_length: float = 20.0,
        field_width: float = 20.0,
        server_timer: str = "real-time",
    ) -> None:
        self.num_envs = int(num_envs)
        self.single_observation_space = observation_space(field_length, field_width)
        self.single_action_space = action_space()
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None
        self._batch = _native.KeepawayBatch(self.num_envs, 0, vision, others, field_length, field_width, server_timer)
        self._seeded = False

    def _states(self, raw: bytes) -> NDArray[np.float32]:
        """The N x 13 states of ``raw`` (float32 bytes from Rust), copied out of the bytes."""
        states: NDArray[np.float32] = np.frombuffer(raw, dtype=np.float32).reshape(self.num_envs, -1).copy()
        return states

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[NDArray[np.float32], Dict[str, Any]]:
        """Starts an episode in every copy."""
        super().reset(seed=seed)
        if seed is not None:
            self._batch.reseed(int(seed))
            self._seeded = True
        elif not self._seeded:
            self._batch.reseed(int(self.np_random.integers(2**63)))
            self._seeded = True
        raw, handcoded = self._batch.reset()
        return self._states(raw), {"handcoded_action": np.asarray(handcoded, dtype=np.int64)}

    def step(
        self, actions: ArrayLike
    ) -> Tuple[NDArray[np.float32], NDArray[Any], NDArray[Any], NDArray[Any], Dict[str, Any]]:
        """Answers every copy's decision; each plays to its next one."""
        raw_actions = np.ascontiguousarray(actions, dtype=np.int64).tobytes()
        raw, rewards, terminated, handcoded, durations = self._batch.step(raw_actions)
        infos = {
            "handcoded_action": np.asarray(handcoded, dtype=np.int64),
            "episode_seconds": np.asarray(durations, dtype=np.float64),
        }
        return (
            self._states(raw),
            np.asarray(rewards, dtype=np.float64),
            np.asarray(terminated, dtype=np.bool_),
            np.zeros(self.num_envs, dtype=np.bool_),
            infos,
        )
