# SPDX-License-Identifier: MIT
"""The hostile inputs of test_hostile.py: objects that lie or raise, the
sphere and circle samples, and the case generators every callable shares
(points, numbers, vectors, modes, covariances, state snapshots)."""

import numpy as np

import sfit

try:
    import pytest
except ImportError:  # the child runner needs no pytest
    pytest = None

HAVE_JOINT = hasattr(sfit, "Joint")
ALLOWED = (sfit.Error, TypeError, ValueError)
NAN, INF = float("nan"), float("inf")


class HostileError(Exception):
    """Raised by the hostile objects themselves: passing it on is fine."""


# ---------------------------------------------------------------------------
# Hostile objects
# ---------------------------------------------------------------------------

class RaisingArray:
    def __array__(self, dtype=None, copy=None):
        raise HostileError("__array__")


class GarbageArray:
    """__array__ returns something that is not an ndarray."""

    def __init__(self, what):
        self.what = what

    def __array__(self, dtype=None, copy=None):
        return self.what


class RaisingSequence:
    def __len__(self):
        return 5

    def __getitem__(self, i):
        raise HostileError("__getitem__")


class LyingSequence:
    """Claims 10**9 items, has 2."""

    def __len__(self):
        return 10 ** 9

    def __getitem__(self, i):
        if i >= 2:
            raise IndexError(i)
        return [1.0, 2.0, 3.0]


class RaisingFloat:
    def __float__(self):
        raise HostileError("__float__")

    def __index__(self):
        raise HostileError("__index__")

    def __bool__(self):
        raise HostileError("__bool__")


class HugeInt(int):
    pass


def sphere(n=40, c=(1.0, 2.0, 3.0), r=10.0, seed=5):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    return u * r + np.asarray(c) + rng.normal(scale=0.01, size=(n, 3))


def circle(n=40, r=10.0):
    t = np.linspace(0.0, 1.5, n)
    return np.stack([r * np.cos(t), r * np.sin(t), np.full(n, 2.0)], axis=1)


P = sphere()
P32 = P.astype(np.float32)


def _with_row(x, row, value):
    y = np.array(x, dtype=np.float64)
    y[row] = value
    return y


def _negative_stride(x):
    v = np.array(x[::-1])[::-1]
    assert v.strides[0] < 0
    return v


def _column_view(x):
    w = np.zeros((len(x), 7))
    w[:, 1:6:2] = x
    return w[:, 1:6:2]


def _readonly(x):
    y = np.array(x)
    y.flags.writeable = False
    return y


class Same:
    """Expect success and the very result of `ref` (the float32 samples)."""

    def __init__(self, ref):
        self.ref = ref


def _ok_like(exp):
    return exp == "ok" or isinstance(exp, Same)


def points_cases(call, allow_one=False, huge=False, base=P, centred=False):
    """(label, thunk, expect) for an argument that takes (N, 3) samples
    (centred: the call also takes the sphere's centre, so the rescaled
    integer samples need not fit it).
    expect: Same (accepted, equal to the call on the float32 samples),
    "ok", an exception class, or None (any allowed outcome)."""
    b = np.asarray(base, dtype=np.float64)
    same = Same(lambda: call(b.astype(np.float32)))
    c = [
        # accepted layouts and dtypes: the very same float32 samples
        ("float32", lambda: call(b.astype(np.float32)), same),
        ("fortran", lambda: call(np.asfortranarray(b)), same),
        ("strided rows", lambda: call(np.repeat(b, 2, axis=0)[::2]), same),
        ("negative stride", lambda: call(_negative_stride(b)), same),
        ("column view", lambda: call(_column_view(b)), same),
        ("big-endian f8", lambda: call(b.astype(">f8")), same),
        ("big-endian f4", lambda: call(b.astype(">f4")), same),
        ("longdouble", lambda: call(b.astype(np.longdouble)), same),
        ("readonly", lambda: call(_readonly(b)), same),
        ("list", lambda: call(b.tolist()), same),
        ("tuple", lambda: call(tuple(map(tuple, b.tolist()))), same),
        # other real dtypes: accepted
        ("int32", lambda: call(np.rint(b * 10).astype(np.int32)), None if centred else "ok"),
        ("uint16", lambda: call(np.rint(b * 10 + 500).astype(np.uint16)), None if centred else "ok"),
        ("float16", lambda: call(b.astype(np.float16)), "ok"),
        # wrong types
        ("None", lambda: call(None), sfit.ArgError),
        ("str", lambda: call("abc"), sfit.ArgError),
        ("bytes", lambda: call(b"abcdef"), sfit.ArgError),
        ("dict", lambda: call({"x": 1}), sfit.ArgError),
        ("object", lambda: call(object()), sfit.ArgError),
        ("scalar", lambda: call(3.0), sfit.ArgError),
        ("__array__ raises", lambda: call(RaisingArray()), sfit.ArgError),
        ("__array__ -> str", lambda: call(GarbageArray("xyz")), sfit.ArgError),
        ("__array__ -> None", lambda: call(GarbageArray(None)), sfit.ArgError),
        ("__array__ -> object array", lambda: call(GarbageArray(np.array([[object()] * 3] * 5))),
         sfit.ArgError),
        ("__getitem__ raises", lambda: call(RaisingSequence()), sfit.ArgError),
        ("lying __len__", lambda: call(LyingSequence()), None),  # numpy reads the 2 rows
        ("ragged list", lambda: call([[1.0, 2.0, 3.0], [1.0, 2.0]]), sfit.ArgError),
        # wrong dtypes
        ("complex", lambda: call(b.astype(complex)), sfit.ArgError),
        ("bool", lambda: call(b > 0), sfit.ArgError),
        ("object dtype", lambda: call(b.astype(object)), sfit.ArgError),
        ("str dtype", lambda: call(b.astype(str)), sfit.ArgError),
        ("datetime64", lambda: call(np.zeros((10, 3), dtype="datetime64[s]")), sfit.ArgError),
        ("structured", lambda: call(np.zeros(10, dtype="f4,f4,f4")), sfit.ArgError),
        # wrong shapes
        ("(N, 2)", lambda: call(b[:, :2]), sfit.ArgError),
        ("(N, 4)", lambda: call(np.hstack([b, b[:, :1]])), sfit.ArgError),
        ("(3, N)", lambda: call(np.ascontiguousarray(b.T)), sfit.ArgError),
        ("(2, N, 3)", lambda: call(np.stack([b, b])), sfit.ArgError),
        ("(N, 3, 1)", lambda: call(b[:, :, None]), sfit.ArgError),
        ("(10, 0)", lambda: call(np.zeros((10, 0))), sfit.ArgError),
        ("0-d", lambda: call(np.float64(1.0)), sfit.ArgError),
        ("(4,)", lambda: call(np.ones(4)), sfit.ArgError),
        # too few, degenerate
        ("(0, 3)", lambda: call(np.zeros((0, 3))), sfit.TooFewError),
        ("[]", lambda: call([]), sfit.TooFewError),
        ("MIN_SAMPLES - 1", lambda: call(b[:sfit.MIN_SAMPLES - 1]), sfit.TooFewError),
        ("all NaN", lambda: call(np.full((20, 3), NAN)), sfit.TooFewError),
        ("all 1e30", lambda: call(b * 1e30), sfit.TooFewError),
        ("coincident", lambda: call(np.ones((20, 3))), sfit.Error),
        ("collinear", lambda: call(np.outer(np.arange(20.0), [1.0, 2.0, 3.0])), sfit.Error),
        # entries the library rejects or that are extreme
        ("NaN row", lambda: call(_with_row(b, 3, NAN)), "ok"),
        ("Inf row", lambda: call(_with_row(b, 3, INF)), "ok"),
        ("-Inf entry", lambda: call(_with_row(b, (3, 1), -INF)), "ok"),
        ("1e38 row", lambda: call(_with_row(b, 3, 1e38)), "ok"),
        ("-1e38 row", lambda: call(_with_row(b, 3, -1e38)), "ok"),
        ("2**27 row", lambda: call(_with_row(b, 3, 2.0 ** 27)), "ok"),
        ("1e300 row (inf in f32)", lambda: call(_with_row(b, 3, 1e300)), "ok"),
        ("denormal row", lambda: call(_with_row(b, 3, 1e-40)), None),
        ("far centre 1e7", lambda: call(b + 1e7), None),
        ("tiny radius 1e-20", lambda: call(sphere(r=1e-20)), None),
        ("huge radius 1e7", lambda: call(sphere(r=1e7)), None),
        ("coplanar (circle)", lambda: call(circle()), None),
    ]
    if allow_one:
        c += [("(3,) one sample", lambda: call(b[0]), "ok"),
              ("(3,) NaN sample", lambda: call(np.array([NAN, 1.0, 2.0])), "ok"),
              ("(3,) str", lambda: call(["a", "b", "c"]), sfit.ArgError)]
    else:
        c += [("(3,)", lambda: call(b[0]), sfit.ArgError)]
    if huge:
        big = np.tile(b, (25_000, 1))  # 10**6 rows
        c.append(("10**6 rows", lambda: call(big), "ok"))
    # more rows than a uint32 counts: a free broadcast view, refused before
    # any copy (48 GiB)
    c.append(("2**32 + 1 rows (broadcast view)",
              lambda: call(np.broadcast_to(b[:1], (2 ** 32 + 1, 3))), sfit.RangeError))
    return c


def number_cases(call, expect_bad=sfit.ArgError, nonneg=True):
    """Values for an argument that is a finite number (>= 0 when nonneg)."""
    c = [("nan", lambda: call(NAN), expect_bad), ("inf", lambda: call(INF), expect_bad),
         ("-inf", lambda: call(-INF), expect_bad), ("1e300", lambda: call(1e300), expect_bad),
         ("None", lambda: call(None), None), ("str", lambda: call("bogus"), None),
         ("list", lambda: call([1.0, 2.0]), None), ("object", lambda: call(object()), None),
         ("complex", lambda: call(1 + 1j), None), ("10**400", lambda: call(10 ** 400), None),
         ("__float__ raises", lambda: call(RaisingFloat()), None),
         ("np.float32 nan", lambda: call(np.float32(NAN)), expect_bad),
         ("1e39", lambda: call(1e39), None), ("1e38", lambda: call(1e38), None),
         ("-1e38", lambda: call(-1e38), None), ("0", lambda: call(0.0), None)]
    if nonneg:
        c.append(("-1", lambda: call(-1.0), expect_bad))
    return c


def vec3_cases(call):
    return [("None", lambda: call(None), sfit.ArgError), ("str", lambda: call("abc"), sfit.ArgError),
            ("2 numbers", lambda: call([1.0, 2.0]), sfit.ArgError),
            ("4 numbers", lambda: call([1.0, 2.0, 3.0, 4.0]), sfit.ArgError),
            ("(3, 1)", lambda: call(np.ones((3, 1))), sfit.ArgError),
            ("complex", lambda: call(np.ones(3, complex)), sfit.ArgError),
            ("__array__ raises", lambda: call(RaisingArray()), sfit.ArgError),
            ("NaN", lambda: call([NAN, 0.0, 0.0]), sfit.Error),
            ("Inf", lambda: call([0.0, INF, 0.0]), sfit.Error),
            ("1e38", lambda: call([1e38, 0.0, 0.0]), sfit.Error),
            ("-1e38", lambda: call([0.0, 0.0, -1e38]), sfit.Error),
            ("1e300", lambda: call([1e300, 0.0, 0.0]), sfit.Error),
            ("strided", lambda: call(np.arange(9.0)[::3]), None),
            ("big-endian", lambda: call(np.array([1.0, 2.0, 3.0], ">f8")), None)]


def mode_cases(call):
    return [(f"mode={m!r}", lambda m=m: call(m), sfit.ArgError)
            for m in ("cube", "", None, 1, b"auto", "AUTO", "auto\0", RaisingFloat())]


def cov_cases(call, solves=True):
    bad = {"(2, 2)": np.eye(2), "(9,)": np.ones(9), "nan": np.eye(3) * NAN,
           "inf": np.diag([INF, 1.0, 1.0]), "asymmetric": np.array([[1.0, 0.1, 0], [0, 1, 0], [0, 0, 1]]),
           "str": "bogus", "complex": np.eye(3, dtype=complex), "object": object(),
           "1e39": np.eye(3) * 1e39, "(3, 3, 1)": np.eye(3)[:, :, None],
           "6 with nan": [1, 1, 1, 0, 0, NAN], "__array__ raises": RaisingArray()}
    c = [(f"noise_cov {k}", lambda v=v: call(v), sfit.ArgError) for k, v in bad.items()]
    # a constructor only stores the model: the solve refuses it later
    c += [("noise_cov -eye", lambda: call(-np.eye(3)), sfit.Error if solves else None),
          ("noise_cov huge", lambda: call(np.eye(3) * 1e30), sfit.Error if solves else None),
          ("noise_cov 6 packed", lambda: call([1e-3, 1e-3, 1e-3, 0, 0, 0]), None)]
    return c


# ---------------------------------------------------------------------------
# State objects: snapshots and hostile subclasses
# ---------------------------------------------------------------------------

def moments_state(m):
    try:
        st = tuple(a.tobytes() for a in m.stats())
    except sfit.Error as e:
        st = e.status
    return (m.count, m.rejected, len(m), st)


def incr_state(s):
    try:
        e = s.estimate()
        est = (e.center.tobytes(), e.radius, e.n)
    except sfit.Error as e:
        est = e.status
    return (s.count, s.rejected, est)


def state_case(label, obj, snapshot, fn, expect=None):
    """A call on a state object: if it raises, the state must be unchanged."""
    def thunk():
        before = snapshot(obj)
        try:
            return fn(obj)
        except BaseException:
            after = snapshot(obj)
            if after != before:
                raise AssertionError("%s: rejected call changed the state: %r -> %r"
                                     % (label, before, after))
            raise
    return (label, thunk, expect)


def _sub_new_returns(base, value):
    return type("Evil" + base.__name__, (base,), {"__new__": lambda cls, *a, **k: value})


def _joint_data(frames=12):
    tpl = np.array([[100.0, 0, 0], [-100.0, 20, 0], [0, 90, 30], [10, -60, 80]])
    par = np.stack([tpl + [0.0, 0.0, 0.1 * f] for f in range(frames)])
    chi = np.stack([[[60 * np.cos(0.2 * f), 60 * np.sin(0.2 * f), 30.0 + f],
                     [40 * np.cos(0.2 * f + 1), 40 * np.sin(0.2 * f + 1), 10.0]]
                    for f in range(frames)])
    return tpl, par, chi


# Everything above, underscored names too, for the next file's "import *".
__all__ = [n for n in dir() if not n.startswith("__")]
