#!/usr/bin/env bash
# ram_budget.sh [OUTDIR] - the RAM gate of `make check` (after isr_path.sh,
# whose objects it reads): tools/check/ram_budget.py on
# firmware/f28335/f28335_flash.cmd (with BUILD/f28335/drive.map when a cl2000 build
# left one), its report in OUTDIR/ram_budget.txt; then the gate's own
# test: a copy of the .cmd whose RAML0L5 (the run range of ramfuncs) is
# shrunk to 0x1000 words must fail it.
set -uo pipefail
out=${1:-build/check}
build=$(dirname "$out")
cd "$(dirname "$0")/../.."
gate=(python3 tools/check/ram_budget.py --objdir "$out/isr" --mk firmware/f28335/target.mk
      --map "$build/f28335/drive.map")

"${gate[@]}" --cmd firmware/f28335/f28335_flash.cmd --out "$out/ram_budget.txt"
rc=$?
[ $rc -eq 0 ] || exit $rc

shrunk="$out/ram_budget_shrunk.cmd"
sed -E 's/^([[:space:]]*RAML0L5[[:space:]]*:[[:space:]]*origin = 0x008000, length = )0x[0-9A-Fa-f]+/\10x001000/' \
    firmware/f28335/f28335_flash.cmd > "$shrunk"
if ! grep -Eq '^[[:space:]]*RAML0L5[[:space:]]*:[[:space:]]*origin = 0x008000, length = 0x001000' "$shrunk"; then
    echo "ram_budget: FAIL self-test: no 'RAML0L5 : origin = 0x008000, length = 0x...' line in firmware/f28335/f28335_flash.cmd to shrink"
    exit 1
fi
"${gate[@]}" --cmd "$shrunk" > "$out/ram_budget_shrunk.txt"
rc=$?
if [ $rc -ne 1 ] || ! grep -q '^ram_budget: FAIL RAML0L5' "$out/ram_budget_shrunk.txt"; then
    echo "ram_budget: FAIL self-test: RAML0L5 shrunk to 0x1000 words did not fail the gate (exit $rc):"
    sed 's/^/    /' "$out/ram_budget_shrunk.txt"
    exit 1
fi
echo "ram_budget: self-test: RAML0L5 shrunk to 0x1000 words fails the gate, as it must"
