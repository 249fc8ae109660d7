#!/usr/bin/env bash
# isr_path.sh [OUTDIR] - host gate of `make check` (D14): the control ISR
# path (app_isr, and link_isr, the link's capture and stream that main.c's
# ISR calls after it) reaches no library function except the FPU fast-RTS members that
# f28335_flash.cmd places in RAM.
#
# On the F28335 the ISR runs from RAM (ramfuncs), but cl2000 implements
# 32-bit integer / and %, 64-bit arithmetic and some struct copies and
# classification macros (isfinite) with RTS functions that stay in .text,
# in flash with 5 wait states. A host stand-in for that: build control/,
# firmware/ (without main.c) and hal/f28335/ with the register fake for an
# ARMv7-A with a single/double FPU but no integer divide, as cl2000 has
# FPU32 but no divider; link with app_isr (and the HAL's ISR timing and
# catch-all ISR) as the only roots, dropping every unreachable function
# (--gc-sections), and without any library: every symbol left undefined is
# a library function the ISR path calls (gcc's turning of zeroing loops into
# memset, which cl2000 does not do, is switched off). Allowed: sinf, cosf, atan2f,
# sqrtf (the fast-RTS members in RAM; the hardware FPU divides inline here,
# FS$$DIV is in RAM on the target). Also fails on isfinite/isnan/isinf/
# fpclassify anywhere in the portable sources (use mathx_isfinitef).
# Leaves its objects and gcc's call graphs (main.c included, not linked)
# in OUTDIR/isr for the RAM gate (tools/check/ram_budget.py).
set -uo pipefail
out=${1:-build/check}/isr
cd "$(dirname "$0")/../.."
mkdir -p "$out"
rm -f "$out"/*.o "$out"/*.ci  # a removed source leaves nothing behind
fail=0

allowed='^(sinf|cosf|atan2f|sqrtf)$'
flags=(-mthumb -march=armv7-a+fp -mfloat-abi=hard -O2 -std=c99 -ffunction-sections -fdata-sections
       -fno-tree-loop-distribute-patterns -fcallgraph-info=su
       -Wall -Wextra -Werror -include control/c28x_portable.h
       -Ihal -Ihal/f28335 -Itests/c2000_fake/include)
for d in $(sed -n 's/^CONTROL_ROOMS *:= *//p' control/rooms.mk); do flags+=(-I"$d"); done
for d in firmware/*/; do flags+=(-I"${d%/}"); done  # the rooms (firmware/rooms.mk)
srcs=$(ls control/*.c control/*/*.c firmware/*/*.c hal/f28335/*.c tests/c2000_fake/*.c)
objs=()
for f in $srcs; do
    o="$out/$(echo "$f" | tr / _).o"
    if ! arm-none-eabi-gcc "${flags[@]}" -c "$f" -o "$o" 2> "$o.log"; then
        echo "FAIL $f: does not compile for the ISR-path check:"; sed 's/^/    /' "$o.log"
        fail=1
    fi
    # main.c: compiled for the RAM gate's figures (ctrl_isr, main's stack), not linked
    [ "$f" = firmware/f28335/main.c ] || objs+=("$o")
done

elf="$out/isr_path.elf"
if [ $fail -eq 0 ]; then
    if ! arm-none-eabi-gcc "${flags[@]}" -nostdlib -nostartfiles -Wl,--gc-sections \
            -Wl,--unresolved-symbols=ignore-all -Wl,-e,app_isr \
            -Wl,-u,hal_f28335_isr_timing_begin -Wl,-u,hal_f28335_isr_timing_end \
            -Wl,-u,f28335_unexpected_isr -Wl,-u,link_isr -Wl,-q -Wl,-Map,"$out/isr_path.map" \
            "${objs[@]}" -o "$elf" 2> "$out/link.log"; then
        echo "FAIL ISR-path link:"; sed 's/^/    /' "$out/link.log"
        fail=1
    fi
fi
if [ $fail -eq 0 ]; then
    calls=$(arm-none-eabi-nm -u "$elf" | awk '{print $NF}' | grep -Ev "$allowed" | tr '\n' ' ')
    if [ -n "$calls" ]; then
        echo "FAIL ISR path (app_isr and what it calls) needs library functions that run from flash on the F28335: $calls"
        # caller -> callee, from the relocations kept in the image (-q)
        edges=$(arm-none-eabi-objdump -dr "$elf" |
            awk '/^[0-9a-f]+ <.*>:$/ {fn = $2} /R_ARM_(THM_)?(CALL|JUMP24|PC24)/ {print "    " fn " calls " $NF}' | sort -u)
        for s in $calls; do
            echo "$edges" | grep -E " calls $s\$"
        done
        fail=1
    fi
    # Every function on the path runs from RAM on the target, or from
    # flash on purpose: control/ whole (target.mk RAMFUNC_ALL, but its
    # RAMFUNC_ALL_EXCEPT files), elsewhere its definition marked RAMFUNC or
    # FLASHFUNC (tools/check/placement.py).
    if ! python3 tools/check/placement.py --map "$out/isr_path.map" $srcs; then
        fail=1
    fi
    code=$(arm-none-eabi-size -A "$elf" | awk '$1 == ".text" {print $2}')
    echo "isr_path: code reached from app_isr ${code:-0} bytes (Thumb-2; the RAM budget: ram_budget.py)"
fi
# cl2000's isfinite and friends may call RTS functions; mathx_isfinitef is inline.
cls=$(grep -nE '\b(isfinite|isnan|isinf|fpclassify)[[:space:]]*\(' control/*.[ch] control/*/*.[ch] firmware/*/*.[ch] hal/f28335/*.[ch] 2>/dev/null)
if [ -n "$cls" ]; then
    echo "FAIL classification macro outside mathx_isfinitef (may call an RTS function):"
    echo "$cls" | sed 's/^/    /'
    fail=1
fi

if [ $fail -ne 0 ]; then
    echo "isr_path: FAILED"
    exit 1
fi
echo "isr_path: the ISR path calls no library function outside the fast-RTS members in RAM"
