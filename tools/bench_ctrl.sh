#!/usr/bin/env bash
# bench_ctrl.sh BIN [STEPS] - cost of one ctrl_step() on x86-64 (-O2),
# measured with callgrind, collecting inside ctrl_step only:
#   instructions per step  = Ir collected / steps
#   divisions per step     = executed div{ss,sd} inside the binary / steps
#   square roots per step  = executed sqrt{ss,sd} (and sqrtf calls) / steps
#   sin/cos per step       = executed calls to sinf/cosf/sincosf / steps
# Prints figures; asserts nothing.
set -euo pipefail
bin=$1
n=${2:-20000}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --dump-instr=yes --toggle-collect=ctrl_step \
    --callgrind-out-file="$out/cg.out" "$bin" "$n" > "$out/stdout" 2> "$out/stderr"
objdump -d --no-show-raw-insn "$bin" > "$out/dis"
python3 - "$out/cg.out" "$out/dis" "$n" <<'PY'
import re, sys
cg, dis, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
# executions per instruction address (callgrind --dump-instr=yes format;
# the line after calls= is the call's inclusive cost, not the address's own)
count, total, addr, skip, npos = {}, 0, 0, False, 1
pos_rx = re.compile(r"^(0x[0-9a-fA-F]+|[+-]\d+|\*)$")
for line in open(cg):
    f = line.split()
    if line.startswith("positions:"):
        npos = len(f) - 1            # "instr line": two position columns
        continue
    if line.startswith("calls="):
        skip = True
        continue
    if len(f) < npos + 1 or not pos_rx.match(f[0]) or not f[npos].isdigit():
        continue
    a = f[0]
    if a.startswith("0x"):
        addr = int(a, 16)
    elif a != "*":
        addr += int(a)
    if skip:
        skip = False
        continue
    ir = int(f[npos])
    count[addr] = count.get(addr, 0) + ir
    total += ir
kinds = {"div": re.compile(r"\bv?div(ss|sd)\b"), "sqrt": re.compile(r"\bv?sqrt(ss|sd)\b|call.*<sqrtf?(@plt)?>"),
         "sincos": re.compile(r"call.*<(sinf|cosf|sincosf|sin|cos|sincos)(@plt)?>")}
tally = {k: 0 for k in kinds}
for line in open(dis):
    m = re.match(r"^\s*([0-9a-f]+):\s+(.*)$", line)
    if not m:
        continue
    a, ins = int(m.group(1), 16), m.group(2)
    for k, rx in kinds.items():
        if rx.search(ins):
            tally[k] += count.get(a, 0)
print(f"ctrl_step (speed mode, x86-64 -O2, callgrind): {total / n:.0f} instructions per step")
print(f"  per step: {tally['div'] / n:.2f} divisions, {tally['sqrt'] / n:.2f} square roots, "
      f"{tally['sincos'] / n:.2f} sin/cos calls (sinf+cosf of one angle count 2)")
PY
