#!/usr/bin/env bash
# Installs everything the tests need on a fresh Debian machine (Python 3.11, root, no display)
# and runs the whole suite: the default run, then the slow-marked checks.
set -euo pipefail
cd "$(dirname "$0")/.."
# OSMesa for off-screen rendering; Qt's system libraries, Xvfb and GLX for the tests that drive the real windows
# (tests/test_app.py).
bash scripts/system-packages.sh osmesa qt x11
python3 -m pip install -q --disable-pip-version-check -e ".[test]"
export VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow
# Two worker processes (pytest-xdist), a module's tests on one worker so that its fixtures are made once; the
# workers share the run's table cache (tests/conftest.py). The slow run hands out the modules in the order
# tests/conftest.py gives them, the longest first.
python3 -m pytest -q -n 2 --dist loadscope --durations=10
python3 -m pytest -q -n 2 --dist loadscope --no-loadscope-reorder -m slow --durations=15
