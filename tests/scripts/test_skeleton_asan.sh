#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `sfit skeleton FILE...` (segments found from the data) under
# AddressSanitizer + UndefinedBehaviorSanitizer on real recordings:
# the two CMU full-body trials (41 markers, tests/data/c3d/cmu), the
# unlabelled full body (44 markers) and arms (tests/data/c3d/unlabeled) and
# the lower-limb session's trials together.
# Every writer is asked for (--json --bvh --trc --svg --html --centres).
# Each run must exit 0, in under 30 s, with no sanitizer report, and its
# JSON must parse with status "ok".
#
# Builds only the CLI (target sfit_cli) in BUILD_DIR/skel-asan with
#   -fsanitize=address,undefined -fno-sanitize-recover=all
# (without the last flag UBSan only prints and exits 0).
#
#   test_skeleton_asan.sh BUILD_DIR SOURCE_DIR
#
# SFIT_SAN_CC picks the compiler (default: gcc). Exit 77 (skipped) when the
# compiler cannot link a sanitized program, unless CI=true.
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/skel-asan"
name=test_skeleton_asan

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
[ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
san_build "$out" sfit_cli
sfit="$out/bin/sfit"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

D="$src/tests/data/c3d"
L="$D/lower_limb_session"
n=0
run() { # run LABEL FILE...
  local label=$1 rc t0 t1 secs; shift
  t0=$(date +%s.%N)
  set +e
  "$sfit" skeleton "$@" --json --bvh "$tmp/o.bvh" --trc "$tmp/o.trc" --svg "$tmp/o.svg" \
    --html "$tmp/o.html" --centres "$tmp/o.csv" >"$tmp/o.json" 2>"$tmp/o.err"
  rc=$?
  set -e
  t1=$(date +%s.%N)
  secs=$(/usr/bin/python3 -c "print(f'{$t1 - $t0:.1f}')")
  if [ "$rc" -ne 0 ] || grep -q "Sanitizer\|runtime error" "$tmp/o.err"; then
    head -n 40 "$tmp/o.err" >&2
    echo "$name: FAIL: $label: exit $rc under ASan+UBSan" >&2
    exit 1
  fi
  /usr/bin/python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
assert d['status'] == 'ok', d
assert len(d['joints']) >= 1, 'no joint'
" "$tmp/o.json" || { echo "$name: FAIL: $label: JSON" >&2; exit 1; }
  /usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 30.0 else 1)" "$secs" \
    || { echo "$name: FAIL: $label took $secs s (>= 30 s)" >&2; exit 1; }
  echo "ok: $label: exit 0, $secs s, no sanitizer report"
  n=$((n + 1))
}
run "CMU 85_12 (41 markers, full body)" "$D/cmu/85_12.c3d"
run "CMU 135_02 (41 markers, full body)" "$D/cmu/135_02.c3d"
run "unlabelled full body (44 markers)" "$D/unlabeled/fullbody_44Markers_clean_120fps.c3d"
run "unlabelled arm 4-2-3" "$D/unlabeled/arm-4-2-3_clean_120fps.c3d"
run "unlabelled arm 4-4-4" "$D/unlabeled/arm-4-4-4_clean_30fps.c3d"
run "lower-limb session, 4 trials" "$L/Test_func_rankle.c3d" "$L/Test_func_rhip.c3d" \
  "$L/Test_func_rknee.c3d" "$L/Test_func_trunk.c3d"
echo "$name: ok: $n skeleton runs under $cc -fsanitize=address,undefined -fno-sanitize-recover=all"
