# fuzz_lib.sh - the libFuzzer driver shared by tests/fuzz/fuzz.sh and
# tests/fuzz/fuzz_link.sh (sourced, not run). The caller sets
#   bin dir target     the harness, its output folder, the count to reach (long)
#   opts               libFuzzer options (array)
#   SHORT_SEED SHORT_RUNS CHUNK_RUNS
#   name unit          the message prefix and what the harness counts
# and defines
#   seed_corpus DIR    writes the seed inputs
#   take_output OUT    adds a run's counts (its stdout) to count and inputs
#   on_finding         (optional) prints more after a finding
# then calls fuzz_run MODE (short | long). A finding (the harness's nonzero
# exit) prints the log's tail and the artefacts, and exits 1.
count=0 inputs=0
start=$(date +%s)

fuzz_chunk() { # corpus-dir extra-options...
    local out rc
    out=$("$bin" "${opts[@]}" "${@:2}" "$1" 2>"$dir/last.log")
    rc=$?
    take_output "$out"
    if [ $rc -ne 0 ]; then
        tail -n 40 "$dir/last.log" >&2
        echo "$name: FINDING after $count $unit ($(ls "$dir"/crash-* "$dir"/timeout-* "$dir"/oom-* 2>/dev/null | tr '\n' ' '))" >&2
        if declare -F on_finding > /dev/null; then on_finding; fi
        exit 1
    fi
}

fuzz_run() { # short | long
    case $1 in
    short)
        corpus=$(mktemp -d)
        trap 'rm -rf "$corpus"' EXIT
        seed_corpus "$corpus"
        fuzz_chunk "$corpus" -seed=$SHORT_SEED -runs=$SHORT_RUNS
        ;;
    long)
        mkdir -p "$dir/corpus"
        seed_corpus "$dir/corpus"
        while [ "$count" -lt "$target" ]; do
            fuzz_chunk "$dir/corpus" -runs=$CHUNK_RUNS
            echo "$name: $count $unit so far ($(( $(date +%s) - start )) s)"
        done
        ;;
    *)
        echo "usage: $(basename "$0") short|long BIN DIR [COUNT]" >&2
        exit 2
        ;;
    esac
}
