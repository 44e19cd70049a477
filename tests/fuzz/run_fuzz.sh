#!/bin/sh
# Runs each libFuzzer harness build/fuzz/bin/fuzz_NAME for SECONDS on a copy of
# its seed corpus: the edge cases in tests/fuzz/corpus/NAME/, plus the shipped
# scenes/*.ini (rod scenes for NAME = scene, beam scenes with [material] for
# fem_scene) and scenes/*.csv (by their header: x,y,z for shape, t,x,y,z... for
# path, t,factor or t,fx,... for load_table), so the seeds follow the scenes.
# New inputs go to a temporary folder, never into the git tree. Each harness counts as one test: it passes when
# libFuzzer ran out its time without a crash, a sanitizer report, a leak, a
# timeout (one input > 10 s) or an out-of-memory (> 2048 MB). A failing input is
# kept in BUILD_DIR/crashes/NAME/ and printed with the command that replays it.
# Ends with "N passed, N failed", also written to BUILD_DIR/summary.
# usage: tests/fuzz/run_fuzz.sh BUILD_DIR SECONDS
build=$1
seconds=${2:-30}
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp:print_suppressions=0"
# The harnesses run FUZZ_JOBS at a time (default: the cores, at most 2),
# each for its SECONDS on its own core, so the fuzzing per harness is what
# one at a time gives; their lines are printed in name order afterwards.
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -gt 2 ] && jobs=2
[ "$jobs" -lt 1 ] && jobs=1
results=$(mktemp -d "${TMPDIR:-/tmp}/rodsim-fuzz-results.XXXXXX")
# fuzz_one BIN: runs one harness; its lines into $results/NAME.log, and
# "pass" or "fail" into $results/NAME.result
fuzz_one() {
    bin=$1
    name=$(basename "$bin")
    {
        seeds=tests/fuzz/corpus/${name#fuzz_}
        echo "== fuzz/$name"
        work=$(mktemp -d "${TMPDIR:-/tmp}/rodsim-fuzz.XXXXXX")
        mkdir -p "$work/corpus" "$work/tmp"
        [ -d "$seeds" ] && cp "$seeds"/* "$work/corpus/" 2>/dev/null
        for scene in scenes/*.ini; do
            if grep -q '^\[material\]' "$scene"; then kind=fem_scene; else kind=scene; fi
            [ "$kind" = "${name#fuzz_}" ] && cp "$scene" "$work/corpus/"
        done
        for table in scenes/*.csv; do # by its header: a shape, a path or a load table
            head=$(grep -v -e '^[[:space:]]*#' -e '^[[:space:]]*$' "$table" | head -n 1 | tr -d ' \r')
            case "$head" in
                x,y,z) kind=shape ;;
                t,x,y,z*) kind=path ;;
                t,*) kind=load_table ;;
                *) kind=none ;;
            esac
            [ "$kind" = "${name#fuzz_}" ] && cp "$table" "$work/corpus/"
        done
        seeds_n=$(ls "$work/corpus" | wc -l)
        dict=tests/fuzz/${name#fuzz_}.dict
        [ -f "$dict" ] && dict_opt="-dict=$dict" || dict_opt=""
        TMPDIR="$work/tmp" "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
            -print_final_stats=1 -artifact_prefix="$work/" $dict_opt "$work/corpus" \
            >"$work/log" 2>&1
        status=$?
        runs=$(grep -E '^stat::number_of_executed_units' "$work/log" | awk '{print $2}')
        cov=$(grep -E '#[0-9]+[[:space:]]+DONE' "$work/log" | sed -n 's/.*cov: \([0-9]*\).*/\1/p' | tail -n 1)
        found=$(ls "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-* 2>/dev/null | head -n 1)
        if [ "$status" -eq 0 ] && [ -z "$found" ]; then
            echo "PASS $name: ${runs:-?} inputs in $seconds s from $seeds_n seeds, coverage ${cov:-?} edges, no crash"
            echo pass >"$results/$name.result"
        else
            tail -n 60 "$work/log"
            if [ -n "$found" ]; then
                mkdir -p "$build/crashes/$name"
                cp "$found" "$build/crashes/$name/"
                kept="$build/crashes/$name/$(basename "$found")"
                echo "FAIL $name: libFuzzer exit status $status; reproducer $kept (replay: $bin $kept)"
            else
                echo "FAIL $name: libFuzzer exit status $status, no reproducer written"
            fi
            echo fail >"$results/$name.result"
        fi
        rm -rf "$work"
    } >"$results/$name.log" 2>&1
}
running=0
for bin in "$build"/bin/fuzz_*; do
    [ -x "$bin" ] || continue
    fuzz_one "$bin" &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then
        wait
        running=0
    fi
done
wait
passed=0
failed=0
for bin in "$build"/bin/fuzz_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    cat "$results/$name.log" 2>/dev/null
    if [ "$(cat "$results/$name.result" 2>/dev/null)" = pass ]; then
        passed=$((passed + 1))
    else
        grep -q '^FAIL' "$results/$name.log" 2>/dev/null ||
            echo "FAIL $name: the harness's run left no result"
        failed=$((failed + 1))
    fi
done
rm -rf "$results"
if [ $((passed + failed)) -eq 0 ]; then
    echo "FAIL fuzz: no harness in $build/bin"
    failed=1
fi
echo "== fuzz: $passed passed, $failed failed"
echo "$passed passed, $failed failed" >"$build/summary"
[ "$failed" -eq 0 ]
