# SPDX-License-Identifier: MIT
"""An independent BVH reader and forward kinematics for the tests (shares
no code with tools/lab/skel_write.c): the BVH format as Biovision
published it and Blender's importer reads it -- HIERARCHY of ROOT / JOINT /
End Site blocks with OFFSET and CHANNELS, then MOTION (Frames, Frame Time,
one line of channel values per frame). Rotation channels compose in the
order listed: the local rotation is R = R_first R_second R_third applied
to column vectors; a node's position is its parent's position plus the
parent's global rotation times its OFFSET (the root's position channels
add to its OFFSET). Also a TRC reader. Pure Python (math only)."""
import math


class Node:
    def __init__(self, name, parent, kind):
        self.name = name
        self.parent = parent
        self.kind = kind  # ROOT, JOINT, End
        self.offset = None
        self.channels = []
        self.children = []


def _axis_rot(axis, deg):
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    if axis == 'X':
        return [[1, 0, 0], [0, c, -s], [0, s, c]]
    if axis == 'Y':
        return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def _mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def _apply(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def read_bvh(path):
    """Returns (nodes in file order, frames (list of value lists), frame_time)."""
    with open(path) as f:
        toks = f.read().split()
    pos = 0
    nodes = []
    stack = []

    def take():
        nonlocal pos
        pos += 1
        return toks[pos - 1]

    if take() != 'HIERARCHY':
        raise ValueError('no HIERARCHY')
    while True:
        t = take()
        if t in ('ROOT', 'JOINT'):
            if (t == 'ROOT') != (not stack):
                raise ValueError('ROOT must be the outermost block')
            n = Node(take(), stack[-1] if stack else None, t)
            if take() != '{':
                raise ValueError('{ expected after ' + n.name)
            nodes.append(n)
            if stack:
                stack[-1].children.append(n)
            stack.append(n)
        elif t == 'End':
            if take() != 'Site' or take() != '{':
                raise ValueError('End Site { expected')
            n = Node(stack[-1].name + '_end', stack[-1], 'End')
            nodes.append(n)
            stack[-1].children.append(n)
            stack.append(n)
        elif t == 'OFFSET':
            stack[-1].offset = [float(take()) for _ in range(3)]
        elif t == 'CHANNELS':
            k = int(take())
            stack[-1].channels = [take() for _ in range(k)]
        elif t == '}':
            stack.pop()
            if not stack:
                break
        else:
            raise ValueError('unexpected token ' + t)
    if take() != 'MOTION' or take() != 'Frames:':
        raise ValueError('MOTION Frames: expected')
    nf = int(take())
    if take() != 'Frame' or take() != 'Time:':
        raise ValueError('Frame Time: expected')
    ft = float(take())
    nch = sum(len(n.channels) for n in nodes)
    frames = []
    for _ in range(nf):
        frames.append([float(take()) for _ in range(nch)])
    if pos != len(toks):
        raise ValueError('trailing tokens after the frames')
    return nodes, frames, ft


def forward(nodes, values):
    """Global positions {name: [x, y, z]} of every node for one frame."""
    out = {}
    rot = {}
    i = 0
    for n in nodes:  # parents come before children in file order
        r = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
        p = list(n.offset)
        for ch in n.channels:
            v = values[i]
            i += 1
            if ch.endswith('position'):
                p[{'X': 0, 'Y': 1, 'Z': 2}[ch[0]]] += v
            else:
                r = _mul(r, _axis_rot(ch[0], v))
        if n.parent is None:
            out[n.name] = p
            rot[n.name] = r
        else:
            w = _apply(rot[n.parent.name], n.offset)
            out[n.name] = [out[n.parent.name][k] + w[k] for k in range(3)]
            rot[n.name] = _mul(rot[n.parent.name], r)
    return out


def read_trc(path):
    """Returns (names, units, rows): rows[f] = {name: [x, y, z]}."""
    with open(path) as f:
        lines = f.read().split('\n')
    meta_keys = lines[1].split('\t')
    meta = dict(zip(meta_keys, lines[2].split('\t')))
    head = lines[3].split('\t')
    names = [h for h in head[2:] if h != '']
    rows = []
    for ln in lines[5:]:
        if ln.strip() == '':
            continue
        c = ln.split('\t')
        vals = [float(x) for x in c[2:]]
        rows.append({nm: vals[3 * k:3 * k + 3] for k, nm in enumerate(names)})
    if len(rows) != int(meta['NumFrames']) or len(names) != int(meta['NumMarkers']):
        raise ValueError('TRC counts disagree with its header')
    return names, meta['Units'], rows
