#!/usr/bin/env bash
# fuzz.sh short|long BIN DIR [STEPS] - run the ISR fuzz harness (tests/fuzz/).
#   short  a seeded pass from an empty corpus (a few seconds): the CI's
#   long   chunks of libFuzzer runs on the corpus DIR/corpus until the
#          harness has made STEPS ISR steps (default 10^8)
# Prints "fuzz: N ISR steps, N inputs, S s, N findings"; a finding (a
# sanitizer report or a broken output rule) leaves DIR/crash-* and exits 1.
set -uo pipefail
mode=$1 bin=$2 dir=$3 target=${4:-100000000}
SHORT_RUNS=4000           # inputs of the short pass
SHORT_SEED=1
CHUNK_RUNS=200000         # inputs per libFuzzer run of the long mode
MAX_LEN=4096              # bytes: up to 255 records, each up to 64 ISR steps
opts=(-max_len=$MAX_LEN -len_control=0 -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$dir/" -print_final_stats=0)
mkdir -p "$dir"

# Seed inputs (tests/fuzz/fuzz_app.c has the format): a start in speed,
# torque and open-loop mode, then plausible periods with the count moving,
# the persistent operator on; the first with calibration and alignment;
# a commissioning (calibrated) asked for by the command block while stopped.
seed_corpus() { # dir
    local rec='\x10\x3f\x05\x03\x00\x00\x00\x00\x00\x00\x00\x04\x00\x00\x00\x00'
    local body='' k
    for k in $(seq 1 32); do body+=$rec; done
    printf "\xc3\x08\x01\x00\x00\x00\x00\x00$body" >"$1/seed_speed_cal_align"
    printf "\xa0\x00\x01\x00\x00\x00\x00\x00$body" >"$1/seed_torque"
    printf "\x80\x00\x01\x00\x00\x00\x00\x00$body" >"$1/seed_open_loop"
    printf "\xd4\x10\x01\x00\x00\x00\x00\x00$body" >"$1/seed_proposed_windows"
    printf "\x01\x08\x00\x00\x00\x00\x00\x00\xc0\x01\x02\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00$body" \
        >"$1/seed_commission"
}

steps=0 inputs=0
states=(0 0 0 0 0 0 0 0 0 0 0)   # ISR steps ending in INIT IDLE CALIBRATE ALIGN IDENTIFY_R RUN FAULT PWM_CHECK ADC_CHECK ENC_CHECK COMMISSION
start=$(date +%s)
run_chunk() { # corpus-dir extra-options...
    local out rc s i
    out=$("$bin" "${opts[@]}" "${@:2}" "$1" 2>"$dir/last.log")
    rc=$?
    s=$(printf '%s\n' "$out" | sed -n 's/^fuzz_app: \([0-9]*\) ISR steps, \([0-9]*\) inputs$/\1/p' | tail -n 1)
    i=$(printf '%s\n' "$out" | sed -n 's/^fuzz_app: \([0-9]*\) ISR steps, \([0-9]*\) inputs$/\2/p' | tail -n 1)
    local st k=0
    st=$(printf '%s\n' "$out" | sed -n 's/^fuzz_app: steps ending in [A-Z_ ]*: //p' | tail -n 1)
    for s_k in $st; do states[k]=$((states[k] + s_k)); k=$((k + 1)); done
    steps=$((steps + ${s:-0}))
    inputs=$((inputs + ${i:-0}))
    if [ $rc -ne 0 ]; then
        tail -n 40 "$dir/last.log" >&2
        echo "fuzz: FINDING after $steps ISR steps ($(ls "$dir"/crash-* "$dir"/timeout-* "$dir"/oom-* 2>/dev/null | tr '\n' ' '))" >&2
        exit 1
    fi
}

case $mode in
short)
    corpus=$(mktemp -d)
    trap 'rm -rf "$corpus"' EXIT
    seed_corpus "$corpus"
    run_chunk "$corpus" -seed=$SHORT_SEED -runs=$SHORT_RUNS
    ;;
long)
    mkdir -p "$dir/corpus"
    seed_corpus "$dir/corpus"
    while [ "$steps" -lt "$target" ]; do
        run_chunk "$dir/corpus" -runs=$CHUNK_RUNS
        echo "fuzz: $steps ISR steps so far ($(( $(date +%s) - start )) s)"
    done
    ;;
*)
    echo "usage: fuzz.sh short|long BIN DIR [STEPS]" >&2
    exit 2
    ;;
esac
echo "fuzz: ISR steps ending in INIT ${states[0]}, IDLE ${states[1]}, CALIBRATE ${states[2]}, ALIGN ${states[3]}, IDENTIFY_R ${states[4]}, RUN ${states[5]}, FAULT ${states[6]}, PWM_CHECK ${states[7]}, ADC_CHECK ${states[8]}, ENC_CHECK ${states[9]}, COMMISSION ${states[10]}"
echo "fuzz: $steps ISR steps, $inputs inputs, $(( $(date +%s) - start )) s, 0 findings"
