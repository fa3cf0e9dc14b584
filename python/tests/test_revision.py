"""Revise a plan, keep what was learned: PlanAgent.load into a revised plan
(issue 39) keeps the values of every option that did not change, exactly."""

import pytest

import learnpnp

CELLS = 3


def lake(moves):
    """A small navigation plan as a designer writes it with the builder: in
    every cell a choice among ``moves`` (back to sensing) or ``stop``; every
    move's execution place is ``<move>.exec`` in every cell."""
    b = learnpnp.PlanBuilder("lake")
    nav, goal = b.initial_place("nav"), b.goal_place()
    for c in range(CELLS):
        cell = b.place(f"cell_{c}")
        b.transition(f"[at_{c}]", [(nav, 1)], [(cell, 1)])
        for m in moves:
            b.action_into(cell, m, nav)
        b.action_into(cell, "stop", goal)
    return b.build(atoms=[f"at_{c}" for c in range(CELLS)])


def play(agent, episodes):
    """Episodes that walk from cell to cell: each move pays by its name, stop ends."""
    for e in range(episodes):
        cell = e % CELLS
        while (name := agent.act({f"at_{cell}"})) is not None:
            agent.reward({"left": -1.0, "right": 1.0, "up": 0.5, "down": 2.0, "stop": 0.0}[name])
            cell = (cell + 1) % CELLS
        agent.end_episode()


def learned(tmp_path, moves):
    agent = learnpnp.PlanAgent(lake(moves), algo="q-learning", seed=3, epsilon=0.5)
    play(agent, 200)
    path = tmp_path / "values.bin"
    agent.save(path)
    return agent, path


def test_a_revised_plan_keeps_the_values_of_the_options_that_remain(tmp_path):
    agent, path = learned(tmp_path, ["left", "right", "up"])
    # values() names markings by labels (cells repeat them): compare as multisets.
    old = sorted((v["marking"], v["value"]) for v in agent.values())
    revised = learnpnp.PlanAgent.load(path, lake(["right", "up", "down"]), seed=4, epsilon=0.5)
    report = revised.migration
    assert not report["unchanged"]
    assert report["kept"] == len(old) - sum("left.exec" in m for m, _ in old)
    assert report["dropped"] and all("left.exec<cell_" in e["marking"] for e in report["dropped"])
    assert report["ambiguous"] == []
    assert {o["option"] for o in report["new_options"]} == {"down.start"}
    assert [(c["added"], c["removed"]) for c in report["changed_choices"]] == [(["down.start"], ["left.start"])] * CELLS
    new = sorted((v["marking"], v["value"]) for v in revised.values())
    assert new == [(m, v) for m, v in old if "left.exec" not in m]  # exactly the old values
    # Every cell's options changed: their visit counts restart.
    assert all(v["visits"] == 0 for v in revised.values() if ".exec" in v["marking"])
    # Learning goes on in the revised plan, the new option included.
    play(revised, 200)
    assert any("down.exec" in v["marking"] for v in revised.values())


def test_the_same_plan_loads_as_saved(tmp_path):
    agent, path = learned(tmp_path, ["left", "right"])
    again = learnpnp.PlanAgent.load(path, lake(["left", "right"]))
    assert again.migration["unchanged"] and again.migration["kept"] == len(agent.values())
    assert again.values() == agent.values()
    assert learnpnp.PlanAgent(lake(["left"])).migration is None


def test_a_plan_that_shares_nothing_is_refused(tmp_path):
    _, path = learned(tmp_path, ["left", "right"])
    b = learnpnp.PlanBuilder("kick")
    start, goal = b.initial_place("start"), b.goal_place()
    b.action_into(start, "walk", goal)
    b.action_into(start, "turn", goal)
    with pytest.raises(ValueError, match=r"share nothing with plan 'kick'.*choice points are \[.*cell_0"):
        learnpnp.PlanAgent.load(path, b.build())
