# SPDX-License-Identifier: MIT
"""Bad and unusual input: shapes, dtypes, NaN / Inf / huge rows, empty and
non-contiguous arrays, invalid options. Never a crash, never a NaN out."""
import numpy as np
import pytest

import ref
import sfit


@pytest.fixture
def pts(rng):
    return ref.as_f32(ref.sphere_samples(rng, 400, (10.0, 20.0, 30.0), 50.0, 0.2, 1.2))


@pytest.mark.parametrize("shape", [(10,), (10, 2), (10, 4), (3, 10), (2, 5, 3), (), (0, 2)])
def test_wrong_shapes(shape):
    with pytest.raises(sfit.ArgError) as ei:
        sfit.fit(np.ones(shape))
    assert isinstance(ei.value, ValueError) and ei.value.status == "bad_argument"
    assert "shape" in str(ei.value)


@pytest.mark.parametrize("bad", [np.array([["a", "b", "c"]] * 5), np.ones((5, 3), dtype=complex),
                                 np.ones((5, 3), dtype=bool), np.array([[object()] * 3] * 5),
                                 "points", None, [[1, 2], [3]]])
def test_wrong_dtypes(bad):
    with pytest.raises(sfit.ArgError):
        sfit.fit(bad)
    with pytest.raises(sfit.ArgError):
        sfit.Moments().add(bad)


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.longdouble, np.int32, np.int64, np.uint16])
def test_numeric_dtypes_accepted(pts, dtype):
    x = np.round(pts).astype(dtype)
    r = sfit.fit(x)
    assert np.array_equal(r.center, sfit.fit(np.round(pts).astype(dtype).astype(np.float32)).center)


def test_float64_is_rounded_to_float32(pts):
    x64 = pts.astype(np.float64) + 1e-9  # below float32 resolution at these magnitudes
    assert np.array_equal(sfit.fit(x64).center, sfit.fit(x64.astype(np.float32)).center)
    assert sfit.fit(x64).center.dtype == np.float64


def test_lists_accepted(pts):
    assert np.array_equal(sfit.fit(pts.tolist()).center, sfit.fit(pts).center)


def test_non_contiguous_arrays(pts):
    big = np.zeros((len(pts), 7), dtype=np.float64)
    big[:, 2:5] = pts
    view = big[:, 2:5]
    assert not view.flags.c_contiguous
    fortran = np.asfortranarray(pts)
    strided = np.repeat(pts, 2, axis=0)[::2]
    want = sfit.fit(pts)
    for v in (view, fortran, strided):
        r = sfit.fit(v)
        assert np.array_equal(r.center, want.center) and r.radius == want.radius
    m = sfit.Moments()
    m.add(view)
    assert np.array_equal(m.fit().center, want.center)
    # reversed order is a different summation order: equal up to rounding
    assert np.allclose(sfit.fit(pts[::-1]).center, want.center, atol=1e-4)


def test_empty_and_too_few():
    for x in (np.zeros((0, 3)), np.zeros((0, 3), dtype=np.float32), [[0, 0, 0]] * 0):
        with pytest.raises(sfit.TooFewError) as ei:
            sfit.fit(x)
        assert ei.value.n == 0 and ei.value.rejected == 0 and ei.value.status == "too_few_samples"
    with pytest.raises(sfit.TooFewError):
        sfit.fit([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(sfit.TooFewError):
        sfit.Moments().fit()
    with pytest.raises(sfit.TooFewError):
        sfit.Moments().stats()
    with pytest.raises(sfit.TooFewError):
        sfit.fit_multi([])


def test_nan_rows_skipped_and_counted(pts):
    x = pts.astype(np.float64).copy()
    bad = [3, 50, 51, 399]
    x[3, 0] = np.nan
    x[50] = np.inf
    x[51, 2] = -np.inf
    x[399, 1] = 2.0 ** 27  # out of range
    r = sfit.fit(x)
    good = np.delete(pts, bad, axis=0)
    want = sfit.fit(good)
    assert r.rejected == 4 and r.n == 396
    assert np.array_equal(r.center, want.center) and r.radius == want.radius
    assert np.all(np.isfinite(r.center)) and np.isfinite(r.radius)
    # also with the stored-sample paths (self-calibration, refinement)
    for kw in ({"noise_var": "auto"}, {"refine": True}):
        a, b = sfit.fit(x, **kw), sfit.fit(good, **kw)
        assert a.rejected == 4 and np.array_equal(a.center, b.center) and a.center_cov is not None
        assert np.array_equal(a.center_cov, b.center_cov)
    m = sfit.Moments()
    assert m.add(x) == 396 and m.rejected == 4 and m.count == 396
    assert m.add([np.nan, 0, 0]) == 0 and m.rejected == 5
    inc = sfit.Incremental()
    assert inc.add(x) == 396 and inc.rejected == 4
    assert sfit.calibrate_noise(x, (10, 20, 30), 50).rejected == 4


def test_float64_overflow_becomes_a_rejected_row(pts):
    x = pts.astype(np.float64).copy()
    x[7] = [1e300, 0, 0]  # beyond float32: inf after rounding
    with np.errstate(over="ignore"):
        r = sfit.fit(x)
    assert r.rejected == 1 and r.n == len(x) - 1


def test_all_nan():
    with pytest.raises(sfit.TooFewError) as ei:
        sfit.fit(np.full((20, 3), np.nan))
    assert ei.value.n == 0 and ei.value.rejected == 20


def test_degenerate_inputs():
    with pytest.raises(sfit.DegenerateError):
        sfit.fit(np.ones((50, 3)))  # coincident
    line = np.outer(np.arange(50.0), [1.0, 2.0, 3.0])
    with pytest.raises(sfit.DegenerateError):
        sfit.fit(line)  # collinear
    with pytest.raises(sfit.DegenerateError):
        sfit.Incremental().start(np.ones((10, 3)))


def test_option_errors(pts):
    for kw in ({"mode": "cube"}, {"mode": 3}, {"noise_var": -1.0}, {"noise_var": float("nan")},
               {"noise_var": "loud"}, {"noise_var": 1.0, "noise_cov": np.eye(3)},
               {"noise_var": "auto", "noise_cov": np.eye(3)}, {"noise_cov": np.ones((2, 2))},
               {"noise_cov": [[1, 2, 0], [0, 1, 0], [0, 0, 1]]}, {"noise_cov": [1, 1, 1, 0, 0, np.nan]},
               {"noise_var": "auto", "mode": "planar"}, {"refine": True, "mode": "planar"},
               {"planar_ratio": 0.7}, {"planar_ratio": -1.0}, {"gate": 0.5},
               {"gate": 4.0, "refine": True}, {"refine": True, "noise_var": 1.0},
               {"refine": True, "noise_cov": np.eye(3)}):
        with pytest.raises(sfit.ArgError):
            sfit.fit(pts, **kw)
    with pytest.raises(sfit.ArgError):  # the library's own check: negative eigen-structure
        sfit.fit(pts, noise_cov=[[1, 2, 0], [2, 1, 0], [0, 0, 1]])
    with pytest.raises(sfit.ArgError):
        sfit.fit_multi([pts], weight="heavy")
    with pytest.raises(sfit.ArgError):
        sfit.fit_multi([pts], noise_var="auto")
    with pytest.raises(sfit.ArgError):
        sfit.fit_multi(pts)  # one (N, 3) array is not a list of markers
    with pytest.raises(sfit.ArgError):
        sfit.Moments().merge("x")
    with pytest.raises(sfit.ArgError):
        sfit.Incremental(noise_var=-2)
    with pytest.raises(sfit.ArgError):
        sfit.refine(pts, (0, 0))
    with pytest.raises(sfit.ArgError):
        sfit.uncertainty(pts, (0, 0, 0), noise_var=0.1)  # radius missing


def test_noise_too_large_is_not_posdef(pts):
    with pytest.raises(sfit.NotPosDefError) as ei:
        sfit.fit(pts, noise_var=1e6)
    assert ei.value.code == -3 and "not_positive_definite" in str(ei.value)


def test_exception_hierarchy():
    for cls in (sfit.ArgError, sfit.TooFewError, sfit.NotPosDefError, sfit.NoConvergenceError,
                sfit.DegenerateError, sfit.NonFiniteError, sfit.RangeError):
        assert issubclass(cls, sfit.Error)
    assert issubclass(sfit.ArgError, ValueError)


def test_results_are_read_only(pts):
    r = sfit.fit(pts)
    with pytest.raises(AttributeError):
        r.radius = 1.0
    d = r.to_dict()
    assert d["radius"] == r.radius and set(d) >= {"center", "flags", "method", "mode", "axis"}
    assert "FitResult(" in repr(r)
