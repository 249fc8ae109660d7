#!/usr/bin/env bash
# app_reach.sh - the tests' surface gate of `make check`: the tests read
# and drive the app's controller through its public surface (app_ctrl()
# with ctrl.h's readers, app_monitor(), app_estimate()) and, for what that
# surface does not give, through tests/app_probe.h, so a change of ctrl_t
# or est_t touches the probe, not the tests.
#   1. no use of an app_t's controller member (`app.ctrl`, `&app.ctrl`,
#      `a->ctrl.mon`, any variable's name) in tests/ outside the allow-list;
#      an app_cfg_t's `cfg.ctrl` (the configuration) is no reach-in
#   2. no member access through the readers' results (`app_ctrl(&app)->`,
#      `probe_ctrl_rw(&app)->`, `ctrl_est(app_ctrl(&app))->`)
# A grep gate: it sees spellings, not a pointer kept in a variable. The
# allow-list: the probe. A white-box test of a control/ module holds its
# own ctrl_t or est_t and is no concern of this gate.
# Each failure names the file and line; exit 1 if any.
set -uo pipefail
cd "$(dirname "$0")/../.."
allow='^tests/app_probe\.h$'
reader='\b(app_ctrl|probe_ctrl_rw)\([^()]*\)'
fail=0
files=$(ls tests/*.[ch] tests/*/*.[ch] 2>/dev/null | grep -vE "$allow")
for f in $files; do
    if hits=$(grep -nP '(?<!cfg)(\.|->)ctrl\b' "$f"); then
        echo "FAIL $f: reaches into the app's controller (app_t.ctrl): use app_ctrl() and ctrl.h's readers, or tests/app_probe.h:"
        echo "$hits" | sed 's/^/    /'
        fail=1
    fi
    if hits=$(grep -nE "$reader\s*->|\bctrl_est(_rw)?\(\s*$reader\s*\)\s*->" "$f"); then
        echo "FAIL $f: reaches into the controller through a reader's result: use ctrl.h's and est.h's readers, or tests/app_probe.h:"
        echo "$hits" | sed 's/^/    /'
        fail=1
    fi
done
if [ "$fail" -eq 0 ]; then
    echo "app_reach: no test reaches into the app's controller outside tests/app_probe.h"
fi
exit "$fail"
