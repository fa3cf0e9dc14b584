"""``KeepawayAECEnv``: the three keepers learning their pass decisions together (PettingZoo AEC).

AEC is the form that fits: a keeper decides only when the ball is kickable
for it, so decisions come one at a time, at irregular moments, and never two
at once. ``agent_selection`` is the keeper that must decide; every keeper is
paid the seconds each step lasted, so each keeper's return is the episode's
duration from the first decision on.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, SupportsInt, Tuple

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray
from pettingzoo import AECEnv

from .. import _native
from .spaces import action_space, observation_space


# An action is None for a keeper whose episode has ended (PettingZoo's dead step).
class KeepawayAECEnv(AECEnv[str, NDArray[np.float32], Optional[SupportsInt]]):
    """Keepers ``keeper_0``, ``keeper_1``, ``keeper_2`` each decide hold or pass
    when they have the ball. Options as ``KeepawayPassEnv`` (``vision``,
    ``field_length``, ``field_width``, ``server_timer``). A keeper's
    observation is the state variables of its latest decision (zeros before
    its first).
    """

    metadata: Dict[str, Any] = {"name": "keepaway_v0", "render_modes": [], "is_parallelizable": False}
    #: Each keeper's latest decision's state variables (set by ``reset``).
    _observations: Dict[str, NDArray[np.float32]]

    def __init__(
        self,
        vision: str = "framework",
        field_length: float = 20.0,
        field_width: float = 20.0,
        render_mode: Optional[str] = None,
        server_timer: str = "real-time",
    ) -> None:
        super().__init__()  # type: ignore[no-untyped-call]  # (PettingZoo leaves it unannotated)
        if render_mode is not None:
            raise ValueError("KeepawayAECEnv has no render mode")
        self.render_mode = None
        self.possible_agents = [f"keeper_{k}" for k in range(3)]
        self._observation_space = observation_space(field_length, field_width)
        self._action_space = action_space()
        self._game = _native.KeepawayGame(3, 0, vision, "handcoded", field_length, field_width, server_timer)
        self._seeded = False

    def observation_space(self, agent: str) -> spaces.Box[np.float32]:
        """The 13 state variables."""
        return self._observation_space

    def action_space(self, agent: str) -> spaces.Discrete[np.int64]:
        """Hold, pass to the nearest teammate, pass to the second nearest."""
        return self._action_space

    def observe(self, agent: str) -> NDArray[np.float32]:
        """The state variables of ``agent``'s latest decision."""
        observation: NDArray[np.float32] = self._observations[agent].copy()
        return observation

    def reset(self, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None) -> None:
        """Starts an episode at its first decision."""
        if seed is not None:
            self._game.reseed(seed)
            self._seeded = True
        elif not self._seeded:
            self._game.reseed(int(np.random.default_rng().integers(2**63)))
            self._seeded = True
        self.agents = self.possible_agents[:]
        self.rewards = {a: 0.0 for a in self.agents}
        self._cumulative_rewards = {a: 0.0 for a in self.agents}
        self.terminations = {a: False for a in self.agents}
        self.truncations = {a: False for a in self.agents}
        self.infos = {a: {} for a in self.agents}
        self._observations = {a: np.zeros(self._observation_space.shape, dtype=np.float32) for a in self.agents}
        decision, before, skipped = self._game.reset()
        self._decide(decision)
        self.infos[self.agent_selection].update(seconds_before=before, skipped_episodes=skipped)

    def _decide(self, decision: Tuple[int, List[float], int]) -> None:
        keeper, state, handcoded = decision
        self.agent_selection = self.possible_agents[keeper]
        self._observations[self.agent_selection] = np.asarray(state, dtype=np.float32)
        self.infos[self.agent_selection] = {"handcoded_action": handcoded}

    def step(self, action: Optional[SupportsInt]) -> None:
        """The selected keeper's decision; play goes on to the next one. A
        keeper whose episode has ended is stepped with ``None`` (PettingZoo's
        dead step)."""
        if self.terminations[self.agent_selection] or self.truncations[self.agent_selection]:
            self._was_dead_step(action)
            return
        if action is None:
            raise TypeError(f"{self.agent_selection} must decide: None steps only a keeper whose episode has ended")
        self._cumulative_rewards[self.agent_selection] = 0.0
        decision, seconds, episode_seconds = self._game.step(int(action))
        for agent in self.agents:
            self.rewards[agent] = float(seconds)
        if decision is None:
            for agent in self.agents:
                self.terminations[agent] = True
                self.infos[agent] = {"episode_seconds": episode_seconds}
        else:
            self._decide(decision)
        self._accumulate_rewards()

    def render(self) -> None:
        """No rendering (record games with ``learnpnp experiment --record``)."""
        return None

    def close(self) -> None:
        """Nothing to release."""
