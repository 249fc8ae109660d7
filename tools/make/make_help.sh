#!/usr/bin/env bash
# make_help.sh [--check] MAKEFILE... - `make help`: one line per target
# documented with a trailing "## text" on its rule line
# ("name: prerequisites ## what it does"), in the order of the files.
# --check instead counts them, or exits 1 naming every
# .PHONY target of the files that has no "## " line (part of `make check`,
# so a new target cannot be left out of `make help`).
set -uo pipefail
check=0
if [ "${1:-}" = --check ]; then check=1; shift; fi
[ $# -gt 0 ] || { echo "usage: make_help.sh [--check] MAKEFILE..." >&2; exit 2; }

# "target<TAB>text" of each documented rule line (several targets on one line: each)
documented() {
    awk '/^[A-Za-z0-9_.%-][A-Za-z0-9_.% -]*:([^=]|$).*## / {
             split($0, parts, "## "); text = parts[2]
             split($0, head, ":"); n = split(head[1], names, " ")
             for (i = 1; i <= n; i++) printf "%s\t%s\n", names[i], text
         }' "$@"
}

if [ "$check" -eq 0 ]; then
    documented "$@" | awk -F '\t' '{ printf "  make %-20s %s\n", $1, $2 }'
    exit 0
fi

phony=$(awk '/^\.PHONY:/ { for (i = 2; i <= NF; i++) print $i }' "$@" | sort -u)
have=$(documented "$@" | cut -f1 | sort -u)
missing=$(comm -23 <(printf '%s\n' "$phony") <(printf '%s\n' "$have"))
if [ -n "$missing" ]; then
    echo "make help: .PHONY targets without a '## ' description on their rule line:" $missing
    exit 1
fi
echo "make help: every .PHONY target ($(printf '%s\n' "$phony" | wc -l)) is described"
