"""Chords of equal length along a polyline, for the scripts that write
starting shapes (overhand_path.py, surgeons_knot_path.py): the scene reader
keeps a shape whose points lie exactly ds apart as it is."""
import math


def place(line, nodes):
    """nodes points along the polyline line (a list of 3-tuples), each
    exactly ds from the one before (chords), ds the largest that fits:
    bisection on ds. Returns (points, ds)."""
    def run(ds):
        out, j = [line[0]], 0
        while len(out) < nodes:
            p = out[-1]
            while j < len(line) - 1 and math.dist(p, line[j + 1]) < ds:
                j += 1
            if j == len(line) - 1:
                return out, False
            a, b = line[j], line[j + 1]
            lo, hi = 0.0, 1.0
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                q = tuple(a[i] + mid * (b[i] - a[i]) for i in range(3))
                if math.dist(p, q) < ds:
                    lo = mid
                else:
                    hi = mid
            out.append(tuple(a[i] + 0.5 * (lo + hi) * (b[i] - a[i]) for i in range(3)))
        return out, True
    arc = sum(math.dist(a, b) for a, b in zip(line, line[1:]))
    lo, hi = arc / (nodes - 1) * 0.99, arc / (nodes - 1)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if run(mid)[1]:
            lo = mid
        else:
            hi = mid
    return run(lo)[0], lo
