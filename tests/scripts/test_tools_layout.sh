#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The rooms of tools/ keep their rules (tools/README.md): the check
# (tests/scripts/tools_layout.py) passes on the tree and on the built host
# library, and fails on copies of the tree each with one breach.
# Usage: test_tools_layout.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
name=test_tools_layout
# shellcheck source=tests/scripts/common.sh
. "$src/tests/scripts/common.sh"
rule_setup "$src/tests/scripts/tools_layout.py"
command -v nm >/dev/null 2>&1 || missing "nm not found (binutils)"
/usr/bin/python3 "$rule_check" "$src" "$build"
cli=sfit # the CLI's folder, tools/$cli
fresh() {
  rm -rf "$tmp/t"; mkdir -p "$tmp/t"
  (cd "$src" && tar cf - --exclude=tests/data --exclude='tests/fuzz/corpus' --exclude='*/__pycache__' \
     tools tests port) | tar xf - -C "$tmp/t"
}
fresh
/usr/bin/python3 "$rule_check" "$tmp/t" > /dev/null || { echo "FAIL: the copy itself does not pass" >&2; exit 1; }
fresh; sed -i '0,/#include "table.h"/s//#include "table.h"\n#include "names.h"/' "$tmp/t/tools/formats/table.c"
must_fail "formats including lab"
fresh; sed -i '0,/#include "frames.h"/s//#include "frames.h"\n#include "cli.h"/' "$tmp/t/tools/lab/frames.c"
must_fail "lab including the CLI"
fresh; printf '#include "../../tools/%s/cli_common.c"\n' "$cli" >> "$tmp/t/tests/fuzz/fuzz_table.c"
must_fail "a fuzzer compiling a CLI file"
fresh; sed -i 's/frames_free(/cli_frames_free(/' "$tmp/t/tools/lab/frames.c"
must_fail "a cli_ name in lab"
fresh; printf 'static void say(void) { printf("x\\n"); }\n' >> "$tmp/t/tools/lab/names.c"
must_fail "printing to stdout in lab"
fresh; printf 'static void esc2(FILE *f, unsigned c) { fprintf(f, "\\\\u%%04x", c); }\n' >> "$tmp/t/tools/lab/swaps.c"
must_fail "a second JSON string escaper"
fresh; printf 'static void svg2(FILE *f) { fputs("<svg xmlns=\\"x\\">", f); }\n' >> "$tmp/t/tools/lab/skel_write.c"
must_fail "a second SVG writer"
fresh; printf 'static const struct { int st; const char *t; } g2[] = {{SFIT_E_ARG, "bad"}};\n' >> "$tmp/t/tools/$cli/cmd_fit.c"
must_fail "a second status-text table"
fresh; printf 'static const json_out_flag_t g3[] = {{SFIT_FLAG_UNTRUSTED, "untrusted"}};\n' >> "$tmp/t/tools/$cli/cmd_fit.c"
must_fail "a second flag-name table"
fresh; printf 'static const struct { const char *n; int (*r)(int, char **); const char *h; } c2[] = {\n    {"fit", cli_cmd_fit, "x"}};\n' >> "$tmp/t/tools/$cli/cmd_track.c"
must_fail "a second command table"
fresh; for _ in $(seq 1000); do echo '/* */'; done >> "$tmp/t/tools/lab/frames.c"
must_fail "a source file over 1,000 lines"
fresh; touch "$tmp/t/tools/lab/extra1.c" "$tmp/t/tools/lab/extra2.h"
must_fail "a folder with more than 20 source files"
fresh; sed -n '/^int frames_parse_range/,/^}/p' "$src/tools/lab/frames.c" >> "$tmp/t/tools/python/src/py_imu.c"
must_fail "a block repeated between the binding and the host code"
fresh; mkdir "$tmp/t/tools/extra"; printf 'int extra_x(void) { return 0; }\n' > "$tmp/t/tools/extra/extra.c"
must_fail "a folder of C sources that is no room of tools/rooms.tsv"
fresh; sed -i 's#\ttools/lab\t#\ttools/labs\t#' "$tmp/t/tools/rooms.tsv"
must_fail "tools/rooms.tsv naming a folder that does not exist"
# A known breach listed as pending that is no longer there: the check, with
# such an entry added to its list, fails on the tree.
fresh; sed 's/^PENDING = {$/PENDING = {\n    r"^tools\/lab\/gone\\.c: ": "a breach mended long ago",/' "$rule_check" > "$tmp/stale.py"
grep -q 'gone' "$tmp/stale.py" || { echo "FAIL: could not add a stale PENDING entry" >&2; exit 1; }
if out=$(/usr/bin/python3 "$tmp/stale.py" "$tmp/t" 2>&1); then
  echo "FAIL: the check passed with a PENDING entry that matches no breach" >&2; exit 1
fi
echo "ok: fails on a PENDING entry that matches no breach any more: $(echo "$out" | head -1)"
