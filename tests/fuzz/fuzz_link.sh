#!/usr/bin/env bash
# fuzz_link.sh short|long BIN DIR [FRAMES] - run the link's fuzz harness (tests/fuzz/fuzz_link.c),
# then, with DRIVE_SIL set, drive_sil --link's socket layer under random clients
# (tests/fuzz/fuzz_link_socket.py: connect, close mid-frame, half-close, a second client, ...).
#   short  a seeded pass from the seed corpus (a few seconds), and SOCKET_SHORT_ACTIONS
#          seeded client actions: make test's
#   long   chunks of libFuzzer runs on the corpus DIR/corpus until the
#          harness has framed FRAMES requests (default 10^7), then
#          SOCKET_LONG_ACTIONS (default 2000) client actions of a new seed
# Prints "fuzz-link: N frames, N inputs, S s, N findings" and the socket
# part's "fuzz-link-socket: N actions, S s, N findings"; a finding leaves
# DIR/crash-* (the socket part: its seed and action) and exits 1.
set -uo pipefail
mode=$1 bin=$2 dir=$3 target=${4:-10000000}
SHORT_RUNS=3000
SHORT_SEED=1
SOCKET_SHORT_ACTIONS=40
SOCKET_LONG_ACTIONS=${SOCKET_LONG_ACTIONS:-2000}
CHUNK_RUNS=100000
MAX_LEN=2048
opts=(-max_len=$MAX_LEN -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$dir/" -print_final_stats=0)
mkdir -p "$dir"

# Seeds (the record format is in tests/fuzz/fuzz_link.c): HELLO, LIST_VARS
# from 0, READ of state, WRITE speed_ref_rpm 500, a capture armed on
# speed_est_rpm > 250 with periods crossing it then read, a stream, ACTION start.
seed_corpus() { # dir
    printf '\x00\x01\x01\x00\x00\x02\x02\x02\x00\x00\x00\x03\x03\x02\x00\x00' >"$1/seed_hello_list_read"
    printf '\x00\x04\x05\x06\x04\x00\x00\x00\xfa\x43\x00\x05\x06\x01\x01' >"$1/seed_write_start"
    printf '\x00\x07\x07\x16\x01\x00\x02\x00\x08\x00\x01\x03\x00\x00\x00\x7a\x43\x00\x00\x00\x00\x02\x0b\x00\x03\x00' >"$1/seed_capture"
    printf '\xf0\x0f\x05\x00\x00\x10\x00\xf0\x0f\x05\x00\x40\x10\x00\xf0\x0f\x05\x00\x08\x10\x00' >>"$1/seed_capture"
    printf '\x00\x08\x08\x00\x00\x09\x09\x04\x00\x00\x08\x00' >>"$1/seed_capture"
    printf '\x00\x06\x0a\x04\x32\x00\x0b\x00\xf0\x3f\x05\x00\x00\x10\x00' >"$1/seed_stream"
    printf '\xc5\x08\x11\x00\x05\xff\x00\x00\x31\x32\x00\x01\x01\x00' >"$1/seed_garbage"
}

name=fuzz-link unit=frames
take_output() { # harness stdout
    local f i
    f=$(printf '%s\n' "$1" | sed -n 's/^fuzz_link: \([0-9]*\) frames, \([0-9]*\) inputs.*/\1/p' | tail -n 1)
    i=$(printf '%s\n' "$1" | sed -n 's/^fuzz_link: \([0-9]*\) frames, \([0-9]*\) inputs.*/\2/p' | tail -n 1)
    count=$((count + ${f:-0}))
    inputs=$((inputs + ${i:-0}))
}
on_finding() {
    echo "fuzz-link: 0 passed, 1 failed"
}
. "$(dirname "$0")/fuzz_lib.sh"
fuzz_run "$mode"
echo "fuzz-link: $count frames, $inputs inputs, $(( $(date +%s) - start )) s, 0 findings"
if [ -n "${DRIVE_SIL:-}" ]; then
    if [ "$mode" = short ]; then
        actions=$SOCKET_SHORT_ACTIONS seed=$SHORT_SEED
    else
        actions=$SOCKET_LONG_ACTIONS seed=$(date +%s)
    fi
    if ! python3 "$(dirname "$0")/fuzz_link_socket.py" "$DRIVE_SIL" "$actions" "$seed"; then
        on_finding
        exit 1
    fi
else
    echo "fuzz-link: the socket layer not fuzzed (DRIVE_SIL unset)"
fi
echo "fuzz-link: 1 passed, 0 failed"
