"""``python -m learnpnp.planning DOMAIN PROBLEM -k 5 -o plan.pnml``: a plan
from a PDDL model through a planner, saved as PNML."""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from . import PLANNERS, PlanningError, plan_from_pddl


def main(argv: Optional[List[str]] = None) -> int:
    """Runs the command; returns its exit status: 0 the plan is written and
    passes the checks, 1 it is written and fails one, 2 no plan is made."""
    parser = argparse.ArgumentParser(prog="python -m learnpnp.planning", description=__doc__)
    parser.add_argument("domain", help="the PDDL domain file")
    parser.add_argument("problem", help="the PDDL problem file")
    parser.add_argument("-k", type=int, default=1, help="how many plans to merge (the k best; default 1)")
    parser.add_argument("--planner", choices=PLANNERS, help="default: fast-downward for one plan, symk for more")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds the planner may take (default 60)")
    parser.add_argument("--rules", help="an execution rules file (*if* COND *during* ACTION *do* RECOVERY)")
    parser.add_argument("--name", help="the plan's name (default: the problem file's)")
    parser.add_argument("-o", "--output", required=True, help="the PNML file to write")
    parser.add_argument("--to", choices=("jarp", "standard"), default="jarp", help="the PNML dialect (default jarp)")
    args = parser.parse_args(argv)
    try:
        rules = None
        if args.rules is not None:
            with open(args.rules, encoding="utf-8") as f:
                rules = f.read()
        plan = plan_from_pddl(args.domain, args.problem, k=args.k, planner=args.planner, timeout=args.timeout, rules=rules, name=args.name)
        plan.save(args.output, args.to)
    except (PlanningError, ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    # Every generated plan should pass (a fail_plan rule's recovery ends in the
    # declared failure end, which the checks accept); if one does not, the plan
    # is written and the failures shown.
    failures = plan.check()["failures"]
    if failures:
        print(f"{args.output}: the generated plan fails the checks: {failures}", file=sys.stderr)
        return 1
    print(f"{args.output}: plan '{plan.name}', {len(plan.actions)} actions; the checks pass", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
