#!/bin/sh
# Runs every test binary of one build flavour; prints each test's lines and
# one closing line "N passed, N failed" for the flavour. A binary that dies
# without its own closing line counts as one failure.
# usage: tests/run_tests.sh BUILD_DIR
build=$1
flavour=$(basename "$build")
# intercept_tls_get_addr=0: this GCC's sanitizer runtime (Debian 12, GCC
# 12) takes a dynamic TLS block that starts 16 bytes past a page boundary
# for one of glibc 2.19-2.24's, which had a header, and reads the two words
# before it (here an ASan chunk header) as the block's range; LeakSanitizer
# scans that range at exit and dies ("Tracer caught signal 11", exit 1).
# Which block lands there is chance, moved by any allocation made before
# it: Mesa's EGL parses every file in /usr/share/drirc.d, so with
# mesa-vulkan-drivers' file there, libLLVM's block lands there in
# test_run_scenes' suture.ini. Leak checking loses nothing: glibc mallocs
# these blocks from ld.so, and LeakSanitizer scans what ld.so allocates as
# reachable. tests/render/test_egl.c places a block there on purpose.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0"
export RODSIM_TEST_FLAVOUR="$flavour"
passed=0
failed=0
# The binaries run RODSIM_TEST_JOBS at a time (default: the cores, at most
# 4), each into its own log; the logs are then printed in name order, so
# the output does not depend on which finished first. Every test writes
# only under its own temporary directory.
jobs=${RODSIM_TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -gt 4 ] && jobs=4
[ "$jobs" -lt 1 ] && jobs=1
logs=$(mktemp -d)
find "$build/tests" -type f -name 'test_*' | sort >"$logs/list"
# Longest first, so no core idles at the end while one long test finishes
# alone: each test's seconds from this build's last run ($build/test_times),
# else from tests/test_times (this flavour's lines, measured on 2 cores); a
# test in neither (a new one) starts first, as if it were the longest.
times=$build/test_times
[ -s "$times" ] || times=tests/test_times
while read -r t; do
    n=$(basename "$t")
    s=$(awk -v f="$flavour" -v n="$n" '$1 == f && $2 == n { print $3; exit }' "$times" 2>/dev/null)
    echo "${s:-9999} $t"
done <"$logs/list" | sort -k1,1nr -k2,2 | cut -d' ' -f2- >"$logs/order"
# shellcheck disable=SC2016
xargs -P "$jobs" -I{} sh -c '
    t=$1; d=$2; n=$(basename "$t")
    [ -x "$t" ] || exit 0
    start=$(date +%s.%N)
    "$t" >"$d/$n.log" 2>&1
    echo $? >"$d/$n.status"
    echo "$start $(date +%s.%N)" >"$d/$n.time"
' run_one {} "$logs" <"$logs/order"
# this run's seconds per test (wall), for the next run's order
while read -r t; do
    n=$(basename "$t")
    [ -f "$logs/$n.time" ] && awk -v f="$flavour" -v n="$n" '{ printf "%s %s %.1f\n", f, n, $2 - $1 }' "$logs/$n.time"
done <"$logs/list" >"$build/test_times.new" && mv "$build/test_times.new" "$build/test_times"
while read -r t; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    echo "== $flavour/$name"
    log="$logs/$name.log"
    status=$(cat "$logs/$name.status" 2>/dev/null || echo 255)
    cat "$log" 2>/dev/null
    last=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" 2>/dev/null | tail -n 1)
    if [ -z "$last" ]; then
        echo "FAIL $name: exited with status $status before its summary"
        failed=$((failed + 1))
        continue
    fi
    p=$(echo "$last" | cut -d' ' -f1)
    f=$(echo "$last" | cut -d' ' -f3)
    if [ "$status" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: exit status $status (sanitizer report or crash after the summary)"
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
done <"$logs/list"
rm -rf "$logs"
# The Python package (tests/python) on this build's librodsim.so, in the
# release flavour only (a sanitized library cannot be loaded into python3).
# Debian's python3 (python3-pytest, python3-numpy: the Makefile's DEBS_TEST); its summary
# line ("N passed, M failed in S s") is counted like a binary's.
python=${RODSIM_PYTHON:-/usr/bin/python3}
if [ "$flavour" = release ] && [ -e "$build/librodsim.so" ]; then
    echo "== $flavour/python"
    log=$(mktemp)
    RODSIM_LIBRARY="$(pwd)/$build/librodsim.so" RODSIM_BIN="$(pwd)/$build/rodsim" \
        "$python" -m pytest -q -rA -p no:cacheprovider tests/python >"$log" 2>&1
    status=$?
    grep -E '^(PASSED|FAILED|ERROR) ' "$log" | sed 's/^PASSED/PASS/; s/^FAILED/FAIL/; s/^ERROR/FAIL/'
    last=$(tail -n 1 "$log")
    p=$(echo "$last" | sed -n 's/.* \([0-9][0-9]*\) passed.*/\1/p; s/^\([0-9][0-9]*\) passed.*/\1/p' | head -n 1)
    f=$(echo "$last" | sed -n 's/^\([0-9][0-9]*\) failed.*/\1/p; s/.* \([0-9][0-9]*\) failed.*/\1/p' | head -n 1)
    e=$(echo "$last" | sed -n 's/.* \([0-9][0-9]*\) errors\{0,1\}.*/\1/p' | head -n 1)
    p=${p:-0}
    f=$((${f:-0} + ${e:-0}))
    if [ "$status" -ne 0 ] && [ "$f" -eq 0 ]; then
        tail -n 30 "$log"
        echo "FAIL python: pytest exited with status $status"
        f=1
    fi
    echo "$p passed, $f failed"
    passed=$((passed + p))
    failed=$((failed + f))
    rm -f "$log"
fi
echo "== $flavour: $passed passed, $failed failed"
echo "$passed passed, $failed failed" >"$build/summary"
[ "$failed" -eq 0 ]
