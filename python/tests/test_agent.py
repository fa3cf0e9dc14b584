"""PlanAgent: parameters as `learnpnp experiment` takes them, bad input, values files."""

import math
import os
import subprocess

import pytest

import learnpnp


def play(agent, episodes):
    """Episodes of the doors plan; returns the total reward."""
    total = 0.0
    for _ in range(episodes):
        while (name := agent.act({"Open": False})) is not None:
            reward = 1.0 if name == "Left" else 0.0
            agent.reward(reward)
            total += reward
        agent.end_episode()
    return total


@pytest.mark.parametrize("algo", learnpnp.ALGORITHMS)
def test_every_algorithm_learns_or_runs(algo, doors):
    agent = learnpnp.PlanAgent(doors(), algo=algo, seed=5)
    play(agent, 300)
    with agent.evaluate():
        assert agent.mode == "greedy"
        greedy = play(agent, 20)
    assert agent.mode == "learn"
    if algo != "random":
        assert greedy == 20, f"{algo} should open the left door greedily"


def test_parameters_have_the_commands_names_and_ranges(doors):
    assert "lambda" in learnpnp.PARAMETERS and "initial_value" in learnpnp.PARAMETERS
    learnpnp.PlanAgent(doors(), algo="sarsa-lambda", alpha=0.5, lambda_=0.8, epsilon="0.2:0:1000", gamma=1)
    learnpnp.PlanAgent(doors(), algo="soft-sosmc", tau=0.5, assess="every:10", step_size="inverse", initial_value=-4)
    learnpnp.PlanAgent(doors(), algo="sarsa0", consistent=True, every_marking=False, initial_value=-math.inf)
    learnpnp.PlanAgent(doors(), algo="soft-sosmc", unestimated="none", exploit_policy="last")
    with pytest.raises(ValueError, match="unknown exploit policy 'best'"):
        learnpnp.PlanAgent(doors(), algo="eps-sosmc", exploit_policy="best")
    with pytest.raises(ValueError, match=r"alpha: 5 is out of range: it must be a number from 0 \(excluded\) to 1"):
        learnpnp.PlanAgent(doors(), algo="q-learning", alpha=5)
    with pytest.raises(ValueError, match="it must be a finite number above 0"):
        learnpnp.PlanAgent(doors(), algo="soft-sosmc", tau=0)
    with pytest.raises(ValueError, match="unknown parameter: the parameters are gamma, alpha"):
        learnpnp.PlanAgent(doors(), algo="q-learning", alfa=0.1)
    with pytest.raises(ValueError, match="eps-sosmc, soft-sosmc"):
        learnpnp.PlanAgent(doors(), algo="dqn")
    with pytest.raises(ValueError, match="neither a number"):
        learnpnp.PlanAgent(doors(), algo="q-learning", alpha=[0.1])


def test_bad_input_is_refused_with_what_is_known(plans, doors):
    agent = learnpnp.PlanAgent(doors(), algo="q-learning")
    with pytest.raises(ValueError, match="unknown atom 'Closed': the plan's atoms are Open"):
        agent.act({"Closed"})
    agent.act(["Open"])
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValueError, match="not a finite number"):
            agent.reward(bad)
    with pytest.raises(ValueError, match="finished, running or failed"):
        agent.act(set(), status="done")
    with pytest.raises(ValueError, match="the environment does not have: its actions are Left"):
        learnpnp.PlanAgent(doors(), actions=["Left"])


def test_a_plan_failing_check_is_refused_unless_unchecked():
    b = learnpnp.PlanBuilder("unsafe")
    start = b.initial_place("start")
    twice = b.place("twice")
    b.transition("split", [(start, 1)], [(twice, 2)])
    b.action_into(twice, "Go", b.goal_place())
    plan = b.build()
    assert not plan.check()["passed"]
    with pytest.raises(learnpnp.PlanCheckError, match="unchecked=True"):
        learnpnp.PlanAgent(plan)
    learnpnp.PlanAgent(plan, unchecked=True)


def test_a_stalled_plan_says_where_it_waits():
    b = learnpnp.PlanBuilder("waits")
    start = b.initial_place("start")
    after = b.place("after")
    b.transition("[Ready]", [(start, 1)], [(after, 1)])
    b.action_into(after, "Go", b.goal_place())
    agent = learnpnp.PlanAgent(b.build(), algo="q-learning")
    with pytest.raises(learnpnp.PlanStalledError, match="start"):
        agent.act(set())
    assert agent.act({"Ready"}) == "Go"


def test_a_rust_panic_arrives_as_a_python_exception():
    provoke = getattr(learnpnp._native, "_provoke_panic", None)
    if provoke is None:
        if os.environ.get("LEARNPNP_REQUIRE_TESTING"):
            pytest.fail("LEARNPNP_REQUIRE_TESTING is set and the package was built without the `testing` feature")
        pytest.skip("the package was built without the cargo feature `testing`")
    with pytest.raises(BaseException) as caught:
        provoke()
    assert type(caught.value).__name__ == "PanicException"


def test_durative_actions_and_interrupts():
    b = learnpnp.PlanBuilder("durative")
    start, goal = b.initial_place("start"), b.goal_place()
    walk = b.action_into(start, "Walk", goal)
    stop = b.place("stopped")
    b.interrupt(walk, "Obstacle", stop)
    b.action_into(stop, "Wait", start)
    agent = learnpnp.PlanAgent(b.build(), algo="q-learning")
    assert agent.act(set()) == "Walk"
    assert agent.act(set(), status="running") == "Walk"
    assert agent.running == ["Walk"]
    assert agent.act({"Obstacle"}, status="running") == "Wait"
    assert agent.act(set()) == "Walk"
    assert agent.act(set()) is None and agent.status == "goal"
    agent.end_episode()


def test_values_files_are_the_commands(tmp_path, plans, learnpnp_cli):
    plan = learnpnp.Plan.load(plans / "choice_point.pnml")
    agent = learnpnp.PlanAgent(plan, algo="sarsa0", seed=2)
    for _ in range(30):
        while (name := agent.act(set())) is not None:
            agent.reward(2.0 if name == "ActionB" else 1.0)
        agent.end_episode()
    saved = tmp_path / "values.bin"
    agent.save(saved)
    listed = subprocess.run([learnpnp_cli, "values", str(saved)], capture_output=True, text=True, check=True).stdout
    rows = [line.split(",") for line in listed.strip().splitlines()[1:]]
    assert [(r[0], r[1], float(r[2]), int(r[3])) for r in rows] == [
        (v["plan"], v["marking"], v["value"], v["visits"]) for v in agent.values()
    ]
    again = learnpnp.PlanAgent.load(saved, plan)
    assert again.algo == "sarsa0" and again.values() == agent.values()
    # The reverse: values the command learned, loaded in Python.
    out = tmp_path / "run"
    subprocess.run(
        [learnpnp_cli, "experiment", "parr-russell", "--plan", str(plans / "parr_russell.pnml"),
         "--algo", "sarsa0", "--runs", "1", "--episodes", "30", "--out", str(out)],
        capture_output=True, check=True,
    )
    grid = learnpnp.Plan.load(plans / "parr_russell.pnml")
    loaded = learnpnp.PlanAgent.load(out / "values.bin", grid)
    assert loaded.values() and all(v["plan"] == "parr_russell" for v in loaded.values())
    with pytest.raises(ValueError, match="share nothing"):
        learnpnp.PlanAgent.load(out / "values.bin", plan)
