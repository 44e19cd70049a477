"""rodsim.Scene against `rodsim run` and `rodsim live` (the same scene, the
same numbers), and against independent values."""
import math
import os
import subprocess

import numpy as np
import pytest

import rodsim
from conftest import ROOT, RODSIM_BIN

IMPULSE = os.path.join(ROOT, "scenes", "impulse.ini")
HANGING = """
[rod]
length = 0.3
diameter = 0.0005
density = 850
youngs_modulus = 87.5e6
shear_modulus = 31.25e6
nodes = 31
origin = 0 0 0
direction = 0 0 1
[ends]
root = free
tip = clamped
[solver]
scheme = implicit
dt = 0.002
duration = 4
[loads]
gravity = 0 0 -9.81
linear_damping = 2e-3
"""


def test_same_as_rodsim_run_csv(tmp_path):
    """The CSV of `rodsim run` (shortest texts that read back exactly) and
    the state read through Python are the same doubles at every output
    frame (t, x, y, z, d3, n)."""
    csv = tmp_path / "run.csv"
    subprocess.run([RODSIM_BIN, "run", IMPULSE, "--set", "solver.duration=0.2", "--no-video",
                    "--quiet", "--csv", str(csv)], check=True)
    rows = [line.split(",") for line in csv.read_text().splitlines()[1:]]
    with rodsim.Scene(IMPULSE, overrides={"solver.duration": 0.2}) as s:
        differ = 0
        frames = len(rows) // s.nodes
        for k in range(frames):
            if k:
                s.run(k / s.frame_rate)
            st = s.state()
            for i in range(s.nodes):
                r = rows[k * s.nodes + i]
                mine = [float(st["t"])] + [float(v) for v in st["positions"][i]] + \
                       [float(v) for v in st["directors"][i, 2]] + \
                       [float(v) + 0.0 for v in st["forces"][i]]
                theirs = [float(x) for x in [r[0]] + r[3:6] + r[6:9] + r[10:13]]
                differ += mine != theirs
    assert frames == 7 and differ == 0, "%d of %d rows differ" % (differ, len(rows))


def test_same_as_rodsim_live(tmp_path):
    """`rodsim live` driven along a path and Python driving the same tip along
    the same poses answer the same end force, to round-off (live renews its
    Jacobian between lines: the same to Newton's tolerance)."""
    scene = tmp_path / "hanging.ini"
    scene.write_text(HANGING)
    poses = []
    for k in range(1, 101):
        t = k * 0.01
        poses.append((t, 0.02 * math.sin(3 * t), 0.0, 0.3 + 0.01 * t, 0.0, 0.0, 0.1 * t))
    lines = "".join(",".join("%.17g" % v for v in p) + "\n" for p in poses)
    out = subprocess.run([RODSIM_BIN, "live", str(scene)], input=lines, capture_output=True,
                         text=True, check=True).stdout.splitlines()
    answers = [line.split(",") for line in out[1:]]
    assert len(answers) == len(poses) and all(a[7] == "ok" for a in answers)
    worst = 0.0
    with rodsim.Scene(str(scene)) as s:
        for p, a in zip(poses, answers):
            s.set_end_pose("tip", p[1:4], rotvec=p[4:7])
            s.step(p[0] - s.t)
            f, m = s.end_load("tip")
            live = np.array([float(v) for v in a[1:7]])
            mine = np.concatenate([f, m])
            assert float(a[0]) == pytest.approx(s.t, abs=1e-15)
            worst = max(worst, np.max(np.abs(mine - live)) / np.max(np.abs(live)))
    print("largest difference of the end loads, relative to the largest: %.3g" % worst)
    assert worst < 1e-9


def test_save_restore_exact():
    with rodsim.Scene(HANGING) as s:
        for k in range(50):
            s.set_end_pose("tip", (0.01 * math.sin(0.1 * k), 0, 0.3), rotvec=(0, 0, 0))
            s.step(0.01)
        blob = s.save()
        for k in range(30):
            s.step(0.01)
        a = s.state()
        s.restore(blob)
        assert s.t == pytest.approx(0.5, abs=1e-15)
        for k in range(30):
            s.step(0.01)
        b = s.state()
    for key in a:
        assert np.array_equal(a[key], b[key]), key


def test_bad_scene_message_is_the_cli_s(tmp_path):
    scene = tmp_path / "bad.ini"
    scene.write_text(HANGING.replace("nodes = 31", "nodes = 2"))
    cli = subprocess.run([RODSIM_BIN, "run", str(scene), "--no-video"], capture_output=True,
                         text=True)
    with pytest.raises(rodsim.Error) as e:
        rodsim.Scene(str(scene))
    assert cli.returncode == 2 and e.value.status == "bad_input"
    assert cli.stderr == "rodsim run: %s\n" % e.value


def refused_as_by_run(scene):
    """rodsim.Scene refuses SCENE (bad_input) with the words `rodsim run`
    prints after "rodsim run: " as it exits 2; returns them."""
    cli = subprocess.run([RODSIM_BIN, "run", str(scene), "--no-video", "--quiet"],
                         capture_output=True, text=True)
    with pytest.raises(rodsim.Error) as e:
        rodsim.Scene(scene)
    assert cli.returncode == 2 and e.value.status == "bad_input"
    assert "rodsim run: %s\n" % e.value in cli.stderr
    return str(e.value)


def test_instruments_through_each_other(tmp_path):
    """Two straight 12 cm forceps crossing at right angles 3 mm apart: their
    shanks overlap by 2 r_jaw + 2 r_shank - h = 2.4 + 2.88 - 3 = 2.28 mm (by
    hand): refused with `rodsim run`'s message, loaded with may_overlap."""
    (tmp_path / "lower.csv").write_text("t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n"
                                        "1,0,0,0,0,0,0,0\n")
    (tmp_path / "upper.csv").write_text("t,x,y,z,rx,ry,rz,jaw\n"
                                        "0,-0.05,0.05,0.003,0,0,1.5707963267948966,0\n"
                                        "1,-0.05,0.05,0.003,0,0,1.5707963267948966,0\n")
    scene = tmp_path / "through.ini"
    scene.write_text(HANGING.replace("duration = 4", "duration = 0.01") +
                     "[instrument]\nkind = forceps\nname = lower\npath = lower.csv\n"
                     "size = 0.12\n[instrument]\nkind = forceps\nname = upper\n"
                     "path = upper.csv\nsize = 0.12\n")
    message = refused_as_by_run(scene)
    assert "the forceps' shank and the forceps' shank overlap by 2.28 mm at t = 0.000 s" \
        in message
    with rodsim.Scene(scene, overrides={"instrument.upper.may_overlap": "yes"}) as s:
        assert s.nodes == 31


def test_jaws_into_a_rigid_pad(tmp_path):
    """Forceps pointing down driven 4 mm under a rigid pad's top: the open
    tines' round ends 4.87 mm deep, over max_depth (2 jaw radii, 2.40 mm):
    refused with `rodsim run`'s message, loaded with max_depth = 6 mm."""
    rv = "1.2091996,1.2091996,-1.2091996"
    (tmp_path / "deep.csv").write_text("t,x,y,z,rx,ry,rz,jaw\n0,0,0,0.03,%s,1\n"
                                       "0.5,0,0,-0.004,%s,1\n" % (rv, rv))
    scene = tmp_path / "pad.ini"
    scene.write_text("[rod]\nlength = 0.1\ndiameter = 0.0005\ndensity = 850\n"
                     "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 11\n"
                     "origin = -0.05 0.02 0.00025\ndirection = 1 0 0\n[surface]\nshape = box\n"
                     "center = 0 0 -0.005\nsize = 0.2 0.2 0.01\n[instrument]\nkind = forceps\n"
                     "path = deep.csv\nsize = 0.12\n[solver]\nscheme = implicit\n"
                     "duration = 0.6\n[loads]\ngravity = 0 0 -9.81\n")
    message = refused_as_by_run(scene)
    assert "the forceps' jaws 4.87 mm into the rigid" in message
    assert "max_depth = 2.40 mm" in message
    with rodsim.Scene(scene, overrides={"instrument.max_depth": 0.006}) as s:
        assert s.nodes == 11


def test_overrides_and_state_shapes():
    with rodsim.Scene(HANGING, overrides={"rod.nodes": 11, "solver.dt": 0.004}) as s:
        assert s.nodes == 11 and s.dt == 0.004
        st = s.state()
        assert st["positions"].shape == (11, 3) and st["directors"].shape == (11, 3, 3)
        # a straight thread along +z: d3 = z, positions 3 cm apart
        assert np.allclose(st["directors"][:, 2], [0, 0, 1])
        assert np.allclose(np.diff(st["positions"][:, 2]), 0.03)
        s.step()
        assert s.t == 0.004
    with pytest.raises(rodsim.Error, match="closed"):
        s.step()


def test_tip_load_is_a_dead_load():
    """A free tip loaded from Python steps as the scene's own tip.force."""
    sets = {"tip.frame": "global", "tip.moment": "0 0 0", "solver.duration": 0.1}
    with rodsim.Scene(IMPULSE, overrides=dict(sets, **{"tip.force": "0 0 1e-4",
                                                       "tip.profile": "step"})) as a, \
            rodsim.Scene(IMPULSE, overrides=sets) as b:
        b.set_tip_load((0, 0, 1e-4))
        a.run()
        b.run()
        assert np.array_equal(a.positions(), b.positions())


def test_render(tmp_path):
    with rodsim.Scene(IMPULSE, overrides={"solver.duration": 0.1, "render.width": 320,
                                          "render.height": 240}) as s:
        s.run()
        s.render(tmp_path)
    mp4, png = tmp_path / "impulse.mp4", tmp_path / "impulse.png"
    assert mp4.stat().st_size > 1000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_library_exports_only_the_api():
    syms = subprocess.run(["nm", "-D", "--defined-only", rodsim.library_path],
                          capture_output=True, text=True, check=True).stdout.split()
    names = [s.split("@")[0] for s in syms if s[0].isalpha() and "@" in s]
    assert names and all(n.startswith("rodsim_") or n == "RODSIM_1" for n in names), names


def test_pip_install_offline(tmp_path):
    """pip install ./python works offline with Debian's setuptools (a venv
    that sees the system's numpy, --no-build-isolation --no-index); the
    installed package finds the library through RODSIM_LIBRARY."""
    import shutil
    import sys
    src = tmp_path / "python"
    shutil.copytree(os.path.join(ROOT, "python"), src,
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    pip = subprocess.run([str(venv / "bin" / "pip"), "install", "-q", "--no-build-isolation",
                          "--no-index", str(src)], capture_output=True, text=True)
    assert pip.returncode == 0, pip.stderr
    probe = subprocess.run([str(venv / "bin" / "python"), "-c",
                            "import rodsim; s = rodsim.Scene(%r); s.step(); "
                            "print(rodsim.__file__, s.t)" % IMPULSE],
                           capture_output=True, text=True, cwd=str(tmp_path),
                           env=dict(os.environ, PYTHONPATH=""))
    assert probe.returncode == 0, probe.stderr
    where, t = probe.stdout.split()
    assert where.startswith(str(venv)) and float(t) == 0.0005


HANGING_RODS = """
[rod short]
length = 0.3
diameter = 0.002
density = 1000
youngs_modulus = 1e8
shear_modulus = 4e7
nodes = 16
origin = 0 0 -0.3
direction = 0 0 1
[ends short]
root = free
tip = pinned
[rod long]
length = 0.5
diameter = 0.002
density = 1000
youngs_modulus = 1e8
shear_modulus = 4e7
nodes = 26
origin = 0.2 0 -0.5
direction = 0 0 1
[ends long]
root = free
tip = pinned
[solver]
scheme = implicit
dt = 0.001
duration = 0.5
[loads]
gravity = 0 0 -9.81
linear_damping = 0.03
"""


def test_several_rods_hang_with_their_weights():
    """Two named rods, each hanging from its own pinned tip, each tip driven
    by set_end_pose(rod=NAME) to a pose of its own and held: at rest each
    holder carries that rod's weight rho A g L (a closed form), each tip node
    is where it was driven, and state(rod=NAME) has that rod's nodes."""
    goal = {"short": np.array([0.01, 0.0, 0.02]), "long": np.array([0.2, -0.015, 0.01])}
    start = {"short": np.zeros(3), "long": np.array([0.2, 0.0, 0.0])}
    length = {"short": 0.3, "long": 0.5}
    with rodsim.Scene(HANGING_RODS, name="hanging_rods") as s:
        assert s.rods == ["short", "long"]
        for i in range(1, 501):  # 0.2 s to the goal, then held to t = 5 s
            f = min(1.0, i / 20.0)
            for rod in s.rods:
                s.set_end_pose("tip", start[rod] + f * (goal[rod] - start[rod]), rod=rod)
            s.step(0.01)
        for rod in s.rods:
            st = s.state(rod=rod)
            weight = 1000 * math.pi * 0.001 ** 2 * 9.81 * length[rod]  # rho A g L, N
            fz = -st["tip_force"][2]
            print("rod %s: -fz %.12g N, rho A g L %.12g N, error %.2g"
                  % (rod, fz, weight, abs(fz - weight) / weight))
            assert abs(fz - weight) <= 1e-6 * weight
            assert np.hypot(*st["tip_force"][:2]) <= 1e-6 * weight
            assert st["positions"].shape == ({"short": 16, "long": 26}[rod], 3)
            assert np.max(np.abs(st["positions"][-1] - goal[rod])) <= 1e-12
            force, _ = s.end_load("tip", rod=rod)
            assert np.array_equal(force, st["tip_force"])
        # the calls without a rod address the first
        assert np.array_equal(s.positions(), s.positions(rod="short"))
        with pytest.raises(rodsim.Error) as e:
            s.state(rod="middle")
        assert e.value.status == "bad_input"
        assert "no rod named 'middle'" in str(e.value) and "its rods: short, long" in str(e.value)
        # save and restore hold every rod: stepping on from a restore
        # repeats stepping on from the save, to the bit
        blob = s.save()
        for _ in range(5):
            s.step(0.01)
        a = {rod: s.state(rod=rod) for rod in s.rods}
        s.restore(blob)
        for _ in range(5):
            s.step(0.01)
        for rod in s.rods:
            b = s.state(rod=rod)
            for key in a[rod]:
                assert np.array_equal(a[rod][key], b[key]), (rod, key)


def test_one_rod_is_named_rod():
    with rodsim.Scene(HANGING) as s:
        assert s.rods == ["rod"]
        assert np.array_equal(s.state(rod="rod")["positions"], s.state()["positions"])


def test_several_rods_same_as_rodsim_run(tmp_path):
    """scenes/crossing.ini (two ropes in contact) run to 0.3 s through Python
    and by `rodsim run`: each rod's tip and tip force bit for bit (the JSON
    summary prints the shortest text that reads back exactly)."""
    import json
    crossing = os.path.join(ROOT, "scenes", "crossing.ini")
    summary = tmp_path / "s.json"
    subprocess.run([RODSIM_BIN, "run", crossing, "--no-video", "--quiet", "--summary",
                    str(summary), "--set", "solver.duration=0.3"], check=True,
                   cwd=tmp_path, capture_output=True)
    rods = json.loads(summary.read_text())["rods"]
    with rodsim.Scene(crossing, overrides={"solver.duration": 0.3}) as s:
        s.run()
        assert s.rods == [r["name"] for r in rods]
        for r in rods:
            st = s.state(rod=r["name"])
            assert list(st["positions"][-1]) == r["tip"], r["name"]
