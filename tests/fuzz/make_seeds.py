#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the seed corpus of the sfit fuzz harnesses (tests/fuzz/corpus/).

Each seed is a small program in the byte format that fuzz_stream.c /
fuzz_kernels.c / fuzz_beyond.c interpret (opcode table in tests/fuzz/README.md): the
scenarios a glitching sensor or a careless caller produce. The files are
committed; rerun this script only when the format changes:

    python3 tests/fuzz/make_seeds.py tests/fuzz/corpus
"""
import math
import os
import struct
import sys

# fuzz_stream.c opcodes (enum fz_op)
ADD_RAW, ADD_FLOAT, ADD_SPHERE, REPEAT, ADD_BLOCK, MERGE, RESET, SOLVE, BATCH, \
    MULTI, STATS, INCR_INIT, INCR_ADD, INCR_START, INCR_SOLVE, CALIBRATE, NULLS = range(17)

NAN = float("nan")
INF = float("inf")


def f(v):
    """fz_float, raw encoding (kind 0): exactly the float32 nearest v."""
    return b"\x00" + struct.pack("<f", v)


def raw3(p):
    return b"".join(struct.pack("<f", c) for c in p)


def op(code, a=0):
    return bytes([code, a])


def add(a, p):
    return op(ADD_RAW, a) + raw3(p)


def cfg(mode=0, noise=0, var=0.0, cov=None, planar=None, null=False):
    """fz_cfg followed, for SOLVE, by the NULL-cfg selector byte."""
    b = mode | (noise << 2) | (0x10 if planar is not None else 0)
    out = bytes([b])
    if planar is not None:
        out += f(planar)
    if noise == 1:
        out += f(var)
    elif noise == 2:
        xx, yy, zz, xy, xz, yz = cov
        out += f(xx) + f(yy) + f(zz) + f(xy) + f(xz) + f(yz)
    return out


def solve(a, **kw):
    null = kw.pop("null", False)
    return op(SOLVE, a) + cfg(**kw) + (b"\x00" if null else b"\x01")


def sphere_pts(c, r, n, cap=math.pi, seed=1):
    """Deterministic points on a cap of half-angle `cap` about +z."""
    pts = []
    g = 0.6180339887498949
    for i in range(n):
        u = ((i + 0.5) * g + seed * 0.37) % 1.0
        z = 1.0 - u * (1.0 - math.cos(cap))
        phi = 2.0 * math.pi * ((i * 0.7548776662466927 + seed * 0.11) % 1.0)
        s = math.sqrt(max(0.0, 1.0 - z * z))
        pts.append((c[0] + r * s * math.cos(phi), c[1] + r * s * math.sin(phi), c[2] + r * z))
    return pts


def circle_pts(c, r, n, arc=math.pi):
    return [(c[0] + r * math.cos(arc * (2 * i / (n - 1) - 1)),
             c[1] + r * math.sin(arc * (2 * i / (n - 1) - 1)), c[2]) for i in range(n)]


FAR = (2700.0, -1200.0, 900.0)


def stream_seeds():
    s = {}
    pts = sphere_pts(FAR, 100.0, 24)
    body = b"".join(add(0, p) for p in pts)
    s["sphere_gdke_ugdk"] = (body + solve(0) + solve(0, mode=1) + solve(0, noise=1, var=1.0)
                             + solve(0, noise=2, cov=(1.0, 2.0, 0.5, 0.1, 0.0, -0.1))
                             + solve(0, null=True) + op(STATS, 0))
    cap = sphere_pts(FAR, 100.0, 40, cap=0.5)
    s["cap_noise_larger_than_spread"] = (b"".join(add(0, p) for p in cap)
                                         + solve(0, noise=1, var=1.0) + solve(0, noise=1, var=1e4)
                                         + solve(0, noise=1, var=1e12) + solve(0, mode=2, noise=1, var=1e4))
    hinge = circle_pts(FAR, 80.0, 30, arc=1.2)
    s["hinge_planar"] = (b"".join(add(1, p) for p in hinge) + solve(1) + solve(1, mode=1)
                         + solve(1, mode=2) + solve(1, mode=2, noise=1, var=0.25)
                         + solve(1, mode=2, noise=2, cov=(0.1, 0.1, 0.1, 0.0, 0.0, 0.0)))
    # Regression (docs/reliability.md finding 1): a hinge solved in planar
    # mode with a noise covariance that is not positive semi-definite.
    s["regress_planar_nonpsd_cov"] = (b"".join(add(1, p) for p in hinge)
                                      + solve(1, mode=2, noise=2, cov=(1.0, 1.0, 2.0, 1e4, 1e4, 1e4))
                                      + solve(1, mode=0, noise=2, cov=(0.5, 0.5, 0.5, 40.0, -40.0, 40.0)))
    bad = [(NAN, 0.0, 0.0), (0.0, INF, 0.0), (0.0, 0.0, -INF), (1e30, 0.0, 0.0),
           (134217728.0, 0.0, 0.0), (134217720.0, -134217720.0, 0.0),
           (1.4e-45, -1.4e-45, 1.2e-38), (3.4e38, 3.4e38, 3.4e38), (1.8446743e19, 0.0, 0.0)]
    s["hostile_samples"] = (b"".join(add(0, p) for p in pts[:6]) + b"".join(add(0, p) for p in bad)
                            + op(ADD_BLOCK, 0) + bytes([12, 1, 3]) + raw3((NAN, 1.0, 1.0))
                            + op(ADD_BLOCK, 0) + bytes([9, 0]) + solve(0) + op(STATS, 0))
    s["coincident_collinear"] = (add(0, (5.0, 5.0, 5.0)) + op(REPEAT, 0) + bytes([200]) + solve(0)
                                 + b"".join(add(1, (float(i), 2.0 * i, 3.0 * i)) for i in range(8))
                                 + solve(1) + op(STATS, 0) + op(STATS, 1))
    s["tiny_subnormal_spread"] = (b"".join(add(0, (p[0] * 1e-40, p[1] * 1e-40, p[2] * 1e-40)) for p in pts[:10])
                                  + solve(0) + b"".join(add(1, (1e6 + p[0] * 1e-3, 1e6, 1e6 + p[2] * 1e-3))
                                                        for p in pts[:10]) + solve(1))
    # 32 self-merges of one sample: the counter limit.
    s["merge_doubling_to_limit"] = (add(2, (1.0, 2.0, 3.0)) + b"".join(op(MERGE, 2) + b"\x02" for _ in range(33))
                                    + add(2, (1.0, 2.0, 3.5)) + op(STATS, 2))
    # acc0 = 6 samples + (2^32 - 7) copies of one point: exactly UINT32_MAX, then one more.
    want = 0xFFFFFFFF - 6
    prog = b"".join(add(0, p) for p in pts[:6]) + add(2, (2750.0, -1150.0, 950.0))
    for k in range(32):
        if want >> k & 1:
            prog += op(MERGE, 0) + b"\x02"
        prog += op(MERGE, 2) + b"\x02"
    prog += add(0, (1.0, 1.0, 1.0)) + op(ADD_BLOCK, 0) + bytes([1, 0]) + solve(0) + op(STATS, 0)
    prog += op(CALIBRATE, 0) + bytes([0]) + raw3(FAR) + b"\x00"
    s["counter_limit"] = prog
    m = b""
    for a, seed in ((0, 1), (1, 2), (2, 3)):
        m += b"".join(add(a, p) for p in sphere_pts(FAR, 60.0 + 20 * a, 12, cap=1.0, seed=seed))
    s["multi_markers"] = (m + op(MULTI, 0) + bytes([3]) + cfg() + op(MULTI, 0) + bytes([3 | 4]) + cfg(noise=1, var=0.5)
                          + op(MULTI, 0) + bytes([2 | 0x80]) + cfg(mode=2) + op(MULTI, 0) + bytes([0]) + cfg()
                          + op(RESET, 1) + op(MULTI, 0) + bytes([3]) + cfg() + op(MERGE, 0) + b"\x02"
                          + op(MULTI, 0) + bytes([3 | 8]) + cfg())
    inc = (op(INCR_INIT, 0) + cfg(noise=1, var=0.01) + b"".join(add(0, p) for p in pts[:10])
           + op(INCR_START, 0) + bytes([10]))
    for p in pts[10:]:
        inc += op(INCR_ADD, 0) + bytes([8]) + raw3(p)
    inc += op(INCR_ADD, 0) + bytes([8]) + raw3((NAN, 0.0, 0.0)) + op(INCR_ADD, 0) + bytes([0]) + raw3((1e30, 0.0, 0.0))
    inc += op(INCR_SOLVE, 0) + op(INCR_INIT, 0) + cfg(mode=2) + op(INCR_INIT, 0) + cfg(noise=1, var=1e9)
    inc += op(INCR_START, 0) + bytes([20]) + op(INCR_SOLVE, 0)
    s["incremental"] = inc
    s["calibrate"] = (b"".join(add(1, p) for p in pts) + op(CALIBRATE, 1) + bytes([0]) + raw3(FAR) + b"\x00"
                      + op(CALIBRATE, 1) + bytes([0]) + raw3(FAR) + b"\x01" + f(100.0)
                      + op(CALIBRATE, 1) + bytes([0]) + raw3((NAN, 0.0, 0.0)) + b"\x00"
                      + op(CALIBRATE, 1) + bytes([0]) + raw3(FAR) + b"\x01" + f(-1.0)
                      + op(CALIBRATE, 2) + bytes([0]) + raw3(FAR) + b"\x00")
    s["batch_and_bad_options"] = (b"".join(add(0, p) for p in pts) + op(BATCH, 0) + bytes([24]) + cfg()
                                  + op(BATCH, 0) + bytes([24]) + cfg(noise=1, var=-1.0)
                                  + op(BATCH, 0) + bytes([24]) + cfg(noise=1, var=NAN)
                                  + op(BATCH, 0) + bytes([24]) + cfg(planar=2.0)
                                  + op(BATCH, 0) + bytes([24]) + bytes([3]) + op(BATCH, 0) + bytes([24]) + bytes([12])
                                  + solve(0, noise=2, cov=(-1.0, 1.0, 1.0, 0.0, 0.0, 0.0))
                                  + solve(0, noise=2, cov=(1.0, 1.0, 1.0, 1e30, 0.0, 0.0))
                                  + op(NULLS, 0))
    s["mixed_floats"] = (b"".join(op(ADD_FLOAT, 0) + bytes([2 | (20 << 3), i, 0, 2 | (20 << 3), 0, i, 2 | (20 << 3), i, i])
                                  for i in range(1, 12)) + solve(0)
                         + b"".join(op(ADD_SPHERE, 1) + bytes([1 | 4, i * 37 % 256, i * 91 % 256, i * 13 % 256, 1, 2, 3])
                                    for i in range(16)) + solve(1) + solve(1, noise=1, var=0.1))
    return s


def kernel_seeds():
    s = {}
    eye = (1.0, 0.0, 1.0, 0.0, 0.0, 1.0)  # lower triangle: a00; a10 a11; a20 a21 a22

    def mat(lt, b=0, extra=()):
        return bytes([b]) + b"".join(f(v) for v in lt) + b"".join(f(v) for v in extra)

    chol = b""
    for lt in (eye, (4.0, 2.0, 3.0, 1.0, 0.5, 2.0), (1.0, 2.0, 1.0, 0.0, 0.0, 1.0), (0.0,) * 6,
               (1e30, 1e15, 1e30, 0.0, 0.0, 1e30), (NAN, 0.0, 1.0, 0.0, 0.0, 1.0), (1.0, 0.0, 1e-8, 0.0, 0.0, 1.0)):
        chol += b"\x00" + mat(lt) + f(1.0) + f(-2.0) + f(3.0)
    s["chol"] = chol
    eig = b""
    for lt in (eye, (2.0, 1.0, 2.0, 0.0, 1.0, 2.0), (1e-40, 1e-41, 1e-40, 0.0, 1e-42, 1e-39),
               (3.0e38, 1e38, -3.0e38, 2e38, 1e37, 3.0e38), (1.0, INF, 1.0, 0.0, 0.0, 1.0),
               (1e4, 1.0, 1e-4, 1e-3, 1e2, 1.0), (0.0, 1.0, 0.0, 1.0, 1.0, 0.0)):
        eig += b"\x01" + b"\x00" + mat(lt) + b"\x01" + b"\x01" + mat(lt, b=1, extra=(7.0,))
    s["eig"] = eig
    cov = b""
    for kind in (0, 1, 2):
        for th in (1, 20, 100, 201, 255):
            cov += b"\x02" + bytes([kind | 64]) + bytes([th]) + bytes([th]) + f(0.01) + f(1.0) + f(1.0)
        cov += b"\x02" + bytes([kind | 4 | 8 | 32 | 64]) + f(NAN) + f(-1.0) + f(INF) + f(0.0) + f(0.0) + f(0.0)
        cov += b"\x02" + bytes([kind | 4 | 8 | 16]) + f(3.1415927) + f(1e20) + bytes([200]) + f(3.0) + f(2.0) + f(1.0)
    s["coverage"] = cov
    s["calib_std"] = (b"\x03" + f(1.0) + f(100.0) + struct.pack("<I", 1000)
                      + b"\x03" + f(-1.0) + f(100.0) + struct.pack("<I", 10)
                      + b"\x03" + f(3e38) + f(3e38) + struct.pack("<I", 1)
                      + b"\x03" + f(1.0) + f(NAN) + struct.pack("<I", 0)
                      + b"\x04\x00\x04\xf9\x04\xf8\x04\x05\x04\x80")
    return s


# fuzz_beyond.c opcodes
(B_POINTS, B_SELFCAL, B_SELFCAL_VAR, B_REFINE, B_UNCERT_MOM, B_UNCERT_PTS, B_GATE_INIT,
 B_GATE_ADD, B_GATE_FEED, B_GATE_REFRESH, B_GATE_SOLVE, B_GATE_RESET, B_BATCH, B_NULLS) = range(14)
# fz_points kinds
P_SPHERE, P_RAW, P_MIXED, P_COINCIDENT, P_COLLINEAR, P_CAP, P_TRANSFORM, P_POISON, P_KEEP = range(9)
WHOLE = b"\x00\x00"  # window: from 0, the rest


def b_cap(cnt, c, r, cap_deg=180.0, circle=False, rotate=False, noise_shift=None):
    """fz_gen_cap: cnt points on a cap (or an arc of the circle z = 0)."""
    flags = (1 if circle else 0) | (2 if rotate else 0) | (4 if noise_shift is not None else 0)
    capb = max(0, min(255, int(round(cap_deg / 180.0 * 256.0)) - 1))
    return (bytes([B_POINTS, P_CAP, flags, capb, cnt, noise_shift or 0])
            + f(c[0]) + f(c[1]) + f(c[2]) + f(r))


def b_mixed3(p):
    return f(p[0]) + f(p[1]) + f(p[2])


def b_operands(center=None, radius=None, var=None, at_point=None, neg=False):
    """fz_fit_operands: None = the last fit (context)."""
    sel = 0
    out = b""
    if at_point is not None:
        sel |= 2
        out += bytes([at_point])
    elif center is not None:
        sel |= 1
        out += b_mixed3(center)
    if radius == "neg":
        sel |= 3 << 2 | (0x40 if neg else 0)
    elif radius is not None:
        sel |= 1 << 2
        out += f(radius)
    if var == 0:
        sel |= 2 << 4
    elif var is not None:
        sel |= 1 << 4
        out += f(var)
    return bytes([sel]) + out


def b_selfcal(window=WHOLE, null=False, **kw):
    return bytes([B_SELFCAL]) + window + cfg(**kw) + (b"\x00" if null else b"\x01")


def b_refine(window=WHOLE, operands=b"\x00", null=False, max_iters=None, tol=None):
    """max_iters: None (0), 1, or ('u32', v) / ('u8', v)."""
    if null:
        return bytes([B_REFINE]) + window + b"\x01" + operands
    b = 0
    extra = b""
    if max_iters == 1:
        b |= 1 << 1
    elif isinstance(max_iters, tuple):
        b |= (2 if max_iters[0] == "u32" else 3) << 1
        extra += struct.pack("<I", max_iters[1]) if max_iters[0] == "u32" else bytes([max_iters[1]])
    if tol is not None:
        b |= 8
        extra += f(tol)
    return bytes([B_REFINE]) + window + bytes([b]) + operands + extra


def b_uncert_mom(gate=False, kind=0, window=WHOLE, operands=b"\x00"):
    src = (1 if gate else 0) | (kind << 1)
    return bytes([B_UNCERT_MOM, src]) + (b"" if gate else window) + operands


def b_uncert_pts(window=WHOLE, operands=b"\x00"):
    return bytes([B_UNCERT_PTS]) + window + operands


def b_gate_init(k=None, noise_var=None, refresh=64, null=False, **fitkw):
    b = (1 if k is not None else 0) | (2 if noise_var is not None else 0) | (4 if refresh > 255 else 0)
    b |= 8 if null else 0
    out = bytes([B_GATE_INIT, b]) + cfg(**fitkw)
    out += f(k) if k is not None else b""
    out += f(noise_var) if noise_var is not None else b""
    out += struct.pack("<I", refresh) if refresh > 255 else bytes([refresh])
    return out


def b_gate_add(p, raw=True, want=True):
    how = (0 if raw else 1) | (0 if want else 4)
    return bytes([B_GATE_ADD, how]) + (raw3(p) if raw else b_mixed3(p))


def beyond_seeds():
    s = {}
    clear = bytes([B_POINTS, P_KEEP, 0])
    no_var = b_selfcal() + b_refine() + b_uncert_pts() + b_uncert_mom() + b_uncert_mom(kind=1)
    analyse = no_var + bytes([B_SELFCAL_VAR]) + WHOLE + b"\x00"
    # A 60-degree cap far from the origin with noise ~ r/128: the pipeline
    # selfcal -> refine -> uncertainty on the context the previous call left.
    s["cap_pipeline"] = (b_cap(120, FAR, 100.0, cap_deg=60.0, noise_shift=7) + analyse
                         + b_refine(operands=b_operands(center=(10.0, -5.0, 3.0)))
                         + bytes([B_BATCH]) + WHOLE + b_uncert_pts(window=b"\x10\x40"))
    s["full_sphere_small_n"] = (b_cap(12, (0.0, 0.0, 0.0), 1.0, noise_shift=10) + analyse
                                + b_selfcal(window=b"\x00\x05") + b_selfcal(window=b"\x00\x04")
                                + b_refine(window=b"\x00\x04") + b_uncert_pts(window=b"\x00\x03"))
    # fz_sphere_point samples (radius 100 about the far centre, perturbed).
    pts = b""
    for i in range(48):
        pts += bytes([1 | 4, i * 37 % 256, i * 91 % 256, i * 13 % 256, i % 7, 3, 250])
    s["sphere_points"] = bytes([B_POINTS, P_SPHERE, 48]) + pts + analyse
    # Coincident, collinear and planar sets: DEGENERATE / NOT_POSDEF, never a result.
    # (No refinement of the coincident set: that is finding 3 of README.md,
    # kept out of the corpus; the fuzzer reaches it in seconds.)
    no_refine = analyse.replace(b_refine(), b"", 1)
    s["degenerate_sets"] = (bytes([B_POINTS, P_COINCIDENT | 0x80, 100]) + b_mixed3((5.0, 5.0, 5.0)) + no_refine
                            + clear + bytes([B_POINTS, P_COLLINEAR, 100]) + b_mixed3((1.0, 2.0, 3.0))
                            + b_mixed3((0.5, -0.25, 2.0)) + analyse
                            + clear + b_cap(80, FAR, 50.0, cap_deg=120.0, circle=True) + analyse
                            + b_uncert_pts(operands=b_operands(at_point=3)))
    # Hostile scales: tiny and huge spheres, a rescale out of range, NaN poison.
    # (No noise_var about the origin of the 1e-30 sphere: a sample "at the
    # centre" by underflow is finding 2 of README.md, kept out of the corpus.)
    s["hostile_scales"] = (b_cap(64, (0.0, 0.0, 0.0), 1e-30, cap_deg=90.0) + no_var + clear
                           + b_cap(64, (1.2e8, -1.2e8, 1e8), 1e7, cap_deg=40.0, noise_shift=12) + analyse
                           + bytes([B_POINTS, P_TRANSFORM]) + f(1e30) + b_mixed3((0.0, 0.0, 0.0)) + analyse
                           + clear + b_cap(64, FAR, 100.0, noise_shift=8) + bytes([B_POINTS, P_POISON, 9])
                           + raw3((NAN, 0.0, 0.0)) + analyse
                           + bytes([B_POINTS, P_POISON, 9]) + raw3((1e30, 0.0, 0.0)) + analyse
                           + bytes([B_POINTS, P_TRANSFORM]) + f(1.4e-45) + b_mixed3((0.0, 1.0, 0.0)) + analyse)
    # Invalid options and arguments: E_ARG, nothing written.
    bad = b_cap(40, FAR, 100.0, noise_shift=8)
    for kw in (dict(mode=2), dict(mode=3), dict(noise=1, var=NAN), dict(noise=1, var=-1.0),
               dict(planar=1.0), dict(noise=2, cov=(1.0, 1.0, 1.0, 5.0, 0.0, 0.0)), dict(noise=3)):
        bad += b_selfcal(**kw)
    bad += b_selfcal(null=True, mode=3)
    for tol in (1.0, NAN, 1e-8, -1e-3, 1e-7, 1e-2):
        bad += b_refine(tol=tol)
    bad += (b_refine(max_iters=("u32", 0xFFFFFFFF)) + b_refine(max_iters=1) + b_refine(max_iters=("u8", 3))
            + b_refine(null=True, operands=b_operands(center=(NAN, 0.0, 0.0))))
    for ops in (b_operands(radius=0.0), b_operands(radius="neg", neg=True), b_operands(var=-1.0),
                b_operands(var=INF), b_operands(center=(INF, 0.0, 0.0)), b_operands(radius=NAN),
                b_operands(var=0)):
        bad += b_uncert_pts(operands=ops) + b_uncert_mom(operands=ops) + bytes([B_SELFCAL_VAR]) + WHOLE + ops
    bad += b_uncert_mom(kind=2) + b_uncert_pts(window=b"\x00\x03") + b_uncert_mom(window=b"\x00\x03")
    for g in (dict(k=1.0), dict(k=NAN), dict(k=-2.0), dict(noise_var=-1.0), dict(noise_var=INF),
              dict(mode=3), dict(noise=1, var=-1.0)):
        bad += b_gate_init(**g)
    s["bad_arguments"] = bad + bytes([B_NULLS]) + clear + bytes([B_NULLS])
    # A gated stream: warm-up on a cap, then a sweep with gross outliers.
    gate = b_gate_init(k=3.0, refresh=32) + b_cap(120, FAR, 100.0, cap_deg=50.0, noise_shift=9)
    gate += bytes([B_GATE_FEED]) + WHOLE + bytes([B_GATE_SOLVE]) + b_uncert_mom(gate=True)
    gate += b_uncert_mom(gate=True, kind=1, operands=b_operands(var=0.25))
    for i in range(12):
        gate += b_gate_add((FAR[0] + 40.0 * i, FAR[1] - 300.0, FAR[2] + 7.0 * i), want=i % 2 == 0)
        gate += b_gate_add((FAR[0], FAR[1] + 100.0 * math.cos(i), FAR[2] + 100.0 * math.sin(i)))
    gate += (b_gate_add((NAN, 0.0, 0.0)) + b_gate_add((0.0, INF, 0.0)) + b_gate_add((1e30, 0.0, 0.0))
             + b_gate_add((134217728.0, 0.0, 0.0), want=False))
    gate += (bytes([B_GATE_REFRESH, B_GATE_SOLVE]) + clear + b_cap(120, FAR, 100.0, cap_deg=170.0, noise_shift=9)
             + bytes([B_GATE_FEED]) + WHOLE + bytes([B_GATE_REFRESH, B_GATE_SOLVE, B_GATE_RESET, B_GATE_SOLVE])
             + bytes([B_GATE_FEED]) + b"\x00\x30" + bytes([B_GATE_REFRESH, B_GATE_SOLVE]))
    s["gate_stream"] = gate
    # Gate with a fixed sigma, refresh after every sample (the sigma x 4 path).
    fixed = b_gate_init(k=2.0, noise_var=1e-6, refresh=1) + b_cap(100, (0.0, 0.0, 0.0), 10.0, noise_shift=6)
    fixed += bytes([B_GATE_FEED]) + WHOLE + bytes([B_GATE_SOLVE])
    for i in range(20):
        fixed += b_gate_add((30.0 + i, 0.0, 0.0))
    s["gate_fixed_sigma_refresh1"] = fixed + bytes([B_GATE_SOLVE]) + b_uncert_mom(gate=True)
    # Planar gate on a hinge, and a warm-up of coincident samples (no fit: ungated).
    hinge = b_gate_init(mode=2, refresh=16) + b_cap(100, FAR, 80.0, cap_deg=70.0, circle=True, noise_shift=9)
    hinge += bytes([B_GATE_FEED]) + WHOLE + bytes([B_GATE_SOLVE, B_GATE_REFRESH])
    hinge += b_gate_add((FAR[0], FAR[1], FAR[2] + 50.0)) + b_gate_add((FAR[0] + 80.0, FAR[1], FAR[2] + 1.0))
    hinge += b_gate_init(null=True) + clear + bytes([B_POINTS, P_COINCIDENT | 0x80, 70]) + b_mixed3((1.0, 2.0, 3.0))
    hinge += bytes([B_GATE_FEED]) + b"\x00\x00" + bytes([B_GATE_SOLVE, B_GATE_REFRESH])
    hinge += clear + b_cap(40, (1.0, 2.0, 3.0), 5.0, noise_shift=8) + bytes([B_GATE_FEED]) + WHOLE
    hinge += bytes([B_GATE_REFRESH, B_GATE_SOLVE]) + b_uncert_mom(gate=True)
    s["gate_planar_and_warmup_fail"] = hinge
    # Early refresh during the warm-up, then gated samples with noise_var 0 windows.
    early = b_gate_init(refresh=0) + b_cap(10, FAR, 100.0, noise_shift=9) + bytes([B_GATE_FEED]) + WHOLE
    early += bytes([B_GATE_SOLVE, B_GATE_REFRESH, B_GATE_SOLVE]) + clear
    early += b_cap(60, FAR, 100.0, noise_shift=9) + bytes([B_GATE_FEED]) + WHOLE + bytes([B_GATE_REFRESH])
    s["gate_early_refresh"] = early + bytes([B_GATE_SOLVE])
    # Refinement from bad starts: a sample at the centre, far away, one iteration.
    s["refine_starts"] = (b_cap(80, FAR, 100.0, cap_deg=90.0, noise_shift=8)
                          + b_refine(operands=b_operands(at_point=5))
                          + b_refine(operands=b_operands(center=(FAR[0] + 1e4, FAR[1], FAR[2])))
                          + b_refine(operands=b_operands(center=(1e30, 0.0, 0.0)))
                          + b_refine(operands=b_operands(center=FAR), max_iters=1)
                          + b_refine(operands=b_operands(center=FAR), tol=1e-2)
                          + b_selfcal() + b_refine() + b_uncert_pts(operands=b_operands(var=1e30))
                          + b_uncert_mom(operands=b_operands(radius=1e30, var=1e30)))
    return s

# fuzz_joint.c opcodes (enum fz_jop)
J_TPL_INIT, J_TPL_FRAME, J_TPL_FRAMES, J_JOINT_INIT, J_ADD, J_REGISTER, J_SOLVE, \
    J_CENTER_AT, J_GARBAGE, J_RESET, J_NULLS = range(11)
J_TPL = [(70.0, 40.0, 10.0), (-75.0, 35.0, 5.0), (-60.0, -50.0, 30.0), (65.0, -25.0, -45.0)]


def j_motion(axis=0, ang=0, far=True):
    return bytes([(axis & 7) | (8 if far else 0), ang & 255])


def j_raw_marker(p):
    return b"\x00" + b"".join(f(c) for c in p)


def j_tpl_init(points, frame=False):
    return bytes([J_TPL_FRAME if frame else J_TPL_INIT, len(points)]) + j_motion(0, 0, False) \
        + b"".join(j_raw_marker(p) for p in points)


def j_add(k, nc=3, par_sel=None, chi_sel=None):
    """A frame: the parent moved by motion k, the child by another motion
    (markers = template markers 0..nc-1 perturbed): in the parent frame the
    child turns about the template origin."""
    out = bytes([J_ADD, 0]) + j_motion(k % 8, (37 * k) % 256) + j_motion((3 * k + 1) % 8, (11 * k + 5) % 256)
    for i in range(4):
        sel = 2 if par_sel is None else par_sel(i)
        out += bytes([sel])
        if sel == 0:
            out += f(INF) * 3
    for i in range(nc):
        sel = 6 if chi_sel is None else chi_sel(i)
        out += bytes([sel])
        if sel & 3 == 0:
            out += f(NAN) * 3
        elif sel & 3 == 2 and sel & 4:
            out += bytes([(5 * i + k) % 256, (7 * i) % 256, (3 * k) % 256])
    return out


def joint_seeds():
    s = {}
    base = j_tpl_init(J_TPL) + bytes([J_JOINT_INIT, 3, 0, 0, 0])
    ball = base + b"".join(j_add(k) for k in range(60))
    s["ball"] = ball + bytes([J_SOLVE, J_CENTER_AT]) + j_motion(2, 40) + bytes([2, 2, 2, 2]) + bytes([J_NULLS])
    s["occluded"] = base + b"".join(
        j_add(k, par_sel=(lambda i, k=k: 1 if i == k % 4 else 2), chi_sel=(lambda i, k=k: 1 if i == k % 3 else 6))
        for k in range(40)) + bytes([J_SOLVE])
    s["rejects"] = base + j_add(1, par_sel=lambda i: 1 if i < 2 else 2) + j_add(2, par_sel=lambda i: 0 if i == 0 else 2) \
        + j_add(3, chi_sel=lambda i: 0 if i == 1 else 6) + bytes([J_SOLVE, J_RESET, J_SOLVE])
    s["collinear"] = j_tpl_init([(0.0, 0.0, 0.0), (100.0, 0.0, 0.0), (50.0, 0.0, 0.0), (-30.0, 0.0, 0.0)]) \
        + j_tpl_init([(1.0, 2.0, 3.0)] * 4, frame=True) + bytes([J_REGISTER, 0]) + j_motion(1, 9) + bytes([2, 2, 2, 2])
    s["garbage"] = ball + bytes([J_GARBAGE, 1, 0, 0, 4, 255, 255, 255, 255]) + j_add(61) + bytes([J_SOLVE]) \
        + bytes([J_GARBAGE, 0, 0, 0, 4, 0, 0, 192, 127]) + bytes([J_REGISTER, 0]) + j_motion(1, 9) + bytes([2, 2, 2, 2])
    frames = bytes([J_TPL_FRAMES, 3, 4]) + b"".join(j_motion(k, 20 * k) + bytes([2, 2, 2, 2]) for k in range(3))
    s["frames"] = j_tpl_init(J_TPL) + frames + bytes([J_JOINT_INIT, 3, 0, 0, 0]) + b"".join(j_add(k) for k in range(30)) \
        + bytes([J_SOLVE])
    s["hinge_planar"] = j_tpl_init(J_TPL) + bytes([J_JOINT_INIT, 2, 2, 0, 0]) \
        + b"".join(bytes([J_ADD, 0]) + j_motion(k % 8, 17 * k) + j_motion(2, 3 * k) + bytes([2] * 4) + bytes([6, 1, 2, 3, 6, 4, 5, 6])
                   for k in range(40)) + bytes([J_SOLVE, J_CENTER_AT]) + j_motion(0, 1) + bytes([2, 2, 2, 2])
    s["marker_noise"] = j_tpl_init(J_TPL) + bytes([J_JOINT_INIT, 3, 4]) + f(0.25) + bytes([0, 1]) \
        + b"".join(j_add(k) for k in range(40)) + bytes([J_SOLVE])
    return s


def c3d_seeds():
    """Small C3D files from the independent writer of the CLI tests
    (tests/scripts/mocap_ref.py): each processor type and storage, invalid
    samples, analog words, a second label block; and broken ones."""
    import tempfile
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "scripts"))
    import mocap_ref as m
    out = {}
    pts = [[(100.0 + p + f, -50.0 * p, 900.0 - f) if (p + f) % 5 else None for p in range(3)]
           for f in range(4)]
    cases = {
        "intel_float": dict(proc=m.INTEL, scale=-0.1),
        "intel_int": dict(proc=m.INTEL, scale=0.05, nanalog=2),
        "dec_float": dict(proc=m.DEC, scale=-1.0),
        "mips_float": dict(proc=m.MIPS, scale=-1.0),
        "mips_int": dict(proc=m.MIPS, scale=0.5, nanalog=1),
        "labels2": dict(proc=m.INTEL, scale=-1.0, label_chunk=2),
    }
    with tempfile.TemporaryDirectory() as d:
        for name, kw in cases.items():
            path = os.path.join(d, name)
            m.write_c3d(path, ["RASIS", "LASIS", "T1"], pts, **kw)
            out[name] = open(path, "rb").read()
    b = out["intel_float"]
    out["truncated_data"] = b[:-20]
    out["truncated_params"] = b[:600]
    out["bad_processor"] = b[:515] + b"\x53" + b[516:]
    # issue 27: one seed per failure class of the reader (tests/data/c3d/cases,
    # made by its make_cases.py from the c3d.org samples)
    cases = os.path.join(os.path.dirname(__file__), "..", "data", "c3d", "cases")
    for fn in sorted(os.listdir(cases)):
        if fn.endswith(".c3d"):
            out["case_" + fn[:-4]] = open(os.path.join(cases, fn), "rb").read()
    # more than 65535 frames announced by POINT:LONG_FRAMES, the file short
    lf = bytearray(out["intel_float"])
    i = lf.find(b"LABELS", 512) - 2
    ent = bytes([11, 1]) + b"LONG_FRAMES" + struct.pack("<H", 9) + bytes([4, 0]) + struct.pack("<f", 70000.0) + b"\0"
    out["long_frames_short"] = bytes(lf[:i]) + ent + bytes(lf[i:])
    # the same ending after whole frames: read to there
    lfc = out["long_frames_short"]
    out["long_frames_complete"] = lfc + bytes(-len(lfc) % 512)
    # the header says 1149 frames, POINT:FRAMES 1000; the file holds 5
    both = bytearray(open(os.path.join(cases, "pc_int_5.c3d"), "rb").read())
    both[8:10] = struct.pack("<H", 1149)
    q = both.find(b"FRAMES", 512) + 6 + 2 + 2  # name, link, type and dimension count
    both[q:q + 2] = struct.pack("<H", 1000)
    out["frames_both_past"] = bytes(both)
    # ANALOG:RATE 100 (16 x 100 / 50 = 32 words) against the header's 64, which
    # the data section's size confirms: the header's layout
    sys.path.insert(0, cases)
    import make_cases
    hb = bytearray(open(os.path.join(cases, "pc_int_5.c3d"), "rb").read())
    q = make_cases.param(hb, "<", "ANALOG", "RATE")
    hb[q:q + 4] = struct.pack("<f", 100.0)
    out["analog_header_by_size"] = bytes(hb)
    # the header says frames 0..4 (5; no POINT:FRAMES): the 5th frame is in
    # the last blocks' zero padding (read as the header says: 5)
    mo = bytearray(out["intel_float"])
    mo[6:10] = struct.pack("<2H", 0, 4)
    out["motive_frames"] = bytes(mo) + bytes(512)
    return out


def table_seeds():
    """Delimited text, one selector byte first (fuzz_table.c)."""
    rows = "1.5,2,3\n4,5,6.25\n7,8,9\n,1,2\n"
    return {
        "csv_header": b"\x00x,y,z\n" + rows.encode(),
        "csv_noheader": b"\x00" + rows.encode(),
        "tab_time": b"\x02t\tx\ty\tz\n0\t1\t2\t3\n0.01\t\t5\t6\n",
        "semicolon_comma": b"\x01x;y;z\n1,5;2,5;3\n4;5;6\n",
        "whitespace": b"\x00  1 2\t3\n4   5 6\n\n7 8 9 10\n",
        "bom_crlf": b"\x00\xef\xbb\xbf\"x\",\"y\",\"z\"\r\n1,2,3\r\n",
        "names_index": b"\x04A,b,c\n1,2,3\nnan,inf,-1e39\n",
        "wide": b"\x05frame,M_X,M_Y,M_Z,N.x,N.y,N.z\n0,1,2,3,4,5,6\n1,,,,4,5,6\n",
        "wide_variants": b"\x05M:x\tM:Y\tM Z\n1\t2\t3\n",
        "one_col": b"\x03v\n1\n2\n\n3\n",
    }


def swaps_seeds():
    """Label-swap programs (fuzz_swaps.c): markers-1, flags (1 repair, 2 a
    first frame, 4 a last frame), the template (3 signed bytes per marker),
    then per frame: opcode (low 3 bits: 0 plain, 1 exchange a b, 2 rotate
    a b c, 3 hostile coordinate, 4 marker missing, 5 raw frame; high 4:
    jitter), angle byte, shift byte, operands."""
    import random
    rnd = random.Random(28)
    tpl5 = bytes([50, 0, 0, 206, 30, 0, 0, 200, 20, 10, 10, 60, 226, 236, 246])

    def frames(n, swaps=(), rot=(), ghost=(), miss=()):
        b = b""
        for f in range(n):
            jit = rnd.randrange(16) << 4
            ang, sh = rnd.randrange(256), rnd.randrange(256)
            if f in swaps:
                b += bytes([jit | 1, ang, sh, 1, 3])
            elif f in rot:
                b += bytes([jit | 2, ang, sh, 0, 2, 4])
            elif f in ghost:
                b += bytes([jit | 3, ang, sh, 2, 1, 1, 0x40])   # special: huge
            elif f in miss:
                b += bytes([jit | 4, ang, sh, 4])
            else:
                b += bytes([jit, ang, sh])
        return b
    return {
        "clean_repair": bytes([4, 1]) + tpl5 + frames(80),
        "swaps_repair": bytes([4, 1]) + tpl5 + frames(120, swaps=range(60, 90), rot={95, 97},
                                                      ghost={100}, miss={10, 11}),
        "swaps_report": bytes([4, 0]) + tpl5 + frames(120, swaps=range(60, 90)),
        "range": bytes([4, 7]) + tpl5 + frames(100, swaps=range(50, 70)) + bytes([20, 60]),
        "three_markers": bytes([2, 1]) + tpl5[:9] + frames(60, swaps={30, 31}),
        "two_markers": bytes([1, 1]) + tpl5[:6] + frames(30),
        "symmetric": bytes([3, 1]) + bytes([50, 0, 0, 206, 0, 0, 0, 50, 0, 0, 206, 0])
        + frames(40, swaps={20}),
        "raw_frames": bytes([4, 1]) + tpl5 + bytes([5] + [rnd.randrange(256) for _ in range(300)]) * 3,
    }


def garbage_seeds():
    """Garbage-state programs (garbage_driver.h): [target] [fill] then bytes.
    Every target with each fill mode, from a fixed-seed generator."""
    import random
    rnd = random.Random(19)
    names = ["moments", "incr", "gate", "cluster", "joint", "multi", "pair", "imu"]
    out = {}
    for t, name in enumerate(names):
        size = 2600 if name in ("gate", "joint", "pair", "imu") else 700
        for fill, how in enumerate(("bytes", "patched", "repeated")):
            body = bytes(rnd.getrandbits(8) for _ in range(size))
            out[f"{name}_{how}"] = bytes([t, fill]) + body
    # A valid gate in warm-up (no samples) whose nwarm-like words are out of
    # range: patches of the hostile-word table (64, 1e6, UINT32_MAX ...).
    patches = b"".join(bytes([off & 0xFF, off >> 8, (k << 1) & 0xFE]) for off, k in
                       ((200, 9), (201, 13), (202, 17), (203, 10)))
    out["gate_counters"] = bytes([2, 1, 0, 4]) + patches + b"\x00" * 40
    return out


def pair_seeds():
    """fuzz_pair.c programs: [op][operands]... (enum fz_pop)."""
    import random
    rnd = random.Random(28)
    P_INIT, P_ADD, P_MARK, P_SOLVE, P_GARB, P_RESET, P_NULLS = range(7)

    def init(sel=8, method=0, mode=0, noise=0, extra=b"", min_frames=0):
        return bytes([P_INIT, sel, method, mode, noise]) + extra + bytes([min_frames])

    def mark(k, hinge=False, noisy=False):
        # parent: slow turn about z; child: about x (hinge) or a star of axes
        pr = bytes([0, 0, 100, (k * 3) % 256])
        if hinge:
            cr = bytes([100, 10, 0, (k * 5) % 120])
        else:
            cr = bytes([(k * 37) % 256, (k * 53) % 256, 20, 10 + (k % 20)])
        sels = bytes([2, 0x11, 3, 4]) if noisy else bytes([3, 4, 5, 6])
        extra = b""
        if noisy:
            extra = bytes([rnd.getrandbits(8)])
            sels = bytes([2]) + extra + bytes([3, 4, 5])
        return bytes([P_MARK]) + pr + cr + sels + bytes([1])

    def add(k):
        pose_p = bytes([1, 0, 0, 100, (k * 3) % 256, 10, 20, 30])
        pose_c = bytes([1, (k * 37) % 256, (k * 11) % 256, 50, 15 + k % 30, 12, 25, 28])
        fits = bytes([2, 40, 1, 2, 40, 1])
        return bytes([P_ADD]) + pose_p + pose_c + fits

    out = {}
    out["ball_markers"] = init() + b"".join(mark(k) for k in range(60)) + bytes([P_SOLVE])
    out["ball_noisy"] = init() + b"".join(mark(k, noisy=True) for k in range(60)) + bytes([P_SOLVE])
    out["hinge_markers"] = init(mode=0) + b"".join(mark(k, hinge=True) for k in range(60)) + bytes([P_SOLVE])
    out["hinge_forced_score"] = init(sel=0, method=1, mode=2, noise=0) + b"".join(mark(k, hinge=True) for k in range(40)) + bytes([P_SOLVE])
    out["poses"] = init() + b"".join(add(k) for k in range(50)) + bytes([P_SOLVE, P_RESET, P_SOLVE])
    out["given_noise"] = init(sel=1, noise=1, extra=bytes([0, 0, 128, 62])) + b"".join(add(k) for k in range(40)) + bytes([P_SOLVE])
    out["garbage"] = init() + b"".join(mark(k) for k in range(30)) + bytes([P_GARB, 0x40, 0, 4, 255, 255, 255, 255, P_SOLVE, P_RESET])
    out["nulls"] = bytes([P_NULLS]) + init() + bytes([P_NULLS, P_SOLVE])
    return out


def skeleton_seeds():
    """fuzz_skeleton.c recordings: [segments - 2] [frames - 12] [mode: 1 markers
    interleaved, 2 no drift, 4 no turning] [noise, 0.1 units]; per segment
    [markers - 1], 3 signed bytes per marker, 3 for the joint, 3 for the
    axis, amplitude, frequency; then occlusion runs (even opcode: frame u32,
    marker, length) and raw samples (odd opcode: frame u32, marker, float)."""
    import random
    rnd = random.Random(38)

    def seg(nmk, spread=60):
        b = bytes([nmk - 1])
        for _ in range(nmk):
            b += bytes([(127 + rnd.randrange(-spread, spread)) & 0xFF for _ in range(3)])
        b += bytes([127, 127, 127 + 100, rnd.randrange(256), rnd.randrange(256),
                    rnd.randrange(256), 160 + rnd.randrange(90), rnd.randrange(256)])
        return b

    def rec(sizes, frames=140, mode=0, noise=3):
        return bytes([len(sizes) - 2, frames - 12, mode, noise]) + b"".join(seg(n) for n in sizes)

    def occl(f, m, n):
        return bytes([0]) + struct.pack("<I", f) + bytes([m, n])

    def raw(f, m, v, axis=0):
        return bytes([1 + 2 * axis]) + struct.pack("<I", f) + bytes([m]) + struct.pack("<f", v)

    return {
        "arm": rec([4, 3, 3]),
        "chain_small_groups": rec([3, 2, 3, 1, 2, 3]),
        "interleaved": rec([3, 3, 2, 3], mode=1),
        "static": rec([3, 3], mode=6, noise=0),
        "noise_free": rec([4, 4, 4], noise=0),
        "occluded": rec([3, 2, 3, 3]) + occl(10, 0, 40) + occl(50, 4, 63) + occl(0, 2, 20),
        "hostile": rec([3, 3, 2]) + raw(5, 0, float("nan")) + raw(6, 1, float("inf"), 1)
        + raw(7, 2, 3e38, 2) + raw(8, 3, -1e12) + raw(9, 4, 1e-40),
        "short": rec([2, 2], frames=12),
    }
def imu_seeds():
    """fuzz_imu.c programs: [op][operands]... (enum fz_iop)."""
    I_INIT, I_ADD, I_MOTION, I_SOLVE, I_GARB, I_NULLS = range(6)
    out = {}
    motion = b"".join(bytes([I_MOTION, 250, 40, 20]) for _ in range(12))
    out["motion_solve"] = motion + bytes([I_SOLVE])
    out["still_solve"] = b"".join(bytes([I_MOTION, 250, 0, 20]) for _ in range(4)) + bytes([I_SOLVE])
    out["rate_100"] = bytes([I_INIT, 1]) + f(100.0) + motion + bytes([I_SOLVE])
    out["bad_rate"] = bytes([I_INIT, 1]) + f(NAN) + bytes([I_INIT, 1]) + f(-5.0) + motion + bytes([I_SOLVE])
    out["hostile_samples"] = motion + b"".join(bytes([I_ADD]) + f(v) * 12 for v in (NAN, INF, 1e30, -0.0)) \
        + bytes([I_SOLVE])
    out["options"] = bytes([I_INIT, 6]) + f(0.001) + f(0.0) + f(1e-6) + f(0.5) + f(2.0) + f(1.0) \
        + f(1e-9) + motion + bytes([I_SOLVE])
    out["garbage_solve"] = motion + bytes([I_GARB, 8, 0, 12]) + bytes(range(12)) + bytes([I_SOLVE, I_NULLS])
    return out


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus")
    for sub, seeds in (("stream", stream_seeds()), ("kernels", kernel_seeds()), ("beyond", beyond_seeds()),
                       ("joint", joint_seeds()), ("c3d", c3d_seeds()), ("table", table_seeds()),
                       ("garbage", garbage_seeds()), ("swaps", swaps_seeds()),
                       ("pair", pair_seeds()), ("skeleton", skeleton_seeds()),
                       ("imu", imu_seeds())):
        d = os.path.join(root, sub)
        os.makedirs(d, exist_ok=True)
        for name, data in sorted(seeds.items()):
            with open(os.path.join(d, name), "wb") as fh:
                fh.write(data)
        print(f"{d}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
