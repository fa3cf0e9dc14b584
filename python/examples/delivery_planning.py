"""The thesis's promise on a world whose model is wrong: a planner's k best
plans merged into one Petri Net Plan, and a learner finding which of them the
world rewards.

SymK gives the 5 best plans of plans/pddl/delivery (Fast Downward the first);
the world (plans/pddl/delivery/world.py) has a door the model does not know is
often locked, a corridor where moves slip, and a corridor cost the model does
not have. For 20 seeds this prints, for the planner's first plan and for the
merged top-5 plan learned with SoSMC and with Q-learning, each with and
without the execution rule plans/pddl/delivery/retry-door.er (wait by a
locked door and try again): the episodes until the greedy policy settles (the
greedy route to the drop, in the model, stays the same to the end of learning,
checked every 10 episodes), and the
greedy policy's success rate and return in the world (mean ± standard
deviation over the seeds). From the repository's root, with the planning
extra installed::

    python python/examples/delivery_planning.py [--seeds 20] [--episodes 1000]
"""

from __future__ import annotations

import argparse
import pathlib
import statistics
import sys
import tempfile
from typing import Dict, List, Optional, Sequence, Tuple

import learnpnp
from learnpnp.planning import plan_from_pddl, plans_from_pddl

DELIVERY = pathlib.Path(__file__).resolve().parents[2] / "plans" / "pddl" / "delivery"
sys.path.insert(0, str(DELIVERY))
import world as delivery  # noqa: E402

CHECK_EVERY = 10
EVALUATION = 200


def route(agent: learnpnp.PlanAgent, scratch: pathlib.Path) -> Tuple[str, ...]:
    """The greedy policy's route in the planner's model (no locks, no slips):
    its actions up to the drop (what it does after the parcel is delivered,
    finish or a useless move, is left out: it changes the return by 1). Run
    by a copy of the agent (its values saved in ``scratch`` and loaded), so
    that looking does not change the learner."""
    agent.save(scratch)
    agent = learnpnp.PlanAgent.load(scratch, agent.plan)
    model = delivery.DeliveryWorld(deterministic=True)
    started: List[str] = []
    with agent.evaluate():
        model.reset()
        status, atoms = "finished", set()
        for _ in range(delivery.MAX_STEPS):
            name = agent.act(atoms & set(agent.atoms), status)
            if name is None:
                break
            started.append(name)
            if name.startswith("drop_"):
                break
            _, status, atoms = model.step(name)
            agent.reward(0.0)
        agent.end_episode()
    return tuple(started)


def evaluate(agent: learnpnp.PlanAgent, seed: int) -> Tuple[float, float]:
    """The greedy policy's success rate and mean return over ``EVALUATION`` episodes."""
    world = delivery.DeliveryWorld(seed=10_000 + seed)
    with agent.evaluate():
        runs = [delivery.run_episode(agent, world) for _ in range(EVALUATION)]
    return sum(ok for _, ok in runs) / len(runs), statistics.fmean(r for r, _ in runs)


def learn(plan: learnpnp.Plan, algo: str, seed: int, episodes: int) -> Tuple[int, float, float]:
    """Learns ``episodes`` episodes: the episode after which the greedy route
    stayed the same, and the greedy success rate and return."""
    agent = learnpnp.PlanAgent(plan, algo=algo, seed=seed)
    world = delivery.DeliveryWorld(seed=seed)
    routes = []
    with tempfile.TemporaryDirectory() as scratch:
        for episode in range(1, episodes + 1):
            delivery.run_episode(agent, world)
            if episode % CHECK_EVERY == 0:
                routes.append((episode, route(agent, pathlib.Path(scratch) / "values.bin")))
    settled = routes[-1][0]
    for episode, r in reversed(routes):
        if r != routes[-1][1]:
            break
        settled = episode
    success, ret = evaluate(agent, seed)
    return settled, success, ret


def plans(rules: Optional[str]) -> Dict[str, learnpnp.Plan]:
    """The first plan (Fast Downward) and the merged top-5 (SymK), with ``rules``."""
    domain, problem = DELIVERY / "domain.pddl", DELIVERY / "problem.pddl"
    return {
        "first plan": plan_from_pddl(domain, problem, k=1, planner="fast-downward", rules=rules, name="first"),
        "top-5 merged": plan_from_pddl(domain, problem, k=5, planner="symk", rules=rules, name="top5"),
    }


def mean_sd(values: Sequence[float]) -> str:
    """``mean ± sd``."""
    return f"{statistics.fmean(values):.2f} ± {statistics.pstdev(values):.2f}"


def main(argv: Optional[List[str]] = None) -> None:
    """Prints the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--episodes", type=int, default=1000)
    args = parser.parse_args(argv)
    rule_text = (DELIVERY / "retry-door.er").read_text()
    top5 = plans_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=5, planner="symk")
    print("SymK's 5 plans:")
    for p in top5:
        print("  " + "; ".join(p))
    print()
    print(f"| plan | learner | execution rule | episodes until greedy settles | greedy success | greedy return |")
    print("|---|---|---|---|---|---|")
    for rule_name, rules in (("none", None), ("retry the door", rule_text)):
        made = plans(rules)
        first = made["first plan"]
        runs = [evaluate(learnpnp.PlanAgent(first, algo="random", seed=s), s) for s in range(args.seeds)]
        print(f"| first plan (Fast Downward) | none | {rule_name} | - | {mean_sd([s for s, _ in runs])} | {mean_sd([r for _, r in runs])} |")
        for algo in ("eps-sosmc", "q-learning"):
            runs3 = [learn(made["top-5 merged"], algo, s, args.episodes) for s in range(args.seeds)]
            print(
                f"| top-5 merged (SymK) | {algo} | {rule_name} | {mean_sd([e for e, _, _ in runs3])} "
                f"| {mean_sd([s for _, s, _ in runs3])} | {mean_sd([r for _, _, r in runs3])} |"
            )


if __name__ == "__main__":
    main()
