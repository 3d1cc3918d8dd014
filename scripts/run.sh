#!/usr/bin/env bash
# Installs planetviz on a fresh Debian machine (Python 3.11, root, no display) and runs the main job:
# the default Earth sky, printed (radiance toward six directions and its colour).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install -q --disable-pip-version-check -e .
planetviz sky "$@"
