"""Plans from a PDDL model through a real planner, as a learnpnp ``Plan``.

The planners are optional: ``pip install './python[planning]'`` installs the
Unified Planning framework with Fast Downward (one plan) and SymK (the k best
plans). ``plans_from_pddl`` asks a planner for plans; ``plan_from_pddl`` turns
them into one Petri Net Plan (``Plan.from_plans``): one plan as a sequence, k
plans merged by their common prefixes, with a choice point wherever they
differ, for a learner to find which of them the world rewards.

Names: a grounded action ``move(a, b)`` is the plan's action ``move_a_b``
(its name and arguments, lower case, joined by ``_``), as ``learnpnp
generate`` names an IPC plan file's ``(move a b)``.

>>> plan_from_pddl("domain.pddl", "problem.pddl", k=5)  # doctest: +SKIP
Plan('problem': 0 atoms, 9 actions)
"""

from __future__ import annotations

import os
from typing import Any, List, Optional, Sequence, Union

from .._native import Plan

_Path = Union[str, "os.PathLike[str]"]

PLANNERS = ("symk", "fast-downward")
"""The planners ``planner=`` names: SymK (top-k) and Fast Downward (one plan)."""

_PACKAGES = {"symk": "up-symk", "fast-downward": "up-fast-downward"}


class PlanningError(RuntimeError):
    """A planner that is not installed, finds no plan, or runs out of time:
    the message names the planner and what happened."""


def grounded_name(name: str, args: Sequence[str]) -> str:
    """The plan's action for a grounded action: ``move``, ``[a, b]`` is ``move_a_b``."""
    return "_".join([name.lower(), *(a.lower() for a in args)])


def _action_name(action: Any) -> str:
    return grounded_name(action.action.name, [str(p) for p in action.actual_parameters])


def _problem(domain: _Path, problem: _Path) -> Any:
    try:
        from unified_planning.io import PDDLReader
        from unified_planning.shortcuts import get_environment
    except ImportError as e:
        raise PlanningError(
            "unified-planning is not installed: pip install './python[planning]' (or unified-planning with up-symk / up-fast-downward)"
        ) from e
    get_environment().credits_stream = None
    return PDDLReader().parse_problem(os.fspath(domain), os.fspath(problem))


def _engine(planner: str) -> None:
    if planner not in PLANNERS:
        raise PlanningError(f"planner '{planner}': it must be one of {', '.join(PLANNERS)}")
    from unified_planning.shortcuts import get_environment

    if planner not in get_environment().factory.engines:
        raise PlanningError(f"planner '{planner}' is not installed: pip install {_PACKAGES[planner]}")


def plans_from_pddl(
    domain: _Path,
    problem: _Path,
    k: int = 5,
    planner: str = "symk",
    timeout: Optional[float] = 60.0,
) -> List[List[str]]:
    """Up to ``k`` distinct plans of the PDDL ``problem`` in ``domain``, best
    first, each a list of the plan's action names (``move_a_b``).

    ``planner``: ``"symk"`` (top-k planning, its k best plans) or
    ``"fast-downward"`` (one plan: ``k`` must be 1). ``timeout``: seconds the
    planner may take. Raises ``PlanningError`` naming the planner when it is
    not installed, finds no plan or times out.
    """
    if k < 1:
        raise ValueError(f"k = {k}: at least one plan")
    if planner == "fast-downward" and k != 1:
        raise PlanningError("planner 'fast-downward' finds one plan: use k=1, or planner='symk' for the k best")
    parsed = _problem(domain, problem)
    _engine(planner)
    from unified_planning.engines import PlanGenerationResultStatus as Status
    from unified_planning.shortcuts import AnytimePlanner, OneshotPlanner

    found: List[List[str]] = []
    last = None
    if planner == "fast-downward":
        with OneshotPlanner(name=planner) as engine:
            result = engine.solve(parsed, timeout=timeout)
            last = result.status
            if result.plan is not None:
                found.append([_action_name(a) for a in result.plan.actions])
    else:
        with AnytimePlanner(name=planner, params={"number_of_plans": k}) as engine:
            for result in engine.get_solutions(parsed, timeout=timeout):
                last = result.status
                if result.plan is None:
                    continue
                names = [_action_name(a) for a in result.plan.actions]
                if names not in found:  # SymK may repeat the last plan at the end of its stream.
                    found.append(names)
                if len(found) == k:
                    break
    if not found:
        if last == Status.TIMEOUT:
            raise PlanningError(f"planner '{planner}' timed out after {timeout} s on {os.fspath(problem)}")
        raise PlanningError(f"planner '{planner}' found no plan for {os.fspath(problem)} (status {getattr(last, 'name', last)})")
    return found


def plan_from_pddl(
    domain: _Path,
    problem: _Path,
    k: int = 1,
    planner: Optional[str] = None,
    timeout: Optional[float] = 60.0,
    rules: Optional[str] = None,
    name: Optional[str] = None,
) -> Plan:
    """The Petri Net Plan of the planner's plans (``plans_from_pddl``): one
    plan as a sequence, ``k`` plans merged with a choice point wherever they
    differ; ``rules``: execution rules text (``*if* COND *during* ACTION *do*
    RECOVERY``), added as interrupts with their recovery. ``planner``: by
    default Fast Downward for one plan, SymK for more. ``name``: by default
    the problem file's name up to its first '.'."""
    chosen = planner or ("fast-downward" if k == 1 else "symk")
    plans = plans_from_pddl(domain, problem, k=k, planner=chosen, timeout=timeout)
    plan_name = name or os.path.basename(os.fspath(problem)).split(".")[0]
    return Plan.from_plans(plan_name, plans, rules=rules)


__all__ = ["PLANNERS", "PlanningError", "grounded_name", "plan_from_pddl", "plans_from_pddl"]
