#!/usr/bin/env bash
# bench_isr.sh DRIVE_SIL SCENARIO [--set KEY=VALUE ...] - the ISR's cost per period (x86-64 -O2,
# callgrind): instructions of app_isr inclusive (the HAL calls it makes on
# hal_sim are a few stores each; the simulated board's period is outside
# it), one callgrind dump per ISR call, over a run through every state of
# the app (tools/bench/bench_isr.ini), for each method. Per method prints
#   app_isr instructions (METHOD): typical N, worst M in STATE
# typical = the median over the periods that started in RUN, worst = the
# largest over every period, STATE the app state that period started in.
# Then a commissioning (drive_sil --commission on the same scenario's
# plant and board, free shaft, its gate trip moved out of the run) prints
#   app_isr instructions (commission): typical N, worst M in STATE
# typical = the median over the periods that started in COMMISSION, worst
# = the largest over every period of that run.
# With BENCH_ISR_LINK=PROGRAM (tools/bench/bench_isr_link.c) the same run again
# with a capture armed and triggering and a stream running, app_isr and
# link_isr each dumped (a dump before and after link_isr), per method
#   app_isr instructions with capture and stream (METHOD): typical N, worst M in STATE
#   link_isr instructions with capture and stream (METHOD): typical N, worst M in STATE
#   control ISR instructions, app_isr + link_isr (METHOD): typical N, worst M in STATE, ...
# the last with the bound (worst <= 2400 and <= 1.3 x typical) checked:
# `within the bound` or `OVER the bound`.
# Prints figures; asserts nothing (it fails only when the dumps and the
# periods do not pair up).
set -euo pipefail
bin=$1
scenario=$2; shift 2
sets=("$@")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for m in conventional proposed; do
    # app_isr is entered by a tail jump from sil_isr (tools/sil/sil.c):
    # collection toggles on app_isr (the pattern form matches the jumped-to
    # function), the dump follows sil_isr's return, which is app_isr's.
    # drive_sil exits 3 for a run that ends in FAULT, as this one does (the trip)
    rc=0
    valgrind --tool=callgrind --toggle-collect='app_isr*' --dump-after='sil_isr' --combine-dumps=yes \
        --dump-instr=no --dump-line=no --callgrind-out-file="$out/$m.cg" \
        "$bin" --scenario "$scenario" --set controller.method=$m --set run.log_every=1 "${sets[@]}" \
        --out "$out/$m.csv" > "$out/$m.stdout" 2> "$out/$m.stderr" || rc=$?
    if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
        echo "bench_isr: $m: drive_sil exit $rc" >&2
        cat "$out/$m.stderr" >&2
        exit 1
    fi
    python3 -c 'import csv, sys; [print(int(float(r["state"]))) for r in csv.DictReader(open(sys.argv[1]))]' \
        "$out/$m.csv" > "$out/$m.states"
    if [ -n "${BENCH_ISR_LINK:-}" ]; then
        # the link's run: app_isr and link_isr both collected, a dump as link_isr
        # starts (app_isr's part) and one as it returns (link_isr's part)
        link_sets=()
        for s in "${sets[@]}"; do [ "$s" = --set ] || link_sets+=("$s"); done
        valgrind --tool=callgrind --toggle-collect='app_isr*' --toggle-collect=link_isr \
            --dump-before=link_isr --dump-after=link_isr --combine-dumps=yes \
            --dump-instr=no --dump-line=no --callgrind-out-file="$out/$m.link.cg" \
            "$BENCH_ISR_LINK" "$scenario" "$out/$m.link.states" controller.method=$m "${link_sets[@]}" \
            > "$out/$m.link.stdout" 2> "$out/$m.link.stderr" || {
            echo "bench_isr: $m: $BENCH_ISR_LINK failed" >&2; cat "$out/$m.link.stderr" >&2; exit 1; }
    fi
done
rc=0
valgrind --tool=callgrind --toggle-collect='app_isr*' --dump-after='sil_isr' --combine-dumps=yes \
    --dump-instr=no --dump-line=no --callgrind-out-file="$out/commission.cg" \
    "$bin" --scenario "$scenario" --commission "$out/commission.ini" --set run.log_every=1 "${sets[@]}" \
    --set faults.gate_trip_s=1e9 \
    --out "$out/commission.csv" > "$out/commission.stdout" 2> "$out/commission.stderr" || rc=$?
if [ "$rc" -ne 0 ]; then
    echo "bench_isr: commission: drive_sil exit $rc" >&2
    cat "$out/commission.stderr" >&2
    exit 1
fi
python3 -c 'import csv, sys; [print(int(float(r["state"]))) for r in csv.DictReader(open(sys.argv[1]))]' \
    "$out/commission.csv" > "$out/commission.states"
python3 - "$out" <<'PY'
import os, statistics, sys
out = sys.argv[1]
STATES = ["INIT", "IDLE", "CALIBRATE", "ALIGN", "IDENTIFY_R", "RUN", "FAULT", "PWM_CHECK", "ADC_CHECK", "ENC_CHECK",
          "COMMISSION"]
WORST_MAX = 2400         # the bound on the worst period [instructions]
WORST_PER_TYPICAL = 1.3  # and on its ratio to the typical one

def parts(path):
    return [int(l.split()[1]) for l in open(path) if l.startswith("totals:")]

def figures(per, after, what, typical_in="RUN"):
    """typical (median of the periods that started in typical_in), worst, the state it started in"""
    per = per[:len(after)]   # the last part is the program's end (nothing collected)
    if len(per) != len(after):
        sys.exit(f"bench_isr: {what}: {len(per)} callgrind dumps for {len(after)} periods")
    entry = [0] + after[:-1]  # the state a period started in: the one the last ended in (INIT first)
    run = [c for c, s in zip(per, entry) if STATES[s] == typical_in]
    k = max(range(len(per)), key=lambda i: per[i])
    return int(statistics.median(run)), per[k], STATES[entry[k]], entry

def plain(m, typical_in):
    """app_isr's figures of run m; every period's cost and states into BENCH_ISR_PERIODS.m, for a closer look"""
    after = [int(l) for l in open(f"{out}/{m}.states")]
    per = parts(f"{out}/{m}.cg")
    typ, worst, st, entry = figures(per, after, m, typical_in)
    if os.environ.get("BENCH_ISR_PERIODS"):
        with open(f"{os.environ['BENCH_ISR_PERIODS']}.{m}", "w") as f:
            f.writelines(f"{i} {c} {STATES[e]} {STATES[a]}\n" for i, (c, e, a) in enumerate(zip(per, entry, after)))
    print(f"app_isr instructions ({m}): typical {typ}, worst {worst} in {st}")

for m in ("conventional", "proposed"):
    plain(m, "RUN")
    if not os.path.exists(f"{out}/{m}.link.cg"):
        continue
    after = [int(l) for l in open(f"{out}/{m}.link.states")]
    both = parts(f"{out}/{m}.link.cg")
    app, link = both[0::2], both[1::2]
    total = [a + b for a, b in zip(app, link)]
    for name, per in (("app_isr", app), ("link_isr", link)):
        typ, worst, st, _ = figures(per, after, f"{m} {name}")
        print(f"{name} instructions with capture and stream ({m}): typical {typ}, worst {worst} in {st}")
    typ, worst, st, _ = figures(total, after, f"{m} total")
    ok = worst <= WORST_MAX and worst <= WORST_PER_TYPICAL * typ
    print(f"control ISR instructions, app_isr + link_isr ({m}): typical {typ}, worst {worst} in {st}, "
          f"{worst / typ:.2f} x typical: {'within' if ok else 'OVER'} the bound "
          f"(worst <= {WORST_MAX} and <= {WORST_PER_TYPICAL} x typical)")
plain("commission", "COMMISSION")
PY
