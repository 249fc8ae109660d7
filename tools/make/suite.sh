#!/usr/bin/env bash
# suite.sh NAME DIR CMD... - run one suite of `make test`, pass its output
# through, and record "PASSED FAILED" in DIR/NAME for tools/make/test_verdict.sh.
# The counts are those of the suite's last closing line "N passed, N failed"
# (one word and a colon may stand before it); a suite without one counts
# as one test. A suite that exits non-zero with no failure counted (a
# crashed runner) counts one failure more. Exits with the suite's status.
set -uo pipefail
name=$1 dir=$2
shift 2
mkdir -p "$dir"
out="$dir/$name.out"
"$@" | tee "$out"
rc=${PIPESTATUS[0]}
line=$(grep -E '^([A-Za-z_ -]+: )?[0-9]+ passed, [0-9]+ failed' "$out" | tail -n 1)
if [ -n "$line" ]; then
    passed=$(printf '%s\n' "$line" | sed -E 's/^([A-Za-z_ -]+: )?([0-9]+) passed, ([0-9]+) failed.*/\2/')
    failed=$(printf '%s\n' "$line" | sed -E 's/^([A-Za-z_ -]+: )?([0-9]+) passed, ([0-9]+) failed.*/\3/')
elif [ "$rc" -eq 0 ]; then
    passed=1 failed=0
else
    passed=0 failed=0
fi
[ "$rc" -ne 0 ] && [ "$failed" -eq 0 ] && failed=1
echo "$passed $failed" > "$dir/$name"
exit "$rc"
