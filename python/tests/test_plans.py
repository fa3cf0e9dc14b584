"""Plans from Python: loading, checking, drawing, building, and file errors."""

import pytest

import learnpnp


def test_loads_pnml_and_schema_and_checks(plans):
    net = learnpnp.Plan.load(plans / "parr_russell.pnml")
    assert net.name == "parr_russell"
    assert set(net.actions) == {"MoveNorth", "MoveSouth", "MoveEast", "MoveWest"}
    report = net.check()
    assert report["passed"] and report["failures"] == []
    assert report["verdicts"]["safety"] == "passed"
    assert "safety" in report["text"]
    schema = learnpnp.Plan.load(plans / "parr_russell.schema")
    assert schema.check()["passed"]
    assert "digraph" in schema.to_dot()
    assert set(schema.actions) == set(net.actions) and "WallLeft" in schema.atoms


def test_file_errors_name_file_element_and_token(tmp_path, plans):
    text = (plans / "choice_point.pnml").read_text()
    broken = tmp_path / "broken.pnml"
    broken.write_text(text.replace("<value>ActionA.end</value>", "<value>ActionA.end [done and]</value>"))
    with pytest.raises(learnpnp.PlanFileError) as caught:
        learnpnp.Plan.load(broken)
    error = caught.value
    assert error.file == str(broken)
    assert error.element is not None and error.element in str(error)
    assert error.token == "and" and "'and'" in str(error)
    assert isinstance(error, ValueError)
    with pytest.raises(learnpnp.PlanFileError) as missing:
        learnpnp.Plan.load(tmp_path / "absent.pnml")
    assert missing.value.file.endswith("absent.pnml")
    garbage = tmp_path / "garbage.schema"
    garbage.write_text("machine m\n  initial choose\n  choose -> nowhere [Wall and]\n")
    with pytest.raises(learnpnp.PlanFileError) as bad_schema:
        learnpnp.Plan.load(garbage)
    assert bad_schema.value.token is not None


def test_builder_has_the_rust_methods_and_refuses_misuse(tmp_path):
    b = learnpnp.PlanBuilder("demo")
    start = b.initial_place("start")
    goal = b.goal_place()
    seen = b.sensing(start, "look", ["ballSeen", "not ballSeen"])
    kick = b.action_into(seen.outcomes[0], "kick", goal)
    b.interrupt(kick, "not ballSeen", seen.outcomes[1])
    options = b.choice_of_actions(seen.outcomes[1], ["turnLeft", "turnRight"])
    for option in options:
        b.transition("back", [(option.done, 1)], [(start, 1)])
    plan = b.build(atoms=["ballSeen"])
    assert set(plan.actions) == {"look", "kick", "turnLeft", "turnRight"}
    assert plan.atoms == ["ballSeen"]
    assert plan.check()["passed"], plan.check()["text"]
    plan.save(tmp_path / "demo.pnml")
    again = learnpnp.Plan.load(tmp_path / "demo.pnml")
    assert again.actions == plan.actions
    with pytest.raises(ValueError, match="already built"):
        b.place("late")
    other = learnpnp.PlanBuilder("other")
    with pytest.raises(ValueError, match="another PlanBuilder"):
        other.action(start, "x")
    closed = learnpnp.PlanBuilder("closed")
    p = closed.initial_place("p")
    closed.transition("[unknownAtom]", [(p, 1)], [(closed.goal_place(), 1)])
    with pytest.raises(ValueError, match="unknownAtom"):
        closed.build(atoms=["known"])


def test_dot_carries_learned_values(plans):
    plan = learnpnp.Plan.load(plans / "choice_point.pnml")
    agent = learnpnp.PlanAgent(plan, algo="q-learning", seed=3)
    for _ in range(20):
        learnpnp_episode(agent)
    drawn = plan.to_dot(values=agent)
    assert "digraph" in drawn and drawn != plan.to_dot()


def learnpnp_episode(agent):
    """One episode of the choice-point plan: each action finishes at once, ActionA pays 1."""
    while (name := agent.act(set())) is not None:
        agent.reward(1.0 if name == "ActionA" else 0.0)
    agent.end_episode()
