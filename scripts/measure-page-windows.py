"""The page's cost within one run of the main job (issue 40): `learnpnp-supervisor
--view` runs, a headless Chromium is open throughout, and the page is opened
in a tab and closed again in turn, window after window; each window's cycles/s
is read from the simulator's journal (every episode's steps, appended as the
episode ends). Each window with the page open is set against the mean of the
windows without it just before and just after, so the run's own drift (its
episodes grow as the keepers learn) and the machine's slow changes cancel.
Prints each window, then the mean of those paired ratios with a seeded 95%
bootstrap interval, their median, and the ratio of the medians.

The view serves in every window (its cost alone is `served` in
measure-view-cost.sh); what differs is the page open in a browser.

    python3 scripts/measure-page-windows.py [--bin target/release] [--windows 100]
        [--seconds 6] [--settle 2] [--episodes 400000]
"""
import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import tempfile
import time
import urllib.request

from run_journal import Journal, chromium_flags

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--bin", default="target/release", help="the directory of learnpnp-supervisor")
parser.add_argument("--windows", type=int, default=100, help="windows in all, open and closed in turn")
parser.add_argument("--seconds", type=float, default=6.0, help="each window's length")
parser.add_argument("--settle", type=float, default=2.0, help="seconds left out after each opening or closing")
parser.add_argument("--episodes", default="400000", help="the run's episodes (more than the windows need)")
parser.add_argument("--port", type=int, default=18877, help="the view's port (loopback)")
parser.add_argument("--chromium", default=os.environ.get("CHROMIUM", "chromium"))
args = parser.parse_args()

debug_port = args.port + 400
CHROMIUM_FLAGS = chromium_flags()
out = tempfile.mkdtemp(prefix="learnpnp-page-windows-")
profile = tempfile.mkdtemp(prefix="learnpnp-page-windows-profile-")
browser = subprocess.Popen(
    [args.chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", f"--remote-debugging-port={debug_port}", "about:blank"],
    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
time.sleep(3)
log = open(os.path.join(out, "run.log"), "w")
run = subprocess.Popen(
    [os.path.join(args.bin, "learnpnp-supervisor"), "--out", os.path.join(out, "run"),
     "--episodes", args.episodes, f"--view=127.0.0.1:{args.port}"],
    stdout=log, stderr=subprocess.STDOUT)


def devtools(path, method="GET"):
    request = urllib.request.Request(f"http://127.0.0.1:{debug_port}{path}", method=method)
    with urllib.request.urlopen(request, timeout=10) as response:
        return json.loads(response.read() or b"null")


journal = Journal(out)
try:
    while journal.read() is None:
        time.sleep(0.1)
    time.sleep(2)
    rates = {"open": [], "closed": []}
    tab = None
    while run.poll() is None and len(rates["open"]) + len(rates["closed"]) < args.windows:
        if tab is None:
            tab = devtools(f"/json/new?http://127.0.0.1:{args.port}/", method="PUT")
            state = "open"
        else:
            urllib.request.urlopen(f"http://127.0.0.1:{debug_port}/json/close/{tab['id']}", timeout=10).read()
            tab, state = None, "closed"
        time.sleep(args.settle)
        steps, start = journal.read(), time.monotonic()
        time.sleep(args.seconds)
        if run.poll() is not None:
            break
        rate = (journal.read() - steps) / (time.monotonic() - start)
        rates[state].append(rate)
        print(f"{state:6s} {rate:8.0f} cycles/s", flush=True)
finally:
    browser.kill()
    if run.poll() is None:
        run.terminate()
        run.wait()
    log.close()
    shutil.rmtree(out, ignore_errors=True)
    shutil.rmtree(profile, ignore_errors=True)

opened, closed = rates["open"], rates["closed"]
# Window 2i is open[i]; the closed windows around it are closed[i-1] and closed[i].
pairs = [r / statistics.mean([closed[j] for j in (i - 1, i) if 0 <= j < len(closed)])
         for i, r in enumerate(opened) if i < len(closed) or i > 0]
rng = random.Random(1)
boots = sorted(statistics.mean(rng.choices(pairs, k=len(pairs))) for _ in range(10000))
print(f"page open / closed: {len(pairs)} windows, mean paired ratio {statistics.mean(pairs):.3f} "
      f"[95% CI {boots[250]:.3f}, {boots[9749]:.3f}], median {statistics.median(pairs):.3f}; "
      f"medians {statistics.median(opened):.0f} / {statistics.median(closed):.0f} = "
      f"{statistics.median(opened) / statistics.median(closed):.3f}")
