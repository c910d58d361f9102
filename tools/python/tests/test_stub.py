# SPDX-License-Identifier: MIT
"""The type stub sfit/__init__.pyi against the module (issue 26): every
function it declares has the runtime's parameters (names, kinds, defaults,
in order), every class its methods (and their parameters where the runtime
exposes a signature), every record the runtime's fields exactly, and every
constant exists. A stub that drifts from the module fails here."""
import ast
import builtins
import inspect
import os

import pytest

import sfit

ALIASES = {"ArrayLike", "Vec3", "Mat3", "Mode", "Kind", "NoiseVar"}


def _tree():
    path = os.path.join(os.path.dirname(sfit.__file__), "__init__.pyi")
    return ast.parse(open(path, encoding="utf-8").read())


def _default(node):
    """The stub's default as a value (literals only; anything else is left
    to the name check)."""
    try:
        return ast.literal_eval(node)
    except ValueError:
        return inspect.Parameter.empty


def _stub_params(fn, drop_first):
    """[(name, kind, default)] of a stub function."""
    a = fn.args
    out = []
    pos = a.posonlyargs + a.args
    defaults = [None] * (len(pos) - len(a.defaults)) + list(a.defaults)
    for arg, d in zip(pos, defaults):
        kind = (inspect.Parameter.POSITIONAL_ONLY if arg in a.posonlyargs
                else inspect.Parameter.POSITIONAL_OR_KEYWORD)
        out.append((arg.arg, kind, inspect.Parameter.empty if d is None else _default(d)))
    if a.vararg is not None:
        out.append((a.vararg.arg, inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.empty))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, inspect.Parameter.KEYWORD_ONLY,
                    inspect.Parameter.empty if d is None else _default(d)))
    if a.kwarg is not None:
        out.append((a.kwarg.arg, inspect.Parameter.VAR_KEYWORD, inspect.Parameter.empty))
    return out[1:] if drop_first else out


def _runtime_params(obj, drop_first):
    sig = inspect.signature(obj)
    ps = [(p.name, p.kind, p.default) for p in sig.parameters.values()]
    return ps[1:] if drop_first else ps


def _decorators(fn):
    return {getattr(d, "id", getattr(d, "attr", "")) for d in fn.decorator_list}


def _check_function(fn, obj, where, drop_stub=False, drop_rt=False):
    want = _stub_params(fn, drop_stub)
    try:
        got = _runtime_params(obj, drop_rt)
    except (ValueError, TypeError):
        return False  # a C method without a text signature: the name only
    if [k for _, k, _ in got] == [inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD]:
        return False  # a C slot (__init__ of a C type): no signature to compare
    assert [(n, k) for n, k, _ in want] == [(n, k) for n, k, _ in got], (
        "%s: stub parameters %s, runtime %s" % (where, want, got))
    for (n, _, dw), (_, _, dg) in zip(want, got):
        if dw is not inspect.Parameter.empty:
            assert dw == dg, "%s: default of %s: stub %r, runtime %r" % (where, n, dw, dg)
        else:
            assert dg is inspect.Parameter.empty or not isinstance(
                dg, (int, float, str, bool, type(None))), (
                "%s: %s has a default at runtime (%r) but not in the stub" % (where, n, dg))
    return True


def _classes():
    return [n for n in _tree().body if isinstance(n, ast.ClassDef)]


def _functions():
    return [n for n in _tree().body if isinstance(n, ast.FunctionDef)]


def test_functions_match_the_runtime():
    checked = 0
    for fn in _functions():
        obj = getattr(sfit, fn.name, None)
        assert callable(obj), "stub function %s is not in the module" % fn.name
        checked += _check_function(fn, obj, fn.name)
    # every module-level function is a Python function: all compared
    assert checked == len(_functions()) >= 18, (checked, len(_functions()))


def test_constants_exist():
    for node in _tree().body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            name = node.target.id
            assert hasattr(sfit, name), name
            if name.isupper():
                assert isinstance(getattr(sfit, name), int), name


@pytest.mark.parametrize("cls", _classes(), ids=lambda c: c.name)
def test_class_matches_the_runtime(cls):
    rt = getattr(sfit, cls.name, None)
    assert isinstance(rt, type), "stub class %s is not in the module" % cls.name
    fields = [n.target.id for n in cls.body
              if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)]
    bases = {getattr(b, "id", "") for b in cls.bases}
    if issubclass(rt, BaseException):
        # the error classes: the stub's bases (their fields are set per raise)
        for b in bases:
            base = getattr(sfit, b, None) or getattr(builtins, b)
            assert issubclass(rt, base), "%s is not a %s" % (cls.name, b)
        return
    slots = [f for f in getattr(rt, "__slots__", ()) if not f.startswith("_")]
    if fields:
        # a record: exactly the runtime's fields, in its order
        assert fields == list(slots), "%s: stub fields %s, runtime %s" % (cls.name, fields,
                                                                          list(slots))
    for fn in (n for n in cls.body if isinstance(n, ast.FunctionDef)):
        where = "%s.%s" % (cls.name, fn.name)
        assert hasattr(rt, fn.name), "%s is not in the module" % where
        deco = _decorators(fn)
        attr = inspect.getattr_static(rt, fn.name)
        if "property" in deco:
            assert isinstance(attr, property) or type(attr).__name__ == "getset_descriptor", where
            continue
        if fn.name in ("__len__",):
            continue
        # a classmethod comes bound (no cls at runtime), a method as a function
        _check_function(fn, getattr(rt, fn.name), where, drop_stub=True,
                        drop_rt="classmethod" not in deco)


def test_every_public_callable_is_in_the_stub():
    """The other direction: sfit.__all__ and every public method of the
    module's classes appear in the stub."""
    stub = {n.name for n in _functions()} | {c.name for c in _classes()}
    stub |= {n.target.id for n in _tree().body
             if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}
    missing = [n for n in sfit.__all__ if n not in stub]
    assert not missing, missing
    for cls in _classes():
        rt = getattr(sfit, cls.name)
        declared = {n.name for n in cls.body if isinstance(n, ast.FunctionDef)}
        declared |= {n.target.id for n in cls.body
                     if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}
        for name, attr in vars(rt).items():
            if name.startswith("_") or name in ("to_dict",):
                continue
            if type(attr).__name__ == "member_descriptor":
                continue  # a record's slot: checked as a field
            assert name in declared, "%s.%s is not in the stub" % (cls.name, name)
