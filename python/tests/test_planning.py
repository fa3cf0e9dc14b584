"""Plans from a PDDL model through real planners (learnpnp.planning): SymK's
k best plans and Fast Downward's one, merged into a plan that passes the
checks, the command-line wrapper, the planners' errors, a public benchmark
(IPC 2000 logistics), and the learner finding on the delivery world which of
the planner's plans the world rewards."""

import pathlib
import subprocess
import sys
import types

import pytest

import learnpnp

pytest.importorskip("unified_planning", reason="the planning extra (pip install './python[planning]')")

from learnpnp.planning import PlanningError, grounded_name, plan_from_pddl, plans_from_pddl  # noqa: E402

PDDL = pathlib.Path(__file__).resolve().parents[2] / "plans" / "pddl"
DELIVERY = PDDL / "delivery"
sys.path.insert(0, str(DELIVERY))
import world as delivery  # noqa: E402

DOOR_PLAN = ["pick_parcel_depot", "move_depot_hall", "move_hall_office", "drop_parcel_office"]
ROUND_PLAN = ["pick_parcel_depot", "move_depot_corridor", "move_corridor_annex", "move_annex_office", "drop_parcel_office"]


def test_grounded_names_join_name_and_arguments():
    assert grounded_name("Move", ["A", "b"]) == "move_a_b"


def test_symk_gives_the_k_best_plans_and_fast_downward_the_first():
    top = plans_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=5, planner="symk")
    assert len(top) == 5 and len({tuple(p) for p in top}) == 5
    assert top[0] == DOOR_PLAN and ROUND_PLAN in top
    first = plans_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=1, planner="fast-downward")
    assert first == [DOOR_PLAN]


def test_the_merged_plan_passes_the_checks_and_chooses_where_plans_differ():
    plan = plan_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=5)
    report = plan.check()
    assert report["failures"] == [], report
    choices = report["choice_points"]
    assert any("move_depot_corridor.start" in c and "move_depot_hall.start" in c for c in choices), choices
    with_rule = plan_from_pddl(
        DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=5, rules=(DELIVERY / "retry-door.er").read_text()
    )
    assert with_rule.check()["failures"] == []
    assert "door_locked" in with_rule.atoms and "wait_door" in with_rule.actions


def test_the_command_line_wrapper_writes_a_plan_that_loads(tmp_path):
    out = tmp_path / "plan.pnml"
    done = subprocess.run(
        [sys.executable, "-m", "learnpnp.planning", str(DELIVERY / "domain.pddl"), str(DELIVERY / "problem.pddl"), "-k", "5", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    plan = learnpnp.Plan.load(out)
    assert plan.name == "problem" and "move_annex_office" in plan.actions


def test_planner_errors_name_the_planner():
    domain, problem = DELIVERY / "domain.pddl", DELIVERY / "problem.pddl"
    with pytest.raises(PlanningError, match="planner 'lama'"):
        plans_from_pddl(domain, problem, planner="lama")
    with pytest.raises(PlanningError, match="'fast-downward' finds one plan"):
        plans_from_pddl(domain, problem, k=3, planner="fast-downward")


def test_a_planner_that_finds_no_plan_says_so(tmp_path):
    domain, problem = DELIVERY / "domain.pddl", DELIVERY / "problem.pddl"
    unsolvable = tmp_path / "unsolvable.pddl"
    unsolvable.write_text(problem.read_text().replace("(connected annex office) (connected office annex)", "").replace(
        "(connected hall office) (connected office hall)", ""
    ))
    for planner, k in (("symk", 2), ("fast-downward", 1)):
        with pytest.raises(PlanningError, match=f"planner '{planner}' found no plan"):
            plans_from_pddl(domain, unsolvable, k=k, planner=planner)


def test_a_planner_that_times_out_names_the_planner_and_the_timeout():
    # A millisecond: the planners' own start takes longer, so neither can answer in time.
    logistics = PDDL / "logistics"
    for planner, k in (("symk", 3), ("fast-downward", 1)):
        with pytest.raises(PlanningError, match=f"planner '{planner}' timed out after 0.001 s on .*problem.pddl"):
            plans_from_pddl(logistics / "domain.pddl", logistics / "problem.pddl", k=k, planner=planner, timeout=0.001)


def test_a_planner_not_installed_says_what_to_install(monkeypatch):
    import unified_planning.shortcuts as shortcuts

    bare = types.SimpleNamespace(credits_stream=None, factory=types.SimpleNamespace(engines=[]))
    monkeypatch.setattr(shortcuts, "get_environment", lambda: bare)
    for planner, package in (("symk", "up-symk"), ("fast-downward", "up-fast-downward")):
        with pytest.raises(PlanningError, match=f"planner '{planner}' is not installed: pip install {package}"):
            plans_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl", k=1, planner=planner)


def test_without_unified_planning_the_error_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "unified_planning.io", None)
    with pytest.raises(PlanningError, match=r"pip install './python\[planning\]'"):
        plans_from_pddl(DELIVERY / "domain.pddl", DELIVERY / "problem.pddl")


def test_a_public_benchmark_generates_checks_and_runs():
    logistics = PDDL / "logistics"
    plan = plan_from_pddl(logistics / "domain.pddl", logistics / "problem.pddl", k=3)
    assert plan.check()["failures"] == []
    agent = learnpnp.PlanAgent(plan, algo="q-learning", seed=1)
    for _ in range(5):
        started = []
        name = agent.act(set())
        while name is not None:
            started.append(name)
            agent.reward(-1.0)
            name = agent.act(set())
        agent.end_episode()
        assert len(started) == 20 and started[-1].startswith("unload"), started


SEEDS = range(10)
EPISODES = 1000


def greedy_route(plan, algo, seed):
    """The greedy route after learning, in the planner's model of the world."""
    agent = learnpnp.PlanAgent(plan, algo=algo, seed=seed)
    world = delivery.DeliveryWorld(seed=seed)
    for _ in range(EPISODES):
        delivery.run_episode(agent, world)
    model = delivery.DeliveryWorld(deterministic=True)
    started = []
    with agent.evaluate():
        model.reset()
        name = agent.act(set())
        while name is not None:
            started.append(name)
            _, status, atoms = model.step(name)
            name = agent.act(atoms & set(agent.atoms), status)
        agent.end_episode()
    return started


@pytest.mark.parametrize("algo", ["eps-sosmc", "q-learning"])
def test_the_learner_finds_the_plan_the_world_rewards(algo):
    """Without the rule the locked door makes the planner's first plan pay
    about 2 and the way round through the corridor about 6: the learner goes
    round. With the rule (wait and retry) the door pays about 11: it takes the
    door. Each in at least 8 of 10 seeds (the gaps are 4 and 5 in return, a
    few standard errors after 1,000 episodes)."""
    domain, problem = DELIVERY / "domain.pddl", DELIVERY / "problem.pddl"
    plain = plan_from_pddl(domain, problem, k=5)
    ruled = plan_from_pddl(domain, problem, k=5, rules=(DELIVERY / "retry-door.er").read_text())
    round_trips = sum(greedy_route(plain, algo, s)[:5] == ROUND_PLAN for s in SEEDS)
    door_trips = sum(greedy_route(ruled, algo, s)[:3] == DOOR_PLAN[:3] for s in SEEDS)
    print(f"\n{algo}: round the door without the rule in {round_trips}/10 seeds, through it with the rule in {door_trips}/10")
    assert round_trips >= 8 and door_trips >= 8
