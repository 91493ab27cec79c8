#!/usr/bin/env bash
# Compares a binding's struct sizes and field offsets with the C header's: the binding prints
# "size TYPE N" and "offset TYPE FIELD N" lines (C#: mono drive.exe --layout; Python:
# python -m wethair.layout); this writes a C program with sizeof/offsetof for every line,
# runs it, and diffs.
# usage: check_layout.sh LAYOUT.txt INCLUDE_DIR
set -euo pipefail
cs=$1  # the binding's lines
inc=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
{
    echo '#include <stddef.h>'
    echo '#include <stdio.h>'
    echo '#include "wethair.h"'
    echo 'int main(void) {'
    while read -r kind ty field _; do
        if [ "$kind" = size ]; then
            echo "    printf(\"size $ty %zu\\n\", sizeof($ty));"
        else
            echo "    printf(\"offset $ty $field %zu\\n\", offsetof($ty, $field));"
        fi
    done <"$cs"
    echo '    return 0;'
    echo '}'
} >"$tmp/layout.c"
cc -std=c11 -Wall -Werror -I"$inc" "$tmp/layout.c" -o "$tmp/layout"
"$tmp/layout" >"$tmp/c.txt"
diff -u "$tmp/c.txt" "$cs"
echo "$(basename "$cs"): layout equals the C header's: $(grep -c '^size' "$cs") structs, $(grep -c '^offset' "$cs") fields"
