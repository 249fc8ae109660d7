#!/usr/bin/env bash
# test_verdict.sh DIR SUITE... - the closing verdict of `make test`: the
# counts tools/make/suite.sh recorded in DIR, one line a suite, then the sum as
# the last line on stdout, "make test: N passed, N failed". A suite that
# recorded nothing (its build or a prerequisite failed) counts as one
# failure. Exits 1 when anything failed.
set -uo pipefail
dir=$1
shift
passed=0 failed=0
echo "make test: suites"
for s in "$@"; do
    if [ -f "$dir/$s" ]; then
        read -r p f < "$dir/$s"
        printf '  %-22s %5d passed, %d failed\n' "$s" "$p" "$f"
    else
        p=0 f=1
        printf '  %-22s did not run (its build or a prerequisite failed: see above)\n' "$s"
    fi
    passed=$((passed + p))
    failed=$((failed + f))
done
echo "make test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
