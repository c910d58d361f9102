#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `sfit imu-joint` on synthetic trials with known truth (written by
# test_imu --write-csv: 20 s at 200 Hz, noise and biases of tests/test_imu.c):
#  1. a hip-like ball joint: JSON fields, both centres within 10 mm, trusted;
#  2. a knee-like hinge: joint "hinge", axes within 3 degrees, axis points
#     within 10 mm; the text output says it in words;
#  2b. a hinge with a wobble at the flexion's frequency: axis_off, untrusted;
#  2c. a hinge whose wobbles are both in step with the flexion: wobble,
#      untrusted, force_ratio in JSON, the reason in words;
#  2d. a hinge whose wobbles are at 2 and 3 times the flexion's frequency:
#      a trusted hinge, axes within 3 degrees, wobble_deg in JSON and text;
#  3. no motion: untrusted, with the reason in words;
#  4. errors: NaN, time going backwards, unknown column, missing file, usage.
# Usage: test_cli_imu.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
cli_setup test_cli_imu "$build" "$src"
gen="$build/tests/test_imu"
[ -x "$gen" ] || missing "$gen not built"
# run_case NAME KIND SEED: the generator's trial KIND (its truth in
# $tmp/NAME_truth.json) through `sfit imu-joint --json` ($out, and
# $tmp/NAME.json).
run_case() {
  "$gen" --write-csv "$tmp/$1.csv" "$2" "$3" > "$tmp/$1_truth.json"
  expect_rc 0 "$sfit" imu-joint --json "$tmp/$1.csv"
  echo "$out" > "$tmp/$1.json"
}

# 1. ball
run_case hip ball 4242
py '
import json, sys, math
o = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2]))
assert o["status"] == "ok" and o["joint"] == "ball", o
assert o["n"] == 4000 and abs(o["rate"] - 200.0) < 1e-3, o
for k in ("r1_cov", "r2_cov"):
    assert len(o[k]) == 3 and all(len(r) == 3 for r in o[k]), o
assert o["axis1"] is None and o["axis2"] is None, o
assert o["flags"]["untrusted"] is False and o["flags"]["reason"] is None, o
assert o["wobble_deg"] > 2.5, o
for k in ("r1", "r2"):
    d = math.dist(o[k], t[k])
    assert d < 0.01, (k, d)
print("ball: r1 %.4f m, r2 %.4f m from the truth" % (math.dist(o["r1"], t["r1"]), math.dist(o["r2"], t["r2"])))
' "$tmp/hip.json" "$tmp/hip_truth.json"

# 2. hinge
run_case knee hinge 4243
py '
import json, sys, math
from imu_c3d_trials import angle as ang
o = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2]))
assert o["status"] == "ok" and o["joint"] == "hinge", o
for k in ("axis1", "axis2"):
    assert ang(o[k], t[k]) < 3.0, (k, ang(o[k], t[k]))
    assert len(o[k + "_cov"]) == 3, o
assert math.dist(o["r1"], t["point1"]) < 0.01 and math.dist(o["r2"], t["point2"]) < 0.01, o
assert 0.0 < o["wobble_deg"] < 2.5, o
print("hinge: axes %.2f, %.2f deg" % (ang(o["axis1"], t["axis1"]), ang(o["axis2"], t["axis2"])))
' "$tmp/knee.json" "$tmp/knee_truth.json"
expect_rc 0 "$sfit" imu-joint "$tmp/knee.csv"
grep -q "^joint         hinge" <<<"$out" || fail "text output: no hinge line: $out"
grep -q "^axis in sensor 1" <<<"$out" || fail "text output: no axis: $out"

# 2b. a hinge whose wobble is at 1 and 2 times the flexion's frequency
# (test_imu --write-csv ... wobble): its axis 1 is 3.4 degrees and its axis
# point 20 mm off, and the rate axes and the freest line of the position
# disagree by more than hinge_off (0.0523): untrusted, axis_off, in JSON
# and in words; the rate axes do not fit the accelerometers either
# (force_ratio 3.45 > wobble_ratio 1.5): wobble.
run_case wobble wobble 4325
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["joint"] == "hinge", o
assert o["line_off"] > 0.0523, o
assert o["flags"]["untrusted"] is True and o["flags"]["names"] == ["axis_off", "wobble"], o
assert o["force_ratio"] > 1.5, o
assert "wobble" in o["flags"]["reason"], o
print("wobble: line_off %.4f, flagged axis_off" % o["line_off"])
' "$out"
expect_rc 0 "$sfit" imu-joint "$tmp/wobble.csv"
grep -q "^UNTRUSTED" <<<"$out" || fail "text output: wobble not untrusted: $out"
grep -q "leave the joint free" <<<"$out" || fail "text output: no axis_off reason: $out"

# 2c. both wobbles in step with the flexion (test_imu --write-csv ... instep):
# axis 1 is 6.8 degrees and the axis points 19 mm off; the freest line of
# the position agrees with the rate axes (line_off 0.022, no axis_off), but
# the rate axes do not fit the accelerometers (force_ratio 2.87): wobble.
run_case instep instep 4326
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["joint"] == "hinge", o
assert o["line_off"] < 0.0523 and o["force_ratio"] > 1.5, o
assert o["flags"]["untrusted"] is True and o["flags"]["names"] == ["wobble"], o
assert "in step with the flexion" in o["flags"]["reason"], o
print("in step: force_ratio %.3f, flagged wobble" % o["force_ratio"])
' "$out"
expect_rc 0 "$sfit" imu-joint "$tmp/instep.csv"
grep -q "^UNTRUSTED" <<<"$out" || fail "text output: in-step wobble not untrusted: $out"
grep -q "do not fit the accelerometers" <<<"$out" || fail "text output: no wobble reason: $out"

# 2d. wobbles of 2 degrees at 2 and 3 times the flexion's frequency: the
# rates' hinge test fails (hinge_ratio above 0.07), the relative rotation
# leaves its best fixed axis by about 2 degrees rms (wobble_deg): a trusted
# hinge, axes within 3 degrees, axis points within 10 mm.
run_case fast fast 4327
py '
import json, sys, math
from imu_c3d_trials import angle as ang
o = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2]))
assert o["status"] == "ok" and o["joint"] == "hinge", o
assert o["hinge_ratio"] > 0.07 and 1.5 < o["wobble_deg"] < 2.5, o
assert o["flags"]["untrusted"] is False, o
for k in ("axis1", "axis2"):
    assert ang(o[k], t[k]) < 3.0, (k, ang(o[k], t[k]))
assert math.dist(o["r1"], t["point1"]) < 0.01 and math.dist(o["r2"], t["point2"]) < 0.01, o
print("fast wobble: wobble_deg %.2f, axes %.2f, %.2f deg" % (o["wobble_deg"], ang(o["axis1"], t["axis1"]), ang(o["axis2"], t["axis2"])))
' "$tmp/fast.json" "$tmp/fast_truth.json"
expect_rc 0 "$sfit" imu-joint "$tmp/fast.csv"
grep -q "^joint         hinge" <<<"$out" || fail "text output: fast wobble not a hinge: $out"
grep -q "wobble [0-9.]* degrees" <<<"$out" || fail "text output: no wobble angle: $out"

# 3. no motion
run_case still still 4244
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["flags"]["untrusted"] is True, o
assert "low_rotation" in o["flags"]["names"] and "hardly rotates" in o["flags"]["reason"], o
' "$out"
expect_rc 0 "$sfit" imu-joint "$tmp/still.csv"
grep -q "^UNTRUSTED" <<<"$out" || fail "text output: no UNTRUSTED line: $out"
grep -q "hardly rotates" <<<"$out" || fail "text output: no reason: $out"

# 4. errors
head -n 50 "$tmp/hip.csv" > "$tmp/nan.csv"
sed -i '30s/^\([^,]*\),[^,]*,/\1,nan,/' "$tmp/nan.csv"
expect_rc 3 "$sfit" imu-joint --json "$tmp/nan.csv"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"]=="format_error" and "acc1_x" in o["message"] and "line 30" in o["message"], o' "$out"
head -n 50 "$tmp/hip.csv" > "$tmp/back.csv"
sed -i '40s/^[^,]*,/0.01,/' "$tmp/back.csv"
expect_rc 3 "$sfit" imu-joint "$tmp/back.csv"
grep -q "time does not increase (line 40)" "$tmp/stderr" || fail "backwards time: $(cat "$tmp/stderr")"
sed '1s/gyr2_z/gyro2_z/' "$tmp/hip.csv" > "$tmp/col.csv"
expect_rc 3 "$sfit" imu-joint --json "$tmp/col.csv"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"]=="format_error" and "unknown column" in o["message"] and "gyro2_z" in o["message"], o' "$out"
expect_rc 3 "$sfit" imu-joint --json "$tmp/none.csv"
expect_usage "unknown option '--bogus'" imu-joint --bogus "$tmp/hip.csv"
expect_help imu-joint --help
echo "test_cli_imu: ok"
