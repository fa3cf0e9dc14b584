"""The installed package type-checks: mypy, with python/pyproject.toml's
configuration (strict), finds nothing in ``learnpnp`` as pip installed it
(the sources, the extension's stub and ``py.typed``)."""

import importlib.util
import pathlib
import subprocess
import sys

import pytest

PYPROJECT = pathlib.Path(__file__).resolve().parents[1] / "pyproject.toml"


def test_the_installed_package_type_checks(tmp_path):
    for needed in ("mypy", "pettingzoo"):  # (mypy reads PettingZoo's annotations for KeepawayAECEnv)
        if importlib.util.find_spec(needed) is None:
            pytest.skip(f"{needed} is not installed (python/requirements-test.txt pins it)")
    # From an empty folder, so that mypy reads the installed package (found by
    # its py.typed), not the source folder; with a cache of its own (a cold
    # check: about 6 s of CPU).
    run = subprocess.run(
        [sys.executable, "-m", "mypy", "--config-file", str(PYPROJECT), "--cache-dir", str(tmp_path / "cache"),
         "-p", "learnpnp"],
        cwd=tmp_path, capture_output=True, text=True,
    )
    assert run.returncode == 0, f"mypy reports:\n{run.stdout}{run.stderr}"
