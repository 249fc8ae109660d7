#!/usr/bin/env bash
# layers.sh - the layer gate of `make check`: layers and rooms point down
# only.
#   control/     includes nothing outside control/
#   hal/         the interface (hal.h) and each board: never firmware/,
#                tools/ or tests/ (hal/f28335 may use control's mathx.h
#                and the C2000 register map, here its host fake)
#   firmware/    in rooms (firmware/rooms.mk, bottom up): a room includes
#                itself, the rooms below it, control/, hal/ and the
#                board's hardware facts; never tools/ or tests/
#   tools/sil/   the SIL runner: the layers above, never tests/
# Every source and header of a layer or room is preprocessed with that
# one's include list only (gcc -MM), and every header it pulls in must lie
# in one of its directories (so a relative "../app/x.h" fails too).
# Each failure names the files and what ties them; exit 1 if any.
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

rooms=$(sed -n 's/^FIRMWARE_ROOMS *:= *//p' firmware/rooms.mk)
[ -n "$rooms" ] || { echo "FAIL firmware/rooms.mk: no FIRMWARE_ROOMS line"; exit 1; }
gate "control" control/*.c control/*.h
gate "hal" hal/*.h
gate "hal hal/f28335 control tests/c2000_fake/include" hal/f28335/*.c hal/f28335/*.h
gate "hal hal/sim" hal/sim/*.c hal/sim/*.h
below=""
for r in $rooms; do
    below="$below firmware/$r"
    gate "$below hal hal/f28335 control" firmware/"$r"/*.[ch]
done
for d in firmware/*/; do
    case " $rooms " in *" $(basename "$d") "*) ;; *)
        echo "FAIL $d: a folder of firmware/ that firmware/rooms.mk does not name"; fail=1 ;;
    esac
done
gate "tools/sil $below hal hal/sim hal/f28335 control" tools/sil/*.[ch]

if [ $fail -ne 0 ]; then
    echo "layer gate: FAILED (a lower layer or room includes a higher one)"
    exit 1
fi
echo "layer gate: control/, hal/, firmware/'s rooms ($rooms) and tools/sil/ include only their own and lower ones"
