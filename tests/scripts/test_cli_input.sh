#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The CLI's input layer: every delimited-text variant through `sfit fit`
# (and the other commands sharing the reader), and the C3D reader against
# an independent reader (tests/scripts/mocap_ref.py, python3 struct) on the
# real trials and on files it writes itself (integer storage, DEC, MIPS,
# invalid samples, LABELS2), plus truncated and corrupt files: exit 3 and a
# JSON format_error naming the problem, never a crash.
# Usage: test_cli_input.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
cli_setup test_cli_input "$build" "$src"

rthi1="$data/mocap/hip_right/RTHI1.csv"
ref=$("$sfit" fit --json "$rthi1")
same_fit() { # same_fit JSON N MISSING: same centre as the plain CSV within 1e-4
  py '
import json, sys, math
o, r = json.loads(sys.argv[1]), json.loads(sys.argv[2])
n, miss = int(sys.argv[3]), int(sys.argv[4])
assert o["status"] == "ok", o
assert o["n"] == n and o["missing"] == miss and o["rejected"] == 0, o
if n == r["n"]:
    assert math.dist(o["center"], r["center"]) <= 1e-4, (o["center"], r["center"])
' "$1" "$ref" "$2" "$3"
}

# 1. Delimiters, header, --cols, blank cells, BOM, time column.
tail -n +2 "$rthi1" > "$tmp/body.csv"                      # comma, no header
out=$("$sfit" fit --json "$tmp/body.csv"); same_fit "$out" 1400 0 || fail "comma, no header: $out"
tr ',' '\t' < "$rthi1" > "$tmp/tab.tsv"                    # tab with header
out=$("$sfit" fit --json "$tmp/tab.tsv"); same_fit "$out" 1400 0 || fail "tab: $out"
tr ',' ';' < "$rthi1" > "$tmp/semi.csv"                    # semicolon
out=$("$sfit" fit --json "$tmp/semi.csv"); same_fit "$out" 1400 0 || fail "semicolon: $out"
sed 's/\./,/g' "$tmp/semi.csv" > "$tmp/semi_comma.csv"     # semicolon + decimal comma
out=$("$sfit" fit --json "$tmp/semi_comma.csv"); same_fit "$out" 1400 0 || fail "decimal comma: $out"
awk -F, 'NR > 1 { printf "  %s   %s\t%s \n", $1, $2, $3 }' "$rthi1" > "$tmp/ws.txt"   # blanks
out=$("$sfit" fit --json "$tmp/ws.txt"); same_fit "$out" 1400 0 || fail "whitespace: $out"
# header naming columns in another order, with a time column; by name by default
awk -F, 'NR == 1 { print "time,Z,note,X,Y"; next } { printf "%.2f,%s,ok,%s,%s\n", (NR-2)/100, $3, $1, $2 }' \
  "$rthi1" > "$tmp/time.csv"
out=$("$sfit" fit --json "$tmp/time.csv"); same_fit "$out" 1400 0 || fail "time column by name: $out"
out=$("$sfit" fit --json --cols X,Y,Z "$tmp/time.csv"); same_fit "$out" 1400 0 || fail "--cols names: $out"
out=$("$sfit" fit --json --cols 4,5,2 "$tmp/time.csv"); same_fit "$out" 1400 0 || fail "--cols indices: $out"
out=$("$sfit" fit --json --cols x,y,z "$tmp/time.csv"); same_fit "$out" 1400 0 || fail "--cols case: $out"
# headerless with a time column: --cols by index only
awk -F, 'NR > 1 { printf "%d\t%s\t%s\t%s\n", NR-2, $1, $2, $3 }' "$rthi1" > "$tmp/t_nohdr.tsv"
out=$("$sfit" fit --json --cols 2,3,4 "$tmp/t_nohdr.tsv"); same_fit "$out" 1400 0 || fail "tab, index: $out"
# UTF-8 BOM before the header; quoted header names
{ printf '\xef\xbb\xbf"x","y","z"\r\n'; tail -n +2 "$rthi1" | sed 's/$/\r/'; } > "$tmp/bom.csv"
out=$("$sfit" fit --json "$tmp/bom.csv"); same_fit "$out" 1400 0 || fail "BOM + CRLF: $out"
# UTF-8 BOM and no header: the BOM must not cost the first sample (1400, not 1399)
{ printf '\xef\xbb\xbf'; tail -n +2 "$rthi1"; } > "$tmp/bom_nohdr.csv"
out=$("$sfit" fit --json "$tmp/bom_nohdr.csv"); same_fit "$out" 1400 0 || fail "BOM, no header: $out"
# A directory as input is an input error (exit 3), for the reader and the C3D sniffer
mkdir "$tmp/adir"
expect_rc 3 "$sfit" fit "$tmp/adir"
expect_rc 3 "$sfit" fit --json "$tmp/adir"
printf '%s\n' "$out" | grep -q '"io_error"' || fail "directory: $out"
expect_rc 3 "$sfit" joint "$tmp/adir" --parent A,B,C --child D,E,F
# blank cells: 28 rows with one blank selected cell are skipped and counted;
# a blank cell in an unselected column does not matter
awk -F, 'NR == 1 { print "t,x,y,z"; next }
         (NR-1) % 50 == 0 { printf ",%s,,%s\n", $1, $3; next }
         { printf "%d,%s,%s,%s\n", NR, $1, $2, $3 }' "$rthi1" > "$tmp/blank.csv"
out=$("$sfit" fit --json "$tmp/blank.csv"); same_fit "$out" 1372 28 || fail "blank cells: $out"
"$sfit" fit "$tmp/blank.csv" > "$tmp/h.txt" 2> "$tmp/e.txt" || fail "blank cells, human"
grep -q "28 missing" "$tmp/h.txt" || fail "human summary lacks the missing count: $(cat "$tmp/h.txt")"
grep -q "28 rows with a blank cell skipped" "$tmp/e.txt" || fail "stderr lacks the missing rows"
# the other commands read through the same layer
"$sfit" track --json --every 0 --cols 4,5,2 "$tmp/time.csv" | grep -q '"n":1400' || fail "track --cols"
"$sfit" noise --json --center -66.13,-93.95,76.08 --radius 254.52 "$tmp/semi_comma.csv" \
  | grep -q '"n":1400' || fail "noise, semicolon"
"$sfit" coverage --json "$tmp/ws.txt" | grep -q '"status":"ok"' || fail "coverage, whitespace"
# errors: no x,y,z and 5 columns -> exit 3 format_error; unknown name; index out of range
expect_rc 3 "$sfit" fit --json "$tmp/t_nohdr.tsv"
echo "$out" | grep -q '"status":"format_error"' || fail "4 columns without --cols: $out"
expect_rc 3 "$sfit" fit --json --cols X,Y,W "$tmp/time.csv"
echo "$out" | grep -q "no column named 'W'" || fail "unknown column: $out"
expect_rc 3 "$sfit" fit --json --cols 1,2,9 "$tmp/time.csv"
expect_rc 3 "$sfit" fit --json --cols 1,2 "$tmp/time.csv"
expect_rc 2 "$sfit" fit --cols
# --cols is an option of every command that reads samples (not of c3d,
# joint, skeleton); a missing or empty value is a usage error
for cmd in fit "noise --center 0,0,0 --radius 1" coverage track; do
  # shellcheck disable=SC2086
  expect_usage "--cols needs a list of column names or 1-based indices" $cmd --cols
  # shellcheck disable=SC2086
  expect_usage "--cols needs a list of column names or 1-based indices" $cmd --cols "" "$tmp/time.csv"
  # shellcheck disable=SC2086
  expect_rc 3 "$sfit" $cmd --json --cols X,Y,W "$tmp/time.csv"
  echo "$out" | grep -q "no column named 'W'" || fail "$cmd --cols X,Y,W: $out"
done
out=$("$sfit" track --json --every 0 --cols 4,5,2 "$tmp/time.csv")
echo "$out" | grep -q '"n":1400' || fail "track --cols: $out"
out=$("$sfit" coverage --json --cols X,Y,Z "$tmp/time.csv")
echo "$out" | grep -q '"n":1400' || fail "coverage --cols: $out"
expect_usage "unknown or incomplete option --cols" c3d --cols 1,2,3 x.c3d
expect_usage "unknown or incomplete option --cols" joint x.c3d --parent A,B,C --child D --cols 1,2,3
expect_usage "unknown or incomplete option --cols" skeleton m.txt x.c3d --cols 1,2,3
# bad rows: wrong cell count and a selected cell that is not a number
{ cat "$tmp/time.csv"; echo "1,2,3"; echo "9.9,abc,ok,1,2"; echo "9.9,1,free text,2,3"; } > "$tmp/bad.csv"
out=$("$sfit" fit --json "$tmp/bad.csv")
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["n"] == 1401 and o["rejected"] == 2, o' "$out" \
  || fail "bad rows: $out"

# 2. C3D: the real trials against the independent reader.
for trial in hip knee; do
  f="$data/c3d/biobuddy_right_$trial.c3d"
  out=$("$sfit" c3d --json "$f")
  "$sfit" c3d "$f" --export "$tmp/$trial.csv" --markers RASIS,LASIS,RTHI1,RLEG3,RMFE --frames 0:919 >/dev/null
  py '
import json, sys, csv, math, mocap_ref
o = json.loads(sys.argv[1]); r = mocap_ref.read_c3d(sys.argv[2])
assert o["status"] == "ok" and o["processor"] == 84 == r["proc"], o
assert o["labels"] == r["labels"] and len(o["labels"]) == 73, (o["labels"], r["labels"])
assert o["frames"] == len(r["frames"]) and o["first_frame"] == r["first"], o
assert o["rate"] == r["rate"] == 100 and o["units"] == r["units"] == "mm", o
assert r["scale"] < 0 and abs(o["scale"] - r["scale"]) <= 1e-7 * abs(r["scale"]), o
rows = list(csv.reader(open(sys.argv[3])))
assert rows[0][:4] == ["frame", "RASIS_X", "RASIS_Y", "RASIS_Z"], rows[0]
names = ["RASIS", "LASIS", "RTHI1", "RLEG3", "RMFE"]
idx = [r["labels"].index(n) for n in names]
assert len(rows) == 921
worst = 0.0
for row in rows[1:]:
    f = int(row[0])
    for k, i in enumerate(idx):
        want = r["frames"][f][i]
        got = [float(v) for v in row[1 + 3 * k:4 + 3 * k]]
        worst = max(worst, max(abs(a - b) for a, b in zip(got, want)))
assert worst <= 1e-4, worst  # float32 values printed with 9 digits
print("c3d %s: 73 labels, %d frames, 920 x 5 points equal (max diff %.2g mm)" % (sys.argv[4], o["frames"], worst))
' "$out" "$f" "$tmp/$trial.csv" "$trial" || fail "c3d $trial vs the independent reader"
done

# 3. C3D variants written by the independent writer: Intel scaled integers,
#    DEC floats, MIPS (big-endian) floats and integers, invalid samples
#    (residual < 0), analog words to skip, 300 labels (LABELS + LABELS2).
py '
import sys, math, mocap_ref as m
labels = ["M%d" % i for i in range(300)]
frames = []
for f in range(12):
    row = []
    for p in range(300):
        if (f + p) % 17 == 0:
            row.append(None)
        else:
            row.append((0.1 * (p + f), -0.1 * p, 1000.0 + 0.1 * f))
    frames.append(row)
d = sys.argv[1]
m.write_c3d(d + "/intel_int.c3d", labels, frames, proc=m.INTEL, scale=0.1, nanalog=6)
m.write_c3d(d + "/dec_float.c3d", labels, frames, proc=m.DEC, scale=-0.1, rate=250.0)
m.write_c3d(d + "/mips_float.c3d", labels, frames, proc=m.MIPS, scale=-1.0, rate=60.0)
m.write_c3d(d + "/mips_int.c3d", labels, frames, proc=m.MIPS, scale=0.1, nanalog=3)
' "$tmp"
for v in intel_int dec_float mips_float mips_int; do
  out=$("$sfit" c3d --json "$tmp/$v.c3d")
  "$sfit" c3d "$tmp/$v.c3d" --export "$tmp/$v.csv" --markers M0,M1,M16,M150,M299 >/dev/null
  py '
import json, sys, csv, mocap_ref as m
o = json.loads(sys.argv[1]); r = m.read_c3d(sys.argv[2])
assert o["points"] == 300 and o["labels"] == ["M%d" % i for i in range(300)], o["labels"][-3:]
assert o["processor"] == r["proc"] and o["frames"] == 12 and o["rate"] == r["rate"], o
rows = list(csv.reader(open(sys.argv[3])))
names = ["M0", "M1", "M16", "M150", "M299"]
blanks = 0
for row in rows[1:]:
    f = int(row[0])
    for k, n in enumerate(names):
        p = int(n[1:])
        cells = row[1 + 3 * k:4 + 3 * k]
        if (f + p) % 17 == 0:
            assert cells == ["", "", ""], (f, p, cells)
            blanks += 1
            continue
        want = (0.1 * (p + f), -0.1 * p, 1000.0 + 0.1 * f)
        for a, b in zip(cells, want):
            assert abs(float(a) - b) <= 1e-4 * max(1.0, abs(b)), (sys.argv[4], f, p, a, b)
assert blanks > 0
' "$out" "$tmp/$v.c3d" "$tmp/$v.csv" "$v" || fail "c3d variant $v"
done

# 3b. The options of c3d: messages, exit 2 and the usage.
hip="$data/c3d/biobuddy_right_hip.c3d"
expect_help c3d --help
expect_usage "FILE missing" c3d --json
expect_usage "one FILE expected" c3d "$hip" "$hip"
expect_usage "unknown or incomplete option --bogus" c3d "$hip" --bogus
expect_usage "--frames needs F:L" c3d "$hip" --frames x
expect_usage "--frames needs F:L" c3d "$hip" --frames 5
expect_usage "--frames needs F:L" c3d "$hip" --frames -1:3
expect_usage "--frames needs F:L, 0 <= F <= L" c3d "$hip" --frames 5:2
expect_usage "--frames needs F:L, 0 <= F <= L" c3d "$hip" --frames 2:x
expect_usage "--frames needs F:L, 0 <= F <= L" c3d "$hip" --frames 99999999999999999999:99999999999999999999
for opt in --frames --export --markers; do
  expect_usage "unknown or incomplete option $opt" c3d "$hip" $opt
done
expect_rc 3 "$sfit" c3d --json "$hip" --export "$tmp/x.csv" --frames 99999:100000
echo "$out" | grep -q -- "--frames starts at 99999" || fail "c3d --frames past the end: $out"

# 4. Truncated and corrupt C3D: exit 3, JSON format_error with a message.
corrupt() { # corrupt NAME MESSAGE_PART: the file $tmp/NAME.c3d must fail clearly
  expect_rc 3 "$sfit" c3d --json "$tmp/$1.c3d"
  echo "$out" | grep -q '"status":"format_error"' || fail "$1: $out"
  echo "$out" | grep -q "$2" || fail "$1: message lacks '$2': $out"
  expect_rc 3 "$sfit" joint --json "$tmp/$1.c3d" --parent RASIS,LASIS,LPSIS --child RTHI1
  echo "$out" | grep -q '"status":"format_error"' || fail "joint on $1: $out"
}
head -c 1000000 "$hip" > "$tmp/trunc_data.c3d";  corrupt trunc_data "truncated"
head -c 300 "$hip" > "$tmp/trunc_header.c3d";    corrupt trunc_header "shorter than the 512-byte header"
head -c 700 "$hip" > "$tmp/trunc_params.c3d";    corrupt trunc_params "parameter"
: > "$tmp/empty.c3d";                             corrupt empty "shorter than"
py '
import sys
d = sys.argv[1]
b = bytearray(open(sys.argv[2], "rb").read())
def put(name, buf): open(d + "/" + name + ".c3d", "wb").write(buf)
x = bytearray(b); x[1] = 0x51; put("bad_key", x)
x = bytearray(b); x[512 + 3] = 83; put("bad_proc", x)
x = bytearray(b[:20000]); x[0] = 200; put("bad_param_block", x)
x = bytearray(b); x[2:4] = (60000).to_bytes(2, "little"); put("bad_points", x)
x = bytearray(b); x[8:10] = (65000).to_bytes(2, "little"); put("bad_frames", x)
x = bytearray(b); x[12:16] = bytes(4)
i = x.find(b"SCALE", 512); x[i + 5 + 2 + 2:i + 5 + 2 + 2 + 4] = bytes(4); put("zero_scale", x)
x = bytearray(b); i = x.find(b"POINT", 512); x[i:i + 5] = b"PXINT"; put("no_point", x)
' "$tmp" "$hip"
corrupt bad_key "no 0x50 key"
corrupt bad_proc "processor type 83"
corrupt bad_param_block "parameter section"
corrupt bad_points "differs from the header"
# the header's frame count disagrees with POINT:FRAMES: the one the file's size supports (issue 27)
expect_rc 0 "$sfit" c3d --json "$tmp/bad_frames.c3d"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["frames"] == 1690, o["frames"]
assert o["warnings"] == ["frame count: the header says 64983, POINT:FRAMES 1690; the file holds 1690: read 1690 (POINT:FRAMES)"], o["warnings"]' "$out" \
  || fail "bad_frames: $out"
corrupt zero_scale "SCALE is 0"
corrupt no_point "no POINT group"
echo "$name: all checks passed"
