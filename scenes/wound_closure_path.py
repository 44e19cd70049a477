#!/usr/bin/env python3
"""Writes wound_closure_shape.csv and wound_closure_root.csv /
wound_closure_tip.csv, the starting thread and its ends' paths of
scenes/wound_closure.ini.

The stitch is placed already (the needle's bite made): the thread comes
straight down into the entry hole (y = -BITE on the skin), turns under the
skin on an arc of radius RC, runs across under the wound at depth RC, turns
up on a second arc into the exit hole (y = +BITE) and goes straight up. Each end, held
H above the skin, is then pulled up by PULL over T_PULL seconds (a smooth
ramp, 3 s^2 - 2 s^3), which draws the holes together:
  python3 wound_closure_path.py"""
import math

BITE, RC = 0.004, 0.003
# the legs as long as the part under the skin: a third of the thread each,
# so that the holes fall on nodes
# (49 nodes: nodes 16 and 32)
H = (math.pi * RC + 2 * (BITE - RC))
PULL, T_PULL, T_REST = 0.002, 2.0, 0.5


def shape():
    """Points (y, z) of the stitch at x = 0: down through the entry hole,
    an arc under the skin, across under the wound at depth RC, an arc, up
    through the exit hole."""
    pts = [(-BITE, H), (-BITE, 0.0)]
    n = 24
    for k in range(1, n + 1):  # centre (-BITE + RC, 0), from the hole down to +y
        a = math.pi + k * (math.pi / 2) / n
        pts.append((-BITE + RC + RC * math.cos(a), RC * math.sin(a)))
    for k in range(n + 1):  # centre (BITE - RC, 0), from +y up to the hole
        a = 1.5 * math.pi + k * (math.pi / 2) / n
        pts.append((BITE - RC + RC * math.cos(a), RC * math.sin(a)))
    pts.append((BITE, H))
    return pts


def main():
    pts = shape()
    with open("wound_closure_shape.csv", "w") as f:
        f.write("x,y,z\n")
        last = None
        for y, z in pts:
            if last and abs(last[0] - y) < 1e-12 and abs(last[1] - z) < 1e-12:
                continue
            f.write(f"0,{y:.9f},{z:.9f}\n")
            last = (y, z)
    for name, y in (("root", pts[0][0]), ("tip", pts[-1][0])):
        with open(f"wound_closure_{name}.csv", "w") as f:
            f.write("t,x,y,z\n")
            steps = 40
            for k in range(steps + 1):
                t = T_PULL * k / steps
                s = t / T_PULL
                f.write(f"{t:.4f},0,{y:.9f},{H + PULL * (3 * s * s - 2 * s ** 3):.9f}\n")
            f.write(f"{T_PULL + T_REST:.4f},0,{y:.9f},{H + PULL:.9f}\n")


if __name__ == "__main__":
    main()
