"""Frame time of the table-based renderer on this machine (OSMesa / llvmpipe here, or any VTK OpenGL window),
per pixel and per vertex, beside a plain textured sphere timed in the same run.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/render_timing.py \\
        [--sizes 1280x720 1920x1080] [--frames 100] [--pixel-frames 10] [--pixel-only]

Views: Earth from orbit (4 radii, 30 deg: the planet fills ~40% of the frame), from the ground (2 m, looking along
the horizon: the whole frame is sky and ground; the scene's default sun, placed at latitude 0, is 4.6 deg below the
horizon at this latitude 45), the same by day (the sun 30 deg up) and in twilight (the sun 3 deg below the horizon
ahead: every sky ray's single scattering by quadrature, docs/tables.md, as under the default sun), from 1e9 m (the
planet a few pixels wide), and from orbit over the terminator (the sun on the horizon under the camera) and the
night side (60 deg below it: a lit crescent along the limb; both with the mesh's sectors where the planet's shadow
meets the halo); the sun as the scene places it by default except in the last two and from the ground by day and in
twilight. The plain sphere is PyVista's textured
sphere with VTK's default lighting and the same Earth texture, seen from the orbit view: what a globe without an
atmosphere costs, drawn in its own window in each round of per-vertex frames (one with the camera just turned by 0.5
deg about its focal point, the way a drag in the window turns it, back and forth from round to round so the view
stays; one with it still), so that each ratio to it is measured over the same seconds (this machine's speed drifts by
10-30% between runs). Median ms per frame over ``--frames`` rounds (``--pixel-frames`` frames for the per-pixel
renderer, at 1-4 s per frame on llvmpipe), each frame finished with WaitForCompletion, after one warm-up frame
(shader compile and table upload). Multisampling is off everywhere (PyVista's default of 8 samples triples llvmpipe's
frame time).
"""
import argparse
import os
import time

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

import pyvista as pv  # noqa: E402

from planetviz.render import Scene  # noqa: E402
from planetviz.render.surface import surface_texture  # noqa: E402


def frame_ms(window, frames, camera=None, plain=None):
    """Median ms per frame of ``window``. With ``camera`` and ``plain`` (another window), each round draws three
    frames: ``window`` after turning ``camera`` by 0.5 deg about its focal point (a camera in motion: the
    per-vertex renderer recomputes its mesh), ``window`` again with the camera still, and ``plain``; the three
    medians (moving, still, plain) are then measured over the same seconds."""
    windows = [window] if plain is None else [window, window, plain]
    for w in windows:
        w.Render()
        w.WaitForCompletion()
    times = [[] for _ in windows]
    for i in range(frames):
        if camera is not None:
            camera.Azimuth(0.5 * (-1) ** i)
        for w, t in zip(windows, times):
            t0 = time.perf_counter()
            w.Render()
            w.WaitForCompletion()
            t.append(1e3 * (time.perf_counter() - t0))
    medians = [float(np.median(t)) for t in times]
    return medians[0] if plain is None else medians


def plain_sphere(atmosphere, size):
    """PyVista's textured sphere of the planet seen from the orbit view (4 radii, 30 deg), multisampling off."""
    plotter = pv.Plotter(off_screen=True, window_size=list(size))
    plotter.ren_win.SetMultiSamples(0)
    sphere = pv.Sphere(radius=atmosphere.bottom_radius_m, theta_resolution=192, phi_resolution=96)
    sphere.texture_map_to_sphere(inplace=True)
    plotter.add_mesh(sphere, texture=pv.Texture(surface_texture(atmosphere)))
    plotter.camera.position = (4 * atmosphere.bottom_radius_m, 0.0, 0.0)
    plotter.camera.focal_point = (0.0, 0.0, 0.0)
    plotter.camera.up = (0.0, 0.0, 1.0)
    plotter.camera.view_angle = 30.0
    plotter.renderer.ResetCameraClippingRange()
    return plotter


VIEWS = {"orbit (4 radii)": lambda s: s.view_from_space(latitude=20, longitude=10),
         "ground, sky and ground": lambda s: s.view_from_ground(latitude=45, heading=90, pitch=5),
         "ground, day": lambda s: (s.set_sun(elevation=30.0, azimuth=135.0, latitude=45.0, longitude=0.0),
                                   s.view_from_ground(latitude=45, heading=90, pitch=5)),
         "ground, twilight": lambda s: (s.set_sun(elevation=-3.0, azimuth=90.0, latitude=45.0, longitude=0.0),
                                        s.view_from_ground(latitude=45, heading=90, pitch=5)),
         "orbit, terminator": lambda s: (s.set_sun(elevation=0.0, azimuth=90.0, latitude=0.0, longitude=0.0),
                                         s.view_from_space(latitude=0, longitude=0)),
         "orbit, night side": lambda s: (s.set_sun(elevation=-60.0, azimuth=90.0, latitude=0.0, longitude=0.0),
                                         s.view_from_space(latitude=0, longitude=0)),
         "1e9 m (a few pixels)": lambda s: s.view_from_space(distance=1e9, fov=30)}


def vertex_reuse(size, frames, rounds=5):
    """The per-vertex renderer's frame at a size where shading the vertices is most of it, with the mesh's
    triangles handed to OpenGL as the renderer hands them (strips of sectors: direction_mesh.strip_triangles), the
    same triangles quad after quad along whole rings, vertex (i, j) at index i n_p + j (ring_triangles), and each of
    their vertices once, as points (what shading every drawn vertex once costs). Median ms per frame over
    ``rounds`` rounds of ``frames`` frames of each, interleaved."""
    from planetviz.render.direction_mesh import VERTEX_STRIDE, _points, _set_cells
    w, h = (int(v) for v in size.split("x"))
    print("| view | vertices drawn | strips of sectors, ms | whole rings, ms | each vertex once, ms |")
    print("|---|---|---|---|---|")
    for name in ("orbit (4 radii)", "ground, sky and ground"):
        scene = Scene("earth", off_screen=True, window_size=(w, h), shading="vertex")
        VIEWS[name](scene)
        scene.render()
        scene.ren_win.Render()                         # the mesh's triangles of this view
        actor = scene.planet
        strips = [actor._cells[k][0] for k in range(len(actor._polys))]
        both = np.concatenate(strips)
        n_t, n_p = int(both.max() // VERTEX_STRIDE) + 1, int((both % VERTEX_STRIDE).max()) + 1
        i, j = np.meshgrid(np.arange(n_t), np.arange(n_p), indexing="ij")
        ring_points = _points(np.stack([i, j, 0 * i], -1).reshape(-1, 3))
        rings = []
        for cells in strips:
            c = (cells // VERTEX_STRIDE) * n_p + cells % VERTEX_STRIDE
            rings.append(c[np.argsort(c[:, 0], kind="stable")])     # quad after quad along the rings
        strip_points = actor._polys[0].GetPoints()
        arrangements = {"strips": [(strip_points, c, "polys") for c in strips],
                        "rings": [(ring_points, c, "polys") for c in rings],
                        "points": [(strip_points, np.unique(c)[:, None], "verts") for c in strips]}
        times = {kind: [] for kind in arrangements}
        for _ in range(rounds):
            for kind, parts in arrangements.items():
                for k, (points, cells, cell_kind) in enumerate(parts):
                    _set_cells(actor._polys[k], points, cells, cell_kind)
                    actor._cells[k] = (cells, cell_kind)
                times[kind].append(frame_ms(scene.ren_win, frames))
        drawn = len(np.unique(both))
        print(f"| {name} | {drawn} | {np.median(times['strips']):.1f} | {np.median(times['rings']):.1f} | "
              f"{np.median(times['points']):.1f} |", flush=True)
        scene.close()


def pixel_only(sizes, frames, quality):
    """Per pixel beside the plain textured sphere: each view's median over ``frames`` frames, then the plain
    sphere's over 10, so that each ratio is measured within seconds."""
    print("| size | view | per pixel | plain textured sphere | per pixel / plain |")
    print("|---|---|---|---|---|")
    for size in sizes:
        w, h = (int(v) for v in size.split("x"))
        scene = Scene("earth", quality=quality, off_screen=True, window_size=(w, h), shading="pixel")
        plain = plain_sphere(scene.atmosphere, (w, h))
        default_sun = vars(scene.sun).copy()
        for name, set_view in VIEWS.items():
            scene.set_sun(**default_sun)
            set_view(scene)
            scene.render()
            pixel_ms, plain_ms = frame_ms(scene.ren_win, frames), frame_ms(plain.ren_win, 10)
            print(f"| {size} | {name} | {pixel_ms:.1f} | {plain_ms:.1f} | {pixel_ms / plain_ms:.1f} |", flush=True)
        plain.close()
        scene.close()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", nargs="+", default=["1280x720", "1920x1080"])
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--pixel-frames", type=int, default=10)
    ap.add_argument("--quality", default="standard")
    ap.add_argument("--pixel-only", action="store_true",
                    help="per pixel only, each view's frames followed by 10 of the plain sphere (their ratio)")
    ap.add_argument("--vertex-reuse", metavar="SIZE", help="only the vertex-reuse comparison (vertex_reuse) at SIZE")
    args = ap.parse_args()
    if args.vertex_reuse:
        return vertex_reuse(args.vertex_reuse, max(args.frames // 10, 5))
    if args.pixel_only:
        return pixel_only(args.sizes, args.pixel_frames, args.quality)
    views = VIEWS
    print("| size | view | per pixel | per vertex | per vertex, camera moving | plain textured sphere | "
          "per vertex / plain | moving / plain |")
    print("|---|---|---|---|---|---|---|---|")
    for size in args.sizes:
        w, h = (int(v) for v in size.split("x"))
        results = {}
        for shading in ("pixel", "vertex"):
            scene = Scene("earth", quality=args.quality, off_screen=True, window_size=(w, h), shading=shading)
            plain = plain_sphere(scene.atmosphere, (w, h)) if shading == "vertex" else None
            default_sun = vars(scene.sun).copy()
            for name, set_view in views.items():
                scene.set_sun(**default_sun)
                set_view(scene)
                scene.render()
                if shading == "pixel":
                    results[name, "pixel"] = frame_ms(scene.ren_win, args.pixel_frames)
                    continue
                results[name, "moving"], results[name, "vertex"], results[name, "plain"] = frame_ms(
                    scene.ren_win, args.frames, scene.renderer.GetActiveCamera(), plain.ren_win)
            if plain is not None:
                plain.close()
            scene.close()
        for name in views:
            plain_ms = results[name, "plain"]
            print(f"| {size} | {name} | {results[name, 'pixel']:.1f} | {results[name, 'vertex']:.1f} | "
                  f"{results[name, 'moving']:.1f} | {plain_ms:.1f} | {results[name, 'vertex'] / plain_ms:.2f} | "
                  f"{results[name, 'moving'] / plain_ms:.2f} |", flush=True)


if __name__ == "__main__":
    main()
