#!/usr/bin/env bash
# run_tests.sh RUNNER... - run every cmocka runner, print each one's output,
# and close with one summary line: "tests: N passed, N failed".
# Exits non-zero when any test failed or any runner crashed.
set -uo pipefail
passed=0
failed=0
bad_runners=()
for r in "$@"; do
    out=$("$r" 2>&1)
    rc=$?
    printf '%s\n' "$out"
    p=$(printf '%s\n' "$out" | sed -n 's/^\[  PASSED  \] \([0-9]*\) test(s)\./\1/p' | tail -n 1)
    f=$(printf '%s\n' "$out" | sed -n 's/^\[  FAILED  \] \([0-9]*\) test(s), listed below:/\1/p' | tail -n 1)
    passed=$((passed + ${p:-0}))
    failed=$((failed + ${f:-0}))
    if [ $rc -ne 0 ] && [ -z "$f" ]; then
        bad_runners+=("$(basename "$r") (exit $rc)")
        failed=$((failed + 1))
    fi
done
for b in "${bad_runners[@]+"${bad_runners[@]}"}"; do
    echo "runner failed without a cmocka report: $b"
done
echo "tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
