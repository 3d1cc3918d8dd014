"""Frame time of the table-based renderer on this machine (OSMesa / llvmpipe here, or any VTK OpenGL window),
per pixel and per vertex, beside a plain textured sphere timed in the same run.

    VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow python benchmarks/render_timing.py \\
        [--sizes 1280x720 1920x1080] [--frames 100] [--pixel-frames 10]

Views: Earth from orbit (4 radii, 30 deg: the planet fills ~40% of the frame), from the ground (2 m, looking
along the horizon: the whole frame is sky and ground), the same in twilight (the sun 3 deg below the horizon
ahead: every ray's single scattering by quadrature, docs/tables.md) and from 1e9 m (the planet a few pixels
wide); the sun as the scene places it by default except in twilight. The plain
sphere is PyVista's textured sphere with VTK's default lighting and the same Earth texture, seen from the orbit
view: what a globe without an atmosphere costs. Median ms per frame over ``--frames`` (``--pixel-frames`` for the
per-pixel renderer, at 1-4 s per frame on llvmpipe), still and (per vertex) with the camera moving, each frame
finished with WaitForCompletion, after one
warm-up frame (shader compile and table upload). Multisampling is off everywhere (PyVista's default of 8
samples triples llvmpipe's frame time).
"""
import argparse
import os
import time

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

import pyvista as pv  # noqa: E402

from planetviz.render import Scene  # noqa: E402
from planetviz.render.surface import surface_texture  # noqa: E402


def frame_ms(window, frames, camera=None):
    """Median ms per frame; with ``camera``, moved by one part in 1e7 before each frame (a camera in motion:
    the per-vertex renderer rebuilds its mesh)."""
    window.Render()
    window.WaitForCompletion()
    times = []
    for i in range(frames):
        if camera is not None:
            camera.SetPosition(*(np.array(camera.GetPosition()) * (1 + 1e-7 * (-1) ** i)))
        t0 = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        times.append(1e3 * (time.perf_counter() - t0))
    return float(np.median(times))


def plain_sphere_ms(atmosphere, size, frames):
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
    ms = frame_ms(plotter.ren_win, frames)
    plotter.close()
    return ms


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", nargs="+", default=["1280x720", "1920x1080"])
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--pixel-frames", type=int, default=10)
    ap.add_argument("--quality", default="standard")
    args = ap.parse_args()
    views = {"orbit (4 radii)": lambda s: s.view_from_space(latitude=20, longitude=10),
             "ground, sky and ground": lambda s: s.view_from_ground(latitude=45, heading=90, pitch=5),
             "ground, twilight": lambda s: (s.set_sun(elevation=-3.0, azimuth=90.0, latitude=45.0, longitude=0.0),
                                            s.view_from_ground(latitude=45, heading=90, pitch=5)),
             "1e9 m (a few pixels)": lambda s: s.view_from_space(distance=1e9, fov=30)}
    print("| size | plain textured sphere | view | per pixel | per vertex | per vertex, camera moving |")
    print("|---|---|---|---|---|---|")
    for size in args.sizes:
        w, h = (int(v) for v in size.split("x"))
        results = {}
        for shading in ("pixel", "vertex"):
            scene = Scene("earth", quality=args.quality, off_screen=True, window_size=(w, h), shading=shading)
            default_sun = vars(scene.sun).copy()
            for name, set_view in views.items():
                scene.set_sun(**default_sun)
                set_view(scene)
                scene.render()
                results[name, shading] = frame_ms(scene.ren_win, args.pixel_frames if shading == "pixel"
                                                  else args.frames)
                if shading == "vertex":
                    results[name, "moving"] = frame_ms(scene.ren_win, args.frames, scene.renderer.GetActiveCamera())
            plain = plain_sphere_ms(scene.atmosphere, (w, h), args.frames) if shading == "vertex" else None
            scene.close()
        for name in views:
            print(f"| {size} | {plain:.1f} | {name} | {results[name, 'pixel']:.1f} | {results[name, 'vertex']:.1f} | "
                  f"{results[name, 'moving']:.1f} |", flush=True)


if __name__ == "__main__":
    main()
