"""Frame time of the table-based renderer on a GPU through EGL, in plain VTK (no PyVista, no SciPy, no
colour-science: what the stripped VTK bundle of ../shared/notes/gpu-timing.md offers).

    python benchmarks/gpu_render_timing.py prepare gpu-tables.npz          # here: Earth's standard tables
    python benchmarks/gpu_render_timing.py run gpu-tables.npz [--sizes 1280x720 1920x1080] [--frames 100]
    python benchmarks/gpu_render_timing.py breakdown gpu-tables.npz --sizes 1920x1080 [--repeats 3]

``prepare`` stores the packed tables and the shader's constant uniforms (which need colour-science);
``run`` builds a window, the same ``AtmosphereActor`` the application uses, and times, per size: a plain
textured sphere (Earth's colour map, VTK's default shading) filling the same part of the frame (the frame floor
of this GPU, as the notes recommend: compare ratios, not absolute figures), then the atmosphere (with the same
colour map) from orbit, from the ground and from 1e9 m (the planet a few pixels wide), per pixel with 32-bit
and with 16-bit float tables, and per vertex (``Scene(shading="vertex")``) with the camera still and moving
(the mesh rebuilt on the CPU each frame); then the quick view (Keller and Bohn per vertex, no tables) from the
ground with 4, 8 and 16 points per path. Median ms per frame, ``WaitForCompletion`` after each frame, after 5
warm-up frames. The share of non-black pixels of each timed frame is printed too: a frame that drew nothing
would time fast. ``breakdown`` times where the per-vertex frame goes (see :func:`breakdown`).
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

TABLES = ("optical_depth", "irradiance", "rayleigh", "mie", "multiple", "multiple_mie")


def prepare(path):
    from planetviz import load_atmosphere
    from planetviz.render.atmosphere_actor import TableTextures
    from planetviz.tables import QUALITY, TableCache, precompute
    from planetviz.render.surface import surface_texture
    atm = load_atmosphere("earth")
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    from planetviz.render.quick_view_actor import QuickViewActor
    surface = surface_texture(atm)
    static = TableTextures(atm, tables, surface).static_uniforms()
    static = {k: (kind, np.asarray(v).tolist()) for k, (kind, v) in static.items()}
    quick = {}
    for n in (4, 8, 16):
        u = QuickViewActor.static_uniforms(SimpleNamespace(atmosphere=atm, terms="physical", sampling="power",
                                                           samples=n, density_samples=n))
        quick[n] = {k: (kind, np.asarray(v).tolist()) for k, (kind, v) in u.items()}
    np.savez_compressed(path, bottom=tables.bottom, top=tables.top, static=json.dumps(static),
                        quick=json.dumps(quick), surface=surface,
                        **{name: getattr(tables, name) for name in TABLES})
    print(f"wrote {path} ({Path(path).stat().st_size / 1e6:.1f} MB)")


class _PreparedActor:
    """An AtmosphereActor (``shading="pixel"``) or VertexAtmosphereActor (``"vertex"``) whose constant uniforms
    come from the prepared file."""

    def __new__(cls, data, renderer, half_float, shading="pixel"):
        from planetviz.render.atmosphere_actor import AtmosphereActor
        from planetviz.render.vertex_actor import VertexAtmosphereActor

        class Prepared(AtmosphereActor if shading == "pixel" else VertexAtmosphereActor):
            def static_uniforms(self):
                return {k: (kind, v) for k, (kind, v) in json.loads(str(data["static"])).items()}

        tables = SimpleNamespace(bottom=float(data["bottom"]), top=float(data["top"]),
                                 **{name: data[name] for name in TABLES})
        atm = SimpleNamespace(bottom_radius_m=float(data["bottom"]), top_radius_m=float(data["top"]))
        return Prepared(atm, tables, renderer, surface=data["surface"], half_float_tables=half_float)


class _PreparedQuick:
    """A QuickViewActor whose constant uniforms come from the prepared file."""

    def __new__(cls, data, renderer, n):
        from planetviz.render.quick_view_actor import QuickViewActor

        class Prepared(QuickViewActor):
            def static_uniforms(self):
                return {k: (kind, v) for k, (kind, v) in json.loads(str(data["quick"]))[str(n)].items()}

        atm = SimpleNamespace(bottom_radius_m=float(data["bottom"]), top_radius_m=float(data["top"]))
        return Prepared(atm, renderer, samples=n)


def frame_ms(window, frames, camera=None):
    """Median ms per frame; with ``camera``, moved by one part in 1e7 before each frame (a camera in motion:
    the per-vertex renderer rebuilds its mesh on the CPU), as benchmarks/render_timing.py does."""
    for _ in range(5):
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


def camera_views(R):
    """{name: (position, focal point, view up)} of the timed views around a planet of radius ``R``."""
    return {"orbit, 4 radii": ((4 * R, 0, 0), (0, 0, 0), (0, 0, 1)),
            "ground, horizon": ((R + 2.0, 0, 0), (R + 2.0, 1e4, 1e3), (1, 0, 0)),
            "1e9 m": ((1e9, 0, 0), (0, 0, 0), (0, 0, 1))}


def offscreen_window(size):
    """(window, renderer): an off-screen window of ``size`` ("WxH"), multisampling off, near plane tolerance
    1e-6 (planetary scale)."""
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    w, h = (int(v) for v in size.split("x"))
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(w, h)
    window.SetMultiSamples(0)
    renderer = vtkRenderer()
    renderer.SetNearClippingPlaneTolerance(1e-6)
    window.AddRenderer(renderer)
    return window, renderer


def set_camera(renderer, position, target, up):
    cam = renderer.GetActiveCamera()
    cam.SetPosition(*position)
    cam.SetFocalPoint(*target)
    cam.SetViewUp(*up)
    cam.SetViewAngle(30.0)
    renderer.ResetCameraClippingRange()


def drawn_share(window):
    """The share of the frame's pixels that are not black."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    pixels = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    return float(np.mean(pixels[:, :3].max(axis=1) > 0))


def textured_sphere(radius, image):
    """A plain VTK actor: a 192x96 sphere with ``image`` (h, w, 3 uint8, equirectangular) as its colour
    texture and VTK's default shading: the plain textured sphere of the issue's target."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkTexture
    sphere = vtkSphereSource()
    sphere.SetRadius(radius)
    sphere.SetThetaResolution(192)
    sphere.SetPhiResolution(96)
    sphere.Update()
    mesh = sphere.GetOutput()
    p = vtk_to_numpy(mesh.GetPoints().GetData()) / radius
    tcoords = np.stack([0.5 + np.arctan2(p[:, 1], p[:, 0]) / (2 * np.pi),
                        0.5 + np.arcsin(np.clip(p[:, 2], -1, 1)) / np.pi], axis=1)
    mesh.GetPointData().SetTCoords(numpy_to_vtk(np.ascontiguousarray(tcoords, dtype=np.float32), deep=True))
    h, w, _ = image.shape
    img = vtkImageData()
    img.SetDimensions(w, h, 1)
    img.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(image[::-1]).reshape(-1, 3), deep=True))
    texture = vtkTexture()
    texture.SetInputData(img)
    texture.InterpolateOn()
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(mesh)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.SetTexture(texture)
    return actor


def run(path, sizes, frames):
    data = np.load(path)
    R = float(data["bottom"])
    views = camera_views(R)
    variants = (("pixel", False), ("pixel", True), ("vertex", False), ("vertex moving", False))
    print("| size | plain textured sphere (4 radii) | "
          + " | ".join(f"{v}, per pixel | {v}, per pixel, float16 tables | {v}, per vertex | "
                       f"{v}, per vertex, camera moving" for v in views) + " |")
    print("|---" * (2 + len(variants) * len(views)) + "|")
    quick_rows = []
    for size in sizes:
        row = [size]
        window, renderer = offscreen_window(size)
        plain = textured_sphere(R, data["surface"])
        renderer.AddActor(plain)
        set_camera(renderer, *views["orbit, 4 radii"])
        row.append(frame_ms(window, frames))
        shares = {"plain": drawn_share(window)}
        renderer.RemoveActor(plain)
        timings = {}
        for shading, half in variants:
            moving = shading.endswith("moving")
            actor = _PreparedActor(data, renderer, half, shading.split()[0])
            actor.sun_direction = np.array([0.6, 0.3, 0.74])
            renderer.AddActor(actor.actor)
            for name, view in views.items():
                set_camera(renderer, *view)
                timings[name, shading, half] = frame_ms(window, frames,
                                                        renderer.GetActiveCamera() if moving else None)
                shares[name, shading, half] = drawn_share(window)
            renderer.RemoveActor(actor.actor)
            actor.release()
        row += [timings[name, shading, half] for name in views for shading, half in variants]
        print("| " + " | ".join([row[0]] + [f"{v:.2f}" for v in row[1:]]) + " |", flush=True)
        print("| non-black share | " + " | ".join([f"{shares['plain']:.3g}"] + [
            f"{shares[name, shading, half]:.3g}" for name in views for shading, half in variants]) + " |",
            flush=True)
        for n in (4, 8, 16):
            quick = _PreparedQuick(data, renderer, n)
            quick.sun_direction = np.array([0.6, 0.3, 0.74])
            renderer.AddActor(quick.actor)
            set_camera(renderer, *views["ground, horizon"])
            quick_rows.append((size, n, frame_ms(window, frames), quick.mapper.GetInput().GetNumberOfPoints()))
            renderer.RemoveActor(quick.actor)
        window.Finalize()
    print("\n| size | quick view, points per path | ms per frame | vertices |")
    print("|---|---|---|---|")
    for size, n, ms, verts in quick_rows:
        print(f"| {size} | {n} | {ms:.2f} | {verts} |")


#: Shader variants of the breakdown: a replacement in the per-vertex renderer's fragment code, and what it shows.
BREAKDOWN = {
    "ground pixels return a constant (the floor of the design)":
        ("ground = ray_hits_ground(ray);", "ground = ray_hits_ground(ray); if (ground) return vec4(0.5);"),
    "surface colour a constant": ("surface_colour_or_unit(n)", "vec3(0.5)"),
    "no tone mapping or sRGB encoding": ("vec4(display_colour(value), 1.0)", "vec4(value, 1.0)"),
}


def breakdown(path, size, frames, repeats=3):
    """Where the per-vertex frame goes: the empty frame, the plain textured sphere, the per-vertex renderer and
    the variants of BREAKDOWN, interleaved ``repeats`` times (the GPU's timings drift by 10-20% between runs),
    from orbit and from the ground; medians of the repeats' medians."""
    from planetviz.render import vertex_actor
    from planetviz.render.shaders import shader_code
    replace = {}

    def patched(*names):
        code = shader_code(*names)
        if names[-1] == "atmosphere_interpolated.glsl" and replace:
            (old, new), = replace.items()
            if old not in code:
                raise RuntimeError(f"breakdown: {old!r} is no longer in the shader")
            code = code.replace(old, new)
        return code

    vertex_actor.shader_code = patched
    data = np.load(path)
    R = float(data["bottom"])
    window, renderer = offscreen_window(size)
    views = {name: view for name, view in camera_views(R).items() if name != "1e9 m"}
    configs = {"empty frame": None, "plain textured sphere": "plain", "per vertex": (), **BREAKDOWN}
    times = {name: [] for name in configs}
    for _ in range(repeats):
        for name, config in configs.items():
            replace.clear()
            actor = None
            if config == "plain":
                actor = textured_sphere(R, data["surface"])
            elif config is not None:
                replace.update([config] if config else [])
                prepared = _PreparedActor(data, renderer, False, "vertex")
                prepared.sun_direction = np.array([0.6, 0.3, 0.74])
                actor = prepared.actor
            if actor is not None:
                renderer.AddActor(actor)
            row = []
            for view in views.values():
                set_camera(renderer, *view)
                row.append(frame_ms(window, frames))
            times[name].append(row)
            if actor is not None:
                renderer.RemoveActor(actor)
            if config not in (None, "plain"):
                prepared.release()
    print(f"| {size} | orbit, 4 radii | ground, horizon |")
    print("|---|---|---|")
    for name, rows in times.items():
        orbit, ground = np.median(np.array(rows), axis=0)
        print(f"| {name} | {orbit:.2f} | {ground:.2f} |")
    # The ratio: each view's per-vertex frame over the plain sphere's orbit frame of the same repeat.
    ratio = np.array(times["per vertex"]) / np.array(times["plain textured sphere"])[:, :1]
    print(f"\nper vertex / plain textured sphere (orbit framing), {repeats} interleaved repeats: median "
          + ", ".join(f"{name} {np.median(r):.2f} (range {r.min():.2f}-{r.max():.2f})"
                      for name, r in zip(views, ratio.T)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=("prepare", "run", "breakdown"))
    ap.add_argument("path")
    ap.add_argument("--sizes", nargs="+", default=["1280x720", "1920x1080", "3840x2160"])
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=3, help="breakdown: interleaved repeats")
    args = ap.parse_args()
    if args.mode == "prepare":
        prepare(args.path)
    else:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
        if args.mode == "run":
            run(args.path, args.sizes, args.frames)
        else:
            for size in args.sizes:
                breakdown(args.path, size, args.frames, args.repeats)


if __name__ == "__main__":
    main()
