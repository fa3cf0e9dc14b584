"""Shared fixtures: the repository's folders, and the plans built in Python."""

import os
import pathlib
import shutil
import sys
import tempfile

import pytest

import learnpnp

ROOT = pathlib.Path(__file__).resolve().parents[2]
PLANS = ROOT / "plans"
sys.path.insert(0, str(PLANS / "python"))


@pytest.fixture
def plans():
    """The repository's plans/ folder."""
    return PLANS


@pytest.fixture
def doors():
    """Builds the plan of two doors from the start: Left pays 1, Right 0."""

    def build():
        b = learnpnp.PlanBuilder("doors")
        start, goal = b.initial_place("start"), b.goal_place()
        b.action_into(start, "Left", goal)
        b.action_into(start, "Right", goal)
        return b.build(atoms=["Open"])

    return build


@pytest.fixture
def learnpnp_cli():
    """The `learnpnp` command built by `cargo test` or `cargo build` (skips if none)."""
    for candidate in (
        os.environ.get("LEARNPNP_CLI"),
        ROOT / "target" / "debug" / "learnpnp",
        ROOT / "target" / "release" / "learnpnp",
    ):
        if candidate and pathlib.Path(candidate).is_file():
            return str(candidate)
    if os.environ.get("LEARNPNP_REQUIRE_CLI"):
        pytest.fail("LEARNPNP_REQUIRE_CLI is set and no learnpnp command was found (set LEARNPNP_CLI)")
    pytest.skip("no learnpnp command built (cargo build --bin learnpnp)")


@pytest.fixture
def built_beside(learnpnp_cli):
    """Finds a binary built beside the `learnpnp` command by its name (skips if it is not built)."""

    def find(name):
        path = pathlib.Path(learnpnp_cli).parent / name
        if not path.is_file():
            pytest.skip(f"{path} is not built")
        return str(path)

    return find


@pytest.fixture
def supervisor(built_beside):
    """The `learnpnp-supervisor` built beside the `learnpnp` command."""
    return built_beside("learnpnp-supervisor")


@pytest.fixture
def sandbox():
    """A directory for a test's runs under /tmp (short: iceoryx2's unix
    socket paths are), removed after the test."""
    root = pathlib.Path(tempfile.mkdtemp(prefix="lpw", dir="/tmp"))
    yield root
    shutil.rmtree(root, ignore_errors=True)
