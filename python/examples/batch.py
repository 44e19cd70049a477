#!/usr/bin/env python3
"""A small study in parallel: the thesis' cantilever (scenes/impulse.ini's
rod, 1 m, EI = 4.295e-6 N m^2) under a dead tip load F, solved by the
static scheme, one process per load (multiprocessing). Prints and writes
OUT/batch.csv: F (N), the tip's deflection (m), and F L^3 / (3 EI), the
small-load (linear) answer it approaches.

    python3 python/examples/batch.py [--out DIR] [--jobs N]
"""
import argparse
import math
import multiprocessing
import os

import rodsim

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "scenes", "impulse.ini")
FORCES = [1e-8, 2e-8, 5e-8, 1e-7, 2e-7, 5e-7, 1e-6, 2e-6]  # N


def deflection(force):
    """One scene, in its own process: the tip's deflection (m) under force (N)."""
    overrides = {"solver.scheme": "static", "solver.dt": "auto", "solver.duration": 1,
                 "tip.frame": "global", "tip.force": [0, force, 0], "tip.moment": [0, 0, 0],
                 "tip.profile": "step"}
    with rodsim.Scene(SCENE, overrides=overrides) as s:
        s.run()
        return float(s.state()["positions"][-1, 1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/python", help="output directory")
    ap.add_argument("--jobs", type=int, default=os.cpu_count(), help="processes")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with multiprocessing.Pool(args.jobs) as pool:
        results = pool.map(deflection, FORCES)
    EI = 87.5e6 * math.pi * 0.001 ** 4 / 64  # N m^2
    path = os.path.join(args.out, "batch.csv")
    with open(path, "w") as f:
        f.write("force,deflection,linear\n")
        for force, y in zip(FORCES, results):
            linear = force * 1.0 ** 3 / (3 * EI)
            f.write("%.10g,%.10g,%.10g\n" % (force, y, linear))
            print("F = %-7g N  tip deflection %.6g m  (linear F L^3/3EI: %.6g m)"
                  % (force, y, linear))
    print("wrote", path)


if __name__ == "__main__":
    main()
