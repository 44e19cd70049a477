#!/bin/sh
# deps.sh: installs the Debian packages a make target needs that are missing
# (make deps-demo, make deps-test; the lists are the Makefile's DEBS_DEMO and
# DEBS_TEST, the README's "Dependencies and why each is there" says why).
# usage: sh tests/deps.sh TARGET PACKAGE...
# Installs as root, or through sudo when not root. When it cannot (neither,
# or apt-get fails) it names each missing package on a line of its own and
# exits 1. Another install holding the package manager's lock is waited for,
# up to DEPS_LOCK_SECONDS (default 600), with a line saying so.
target=$1
shift
missing=""
for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0

cannot_install() { # why
    echo "rodsim: make $target cannot install Debian packages ($1); missing:" >&2
    for p in $missing; do
        echo "rodsim: missing Debian package $p: install it with: apt-get install $p (as root)" >&2
    done
    exit 1
}

if [ "$(id -u)" = 0 ]; then
    sudo=""
elif command -v sudo >/dev/null 2>&1; then
    sudo="sudo"
else
    cannot_install "not root and no sudo"
fi
command -v apt-get >/dev/null 2>&1 || cannot_install "no apt-get"

# apt_get ARGS: apt-get without waiting first; if another install holds a
# lock, says so and waits: apt-get's DPkg::Lock::Timeout for dpkg's lock, and
# retries every 5 s for the package lists' lock (apt-get update ignores it).
lock_seconds=${DEPS_LOCK_SECONDS:-600}
log=$(mktemp) || exit 1
locked() { grep -q "Could not get lock\|Unable to acquire\|Unable to lock" "$log"; }
apt_get() {
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=0 "$@" >"$log" 2>&1 && return 0
    if locked; then
        echo "rodsim: waiting for the package manager lock (held by another install; up to ${lock_seconds} s)"
        deadline=$(($(date +%s) + lock_seconds))
        while :; do
            left=$((deadline - $(date +%s)))
            [ "$left" -lt 1 ] && left=1
            $sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout="$left" "$@" \
                >"$log" 2>&1 && return 0
            locked && [ "$(date +%s)" -lt "$deadline" ] || break
            sleep 5
        done
    fi
    cat "$log" >&2
    return 1
}

echo "rodsim: make $target: installing missing Debian packages:$missing"
# shellcheck disable=SC2086
if ! apt_get update -qq || ! apt_get install -y -qq $missing; then
    rm -f "$log"
    cannot_install "apt-get failed"
fi
rm -f "$log"
