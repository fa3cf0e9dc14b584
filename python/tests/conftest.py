"""Shared fixtures: the repository's folders, and the plans built in Python."""

import os
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PLANS = ROOT / "plans"
sys.path.insert(0, str(PLANS / "python"))


@pytest.fixture
def plans():
    """The repository's plans/ folder."""
    return PLANS


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
