#!/usr/bin/env bash
# est_owner.sh - the estimation's owner gate of `make check`: nothing
# outside control/est/est.[ch] and control/est/est_cfg.c (the owner's start-up)
# touches the estimation's state (control/est/est.h).
#   1. no member access through an est_t: `.est.` or `->est.` followed by
#      a member, outside the owner's files (tests/ may look inside: white box)
#   2. no per-period call of the estimation's blocks (smo_, rs_ident_,
#      param_est_, est_gate_, r_track_, psi_band_ functions, their names
#      with digits too, other than the *_cfg_defaults of a configuration)
#      outside the owner's files and the blocks themselves
# Each failure names the file and line; exit 1 if any.
set -uo pipefail
cd "$(dirname "$0")/../.."
fail=0
blocks='control/est/(smo|smo_cfg|rs_ident|param_est|est_gate|r_track|psi_band)\.[ch]$'
files=$(ls control/*.[ch] control/*/*.[ch] firmware/*/*.[ch] hal/*.h hal/*/*.[ch] tools/bench/*.c tools/sil/*.[ch] 2>/dev/null |
        grep -vE '^control/est/est(\.[ch]|_cfg\.c)$')
for f in $files; do
    if hits=$(grep -nE '(\.|->)est\.[A-Za-z_]' "$f"); then
        echo "FAIL $f: touches the estimation's members (use est.h's calls and readers):"
        echo "$hits" | sed 's/^/    /'
        fail=1
    fi
    if echo "$f" | grep -qE "$blocks"; then
        continue
    fi
    if hits=$(grep -nE '\b(smo|rs_ident|param_est|est_gate|r_track|psi_band)_[a-z0-9_]+\(' "$f" |
              grep -vE '\b(smo|rs_ident|param_est|est_gate|r_track|psi_band)_cfg_defaults\('); then
        echo "FAIL $f: calls an estimation block directly (the estimation owns them: est.h):"
        echo "$hits" | sed 's/^/    /'
        fail=1
    fi
done
if [ "$fail" -eq 0 ]; then
    echo "est_owner: nothing outside control/est/est.[ch], est_cfg.c touches the estimation's state"
fi
exit "$fail"
