#!/bin/sh
# SPDX-License-Identifier: MIT
#
# update_block.sh NAME BLOCK_FILE DOC...
#
# Replace, in each DOC, the lines between <!-- NAME:begin --> and
# <!-- NAME:end --> with the contents of BLOCK_FILE (the generated tables
# of run.sh --update-docs and cores.sh --update-docs).
# Exit status 2 when a DOC lacks the markers (nothing is changed in it).
set -u
if [ $# -lt 3 ]; then
    echo "usage: $0 NAME BLOCK_FILE DOC..." >&2
    exit 2
fi
name=$1
block=$2
shift 2
for doc in "$@"; do
    if ! grep -q "<!-- $name:begin -->" "$doc" || ! grep -q "<!-- $name:end -->" "$doc"; then
        echo "update_block: $doc has no <!-- $name:begin/end --> markers" >&2
        exit 2
    fi
    awk -v tf="$block" -v b="<!-- $name:begin -->" -v e="<!-- $name:end -->" '
        index($0, b) { print; while ((getline l < tf) > 0) print l; close(tf); skip = 1; next }
        index($0, e) { skip = 0 }
        !skip { print }' "$doc" >"$doc.tmp.$$" && mv "$doc.tmp.$$" "$doc"
    echo "update_block: updated $doc" >&2
done
