#!/usr/bin/env python3
"""Writes surgeons_knot_shape.csv for surgeons_knot.ini: a loose surgeon's
knot (a double throw, then a single throw turned the other way) tied over a
suture's bite through a practice pad, ready to be pulled tight by its ends.

How the knot is built (lengths in cord diameters D):
- The bite: the cord enters the pad (its top is the plane z = 0) at
  y = -W, passes DEPTH under it, and leaves at y = +W (x = 0: the wound
  runs along x).
- A throw is the two strands wrapped around each other: a double helix of
  radius R and pitch P about a line along y, the strands half a turn apart.
  A single throw is 1.5 turns (3 half-twists: closed through the bite and
  far from the knot, a trefoil: the half knot); the double throw 2.5 turns
  (5 half-twists: the double overhand knot, closed the cinquefoil). The
  first (double) throw's axis is Z1 above the pad, the second's Z2. The
  second's helix has the same hand as the first's, but strand A runs it
  backwards along y, so the throw turns the other way, as a square knot's
  second throw does: closed, cinquefoil + mirror trefoil, signature 2 (the
  run's summary checks it; HAND2 = -1 gives the granny, signature 6).
- A strand leaves the first throw heading out along y, turns up in a half
  circle of radius (Z2 - Z1 - 2R) / 2 and enters the second throw from the
  same side; the ends leave the second throw at its top and run out and
  down to END_Z above the pad, TAIL beyond the U-turns, where the scene
  pulls them along y.
Closest approach of two strands: 2R across a throw's axis, P/2 along it
(the other strand lies half a pitch on).

The waypoints are joined by straight pieces, sampled every 0.02 D, smoothed
by a Gaussian of 1.5 D (rounding the joints; a helix turn of 26 D keeps 94
% of its radius), and NODES points are placed exactly ds apart along the
result (chords.py), so the scene reader keeps them as they are. The script
prints the closest approach of segments more than 3 D apart along the cord,
the sharpest bend, and the two points where the cord crosses the pad's top
(the scene's [puncture] points).
"""
import math

import chords

D = 0.004                   # m: the cord's diameter
NODES = 401
R, P = 4.0, 8.0             # throw radius and pitch, D
Z1, Z2 = 7.0, 23.0          # the throws' axes above the skin, D
W, DEPTH = 12.0, 6.0        # half the bite's width, its depth under the skin, D
TAIL = 16.0                 # D beyond the U-turns
END_Z = 3.0                 # D: the ends' height above the skin
TURNS1, TURNS2 = 2.5, 1.5   # double throw, single throw
HAND1, HAND2 = 1.0, 1.0     # helix hands (see the top)


def semicircle(cy, cz, radius, side, downward, n=200):
    """Points of a U-turn in the y-z plane: a half circle about (cy, cz) on
    the side sign(side) of it, from its top to its bottom when downward."""
    pts = []
    for k in range(n + 1):
        a = math.pi * k / n
        a = a if downward else math.pi - a
        pts.append((0.0, cy + side * radius * math.sin(a), cz + radius * math.cos(a)))
    return pts


def strand_points():
    a1, a2 = TURNS1 * P / 2, TURNS2 * P / 2
    ru = 0.5 * (Z2 - Z1 - 2 * R)         # the U-turns' radius
    out = a1 + 0.5 * R                   # where the U-turns start
    zm = 0.5 * (Z1 + Z2)

    # A strand's angle on a throw (in the x-z plane about its axis; -pi/2
    # is the bottom) as a function of y; the other strand is half a turn on.
    def phi1(y):                         # A at the bottom at y = -a1
        return -math.pi / 2 + HAND1 * 2 * math.pi * TURNS1 * (y + a1) / (2 * a1)

    def phi2(y):                         # A at the bottom at y = +a2
        return -math.pi / 2 + HAND2 * 2 * math.pi * TURNS2 * (a2 - y) / (2 * a2)

    def sweep(z, phi, shift, y0, y1, n=800):
        ys = [y0 + (y1 - y0) * k / n for k in range(n + 1)]
        return [(R * math.cos(phi(y) + shift), y, z + R * math.sin(phi(y) + shift)) for y in ys]

    # strand A (the root's): its tail at -y at the second throw's top, through
    # the second throw from -a2 to +a2 (leaving at the bottom), the U-turn at
    # +y down to the first throw's top, through the first throw from +a1 to
    # -a1 (leaving at the bottom), down to the puncture at -W
    pts = [(0.0, -(out + TAIL), END_Z), (0.0, -(out + 0.5 * TAIL), Z2 + R), (0.0, -a2 - 0.5 * R, Z2 + R)]
    pts += sweep(Z2, phi2, 0.0, -a2, a2)
    pts += [(0.0, out, Z2 - R)] + semicircle(out, zm, ru, 1, True)[1:-1] + [(0.0, out, Z1 + R)]
    pts += sweep(Z1, phi1, 0.0, a1, -a1)
    pts += [(0.0, -a1 - 0.5 * R, Z1 - R), (0.0, -W, 0.0)]
    # the bite: half an ellipse under the skin
    pts += [(0.0, -W * math.cos(math.pi * k / 60), -DEPTH * math.sin(math.pi * k / 60))
            for k in range(1, 60)]
    # strand B, the mirror image of A's path through y -> -y, half a turn on
    pts += [(0.0, W, 0.0), (0.0, a1 + 0.5 * R, Z1 - R)]
    pts += sweep(Z1, phi1, math.pi, a1, -a1)
    pts += [(0.0, -out, Z1 + R)] + semicircle(-out, zm, ru, -1, False)[1:-1] + [(0.0, -out, Z2 - R)]
    pts += sweep(Z2, phi2, math.pi, -a2, a2)
    pts += [(0.0, a2 + 0.5 * R, Z2 + R), (0.0, out + 0.5 * TAIL, Z2 + R), (0.0, out + TAIL, END_Z)]
    return pts


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
        m = min(j - lo, hi - j)          # symmetric window: the ends stay put
        s, acc = 0.0, [0.0, 0.0, 0.0]
        for k in range(j - m, j + m + 1):
            wk = w[k - j + half]
            s += wk
            for i in range(3):
                acc[i] += wk * pts[k][i]
        out.append(tuple(c / s for c in acc))
    return out


def seg_dist(p, q, r, s):
    """Distance between segments pq and rs (sampled finely enough here)."""
    best = 1e30
    for i in range(11):
        a = tuple(p[c] + (q[c] - p[c]) * i / 10 for c in range(3))
        for j in range(11):
            b = tuple(r[c] + (s[c] - r[c]) * j / 10 for c in range(3))
            best = min(best, math.dist(a, b))
    return best


def main():
    line = smooth(densify(strand_points()))
    pts, ds = chords.place(line, NODES)
    # closest approach of segments more than 3 D apart along the thread
    skip = int(math.ceil(3.0 / ds)) + 1
    best, where = 1e30, None
    for i in range(len(pts) - 1):
        for j in range(i + skip, len(pts) - 1):
            if math.dist(pts[i], pts[j]) > best + 2 * ds:
                continue
            d = seg_dist(pts[i], pts[i + 1], pts[j], pts[j + 1])
            if d < best:
                best, where = d, (i, j)
    bend = 0.0
    for a, b, c in zip(pts, pts[1:], pts[2:]):
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - b[i] for i in range(3)]
        cosang = sum(u[i] * v[i] for i in range(3)) / (math.hypot(*u) * math.hypot(*v))
        bend = max(bend, math.acos(max(-1.0, min(1.0, cosang))))
    print("closest far segments: %.3f D (segments %d and %d); ds = %.4f D; "
          "sharpest bend %.3f rad per segment" % (best, where[0], where[1], ds, bend))
    crossings = []
    for a, b in zip(pts, pts[1:]):
        if (a[2] > 0) != (b[2] > 0):
            t = a[2] / (a[2] - b[2])
            crossings.append(tuple(D * (a[i] + t * (b[i] - a[i])) for i in range(3)))
    with open("surgeons_knot_shape.csv", "w") as f:
        f.write("x,y,z\n")
        for p in pts:
            f.write("%.12f,%.12f,%.12f\n" % tuple(D * c for c in p))
    print("length = %.9f m ((NODES - 1) ds)" % ((NODES - 1) * ds * D))
    for c in crossings:
        print("puncture point = %.9f %.9f %.9f" % c)


if __name__ == "__main__":
    main()
