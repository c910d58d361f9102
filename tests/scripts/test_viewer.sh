#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The pictures a lab would show, looked at in headless Chromium:
#  1. tools/docs/figures.sh makes every docs picture again (the SVG of
#     `sfit apply`, its screenshot, the skeleton page orbited and not), and
#     the pictures in docs/figures have the same sizes, the skeleton SVGs
#     without a map (CMU 135_02, the 44-marker body) the same bytes;
#  2. the skeleton page (`sfit skeleton --html`) opened orbited: the view
#     asked for is the view drawn, each of the 4 joints has its ellipsoid,
#     no joint label overlaps another label or a joint, and the canvas
#     shows the ellipsoids' fill, the floor grid and the scale bar;
#  3. the page is self-contained (nothing loaded from elsewhere);
#  4. the apply SVG names its trial, its view direction, its ellipsoid
#     magnification and has a scale bar.
# Usage: test_viewer.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
. "$(dirname "$0")/common.sh"
cli_setup viewer "$1" "$2"
src=$2
chrome=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chrome" ] || missing "chromium not found (Debian package chromium)"
L="$data/c3d/lower_limb_session"

# 1. the docs pictures
bash "$src/tools/docs/figures.sh" "$1" "$tmp/fig" > /dev/null || fail "tools/docs/figures.sh"
py '
import sys, os, png_ref
for n in ("lower_limb_session.png", "skeleton_viewer.png", "skeleton_page.png"):
    a = png_ref.read_png(os.path.join(sys.argv[1], n))[:2]
    b = png_ref.read_png(os.path.join(sys.argv[2], n))[:2]
    assert a == b, (n, a, b)
print("docs pictures: made again, sizes as in docs/figures")
' "$tmp/fig" "$src/docs/figures" || fail "the docs pictures"
for n in skeleton_cmu.svg skeleton_fullbody44.svg; do
  cmp -s "$tmp/fig/$n" "$src/docs/figures/$n" || fail "docs/figures/$n is not what tools/docs/figures.sh makes"
done

# 2. the page, orbited
"$sfit" skeleton "$src/docs/lower_limb_session.txt" "$L/Test_func_rankle.c3d" "$L/Test_func_rhip.c3d" \
  "$L/Test_func_rknee.c3d" "$L/Test_func_trunk.c3d" --html "$tmp/s.html" > /dev/null 2>&1 \
  || fail "skeleton --html"
url="file://$tmp/s.html#frame=300&yaw=-1.1&pitch=0.3&zoom=1.0&ell=5"
"$chrome" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=930,760 \
  --screenshot="$tmp/v.png" "$url" > /dev/null 2>&1
"$chrome" --headless --no-sandbox --disable-gpu --window-size=930,760 --dump-dom "$url" \
  > "$tmp/v.dom" 2> /dev/null
[ -s "$tmp/v.png" ] || fail "no screenshot"
py '
import sys, json, png_ref
t = open(sys.argv[2]).read()
a = t.index("<pre id=\"state\">") + len("<pre id=\"state\">")
st = json.loads(t[a:t.index("</pre>", a)].replace("&quot;", "\"").replace("&amp;", "&"))
assert st["frame"] == 300, st["frame"]
assert abs(st["view"]["yaw"] + 1.1) < 1e-3 and abs(st["view"]["pitch"] - 0.3) < 1e-3, st["view"]
assert st["ellipses"] == 4, st["ellipses"]
assert set(st["nodes"]) == {"pelvis", "r_hip", "r_knee", "r_ankle", "trunk"}, st["nodes"]
boxes = [b[1:] for b in st["labels"]]
for i, p in enumerate(boxes):
    for q in boxes[i + 1:]:
        assert not (p[0] < q[2] and p[2] > q[0] and p[1] < q[3] and p[3] > q[1]), ("labels overlap", p, q)
    for n, (x, y) in st["nodes"].items():
        assert not (p[0] < x + 6 and p[2] > x - 6 and p[1] < y + 6 and p[3] > y - 6), ("a label hides joint", n, p)
w, h, rows = png_ref.read_png(sys.argv[1])
left, top, cw, ch = [int(round(v)) for v in st["canvas"]]
fill = grid = dark = 0
for y in range(top, min(h, top + ch)):
    for x in range(left, min(w, left + cw)):
        r, g, b = rows[y][x][:3]
        if r > 215 and 150 < g < 225 and abs(g - b) < 12 and r - g > 25:
            fill += 1
        elif 220 <= r <= 236 and abs(r - g) < 3 and abs(g - b) < 3:
            grid += 1
        elif r < 60 and g < 60 and b < 60 and y > top + ch - 40 and x < left + 200:
            dark += 1
assert fill > 2000, ("ellipsoid fill pixels", fill)
assert grid > 2000, ("floor grid pixels", grid)
assert dark > 100, ("scale bar pixels", dark)
print("page orbited (yaw %.2f, pitch %.2f): 4 ellipsoids (%d fill pixels), grid (%d), scale bar (%d), %d labels apart" % (
    st["view"]["yaw"], st["view"]["pitch"], fill, grid, dark, len(boxes)))
' "$tmp/v.png" "$tmp/v.dom" || fail "the orbited page"

# 3. self-contained
if grep -Eiq '(src|href)="?(https?:)?//|<script[^>]+src=|<link |import\(' "$tmp/s.html"; then
  fail "the page loads something from outside itself"
fi

# 4. the static picture
svg="$tmp/fig/lower_limb_session.svg"
grep -q 'anatomical_posture.c3d, frame 0' "$svg" || fail "SVG: no trial name"
grep -q 'orthographic view from lab' "$svg" || fail "SVG: no view direction"
grep -Eq 'drawn x(1|2|5|10)\)' "$svg" || fail "SVG: no ellipsoid magnification"
grep -Eq '>[0-9]+ mm</text>' "$svg" || fail "SVG: no scale bar"
echo "viewer: ok"
