#!/bin/sh
# The README's test command (make test): builds and runs every test twice,
# in the release build and under AddressSanitizer + UndefinedBehaviorSanitizer,
# then fuzzes each parser for FUZZ_SECONDS (make fuzz: one test per parser),
# and prints one closing line "N passed, N failed" over all three.
cd "$(dirname "$0")/.." || exit 1
status=0
rm -f build/release/summary build/asan/summary build/fuzz/summary
# The three builds compile on every core (make -j: a few hundred files each;
# one at a time they took about as long as the tests).
jobs=${RODSIM_TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
# Each phase's wall and CPU seconds (user + sys of everything it ran and
# waited for: the shell's `times`, its children's line, before and after;
# `times` itself, never in a subshell, which counts no children), printed
# at the end so a log shows where the time went.
phases=$(mktemp -d)
# phase NAME COMMAND...: runs COMMAND, adds "NAME WALL CPU" to the table
phase() {
    name=$1
    shift
    w0=$(date +%s.%N)
    times >"$phases/before"
    "$@"
    rc=$?
    times >"$phases/after"
    w1=$(date +%s.%N)
    awk -v name="$name" -v wall="$w1 - $w0" '
        FNR == 2 { for (i = 1; i <= 2; i++) { split($i, a, "m"); c[FILENAME] += a[1] * 60 + a[2] } }
        END { split(wall, w, " - "); printf "%-14s %8.1f %8.1f\n", name, w[1] - w[2],
                  c[ARGV[2]] - c[ARGV[1]] }' "$phases/before" "$phases/after" >>"$phases/table"
    return $rc
}
if phase release-build make -j"$jobs" --no-print-directory build-release; then
    phase release-tests sh tests/run_tests.sh build/release || status=1
else
    status=1
fi
if phase asan-build make -j"$jobs" --no-print-directory build-asan; then
    phase asan-tests sh tests/run_tests.sh build/asan || status=1
else
    status=1
fi
if phase fuzz-build make -j"$jobs" --no-print-directory fuzzers; then
    phase fuzz-run make --no-print-directory fuzz || status=1
else
    status=1
fi
passed=0
failed=0
for flavour in release asan fuzz; do
    summary=build/$flavour/summary
    if [ -f "$summary" ]; then
        passed=$((passed + $(cut -d' ' -f1 "$summary")))
        failed=$((failed + $(cut -d' ' -f3 "$summary")))
    else
        echo "FAIL $flavour build: no test ran (build failed?)"
        failed=$((failed + 1))
    fi
done
[ "$status" -ne 0 ] && [ "$failed" -eq 0 ] && failed=1
echo
echo "phase          wall s    CPU s (user + sys)"
cat "$phases/table"
awk '{ w += $2; c += $3 } END { printf "%-14s %8.1f %8.1f\n", "total", w, c }' "$phases/table"
rm -rf "$phases"
echo
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
