#!/usr/bin/env python3
"""Writes the thread's starting shape, the needle holder's path and the
hand's path for instrument_tie_hand.ini: the first throw of an instrument
tie with the long end held by the surgeon's hand, cinched onto the skin.

  python3 instrument_tie_hand.py

writes instrument_tie_hand_shape.csv, instrument_tie_hand_holder.csv (poses
every 20 ms, eased between key poses) and instrument_tie_hand_hand.csv (the
thread's tip, t,x,y,z) and prints the rod's length and the puncture points
for the scene.

The stitch, the holder's grasp of the tail, the turn's place and its
spiral are instrument_tie_high.py's (imported): the holder points at the
tail's end, 20 degrees down, and takes it first; the turn is made round its
shanks 15 mm over the wound. The long end's end is held by the hand, which
is the thread's tip driven along a path (ends.tip = pinned): a point, so
nothing but the holder is ever inside the stitch's ring, and the throw can
be drawn down (with forceps, their shaft lay inside the ring and the knot
stayed 5 mm up on it: docs/decisions/0107-tie-high.md).
- the hand carries the long end's end once round the holder's shanks
  (instrument_tie_high's forceps spiral), then in toward the shanks;
- the holder draws back along its axis: the turn slides off the jaws' tip
  onto the tail, drawn through it: the half knot;
- the hands cross: the holder lays the tail to the long end's side (+y),
  the hand the long end to the tail's side (-y), low over the skin;
- the cinch: both draw apart along the skin, low, to where the thread
  between them is taut; the throw is laid down onto the wound.
"""
import math

import numpy as np

import chords
import instrument_tie_high as high
from instrument_tie import Track, densify, smooth

MM = 1e-3
DS = 0.92
# the cross and the cinch (mm): the holder's tip and the hand
CROSS_T, DOWN_T = 1.2, 0.6       # s
HOLD_CROSS = np.array([0.0, 14.0, 5.0])
HAND_CROSS = np.array([1.0, -20.0, 5.0])
HOLD_LOW = np.array([0.0, high.HOLD_Y, 3.0])
HAND_LOW = np.array([1.0, -26.0, 3.0])
CINCH_T = 3.0                    # s: the draw apart along the skin (2 s: the long end kinked at its puncture)
HOLD_CINCH = np.array([0.0, 23.0, 1.5])
HAND_CINCH = np.array([0.0, -63.0, 1.2])
HOLD_END = 1.0                   # s: held taut to the end


def thread_line():
    """Waypoints of the starting shape (mm), from the tail's end to the long
    end's end at the hand (instrument_tie_high's, without the stub beyond
    the forceps)."""
    return high.thread_line()[:-1]


def paths():
    """The holder's key poses and the hand's (a Track whose rotation is
    not used); returns (holder, hand, the time the draw-back ends)."""
    holder = Track(high.GRASP - 12.0 * high.AXIS, high.R, 0.22)
    hand = Track(high.around(high.PHI0, high.R0), high.R, 0.0)
    holder.to(0.5, pos=high.GRASP + 0.5 * high.AXIS)
    hand.to(0.5)
    holder.to(0.7, jaw=0.0)
    hand.to(0.7)
    # the hand carries the long end once round the holder's shanks
    hand.to(1.7, path=high.spiral)
    holder.to(1.7)
    # and in toward the turn (the long end slack)
    fed = high.TURN + high.LEAD * high.AXIS + 6.0 * (0.5 * high.R[:, 2] + high.UP)
    hand.to(2.1, pos=fed)
    holder.to(2.1)
    # the holder draws back along its axis through the turn
    back = np.linalg.norm(high.GRASP - high.TURN) + 4.0
    t_back = 3.6
    holder.to(t_back, pos=high.GRASP - back * high.AXIS)
    hand.to(t_back)
    # the hands cross: the tail to +y, the long end to -y, low over the wound
    t = t_back + CROSS_T
    holder.to(t, pos=HOLD_CROSS)
    hand.to(t, pos=HAND_CROSS)
    t += DOWN_T
    holder.to(t, pos=HOLD_LOW)
    hand.to(t, pos=HAND_LOW)
    # the cinch: apart along the skin
    t += CINCH_T
    holder.to(t, pos=HOLD_CINCH)
    hand.to(t, pos=HAND_CINCH)
    t += HOLD_END
    holder.to(t)
    hand.to(t)
    return holder, hand, t_back


def write_hand(hand, start, name):
    """The hand's path: the thread's tip (m), its first row where the
    shape's tip starts."""
    with open(name, "w") as f:
        f.write("t,x,y,z\n")
        for k, (t, p, _q, _j) in enumerate(hand.rows):
            q = start if k == 0 else p
            f.write("%.2f,%.9f,%.9f,%.9f\n" % (t, q[0] * MM, q[1] * MM, q[2] * MM))


def write_shape(name, way):
    """Writes NAME (the thread along WAY, the points of a stitch and its
    long end, mm, as nodes DS apart), prints what the scene's .ini takes
    from it and returns the nodes (mm)."""
    k = 8                                     # the point above the long end's puncture
    line = smooth(densify(way[:k + 1]), 1.5)[:-1] + smooth(densify(way[k:]), 4.0)
    arc = sum(math.dist(a, b) for a, b in zip(line, line[1:]))
    nodes = int(round(arc / DS)) + 1
    pts, ds = chords.place(line, nodes)
    crossings = []
    for a, b in zip(pts, pts[1:]):
        if (a[2] > 0) != (b[2] > 0):
            u = a[2] / (a[2] - b[2])
            crossings.append(tuple(MM * (a[i] + u * (b[i] - a[i])) for i in range(3)))
    with open(name, "w") as f:
        f.write("x,y,z\n")
        for p in pts:
            f.write("%.12f,%.12f,%.12f\n" % tuple(MM * c for c in p))
    print("nodes = %d; length = %.9f m; ds = %.4f mm" % (nodes, (nodes - 1) * ds * MM, ds))
    exit2 = max(i for i in range(len(pts)) if pts[i][2] < 0)
    print("the long end from its puncture: %.1f mm (node %d on)" % ((len(pts) - 1 - exit2) * ds,
                                                                    exit2 + 1))
    for c in crossings:
        print("puncture point = %.9f %.9f %.9f" % c)
    return pts


def write_scene(prefix, way, paths):
    """Writes PREFIX_shape.csv (write_shape), PREFIX_holder.csv and
    PREFIX_hand.csv (PATHS() gives the holder's and the hand's tracks and
    the draw-back's end) and prints what the scene's .ini takes from them."""
    pts = write_shape(prefix + "_shape.csv", way)
    holder, hand, t_back = paths()
    holder.write(prefix + "_holder.csv")
    write_hand(hand, np.array(pts[-1]), prefix + "_hand.csv")
    print("duration %.2f s; the draw-back ends %.2f s; the tip starts %s mm (path %s)" % (
        holder.t, t_back, np.round(pts[-1], 3), np.round(hand.rows[0][1], 3)))


def main():
    write_scene("instrument_tie_hand", thread_line(), paths)


if __name__ == "__main__":
    main()
