#!/usr/bin/env bash
# Compares the C# structs' sizes and field offsets (mono drive.exe --layout) with the C
# header's: writes a C program with sizeof/offsetof for every line, runs it, diffs.
# usage: check_layout.sh CSHARP_LAYOUT.txt INCLUDE_DIR
set -euo pipefail
cs=$1
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
echo "C# layout equals the C header's: $(grep -c '^size' "$cs") structs, $(grep -c '^offset' "$cs") fields"
