#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The `sfit fit` command line: JSON shape, rejected lines counted, exit
# codes, status names. Usage: test_cli.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"  # expect_usage, expect_help
sfit="$build/bin/sfit"
data="$src/tests/data"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
py() { /usr/bin/python3 -c "$@"; }

# 1. The hip marker: JSON, centre within 0.01 mm of the double-precision
#    Kasa reference (tests/ref, printed by test_ref_selfcheck's author:
#    (-66.128738, -93.950381, 76.080840), r 254.518889).
out=$("$sfit" fit --json "$data/mocap/hip_right/RTHI1.csv")
py '
import json, sys, math
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["method"] == "gdke" and o["mode"] == "sphere", o
assert o["n"] == 1400 and o["rejected"] == 0, o
ref = (-66.128738, -93.950381, 76.080840)
d = math.dist(o["center"], ref)
assert d <= 0.01, d
assert abs(o["radius"] - 254.518889) <= 0.01
e = o["eigenvalues"]; assert e[0] <= e[1] <= e[2]
assert o["trust_ratio"] == 0
for k in ("status","method","mode","n","rejected","center","radius","eigenvalues","trust_ratio"):
    assert k in o, k
' "$out" || fail "RTHI1 json: $out"

# 2. Bad lines are rejected, counted, and the fit goes on.
{
  echo "x,y,z"
  head -n 401 "$data/mocap/hip_right/RTHI1.csv" | tail -n 400
  echo "nan,1,2"
  echo "1,2"
  echo "abc,def,ghi"
  echo "1e30,0,0"
  echo "inf,0,0"
  echo "1,2,3,4"
  echo ""
} > "$tmp/bad.csv"
out=$("$sfit" fit --json "$tmp/bad.csv")
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["n"] == 400 and o["rejected"] == 6, o
' "$out" || fail "rejected lines: $out"
"$sfit" fit "$tmp/bad.csv" >"$tmp/human.txt" 2>"$tmp/err.txt" || fail "human run"
grep -q "6 rejected" "$tmp/human.txt" || fail "human summary lacks the rejected count"
grep -q "bad.csv:402 rejected: not finite" "$tmp/err.txt" || fail "stderr lacks line 402: $(cat "$tmp/err.txt")"
grep -q "centre" "$tmp/human.txt" || fail "human summary lacks the centre"

# 3. Too few samples: status, message, exit 1.
printf 'x,y,z\n1,2,3\n4,5,6\n7,8,10\n' > "$tmp/few.csv"
set +e
out=$("$sfit" fit --json "$tmp/few.csv"); rc=$?
set -e
[ "$rc" -eq 1 ] || fail "too few: exit $rc"
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "too_few_samples" and o["message"], o
' "$out" || fail "too few json: $out"

# 4. Missing file: exit 3 (JSON io_error); bad option: exit 2.
set +e
out=$("$sfit" fit --json "$tmp/none.csv"); rc=$?
set -e
[ "$rc" -eq 3 ] || fail "missing file: exit $rc"
echo "$out" | grep -q '"status":"io_error"' || fail "missing file json: $out"
for args in "fit --bogus x.csv" "fit" "nosuchcmd" "fit --noise-var -1 x.csv" \
            "fit --noise-var 1 --noise-cov 1,1,1,0,0,0 x.csv" "fit --mode cube x.csv"; do
  set +e
  # shellcheck disable=SC2086
  "$sfit" $args >/dev/null 2>&1; rc=$?
  set -e
  [ "$rc" -eq 2 ] || fail "'$args': exit $rc, expected 2"
done
"$sfit" fit --help | grep -q "usage: sfit fit" || fail "fit --help"

# 5. UGDK options and the planar solution on the knee.
out=$("$sfit" fit --json --noise-var 1 "$data/mocap/hip_right/RTHI1.csv")
echo "$out" | grep -q '"method":"ugdk"' || fail "noise-var: $out"
out=$("$sfit" fit --json --noise-cov 1,1,1,0,0,0 "$data/mocap/hip_right/RTHI1.csv")
echo "$out" | grep -q '"method":"ugdk"' || fail "noise-cov: $out"
out=$("$sfit" fit --json "$data/mocap/knee_right/RATT.csv")
py '
import json, sys, math
o = json.loads(sys.argv[1])
assert o["mode"] == "planar", o
assert abs(math.hypot(*o["axis"]) - 1) < 1e-5, o
' "$out" || fail "knee planar: $out"
# Exactly planar data forced to a sphere: degenerate, exit 1.
printf '1,7,0\n2,6,0\n5,8,0\n7,7,0\n9,5,0\n3,7,0\n' > "$tmp/ggs.csv"
set +e
out=$("$sfit" fit --json --mode sphere "$tmp/ggs.csv"); rc=$?
set -e
[ "$rc" -eq 1 ] || fail "planar as sphere: exit $rc"
echo "$out" | grep -q '"status":"degenerate"' || fail "planar as sphere: $out"
# stdin
"$sfit" fit --json - < "$tmp/ggs.csv" | grep -q '"mode":"planar"' || fail "stdin"
# 6. Several markers, one centre (one file per marker).
out=$("$sfit" fit --json "$data"/mocap/hip_right/*.csv)
py '
import json, sys, math
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["mode"] == "sphere", o
assert len(o["markers"]) == 6 and all(m["n"] == 1400 for m in o["markers"]), o
# Common centre vs the double-precision eq. 220 reference (tests/ref):
# (-63.058, -91.618, 85.293) mm, printed to 3 decimals.
assert math.dist(o["center"], (-63.058, -91.618, 85.293)) <= 0.002, o["center"]
' "$out" || fail "hip multi: $out"
out=$("$sfit" fit --json "$data"/mocap/knee_right/*.csv)
echo "$out" | grep -q '"mode":"planar"' || fail "knee multi: $out"
echo "$out" | grep -q '"axis":\[' || fail "knee multi axis: $out"
printf 'x,y,z\n1,2,3\n' > "$tmp/one.csv"
out=$("$sfit" fit --json "$data/mocap/hip_right/RTHI1.csv" "$tmp/one.csv")
echo "$out" | grep -q '"radius":null' || fail "skipped marker: $out"
# 7. noise and coverage sub-commands.
out=$("$sfit" noise --json --center -66.13,-93.95,76.08 --radius 254.52 "$data/mocap/hip_right/RTHI1.csv")
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["n"] == 1400, o
for k in ("noise_var", "noise_var_std"):
    assert isinstance(o[k], float), k
' "$out" || fail "noise: $out"
out=$("$sfit" coverage --json --noise-var 3.06 "$data/mocap/hip_right/RTHI1.csv")
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["kind"] == "cap", o
assert 20 < o["half_angle_deg"] < 40 and o["rotate_further"] is False, o
' "$out" || fail "coverage: $out"
"$sfit" coverage --json "$data/mocap/knee_right/RATT.csv" | grep -q '"kind":"arc"' || fail "coverage arc"
# 8. Self-calibration and refinement: the double-precision geometric fit
#    of tests/data/README.md is (-67.033, -88.814, 72.238), r 260.495.
out=$("$sfit" fit --json --noise-var auto --refine "$data/mocap/hip_right/RTHI1.csv")
py '
import json, sys, math
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["method"] == "geometric", o
assert math.dist(o["center"], (-67.033, -88.814, 72.238)) <= 0.01, o["center"]
assert abs(o["radius"] - 260.495) <= 0.01
c = o["center_cov"]  # 3x3 rows, symmetric, positive diagonal
assert len(c) == 3 and all(len(row) == 3 for row in c) and o["noise_estimated"] is True, c
assert all(c[i][j] == c[j][i] for i in range(3) for j in range(3)) and min(c[i][i] for i in range(3)) > 0
for k in ("noise_var", "iterations", "outliers"):
    assert k in o, k
' "$out" || fail "auto+refine: $out"
out=$("$sfit" fit --json --noise-var 3 --gate 4 "$data/mocap/hip_right/RTHI1.csv")
echo "$out" | grep -q '"outliers":0' || fail "gate: $out"
# 9. Issue 14's cap30 case (30-degree cap, r 100, sigma 5, N 1000, centre
#    (1000, -2000, 1500), written with a fixed seed): the self-calibrated
#    fit hits its noise cap; JSON and text must say untrusted and why, the
#    text must not claim the Leontief condition holds, and the fit with the
#    true sigma^2 = 25 is untrusted too.
py '
import numpy as np, sys
g = np.random.default_rng(14)
ax = np.array([0.3, -0.5, 0.8]); ax /= np.linalg.norm(ax)
e1 = np.cross(ax, [1.0, 0, 0]); e1 /= np.linalg.norm(e1); e2 = np.cross(ax, e1)
z = 1 - g.random(1000) * (1 - np.cos(np.radians(30))); s = np.sqrt(1 - z * z)
ph = 2 * np.pi * g.random(1000)
d = z[:, None] * ax + s[:, None] * (np.cos(ph)[:, None] * e1 + np.sin(ph)[:, None] * e2)
x = np.array([1000.0, -2000.0, 1500.0]) + 100 * d + 5 * g.standard_normal((1000, 3))
np.savetxt(sys.argv[1], x, delimiter=",", header="x,y,z", comments="", fmt="%.6f")
' "$tmp/cap30.csv"
for opt in "--noise-var auto" "--noise-var auto --refine" "--noise-var 25"; do
    out=$("$sfit" fit --json $opt "$tmp/cap30.csv")
    py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok", o
assert "untrusted" in o["flags"], o["flags"]
assert ("noise_capped" in o["flags"]) == o["noise_capped"], o
if sys.argv[2] != "--noise-var 25":
    assert o["noise_capped"] is True and "noise_capped" in o["flags"], o
' "$out" "$opt" || fail "cap30 $opt: $out"
done
out=$("$sfit" fit --noise-var auto "$tmp/cap30.csv")
echo "$out" | grep -q "the spread of the samples is large enough" && fail "cap30 text claims the condition: $out"
echo "$out" | grep -q "^untrusted" || fail "cap30 text: no untrusted line: $out"
echo "$out" | grep -q "reason     noise_capped" || fail "cap30 text: no reason: $out"
# 10. The option parser (cli_parse) of fit, noise, coverage and track: each
#     bad value, missing value, unknown option and missing FILE gives its
#     own message, exit 2 and the usage; --help wins only before an error.
x=x.csv
expect_help fit --help
expect_help fit -h
expect_help fit --help --bogus
expect_usage "unknown or incomplete option --bogus" fit --bogus --help
expect_usage "unknown or incomplete option --bogus" fit --bogus $x
expect_usage "FILE missing" fit
expect_usage "FILE missing" fit --json
expect_usage "unknown or incomplete option --gate" fit $x --gate
expect_usage "--gate needs one finite value K > 1 (sigmas)" fit --gate 1 $x
expect_usage "--gate needs one finite value K > 1 (sigmas)" fit --gate x $x
expect_usage "--noise-var needs one finite value >= 0 (not with --noise-cov)" fit --noise-var -1 $x
expect_usage "--noise-var needs one finite value >= 0 (not with --noise-cov)" fit --noise-var nan $x
expect_usage "--noise-var needs one finite value >= 0 (not with --noise-cov)" fit --noise-var 1 --noise-var 2 $x
expect_usage "--noise-var needs one finite value >= 0 (not with --noise-cov)" fit --noise-cov 1,1,1,0,0,0 --noise-var 1 $x
expect_usage "--noise-var auto: noise model given twice" fit --noise-var 1 --noise-var auto $x
expect_usage "--noise-var auto: noise model given twice" fit --noise-var auto --noise-var auto $x
expect_usage "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)" fit --noise-cov 1,1,1,0,0 $x
expect_usage "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)" fit --noise-cov 1,1,1,0,0,inf $x
expect_usage "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)" fit --noise-cov nan,1,1,0,0,0 $x
expect_usage "--noise-var needs one finite value >= 0 (not with --noise-cov)" fit --noise-var inf $x
expect_usage "--gate needs one finite value K > 1 (sigmas)" fit --gate inf $x
expect_usage "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)" fit --noise-var auto --noise-cov 1,1,1,0,0,0 $x
expect_usage "--mode is auto, sphere or planar" fit --mode cube $x
expect_usage "--weight is equal or samples" fit --weight bogus $x
expect_usage "--noise-var auto, --refine and --gate take one FILE" fit --refine $x $x
expect_usage "--noise-var auto, --refine and --gate take one FILE" fit --gate 3 $x $x
expect_usage "--gate does not combine with --noise-var auto / --refine" fit --gate 3 --refine $x
expect_usage "--noise-var auto / --refine fit spheres (not --mode planar)" fit --noise-var auto --mode planar $x
expect_help noise --help
expect_usage "--center and --radius are required" noise $x
expect_usage "--center and --radius are required" noise --center 1,2,3 $x
expect_usage "--center and --radius are required" noise --radius 1
expect_usage "FILE missing" noise --center 1,2,3 --radius 1
expect_usage "--center needs X,Y,Z (finite)" noise --center 1,2 --radius 1 $x
expect_usage "--radius needs one finite value >= 0" noise --center 1,2,3 --radius -1 $x
expect_usage "--radius needs one finite value >= 0" noise --center 1,2,3 --radius abc $x
expect_usage "one FILE expected" noise --center 1,2,3 --radius 1 $x $x
expect_usage "--center needs X,Y,Z (finite)" noise --center 1,nan,3 --radius 1 $x
expect_usage "--center needs X,Y,Z (finite)" noise --center 1,2,-inf --radius 1 $x
expect_usage "--radius needs one finite value >= 0" noise --center 1,2,3 --radius inf $x
expect_usage "unknown or incomplete option --radius" noise --center 1,2,3 $x --radius
expect_help coverage -h
expect_usage "FILE missing" coverage --cap
expect_usage "--cap and --arc exclude each other" coverage --cap --arc --help
expect_usage "--cap and --arc exclude each other" coverage --arc --cap $x
expect_usage "--noise-var needs one finite value >= 0" coverage --noise-var -1 $x
expect_usage "--noise-var needs one finite value >= 0" coverage --noise-var inf $x
expect_usage "--rho-max needs one value in (0, 1]" coverage --rho-max 0 $x
expect_usage "--rho-max needs one value in (0, 1]" coverage --rho-max 1.5 $x
expect_usage "unknown or incomplete option --mode" coverage --mode planar $x
expect_usage "one FILE expected" coverage $x $x
out=$("$sfit" coverage --json --cap --cap --rho-max 1 "$data/mocap/knee_right/RATT.csv")
echo "$out" | grep -q '"kind":"cap"' || fail "coverage --cap twice: $out"
expect_help track --help
expect_usage "FILE missing" track --every 5
expect_usage "--every needs a whole number >= 0" track --every -1 $x
expect_usage "--every needs a whole number >= 0" track --every 1.5 $x
expect_usage "--every needs a whole number >= 0" track --every 99999999999999999999999 $x
expect_usage "--noise-var needs one finite value >= 0" track --noise-var -1 $x
expect_usage "--noise-var needs one finite value >= 0" track --noise-var inf $x
expect_usage "unknown or incomplete option --every" track $x --every
expect_usage "unknown or incomplete option --mode" track --mode planar $x
expect_usage "one FILE expected" track $x $x
# track: --every K prints after every K-th sample and after the last one;
# --noise-var given twice keeps the last value (UGDK with V = 3 equals the
# fit of the same samples, 0.001 mm away; with V = 1 it is 3.5 mm away)
out=$("$sfit" track --every 600 "$data/mocap/hip_right/RTHI1.csv")
[ "$(echo "$out" | awk 'NR > 1 { print $1 }' | tr '\n' ' ')" = "600 1200 1400 " ] || fail "track --every: $out"
out=$("$sfit" track --json --every 0 --noise-var 1 --noise-var 3 "$data/mocap/hip_right/RTHI1.csv")
fitout=$("$sfit" fit --json --mode sphere --noise-var 3 "$data/mocap/hip_right/RTHI1.csv")
py '
import json, sys, math
t, f = json.loads(sys.argv[1]), json.loads(sys.argv[2])
assert t["n"] == 1400 and f["method"] == "ugdk", (t, f)
assert math.dist(t["center"], f["center"]) <= 1e-3 * f["radius"], (t, f)
' "$out" "$fitout" || fail "track --noise-var: $out / $fitout"
# Issue 32: the reproducer of the rounding flag at small N (tests/data/repro,
# 69 samples of an 8.3-degree cap): the float centre is 1.5e-4 r from the
# double fit of the same samples (test_hostile test_i32_repro), so the
# result carries "rounding" beside "near_planar"; the human output says it.
out=$("$sfit" fit --mode sphere --noise-var 110.708748 --json "$data/repro/small_cap_rounding.csv")
py '
import json, sys
o = json.loads(sys.argv[1])
assert o["status"] == "ok" and o["method"] == "ugdk" and o["n"] == 69, o
assert "near_planar" in o["flags"] and "rounding" in o["flags"], o["flags"]
' "$out" || fail "small-cap rounding reproducer: $out"
"$sfit" fit --mode sphere --noise-var 110.708748 "$data/repro/small_cap_rounding.csv" >"$tmp/repro.txt" \
    || fail "small-cap reproducer, text output"
grep -q "rounding" "$tmp/repro.txt" || fail "text output lacks the rounding flag: $(cat "$tmp/repro.txt")"
echo "cli: all checks passed"
