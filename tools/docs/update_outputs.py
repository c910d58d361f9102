# SPDX-License-Identifier: MIT
"""Write again the command outputs the user documentation shows, the ones
tests/scripts/doc_check.py compares (ctest sfit.script.docs):

- every `$ sfit ...` command in a fenced block of README.md and docs/*.md
  whose shown output has no `...` elision (an elided JSON is kept as
  written: its pieces are chosen by hand);
- the README demo's output block ("Demo output (measured):").

Usage: /usr/bin/python3 tools/docs/update_outputs.py BUILD_DIR [SOURCE_DIR]
Prints the documents it changed. Run it after a change of what the tool
prints, then read the diff: the prose around an output may need the same
change.
"""
import glob
import os
import re
import subprocess
import sys
import tempfile

build = os.path.abspath(sys.argv[1])
src = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", ".."))
sfit = os.path.join(build, "bin", "sfit")
docs = [os.path.join(src, "README.md")] + sorted(glob.glob(os.path.join(src, "docs", "*.md")))


def run(argv, cwd):
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True).stdout.splitlines()


def update_commands(text, cwd):
    out, pos = [], 0
    for m in re.finditer(r"^```[a-z]*\n(.*?)^```", text, re.S | re.M):
        out.append(text[pos:m.start(1)])
        lines = m.group(1).splitlines()
        starts = [i for i, l in enumerate(lines) if l.startswith("$ ")] + [len(lines)]
        new = lines[:starts[0]]
        for i, j in zip(starts, starts[1:]):
            argv = lines[i][2:].split()
            shown = lines[i + 1:j]
            new.append(lines[i])
            files = [a for a in argv[1:] if re.search(r"\.(csv|tsv|txt|c3d)$", a)]
            runnable = (argv[0] == "sfit" or argv[0].endswith("/bin/sfit")) and \
                all(os.path.exists(os.path.join(cwd, a)) for a in files)
            if runnable and not any("..." in w for w in shown):
                new += run([sfit] + argv[1:], cwd)
            else:
                new += shown
        out.append("\n".join(new) + ("\n" if new else ""))
        pos = m.end(1)
    out.append(text[pos:])
    return "".join(out)


def update_demo(text):
    demo = re.search(r"^```sh\ncmake --preset default && cmake --build --preset default && "
                     r"(?:mkdir -p (out) && )?(\./build/bin/sfit [^\n]*)\n```", text, re.M)
    shown = re.search(r"^Demo output \(measured\):\n\n```\n(.*?)^```", text, re.S | re.M)
    if not demo or not shown:
        return text
    got = []
    with tempfile.TemporaryDirectory() as scratch:
        for sub in ("tests", "docs"):
            os.symlink(os.path.join(src, sub), os.path.join(scratch, sub))
        if demo.group(1):
            os.mkdir(os.path.join(scratch, demo.group(1)))
        for part in demo.group(2).split(" && "):
            args = []
            for a in part.split()[1:]:
                hits = sorted(glob.glob(os.path.join(scratch, a))) if "*" in a else []
                args += [os.path.relpath(h, scratch) for h in hits] if hits else [a]
            got += run([sfit] + args, scratch)
    return text[:shown.start(1)] + "\n".join(got) + "\n" + text[shown.end(1):]


for doc in docs:
    with open(doc, encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"Commands run from `([^`]+)`", text)
    cwd = os.path.join(src, m.group(1)) if m else src
    new = update_commands(text, cwd)
    if doc.endswith("README.md"):
        new = update_demo(new)
    if new != text:
        with open(doc, "w", encoding="utf-8") as f:
            f.write(new)
        print("updated " + os.path.relpath(doc, src))
