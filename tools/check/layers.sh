#!/usr/bin/env bash
# layers.sh - the layer gate of `make check`: layers point down only.
#   control/     includes nothing outside control/
#   hal/         the interface (hal.h) and each board: never firmware/,
#                tools/ or tests/ (hal/f28335 may use control's mathx.h
#                and the C2000 register map, here its host fake)
#   firmware/    control/, hal/ and the board's hardware facts; never
#                tools/ or tests/
# Every source and header of a layer is preprocessed with that layer's
# include list only (gcc -MM), and every header it pulls in must lie in
# one of the layer's directories (so a relative "../firmware/x.h" fails
# too). Each failure names the file and the header; exit 1 if any.
set -uo pipefail
cd "$(dirname "$0")/../.."
fail=0

# gate DIRS FILE...: DIRS (space-separated) is both the include list and
# the set of directories the file's headers may come from.
gate() {
    local dirs=$1; shift
    local incs=() d f deps dep dir ok
    for d in $dirs; do incs+=("-I$d"); done
    for f in "$@"; do
        if ! deps=$(gcc -MM -x c -std=c99 "${incs[@]}" "$f" 2>&1); then
            echo "FAIL $f: includes a header outside its layer (allowed: $dirs):"
            echo "$deps" | grep -E 'error' | sed 's/^/    /'
            fail=1
            continue
        fi
        for dep in $(echo "$deps" | tr -d '\\' | cut -d: -f2-); do
            dir=$(dirname "$(realpath --relative-to=. "$dep")")
            ok=0
            for d in $dirs; do [ "$dir" = "$d" ] && ok=1; done
            if [ $ok -eq 0 ]; then
                echo "FAIL $f: includes $dep, outside its layer (allowed: $dirs)"
                fail=1
            fi
        done
    done
}

gate "control" control/*.c control/*.h
gate "hal" hal/*.h
gate "hal hal/f28335 control tests/c2000_fake/include" hal/f28335/*.c hal/f28335/*.h
gate "hal hal/sim" hal/sim/*.c hal/sim/*.h
gate "firmware hal hal/f28335 control" firmware/*.c firmware/*.h

if [ $fail -ne 0 ]; then
    echo "layer gate: FAILED (a lower layer includes a higher one)"
    exit 1
fi
echo "layer gate: control/, hal/ and firmware/ include only their own and lower layers"
