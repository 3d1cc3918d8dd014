#!/usr/bin/env bash
# Renders the pictures of docs/gallery.md (off-screen, standard tables): bash docs/make_gallery.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export VTK_DEFAULT_OPENGL_WINDOW=${VTK_DEFAULT_OPENGL_WINDOW:-vtkOSOpenGLRenderWindow}
out=docs/img/gallery
r() { python3 -m planetviz render --size 640x360 "$@"; }
r --atmosphere earth --view space --latitude 25 --longitude 15 --sun-elevation 55 --sun-azimuth 120 --screenshot $out/earth-orbit-day.png
r --atmosphere earth --view space --latitude 10 --longitude 40 --sun-elevation 0 --sun-azimuth 270 --screenshot $out/earth-orbit-terminator.png
r --atmosphere earth --view ground --altitude 4e5 --latitude 30 --heading 180 --pitch -17 --fov 40 --sun-elevation 25 --sun-azimuth 150 --screenshot $out/earth-limb.png
r --atmosphere earth --view ground --latitude 45 --heading 0 --pitch 25 --fov 90 --sun-elevation 60 --sun-azimuth 180 --screenshot $out/earth-ground-noon.png
r --atmosphere earth --view ground --latitude 45 --heading 270 --pitch 6 --fov 70 --sun-elevation 1 --sun-azimuth 270 --screenshot $out/earth-ground-sunset.png
r --atmosphere earth --view ground --latitude 45 --heading 270 --pitch 10 --fov 90 --sun-elevation -5 --sun-azimuth 270 --exposure 3e-3 --screenshot $out/earth-ground-twilight.png
r --atmosphere mars --view space --latitude -10 --longitude 0 --sun-elevation 40 --sun-azimuth 100 --exposure 2.3e-4 --screenshot $out/mars-orbit.png
r --atmosphere mars --view ground --heading 270 --pitch 6 --fov 70 --sun-elevation 3 --sun-azimuth 270 --exposure 4.6e-4 --screenshot $out/mars-ground-sunset.png
r --atmosphere exo-co2-thick --view ground --heading 180 --pitch 20 --fov 90 --sun-elevation 40 --sun-azimuth 180 --screenshot $out/exo-co2-thick-ground.png
r --atmosphere exo-mdwarf --view space --latitude 0 --longitude 0 --sun-elevation 10 --sun-azimuth 90 --screenshot $out/exo-mdwarf-orbit.png
r --method quick --view ground --latitude 45 --heading 270 --pitch 6 --fov 70 --sun-elevation 1 --sun-azimuth 270 --screenshot $out/earth-quick-sunset.png
