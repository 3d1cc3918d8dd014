"""Time of a dome master through the renderer (a cube of faces read per vertex, resampled) against the NumPy
evaluator per pixel, and the difference between the two.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/dome_timing.py [--sizes 4096 8192]
                                                                                     [--numpy-up-to 4096]

From the ground (Earth, standard tables, the sun 10 deg up), in one process after a first frame: per size, the
seconds to the radiance of every pixel (directions, faces, resampling) and to the 8-bit picture (colour and tone
mapping), for each method; then the RMS and 99th percentile of the relative difference between the methods away
from the horizon (0.5 deg either side), where both are computed.
"""
import argparse
import os
import time

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.model.color import display_colour, linear_srgb  # noqa: E402
from planetviz.model.geometry import local_frame, site_of  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.render.cube_faces import render_directions  # noqa: E402
from planetviz.tables.panorama import fisheye_directions  # noqa: E402
from planetviz.tables.panorama import render_directions as evaluator_directions  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[4096, 8192])
    ap.add_argument("--numpy-up-to", type=int, default=4096)
    args = ap.parse_args()
    scene = Scene("earth", quality="standard", off_screen=True, window_size=(320, 200))
    scene.view_from_ground(latitude=45, heading=0, pitch=10)
    scene.set_sun(elevation=10, azimuth=120, latitude=45, longitude=0)
    scene.settings.show_sun = False          # the evaluator draws no sun disc: compare the skies
    scene.screenshot()
    cam = scene.camera_location
    print("| size | method | radiance [s] | picture [s] |")
    print("|---|---|---|---|")
    notes = []
    for size in args.sizes:
        results = {}
        for method in ("render", "numpy") if size <= args.numpy_up_to else ("render",):
            t0 = time.perf_counter()
            dirs = fisheye_directions(cam, size)
            if method == "render":
                radiance = render_directions(scene, dirs, size // 2)
            else:
                radiance = evaluator_directions(scene.planet.tables, scene.atmosphere, cam, dirs, scene.sun_direction)
            t1 = time.perf_counter()
            np.round(display_colour(linear_srgb(radiance, scene.atmosphere), 1e-4, "exponential") * 255).astype(np.uint8)
            t2 = time.perf_counter()
            print(f"| {size} | {method} | {t1 - t0:.1f} | {t2 - t0:.1f} |", flush=True)
            results[method] = radiance
        if len(results) == 2:
            ok = np.all(np.isfinite(dirs), axis=-1)
            up = local_frame(*site_of(cam))[0]
            away = np.abs(np.degrees(np.arcsin(np.clip(dirs[ok] @ up, -1, 1)))) > 0.5
            want = results["numpy"][ok][away]
            rel = np.abs(results["render"][ok][away] - want) / np.maximum(want, 1e-30)
            notes.append(f"{size}: render against numpy away from the horizon: RMS {100 * np.sqrt(np.mean(rel ** 2)):.2f}%, "
                         f"p99 {100 * np.percentile(rel, 99):.2f}%")
        del results
    print("\n".join(notes))
    scene.close()


if __name__ == "__main__":
    main()
