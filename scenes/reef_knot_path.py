#!/usr/bin/env python3
"""Writes the starting shapes of reef_knot.ini and granny_knot.ini: two
threads, a and b, tied together loosely by a reef (square) knot or a granny
knot, ready to be pulled apart.

How the knot is built (lengths in thread diameters D), as surgeons_knot_path.py
builds its throws, with single throws and no bite:
- A throw is the two threads wrapped around each other: a double helix of
  radius R and pitch P about a line along y, the threads half a turn apart,
  1.5 turns (3 half-twists: a half knot). The first throw's axis is at
  z = Z1, the second's at Z2.
- Each thread is a bight: thread a's tail leaves the second throw at its
  top towards -y; a runs the second throw to +y, turns down in a U-turn at
  +y, runs the first throw back to -y and leaves it at the bottom towards
  -y: its standing part. Thread b is a turned through y -> -y (half a turn
  on along the throws): its legs leave towards +y.
- The second throw's helix turned the other way along the threads than the
  first's (HAND2 = 1 here, as the surgeon's script reads it) is the reef
  knot; the same way (HAND2 = -1) the granny. Closed as two threads are
  (the standing parts joined below, the tails above: sim/geometry/
  knot_across.c), the reef is the square knot, the granny the granny.
- Each thread's node 0 is its tail's end and its last node its standing
  end, which the scenes pull.

The waypoints are joined by straight pieces, sampled every 0.02 D, smoothed
by a Gaussian of 1.5 D, and NODES points placed exactly ds apart along the
result (chords.py). The script prints the closest approach of the two
threads' segments and of each thread's own (more than 3 D apart along it).

    python3 reef_knot_path.py     # writes reef_knot_{a,b}.csv, granny_knot_{a,b}.csv
"""
import math

import chords

D = 0.0008                  # m: the thread's diameter
NODES = 321
R, P = 4.0, 8.0             # throw radius and pitch, D
Z1, Z2 = 7.0, 23.0          # the throws' axes, D
TAIL = 30.0                 # D: a tail beyond the U-turns
STANDING = 40.0             # D: a standing part beyond the U-turns
TURNS = 1.5


def semicircle(cy, cz, radius, side, downward, n=200):
    pts = []
    for k in range(n + 1):
        a = math.pi * k / n
        a = a if downward else math.pi - a
        pts.append((0.0, cy + side * radius * math.sin(a), cz + radius * math.cos(a)))
    return pts


def threads(hand2):
    a1 = TURNS * P / 2
    ru = 0.5 * (Z2 - Z1 - 2 * R)
    out = a1 + 0.5 * R
    zm = 0.5 * (Z1 + Z2)

    def phi1(y):
        return -math.pi / 2 + 2 * math.pi * TURNS * (y + a1) / (2 * a1)

    def phi2(y):
        return -math.pi / 2 + hand2 * 2 * math.pi * TURNS * (a1 - y) / (2 * a1)

    def sweep(z, phi, shift, y0, y1, n=800):
        ys = [y0 + (y1 - y0) * k / n for k in range(n + 1)]
        return [(R * math.cos(phi(y) + shift), y, z + R * math.sin(phi(y) + shift)) for y in ys]

    # a: tail (-y, top) -> second throw -> U-turn at +y -> first throw -> standing (-y, bottom)
    a = [(0.0, -(out + TAIL), Z2 + R), (0.0, -a1 - 0.5 * R, Z2 + R)]
    a += sweep(Z2, phi2, 0.0, -a1, a1)
    a += [(0.0, out, Z2 - R)] + semicircle(out, zm, ru, 1, True)[1:-1] + [(0.0, out, Z1 + R)]
    a += sweep(Z1, phi1, 0.0, a1, -a1)
    a += [(0.0, -a1 - 0.5 * R, Z1 - R), (0.0, -(out + STANDING), Z1 - R)]
    # b: tail (+y, top) -> second throw -> U-turn at -y -> first throw -> standing (+y, bottom)
    b = [(0.0, out + TAIL, Z2 + R), (0.0, a1 + 0.5 * R, Z2 + R)]
    b += sweep(Z2, phi2, math.pi, a1, -a1)
    b += [(0.0, -out, Z2 - R)] + semicircle(-out, zm, ru, -1, True)[1:-1] + [(0.0, -out, Z1 + R)]
    b += sweep(Z1, phi1, math.pi, -a1, a1)
    b += [(0.0, a1 + 0.5 * R, Z1 - R), (0.0, out + STANDING, Z1 - R)]
    return a, b


def densify(pts, h=0.02):
    out = [pts[0]]
    for a, b in zip(pts, pts[1:]):
        n = max(1, int(math.dist(a, b) / h))
        for k in range(1, n + 1):
            out.append(tuple(a[i] + (b[i] - a[i]) * k / n for i in range(3)))
    return out


def smooth(pts, sigma=1.5, h=0.02):
    half = int(3 * sigma / h)
    w = [math.exp(-0.5 * (k * h / sigma) ** 2) for k in range(-half, half + 1)]
    out = []
    n = len(pts)
    for j in range(n):
        lo, hi = max(0, j - half), min(n - 1, j + half)
        m = min(j - lo, hi - j)
        s, acc = 0.0, [0.0, 0.0, 0.0]
        for k in range(j - m, j + m + 1):
            wk = w[k - j + half]
            s += wk
            for i in range(3):
                acc[i] += wk * pts[k][i]
        out.append(tuple(c / s for c in acc))
    return out


def seg_dist(p, q, r, s):
    best = 1e30
    for i in range(11):
        a = tuple(p[c] + (q[c] - p[c]) * i / 10 for c in range(3))
        for j in range(11):
            b = tuple(r[c] + (s[c] - r[c]) * j / 10 for c in range(3))
            best = min(best, math.dist(a, b))
    return best


def closest(p, q, skip):
    best = 1e30
    for i in range(len(p) - 1):
        for j in range(len(q) - 1):
            if p is q and j < i + skip:
                continue
            if math.dist(p[i], q[j]) > best + 2:
                continue
            best = min(best, seg_dist(p[i], p[i + 1], q[j], q[j + 1]))
    return best


def main():
    for name, hand2 in (("reef_knot", 1.0), ("granny_knot", -1.0)):
        a, b = threads(hand2)
        pa, dsa = chords.place(smooth(densify(a)), NODES)
        pb, dsb = chords.place(smooth(densify(b)), NODES)
        skip = int(math.ceil(3.0 / dsa)) + 1
        print("%s: ds = %.4f D (a), %.4f D (b); closest a-b %.3f D, a-a %.3f D, b-b %.3f D"
              % (name, dsa, dsb, closest(pa, pb, 0), closest(pa, pa, skip), closest(pb, pb, skip)))
        for tag, pts, ds in (("a", pa, dsa), ("b", pb, dsb)):
            with open("%s_%s.csv" % (name, tag), "w") as f:
                f.write("x,y,z\n")
                for p in pts:
                    f.write("%.12f,%.12f,%.12f\n" % tuple(D * c for c in p))
            print("  %s: length = %.9f m ((NODES - 1) ds), tail end (%.6f, %.6f, %.6f) m, "
                  "standing end (%.6f, %.6f, %.6f) m" % ((tag, (NODES - 1) * ds * D)
                  + tuple(D * c for c in pts[0]) + tuple(D * c for c in pts[-1])))


if __name__ == "__main__":
    main()
