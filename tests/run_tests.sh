#!/bin/sh
# Runs every test binary of one build flavour; prints each test's lines and
# one closing line "N passed, N failed" for the flavour. A binary that dies
# without its own closing line counts as one failure.
# usage: tests/run_tests.sh BUILD_DIR
build=$1
flavour=$(basename "$build")
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0"
export RODSIM_TEST_FLAVOUR="$flavour"
passed=0
failed=0
log=$(mktemp)
for t in $(find "$build/tests" -type f -name 'test_*' | sort); do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    echo "== $flavour/$name"
    "$t" >"$log" 2>&1
    status=$?
    cat "$log"
    last=$(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$log" | tail -n 1)
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
done
rm -f "$log"
echo "== $flavour: $passed passed, $failed failed"
echo "$passed passed, $failed failed" >"$build/summary"
[ "$failed" -eq 0 ]
