# SPDX-License-Identifier: MIT
"""One name, one file (ctest sfit.script.api_names).

Usage: api_names.py SOURCE_DIR [--list]

The rule (README.md, "API"): every public function sfit_<family>_<verb> is
declared in lib/include/sfit/sfit_<family>.h and defined in
lib/src/sfit_<family>.c, and nowhere else. <family> is the longest
header name that prefixes the function name. Headers that declare no
function (sfit.h the umbrella, sfit_types.h, sfit_config.h) are the only
ones allowed to declare none; every other public header declares at least
one function of its own family, and every lib/src/sfit_<family>.c with a
public header defines only functions of that family (internal helpers are
sfit_i_* or static prv_*).

--counts prints the size of the surface: public functions, public types
(typedef names) and result types (struct types a public function writes
through a non-const pointer other than its first, vec3/mat3 aside).

Functions are read from the text: comments and preprocessor lines are
removed, then a declaration is a top-level statement of the form
`<type> sfit_x(...)` ending in `;` (a header) or `{` (a definition, a
static inline in a header included). --list prints the table it checks.
"""
import glob
import os
import re
import sys

src = os.path.abspath(sys.argv[1])
inc = os.path.join(src, "lib", "include", "sfit")
lib = os.path.join(src, "lib", "src")
NO_FUNCTION_HEADERS = {"sfit", "sfit_types", "sfit_config"}


def strip(text):
    """Text without comments, string literals and preprocessor lines."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text)
    text = re.sub(r"^[ \t]*#[^\n]*(\\\n[^\n]*)*", "", text, flags=re.M)
    return re.sub(r'extern\s*""\s*\{', "", text)  # the C++ guard; its '}' is skipped below


def top_level(text):
    """(name, terminator) of each top-level function declarator."""
    out, depth, start = [], 0, 0
    for i, c in enumerate(text):
        if c == "{":
            if depth == 0:
                out.append((text[start:i], "{"))
            depth += 1
            start = i + 1
        elif c == "}":
            depth = max(depth - 1, 0)
            start = i + 1
        elif c == ";" and depth == 0:
            out.append((text[start:i], ";"))
            start = i + 1
    found = []
    for stmt, term in out:
        s = " ".join(stmt.split())
        if s.startswith("typedef") or s.startswith("extern \"\"") or "(" not in s:
            continue
        # the declarator: the identifier right before the first '(' (not a
        # function pointer '(*'), after a return type
        m = re.match(r"^(?:(?:static|inline|extern|const|unsigned|signed|struct|enum)\s+)*"
                     r"[A-Za-z_]\w*(?:\s*\*)*\s*\**\s*(sfit_\w+)\s*\(", s)
        if m:
            found.append((m.group(1), term, "static" in s.split("(")[0].split(), s))
    return found


def family(name, families):
    best = None
    for f in families:
        if name == f or name.startswith(f + "_"):
            if best is None or len(f) > len(best):
                best = f
    return best


headers = {os.path.basename(p)[:-2]: p for p in glob.glob(os.path.join(inc, "sfit*.h"))}
sources = {os.path.basename(p)[:-2]: p for p in glob.glob(os.path.join(lib, "*.c"))}
problems, table = [], []

declared = {}  # name -> set of headers
types, results = set(), set()
for h, path in sorted(headers.items()):
    with open(path, encoding="utf-8") as f:
        text = strip(f.read())
        types.update(re.findall(r"\}\s*(sfit_\w+_t)\s*;", text))
        types.update(re.findall(r"typedef\s+[^;{]*?\b(sfit_\w+_t)\s*;", text))
        for name, term, _, decl in top_level(text):
            declared.setdefault(name, set()).add(h)
            params = decl[decl.index("(") + 1:].split(",")
            for q in params[1:]:
                m = re.match(r"\s*(?:struct\s+)?(sfit_\w+_t)\s*\*", q)
                if m and m.group(1) not in ("sfit_vec3_t", "sfit_mat3_t"):
                    results.add(m.group(1))

defined = {}  # name -> set of sources
for s, path in sorted(sources.items()):
    with open(path, encoding="utf-8") as f:
        for name, term, is_static, _ in top_level(strip(f.read())):
            if term == "{" and not is_static and not name.startswith("sfit_i_"):
                defined.setdefault(name, set()).add(s)

families = sorted(headers)
for name in sorted(set(declared) | set(defined)):
    fam = family(name, families)
    where_h = sorted(declared.get(name, ()))
    where_c = sorted(defined.get(name, ()))
    table.append((name, fam, ",".join(where_h) or "-", ",".join(where_c) or "-"))
    if fam is None or fam in NO_FUNCTION_HEADERS:
        problems.append("%s: its prefix names no public header (declared in %s, defined in %s)"
                        % (name, where_h or "no header", where_c or "no source"))
        continue
    if where_h != [fam]:
        problems.append("%s: declared in %s, expected only in lib/include/sfit/%s.h"
                        % (name, ", ".join(h + ".h" for h in where_h) or "no public header", fam))
    if name not in declared:
        continue
    if where_c != [fam]:
        problems.append("%s: defined in %s, expected only in lib/src/%s.c"
                        % (name, ", ".join(c + ".c" for c in where_c) or "no source", fam))

for h in sorted(headers):
    own = [n for n in declared if family(n, families) == h]
    if h in NO_FUNCTION_HEADERS:
        if own:
            problems.append("%s.h: declares functions (%s) but is a no-function header"
                            % (h, ", ".join(sorted(own))))
    elif not own:
        problems.append("%s.h: declares no function of its own family (fold it into its "
                        "users or list it as a no-function header)" % h)
for s in sorted(sources):
    if s in headers:
        continue
    public = [n for n in defined if s in defined[n]]
    if public:
        problems.append("lib/src/%s.c: defines public functions (%s) but no public header is "
                        "named %s.h" % (s, ", ".join(sorted(public)), s))

if "--list" in sys.argv[2:]:
    print("%-34s %-14s %-28s %s" % ("function", "family", "declared in", "defined in"))
    for row in table:
        print("%-34s %-14s %-28s %s" % row)
n_fun = len(table)
if "--counts" in sys.argv[2:]:
    print("public functions %d, public types %d, result types %d: %s"
          % (len(declared), len(types), len(results), " ".join(sorted(results))))
if problems:
    for p in problems:
        print("FAIL: " + p, file=sys.stderr)
    sys.exit(1)
print("api_names: %d public functions in %d families, each declared in sfit_<family>.h and "
      "defined in sfit_<family>.c" % (n_fun, len({r[1] for r in table})))
