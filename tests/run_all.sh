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
make -j"$jobs" --no-print-directory test-release || status=1
make -j"$jobs" --no-print-directory test-asan || status=1
make -j"$jobs" --no-print-directory fuzz || status=1
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
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
