"""A plan for gymnasium's grid worlds (CliffWalking, FrozenLake): in every cell,
a choice among the four moves.

The observation is the agent's cell, read as the atom ``at_N`` (N the cell's
index, as gymnasium numbers them); the plan senses the cell, then leaves the
move open. A learner in this plan learns what a tabular learner learns on the
grid: the plan shows the baseline case of learning in plan space, where the
designer leaves every choice open.
"""

import learnpnp

#: gymnasium's action order for both environments differs: each module below
#: names its own.
CLIFF_ACTIONS = ("up", "right", "down", "left")
LAKE_ACTIONS = ("left", "down", "right", "up")


def atoms(observation):
    """The atoms that hold in ``observation`` (a cell index)."""
    return (f"at_{int(observation)}",)


def build(name, cells, actions, goal_cells):
    """The plan: sense the cell among ``cells``, choose one of ``actions``,
    repeat; the cells of ``goal_cells`` lead to the goal."""
    b = learnpnp.PlanBuilder(name)
    sense = b.initial_place("sense")
    goal = b.goal_place()
    for cell in range(cells):
        if cell in goal_cells:
            b.transition(f"[at_{cell}]", [(sense, 1)], [(goal, 1)])
            continue
        here = b.place(f"cell_{cell}")
        b.transition(f"[at_{cell}]", [(sense, 1)], [(here, 1)])
        for action in actions:
            b.action_into(here, action, sense)
    return b.build(atoms=[f"at_{c}" for c in range(cells)])
