#!/usr/bin/env python3
"""Writes suture_path.csv, the needle holder's path of scenes/suture.ini.

The thread's tip carries a 3/8 curved needle of radius RN (its back at the
tip, the needle bending toward the tip's d1 and pointing along its d3:
src/render/render.c needle_arc_points). Each bite drives the needle along its
own circle, in the y-z plane across the wound (the x axis), centred ZC above
the skin so that it enters at y = -BITE and leaves at y = +BITE; the back
follows the point through the same holes. Between bites the holder lifts the
needle, pulls the thread through and carries it over the wound to the next
bite (a running suture). The tip starts at rest at the end of the starting U
(frame Q0: d1 = -y, d2 = z, d3 = -x), so a row's rotation vector is the log
of the needle's frame times Q0^T; it is unwrapped (angle + 2 pi k) to
stay continuous, since the path interpolates it component by component.
It also writes suture_shape_u.csv, the thread laid in a U on the skin, and
suture_hold.csv, the holder at rest at the path's start. The monofilament
(bending length 8 cm) springs out of the U in 0.1 s, so suture.ini starts
from the U settled for 1 s with the needle held, suture_shape.csv:
  python3 suture_path.py > suture_path.csv
  ../rodsim run suture.ini --no-video --quiet --csv settle.csv \
      --set rod.shape=suture_shape_u.csv --set ends.tip_motion=suture_hold.csv \
      --set solver.duration=1
  awk -F, 'NR == 1 {print "x,y,z"} $1 == 1 {print $4 "," $5 "," $6}' \
      settle.csv > suture_shape.csv"""
import math

RN, BITE = 0.005, 0.004
ZC = math.sqrt(RN * RN - BITE * BITE)          # 3 mm: the bite is 2 mm deep
XS = [-0.012, 0.0, 0.012]                      # bites along the wound
PHI_IN = math.atan2(-ZC, -BITE) % (2 * math.pi)  # back at the entry hole
PHI_OUT = math.atan2(-ZC, BITE) % (2 * math.pi)  # back at the exit hole
ARC = 0.375 * 2 * math.pi                      # the needle's 3/8 circle
PHI_START = PHI_IN - ARC                       # the point at the entry hole


def frame(phi):
    """Columns d1 (toward the circle's centre), d2 = x, d3 (along the motion)."""
    c, s = math.cos(phi), math.sin(phi)
    d1, d2, d3 = (0.0, -c, -s), (1.0, 0.0, 0.0), (0.0, -s, c)
    return [[d1[i], d2[i], d3[i]] for i in range(3)]


def back(x, phi):
    return (x, RN * math.cos(phi), ZC + RN * math.sin(phi))


def log_rot(r):
    tr = r[0][0] + r[1][1] + r[2][2]
    ang = math.acos(max(-1.0, min(1.0, (tr - 1) / 2)))
    if ang < 1e-9:
        return (0.0, 0.0, 0.0)
    if math.pi - ang < 1e-6:  # axis from the symmetric part
        ax = [math.sqrt(max(0.0, (r[i][i] + 1) / 2)) for i in range(3)]
        k = max(range(3), key=lambda i: ax[i])
        for i in range(3):
            if i != k:
                ax[i] = math.copysign(ax[i], r[i][k] + r[k][i])
    else:
        ax = [r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]]
        n = math.sqrt(sum(a * a for a in ax))
        ax = [a / n for a in ax]
    return tuple(ang * a for a in ax)


def unwrap(v, prev):
    """The rotation vector equal to v (angle + 2 pi k) nearest prev."""
    ang = math.sqrt(sum(a * a for a in v))
    if ang == 0.0:
        return v
    ax = [a / ang for a in v]
    best = v
    for k in range(-3, 4):
        cand = tuple(a * (ang + 2 * math.pi * k) for a in ax)
        if sum((c - p) ** 2 for c, p in zip(cand, prev)) < sum((b - p) ** 2 for b, p in zip(best, prev)):
            best = cand
    return best


def slerp_frames(r0, r1, f):
    """Frame between r0 and r1 (fraction f) by the relative rotation."""
    rel = [[sum(r0[k][i] * r1[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    w = log_rot(rel)
    w = tuple(f * a for a in w)
    ang = math.sqrt(sum(a * a for a in w))
    if ang < 1e-12:
        e = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    else:
        ax = [a / ang for a in w]
        c, s = math.cos(ang), math.sin(ang)
        k = [[0, -ax[2], ax[1]], [ax[2], 0, -ax[0]], [-ax[1], ax[0], 0]]
        e = [[(1.0 if i == j else 0.0) + s * k[i][j] + (1 - c) * sum(k[i][m] * k[m][j] for m in range(3))
              for j in range(3)] for i in range(3)]
    return [[sum(r0[i][k] * e[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


rows = []  # (t, position, frame)
ident = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def move(t0, duration, p0, r0, p1, r1, count):
    for i in range(1, count + 1):
        f = i / count
        p = tuple(a + f * (b - a) for a, b in zip(p0, p1))
        rows.append((t0 + f * duration, p, slerp_frames(r0, r1, f)))
    return t0 + duration


def bite(t0, duration, x, count):
    for i in range(1, count + 1):
        phi = PHI_START + (PHI_OUT + 0.15 - PHI_START) * i / count
        rows.append((t0 + duration * i / count, back(x, phi), frame(phi)))
    return t0 + duration


ANCHOR = (-0.024, -0.004, 0.00015)  # on the skin at the thread radius
LENGTH = 0.12
STRAIGHT, TURN = 0.035, 0.008  # m: the starting U on the skin (see shape)


NODES = 81  # suture.ini's rod.nodes: the shape is written as its nodes, ds apart


def curve(u):
    """The starting centreline at arc length u, lying slack on the skin: from
    the anchor STRAIGHT along +x, a half circle of radius TURN toward -y, then
    back along -x (a thread held at both ends must not start straight: its
    tension would be undetermined)."""
    arc = math.pi * TURN
    if u <= STRAIGHT:
        p = (ANCHOR[0] + u, ANCHOR[1])
    elif u <= STRAIGHT + arc:
        a = (u - STRAIGHT) / TURN
        p = (ANCHOR[0] + STRAIGHT + TURN * math.sin(a), ANCHOR[1] - TURN * (1 - math.cos(a)))
    else:
        p = (ANCHOR[0] + STRAIGHT - (u - STRAIGHT - arc), ANCHOR[1] - 2 * TURN)
    return (p[0], p[1], ANCHOR[2])


def shape():
    """NODES points exactly ds apart along the curve (chords, by bisection):
    rodsim's resampling keeps them as they are."""
    ds = LENGTH / (NODES - 1)
    pts, u = [curve(0.0)], 0.0
    for _ in range(NODES - 1):
        lo, hi = u, u + 2 * ds
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if math.dist(curve(mid), pts[-1]) < ds:
                lo = mid
            else:
                hi = mid
        u = 0.5 * (lo + hi)
        pts.append(curve(u))
    return pts


SHAPE = shape()
with open("suture_shape_u.csv", "w") as f:
    f.write("x,y,z\n")
    for q in SHAPE:
        f.write("%.9f,%.9f,%.9f\n" % q)
with open("suture_hold.csv", "w") as f:
    f.write("t,x,y,z,rx,ry,rz\n")
    for tt in (0.0, 1.0):
        f.write("%.4f,%.7f,%.7f,%.7f,0.0000000,0.0000000,0.0000000\n" % ((tt,) + SHAPE[-1]))
# the tip's starting frame: the root's (d1 = y, d2 = z, d3 = x) carried along
# the U by parallel transport, a half turn about z
Q0 = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]
start = SHAPE[-1]
t = 0.0
rows.append((0.0, start, Q0))
pos, rot = start, Q0
for k, x in enumerate(XS):
    first = back(x, PHI_START)
    t = move(t, 2.0 if k == 0 else 1.5, pos, rot, first, frame(PHI_START), 12)
    t = bite(t, 2.5, x, 40)
    phi_end = PHI_OUT + 0.15
    p_end, r_end = back(x, phi_end), frame(phi_end)
    # pull the thread through: up and away across the wound
    pulled = (x + 0.01, 0.02, 0.03)
    t = move(t, 1.5, p_end, r_end, pulled, r_end, 6)
    pos, rot = pulled, r_end
t += 1.0  # rest at the end
rows.append((t, pos, rot))

print("t,x,y,z,rx,ry,rz")
prev = (0.0, 0.0, 0.0)
for tt, p, r in rows:
    rel = [[sum(r[i][k] * Q0[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    v = unwrap(log_rot(rel), prev)
    prev = v
    print("%.4f,%.7f,%.7f,%.7f,%.7f,%.7f,%.7f" % ((tt,) + tuple(p) + v))
