#!/usr/bin/env python3
"""Writes the thread's starting shape and the two instruments' paths for
instrument_tie.ini: an instrument tie over one interrupted stitch. Nothing is
tied in the start: the turns are made by the instruments' paths and kept by
contact and friction of the thread on the jaws and on itself.

  python3 instrument_tie.py single     # the first throw (instrument_tie.ini)
  python3 instrument_tie.py            # square knot: single, then single the other way
  python3 instrument_tie.py granny     # granny knot: the second throw the same way
  python3 instrument_tie.py surgeons   # surgeon's knot: double, then single the other way

Each writes instrument_tie[_VARIANT]_holder.csv and ..._forceps.csv (poses
every 20 ms, eased between key poses) and instrument_tie_shape.csv
(instrument_tie_surgeons_shape.csv for the double first throw), and prints the rod's length and the puncture points for the
scene. Only the first throw's wrap, grasp and the start of the back-out run
yet (instrument_tie.ini stops at 5.4 s); the later poses of every variant are
written but untried past that (the turn is not yet stripped off the jaws'
tip).

Lengths in mm below, written in m. The pad's top is z = 0, the wound runs
along x; the thread's root (node 0) is the short tail's end, lying on the
skin on the -y side; the thread enters the pad at y = -W, runs DEPTH under
it and leaves at y = +W; the long end rises from there straight to the
forceps (at the start of their spiral) and STUB beyond them.

A throw (the tail on side S of the wound):
- the needle holder comes over the wound, its jaws slightly open (0.22:
  the narrowest that takes the tail at their tip) pointing to the tail and
  down by TILT, REACH short of where they take it;
- the forceps carry the long end round the holder's axis WRAPS times in the
  throw's sense, each turn PITCH further back: a spiral from the distance
  that keeps the long end's length (straight at the start, wound at the end)
  in to RF by half a turn, so that they pass under the holder clear of the
  skin;
- the holder runs REACH along its axis onto the tail, the forceps LEAD
  further (the long end keeps the turn near the jaws' tip), and its jaws
  close on the tail (the grasp);
- the holder backs out along its axis and up, turning tip-down, while the
  forceps feed the long end, meant to strip the turns off the tip over the
  held tail;
- the hands cross: the holder carries the tail over the wound to -S, the
  forceps the long end to S, both near the skin;
- between throws the holder lays the tail down on the other side, lets it
  go, and turns round.
"""
import math
import sys

import numpy as np

import chords

VARIANT = sys.argv[1] if len(sys.argv) > 1 else "square"
MM = 1e-3
W, DEPTH = 4.0, 3.0          # half the bite's width, its depth under the skin
TILT = math.radians(35.0)    # the holder's jaws pointing down by this
RF = 8.0                     # the forceps' circle about the holder's axis
WRAP_R = 2.4                 # mm: a turn's radius round the jaws (their 1.7 + d/2, and slack)
PITCH = 1.6                  # back along the jaws per turn
XF = -6.0                    # the forceps' circle along the holder's axis (from its tip)
REACH = 14.0                 # the holder's run along its axis to the tail
LEAD = 8.0                   # mm: the forceps run this much further along it
BACK, BACK_UP = 15.0, 12.0   # mm: the holder's back-out from the grasp, along its axis and up
BACK_T = 3.0                 # s: over this
BACK_TILT = math.radians(20.0)  # turning its tip down by this meanwhile
AHEAD = -16.0                # mm: the forceps meanwhile to this along the holder's axis past
                             # where its run alone takes them (LEAD: where they are; less feeds)
FEED_UP = 4.0                # mm: and up
TAIL_GRASP = 21.0            # mm: where the holder takes the tail (-y, on side -1)
TAIL_END = 30.0              # the tail's end: -y (on side -1), lying on the skin
STUB = 4.0                   # mm: the long end beyond the forceps, along their tines
NODES = 160
DT = 0.02                    # s between path rows

# (wraps, sense) of each throw; sense +1: the long end goes over the holder
# from +x first
THROWS = {
    "single": [(1, +1)],
    "square": [(1, +1), (1, -1)],
    "granny": [(1, +1), (1, +1)],
    "surgeons": [(2, +1), (1, -1)],
}[VARIANT]


def holder_frame(side, tilt=TILT):
    """The holder's rotation (columns: local x to the tip, y, z = the jaws'
    opening direction = global x) pointing to side `side` and down by
    `tilt`."""
    c, s = math.cos(tilt), math.sin(tilt)
    x = np.array([0.0, side * c, -s])
    z = np.array([1.0, 0.0, 0.0])
    return np.column_stack([x, np.cross(z, x), z])


def up_of(r):
    """The unit vector across the holder's axis, upward, in its y-z plane."""
    y = r[:, 1]
    return -y if y[2] < 0 else y


def quat(r):
    w = math.sqrt(max(0.0, 1.0 + np.trace(r))) / 2.0
    if w > 1e-6:
        return np.array([w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w),
                         (r[1, 0] - r[0, 1]) / (4 * w)])
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    v = math.sqrt(max(0.0, 1.0 + r[i, i] - r[j, j] - r[k, k])) / 2.0
    q = np.zeros(4)
    q[0] = (r[k, j] - r[j, k]) / (4 * v)
    q[1 + i] = v
    q[1 + j] = (r[j, i] + r[i, j]) / (4 * v)
    q[1 + k] = (r[k, i] + r[i, k]) / (4 * v)
    return q


def slerp(q0, q1, u):
    d = float(np.dot(q0, q1))
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + u * (q1 - q0)
        return q / np.linalg.norm(q)
    a = math.acos(d)
    return (math.sin((1 - u) * a) * q0 + math.sin(u * a) * q1) / math.sin(a)


def rotvec(q):
    q = q if q[0] >= 0 else -q
    n = np.linalg.norm(q[1:])
    if n < 1e-12:
        return np.zeros(3)
    return q[1:] / n * 2.0 * math.atan2(n, q[0])


def tail_grasp(side):
    """Where the holder's tip takes the tail (its end stands there)."""
    return np.array([0.0, side * TAIL_GRASP, 2.0])


def tip_wrap(side):
    """The holder's tip while the forceps wrap: REACH short of the tail."""
    return tail_grasp(side) - REACH * holder_frame(side)[:, 0]


def on_circle(side, phi, xf, radius=RF):
    """A point at angle phi about the holder's axis at the wrap (0: global
    +x, pi/2: above), xf along the axis from its tip."""
    r = holder_frame(side)
    return tip_wrap(side) + xf * r[:, 0] + radius * (math.cos(phi) * r[:, 2] +
                                                     math.sin(phi) * up_of(r))


def radius_reaching(at, target, length, lo, hi):
    """The distance r in [lo, hi] (mm) of a hand or forceps on its circle,
    at(r), whose straight line to target is length long: 60 halvings."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if np.linalg.norm(at(mid) - target) < length:
            lo = mid
        else:
            hi = mid
    return lo


def spiral_radius(wraps, e):
    """The forceps' distance from the holder's axis at the fraction e of the
    wraps: what the turns round the jaws take, given back as they are made
    (the long end's length held)."""
    # at the start the long end runs straight from its puncture to the
    # forceps; wound, it runs to the jaws, round them and on to the forceps
    p2 = np.array([0.0, W, 0.0])
    axis = tip_wrap(-1) + XF * holder_frame(-1)[:, 0]
    need = np.linalg.norm(p2 - axis) + 2.0 * math.pi * WRAP_R * wraps + RF
    lo = radius_reaching(lambda r: on_circle(-1, 0.0, XF, r), p2, need, RF, 200.0)
    # in to RF by half a turn (the forceps' passage under the holder stays
    # clear of the skin); the slack that leaves is taken up after the wraps
    return RF + (lo - RF) * max(0.0, 1.0 - 2.0 * e) ** 2


def thread_line():
    """Waypoints of the starting shape (mm), from the tail's end."""
    # 1.5 mm before its hole the tail is 1.4 mm up: at 1.0 the line
    # resampled to 132 nodes cut 56 um into the skin beside the hole
    pts = [(0.0, -TAIL_END, 0.6), (0.0, -W - 3.0, 1.0), (0.0, -W - 1.5, 1.4), (0.0, -W, 0.0),
           (0.0, -W + 1.5, -DEPTH * 0.8), (0.0, 0.0, -DEPTH), (0.0, W - 1.5, -DEPTH * 0.8),
           (0.0, W, 0.0), (1.0, W + 0.5, 1.5)]
    f = on_circle(-1, 0.0, XF, spiral_radius(THROWS[0][0], 0.0))
    d = (f - np.array(pts[-1])) / np.linalg.norm(f - np.array(pts[-1]))
    pts.append(tuple(f))
    pts.append(tuple(f + STUB * d))
    return pts


def densify(pts, h=0.02):
    out = [pts[0]]
    for a, b in zip(pts, pts[1:]):
        n = max(1, int(math.dist(a, b) / h))
        for k in range(1, n + 1):
            out.append(tuple(a[i] + (b[i] - a[i]) * k / n for i in range(3)))
    return out


def smooth(pts, sigma, h=0.02):
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


class Track:
    """Key poses of one instrument: position, rotation, opening; eased
    between (smoothstep), or along a given path, sampled every DT."""

    def __init__(self, pos, rot, jaw):
        self.t = 0.0
        self.p = np.array(pos, float)
        self.q = quat(rot)
        self.jaw = jaw
        self.rows = [(0.0, self.p, self.q, jaw)]

    def to(self, t1, pos=None, rot=None, jaw=None, path=None):
        p1 = self.p if pos is None else np.array(pos, float)
        if path is not None:
            p1 = path(1.0)
        q1 = self.q if rot is None else quat(rot)
        j1 = self.jaw if jaw is None else jaw
        n = max(1, int(round((t1 - self.t) / DT)))
        for k in range(1, n + 1):
            u = k / n
            e = u * u * (3 - 2 * u)
            p = path(e) if path is not None else self.p + e * (p1 - self.p)
            self.rows.append((self.t + (t1 - self.t) * u, p, slerp(self.q, q1, e),
                              self.jaw + e * (j1 - self.jaw)))
        self.t, self.p, self.q, self.jaw = t1, p1, q1, j1

    def write(self, name):
        prev = None
        with open(name, "w") as f:
            f.write("t,x,y,z,rx,ry,rz,jaw\n")
            for t, p, q, j in self.rows:
                rv = rotvec(q)
                if prev is not None and np.linalg.norm(rv - prev) > 0.5:
                    raise SystemExit("%s: the rotation vector jumps at t = %g" % (name, t))
                prev = rv
                f.write("%.2f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.4f\n" % (
                    t, p[0] * MM, p[1] * MM, p[2] * MM, rv[0], rv[1], rv[2], j))


def forceps_frame(side):
    return holder_frame(side)


def throw(holder, forceps, side, wraps, sense, t):
    """One throw, the tail standing on side `side`; returns the time after."""
    r = holder_frame(side)
    x = r[:, 0]
    # the holder over the wound, the forceps to the circle's start
    holder.to(t + 0.6, pos=tip_wrap(side), rot=r, jaw=0.22)
    forceps.to(t + 0.6, pos=on_circle(side, 0.0, XF, spiral_radius(wraps, 0.0)),
               rot=forceps_frame(side))
    t += 0.7
    holder.to(t)
    forceps.to(t)
    tw = 1.2 * wraps

    def circle(e):
        return on_circle(side, sense * 2 * math.pi * wraps * e, XF - PITCH * wraps * e,
                         spiral_radius(wraps, e))
    forceps.to(t + tw, path=circle)
    holder.to(t + tw)
    t += tw
    # snug the turns onto the jaws: out along +x by the slack the spiral left
    slack = 0.5 * (spiral_radius(wraps, 0.0) - RF) if wraps == 1 else \
        (spiral_radius(wraps, 0.0) - RF) * (1.0 - 0.5 / wraps)
    fw = circle(1.0) + 0.0 * slack * r[:, 2]
    forceps.to(t + 0.4, pos=fw)
    holder.to(t + 0.4)
    t += 0.4
    # the holder runs to the tail, opening; the forceps run LEAD further, so
    # that the long end draws the turn toward the jaws' tip against the
    # strand from the puncture, which drags it back toward the box lock
    holder.to(t + 0.4, pos=tip_wrap(side) + 0.4 * REACH * x, jaw=0.22)
    inward = -r[:, 2]                          # the circle ends on the +x side
    forceps.to(t + 0.4, pos=fw + 0.4 * (REACH + LEAD) * x + 3.0 * inward)
    t += 0.4
    holder.to(t + 0.4, pos=tail_grasp(side) + 0.5 * x)
    forceps.to(t + 0.4, pos=fw + (REACH + LEAD) * x + 3.0 * inward)
    t += 0.4
    holder.to(t + 0.2, jaw=0.0)                # the grasp
    forceps.to(t + 0.2)
    t += 0.3
    holder.to(t)
    forceps.to(t)
    # back out: the holder along its axis and up, turning tip-down, while
    # the forceps feed the long end (the tension stays low: drawing it
    # toward the tip cinches the turn on the jaws), meant to slide the turn
    # off the jaws' tip over the held tail
    g = tail_grasp(side)
    up = np.array([0.0, 0.0, 1.0])
    holder.to(t + BACK_T, pos=g - BACK * x + BACK_UP * up, rot=holder_frame(side, TILT + BACK_TILT))
    forceps.to(t + BACK_T, pos=fw + (REACH + AHEAD) * x + 3.0 * inward + FEED_UP * up)
    t += BACK_T
    # the hands cross: the tail to -side, the long end to side, near the skin
    holder.to(t + 1.2, pos=np.array([0.0, -side * 7.0, 4.0]))
    forceps.to(t + 1.2, pos=np.array([2.0, side * 11.0, 4.0]))
    t += 1.2
    holder.to(t + 0.6, pos=np.array([0.0, -side * 8.0, 2.5]))
    forceps.to(t + 0.6, pos=np.array([2.0, side * 13.0, 2.5]))
    t += 0.8
    holder.to(t)
    forceps.to(t)
    return t


def main():
    way = thread_line()
    # the tail and the bite smoothed by 1.5 mm, the long end's wide turns by 4 mm
    k = way.index((1.0, W + 0.5, 1.5))
    line = smooth(densify(way[:k + 1]), 1.5)[:-1] + smooth(densify(way[k:]), 4.0)
    pts, ds = chords.place(line, NODES)
    crossings = []
    for a, b in zip(pts, pts[1:]):
        if (a[2] > 0) != (b[2] > 0):
            u = a[2] / (a[2] - b[2])
            crossings.append(tuple(MM * (a[i] + u * (b[i] - a[i])) for i in range(3)))
    # the long end's start depends on the first throw's turns
    shape = "instrument_tie_shape.csv" if THROWS[0][0] == 1 else "instrument_tie_surgeons_shape.csv"
    with open(shape, "w") as f:
        f.write("x,y,z\n")
        for p in pts:
            f.write("%.12f,%.12f,%.12f\n" % tuple(MM * c for c in p))
    print("length = %.9f m; ds = %.4f mm" % ((NODES - 1) * ds * MM, ds))
    f = on_circle(-1, 0.0, XF, spiral_radius(THROWS[0][0], 0.0))
    grip = min(range(len(pts)), key=lambda i: math.dist(pts[i], f))
    exit2 = max(i for i in range(len(pts)) if pts[i][2] < 0)
    print("the long end from its puncture to the forceps: %.1f mm" % ((grip - exit2) * ds))
    for c in crossings:
        print("puncture point = %.9f %.9f %.9f" % c)

    side = -1
    r = holder_frame(side)
    holder = Track(tip_wrap(side) - 20.0 * r[:, 0], r, 0.22)
    forceps = Track(on_circle(side, 0.0, XF, spiral_radius(THROWS[0][0], 0.0)),
                    forceps_frame(side), 0.0)
    t = 0.0
    for k, (wraps, sense) in enumerate(THROWS):
        t = throw(holder, forceps, side, wraps, sense, t)
        side = -side
        if k + 1 < len(THROWS):
            # stand the tail up on the new side and let it go; lift away
            holder.to(t + 0.6, pos=tail_grasp(side) + 0.5 * holder_frame(-side)[:, 0])
            forceps.to(t + 0.6)
            t += 0.6
            holder.to(t + 0.2, jaw=0.6)
            forceps.to(t + 0.2)
            t += 0.2
            holder.to(t + 0.5, pos=tail_grasp(side) + np.array([0.0, 0.0, 12.0]) -
                      10.0 * holder_frame(-side)[:, 0])
            forceps.to(t + 0.5)
            t += 0.5
    holder.to(t + 0.3)
    forceps.to(t + 0.3)
    t += 0.3
    name = "instrument_tie" if VARIANT == "square" else "instrument_tie_" + VARIANT
    holder.write(name + "_holder.csv")
    forceps.write(name + "_forceps.csv")
    print("duration %.2f s" % t)


if __name__ == "__main__":
    main()
