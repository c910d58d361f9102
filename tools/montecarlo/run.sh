#!/bin/sh
# SPDX-License-Identifier: MIT
#
# tools/montecarlo/run.sh [--quick] [--build-dir DIR] [--out DIR] [--no-plot] [--no-coverage]
#
# Regenerates the statistical validation of docs/validation.md in one
# command:
#  1. configures and builds the harness (tools/montecarlo, which pulls in
#     the library from the repository root) in Release mode into DIR
#     (default <source>/build-montecarlo);
#  2. runs it (fixed seeds): writes the CSVs, results_table.md and
#     claims.md into the output directory (default <source>/docs/figures);
#     then sfit_mc_beyond writes beyond_table.md (docs/beyond.md), and
#     sfit_mc_coverage coverage_table.md and coverage.csv (docs/coverage.md;
#     245 scenarios x 3 estimators x 10^4 trials at N <= 100, 3000 at
#     N = 1000, 1000 at N = 10^4: about 3 minutes of CPU;
#     --no-coverage skips it); sfit_mc_joint_bench the joint benchmark of
#     docs/joint_benchmark.md (joint_bench.csv, joint_bench_table.md,
#     joint_bench_claims.md; about a minute);
#  3. draws the PNGs with gnuplot (tools/montecarlo/plots.gp, coverage.gp,
#     joint_bench.gp).
# --quick: a tenth of the trials (smoke test), written by default into
#          DIR/quick instead of docs/figures.
# The full run takes about 1.5 minutes of CPU on one core (fixed seeds:
# the CSVs are identical from run to run on the same platform).
# Exit status: 0 on success; 1 on a build or run failure; 77 when cmake or
# gnuplot is missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build="$src/build-montecarlo"
out=""
quick=""
plot=1
coverage=1
while [ $# -gt 0 ]; do
    case $1 in
    --quick) quick=quick ;;
    --build-dir) build=$2; shift ;;
    --out) out=$2; shift ;;
    --no-plot) plot=0 ;;
    --no-coverage) coverage=0 ;;
    -h | --help) sed -n '3,26p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
if [ -z "$out" ]; then
    if [ -n "$quick" ]; then out="$build/quick"; else out="$src/docs/figures"; fi
fi
command -v cmake >/dev/null 2>&1 || { echo "run.sh: cmake not found" >&2; exit 77; }
if [ "$plot" = 1 ] && ! command -v gnuplot >/dev/null 2>&1; then
    echo "run.sh: gnuplot not found (apt-get install gnuplot-nox), or use --no-plot" >&2
    exit 77
fi
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null || exit 1
cmake --build "$build" -j2 >/dev/null || exit 1
mkdir -p "$out"
echo "run.sh: running the Monte Carlo into $out" >&2
"$build/sfit_mc" "$out" $quick || exit 1
"$build/sfit_mc_beyond" "$out" $quick || exit 1
if [ "$coverage" = 1 ]; then
    "$build/sfit_mc_coverage" "$out" $quick || exit 1
    "$build/sfit_mc_coverage_joint" "$out" $quick || exit 1
fi
"$build/sfit_mc_joint_bench" "$out" ${quick:-full} || exit 1
if [ "$plot" = 1 ]; then
    gnuplot -e "d='$out'" "$here/plots.gp" || exit 1
    if [ "$coverage" = 1 ]; then
        gnuplot -e "d='$out'" "$here/coverage.gp" || exit 1
    fi
    gnuplot -e "d='$out'" "$here/joint_bench.gp" || exit 1
fi
echo "run.sh: done; see $out/claims.md, $out/results_table.md and $out/beyond_table.md" >&2
