"""The main job's cycles/s through each run, every few seconds (issue 40):
`learnpnp-supervisor` on its defaults (plus any `--job-args`), whole runs alternating between modes
(the first mode of each round turns), each run's steps read from the
simulator's journal (every episode's steps, appended as the episode ends).
Modes: `none` (no view), `served` (`--view`, no client: the view process
alone, as when the page is open on another machine), `page` (`--view`, a
headless Chromium started on a blank page before the run and the page opened
in a tab once the view listens), `page2` (the same, the page redrawn every
2 s: `?every=2`), and, to calibrate what other work costs the run, `burn` (no
view; beside the run, a process of normal priority taking 10 ms of CPU once a
second, 1% of a core, in one burst) and `burn-batch` (the same process
scheduled as SCHED_BATCH, as the view's threads are).

It shows what a run's single figure hides: on this 2-core machine a run moves
between two speeds for tens of seconds at a time, so whole runs differ by more
than the view costs. Prints one line per run: the mode, the round and its rate
in thousands of cycles/s for each stretch (the first, the run's start, left
out of what follows); then, per mode, the share of stretches above `--split`
(the faster speed) and the median of the stretches above and below it, each
against the first mode's: the cost within either speed, apart from how long
runs spent in each.

    python3 scripts/measure-run-profile.py [--bin target/release] [--rounds 4]
        [--modes none served page page2 burn burn-batch] [--every 4] [--split 53.5] [--job-args "--wait hybrid"]
"""
import argparse
import os
import shutil
import socket
import statistics
import subprocess
import tempfile
import time
import urllib.request

from run_journal import Journal, chromium_flags

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--bin", default="target/release", help="the directory of learnpnp-supervisor")
parser.add_argument("--rounds", type=int, default=4)
parser.add_argument("--modes", nargs="+", default=["none", "page"], choices=["none", "served", "page", "page2", "burn", "burn-batch"])
parser.add_argument("--every", type=float, default=4.0, help="seconds a stretch lasts")
parser.add_argument("--split", type=float, default=53.5,
                    help="thousands of cycles/s between the two speeds (this machine's)")
parser.add_argument("--port", type=int, default=18800, help="the view's first port (loopback)")
parser.add_argument("--job-args", default="", help="more arguments for every run, e.g. '--wait hybrid'")
parser.add_argument("--chromium", default=os.environ.get("CHROMIUM", "chromium"))
args = parser.parse_args()

CHROMIUM_FLAGS = chromium_flags()

# The `burn` modes' process: 10 ms of its own CPU time, then a second's sleep, over and over.
BURNER = """
import time
while True:
    start = time.thread_time()
    while time.thread_time() - start < 0.010:
        pass
    time.sleep(1)
"""


def open_page(port, debug_port, query):
    """Opens the page (with `query`) in a tab once the view listens; whether it did."""
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
        request = urllib.request.Request(
            f"http://127.0.0.1:{debug_port}/json/new?http://127.0.0.1:{port}/{query}", method="PUT")
        urllib.request.urlopen(request, timeout=5).read()
        return True
    except OSError:
        return False


def one_run(mode, round_):
    out = tempfile.mkdtemp(prefix="learnpnp-run-profile-")
    port, debug_port = args.port + round_, args.port + 400 + round_
    command = [os.path.join(args.bin, "learnpnp-supervisor"), "--out", os.path.join(out, "run"), *args.job_args.split()]
    beside = None  # the process beside the run: the browser, or the burner
    paged = mode in ("page", "page2")
    if paged:
        beside = subprocess.Popen(
            [args.chromium, *CHROMIUM_FLAGS, f"--user-data-dir={os.path.join(out, 'profile')}",
             f"--remote-debugging-port={debug_port}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(3)
    if mode in ("burn", "burn-batch"):
        batch = ["chrt", "--batch", "0"] if mode == "burn-batch" else []
        beside = subprocess.Popen([*batch, "python3", "-c", BURNER])
    elif mode != "none":
        command.append(f"--view=127.0.0.1:{port}")
    with open(os.path.join(out, "run.log"), "w") as log:
        run = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
    try:
        journal = Journal(out)
        while journal.read() is None and run.poll() is None:
            time.sleep(0.05)
        opened = not paged
        rates, last = [], (time.monotonic(), journal.read())
        while run.poll() is None:
            time.sleep(0.25)
            opened = opened or open_page(port, debug_port, "%3Fevery=2" if mode == "page2" else "")
            now = time.monotonic()
            if now - last[0] >= args.every:
                steps = journal.read()
                if steps is None:  # the run is ending: its directory has its final name
                    break
                rates.append((steps - last[1]) / (now - last[0]))
                last = (now, steps)
    finally:
        if beside:
            beside.kill()
            beside.wait()
        try:
            run.wait(timeout=60)
        except subprocess.TimeoutExpired:
            run.terminate()
            run.wait()
        shutil.rmtree(out, ignore_errors=True)
    print(f"{mode:5s} {round_ + 1:2d} " + " ".join(f"{r / 1000:5.1f}" for r in rates), flush=True)
    return [r / 1000 for r in rates[1:]]


def median_or_none(values):
    return statistics.median(values) if values else None


print(f"thousands of cycles/s per {args.every:g} s stretch of each run")
stretches = {mode: [] for mode in args.modes}
for round_ in range(args.rounds):
    for i in range(len(args.modes)):
        mode = args.modes[(i + round_) % len(args.modes)]
        stretches[mode] += one_run(mode, round_)
base = args.modes[0]
speeds = {}
for mode, rates in stretches.items():
    fast = [r for r in rates if r >= args.split]
    slow = [r for r in rates if r < args.split]
    speeds[mode] = (median_or_none(fast), median_or_none(slow))
    line = f"{mode:5s} {len(rates)} stretches, {len(fast) / max(len(rates), 1):.0%} at the faster speed"
    for name, value, at_base in (("faster", speeds[mode][0], speeds[base][0]),
                                 ("slower", speeds[mode][1], speeds[base][1])):
        if value is not None:
            line += f"; {name} median {value:.1f}"
            if mode != base and at_base:
                line += f" ({value / at_base:.3f} of {base}'s)"
    print(line)
