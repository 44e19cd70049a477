"""python/README.md's examples run as printed: every ```python block is
executed from the repository's root; the several-rods example's force on
the short rod's pinned tip is its weight, rho A L g straight down."""
import math
import os
import re

import pytest

from conftest import ROOT

README = os.path.join(ROOT, "python", "README.md")


def blocks():
    with open(README) as f:
        return re.findall(r"```python\n(.*?)```", f.read(), re.S)


def test_readme_has_examples():
    assert len(blocks()) >= 1


@pytest.mark.parametrize("index", range(len(blocks())))
def test_readme_block_runs(index, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    namespace = {}
    exec(compile(blocks()[index], "python/README.md block %d" % index, "exec"), namespace)
    if "TWO_RODS" in namespace:
        weight = 1000 * math.pi * 0.001 ** 2 / 4 * 0.1 * 9.81  # rho A L g, N
        force = namespace["force"]
        assert force[2] == pytest.approx(-weight, rel=1e-3)
        assert abs(force[0]) < 1e-6 * weight and abs(force[1]) < 1e-6 * weight
        assert "['short', 'long']" in capsys.readouterr().out
