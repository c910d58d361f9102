#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Grouping accuracy of `sfit skeleton FILE --json` (segments found from the
data) against the true segments: the adjusted Rand index (Hubert and Arabie
1985) of the groups `grouping.groups[].markers`, the true segments found
exactly, and whether named segments (hands, feet) are exact.

    skeleton_ari.py OUT.json --truth names|sequential:4,2,3|file:TABLE.tsv
                    [--min ARI] [--exact SEG,SEG,...] [--quiet]

--truth names: the true segment of a marker from its label (a prefix
before ':' is dropped), by the Vicon full-body naming convention of the
CMU and Plug-in Gait marker sets (the table SEGMENT_OF below, documented
in docs/skeleton.md); a label not in the table is left out of the index.
--truth sequential:4,2,3: the markers in file order, 4 on the first
segment, 2 on the second, 3 on the third (the unlabelled arm recordings).
--truth file:TABLE.tsv: lines `label<TAB>segment` ('#' comments), e.g. the
hand-labelled unlabelled full body (tests/data/c3d/unlabeled/
fullbody_44Markers_segments.tsv, segment names as in the table below).

Exit 1 when the index is below --min or a segment of --exact is not found
exactly (one group holding that segment's markers and nothing else).
Independent of sfit: it reads only the JSON.
"""
import argparse
import json
import sys
from collections import Counter


def _table():
    seg = {}
    for n in 'LFHD RFHD LBHD RBHD C2'.split():
        seg[n] = 'head'
    for n in 'C7 T1 T6 T10 CLAV STRN RBAC RBAK'.split():
        seg[n] = 'thorax'
    for n in 'LFWT RFWT LBWT RBWT LASI RASI LPSI RPSI S1 S3 SACR'.split():
        seg[n] = 'pelvis'
    per_side = {
        'shoulder': 'SHO', 'upperarm': 'UPA ELB', 'forearm': 'FRM FRA WRA WRB', 'hand': 'FIN',
        'thigh': 'THI THIB THID KNE KNEM', 'shank': 'SHN TIB TIBF TIBD ANK ANKM',
        'foot': 'HEE TOE MT5 NAV TOE5',
    }
    for s, names in per_side.items():
        for n in names.split():
            seg['L' + n] = 'L' + s
            seg['R' + n] = 'R' + s
    return seg


SEGMENT_OF = _table()

# The 16 joints of the 17-segment body.
BODY_JOINTS = [('head', 'thorax'), ('thorax', 'pelvis')]
for _s in 'LR':
    BODY_JOINTS += [('thorax', _s + 'shoulder'), (_s + 'shoulder', _s + 'upperarm'),
                    (_s + 'upperarm', _s + 'forearm'), (_s + 'forearm', _s + 'hand'),
                    ('pelvis', _s + 'thigh'), (_s + 'thigh', _s + 'shank'),
                    (_s + 'shank', _s + 'foot')]


def _path(a, b):
    """Segments on the body's path from a to b (both included)."""
    adj = {}
    for x, y in BODY_JOINTS:
        adj.setdefault(x, []).append(y)
        adj.setdefault(y, []).append(x)
    prev, todo = {a: None}, [a]
    while todo:
        x = todo.pop(0)
        for y in adj.get(x, []):
            if y not in prev:
                prev[y] = x
                todo.append(y)
    out, x = [], b
    while x is not None:
        out.append(x)
        x = prev.get(x)
    return out[::-1]


def judge_joints(d, truth_of):
    """The tree's joints against the body: a joint between two segments is
    between neighbours when some true segment of one and some of the other are
    the same or joined in the body through segments no posed segment
    represents (a shoulder of one marker left out makes thorax - upper arm
    neighbours). Returns (joints, unflagged, unflagged non-neighbour joints,
    body joints found by an unflagged joint, their names)."""
    segs = {g['name']: {truth_of(m) for m in g['markers']} - {None} for g in d['segments']}
    major = {}
    for g in d['segments']:
        c = Counter(t for t in (truth_of(m) for m in g['markers']) if t is not None)
        major[g['name']] = {t for t, n in c.items() if n == max(c.values())} if c else set()
    represented = set().union(*segs.values()) if segs else set()

    def neighbours(a, b):
        for x in segs[a]:
            for y in segs[b]:
                if x == y:
                    return True
                inner = _path(x, y)[1:-1]
                if not any(z in represented for z in inner):
                    return True
        return False
    bad, found, unflagged = [], set(), 0
    for j in d['joints']:
        if 'untrusted' in j['flags']:
            continue
        unflagged += 1
        if not neighbours(j['parent'], j['child']):
            bad.append((j['parent'], j['child']))
        for x, y in BODY_JOINTS:
            if (x in major[j['parent']] and y in major[j['child']]) or \
               (y in major[j['parent']] and x in major[j['child']]):
                found.add((x, y))
    return len(d['joints']), unflagged, bad, len(found), sorted('%s-%s' % e for e in found)


def ari(a, b):
    """Adjusted Rand index of two labelings of the same items."""
    n = len(a)
    if n < 2:
        return 1.0

    def c2(x):
        return x * (x - 1) / 2.0
    s = sum(c2(v) for v in Counter(zip(a, b)).values())
    sa = sum(c2(v) for v in Counter(a).values())
    sb = sum(c2(v) for v in Counter(b).values())
    exp = sa * sb / c2(n)
    mx = (sa + sb) / 2.0
    return 1.0 if mx == exp else (s - exp) / (mx - exp)


def evaluate(groups, truth_of):
    """groups: list of marker-label lists. truth_of(label) -> segment or None.
    Returns (ari, exact segments, true segments, markers scored)."""
    found, true = [], []
    for gi, g in enumerate(groups):
        for m in g:
            t = truth_of(m)
            if t is not None:
                found.append(gi)
                true.append(t)
    members = {}
    for f, t in zip(found, true):
        members.setdefault(t, set()).add(f)
    sizes = Counter(true)
    exact = set()
    for t, gs in members.items():
        if len(gs) == 1:
            g = next(iter(gs))
            if sum(1 for f in found if f == g) == sizes[t]:
                exact.add(t)
    return ari(found, true), exact, sorted(sizes), len(found)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('json')
    ap.add_argument('--truth', required=True)
    ap.add_argument('--min', type=float, default=None)
    ap.add_argument('--exact', default='')
    ap.add_argument('--quiet', action='store_true')
    ap.add_argument('--joints', action='store_true',
                    help='also judge the tree (--truth names): no unflagged joint between '
                         'segments that are not neighbours')
    ap.add_argument('--min-joints', type=int, default=None,
                    help='at least this many body joints found by an unflagged joint')
    a = ap.parse_args()
    d = json.load(open(a.json))
    groups = [g['markers'] for g in d['grouping']['groups']]
    if a.truth == 'names':
        def truth_of(label):
            return SEGMENT_OF.get(label.split(':')[-1])
    elif a.truth.startswith('sequential:'):
        sizes = [int(x) for x in a.truth.split(':', 1)[1].split(',')]
        order = [m for g in groups for m in g]
        order.sort()
        seq = {}
        k = 0
        for si, n in enumerate(sizes):
            for _ in range(n):
                seq[order[k]] = 'seg%d' % (si + 1)
                k += 1

        def truth_of(label):
            return seq.get(label)
    elif a.truth.startswith('file:'):
        table = {}
        for line in open(a.truth.split(':', 1)[1]):
            line = line.strip()
            if line and not line.startswith('#'):
                lab, seg = line.split('\t')
                table[lab] = seg

        def truth_of(label):
            return table.get(label.split(':')[-1])
    else:
        sys.exit('unknown --truth ' + a.truth)
    r, exact, segs, nm = evaluate(groups, truth_of)
    want = [s for s in a.exact.split(',') if s]
    missing = [s for s in want if s not in exact]
    print('ari %.3f groups %d true_segments %d exact %d markers %d exact_segments %s'
          % (r, len(groups), len(segs), len(exact), nm, ','.join(sorted(exact))))
    if not a.quiet:
        for g in groups:
            print('  group ' + ' '.join('%s(%s)' % (m.split(':')[-1], truth_of(m)) for m in g))
    ok = True
    if a.joints:
        nj, nu, bad, nfound, names = judge_joints(d, truth_of)
        print('joints %d unflagged %d unflagged_non_neighbours %d body_joints_found %d of %d %s'
              % (nj, nu, len(bad), nfound, len(BODY_JOINTS), ','.join(names)))
        for p, c in bad:
            print('FAIL: joint %s - %s joins segments that are not neighbours, without untrusted'
                  % (p, c))
            ok = False
        if a.min_joints is not None and nfound < a.min_joints:
            print('FAIL: %d body joints found by an unflagged joint, fewer than %d'
                  % (nfound, a.min_joints))
            ok = False
    if a.min is not None and r < a.min:
        print('FAIL: adjusted Rand index %.3f below %.3f' % (r, a.min))
        ok = False
    if missing:
        print('FAIL: not found exactly: ' + ','.join(missing))
        ok = False
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
