#!/bin/sh
# SPDX-License-Identifier: MIT
#
# footprint.sh M4F_BUILD_DIR [BUDGET_FILE]
#
# Footprint of the library on Cortex-M4F, from the objects built by
# tests/target (sfit_fp_Os / sfit_fp_O2: the lib/src/*.c at -Os and -O2
# with -fstack-usage -fcallgraph-info=su; sfit_fp_sizes: sizeof of each
# public struct). Prints, one record per line:
#   code MODULE TEXT_OS TEXT_O2          .text+.rodata bytes per module (object)
#   code_total TOTAL_OS TOTAL_O2
#   part APP PART BYTES_OS BYTES_O2      the minimal applications' bytes by
#                                        part (accumulator, system, driver,
#                                        screen, cholesky, solver, jacobi,
#                                        other; below)
#   struct TYPE BYTES
#   stack FUNCTION BYTES_OS BYTES_O2     worst-case stack of a public function:
#                                        its frame + the deepest callee chain
#                                        (call graph of -fcallgraph-info; C
#                                        library callees from their disassembly)
#   check NAME ok|FAIL DETAIL            heap, static_data, double, stack_bounded,
#                                        budget
# Exit status 1 when a check fails. Budget file lines (default
# tools/flopcount/footprint_budget.txt):
#   code_os MODULE BYTES | code_o2 MODULE BYTES | stack FUNCTION|* BYTES
# A module without a code budget is reported (check budget ... unbudgeted)
# but does not fail.
set -u
if [ $# -lt 1 ]; then
    echo "usage: $0 M4F_BUILD_DIR [BUDGET_FILE]" >&2
    exit 2
fi
m4f=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
budget=${2:-$here/footprint_budget.txt}
nm=${SFIT_NM:-arm-none-eabi-nm}
objdump=${SFIT_OBJDUMP:-arm-none-eabi-objdump}
size=${SFIT_SIZE:-arm-none-eabi-size}
gcc=${SFIT_GCC:-arm-none-eabi-gcc}
arch="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard"
if [ -f "$m4f/core.txt" ]; then # the tree's core (tests/target, SFIT_ARM_CORE)
    arch=$(sed -n 's/^arch //p' "$m4f/core.txt")
fi

for f in "$m4f/libsfit_fp_Os.a" "$m4f/libsfit_fp_O2.a" "$m4f/libsfit_fp_sizes_a.a"; do
    if [ ! -f "$f" ]; then
        echo "footprint.sh: $f missing: build tests/target first (tests/target/build.sh)" >&2
        exit 2
    fi
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail=0

# ---- code size per module ----------------------------------------------------
for opt in Os O2; do
    "$size" "$m4f/libsfit_fp_$opt.a" | awk -v opt="$opt" 'NR > 1 {
        m = $6; sub(/\.c\.(obj|o)$/, "", m); print opt, m, $1, $2, $3 }'
done >"$tmp/size.txt"
awk '
{ t[$2 " " $1] = $3; mods[$2] = 1; if ($4 + $5 > 0) bad[$2] = $4 + $5 }
END {
    for (m in mods) { printf "code %s %d %d\n", m, t[m " Os"], t[m " O2"]; os += t[m " Os"]; o2 += t[m " O2"] }
    printf "code_total %d %d\n", os, o2
    for (m in bad) printf "staticdata %s %d\n", m, bad[m]
}' "$tmp/size.txt" | sort >"$tmp/code.txt"
grep -v '^staticdata' "$tmp/code.txt"

# ---- minimal application -----------------------------------------------------
# minimal_app.c (moments + the default fit, sfit_fit_moments_default) linked
# with --gc-sections against
# the -Os and -O2 objects: the .text/.rodata input sections taken from the
# library (link map); SFIT_MINAPP_DETAIL=1 lists them on stderr
# ("section NAME OPT SECTION BYTES"). Reported as the pseudo-module minimal_app (budget lines
# code_os/code_o2 minimal_app); not part of code_total. -lm: a core without
# an FPU takes sqrtf from libm (not counted: only libsfit's sections are).
# minimal_app_screened: the application with sfit_fit_moments(m, NULL, ...)
# instead (-DSFIT_MINAPP_SCREENED: the screen and its full-solver fallback);
# minimal_app_lean: that one against the library built without the
# fallback (libsfit_fp_lean_*, -DSFIT_FULL_SOLVER=0).
# Each application's bytes are also grouped into parts (records "part APP
# PART OS O2", the itemisation of docs/cost.md), by the object and the
# section: accumulator (sfit_moments.c but its system, sfit_check.c), system
# (sfit_i_moments_system), driver (sfit_fit.c, the option checks and the
# coincidence scale of sfit_solve.c, the rounding test of sfit_lean.c),
# screen (sfit_i_solve_lean), cholesky (sfit_mat3.c but the Jacobi,
# sfit_mat3_i.c), solver (the rest of sfit_solve.c), jacobi
# (sfit_i_eig_sym and its rotation); anything else is "other".
srcroot=$(cd "$here/../.." && pwd)
minapp() { # minapp NAME LIBPREFIX [CFLAGS] -> "code NAME OS O2" (parts in $tmp/NAME_OPT.parts)
    for opt in Os O2; do
        if [ -f "$m4f/lib$2_$opt.a" ] &&
            "$gcc" $arch -std=c99 -"$opt" -fno-math-errno -ffunction-sections -fdata-sections \
                -I"$srcroot/lib/include" -I"$srcroot/port" -I"$srcroot/port/cortex-m4f" \
                ${3:-} -c "$here/minimal_app.c" -o "$tmp/$1_$opt.o" &&
            "$gcc" $arch --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections \
                -Wl,-Map="$tmp/$1_$opt.map" "$tmp/$1_$opt.o" "$m4f/lib$2_$opt.a" \
                -lm -o "$tmp/$1_$opt.elf" >/dev/null 2>&1; then
            awk '/^Linker script and memory map/ { on = 1 } on' "$tmp/$1_$opt.map" | awk -v lib="lib$2_" \
                -v detail="${SFIT_MINAPP_DETAIL:-0}" -v tag="$1 $opt" '
            function hex(s,  i, v) { v = 0; s = tolower(s); sub(/^0x/, "", s)
                for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789abcdef", substr(s, i, 1)) - 1
                return v }
            function part(f, sec,  o, fn) {
                o = f; sub(/^.*\(/, "", o); sub(/\.c\.(obj|o)\)$/, "", o)
                fn = sec; sub(/^\.(text|rodata)\./, "", fn); sub(/\..*$/, "", fn)
                if (o == "sfit_moments") return (fn == "sfit_i_moments_system") ? "system" : "accumulator"
                if (o == "sfit_check") return "accumulator"
                if (o == "sfit_fit") return "driver"
                if (o == "sfit_lean") return (fn == "sfit_i_rounding_test") ? "driver" : "screen"
                if (o == "sfit_solve") return (fn ~ /^sfit_i_(check_cfg|check_noise|coincident_scale)$/) ? "driver" : "solver"
                if (o == "sfit_mat3") return (fn ~ /^(sfit_i_eig_sym|prv_rotate|prv_rot2)$/) ? "jacobi" : "cholesky"
                if (o == "sfit_mat3_i") return "cholesky"
                return "other"
            }
            /^ \.(text|rodata)/ { sec = $1; if (NF == 1) { getline; sz = $2; f = $3 } else { sz = $3; f = $4 }
                if (index(f, lib) > 0) { tot += hex(sz); pt[part(f, sec)] += hex(sz)
                    if (detail == 1) printf "section %s %s %d\n", tag, sec, hex(sz) > "/dev/stderr" } }
            END { for (p in pt) print p, pt[p] > parts; print tot + 0 }' parts="$tmp/$1_$opt.parts"
        else
            echo -1
        fi
    done | tr '\n' ' ' | awk -v name="$1" '{ printf "code %s %d %d\n", name, $1, $2 }'
}
minparts() { # minparts NAME -> "part NAME PART OS O2" (after minapp NAME)
    [ -f "$tmp/$1_Os.parts" ] && [ -f "$tmp/$1_O2.parts" ] &&
        awk -v name="$1" 'FILENAME ~ /_Os\.parts$/ { os[$1] = $2; p[$1] = 1; next }
            { o2[$1] = $2; p[$1] = 1 }
            END { for (k in p) printf "part %s %s %d %d\n", name, k, os[k], o2[k] }' \
            "$tmp/$1_Os.parts" "$tmp/$1_O2.parts" | sort
}
{
    minapp minimal_app sfit_fp
    minapp minimal_app_screened sfit_fp -DSFIT_MINAPP_SCREENED
    minapp minimal_app_lean sfit_fp_lean -DSFIT_MINAPP_SCREENED
} >"$tmp/minapp.txt"
cat "$tmp/minapp.txt"
for a in minimal_app minimal_app_screened minimal_app_lean; do minparts "$a"; done
if grep -q -- '-1' "$tmp/minapp.txt"; then
    echo "check minimal_app FAIL the minimal application did not link"
    fail=1
fi

# ---- struct sizes -------------------------------------------------------------
"$nm" -S "$m4f/libsfit_fp_sizes_a.a" | awk '$4 ~ /^fc_sizeof_/ { n = $4; sub(/^fc_sizeof_/, "", n); print n, $2 }' |
    while read -r n hx; do printf 'struct %s %d\n' "$n" "$((0x$hx))"; done

# ---- checks on the objects --------------------------------------------------------
# Heap: no reference to an allocator.
heap=$("$nm" -u "$m4f/libsfit_fp_Os.a" "$m4f/libsfit_fp_O2.a" "$m4f/sfit/lib/libsfit.a" 2>/dev/null |
    awk '$1 == "U" && $2 ~ /^(_?malloc|_?calloc|_?realloc|_?free|_malloc_r|_calloc_r|_realloc_r|_free_r|_?sbrk|_sbrk_r|aligned_alloc|posix_memalign|memalign|alloca|__builtin_alloca)$/ { print $2 }' | sort -u | tr '\n' ' ')
if [ -n "$heap" ]; then
    echo "check heap FAIL references $heap"
    fail=1
else
    echo "check heap ok no allocator referenced"
fi
# Mutable static data: no .data/.bss/COMMON in any library object.
sd=$(grep '^staticdata' "$tmp/code.txt" | awk '{ printf "%s(%d B) ", $2, $3 }')
sdsym=$("$nm" "$m4f/libsfit_fp_Os.a" "$m4f/libsfit_fp_O2.a" "$m4f/sfit/lib/libsfit.a" 2>/dev/null |
    awk 'NF == 3 && $2 ~ /^[dDbBcC]$/ { print $3 }' | sort -u | tr '\n' ' ')
if [ -n "$sd$sdsym" ]; then
    echo "check static_data FAIL $sd $sdsym"
    fail=1
else
    echo "check static_data ok no .data/.bss/COMMON"
fi
# Double precision: no soft-double helper referenced, no .f64 instruction
# (the same checker as tests/scripts/test_m4f_build.sh).
if dbl=$("$here/../../tests/target/check_double.sh" "$m4f/libsfit_fp_Os.a" "$m4f/libsfit_fp_O2.a" \
    "$m4f/sfit/lib/libsfit.a" 2>&1); then
    echo "check double ok no double helper, no .f64"
else
    echo "check double FAIL $(printf '%s' "$dbl" | tr '\n' ' ')"
    fail=1
fi

# ---- worst-case stack ---------------------------------------------------------------
# Public functions: global text symbols, minus the sfit_i_ internals.
"$nm" -g --defined-only "$m4f/libsfit_fp_O2.a" | awk '$2 == "T" && $3 !~ /^sfit_i_/ { print $3 }' |
    sort -u >"$tmp/public.txt"
# The C-library / libgcc / libm callees, as call-graph nodes of their own:
# each is bounded by its whole object file (the sum of every push, vpush
# and sp adjustment in it: routines written in assembly share code and fall
# through into each other, e.g. libgcc's soft float), with an edge to every
# symbol the object calls or tail-calls outside itself (relocations).
# ext.txt: NAME FRAME CALLEE...   (FRAME -1: not found in those libraries)
libc=$("$gcc" $arch -print-file-name=libc_nano.a)
libm=$("$gcc" $arch -print-file-name=libm.a)
libgcc=$("$gcc" $arch -print-libgcc-file-name)
for opt in Os O2; do
    find "$m4f/CMakeFiles/sfit_fp_$opt.dir" -name '*.ci' -exec cat {} + >"$tmp/cg_$opt.ci"
done
"$nm" -A --defined-only "$libc" "$libm" "$libgcc" 2>/dev/null |
    awk 'NF == 3 && $2 ~ /^[TW]$/ { n = split($1, p, ":"); if (!($3 in seen)) { seen[$3] = 1; print $3, p[1], p[2] } }' \
    >"$tmp/libsyms.txt"
awk '/^edge:/ { s = $0; sub(/.*targetname: "/, "", s); sub(/".*/, "", s); print s }' \
    "$tmp/cg_Os.ci" "$tmp/cg_O2.ci" | sort -u >"$tmp/queue.txt"
: >"$tmp/ext.txt"  # SFIT_FP_DEBUG=1 keeps a copy in $m4f/footprint_ext.txt
: >"$tmp/done.txt"
mkdir -p "$tmp/obj"
round=0
while [ -s "$tmp/queue.txt" ] && [ "$round" -lt 16 ]; do
    round=$((round + 1))
    : >"$tmp/next.txt"
    while read -r t; do
        grep -qx "$t" "$tmp/done.txt" && continue
        echo "$t" >>"$tmp/done.txt"
        if grep -q "^node: { title: \"$t\" label: \"[^\"]*bytes" "$tmp/cg_O2.ci"; then
            continue # defined in the library
        fi
        loc=$(awk -v t="$t" '$1 == t { print $2, $3; exit }' "$tmp/libsyms.txt")
        if [ -z "$loc" ]; then
            echo "$t -1" >>"$tmp/ext.txt"
            continue
        fi
        arc=${loc% *}
        mem=${loc#* }
        d="$tmp/obj/$(printf '%s' "$arc" | tr '/' '_')"
        mkdir -p "$d"
        [ -f "$d/$mem" ] || (cd "$d" && "${SFIT_AR:-arm-none-eabi-ar}" x "$arc" "$mem")
        # every symbol the object defines (aliases included: objdump labels
        # one name per address)
        "$nm" --defined-only "$d/$mem" 2>/dev/null | awk 'NF == 3 { print "def", $3 }' >"$tmp/defs.txt"
        "$objdump" -dr --no-show-raw-insn "$d/$mem" 2>/dev/null | awk -v name="$t" '
        function nregs(ops,  l, a, k, i, r, n, lo, hi) {
            if (!match(ops, /\{[^}]*\}/)) return 0
            l = substr(ops, RSTART + 1, RLENGTH - 2); k = split(l, a, /, */); n = 0
            for (i = 1; i <= k; i++) {
                if (split(a[i], r, "-") == 2) { lo = r[1]; hi = r[2]; gsub(/[^0-9]/, "", lo); gsub(/[^0-9]/, "", hi); n += (hi - lo + 1) * (a[i] ~ /^d/ ? 2 : 1) }
                else n += (a[i] ~ /^d/ ? 2 : 1)
            }
            return n
        }
        FILENAME != "-" && $1 == "def" { def[$2] = 1; next }
        /^[0-9a-f]+ <[^>]*>:$/ { next }
        /R_ARM_(THM_CALL|THM_JUMP24|THM_JUMP19|CALL|JUMP24|PC24)/ { c = $NF; sub(/[+-]0x[0-9a-f]+$/, "", c); call[c] = 1; next }
        /\t/ {
            split($0, f, "\t"); m = f[2]; o = f[3]
            if (m ~ /^(push|stmdb)/ && o ~ /sp/ || m ~ /^push/) b += 4 * nregs(o)
            if (m ~ /^vpush/) b += 4 * nregs(o)
            if (m ~ /^sub/ && o ~ /^sp, sp, #/ || m ~ /^sub/ && o ~ /^sp, #/) { v = o; sub(/.*#/, "", v); b += v + 0 }
        }
        END {
            line = name " " (b + 0)
            for (c in call) if (!(c in def) && c !~ /^\./) line = line " " c
            print line
        }' "$tmp/defs.txt" - >>"$tmp/ext.txt"
        tail -n 1 "$tmp/ext.txt" | cut -d' ' -f3- | tr ' ' '\n' | sed '/^$/d' >>"$tmp/next.txt"
    done <"$tmp/queue.txt"
    sort -u "$tmp/next.txt" >"$tmp/queue.txt"
done
[ "${SFIT_FP_DEBUG:-0}" = 1 ] && cp "$tmp/ext.txt" "$m4f/footprint_ext.txt"

for opt in Os O2; do
    awk -v opt="$opt" '
    FILENAME ~ /ext\.txt$/ {
        if ($2 < 0) { ext[$1] = -1; next }
        frame[$1] = $2
        for (i = 3; i <= NF; i++) { ne[$1]++; e[$1, ne[$1]] = $i }
        next
    }
    FILENAME ~ /public\.txt$/ { pub[$1] = 1; next }
    /^node:/ {
        t = $0; sub(/^node: \{ title: "/, "", t); sub(/".*/, "", t)
        if (match($0, /[0-9]+ bytes \([a-z,]*\)/)) {
            s = substr($0, RSTART, RLENGTH); q = s; sub(/ bytes.*/, "", s)
            frame[t] = s + 0
            if (q ~ /dynamic/) dyn[t] = 1
        }
        next
    }
    /^edge:/ {
        s = $0; sub(/.*sourcename: "/, "", s); sub(/".*/, "", s)
        d = $0; sub(/.*targetname: "/, "", d); sub(/".*/, "", d)
        ne[s]++; e[s, ne[s]] = d
        next
    }
    # depth-first, iterative (no recursion in the library: a cycle is reported)
    function worst(f,    sp, stk, it, best, i, c, w, n) {
        if (f in memo) return memo[f]
        if (!(f in frame)) { if (f in ext) return ext[f]; return -1 }
        if (onpath[f]) return -2
        onpath[f] = 1
        best = 0
        for (i = 1; i <= ne[f]; i++) {
            c = e[f, i]
            w = worst(c)
            if (w < 0) { onpath[f] = 0; memo[f] = w; why[f] = (w == -2 ? "recursion via " c : "unknown callee " c (c in why ? " (" why[c] ")" : "")); return w }
            if (w > best) best = w
        }
        onpath[f] = 0
        if (f in dyn) { memo[f] = -3; why[f] = "dynamic frame"; return -3 }
        memo[f] = frame[f] + best
        return memo[f]
    }
    END {
        for (f in pub) { w = worst(f); printf "%s %s %d %s\n", opt, f, w, (w < 0 ? why[f] : "") }
    }' "$tmp/ext.txt" "$tmp/public.txt" "$tmp/cg_$opt.ci"
done >"$tmp/stack.txt"
awk '
{ v[$2, $1] = $3; f[$2] = 1; if ($3 < 0) { note[$2] = $0 } }
END { for (x in f) printf "stack %s %d %d%s\n", x, v[x, "Os"], v[x, "O2"], (x in note ? " " note[x] : "") }' \
    "$tmp/stack.txt" | sort >"$tmp/stack_rec.txt"
cat "$tmp/stack_rec.txt"
unb=$(awk '$3 < 0 || $4 < 0 { printf "%s ", $2 }' "$tmp/stack_rec.txt")
if [ -n "$unb" ]; then
    echo "check stack_bounded FAIL no bound for: $unb"
    fail=1
else
    echo "check stack_bounded ok every public function has a static bound"
fi

# ---- budgets ---------------------------------------------------------------------------
if [ -f "$budget" ]; then
    awk '
    FILENAME == ARGV[1] {
        sub(/#.*/, ""); if (NF < 3) next
        if ($1 == "stack") sb[$2] = $3; else if ($1 == "code_os") co[$2] = $3; else if ($1 == "code_o2") c2[$2] = $3
        next
    }
    $1 == "code" {
        if (!($2 in co) || !($2 in c2)) { printf "check budget ok unbudgeted module %s (%d B -Os, %d B -O2)\n", $2, $3, $4; next }
        if ($3 > co[$2]) { printf "check budget FAIL code -Os %s %d B > %d B\n", $2, $3, co[$2]; bad = 1 }
        if ($4 > c2[$2]) { printf "check budget FAIL code -O2 %s %d B > %d B\n", $2, $4, c2[$2]; bad = 1 }
    }
    $1 == "stack" {
        lim = ($2 in sb) ? sb[$2] : (("*" in sb) ? sb["*"] : -1)
        if (lim < 0) next
        if ($3 > lim || $4 > lim) { printf "check budget FAIL stack %s %d/%d B > %d B\n", $2, $3, $4, lim; bad = 1 }
    }
    END { if (!bad) print "check budget ok within " ARGV[1]; exit bad }' "$budget" "$tmp/code.txt" \
        "$tmp/minapp.txt" "$tmp/stack_rec.txt" || fail=1
else
    echo "check budget ok no budget file ($budget)"
fi
exit "$fail"
