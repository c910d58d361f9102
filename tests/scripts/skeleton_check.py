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


def _csv(path):
    with open(path) as f:
        head = f.readline().strip().split(',')
        rows = [ln.strip().split(',') for ln in f if ln.strip()]
    return head, rows


def cmd_centres(args):
    """centres SKEL.json CENTRES.csv START JOINT.json NAME MAX_SIGMAS: the
    joint's centre from all trials together against `sfit joint --json` on
    its own functional trial, in the lab at that joint's reference frame
    (`sfit joint` gives its template frame the lab axes there), frame 0 of
    the trial being frame START of the session. A ball: the distance between
    the centres. A hinge: the distance, in the plane through this centre
    across this axis, to the point where `sfit joint`'s axis crosses it (the
    place along an axis is a convention), and the angle between the axes.
    The distance is compared with this joint's 1-sigma radius."""
    js = json.load(open(args[0]))
    head, rows = _csv(args[1])
    start = int(args[2])
    jo = json.load(open(args[3]))
    name, maxs = args[4], float(args[5])
    j = [x for x in js['joints'] if x['name'] == name][0]
    ci = head.index(name + '_X')
    row = rows[start + jo['reference_frame']]
    if row[ci] == '':
        fail('%s: no pose of the parent at the reference frame' % name)
    c = [float(row[ci + k]) for k in range(3)]
    b = jo['center_lab_reference']
    extra = ''
    if j['type'] == 'hinge':
        a = [float(row[ci + 3 + k]) for k in range(3)]
        ax = jo['axis']
        den = sum(ax[k] * a[k] for k in range(3))
        t = sum((c[k] - b[k]) * a[k] for k in range(3)) / den
        b = [b[k] + t * ax[k] for k in range(3)]
        ang = math.degrees(math.acos(min(1.0, abs(den))))
        extra = ', axes %.1f deg apart' % ang
    d = math.dist(c, b)
    print('%s (%s): %.2f %s from `sfit joint` (%s, %s) on its trial%s; 1 sigma %.2f: %.2f sigma'
          % (name, j['type'], d, js['units'], jo.get('method'), jo['mode'], extra, j['sigma'],
             d / j['sigma']))
    if not d <= maxs * j['sigma']:
        fail('%s: %.2f %s from sfit joint, more than %g sigma (%.2f)'
             % (name, d, js['units'], maxs, j['sigma']))


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
    near = sum(1 for (x, y) in diff if min(_seg_dist(x, y, b) for b in bones) <= 40.0)
    frac = near / len(diff)
    if frac < 0.9:
        fail('only %.2f of the changed pixels lie within 40 px of the skeleton' % frac)
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
    {'unlabeled': cmd_unlabeled, 'synth': cmd_synth, 'centres': cmd_centres, 'session': cmd_session, 'tree': cmd_tree, 'norigid': cmd_norigid,
     'bvh': cmd_bvh, 'screens': cmd_screens}[sys.argv[1]](sys.argv[2:])
