"""The shaders on a GPU against the NumPy evaluator: what tests/test_render.py and tests/test_vertex_shading.py
check on llvmpipe, on the GPU machine (plain VTK from the stripped bundle of ../shared/notes/gpu-timing.md).

    python benchmarks/gpu_render_timing.py prepare gpu-tables.npz        # here
    python3 benchmarks/gpu_agreement.py render gpu-tables.npz $OUT/agreement.npz      # on the GPU machine
    python benchmarks/gpu_agreement.py compare agreement.npz           # here: the evaluator for the same rays

``render`` draws Earth (standard tables, the file's uniform ground albedo, no sun disc) at 160x120 from orbit,
from 2 m and from 10 km, with the sun high and low, per pixel and per vertex (the vertex actor drawing points
at every fourth pixel's direction, so each of those pixels holds one vertex's value with no interpolation), and
stores the spectral radiance read back as float32 with the camera's uniforms. ``compare`` evaluates
``sky_radiance`` for the same rays and prints the largest and the RMS relative difference per case, over the
rays that see the atmosphere (radiance above 1e-6 of the case's largest), and the largest over the
ray-wavelengths above 1e-3 of it.
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

SIZE = "160x120"
SUNS = {"sun 40 deg": np.array([0.6, 0.3, 0.74]), "sun 3 deg": np.array([0.05, 0.9985, 0.0])}


def views(R):
    return {"orbit, 4 radii": ((4 * R, 0, 0), (0, 0, 0), (0, 0, 1)),
            "ground, 2 m": ((R + 2.0, 0, 0), (R + 2.0, 1e4, 1e3), (1, 0, 0)),
            "aircraft, 10 km": ((R + 1e4, 0, 0), (R + 1e4 - 1e3, 1e4, 0), (1, 0, 0))}


def pixel_directions(camera, rows, cols):
    """The fragment shader's pixel_direction (Scene.pixel_directions) from the stored camera uniforms."""
    x0, y0, w, h = camera["viewport"]
    ndc_x = (cols + 0.5 - x0) / w * 2 - 1
    ndc_y = ((h - 1 - rows) + 0.5 - y0) / h * 2 - 1
    v = camera["camera_forward"] + ndc_x[..., None] * camera["camera_right"] + ndc_y[..., None] * camera["camera_up"]
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def render(path, out):
    from gpu_render_timing import offscreen_window, prepared_actor, set_camera
    from planetviz.render.hdr import render_spectral
    from planetviz.render.uniforms import camera_uniforms
    from planetviz import load_atmosphere
    data = np.load(path)
    R = load_atmosphere("earth").bottom_radius_m
    window, renderer = offscreen_window(SIZE)
    h, w = (int(v) for v in SIZE.split("x")[::-1])
    rows, cols = np.meshgrid(np.arange(1, h, 4), np.arange(1, w, 4), indexing="ij")
    saved = {}
    for shading in ("pixel", "vertex"):
        actor = prepared_actor(data, renderer, False, shading)
        # The uniform albedo of the atmosphere file instead of the colour map (the evaluator's ground).
        actor.textures.surface = None
        for store in getattr(actor, "_stores", None) or [actor._store]:
            store.update({"use_surface_texture": ("i", 0), "surface_face_size": ("f", 1.0)})
        actor.settings.show_sun = False
        renderer.AddActor(actor.actor)
        for vname, view in views(R).items():
            set_camera(renderer, *view)
            camera = {k: np.asarray(v, float) for k, (_, v) in camera_uniforms(renderer).items()}
            if shading == "vertex":
                actor.directions = pixel_directions(camera, rows, cols).reshape(-1, 3)
            for sname, sun in SUNS.items():
                actor.sun_direction = sun / np.linalg.norm(sun)
                image = render_spectral(actor, window)
                key = f"{shading}|{vname}|{sname}"
                saved[key + "|radiance"] = image[rows, cols]
                saved[key + "|sun"] = actor.sun_direction
                for k, v in camera.items():
                    saved[key + "|" + k] = v
        renderer.RemoveActor(actor.actor)
        actor.release()
    np.savez(out, rows=rows, cols=cols, **saved)
    print(f"wrote {out}: {len(saved) // 7} cases")


def compare(path):
    from planetviz import load_atmosphere
    from planetviz.tables import QUALITY, TableCache, precompute
    from planetviz.tables.evaluator import sky_radiance
    atm = load_atmosphere("earth")
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    f = np.load(path)
    rows, cols = f["rows"], f["cols"]
    cases = sorted({k.rsplit("|", 1)[0] for k in f.files if "|" in k})
    print("| shading | view | sun | rays | largest relative difference | RMS | rays above 1e-3 of the case's largest "
          "value | largest relative difference there |")
    print("|---|---|---|---|---|---|---|---|")
    for case in cases:
        camera = {k: f[f"{case}|{k}"] for k in ("camera_position", "camera_forward", "camera_right", "camera_up",
                                                "viewport")}
        dirs = pixel_directions(camera, rows, cols).reshape(-1, 3)
        want, _ = sky_radiance(tables, atm, np.tile(camera["camera_position"], (len(dirs), 1)), dirs, f[f"{case}|sun"])
        got = f[f"{case}|radiance"].reshape(-1, want.shape[-1])
        seen = want.max(-1) > 1e-6 * want.max()
        rel = np.abs(got - want)[seen] / want[seen]
        bright = want > 1e-3 * want.max()
        rel_bright = np.abs(got - want)[bright] / want[bright]
        print(f"| {' | '.join(case.split('|'))} | {seen.sum()} | {rel.max():.2e} | {np.sqrt(np.mean(rel ** 2)):.2e} "
              f"| {bright.sum()} | {rel_bright.max():.2e} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=("render", "compare"))
    ap.add_argument("paths", nargs="+")
    args = ap.parse_args()
    if args.mode == "render":
        import os
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
        render(*args.paths)
    else:
        compare(*args.paths)


if __name__ == "__main__":
    main()
