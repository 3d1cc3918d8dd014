#!/usr/bin/env bash
# Installs everything the tests need on a fresh Debian machine (Python 3.11, root, no display)
# and runs the whole suite: the default run, then the slow-marked checks.
set -euo pipefail
cd "$(dirname "$0")/.."
# OSMesa for off-screen rendering; Xvfb for the test that drives the real window (tests/test_app.py).
need=()
ldconfig -p | grep -q libOSMesa || need+=(libosmesa6)
command -v Xvfb >/dev/null || need+=(xvfb)
dpkg -s libglx-mesa0 >/dev/null 2>&1 || need+=(libglx-mesa0 libgl1-mesa-dri)     # GLX for the X11 window
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi
python3 -m pip install -q --disable-pip-version-check -e ".[test]"
export VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow
python3 -m pytest -q --durations=10
python3 -m pytest -q -m slow --durations=15
