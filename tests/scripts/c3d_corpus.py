# SPDX-License-Identifier: MIT
"""The C3D corpus check (tests/scripts/test_c3d_corpus.sh; not a test by
itself): every file of ../shared/data/c3d/corpus/MANIFEST.tsv, and the other
shared recordings, read by `sfit c3d` and by the independent reader
c3d_ref.py (its non-strict mode: the repairs docs/c3d.md lists), then
written back with a point added and read again by both.

For a file the manifest calls `identical`: sfit reads it (exit 0), with the
manifest's frames x points, the independent reader's labels and every
sample bit for bit (float32; NaN where the residual is negative). For a
`refuse` file: sfit exits 3 with a format_error whose message names the
conflict with its numbers, and the independent reader refuses too. Every
file read is written back with `--add` (a point missing in some frames):
the strict independent reader (the plain format, no repair) and sfit read
the written file with the same frame count, the original samples unchanged
and the new point where it was put.

Usage: c3d_corpus.py SFIT SHARED_DATA_DIR TMP_DIR
Prints one line per file and the counts; exits 1 on any wrong read, crash
or failed write-back.
"""
import csv
import hashlib
import json
import os
import re
import subprocess
import sys

import numpy as np

import c3d_ref

NEW = "CORPUS_NEW"


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if p.returncode < 0 or p.returncode not in (0, 3):
        raise RuntimeError("crash: %s exited %d: %s" % (cmd[:3], p.returncode, p.stderr[-300:]))
    return p.returncode, p.stdout.decode()


def norm_labels(labels, n):
    """The labels as sfit names them: blanks and NULs trimmed both sides,
    non-printable characters '?', at most 63 characters, an empty one
    POINTk, and the second and later copies of a label LABEL#2, LABEL#3."""
    out = []
    for k in range(n):
        s = labels[k] if k < len(labels) else ""
        s = s.strip(" \0")
        s = "".join(c if 0x20 <= ord(c) < 0x7f else "?" for c in s)[:63]
        out.append(s if s else "POINT%d" % (k + 1))
    seen = {}
    for k, s in enumerate(out):
        seen[s] = seen.get(s, 0) + 1
        if seen[s] > 1:
            out[k] = "%.51s#%d" % (s, seen[s])
    return out


def export(sfit, path, csv_path):
    run([sfit, "c3d", path, "--export", csv_path])
    rows = list(csv.reader(open(csv_path)))
    vals = np.array([[np.float32(c) if c != "" else np.nan for c in r[1:]] for r in rows[1:]],
                    dtype=np.float64)
    return rows[0], vals


def want_xyz(r):
    valid = r["residual"] >= 0  # NaN residual: invalid
    return np.where(valid[:, :, None], r["xyz"].astype(np.float32).astype(np.float64), np.nan)


def same(a, b):
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


def check_read(sfit, path, tmp, frames_points):
    """sfit against the independent reader on one file; returns (ref, json)."""
    rc, out = run([sfit, "c3d", "--json", path])
    o = json.loads(out)
    assert rc == 0 and o["status"] == "ok", "sfit refused: %s" % o.get("message")
    r = c3d_ref.read(path, strict=False)
    if frames_points is not None:
        assert (o["frames"], o["points"]) == frames_points, \
            "sfit %dx%d, the manifest %dx%d" % ((o["frames"], o["points"]) + frames_points)
    assert (o["frames"], o["points"]) == (r["nframes"], r["npoints"]), \
        "sfit %dx%d, the independent reader %dx%d" % (o["frames"], o["points"], r["nframes"], r["npoints"])
    labels = norm_labels(r["labels"], r["npoints"])
    assert o["labels"] == labels, "labels differ: %s" % [
        (a, b) for a, b in zip(o["labels"], labels) if a != b][:3]
    _, got = export(sfit, path, os.path.join(tmp, "x.csv"))
    got = got.reshape(r["nframes"], r["npoints"], 3) if r["npoints"] else got
    if r["npoints"]:
        want = want_xyz(r)
        bad = ~((got == want) | (np.isnan(got) & np.isnan(want)))
        assert not bad.any(), "%d samples differ, first at %s: sfit %s, reader %s" % (
            bad.sum(), np.argwhere(bad)[0], got[tuple(np.argwhere(bad)[0])],
            want[tuple(np.argwhere(bad)[0])])
    return r, o


def check_write(sfit, path, tmp, r, o):
    """Write back with one point added; read by both readers."""
    n = r["nframes"]
    xyz = np.full((n, 1, 3), np.nan)
    add = os.path.join(tmp, "add.csv")
    with open(add, "w") as f:
        f.write("frame,%s_X,%s_Y,%s_Z\n" % (NEW, NEW, NEW))
        for i in range(n):
            if i % 11 == 5:
                continue
            v = (1.0 + 0.5 * (i % 100), -2.25, 3.0 + i % 7)
            xyz[i, 0] = v
            f.write("%d,%r,%r,%r\n" % ((i,) + v))
    outp = os.path.join(tmp, "out.c3d")
    rc, txt = run([sfit, "c3d", path, "--add", add, "--write", outp])
    assert rc == 0, "write refused: %s" % txt[-300:]
    rc, out = run([sfit, "c3d", "--json", outp])
    b = json.loads(out)
    assert rc == 0 and b["status"] == "ok", b
    assert (b["frames"], b["points"]) == (n, r["npoints"] + 1), \
        "sfit reads the written file %dx%d, %dx%d written" % (b["frames"], b["points"], n, r["npoints"] + 1)
    assert b["labels"][-1].endswith(NEW), b["labels"][-1]
    w = c3d_ref.read(outp, strict=True)
    assert (w["nframes"], w["npoints"]) == (n, r["npoints"] + 1), \
        "the independent reader reads the written file %dx%d" % (w["nframes"], w["npoints"])
    prefix = b["labels"][-1][:-len(NEW)]
    if r["groups"]:
        c3d_ref.check_added(r, w, [NEW], xyz, prefix)
    else:  # no POINT group before: written with one; samples and analog kept
        assert np.array_equal(w["raw_points"][:, :r["npoints"]], r["raw_points"], equal_nan=True) \
            if w["word"] == r["word"] else same(want_xyz(w)[:, :r["npoints"]], want_xyz(r))
        assert np.array_equal(w["analog"], r["analog"], equal_nan=True)
    _, got = export(sfit, outp, os.path.join(tmp, "y.csv"))
    got = got.reshape(n, r["npoints"] + 1, 3)
    assert same(got, want_xyz(w)), "sfit and the independent reader differ on the written file"
    tol = 0.0 if w["word"] == 4 else abs(w["scale"]) / 2 * 1.0001
    err = np.nanmax(np.abs(got[:, -1] - xyz[:, 0]))
    assert np.array_equal(np.isnan(got[:, -1]), np.isnan(xyz[:, 0])) and err <= tol, (err, tol)


def main():
    sfit, shared, tmp = sys.argv[1:4]
    corpus = os.path.join(shared, "c3d", "corpus")
    rows = []
    for line in open(os.path.join(corpus, "MANIFEST.tsv")):
        if line.startswith("#") or not line.strip():
            continue
        f = line.rstrip("\n").split("\t")
        fp = tuple(int(v) for v in f[6].split("x"))
        rows.append((f[0] + ".c3d", corpus, f[1], f[4], f[5], fp))
    listed = set(r[0] for r in rows)
    on_disk = set(f for f in os.listdir(corpus) if f.lower().endswith(".c3d"))
    assert rows and on_disk == listed, "the manifest and the corpus differ: %s" % sorted(on_disk ^ listed)
    # the other shared recordings (systems outside the corpus)
    base = os.path.join(shared, "c3d")
    for sub in ("", "c3d_org", "cmu", "unlabeled", "lower_limb_session"):
        d = os.path.join(base, sub)
        for name in sorted(os.listdir(d)) if os.path.isdir(d) else []:
            if name.lower().endswith(".c3d") and not (sub == "c3d_org" and name.startswith(("s02_", "sub_"))):
                rows.append((name, d, sub or "biobuddy", None, "identical", None))
    counts = {"identical": 0, "refused": 0, "wrong": 0, "crash": 0, "write": 0}
    failures = []
    for name, d, system, sha, expect, fp in rows:
        path = os.path.join(d, name)
        tag = "%s (%s)" % (os.path.relpath(path, shared), system)
        try:
            if sha is not None:
                h = hashlib.sha256(open(path, "rb").read()).hexdigest()
                assert h == sha, "sha256 %s, the manifest %s" % (h, sha)
            if expect == "refuse":
                rc, out = run([sfit, "c3d", "--json", path])
                o = json.loads(out)
                assert rc == 3 and o["status"] == "format_error", "read, the manifest says refuse"
                msg = o["message"]
                assert re.search(r"conflict|differs|disagree", msg) and len(re.findall(r"\d+", msg)) >= 2, \
                    "the refusal names no conflict with its numbers: " + msg
                try:
                    c3d_ref.read(path, strict=False)
                    raise AssertionError("the independent reader reads it")
                except ValueError:
                    pass
                counts["refused"] += 1
                print("refused    %s: %s" % (tag, msg))
                continue
            r, o = check_read(sfit, path, tmp, fp)
            counts["identical"] += 1
            check_write(sfit, path, tmp, r, o)
            counts["write"] += 1
            print("identical  %s: %d frames x %d points, %d warnings; written back +1 point, %d frames"
                  % (tag, r["nframes"], r["npoints"], len(o["warnings"]), r["nframes"]))
        except RuntimeError as e:
            counts["crash"] += 1
            failures.append("%s: %s" % (tag, e))
            print("CRASH      %s: %s" % (tag, e))
        except (AssertionError, ValueError, KeyError, IndexError) as e:
            counts["wrong"] += 1
            failures.append("%s: %s" % (tag, e))
            print("WRONG      %s: %s: %s" % (tag, type(e).__name__, e))
    print("c3d corpus: %d files: %d identical (%d written back and read again), %d refused, "
          "%d wrong, %d crash" % (len(rows), counts["identical"], counts["write"], counts["refused"],
                                  counts["wrong"], counts["crash"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
