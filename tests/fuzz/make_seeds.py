#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the seed corpus of the sfit fuzz harnesses (tests/fuzz/corpus/).

Each seed is a small program in the byte format that fuzz_stream.c /
fuzz_kernels.c interpret (opcode table in tests/fuzz/README.md): the
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


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus")
    for sub, seeds in (("stream", stream_seeds()), ("kernels", kernel_seeds())):
        d = os.path.join(root, sub)
        os.makedirs(d, exist_ok=True)
        for name, data in sorted(seeds.items()):
            with open(os.path.join(d, name), "wb") as fh:
                fh.write(data)
        print(f"{d}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
