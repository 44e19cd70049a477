"""rodsim.Scene on a graded grid (rod.refine): the nodes' arc lengths are
the grid's, against its formula and `rodsim run`'s CSV."""
import subprocess

import numpy as np

import rodsim
from conftest import RODSIM_BIN

NODES = 81
GRADED = """
[rod]
length = 1.0
diameter = 0.01
density = 850
youngs_modulus = 87.5e6
shear_modulus = 31.25e6
nodes = 81
self_contact = no
refine = 0.3 0.5 4
direction = 1 0 0
[loads]
gravity = 0 0 -9.81
[solver]
duration = 0.1
"""


def graded_arc(i):
    """refine = 0.3 0.5 4 on L = 1 m: the nodes equally spaced in the
    stretched arc S(s) = s + 3 |[0.3, 0.5] below s| (S(L) = 1.6 m)."""
    stretched = i * 1.6 / (NODES - 1)
    if stretched <= 0.3:
        return stretched
    if stretched <= 1.1:
        return 0.3 + (stretched - 0.3) / 4.0
    return 0.5 + (stretched - 1.1)


def test_graded_arc(tmp_path):
    """A graded scene loads and steps; arc() and state()["arc"] are the
    grid's formula's s_i (not i L / (NS - 1)) and the CSV's s column."""
    want = np.array([graded_arc(i) for i in range(NODES)])
    with rodsim.Scene(GRADED) as s:
        s.run()
        arc = s.arc()
        st = s.state()
    err = np.max(np.abs(arc - want))
    print("arc: largest difference from the formula %.3e m; node 40: %.6f m (i L/(NS-1) = 0.5)"
          % (err, arc[40]))
    assert err < 1e-12
    assert abs(arc[40] - 0.425) < 1e-12
    assert np.array_equal(st["arc"], arc)
    scene = tmp_path / "graded.ini"
    scene.write_text(GRADED)
    csv = subprocess.run([RODSIM_BIN, "run", str(scene), "-o", str(tmp_path / "out"),
                          "--no-video", "--csv", "-"], check=True, capture_output=True,
                         text=True).stdout.splitlines()
    header = csv[0].split(",")
    rows = [r.split(",") for r in csv[1:]]
    last_t = rows[-1][header.index("t")]
    s_col = [float(r[header.index("s")]) for r in rows if r[header.index("t")] == last_t]
    assert len(s_col) == NODES
    csv_err = np.max(np.abs(np.array(s_col) - arc))
    print("arc against the CSV's s: largest difference %.3e m" % csv_err)
    assert csv_err == 0.0  # the CSV prints shortest round-trip decimals
