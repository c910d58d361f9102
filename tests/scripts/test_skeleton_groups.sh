#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `sfit skeleton FILE` without a map on full-body recordings: how well the
# segments found from the data match the true segments, measured by
# tests/scripts/skeleton_ari.py (adjusted Rand index; truth from the marker
# names, which sfit ignores when it groups; docs/skeleton.md).
#  1. skeleton_ari.py itself on a partition computed by hand;
#  2. the two unlabelled arm recordings: every segment exact (index 1);
#  3. the two CMU full-body trials (41 markers, 17 segments) and the
#     unlabelled 44-marker full body (truth labelled by hand,
#     tests/data/c3d/unlabeled/fullbody_44Markers_segments.tsv): the index at
#     least the figure docs/skeleton.md gives (rounded down to 0.01; each at
#     least 0.80, the 44-marker body at least 0.85), both hands exact on
#     85_12, the left foot on 135_02, both hands and both feet on the 44-marker
#     body;
#  4. the tree on the same recordings (skeleton_ari.py --joints): no joint
#     without `untrusted` between two segments that are not neighbours in
#     the body, and at least the body joints docs/skeleton.md gives found
#     by a joint without it (10 of 16 on 85_12 and on the 44-marker body);
#     the 44-marker body's SVG drawn with +Z up (its floor found);
#  5. the BVH's distance to the joint centres the JSON reports, recomputed.
# Usage: test_skeleton_groups.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
. "$(dirname "$0")/common.sh"
cli_setup skeleton_groups "$1" "$2"
ari() { /usr/bin/python3 "$cli_src/tests/scripts/skeleton_ari.py" "$@"; }
D="$data/c3d"

# 1. [0,0,1,1] against [0,0,1,2]: index 4/7 (pairs: 1 agreeing, expected 1/3, mean 3/2).
py 'import skeleton_ari as A; r = A.ari([0, 0, 1, 1], [0, 0, 1, 2]); assert abs(r - 4 / 7) < 1e-12, r
assert A.ari([0, 1, 2], [5, 6, 7]) == 1.0 and abs(A.ari([0, 0, 1, 1], [0, 1, 0, 1]) + 0.5) < 1e-12' \
  || fail "adjusted Rand index of the hand-computed cases"

# 2. arms
"$sfit" skeleton "$D/unlabeled/arm-4-2-3_clean_120fps.c3d" --json > "$tmp/a423.json"
ari "$tmp/a423.json" --truth sequential:4,2,3 --min 1.0 --quiet || fail "arm-4-2-3"
"$sfit" skeleton "$D/unlabeled/arm-4-4-4_clean_30fps.c3d" --json > "$tmp/a444.json"
ari "$tmp/a444.json" --truth sequential:4,4,4 --min 1.0 --quiet || fail "arm-4-4-4"

# 3. CMU full body and the unlabelled 44-marker full body
"$sfit" skeleton "$D/cmu/85_12.c3d" --json --bvh "$tmp/85.bvh" --centres "$tmp/85.csv" > "$tmp/85.json"
ari "$tmp/85.json" --truth names --min 0.85 --exact Lhand,Rhand --joints --min-joints 10 --quiet \
  || fail "CMU 85_12"
"$sfit" skeleton "$D/cmu/135_02.c3d" --json > "$tmp/135.json"
ari "$tmp/135.json" --truth names --min 0.80 --exact Lfoot --joints --min-joints 6 --quiet \
  || fail "CMU 135_02"
"$sfit" skeleton "$D/unlabeled/fullbody_44Markers_clean_120fps.c3d" --json --svg "$tmp/fb44.svg" \
  --frame 2000 > "$tmp/fb44.json"
ari "$tmp/fb44.json" --truth "file:$D/unlabeled/fullbody_44Markers_segments.tsv" --min 0.92 \
  --exact Lhand,Rhand,Lfoot,Rfoot --joints --min-joints 10 --quiet || fail "44-marker full body"
# its picture upright: the recording's vertical is +Z (the feet's end of the
# body is the steady one), though the hands are raised above the root
grep -q 'view along X: Y right, Z up' "$tmp/fb44.svg" || fail "44-marker full body drawn upside down"
# the members tools read keep their names and types
py 'import json, sys
d = json.load(open(sys.argv[1]))
assert all(isinstance(m, str) for s in d["segments"] for m in s["markers"])
assert all(isinstance(m, str) for g in d["grouping"]["groups"] for m in g["markers"])
for j in d["joints"]:
    assert isinstance(j["name"], str) and j["type"] in ("ball", "hinge")
    assert j["parent"] in [s["name"] for s in d["segments"]] and j["child"] in [s["name"] for s in d["segments"]]
    assert isinstance(j["flags"], list) and all(isinstance(f, str) for f in j["flags"])
    assert ("untrusted" in j["flags"]) == bool(j["untrusted_why"]), j' "$tmp/85.json" \
  || fail "JSON members of segments, grouping and joints"

# 5. the JSON's bvh_distance on the full body, recomputed from the BVH and the
# centres (tests/scripts/skeleton_check.py bvhdist); figures printed
PYTHONPATH="$cli_src/tests/scripts" /usr/bin/python3 "$cli_src/tests/scripts/skeleton_check.py" \
  bvhdist "$tmp/85.bvh" "$tmp/85.csv" "$tmp/85.json" || fail "BVH distance, CMU 85_12"
echo "skeleton_groups: ok"
