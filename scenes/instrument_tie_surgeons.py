#!/usr/bin/env python3
"""Writes the thread's starting shape, the needle holder's path and the
hand's path for instrument_tie_surgeons.ini: a surgeon's knot thrown with
instruments, the long end held by the surgeon's hand.

  python3 instrument_tie_surgeons.py

writes instrument_tie_surgeons_shape.csv, instrument_tie_surgeons_holder.csv
(poses every 20 ms, eased between key poses) and
instrument_tie_surgeons_hand.csv (the thread's tip, t,x,y,z) and prints the
rod's length and the puncture points for the scene.

The stitch, the grasp, the turn's place and the cross are
instrument_tie_high.py's and instrument_tie_hand.py's (imported); what
differs:
- the double throw: the hand carries the long end TWICE round the holder's
  shanks, its circle moving PITCH toward the jaws' tip per turn; the long
  end is longer by what a second turn takes (a straight line at the start,
  from its puncture past the shanks to the hand, as long as it is wound);
  the first turn lies where the long end from its puncture meets the
  shanks, 10-15 mm behind the second;
- the holder draws back through both turns farther: the single throw's
  draw-back and BACK_MORE (the turn nearer the tip off it onto the tail),
  then BACK_ON more along its axis (the turn behind, past the box lock and
  off the tip too);
- the cinch draws the hand and the holder farther and slower (HAND_CINCH,
  HOLD_CINCH, CINCH_T): a double throw slides down its stitch harder than a
  single one.
The scene's holder has friction 0.05 on the thread (0.15 in the single
throw): at 0.15 Newton stalls at 3.2 s, where the turns slide on the
shanks (docs/decisions/0122-tie-surgeons.md). HAND_OUT and BACK_HOLD are
variants tried there (0: off).
"""
import math

import numpy as np

import instrument_tie_high as high
import instrument_tie_hand as hand_tie
from instrument_tie import Track, radius_reaching

WRAPS = 2
PER_TURN = 2 * math.pi * 6.0     # mm of thread a loose turn round the shanks takes
PITCH = 1.6                      # mm: the hand's circle toward the tip per turn
WIND_T = 1.0                     # s per turn
BACK_T = 2.4                     # s: the holder's draw-back through both turns (1.8: Newton stalled at 3.25 s)
BACK_MORE = 4.0                  # mm: beyond the single throw's draw-back
BACK_ON, BACK_ON_T = 22.0, 1.0   # mm, s: then on along the axis, the turn nearer the box lock off the tip too
HAND_CINCH = np.array([0.0, -80.0, 1.2])  # mm: the hand there (-84 to -88: kinks)
HOLD_CINCH = np.array([0.0, 31.0, 1.5])  # mm: the holder's tip at the cinch's end (+23: 3.8 mm up)
CINCH_T = 5.5                    # s: the draw apart along the skin
HAND_OUT = 0.0                   # mm: the hand this far from the axis during the draw-back (0: stays)
BACK_HOLD = 0.0                  # s: the holder still before it draws on
FEED = 6.0                       # mm: the hand's place from the axis after the turns (toward +x and up)


def start_radius(extra=0.0):
    """The hand's starting distance from the holder's axis: the long end
    straight from its puncture past the shanks to it is as long as it is
    wound (puncture to the turn, WRAPS turns, out to R_END), and EXTRA mm."""
    need = np.linalg.norm(high.P_LONG - high.TURN) + WRAPS * PER_TURN + high.R_END + extra
    return radius_reaching(lambda r: high.around(high.PHI0, r), high.P_LONG, need, high.R_END,
                           300.0)


R0 = start_radius()


def spiral(e):
    """The hand at fraction e of the double throw: in from R0 to R_END by
    half a turn, WRAPS turns in all, PITCH toward the tip per turn."""
    r = high.R_END + (R0 - high.R_END) * max(0.0, 1.0 - 2.0 * WRAPS * e) ** 2
    return high.around(high.PHI0 + 2 * math.pi * WRAPS * e, r,
                       high.LEAD + PITCH * WRAPS * e)


def thread_line():
    """Waypoints of the starting shape (mm), from the tail's end to the long
    end's end at the hand."""
    pts = high.thread_line()[:-2]
    pts.append(tuple(high.around(high.PHI0, R0)))
    return pts


def paths():
    """The holder's key poses and the hand's (a Track whose rotation is
    not used); returns (holder, hand, the time the draw-back ends)."""
    holder = Track(high.GRASP - 12.0 * high.AXIS, high.R, 0.22)
    hand = Track(high.around(high.PHI0, R0), high.R, 0.0)
    holder.to(0.5, pos=high.GRASP + 0.5 * high.AXIS)
    hand.to(0.5)
    holder.to(0.7, jaw=0.0)
    hand.to(0.7)
    # the hand carries the long end twice round the holder's shanks
    t = 0.7 + WRAPS * WIND_T
    hand.to(t, path=spiral)
    holder.to(t)
    # and in toward the turns (the long end slack)
    lead = high.LEAD + PITCH * WRAPS
    fed = high.TURN + lead * high.AXIS + FEED * (0.5 * high.R[:, 2] + high.UP)
    t += 0.4
    hand.to(t, pos=fed)
    holder.to(t)
    # the holder draws back along its axis through both turns
    back = np.linalg.norm(high.GRASP - high.TURN) + 4.0 + BACK_MORE
    t += BACK_T
    t_back = t
    holder.to(t, pos=high.GRASP - back * high.AXIS)
    if HAND_OUT > 0.0:
        hand.to(t, pos=high.TURN + lead * high.AXIS + HAND_OUT * (0.5 * high.R[:, 2] + high.UP))
    else:
        hand.to(t)
    if BACK_ON > 0.0:
        if BACK_HOLD > 0.0:
            t += BACK_HOLD
            holder.to(t)
            hand.to(t)
        t += BACK_ON_T
        holder.to(t, pos=high.GRASP - (back + BACK_ON) * high.AXIS)
        hand.to(t)
    # the hands cross: the tail to +y, the long end to -y, low over the wound
    t += hand_tie.CROSS_T
    holder.to(t, pos=hand_tie.HOLD_CROSS)
    hand.to(t, pos=hand_tie.HAND_CROSS)
    t += hand_tie.DOWN_T
    holder.to(t, pos=hand_tie.HOLD_LOW)
    hand.to(t, pos=hand_tie.HAND_LOW)
    # the cinch: apart along the skin
    t += CINCH_T
    holder.to(t, pos=HOLD_CINCH)
    hand.to(t, pos=HAND_CINCH)
    t += hand_tie.HOLD_END
    holder.to(t)
    hand.to(t)
    return holder, hand, t_back


def main():
    hand_tie.write_scene("instrument_tie_surgeons", thread_line(), paths)


if __name__ == "__main__":
    main()
