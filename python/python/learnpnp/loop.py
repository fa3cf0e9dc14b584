"""The environment loop of a ``PlanAgent`` in a gymnasium environment."""

from __future__ import annotations

from typing import Any, Callable, Dict, Iterable, Optional, Protocol, Sequence, SupportsFloat, Tuple, TypeVar

from ._native import PlanAgent

_Obs = TypeVar("_Obs", covariant=True)


class SteppedEnv(Protocol[_Obs]):
    """What ``run_episode`` needs of an environment: gymnasium's ``reset`` and
    ``step`` with a discrete action (its index), as every ``gymnasium.Env`` of
    a ``Discrete`` action space has."""

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[_Obs, Dict[str, Any]]:
        """Starts an episode: its first observation and an info dict."""
        ...

    def step(self, action: int, /) -> Tuple[_Obs, SupportsFloat, bool, bool, Dict[str, Any]]:
        """Takes action ``action``: observation, reward, terminated, truncated, info."""
        ...


def run_episode(
    env: SteppedEnv[_Obs],
    agent: PlanAgent,
    atoms: Callable[[_Obs], Iterable[str]],
    actions: Sequence[str],
    *,
    seed: Optional[int] = None,
    options: Optional[Dict[str, Any]] = None,
) -> Tuple[float, int]:
    """Plays one episode of ``env`` with ``agent`` choosing in its plan.

    ``atoms(observation)`` says which of the plan's atoms hold; ``actions`` is
    the environment's action names in index order (the plan names them). Each
    step: the plan names an action, the environment takes it, the agent is
    paid its reward. The episode ends when the environment terminates or
    truncates it, or when the plan reaches its goal. Returns the undiscounted
    return and the number of environment steps.
    """
    obs, _ = env.reset(seed=seed, options=options)
    total, steps = 0.0, 0
    try:
        while True:
            name = agent.act(atoms(obs))
            if name is None:
                break
            obs, reward, terminated, truncated, _ = env.step(actions.index(name))
            agent.reward(float(reward))
            total += float(reward)
            steps += 1
            if terminated or truncated:
                break
    finally:
        agent.end_episode()
    return total, steps
