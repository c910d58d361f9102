# SPDX-License-Identifier: MIT
"""The user documentation against the tree and the CLI (ctest sfit.script.docs).

Usage: doc_check.py BUILD_DIR SOURCE_DIR

1. Every relative link of README.md and docs/*.md names an existing file,
   and an existing heading when it has an #anchor (GitHub's slugs); so does
   every repository path written in the text (docs/..., tests/..., tools/...,
   lib/..., port/..., with an optional .md#anchor).
2. Every command shown with a `$ ` prompt in a fenced block whose program is
   `sfit` (or `./build/bin/sfit`) runs with BUILD_DIR/bin/sfit and prints
   exactly the lines that follow it. A `...` in the shown output elides
   part of one JSON object: the pieces around it must appear in order. The
   commands run from the source directory, or from the directory a document
   names in "Commands run from `DIR`". A command whose input file is not
   shipped is skipped and listed.
3. The README's demo output ("Demo output (measured):") is what the demo
   command prints.
"""
import glob
import os
import re
import subprocess
import sys

build, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
sfit = os.path.join(build, "bin", "sfit")
docs = [os.path.join(src, "README.md")] + sorted(glob.glob(os.path.join(src, "docs", "*.md")))
problems = []


def rel(path):
    return os.path.relpath(path, src)


def outside_fences(text):
    """(line number, line) of the lines outside fenced code blocks."""
    fence = False
    for num, line in enumerate(text.splitlines(), 1):
        if line.startswith("```"):
            fence = not fence
            continue
        if not fence:
            yield num, line


def anchors(path, cache={}):
    if path not in cache:
        seen, out = {}, set()
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for _, line in outside_fences(text):
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                title = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", m.group(1)).replace("`", "")
                slug = re.sub(r"[^\w\- ]", "", title.strip().lower()).replace(" ", "-")
                if slug in seen:
                    seen[slug] += 1
                    slug = "%s-%d" % (slug, seen[slug])
                else:
                    seen[slug] = 0
                out.add(slug)
            out.update(re.findall(r'<a (?:name|id)="([^"]+)"', line))
        cache[path] = out
    return cache[path]


def check_target(doc, num, target, base):
    path, _, anchor = target.partition("#")
    full = os.path.normpath(os.path.join(base, path)) if path else doc
    if not os.path.exists(full):
        problems.append("%s:%d: %s does not exist" % (rel(doc), num, target))
    elif anchor and full.endswith(".md") and anchor not in anchors(full):
        problems.append("%s:%d: no heading for #%s in %s" % (rel(doc), num, anchor, rel(full)))


# 1. Links and paths.
for doc in docs:
    with open(doc, encoding="utf-8") as f:
        text = f.read()
    for num, line in outside_fences(text):
        for m in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", line):
            if not re.match(r"^[a-z]+:", m.group(1)):
                check_target(doc, num, m.group(1), os.path.dirname(doc))
        for m in re.finditer(r"(?<![\w/(.-])((?:docs|tests|tools|lib|port)/[\w./\-]+?)"
                             r"(\.md#[\w\-]+)?(?=[`\s),;:]|$)", line):
            path = m.group(1).rstrip(".")
            if m.group(2):
                path += m.group(2)
            if re.search(r"[*{]", line[m.end():m.end() + 1]):
                continue  # a pattern such as docs/figures/*.png
            check_target(doc, num, path, src)


# 2. `$ sfit ...` commands and their output.
def run(argv, cwd):
    p = subprocess.run(argv, cwd=cwd, capture_output=True, text=True)
    return p.stdout.splitlines()


def matches(want, got):
    if not any("..." in w for w in want):
        return want == got
    shown, printed, pos = "".join(w.strip() for w in want), "".join(got), 0
    for piece in shown.split("..."):
        piece = piece.strip(" ,")
        at = printed.find(piece, pos)
        if at < 0:
            return False
        pos = at + len(piece)
    return True


checked, skipped = 0, []
for doc in docs:
    with open(doc, encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"Commands run from `([^`]+)`", text)
    cwd = os.path.join(src, m.group(1)) if m else src
    for block in re.findall(r"^```[a-z]*\n(.*?)^```", text, re.S | re.M):
        lines = block.splitlines()
        starts = [i for i, l in enumerate(lines) if l.startswith("$ ")] + [len(lines)]
        for i, j in zip(starts, starts[1:]):
            argv = lines[i][2:].split()
            if not (argv[0] == "sfit" or argv[0].endswith("/bin/sfit")):
                continue
            files = [a for a in argv[1:] if re.search(r"\.(csv|tsv|txt|c3d)$", a)]
            absent = [a for a in files if not os.path.exists(os.path.join(cwd, a))]
            if absent:
                skipped.append("%s: %s (not shipped: %s)" % (rel(doc), lines[i], " ".join(absent)))
                continue
            got = run([sfit] + argv[1:], cwd)
            checked += 1
            if not matches(lines[i + 1:j], got):
                problems.append("%s: `%s` prints\n    %s\n  the document shows\n    %s" % (
                    rel(doc), lines[i][2:], "\n    ".join(got), "\n    ".join(lines[i + 1:j])))

# 3. The README's demo: after the build, one or more `./build/bin/sfit ...`
# commands chained with &&, after an optional `mkdir -p out` (the ignored
# folder the outputs go to); each runs in a scratch directory that sees the
# tree's tests/ and docs/ (its output files land there), shell globs
# expanded; their outputs, one after the other, are the block shown.
with open(docs[0], encoding="utf-8") as f:
    readme = f.read()
demo = re.search(r"^```sh\n(cmake --preset default && cmake --build --preset default && "
                 r"(?:mkdir -p (out) && )?(\./build/bin/sfit [^\n]*))\n```", readme, re.M)
shown = re.search(r"^Demo output \(measured\):\n\n```\n(.*?)^```", readme, re.S | re.M)
if not demo or not shown:
    problems.append("README.md: the demo command or its output block is not found")
else:
    import tempfile
    got = []
    with tempfile.TemporaryDirectory() as scratch:
        for sub in ("tests", "docs"):
            os.symlink(os.path.join(src, sub), os.path.join(scratch, sub))
        if demo.group(2):
            os.mkdir(os.path.join(scratch, demo.group(2)))
        for part in demo.group(3).split(" && "):
            argv = part.split()
            if argv[0] != "./build/bin/sfit":
                problems.append("README.md: the demo runs %s, not sfit" % argv[0])
                break
            args = []
            for a in argv[1:]:
                hits = sorted(glob.glob(os.path.join(scratch, a))) if "*" in a else []
                args += [os.path.relpath(h, scratch) for h in hits] if hits else [a]
            got += run([sfit] + args, scratch)
    checked += 1
    if got != shown.group(1).splitlines():
        problems.append("README.md: the demo prints\n    %s" % "\n    ".join(got))

for s in skipped:
    print("skipped: " + s)
print("docs: %d files, %d commands compared with their output" % (len(docs), checked))
for p in problems:
    print("FAIL: " + p, file=sys.stderr)
sys.exit(1 if problems or checked == 0 else 0)
