#!/usr/bin/env python3
"""The best Keepaway pass policy the 8 observations of Figure 7.3 can express.

Every deterministic policy over the three binary features of
plans/keepaway_pass.schema (lane to teammate 1 open, lane to teammate 2 open,
closest taker far) is a string of 8 letters, one per observation in the order
(L1, L2, F) = 111, 110, 101, 100, 011, 010, 001, 000: `h` hold, `1` pass to
the nearer teammate, `2` pass to the farther one. Each policy is written as a
plan schema with no choice (the learning keeper's plan with each observation
sent to one action) and scored with `learnpnp experiment keepaway-pass --plan`
by its greedy evaluation, the two other keepers playing the threshold policy
as in Figure 7.3. A coordinate ascent (change one observation's action while
the score rises by more than 0.05 s, common random numbers: one seed) runs
from each start; the optima are then scored on five fresh seeds.

Usage: observation_policies.py LEARNPNP OUT START [START ...] [-- EXPERIMENT-OPTIONS]
(for example `-- --vision full-state`; the options go to every experiment).
"""

import itertools
import pathlib
import re
import subprocess
import sys

OBSERVATIONS = list(itertools.product([1, 0], repeat=3))
ACTIONS = {"h": "hold", "1": "pass1", "2": "pass2"}
FEATURES = ("Lane1Open", "Lane2Open", "TakerFar")
HEAD = """machine keepaway_fixed_observation_policy
  initial decide
  state ball
  state hold {Hold}
  state pass1 {Pass1}
  state pass2 {Pass2}
  state intercept {Intercept}
  state support {GetOpen}
  decide -> ball [HasBall]
  decide -> intercept [and (not HasBall) Fastest]
  decide -> support [and (not HasBall) (not Fastest)]
"""
TAIL = """  hold -> decide on Hold.finished
  pass1 -> decide on Pass1.finished
  pass2 -> decide on Pass2.finished
  intercept -> decide on Intercept.finished
  support -> decide on GetOpen.finished
"""


def schema(policy: str) -> str:
    """The plan schema playing `policy` at the ball."""
    edges = []
    for values, action in zip(OBSERVATIONS, policy):
        literals = [name if held else f"(not {name})" for name, held in zip(FEATURES, values)]
        guard = f"and {literals[0]} (and {literals[1]} {literals[2]})"
        edges.append(f"  ball -> {ACTIONS[action]} [{guard}]\n")
    return HEAD + "".join(edges) + TAIL


class Scorer:
    """Scores policies with the learnpnp binary, remembering every score."""

    def __init__(self, learnpnp: str, out: pathlib.Path, options: list[str]):
        self.learnpnp = learnpnp
        self.out = out
        self.options = options
        self.scores: dict[tuple[str, int, int], float] = {}

    def score(self, policy: str, episodes: int = 1000, seed: int = 2011) -> float:
        key = (policy, episodes, seed)
        if key not in self.scores:
            plan = self.out / f"policy-{policy}.schema"
            plan.write_text(schema(policy))
            run = subprocess.run(
                [self.learnpnp, "experiment", "keepaway-pass", "--plan", str(plan), "--unchecked",
                 "--algo", "random", "--runs", "1", "--episodes", "1", "--eval-every", "1",
                 "--eval-episodes", "0", "--greedy-episodes", str(episodes), "--threads", "1",
                 "--seed", str(seed), "--out", str(self.out / f"run-{policy}-{seed}"), *self.options],
                capture_output=True, text=True, check=True)
            found = re.search(r"greedy ([0-9.]+) s", run.stdout + run.stderr)
            if found is None:
                raise RuntimeError(f"no greedy score for {policy}: {run.stderr[-400:]}")
            self.scores[key] = float(found.group(1))
        return self.scores[key]

    def ascend(self, policy: str) -> str:
        best = self.score(policy)
        improved = True
        while improved:
            improved = False
            for index in range(len(policy)):
                for action in ACTIONS:
                    if action != policy[index]:
                        other = policy[:index] + action + policy[index + 1:]
                        value = self.score(other)
                        if value > best + 0.05:
                            best, policy, improved = value, other, True
        return policy


def main() -> None:
    arguments = sys.argv[1:]
    options = arguments[arguments.index("--") + 1:] if "--" in arguments else []
    arguments = arguments[:arguments.index("--")] if "--" in arguments else arguments
    learnpnp, out, starts = arguments[0], pathlib.Path(arguments[1]), arguments[2:]
    out.mkdir(parents=True, exist_ok=True)
    scorer = Scorer(learnpnp, out, options)
    optima = []
    for start in starts:
        optimum = scorer.ascend(start)
        print(f"start {start} ({scorer.score(start):.2f} s) -> {optimum} ({scorer.score(optimum):.2f} s)", flush=True)
        optima.append(optimum)
    for optimum in dict.fromkeys(optima):
        fresh = [scorer.score(optimum, 1000, seed) for seed in (1, 2, 3, 4, 5)]
        print(f"{optimum}: fresh seeds {', '.join(f'{v:.2f}' for v in fresh)}; mean {sum(fresh) / 5:.2f} s")
    print(f"{len(scorer.scores)} evaluations of 1000 episodes")


if __name__ == "__main__":
    main()
