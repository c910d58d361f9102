#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# C3D in and out (issue 27, docs/c3d.md):
#  1. every failure class of the reader on a file of tests/data/c3d/cases/
#     (made by make_cases.py from the c3d.org samples) or written here: the
#     refusal's message, or the warning and the values read;
#  2. the writer's round trip on the six c3d.org format variants, the
#     two-subject file and the file with more than 255 labels: the output
#     read back by an independent reader (tests/scripts/c3d_ref.py, numpy
#     and struct) and by sfit's: every original sample, analog word and
#     parameter identical, the new points where they were put;
#  3. the TRC file read back with OpenSim's header rules;
#  4. `sfit joint ... --write`: the new point equals --trajectory.
# The two larger c3d.org files are read from ../shared/data beside the
# source tree (SFIT_SHARED_DATA overrides).
# Usage: test_cli_c3d.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
cli_setup test_cli_c3d "$build" "$src"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "python3-numpy not installed"
cases="$data/c3d/cases"
org="$data/c3d/c3d_org"
shared=${SFIT_SHARED_DATA:-$src/../shared/data}
[ -f "$shared/c3d/c3d_org/sub_labels.c3d" ] || missing "shared data not found at $shared"

json() { "$sfit" c3d --json "$1"; }

# ---------------------------------------------------------------- 1. reader
# Analog layout: the header's 16 words per frame against ANALOG:USED x rate
# ratio (64). The data section's size decides where only one layout ends the
# announced frames in its last block; where neither does, refused.
expect_rc 3 "$sfit" c3d --json "$cases/analog_ambiguous.c3d"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "format_error", o
want = ("analog layout conflict: the header says 16 analog words per frame, ANALOG:USED 16 x "
        "ANALOG:RATE 200 / POINT:RATE 50 = 64; 5 frames announced, the data section holds 11 "
        "frames of the header\u0027s layout, 8 of the parameters\u0027")
assert o["message"] == want, o["message"]; print("analog conflict refused:", o["message"])' "$out" \
  || fail "analog conflict"
expect_rc 3 "$sfit" joint --json "$cases/analog_ambiguous.c3d" --parent RFT1,RFT2,RFT3 --child RSK1
echo "$out" | grep -q "analog layout conflict" || fail "joint on the analog conflict: $out"
"$sfit" c3d "$cases/pc_int_5.c3d" --export "$tmp/pc5.csv" >/dev/null
"$sfit" c3d "$cases/analog_conflict.c3d" --export "$tmp/ac.csv" >/dev/null 2>&1
cmp -s "$tmp/pc5.csv" "$tmp/ac.csv" || fail "analog conflict decided by the data size: values differ"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["analog_words"] == 64, o
assert o["warnings"] == ["analog layout: the header says 16 analog words per frame, ANALOG:USED 16 x ANALOG:RATE 200 / POINT:RATE 50 = 64; the data section (2560 bytes) holds the 5 frames announced in the parameters\u0027 layout only: read so"], o["warnings"]
print("analog layout by the data size:", o["warnings"][0])' "$(json "$cases/analog_conflict.c3d")" || fail "analog by data size"

# A link that leads nowhere: the walk ends there when the layout's
# parameters were read before it, else refused naming the link.
"$sfit" c3d "$cases/link_end.c3d" --export "$tmp/le.csv" >/dev/null 2>&1
cmp -s "$tmp/pc5.csv" "$tmp/le.csv" || fail "link_end: values differ"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["frames"] == 5, o
assert o["warnings"] == ["parameter section: the link after ANALOG:LABELS (byte 5581) points to byte 67261, where no entry starts: the walk ends there, 47 entries read (the layout\u0027s parameters among them)"], o["warnings"]
print("walk ended:", o["warnings"][0])' "$(json "$cases/link_end.c3d")" || fail "link_end"
expect_rc 3 "$sfit" c3d --json "$cases/link_early.c3d"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "format_error", o
assert o["message"] == "parameter section: the link after ANALOG:RATE (byte 5213) points to byte 66893, where no entry starts (neither the other byte order nor the entry\u0027s length gives one), and POINT:LABELS was not read before it", o["message"]
print("walk ended early, refused:", o["message"])' "$out" || fail "link_early"

# A first parameter block that declares too few blocks: the entries run on
# to the data section and are read to there.
"$sfit" c3d "$cases/params_past_size.c3d" --export "$tmp/pp.csv" >/dev/null 2>&1
cmp -s "$tmp/pc5.csv" "$tmp/pp.csv" || fail "params_past_size: values differ"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["labels"][0] == "RFT1", o
assert o["warnings"] == ["parameter section: its first block declares 5 blocks (2560 bytes), its entries run to byte 5748, before the data section (block 13): read to there"], o["warnings"]
print("section past its size:", o["warnings"][0])' "$(json "$cases/params_past_size.c3d")" || fail "params_past_size"

# A section without groups: the header alone.
"$sfit" c3d "$cases/no_groups.c3d" --export "$tmp/ng.csv" >/dev/null 2>&1
py 'import json,sys,csv; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["points"] == 36 and o["frames"] == 5, o
assert o["warnings"] == ["parameter section: no groups (0 entries): counts, scale and rate from the header, points named POINT1, POINT2, ..."], o["warnings"]
a = [r[1:] for r in csv.reader(open(sys.argv[2]))][1:]; b = [r[1:] for r in csv.reader(open(sys.argv[3]))][1:]
assert a == b, "values"; print("no groups:", o["warnings"][0])' "$(json "$cases/no_groups.c3d")" "$tmp/ng.csv" "$tmp/pc5.csv" \
  || fail "no groups"

# Header and POINT:FRAMES both say 1149, the file ends after 5 frames and
# its last block: read 5 (the zero padding is not a frame). The header's
# 6th frame is the padding: read POINT:FRAMES's 5.
for c in frames_both_1149 frames_pad_6; do
  "$sfit" c3d "$cases/$c.c3d" --export "$tmp/$c.csv" >/dev/null 2>&1
  cmp -s "$tmp/pc5.csv" "$tmp/$c.csv" || fail "$c: values differ"
done
py 'import json,sys; a=json.loads(sys.argv[1]); b=json.loads(sys.argv[2])
assert a["frames"] == 5 and a["warnings"] == ["frame count: 1149 announced (header, POINT:FRAMES), the data section holds 6 whole frames and ends there: read 5"], a
assert b["frames"] == 5 and b["warnings"] == ["frame count: the header says 6, POINT:FRAMES 5; frames 5 to 5 of the data section are zero bytes (padding): read 5 (POINT:FRAMES)"], b
print("frames:", a["warnings"][0]); print("frames:", b["warnings"][0])' "$(json "$cases/frames_both_1149.c3d")" "$(json "$cases/frames_pad_6.c3d")" \
  || fail "frames past the data"

# The c3d.org SGI sample: POINT:LABELS links in the other byte order.
"$sfit" c3d "$cases/sgi_bad_link.c3d" --export "$tmp/sgi5.csv" >/dev/null 2>&1
cmp -s "$tmp/pc5.csv" "$tmp/sgi5.csv" || fail "SGI sample differs from the Intel one"
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["processor"] == 86
assert o["warnings"] == ["parameter section: the link after POINT:LABELS (byte 5429) reads 16129, outside the section; read as 319 (the other byte order)"], o["warnings"]
print("SGI bad link:", o["warnings"][0])' "$(json "$cases/sgi_bad_link.c3d")" || fail "SGI bad link"
for full in s02_sgi_int s02_sgi_real; do
  py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok" and o["frames"] == 89 and o["points"] == 36, o' \
    "$(json "$org/$full.c3d")" || fail "$full"
done

# Header frame count against POINT:FRAMES: the one the file's size supports.
py 'import json,sys
for a, which, src in ((sys.argv[1], "POINT:FRAMES", "POINT:FRAMES (file size)"), (sys.argv[2], "the header", "header (file size)")):
    o = json.loads(a); assert o["status"] == "ok" and o["frames"] == 5, o
    assert o["sources"]["frames"] == src, o["sources"]
    h, p = (1149, 5) if which == "POINT:FRAMES" else (5, 1149)
    assert o["warnings"] == ["frame count: the header says %d, POINT:FRAMES %d; the file holds 6: read 5 (%s)" % (h, p, which)], o["warnings"]
    print("frames:", o["warnings"][0])' "$(json "$cases/frames_header_1149.c3d")" "$(json "$cases/frames_param_1149.c3d")" \
  || fail "frame count"
for c in frames_header_1149 frames_param_1149; do
  "$sfit" c3d "$cases/$c.c3d" --export "$tmp/$c.csv" >/dev/null 2>&1
  cmp -s "$tmp/pc5.csv" "$tmp/$c.csv" || fail "$c: values differ"
done

# No parameter section: read from the header.
"$sfit" c3d "$cases/no_params.c3d" --export "$tmp/np.csv" >/dev/null 2>&1
py 'import json,sys,csv
o = json.loads(sys.argv[1]); assert o["status"] == "ok" and o["points"] == 36 and o["frames"] == 5, o
assert o["sources"]["processor"] == "header (no parameter section)" and o["parameter_section"] is False, o
assert o["labels"][:2] == ["POINT1", "POINT2"] and o["rate"] == 50, o
assert o["warnings"][0].startswith("no parameter section"), o["warnings"]
a = [r[1:] for r in csv.reader(open(sys.argv[2]))][1:]; b = [r[1:] for r in csv.reader(open(sys.argv[3]))][1:]
assert a == b, "values"
print("no parameter section:", o["warnings"][0])' "$(json "$cases/no_params.c3d")" "$tmp/np.csv" "$tmp/pc5.csv" \
  || fail "no parameter section"

# More than 65535 frames: TRIAL:ACTUAL_*_FIELD, POINT:LONG_FRAMES.
py '
import struct, sys
def write(path, extra, nframes=70000):
    e = "<"
    def ent(name, gid, body):
        return struct.pack("bb", len(name), gid) + name.encode() + struct.pack(e + "H", 2 + len(body)) + body
    def par(name, gid, typ, dims, data):
        return ent(name, gid, struct.pack("bB", typ, len(dims)) + bytes(dims) + data + b"\0")
    body = ent("POINT", -1, b"\0") + ent("TRIAL", -2, b"\0")
    body += par("USED", 1, 2, [], struct.pack(e + "h", 1))
    body += par("SCALE", 1, 4, [], struct.pack(e + "f", 0.5))
    body += par("RATE", 1, 4, [], struct.pack(e + "f", 1000.0))
    body += par("FRAMES", 1, 2, [], struct.pack(e + "H", nframes & 0xffff))
    body += par("LABELS", 1, -1, [4, 1], b"M1  ")
    body += extra
    body += b"\0\0"
    nb = (4 + len(body) + 511) // 512
    ps = bytes((1, 0x50, nb, 84)) + body
    ps += bytes(nb * 512 - len(ps))
    hdr = bytearray(512); hdr[0], hdr[1] = 2, 0x50
    hdr[2:10] = struct.pack(e + "4H", 1, 0, 1, 65535)
    hdr[12:16] = struct.pack(e + "f", 0.5); hdr[16:18] = struct.pack(e + "H", 2 + nb)
    hdr[20:24] = struct.pack(e + "f", 1000.0)
    data = b"".join(struct.pack(e + "4h", f % 1000, 7, -(f % 300), 0) for f in range(nframes))
    open(path, "wb").write(bytes(hdr) + ps + data)
def field(v): return struct.pack("<2H", v & 0xffff, v >> 16)
write(sys.argv[1], struct.pack("bb", 18, 2) + b"ACTUAL_START_FIELD" + struct.pack("<H", 2 + 8) + struct.pack("bBB", 2, 1, 2) + field(1) + b"\0"
      + struct.pack("bb", 16, 2) + b"ACTUAL_END_FIELD" + struct.pack("<H", 2 + 8) + struct.pack("bBB", 2, 1, 2) + field(70000) + b"\0")
write(sys.argv[2], struct.pack("bb", 11, 1) + b"LONG_FRAMES" + struct.pack("<H", 2 + 7) + struct.pack("bB", 4, 0) + struct.pack("<f", 70000.0) + b"\0")
' "$tmp/long_trial.c3d" "$tmp/long_point.c3d"
for v in long_trial:TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD long_point:POINT:LONG_FRAMES; do
  f=${v%%:*} src=${v#*:}
  "$sfit" c3d "$tmp/$f.c3d" --export "$tmp/$f.csv" >/dev/null
  py 'import json,sys,csv; o=json.loads(sys.argv[1]); assert o["frames"] == 70000 and o["sources"]["frames"] == sys.argv[2], o
rows = list(csv.reader(open(sys.argv[3])))
assert len(rows) == 70001 and rows[-1] == ["69999", "499.5", "3.5", "-49.5"], rows[-1]
print("70000 frames from", sys.argv[2])' "$(json "$tmp/$f.c3d")" "$src" "$tmp/$f.csv" || fail "$f"
done

# Header scale against POINT:SCALE: a warning, POINT:SCALE used.
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["status"] == "ok"
assert o["warnings"] == ["the header\u0027s scale 0.5 differs from POINT:SCALE 0.281182: POINT:SCALE used"], o["warnings"]
assert o["sources"]["scale"] == "POINT:SCALE (the header differs)"' "$(json "$cases/scale_mismatch.c3d")" \
  || fail "scale mismatch"
"$sfit" c3d "$cases/scale_mismatch.c3d" --export "$tmp/sm.csv" >/dev/null 2>&1
cmp -s "$tmp/pc5.csv" "$tmp/sm.csv" || fail "scale mismatch: values differ"

# A marker at exactly (0, 0, 0) with a valid residual: a warning; joint and
# skeleton take it as missing.
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["zero_samples"] == 2, o
assert o["warnings"][0].startswith("2 samples of 1 markers at exactly (0, 0, 0) with a valid residual"), o["warnings"]' \
  "$(json "$cases/zero_marker.c3d")" || fail "zero marker warning"
hip="$data/c3d/biobuddy_right_hip.c3d"
py '
import sys, struct
b = bytearray(open(sys.argv[1], "rb").read())
# RTHI1 is point 68 (0-based 67) of 73; float storage; frames 100..139 zeroed (x, y, z), residual kept
p = (b[0] - 1) * 512; npts = struct.unpack("<H", b[2:4])[0]; nan = struct.unpack("<H", b[4:6])[0]
dblock = struct.unpack("<H", b[16:18])[0]; fb = (4 * npts + nan) * 4
import c3d_ref
r = c3d_ref.read(sys.argv[1]); k = r["labels"].index("RTHI1")
for f in range(100, 140):
    o = (dblock - 1) * 512 + f * fb + k * 16
    b[o:o + 12] = bytes(12)
open(sys.argv[2], "wb").write(b)
' "$hip" "$tmp/hip_zero.c3d"
parent=RASIS,LASIS,LPSIS,RPSIS child=RTHI1,RTHI2,RTHI3,RLFE,RMFE
"$sfit" joint "$tmp/hip_zero.c3d" --parent $parent --child $child --json >"$tmp/z.json" 2>"$tmp/z.err"
grep -q "40 samples of 1 markers at exactly (0, 0, 0)" "$tmp/z.err" || fail "joint: no zero warning: $(cat "$tmp/z.err")"
py 'import json,sys; o=json.load(open(sys.argv[1])); m={x["name"]: x["n"] for x in o["markers"]}
assert m["RTHI1"] == 1690 - 40 and m["RTHI2"] == 1690, m; print("zero marker: taken as missing in 40 frames")' "$tmp/z.json" \
  || fail "joint: zero marker"

# Duplicate labels: renamed LABEL#2, LABEL#3, each selectable.
py 'import json,sys; o=json.loads(sys.argv[1]); assert o["labels"][:3] == ["RFT1", "RFT1#2", "RFT1#3"], o["labels"][:4]
assert o["warnings"] == ["duplicate labels: 2 renamed LABEL#2, LABEL#3, ... in point order; first: RFT1 (points 1 and 2) -> RFT1#2"], o["warnings"]' \
  "$(json "$cases/dup_labels.c3d")" || fail "duplicate labels"
"$sfit" c3d "$cases/dup_labels.c3d" --export "$tmp/dup.csv" --markers RFT1#2,RFT1#3 >/dev/null 2>&1
"$sfit" c3d "$cases/pc_int_5.c3d" --export "$tmp/nodup.csv" --markers RFT2,RFT3 >/dev/null
[ "$(cut -d, -f2- "$tmp/dup.csv" | tail -n +2)" = "$(cut -d, -f2- "$tmp/nodup.csv" | tail -n +2)" ] \
  || fail "duplicate labels: values of RFT1#2, RFT1#3"

# --export past 256 markers: every marker.
py 'import sys, mocap_ref as m
m.write_c3d(sys.argv[1], ["M%d" % i for i in range(300)], [[(float(i), 2.0, 3.0) for i in range(300)]] * 3)' "$tmp/m300.c3d"
"$sfit" c3d "$tmp/m300.c3d" --export "$tmp/m300.csv" >/dev/null
[ "$(head -1 "$tmp/m300.csv" | tr , '\n' | wc -l)" -eq 901 ] || fail "--export of 300 markers"
[ "$(tail -1 "$tmp/m300.csv" | cut -d, -f899-901)" = "299,2,3" ] || fail "--export: marker 300"

# ----------------------------------------------------------- 2. round trip
# Two points: A everywhere but every 7th frame, B with one coordinate blank
# (missing) in every frame but even ones.
mkadd() { # mkadd C3D OUT.csv [BIG]: the points to add, from the frame count
  py '
import json, sys, subprocess
o = json.loads(subprocess.check_output([sys.argv[3], "c3d", "--json", sys.argv[1]]))
big = len(sys.argv) > 4
with open(sys.argv[2], "w") as f:
    f.write("frame,NEWA_X,NEWA_Y,NEWA_Z,NEWB_X,NEWB_Y,NEWB_Z\n")
    for i in range(o["frames"]):
        if i % 7 == 3:
            continue
        a = (100.0 + 0.37 * i, -200.25 + (1e5 if big and i == 5 else 0.0), 300.0 + i)
        b = (i * 1.5, 10.0, -5.0) if i % 2 == 0 else (i * 1.5, "", -5.0)
        f.write("%d,%r,%r,%r,%s,%s,%s\n" % ((i,) + a + b))
' "$1" "$2" "$sfit" ${3:-}
}
check() { # check ORIG NEW ADD.csv PREFIX: the independent reader and sfit's
  py '
import sys, csv, json, subprocess, numpy as np, c3d_ref
orig, new, addcsv, prefix, sfit = sys.argv[1:6]
a, b = c3d_ref.read(orig), c3d_ref.read(new)
rows = list(csv.reader(open(addcsv)))
xyz = np.full((a["nframes"], 2, 3), np.nan)
for r in rows[1:]:
    v = [float(c) if c != "" else np.nan for c in r[1:]]
    xyz[int(r[0])] = np.array(v).reshape(2, 3)
xyz[np.isnan(xyz).any(axis=2)] = np.nan
worst = c3d_ref.check_added(a, b, ["NEWA", "NEWB"], xyz, prefix)
# sfit reads the new file: labels, the original samples and the new points
o = json.loads(subprocess.check_output([sfit, "c3d", "--json", new]))
assert o["status"] == "ok" and o["points"] == a["npoints"] + 2 and o["frames"] == a["nframes"], o
assert o["labels"][-2:] == [prefix + "NEWA", prefix + "NEWB"], o["labels"][-2:]
subprocess.check_output([sfit, "c3d", new, "--export", new + ".csv"])
got = np.array([[float(c) if c != "" else np.nan for c in r[1:]] for r in list(csv.reader(open(new + ".csv")))[1:]])
got = got.reshape(a["nframes"], -1, 3)
want = np.where(b["residual"][:, :, None] < 0, np.nan, b["xyz"])
assert np.allclose(got, want, rtol=1e-7, atol=0, equal_nan=True), "sfit vs the independent reader"
print("round trip %s: %d points, %d frames, %d analog words/frame, word %d -> %d, %d labels, new points max err %.3g"
      % (orig.split("/")[-1], a["npoints"], a["nframes"], a["analog"].shape[1], a["word"], b["word"], len(b["all_labels"]), worst))
' "$1" "$2" "$3" "$4" "$sfit" || fail "round trip $(basename "$1")"
}
for f in "$org"/s02_pc_int.c3d "$org"/s02_dec_int.c3d "$org"/s02_sgi_int.c3d \
         "$org"/s02_pc_real.c3d "$org"/s02_dec_real.c3d "$org"/s02_sgi_real.c3d \
         "$shared/c3d/c3d_org/opensim_task_labels2.c3d"; do
  b=$(basename "$f" .c3d)
  mkadd "$f" "$tmp/$b.add.csv"
  "$sfit" c3d "$f" --add "$tmp/$b.add.csv" --write "$tmp/$b.out.c3d" >/dev/null 2>&1
  check "$f" "$tmp/$b.out.c3d" "$tmp/$b.add.csv" ""
done
# two subjects: the prefix given; integer storage that cannot hold a new point: float
sub="$shared/c3d/c3d_org/sub_labels.c3d"
mkadd "$sub" "$tmp/sub.add.csv"
"$sfit" c3d "$sub" --add "$tmp/sub.add.csv" --write "$tmp/sub.out.c3d" --prefix Matt: >/dev/null 2>&1
check "$sub" "$tmp/sub.out.c3d" "$tmp/sub.add.csv" "Matt:"
mkadd "$org/s02_dec_int.c3d" "$tmp/big.add.csv" big
"$sfit" c3d "$org/s02_dec_int.c3d" --add "$tmp/big.add.csv" --write "$tmp/big.out.c3d" >/dev/null 2>"$tmp/big.err"
grep -q "written with float storage" "$tmp/big.err" || fail "no float note: $(cat "$tmp/big.err")"
check "$org/s02_dec_int.c3d" "$tmp/big.out.c3d" "$tmp/big.add.csv" ""
# every label with one subject prefix: carried to the new points by default
py 'import sys, mocap_ref as m
m.write_c3d(sys.argv[1], ["P01:A", "P01:B", "P01:C"], [[(1.0, 2.0, 3.0), (4.0, 5.0, 6.0), None]] * 4, proc=m.MIPS, scale=0.25, nanalog=2)' "$tmp/p01.c3d"
mkadd "$tmp/p01.c3d" "$tmp/p01.add.csv"
"$sfit" c3d "$tmp/p01.c3d" --add "$tmp/p01.add.csv" --write "$tmp/p01.out.c3d" >/dev/null
check "$tmp/p01.c3d" "$tmp/p01.out.c3d" "$tmp/p01.add.csv" "P01:"

# ------------------------------------------------------------------ 3. TRC
"$sfit" c3d "$org/s02_pc_real.c3d" --add "$tmp/s02_pc_real.add.csv" --write "$tmp/x.c3d" --trc "$tmp/x.trc" >/dev/null
py '
import sys, numpy as np, c3d_ref
t = c3d_ref.read_trc(sys.argv[1]); n = c3d_ref.read(sys.argv[2])
m = t["meta"]
assert float(m["DataRate"]) == 50 and float(m["CameraRate"]) == 50 and int(m["NumFrames"]) == 89, m
assert int(m["NumMarkers"]) == 38 and m["Units"] == "mm" and int(m["OrigDataStartFrame"]) == 1 and int(m["OrigNumFrames"]) == 89, m
assert t["names"] == n["labels"], (t["names"][-3:], n["labels"][-3:])
assert t["frames"] == list(range(1, 90)) and np.allclose(t["times"], np.arange(89) / 50.0, rtol=0, atol=1e-12)
want = np.where(n["residual"][:, :, None] < 0, np.nan, n["xyz"])
assert np.allclose(t["xyz"], want, rtol=1e-7, atol=0, equal_nan=True)
print("TRC: 38 markers x 89 frames equal the C3D (%d missing cells)" % np.isnan(t["xyz"]).sum())
' "$tmp/x.trc" "$tmp/x.c3d" || fail "TRC"

# ------------------------------------------------------- 4. joint --write
"$sfit" joint "$hip" --parent $parent --child $child --trajectory "$tmp/traj.csv" --frames 0:1399 \
  --write "$tmp/hipjc.c3d" --trc "$tmp/hipjc.trc" --json >/dev/null
py '
import sys, csv, numpy as np, c3d_ref
a, b = c3d_ref.read(sys.argv[1]), c3d_ref.read(sys.argv[2])
traj = {int(r[0]): [float(v) for v in r[1:]] for r in list(csv.reader(open(sys.argv[3])))[1:]}
xyz = np.full((a["nframes"], 1, 3), np.nan)
for f, v in traj.items():
    xyz[f, 0] = v
worst = c3d_ref.check_added(a, b, ["JC"], xyz)
assert worst == 0.0 and len(traj) == 1400, (worst, len(traj))
assert np.all(b["residual"][1400:, -1] == -1)
t = c3d_ref.read_trc(sys.argv[4]); assert t["names"][-1] == "JC"
assert np.allclose(t["xyz"][:1400, -1], xyz[:1400, 0], rtol=1e-7, atol=0)
print("joint --write: JC equals --trajectory in all 1400 frames (max diff %g); frames 1400-1689 residual -1" % worst)
' "$hip" "$tmp/hipjc.c3d" "$tmp/traj.csv" "$tmp/hipjc.trc" || fail "joint --write"
# a hinge: the centre and two points on the axis, 100 mm either side
knee="$data/c3d/biobuddy_right_knee.c3d"
"$sfit" joint "$knee" --parent RTHI1,RTHI2,RTHI3,RLFE,RMFE --child RATT,RLM,RSPH,RLEG1,RLEG2,RLEG3 \
  --mode planar --name KJC --write "$tmp/knee.c3d" --trajectory "$tmp/ktraj.csv" >/dev/null
py '
import sys, csv, numpy as np, c3d_ref
b = c3d_ref.read(sys.argv[1]); assert b["labels"][-3:] == ["KJC", "KJC_AX1", "KJC_AX2"], b["labels"][-3:]
traj = {int(r[0]): [float(v) for v in r[1:]] for r in list(csv.reader(open(sys.argv[2])))[1:]}
for f, v in traj.items():
    c, p, q = b["xyz"][f, -3], b["xyz"][f, -2], b["xyz"][f, -1]
    assert np.allclose(c, v, rtol=1e-7, atol=0)
    assert abs(np.linalg.norm(p - c) - 100) < 1e-3 and abs(np.linalg.norm(q - c) - 100) < 1e-3
    assert np.linalg.norm((p + q) / 2 - c) < 1e-3
print("hinge --write: KJC and KJC_AX1/AX2 100 mm either side on the axis in %d frames" % len(traj))
' "$tmp/knee.c3d" "$tmp/ktraj.csv" || fail "hinge --write"

# A header that says frames 0..N while POINT:FRAMES says N (as OptiTrack
# Motive writes): the file holds N frames and a last block whose zero
# padding is longer than a frame. sfit reads N; `joint --write` writes N
# frames with a header and a POINT:FRAMES that say N, so a reader that
# trusts the header's first and last frame (py-c3d), one that trusts
# POINT:FRAMES (c3d_ref's strict mode) and sfit all read N.
arm="$shared/c3d/unlabeled/arm-4-4-4_clean_30fps.c3d"
py '
import sys, struct, c3d_ref
b = bytearray(open(sys.argv[1], "rb").read()); r = c3d_ref.read(sys.argv[1])
n, fb = r["nframes"], (4 * r["npoints"] + r["analog"].shape[1]) * r["word"]
end = (r["data_block"] - 1) * 512 + n * fb
b = b[:end] + bytes(512 + (-end) % 512)       # padding longer than a frame
assert len(b) - end >= fb and len(b) % 512 == 0
b[6:10] = struct.pack("<2H", 0, n)            # the header: frames 0..N
open(sys.argv[2], "wb").write(bytes(b))
print("motive-like input: header frames 0..%d, POINT:FRAMES %d, %d bytes of padding (frame %d bytes)" % (n, n, len(b) - end, fb))
' "$arm" "$tmp/motive.c3d"
"$sfit" joint "$tmp/motive.c3d" --parent M000,M001,M002,M003 --child M004,M005,M006,M007 \
  --write "$tmp/motive_jc.c3d" >/dev/null 2>"$tmp/motive.err"
py '
import sys, json, subprocess, c3d_ref
a = json.loads(subprocess.check_output([sys.argv[3], "c3d", "--json", sys.argv[1]]))
assert a["frames"] == 1831 and a["warnings"][0] == "frame count: the header says 1832, POINT:FRAMES 1831; frames 1831 to 1831 of the data section are zero bytes (padding): read 1831 (POINT:FRAMES)", a
w = c3d_ref.read(sys.argv[2])                 # POINT:FRAMES, strict
hdr = w["words"][4] - w["words"][3] + 1       # the header alone
b = json.loads(subprocess.check_output([sys.argv[3], "c3d", "--json", sys.argv[2]]))
assert (w["nframes"], hdr, b["frames"]) == (1831, 1831, 1831), (w["nframes"], hdr, b["frames"])
assert b["labels"][-1] == "JC" and b["warnings"] == [], b["warnings"]
print("joint --write on the motive-like file: 1831 frames by POINT:FRAMES, by the header (%d..%d) and by sfit" % (w["words"][3], w["words"][4]))
' "$tmp/motive.c3d" "$tmp/motive_jc.c3d" "$sfit" || fail "motive-like frame count"

# Options: --write needs a C3D file; --add and --write together.
expect_usage "--add and --write go together (--prefix with them)" c3d "$hip" --add "$tmp/traj.csv"
"$sfit" c3d "$hip" --export "$tmp/wide.csv" --markers $parent,$child >/dev/null
expect_rc 3 "$sfit" joint "$tmp/wide.csv" --parent $parent --child $child --write "$tmp/no.c3d"
grep -q "need a C3D file" "$tmp/stderr" || fail "joint --write on a table: $(cat "$tmp/stderr")"
echo "$name: all checks passed"
