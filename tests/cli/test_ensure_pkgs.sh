#!/usr/bin/env bash
# test_ensure_pkgs.sh - tools/make/ensure_pkgs.sh under concurrency, against a
# fake dpkg-query, apt-get and id on PATH (nothing is installed for real).
# The fake apt-get fails when two of it run at once, as apt's lists lock
# does; concurrent callers must all succeed with one update and one install.
set -uo pipefail
here=$(cd "$(dirname "$0")/../../tools/make" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
npass=0 nfail=0
check() { # NAME CONDITION-STATUS
    if [ "$2" -eq 0 ]; then echo "ok   ensure_pkgs $1"; npass=$((npass + 1));
    else echo "FAIL ensure_pkgs $1"; nfail=$((nfail + 1)); fi
}

fake=$dir/bin state=$dir/state
mkdir -p "$fake" "$state"
: > "$state/installed"
cat > "$fake/dpkg-query" <<'F'
#!/usr/bin/env bash
grep -qx "${!#}" "$FAKE_STATE/installed" && printf 'install ok installed'
exit 0
F
cat > "$fake/apt-get" <<'F'
#!/usr/bin/env bash
mkdir "$FAKE_STATE/running" 2>/dev/null || { echo "E: Could not get lock (fake)" >&2; echo concurrent >> "$FAKE_STATE/log"; exit 100; }
sleep 0.3
for a in "$@"; do
    case $a in update) echo update >> "$FAKE_STATE/log";; install) echo install >> "$FAKE_STATE/log";; esac
done
if [[ " $* " == *" install "* ]]; then
    for a in "$@"; do case $a in -*|install) ;; *) echo "$a" >> "$FAKE_STATE/installed";; esac; done
fi
rmdir "$FAKE_STATE/running"
F
printf '#!/usr/bin/env bash\necho "${FAKE_UID:-0}"\n' > "$fake/id"
chmod +x "$fake"/*
export FAKE_STATE=$state ENSURE_PKGS_LOCK=$dir/lock ENSURE_PKGS_RETRY_S=0 PATH=$fake:$PATH

pids=()
for k in 1 2 3 4; do
    "$here/ensure_pkgs.sh" pkg-a pkg-b 2> "$dir/err$k" & pids+=($!)
done
rcs=0
for p in "${pids[@]}"; do wait "$p" || rcs=1; done
check "four concurrent callers all succeed" $rcs
! grep -q concurrent "$state/log"; check "apt-get never runs twice at once" $?
[ "$(grep -c update "$state/log")" -eq 1 ] && [ "$(grep -c install "$state/log")" -eq 1 ]
check "one update and one install for the four callers" $?

"$here/ensure_pkgs.sh" pkg-a pkg-b 2> "$dir/err"
[ $? -eq 0 ] && [ "$(grep -c install "$state/log")" -eq 1 ]
check "nothing missing: no apt-get at all" $?

FAKE_UID=1000 "$here/ensure_pkgs.sh" pkg-c 2> "$dir/err"
[ $? -eq 2 ] && grep -q "pkg-c" "$dir/err" && grep -q "apt-get install -y pkg-c" "$dir/err"
check "without root: exit 2, the package and the command named" $?

mkdir "$state/running"
"$here/ensure_pkgs.sh" pkg-d 2> "$dir/err" </dev/null
rc=$?
rmdir "$state/running"
[ $rc -eq 2 ] && grep -q "pkg-d" "$dir/err" && grep -q "apt-get update" "$dir/err"
check "apt-get failing: exit 2, the package and the command named" $?

echo "ensure_pkgs: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
