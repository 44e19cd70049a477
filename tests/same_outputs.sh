#!/bin/sh
# same_outputs.sh: checks that a change of code left every shipped scene's
# results byte for byte as they were (a refactoring must not change a number).
#
#   sh tests/same_outputs.sh record BIN DIR   run every scene with BIN, keep the outputs in DIR
#   sh tests/same_outputs.sh compare BIN DIR  run them again with BIN, compare with DIR
#
# A rod scene gives its centreline CSV (rodsim run --no-video --csv); a beam
# scene its nodal CSV and figure (rodsim fem); the pictures come from short
# runs of four scenes (poster PNG and video, 320x180, the first 0.3 s), which
# pass through every part of the renderer (tube, twist stripe, shadows,
# surfaces, needle, overlay). Exit 0 when everything is identical; otherwise
# each differing file is named.
set -u
mode=${1:-}
bin=${2:-}
dir=${3:-}
if [ -z "$mode" ] || [ -z "$bin" ] || [ -z "$dir" ] || [ ! -x "$bin" ]; then
    echo "usage: sh tests/same_outputs.sh record|compare BIN DIR" >&2
    exit 2
fi
cd "$(dirname "$0")/.." || exit 2
case "$mode" in
    record) out=$dir ;;
    compare) out=$(mktemp -d) ;;
    *) echo "same_outputs.sh: mode is record or compare, not '$mode'" >&2; exit 2 ;;
esac
mkdir -p "$out"
failed=0

run() { # name, command...: runs it, notes a failure
    name=$1
    shift
    if ! "$@" >"$out/$name.log" 2>&1; then
        echo "FAIL $name: exit status $? ($*)"
        failed=1
    fi
}

for scene in scenes/*.ini; do
    name=$(basename "$scene" .ini)
    if grep -q '^\[material\]' "$scene"; then
        run "$name" "$bin" fem "$scene" --csv "$out/$name.csv" --png "$out/$name.png"
    else
        run "$name" "$bin" run "$scene" --no-video --quiet --csv "$out/$name.csv"
    fi
done
for name in suture surgeons_knot skin_drop buckling_twist; do
    mkdir -p "$out/video_$name"
    run "video_$name" "$bin" run "scenes/$name.ini" -o "$out/video_$name" --quiet \
        --set render.width=320 --set render.height=180 --set solver.duration=0.3
done

if [ "$mode" = compare ]; then
    for f in $(cd "$dir" && find . -type f ! -name '*.log' | sort); do
        if ! cmp -s "$dir/$f" "$out/$f"; then
            echo "DIFFERS $f"
            failed=1
        fi
    done
    [ "$failed" -eq 0 ] && echo "same outputs: every file in $dir identical"
    rm -rf "$out"
fi
exit "$failed"
