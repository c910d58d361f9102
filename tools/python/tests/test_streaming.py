# SPDX-License-Identifier: MIT
"""Streaming: sfit.Moments over chunks gives the same answer as one call."""
import numpy as np
import pytest

import ref
import sfit
from conftest import DATA_DIR, read_csv_f32


def test_chunks_equal_one_call_bit_for_bit(rng):
    x = ref.as_f32(ref.sphere_samples(rng, 100_000, (2700.0, 10.0, -400.0), 300.0, 1.0, 0.8))
    x[1234] = np.nan
    one = sfit.fit(x)
    m = sfit.Moments()
    for chunk in np.array_split(x, 37):  # uneven chunks, one with a NaN row
        m.add(chunk)
    m.add(np.zeros((0, 3)))
    got = m.fit()
    assert m.count == one.n == 99_999 and m.rejected == one.rejected == 1
    assert np.array_equal(got.center, one.center) and got.radius == one.radius
    assert np.array_equal(got.eigenvalues, one.eigenvalues)
    # sample by sample, too
    m1 = sfit.Moments()
    for row in x[:3000]:
        m1.add(row)
    assert np.array_equal(m1.fit().center, sfit.fit(x[:3000]).center)
    # with a noise model, through solve()
    assert np.array_equal(m.solve(noise_var=1.0).center, sfit.fit(x, noise_var=1.0).center)


def test_merge_of_chunks_equals_one_call(rng):
    x = ref.as_f32(ref.sphere_samples(rng, 50_000, (2700.0, 10.0, -400.0), 300.0, 1.0, 0.8))
    parts = [sfit.Moments(c) for c in np.array_split(x, 9)]
    total = sfit.Moments()
    for p in parts:
        total.merge(p)
    one = sfit.fit(x)
    got = total.fit()
    assert total.count == len(x)
    # exact merge formulas, different rounding order: float32 agreement
    assert np.linalg.norm(got.center - one.center) < 1e-5 * one.radius
    assert got.radius == pytest.approx(one.radius, rel=1e-5)
    c_ref, r_ref = ref.sphere(x.astype(np.float64))[:2]
    assert np.linalg.norm(got.center - c_ref) < 1e-4 * r_ref


def test_copy_reset_len():
    x = read_csv_f32(f"{DATA_DIR}/mocap/hip_right/RTHI1.csv")
    m = sfit.Moments(x[:700])
    c = m.copy()
    c.add(x[700:])
    assert len(m) == 700 and len(c) == 1400
    assert np.array_equal(c.fit().center, sfit.fit(x).center)
    m.merge(m)  # self-merge doubles the weights: same centre
    assert len(m) == 1400
    assert np.allclose(m.fit().center, sfit.fit(x[:700]).center, atol=1e-3)
    m.reset()
    assert m.count == 0 and m.rejected == 0
    assert "count=0" in repr(m)
