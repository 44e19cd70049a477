#!/bin/sh
# make demo: renders the headline scenes into out/ (filled in as parts land).
cd "$(dirname "$0")/.." || exit 1
echo "rodsim demo: nothing to render yet"
