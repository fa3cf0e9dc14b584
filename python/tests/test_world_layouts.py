"""The world kit's ctypes mirrors lie in memory as shm_layouts' Rust types:
every size and field offset, and the limits, as shm_layouts/layouts.json lists them."""

import ctypes
import json
import pathlib

import pytest

from learnpnp import world

LAYOUTS = json.loads(
    (pathlib.Path(__file__).resolve().parents[2] / "shm_layouts" / "layouts.json").read_text(encoding="utf-8")
)
MIRRORS = {t.__name__: t for t in world.MESSAGE_TYPES}


def test_every_listed_type_has_a_mirror():
    assert sorted(MIRRORS) == sorted(LAYOUTS["types"])


@pytest.mark.parametrize("name", sorted(LAYOUTS["types"]))
def test_size_offsets_and_type_name(name):
    mirror, layout = MIRRORS[name], LAYOUTS["types"][name]
    assert ctypes.sizeof(mirror) == layout["size"]
    assert ctypes.alignment(mirror) == 8
    assert [f for f, _ in mirror._fields_] == list(layout["offsets"])
    assert {f: getattr(mirror, f).offset for f, _ in mirror._fields_} == layout["offsets"]
    assert mirror.type_name() == f"learnpnp::{name}"


def test_limits_and_protocol_version():
    assert LAYOUTS["protocol_version"] == world.PROTOCOL_VERSION
    assert LAYOUTS["limits"] == {
        "MAX_ATOMS": world.MAX_ATOMS,
        "MAX_FLUENTS": world.MAX_FLUENTS,
        "MAX_ARGS": world.MAX_ARGS,
        "MAX_ACTIONS": world.MAX_ACTIONS,
        "MAX_AGENTS": world.MAX_AGENTS,
        "NAME_LEN": world.NAME_LEN,
        "NAMES_PER_PART": world.NAMES_PER_PART,
    }


def test_arrays_hold_the_limits():
    snapshot, command, vocabulary = world.WorldSnapshot(), world.WorldCommand(), world.WorldVocabulary()
    assert len(snapshot.atoms) * 64 == world.MAX_ATOMS
    assert len(snapshot.fluents) == world.MAX_FLUENTS
    assert len(command.args) == world.MAX_ARGS
    assert len(vocabulary.names) == world.NAMES_PER_PART
    assert len(vocabulary.names[0]) == world.NAME_LEN
    assert len(world.Heartbeat().rejected) == world.Reject.COUNT
