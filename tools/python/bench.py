#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Benchmark (not a test): sfit against a few lines of numpy on the same data,
side by side in one run.

    /usr/bin/python3 tools/python/bench.py [N] [REPEATS]
    /usr/bin/python3 tools/python/bench.py joint [FRAMES] [REPEATS]

The first form: sfit.fit against a numpy least-squares Kasa fit on the
same 10^6-point array.

Both get the same float64 (N, 3) array (what numpy code usually holds);
sfit's time includes its conversion to float32. The Kasa fit solves
[2x 2y 2z 1] [c; d] = |x|^2 with numpy.linalg.lstsq, r = sqrt(d + |c|^2),
the textbook algebraic fit (GDKE is the same estimator). Each timing is the
median of REPEATS runs; the ratio is numpy / sfit.

The second form: sfit.joint_center(P, C) (the default call: label-swap
check, templates, SCoRE with the bias removed, centre in the global frame
per frame) against a numpy SCoRE on the same simulated ball trial of
FRAMES frames (4 parent and 4 child markers, 0.3 mm noise, 5 % occluded):
the templates from the first frame of each cluster, a Kabsch registration
of both clusters in every frame (batched SVD, missing markers weighted 0)
and the 6x6 least-squares solve of R_p c_p + t_p = R_c c_c + t_c. The two
are called alternately, REPEATS times each, and each timing is the median.
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


def _rot(axis, angle):
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def ball_trial(frames, rng, sigma=0.3):
    """(parent (F, 4, 3), child (F, 4, 3)) float32 of a ball joint, mm."""
    tpl = np.array([[100.0, 0, 0], [-100.0, 20, 0], [0, 90, 30], [10, -60, 80]])
    centre = np.array([-70.0, -90.0, 80.0])
    offs = np.array([[0, -250.0, 40], [30, -400, -20], [-40, -150, 0], [60, -320, 50]])
    parent = np.empty((frames, 4, 3))
    child = np.empty((frames, 4, 3))
    for f in range(frames):
        r = _rot(rng.normal(size=3), rng.uniform(0, 0.6))
        t = np.array([500.0, 1200.0, 900.0]) + rng.normal(0, 50, 3)
        q = _rot([rng.normal(), 0.0, rng.normal()], rng.uniform(0, 0.7))
        parent[f] = tpl @ r.T + t
        child[f] = (centre + offs @ q.T) @ r.T + t
    parent += rng.normal(0, sigma, parent.shape)
    child += rng.normal(0, sigma, child.shape)
    parent[rng.uniform(size=parent.shape[:2]) < 0.05] = np.nan
    child[rng.uniform(size=child.shape[:2]) < 0.05] = np.nan
    return parent.astype(np.float32), child.astype(np.float32)


def kabsch_frames(x):
    """Per-frame rotations and translations of x (F, M, 3) onto its first
    complete frame (missing markers weighted 0): (R (F, 3, 3), t (F, 3),
    template (M, 3), ok (F,): 3 markers or more seen), x ~ R template + t."""
    x = x.astype(np.float64)
    w = np.all(np.isfinite(x), axis=2).astype(np.float64)
    x = np.where(w[..., None] > 0, x, 0.0)
    first = int(np.argmax(w.all(axis=1)))
    tpl = x[first] - x[first].mean(axis=0)
    n = np.maximum(w.sum(axis=1), 1.0)
    xc = (w[..., None] * x).sum(axis=1) / n[:, None]
    pc = w @ tpl / n[:, None]
    h = np.einsum("fm,fmi,fmj->fij", w, x - xc[:, None], tpl[None] - pc[:, None])
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(u @ vt))
    u[:, :, 2] *= d[:, None]
    r = u @ vt
    return r, xc - np.einsum("fij,fj->fi", r, pc), tpl, w.sum(axis=1) >= 3


def score_numpy(parent, child):
    """SCoRE: the centre in each segment's frame from R_p c_p + t_p =
    R_c c_c + t_c over all frames (least squares); (c_p, c_c)."""
    rp, tp, _, okp = kabsch_frames(parent)
    rc, tc, _, okc = kabsch_frames(child)
    ok = okp & okc
    a = np.concatenate([rp[ok], -rc[ok]], axis=2).reshape(-1, 6)
    b = (tc[ok] - tp[ok]).reshape(-1)
    sol = np.linalg.solve(a.T @ a, a.T @ b)
    return sol[:3], sol[3:]


def bench_joint(frames, repeats):
    parent, child = ball_trial(frames, np.random.default_rng(7))
    ts, tn = [], []
    res = cp = None
    for _ in range(repeats):  # interleaved: the same machine state for both
        t0 = time.perf_counter()
        res = sfit.joint_center(parent, child)
        ts.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        cp, _ = score_numpy(parent, child)
        tn.append(time.perf_counter() - t0)
    t_s, t_n = float(np.median(ts)), float(np.median(tn))
    # both centres in the global frame of the first frame with the parent seen
    f = int(np.argmax(res.valid))
    rp, tp, _, _ = kabsch_frames(parent)
    g_np = rp[f] @ cp + tp[f]
    print("frames          %d (ball trial, 4 + 4 markers), median of %d interleaved runs"
          % (frames, repeats))
    print("sfit.joint_center %6.2f ms  centre (frame %d) %s" % (1e3 * t_s, f,
          np.array2string(res.center_global[f], precision=3)))
    print("numpy SCoRE       %6.2f ms  centre (frame %d) %s" % (1e3 * t_n, f,
          np.array2string(g_np, precision=3)))
    print("ratio           %.2f (sfit.joint_center time / numpy SCoRE time)" % (t_s / t_n))


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "joint":
        frames = int(float(sys.argv[2])) if len(sys.argv) > 2 else 500
        repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 200
        bench_joint(frames, repeats)
        return
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
