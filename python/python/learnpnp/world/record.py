"""A record of the episodes a world served, kept by the world itself."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Optional, SupportsFloat, Tuple, TypeVar, Union

import gymnasium as gym

_Obs = TypeVar("_Obs")
_Act = TypeVar("_Act")


class RecordEpisodes(gym.Wrapper[_Obs, _Act, _Obs, _Act]):
    """Appends one JSON line per episode to ``path``: the start observation
    (``start``, when it is a number or a list of numbers), the return, the
    steps, and whether the episode terminated. An episode the world discarded
    (reset before it ended) is recorded with ``"ended": false``.

    The world's own account of a run, independent of the agents': tests
    compare it with what the agents learned, and a user reads what the world
    saw (``python examples/taxi_world.py --record episodes.jsonl``).
    """

    def __init__(self, env: gym.Env[_Obs, _Act], path: Union[str, os.PathLike[str]]) -> None:
        super().__init__(env)
        self._file = open(path, "a", encoding="utf-8")  # noqa: SIM115 (closed in close())
        #: The episode in flight: ``start``, ``return``, ``steps``, ``terminated``.
        self._episode: Optional[Dict[str, Any]] = None

    def reset(self, **kwargs: Any) -> Tuple[_Obs, Dict[str, Any]]:
        """Records the episode in flight as discarded, if any, and starts one
        (``kwargs``, ``seed`` and ``options``, go to the environment)."""
        self._flush(ended=False)
        observation, info = self.env.reset(**kwargs)
        start = observation if isinstance(observation, (int, float, list)) else None
        if hasattr(observation, "item") and getattr(observation, "ndim", 1) == 0:
            start = observation.item()
        self._episode = {"start": start, "return": 0.0, "steps": 0, "terminated": False}
        return observation, info

    def step(self, action: _Act) -> Tuple[_Obs, SupportsFloat, bool, bool, Dict[str, Any]]:
        """Steps the environment; records the episode when it ends."""
        observation, reward, terminated, truncated, info = self.env.step(action)
        if self._episode is not None:
            self._episode["return"] += float(reward)
            self._episode["steps"] += 1
            if terminated or truncated:
                self._episode["terminated"] = bool(terminated)
                self._flush(ended=True)
        return observation, reward, terminated, truncated, info

    def _flush(self, ended: bool) -> None:
        if self._episode is not None:
            self._episode["ended"] = ended
            self._file.write(json.dumps(self._episode) + "\n")
            self._file.flush()
            self._episode = None

    def close(self) -> None:
        """Closes the record, then the environment."""
        self._file.close()
        super().close()
