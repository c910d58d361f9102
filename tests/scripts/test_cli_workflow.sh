#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One workflow: the help a user finds, one model format, user docs that
# speak to users, and a demo that leaves the tree clean. Claims checked:
#  1. `sfit help` and `sfit help COMMAND` exit 0 and print the same as
#     `sfit --help` / `sfit COMMAND --help`; an unknown command is a usage
#     error; `sfit --help` and `sfit skeleton --help` name --bvh, and the
#     latter shows both forms of the command;
#  2. `sfit skeleton SESSION_MODEL TRIAL...` (the session model of
#     `sfit calibrate`) gives the same JSON as `--segments SESSION_MODEL`;
#  3. no model file in docs/ uses the per-joint marker-list shorthand;
#  4. no user document names an issue number or a branch;
#  5. the README demo writes into out/, which git ignores;
#  6. the knee centre of the shared session lies within 20 mm of the
#     epicondyles' mid-point, and the session and the C3D name the rule.
# Usage: test_cli_workflow.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
. "$(dirname "$0")/common.sh"
cli_setup cli_workflow "$1" "$2"
src=$2
L="$data/c3d/lower_limb_session"

# 1. help
expect_rc 0 "$sfit" help
top=$out
expect_rc 0 "$sfit" --help
[ "$out" = "$top" ] || fail "sfit help differs from sfit --help"
grep -q -- '--bvh' <<<"$top" || fail "sfit --help does not name --bvh"
for c in fit noise track coverage joint skeleton calibrate apply c3d; do
  grep -q "^  $c " <<<"$top" || fail "sfit help does not list $c"
  expect_rc 0 "$sfit" help "$c"
  h=$out
  expect_rc 0 "$sfit" "$c" --help
  [ "$out" = "$h" ] || fail "sfit help $c differs from sfit $c --help"
  grep -q "usage: sfit $c" <<<"$h" || fail "sfit help $c: no usage line"
done
expect_rc 0 "$sfit" skeleton --help
grep -q -- '--bvh' <<<"$out" || fail "sfit skeleton --help does not name --bvh"
grep -q -- '--segments' <<<"$out" || fail "sfit skeleton --help: no session form"
grep -q -- '--no-repair-swaps' <<<"$out" || fail "sfit skeleton --help: no shorthand form"
expect_rc 2 "$sfit" help nosuch
grep -q "no command 'nosuch'" "$tmp/stderr" || fail "help nosuch: $(cat "$tmp/stderr")"

# 2. the session model as the skeleton's model
trials=("$L/Test_func_rankle.c3d" "$L/Test_func_rhip.c3d" "$L/Test_func_rknee.c3d" "$L/Test_func_trunk.c3d")
expect_rc 0 "$sfit" skeleton "$src/docs/lower_limb_session.txt" "${trials[@]}" --json
echo "$out" > "$tmp/a.json"
expect_rc 0 "$sfit" skeleton "${trials[@]}" --segments "$src/docs/lower_limb_session.txt" --json
echo "$out" > "$tmp/b.json"
cmp -s "$tmp/a.json" "$tmp/b.json" || fail "skeleton MODEL TRIALS differs from --segments MODEL"
py 'import json,sys; d=json.load(open(sys.argv[1])); assert d["status"] == "ok" and len(d["joints"]) == 4, d["joints"]' "$tmp/a.json" \
  || fail "skeleton with the session model: $(head -c 300 "$tmp/a.json")"

# 3. one model format in docs/
if grep -lE '^[[:space:]]*joint[[:space:]]+[^[:space:]]+[[:space:]]+[^[:space:]]*,' "$src"/docs/*.txt; then
  fail "a model file in docs/ uses the per-joint marker-list shorthand"
fi

# 4. user docs
if grep -niE 'issues?[- ]?#?[0-9]+|this branch|must-show' "$src/README.md" "$src"/docs/*.md; then
  fail "user docs name an issue or a branch (history goes to CHANGELOG.md)"
fi

# 5. the demo's outputs
grep -q 'mkdir -p out && ./build/bin/sfit calibrate [^ ]* [^ ]* -o out/' "$src/README.md" \
  || fail "the README demo does not write into out/"
if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
  git -C "$src" check-ignore -q out/session.json || fail "out/ is not ignored by git"
fi
# 6. the field's convention for the knee centre: on the functional axis,
# nearest the mid-point of the epicondyle markers (the model's landmarks);
# the session JSON and the C3D's point descriptions name it
"$sfit" calibrate "$src/docs/lower_limb_session.txt" "$L"/*.c3d -o "$tmp/s.json" >/dev/null 2>&1 \
  || fail "calibrate"
"$sfit" apply "$tmp/s.json" "$L/anatomical_posture.c3d" -o "$tmp/ap.c3d" >/dev/null 2>&1 || fail "apply"
py '
import sys, json, numpy as np, c3d_ref
s = {j["name"]: j for j in json.load(open(sys.argv[1]))["joints"]}
assert "nearest the mid-point of RKNE and RKNEM" in s["r_knee"]["center_convention"], s["r_knee"]["center_convention"]
assert s["r_hip"]["center_convention"].startswith("functional"), s["r_hip"]["center_convention"]
b = c3d_ref.read(sys.argv[2]); L = b["labels"]; x = b["xyz"]
mid = (x[:, L.index("RKNE")] + x[:, L.index("RKNEM")]) / 2
d = np.linalg.norm(x[:, L.index("RKJC")] - mid, axis=1)
assert np.isfinite(d).all() and d.mean() <= 20.0, d.mean()
desc = b["descriptions"][L.index("RKJC")]
assert "RKNE" in desc and "RKNEM" in desc, desc
import re
doc = open(sys.argv[3]).read()
m = re.search(r"RKJC` is then\s+(\d+) mm from the mid-point of RKNE and RKNEM", doc)
assert m and abs(int(m.group(1)) - d.mean()) < 0.5 + 1e-9, ("docs/session.md says", m and m.group(1), d.mean())
print("RKJC: %.1f mm from the mid-point of RKNE and RKNEM (mean over %d frames); description: %s" % (d.mean(), len(d), desc))
' "$tmp/s.json" "$tmp/ap.c3d" "$src/docs/session.md" || fail "the knee centre convention"
echo "cli_workflow: ok"
