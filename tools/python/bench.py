#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Benchmark (not a test): sfit.fit against a numpy least-squares Kasa fit on
the same 10^6-point array, side by side in one run.

    /usr/bin/python3 tools/python/bench.py [N] [REPEATS]

Both get the same float64 (N, 3) array (what numpy code usually holds);
sfit's time includes its conversion to float32. The Kasa fit solves
[2x 2y 2z 1] [c; d] = |x|^2 with numpy.linalg.lstsq, r = sqrt(d + |c|^2),
the textbook algebraic fit (GDKE is the same estimator). Each timing is the
median of REPEATS runs; the ratio is numpy / sfit.
"""
import os
import sys
import time

import numpy as np

try:
    import sfit
except ImportError:  # run from a checkout after `setup.py build_ext --inplace`
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import sfit


def kasa_lstsq(x):
    a = np.empty((len(x), 4))
    a[:, :3] = 2.0 * x
    a[:, 3] = 1.0
    b = np.einsum("ij,ij->i", x, x)
    sol = np.linalg.lstsq(a, b, rcond=None)[0]
    c = sol[:3]
    return c, np.sqrt(sol[3] + c @ c)


def median_time(fn, repeats):
    times = []
    out = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def main():
    n = int(float(sys.argv[1])) if len(sys.argv) > 1 else 1_000_000
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    rng = np.random.default_rng(1)
    # a 60-degree cap of radius 250 mm, centre 1 m from the origin, 1 mm noise
    z = rng.uniform(np.cos(np.pi / 3), 1.0, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    s = np.sqrt(1 - z * z)
    x = (np.array([1000.0, -200.0, 300.0])
         + 250.0 * np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)
         + rng.normal(0, 1.0, (n, 3)))
    t_sfit, r = median_time(lambda: sfit.fit(x), repeats)
    t_np, (c_np, r_np) = median_time(lambda: kasa_lstsq(x), repeats)
    print("points          %d (float64 array, C order), median of %d runs" % (n, repeats))
    print("sfit.fit        %8.1f ms  centre %s r %.4f" % (1e3 * t_sfit, np.array2string(r.center, precision=4), r.radius))
    print("numpy lstsq     %8.1f ms  centre %s r %.4f" % (1e3 * t_np, np.array2string(c_np, precision=4), r_np))
    print("ratio           %.1fx (numpy lstsq time / sfit.fit time)" % (t_np / t_sfit))
    print("centre diff     %.2e (|sfit - numpy| / r)" % (np.linalg.norm(r.center - c_np) / r_np))
    x32 = x.astype(np.float32)
    t32, _ = median_time(lambda: sfit.fit(x32), repeats)
    print("sfit.fit f32    %8.1f ms  (float32 input: no conversion)" % (1e3 * t32))


if __name__ == "__main__":
    main()
