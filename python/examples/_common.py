"""What the example world processes share: their command line (``--record``)
and serving a gymnasium environment with the atoms and actions of a plan
module of plans/python/."""

import argparse
import importlib
import pathlib
import sys
from types import ModuleType
from typing import Any, Callable

from learnpnp.world import RecordEpisodes, serve

#: The plan modules' folder (plans/python/ of the repository).
PLANS = pathlib.Path(__file__).resolve().parents[2] / "plans" / "python"


def plan_module(name: str) -> ModuleType:
    """The plan module ``name`` of plans/python/ (its atoms and actions)."""
    sys.path.insert(0, str(PLANS))
    return importlib.import_module(name)


def serve_plan_world(description: str, make_env: Callable[[], Any], plan: ModuleType) -> None:
    """Serves the environment ``make_env`` builds, with ``plan``'s atoms and
    actions, until the supervisor says stop; ``--record FILE`` appends one JSON
    line per episode the world served."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--record", help="append each episode the world served to this file (JSON lines)")
    args = parser.parse_args()
    env = make_env()
    if args.record:
        env = RecordEpisodes(env, args.record)
    try:
        serve(
            env,
            atoms=lambda observation: plan.atoms(env, observation),
            actions=plan.ACTIONS,
            atom_names=plan.atom_names(),
        )
    finally:
        env.close()
