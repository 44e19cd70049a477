#!/usr/bin/env python3
"""Writes stitch_shape.csv, stitch_holder.csv, stitch_forceps.csv and
stitch_root.csv, the starting thread, the needle holder's and the forceps'
paths and the tail's path of scenes/stitch.ini, and prints the scene's rod
length, the handover's time and the planned holes:
  RODSIM=../build/release/rodsim python3 stitch_path.py

The needle (a 1/2 circle of radius RN) turns about the x axis, the wound's
direction, in the plane x = 0: the holder holds it at its back (the
thread's tip), its shafts along x, and pronates: its path's rotation is a
turn about x by the needle's angle. The needle's circle is centred ZC over
the skin at the wound, so its point enters the skin BITE before the wound
(y = -BITE), passes DEPTH under the skin and leaves BITE beyond it.

The holder drives the needle until its point is out beyond the exit and
its back still over the entry, its jaws (1.44 mm thick) clear of the skin:
the bite's arc between the holes (137 degrees) leaves a 1/2 circle 43
degrees for both. The forceps, their shafts along x too, come down onto
the needle GRASP_BACK behind its point, close, and take it (the scene's
[needle_grasp] at T_GRASP); the holder opens, backs off along its shafts,
closes and moves aside, out of their way, and the forceps draw the
needle out along its circle (a turn about x about the circle's centre,
the forceps turning about their own shafts) and then pull the thread
through, the needle carried as they took it.

The ends are then swung over the wound, each about its hole at its
length, from rising away from the wound to ACROSS (60 degrees over the
skin toward the other side, as a throw's crossed ends are drawn), and
drawn DRAW each. The thread's pull at a hole is its tension along both
strands: with the strand outside rising at angle a from the skin, away
from the wound, the pad gets T (1 - cos a) toward the wound and T sin a
up at each side; the needle's track (a U 4 mm deep) carries the up part
to the tissue under the wound. Drawn up at 66 degrees (0.59 T toward the
wound, 0.91 T up) the pad's middle rises 3.2 mm and the ends reach 30 N
as the edges meet; swung to 120 degrees (1.5 T toward the wound,
0.87 T up) they meet at 3.1 N.

The thread's starting tip frame is the needle's at the top of its circle
(d1 down to the centre, d2 = +x, d3 = -y), and the holder's rotation is
taken from it: the thread starts as a planar curve in x = 0 whose first
piece runs straight down from the tail (rodsim gives a straight start
along -z the frame d1 = y, d2 = x, and carries it twist-free along a
planar curve), so its tip's d2 is +x. From the tail it runs down, turns
toward +y, runs over the wound HIGH over the skin, turns down and back
round a half circle, and comes into the needle's back heading -y.

The skin is the pad as it is at t = 0, settled under its pretension;
wound_closure_path.py's reader of the settled top is used with this
scene's [surface]."""
import math
import os

import wound_closure_path as wcp

RN = 0.0065                           # m: the needle's radius, a 1/2 circle 20.4 mm along its arc
DEPTH = 0.0040                         # m: the bite's depth under the skin (the slit is 2 mm)
ZC = RN - DEPTH                       # m: the circle's centre over the skin
BITE = math.sqrt(RN * RN - ZC * ZC)   # m: each hole's distance from the wound's middle
PHI_IN = math.pi + math.asin(ZC / RN)      # the back's angle with the point at the entry
PHI_OUT = 2 * math.pi - math.asin(ZC / RN)  # the point at the exit (y = +BITE)
PHI0 = math.pi / 2                    # the back at the top of its circle at t = 0
ARC = math.pi                         # the needle's 1/2 circle: its point this far ahead
PHI_START = PHI_IN - ARC              # the turn's start: the point on the entry hole
LIFT = (0.0, -0.002, 0.005)           # m: the needle's start, over the bite's circle
HAND_HIGH = 0.0021                    # m: the back over the holes at the handover, the grip as
                                      # high: the shafts, along x, 0.5 mm over the pad's held
                                      # edge (the skin 1.7 mm higher there than at the holes)
CLEAR = math.asin(ZC / RN) + math.asin((HAND_HIGH - ZC) / RN)  # rad: the back this far
                                      # before the entry at the handover, the grip as far
                                      # beyond the exit
PHI_HAND = PHI_IN - CLEAR             # the back's angle when the holder lets go
PHI_GRASP = PHI_OUT + CLEAR           # the forceps' grip on the circle
GRASP_BACK = PHI_HAND + ARC - PHI_GRASP  # rad: the grip behind the point (1.6 mm)
PHI_END = PHI_OUT + 0.35              # the back 2.8 mm out of the exit hole

T_HOLD, T_APPROACH, T_BITE = 0.3, 0.7, 2.0  # s: still, lowered onto the skin, turned in
T_REACH, T_CLOSE_F = 0.9, 0.2         # s: the forceps come onto the needle, close
T_HAND = 0.6                          # s: the needle still, handed over
T_GRASP = T_HOLD + T_APPROACH + T_BITE + 0.55  # s: the forceps hold the needle ([needle_grasp])
T_DRAW = 1.4                          # s: the needle drawn out along its circle
T_PULL = 2.6                          # s: the thread drawn through, the tail coming taut
T_CLOSE, T_REST = 2.5, 0.5            # s: the ends swung over the wound and drawn; a rest
PULL_UP = 1.15                        # rad: the long end's rise from the skin, drawn through
SLACK = 0.001                         # m: thread left slack at the pull's end (its sag)
PULL_DIR = (0.0, math.cos(PULL_UP), math.sin(PULL_UP))  # the pull's direction from the exit hole
PHI_PULL = 2 * math.pi + PULL_UP - math.pi / 2  # the needle's back then heading along it (d3)
TAIL_TO = (0.0, -0.010, 0.020)        # m: the tail's end (from the entry hole) after the bite
ACROSS = 2 * math.pi / 3              # rad: each end's angle from the skin, away from its
                                      # hole's side, once swung over the wound: 60 degrees
                                      # over the skin toward the other side, crossing its
                                      # fellow as a throw's ends do
TAIL_X = 0.004                        # m: the tail's end moved aside (+x) as it swings over,
                                      # clear of the long end where they cross
SWEEP = 0.5                           # the share of T_CLOSE spent swinging the ends over, at
                                      # their lengths from the holes; then they are drawn
DRAW = 0.0019                         # m: each end's draw: the edges meet at 1.73 mm (3.1 N
                                      # on each end), the thread first tight at about 0.4 mm
NODES = 81                            # stitch.ini's rod.nodes
FORCEPS_FROM = (0.0, 0.0105, 0.005)   # m: the forceps' start from their grip: beyond the
                                      # exit, under the thread's starting run back to the needle,
                                      # their open jaws 1.7 mm clear of the holder's box lock as
                                      # it lowers the needle past them (0.9 .. 1.3 s)
HOLDER_OPEN = 0.2                     # the holder's opening off the needle: the jaws' tips 1.8 mm
                                      # apart; its shanks, which cross at the box lock, spread
                                      # 72 mm x sin(0.35 x opening) each at their back ends (5 mm)
HOLDER_SHUT = 0.12                    # ... and as it goes: 3 mm, not closed (under 0.1 its jaws
                                      # would take the thread as ordinary jaws do)
HOLDER_BACK = 0.015                   # m: the holder backed off along its shafts (-x): its
                                      # jaws' tips clear of the needle and the thread (x = 0)
HOLDER_ASIDE = 0.012                  # m: and moved aside (-y) once they are, out of the
                                      # forceps' way over the needle's circle and back to the
                                      # entry (their shanks 1.6 mm apart at 4.25 s)
HOLDER_UP = 0.004                     # m: and lifted (lifted 5 mm, its shanks come within
                                      # 1.3 mm of the forceps' at the top of the circle)
DURATION = T_HOLD + T_APPROACH + T_BITE + T_HAND + T_DRAW + T_PULL + T_CLOSE + T_REST


def scene_pad():
    """wound_closure_path's settled top, read with stitch.ini's pad."""
    wcp.pad_section = lambda scene="stitch.ini", read=wcp.pad_section: read(scene)
    return wcp.settled_top()


def top_at(top, x, y):
    """z of the settled top at (x, y): wound_closure_path's smallest
    triangle of the nearest nodes, else (outside the 2 mm cells at the
    wound, where eight nodes may not surround the point) its nearest
    triangle of the nearest twelve: a plane through three nodes."""
    try:
        return wcp.top_at(top, x, y)
    except TypeError:
        near = sorted(top, key=lambda p: (p[0] - x) ** 2 + (p[1] - y) ** 2)[:12]
        a, b, c = near[0], near[1], next(p for p in near[2:] if abs(
            (near[1][0] - near[0][0]) * (p[1] - near[0][1]) -
            (p[0] - near[0][0]) * (near[1][1] - near[0][1])) > 1e-9)
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det
        v = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det
        return a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])


def smooth(s):
    """0 .. 1 with zero slope at both ends."""
    s = min(1.0, max(0.0, s))
    return 3 * s * s - 2 * s ** 3


def drawn(f, up, length):
    """(angle from the skin, away from the wound; distance from its hole) of
    an end f of the way through the draw-up: swung over the wound at its
    length, then drawn DRAW."""
    return (up + (ACROSS - up) * smooth(f / SWEEP),
            length + DRAW * smooth((f - SWEEP) / (1 - SWEEP)))


def back(phi, skin):
    """The needle's back (the thread's tip) at angle phi of its circle."""
    return (0.0, RN * math.cos(phi), skin + ZC + RN * math.sin(phi))


def start_shape(skin):
    """The starting centreline, root to tip, as points 0.05 mm apart."""
    tip = tuple(a + b for a, b in zip(back(PHI0, skin), LIFT))
    rc = 0.004                       # m: the half circle coming back into the needle
    high = tip[2] + 2 * rc           # m: the run over the wound
    ra, drop = 0.003, 0.002          # m: the first turn, the straight start down
    y_root, y_turn = -0.016, 0.022   # m
    pts = [(y_root, high + ra + drop)]
    step = 5e-5

    def line(to):
        a = pts[-1]
        n = max(1, int(round(math.dist(a, to) / step)))
        pts.extend((a[0] + (to[0] - a[0]) * k / n, a[1] + (to[1] - a[1]) * k / n)
                   for k in range(1, n + 1))

    def arc(cy, cz, r, a0, a1):
        n = max(2, int(round(abs(a1 - a0) * r / step)))
        pts.extend((cy + r * math.cos(a0 + (a1 - a0) * k / n), cz + r * math.sin(a0 + (a1 - a0) * k / n))
                   for k in range(1, n + 1))

    line((y_root, high + ra))
    arc(y_root + ra, high + ra, ra, math.pi, 1.5 * math.pi)        # down, turning to +y
    line((y_turn, high))
    arc(y_turn, high - rc, rc, 0.5 * math.pi, -0.5 * math.pi)     # over and back, to -y
    line((tip[1], tip[2]))
    return [(0.0, y, z) for y, z in pts]


def on_nodes(fine):
    """NODES points along the fine polyline, each next one a chord DS from
    the last, DS chosen so that the last lands on its end: rodsim takes
    them as they are (resampled, the tip would move off the path's start)."""
    arc = [0.0]
    for a, b in zip(fine, fine[1:]):
        arc.append(arc[-1] + math.dist(a, b))

    def at(s):
        k = min(max(0, next((i for i, v in enumerate(arc) if v >= s), len(arc) - 1) - 1),
                len(arc) - 2)
        f = (s - arc[k]) / (arc[k + 1] - arc[k])
        return tuple(p + f * (q - p) for p, q in zip(fine[k], fine[k + 1]))

    def walk(ds):
        pts, s = [fine[0]], 0.0
        for _ in range(NODES - 1):
            lo, hi = s, s + 2 * ds
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                if math.dist(at(mid), pts[-1]) < ds:
                    lo = mid
                else:
                    hi = mid
            s = 0.5 * (lo + hi)
            pts.append(at(s))
        return pts, s

    lo, hi = 0.99 * arc[-1] / (NODES - 1), arc[-1] / (NODES - 1)
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if walk(mid)[1] < arc[-1]:
            lo = mid
        else:
            hi = mid
    pts = walk(0.5 * (lo + hi))[0]
    pts[-1] = fine[-1]
    return pts


def needle_rows(skin, pull):
    """(t, back, angle about x from the start) of the needle's back, the
    thread's tip, the whole run."""
    start = tuple(a + b for a, b in zip(back(PHI0, skin), LIFT))
    rows = [(0.0, start, 0.0), (T_HOLD, start, 0.0)]
    for k in range(1, 31):  # lowered and turned until the point touches the entry
        s = smooth(k / 30)
        phi = PHI0 + (PHI_START - PHI0) * s
        p = tuple(a + (1 - s) * b for a, b in zip(back(phi, skin), LIFT))
        rows.append((T_HOLD + T_APPROACH * k / 30, p, phi - PHI0))
    t0 = T_HOLD + T_APPROACH
    for k in range(1, 101):  # the holder's turn, eased in and out: the point out
        phi = PHI_START + (PHI_HAND - PHI_START) * smooth(k / 100)
        rows.append((t0 + T_BITE * k / 100, back(phi, skin), phi - PHI0))
    t0 += T_BITE
    for k in range(1, 7):  # still while the forceps take it
        rows.append((t0 + T_HAND * k / 6, back(PHI_HAND, skin), PHI_HAND - PHI0))
    t0 += T_HAND
    for k in range(1, 71):  # drawn out along its circle by the forceps
        phi = PHI_HAND + (PHI_END - PHI_HAND) * smooth(k / 70)
        rows.append((t0 + T_DRAW * k / 70, back(phi, skin), phi - PHI0))
    out, exit_hole = back(PHI_END, skin), (0.0, BITE, skin)
    to = tuple(h + pull * p for h, p in zip(exit_hole, PULL_DIR))
    t0 += T_DRAW
    for k in range(1, 61):  # the needle turned back to lead the thread along the pull
        s = smooth(k / 60)
        rows.append((t0 + T_PULL * k / 60, tuple(a + s * (b - a) for a, b in zip(out, to)),
                     PHI_END + s * (PHI_PULL - PHI_END) - PHI0))
    t0 += T_PULL
    for k in range(1, 61):  # swung over the wound, then drawn: the needle's back still
                            # heading along the thread (d3 along the pull)
        turn, length = drawn(k / 60, PULL_UP, pull)
        rows.append((t0 + T_CLOSE * k / 60,
                     tuple(h + length * c for h, c in zip(exit_hole, (0.0, math.cos(turn),
                                                                       math.sin(turn)))),
                     2 * math.pi + turn - math.pi / 2 - PHI0))
    rows.append((DURATION, rows[-1][1], rows[-1][2]))
    return rows


def turn_x(v, a):
    """v turned by a about the x axis."""
    return (v[0], v[1] * math.cos(a) - v[2] * math.sin(a), v[1] * math.sin(a) + v[2] * math.cos(a))


def holder_rows(skin, pull):
    """(t, point, angle about x, jaw) of the holder's path: the needle's
    back until the handover, then opened a little, backed off along its
    shafts (-x) and lifted, its jaws closing again, and moved aside (-y):
    the forceps draw the needle over the top of its circle to where the
    holder held it, and then up and over the wound; the two shapes stay
    1.6 mm apart at least (the scene's check refuses paths that take one
    instrument through another)."""
    rows = [r + (0.0,) for r in needle_rows(skin, pull) if r[0] <= T_GRASP + 1e-9]
    at, turn = back(PHI_HAND, skin), PHI_HAND - PHI0
    t0 = T_GRASP + 0.05
    rows += [(t0, at, turn, 0.0), (t0 + 0.2, at, turn, HOLDER_OPEN)]  # opened off the needle
    for k in range(1, 21):  # backed off and lifted, its jaws closing once their tips are
                            # 2.3 mm back (k = 5), then moved aside: out of the forceps' way
        s, late = smooth(k / 20), smooth(k / 10 - 1)
        rows.append((t0 + 0.2 + 0.8 * k / 20,
                     (at[0] - HOLDER_BACK * s, at[1] - HOLDER_ASIDE * late, at[2] + HOLDER_UP * s),
                     turn, HOLDER_OPEN - (HOLDER_OPEN - HOLDER_SHUT) * smooth((k - 5) / 5)))
    rows.append((DURATION, rows[-1][1], turn, rows[-1][3]))
    return rows


def forceps_rows(skin, pull):
    """(t, point, angle about x, jaw) of the forceps: their shafts along x,
    their jaws opening across the needle's wire (their local z along the
    circle's radius at the grip); still and open, lowered onto the grip,
    closed; from the handover carrying the needle as they took it."""
    grip = (0.0, RN * math.cos(PHI_GRASP), skin + ZC + RN * math.sin(PHI_GRASP))
    turn0 = -math.pi / 2  # local z (0, -sin, cos) = +y: the jaws open level, across the wire
    start = tuple(g + f for g, f in zip(grip, FORCEPS_FROM))
    t_reach = T_HOLD + T_APPROACH + T_BITE - 0.6  # s: they set off before the holder stops
    rows = [(0.0, start, turn0, 0.5), (t_reach, start, turn0, 0.5)]
    for k in range(1, 21):
        s = smooth(k / 20)
        rows.append((t_reach + T_REACH * k / 20,
                     tuple(g + (1 - s) * f for g, f in zip(grip, FORCEPS_FROM)), turn0, 0.5))
    t0 = t_reach + T_REACH
    rows.append((t0 + T_CLOSE_F, grip, turn0, 0.0))
    b0 = back(PHI_HAND, skin)
    rel = tuple(g - b for g, b in zip(grip, b0))
    for t, b, turn in needle_rows(skin, pull):
        if t <= T_GRASP + 1e-9:
            continue
        a = turn - (PHI_HAND - PHI0)
        rows.append((t, tuple(p + q for p, q in zip(b, turn_x(rel, a))), turn0 + a, 0.0))
    return rows


def root_rows(shape, skin):
    """(t, point) of the tail's end: lowered to TAIL_TO from the entry hole
    over the bite, then swung over the wound and drawn as the long end is
    (drawn), moved TAIL_X aside."""
    start, entry = shape[0], (0.0, -BITE, skin)
    to = tuple(h + p for h, p in zip(entry, TAIL_TO))
    rows = [(0.0, start), (T_HOLD, start)]
    for k in range(1, 41):
        s = smooth(k / 40)
        rows.append((T_HOLD + (T_APPROACH + T_BITE + T_HAND + T_DRAW) * k / 40,
                     tuple(a + s * (b - a) for a, b in zip(start, to))))
    t0 = T_HOLD + T_APPROACH + T_BITE + T_HAND + T_DRAW + T_PULL
    rows.append((t0, to))
    up, tail = math.atan2(TAIL_TO[2], -TAIL_TO[1]), math.hypot(TAIL_TO[1], TAIL_TO[2])
    for k in range(1, 61):
        turn, length = drawn(k / 60, up, tail)
        side = TAIL_X * smooth(k / 60 / SWEEP)
        v = (side, -length * math.cos(turn), length * math.sin(turn))
        rows.append((t0 + T_CLOSE * k / 60,
                     tuple(h + length * c / math.hypot(*v) for h, c in zip(entry, v))))
    rows.append((DURATION, rows[-1][1]))
    return rows


def main():
    top = scene_pad()
    skin = 0.5 * (top_at(top, 0.0, -BITE) + top_at(top, 0.0, BITE))
    print(f"skin at the holes {top_at(top, 0.0, -BITE):.6g}, {top_at(top, 0.0, BITE):.6g} m")
    shape = on_nodes(start_shape(skin))
    length = (NODES - 1) * math.dist(shape[0], shape[1])
    tail = math.hypot(TAIL_TO[1], TAIL_TO[2])
    # the long end's length once drawn through: the thread between the holes
    # lies in the needle's track ([surface] track_spacing), along the bite's arc
    pull = length - tail - RN * (PHI_OUT - PHI_IN) - SLACK
    with open("stitch_shape.csv", "w") as f:
        f.write("x,y,z\n")
        for p in shape:
            f.write(f"{p[0]:.12g},{p[1]:.12f},{p[2]:.12f}\n")
    for name, rows in (("stitch_holder.csv", holder_rows(skin, pull)),
                       ("stitch_forceps.csv", forceps_rows(skin, pull))):
        with open(name, "w") as f:
            f.write("t,x,y,z,rx,ry,rz,jaw\n")
            for t, p, turn, jaw in rows:
                f.write(f"{t:.5f},{p[0]:.12g},{p[1]:.12f},{p[2]:.12f},{turn:.12f},0,0,{jaw:g}\n")
    with open("stitch_root.csv", "w") as f:
        f.write("t,x,y,z\n")
        for t, p in root_rows(shape, skin):
            f.write(f"{t:.5f},{p[0]:.12g},{p[1]:.12f},{p[2]:.12f}\n")
    print(f"[rod] length = {length:.12g}")
    print(f"needle radius {RN:.6g} m, holes at y = -+{BITE:.6g} m on the skin at z = {skin:.6g} m")
    print(f"tail {tail:.4g} m, long end {pull:.4g} m from the exit hole at the pull's end")
    rows = needle_rows(skin, pull)
    for what, phi in (("the point enters", PHI_IN - ARC), ("the point leaves", PHI_OUT - ARC),
                      ("the back enters", PHI_IN), ("the back leaves", PHI_OUT)):
        (t0, _, a0), (t1, _, a1) = next((r, q) for r, q in zip(rows, rows[1:])
                                        if r[2] + PHI0 - 1e-9 <= phi <= q[2] + PHI0 and q[2] > r[2])
        print(f"{what} at t = {t0 + (t1 - t0) * (phi - PHI0 - a0) / (a1 - a0):.3f} s")
    print(f"[needle_grasp] t = {T_GRASP:.6g}  # the forceps take the needle {RN * GRASP_BACK:.3g} m "
          f"behind its point")
    t0 = T_HOLD + T_APPROACH + T_BITE + T_HAND + T_DRAW
    print(f"the pull {t0:.3g} .. {t0 + T_PULL:.3g} s, the ends swung over the wound to "
          f"{t0 + T_PULL + SWEEP * T_CLOSE:.3g} s, drawn {1e3 * DRAW:.3g} mm each to "
          f"{t0 + T_PULL + T_CLOSE:.3g} s")
    print(f"[solver] duration = {DURATION:.6g}")


if __name__ == "__main__":
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    main()
