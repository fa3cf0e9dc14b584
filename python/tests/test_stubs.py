"""The .pyi stubs name exactly what the extension has, with its parameters
and defaults, and everything public has a docstring."""

import ast
import inspect
import pathlib
import sys

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


def stub_parameters(function):
    """``(name, default)`` of each parameter of a stub's ``def`` (``*args`` and
    ``**kwargs`` with their stars, ``inspect.Parameter.empty`` for no default)."""
    args = function.args
    positional = args.posonlyargs + args.args
    defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)
    out = [(a.arg, d) for a, d in zip(positional, defaults)]
    out += [("*" + args.vararg.arg, None)] if args.vararg else []
    out += list(zip((a.arg for a in args.kwonlyargs), args.kw_defaults))
    out += [("**" + args.kwarg.arg, None)] if args.kwarg else []
    return [(name, inspect.Parameter.empty if d is None else ast.literal_eval(d)) for name, d in out]


def runtime_parameters(obj):
    """``(name, default)`` of each parameter of the extension's ``obj``, as pyo3's text signature gives them."""
    stars = {inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.VAR_KEYWORD: "**"}
    return [(stars.get(p.kind, "") + p.name, p.default) for p in inspect.signature(obj).parameters.values()]


def test_stub_signatures_match_the_extension():
    # Every method's parameters, in order, with their defaults (pyo3 shows a
    # default it cannot write as `...`: the stub must then give one).
    for node in ast.parse(STUB.read_text()).body:
        if not isinstance(node, ast.ClassDef):
            continue
        cls = getattr(_native, node.name)
        for function in (n for n in node.body if isinstance(n, ast.FunctionDef)):
            decorators = {d.id for d in function.decorator_list if isinstance(d, ast.Name)}
            if "property" in decorators:
                continue
            stub = stub_parameters(function)[0 if "staticmethod" in decorators else 1 :]
            try:
                runtime = runtime_parameters(cls if function.name == "__init__" else getattr(cls, function.name))
            except ValueError:
                assert sys.version_info < (3, 10), f"{node.name}.{function.name} has no signature"
                continue  # (Python 3.9's inspect reads no class's text signature)
            runtime = runtime[1:] if runtime and runtime[0][0] == "self" else runtime
            where = f"{node.name}.{function.name}"
            names = [n for n, _ in stub]
            assert names == [n for n, _ in runtime], f"{where}: {stub} in the stub, {runtime} in the extension"
            for (name, stub_default), (_, default) in zip(stub, runtime):
                if default is Ellipsis:
                    assert stub_default is not inspect.Parameter.empty, f"{where}: {name} has a default the stub lacks"
                else:
                    assert stub_default == default, f"{where}: {name}={stub_default!r} in the stub, {default!r} in Rust"


def test_everything_public_has_a_docstring():
    for module in (learnpnp, learnpnp.envs):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                assert obj.__doc__, f"{module.__name__}.{name} has no docstring"
                for attr, member in vars(obj).items():
                    if not attr.startswith("_") and callable(member):
                        assert member.__doc__, f"{name}.{attr} has no docstring"
