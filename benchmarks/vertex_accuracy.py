"""What reading the 4D tables per vertex (``Scene(shading="vertex")``) costs in accuracy: the same frames drawn
per pixel and per vertex, compared in CIE Y (``render_hdr``, linear sRGB), over the pixels above 1e-3 of the
frame's 99th percentile, the sun's disc left out.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/vertex_accuracy.py [--size 1280x720]

Prints, per view, the RMS, 99th percentile and largest relative difference, over all lit pixels and over the
ground's and the sky's separately (a ground pixel is one whose ray meets the planet).
"""
import argparse
import os

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.model.geometry import distance_to_ground  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.validation.pictures import view_luminance  # noqa: E402

#: name: (camera call, its keywords, sun keywords)
VIEWS = {
    "ground, sun 10 deg": ("view_from_ground", dict(latitude=45, heading=90, pitch=5), dict(elevation=10, azimuth=100)),
    "ground, sunset (sun 1 deg, looking 2 deg down)":
        ("view_from_ground", dict(latitude=45, heading=90, pitch=-2), dict(elevation=1, azimuth=90)),
    "orbit, sun 30 deg": ("view_from_space", dict(latitude=20, longitude=10), dict(elevation=30, azimuth=100)),
    "orbit, terminator through the centre": ("view_from_space", dict(latitude=0, longitude=0),
                                             dict(elevation=0, azimuth=90)),
}


def frames(size, quality):
    """{view: (per-pixel Y, per-vertex Y, ground mask)}"""
    out = {}
    scenes = {s: Scene("earth", quality=quality, surface="texture", off_screen=True, window_size=size, shading=s)
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
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print(f"{args.size}, {args.quality} tables: relative difference of per-vertex from per-pixel CIE Y")
    print("| view | pixels | RMS | p99 | max | ground RMS | ground p99 | sky RMS | sky p99 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (pixel, vertex, ground) in frames(size, args.quality).items():
        lit = pixel > 1e-3 * np.percentile(pixel, 99)
        rel = np.abs(vertex - pixel) / np.where(lit, pixel, 1.0)
        cells = []
        for mask in (lit, lit & ground, lit & ~ground):
            r = rel[mask]
            cells.append((f"{np.sqrt(np.mean(r ** 2)):.4f}", f"{np.percentile(r, 99):.4f}", f"{r.max():.3g}")
                         if r.size else ("-", "-", "-"))
        print(f"| {name} | {lit.sum()} | {' | '.join(cells[0])} | {' | '.join(cells[1][:2])} | "
              f"{' | '.join(cells[2][:2])} |")


if __name__ == "__main__":
    main()
