#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The pictures of the session and skeleton docs, made again from the shared
# session (tests/data/c3d/lower_limb_session) with the built `sfit` and
# headless Chromium:
#   docs/figures/lower_limb_session.svg, .png  `sfit apply --svg` of the
#                                              static trial, and its screenshot
#   docs/figures/skeleton_viewer.png           the `sfit skeleton --html`
#                                              page, orbited, ellipsoids x5
#   docs/figures/skeleton_page.png             the same page, default view
#   docs/figures/skeleton_cmu.svg              `sfit skeleton --svg` without a
#                                              map: CMU 135_02 (tests/data/c3d/cmu)
#   docs/figures/skeleton_fullbody44.svg       the same, the unlabelled 44-marker
#                                              full body (tests/data/c3d/unlabeled)
# Usage: tools/docs/figures.sh BUILD_DIR OUT_DIR   (OUT_DIR = docs/figures to
# update the docs; tests/scripts/test_viewer.sh writes to a scratch folder)
set -euo pipefail
build=$1
out=$2
src=$(cd "$(dirname "$0")/../.." && pwd)
sfit="$build/bin/sfit"
L="$src/tests/data/c3d/lower_limb_session"
chrome=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chrome" ] || { echo "figures: chromium not found (Debian package chromium)" >&2; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
out=$(cd "$out" && pwd)
build=$(cd "$build" && pwd)
sfit="$build/bin/sfit"
"$sfit" calibrate "$src/docs/lower_limb_session.txt" "$L"/*.c3d -o "$tmp/session.json" > /dev/null 2>&1
"$sfit" apply "$tmp/session.json" "$L/anatomical_posture.c3d" -o "$tmp/ap.c3d" \
  --svg "$out/lower_limb_session.svg" > /dev/null 2>&1
"$sfit" skeleton "$src/docs/lower_limb_session.txt" "$L/Test_func_rankle.c3d" "$L/Test_func_rhip.c3d" \
  "$L/Test_func_rknee.c3d" "$L/Test_func_trunk.c3d" --html "$tmp/s.html" > /dev/null 2>&1
"$sfit" skeleton "$src/tests/data/c3d/cmu/135_02.c3d" --svg "$out/skeleton_cmu.svg" --frame 2000 \
  > /dev/null 2>&1
"$sfit" skeleton "$src/tests/data/c3d/unlabeled/fullbody_44Markers_clean_120fps.c3d" \
  --svg "$out/skeleton_fullbody44.svg" --frame 2000 > /dev/null 2>&1
shot() { # URL PNG W H
  "$chrome" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size="$3,$4" \
    --screenshot="$2" "$1" > /dev/null 2>&1
  [ -s "$2" ] || { echo "figures: chromium wrote no $2" >&2; exit 1; }
}
shot "file://$out/lower_limb_session.svg" "$out/lower_limb_session.png" 640 900
shot "file://$tmp/s.html#frame=300&yaw=-1.1&pitch=0.3&zoom=1.0&ell=5" "$out/skeleton_viewer.png" 930 760
shot "file://$tmp/s.html#frame=700" "$out/skeleton_page.png" 930 760
echo "figures: $out/lower_limb_session.svg, lower_limb_session.png, skeleton_viewer.png, skeleton_page.png," \
  "skeleton_cmu.svg, skeleton_fullbody44.svg"
