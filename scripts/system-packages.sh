#!/usr/bin/env bash
# Installs the Debian packages that the named parts need, where missing (run as root; a no-op when all are there):
#   osmesa  off-screen rendering (OSMesa)
#   qt      the Qt window's xcb platform plugin and its OpenGL (PySide6's wheels need these system libraries)
#   x11     Xvfb and Mesa's GLX, for tests that open real windows on a virtual display
# Usage: bash scripts/system-packages.sh osmesa qt x11
set -euo pipefail
need=()
want() { dpkg -s "$1" >/dev/null 2>&1 || need+=("$1"); }
for part in "$@"; do
  case "$part" in
    osmesa) ldconfig -p | grep -q libOSMesa || need+=(libosmesa6) ;;
    qt) for p in libxcb-cursor0 libxkbcommon-x11-0 libxcb-icccm4 libxcb-keysyms1 libxcb-image0 libxcb-render-util0 \
                 libxcb-shape0 libxcb-xinerama0 libxcb-randr0 libegl1 libdbus-1-3 libfontconfig1; do want "$p"; done ;;
    x11) command -v Xvfb >/dev/null || need+=(xvfb); want libglx-mesa0; want libgl1-mesa-dri ;;
    *) echo "system-packages.sh: unknown part $part (osmesa, qt, x11)" >&2; exit 2 ;;
  esac
done
if [ ${#need[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi
