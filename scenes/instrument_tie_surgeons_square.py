#!/usr/bin/env python3
"""Writes the thread's starting shape, the needle holder's path and the
hand's path for instrument_tie_surgeons_square.ini: a whole surgeon's knot
thrown with instruments, the long end held by the surgeon's hand: a double
throw, then a single throw the other way. A trial that does not run
through yet: the scene is not shipped (docs/decisions/0145-surgeons-square.md
says where it is and where each run ends).

  python3 instrument_tie_surgeons_square.py
  python3 instrument_tie_surgeons_square.py --aim ../build/release/rodsim

writes instrument_tie_surgeons_square_shape.csv, _holder.csv (poses every
20 ms, eased between key poses) and _hand.csv (the thread's tip, t,x,y,z)
and prints the rod's length and the puncture points for the scene. With
--aim it first runs the scene to AIM_T (the hand's second turn wound, the
holder about to run on) and puts the holder's second take (TAKE2) where the
tail's end lies then.

Nothing here is new but the joins (no function copied):
- the double throw is instrument_tie_surgeons.py's (the hand winds the long
  end twice round the holder's shanks, the holder draws the tail through
  both turns, the hands cross and cinch), the long end EXTRA longer: the
  hand starts farther out on the same spiral and the cinch draws it EXTRA
  farther (HAND_CINCH1);
- the single throw is instrument_tie_square.py's second throw (its
  paths(-1)): the holder lets go of the tail, rises, turns half round and
  comes down over the knot; the hand lifts the long end over the holder's
  far side and winds it once round the shanks, the mirror of the first
  turns (sense -1: the double throw right-handed, this throw left-handed,
  the surgeon's knot, not the granny surgeon's); the holder runs on to
  where the tail's end lies, takes it and draws it back through the turn;
  the hands cross back and cinch along the skin.
"""
import sys

import numpy as np

# instrument_tie.py, imported below, reads its variant from the arguments
AIM_WITH = sys.argv[2] if len(sys.argv) == 3 and sys.argv[1] == "--aim" else None
del sys.argv[1:]

import instrument_tie_hand as hand_tie
import instrument_tie_square as sq
import instrument_tie_surgeons as surg

PREFIX = "instrument_tie_surgeons_square"
EXTRA = 8.0                        # mm: the long end longer than instrument_tie_surgeons'
LONG1 = 73.0                       # mm: the long end beyond the double throw there
HAND_CINCH1 = surg.HAND_CINCH - np.array([0.0, EXTRA, 0.0])  # the first cinch's hand
SENSE = -1                         # the single throw's turn (the square's mirror)
# the single throw's holder: pointing to +y (the tail, let go, lies along
# +y from the knot, its end 32 mm out: the double throw's cinch laid it
# there), YAW2 (rad) about the vertical from there, the turn NEAR2 mm
# nearer the knot than instrument_tie_square's TURN2_0
YAW2 = 0.0
NEAR2 = -4.0
# mm: the tail's end where the holder takes it (None: on along its axis);
# measured by --aim
TAKE2 = (1.6, 32.0, 1.2)
AIM_T = None                       # s: set below, the hand's turn done

# the double throw with the longer long end: instrument_tie_surgeons'
# spiral from farther out, its cinch farther
surg.R0 = surg.start_radius(EXTRA)
surg.HAND_CINCH = HAND_CINCH1
sq.YAW2, sq.NEAR2 = YAW2, NEAR2
sq.derive()
FILES = {SENSE: (PREFIX + "_hand.csv", PREFIX + "_holder.csv")}


def first_throw():
    """The double throw's tracks at the end of its cinch's hold."""
    holder, hand, _t_back = surg.paths()
    return sq.turning(holder), hand


def paths():
    sq.TAKE2 = {SENSE: TAKE2}
    return sq.paths(SENSE, first=first_throw, avail=LONG1 + EXTRA)


def main():
    pts = hand_tie.write_shape(PREFIX + "_shape.csv", surg.thread_line())
    holder, hand = paths()
    hand_tie.write_hand(hand, np.array(pts[-1]), FILES[SENSE][0])
    holder.write(FILES[SENSE][1])
    print("duration %.2f s" % holder.t)


def aim(rodsim, iterations=2):
    """The take aimed where the tail lies as the jaws run on (instrument_tie_square's aim)."""
    global TAKE2
    for k in range(iterations):
        main()
        end, _d = sq.tail_end(rodsim, SENSE, AIM_T, PREFIX + ".ini", FILES)
        print("aim %d: the tail's end at (%.2f, %.2f, %.2f) mm at %g s" % (k + 1, end[0], end[1],
                                                                          end[2], AIM_T))
        TAKE2 = (round(end[0], 1), round(end[1], 1), sq.TAIL2_Z)
    print("TAKE2 =", TAKE2)
    main()


# the hand's turn done 5.6 s after the double throw's cinch (as in instrument_tie_square)
AIM_T = surg.paths()[0].t + sq.AIM_T - sq.first_throw()[0].t

if __name__ == "__main__":
    if AIM_WITH:
        aim(AIM_WITH)
    else:
        main()
