"""Frame time of the table-based renderer and of the quick view on a GPU through EGL, in plain VTK (no PyVista, no
SciPy, no colour-science: what the stripped VTK bundle of ../shared/notes/gpu-timing.md offers).

    python benchmarks/gpu_render_timing.py prepare gpu-tables.npz          # here: Earth's standard tables
    python benchmarks/gpu_render_timing.py run gpu-tables.npz [--sizes 1280x720 1920x1080] [--frames 100]
    python benchmarks/gpu_render_timing.py breakdown gpu-tables.npz --sizes 1920x1080 [--repeats 3]
    python benchmarks/gpu_render_timing.py pixel-breakdown gpu-tables.npz --sizes 1920x1080 [--repeats 3]

``prepare`` stores the tables of the orders above the first, the quick view's table of the orders above the first and the shaders'
constant uniforms (they need colour-science); the atmosphere itself is the Earth preset, loaded where the
benchmark runs. ``run`` builds a window, the same actors the application uses, and times, per size: a plain
textured sphere (Earth's colour map, VTK's default shading) filling the same part of the frame (the frame floor
of this GPU, as the notes recommend: compare ratios, not absolute figures), then the atmosphere (with the same
colour map) from orbit, from the ground and from 1e9 m (the planet a few pixels wide), per pixel with 32-bit
and with 16-bit float tables, per vertex (``Scene(shading="vertex")``) with the camera still and moving (the
mesh rebuilt on the CPU each frame), and the quick view (all orders, the surface texture, 8 points per path) still
and moving. Median ms per frame, ``WaitForCompletion`` after each frame, after 5 warm-up frames. The share of
non-black pixels of each timed frame is printed too: a frame that drew nothing would time fast. ``breakdown``
and ``pixel-breakdown`` time where the per-vertex and the per-pixel frame go (see :func:`breakdown`).
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np


#: The tables the prepared file holds: those whose precompute needs SciPy.
MULTIPLE_TABLES = ("irradiance", "multiple", "multiple_mie", "top_multiple", "top_multiple_mie")
#: Points per path of the timed quick view: the application's default (Scene's quick_samples).
QUICK_SAMPLES = 8


def _encode(uniforms):
    return json.dumps({k: (kind, np.asarray(v).tolist()) for k, (kind, v) in uniforms.items()})


def prepare(path):
    from vtkmodules.vtkRenderingCore import vtkRenderer
    from planetviz import load_atmosphere
    from planetviz.quick_view.multiple_scattering import quick_view_tables
    from planetviz.render.atmosphere_actor import TableTextures
    from planetviz.render.quick_view_actor import QuickViewActor
    from planetviz.render.surface import surface_texture
    from planetviz.tables import QUALITY, TableCache, precompute
    atm = load_atmosphere("earth")
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    surface = surface_texture(atm)
    quick = QuickViewActor(atm, vtkRenderer(), samples=QUICK_SAMPLES, orders="single", surface=surface)
    quick_static = quick.static_uniforms()
    quick.release()
    multiple, ground_sky = quick_view_tables(atm)
    np.savez_compressed(path, static=_encode(TableTextures(atm, tables, surface).static_uniforms()),
                        quick=_encode(quick_static), surface=surface, quick_multiple=multiple,
                        quick_ground_sky=ground_sky, **{name: getattr(tables, name) for name in MULTIPLE_TABLES})
    print(f"wrote {path} ({Path(path).stat().st_size / 1e6:.1f} MB)")


_TABLES = {}


def earth_tables(data):
    """Earth's standard tables: the transmittance and single scattering computed here (NumPy only, 2 s; the file
    would not fit beside the VTK bundle), the orders above the first from the prepared file (their precompute
    needs SciPy)."""
    if not _TABLES:
        from planetviz import load_atmosphere
        from planetviz.tables import QUALITY, precompute
        tables = precompute(load_atmosphere("earth"), QUALITY["standard"], multiple=False)
        for name in MULTIPLE_TABLES:
            setattr(tables, name, data[name])
        _TABLES["earth"] = tables
    return _TABLES["earth"]


def _static(data, key):
    return {k: (kind, v) for k, (kind, v) in json.loads(str(data[key])).items()}


def prepared_actor(data, renderer, half_float, shading="pixel"):
    """An AtmosphereActor (``shading="pixel"``) or VertexAtmosphereActor (``"vertex"``) of Earth with
    :func:`earth_tables`, whose constant uniforms come from the prepared file."""
    from planetviz import load_atmosphere
    from planetviz.render.atmosphere_actor import AtmosphereActor
    from planetviz.render.vertex_actor import VertexAtmosphereActor

    class Prepared(AtmosphereActor if shading == "pixel" else VertexAtmosphereActor):
        def static_uniforms(self):
            factor = self.factor_textures.uniforms() if shading == "vertex" else {}
            return {**_static(data, "static"), **factor}

    return Prepared(load_atmosphere("earth"), earth_tables(data), renderer, surface=data["surface"],
                    half_float_tables=half_float)


def prepared_quick(data, renderer):
    """A QuickViewActor of Earth (all orders, the surface texture) whose constant uniforms and table of the orders
    above the first come from the prepared file."""
    from planetviz import load_atmosphere
    from planetviz.render.quick_view_actor import QuickViewActor

    class Prepared(QuickViewActor):
        def static_uniforms(self):
            return _static(data, "quick")

    quick = Prepared(load_atmosphere("earth"), renderer, samples=QUICK_SAMPLES, orders="single",
                     surface=data["surface"])
    quick.multiple, quick.ground_sky = data["quick_multiple"], data["quick_ground_sky"]
    return quick


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
    from planetviz import load_atmosphere
    data = np.load(path)
    R = load_atmosphere("earth").bottom_radius_m
    views = camera_views(R)
    variants = (("pixel", False), ("pixel", True), ("vertex", False), ("vertex moving", False),
                ("quick", False), ("quick moving", False))
    names = {("pixel", False): "per pixel", ("pixel", True): "per pixel, float16 tables",
             ("vertex", False): "per vertex", ("vertex moving", False): "per vertex, camera moving",
             ("quick", False): "quick view", ("quick moving", False): "quick view, camera moving"}
    print("| size | view | plain textured sphere (4 radii) | " + " | ".join(names.values()) + " |")
    print("|---" * (3 + len(variants)) + "|")
    for size in sizes:
        window, renderer = offscreen_window(size)
        plain = textured_sphere(R, data["surface"])
        renderer.AddActor(plain)
        set_camera(renderer, *views["orbit, 4 radii"])
        plain_ms = frame_ms(window, frames)
        shares = {"plain": drawn_share(window)}
        renderer.RemoveActor(plain)
        timings = {}
        for shading, half in variants:
            kind, moving = shading.split()[0], shading.endswith("moving")
            actor = (prepared_quick(data, renderer) if kind == "quick"
                     else prepared_actor(data, renderer, half, kind))
            actor.sun_direction = np.array([0.6, 0.3, 0.74])
            renderer.AddActor(actor.actor)
            for name, view in views.items():
                set_camera(renderer, *view)
                timings[name, shading, half] = frame_ms(window, frames,
                                                        renderer.GetActiveCamera() if moving else None)
                shares[name, shading, half] = drawn_share(window)
            renderer.RemoveActor(actor.actor)
            actor.release()
        for i, name in enumerate(views):
            print(f"| {size} | {name} | {plain_ms:.2f} | "
                  + " | ".join(f"{timings[name, v, h]:.2f}" for v, h in variants) + " |", flush=True)
        print(f"| {size} | non-black share | {shares['plain']:.3g} | " + " | ".join(
            "/".join(f"{shares[name, v, h]:.2g}" for name in views) for v, h in variants) + " |", flush=True)
        window.Finalize()


def _interleaved(data, size, frames, repeats, configs, make_actor):
    """(views, {config: [[ms per view] per repeat]}): the empty frame, the plain textured sphere and each of
    ``configs`` (made by ``make_actor(config, renderer)``), interleaved ``repeats`` times, from orbit and from the ground."""
    from planetviz import load_atmosphere
    R = load_atmosphere("earth").bottom_radius_m
    window, renderer = offscreen_window(size)
    views = {name: view for name, view in camera_views(R).items() if name != "1e9 m"}
    configs = {"empty frame": None, "plain textured sphere": "plain", **configs}
    times = {name: [] for name in configs}
    for _ in range(repeats):
        for name, config in configs.items():
            prepared = None
            if config == "plain":
                actor = textured_sphere(R, data["surface"])
            elif config is not None:
                prepared = make_actor(config, renderer)
                prepared.sun_direction = np.array([0.6, 0.3, 0.74])
                actor = prepared.actor
            if config is not None:
                renderer.AddActor(actor)
            row = []
            for view in views.values():
                set_camera(renderer, *view)
                row.append(frame_ms(window, frames))
            times[name].append(row)
            if config is not None:
                renderer.RemoveActor(actor)
            if prepared is not None:
                prepared.release()
    window.Finalize()
    print(f"| {size} | orbit, 4 radii | ground, horizon |")
    print("|---|---|---|")
    for name, rows in times.items():
        orbit, ground = np.median(np.array(rows), axis=0)
        print(f"| {name} | {orbit:.2f} | {ground:.2f} |")
    return views, times


def _ratio(views, times, name, repeats):
    """The issue's ratio: each view's frame of ``name`` over the plain sphere's orbit frame of the same repeat."""
    ratio = np.array(times[name]) / np.array(times["plain textured sphere"])[:, :1]
    print(f"\n{name} / plain textured sphere (orbit framing), {repeats} interleaved repeats: median "
          + ", ".join(f"{view} {np.median(r):.2f} (range {r.min():.2f}-{r.max():.2f})"
                      for view, r in zip(views, ratio.T)), flush=True)


def _patching(module, last_shader, replacements):
    """Make ``module``'s shader_code apply ``replacements`` (a list of (old, new), changed in place by the caller) to
    the code that ends with ``last_shader``."""
    from planetviz.render.shaders import shader_code

    def patched(*names):
        code = shader_code(*names)
        if names[-1] == last_shader:
            for old, new in replacements:
                if old not in code:
                    raise RuntimeError(f"breakdown: {old!r} is no longer in the shader")
                code = code.replace(old, new)
        return code

    module.shader_code = patched


#: Shader variants of the breakdown: a replacement in the per-vertex renderer's fragment code, and what it shows.
BREAKDOWN = {
    "ground pixels return a constant (the floor of the design)":
        [("ground = ray_hits_ground(ray);", "ground = ray_hits_ground(ray); if (ground) return vec4(0.5);")],
    "surface colour a constant": [("surface_colour_or_unit(n)", "vec3(0.5)")],
    "no tone mapping or sRGB encoding": [("vec4(display_colour(value), 1.0)", "vec4(value, 1.0)")],
}

_NO_HORIZON = ("float share = quadrature_share(a, mu, mu_s, nu, intersects_ground);", "float share = 0.0;")
_NO_NEAR_GROUND = ("if (near_ground_rays(a, intersects_ground)) {", "if (false) {")
_NO_ROW_FACTOR = ("vec4 row = ground_row_factor(a, mu, intersects_ground, multiple_size.w, multiple_row_1_rho, g);",
                  "vec4 row = vec4(1.0);")
#: Shader variants of the per-pixel breakdown: replacements in the per-pixel renderer's code, and what they show.
PIXEL_BREAKDOWN = {
    "no horizon quadrature": [_NO_HORIZON],
    "no near-ground quadrature": [_NO_NEAR_GROUND],
    "no ground-row factor": [_NO_ROW_FACTOR],
    "none of the three": [_NO_HORIZON, _NO_NEAR_GROUND, _NO_ROW_FACTOR],
    "multiple-scattering tables not read": [
        ("""    return ScatteringParts(s_r, s_m,
        get_multiple_scattering(multiple_texture, top_multiple_texture, multiple_size, a, mu, mu_s, nu,
                                intersects_ground, opacity, g) * row,
        get_multiple_scattering(multiple_mie_texture, top_multiple_mie_texture, multiple_size, a, mu, mu_s, nu,
                                intersects_ground, opacity, g) * row);""",
         "    return ScatteringParts(s_r, s_m, vec4(0.0), vec4(0.0));")],
}


def breakdown(path, size, frames, repeats=3):
    """Where the per-vertex frame goes: the empty frame, the plain textured sphere, the per-vertex renderer and
    the variants of BREAKDOWN, interleaved ``repeats`` times (the GPU's timings drift by 10-20% between runs),
    from orbit and from the ground; medians of the repeats' medians."""
    from planetviz.render import vertex_actor
    data = np.load(path)
    replace = []
    _patching(vertex_actor, "atmosphere_interpolated.glsl", replace)

    def make(config, renderer):
        replace[:] = config
        return prepared_actor(data, renderer, False, "vertex")

    views, times = _interleaved(data, size, frames, repeats, {"per vertex": [], **BREAKDOWN}, make)
    _ratio(views, times, "per vertex", repeats)


def pixel_breakdown(path, size, frames, repeats=3):
    """Where the per-pixel frame goes: the per-pixel renderer with 32-bit and 16-bit float tables and the variants of
    PIXEL_BREAKDOWN beside the empty frame and the plain textured sphere, interleaved as in :func:`breakdown`."""
    from planetviz.render import atmosphere_actor
    data = np.load(path)
    replace = []
    _patching(atmosphere_actor, "atmosphere_fragment.glsl", replace)
    configs = {"per pixel": ([], False), "per pixel, float16 tables": ([], True),
               **{name: (edits, False) for name, edits in PIXEL_BREAKDOWN.items()}}

    def make(config, renderer):
        replace[:] = config[0]
        return prepared_actor(data, renderer, config[1], "pixel")

    views, times = _interleaved(data, size, frames, repeats, configs, make)
    _ratio(views, times, "per pixel", repeats)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=("prepare", "run", "breakdown", "pixel-breakdown"))
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
                (breakdown if args.mode == "breakdown" else pixel_breakdown)(args.path, size, args.frames,
                                                                            args.repeats)


if __name__ == "__main__":
    main()
