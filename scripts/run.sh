#!/usr/bin/env bash
# Installs planetviz on a fresh Debian machine (Python 3.11, root, no display) and runs the main job: the
# default scene (Earth from orbit, standard tables) rendered off-screen to planetviz.png in the current folder,
# and the default Earth sky printed (radiance toward six directions and its colour). Extra arguments go to app.py.
set -euo pipefail
here="$PWD"
cd "$(dirname "$0")/.."
if ! ldconfig -p | grep -q libOSMesa; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libosmesa6 >/dev/null
fi
python3 -m pip install -q --disable-pip-version-check -e .
export VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow
python3 app.py --size 1280x720 --screenshot "$here/planetviz.png" "$@"
planetviz sky
