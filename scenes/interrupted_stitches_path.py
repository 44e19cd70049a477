#!/usr/bin/env python3
"""Writes the starting threads and their ends' paths of
scenes/interrupted_stitches.ini (interrupted_stitches_NAME_shape.csv,
_root.csv, _tip.csv for the rods left, middle, right) and prints the
scene's [puncture] sections.

Three simple interrupted stitches across wound_closure.ini's incision (the
same pad, the same 24 mm wound along x), SPACING apart along it: each is
wound_closure.ini's stitch (wound_closure_path.py lays it: its curve, its
chords, its ends' pull, imported from there), moved to x = -SPACING, 0,
+SPACING and laid on the settled skin there (the pad's top sinks less
towards the wound's ends). Each thread is a rod of its own; the three pull
the one pad. RODSIM names the program (default ../build/release/rodsim):
  RODSIM=../build/release/rodsim python3 interrupted_stitches_path.py"""
import wound_closure_path as stitch

SPACING = 0.008                # m: between the stitches along the wound
STITCHES = (("left", -SPACING), ("middle", 0.0), ("right", SPACING))


def main():
    top = stitch.settled_top()  # the pad is wound_closure.ini's
    ds = stitch.chord_length()
    half, pts = stitch.stitch_half(ds)
    height = stitch.LEGS * ds
    turn = stitch.turn_on_chord(half, ds)[1]
    print(f"[rod NAME] length = {(stitch.NODES - 1) * ds:.12g}, nodes = {stitch.NODES}")
    for name, x in STITCHES:
        skin = stitch.top_at(top, x, -stitch.BITE)
        with open(f"interrupted_stitches_{name}_shape.csv", "w") as f:
            f.write("x,y,z\n")
            for y, z in pts:
                f.write(f"{x:.12g},{y:.12f},{z + skin:.12f}\n")
        for end, y in (("root", pts[0][0]), ("tip", pts[-1][0])):
            with open(f"interrupted_stitches_{name}_{end}.csv", "w") as f:
                stitch.end_path(f, y, skin, height, x)
        for y, z in ((-stitch.BITE, 0.0), (-turn[0], turn[1]), (turn[0], turn[1]),
                     (stitch.BITE, 0.0)):
            print(f"[puncture]\nrod = {name}\npoint = {x:.12g} {y:.12g} {z + skin:.12g}\n"
                  "friction = 0")


if __name__ == "__main__":
    main()
