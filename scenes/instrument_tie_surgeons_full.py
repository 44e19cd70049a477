#!/usr/bin/env python3
"""Writes the thread's starting shape, the needle holder's path and the
hand's path for a trial of the whole surgeon's knot thrown with
instruments: instrument_tie_surgeons.ini's double throw (its paths and
shape, imported from instrument_tie_surgeons.py), then a single throw the
other way on top. It does not run through yet (Newton stalls in the
second throw's draw-back or cinch: docs/decisions/0140-surgeons-single.md),
so no scene of it is shipped.

  python3 instrument_tie_surgeons_full.py

writes instrument_tie_surgeons_full_shape.csv, _holder.csv and _hand.csv
in the current directory; the trial's scene is instrument_tie_surgeons.ini
with those three files and solver.duration = 25.6 s.

The single throw keeps the tail in the holder's jaws (a re-grasp is where
every second throw stalled before): after the double throw's cinch the
holder carries the tail back over the knot to the tail's first side (-y),
its shanks over the knot; the hand winds the long end once round the
shanks BEHIND the jaws' tip, the other way round (SENSE); the holder draws
back along its axis, so that the turn slides off its jaws' tip onto the
tail held in them (it cannot leave the tip without it) and the tail is
drawn through; then both ends are drawn apart along the skin.
"""
import math

import numpy as np

import instrument_tie_high as high
import instrument_tie_hand as hand_tie
import instrument_tie_surgeons as surg
from instrument_tie import radius_reaching

SENSE = -1                       # the turn about the holder's axis (+1: the double throw's start, mirrored for -1)
PHI2 = None                      # degrees: the hand's start about the axis (None: by SENSE)
T_OVER = 1.6                     # s: the holder over the knot to the -y side
TIP2 = np.array([0.0, -14.0, 6.0])  # mm: the holder's tip (the tail's end) for the turn
BEHIND = 30.0                    # mm: the turn this far behind the jaws' tip (16: it slid round the tip)
EXIT = np.array([0.0, -6.0, 1.0])   # mm: where the long end leaves the double throw
LONG = 73.0                      # mm: the long end's length from EXIT to the hand
PRE2 = np.array([0.0, 20.0, 45.0])  # mm: the hand first there, the long end behind the holder (None: straight lift)
SLACK2 = 4.0                     # mm: the long end this much short of straight (2: stalled in the lift)
PER_TURN2 = 2 * math.pi * 5.5    # mm of thread the turn takes
R_END2 = 8.0                     # mm: the hand's distance from the axis after the turn
WIND2_T = 1.2                    # s: the turn
FEED2 = 5.0                      # mm: the hand this far from the axis after it
BACK2 = 10.0                     # mm: the holder draws back beyond the turn's distance to the tip
FOLLOW2 = 0.5                    # the hand follows the draw-back by this fraction
BACK2_T = 2.4                    # s
HOLD_CINCH2 = np.array([0.0, -31.0, 1.5])  # mm: the holder's tip at the cinch's end
HAND_CINCH2 = np.array([0.0, 35.0, 1.2])   # mm: the hand there (+50: beyond the long end's reach)
CINCH2_T = 4.0                   # s
END2 = 1.0                       # s: held


def turn_centre():
    """The turn's centre on the holder's axis (mm), BEHIND its tip at TIP2."""
    return TIP2 - BEHIND * high.AXIS


def around2(phi, r):
    """A point at angle phi about the holder's axis (0: +x, pi/2: up), r from it."""
    return turn_centre() + r * (math.cos(phi) * high.R[:, 2] + math.sin(phi) * high.UP)


def phi_of(e):
    """The hand's angle about the holder's axis at fraction e of its turn
    (0: +x, pi/2: up): from PHI2 (default: the first throw's start PHI0 for
    SENSE +1, mirrored in the plane x = 0 for -1), SENSE the way round."""
    phi2 = math.radians(PHI2) if PHI2 is not None else \
        (high.PHI0 if SENSE > 0 else math.pi - high.PHI0)
    return phi2 + SENSE * 2 * math.pi * e


def start_radius2():
    """The hand's starting distance from the axis: the long end straight
    from EXIT to it as long as the turn takes, at most LONG - SLACK2."""
    need = min(np.linalg.norm(EXIT - turn_centre()) + PER_TURN2 + R_END2, LONG - SLACK2)
    return radius_reaching(lambda r: around2(phi_of(0.0), r), EXIT, need, R_END2, 300.0)


def spiral2(e):
    """The hand at fraction e of the turn: in to R_END2 by half a turn."""
    r0 = start_radius2()
    r = R_END2 + (r0 - R_END2) * max(0.0, 1.0 - 2.0 * e) ** 2
    return around2(phi_of(e), r)


def paths():
    holder, hand, t_back = surg.paths()
    t = holder.t
    # the holder carries the tail up, back over the knot and down on -y;
    # the hand to the turn's start
    up = np.array([0.0, 8.0, 16.0])
    holder.to(t + 0.5 * T_OVER, pos=up)
    holder.to(t + T_OVER, pos=TIP2)
    # the hand lifts the long end to the turn's start: straight about
    # where it leaves the knot, or (PRE2) first up behind the holder
    a = hand.p - EXIT
    b = spiral2(0.0) - EXIT
    ra, rb = np.linalg.norm(a), np.linalg.norm(b)
    ua, ub = a / ra, b / rb
    om = math.acos(max(-1.0, min(1.0, float(np.dot(ua, ub)))))

    def lift(e):
        u = (math.sin((1 - e) * om) * ua + math.sin(e * om) * ub) / math.sin(om)
        return EXIT + min(ra - SLACK2 * min(1.0, 4.0 * e), ra + e * (rb - ra)) * u
    if PRE2 is None:
        hand.to(t + T_OVER, path=lift)
    else:
        hand.to(t + 0.5 * T_OVER, pos=PRE2)
        hand.to(t + T_OVER, pos=spiral2(0.0))
    t += T_OVER + 0.2
    holder.to(t)
    hand.to(t)
    # the turn round the shanks, the other way
    t += WIND2_T
    hand.to(t, path=spiral2)
    holder.to(t)
    fed = turn_centre() + 4.0 * high.AXIS + FEED2 * (0.5 * high.R[:, 2] * SENSE + high.UP)
    t += 0.4
    hand.to(t, pos=fed)
    holder.to(t)
    # the holder draws back along its axis: the turn off its tip onto the tail
    t += BACK2_T
    holder.to(t, pos=TIP2 - (BEHIND + BACK2) * high.AXIS)
    hand.to(t, pos=fed - FOLLOW2 * (BEHIND + BACK2) * high.AXIS)
    # the cinch: apart along the skin
    t += CINCH2_T
    holder.to(t, pos=HOLD_CINCH2)
    hand.to(t, pos=HAND_CINCH2)
    t += END2
    holder.to(t)
    hand.to(t)
    return holder, hand, t_back


def main():
    hand_tie.write_scene("instrument_tie_surgeons_full", surg.thread_line(), paths)


if __name__ == "__main__":
    main()
