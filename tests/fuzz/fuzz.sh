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

name=fuzz unit="ISR steps"
states=(0 0 0 0 0 0 0 0 0 0 0)   # ISR steps ending in INIT IDLE CALIBRATE ALIGN IDENTIFY_R RUN FAULT PWM_CHECK ADC_CHECK ENC_CHECK COMMISSION
take_output() { # harness stdout
    local s i st s_k k=0
    s=$(printf '%s\n' "$1" | sed -n 's/^fuzz_app: \([0-9]*\) ISR steps, \([0-9]*\) inputs$/\1/p' | tail -n 1)
    i=$(printf '%s\n' "$1" | sed -n 's/^fuzz_app: \([0-9]*\) ISR steps, \([0-9]*\) inputs$/\2/p' | tail -n 1)
    st=$(printf '%s\n' "$1" | sed -n 's/^fuzz_app: steps ending in [A-Z_ ]*: //p' | tail -n 1)
    for s_k in $st; do states[k]=$((states[k] + s_k)); k=$((k + 1)); done
    count=$((count + ${s:-0}))
    inputs=$((inputs + ${i:-0}))
}
. "$(dirname "$0")/fuzz_lib.sh"
fuzz_run "$mode"
echo "fuzz: ISR steps ending in INIT ${states[0]}, IDLE ${states[1]}, CALIBRATE ${states[2]}, ALIGN ${states[3]}, IDENTIFY_R ${states[4]}, RUN ${states[5]}, FAULT ${states[6]}, PWM_CHECK ${states[7]}, ADC_CHECK ${states[8]}, ENC_CHECK ${states[9]}, COMMISSION ${states[10]}"
echo "fuzz: $count ISR steps, $inputs inputs, $(( $(date +%s) - start )) s, 0 findings"
