#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Label swaps within a cluster (tools/lab/swaps.c) in `sfit joint` and
# `sfit skeleton`, against references computed here (numpy, the C3D
# reader/writer of tests/scripts/mocap_ref.py), never by the code under test:
#  1. biobuddy's hip trial (issue 28, must-show 3): the RLFE/RMFE exchange
#     is reported (frames and count), and the centre equals that of a copy
#     of the trial whose labels this test put back (within 0.1 mm);
#  2. synthetic swaps (random frames, pairs and rotations of three labels,
#     noise, missing markers, ghost markers): detection counts and frames
#     exact, ghosts rejected, the centre that of the clean data;
#  3. no false positive on the clean recordings (knee trial, the hip trial
#     before the swap, tests/data/mocap);
#  4. a near-symmetric cluster: the swap is reported undecidable and left;
#  5. --no-repair-swaps: reported, nothing changed; skeleton reports too.
# Usage: test_cli_swaps.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
cli_setup test_cli_swaps "$build" "$src"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "python3-numpy not installed"

hip="$data/c3d/biobuddy_right_hip.c3d"
knee="$data/c3d/biobuddy_right_knee.c3d"
pelvis=RASIS,LASIS,LPSIS,RPSIS
thigh=RTHI1,RTHI2,RTHI3,RLFE,RMFE
shank=RLEG1,RLEG2,RLEG3,RATT,RLM,RSPH

# 1. Must-show 3: the command verbatim (all frames).
"$sfit" joint "$hip" --parent $pelvis --child $thigh --json > "$tmp/hip.json"
"$sfit" joint "$hip" --parent $pelvis --child $thigh --json --no-repair-swaps > "$tmp/hip_raw.json"
"$sfit" joint "$hip" --parent $pelvis --child $thigh > "$tmp/hip.txt"
# The test's own put-back: a frame is swapped when the distances of the
# points labelled RLFE and RMFE to RTHI1-3 match the other knee marker's
# distances at the start of the trial (medians of frames 0-49) better
# than their own; those frames get RLFE and RMFE exchanged in a copy.
py '
import sys, numpy as np, mocap_ref as m
c = m.read_c3d(sys.argv[1]); L = c["labels"]; nf = len(c["frames"])
X = lambda n: np.array([c["frames"][f][L.index(n)] for f in range(nf)], float)
thi = [X(n) for n in ("RTHI1", "RTHI2", "RTHI3")]
lfe, mfe = X("RLFE"), X("RMFE")
dl = np.stack([np.linalg.norm(t - lfe, axis=1) for t in thi], 1)
dm = np.stack([np.linalg.norm(t - mfe, axis=1) for t in thi], 1)
al, am = np.median(dl[:50], 0), np.median(dm[:50], 0)
given = ((dl - al) ** 2 + (dm - am) ** 2).sum(1)
exch = ((dl - am) ** 2 + (dm - al) ** 2).sum(1)
sw = exch < given
np.savetxt(sys.argv[3], np.nonzero(sw)[0], fmt="%d")
names = ["RASIS", "LASIS", "LPSIS", "RPSIS", "RTHI1", "RTHI2", "RTHI3", "RLFE", "RMFE"]
frames = []
for f in range(nf):
    row = [c["frames"][f][L.index(n)] for n in names]
    if sw[f]:
        row[7], row[8] = row[8], row[7]
    frames.append(row)
m.write_c3d(sys.argv[2], names, frames)
' "$hip" "$tmp/hip_fixed.c3d" "$tmp/swapped_frames.txt"
"$sfit" joint "$tmp/hip_fixed.c3d" --parent $pelvis --child $thigh --json --no-repair-swaps \
  > "$tmp/fixed_raw.json"
"$sfit" joint "$tmp/hip_fixed.c3d" --parent $pelvis --child $thigh --json > "$tmp/fixed.json"
py '
import json, sys, math, numpy as np
o, raw, ref, fixed = (json.load(open(p)) for p in sys.argv[1:5])
want = [int(v) for v in np.loadtxt(sys.argv[5], dtype=int, ndmin=1)]
assert o["status"] == "ok" and o["frames_used"] == 1690, o
ls = o["label_swaps"]
assert ls["repair"] is True and ls["parent"]["checked"] and ls["child"]["checked"], ls
assert ls["parent"]["swapped_frames"] == 0 and ls["parent"]["swaps"] == [], ls["parent"]
ch = ls["child"]
assert len(ch["swaps"]) == 1, ch["swaps"]
s = ch["swaps"][0]
assert s["labels"] == ["RLFE", "RMFE"] and s["true"] == ["RMFE", "RLFE"], s
assert s["action"] == "repaired" and ch["rejected"]["count"] == 0, ch
got = [f for a, b in s["runs"] for f in range(a, b + 1)]
assert s["count"] == len(want) == len(got) == ch["swapped_frames"], (s, len(want))
assert got == want, (s["runs"], want[:3], want[-3:])
d = math.dist(o["center"], ref["center"])
assert d <= 0.1, (o["center"], ref["center"], d)       # must-show 3
draw = math.dist(raw["center"], ref["center"])
assert draw >= 10.0, draw                                # the swap matters (15 mm)
assert raw["label_swaps"]["repair"] is False
assert raw["label_swaps"]["child"]["swaps"][0]["action"] == "detected"
assert raw["label_swaps"]["child"]["swaps"][0]["count"] == len(want)
# the copy the test repaired has nothing left to repair
assert fixed["label_swaps"]["child"]["swapped_frames"] == 0, fixed["label_swaps"]
assert fixed["label_swaps"]["child"]["rejected"]["count"] == 0
assert math.dist(fixed["center"], ref["center"]) <= 1e-4
print("hip: RLFE/RMFE exchanged in %d frames (%s), centre %s vs the put-back copy %s: %.4f mm;"
      " raw %.2f mm away" % (s["count"], s["runs"], np.round(o["center"], 3),
                              np.round(ref["center"], 3), d, draw))
' "$tmp/hip.json" "$tmp/hip_raw.json" "$tmp/fixed_raw.json" "$tmp/fixed.json" \
  "$tmp/swapped_frames.txt" || fail "biobuddy hip swap (must-show 3)"
grep -q "RLFE<->RMFE in 958 frames (732-1689): repaired" "$tmp/hip.txt" \
  || fail "text report: $(grep -A3 'label swaps' "$tmp/hip.txt")"

# 2. Synthetic swaps, 12 seeds: a 4-marker parent and a 5-marker child
#    rotating about a ball joint, noise 0.3 mm, 3 % missing markers;
#    exchanges of two labels in random parent and child frames (isolated
#    and in runs), rotations of three child labels, ghost child markers
#    (one marker 150 mm off). Geometries whose relabellings change the
#    distances by less than 40 mm are drawn again (all decidable).
for seed in 1 2 3 4 5 6 7 8 9 10 11 12; do
  py '
import sys, itertools, json, numpy as np, mocap_ref as m
seed = int(sys.argv[1]); out = sys.argv[2]
rng = np.random.default_rng(seed)
def rot(a, t):
    a = a / np.linalg.norm(a); k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * k @ k
def relabels(n):
    for i, j in itertools.combinations(range(n), 2):
        p = list(range(n)); p[i], p[j] = j, i; yield p
    for i, j, k in itertools.combinations(range(n), 3):
        for a, b, c in ((j, k, i), (k, i, j)):
            p = list(range(n)); p[i], p[j], p[k] = a, b, c; yield p
def cluster(n, spread):
    while True:
        x = rng.uniform(-spread, spread, (n, 3))
        d = np.linalg.norm(x[:, None] - x[None], axis=2)
        iu = np.triu_indices(n, 1)
        if min(np.linalg.norm(d[np.ix_(p, p)][iu] - d[iu]) for p in relabels(n)) >= 40.0:
            return x
F, sigma = 600, 0.3
ptpl = cluster(4, 120.0)
ctpl = cluster(5, 110.0) + np.array([0.0, -300.0, 0.0])   # child, about the joint at 0
centre = np.array([60.0, -80.0, 40.0])                       # joint centre, parent frame
P = np.empty((F, 4, 3)); C = np.empty((F, 5, 3))
for f in range(F):
    r = rot(rng.normal(size=3), rng.uniform(0, 0.4)); t = np.array([800.0, 600.0, 900.0]) + rng.normal(0, 40, 3)
    q = rot(rng.normal(size=3), rng.uniform(0, 0.8))
    P[f] = ptpl @ r.T + t
    C[f] = (centre + ctpl @ q.T) @ r.T + t
P += rng.normal(0, sigma, P.shape); C += rng.normal(0, sigma, C.shape)
clean_P, clean_C = P.copy(), C.copy()
inj = {"parent": {}, "child": {}}
run0 = int(rng.integers(100, 400))              # a run of one exchange in the child
ij = rng.choice(5, 2, replace=False)
for f in range(run0, run0 + 25):
    inj["child"][f] = {int(ij[0]): int(ij[1]), int(ij[1]): int(ij[0])}
# the other frames at random, away from the anchor (frames 0-49) and the run
used = iter(f for f in rng.permutation(np.arange(60, F)) if not run0 <= f < run0 + 25)
def take(k): return [int(next(used)) for _ in range(k)]
for f in take(int(rng.integers(10, 30))):       # isolated exchanges, parent
    i, j = (int(v) for v in rng.choice(4, 2, replace=False))
    inj["parent"][f] = {i: j, j: i}
for f in take(int(rng.integers(10, 30))):       # isolated exchanges, child
    i, j = (int(v) for v in rng.choice(5, 2, replace=False))
    inj["child"][f] = {i: j, j: i}
for f in take(int(rng.integers(3, 10))):        # rotations of three child labels
    i, j, k = (int(v) for v in rng.choice(5, 3, replace=False))
    inj["child"][f] = {i: j, j: k, k: i}        # the point labelled i is marker j
ghosts = take(5)
for seg, X in (("parent", P), ("child", C)):
    for f, mp in inj[seg].items():
        row = X[f].copy()
        for given, true in mp.items():
            X[f, given] = row[true]
for f in ghosts:
    k = int(rng.integers(5)); v = rng.normal(size=3)
    C[f, k] += 150.0 * v / np.linalg.norm(v)
swapped = set(inj["parent"]) | set(inj["child"]) | set(ghosts)
miss = (rng.uniform(size=(F, 9)) < 0.03)
miss[sorted(swapped)] = False                   # swaps and ghosts: every marker seen
names = ["P1", "P2", "P3", "P4", "C1", "C2", "C3", "C4", "C5"]
def write(path, A, B, ghost_missing):
    rows = []
    for f in range(F):
        row = [tuple(v) for v in A[f]] + [tuple(v) for v in B[f]]
        for k in range(9):
            if miss[f, k] or (ghost_missing and f in ghosts and k >= 4):
                row[k] = None
        rows.append(row)
    m.write_c3d(path, names, rows)
write(out + "/syn.c3d", P, C, False)
write(out + "/syn_clean.c3d", clean_P, clean_C, True)
json.dump({"inj": {s: {str(f): {str(a): b for a, b in mp.items()} for f, mp in d.items()}
                   for s, d in inj.items()}, "ghosts": ghosts}, open(out + "/syn.json", "w"))
' "$seed" "$tmp"
  "$sfit" joint "$tmp/syn.c3d" --parent P1,P2,P3,P4 --child C1,C2,C3,C4,C5 --json > "$tmp/s.json"
  "$sfit" joint "$tmp/syn_clean.c3d" --parent P1,P2,P3,P4 --child C1,C2,C3,C4,C5 --json \
    --no-repair-swaps > "$tmp/s_clean.json"
  py '
import json, sys, math
o, clean, truth = (json.load(open(p)) for p in sys.argv[1:4])
names = {"parent": ["P1", "P2", "P3", "P4"], "child": ["C1", "C2", "C3", "C4", "C5"]}
assert o["status"] == "ok", o
for seg in ("parent", "child"):
    cl = o["label_swaps"][seg]
    want = {int(f): {names[seg][int(a)]: names[seg][b] for a, b in mp.items()}
            for f, mp in truth["inj"][seg].items()}
    got = {}
    for s in cl["swaps"]:
        assert s["nruns"] == len(s["runs"]) and s["action"] == "repaired", s
        mp = dict(zip(s["labels"], s["true"]))
        n = 0
        for a, b in s["runs"]:
            for f in range(a, b + 1):
                assert f not in got, f
                got[f] = mp; n += 1
        assert n == s["count"], s
    assert got == want, (seg, len(got), len(want),
                         [(f, got.get(f), want.get(f)) for f in sorted(set(got) | set(want))
                          if got.get(f) != want.get(f)][:5])
    assert cl["swapped_frames"] == len(want), (cl["swapped_frames"], len(want))
    assert cl["undecidable"] == [], cl["undecidable"]
    rej = cl["rejected"]
    assert rej["ambiguous"]["count"] == 0, rej
    gh = sorted(truth["ghosts"]) if seg == "child" else []
    runs = [f for a, b in rej["no_fit"]["runs"] for f in range(a, b + 1)]
    assert rej["no_fit"]["count"] == len(gh) and runs == gh, (seg, rej, gh)
d = math.dist(o["center"], clean["center"])
assert d <= 1e-3, (o["center"], clean["center"], d)
print("seed %s: parent %d, child %d frames relabelled exactly, %d ghosts rejected; centre %.2g mm"
      " from the clean data" % (sys.argv[4], o["label_swaps"]["parent"]["swapped_frames"],
      o["label_swaps"]["child"]["swapped_frames"], len(truth["ghosts"]), d))
' "$tmp/s.json" "$tmp/s_clean.json" "$tmp/syn.json" "$seed" || fail "synthetic swaps, seed $seed"
done

# 3. No false positive on clean data: nothing relabelled, nothing rejected,
#    no relabelling undecidable (clean_check JSON WHAT [N]: N undecidable
#    child relabellings expected instead).
clean_check() {
  py '
import json, sys
o = json.load(open(sys.argv[1]))
joints = o["joints"] if "joints" in o else [o]
for j in joints:
    for seg in ("parent", "child"):
        cl = j["label_swaps"][seg]
        assert cl["checked"], (sys.argv[2], seg, cl)
        assert cl["swapped_frames"] == 0 and cl["swaps"] == [], (sys.argv[2], seg, cl)
        assert cl["rejected"]["count"] == 0, (sys.argv[2], seg, cl["rejected"])
        und = int(sys.argv[3]) if seg == "child" else 0
        assert len(cl["undecidable"]) == und, (sys.argv[2], seg, cl["undecidable"])
' "$1" "$2" "${3:-0}" || fail "false positive: $2"
}
"$sfit" joint "$knee" --parent $thigh --child $shank --json > "$tmp/c.json"
clean_check "$tmp/c.json" "knee trial, thigh/shank"
"$sfit" joint "$knee" --parent $pelvis --child $thigh --json > "$tmp/c.json"
clean_check "$tmp/c.json" "knee trial, pelvis/thigh"
"$sfit" joint "$hip" --parent $pelvis --child $thigh --frames 0:725 --json > "$tmp/c.json"
clean_check "$tmp/c.json" "hip trial before the swap"
"$sfit" joint "$hip" --parent $thigh --child $shank --frames 0:725 --json > "$tmp/c.json"
clean_check "$tmp/c.json" "hip trial, thigh/shank before the swap"
"$sfit" skeleton "$src/tests/data/models/knee_joints.txt" "$knee" --json > "$tmp/c.json"
clean_check "$tmp/c.json" "knee model"
# tests/data/mocap: each folder's markers (in their parent's frame, so
# their distances are the segment's) as the child of a still 3-marker
# parent, in one wide table.
for d in hip_right knee_right elbow_right; do
  py '
import sys, os, numpy as np
d = sys.argv[1]; names = sorted(f[:-4] for f in os.listdir(d) if f.endswith(".csv"))
cols = [np.loadtxt(os.path.join(d, n + ".csv"), delimiter=",", skiprows=1) for n in names]
F = min(len(c) for c in cols)
still = [("Q1", (0, 0, 0.1)), ("Q2", (0.2, 0, 0)), ("Q3", (0, 0.35, 0))]  # scalene
with open(sys.argv[2], "w") as f:
    f.write(",".join("%s_%s" % (n, a) for n in [q for q, _ in still] + names for a in "XYZ") + "\n")
    for i in range(F):
        f.write(",".join(["%r" % v for _, p in still for v in p]
                         + ["%r" % v for c in cols for v in c[i]]) + "\n")
print(",".join(names))
' "$data/mocap/$d" "$tmp/wide.csv" > "$tmp/names.txt"
  "$sfit" joint "$tmp/wide.csv" --parent Q1,Q2,Q3 --child "$(cat "$tmp/names.txt")" --json \
    > "$tmp/c.json"
  # the elbow's forearm markers are a near-equilateral triangle (sides 42.9,
  # 43.2, 43.2 mm): none of its 5 relabellings can be decided (the most
  # distinct moves the distances by 0.42 mm, 2 z s = 1.6 mm)
  clean_check "$tmp/c.json" "tests/data/mocap/$d" "$([ $d = elbow_right ] && echo 5 || echo 0)"
done

# 4. A near-symmetric child: C1 and C2 mirror images across the plane of
#    C3, C4, C5 (one 0.2 mm off): exchanging them moves no distance by more
#    than the noise. Frames 200-259 have them exchanged: reported
#    undecidable, not repaired (the centre is the raw one), nothing else.
py '
import sys, numpy as np, mocap_ref as m
rng = np.random.default_rng(28)
def rot(a, t):
    a = a / np.linalg.norm(a); k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * k @ k
ptpl = np.array([[100.0, 0, 0], [-80, 60, 0], [0, -90, 40], [20, 30, 110]])
ctpl = np.array([[60.0, -300, 50], [60.2, -300, -50], [0, -250, 0], [-70, -380, 0], [30, -450, 0]])
F = 400; rows = []
for f in range(F):
    r = rot(rng.normal(size=3), rng.uniform(0, 0.3)); t = np.array([500.0, 700, 900]) + rng.normal(0, 30, 3)
    q = rot(rng.normal(size=3), rng.uniform(0, 0.8))
    P = ptpl @ r.T + t + rng.normal(0, 0.3, (4, 3))
    C = (np.array([40.0, -60, 30]) + ctpl @ q.T) @ r.T + t + rng.normal(0, 0.3, (5, 3))
    if 200 <= f < 260:
        C[[0, 1]] = C[[1, 0]]
    rows.append([tuple(v) for v in P] + [tuple(v) for v in C])
m.write_c3d(sys.argv[1], ["P1", "P2", "P3", "P4", "C1", "C2", "C3", "C4", "C5"], rows)
' "$tmp/sym.c3d"
"$sfit" joint "$tmp/sym.c3d" --parent P1,P2,P3,P4 --child C1,C2,C3,C4,C5 --json > "$tmp/sym.json"
"$sfit" joint "$tmp/sym.c3d" --parent P1,P2,P3,P4 --child C1,C2,C3,C4,C5 --json --no-repair-swaps \
  > "$tmp/sym_raw.json"
"$sfit" joint "$tmp/sym.c3d" --parent P1,P2,P3,P4 --child C1,C2,C3,C4,C5 > "$tmp/sym.txt"
py '
import json, sys
o, raw = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
ch = o["label_swaps"]["child"]
und = [(u["labels"], u["true"]) for u in ch["undecidable"]]
assert (["C1", "C2"], ["C2", "C1"]) in und, ch["undecidable"]
assert all(u["pattern_change"] < ch["decidable_above"] for u in ch["undecidable"]), ch
assert ch["swapped_frames"] == 0 and ch["swaps"] == [] and ch["rejected"]["count"] == 0, ch
assert o["center"] == raw["center"], (o["center"], raw["center"])
' "$tmp/sym.json" "$tmp/sym_raw.json" || fail "near-symmetric cluster"
grep -q "undecidable: C1<->C2 changes the distances by" "$tmp/sym.txt" \
  || fail "undecidable not in the text: $(cat "$tmp/sym.txt")"

# 5. Skeleton: the same report per joint; --no-repair-swaps there too.
"$sfit" skeleton "$src/tests/data/models/hip_joints.txt" "$hip" --json > "$tmp/sk.json"
"$sfit" skeleton "$src/tests/data/models/hip_joints.txt" "$hip" --json --no-repair-swaps > "$tmp/sk_raw.json"
"$sfit" skeleton "$src/tests/data/models/hip_joints.txt" "$hip" > "$tmp/sk.txt"
py '
import json, sys, math
sk, raw, j, jr = (json.load(open(p)) for p in sys.argv[1:5])
h, hr = sk["joints"][0], raw["joints"][0]
assert h["label_swaps"] == j["label_swaps"], (h["label_swaps"], j["label_swaps"])
assert hr["label_swaps"]["child"]["swaps"][0]["action"] == "detected"
assert math.dist(h["center"], j["center"]) <= 1e-4 and math.dist(hr["center"], jr["center"]) <= 1e-4
' "$tmp/sk.json" "$tmp/sk_raw.json" "$tmp/hip.json" "$tmp/hip_raw.json" || fail "skeleton"
grep -q "RLFE<->RMFE in 958 frames (732-1689): repaired" "$tmp/sk.txt" || fail "skeleton text"
"$sfit" joint --help | grep -q -- "--no-repair-swaps" || fail "joint --help"
"$sfit" skeleton --help | grep -q -- "--no-repair-swaps" || fail "skeleton --help"
echo "$name: all checks passed"
