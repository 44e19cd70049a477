#!/usr/bin/env python3
"""Writes overhand_shape.csv, overhand_root.csv and overhand_tip.csv for
overhand.ini: a loose overhand (open trefoil) knot whose two ends are pulled
apart along their tails.

The knot is Shastri's polynomial long trefoil (a knot as a polynomial curve,
R -> R^3): x = t^3 - 3t, y = t^4 - 4t^2, z = 0.2 (t^5 - 10t), for
-1.9 <= t <= 1.9, scaled so that its strands pass 2.5 diameters apart at the
nearest (0.424 units at this z scale), with straight tails of 6 cm along the
ends' tangents. The points are placed NODES of them exactly ds apart along the
curve (chords), so the scene reader keeps them as they are and the paths start
where the ends are.
"""
import math

import chords

D, NODES, TAIL, PULL, T_PULL = 0.004, 241, 0.06, 0.2, 14.0


def knot(t):
    return (t**3 - 3 * t, t**4 - 4 * t**2, 0.2 * (t**5 - 10 * t))


def main():
    scale = 2.5 * D / 0.424
    dense = [tuple(scale * c for c in knot(-1.9 + 3.8 * k / 20000)) for k in range(20001)]
    def unit(a, b):
        d = [b[i] - a[i] for i in range(3)]
        n = math.sqrt(sum(c * c for c in d))
        return [c / n for c in d]
    t0, t1 = unit(dense[1], dense[0]), unit(dense[-2], dense[-1])
    head = [tuple(dense[0][i] + t0[i] * TAIL * k / 200 for i in range(3)) for k in range(200, 0, -1)]
    tail = [tuple(dense[-1][i] + t1[i] * TAIL * k / 200 for i in range(3)) for k in range(1, 201)]
    line = head + dense + tail
    pts, lo = chords.place(line, NODES)
    with open("overhand_shape.csv", "w") as f:
        f.write("x,y,z\n")
        for p in pts:
            f.write("%.12f,%.12f,%.12f\n" % p)
    print("length = %.9f m (NODES - 1) ds, ds = %.9f m" % ((NODES - 1) * lo, lo))
    for name, p, t in (("root", pts[0], t0), ("tip", pts[-1], t1)):
        with open("overhand_%s.csv" % name, "w") as f:
            f.write("t,x,y,z\n")
            for k in range(0, 33):
                tt = 0.5 * k
                s = PULL * min(1.0, max(0.0, (tt - 0.5) / T_PULL))
                f.write("%g,%.12f,%.12f,%.12f\n" % (tt, *(p[i] + t[i] * s for i in range(3))))


if __name__ == "__main__":
    main()
