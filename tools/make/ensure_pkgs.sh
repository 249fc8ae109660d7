#!/usr/bin/env bash
# ensure_pkgs.sh PKG... - make sure these Debian packages are installed.
# As root it installs what is missing with apt-get; otherwise it names the
# packages to install and exits 2. Calls are serialised by a lock
# (ENSURE_PKGS_LOCK, default /tmp/ensure_pkgs.lock): under `make -j` several
# rules may ask at once, and two `apt-get update`s racing for apt's lists
# lock fail. The list of what is missing is read again under the lock, so
# what one call installed the next one does not install again.
set -uo pipefail
lock=${ENSURE_PKGS_LOCK:-/tmp/ensure_pkgs.lock}
UPDATE_TRIES=3           # apt's lists lock may be held by an apt run outside make
UPDATE_RETRY_S=${ENSURE_PKGS_RETRY_S:-5}  # s between tries

missing_pkgs() {
    local p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || printf '%s ' "$p"
    done
}

missing=$(missing_pkgs "$@")
[ -z "$missing" ] && exit 0
exec 9>"$lock" || { echo "error: cannot open the lock file $lock (set ENSURE_PKGS_LOCK)" >&2; exit 2; }
flock 9
missing=$(missing_pkgs "$@")
[ -z "$missing" ] && exit 0
missing=${missing% }
if [ "$(id -u)" -ne 0 ]; then
    echo "error: missing Debian packages: $missing" >&2
    echo "       install them as root with: apt-get update && apt-get install -y $missing" >&2
    exit 2
fi
echo "installing Debian packages: $missing" >&2
export DEBIAN_FRONTEND=noninteractive
fail() { # what rc
    echo "error: $1 failed (exit $2) while installing: $missing" >&2
    echo "       run as root: apt-get update && apt-get install -y $missing" >&2
    exit 2
}
for try in $(seq 1 $UPDATE_TRIES); do
    apt-get -o DPkg::Lock::Timeout=300 update -qq >&2 && break
    rc=$?
    [ "$try" -eq $UPDATE_TRIES ] && fail "apt-get update" $rc
    sleep $UPDATE_RETRY_S
done
# shellcheck disable=SC2086 # the list is words
apt-get -o DPkg::Lock::Timeout=300 install -y -qq --no-install-recommends $missing >&2 || fail "apt-get install" $?
