#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `sfit skeleton FILE...`: the skeleton found in the recording
# (docs/skeleton.md). Claims checked (tests/scripts/skeleton_check.py):
#  1. the unlabeled arm recordings: the marker groups found from the data
#     (listed) and a chain of two joints, without a map;
#  2. the lower-limb session, all four functional trials together, segments
#     given: the tree pelvis - thigh - shank - foot and pelvis - trunk, the
#     knee a hinge, each joint centre within its uncertainty of the one
#     `sfit calibrate` gives; two segments that never move relative to each
#     other are no joint;
#  3. the BVH re-read by an independent parser (tests/scripts/bvh_ref.py):
#     its forward kinematics gives the TRC's joint centres in every frame
#     within 0.1 mm, and each joint's distance to the centre its parent
#     carries (median, 95th percentile) is the JSON's bvh_distance;
#  4. the HTML page in headless Chromium: screenshots at two frames differ
#     where the skeleton moved (the page's own report of where it drew
#     the joints, via --dump-dom);
#  5. errors: bad options, a missing file, a malformed map.
# Usage: test_skeleton.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
. "$(dirname "$0")/common.sh"
cli_setup skeleton "$1" "$2"
chk() { PYTHONPATH="$cli_src/tests/scripts" /usr/bin/python3 "$cli_src/tests/scripts/skeleton_check.py" "$@"; }
U="$data/c3d/unlabeled"
L="$data/c3d/lower_limb_session"
trials=("$L/Test_func_rankle.c3d" "$L/Test_func_rhip.c3d" "$L/Test_func_rknee.c3d" "$L/Test_func_trunk.c3d")

# 0. A synthetic chain (tests/scripts/skeleton_synth.py: ball joint, then a
# hinge, markers interleaved in the file, one marker missing for 20 frames):
# noise-free, everything found again exactly; with 0.3 mm noise, within 4
# sigma of the truth.
synth() { PYTHONPATH="$cli_src/tests/scripts" /usr/bin/python3 "$cli_src/tests/scripts/skeleton_synth.py" "$@"; }
synth "$tmp/syn0.c3d" "$tmp/syn0.json" 0
"$sfit" skeleton "$tmp/syn0.c3d" --frame 300 --json --bvh "$tmp/syn0.bvh" --trc "$tmp/syn0.trc" > "$tmp/syn0.out"
chk synth "$tmp/syn0.out" "$tmp/syn0.json" 0.01 0 0.01 || fail "noise-free synthetic chain"
chk bvh "$tmp/syn0.bvh" "$tmp/syn0.trc" "$tmp/syn0.out" || fail "BVH of the synthetic chain"
synth "$tmp/syn1.c3d" "$tmp/syn1.json" 0.3
"$sfit" skeleton "$tmp/syn1.c3d" --frame 300 --json > "$tmp/syn1.out"
chk synth "$tmp/syn1.out" "$tmp/syn1.json" 0 4 1.0 || fail "noisy synthetic chain"

# 1. Unlabeled: groups and a chain of two joints.
"$sfit" skeleton "$U/arm-4-4-4_clean_30fps.c3d" --json > "$tmp/a444.json"
chk unlabeled "$tmp/a444.json" \
  '[["M000","M001","M002","M003"],["M004","M005","M006","M007"],["M008","M009","M010","M011"]]' \
  || fail "arm-4-4-4"
# 10608 frames at 120 Hz: every 4th frame (30 Hz) is enough and 4 times faster.
"$sfit" skeleton "$U/arm-4-2-3_clean_120fps.c3d" --step 4 --json > "$tmp/a423.json"
chk unlabeled "$tmp/a423.json" \
  '[["M000","M001","M002","M003"],["M004","M005"],["M006","M007","M008"]]' \
  || fail "arm-4-2-3"
"$sfit" skeleton "$U/arm-4-2-3_clean_120fps.c3d" --step 4 > "$tmp/a423.txt"
grep -q "^  group 2    M004 M005  (spread .*) 2 markers: posed with a joint centre" "$tmp/a423.txt" \
  || fail "the human listing of the groups: $(cat "$tmp/a423.txt")"

# 2. The lower-limb session with its segments given (types left to the data).
cat > "$tmp/session.txt" <<'EOF'
# the shared lower-limb session (SESSION_MODEL.md format)
segment pelvis  RASI,LASI,RPSI,LPSI
segment r_thigh RTHI,RTHIB,RTHID,RKNE,RKNEM
segment r_shank RTIB,RTIBF,RTIBD,RANK,RANKM
segment r_foot  RHEE,RTOE,RNAV,RTOE5
segment trunk   C7,T1,T6,T10,CLAV,STRN,RBAK
joint r_hip   pelvis  r_thigh auto RHJC *func_rhip*
joint r_knee  r_thigh r_shank auto RKJC *func_rknee*
joint r_ankle r_shank r_foot  auto RAJC *func_rankle*
joint trunk   pelvis  trunk   auto TJC  *func_trunk*
root pelvis
EOF
"$sfit" skeleton "${trials[@]}" --segments "$tmp/session.txt" --json \
  --bvh "$tmp/s.bvh" --trc "$tmp/s.trc" --svg "$tmp/s.svg" --html "$tmp/s.html" --frame 700 \
  --centres "$tmp/s.csv" > "$tmp/session.json"
chk session "$tmp/session.json" || fail "lower-limb tree"
# 2b. Against `sfit calibrate` (docs/session.md) with the shared session model
# (docs/lower_limb_session.txt: knee hinge, each joint on its own functional
# trial), the same four trials, the same segments: every joint an edge of the
# tree, the same type, the centre inside the 95 % region of the two results'
# covariances (tests/scripts/skeleton_check.py calib: distance and
# Mahalanobis value per joint printed). Twice: with the model's types, and
# with every type left to the data (docs/skeleton_session.txt).
"$sfit" calibrate "$cli_src/docs/lower_limb_session.txt" "${trials[@]}" -o "$tmp/calib.json" \
  > /dev/null 2>&1 || fail "sfit calibrate of the session"
for model in lower_limb_session.txt skeleton_session.txt; do
  "$sfit" skeleton "${trials[@]}" --segments "$cli_src/docs/$model" --json > "$tmp/sk_$model.json" \
    2> /dev/null
  echo "skeleton --segments docs/$model against sfit calibrate:"
  chk calib "$tmp/sk_$model.json" "$tmp/calib.json" || fail "against sfit calibrate ($model)"
done
# the knee is a hinge from the data alone (no trial pattern in the model:
# its functional trial found as the one where it turns most)
sed 's/ \*func_[a-z]*\*$//' "$tmp/session.txt" > "$tmp/nopattern.txt"
"$sfit" skeleton "${trials[@]}" --segments "$tmp/nopattern.txt" --json > "$tmp/nopattern.json"
chk session "$tmp/nopattern.json" || fail "lower-limb tree without trial patterns"
# the pair module's members in --json, as `sfit joint --json` writes them
py '
import json, sys
d = json.load(open(sys.argv[1]))
names = {"none", "few_frames", "small_motion", "axis_free", "ambiguous", "misfit", "no_noise"}
for j in d["joints"]:
    assert len(j["center_cov"]) == 3 and all(len(r) == 3 for r in j["center_cov"]), j["name"]
    assert ("axis_cov" in j) == (j["type"] == "hinge"), j["name"]
    assert j["reason"] in names, j["reason"]
    assert j["untrusted"] == (j["reason"] != "none"), j["name"]
    assert j["marker_noise"]["source"] == "registration_residuals" and j["marker_noise"]["var"] > 0
    assert all(isinstance(f, str) for f in j["pair_flags"]), j["pair_flags"]
    assert j["type_rule"] in ("map", "all_trials", "functional_trial"), j["type_rule"]
knee = [j for j in d["joints"] if j["name"] == "r_knee"][0]
assert knee["type_rule"] == "functional_trial" and knee["type_trial"].endswith("Test_func_rknee.c3d"), knee
assert knee["trials_used"] == [knee["type_trial"]], knee["trials_used"]
print("json: per joint center_cov, axis_cov (hinge), marker_noise, reason, pair_flags; knee: type from",
      knee["type_trial"].split("/")[-1])
' "$tmp/sk_skeleton_session.txt.json" || fail "the pair module's members in --json"
# without the root line the root is the segment that moves least: the pelvis
grep -v '^root' "$tmp/session.txt" > "$tmp/noroot.txt"
"$sfit" skeleton "${trials[@]}" --segments "$tmp/noroot.txt" --json > "$tmp/noroot.json"
py 'import json,sys; d=json.load(open(sys.argv[1])); assert d["root"]=="pelvis" and d["root_rule"]=="moves_least", d["root"]' \
  "$tmp/noroot.json" || fail "root rule"
# Two segments on the same rigid pelvis (markers shared) never move: no joint.
cat > "$tmp/rigid.txt" <<'EOF'
segment a RASI,LASI,RPSI
segment b LASI,RPSI,LPSI
segment r_thigh RTHI,RTHIB,RTHID,RKNE,RKNEM
EOF
"$sfit" skeleton "$L/Test_func_rhip.c3d" --segments "$tmp/rigid.txt" --json > "$tmp/rigid.json"
chk norigid "$tmp/rigid.json" || fail "no-motion pair"
# a map joint the data do not support is reported
printf 'segment pelvis RASI,LASI,RPSI,LPSI\nsegment r_thigh RTHI,RTHIB,RTHID,RKNE,RKNEM\nsegment r_shank RTIB,RTIBF,RTIBD,RANK,RANKM\njoint wrong pelvis r_shank auto X\n' > "$tmp/wrong.txt"
"$sfit" skeleton "${trials[@]}" --segments "$tmp/wrong.txt" > "$tmp/wrong.out"
grep -q "^map joint    wrong (pelvis - r_shank) is not in the tree found" "$tmp/wrong.out" \
  || fail "map joint not in the tree: $(cat "$tmp/wrong.out")"

# 3. BVH: independent reader, forward kinematics = the TRC's joint centres.
chk bvh "$tmp/s.bvh" "$tmp/s.trc" "$tmp/session.json" || fail "BVH"
# the JSON's bvh_distance per joint: the BVH's forward kinematics against the
# centres the parents carry (--centres), recomputed here; figures printed
# (docs/skeleton.md: the knee's and ankle's are the hip's and knee's residuals)
chk bvhdist "$tmp/s.bvh" "$tmp/s.csv" "$tmp/session.json" || fail "BVH distance to the centres"
"$sfit" skeleton "$U/arm-4-2-3_clean_120fps.c3d" --step 4 --json --bvh "$tmp/a.bvh" \
  --trc "$tmp/a.trc" > "$tmp/a.json"
chk bvh "$tmp/a.bvh" "$tmp/a.trc" "$tmp/a.json" || fail "BVH of the unlabeled arm"
grep -q '^<svg ' "$tmp/s.svg" && grep -q '</svg>' "$tmp/s.svg" || fail "SVG"

# 4. The HTML page in headless Chromium: self-contained, two frames differ
# where the skeleton moved.
if grep -Eiq '(src|href)="?(https?:)?//|<script[^>]+src=|<link ' "$tmp/s.html"; then
  fail "the page loads something from outside itself"
fi
chrome=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chrome" ] || missing "chromium not found (Debian package chromium)"
shot() { # FRAME: screenshot and DOM of the page at that frame
  "$chrome" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=920,760 \
    --screenshot="$tmp/f$1.png" "file://$tmp/s.html#frame=$1&ell=0" > /dev/null 2>&1
  "$chrome" --headless --no-sandbox --disable-gpu --window-size=920,760 --dump-dom \
    "file://$tmp/s.html#frame=$1&ell=0" > "$tmp/f$1.dom" 2> /dev/null
  [ -s "$tmp/f$1.png" ] && grep -q '<pre id="state">{' "$tmp/f$1.dom" \
    || fail "chromium did not render frame $1"
}
shot 0
shot 700
chk screens "$tmp/f0.png" "$tmp/f700.png" "$tmp/f0.dom" "$tmp/f700.dom" || fail "screenshots"

# 5. Errors.
expect_usage "FILE missing" skeleton --bvh "$tmp/x.bvh"
expect_usage "--step needs a whole number >= 1" skeleton "$U/arm-4-4-4_clean_30fps.c3d" --step 0
expect_usage "--bvh needs a value" skeleton "$U/arm-4-4-4_clean_30fps.c3d" --bvh
expect_rc 3 "$sfit" skeleton "$tmp/nothing.c3d" --bvh "$tmp/x.bvh"
printf 'segment a RASI,LASI\n' > "$tmp/bad.txt"
expect_rc 3 "$sfit" skeleton "$L/Test_func_rhip.c3d" --segments "$tmp/bad.txt" --json
py 'import json,sys; d=json.loads(sys.argv[1]); assert d["status"]=="format_error" and "3 to" in d["message"], d' "$out" \
  || fail "malformed map: $out"
printf 'segment a RASI,LASI,RPSI\nsegment a LASI,RPSI,LPSI\n' > "$tmp/twice.txt"
expect_rc 3 "$sfit" skeleton "$L/Test_func_rhip.c3d" --segments "$tmp/twice.txt"
grep -q "segment a given twice" "$tmp/stderr" || fail "duplicate segment: $(cat "$tmp/stderr")"
printf 'segment a RASI,LASI,RPSI\njoint j a b hinge\n' > "$tmp/badjoint.txt"
expect_rc 3 "$sfit" skeleton "$L/Test_func_rhip.c3d" --segments "$tmp/badjoint.txt"
printf 'segment a RASI,LASI,RPSI\nsegment b NOPE1,NOPE2,NOPE3\n' > "$tmp/absent.txt"
expect_rc 3 "$sfit" skeleton "$L/Test_func_rhip.c3d" --segments "$tmp/absent.txt"
grep -q "marker NOPE1 is in none of the files" "$tmp/stderr" || fail "absent marker: $(cat "$tmp/stderr")"
expect_rc 2 "$sfit" skeleton "$U/arm-4-4-4_clean_30fps.c3d" --frame 99999
expect_rc 3 "$sfit" skeleton "$U/arm-4-4-4_clean_30fps.c3d" --bvh "$tmp/no/such/dir.bvh"
# Hostile recordings (written with skeleton_synth.write_c3d): a marker at
# 1e30 (beyond the library's range: unseen, counted), one at +Inf, no motion
# at all (no joint: exit 1), only 6 frames with markers (exit 1); the JSON
# stays JSON (no NaN, no Inf).
py '
import sys, skeleton_synth as S
out = sys.argv[1]
labels = ["P%02d" % k for k in range(12)]
def rec(kind):
    frames = []
    for f in range(300):
        ps = S.poses(0.0 if kind == "static" else f / 50.0)[0]
        row = [S.add(S.app(ps[g][0], m), ps[g][1]) for g in "ABC" for m in S.MK[g]]
        if kind == "huge":
            row[3] = [1e30, 1e30, 1e30]
        if kind == "inf":
            row[3] = [float("inf"), 0.0, 0.0]
        if kind == "few" and f > 5:
            row = [None] * 12
        frames.append(row)
    S.write_c3d("%s/%s.c3d" % (out, kind), labels, frames, 100.0)
for k in ("huge", "inf", "static", "few"):
    rec(k)
' "$tmp"
for k in huge inf; do
  expect_rc 0 "$sfit" skeleton "$tmp/$k.c3d" --json --bvh "$tmp/$k.bvh" --trc "$tmp/$k.trc"
  py 'import json,sys; d=json.loads(sys.argv[1], parse_constant=lambda c: sys.exit("non-JSON constant " + c)); assert d["dropped"] == 300 and len(d["joints"]) == 2, d' "$out" \
    || fail "$k: $out"
  chk bvh "$tmp/$k.bvh" "$tmp/$k.trc" <(echo "$out") || fail "BVH of $k"
done
expect_rc 1 "$sfit" skeleton "$tmp/static.c3d"
grep -q "fewer than two segments with a pose: no joint" "$tmp/stderr" || fail "static: $(cat "$tmp/stderr")"
expect_rc 1 "$sfit" skeleton "$tmp/few.c3d" --json
py 'import json,sys; d=json.loads(sys.argv[1]); assert d["status"] == "error", d' "$out" || fail "few: $out"
echo "skeleton: ok"
