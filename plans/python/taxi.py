"""A plan for gymnasium's Taxi-v4 in the spirit of Dietterich's MAXQ task graph.

The designer writes what a taxi does, and leaves open what MAXQ leaves open:
- the subtask order: at the root the plan chooses between Get (go to the
  passenger and pick up) and Put (go to the destination and drop off), whether
  or not the passenger is aboard;
- navigation: Navigate(site) chooses, in each cell, among the four moves and
  ending the navigation with the subtask's last action (pickup or dropoff).
The learner learns in this plan's choice points; the environment's observation
is read as the plan's atoms by ``atoms``.

Atoms: ``taxi_R_C`` (the taxi's cell), ``waiting_S`` (the passenger waits at
site S), ``carrying`` (the passenger is aboard), ``dest_S`` (the destination).
Actions: gymnasium's ``south north east west pickup dropoff``.
"""

import gymnasium as gym
import numpy as np

import learnpnp

SITES = ("R", "G", "Y", "B")
ACTIONS = ("south", "north", "east", "west", "pickup", "dropoff")
MOVES = ACTIONS[:4]
SIZE = 5


def atom_names():
    """Every atom of the plan, in a fixed order."""
    cells = [f"taxi_{r}_{c}" for r in range(SIZE) for c in range(SIZE)]
    return cells + [f"waiting_{s}" for s in SITES] + ["carrying"] + [f"dest_{s}" for s in SITES]


def atoms(env, observation):
    """The atoms that hold in ``observation`` (an int of Taxi's state space)."""
    row, col, passenger, destination = env.unwrapped.decode(observation)
    holds = {f"taxi_{row}_{col}", f"dest_{SITES[destination]}"}
    holds.add("carrying" if passenger == 4 else f"waiting_{SITES[passenger]}")
    return holds


def _navigate(b, name, last_action, done):
    """Navigate(site) as place ``name``: sense the taxi's cell, then choose a
    move (back to the sensing) or the subtask's ``last_action`` (into ``done``)."""
    nav = b.place(name)
    for r in range(SIZE):
        for c in range(SIZE):
            cell = b.place(f"{name}_{r}_{c}")
            b.transition(f"[taxi_{r}_{c}]", [(nav, 1)], [(cell, 1)])
            for move in MOVES:
                b.action_into(cell, move, nav)
            b.action_into(cell, last_action, done)
    return nav


def build():
    """The plan (a ``learnpnp.Plan``)."""
    b = learnpnp.PlanBuilder("taxi")
    root = b.initial_place("root")
    subtasks = {}
    for aboard, sensed_name in (("not carrying", "empty"), ("carrying", "full")):
        sensed = b.place(f"root_{sensed_name}")
        b.transition(f"[{aboard}]", [(root, 1)], [(sensed, 1)])
        # The subtask order, left open: Get or Put, passenger aboard or not.
        for subtask in ("get", "put"):
            place = b.place(f"{subtask}_{sensed_name}")
            b.transition(f"choose_{subtask}", [(sensed, 1)], [(place, 1)])
            subtasks[subtask, sensed_name] = place
    # Get: navigate to the waiting passenger's site and pick up.
    for site in SITES:
        nav = _navigate(b, f"get_{site}", "pickup", root)
        b.transition(f"[waiting_{site}]", [(subtasks["get", "empty"], 1)], [(nav, 1)])
    # Put: navigate to the destination and drop off.
    for site in SITES:
        nav = _navigate(b, f"put_{site}", "dropoff", root)
        b.transition(f"[dest_{site}]", [(subtasks["put", "full"], 1)], [(nav, 1)])
    # The wrong subtask is its last action alone (illegal: -10 in Taxi).
    b.action_into(subtasks["get", "full"], "pickup", root)
    b.action_into(subtasks["put", "empty"], "dropoff", root)
    return b.build(atoms=atom_names())


class StartFrom(gym.Wrapper):
    """Resets into ``start`` (a Taxi state) when it is set."""

    def __init__(self, env):
        super().__init__(env)
        self.start = None

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        if self.start is not None:
            self.env.unwrapped.s = self.start
            obs = self.start
        return obs, info


def optimal_returns(env):
    """The optimal return from every state (value iteration, undiscounted)."""
    table = env.unwrapped.P
    value = np.zeros(env.observation_space.n)
    while True:
        q = np.array(
            [
                [sum(p * (r + (0.0 if done else value[s2])) for p, s2, r, done in table[s][a]) for a in table[s]]
                for s in range(len(value))
            ]
        )
        if np.abs(q.max(1) - value).max() < 1e-9:
            return q.max(1)
        value = q.max(1)


def greedy_returns(env, agent, starts):
    """The greedy policy's return from each of ``starts`` (``env`` a ``StartFrom``)."""
    out = []
    with agent.evaluate():
        for s in starts:
            env.start = s
            out.append(learnpnp.run_episode(env, agent, lambda o: atoms(env, o), ACTIONS)[0])
    env.start = None
    return np.array(out)
