# SPDX-License-Identifier: MIT
"""The package surface: the .pyi stub and the runtime agree, every public
callable has a docstring, and the version is the C library's."""
import ast
import os
import re

import sfit
from conftest import SOURCE_DIR


def _stub_names():
    path = os.path.join(os.path.dirname(sfit.__file__), "__init__.pyi")
    tree = ast.parse(open(path, encoding="utf-8").read())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names


def test_stub_covers_the_runtime():
    stub = _stub_names()
    missing = [n for n in sfit.__all__ if n not in stub]
    assert not missing, missing


def test_stub_names_exist_at_runtime():
    for name in _stub_names():
        if name in {"ArrayLike", "Vec3", "Mat3", "Mode", "Kind", "NoiseVar"}:
            continue
        assert hasattr(sfit, name), name


def test_docstrings():
    for name in sfit.__all__:
        obj = getattr(sfit, name)
        if callable(obj):
            assert obj.__doc__ and len(obj.__doc__) > 20, name
    for cls in (sfit.Moments, sfit.Incremental):
        for meth in ("add", "fit", "solve", "reset") if cls is sfit.Moments else ("add", "update", "fit", "estimate", "track", "start"):
            assert getattr(cls, meth).__doc__, (cls, meth)


def test_version_is_the_library_version():
    text = open(os.path.join(SOURCE_DIR, "lib", "include", "sfit", "sfit.h"), encoding="utf-8").read()
    want = ".".join(re.search(r"#define SFIT_VERSION_%s (\d+)" % k, text).group(1)
                    for k in ("MAJOR", "MINOR", "PATCH"))
    assert sfit.__version__ == want
