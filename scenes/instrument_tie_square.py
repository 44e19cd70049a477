#!/usr/bin/env python3
"""Writes the thread's starting shape and, for each knot, the needle
holder's path and the hand's for instrument_tie_square.ini: an instrument
tie's two throws, the long end held by the surgeon's hand; the second
throw's turn wound one way (a square knot) or the other (a granny).

  python3 instrument_tie_square.py
  python3 instrument_tie_square.py --aim ../build/release/rodsim

writes instrument_tie_square_shape.csv, the square's
instrument_tie_square_holder.csv (poses every 20 ms, eased between key
poses) and instrument_tie_square_hand.csv (the thread's tip, t,x,y,z), the
granny's instrument_tie_square_granny_holder.csv and
instrument_tie_square_granny.csv, and prints the rod's length and the
puncture points for the scene. With --aim it first runs the scene to
AIM_T (the hand's second turn wound, the holder about to run on) and puts
the square's take (TAKE2) where the tail's end lies then (aim()).

The first throw is instrument_tie_hand.py's (imported) with the long end
EXTRA longer: the hand starts farther out on the same spiral and draws the
cinch farther. The second throw (paths(); docs/decisions/0129-tie-square.md):
the holder lets go of the tail, rises and turns half round and YAW2 about
the vertical (toward where the let-go tail springs to), comes down
pointing at the tail's end; the hand winds the long end round its shanks;
the holder runs on to the tail's end, takes it and draws back through the
turn; the hands cross back and draw the ends apart along the skin. The
holder's frame is the first throw's turned, so the hand's turn in the
first throw's sense (+1) makes a copy of the first half knot, turned: the
granny; the turn's mirror (-1) the square knot, its long end first lifted
(SLACKEN2[-1]) and carried over the far side of the holder's axis (FAR2_M)
so that the turn starts under the shanks, the mirror of the granny's
start. That lift draws the first knot round and the square's tail in
(its end 11 mm from where the granny's lies), so the square's holder runs
on to where its tail's end is measured (TAKE2), not along its axis.
KEPT (paths_kept(), a variant that was tried): the holder keeps the tail
and lifts it on an arc over the knot; the hand winds the long end once
round its shanks KEEP_BEHIND behind the jaws' tip, then back along the
shanks and up; the holder draws back along its axis through the turn and
returns along the arc while the hand draws the long end out low.
"""
import math
import sys

import numpy as np

# instrument_tie.py, imported below, reads its variant from the arguments
AIM_WITH = sys.argv[2] if len(sys.argv) == 3 and sys.argv[1] == "--aim" else None
del sys.argv[1:]

import instrument_tie_high as high
import instrument_tie_hand as hand_tie
from instrument_tie import Track, radius_reaching

MM = 1e-3
DS = 0.92
EXTRA = 20.0                      # mm: the long end longer than instrument_tie_hand's
HAND_CINCH1 = np.array([0.0, -62.2 - EXTRA, 1.2])  # the first cinch (-63 - EXTRA: kinked at 8.29 s)
KEPT = False                      # the second throw with the tail kept (False: let go, turned round)
# the second throw (mm, s)
OPEN_T = 1.0                      # s: the holder lets go of the tail over this
TILT2 = math.radians(32.0)        # the holder pointing to +y and down by this
YAW2 = math.radians(55.0)         # the whole second throw turned about the vertical toward the tail
NEAR2 = 10.6                      # mm: the turn this much nearer the knot (before the yaw)
TURN2_0 = np.array([0.0, 5.0, 15.0])  # on its axis, where the turn is made (before NEAR2, YAW2)
TAIL2_Z = 1.2                     # mm: the height at which its tip takes the tail's end
HIGH2_0 = np.array([0.0, 20.0, 45.0])  # where the holder rises to (before YAW2)
R_END2 = 9.0                      # the hand's distance from the axis after the turn
PHI2 = math.radians(40.0)         # where the hand starts on its circle (sense +1)
PHI2_M = math.radians(170.0)      # and with sense -1 (140: the long end then over the holder)
FAR2_M = 0.8                      # with sense -1 the hand first over its start, at this x r0
SLACKEN2 = {-1: np.array([0.0, -15.0, 35.0]), +1: None}  # mm: the hand here as the holder rises (None: stays)
LEAD2 = 4.0                       # the hand's circle toward the tip from the turn
SLACK2 = 3.0                      # mm of the long end left slack at the spiral's start
SLACK2_M = 3.0                    # and with sense -1
KNOT1 = np.array([0.0, 0.0, 1.5])   # the first knot, where the long end leaves it
HOLD2_CROSS = np.array([0.0, -18.0, 10.0])  # (-14, 5: the square's path stalls by the tail's puncture)
HAND2_CROSS = np.array([1.0, 24.0, 10.0])
HOLD2_LOW = np.array([0.0, -17.0, 3.0])
HAND2_LOW = np.array([1.0, 26.0, 3.0])
HOLD2_CINCH = np.array([0.0, -20.0, 1.5])
HAND2_CINCH = np.array([0.0, 60.0, 1.2])
# the square's cinch lower (at 1.5 and 1.2 mm: 2.54 mm up, strands 0.970 d;
# the granny's at 0.9 stalls at 21.18 s)
HOLD2_CINCH_M = np.array([0.0, -20.0, 0.9])
HAND2_CINCH_M = np.array([0.0, 60.0, 0.9])
TURNS2, TURNS2_M = 1.0, 1.0       # the hand's turns round the holder (sense +1, -1)
# mm: the tail's end where the holder takes it, for each sense (None: on
# along its axis to GRASP2); measured by aim() (python3 instrument_tie_square.py --aim RODSIM)
TAKE2 = {-1: (-8.9, -2.0, 1.2), +1: None}
TAKE2_YAW = 0.0                   # rad: the holder turned by this about the vertical as it takes it
TAKE2_ON = 0.5                    # mm: its tip this far past the end along its axis
BACK2_T, CROSS2_T, LOW2_T, CINCH2_T = 1.5, 1.2, 0.6, 5.0  # s: the draw back, the cross, down, the cinch (3: stalls)
# the square's cinch after the hands are down: stages (s, the holder's tip,
# the hand (mm; None: stays), the holder's axis: None kept, a number its
# pitch below the horizontal (rad, heading kept), (heading, pitch) (rad,
# heading from +x), "R2" the second throw's); the variants tried with a
# press of the holder on the knot, record 0129
CINCH2_M = [(CINCH2_T, HOLD2_CINCH_M, HAND2_CINCH_M, None), (1.0, None, None, None)]


def start_radius():
    """instrument_tie_high's start radius for a long end EXTRA longer."""
    need = np.linalg.norm(high.P_LONG - high.TURN) + 2 * math.pi * 7.0 + high.R_END + EXTRA
    return radius_reaching(lambda r: high.around(high.PHI0, r), high.P_LONG, need, high.R_END,
                           300.0)


R0 = start_radius()


def spiral(e):
    r = high.R_END + (R0 - high.R_END) * max(0.0, 1.0 - 2.0 * e) ** 2
    return high.around(high.PHI0 + 2 * math.pi * e, r)


def thread_line():
    f = high.around(high.PHI0, R0)
    pts = high.thread_line()[:-2]
    pts.append(tuple(f))
    return pts


def yaw(v):
    """v turned YAW2 about the vertical (+: from +y toward -x)."""
    c, s = math.cos(YAW2), math.sin(YAW2)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.asarray(v, dtype=float)


def yaw_by(a):
    """The rotation by a about the vertical."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def frame2():
    """The holder's rotation for the second throw: the first's turned half
    round about the vertical, tilted to TILT2, turned YAW2."""
    c, s = math.cos(TILT2), math.sin(TILT2)
    x = np.array([0.0, c, -s])
    z = np.array([-1.0, 0.0, 0.0])
    return np.column_stack([yaw(x), yaw(np.cross(z, x)), yaw(z)])


def derive():
    """The second throw's frame and points from the keys above."""
    global R2, AXIS2, UP2, TURN2, GRASP2, HIGH2
    R2 = frame2()
    AXIS2 = R2[:, 0]
    UP2 = yaw(np.array([0.0, math.sin(TILT2), math.cos(TILT2)]))
    TURN2 = yaw(TURN2_0 - np.array([0.0, NEAR2, 0.0]))
    HIGH2 = yaw(HIGH2_0)
    # the grasp on the axis through TURN2: the tip where the axis meets TAIL2_Z
    GRASP2 = TURN2 + (TURN2[2] - TAIL2_Z) / math.sin(TILT2) * AXIS2


derive()


def around2(phi, radius, lead=LEAD2):
    """A point at angle phi about the second throw's axis (0: -x, the jaws'
    opening direction; pi/2: above)."""
    return TURN2 + lead * AXIS2 + radius * (math.cos(phi) * R2[:, 2] + math.sin(phi) * UP2)


def start2(avail, phi0):
    """The hand's distance from the axis at the second spiral's start: the
    long end straight from the first knot to it, avail long."""
    return radius_reaching(lambda r: around2(phi0, r), KNOT1, avail, R_END2, 300.0)


def first_throw():
    """instrument_tie_hand's first throw with the longer long end: the
    holder's track (written continuously through half turns) and the
    hand's, both at the end of the cinch's hold."""
    holder, hand, t_back = hand_tie.paths()
    # the first throw with the longer long end: the hand's spiral from R0
    # and a longer cinch (rebuild the hand's rows)
    hand = Track(high.around(high.PHI0, R0), high.R, 0.0)
    hand.to(0.5)
    hand.to(0.7)
    hand.to(1.7, path=spiral)
    fed = high.TURN + high.LEAD * high.AXIS + 6.0 * (0.5 * high.R[:, 2] + high.UP)
    hand.to(2.1, pos=fed)
    hand.to(t_back)
    t = t_back + hand_tie.CROSS_T
    hand.to(t, pos=hand_tie.HAND_CROSS)
    t += hand_tie.DOWN_T
    hand.to(t, pos=hand_tie.HAND_LOW)
    t += hand_tie.CINCH_T
    hand.to(t, pos=HAND_CINCH1)
    t += hand_tie.HOLD_END
    hand.to(t)
    assert abs(t - holder.t) < 1e-9
    return turning(holder), hand


def turning(holder):
    """The holder's rows again as a track whose rotation vector is written
    continuously through the second throw's half turn."""
    h2 = high.TurningTrack(holder.p, high.R, holder.jaw)
    h2.rows = holder.rows
    h2.t, h2.p, h2.q, h2.jaw = holder.t, holder.p, holder.q, holder.jaw
    return h2


def paths(sense, first=None, avail=None):
    """The second throw after FIRST() (the holder's and the hand's tracks
    at the first cinch's end; default first_throw), AVAIL mm of the long
    end beyond the first knot (default hand_tie_long_beyond_knot())."""
    holder, hand = (first or first_throw)()
    t = holder.t
    # the second throw: the holder opens, backs off along its axis and up
    holder.to(t + OPEN_T, jaw=0.22)
    hand.to(t + OPEN_T)
    t += OPEN_T
    holder.to(t + 0.6, pos=holder.p - 10.0 * high.AXIS + np.array([0.0, 0.0, 6.0]))
    hand.to(t + 0.6)
    t += 0.6
    holder.to(t + 0.8, pos=HIGH2)
    hand.to(t + 0.8, pos=SLACKEN2.get(sense))
    t += 0.8
    # turns round high over the wound and comes down, its tip short of the tail
    holder.to(t + 1.0, pos=GRASP2 - 12.0 * AXIS2 + np.array([0.0, 0.0, 20.0]), rot=R2)
    if avail is None:
        avail = hand_tie_long_beyond_knot()
    phi0 = PHI2 if sense > 0 else PHI2_M
    r0 = start2(avail - (SLACK2 if sense > 0 else SLACK2_M), phi0)
    # the hand over its start (the long end then under the holder's shanks,
    # on the far side of their axis: the mirror's start) or half way to it
    via = around2(phi0, FAR2_M * r0) if (sense < 0 and FAR2_M) else 0.5 * (hand.p + around2(phi0, r0))
    hand.to(t + 1.0, pos=via + np.array([0.0, 0.0, 15.0]))
    t += 1.0
    holder.to(t + 0.6, pos=GRASP2 - 12.0 * AXIS2)
    hand.to(t + 0.6, pos=around2(phi0, r0))
    t += 0.6

    turns = TURNS2 if sense > 0 else TURNS2_M

    def spiral2(e):
        r = R_END2 + (r0 - R_END2) * max(0.0, 1.0 - 2.0 * e) ** 2
        return around2(phi0 + sense * 2 * math.pi * turns * e, r)
    hand.to(t + 1.2 * turns, path=spiral2)
    # the holder's path is the same for both knots: it waits for the longer turn
    wait = 1.2 * max(TURNS2, TURNS2_M)
    if wait > 1.2 * turns + 1e-9:
        hand.to(t + wait)
    holder.to(t + wait)
    t += wait
    # fed on a little past where the turn ends, 6.7 mm from the axis
    phi_fed = phi0 + sense * (2 * math.pi * turns + math.radians(23.0))
    fed2 = TURN2 + LEAD2 * AXIS2 + 6.7 * (math.cos(phi_fed) * R2[:, 2] + math.sin(phi_fed) * UP2)
    hand.to(t + 0.4, pos=fed2)
    holder.to(t + 0.4)
    t += 0.4
    # the holder runs on to the tail's end and takes it: at TAKE2, where the
    # tail's end was measured (aim()), its axis turned TAKE2_YAW about the
    # vertical; or on along its axis
    take = TAKE2.get(sense)
    if take is None:
        holder.to(t + 0.5, pos=GRASP2 + 0.5 * AXIS2)
    else:
        rt = yaw_by(TAKE2_YAW) @ R2
        holder.to(t + 0.5, pos=np.asarray(take, dtype=float) + TAKE2_ON * rt[:, 0], rot=rt)
    hand.to(t + 0.5)
    t += 0.5
    holder.to(t + 0.2, jaw=0.0)
    hand.to(t + 0.2)
    t += 0.2
    # draws back through the turn
    back = np.linalg.norm(GRASP2 - TURN2) + 4.0
    if take is None:
        holder.to(t + BACK2_T, pos=GRASP2 - back * AXIS2)
    else:
        holder.to(t + BACK2_T, pos=holder.p - (back + TAKE2_ON) * (yaw_by(TAKE2_YAW) @ R2)[:, 0])
    hand.to(t + BACK2_T)
    t += BACK2_T
    # the hands cross back, then the cinch
    holder.to(t + CROSS2_T, pos=HOLD2_CROSS)
    hand.to(t + CROSS2_T, pos=HAND2_CROSS)
    t += CROSS2_T
    holder.to(t + LOW2_T, pos=HOLD2_LOW)
    hand.to(t + LOW2_T, pos=HAND2_LOW)
    t += LOW2_T
    if sense > 0:
        holder.to(t + CINCH2_T, pos=HOLD2_CINCH)
        hand.to(t + CINCH2_T, pos=HAND2_CINCH)
        t += CINCH2_T
        holder.to(t + 1.0)
        hand.to(t + 1.0)
        t += 1.0
        return holder, hand
    # the square's cinch: its stages in turn
    for dur, hold, hnd, turn in CINCH2_M:
        if turn is None:
            rot = None
        elif isinstance(turn, str):
            rot = R2
        elif isinstance(turn, tuple):
            rot = headed(holder_rot(holder), turn[0], turn[1])
        else:
            rot = pitched(holder_rot(holder), turn)
        holder.to(t + dur, pos=hold, rot=rot)
        hand.to(t + dur, pos=hnd)
        t += dur
    return holder, hand


def holder_rot(track):
    """The track's present rotation as a matrix."""
    w, x, y, z = track.q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def headed(r, heading, pitch):
    """The holder's rotation with its axis (local x) at `heading` about the
    vertical (rad, from +x) and `pitch` below the horizontal (rad), local z
    horizontal and local y down when r's is (up when r's is up): no roll
    through half a turn."""
    ax = np.array([math.cos(heading) * math.cos(pitch), math.sin(heading) * math.cos(pitch),
                   -math.sin(pitch)])
    z = np.array([-math.sin(heading), math.cos(heading), 0.0])  # local y = z x x then down
    if r[2, 1] > 0:
        z = -z
    return np.column_stack([ax, np.cross(z, ax), z])


def pitched(r, pitch):
    """headed() with r's heading kept."""
    return headed(r, math.atan2(r[1, 0], r[0, 0]), pitch)


# the second throw with the tail kept: the holder lifts it on an arc over
# the knot, the hand winds the long end round its shanks BEHIND the grasp,
# the jaws open, run on, close on the tail again farther back in them and
# draw back through the turn; back along the arc, the hand out low
KEEP_C = np.array([0.0, 3.0, 1.5])   # the arc's centre: the tail's exit from the first knot
KEEP_R, KEEP_DEG = 20.0, 125.0       # its radius (mm) and sweep (degrees)
KEEP_TILT = 20.0                     # degrees: the holder's tip down by this over the knot (the first throw's)
KEEP_BEHIND = 12.0                   # mm: the turn's place behind the jaws' tip
KEEP_REND = 8.0                      # mm: the hand's distance from the axis after the turn
KEEP_OPEN = False                    # the jaws let go of the tail after the turn, and take it again
KEEP_IN = 1.0                        # the hand's spiral reaches KEEP_REND after 1/KEEP_IN turn
KEEP_TAKE, KEEP_UP = 15.0, 25.0      # mm: then the hand back along the shanks and up (0: stays)
KEEP_ON = 0.0                        # mm: the open jaws run on along the axis before closing
KEEP_BACK = 18.0                     # mm: then draw back along it
KEEP_SLACK = 3.0                     # mm: the long end less than straight at the turn's start
HAND_OUT = np.array([0.0, -50.0, 1.5])
HAND_OUT2 = np.array([0.0, -62.0, 1.2])


def arc(e, deg=KEEP_DEG):
    a = math.radians(deg) * e
    return KEEP_C + KEEP_R * np.array([0.0, math.cos(a), math.sin(a)])


def paths_kept(sense):
    holder, hand = first_throw()
    t = holder.t
    top = arc(1.0)
    tau = math.radians(KEEP_TILT)
    rk = np.column_stack([np.array([0.0, -math.cos(tau), -math.sin(tau)]),
                          np.array([0.0, math.sin(tau), -math.cos(tau)]), high.R[:, 2]])
    axis = rk[:, 0]
    holder.to(t + 1.2, path=arc, rot=rk)
    hand.to(t + 1.2)
    t += 1.2
    centre = top - KEEP_BEHIND * axis
    up = np.array([0.0, -math.sin(tau), math.cos(tau)])

    def around_k(phi, r):
        return centre + r * (math.cos(phi) * rk[:, 2] + math.sin(phi) * up)
    phi0 = math.radians(40.0) if sense > 0 else math.radians(140.0)
    avail = hand_tie_long_beyond_knot() - KEEP_SLACK
    r0 = radius_reaching(lambda r: around_k(phi0, r), KNOT1, avail, KEEP_REND, 300.0)
    hand.to(t + 1.0, pos=around_k(phi0, r0))
    holder.to(t + 1.0)
    t += 1.0

    def sp(e):
        r = KEEP_REND + (r0 - KEEP_REND) * max(0.0, 1.0 - KEEP_IN * e) ** 2
        return around_k(phi0 + sense * 2 * math.pi * e, r)
    hand.to(t + 1.2, path=sp)
    holder.to(t + 1.2)
    t += 1.2
    # the hand takes up the slack: back along the shanks and up, the turn
    # drawn snug behind the grasp
    if KEEP_TAKE > 0:
        hand.to(t + 0.6, pos=centre - KEEP_TAKE * axis + KEEP_UP * up)
        holder.to(t + 0.6)
        t += 0.6
    # the jaws open, run on, close again on the tail
    holder.to(t + 0.3, jaw=0.22 if KEEP_OPEN else 0.0)
    hand.to(t + 0.3)
    t += 0.3
    holder.to(t + 0.4, pos=top + KEEP_ON * axis)
    hand.to(t + 0.4)
    t += 0.4
    holder.to(t + 0.2, jaw=0.0)
    hand.to(t + 0.2)
    t += 0.2
    holder.to(t + 1.2, pos=top + (KEEP_ON - KEEP_BACK) * axis)
    hand.to(t + 1.2)
    t += 1.2
    back = holder.p.copy()
    holder.to(t + 2.4, path=lambda e: arc(1.0 - e) + (1.0 - e) * (back - top), rot=high.R)
    hand.to(t + 2.4, pos=HAND_OUT)
    t += 2.4
    holder.to(t + 1.5)
    hand.to(t + 1.5, pos=HAND_OUT2)
    t += 1.5
    holder.to(t + 1.0)
    hand.to(t + 1.0)
    t += 1.0
    return holder, hand


def hand_tie_long_beyond_knot():
    """mm of the long end beyond the first knot (59 in instrument_tie_hand)."""
    return 59.0 + EXTRA


def main():
    pts = hand_tie.write_shape("instrument_tie_square_shape.csv", thread_line())
    # the second turn the mirror of the first (sense -1 in the holder's
    # turned frame): the square knot; the first's copy turned half round
    # (+1): the granny
    for sense in (-1, +1):
        holder, hand = (paths_kept if KEPT else paths)(sense)
        hand_tie.write_hand(hand, np.array(pts[-1]), FILES[sense][0])
        holder.write(FILES[sense][1])
    print("duration %.2f s" % holder.t)


# each knot's hand and holder paths: the scene's (the square) and the
# granny's (the scene's [variant granny]: --set variant=granny)
FILES = {-1: ("instrument_tie_square_hand.csv", "instrument_tie_square_holder.csv"),
         +1: ("instrument_tie_square_granny.csv", "instrument_tie_square_granny_holder.csv")}


AIM_T = 15.0                      # s: the hand's turn done, the holder about to run on


def tail_end(rodsim, sense, until, scene="instrument_tie_square.ini", files=None):
    """Runs SCENE (written in this folder) to `until` (s) with the knot's
    paths (FILES[sense], default this scene's) and returns the tail's end
    (node 0, mm) and the direction of its last 3 segments in the last
    frame."""
    files = files or FILES
    import os
    import subprocess
    import tempfile
    fd, csv = tempfile.mkstemp(suffix=".csv")
    os.close(fd)
    try:
        subprocess.run([rodsim, "run", scene, "--no-video", "--quiet",
                        "--csv", csv, "--set", "ends.tip_motion=" + files[sense][0],
                        "--set", "instrument.path=" + files[sense][1],
                        "--set", "solver.duration=%g" % until], check=True)
        rows = {}
        with open(csv) as f:
            next(f)
            for line in f:
                v = line.split(",")
                rows.setdefault(float(v[0]), {})[int(v[1])] = np.array([float(c) for c in v[3:6]])
    finally:
        os.remove(csv)
    last = rows[max(rows)]
    d = last[0] - last[3]
    return last[0] / MM, d / np.linalg.norm(d)


def aim(rodsim, iterations=2, senses=(-1,)):
    """The square's take aimed where its tail lies as the jaws run on (what
    a surgeon does by eye): the scene run to AIM_T (the paths before it do
    not depend on the take), the tail's end read and TAKE2 put there, its
    tip at TAIL2_Z; again, to check that it stays. (The granny's tail lies
    3 mm from its axis, which takes it 2.5 mm from its end; aimed at its
    end, the granny's path stalls at 16.13 s.)"""
    for k in range(iterations):
        main()
        for sense in senses:
            end, d = tail_end(rodsim, sense, AIM_T)
            R = frame2()
            off = math.atan2(d[1], d[0]) - math.atan2(R[1, 0], R[0, 0])
            off = (off + math.pi) % (2 * math.pi) - math.pi
            print("aim %d, sense %+d: the tail's end at (%.2f, %.2f, %.2f) mm at %g s, "
                  "%.0f degrees about the vertical from the holder's axis"
                  % (k + 1, sense, end[0], end[1], end[2], AIM_T, math.degrees(off)))
            TAKE2[sense] = (round(end[0], 1), round(end[1], 1), TAIL2_Z)
    print("TAKE2 =", TAKE2)
    main()


if __name__ == "__main__":
    if AIM_WITH:
        aim(AIM_WITH)
    else:
        main()
