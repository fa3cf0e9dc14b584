"""What the page measurements share (measure-page-windows.py,
measure-run-profile.py): the simulator's journal of a main-job run read as it
grows, and the flags the scripts start headless Chromium with."""
import glob
import json
import os


def chromium_flags():
    """The flags in `chromium-flags` beside this file (comment lines left out)."""
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "chromium-flags")) as flags:
        return [line.strip() for line in flags if line.strip() and not line.startswith("#")]


class Journal:
    """The steps of the episodes the simulator of the run written to `out`
    has journaled so far (read on from where it was)."""

    def __init__(self, out):
        self.out, self.offset, self.steps, self.partial = out, 0, 0, b""

    def read(self):
        """The steps so far; None while the run's staging directory does not
        exist (before it starts, and once it has its final name)."""
        found = glob.glob(os.path.join(self.out, ".run.staging-*", "runs", "run-0", "simulator.journal"))
        if not found:
            return None
        with open(found[0], "rb") as f:
            f.seek(self.offset)
            data = f.read()
        self.offset += len(data)
        lines = (self.partial + data).split(b"\n")
        self.partial = lines.pop()
        for line in lines:
            try:
                self.steps += json.loads(line)["outcome"]["steps"]
            except (ValueError, KeyError, TypeError):
                pass
        return self.steps
