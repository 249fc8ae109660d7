#!/usr/bin/env bash
# target_cfg.sh - host gate of `make check` for what only cl2000 would see:
# the target build's options, libraries and linker placement
# (firmware/f28335/target.mk, firmware/f28335/f28335_flash.cmd) and the HAL's pragmas,
# against C2000Ware's F2833x projects (F28335.cmd, the FPUfastRTS examples,
# InitFlash/InitAdc). Each failure names the file and the problem; exit 1
# if any check failed. Usage: target_cfg.sh [ROOT] (default: the repository).
set -uo pipefail
root=${1:-$(dirname "$0")/../..}
mk=$root/firmware/f28335/target.mk
cmd=$root/firmware/f28335/f28335_flash.cmd
hal=$root/hal/f28335
fail=0

bad() { echo "FAIL $1: $2"; fail=1; }
# has FILE REGEX: the file holds a line matching the (extended) regex
has() { grep -Eq -- "$2" "$1"; }

# D9: --issue_remarks is not a cl2000 option form (remarks: --issue_remarks / -pdr).
if has "$mk" '--issue_remarks='; then
    bad "$mk" "'--issue_remarks=...' is not a documented cl2000 option; drop it"
fi
# D10: entry point and library priority as in TI's F2833x projects.
has "$mk" '--entry_point=code_start' ||
    bad "$mk" "link without --entry_point=code_start: a debugger load skips the watchdog-disable branch"
has "$mk" '(^|[[:space:]])--priority([[:space:]]|$)' ||
    bad "$mk" "link without --priority: library search order alone decides which FS\$\$DIV/sin/cos wins"
# D4: the fast-RTS objects live in the _coff library (COFF ABI build).
for f in "$mk" "$cmd"; do
    if grep -Eo 'rts2800_fpu32_fast_supplement[a-z_]*\.lib' "$f" | grep -vq '_coff\.lib$'; then
        bad "$f" "names rts2800_fpu32_fast_supplement.lib (an index of .libinfo files); use rts2800_fpu32_fast_supplement_coff.lib"
    fi
done
has "$mk" -- '--library=rts2800_fpu32_fast_supplement_coff\.lib' ||
    bad "$mk" "does not link rts2800_fpu32_fast_supplement_coff.lib"
for m in sincos_f32 div_f32 sqrt_f32 atan2_f32; do
    has "$cmd" "rts2800_fpu32_fast_supplement_coff\\.lib<$m\\.obj>" ||
        bad "$cmd" "fast-RTS member $m.obj is not placed in ramfuncs (it would run from flash)"
done
# D6: ADC_cal's section from C2000Ware, placed (not loaded) at its OTP address.
has "$mk" 'DSP2833x_ADC_cal\.asm' ||
    bad "$mk" "does not assemble C2000Ware's DSP2833x_ADC_cal.asm (ADC_cal unresolved)"
has "$cmd" 'ADC_CAL[[:space:]]*:[[:space:]]*origin[[:space:]]*=[[:space:]]*0x380080' ||
    bad "$cmd" "no ADC_CAL memory at 0x380080 (TI-reserved OTP)"
has "$cmd" '\.adc_cal[[:space:]]*:.*ADC_CAL.*NOLOAD' ||
    bad "$cmd" "section .adc_cal not placed NOLOAD in ADC_CAL"
grep -q 'ADC_cal();' "$hal"/*.c || bad "$hal" "ADC_cal() is never called (TI's InitAdc calls it)"
# D5: the flash wait-state set-up runs from RAM and is never inlined into flash code.
grep -Eq '^RAMFUNC [^(]*\bf28335_flash_init\(' "$hal"/*.c ||
    bad "$hal" "f28335_flash_init is not RAMFUNC (in ramfuncs)"
grep -q 'FUNC_CANNOT_INLINE(f28335_flash_init)' "$hal"/*.c ||
    bad "$hal" "f28335_flash_init may be inlined into its flash-resident caller (FUNC_CANNOT_INLINE)"
# The boot entry: ours, zeroing .ebss (COFF zeroes nothing) with the
# watchdog off before _c_int00; C2000Ware's would define code_start twice.
asm=$root/firmware/f28335/f28335_codestart.asm
has "$mk" 'APP_ASM_SRCS[[:space:]]*:=.*firmware/f28335/f28335_codestart\.asm' ||
    bad "$mk" "does not assemble firmware/f28335/f28335_codestart.asm (code_start: watchdog off, .ebss zeroed)"
if has "$mk" '^[^#]*DSP2833x_CodeStartBranch\.asm'; then
    bad "$mk" "assembles C2000Ware's DSP2833x_CodeStartBranch.asm: code_start defined twice, .ebss not zeroed"
fi
has "$cmd" 'RUN_START\(_EbssRunStart\)' && has "$cmd" 'RUN_SIZE\(_EbssRunSize\)' ||
    bad "$cmd" ".ebss has no RUN_START(_EbssRunStart)/RUN_SIZE(_EbssRunSize): code_start cannot zero it"
for s in _EbssRunStart _EbssRunSize _c_int00 'MOV[[:space:]]+@WDCR,[[:space:]]*#WDCR_DISABLE'; do
    has "$asm" "$s" || bad "$asm" "no '$s': the start-up must disable the watchdog, zero .ebss from the linker's symbols and branch to _c_int00"
done
grep -q 'WDCR_DISABLE[[:space:]]*\.set[[:space:]]*0x0068' "$asm" || bad "$asm" "WDCR_DISABLE is not 0x0068 (WDDIS, WDCHK = 101b)"
# The flash CRC records main.c checks (flash_crc.h: CRC32_PRIME only).
for s in '\.text' ramfuncs '\.econst'; do
    grep -Eq "^[[:space:]]*${s}[[:space:]]*:.*crc_table\(_flash_crc_table, algorithm = CRC32_PRIME\)" "$cmd" ||
        awk "/^[[:space:]]*${s}[[:space:]]*:/,/^\$/" "$cmd" | grep -q 'crc_table(_flash_crc_table, algorithm = CRC32_PRIME)' ||
        bad "$cmd" "section ${s//\\/} has no crc_table(_flash_crc_table, algorithm = CRC32_PRIME): its flash is not checked"
done
has "$cmd" '\.TI\.crctab[[:space:]]*:' || bad "$cmd" ".TI.crctab (the linker's CRC table) is not placed"
# The copy of ramfuncs the HAL relies on.
has "$cmd" 'codestart[[:space:]]*:[[:space:]]*>[[:space:]]*BEGIN' || bad "$cmd" "codestart not at BEGIN (0x33FFF6)"
has "$cmd" 'RUN_START\(_RamfuncsRunStart\)' || bad "$cmd" "ramfuncs has no RUN_START(_RamfuncsRunStart)"
# RAMFUNC (control/c28x_portable.h) and --ramfunc=on put code in .TI.ramfunc.
awk '/^[[:space:]]*ramfuncs[[:space:]]*:/,/}/' "$cmd" | grep -q '\*(\.TI\.ramfunc)' ||
    bad "$cmd" "ramfuncs does not take *(.TI.ramfunc): RAMFUNC code would not be copied to RAM"

# The parameter store (hal/f28335/hal_f28335_nv.c): sector B reserved in
# the memory map where the HAL reads it, nothing placed in it (no CRC
# record covers it); TI's flash API run from RAM over ramfuncs' start (a
# UNION), the writer in nvfuncs at ramfuncs' end, beyond the API's reach.
cfg=$hal/hal_f28335_cfg.h
nv_addr=$(grep -Eo 'F28335_NV_SECTOR_ADDR[[:space:]]+0x[0-9A-Fa-f]+' "$cfg" | awk '{print $2}')
nv_len=$(grep -Eo 'F28335_NV_SECTOR_WORDS[[:space:]]+0x[0-9A-Fa-f]+' "$cfg" | awk '{print $2}')
if [ -z "$nv_addr" ] || [ -z "$nv_len" ] ||
        ! grep -Eiq "^[[:space:]]*FLASHB_NV[[:space:]]*:[[:space:]]*origin[[:space:]]*=[[:space:]]*${nv_addr%UL}UL?,[[:space:]]*length[[:space:]]*=[[:space:]]*0*${nv_len#0x}" "$cmd" &&
        ! grep -Eiq "^[[:space:]]*FLASHB_NV[[:space:]]*:[[:space:]]*origin[[:space:]]*=[[:space:]]*${nv_addr},[[:space:]]*length[[:space:]]*=[[:space:]]*0x0*${nv_len#0x}" "$cmd"; then
    bad "$cmd" "no FLASHB_NV range at F28335_NV_SECTOR_ADDR ($nv_addr), F28335_NV_SECTOR_WORDS ($nv_len) long: the parameter sector is not reserved where the HAL reads it"
fi
if grep -Eq '(>|LOAD[[:space:]]*=|RUN[[:space:]]*=)[[:space:]]*FLASHB_NV' "$cmd"; then
    bad "$cmd" "a section is placed in FLASHB_NV, the parameter store's sector: a save would erase it"
fi
PYTHONPATH=$root/tools/check python3 -c 'import ram_budget as r, re, sys
u = r.union_block(re.sub(r"/\*.*?\*/", "", open(sys.argv[1]).read(), flags=re.S))
sys.exit(0 if u and re.search(r"\bramfuncs\s*:", u[1]) and re.search(r"\bFlash28_API\s*:", u[1]) else 1)' "$cmd" ||
    bad "$cmd" "TI's flash API (Flash28_API) does not run over ramfuncs in a UNION"
for s in _Flash28_API_LoadStart _Flash28_API_LoadEnd _Flash28_API_RunStart; do
    has "$cmd" "$s" || bad "$cmd" "Flash28_API has no $s: hal_f28335_nv.c copies the API with it"
done
awk '/^[[:space:]]*ramfuncs[[:space:]]*:/,/}/' "$cmd" | grep -v '^[[:space:]]*}' | tail -n 1 | grep -q '\*(nvfuncs)' ||
    bad "$cmd" "ramfuncs does not end with *(nvfuncs): the flash API could overwrite the code that runs it"
grep -q 'CODE_SECTION(hal_nv_write, "nvfuncs")' "$hal/hal_f28335_nv.c" ||
    bad "$hal/hal_f28335_nv.c" "hal_nv_write is not in section nvfuncs"

# Code security: the image programs no CSM password (hal/f28335/README.md,
# "Code security"): RAM code in L4-L5, outside the secure zone, reads flash.
if has "$mk" '^[^#]*DSP2833x_CSMPasswords\.asm'; then
    bad "$mk" "assembles DSP2833x_CSMPasswords.asm: a secured device reads 0 from flash in the RAM code L4-L5 holds"
fi

if [ $fail -ne 0 ]; then
    echo "target_cfg: FAILED"
    exit 1
fi
echo "target_cfg: target build options, libraries and placement as in C2000Ware's F2833x projects"
