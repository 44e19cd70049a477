#!/bin/sh
# make demo: runs the headline scene into out/. Until the renderer lands this
# is the simulation alone: it writes out/suture.csv (the centreline at every
# frame) and prints the run's summary; the lead wires the video in run.c.
cd "$(dirname "$0")/.." || exit 1
bin=build/release/rodsim
[ -x "$bin" ] || { echo "demo: $bin is missing; run make first" >&2; exit 1; }
mkdir -p out
"$bin" run scenes/suture.ini -o out --csv out/suture.csv
status=$?
if [ "$status" -ne 0 ]; then
    echo "demo: rodsim run scenes/suture.ini failed with exit status $status" >&2
    exit "$status"
fi
echo "demo: wrote out/suture.csv ($(wc -l <out/suture.csv) lines)"
