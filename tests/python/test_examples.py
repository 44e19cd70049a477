"""The examples run and their outputs hold: drive_needle's CSV ends at the
thread's weight (rho A L g, straight down) and its plot is a PNG; batch's
loads in parallel give what one process gives, and small loads the linear
cantilever's F L^3 / (3 EI)."""
import csv
import math
import os
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = os.path.join(ROOT, "python", "examples")


def run_example(name, out):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, name), "--out", str(out)],
                          env=env, check=True, capture_output=True, text=True).stdout


def test_drive_needle(tmp_path):
    run_example("drive_needle.py", tmp_path)
    png = (tmp_path / "drive_needle.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000
    with open(tmp_path / "drive_needle.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 800 and float(rows[-1]["t"]) == pytest.approx(8.0)
    weight = 850 * math.pi * 0.0005 ** 2 / 4 * 0.3 * 9.81  # rho A L g, N
    last = rows[-1]
    assert float(last["fz"]) == pytest.approx(-weight, rel=1e-4)
    assert abs(float(last["fx"])) < 1e-4 * weight and abs(float(last["fy"])) < 1e-4 * weight
    # while the needle lifts, the thread pulls harder than its weight
    assert min(float(r["fz"]) for r in rows[:100]) < -1.05 * weight


def test_batch(tmp_path):
    run_example("batch.py", tmp_path)
    sys.path.insert(0, EXAMPLES)
    import batch
    with open(tmp_path / "batch.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(batch.FORCES)
    for r in rows:
        force, y, linear = float(r["force"]), float(r["deflection"]), float(r["linear"])
        EI = 87.5e6 * math.pi * 0.001 ** 4 / 64
        assert linear == pytest.approx(force / (3 * EI), rel=1e-9)
        if force <= 5e-8:  # small loads: linear, to the grid's O(ds^2) (NS = 51)
            assert y == pytest.approx(linear, rel=3e-4)
        assert "%.10g" % batch.deflection(force) == r["deflection"]
