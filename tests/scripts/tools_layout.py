#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The rooms of tools/ and their rules (tools/README.md), checked.

Usage: tools_layout.py SRC [BUILD]

The rooms (formats, lab, the CLI, the binding) and what each may include
are read from their one list, tools/rooms.tsv; every folder of tools/
with C sources (montecarlo and flopcount aside) must be in it.

- Includes: tools/formats includes only its own headers and the library's
  types (sfit/sfit_types.h); tools/lab its own, formats' and the
  library's; the CLI and the binding (tools/python/src) any
  of those; nothing outside the CLI includes a CLI header or a CLI path.
- formats and lab write nothing to stdout.
- No `cli_` / `CLI_` name in code (comments aside) of formats, lab, the
  binding or the fuzzers; with BUILD, no `cli_` symbol in the host
  library (libsfit_host.a), and every name it exports carries its file's
  prefix (the file name's first word: c3d_write.c -> c3d_, frames.c ->
  frames_; json_out.c and joint_run.c their two words).
- Sizes: no source file of tools/ (montecarlo and flopcount aside) over
  1,000 lines, no binding file (tools/python/src, tools/python/sfit) over
  650; no folder of tools/ with more than 20 source files.
- One of each in the C host code: one command table, one status-text
  table, one flag-name table, one JSON string escaper, one SVG writer.
- No repeated block of 6 lines between the binding and the C host code.

Prints every breach and exits 1 if there is one. A breach listed in
PENDING (a known piece of work not yet done, with the reason) is printed
but passes; a PENDING entry that matches no breach any more fails, so the
list only shrinks.
"""
import glob
import hashlib
import os
import re
import subprocess
import sys

# Known breaches, each a regular expression over the breach's message and
# why it is still there.
PENDING = {
}

SRC = os.path.abspath(sys.argv[1])
BUILD = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 else None
os.chdir(SRC)
fails = []


def fail(msg):
    fails.append(msg)


def read(p):
    with open(p, encoding="utf-8", errors="replace") as f:
        return f.read()


def c_files(d, recursive=False):
    pat = os.path.join(d, "**", "*.[ch]") if recursive else os.path.join(d, "*.[ch]")
    return sorted(glob.glob(pat, recursive=recursive))


def strip_comments(text, strings=True):
    """C text with comments (and string literals, unless strings is False)
    blanked, lines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
        elif text[i] == "'":  # a character literal, kept
            j = i + 1
            while j < n and text[j] != "'" and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text[i] == '"':
            j = i + 1
            while j < n and text[j] != '"' and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append('""' if strings else text[i:j + 1])
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


# The rooms and the dependency rule, from their one list (tools/rooms.tsv).
ROOMS, MAY = {}, {}
for line in read("tools/rooms.tsv").splitlines():
    if line.strip() and not line.startswith("#"):
        role, folder, may = line.split("\t")
        ROOMS[role], MAY[role] = folder, may.split()
FORMATS, LAB, CLI, BINDING = (ROOMS[r] for r in ("formats", "lab", "cli", "binding"))
for folder in ROOMS.values():
    if not os.path.isdir(folder):
        fail("tools/rooms.tsv lists %s, which does not exist" % folder)
for d in sorted(glob.glob("tools/*/")):
    d = d.rstrip("/")
    if c_files(d) and d not in ROOMS.values() and d not in ("tools/montecarlo", "tools/flopcount"):
        fail("%s holds C sources but is not a room of tools/rooms.tsv" % d)
headers = {room: {os.path.basename(h) for h in glob.glob(room + "/*.h")}
           for room in (FORMATS, LAB, CLI, BINDING)}
GENERATED = {"skel_view_js.h"}  # lab: the skeleton page's script, made by the build
INC = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def room_of(name, own):
    """Where a quoted include resolves: the including file's folder first."""
    if name in headers.get(own, ()):
        return own
    if name.startswith("sfit/"):
        return "lib"
    for room in (FORMATS, LAB, CLI):
        if name in headers[room]:
            return room
    return None


# ---- includes: the dependency rule
allowed = {ROOMS[role]: {ROOMS[role]} | {"lib" if m == "lib" else ROOMS[m]
                                           for m in may if m != "lib-types"}
           for role, may in MAY.items()}
role_of = {folder: role for role, folder in ROOMS.items()}
for room, ok in allowed.items():
    for p in c_files(room):
        for name in INC.findall(read(p)):
            r = room_of(name, room)
            if "lib-types" in MAY[role_of[room]] and name == "sfit/sfit_types.h":
                continue
            if room == LAB and name in GENERATED:
                continue
            if r not in ok:
                fail("%s includes \"%s\" (%s): %s may include %s" % (
                    p, name, r or "unknown", room, ", ".join(sorted(ok))))

# nothing outside the CLI includes or names a file of the CLI in code
cli_names = {os.path.basename(p) for p in glob.glob(CLI + "/*.[ch]")}
outside = (c_files(FORMATS) + c_files(LAB) + c_files(BINDING) + c_files("tests", True)
           + c_files("port", True))
for p in outside:
    for name in INC.findall(read(p)):
        if CLI + "/" in name or "/sfit/cli" in name or (
                os.path.basename(name) in cli_names and name not in headers.get(os.path.dirname(p), ())):
            fail("%s includes \"%s\", a file of the CLI" % (p, name))
build_files = (["tools/python/setup.py"] + glob.glob("tests/**/CMakeLists.txt", recursive=True)
               + glob.glob("port/**/CMakeLists.txt", recursive=True)
               + glob.glob("port/**/Makefile", recursive=True)
               + glob.glob("tests/scripts/*.sh"))
CLI_SRC = re.compile(r"tools[/\"', ]+sfit[/\"']+[\w]*\.c\b|\"sfit\"\s*,\s*\"\w+\.c\"")
for p in build_files:
    if os.path.exists(p) and CLI_SRC.search(read(p)):
        fail("%s compiles a source of the CLI (%s)" % (p, CLI_SRC.search(read(p)).group(0)))

# no cli_ name outside the CLI (code, not comments or strings)
CLI_NAME = re.compile(r"\b(cli_\w+|CLI_\w+)")
for p in c_files(FORMATS) + c_files(LAB) + c_files(BINDING) + c_files("tests/fuzz"):
    for k, line in enumerate(strip_comments(read(p)).split("\n"), 1):
        m = CLI_NAME.search(line)
        if m:
            fail("%s:%d: CLI name %s outside the CLI" % (p, k, m.group(1)))

# formats and lab print nothing on stdout (their callers do)
STDOUT = re.compile(r"\b(printf|puts|putchar|vprintf)\s*\(|\bstdout\b")
for p in c_files(FORMATS) + c_files(LAB):
    for k, line in enumerate(strip_comments(read(p)).split("\n"), 1):
        m = STDOUT.search(line)
        if m:
            fail("%s:%d: %s in the host library (stdout is the CLI's)" % (p, k, m.group(0)))

# the host library: no cli_ symbol; exported names carry the file's prefix
TWO_WORDS = {"json_out", "joint_run"}
if BUILD is not None:
    lib = os.path.join(BUILD, "tools", "libsfit_host.a")
    if not os.path.exists(lib):
        fail("%s not built" % lib)
    else:
        nm = subprocess.run(["nm", "-A", "-g", "--defined-only", lib], capture_output=True,
                            text=True, check=True).stdout
        nsym = 0
        for line in nm.splitlines():
            parts = line.split()
            if len(parts) < 3 or ":" not in parts[0]:
                continue
            obj = parts[0].split(":")[1]
            sym = parts[-1]
            stem = obj.split(".")[0]
            words = stem.split("_")
            prefix = "_".join(words[:2]) if "_".join(words[:2]) in TWO_WORDS else words[0]
            nsym += 1
            if sym.startswith("cli_"):
                fail("%s: %s exports the CLI name %s" % (lib, obj, sym))
            elif sym != prefix and not sym.startswith(prefix + "_"):
                fail("%s: %s exports %s, not %s_*" % (lib, obj, sym, prefix))
        if nsym < 20:
            fail("%s: only %d exported names seen (nm output not understood?)" % (lib, nsym))

# ---- sizes
SOURCE = (".c", ".h", ".py", ".pyi", ".js")
for p in sorted(glob.glob("tools/**/*", recursive=True)):
    if not p.endswith(SOURCE) or not os.path.isfile(p):
        continue
    if p.startswith(("tools/montecarlo/", "tools/flopcount/")):
        continue
    n = read(p).count("\n")
    limit = 650 if p.startswith((BINDING + "/", "tools/python/sfit/")) else 1000
    if n > limit:
        fail("%s: %d lines (at most %d)" % (p, n, limit))
for d, _, files in os.walk("tools"):
    n = sum(1 for f in files if f.endswith(SOURCE))
    if n > 20:
        fail("%s: %d source files (at most 20)" % (d, n))

# ---- one of each in the C host code (formats, lab, the CLI, the binding)
host_c = c_files(FORMATS) + c_files(LAB) + c_files(CLI) + c_files(BINDING)


def files_with(regex, code_only=False):
    rx = re.compile(regex)
    return [p for p in host_c if rx.search(strip_comments(read(p)) if code_only else read(p))]


def one(what, regex, expect, code_only=False):
    got = files_with(regex, code_only)
    if got != [expect]:
        fail("one %s expected (in %s), found in: %s" % (what, expect, ", ".join(got) or "none"))


# the command table: rows naming a command's entry point (CLI_COMMANDS)
one("command table", r'(\{|\bX\()\s*"[\w-]+"\s*,\s*cli_cmd_\w+\s*,', CLI + "/cli.h")
# the status texts: SFIT_E_* next to its words
one("status-text table", r"\{\s*SFIT_E_\w+\s*,\s*\{?\s*\"", LAB + "/names.c")
# flag names: a flag or information bit next to its name
one("flag-name table",
    r"\{\s*\(?\s*(?:uint32_t\)\s*)?(?:SFIT_\w*(?:FLAG|INFO)\w*|SKEL_[FU]_\w+)\s*,\s*\"",
    LAB + "/names.c")
# the JSON string escaper: the \u escape of a control character
one("JSON string escaper", r"u%04x", FORMATS + "/json_out.c")
# the SVG writer: the document's root element
one("SVG writer", r"<svg xmlns", FORMATS + "/svg.c")

# ---- no repeated block of 6 lines between the binding and the C host code
WINDOW = 6


def norm_lines(p):
    out = []
    for line in strip_comments(read(p), strings=False).split("\n"):
        s = " ".join(line.split())
        if s and not s.startswith("#") and s not in ("{", "}", "};", "});", "break;", "return 0;", "return NULL;",
                           "else {", "} else {", "return -1;", "#endif"):
            out.append(s)
    return out


def windows(p):
    lines = norm_lines(p)
    return {hashlib.sha1("\n".join(lines[i:i + WINDOW]).encode()).hexdigest(): i
            for i in range(len(lines) - WINDOW + 1)}


host = {p: windows(p) for p in c_files(FORMATS) + c_files(LAB) + c_files(CLI)}
for b in c_files(BINDING):
    wb = windows(b)
    for p, wp in host.items():
        common = set(wb) & set(wp)
        if common:
            fail("%s and %s share %d block(s) of %d lines" % (b, p, len(common), WINDOW))

used = set()
bad = []
pending = []
for f in fails:
    keys = [k for k in PENDING if re.search(k, f)]
    if keys:
        used.update(keys)
        pending.append(f)
    else:
        bad.append(f)
bad += ["PENDING entry %r matches no breach any more: remove it" % k
        for k in PENDING if k not in used]
for f in bad:
    print("FAIL:", f)
for f in pending:
    print("pending:", f)
npending = len(pending)
print("tools layout: %d breach(es), %d pending" % (len(bad), npending))
sys.exit(1 if bad else 0)
