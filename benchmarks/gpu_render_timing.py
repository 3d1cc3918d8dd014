"""Frame time of the table-based renderer on a GPU through EGL, in plain VTK (no PyVista, no SciPy, no
colour-science: what the stripped VTK bundle of ../shared/notes/gpu-timing.md offers).

    python benchmarks/gpu_render_timing.py prepare gpu-tables.npz          # here: Earth's standard tables
    python benchmarks/gpu_render_timing.py run gpu-tables.npz [--sizes 1280x720 1920x1080] [--frames 50]

``prepare`` stores the packed tables and the shader's constant uniforms (which need colour-science);
``run`` builds a window, the same ``AtmosphereActor`` the application uses, and times, per size: a plain
sphere with VTK's default shading filling the same part of the frame (the frame floor of this GPU, as the
notes recommend: compare ratios, not absolute figures), then the atmosphere from orbit, from the ground and
from 1e9 m (the planet a few pixels wide), per pixel with 32-bit and with 16-bit float tables and per vertex
(``Scene(shading="vertex")``); then the quick view
(Keller and Bohn per vertex, no tables) from the ground with 4, 8 and 16 points per path. Median ms per frame,
``WaitForCompletion`` after each frame, after 5 warm-up frames.
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
    atm = load_atmosphere("earth")
    tables = precompute(atm, QUALITY["standard"], cache=TableCache())
    from planetviz.render.fallback_actor import FallbackActor
    static = TableTextures(atm, tables).static_uniforms()
    static = {k: (kind, np.asarray(v).tolist()) for k, (kind, v) in static.items()}
    quick = {}
    for n in (4, 8, 16):
        u = FallbackActor._static_uniforms(SimpleNamespace(atmosphere=atm, terms="physical", sampling="power",
                                                           samples=n, density_samples=n))
        quick[n] = {k: (kind, np.asarray(v).tolist()) for k, (kind, v) in u.items()}
    np.savez_compressed(path, bottom=tables.bottom, top=tables.top, static=json.dumps(static),
                        quick=json.dumps(quick), **{name: getattr(tables, name) for name in TABLES})
    print(f"wrote {path} ({Path(path).stat().st_size / 1e6:.1f} MB)")


class _PreparedActor:
    """An AtmosphereActor (``shading="pixel"``) or VertexAtmosphereActor (``"vertex"``) whose constant uniforms
    come from the prepared file."""

    def __new__(cls, data, renderer, half_float, shading="pixel"):
        from planetviz.render.atmosphere_actor import AtmosphereActor
        from planetviz.render.vertex_actor import VertexAtmosphereActor

        class Prepared(AtmosphereActor if shading == "pixel" else VertexAtmosphereActor):
            def _static_uniforms(self):
                return {k: (kind, v) for k, (kind, v) in json.loads(str(data["static"])).items()}

        tables = SimpleNamespace(bottom=float(data["bottom"]), top=float(data["top"]),
                                 **{name: data[name] for name in TABLES})
        atm = SimpleNamespace(bottom_radius_m=float(data["bottom"]), top_radius_m=float(data["top"]))
        return Prepared(atm, tables, renderer, half_float_tables=half_float)


class _PreparedQuick:
    """A FallbackActor whose constant uniforms come from the prepared file."""

    def __new__(cls, data, renderer, n):
        from planetviz.render.fallback_actor import FallbackActor

        class Prepared(FallbackActor):
            def _static_uniforms(self):
                return {k: (kind, v) for k, (kind, v) in json.loads(str(data["quick"]))[str(n)].items()}

        atm = SimpleNamespace(bottom_radius_m=float(data["bottom"]), top_radius_m=float(data["top"]))
        return Prepared(atm, renderer, samples=n)


def frame_ms(window, frames):
    for _ in range(5):
        window.Render()
    window.WaitForCompletion()
    times = []
    for _ in range(frames):
        t0 = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        times.append(1e3 * (time.perf_counter() - t0))
    return float(np.median(times))


def set_camera(renderer, position, target, up):
    cam = renderer.GetActiveCamera()
    cam.SetPosition(*position)
    cam.SetFocalPoint(*target)
    cam.SetViewUp(*up)
    cam.SetViewAngle(30.0)
    renderer.ResetCameraClippingRange()


def run(path, sizes, frames):
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow
    data = np.load(path)
    R = float(data["bottom"])
    views = {"orbit, 4 radii": ((4 * R, 0, 0), (0, 0, 0), (0, 0, 1)),
             "ground, horizon": ((R + 2.0, 0, 0), (R + 2.0, 1e4, 1e3), (1, 0, 0)),
             "1e9 m": ((1e9, 0, 0), (0, 0, 0), (0, 0, 1))}
    variants = (("pixel", False), ("pixel", True), ("vertex", False))
    print("| size | plain sphere (4 radii) | " + " | ".join(f"{v}, per pixel | {v}, per pixel, float16 tables | "
                                                         f"{v}, per vertex" for v in views) + " |")
    print("|---" * (2 + len(variants) * len(views)) + "|")
    quick_rows = []
    for size in sizes:
        w, h = (int(v) for v in size.split("x"))
        row = [size]
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(w, h)
        window.SetMultiSamples(0)
        renderer = vtkRenderer()
        renderer.SetNearClippingPlaneTolerance(1e-6)
        window.AddRenderer(renderer)
        sphere = vtkSphereSource()
        sphere.SetRadius(R)
        sphere.SetThetaResolution(128)
        sphere.SetPhiResolution(64)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(sphere.GetOutputPort())
        plain = vtkActor()
        plain.SetMapper(mapper)
        renderer.AddActor(plain)
        set_camera(renderer, *views["orbit, 4 radii"])
        row.append(frame_ms(window, frames))
        renderer.RemoveActor(plain)
        timings = {}
        for shading, half in variants:
            actor = _PreparedActor(data, renderer, half, shading)
            actor.sun_direction = np.array([0.6, 0.3, 0.74])
            renderer.AddActor(actor.actor)
            for name, view in views.items():
                set_camera(renderer, *view)
                timings[name, shading, half] = frame_ms(window, frames)
            renderer.RemoveActor(actor.actor)
            actor.release()
        row += [timings[name, shading, half] for name in views for shading, half in variants]
        print("| " + " | ".join([row[0]] + [f"{v:.2f}" for v in row[1:]]) + " |", flush=True)
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=("prepare", "run"))
    ap.add_argument("path")
    ap.add_argument("--sizes", nargs="+", default=["1280x720", "1920x1080", "3840x2160"])
    ap.add_argument("--frames", type=int, default=50)
    args = ap.parse_args()
    if args.mode == "prepare":
        prepare(args.path)
    else:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
        run(args.path, args.sizes, args.frames)


if __name__ == "__main__":
    main()
