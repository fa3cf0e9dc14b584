"""Why the main job runs at two speeds here: one main-job run (`learnpnp-supervisor`,
`--episodes`, default 40,000), and every `--every` seconds its cycles/s since
the last sample (the simulator's journal) beside how fast a cache line goes
between CPU 0 and CPU 1 just then (the `core_to_core` example, for
`--probe-ms` milliseconds, the run's processes waiting meanwhile).

On a virtual machine the host places the two virtual CPUs, and moves them;
the lock-step hands every cycle across both CPUs through shared memory, so
its speed follows the round trip. Prints one line per sample (seconds into
the run, cycles/s, round trips/s), then the samples grouped by the round
trip (split at `--split-trips` round trips/s): how many, and the median and
range of their cycles/s.

    cargo build --release -p learnpnp-probes --example core_to_core
    python3 scripts/measure-speed-placement.py [--bin target/release] [--episodes 40000]
"""
import argparse
import os
import shutil
import statistics
import subprocess
import tempfile
import time

from run_journal import Journal

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--bin", default="target/release", help="the directory of learnpnp-supervisor")
parser.add_argument("--probe", default="target/release/examples/core_to_core")
parser.add_argument("--episodes", type=int, default=40000)
parser.add_argument("--every", type=float, default=2.0, help="seconds between samples")
parser.add_argument("--probe-ms", type=int, default=100)
parser.add_argument("--split-trips", type=float, default=8e6,
                    help="round trips/s between the two placements (this machine's)")
args = parser.parse_args()


def round_trips():
    """Round trips a second between CPU 0 and CPU 1 now (None: the probe failed)."""
    done = subprocess.run([args.probe, str(args.probe_ms)], capture_output=True, text=True)
    try:
        return float(done.stdout.split(":")[1].split()[0])
    except (IndexError, ValueError):
        return None


out = tempfile.mkdtemp(prefix="learnpnp-speed-placement-")
run = subprocess.Popen(
    [os.path.join(args.bin, "learnpnp-supervisor"), "--out", os.path.join(out, "run"), "--episodes", str(args.episodes)],
    stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
journal = Journal(out)
samples, last, start = [], None, None
try:
    while run.poll() is None:
        time.sleep(args.every)
        steps, now = journal.read(), time.monotonic()
        if steps is None:
            continue
        if last is None:
            start = now
        else:
            rate = (steps - last[0]) / (now - last[1])
            trips = round_trips()
            samples.append((rate, trips))
            print(f"{now - start:6.1f} s  {rate:8.0f} cycles/s  {trips or 0:12.0f} round trips/s", flush=True)
            # The probe's own time is left out of the next sample.
            steps, now = journal.read(), time.monotonic()
        last = (steps, now)
    output = run.stdout.read().decode(errors="replace")
finally:
    if run.poll() is None:
        run.kill()
        run.wait()
    shutil.rmtree(out, ignore_errors=True)
print(*[line for line in output.splitlines() if "cycles/s" in line], sep="\n")
for name, group in (("far (round trips below the split)", [r for r, t in samples if t and t < args.split_trips]),
                    ("near (round trips above it)", [r for r, t in samples if t and t >= args.split_trips])):
    if group:
        print(f"{name}: {len(group)} samples, median {statistics.median(group):.0f} cycles/s "
              f"({min(group):.0f}-{max(group):.0f})")
    else:
        print(f"{name}: no samples")
