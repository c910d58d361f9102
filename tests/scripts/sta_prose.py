#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The soft-tissue benchmark's summary in docs/joint_benchmark.md is the
measured one: each of its three ball rows (rigid, per-marker, noise only)
states the unflagged counts, the per-cell coverage range and overall
coverage, the median d'C^-1 d range and the mean error range that
docs/figures/sta_bench.csv (written by tools/montecarlo/sta_bench.c) holds,
to the digits written.

Usage: sta_prose.py SOURCE_DIR   (exit 1 and a message on a mismatch)
"""
import csv
import re
import sys

ROWS = {
    "rigid cluster motion": "rigid",
    "per-marker motion + drift": "marker",
    "marker noise only": "none",
}


def near(text, value):
    """text (as written, e.g. '93.6' or '23') equals value to its digits."""
    dec = len(text.split(".")[1]) if "." in text else 0
    return abs(float(text) - value) <= 0.5 * 10 ** -dec + 1e-9


def measured(rows):
    cov = [float(r["coverage"]) * 100 for r in rows]
    return {
        "unfl": (min(int(r["unflagged"]) for r in rows), max(int(r["unflagged"]) for r in rows)),
        "trials": int(rows[0]["trials"]),
        "cov": (min(cov), max(cov)),
        "all": 100.0 * sum(int(r["covered"]) for r in rows) / sum(int(r["unflagged"]) for r in rows),
        "med": (min(float(r["med_d2"]) for r in rows), max(float(r["med_d2"]) for r in rows)),
        "err": (min(float(r["mean_err"]) for r in rows), max(float(r["mean_err"]) for r in rows)),
    }


def pair(text):
    m = re.fullmatch(r"\s*([0-9.]+)(?:-([0-9.]+))?\s*", text)
    if not m:
        return None
    return m.group(1), m.group(2) or m.group(1)


def check(src):
    with open(f"{src}/docs/figures/sta_bench.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["cell"].startswith("ball ")]
    doc = open(f"{src}/docs/joint_benchmark.md").read()
    errs = []
    for label, sta in ROWS.items():
        cells = [r for r in rows if r["sta"] == sta]
        line = next((ln for ln in doc.splitlines() if ln.startswith(f"| {label}, ")), None)
        if line is None or not cells:
            errs.append(f"no summary row or no cells for '{label}'")
            continue
        meas = measured(cells)
        col = [c.strip() for c in line.strip("|").split("|")]
        want = re.match(r"(\d+) cells", col[0].split(", ")[1])
        if not want or int(want.group(1)) != len(cells):
            errs.append(f"{label}: {col[0]!r} but {len(cells)} cells")
        m = re.match(r"([0-9]+)(?:-([0-9]+))? of ([0-9]+)", col[1])
        got = (int(m.group(1)), int(m.group(2) or m.group(1)), int(m.group(3))) if m else None
        if got != (meas["unfl"][0], meas["unfl"][1], meas["trials"]):
            errs.append(f"{label}: unflagged {col[1]!r}, measured {meas['unfl']} of {meas['trials']}")
        m = re.match(r"([0-9.]+)-([0-9.]+) %(?: \(all: ([0-9.]+) %\))?", col[2])
        if not m or not (near(m.group(1), meas["cov"][0]) and near(m.group(2), meas["cov"][1])) \
                or (m.group(3) and not near(m.group(3), meas["all"])):
            errs.append(f"{label}: coverage {col[2]!r}, measured {meas['cov'][0]:.2f}-"
                        f"{meas['cov'][1]:.2f} % (all {meas['all']:.2f} %)")
        for key, text in (("med", col[3]), ("err", col[4].replace(" mm", ""))):
            p = pair(text)
            if p is None or not (near(p[0], meas[key][0]) and near(p[1], meas[key][1])):
                errs.append(f"{label}: {key} {text!r}, measured {meas[key][0]:.3g}-{meas[key][1]:.3g}")
    return errs


def main(argv):
    src = argv[1] if len(argv) > 1 else "."
    errs = check(src)
    for e in errs:
        print(f"sta_prose: {e}", file=sys.stderr)
    if not errs:
        print("sta_prose: the soft-tissue summary matches docs/figures/sta_bench.csv")
    return 1 if errs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
