"""The environment loop of a ``PlanAgent`` in a gymnasium environment."""

from typing import Any, Callable, Dict, Iterable, Optional, Sequence, Tuple


def run_episode(
    env: Any,
    agent: Any,
    atoms: Callable[[Any], Iterable[str]],
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
