# SPDX-License-Identifier: MIT
"""IMU signals of two virtual sensors from real motion (recorded markers).

    imu_from_c3d.py TRIAL SEED OUT.csv [--carrier] [--exact]   (truth JSON on stdout)
    imu_from_c3d.py --list

A trial names a C3D file of tests/data/c3d and two marker clusters joined by
a joint (TRIALS below). The steps, all in double precision with numpy:

1. Rigid registration (Kabsch) of each cluster to its mean shape gives the
   segment poses R_i(t), p_i(t) at the recording's rate.
2. The joint centre from the markers: c1, c2 (each in its segment) minimise
   sum_t |p1 + R1 c1 - p2 - R2 c2|^2 (SCoRE, Ehrig et al. 2006), with a weak
   pull (1 mm per 10 m of misfit) towards the midpoint of the named
   landmark markers, which fixes the free direction of a near-hinge.
   For a hinge the axis is the principal direction of the relative angular
   rate, in each segment.
3. The motion is made exactly rigid about that centre: segment 1 moves as
   registered (smoothed), segment 2 turns as registered relative to segment
   1 and is carried so that its c2 meets segment 1's c1 at every instant.
   With --carrier segment 1 is moreover carried by a walking motion (1 Hz
   gait: forward 1.2 m/s, yaw 10, roll 5, pitch 4 degrees, 2 cm of bob and
   sway), for a parent that hardly turns in the laboratory.
4. Smoothing: the quaternions (sign-continuous) and positions are smoothed
   by a Gaussian kernel (sigma 25 ms, a zero-lag low-pass of about 6 Hz)
   evaluated at any time (Nadaraya-Watson), so the poses are smooth
   functions; the rate, its derivative and the accelerations come from
   5-point differences with a 0.5 ms step (truncation ~1e-9 relative),
   at 200 Hz, 0.3 s trimmed at each end.
5. Sensors: each at a landmark of its segment (plus up to 2 cm, random),
   turned by a random rotation. Specific force = R^T (p'' - g), g = 9.81 m/s^2
   down the laboratory's vertical axis. Noise 0.005 rad/s and 0.02 m/s^2 per
   sample, biases up to 0.01 rad/s and 0.05 m/s^2 in random directions
   (--exact: none, and the exact w' in 3 more columns per sensor).

The truth (stdout, JSON): r1, r2 (joint centre in each sensor's frame, m);
for a hinge axis1, axis2 and the axis points nearest each sensor; the
largest gap of Seel's constraint on the exact signals (m/s^2), the biases.
"""
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import c3d_ref  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, '..', 'data', 'c3d')
RATE = 200.0
G = 9.81

# name: file, frames [a, b), vertical axis, segment 1, segment 2, joint kind,
# landmarks for the centre's free direction, sensor landmarks (1, 2)
TRIALS = {
    'hip': dict(file='biobuddy_right_hip.c3d', frames=(0, 1400), up=2,
                seg1=['RASIS', 'LASIS', 'RPSIS', 'LPSIS'],
                seg2=['RTHI1', 'RTHI2', 'RTHI3', 'RLFE', 'RMFE', 'RGT'], kind='ball',
                centre=None, sensor1=['RPSIS', 'LPSIS'], sensor2=['RTHI1', 'RTHI2', 'RTHI3']),
    'knee': dict(file='biobuddy_right_knee.c3d', frames=(0, 922), up=2,
                 seg1=['RTHI1', 'RTHI2', 'RTHI3', 'RLFE', 'RMFE'],
                 seg2=['RLEG1', 'RLEG2', 'RLEG3', 'RATT', 'RLM', 'RSPH'], kind='hinge',
                 centre=['RLFE', 'RMFE'], sensor1=['RTHI1', 'RTHI2', 'RTHI3'],
                 sensor2=['RLEG1', 'RLEG2', 'RLEG3']),
    'cmu_elbow': dict(file='cmu/135_02.c3d', frames=(0, 2400), up=1,
                      seg1=['RSHO', 'RUPA', 'RELB'], seg2=['RFRM', 'RWRA', 'RWRB'],
                      kind='ball', centre=['RELB'], sensor1=['RUPA'], sensor2=['RFRM']),
}


def kabsch(ref, x):
    """R, p with x ~ p + R ref (ref centred)."""
    c = x.mean(0)
    h = ref.T @ (x - c)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return r, c


def rot2q(r):
    w = math.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
    x = math.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2
    y = math.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2
    z = math.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2
    x = math.copysign(x, r[2, 1] - r[1, 2])
    y = math.copysign(y, r[0, 2] - r[2, 0])
    z = math.copysign(z, r[1, 0] - r[0, 1])
    return np.array([w, x, y, z])


def q2rot(q):
    """(..., 4) unit quaternions -> (..., 3, 3)."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def euler_q(ax, ang):
    """(n,) angles about a coordinate axis -> (n, 4)."""
    q = np.zeros(ang.shape + (4,))
    q[..., 0] = np.cos(ang / 2)
    q[..., 1 + ax] = np.sin(ang / 2)
    return q


def qmul(a, b):
    w1, x1, y1, z1 = np.moveaxis(a, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(b, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], -1)


def random_rot(rng):
    q = rng.normal(size=4)
    return q2rot(q / np.linalg.norm(q))


class Smooth:
    """Gaussian-kernel (Nadaraya-Watson) smoothing of samples y(t_k), a C-infinity function of t."""

    def __init__(self, t, y, sigma):
        self.t, self.y, self.s = t, y, sigma

    def __call__(self, tq):
        out = np.empty((len(tq),) + self.y.shape[1:])
        for a in range(0, len(tq), 512):
            tt = tq[a:a + 512]
            # the kernel below 1e-17 of its peak (9 sigma) is left out
            i0, i1 = np.searchsorted(self.t, [tt.min() - 9 * self.s, tt.max() + 9 * self.s])
            w = np.exp(-0.5 * ((tt[:, None] - self.t[None, i0:i1]) / self.s) ** 2)
            out[a:a + 512] = np.tensordot(w, self.y[i0:i1], 1) / w.sum(1)[:, None]
        return out


def load(trial):
    d = TRIALS[trial]
    c = c3d_ref.read(os.path.join(DATA, d['file']))
    labels = [s.split(':')[-1] for s in c['labels']]
    xyz = np.asarray(c['xyz'], dtype=float) / 1000.0
    res = np.asarray(c['residual'], dtype=float)
    a, b = d['frames']
    b = min(b, xyz.shape[0])
    xyz, res = xyz[a:b], res[a:b]
    rate = float(c['rate'])
    up = d['up']
    # laboratory frame with z up (a right-handed cyclic permutation)
    perm = [(up + 1) % 3, (up + 2) % 3, up]
    xyz = xyz[..., perm]

    def idx(names):
        return [labels.index(n) for n in names]
    i1, i2 = idx(d['seg1']), idx(d['seg2'])
    ok = (res[:, i1 + i2] >= 0).all(1)
    if not ok.all():  # the longest run of complete frames
        best, start, run = (0, 0), None, 0
        for k, v in enumerate(list(ok) + [False]):
            if v and start is None:
                start = k
            if not v and start is not None:
                if k - start > best[1] - best[0]:
                    best = (start, k)
                start = None
        xyz = xyz[best[0]:best[1]]
    return d, labels, xyz, rate, idx


def poses(x):
    ref = x.mean(0)
    ref = ref - ref.mean(0)
    n = x.shape[0]
    rs, ps = np.empty((n, 3, 3)), np.empty((n, 3))
    for k in range(n):
        rs[k], ps[k] = kabsch(ref, x[k])
    return ref, rs, ps


_CACHE = {}


def generate(trial, seed, carrier=False, exact=False):
    if trial not in _CACHE:
        d, labels, xyz, rate, idx = load(trial)
        _CACHE[trial] = (d, labels, xyz, rate, idx, poses(xyz[:, idx(d['seg1'])]),
                         poses(xyz[:, idx(d['seg2'])]))
    d, labels, xyz, rate, idx, (ref1, ra, pa), (ref2, rb, pb) = _CACHE[trial]
    n = xyz.shape[0]
    # SCoRE with a weak pull towards the landmarks (segment frames: centroid of the mean shape)
    lam = 1e-4
    rows = np.zeros((3 * n + 6, 6))
    rhs = np.zeros(3 * n + 6)
    rows[:3 * n, :3] = ra.reshape(-1, 3, 3).reshape(3 * n, 3)
    rows[:3 * n, 3:] = -rb.reshape(3 * n, 3)
    rhs[:3 * n] = (pb - pa).reshape(-1)
    if d['centre'] is not None:
        mid = xyz[:, idx(d['centre'])].mean(1)
        c1p = np.einsum('kji,kj->ki', ra, mid - pa).mean(0)
        c2p = np.einsum('kji,kj->ki', rb, mid - pb).mean(0)
        rows[3 * n:, :] = lam * math.sqrt(n) * np.eye(6)
        rhs[3 * n:] = lam * math.sqrt(n) * np.concatenate([c1p, c2p])
    sol = np.linalg.lstsq(rows, rhs, rcond=None)[0]
    c1, c2 = sol[:3], sol[3:]
    miss = (pa + np.einsum('kij,j->ki', ra, c1)) - (pb + np.einsum('kij,j->ki', rb, c2))
    score_rms = float(np.sqrt((miss ** 2).sum(1).mean()))

    # smooth pose functions: segment 1 (q1, p1) and the relative rotation q12
    t = np.arange(n) / rate
    q1 = np.array([rot2q(r) for r in ra])
    q12 = np.array([rot2q(ra[k].T @ rb[k]) for k in range(n)])
    for q in (q1, q12):
        for k in range(1, n):
            if q[k] @ q[k - 1] < 0:
                q[k] = -q[k]
    sig = 0.025
    f_q1, f_p1, f_q12 = Smooth(t, q1, sig), Smooth(t, pa, sig), Smooth(t, q12, sig)
    rng = np.random.default_rng(seed)
    ph = rng.uniform(0, 2 * math.pi, 6)
    fg = 1.0

    def pose(tq):
        a = f_q1(tq)
        a /= np.linalg.norm(a, axis=1)[:, None]
        p = f_p1(tq)
        b = f_q12(tq)
        b /= np.linalg.norm(b, axis=1)[:, None]
        if carrier:
            w = 2 * math.pi * fg * tq
            qc = qmul(qmul(euler_q(2, math.radians(10) * np.sin(w + ph[0])),
                           euler_q(0, math.radians(5) * np.sin(w + ph[1]))),
                      euler_q(1, math.radians(4) * np.sin(2 * w + ph[2])))
            rc = q2rot(qc)
            pc = np.stack([1.2 * tq, 0.02 * np.sin(w + ph[3]), 0.02 * np.sin(2 * w + ph[4])], 1)
            p = pc + np.einsum('kij,kj->ki', rc, p)
            a = qmul(qc, a)
        return a, p, qmul(a, b)

    # sensors
    def place(names, r, pp):
        land = xyz[:, idx(names)].mean(1)
        s = np.einsum('kji,kj->ki', r, land - pp).mean(0)
        return s + rng.uniform(-0.02, 0.02, 3)
    s1 = place(d['sensor1'], ra, pa)
    s2 = place(d['sensor2'], rb, pb)
    cs1, cs2 = random_rot(rng), random_rot(rng)

    h = 5e-4
    tt = np.arange(0.3, t[-1] - 0.3, 1.0 / RATE)
    m = len(tt)
    st = [-2, -1, 1, 2]
    d1 = np.array([1, -8, 8, -1]) / (12 * h)
    q1s, q2s, ps1, ps2 = [], [], [], []
    for k in [-2, -1, 0, 1, 2]:
        qa, p, qb = pose(tt + k * h)
        ra_, rb_ = q2rot(qa), q2rot(qb)
        pj = p + np.einsum('kij,j->ki', ra_, c1)
        q1s.append(qa)
        q2s.append(qb)
        ps1.append(p + np.einsum('kij,j->ki', ra_, s1))
        ps2.append(pj + np.einsum('kij,j->ki', rb_, s2 - c2))
    d2 = np.array([-1, 16, -30, 16, -1]) / (12 * h * h)

    def rates(qs):
        q = qs[2]
        qd = sum(c * qs[i if i < 2 else i + 1] for c, i in zip(d1, range(4)))
        qdd = sum(c * qs[i] for c, i in zip(d2, range(5)))
        qc = q * np.array([1, -1, -1, -1])
        w = 2 * qmul(qc, qd)[:, 1:]
        dw = 2 * qmul(qc, qdd)[:, 1:]
        return q2rot(q), w, dw
    r1, w1, dw1 = rates(q1s)
    r2, w2, dw2 = rates(q2s)
    gv = np.array([0.0, 0.0, -G])

    def force(ps, r):
        acc = sum(c * ps[i] for c, i in zip(d2, range(5)))
        return np.einsum('kji,kj->ki', r, acc - gv)
    f1, f2 = force(ps1, r1), force(ps2, r2)
    # into the sensor frames
    a1, g1, e1 = f1 @ cs1, w1 @ cs1, dw1 @ cs1
    a2, g2, e2 = f2 @ cs2, w2 @ cs2, dw2 @ cs2
    rr1, rr2 = cs1.T @ (c1 - s1), cs2.T @ (c2 - s2)

    def gmul(w, dw, r):
        return np.cross(w, np.cross(w, r)) + np.cross(dw, r)
    gap = np.abs(np.linalg.norm(a1 + gmul(g1, e1, rr1), axis=1) - np.linalg.norm(a2 + gmul(g2, e2, rr2), axis=1))
    truth = dict(trial=trial, seed=seed, carrier=carrier, samples=m, rate=RATE,
                 r1=rr1.tolist(), r2=rr2.tolist(), dist1=float(np.linalg.norm(rr1)),
                 dist2=float(np.linalg.norm(rr2)), gap_max=float(gap.max()),
                 acc_rms=float(np.sqrt((f1 ** 2).sum(1).mean())), score_rms=score_rms,
                 rate_rms1=float(np.sqrt((w1 ** 2).sum(1).mean())),
                 rate_rms2=float(np.sqrt((w2 ** 2).sum(1).mean())), kind=d['kind'])
    if d['kind'] == 'hinge':
        # relative rate in segment 1 (spatial) and in segment 2 (body)
        w12_2 = w2 - np.einsum('kji,kj->ki', np.einsum('kji,kjl->kil', r1, r2), w1)
        w12_1 = np.einsum('kji,kjl->kil', r1, r2)
        w12_1 = np.einsum('kij,kj->ki', w12_1, w12_2)
        j1 = np.linalg.eigh(w12_1.T @ w12_1)[1][:, 2]
        j2 = np.linalg.eigh(w12_2.T @ w12_2)[1][:, 2]
        if (w12_1 @ j1).sum() < 0:
            j1 = -j1
        if (w12_2 @ j2).sum() < 0:
            j2 = -j2
        # how far the relative rotation strays from the axis (rms angle, fast samples)
        nrm = np.linalg.norm(w12_1, axis=1)
        big = nrm > 0.5
        spread = np.degrees(np.arccos(np.clip(np.abs(w12_1[big] @ j1) / nrm[big], 0, 1)))
        j1, j2 = cs1.T @ j1, cs2.T @ j2
        truth.update(axis1=j1.tolist(), axis2=j2.tolist(),
                     point1=(rr1 - (rr1 @ j1) * j1).tolist(), point2=(rr2 - (rr2 @ j2) * j2).tolist(),
                     wobble_deg_rms=float(np.sqrt((spread ** 2).mean())))
    if not exact:
        for a, g in ((a1, g1), (a2, g2)):
            bg, ba = rng.normal(size=3), rng.normal(size=3)
            bg *= rng.uniform(0, 0.01) / np.linalg.norm(bg)
            ba *= rng.uniform(0, 0.05) / np.linalg.norm(ba)
            a += ba + rng.normal(0, 0.02, a.shape)
            g += bg + rng.normal(0, 0.005, g.shape)
    cols = [tt - tt[0], a1, g1, a2, g2] + ([e1, e2] if exact else [])
    return truth, np.column_stack(cols)


def main(argv):
    if argv[1:2] == ['--list']:
        print(' '.join(TRIALS))
        return 0
    trial, seed, out = argv[1], int(argv[2]), argv[3]
    truth, data = generate(trial, seed, '--carrier' in argv, '--exact' in argv)
    head = 'time,acc1_x,acc1_y,acc1_z,gyr1_x,gyr1_y,gyr1_z,acc2_x,acc2_y,acc2_z,gyr2_x,gyr2_y,gyr2_z'
    if '--exact' in argv:
        head += ',dgyr1_x,dgyr1_y,dgyr1_z,dgyr2_x,dgyr2_y,dgyr2_z'
    fmt = ['%.4f'] + ['%.6f'] * (data.shape[1] - 1)
    np.savetxt(out, data, fmt=fmt, delimiter=',', header=head, comments='')
    print(json.dumps(truth))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
