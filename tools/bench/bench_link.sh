#!/usr/bin/env bash
# bench_link.sh BIN [CALLS] - the link's cost in the control ISR: x86-64 -O2
# instructions per link_isr() call, measured with callgrind collecting
# inside link_isr only, one dump per call, for tools/bench/bench_link.c's cases
# (idle; a capture armed, waiting; a capture armed again and triggering
# with an 8-variable stream every period: the worst a period can take).
# Prints per case the typical (median) and worst (largest) call; asserts
# nothing.
set -euo pipefail
bin=$1
n=${2:-20000}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for m in idle capture worst; do
    valgrind --tool=callgrind --toggle-collect=link_isr --dump-after=link_isr --combine-dumps=yes \
        --dump-instr=no --dump-line=no --callgrind-out-file="$out/$m.cg" "$bin" "$n" "$m" \
        > "$out/$m.stdout" 2> "$out/$m.stderr"
    python3 - "$out/$m.cg" "$n" "$m" <<'PY'
import statistics, sys
path, n, mode = sys.argv[1], int(sys.argv[2]), sys.argv[3]
per = [int(l.split()[1]) for l in open(path) if l.startswith("totals:")][:n]
print(f"bench-link: link_isr {mode:<8} typical {int(statistics.median(per)):4d}, worst {max(per):4d} "
      "instructions per period (x86-64 -O2, callgrind)")
PY
done
