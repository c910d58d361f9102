# SPDX-License-Identifier: MIT
"""A synthetic three-segment chain for `sfit skeleton` (tests/scripts/
test_skeleton.sh): segment A moves freely, B turns about a ball joint fixed
in A, C about a hinge fixed in B; four markers on each segment; written as
a small C3D file (Intel, float storage) by a writer of its own. The truth
(joint centres in the lab at every frame, the hinge axis) goes to a JSON
file. Pure Python; fixed seed.

usage: skeleton_synth.py OUT.c3d TRUTH.json NOISE_SD [FRAMES [SEED]]"""
import json
import math
import random
import struct
import sys


def rot(axis, deg):
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    x, y, z = axis
    n = math.sqrt(x * x + y * y + z * z)
    x, y, z = x / n, y / n, z / n
    return [[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
            [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
            [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def app(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


# Geometry (mm): joint centres in each segment's frame, marker positions.
CA = [0.0, -50.0, -200.0]      # ball joint A-B in A
CB = [10.0, 0.0, 220.0]        # the same point in B
DB = [0.0, 20.0, -240.0]       # hinge B-C centre in B
DC = [0.0, -10.0, 180.0]       # the same point in C
AXIS_B = [1.0, 0.2, 0.1]       # hinge axis in B
MK = {
    'A': [[80, 0, 0], [0, 90, 30], [-70, -20, 60], [10, -60, -90]],
    'B': [[50, 10, 60], [-40, 45, -20], [5, -55, -80], [45, -30, 10]],
    'C': [[55, 0, 40], [-35, 40, -10], [0, -50, -70], [40, 30, 90]],
}


def poses(t):
    ra = mul(rot([0, 0, 1], 20 * math.sin(0.5 * t)), rot([1, 0, 0], 10 * math.sin(0.8 * t)))
    ta = [150 * math.sin(0.3 * t), 80 * math.cos(0.45 * t), 1000.0]
    rrel = mul(mul(rot([0, 0, 1], 40 * math.sin(0.9 * t)), rot([1, 0, 0], 30 * math.sin(1.7 * t))),
               rot([0, 1, 0], 25 * math.sin(0.6 * t + 1)))
    rb = mul(ra, rrel)
    jab = add(app(ra, CA), ta)
    tb = sub(jab, app(rb, CB))
    rc = mul(rb, rot(AXIS_B, 45 + 45 * math.sin(1.1 * t)))
    jbc = add(app(rb, DB), tb)
    tc = sub(jbc, app(rc, DC))
    return {'A': (ra, ta), 'B': (rb, tb), 'C': (rc, tc)}, jab, jbc, app(rb, AXIS_B)


def write_c3d(path, labels, frames, rate):
    """Intel float C3D: header block, two parameter blocks, the data."""
    npt = len(labels)
    params = bytearray()

    def entry(name, gid, body):
        nm = name.encode()
        e = struct.pack('<bb', len(nm), gid) + nm
        nxt = 2 + len(body) + 1  # offset word, body, description length byte
        return e + struct.pack('<h', nxt) + body + b'\x00'

    def par(name, typ, dims, data):
        return entry(name, 1, struct.pack('<bB', typ, len(dims))
                     + bytes(dims) + data)

    lw = max(len(s) for s in labels)
    nblk_par = 2
    data_start = 1 + nblk_par + 1
    params += entry('POINT', -1, b'')
    params += par('USED', 2, [], struct.pack('<h', npt))
    params += par('SCALE', 4, [], struct.pack('<f', -1.0))
    params += par('RATE', 4, [], struct.pack('<f', rate))
    params += par('DATA_START', 2, [], struct.pack('<h', data_start))
    params += par('FRAMES', 2, [], struct.pack('<h', len(frames)))
    params += par('UNITS', -1, [2], b'mm')
    params += par('LABELS', -1, [lw, npt], b''.join(s.ljust(lw).encode() for s in labels))
    # the last entry's offset is 0
    last = params.rfind(b'LABELS') + 6
    params[last:last + 2] = struct.pack('<h', 0)
    pblock = bytearray(struct.pack('<BBBB', 1, 0x50, nblk_par, 84)) + params
    if len(pblock) > 512 * nblk_par:
        raise ValueError('parameters too long')
    pblock += bytes(512 * nblk_par - len(pblock))
    head = bytearray(512)
    struct.pack_into('<BB', head, 0, 2, 0x50)
    struct.pack_into('<hhhhh', head, 2, npt, 0, 1, len(frames), 0)
    struct.pack_into('<f', head, 12, -1.0)
    struct.pack_into('<hh', head, 16, data_start, 0)
    struct.pack_into('<f', head, 20, rate)
    data = bytearray()
    for fr in frames:
        for p in fr:
            if p is None:
                data += struct.pack('<ffff', 0.0, 0.0, 0.0, -1.0)
            else:
                data += struct.pack('<ffff', p[0], p[1], p[2], 0.0)
    with open(path, 'wb') as f:
        f.write(bytes(head) + bytes(pblock) + bytes(data))


def main():
    out, truth_path, sd = sys.argv[1], sys.argv[2], float(sys.argv[3])
    nf = int(sys.argv[4]) if len(sys.argv) > 4 else 1200
    rate = 100.0
    rng = random.Random(int(sys.argv[5]) if len(sys.argv) > 5 else 20261127)
    labels = ['P%02d' % k for k in range(12)]
    frames, truth = [], {'ab': [], 'bc': [], 'axis_bc': []}
    for f in range(nf):
        ps, jab, jbc, ax = poses(f / rate * 2.0)
        row = []
        for seg in 'ABC':
            r, t = ps[seg]
            for m in MK[seg]:
                x = add(app(r, m), t)
                # frame 0 carries no noise: the segments' template frames
                # (lab axes at the first frame, origin at the markers'
                # centroid, docs/joint.md) are then known exactly
                row.append([v + rng.gauss(0.0, sd) for v in x] if sd > 0 and f > 0 else x)
        # a few missing samples: marker P05 unseen in frames 100-119
        if 100 <= f < 120:
            row[5] = None
        frames.append(row)
        if f == 0:  # the truth in the parents' template frames
            cen = {}
            for seg in 'ABC':
                r, t = ps[seg]
                pts = [add(app(r, m), t) for m in MK[seg]]
                cen[seg] = [sum(p[i] for p in pts) / 4.0 for i in range(3)]
            truth['ab_parent'] = sub(jab, cen['A'])
            truth['bc_parent'] = sub(jbc, cen['B'])
            truth['axis_bc_parent'] = ax
        truth['ab'].append(jab)
        truth['bc'].append(jbc)
        truth['axis_bc'].append(ax)
    # the labels interleave the segments so that grouping has to find them
    order = [0, 4, 8, 1, 5, 9, 2, 6, 10, 3, 7, 11]
    write_c3d(out, [labels[k] for k in order], [[fr[k] for k in order] for fr in frames], rate)
    truth['groups'] = [['P%02d' % (4 * s + m) for m in range(4)] for s in range(3)]
    with open(truth_path, 'w') as f:
        json.dump(truth, f)


if __name__ == '__main__':
    main()
