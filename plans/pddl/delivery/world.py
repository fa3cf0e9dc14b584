"""The delivery world, where the planner's model (domain.pddl) is wrong.

The model says every connection takes one unit-cost move. In this world:

- the door between hall and office is locked on 70% of the tries
  (``P_LOCKED``): a robot moving through it sees ``door_locked`` while the
  move runs; if its plan does not react, it gives up and stays in the hall;
- moves into and out of the corridor slip on 20% of them (``P_SLIP``): the
  robot stays where it was;
- the corridor is long: a move along it costs 2, not 1 (``CORRIDOR_COST``).

Every action costs 1 (moves along the corridor 2); delivering the parcel to
the office pays ``DELIVERY`` (20). An action whose precondition does not hold
where the robot really is does nothing (and costs its price). ``wait_door``
(the recovery of plans/pddl/delivery/retry-door.er) waits a step by the door.

``run_episode(agent, world)`` plays one episode of a ``learnpnp.PlanAgent``.
"""

from __future__ import annotations

import random
from typing import Optional, Set, Tuple

P_LOCKED = 0.7
P_SLIP = 0.2
CORRIDOR_COST = 2.0
DELIVERY = 20.0
MAX_STEPS = 40

ROOMS = ("depot", "hall", "office", "corridor", "annex")
DOOR = ("hall", "office")


class DeliveryWorld:
    """The world's state: where the robot and the parcel are, and whether the
    robot is held at the locked door. ``deterministic``: no locks and no slips
    (the planner's model, with the corridor's cost)."""

    def __init__(self, seed: int = 0, deterministic: bool = False) -> None:
        self.rng = random.Random(seed)
        self.deterministic = deterministic
        self.reset()

    def reset(self) -> None:
        """A new episode: robot and parcel at the depot."""
        self.robot = "depot"
        self.parcel: Optional[str] = "depot"  # None: held
        self.at_locked_door = False
        self.delivered = False

    def _chance(self, p: float) -> bool:
        return not self.deterministic and self.rng.random() < p

    def step(self, action: str) -> Tuple[float, str, Set[str]]:
        """Runs ``action`` for one step: its reward, its status (``finished``
        or ``running``) and the atoms that hold."""
        words = action.split("_")
        if words[0] == "move" and len(words) == 3:
            return self._move(words[1], words[2])
        self.at_locked_door = False
        if action == "wait_door":
            return -1.0, "finished", set()
        if words[0] == "pick" and len(words) == 3 and self.parcel == words[2] == self.robot:
            self.parcel = None
        elif words[0] == "drop" and len(words) == 3 and self.parcel is None and words[2] == self.robot:
            self.parcel = self.robot
            if self.robot == "office":
                self.delivered = True
                return DELIVERY - 1.0, "finished", set()
        return -1.0, "finished", set()

    def _move(self, src: str, dst: str) -> Tuple[float, str, Set[str]]:
        cost = -CORRIDOR_COST if "corridor" in (src, dst) else -1.0
        if self.robot != src:
            self.at_locked_door = False
            return cost, "finished", set()
        if (src, dst) in (DOOR, DOOR[::-1]):
            if self.at_locked_door:  # The plan did not react: the robot gives up.
                self.at_locked_door = False
                return 0.0, "finished", set()
            if self._chance(P_LOCKED):
                self.at_locked_door = True
                return cost, "running", {"door_locked"}
        elif "corridor" in (src, dst) and self._chance(P_SLIP):
            return cost, "finished", set()
        self.robot = dst
        return cost, "finished", set()


def run_episode(agent, world: DeliveryWorld) -> Tuple[float, bool]:
    """Plays one episode of ``agent``'s plan in ``world``: its return and
    whether the parcel reached the office."""
    world.reset()
    total, status, atoms = 0.0, "finished", set()
    try:
        for _ in range(MAX_STEPS):
            name = agent.act(atoms & set(agent.atoms), status)
            if name is None:
                break
            reward, status, atoms = world.step(name)
            agent.reward(reward)
            total += reward
    finally:
        agent.end_episode()
    return total, world.delivered
