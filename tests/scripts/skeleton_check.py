# SPDX-License-Identifier: MIT
"""Checks of `sfit skeleton FILE...` for tests/scripts/test_skeleton.sh.
Each sub-command reads the outputs of a run and exits non-zero with a
message when a claim does not hold; figures are printed."""
import json
import math
import sys

import bvh_ref
import png_ref


def fail(msg):
    print('FAIL: ' + msg, file=sys.stderr)
    sys.exit(1)


def tree_edges(js):
    return sorted((j['parent'], j['child']) for j in js['joints'])


def groups(js):
    return [g['markers'] for g in js['grouping']['groups']]


def chain(js):
    """The tree as a path root -> ... -> leaf, or None if it is not a chain."""
    kids = {}
    for j in js['joints']:
        kids.setdefault(j['parent'], []).append(j['child'])
    path = [js['root']]
    while path[-1] in kids:
        if len(kids[path[-1]]) != 1:
            return None
        path.append(kids[path[-1]][0])
    return path if len(path) == len(js['segments']) else None


def cmd_unlabeled(args):
    """unlabeled JSON EXPECTED_GROUPS: groups listed, a chain of two joints."""
    js = json.load(open(args[0]))
    want = json.loads(args[1])
    if js['segments_from'] != 'data':
        fail('segments not found from the data')
    got = groups(js)
    if got != want:
        fail('groups %s, expected %s' % (got, want))
    if len(js['joints']) != 2:
        fail('%d joints, expected a chain of two' % len(js['joints']))
    path = chain(js)
    if path is None:
        fail('the tree is not a chain: %s' % tree_edges(js))
    for j in js['joints']:
        if j['type'] not in ('ball', 'hinge'):
            fail('joint %s of type %s' % (j['name'], j['type']))
    print('groups %s (threshold %.3g, rigid level %.3g); chain %s; joint costs %s' % (
        got, js['grouping']['threshold'], js['grouping']['noise'], ' - '.join(path),
        ', '.join('%.3g' % j['cost'] for j in js['joints'])))


def cmd_session(args):
    """session JSON: the lower-limb tree, the knee a hinge, no-motion pairs never joints."""
    js = json.load(open(args[0]))
    want = sorted([('pelvis', 'r_thigh'), ('r_thigh', 'r_shank'), ('r_shank', 'r_foot'),
                   ('pelvis', 'trunk')])
    if tree_edges(js) != want:
        fail('tree %s, expected %s' % (tree_edges(js), want))
    if js['root'] != 'pelvis':
        fail('root %s' % js['root'])
    types = {j['name']: j['type'] for j in js['joints']}
    if types.get('r_knee') != 'hinge':
        fail('knee found to be %s' % types.get('r_knee'))
    for j in js['joints']:
        if 'forced' in j['flags']:
            fail('joint %s forced: the test model says auto' % j['name'])
    if js['map_joints_not_in_tree']:
        fail('map joints not in the tree: %s' % js['map_joints_not_in_tree'])
    print('tree %s; types %s' % (' '.join('%s-%s' % e for e in tree_edges(js)), types))


def cmd_tree(args):
    """tree JSON: the lower-limb tree only (the joints' types printed)."""
    js = json.load(open(args[0]))
    want = sorted([('pelvis', 'r_thigh'), ('r_thigh', 'r_shank'), ('r_shank', 'r_foot'),
                   ('pelvis', 'trunk')])
    if tree_edges(js) != want:
        fail('tree %s, expected %s' % (tree_edges(js), want))
    print('tree %s; types %s' % (' '.join('%s-%s' % e for e in tree_edges(js)),
                                 {j['name']: (j['type'], j['flags']) for j in js['joints']}))


def cmd_norigid(args):
    """norigid JSON: a pair that never moved is no joint (type none, no edge)."""
    js = json.load(open(args[0]))
    pairs = {(p['a'], p['b']): p for p in js['pairs']}
    p = pairs.get(('a', 'b')) or pairs.get(('b', 'a'))
    if p is None or p['type'] != 'none' or 'no_motion' not in p['flags']:
        fail('the rigid pair a-b: %s' % p)
    for j in js['joints']:
        if {j['parent'], j['child']} == {'a', 'b'}:
            fail('a-b taken as a joint')
    print('rigid pair a-b: type none, spread %s deg' % p['rotation_spread_deg'])


def cmd_bvh(args):
    """bvh OUT.bvh OUT.trc JSON: structure, and FK = the TRC's joint centres."""
    nodes, frames, ft = bvh_ref.read_bvh(args[0])
    names, units, rows = bvh_ref.read_trc(args[1])
    js = json.load(open(args[2]))
    root = nodes[0]
    if root.kind != 'ROOT' or root.offset != [0.0, 0.0, 0.0]:
        fail('root %s offset %s' % (root.kind, root.offset))
    if root.channels != ['Xposition', 'Yposition', 'Zposition', 'Zrotation', 'Xrotation',
                         'Yrotation']:
        fail('root channels %s' % root.channels)
    for n in nodes[1:]:
        if n.kind == 'JOINT' and (len(n.channels) != 3
                                  or not all(c.endswith('rotation') for c in n.channels)):
            fail('joint %s channels %s' % (n.name, n.channels))
        if n.kind == 'End' and n.channels:
            fail('end site with channels')
        if n.kind == 'JOINT' and not n.children:
            fail('joint %s has neither child nor End Site' % n.name)
    if len(frames) != len(rows) or len(frames) != js['frames']:
        fail('%d BVH frames, %d TRC rows, %d frames' % (len(frames), len(rows), js['frames']))
    if units != js['units']:
        fail('TRC units %s' % units)
    # BVH node (segment) -> TRC column (root: segment name; else its joint's name)
    col = {js['root']: js['root']}
    for j in js['joints']:
        col[j['child']] = j['name']
    bvh_joints = [n.name for n in nodes if n.kind != 'End']
    if sorted(bvh_joints) != sorted(col):
        fail('BVH joints %s, segments in the tree %s' % (bvh_joints, sorted(col)))
    worst = 0.0
    where = None
    for f, vals in enumerate(frames):
        pos = bvh_ref.forward(nodes, vals)
        for seg, name in col.items():
            d = math.dist(pos[seg], rows[f][name])
            if d > worst:
                worst, where = d, (f, seg)
    if not worst <= 0.1:
        fail('BVH forward kinematics off the TRC joint centres by %.4g %s (frame %d, %s)'
             % (worst, units, where[0], where[1]))
    print('BVH: %d nodes, %d frames, frame time %.6g s; forward kinematics vs the TRC: '
          'largest difference %.2e %s over every frame and joint' % (
              len(nodes), len(frames), ft, worst, units))


def cmd_bvhdist(args):
    """bvhdist OUT.bvh CENTRES.csv JSON [LIMIT_P95]: per joint, the distance
    from the BVH's forward kinematics (this file's own reader) to the centre
    its parent carries (the --centres CSV) over the frames where that centre
    is given; its median and 95th percentile (nearest rank) are the JSON's
    bvh_distance within 0.1 (the BVH's written precision); printed. With
    LIMIT_P95, every joint's 95th percentile at most that."""
    import csv
    nodes, frames, _ = bvh_ref.read_bvh(args[0])
    rows = list(csv.reader(open(args[1])))
    head, body = rows[0], rows[1:]
    js = json.load(open(args[2]))
    limit = float(args[3]) if len(args) > 3 else None
    if len(body) != len(frames):
        fail('%d CSV rows, %d BVH frames' % (len(body), len(frames)))
    pos = [bvh_ref.forward(nodes, v) for v in frames]
    for j in js['joints']:
        c = head.index(j['name'] + '_X')
        d = []
        for f, r in enumerate(body):
            if r[c] == '':
                continue
            d.append(math.dist(pos[f][j['child']], [float(r[c + i]) for i in range(3)]))
        d.sort()
        got = j['bvh_distance']
        if not d:
            if got is not None:
                fail('%s: no frame with a centre, JSON %s' % (j['name'], got))
            continue
        n = len(d)
        med = d[n // 2] if n % 2 else 0.5 * (d[n // 2 - 1] + d[n // 2])
        p95 = d[max(1, math.ceil(0.95 * n)) - 1]
        if got is None or got['frames'] != n or abs(got['median'] - med) > 0.1 \
           or abs(got['p95'] - p95) > 0.1:
            fail('%s: BVH to centre median %.4g p95 %.4g over %d frames, JSON %s'
                 % (j['name'], med, p95, n, got))
        print('%-10s %s -> %s: BVH forward kinematics to the centre: median %.2f, 95th '
              'percentile %.2f %s (%d frames)%s' % (j['name'], j['parent'], j['child'], med, p95,
                                                    js['units'], n,
                                                    '' if 'untrusted' not in j['flags'] else
                                                    ' [untrusted]'))
        if limit is not None and p95 > limit:
            fail('%s: 95th percentile %.2f above %.2f' % (j['name'], p95, limit))


def cmd_synth(args):
    """synth JSON TRUTH ABS_TOL K_SIGMA ANGLE_TOL_DEG: the synthetic chain found
    again: groups, chain A - B - C, ball then hinge, centres and axis vs the truth."""
    js = json.load(open(args[0]))
    truth = json.load(open(args[1]))
    tol, ks, atol = float(args[2]), float(args[3]), float(args[4])
    got = sorted(sorted(g) for g in groups(js) if len(g) >= 3)
    if got != sorted(truth['groups']):
        fail('groups %s, expected %s' % (got, truth['groups']))
    path = chain(js)
    if path is None or len(path) != 3:
        fail('not a chain of three segments: %s' % tree_edges(js))
    seg_of = {s['name']: sorted(s['markers']) for s in js['segments']}
    names = [seg_of[p] for p in path]
    if names != truth['groups']:
        fail('chain %s, expected A - B - C' % names)
    j1, j2 = js['joints'] if js['joints'][0]['parent'] == path[0] else js['joints'][::-1]
    if j1['type'] != 'ball' or j2['type'] != 'hinge':
        fail('types %s %s, expected ball hinge' % (j1['type'], j2['type']))
    # in the parents' template frames (the generator makes frame 0 noise-free)
    d1 = math.dist(j1['center_parent'], truth['ab_parent'])
    if not d1 <= max(tol, ks * j1['sigma']):
        fail('ball centre %.4g mm from the truth (sigma %.3g)' % (d1, j1['sigma']))
    ax = j2['axis_parent']
    tv = truth['axis_bc_parent']
    n = math.sqrt(sum(v * v for v in tv))
    cr = [ax[1] * tv[2] - ax[2] * tv[1], ax[2] * tv[0] - ax[0] * tv[2], ax[0] * tv[1] - ax[1] * tv[0]]
    ang = math.degrees(math.asin(min(1.0, math.sqrt(sum(v * v for v in cr)) / n)))
    if not ang <= atol:
        fail('hinge axis %.4g deg off' % ang)
    w = [truth['bc_parent'][i] - j2['center_parent'][i] for i in range(3)]
    cw = [w[1] * ax[2] - w[2] * ax[1], w[2] * ax[0] - w[0] * ax[2], w[0] * ax[1] - w[1] * ax[0]]
    d2 = math.sqrt(sum(v * v for v in cw))  # distance of the true centre to the found axis
    if not d2 <= max(tol, ks * j2['sigma']):
        fail('the true hinge centre is %.4g mm off the found axis (sigma %.3g)' % (d2, j2['sigma']))
    print('synthetic chain: ball centre %.3g mm from the truth (1 sigma %.3g), hinge axis %.3g deg '
          'off, true hinge centre %.3g mm off the axis (1 sigma %.3g)'
          % (d1, j1['sigma'], ang, d2, j2['sigma']))


def _kabsch(src, dst):
    """R, t (double) with dst ~ R src + t, least squares (Kabsch / Horn, SVD)."""
    import numpy as np
    src, dst = np.asarray(src, float), np.asarray(dst, float)
    cs, cd = src.mean(0), dst.mean(0)
    u, _, vt = np.linalg.svd((dst - cd).T @ (src - cs))
    d = np.sign(np.linalg.det(u @ vt))
    r = u @ np.diag([1.0, 1.0, d]) @ vt
    return r, cd - r @ cs


def cmd_calib(args):
    """calib SKEL.json SESSION.json: every joint of `sfit skeleton` (all trials
    together) against `sfit calibrate` (each joint on its own trial): the tree
    edge, the type, and the centre within its uncertainty. Both centres are
    compared in the calibrate parent template frame: the skeleton's parent
    template is put onto calibrate's by a rigid least-squares fit of the two
    templates (same markers; an independent SVD here). A ball: the 3-D
    difference; a hinge: its part across calibrate's axis (the place along an
    axis is a convention), and the angle between the axes. Mahalanobis value
    m = sqrt(d^T C^-1 d) with C = the skeleton's covariance as it reports it
    (the pair module's, inflated for the slow residual) + calibrate's
    (the pair module's on the one trial); passes when m is inside the 95 %
    region (chi-square, 3 or 2 degrees of freedom). Also printed: m with the
    two modules' covariances as they come (no inflation)."""
    import numpy as np
    sk = json.load(open(args[0]))
    ca = json.load(open(args[1]))
    q95 = {3: math.sqrt(7.8147), 2: math.sqrt(5.9915)}
    segs = {g['name']: g for g in sk['segments']}
    skj = {(j['parent'], j['child']): j for j in sk['joints']}
    if len(ca['joints']) != len(sk['joints']):
        fail('%d joints calibrated, %d in the skeleton' % (len(ca['joints']), len(sk['joints'])))
    bad = []
    for c in ca['joints']:
        key = (c['parent'], c['child'])
        if key not in skj:
            fail('%s: %s - %s is not an edge of the tree found (%s)'
                 % (c['name'], key[0], key[1], tree_edges(sk)))
        j = skj[key]
        if j['type'] != c['type']:
            fail('%s: the skeleton says %s, calibrate %s' % (c['name'], j['type'], c['type']))
        g = segs[c['parent']]
        if g['markers'][:len(g['template'])] != c['parent_markers'][:len(g['template'])]:
            fail('%s: parent markers differ' % c['name'])
        n = min(len(g['template']), len(c['template']))
        r, t = _kabsch(g['template'][:n], c['template'][:n])
        fitres = np.sqrt(np.mean(np.sum((np.asarray(g['template'][:n]) @ r.T + t
                                         - np.asarray(c['template'][:n])) ** 2, 1)))
        xs = r @ np.asarray(j['center_parent']) + t
        xc = np.asarray(c['center'], float)
        cs = r @ np.asarray(j['cov_parent']).reshape(3, 3) @ r.T
        cs_raw = r @ np.asarray(j['center_cov']) @ r.T
        cc = np.asarray(c['center_cov'], float)
        d = xs - xc
        extra = ''
        if c['type'] == 'hinge':
            ax = np.asarray(c['axis'], float)
            ax /= np.linalg.norm(ax)
            axs = r @ np.asarray(j['axis_parent'])
            extra = ', axes %.1f deg apart' % math.degrees(math.acos(min(1.0, abs(ax @ axs))))
            e1 = np.cross(ax, [1.0, 0.0, 0.0] if abs(ax[0]) < 0.9 else [0.0, 1.0, 0.0])
            e1 /= np.linalg.norm(e1)
            b = np.vstack([e1, np.cross(ax, e1)])  # the plane across the axis
            d, cs, cs_raw, cc = b @ d, b @ cs @ b.T, b @ cs_raw @ b.T, b @ cc @ b.T
        dof = len(d)
        m = math.sqrt(d @ np.linalg.solve(cs + cc, d))
        m_raw = math.sqrt(d @ np.linalg.solve(cs_raw + cc, d))
        m_sk = math.sqrt(d @ np.linalg.solve(cs, d))
        print('%-8s %s - %s, %s (skeleton: %s, calibrate: %s): %.2f %s %s%s; Mahalanobis %.2f '
              '(skeleton %s + calibrate covariance; 95 %% limit %.2f), %.2f with the skeleton\'s '
              'alone, %.1f with both modules\' uninflated; templates fitted to %.2f %s rms'
              % (c['name'], c['parent'], c['child'], c['type'], ','.join(j['pair_flags']) or 'trusted',
                 ','.join(c['flags']) or 'trusted', float(np.linalg.norm(d)), sk['units'],
                 'across the axis' if dof == 2 else 'apart', extra, m,
                 '(variance inflated x%.3g)' % j['inflation'], q95[dof], m_sk, m_raw, fitres, sk['units']))
        if not m <= q95[dof]:
            bad.append('%s: Mahalanobis %.2f > %.2f' % (c['name'], m, q95[dof]))
    if bad:
        fail('; '.join(bad))


def _state(path):
    text = open(path).read()
    a = text.index('<pre id="state">') + len('<pre id="state">')
    b = text.index('</pre>', a)
    return json.loads(text[a:b].replace('&quot;', '"').replace('&amp;', '&'))


def _seg_dist(px, py, b):
    x1, y1, x2, y2 = b
    dx, dy = x2 - x1, y2 - y1
    L = dx * dx + dy * dy
    t = 0.0 if L == 0 else max(0.0, min(1.0, ((px - x1) * dx + (py - y1) * dy) / L))
    return math.hypot(px - x1 - t * dx, py - y1 - t * dy)


def cmd_screens(args):
    """screens A.png B.png A.dom B.dom: the shots differ, and where the skeleton moved."""
    wa, ha, ra = png_ref.read_png(args[0])
    wb, hb, rb = png_ref.read_png(args[1])
    sa, sb = _state(args[2]), _state(args[3])
    if (wa, ha) != (wb, hb):
        fail('screenshot sizes differ')
    if sa['frame'] == sb['frame']:
        fail('both pages show frame %d' % sa['frame'])
    left, top, cw, ch = sa['canvas']
    left, top = int(round(left)), int(round(top))
    diff = []
    for y in range(top, min(ha, top + ch)):
        for x in range(left, min(wa, left + cw)):
            if max(abs(p - q) for p, q in zip(ra[y][x], rb[y][x])) > 40:
                diff.append((x - left, y - top))
    if len(diff) < 200:
        fail('the two frames differ in %d canvas pixels only' % len(diff))
    bones = sa['bones'] + sb['bones']
    # a joint's label (the page reports its box) moves with the joint
    boxes = [l[1:] for l in sa.get('labels', []) + sb.get('labels', [])]
    def in_box(x, y):
        return any(b[0] - 2 <= x <= b[2] + 2 and b[1] - 2 <= y <= b[3] + 2 for b in boxes)
    near = sum(1 for (x, y) in diff if in_box(x, y) or min(_seg_dist(x, y, b) for b in bones) <= 40.0)
    frac = near / len(diff)
    if frac < 0.9:
        fail('only %.2f of the changed pixels lie within 40 px of the skeleton or in a label' % frac)
    moved = []
    for name, (xa, ya) in sa['nodes'].items():
        xb, yb = sb['nodes'][name]
        if math.hypot(xb - xa, yb - ya) > 20:
            moved.append(name)
            for (x, y) in ((xa, ya), (xb, yb)):
                if not any(abs(dx - x) <= 4 and abs(dy - y) <= 4 for (dx, dy) in diff):
                    fail('joint %s moved but the pixels at (%d, %d) did not change' % (name, x, y))
    if not moved:
        fail('no joint moved by more than 20 px between the frames')
    print('screenshots at frames %d and %d: %d canvas pixels differ, %.3f of them within 40 px '
          'of the skeleton; joints moved (> 20 px) and changed there: %s' % (
              sa['frame'], sb['frame'], len(diff), frac, ', '.join(moved)))


if __name__ == '__main__':
    {'unlabeled': cmd_unlabeled, 'synth': cmd_synth, 'session': cmd_session, 'tree': cmd_tree, 'norigid': cmd_norigid,
     'bvh': cmd_bvh, 'screens': cmd_screens, 'calib': cmd_calib, 'bvhdist': cmd_bvhdist}[sys.argv[1]](sys.argv[2:])
