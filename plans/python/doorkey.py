"""A plan for MiniGrid's DoorKey (``MiniGrid-DoorKey-5x5-v0``, minigrid 3.x).

The agent must pick up the key, unlock the door with it and reach the goal
behind the door, seeing only its egocentric 7x7 view (walls and closed doors
occlude). The designer writes the obvious structure:
- three phases, each a loop that senses and then acts: find the key, find the
  door, find the goal; the plan moves on when the phase's target is reached;
- key right ahead (and not carried): ``pickup``; carrying the key: the door
  phase begins;
- closed door right ahead: ``toggle``; the door seen open: the goal phase
  begins;
- goal right ahead: ``forward``, into the plan's goal.

The plan leaves open how to search. In each phase, every other situation is a
choice point among ``left``, ``right`` and ``forward``: a situation is where
the phase's target is in view and whether the cell ahead is blocked, or, with
the target out of view, the agent's heading and whether the cell ahead is
blocked (3 phases x 9 situations x 2 = 54 choice points). The learner thus
learns how to approach a target it sees and where to look for one it does not
see (the door is always east of the agent's room and the goal south-east of
it, but the plan does not say so). With random choices the agent reaches the
goal in about 80% of the episodes, in about 130 steps; Q-learning (gamma 0.9,
the other parameters at their defaults) learns the shortest paths, about 10
steps, in 200 episodes.

Atoms, all from the observation (``obs["image"]``, ``obs["direction"]``):
- ``T_P`` for each target T (``key``, ``door``, ``goal``) and place P in view:
  ``ahead`` (the cell in front), ``front`` (straight ahead, farther), ``left``
  / ``right`` (ahead of the agent, to that side), ``beside_left`` /
  ``beside_right`` (on the agent's row, to that side), ``unseen`` (not in
  view). Exactly one holds for each target (DoorKey has one of each).
- ``door_open``: the door is in view and open.
- ``blocked``: the cell in front cannot be entered (wall, closed door, key...).
- ``carrying_key``: the key is carried (MiniGrid draws the carried object on
  the agent's own cell of the view).
- ``facing_east`` / ``facing_south`` / ``facing_west`` / ``facing_north``:
  the agent's heading (``obs["direction"]`` 0..3).
Actions: MiniGrid's, in index order (``ACTIONS``); the plan names ``left``,
``right``, ``forward``, ``pickup`` and ``toggle``.
"""

import numpy as np

import learnpnp

ACTIONS = ("left", "right", "forward", "pickup", "drop", "toggle", "done")
MOVES = ("left", "right", "forward")
TARGETS = ("key", "door", "goal")
#: Where a target is in view; ``ahead`` is handled by the designer's structure.
PLACES_IN_VIEW = ("ahead", "front", "left", "right", "beside_left", "beside_right")
HEADINGS = ("east", "south", "west", "north")  # obs["direction"] 0..3

# MiniGrid's encoding (minigrid.core.constants): object and door-state indices.
_OBJECT = {"empty": 1, "floor": 3, "door": 4, "key": 5, "goal": 8}
_DOOR_OPEN = 0
# The agent's cell in the 7x7 view (column, row): bottom centre, facing up.
_AGENT_X, _AGENT_Y = 3, 6


def atom_names():
    """Every atom of the plan, in a fixed order."""
    names = [f"{t}_{p}" for t in TARGETS for p in PLACES_IN_VIEW + ("unseen",)]
    return names + ["door_open", "blocked", "carrying_key"] + [f"facing_{h}" for h in HEADINGS]


def _place_in_view(x, y):
    """The place (``PLACES_IN_VIEW``) of view cell (column ``x``, row ``y``)."""
    if y == _AGENT_Y:
        return "beside_left" if x < _AGENT_X else "beside_right"
    if x == _AGENT_X:
        return "ahead" if y == _AGENT_Y - 1 else "front"
    return "left" if x < _AGENT_X else "right"


def atoms(env, observation):
    """The atoms that hold in ``observation`` (MiniGrid's dict observation).

    Reads the egocentric view and the heading only; ``env`` is not consulted
    (the argument keeps the signature of the other plans' ``atoms``).
    """
    image = observation["image"]
    objects, states = image[:, :, 0].copy(), image[:, :, 2]
    holds = {f"facing_{HEADINGS[int(observation['direction'])]}"}
    if objects[_AGENT_X, _AGENT_Y] == _OBJECT["key"]:
        holds.add("carrying_key")
    objects[_AGENT_X, _AGENT_Y] = _OBJECT["empty"]  # the carried object is not in view
    for target in TARGETS:
        cells = np.argwhere(objects == _OBJECT[target])
        if len(cells) == 0:
            holds.add(f"{target}_unseen")
            continue
        x, y = cells[0]  # DoorKey has one of each
        holds.add(f"{target}_{_place_in_view(x, y)}")
        if target == "door" and states[x, y] == _DOOR_OPEN:
            holds.add("door_open")
    ahead, ahead_state = objects[_AGENT_X, _AGENT_Y - 1], states[_AGENT_X, _AGENT_Y - 1]
    passable = ahead in (_OBJECT["empty"], _OBJECT["floor"], _OBJECT["goal"]) or (
        ahead == _OBJECT["door"] and ahead_state == _DOOR_OPEN
    )
    if not passable:
        holds.add("blocked")
    return holds


def _search(b, phase, target, guard):
    """The open part of a phase: from place ``phase``, when ``guard`` holds and
    ``target`` is not ahead, sense where it is (or, unseen, the heading) and
    whether the way is blocked, then choose a move and sense again."""
    situations = [(f"{target}_{p}", p) for p in PLACES_IN_VIEW if p != "ahead"]
    situations += [(f"and {target}_unseen facing_{h}", f"unseen_{h}") for h in HEADINGS]
    for condition, name in situations:
        for blocked, suffix in (("blocked", "blocked"), ("not blocked", "free")):
            here = b.place(f"seek_{target}_{name}_{suffix}")
            b.transition(f"[and ({guard}) ({condition}) ({blocked})]", [(phase, 1)], [(here, 1)])
            for move in MOVES:  # the choice point: how to look for the target
                b.action_into(here, move, phase)


def build():
    """The plan (a ``learnpnp.Plan``)."""
    b = learnpnp.PlanBuilder("doorkey")
    find_key = b.initial_place("find_key")
    find_door = b.place("find_door")
    find_goal = b.place("find_goal")
    goal = b.goal_place()
    # Key: right ahead, pick it up; once carried, look for the door.
    b.transition("[carrying_key]", [(find_key, 1)], [(find_door, 1)])
    pickup = b.place("before_key")
    b.transition("[and (not carrying_key) key_ahead]", [(find_key, 1)], [(pickup, 1)])
    b.action_into(pickup, "pickup", find_key)
    _search(b, find_key, "key", "not carrying_key")
    # Door: closed and right ahead, unlock it; once open, look for the goal.
    b.transition("[door_open]", [(find_door, 1)], [(find_goal, 1)])
    toggle = b.place("before_door")
    b.transition("[and (not door_open) door_ahead]", [(find_door, 1)], [(toggle, 1)])
    b.action_into(toggle, "toggle", find_door)
    _search(b, find_door, "door", "not door_open")
    # Goal: right ahead, step onto it (MiniGrid ends the episode there).
    step_in = b.place("before_goal")
    b.transition("[goal_ahead]", [(find_goal, 1)], [(step_in, 1)])
    b.action_into(step_in, "forward", goal)
    _search(b, find_goal, "goal", "not goal_ahead")
    return b.build(atoms=atom_names())
