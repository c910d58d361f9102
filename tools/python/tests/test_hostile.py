# SPDX-License-Identifier: MIT
"""Hostile input to every public function, class and method of the sfit
package: wrong types, garbage objects (whose __array__ raises, returns
garbage or mutates the caller's list), wrong shapes and dtypes, non-contiguous
and negative-stride views, NaN / Inf / +-1e38 / 2**27 entries, too few and
degenerate samples, bad option values, subclasses whose __new__ returns
something else, methods before __init__, after errors and repeated.

The rule: every call either returns a result with no NaN / Inf in it (NaN
only where documented: the rows of Joint.center_at / joint_center whose
``valid`` is False) or raises sfit.Error (or one of its subclasses),
TypeError or ValueError (or the hostile object's own exception). A crash,
a SystemError or any other exception type is a defect. A call on a state
object that raises leaves the state unchanged.

Each public callable runs its cases in a child interpreter with
faulthandler on, so a crash names the case that caused it. The table of
cases must cover every public callable: test_table_covers_the_api fails
when sfit.__all__, a class or the .pyi stub has one without cases.

The hostile objects and shared case generators are in hostile_inputs.py,
the table of cases (build_cases) in hostile_cases.py.

Run one callable's cases by hand (no argument: the table's size):
    PYTHONPATH=build/python/lib python3 tools/python/tests/test_hostile.py fit
Under AddressSanitizer: build the extension with CFLAGS=-fsanitize=address
into another --build-lib and run the same with SFIT_NO_RLIMIT=1,
PYTHONMALLOC=malloc, ASAN_OPTIONS=detect_leaks=0 and
LD_PRELOAD=$(gcc -print-file-name=libasan.so).
"""
import ast
import os
import subprocess
import sys
import traceback

import numpy as np

import sfit

# pytest (None in the child runner), HAVE_JOINT, ALLOWED, NAN and INF come
# with the inputs (hostile_inputs.py) through the table's module.
from hostile_cases import *  # noqa: F401,F403  (the inputs and the table of cases)

# ---------------------------------------------------------------------------
# Checking one outcome
# ---------------------------------------------------------------------------

def nonfinite(x, path="result"):
    """The path of the first NaN / Inf in a result, or None."""
    if isinstance(x, (bool, np.bool_, int, np.integer, str, bytes, type(None))):
        return None
    if isinstance(x, (float, np.floating)):
        return None if np.isfinite(x) else path
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc" and not np.all(np.isfinite(x)):
            return path
        return None
    if isinstance(x, dict):
        for k, v in x.items():
            p = nonfinite(v, "%s[%r]" % (path, k))
            if p:
                return p
        return None
    if isinstance(x, (list, tuple)):
        for i, v in enumerate(x):
            p = nonfinite(v, "%s[%d]" % (path, i))
            if p:
                return p
        return None
    for k in getattr(type(x), "__slots__", ()):
        if not k.startswith("_") and k != "cluster":
            p = nonfinite(getattr(x, k, None), path + "." + k)
            if p:
                return p
    return None


def _valid_rows(name, out):
    """The documented NaN rows: Joint.center_at / joint_center where not valid."""
    if name == "Joint.center_at" and isinstance(out, tuple) and len(out) == 3:
        return np.asarray(out[2], dtype=bool)
    if name == "joint_center" and getattr(out, "valid", None) is not None:
        return np.asarray(out.valid, dtype=bool)
    return None


def _names_of(expect):
    want = expect if isinstance(expect, tuple) else (expect,)
    return "/".join(w.__name__ for w in want)


def check(name, label, thunk, expect):
    """'PASS' or 'FAIL: why'."""
    allowed = ALLOWED + (HostileError,)
    if expect is AttributeError or (isinstance(expect, tuple) and AttributeError in expect):
        allowed += (AttributeError,)
    if expect is OSError or (isinstance(expect, tuple) and OSError in expect):
        allowed += (OSError,)  # the C3D file functions: a path that cannot be read or written
    try:
        out = thunk()
    except AssertionError as e:
        return "FAIL: " + str(e)
    except BaseException as e:  # noqa: B902  (everything is judged)
        if isinstance(e, SystemError) or not isinstance(e, allowed):
            return "FAIL: %s: %s\n%s" % (type(e).__name__, e, traceback.format_exc())
        if isinstance(e, sfit.Error):
            for a in ("status", "code", "message", "n", "rejected"):
                if not hasattr(e, a):
                    return "FAIL: %s without attribute %s" % (type(e).__name__, a)
            if not str(e):
                return "FAIL: empty message"
        if _ok_like(expect):
            return "FAIL: expected success, got %s: %s" % (type(e).__name__, e)
        if expect is not None and not isinstance(e, expect) and not isinstance(e, HostileError):
            return "FAIL: expected %s, got %s: %s" % (_names_of(expect), type(e).__name__, e)
        return "PASS"
    if not (expect is None or _ok_like(expect)):
        return "FAIL: expected %s, the call returned %r" % (_names_of(expect), out)
    if name in ("Joint.center_at", "joint_center"):
        p = _nonfinite_joint(name, out, _valid_rows(name, out))
    else:
        p = nonfinite(out)
    if p:
        return "FAIL: non-finite value in %s: %r" % (p, out)
    if isinstance(expect, Same):
        ref = expect.ref()
        if not _same(out, ref):
            return "FAIL: differs from the call on the float32 samples: %r vs %r" % (out, ref)
    return "PASS"


def _nonfinite_joint(name, out, valid):
    if valid is None:
        return nonfinite(out)
    if name == "Joint.center_at":
        c, a, v = out
        parts = {"centers": c, "axes": a}
    else:
        parts = {"center_global": out.center_global, "axis_global": out.axis_global}
        rest = {k: getattr(out, k) for k in type(out).__slots__
                if k not in parts and k not in ("_raw", "cluster", "valid")}
        p = nonfinite(rest, "result")
        if p:
            return p
    for k, arr in parts.items():
        arr = np.asarray(arr)
        if not np.all(np.isfinite(arr[valid])):
            return k + " (a valid row)"
        if np.any(np.isfinite(arr[~valid])):
            return k + " (an invalid row is not NaN)"
    return None


def _same(a, b):
    if isinstance(a, sfit.Moments):
        return isinstance(b, sfit.Moments) and moments_state(a) == moments_state(b)
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and np.array_equal(a, b)
    slots = getattr(type(a), "__slots__", None)
    if slots:
        return all(_same(getattr(a, k), getattr(b, k)) for k in slots if k != "_raw")
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b or (a != a and b != b)


# ---------------------------------------------------------------------------
# Child runner and the tests
# ---------------------------------------------------------------------------

def run_child(name):
    cases = build_cases()[name]
    for i, (label, thunk, expect) in enumerate(cases):
        print("START\t%d\t%s" % (i, label), flush=True)
        verdict = check(name, label, thunk, expect)
        print("END\t%d\t%s" % (i, verdict.replace("\n", "\\n")), flush=True)
    print("DONE\t%d" % len(cases), flush=True)


def public_api():
    """Every public callable of the package: functions and classes of
    sfit.__all__ (not the exception types), and the public methods and
    properties of those classes, as "name" / "Class.member"."""
    names = set()
    for n in sfit.__all__:
        obj = getattr(sfit, n)
        if isinstance(obj, type) and issubclass(obj, BaseException):
            continue
        if not callable(obj):
            continue
        names.add(n)
        if isinstance(obj, type):
            for m in dir(obj):
                if m.startswith("_"):
                    continue
                attr = obj.__dict__.get(m, None)
                for klass in obj.__mro__:
                    if m in klass.__dict__:
                        attr = klass.__dict__[m]
                        break
                kind = type(attr).__name__
                if kind == "member_descriptor":  # a record's slot: data
                    continue
                names.add("%s.%s" % (n, m))
    return names


def stub_api():
    """The same names from the type stub sfit/__init__.pyi."""
    path = os.path.join(os.path.dirname(sfit.__file__), "__init__.pyi")
    tree = ast.parse(open(path, encoding="utf-8").read())
    names = set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.ClassDef):
            bases = [getattr(b, "id", "") for b in node.bases]
            if "Exception" in bases or "Error" in bases:
                continue
            names.add(node.name)
            for sub in node.body:
                if isinstance(sub, ast.FunctionDef) and not sub.name.startswith("_"):
                    names.add("%s.%s" % (node.name, sub.name))
    if not HAVE_JOINT:
        names -= {n for n in names if n.split(".")[0] in ("Pose", "Cluster", "JointResult",
                                                             "Joint", "joint_center")}
    return names


def _names():
    try:
        return sorted(build_cases())
    except Exception:  # reported by test_table_builds
        return []


if pytest is not None and __name__ != "__main__":

    def test_table_builds():
        build_cases()

    def test_table_covers_the_api():
        table = set(build_cases())
        missing = sorted(public_api() - table)
        assert not missing, "public callables without hostile cases: %s" % missing
        stub_missing = sorted(stub_api() - table)
        assert not stub_missing, "callables of the .pyi stub without hostile cases: %s" % stub_missing
        not_public = sorted(table - public_api())
        assert not not_public, "cases for callables that are not public: %s" % not_public
        small = sorted(n for n, c in build_cases().items() if len(c) < 3)
        assert not small, "fewer than 3 hostile cases: %s" % small

    @pytest.mark.parametrize("name", _names())
    def test_hostile(name):
        env = dict(os.environ, PYTHONFAULTHANDLER="1")
        p = subprocess.run([sys.executable, "-X", "faulthandler", os.path.abspath(__file__), name],
                           capture_output=True, text=True, env=env, timeout=600)
        started, failures, done = {}, [], False
        for line in p.stdout.splitlines():
            parts = line.split("\t", 2)
            if parts[0] == "START":
                started[parts[1]] = parts[2]
            elif parts[0] == "END":
                label = started.pop(parts[1])
                if parts[2] != "PASS":
                    failures.append("%s [%s]: %s" % (name, label, parts[2].replace("\\n", "\n")))
            elif parts[0] == "DONE":
                done = True
        if not done or p.returncode != 0:
            failures.append("%s: the child died (rc %d) during %s\n%s" % (
                name, p.returncode, list(started.values()), p.stderr[-3000:]))
        assert not failures, "\n".join(failures)


if __name__ == "__main__":
    import faulthandler
    faulthandler.enable()
    try:  # a regression that copies a huge view fails with MemoryError, not the OOM killer
        if os.environ.get("SFIT_NO_RLIMIT"):  # e.g. under AddressSanitizer
            raise ImportError
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (8 << 30, resource.getrlimit(resource.RLIMIT_AS)[1]))
    except (ImportError, ValueError, OSError):
        pass
    if len(sys.argv) != 2:
        print("\n".join("%-28s %d cases" % (n, len(c)) for n, c in sorted(build_cases().items())))
        print("total: %d callables, %d cases" % (len(build_cases()),
                                                 sum(len(c) for c in build_cases().values())))
    else:
        run_child(sys.argv[1])


_LYING_CHILD = r"""
import resource, sys
import numpy as np
import sfit

class Lying:
    '''Claims 10**9 markers; holds two good ones.'''
    def __init__(self, items):
        self.items = items
    def __len__(self):
        return 10 ** 9
    def __length_hint__(self):
        return 10 ** 9
    def __getitem__(self, i):
        if i >= len(self.items):
            raise IndexError(i)
        return self.items[i]

rng = np.random.default_rng(1)
def sphere(c):
    u = rng.normal(size=(200, 3))
    return c + 50.0 * u / np.linalg.norm(u, axis=1)[:, None]
good = [sphere(np.zeros(3)), sphere(np.zeros(3))]
out = []
try:
    sfit.fit_multi(Lying([[1.0, 2.0, 3.0]] * 2))
    out.append("bad items: no error")
except sfit.ArgError:
    out.append("bad items: ArgError")
r = sfit.fit_multi(Lying(good))
out.append("good items: %d markers" % len(r.radii))
try:
    sfit.fit_multi(good[0] for _ in range(10 ** 9))
    out.append("endless: no error")
except sfit.ArgError:
    out.append("endless: ArgError")
print(";".join(out))
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)  # kB on Linux
"""


def test_fit_multi_never_trusts_a_length():
    """A sequence whose __len__ claims 10**9 markers: fit_multi reads the
    items there are (an ArgError for bad ones, a fit for good ones), an
    endless generator stops at the item cap; the process stays small."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    out = subprocess.run([sys.executable, "-c", _LYING_CHILD], capture_output=True, text=True,
                         env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.split()
    res, peak_kb = " ".join(lines[:-1]), int(lines[-1])
    assert res == "bad items: ArgError;good items: 2 markers;endless: ArgError", res
    assert peak_kb < 500 * 1024, "peak %d kB" % peak_kb
