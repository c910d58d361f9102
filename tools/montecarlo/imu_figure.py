#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""docs/figures/imu_errors.svg: the error of the joint position of
`sfit imu-joint` against the size its covariance predicts, over synthetic
hip-like trials (tests/test_imu --write-csv, seeds 5000..5000+N-1), and
the summary line printed for docs/imu.md.

    python3 tools/montecarlo/imu_figure.py BUILD_DIR [N] > docs/figures/imu_errors.svg
"""
import json
import math
import os
import subprocess
import sys
import tempfile

build = sys.argv[1]
n = int(sys.argv[2]) if len(sys.argv) > 2 else 40
gen = os.path.join(build, "tests", "test_imu")
cli = os.path.join(build, "bin", "sfit")
pts = []
with tempfile.TemporaryDirectory() as tmp:
    csv = os.path.join(tmp, "t.csv")
    for seed in range(5000, 5000 + n):
        truth = json.loads(subprocess.run([gen, "--write-csv", csv, "ball", str(seed)], check=True,
                                          capture_output=True, text=True).stdout)
        o = json.loads(subprocess.run([cli, "imu-joint", "--json", csv], check=True,
                                      capture_output=True, text=True).stdout)
        for k in ("r1", "r2"):
            err = math.dist(o[k], truth[k]) * 1e3
            sd = math.sqrt(sum(o[k + "_cov"][i][i] for i in range(3)) / 3.0) * 1e3
            pts.append((sd, err, o["flags"]["untrusted"]))

W, H, M = 520, 360, 50
xmax = max(p[0] for p in pts) * 1.15
ymax = max(max(p[1] for p in pts), 10.0) * 1.1


def X(v):
    return M + (W - 2 * M) * v / xmax


def Y(v):
    return H - M - (H - 2 * M) * v / ymax


out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" '
       'font-size="12">' % (W, H),
       '<rect width="100%" height="100%" fill="white"/>',
       '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="black"/>' % (M, H - M, W - M, H - M),
       '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="black"/>' % (M, H - M, M, M),
       # 10 mm: the accuracy asked for; 2.8 sd: the 95 % radius of a 3-D Gaussian
       '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="#c00" stroke-dasharray="4 3"/>'
       % (M, Y(10), W - M, Y(10)),
       '<text x="%g" y="%g" fill="#c00">10 mm</text>' % (W - M - 40, Y(10) - 4),
       '<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="#06c" stroke-dasharray="2 2"/>'
       % (X(0), Y(0), X(min(xmax, ymax / 2.8)), Y(2.8 * min(xmax, ymax / 2.8))),
       '<text x="%g" y="%g" fill="#06c">error = 2.8 SD (95 %% radius)</text>'
       % (X(min(xmax, ymax / 2.8)) - 170, Y(2.8 * min(xmax, ymax / 2.8)) + 14),
       '<text x="%g" y="%g" text-anchor="middle">predicted SD per axis (sqrt(trace / 3) of the covariance), mm'
       '</text>' % (W / 2, H - 12),
       '<text x="14" y="%g" transform="rotate(-90 14 %g)" text-anchor="middle">error, mm</text>'
       % (H / 2, H / 2)]
for t in range(0, int(xmax) + 1):
    out.append('<text x="%g" y="%g" text-anchor="middle">%d</text>' % (X(t), H - M + 16, t))
for t in range(0, int(ymax) + 1, 2):
    out.append('<text x="%g" y="%g" text-anchor="end">%d</text>' % (M - 4, Y(t) + 4, t))
for sd, err, bad in pts:
    out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s" fill-opacity="0.7"/>'
               % (X(sd), Y(err), "#999" if bad else "#222"))
out.append('<text x="%g" y="20" text-anchor="middle">sfit imu-joint: %d hip-like trials, r1 and r2'
           '</text>' % (W / 2, n))
out.append("</svg>")
print("\n".join(out))
good = sum(1 for sd, e, b in pts if e < 10.0)
inside = sum(1 for sd, e, b in pts if e < 2.8 * sd)
print("imu_figure: %d positions, %d within 10 mm, %d within 2.8 SD, %d untrusted"
      % (len(pts), good, inside, sum(1 for p in pts if p[2])), file=sys.stderr)
