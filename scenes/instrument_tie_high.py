#!/usr/bin/env python3
"""Writes the thread's starting shape and the two instruments' paths for
instrument_tie_high.ini: the first throw of an instrument tie with the long
end held high, so that it rises steeply from its puncture and never turns
back on itself there.

  python3 instrument_tie_high.py

writes instrument_tie_high_shape.csv, instrument_tie_high_holder.csv and
instrument_tie_high_forceps.csv (poses every 20 ms, eased between key
poses) and prints the rod's length and the puncture points for the scene.

Lengths in mm below, written in m. The pad's top is z = 0, the wound runs
along x; the thread's root (node 0) is the short tail's end, lying on the
skin on the -y side; the thread enters the pad at y = -W, runs DEPTH under
it and leaves at y = +W.

The geometry (the why: a long end that comes up out of its puncture and
turns back toward the tail's side kinks there, a hairpin the 0.92 mm grid
cannot hold; a turn the tail is drawn through ties a half knot only if the
long end comes into it from the side the tail leaves by; and the stitch's
ring, the long end up from its puncture to the knot, the tail and the bite,
tightens on whatever passes through it):
- the needle holder points at the tail's end and down by TILT; its tip
  takes the tail's end on the skin first (held, the tail is not drawn
  through the punctures while the long end is wound), while its axis passes
  WRAP_H above the wound (at y = WRAP_Y, between the punctures);
- the long end rises steeply from its puncture to the forceps, past the
  holder's shanks on their +x side;
- the forceps carry the long end once round the holder's axis there (over
  it first), a spiral in from where the long end's length keeps them to
  R_END (a loose turn, 7 mm in radius round the shanks' 3.9 mm half width:
  it must pass the box lock), LEAD nearer the tip than the turn, their
  body turned away from the holder all the way round (body_dir): out from
  its axis over the top, along -x under it, then round through the forward
  horizontal to +x once their tip is beside the shanks (x > 5.3 mm, the
  shanks' half width and the forceps' radius), and out again. A body kept
  parallel to the holder, as in the first version, passes between the
  holder and the strand rising from the puncture as the tip goes under
  (that strand reaches the skin below the holder's axis: no path round it
  stays above the pad), so the turn's first half is laid over the forceps'
  jaws and shanks and the ring, once the turn is off the holder, hangs on
  them: drawn apart it tightened on their shaft, the knot 4-6 mm up;
- the forceps stay where the spiral ends, outside the turn;
- the holder draws back along its axis: the turn slides along the shanks,
  over the box lock and off the jaws' tip onto the tail, which it draws
  through the turn (the long end enters the turn from the hand's side, the
  tail leaves it by that side: a half knot); the long end keeps rising from
  its puncture to the turn and neither puncture kinks;
- the hands cross slowly (1.2 s, then 0.6 s down to 3 mm over the skin):
  the holder lays the tail to the long end's side (+y), the forceps the
  long end to the tail's side (-y);
- the cinch: both ends drawn apart low along the skin over 2 s, the
  holder's tip to CINCH_HOLDER, the forceps' to CINCH_FORCEPS (1.5 mm over
  the skin), and held 0.7 s: the throw is laid down on the skin between the
  punctures. A narrow window: the forceps' pull 0.5 mm shorter leaves it
  1.8 mm up, 1 mm longer, or the holder's 0.25 mm either way, kinks the
  bite by the tail's puncture or stalls Newton (the knot's strands pressed
  onto the pad).
With the turn beyond the long end's puncture (y = +8 mm) the long end came
into it from the tip's side, as the tail did: the turn came off the tip
with the strands twisted once round each other, an unknot
(docs/decisions/0107-tie-high.md).
"""
import math

import numpy as np

import chords
# the paths' sampling and key poses, the thread's smoothing: the low tie's
from instrument_tie import DT, Track, densify, quat, radius_reaching, rotvec, smooth

MM = 1e-3
W, DEPTH = 4.0, 3.0          # half the bite's width, its depth under the skin
TILT = math.radians(20.0)    # the holder pointing down by this
WRAP_Y, WRAP_H = -3.0, 15.0  # where the turn is made on the holder's axis (y, z): over the wound
LEAD = 4.0                   # the forceps' circle this far from the turn toward the tip
R_END = 9.0                  # the forceps' distance from the holder's axis after the turn
PHI0 = math.radians(40.0)    # where the forceps start on their circle (0: +x, 90: above)
TIP_Z = 2.0                  # the holder's tip where it takes the tail
STUB = 3.0                   # the long end beyond the forceps
NODES = 0                    # set below from the length: ds about DS
DS = 0.92
HOLD_Y = 17.0                # the holder's place over the long end's side after the cross
SWING = (300.0, 350.0)       # degrees of the forceps' turn over which their body swings to +x
SPIN = 1.2                   # rad: the most their rotation vector turns between rows (the swing)
CINCH_HOLDER = (0.0, 26.0, 1.5)    # the cinch: where the holder's tip draws the tail
CINCH_FORCEPS = (1.0, -60.0, 1.5)  # and the forceps' tip the long end


def holder_frame():
    """The holder's rotation (columns: local x to the tip, y, z = the jaws'
    opening direction = global x), pointing to -y and down by TILT."""
    c, s = math.cos(TILT), math.sin(TILT)
    x = np.array([0.0, -c, -s])
    z = np.array([1.0, 0.0, 0.0])
    return np.column_stack([x, np.cross(z, x), z])


R = holder_frame()
AXIS = R[:, 0]
UP = np.array([0.0, -math.sin(TILT), math.cos(TILT)])  # across the axis, upward
TURN = np.array([0.0, WRAP_Y, WRAP_H])                  # on the axis, where the turn is made
GRASP = TURN + (WRAP_H - TIP_Z) / math.sin(TILT) * AXIS  # the tip where it takes the tail
TAIL_END = -GRASP[1] - 1.0   # the tail's end lies 1 mm short of where the jaws' tip takes it
P_LONG = np.array([0.0, W, 0.0])


def around(phi, radius, lead=LEAD):
    """A point at angle phi about the holder's axis (0: +x, pi/2: above),
    `lead` from the turn toward the tip."""
    return TURN + lead * AXIS + radius * (math.cos(phi) * R[:, 2] + math.sin(phi) * UP)


def start_radius():
    """The forceps' starting distance from the axis: the long end straight
    from its puncture past the shanks to them is as long as it is wound
    (puncture to the turn, a turn round the shanks, out to R_END)."""
    shank = 2 * math.pi * 7.0          # a loose turn round the shanks (their 3.9 mm half width)
    need = np.linalg.norm(P_LONG - TURN) + shank + R_END
    return radius_reaching(lambda r: around(PHI0, r), P_LONG, need, R_END, 200.0)


R0 = start_radius()


def spiral(e):
    """The forceps on their turn at fraction e: in from R0 to R_END by half a turn."""
    r = R_END + (R0 - R_END) * max(0.0, 1.0 - 2.0 * e) ** 2
    return around(PHI0 + 2 * math.pi * e, r)


def body_dir(phi):
    """The forceps' body direction (from their tip back, unit) at angle phi
    (rad, PHI0 .. PHI0 + 2 pi) of their turn round the holder: away from
    the holder's axis over the top, along -x under it, swinging through the
    forward horizontal (-y) to +x over SWING, then out again to PHI0."""
    deg = math.degrees(phi)
    if deg <= 180.0:
        return math.cos(phi) * R[:, 2] + math.sin(phi) * UP
    if deg <= SWING[0]:
        return -R[:, 2]
    if deg <= SWING[1]:
        th = math.pi * (1.0 + (deg - SWING[0]) / (SWING[1] - SWING[0]))
        return np.array([math.cos(th), math.sin(th), 0.0])
    a = PHI0 * (deg - SWING[1]) / (math.degrees(PHI0) + 360.0 - SWING[1])
    return math.cos(a) * R[:, 2] + math.sin(a) * UP


def transported(lx, z_before):
    """The rotation with local x = lx whose z is z_before made normal to it
    (the jaws' opening plane carried along without twist)."""
    z = z_before - np.dot(z_before, lx) * lx
    z /= np.linalg.norm(z)
    return np.column_stack([lx, np.cross(z, lx), z])


class TurningTrack(Track):
    """A Track whose rotation may follow a direction path (the forceps'
    turn); its rotation vector is written continuously through half turns
    (the path file's rotations are interpolated component-wise)."""

    def __init__(self, pos, rot, jaw):
        super().__init__(pos, rot, jaw)
        self.rot = rot

    def turn(self, t1, path, direction):
        """To t1 along path(e), local x = -direction(e) (the body behind
        the tip), e eased from 0 to 1 (smoothstep)."""
        n = max(1, int(round((t1 - self.t) / DT)))
        z = self.rot[:, 2]
        for k in range(1, n + 1):
            u = k / n
            e = u * u * (3 - 2 * u)
            self.rot = transported(-direction(e), z)
            z = self.rot[:, 2]
            self.rows.append((self.t + (t1 - self.t) * u, path(e), quat(self.rot), self.jaw))
        self.t, self.p, self.q = t1, path(1.0), quat(self.rot)

    def write(self, name):
        prev = None
        with open(name, "w") as f:
            f.write("t,x,y,z,rx,ry,rz,jaw\n")
            for t, p, q, j in self.rows:
                rv = rotvec(q)
                n = np.linalg.norm(rv)
                if prev is not None and n > 1e-9:
                    # of the vectors naming this rotation, the nearest the last row's
                    rv = min((rv + 2 * math.pi * k * rv / n for k in range(-2, 3)),
                             key=lambda c: np.linalg.norm(c - prev))
                if prev is not None and np.linalg.norm(rv - prev) > SPIN:
                    raise SystemExit("%s: the rotation vector jumps at t = %g" % (name, t))
                prev = rv
                f.write("%.2f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.4f\n" % (
                    t, p[0] * MM, p[1] * MM, p[2] * MM, rv[0], rv[1], rv[2], j))


def thread_line():
    """Waypoints of the starting shape (mm), from the tail's end."""
    f = around(PHI0, R0)
    pts = [(0.0, -TAIL_END, 0.6), (0.0, -W - 3.0, 1.0), (0.0, -W - 1.5, 1.4), (0.0, -W, 0.0),
           (0.0, -W + 1.5, -DEPTH * 0.8), (0.0, 0.0, -DEPTH), (0.0, W - 1.5, -DEPTH * 0.8),
           (0.0, W, 0.0), (0.6, W + 0.5, 1.5)]
    d = (f - np.array(pts[-1])) / np.linalg.norm(f - np.array(pts[-1]))
    pts.append(tuple(f))
    pts.append(tuple(f + STUB * d))
    return pts


def paths():
    """Both instruments' key poses; returns (holder, forceps, the time the
    draw-back ends)."""
    holder = Track(GRASP - 12.0 * AXIS, R, 0.22)
    forceps = TurningTrack(around(PHI0, R0), transported(-body_dir(PHI0), AXIS), 0.0)
    # the holder runs along its axis onto the tail, jaws open
    holder.to(0.5, pos=GRASP + 0.5 * AXIS)
    forceps.to(0.5)
    # the jaws close on the tail's end first: held, the tail is not drawn
    # through the punctures by the long end while the forceps wind it
    holder.to(0.7, jaw=0.0)
    forceps.to(0.7)
    # the forceps carry the long end once round the holder's shanks, their
    # body turned away from it
    forceps.turn(1.7, spiral, lambda e: body_dir(PHI0 + 2 * math.pi * e))
    holder.to(1.7)
    # both stay: the forceps outside the turn
    forceps.to(2.1)
    holder.to(2.1)
    # the holder draws back along its axis through the turn
    back = np.linalg.norm(GRASP - TURN) + 4.0
    t_back = 3.6
    holder.to(t_back, pos=GRASP - back * AXIS)
    forceps.to(t_back)                        # the forceps stay: the turn's tension stays low
    # the hands cross: the tail to +y, the long end to -y, low over the wound
    holder.to(t_back + 1.2, pos=np.array([0.0, 14.0, 5.0]))
    forceps.to(t_back + 1.2, pos=np.array([1.0, -20.0, 5.0]))
    holder.to(t_back + 1.8, pos=np.array([0.0, HOLD_Y, 3.0]))
    forceps.to(t_back + 1.8, pos=np.array([1.0, -26.0, 3.0]))
    holder.to(t_back + 2.2)
    forceps.to(t_back + 2.2)
    # the cinch: the ends drawn apart low along the skin, the throw laid down
    holder.to(t_back + 4.2, pos=np.array(CINCH_HOLDER))
    forceps.to(t_back + 4.2, pos=np.array(CINCH_FORCEPS))
    holder.to(t_back + 4.9)
    forceps.to(t_back + 4.9)
    return holder, forceps, t_back


def main():
    global NODES
    way = thread_line()
    k = 8                                     # the point above the long end's puncture
    line = smooth(densify(way[:k + 1]), 1.5)[:-1] + smooth(densify(way[k:]), 4.0)
    arc = sum(math.dist(a, b) for a, b in zip(line, line[1:]))
    NODES = int(round(arc / DS)) + 1
    pts, ds = chords.place(line, NODES)
    crossings = []
    for a, b in zip(pts, pts[1:]):
        if (a[2] > 0) != (b[2] > 0):
            u = a[2] / (a[2] - b[2])
            crossings.append(tuple(MM * (a[i] + u * (b[i] - a[i])) for i in range(3)))
    with open("instrument_tie_high_shape.csv", "w") as f:
        f.write("x,y,z\n")
        for p in pts:
            f.write("%.12f,%.12f,%.12f\n" % tuple(MM * c for c in p))
    print("nodes = %d; length = %.9f m; ds = %.4f mm" % (NODES, (NODES - 1) * ds * MM, ds))
    print("tail end y = %.2f mm, grasp %s, turn %s, forceps start %s (r %.1f mm)" % (
        -TAIL_END, np.round(GRASP, 2), TURN, np.round(around(PHI0, R0), 2), R0))
    exit2 = max(i for i in range(len(pts)) if pts[i][2] < 0)
    print("the long end from its puncture: %.1f mm (node %d on)" % ((len(pts) - 1 - exit2) * ds,
                                                                    exit2 + 1))
    for c in crossings:
        print("puncture point = %.9f %.9f %.9f" % c)
    holder, forceps, t_back = paths()
    holder.write("instrument_tie_high_holder.csv")
    forceps.write("instrument_tie_high_forceps.csv")
    print("duration %.2f s; the draw-back ends %.2f s" % (holder.t, t_back))


if __name__ == "__main__":
    main()
