"""What reading the 4D tables per vertex (``Scene(shading="vertex")``) costs in accuracy: the same frames drawn
per pixel and per vertex, compared in CIE Y (``render_hdr``, linear sRGB, the sun's disc left out) in each view
class of :data:`planetviz.validation.pictures.VIEWS`.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/vertex_accuracy.py \\
        [--size 1280x720] [--presets earth mars exo-co2-thick]

Prints, per atmosphere and view, the RMS and the 99th percentile of the per-vertex frame's difference from the
per-pixel frame relative to the per-pixel value floored at 1% of the frame's 99th percentile
(:func:`~planetviz.validation.pictures.floored_difference`), over the whole frame and over the ground's and the
sky's pixels apart (a ground pixel is one whose ray meets the planet).
"""
import argparse
import os

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.model.geometry import distance_to_ground  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.validation.pictures import VIEWS, floored_difference, view_luminance  # noqa: E402


def frames(preset, size, quality):
    """{view: (per-pixel Y, per-vertex Y, ground mask)}"""
    out = {}
    scenes = {s: Scene(preset, quality=quality, surface="texture", off_screen=True, window_size=size, shading=s)
              for s in ("pixel", "vertex")}
    try:
        for name, view in VIEWS.items():
            images = {shading: view_luminance(scene, view) for shading, scene in scenes.items()}
            scene = scenes["pixel"]
            rows, cols = np.indices(images["pixel"].shape)
            dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
            ground = np.isfinite(distance_to_ground(np.tile(scene.camera_location, (len(dirs), 1)), dirs,
                                                    scene.atmosphere.bottom_radius_m)).reshape(rows.shape)
            out[name] = (images["pixel"], images["vertex"], ground)
    finally:
        for scene in scenes.values():
            scene.close()
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--quality", default="standard")
    ap.add_argument("--presets", nargs="+", default=["earth", "mars", "exo-co2-thick"])
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print(f"{args.size}, {args.quality} tables: difference of per-vertex from per-pixel CIE Y, relative to the "
          "per-pixel value floored at 1% of the frame's 99th percentile")
    print("| atmosphere | view | RMS | p99 | ground RMS | ground p99 | sky RMS | sky p99 |")
    print("|---|---|---|---|---|---|---|---|")
    for preset in args.presets:
        for name, (pixel, vertex, ground) in frames(preset, size, args.quality).items():
            rel = floored_difference(vertex, pixel)
            cells = []
            for mask in (np.ones_like(ground), ground, ~ground):
                r = rel[mask]
                cells += ([f"{np.sqrt(np.mean(r ** 2)):.4f}", f"{np.percentile(r, 99):.4f}"] if r.size
                          else ["-", "-"])
            print(f"| {preset} | {name} | {' | '.join(cells)} |", flush=True)


if __name__ == "__main__":
    main()
