#!/usr/bin/env python3
"""Writes mesh_bowl.stl, the bumpy bowl of scenes/mesh_bowl.ini (binary STL).

A spherical cap of radius RS cut at the opening radius RO (its lowest point
at the origin), with a rim turned outward and down, and three gentle bumps
in its floor: z(r, phi) = RS - sqrt(RS^2 - r^2) + BUMP * sin(pi r / RO)^2
cos(3 phi). A sheet (open), its front (counter-clockwise side) up and in:
the solid is below it. RINGS x SIDES quads, the centre a fan:
  python3 make_bowl.py   (writes mesh_bowl.stl beside this script)"""
import math
import os
import struct

RS, RO, BUMP = 0.12, 0.09, 0.008     # m
RIM = 0.02                           # m: the rim's width, outward and down
RINGS, SIDES = 18, 48


def point(r, phi):
    if r <= RO:
        z = RS - math.sqrt(RS * RS - r * r) + BUMP * math.sin(math.pi * r / RO) ** 2 * math.cos(3 * phi)
    else:  # the rim: a quarter circle turning down from the cap's edge
        z0 = RS - math.sqrt(RS * RS - RO * RO)
        z = z0 + 0.5 * RIM * math.sin(math.pi * (r - RO) / RIM)
    return (r * math.cos(phi), r * math.sin(phi), z)


def radius(i):
    """ring i of RINGS + 4 (the last 4 on the rim)"""
    return RO * i / RINGS if i <= RINGS else RO + RIM * (i - RINGS) / 4


triangles = []
for j in range(SIDES):
    # the last column shares the first one's points exactly (one closed surface)
    a0, a1 = 2 * math.pi * j / SIDES, 2 * math.pi * ((j + 1) % SIDES) / SIDES
    triangles.append((point(0, 0), point(radius(1), a0), point(radius(1), a1)))
    for i in range(1, RINGS + 4):
        p00, p01 = point(radius(i), a0), point(radius(i), a1)
        p10, p11 = point(radius(i + 1), a0), point(radius(i + 1), a1)
        triangles.append((p00, p10, p11))   # counter-clockwise seen from above
        triangles.append((p00, p11, p01))

out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mesh_bowl.stl")
with open(out, "wb") as f:
    f.write(b"mesh_bowl.stl: a bumpy bowl, written by make_bowl.py".ljust(80, b" "))
    f.write(struct.pack("<I", len(triangles)))
    for t in triangles:
        f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
        for p in t:
            f.write(struct.pack("<3f", *p))
        f.write(b"\0\0")
print(f"{out}: {len(triangles)} triangles")
