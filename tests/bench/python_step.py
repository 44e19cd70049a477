"""bench_api's Python side (not a test): the cost of Scene.step() per step.
usage: python3 python_step.py SCENE STEPS [section.key=value]...
Prints: us per step of Scene.step(), and of Scene.step() + state(), the
least of three stretches of STEPS / 3 (CPU time)."""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
import rodsim  # noqa: E402

scene, steps, sets = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
with rodsim.Scene(scene, overrides=sets) as s:
    for _ in range(min(steps, 200)):  # warm up: the scheme's first Jacobians
        s.step()
    best, best_state = float("inf"), float("inf")
    for _ in range(3):  # the least of three: a shared machine only adds
        t0 = time.process_time()
        for _ in range(steps // 3):
            s.step()
        t1 = time.process_time()
        for _ in range(steps // 30):
            s.step()
            s.state()
        t2 = time.process_time()
        best = min(best, (t1 - t0) / (steps // 3))
        best_state = min(best_state, (t2 - t1) / (steps // 30))
print("%.4f %.4f" % (1e6 * best, 1e6 * best_state))
