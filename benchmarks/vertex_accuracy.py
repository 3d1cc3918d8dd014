"""What reading the 4D tables per vertex (``Scene(shading="vertex")``) costs in accuracy: the same frames drawn
per pixel and per vertex, compared in CIE Y (``render_hdr``, linear sRGB, the sun's disc left out) in each view
class of :data:`planetviz.validation.pictures.VIEWS`.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/vertex_accuracy.py \\
        [--size 1280x720] [--presets earth mars exo-co2-thick] [--random N]

Prints, per atmosphere and view, the RMS and the 99th percentile of the per-vertex frame's difference from the
per-pixel frame relative to the per-pixel value floored at 1% of the frame's 99th percentile
(:func:`~planetviz.validation.pictures.floored_difference`), over the whole frame and over the ground's and the
sky's pixels apart (a ground pixel is one whose ray meets the planet). ``--random N``: then, per split of
:data:`planetviz.validation.random_suite.SPLITS`, the first N random legal atmospheres in the same views, the
median and the largest RMS and 99th percentile over them per view.
"""
import argparse
import os

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.model.geometry import distance_to_ground  # noqa: E402
from planetviz.render import Scene  # noqa: E402
from planetviz.validation.pictures import VIEWS, floored_difference, view_luminance  # noqa: E402


def frames(atmosphere, size, quality):
    """{view: (per-pixel Y, per-vertex Y, ground mask)}"""
    out = {}
    scenes = {s: Scene(atmosphere, quality=quality, surface="texture", off_screen=True, window_size=size,
                       shading=s) for s in ("pixel", "vertex")}
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


def random_atmospheres(split, count, size, quality):
    """The median and largest RMS and 99th percentile per view over the first ``count`` random atmospheres of
    ``split``."""
    from planetviz.validation.random_suite import SPLITS, random_atmosphere
    rms, p99 = {name: [] for name in VIEWS}, {name: [] for name in VIEWS}
    for seed in list(SPLITS[split])[:count]:
        for name, (pixel, vertex, _) in frames(random_atmosphere(seed), size, quality).items():
            if np.percentile(pixel, 99) <= 0.0:          # nothing lit in view (a small planet out of the frame)
                continue
            rel = floored_difference(vertex, pixel)
            rms[name].append(np.sqrt(np.mean(rel ** 2)))
            p99[name].append(np.percentile(rel, 99))
    print(f"\n{split} split, the first {count} random atmospheres: median / largest over those with a lit frame")
    print("| view | frames | RMS median | RMS largest | p99 median | p99 largest |")
    print("|---|---|---|---|---|---|")
    for name in VIEWS:
        if rms[name]:
            print(f"| {name} | {len(rms[name])} | {np.median(rms[name]):.4f} | {np.max(rms[name]):.4f} | "
                  f"{np.median(p99[name]):.4f} | {np.max(p99[name]):.4f} |", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--quality", default="standard")
    ap.add_argument("--presets", nargs="*", default=["earth", "mars", "exo-co2-thick"])
    ap.add_argument("--random", type=int, default=0, help="also this many random atmospheres per split")
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
    for split in ("tuning", "held-out") if args.random else ():
        random_atmospheres(split, args.random, size, args.quality)


if __name__ == "__main__":
    main()
