#!/usr/bin/env bash
# portability.sh OUTDIR - the gates of `make check`. Each failure names the
# file and the problem; the script exits 1 if any gate failed.
#   1. float-only: control/, firmware/, hal/f28335/ built for a Cortex-M4F
#      (single-precision FPU); no object may reference a double-precision
#      helper or a double libm function.
#   2. 16-bit int: the same sources built with avr-gcc (int is 16 bits, as
#      on the C28x); control/ additionally with -Wconversion.
#   3. cppcheck with the C28x data model (tools/check/c28x.xml).
#   4. layers (tools/check/layers.sh): no include or call upward between
#      layers and between firmware/'s rooms, no loop anywhere.
set -uo pipefail
out=${1:-build/check}
cd "$(dirname "$0")/../.."
mkdir -p "$out/arm" "$out/avr"

# Each layer's include list, as the Makefile's: control/ sees its rooms only.
inc_control=()
for d in $(sed -n 's/^CONTROL_ROOMS *:= *//p' control/rooms.mk); do inc_control+=(-I"$d"); done
inc_firmware=(-Ihal -Ihal/f28335 "${inc_control[@]}")
for d in firmware/*/; do inc_firmware+=(-I"${d%/}"); done  # the rooms (layers.sh gates their order)
inc_f28335=(-Ihal -Ihal/f28335 "${inc_control[@]}" -Itests/c2000_fake/include)
inc=("${inc_firmware[@]}" -Itests/c2000_fake/include)
common=(-std=c99 -Wall -Wextra -Werror -Wshadow -Wdouble-promotion -Wfloat-conversion
        -Wunsuffixed-float-constants -include control/c28x_portable.h)
# inc_of FILE: its layer's include list.
inc_of() {
    case "$1" in
        control/*) echo "${inc_control[@]}" ;;
        firmware/*) echo "${inc_firmware[@]}" ;;
        *) echo "${inc_f28335[@]}" ;;
    esac
}
srcs=$(ls control/*.c control/*/*.c firmware/*/*.c hal/f28335/*.c 2>/dev/null)
# Header-only modules (static inline transforms) are gated as their own
# translation units, with their unused inline functions still emitted.
hdrs=$(ls control/*.h control/*/*.h 2>/dev/null)
keep=(-fkeep-inline-functions -fkeep-static-functions)
fail=0

# Double-precision soft-float helpers (ARM RTABI and libgcc names) and the
# double versions of libm functions.
forbidden='^(__aeabi_d[a-z0-9]*|__aeabi_f2d|__aeabi_[ul]*i2d|__aeabi_[ul]2d|__[a-z]*df[0-9]*|__extendsfdf2|__truncdfsf2|sqrt|sin|cos|tan|asin|acos|atan|atan2|exp|log|log10|pow|fabs|floor|ceil|fmod|round|trunc|hypot|sincos)$'

# arm_gate FILE [FLAGS...]: compile for the Cortex-M4F single-precision FPU
# and scan the object for double-precision references.
arm_gate() {
    local f=$1; shift
    local o="$out/arm/$(echo "$f" | tr / _).o"
    if ! arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -O2 \
            "${common[@]}" $(inc_of "$f") "$@" -c "$f" -o "$o" 2> "$o.log"; then
        echo "FAIL $f: does not compile float-only for Cortex-M4F:"; sed 's/^/    /' "$o.log"
        fail=1; return
    fi
    local bad
    bad=$(arm-none-eabi-nm -u "$o" | awk '{print $NF}' | grep -E "$forbidden" | tr '\n' ' ')
    if [ -n "$bad" ]; then
        echo "FAIL $f: uses double precision (references: $bad)"
        fail=1
    fi
}

# avr_gate FILE [FLAGS...]: compile with avr-gcc, where int is 16 bits.
avr_gate() {
    local f=$1; shift
    local o="$out/avr/$(echo "$f" | tr / _).o"
    if ! avr-gcc -mmcu=atmega2560 -Os "${common[@]}" $(inc_of "$f") "$@" -c "$f" -o "$o" 2> "$o.log"; then
        echo "FAIL $f: does not compile with 16-bit int (avr-gcc):"; sed 's/^/    /' "$o.log"
        fail=1
    fi
}

echo "check 1/4: float-only build (arm-none-eabi-gcc, Cortex-M4F single-precision FPU)"
for f in $srcs; do arm_gate "$f"; done
for h in $hdrs; do arm_gate "$h" "${keep[@]}" -x c; done

echo "check 2/4: 16-bit int build (avr-gcc, atmega2560; control/ with -Wconversion)"
for f in $srcs; do
    case "$f" in control/*) avr_gate "$f" -Wconversion ;; *) avr_gate "$f" ;; esac
done
for h in $hdrs; do avr_gate "$h" -Wconversion -x c; done

echo "check 3/4: cppcheck (warning, portability) with the C28x data model"
if ! cppcheck --quiet --enable=warning,portability --platform=tools/check/c28x.xml \
        --error-exitcode=1 --inline-suppr --std=c99 -D__GNUC__ "${inc[@]}" \
        --template='FAIL {file}:{line}: cppcheck {severity} ({id}): {message}' \
        control firmware hal/f28335 2>&1; then
    fail=1
fi

echo "check 4/4: layers (control/, hal/, firmware/'s rooms, tools/sil/ point down only; no loop)"
if ! tools/check/layers.sh "$out"; then
    fail=1
fi

if [ $fail -ne 0 ]; then
    echo "make check: FAILED"
    exit 1
fi
echo "make check: all gates passed ($(echo "$srcs" | wc -w) portable sources, $(echo "$hdrs" | wc -w) control headers)"
