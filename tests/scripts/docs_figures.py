#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Every cost figure the prose of README.md and docs/*.md quotes is the
measured one.

    docs_figures.py SOURCE_DIR FLOPCOUNT_JSON FOOTPRINT_TXT
    docs_figures.py --selftest SOURCE_DIR FLOPCOUNT_JSON FOOTPRINT_TXT

FLOPCOUNT_JSON is `tools/flopcount/run.sh --json`, FOOTPRINT_TXT the
footprint record it leaves in BUILD/m4f/footprint.txt. Outside the
generated blocks (<!-- flopcount:begin --> ... end, cores) and code
fences, a figure cites its row in one of these forms, and must equal it:

    114 FLOPs (`solve_gdke`)             flops of the row
    756 M4F instructions (`solve_gdke`)  insns ("instructions" also)
    1390 estimated cycles (`solve_gdke`) cycles_est
    304 B stack (`solve_gdke`)           stack_O2 (worst case at -O2)
    4034 B (`code -Os minimal_app`)      footprint code record, -Os or -O2
    596 B (`part -Os minimal_app_screened screen`)
                                         footprint part record (an
                                         application's bytes by part)

A number is compared as written (thousands commas dropped; a decimal
figure to the decimals it shows). A line that names a cost row in
backticks next to a number with one of these units, not in a citation
form, fails too (an uncited copy of a table figure; a limit, "at most N
...", is not a copy). --selftest checks
that the check fails on drifted copies of the docs.
"""
import glob
import json
import os
import re
import shutil
import sys
import tempfile

UNITS = {"FLOPs": "flops", "M4F instructions": "insns", "instructions": "insns",
         "estimated cycles": "cycles_est", "B stack": "stack_O2"}
NUM = r"(\d[\d,]*(?:\.\d+)?)"
# a citation may be broken over lines: any white space between its words
CITE = re.compile(NUM + r"\s+(FLOPs|M4F\s+instructions|instructions|estimated\s+cycles|B\s+stack)"
                  r"\s+\(`(\w+)`\)")
SIZE = re.compile(NUM + r"\s+B\s+\(`code\s+(-Os|-O2)\s+(\w+)`\)")
PART = re.compile(NUM + r"\s+B\s+\(`part\s+(-Os|-O2)\s+(\w+)\s+(\w+)`\)")
BARE = re.compile(r"\b\d[\d,]*(?:\.\d+)? (?:FLOPs|M4F instructions|instructions|"
                  r"estimated cycles|cycles|B stack)\b")


def load(json_path, fp_path):
    with open(json_path) as f:
        ops = {o["name"]: o for o in json.load(f)["operations"]}
    code = {}
    with open(fp_path) as f:
        for line in f:
            w = line.split()
            if len(w) == 4 and w[0] == "code":
                code[(w[1], "-Os")] = int(w[2])
                code[(w[1], "-O2")] = int(w[3])
            elif len(w) == 5 and w[0] == "part":  # keyed "APP PART"
                code[(w[1] + " " + w[2], "-Os")] = int(w[3])
                code[(w[1] + " " + w[2], "-O2")] = int(w[4])
    return ops, code


def same(written, value):
    """written (a string from the prose) equals value at its precision."""
    w = written.replace(",", "")
    dec = len(w.split(".")[1]) if "." in w else 0
    return ("%.*f" % (dec, float(value))) == ("%.*f" % (dec, float(w)))


def doc_files(src):
    return [os.path.join(src, "README.md")] + sorted(glob.glob(os.path.join(src, "docs", "*.md")))


def prose(path):
    """The text of path with the generated blocks and code fences blanked
    (line numbers kept)."""
    gen = fence = False
    out = []
    with open(path, encoding="utf-8") as f:
        for line in f.read().split("\n"):
            keep = True
            if re.search(r"<!-- (flopcount|cores):begin", line):
                gen = True
            if re.search(r"<!-- (flopcount|cores):end", line):
                gen = False
                keep = False
            if line.startswith("```"):
                fence = not fence
                keep = False
            out.append(line if keep and not gen and not fence else "")
    return "\n".join(out)


def blank(text, m):
    """text with match m replaced by spaces (its newlines kept)."""
    return text[:m.start()] + re.sub(r"[^\n]", " ", m.group(0)) + text[m.end():]


def check(src, ops, code):
    errors, checked = [], 0
    for path in doc_files(src):
        rel = os.path.relpath(path, src)
        text = prose(path)
        rest = text
        for m in CITE.finditer(text):
            num, unit, row = m.groups()
            unit = " ".join(unit.split())
            where = "%s:%d" % (rel, text.count("\n", 0, m.start()) + 1)
            checked += 1
            rest = blank(rest, m)
            if row not in ops:
                errors.append("%s: `%s` is no cost row" % (where, row))
            elif not same(num, ops[row][UNITS[unit]]):
                errors.append("%s: %s %s (`%s`), measured %s" % (where, num, unit, row,
                                                                  ops[row][UNITS[unit]]))
        sizes = [(m, m.group(1), m.group(2), m.group(3)) for m in SIZE.finditer(text)]
        sizes += [(m, m.group(1), m.group(2), m.group(3) + " " + m.group(4))
                  for m in PART.finditer(text)]
        for m, num, level, mod in sizes:
            where = "%s:%d" % (rel, text.count("\n", 0, m.start()) + 1)
            checked += 1
            rest = blank(rest, m)
            if (mod, level) not in code:
                errors.append("%s: no footprint record code/part %s" % (where, mod))
            elif not same(num, code[(mod, level)]):
                errors.append("%s: %s B (code %s %s), measured %d B" % (
                    where, num, level, mod, code[(mod, level)]))
        for no, line in enumerate(rest.split("\n"), 1):
            # a limit ("at most 1500 M4F instructions") is no copy of a figure
            line = re.sub(r"(at most|under|below|<=) \d[\d,]*", "", line)
            named = set(re.findall(r"`(\w+)`", line)) & set(ops)
            if named and BARE.search(line):
                errors.append("%s:%d: a figure next to cost row %s not in a citation form "
                              "(N unit (`row`)): %s" % (rel, no, ", ".join(sorted(named)),
                                                        line.strip()))
    return errors, checked


def selftest(src, ops, code):
    """The check must fail on a drifted citation, an unknown row, a drifted
    size and an uncited figure next to a row name."""
    bad = 0
    cases = [("%d FLOPs (`solve_gdke`)" % (ops["solve_gdke"]["flops"] + 1), "drifted FLOPs"),
             ("%d M4F instructions (`moments_add_batch`)" % (ops["moments_add_batch"]["insns"] + 9),
              "drifted instructions"),
             ("3 FLOPs (`no_such_row`)", "unknown row"),
             ("%d B (`code -Os minimal_app`)" % (code[("minimal_app", "-Os")] + 16), "drifted size"),
             ("%d B (`part -Os minimal_app_screened screen`)"
              % (code[("minimal_app_screened screen", "-Os")] + 2), "drifted part"),
             ("4 B (`part -Os minimal_app_screened no_such_part`)", "unknown part"),
             ("`solve_gdke` costs 99 FLOPs", "uncited figure"),
             ("a frame in %d\ninstructions (`lower_limb_track_frame`)"
              % (round(ops["lower_limb_track_frame"]["insns"]) + 1), "drift over two lines")]
    for text, what in cases:
        tmp = tempfile.mkdtemp()
        try:
            os.makedirs(os.path.join(tmp, "docs"))
            shutil.copy(os.path.join(src, "README.md"), tmp)
            for p in glob.glob(os.path.join(src, "docs", "*.md")):
                shutil.copy(p, os.path.join(tmp, "docs"))
            with open(os.path.join(tmp, "docs", "cost.md"), "a") as f:
                f.write("\n" + text + "\n")
            errors, _ = check(tmp, ops, code)
            if not errors:
                print("docs_figures: FAIL: selftest: %s (%s) not detected" % (what, text))
                bad = 1
        finally:
            shutil.rmtree(tmp)
    return bad


def main(argv):
    st = argv[1:2] == ["--selftest"]
    args = argv[2:] if st else argv[1:]
    if len(args) != 3:
        print(__doc__)
        return 2
    src, json_path, fp_path = args
    ops, code = load(json_path, fp_path)
    errors, checked = check(src, ops, code)
    for e in errors:
        print("docs_figures: FAIL: " + e)
    rc = 1 if errors else 0
    if st:
        rc |= selftest(src, ops, code)
    print("docs_figures: %d cited figures checked, %d wrong" % (checked, len(errors)))
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv))
