"""The Python package's tests: the checkout's python/ first on the path, the
library from RODSIM_LIBRARY (tests/run_tests.sh sets it to the build's),
the binary from RODSIM_BIN (else build/release/rodsim)."""
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
os.environ.setdefault("RODSIM_LIBRARY", os.path.join(ROOT, "build", "release", "librodsim.so"))
RODSIM_BIN = os.environ.get("RODSIM_BIN", os.path.join(ROOT, "build", "release", "rodsim"))
