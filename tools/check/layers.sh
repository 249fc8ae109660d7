#!/usr/bin/env bash
# layers.sh [OUTDIR] - the layer gate of `make check`: layers and rooms
# point down only, and nothing loops.
#   control/     in rooms (control/rooms.mk, bottom up): a room includes
#                itself and the rooms below it, nothing outside control/
#   hal/         the interface (hal.h) and each board: never firmware/,
#                tools/ or tests/ (hal/f28335 may use control's mathx.h
#                and the C2000 register map, here its host fake)
#   firmware/    in rooms (firmware/rooms.mk, bottom up): a room includes
#                itself, the rooms below it, control/, hal/ and the
#                board's hardware facts; never tools/ or tests/
#   tools/sil/   the SIL runner: the layers above, never tests/
# 1. Every source and header of a layer or room is preprocessed with that
#    one's include list only (gcc -MM), and every header it pulls in must
#    lie in one of its directories (so a relative "../app/x.h" fails too).
# 2. tools/check/deps.py: no unit (a source with its header) includes or
#    calls one of a higher layer or room or a sibling, and no units use
#    each other in a loop, inside a folder too.
# 3. No folder of control/, hal/, firmware/ or tools/ holds more than
#    C_FILES_MAX C files (tests/ is no room of the house).
# 4. deps.py's self-test on seeded copies of the tree in OUTDIR/layers: an
#    include loop inside one room, a call loop inside control/ and a lower
#    room including a higher one's header must each fail it.
# Each failure names the files and what ties them; exit 1 if any.
set -uo pipefail
out=${1:-build/check}/layers
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
croom=$(sed -n 's/^CONTROL_ROOMS *:= *//p' control/rooms.mk)
[ -n "$croom" ] || { echo "FAIL control/rooms.mk: no CONTROL_ROOMS line"; exit 1; }
cbelow=""
for r in $croom; do
    cbelow="$cbelow $r"
    gate "$cbelow" "$r"/*.[ch]
done
for d in control/*/; do
    case " $croom " in *" ${d%/} "*) ;; *)
        echo "FAIL $d: a folder of control/ that control/rooms.mk does not name"; fail=1 ;;
    esac
done
gate "hal" hal/*.h
gate "hal hal/f28335 $croom tests/c2000_fake/include" hal/f28335/*.c hal/f28335/*.h
gate "hal hal/sim" hal/sim/*.c hal/sim/*.h
below=""
for r in $rooms; do
    below="$below firmware/$r"
    gate "$below hal hal/f28335 $croom" firmware/"$r"/*.[ch]
done
for d in firmware/*/; do
    case " $rooms " in *" $(basename "$d") "*) ;; *)
        echo "FAIL $d: a folder of firmware/ that firmware/rooms.mk does not name"; fail=1 ;;
    esac
done
gate "tools/sil $below hal hal/sim hal/f28335 $croom" tools/sil/*.[ch]

if ! python3 tools/check/deps.py; then
    fail=1
fi

C_FILES_MAX=16
while read -r n d; do
    if [ "$n" -gt "$C_FILES_MAX" ]; then
        echo "FAIL $d/: $n C files, more than $C_FILES_MAX: split it into rooms of one job each"
        fail=1
    fi
done < <(find control hal firmware tools -name '*.c' -printf '%h\n' | sort | uniq -c)

# The self-test: seeded copies must fail deps.py, each for its seed.
seeded() {
    local name=$1 expect=$2 copy="$out/$1"
    rm -rf "$copy" && mkdir -p "$copy/tools"
    cp -r control hal firmware "$copy/" && cp -r tools/sil "$copy/tools/"
    (cd "$copy" && eval "$3")
    if python3 tools/check/deps.py --root "$copy" > "$copy.txt"; then
        echo "FAIL layers self-test: $name passed deps.py:"; sed 's/^/    /' "$copy.txt"
        fail=1
    elif ! grep -q -- "$expect" "$copy.txt"; then
        echo "FAIL layers self-test: $name failed deps.py without '$expect':"; sed 's/^/    /' "$copy.txt"
        fail=1
    fi
}
mkdir -p "$out"
seeded include_loop 'a loop of 2 units: firmware/protect/app_step, firmware/protect/protect' \
    "sed -i 's|^#include <stdint.h>|&\n#include \"protect.h\"|' firmware/protect/app_step.h"
seeded call_loop 'control/pi -> control/svpwm: svpwm_seed()' \
    "printf 'void pi_seed(void)\n{\n    svpwm_seed();\n}\n' >> control/pi.c
     printf 'void svpwm_seed(void)\n{\n    pi_reset(0);\n}\n' >> control/svpwm.c"
seeded room_up 'firmware/protect/protect -> firmware/app/app (#include "app.h"): firmware/protect/ uses firmware/app/, a higher one' \
    "sed -i 's|^#include \"hal.h\"|&\n#include \"app.h\"|' firmware/protect/protect.h"

if [ $fail -ne 0 ]; then
    echo "layer gate: FAILED (a lower layer or room includes or calls a higher one, or a loop)"
    exit 1
fi
echo "layer gate: control/'s rooms ($croom), hal/, firmware/'s rooms ($rooms) and tools/sil/ point down only, no loop," \
     "no folder over $C_FILES_MAX C files; self-test: an include loop, a call loop and a room" \
     "including a higher one each fail it"
