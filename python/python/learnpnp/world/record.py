"""A record of the episodes a world served, kept by the world itself."""

import json

import gymnasium as gym


class RecordEpisodes(gym.Wrapper):
    """Appends one JSON line per episode to ``path``: the start observation
    (``start``, when it is a number or a list of numbers), the return, the
    steps, and whether the episode terminated. An episode the world discarded
    (reset before it ended) is recorded with ``"ended": false``.

    The world's own account of a run, independent of the agents': tests
    compare it with what the agents learned, and a user reads what the world
    saw (``python examples/taxi_world.py --record episodes.jsonl``).
    """

    def __init__(self, env, path):
        super().__init__(env)
        self._file = open(path, "a", encoding="utf-8")  # noqa: SIM115 (closed in close())
        self._episode = None

    def reset(self, **kwargs):
        self._flush(ended=False)
        observation, info = self.env.reset(**kwargs)
        start = observation if isinstance(observation, (int, float, list)) else None
        if hasattr(observation, "item") and getattr(observation, "ndim", 1) == 0:
            start = observation.item()
        self._episode = {"start": start, "return": 0.0, "steps": 0, "terminated": False}
        return observation, info

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        if self._episode is not None:
            self._episode["return"] += float(reward)
            self._episode["steps"] += 1
            if terminated or truncated:
                self._episode["terminated"] = bool(terminated)
                self._flush(ended=True)
        return observation, reward, terminated, truncated, info

    def _flush(self, ended):
        if self._episode is not None:
            self._episode["ended"] = ended
            self._file.write(json.dumps(self._episode) + "\n")
            self._file.flush()
            self._episode = None

    def close(self):
        self._file.close()
        super().close()
