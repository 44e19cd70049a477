#!/usr/bin/env python3
"""Writes wound_closure_shape.csv and wound_closure_root.csv /
wound_closure_tip.csv, the starting thread and its ends' paths of
scenes/wound_closure.ini, and prints the scene's rod length and inner
puncture points.

The stitch is placed already (the needle's bite made): the thread comes
straight down into the entry hole (y = -BITE on the skin), turns under the
skin on an arc of radius RC, runs across under the wound at depth RC, turns
up on a second arc into the exit hole (y = +BITE) and goes straight up. Each
end, held H above the skin, is then pulled up by PULL over T_PULL seconds (a
smooth ramp, 3 s^2 - 2 s^3), which draws the holes together:
  python3 wound_closure_path.py

The shape is written at the rod's 49 nodes, every chord DS long, so the run
takes it as it is: resampled, a shape's ends and corners move (the ends'
paths would start off the ends, the punctures off the thread). The nodes
are walked along that curve from its middle (node 24, under the wound) by
chords DS, DS chosen so that the eighth lands on each hole (nodes 16 and
32); the legs are 16 chords each. The two points where the bite turns
across fall inside a chord: their punctures are put on it (12 um from the
curve's turn).

The skin is the pad as it is at t = 0: settled under its pretension (the
held sides stretched 30 % across the wound), its top some 1.86 mm under the
box's top z = 0 at the holes. The script reads that settled top from
`rodsim run --tissue-csv` of the pad alone (wound_closure.ini's [surface],
a short rod far above it, one step): the holes are put on it (the scene's
punctures are points of the settled skin) and the whole stitch lowered with
them, so the bite runs RC under the skin. RODSIM names the program
(default ../build/release/rodsim):
  RODSIM=../build/release/rodsim python3 wound_closure_path.py"""
import math
import os
import subprocess
import tempfile

BITE, RC = 0.004, 0.003       # m: each hole's distance from the wound; the arcs' radius
HALF_BOTTOM = BITE - RC       # m: half the straight run under the wound
UNDER, LEGS = 8, 16           # chords from the middle to a hole; chords of a leg
NODES = 2 * (UNDER + LEGS) + 1
PULL, T_PULL, T_REST = 0.002, 2.0, 0.5


def curve(s):
    """The point (y, z) of the +y half at arc length s from the middle."""
    if s <= HALF_BOTTOM:
        return (s, -RC)
    a = (s - HALF_BOTTOM) / RC
    if a <= math.pi / 2:  # centre (BITE - RC, 0), from -RC up to the hole
        return (HALF_BOTTOM + RC * math.sin(a), -RC * math.cos(a))
    return (BITE, s - HALF_BOTTOM - RC * math.pi / 2)


def walk(ds, chords):
    """Arc lengths of the nodes from the middle, each next node DS (chord)
    from the last, further along."""
    s, out = 0.0, [0.0]
    for _ in range(chords):
        p, lo, hi = curve(s), s, s + 2 * ds
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            q = curve(mid)
            if math.hypot(q[0] - p[0], q[1] - p[1]) < ds:
                lo = mid
            else:
                hi = mid
        s = 0.5 * (lo + hi)
        out.append(s)
    return out


def chord_length():
    """DS such that the UNDER-th node lands on the hole."""
    hole = HALF_BOTTOM + RC * math.pi / 2
    lo, hi = 0.9 * hole / UNDER, hole / UNDER
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if walk(mid, UNDER)[-1] < hole:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def pad_section(scene="wound_closure.ini"):
    """The [surface] section of the scene, as it is written."""
    lines, inside = [], False
    with open(scene) as f:
        for line in f:
            if line.startswith("["):
                inside = line.split("#")[0].strip() == "[surface]"
            if inside:
                lines.append(line)
    return "".join(lines)


def settled_top():
    """The settled pad's top-face nodes at t = 0, [(x, y, z)] (m)."""
    rodsim = os.environ.get("RODSIM", "../build/release/rodsim")
    with tempfile.TemporaryDirectory() as tmp:
        scene, csv = os.path.join(tmp, "pad.ini"), os.path.join(tmp, "top.csv")
        with open(scene, "w") as f:
            f.write("[rod]\nlength = 0.01\ndiameter = 0.0003\ndensity = 1140\nyoungs_modulus = 1e9\n"
                    "shear_modulus = 0.37e9\nnodes = 5\n"
                    "origin = -0.005 0 0.02\n[solver]\nscheme = implicit\ndt = 0.001\n"
                    "duration = 0.001\n[physics]\ngravity = off\n" + pad_section())
        subprocess.run([rodsim, "run", scene, "--no-video", "--quiet", "--tissue-csv", csv],
                       check=True)
        with open(csv) as f:
            rows = [r.strip().split(",") for r in f.readlines()[1:]]
    return [tuple(map(float, r[2:5])) for r in rows if float(r[0]) == 0.0]


def top_at(top, x, y):
    """z of the settled top at (x, y): linear on the triangle of three
    nearby nodes that holds (x, y) and is smallest (the pad's top is flat
    to some 30 um over a cell there)."""
    near = sorted(top, key=lambda p: (p[0] - x) ** 2 + (p[1] - y) ** 2)[:8]
    best = None
    for i in range(len(near)):
        for j in range(i + 1, len(near)):
            for k in range(j + 1, len(near)):
                a, b, c = near[i], near[j], near[k]
                det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
                if abs(det) < 1e-12:
                    continue
                u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det
                v = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det
                if min(u, v, 1 - u - v) < -1e-12:
                    continue
                if best is None or abs(det) < best[0]:
                    best = (abs(det), a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]))
    return best[1]


def stitch_half(ds):
    """The +y half of the stitch from the middle: the nodes (y, z) (z from
    the skin), the UNDER-th on the hole; and the whole stitch's NODES."""
    under = [curve(s) for s in walk(ds, UNDER)]
    half = under + [(BITE, k * ds) for k in range(1, LEGS + 1)]
    half[UNDER] = (BITE, 0.0)  # on the hole to round-off
    pts = [(-y, z) for y, z in reversed(half[1:])] + half
    assert len(pts) == NODES
    return half, pts


def turn_on_chord(half, ds):
    """The turn across (y = HALF_BOTTOM, z = -RC) put on the chord of the
    half that passes it: (distance from the turn, (y, z))."""
    turn = (HALF_BOTTOM, -RC)
    best = None
    for a, b in zip(half, half[1:]):
        e = (b[0] - a[0], b[1] - a[1])
        tau = ((turn[0] - a[0]) * e[0] + (turn[1] - a[1]) * e[1]) / (ds * ds)
        tau = min(1.0, max(0.0, tau))
        q = (a[0] + tau * e[0], a[1] + tau * e[1])
        d = math.hypot(q[0] - turn[0], q[1] - turn[1])
        if best is None or d < best[0]:
            best = (d, q)
    return best


def end_path(f, y, skin, height, x=0.0):
    """An end's path: held `height` above the skin at (x, y), pulled up by
    PULL over T_PULL (3 s^2 - 2 s^3), then held over T_REST."""
    f.write("t,x,y,z\n")
    steps = 40
    for k in range(steps + 1):
        t = T_PULL * k / steps
        s = t / T_PULL
        z = skin + height + PULL * (3 * s * s - 2 * s ** 3)
        f.write(f"{t:.4f},{x:.12g},{y:.12f},{z:.12f}\n")
    f.write(f"{T_PULL + T_REST:.4f},{x:.12g},{y:.12f},{skin + height + PULL:.12f}\n")


def main():
    top = settled_top()
    skin = top_at(top, 0.0, -BITE)  # the holes' height; the mesh is mirrored about the slit
    ds = chord_length()
    half, pts = stitch_half(ds)
    height = LEGS * ds
    with open("wound_closure_shape.csv", "w") as f:
        f.write("x,y,z\n")
        for y, z in pts:
            f.write(f"0,{y:.12f},{z + skin:.12f}\n")
    for name, y in (("root", pts[0][0]), ("tip", pts[-1][0])):
        with open(f"wound_closure_{name}.csv", "w") as f:
            end_path(f, y, skin, height)
    best = turn_on_chord(half, ds)
    print(f"[rod] length = {(NODES - 1) * ds:.12g}, nodes = {NODES} (ds {ds:.6g} m), "
          f"the ends {height:.6g} m above the skin")
    print(f"[puncture] the holes: 0 -+{BITE:.12g} {skin:.12g} (the settled skin; "
          f"{top_at(top, 0.0, BITE) - skin:.2g} m between the two sides)")
    print(f"[puncture] under the skin: 0 -+{best[1][0]:.12g} {best[1][1] + skin:.12g} "
          f"({best[0]:.2g} m from the curve's turn)")


if __name__ == "__main__":
    main()
