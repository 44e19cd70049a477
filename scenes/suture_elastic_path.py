#!/usr/bin/env python3
"""Writes suture_elastic_path.csv, the needle holder's path of
scenes/suture_elastic.ini: suture_path.py's running suture made for the
elastic pad's top as it sits, not the plane z = 0.

Held at its sides and stretched 30 % across the wound, the 2 cm pad sinks
(Poisson): its top is 4.6 mm down at the wound, 3.5 mm at y = +-27 mm and
0 at the held edges. suture_elastic_top.csv holds that top (the pad's
top-face nodes, settled under its pretension, at t = 0 with nothing on it):
  ../rodsim run suture_elastic.ini --no-video --quiet --set solver.duration=0.001 \
      --tissue-csv pad.csv
  awk -F, 'NR == 1 {print "x,y,z"} NR > 1 && $1 == 0 {print $3 "," $4 "," $5}' \
      pad.csv > suture_elastic_top.csv
top(x, y) is a plane fitted to those nodes near (x, y), weighted by a
Gaussian of 5 mm (the mesh is 5 mm at the wound). Each bite's circle is
centred ZC = 2 mm above the mean top at its two holes, so the 5 mm
needle enters and leaves the skin 4.58 mm either side of the wound and
passes 3 mm under the top (the wound is 2 mm deep); two bites, 12 mm
apart. The lifts and the thread's starting U are taken from that top
too, and the holder first lifts the needle off the skin. Then, as for
suture.ini (settled 1 s with the needle held):
  python3 suture_elastic_path.py > suture_elastic_path.csv
  ../rodsim run suture_elastic.ini --no-video --quiet --csv settle.csv \
      --set rod.shape=suture_elastic_shape_u.csv \
      --set ends.tip_motion=suture_elastic_hold.csv --set solver.duration=1
  awk -F, 'NR == 1 {print "x,y,z"} $1 == 1 {printf "%s,%s,%.10g\\n", $4, $5, $6 + 5e-5}' \
      settle.csv > suture_elastic_shape.csv
The settled thread is written LIFT = 0.05 mm higher, the path's start with
it: where it drapes over the pad's rounded held edge, the shape resampled
to other rod.nodes (121) cuts into the edge by 0.04 mm otherwise."""
import csv
import math

RN, DEPTH = 0.005, 0.003                       # the bite 3 mm deep, under the 2 mm wound
ZC = RN - DEPTH                                # 2 mm: the circle's centre over the skin
BITE = math.sqrt(RN * RN - ZC * ZC)            # 4.58 mm: the holes either side
XS = [-0.012, 0.0]                             # bites along the wound (two)
PHI_IN = math.atan2(-ZC, -BITE) % (2 * math.pi)  # back at the entry hole
PHI_OUT = math.atan2(-ZC, BITE) % (2 * math.pi)  # back at the exit hole
ARC = 0.375 * 2 * math.pi                      # the needle's 3/8 circle
PHI_START = PHI_IN - ARC                       # the point at the entry hole
TOP = [tuple(float(v) for v in (r["x"], r["y"], r["z"]))
       for r in csv.DictReader(open("suture_elastic_top.csv"))]
SIGMA = 0.005                                  # m: the fit's reach


def top(x, y):
    """The pad's top z at (x, y): a plane fitted by weighted least squares."""
    a = [[0.0] * 3 for _ in range(3)]
    rhs = [0.0] * 3
    for px, py, pz in TOP:
        w = math.exp(-((px - x) ** 2 + (py - y) ** 2) / (2 * SIGMA * SIGMA))
        row = (1.0, px - x, py - y)
        for i in range(3):
            rhs[i] += w * row[i] * pz
            for j in range(3):
                a[i][j] += w * row[i] * row[j]
    for i in range(3):  # Gaussian elimination; the constant term is z
        for k in range(i + 1, 3):
            f = a[k][i] / a[i][i]
            for j in range(3):
                a[k][j] -= f * a[i][j]
            rhs[k] -= f * rhs[i]
    sol = [0.0] * 3
    for i in (2, 1, 0):
        sol[i] = (rhs[i] - sum(a[i][j] * sol[j] for j in range(i + 1, 3))) / a[i][i]
    return sol[0]


ZS = {x: 0.5 * (top(x, -BITE) + top(x, BITE)) for x in XS}  # each bite's skin



def frame(phi):
    """Columns d1 (toward the circle's centre), d2 = x, d3 (along the motion)."""
    c, s = math.cos(phi), math.sin(phi)
    d1, d2, d3 = (0.0, -c, -s), (1.0, 0.0, 0.0), (0.0, -s, c)
    return [[d1[i], d2[i], d3[i]] for i in range(3)]


def back(x, phi):
    return (x, RN * math.cos(phi), ZS[x] + ZC + RN * math.sin(phi))


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



LENGTH = 0.12
STRAIGHT, TURN = 0.035, 0.008  # m: the starting U on the skin (see shape)
R = 0.00015  # m: the thread's radius, its centreline that far over the skin
LIFT = 0.00005  # m: the settled shape's lift (see the module's comment)
ANCHOR = (-0.024, -0.004, top(-0.024, -0.004) + R)  # the tail, on the skin


NODES = 81  # suture_elastic.ini's rod.nodes: the shape is written as its nodes


def curve(u):
    """The starting centreline at arc length u (nearly: the U follows the
    top's slope), lying slack on the skin: from the anchor STRAIGHT along
    +x, a half circle of radius TURN toward -y, then back along -x."""
    arc = math.pi * TURN
    if u <= STRAIGHT:
        p = (ANCHOR[0] + u, ANCHOR[1])
    elif u <= STRAIGHT + arc:
        a = (u - STRAIGHT) / TURN
        p = (ANCHOR[0] + STRAIGHT + TURN * math.sin(a), ANCHOR[1] - TURN * (1 - math.cos(a)))
    else:
        p = (ANCHOR[0] + STRAIGHT - (u - STRAIGHT - arc), ANCHOR[1] - 2 * TURN)
    return (p[0], p[1], top(p[0], p[1]) + R)


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
with open("suture_elastic_shape_u.csv", "w") as f:
    f.write("x,y,z\n")
    for q in SHAPE:
        f.write("%.9f,%.9f,%.9f\n" % q)
with open("suture_elastic_hold.csv", "w") as f:
    f.write("t,x,y,z,rx,ry,rz\n")
    for tt in (0.0, 1.0):
        f.write("%.4f,%.7f,%.7f,%.7f,0.0000000,0.0000000,0.0000000\n" % ((tt,) + SHAPE[-1]))
# the tip's starting frame: the root's (d1 = y, d2 = z, d3 = x) carried along
# the U by parallel transport, a half turn about z
Q0 = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]
# the settled thread is written LIFT higher (see the module's comment)
start = (SHAPE[-1][0], SHAPE[-1][1], SHAPE[-1][2] + LIFT)
t = 0.0
rows.append((0.0, start, Q0))
pos, rot = start, Q0
# first lift the needle lying on the skin 8 mm clear: turned as it is carried
# to the first bite, its point would cut the skin, which rises toward the
# held sides
lifted = (start[0], start[1], start[2] + 0.008)
t = move(t, 0.5, pos, rot, lifted, rot, 3)
pos = lifted
for k, x in enumerate(XS):
    first = back(x, PHI_START)
    t = move(t, 1.5, pos, rot, first, frame(PHI_START), 12)
    t = bite(t, 2.5, x, 40)
    phi_end = PHI_OUT + 0.15
    p_end, r_end = back(x, phi_end), frame(phi_end)
    # pull the thread through: up and away across the wound, 3 cm over the skin
    pulled = (x + 0.01, 0.02, ZS[x] + 0.03)
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
