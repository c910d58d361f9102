# SPDX-License-Identifier: MIT
"""Every module has every step (ctest sfit.script.modules).

Usage: modules_check.py SOURCE_DIR

Reads the table of modules in docs/modules.md (between <!-- modules:begin -->
and <!-- modules:end -->) and the table of internal sources (<!-- internal:
begin/end -->), and fails when:
- a public header other than sfit.h, sfit_types.h, sfit_config.h has no
  row, or a row has no header lib/include/sfit/sfit_<m>.h or no source
  lib/src/sfit_<m>.c; a library source is in neither table;
- a module's test tests/<file> does not exist or calls no sfit_<m>_
  function; the same for its fuzz harness (tests/fuzz), garbage driver
  (tests/fuzz), on-target suite (tests/target), binding (tools/python/src)
  and CLI file (the CLI's room, or the lab code it runs; the rooms are
  read from tools/rooms.tsv);
- a reference function is not defined in tests/ref/*.c or not called by
  the module's test;
- a module with sfit_<m>_init has no garbage-state entry;
- a module or internal source has no code_os / code_o2 row in
  tools/flopcount/footprint_budget.txt;
- the docs cell is not a heading of a docs/ page;
- a cell is empty, or says n/a without a reason, or n/a where no n/a is
  allowed (test, docs; garbage for a module with a state).
"""
import glob
import os
import re
import sys

src = os.path.abspath(sys.argv[1])
problems = []
NO_FUNCTION_HEADERS = {"sfit", "sfit_types", "sfit_config"}


def read(path):
    with open(os.path.join(src, path), encoding="utf-8") as f:
        return f.read()


def rooms():
    """role -> folder, from the one list of tools/' rooms."""
    out = {}
    for line in read("tools/rooms.tsv").splitlines():
        if line.strip() and not line.startswith("#"):
            role, folder = line.split("\t")[:2]
            out[role] = folder
    return out


ROOMS = rooms()


def table(text, name):
    m = re.search(r"<!-- %s:begin -->\n(.*?)<!-- %s:end -->" % (name, name), text, re.S)
    if not m:
        problems.append("docs/modules.md: no <!-- %s:begin/end --> table" % name)
        return [], []
    rows = [l for l in m.group(1).splitlines() if l.startswith("|")]
    head = [c.strip() for c in rows[0].strip("|").split("|")]
    body = [[c.strip() for c in r.strip("|").split("|")] for r in rows[2:]]
    return head, body


def slug(title):
    title = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", title).replace("`", "")
    return re.sub(r"[^\w\- ]", "", title.strip().lower()).replace(" ", "-")


def calls(path, m):
    return re.search(r"\bsfit_%s_\w+\s*\(" % m, read(path)) is not None


doc = read("docs/modules.md")
head, rows = table(doc, "modules")
_, internal = table(doc, "internal")
want = ["module", "test", "ref", "fuzz", "garbage", "target", "python", "cli", "docs"]
if head and head != want:
    problems.append("docs/modules.md: the table's columns are %s, expected %s" % (head, want))
    rows = []

ref_text = "".join(read(os.path.relpath(p, src)) for p in glob.glob(os.path.join(src, "tests/ref/*.c")))
budget = read("tools/flopcount/footprint_budget.txt")
listed = set()
for row in rows:
    if len(row) != len(want):
        problems.append("docs/modules.md: row %s has %d cells" % (row[:1], len(row)))
        continue
    cell = dict(zip(want, row))
    m = cell["module"]
    listed.add("sfit_" + m)
    where = "docs/modules.md: module %s" % m
    hdr, srcf = "lib/include/sfit/sfit_%s.h" % m, "lib/src/sfit_%s.c" % m
    for path in (hdr, srcf):
        if not os.path.exists(os.path.join(src, path)):
            problems.append("%s: %s does not exist" % (where, path))
    has_state = os.path.exists(os.path.join(src, hdr)) and re.search(
        r"\bsfit_%s_init\s*\(" % m, read(hdr)) is not None
    for col in want[1:]:
        v = cell[col]
        if not v:
            problems.append("%s: the %s cell is empty" % (where, col))
            continue
        if v.startswith("n/a"):
            if not re.match(r"n/a: \S", v):
                problems.append("%s: %s says n/a without a reason" % (where, col))
            if col in ("test", "docs") or (col == "garbage" and has_state):
                problems.append("%s: %s cannot be n/a%s" % (
                    where, col, " (the module has sfit_%s_init: a state)" % m if col == "garbage" else ""))
            continue
        if col == "ref":
            test_file = "tests/" + cell["test"]
            for fn in re.findall(r"`(\w+)`", v) or [v]:
                if not re.search(r"^[\w \t\*]*\b%s\s*\(" % fn, ref_text, re.M):
                    problems.append("%s: reference %s is not defined in tests/ref/*.c" % (where, fn))
                elif os.path.exists(os.path.join(src, test_file)) and \
                        not re.search(r"\b%s\s*\(" % fn, read(test_file)):
                    problems.append("%s: reference %s is not called by %s" % (where, fn, test_file))
            continue
        if col == "docs":
            page, _, anchor = v.partition("#")
            path = os.path.join("docs", page)
            if not os.path.exists(os.path.join(src, path)):
                problems.append("%s: %s does not exist" % (where, path))
            elif anchor not in {slug(h) for h in re.findall(r"^#{1,6}\s+(.*?)\s*$", read(path), re.M)}:
                problems.append("%s: no heading #%s in %s" % (where, anchor, path))
            continue
        folder = {"test": "tests", "fuzz": "tests/fuzz", "garbage": "tests/fuzz",
                  "target": "tests/target", "python": ROOMS["binding"], "cli": ROOMS["cli"]}[col]
        for name in re.split(r",\s*", v):
            path = os.path.join(folder, name)
            if col == "cli":  # a command of the CLI, or the lab code it runs
                path = next((os.path.join(d, name) for d in (ROOMS["cli"], ROOMS["lab"])
                             if os.path.exists(os.path.join(src, d, name))), path)
            if not os.path.exists(os.path.join(src, path)):
                problems.append("%s: %s does not exist" % (where, path))
            elif not calls(path, m):
                problems.append("%s: %s calls no sfit_%s_ function" % (where, path, m))
    for level in ("code_os", "code_o2"):
        if not re.search(r"^%s\s+sfit_%s\s+\d+" % (level, m), budget, re.M):
            problems.append("%s: no '%s sfit_%s' row in tools/flopcount/footprint_budget.txt"
                            % (where, level, m))

for row in internal:
    s = row[0]
    listed.add(s)
    if not os.path.exists(os.path.join(src, "lib/src/%s.c" % s)):
        problems.append("docs/modules.md: internal source lib/src/%s.c does not exist" % s)
    for level in ("code_os", "code_o2"):
        if not re.search(r"^%s\s+%s\s+\d+" % (level, s), budget, re.M):
            problems.append("docs/modules.md: internal %s: no '%s %s' row in "
                            "tools/flopcount/footprint_budget.txt" % (s, level, s))

for path in sorted(glob.glob(os.path.join(src, "lib/include/sfit/*.h"))):
    h = os.path.basename(path)[:-2]
    if h not in NO_FUNCTION_HEADERS and h not in listed:
        problems.append("lib/include/sfit/%s.h: not a module of docs/modules.md" % h)
for path in sorted(glob.glob(os.path.join(src, "lib/src/*.c"))):
    s = os.path.basename(path)[:-2]
    if s not in listed:
        problems.append("lib/src/%s.c: in neither table of docs/modules.md" % s)

if problems:
    for p in problems:
        print("FAIL: " + p, file=sys.stderr)
    sys.exit(1)
print("modules: %d modules and %d internal sources, every step present" % (len(rows), len(internal)))
