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


#: The ctypes scalars of the messages: how layouts.py names each, and the Python type ctypes reads it as.
SCALARS = {
    ctypes.c_uint8: ("c_uint8", "int"),
    ctypes.c_uint32: ("c_uint32", "int"),
    ctypes.c_uint64: ("c_uint64", "int"),
    ctypes.c_double: ("c_double", "float"),
}


def element(c_type):
    """An array's element as an annotation names it (``ctypes.c_uint8``, ...)."""
    if issubclass(c_type, ctypes.Array):
        return f"ctypes.Array[{element(c_type._type_)}]"
    return f"ctypes.{SCALARS[c_type][0]}"


def annotation(c_type):
    """The annotation of a field of C type ``c_type``: the Python type ctypes
    reads it as, a ``ctypes.Array`` for arrays, the structure for structures."""
    if issubclass(c_type, ctypes.Array):
        return f"ctypes.Array[{element(c_type._type_)}]"
    return SCALARS[c_type][1] if c_type in SCALARS else c_type.__name__


@pytest.mark.parametrize("name", sorted(LAYOUTS["types"]))
def test_annotations_match_the_fields(name):
    # What a type checker reads (the annotations) is what ctypes lays out (_fields_), in order.
    mirror = MIRRORS[name]
    assert list(mirror.__annotations__.items()) == [(f, annotation(t)) for f, t in mirror._fields_]


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
