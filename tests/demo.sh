#!/bin/sh
# make demo: renders the headline scenes into out/:
#   out/stitch.mp4 (+ .png poster): a simple interrupted stitch, a needle
#     holder driving a curved needle across a gaping wound in elastic skin,
#     forceps taking it by its point and drawing it out, the thread drawn
#     through and the wound's edges drawn together, each step captioned
#     (about 45 s of CPU);
#   out/suture.mp4 (+ .png poster, + .csv centreline): a running suture, a
#     needle making three bites across a wound (about 2 minutes);
#   out/skin_drop.mp4 (+ .png): a thread dropped on a skin pad (contact,
#     friction, shadows);
#   out/overhand_tight.mp4 (+ .png): a loose overhand knot pulled tight by a
#     force, its strands kept apart by self-contact, the camera on the knot;
#   out/surgeons_knot.mp4 (+ .png): a surgeon's knot over a suture's bite
#     through a practice pad, cinched by both ends (about 70 s);
#   out/buckling_twist.mp4 (+ .png): a rod twisted under tension coiling into
#     a plectoneme, the stripe (a material line) showing the twist.
cd "$(dirname "$0")/.." || exit 1
bin=build/release/rodsim
[ -x "$bin" ] || { echo "demo: $bin is missing; run make first" >&2; exit 1; }
mkdir -p out
for scene in stitch suture skin_drop overhand_tight surgeons_knot buckling_twist; do
    csv=""
    [ "$scene" = suture ] && csv="--csv out/suture.csv"
    # shellcheck disable=SC2086
    "$bin" run "scenes/$scene.ini" -o out $csv
    status=$?
    if [ "$status" -ne 0 ]; then
        echo "demo: rodsim run scenes/$scene.ini failed with exit status $status" >&2
        exit "$status"
    fi
done
echo "demo: wrote out/stitch.mp4, out/stitch.png, out/suture.mp4, out/suture.png, out/suture.csv, out/skin_drop.mp4, out/skin_drop.png, out/overhand_tight.mp4, out/overhand_tight.png, out/surgeons_knot.mp4, out/surgeons_knot.png, out/buckling_twist.mp4, out/buckling_twist.png"
