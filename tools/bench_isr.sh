#!/usr/bin/env bash
# bench_isr.sh DRIVE_SIL SCENARIO [--set KEY=VALUE ...] - the ISR's cost per period (x86-64 -O2,
# callgrind): instructions of app_isr inclusive (the HAL calls it makes on
# hal_sim are a few stores each; the simulated board's period is outside
# it), one callgrind dump per ISR call, over a run through every state of
# the app (tools/bench_isr.ini), for each method. Per method prints
#   app_isr instructions (METHOD): typical N, worst M in STATE
# typical = the median over the periods that started in RUN, worst = the
# largest over every period, STATE the app state that period started in.
# Then a commissioning (drive_sil --commission on the same scenario's
# plant and board, free shaft, its gate trip moved out of the run) prints
#   app_isr instructions (commission): typical N, worst M in STATE
# typical = the median over the periods that started in COMMISSION, worst
# = the largest over every period of that run.
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
python3 - "$out" <<'PY'
import csv, os, statistics, sys
out = sys.argv[1]
STATES = ["INIT", "IDLE", "CALIBRATE", "ALIGN", "IDENTIFY_R", "RUN", "FAULT", "PWM_CHECK", "ADC_CHECK", "ENC_CHECK",
          "COMMISSION"]
for m in ("conventional", "proposed"):
    per = [int(l.split()[1]) for l in open(f"{out}/{m}.cg") if l.startswith("totals:")]
    after = [int(float(r["state"])) for r in csv.DictReader(open(f"{out}/{m}.csv"))]
    per = per[:len(after)]   # the last part is the program's end (nothing collected)
    if len(per) != len(after):
        sys.exit(f"bench_isr: {m}: {len(per)} callgrind dumps for {len(after)} periods")
    entry = [0] + after[:-1]  # the state a period started in: the one the last ended in (INIT first)
    run = [c for c, s in zip(per, entry) if STATES[s] == "RUN"]
    k = max(range(len(per)), key=lambda i: per[i])
    if os.environ.get("BENCH_ISR_PERIODS"):  # every period's cost and states, for a closer look
        with open(f"{os.environ['BENCH_ISR_PERIODS']}.{m}", "w") as f:
            f.writelines(f"{i} {c} {STATES[e]} {STATES[a]}\n" for i, (c, e, a) in enumerate(zip(per, entry, after)))
    print(f"app_isr instructions ({m}): typical {int(statistics.median(run))}, worst {per[k]} in {STATES[entry[k]]}")
per = [int(l.split()[1]) for l in open(f"{out}/commission.cg") if l.startswith("totals:")]
after = [int(float(r["state"])) for r in csv.DictReader(open(f"{out}/commission.csv"))]
per = per[:len(after)]
if len(per) != len(after):
    sys.exit(f"bench_isr: commission: {len(per)} callgrind dumps for {len(after)} periods")
entry = [0] + after[:-1]
comm = [c for c, s in zip(per, entry) if STATES[s] == "COMMISSION"]
k = max(range(len(per)), key=lambda i: per[i])
if os.environ.get("BENCH_ISR_PERIODS"):
    with open(f"{os.environ['BENCH_ISR_PERIODS']}.commission", "w") as f:
        f.writelines(f"{i} {c} {STATES[e]} {STATES[a]}\n" for i, (c, e, a) in enumerate(zip(per, entry, after)))
print(f"app_isr instructions (commission): typical {int(statistics.median(comm))}, worst {per[k]} in {STATES[entry[k]]}")
PY
