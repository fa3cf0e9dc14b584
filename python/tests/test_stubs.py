"""The .pyi stubs name exactly what the extension has, and everything public has a docstring."""

import ast
import inspect
import pathlib

import learnpnp
import learnpnp.envs
from learnpnp import _native

STUB = pathlib.Path(learnpnp.__file__).with_name("_native.pyi")


def stub_members():
    tree = ast.parse(STUB.read_text())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {
                n.name if isinstance(n, ast.FunctionDef) else n.target.id
                for n in node.body
                if isinstance(n, ast.FunctionDef) or (isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name))
            }
        elif isinstance(node, ast.FunctionDef):
            out[node.name] = set()
    return out


def runtime_members(cls):
    return {name for name in vars(cls) if not name.startswith("__") or name in ("__init__", "__enter__", "__exit__")}


def test_stubs_match_the_extension():
    stubs = stub_members()
    for name, members in stubs.items():
        assert hasattr(_native, name), f"the stub names {name}, which the extension lacks"
        runtime = getattr(_native, name)
        if inspect.isclass(runtime) and not issubclass(runtime, Exception):
            extra = {m for m in members if m != "__init__"} - runtime_members(runtime)
            assert not extra, f"{name}: the stub names {extra}, which the extension lacks"
            missing = {m for m in runtime_members(runtime) if not m.startswith("_")} - members
            assert not missing, f"{name}: {missing} missing from the stub"
    public = {n for n in dir(_native) if not n.startswith("_") and n not in ("ALGORITHMS", "PARAMETERS")}
    assert public <= set(stubs), f"missing from the stub: {public - set(stubs)}"


def test_everything_public_has_a_docstring():
    for module in (learnpnp, learnpnp.envs):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                assert obj.__doc__, f"{module.__name__}.{name} has no docstring"
                for attr, member in vars(obj).items():
                    if not attr.startswith("_") and callable(member):
                        assert member.__doc__, f"{name}.{attr} has no docstring"
