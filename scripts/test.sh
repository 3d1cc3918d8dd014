#!/usr/bin/env bash
# Installs everything the tests need on a fresh Debian machine (Python 3.11, root, no display)
# and runs the whole suite: the default run, then the slow-marked checks.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! ldconfig -p | grep -q libOSMesa; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libosmesa6 >/dev/null
fi
python3 -m pip install -q --disable-pip-version-check -e ".[test]"
export VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow
python3 -m pytest -q
python3 -m pytest -q -m slow
