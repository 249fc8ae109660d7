#!/usr/bin/env bash
# bench_link.sh BIN [CALLS] - the link's cost in the control ISR: x86-64 -O2
# instructions per link_isr() call, measured with callgrind collecting
# inside link_isr only, for tools/bench_link.c's cases (idle, capture
# armed, capture armed plus an 8-variable stream every period: the worst a
# period can take; each case's calls take the same path, so its mean is
# also its worst). Prints figures; asserts nothing.
set -euo pipefail
bin=$1
n=${2:-20000}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for m in idle capture worst; do
    valgrind --tool=callgrind --toggle-collect=link_isr --callgrind-out-file="$out/$m.cg" "$bin" "$n" "$m" \
        > "$out/$m.stdout" 2> "$out/$m.stderr"
    ir=$(callgrind_annotate "$out/$m.cg" 2>/dev/null | sed -n 's/^ *\([0-9,]*\) .*PROGRAM TOTALS.*/\1/p' | tr -d ,)
    printf 'bench-link: link_isr %-8s %6.1f instructions per period (x86-64 -O2, callgrind)\n' "$m" \
        "$(echo "$ir / $n" | bc -l)"
done
