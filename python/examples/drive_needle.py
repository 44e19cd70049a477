#!/usr/bin/env python3
"""A needle driven from Python: a suture thread (0.3 m, 0.5 mm) hangs from a
curved needle held at its tip (clamped); Python moves the needle along a
path at 100 Hz, a haptic device's rate: up 5 cm, across 5 cm and back,
then held while the thread settles. Each step's force the thread exerts on
the needle goes to OUT/drive_needle.csv (t, x, y, z m, fx, fy, fz N) and is
plotted to OUT/drive_needle.png; at rest it is the thread's weight,
rho A L g, straight down.

    python3 python/examples/drive_needle.py [--out DIR] [--video]
"""
import argparse
import csv
import math
import os

import numpy as np

import rodsim

# needle_lift.ini's thread, its tip held by the needle and driven from here
SCENE = """
[rod]
length = 0.3
diameter = 0.0005
density = 850
youngs_modulus = 87.5e6
shear_modulus = 31.25e6
nodes = 61
origin = 0 0 0
direction = 0 0 1
[ends]
root = free
tip = clamped
needle = 0.01
[solver]
scheme = implicit
dt = 0.001
duration = 8
[loads]
gravity = 0 0 -9.81
linear_damping = 2e-3
[render]
fps = 30
view = 0.6 -1 0.4
title = A needle driven from Python
"""


def needle_path(t):
    """The needle's tip, m: up 5 cm in the first second, across 5 cm and
    back by 3 s (smooth), then held."""
    s = min(t, 1.0)
    z = 0.3 + 0.05 * (3 * s * s - 2 * s ** 3)
    x = 0.05 * math.sin(math.pi * (t - 1.0) / 2.0) ** 2 if 1.0 <= t <= 3.0 else 0.0
    return np.array([x, 0.0, z])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/python", help="output directory")
    ap.add_argument("--video", action="store_true", help="also OUT/needle.mp4 and .png")
    ap.add_argument("--rate", type=float, default=100.0, help="poses per second (Hz)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    h = 1.0 / args.rate
    rows = []
    with rodsim.Scene(SCENE, name="needle") as s:
        steps = int(round(s.duration / h))
        for k in range(1, steps + 1):
            p = needle_path(k * h)
            s.set_end_pose("tip", p, rotvec=(0.0, 0.0, 0.0))
            s.step(h)
            force, _ = s.end_load("tip")
            rows.append([s.t, *p, *force])
        weight = 850 * math.pi * 0.0005 ** 2 / 4 * 0.3 * 9.81  # rho A L g, N
        if args.video:
            s.render(args.out)
    csv_path = os.path.join(args.out, "drive_needle.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "x", "y", "z", "fx", "fy", "fz"])
        w.writerows([["%.10g" % v for v in r] for r in rows])
    data = np.array(rows)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=100)
    for col, name in ((4, "fx"), (6, "fz")):
        ax.plot(data[:, 0], 1e3 * data[:, col], label=name)
    ax.axhline(-1e3 * weight, color="gray", ls="--", lw=1,
               label="-rho A L g = %.3f mN" % (-1e3 * weight))
    ax.axvspan(0, 3, color="0.93", zorder=0)
    ax.text(1.5, -0.25, "needle moving", ha="center", color="0.4")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("force of the thread on the needle (mN)")
    ax.set_title("A suture thread hanging from a needle driven at %g Hz" % args.rate)
    ax.legend(loc="center right")
    fig.tight_layout()
    png = os.path.join(args.out, "drive_needle.png")
    fig.savefig(png)
    print("wrote %s and %s (%d poses); at rest fz = %.6g N, -rho A L g = %.6g N"
          % (csv_path, png, len(rows), data[-1, 6], -weight))


if __name__ == "__main__":
    main()
