#!/usr/bin/env bash
# Installs planetviz on a fresh Debian machine (Python 3.11, root, no display) and runs the main job: the
# default scene (Earth from orbit, standard tables) rendered off-screen to planetviz.png in the current folder,
# and the default Earth sky printed (radiance toward six directions and its colour). Extra arguments go to app.py.
# It also installs the Qt window's packages, so that python app.py opens it on a desktop.
set -euo pipefail
here="$PWD"
cd "$(dirname "$0")/.."
bash scripts/system-packages.sh osmesa qt           # qt: what the desktop window (python app.py) needs
python3 -m pip install -q --disable-pip-version-check -e ".[app]"
export VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow
python3 app.py --size 1280x720 --screenshot "$here/planetviz.png" "$@"
planetviz sky
