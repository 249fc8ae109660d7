#!/usr/bin/env bash
# bench_ctrl.sh BIN [STEPS] - cost of one ctrl_step() on x86-64 (-O2) for
# the conventional and the proposed method (step 2 running; also with
# track_R, the d-current injection) and the
# proposed method's overhead, measured with callgrind, collecting inside
# ctrl_step only:
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
for m in conventional proposed proposed_track_R; do
    valgrind --tool=callgrind --dump-instr=yes --toggle-collect=ctrl_step \
        --callgrind-out-file="$out/$m.cg" "$bin" "$n" "$m" > "$out/$m.stdout" 2> "$out/$m.stderr"
done
objdump -d --no-show-raw-insn "$bin" > "$out/dis"
python3 - "$out/conventional.cg" "$out/proposed.cg" "$out/proposed_track_R.cg" "$out/dis" "$n" <<'PY'
import re, sys
cgs, dis, n = sys.argv[1:4], sys.argv[4], int(sys.argv[5])


def cost(cg):
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
    return count, total


kinds = {"div": re.compile(r"\bv?div(ss|sd)\b"), "sqrt": re.compile(r"\bv?sqrt(ss|sd)\b|call.*<sqrtf?(@plt)?>"),
         "sincos": re.compile(r"call.*<(sinf|cosf|sincosf|sin|cos|sincos)(@plt)?>")}
dis_lines = []
for line in open(dis):
    m = re.match(r"^\s*([0-9a-f]+):\s+(.*)$", line)
    if m:
        dis_lines.append((int(m.group(1), 16), m.group(2)))
res = {}
for name, cg in zip(("conventional", "proposed", "proposed_track_R"), cgs):
    count, total = cost(cg)
    tally = {k: 0 for k in kinds}
    for a, ins in dis_lines:
        for k, rx in kinds.items():
            if rx.search(ins):
                tally[k] += count.get(a, 0)
    res[name] = (total / n, {k: v / n for k, v in tally.items()})
    print(f"ctrl_step {name} (speed mode, x86-64 -O2, callgrind): {total / n:.0f} instructions per step")
    print(f"  per step: {tally['div'] / n:.2f} divisions, {tally['sqrt'] / n:.2f} square roots, "
          f"{tally['sincos'] / n:.2f} sin/cos calls (sinf+cosf of one angle count 2)")
(ic, tc) = res["conventional"]
for name in ("proposed", "proposed_track_R"):
    ip, tp = res[name]
    print(f"{name} - conventional: {ip - ic:+.0f} instructions ({100.0 * (ip - ic) / ic:+.0f} %), "
          f"{tp['div'] - tc['div']:+.2f} divisions, {tp['sqrt'] - tc['sqrt']:+.2f} square roots, "
          f"{tp['sincos'] - tc['sincos']:+.2f} sin/cos")
PY
