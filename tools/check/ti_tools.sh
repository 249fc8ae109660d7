#!/usr/bin/env bash
# ti_tools.sh - stop with a clear message (exit 2) unless TI's C2000 tools are present.
ok=1
if [ -z "${CG_TOOL_ROOT:-}" ] || [ ! -x "${CG_TOOL_ROOT}/bin/cl2000" ]; then ok=0; fi
if [ -z "${C2000WARE_ROOT:-}" ] || [ ! -d "${C2000WARE_ROOT}/device_support/f2833x" ]; then ok=0; fi
api=${FLASH_API_ROOT:-${C2000WARE_ROOT:-}/libraries/flash_api/f2833x}
if [ $ok -eq 1 ] && [ ! -f "$api/lib/Flash28335_API_V210.lib" ]; then
    cat >&2 <<MSG
error: TI's Flash2833x API (the parameter store's flash writer) is not found:
  FLASH_API_ROOT  = '$api'  (must contain lib/Flash28335_API_V210.lib and
                    include/Flash2833x_API_Library.h)
  It ships with C2000Ware (libraries/flash_api/f2833x) and as TI's SPRC539;
  pass FLASH_API_ROOT=<its folder> if yours lies elsewhere.
MSG
    exit 2
fi
if [ $ok -eq 0 ]; then
    cat >&2 <<MSG
error: the F28335 build needs TI's C2000 tools, which are not found.
  CG_TOOL_ROOT    = '${CG_TOOL_ROOT:-}'  (must contain bin/cl2000)
  C2000WARE_ROOT  = '${C2000WARE_ROOT:-}'  (must contain device_support/f2833x)
  Get the C2000 code generation tools (TI-CGT C2000, or the copy inside Code
  Composer Studio: <ccs>/tools/compiler/ti-cgt-c2000_<ver>) and C2000Ware
  from ti.com, then run, for example:
    make firmware CG_TOOL_ROOT=/opt/ti/ti-cgt-c2000_22.6.1.LTS C2000WARE_ROOT=/opt/ti/C2000Ware_5_02_00_00
MSG
    exit 2
fi
