"""The live view's cost from the tables `measure-view-cost.sh` prints: for
each mode against the base mode (no view, or BASE: `blank` when the browser
was open in both), over every round of every file given, the mean of the
per-round ratios (the mode's cycles/s over the base's in the same round)
with a 95% bootstrap interval over rounds (seeded: the same files give the
same figures), and the ratio of the medians.

    python3 scripts/view_cost_stats.py RESULT.txt [RESULT.txt ...]
    BASE=blank python3 scripts/view_cost_stats.py RESULT.txt
"""
import math
import os
import random
import re
import statistics
import sys

BASE = os.environ.get("BASE", "none")
ROW = re.compile(r"^(none|blank|served|page2|page|client|all)\s+(\d+)\s+[\d.]+ [\d.]+ [\d.]+\s+(\d+)")

ratios = {}  # mode -> [log(mode / base), one per round]
values = {}  # mode -> [cycles/s]
for path in sys.argv[1:]:
    rounds = {}
    for line in open(path):
        m = ROW.match(line)
        if m:
            mode, round_, cycles = m.group(1), int(m.group(2)), int(m.group(3))
            rounds.setdefault(round_, {})[mode] = cycles
            values.setdefault(mode, []).append(cycles)
    for run in rounds.values():
        for mode, cycles in run.items():
            if mode != BASE and BASE in run:
                ratios.setdefault(mode, []).append(math.log(cycles / run[BASE]))
for mode, logs in sorted(ratios.items()):
    rng = random.Random(1)
    boots = sorted(statistics.mean(rng.choices(logs, k=len(logs))) for _ in range(10000))
    median_ratio = statistics.median(values[mode]) / statistics.median(values[BASE])
    print(
        f"{mode}: {len(logs)} rounds, mean paired ratio {math.exp(statistics.mean(logs)):.3f} "
        f"[95% CI {math.exp(boots[250]):.3f}, {math.exp(boots[9749]):.3f}]; medians: {BASE} "
        f"{statistics.median(values[BASE]):.0f}, {mode} {statistics.median(values[mode]):.0f}, ratio {median_ratio:.3f}"
    )
