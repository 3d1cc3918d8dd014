"""Off-screen pictures: the options and the work of ``planetviz render`` and of ``python app.py`` with an output.

    planetviz render --preset mars --view ground --sun-elevation 3 --sun-azimuth 0 --size 1920x1080 \\
                     --screenshot out.png [--exr out.exr]
    planetviz render ... --sweep-sun -6 30 2 --screenshot frames/sun.png      # numbered frames sun_0000.png ...
    planetviz render --view ground --site 48.85,2.35 --time 2026-06-21T21:30+02:00 --screenshot paris.png
    planetviz render ... --site 48.85,2.35 --time-lapse 2026-06-21T19:00Z 2026-06-21T21:00Z 10min \
                     --screenshot frames/day.png                              # the Sun of each time
    planetviz render ... --flight 120 --screenshot frames/fly.png             # orbit to the ground in 120 frames
    planetviz render ... --fisheye dome.png [--fisheye-size 2048] [--fisheye-tilt 25]   # 180 deg dome master
    planetviz render ... --panorama sky.exr [--panorama-size 2048x1024]        # equirectangular HDR sky
    (with --sweep-sun, --time-lapse or --flight: a dome master and a panorama per frame, numbered)
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ..model.geometry import EYE_HEIGHT_M
from ..model.presets import PRESETS
from ..quick_view.multiple_scattering import ORDERS
from ..quick_view.single_scattering import DEFAULT_SAMPLES
from ..tables.compact import TABLE_KINDS


def _size(text):
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size: WIDTHxHEIGHT, e.g. 1920x1080, got {text!r}") from None
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise argparse.ArgumentTypeError(f"size: 1 to 16384 pixels each way, got {text!r}")
    return w, h


def add_render_options(p):
    """The options shared by ``planetviz render`` and ``app.py``."""
    presets = ", ".join(PRESETS)
    p.add_argument("--atmosphere", "--preset", dest="atmosphere", default="earth",
                   help=f"preset ({presets}) or JSON file")
    p.add_argument("--quality", choices=("draft", "standard", "high"), default="standard")
    p.add_argument("--view", choices=("space", "ground"), default="space")
    p.add_argument("--latitude", type=float, default=0.0, help="site below the camera [deg]")
    p.add_argument("--longitude", type=float, default=0.0, help="[deg]")
    p.add_argument("--distance", type=float, default=None, help="space: from the planet centre [m]")
    p.add_argument("--altitude", type=float, default=EYE_HEIGHT_M, help="ground: above the ground [m]")
    p.add_argument("--heading", type=float, default=0.0, help="ground: view azimuth from north [deg]")
    p.add_argument("--pitch", type=float, default=10.0, help="ground: view above the horizontal [deg]")
    p.add_argument("--fov", type=float, default=None, help="vertical field of view [deg]")
    p.add_argument("--sun-elevation", type=float, default=30.0, help="seen from the site [deg]")
    p.add_argument("--sun-azimuth", type=float, default=135.0, help="from north through east [deg]")
    p.add_argument("--site", default=None, metavar="LAT,LON",
                   help="the site [deg, north and east positive], instead of --latitude and --longitude")
    p.add_argument("--time", default=None, metavar="ISO8601",
                   help="the Sun in Earth's sky over the site at this time (with an offset, or UTC; or now), "
                        "instead of --sun-elevation and --sun-azimuth")
    p.add_argument("--exposure", type=float, default=1e-4, help="multiplies linear sRGB in cd/m^2")
    p.add_argument("--tone-mapping", choices=("exponential", "filmic", "clamp"), default="exponential")
    p.add_argument("--uniform-albedo", action="store_true", help="the atmosphere's ground albedo, no texture")
    p.add_argument("--tables", choices=TABLE_KINDS, default="4d",
                   help="tables drawn: 4d, or compact (a third of the GPU memory, less accurate: docs/benchmarks.md)")
    p.add_argument("--method", choices=("tables", "quick"), default="tables",
                   help="tables (all orders) or the quick view (no 4D tables, no precompute)")
    p.add_argument("--shading", choices=("pixel", "vertex", "auto"), default=None,
                   help="tables read per pixel or per vertex (auto: per vertex on a software OpenGL); "
                        "default: pixel for pictures, auto for the window")
    p.add_argument("--samples", type=int, default=DEFAULT_SAMPLES, help="quick: points per path")
    p.add_argument("--terms", choices=("physical", "artistic"), default="physical",
                   help="quick: the atmosphere's physics, or Keller and Bohn's simplified Table 1 terms")
    p.add_argument("--quick-orders", choices=ORDERS, default="all",
                   help="quick: all orders (single scattering and a table of the orders above) or "
                        "single scattering alone")
    p.add_argument("--size", type=_size, default=(960, 540), help="WIDTHxHEIGHT")
    p.add_argument("--screenshot", default=None, help="PNG of the tone-mapped view (batch: the name's stem)")
    p.add_argument("--exr", default=None, help="OpenEXR of the linear radiance (batch: the name's stem)")
    p.add_argument("--sweep-sun", nargs=3, type=float, metavar=("START", "STOP", "STEP"), default=None,
                   help="batch: one frame per sun elevation from START to STOP [deg]")
    p.add_argument("--time-lapse", nargs=3, default=None, metavar=("START", "STOP", "STEP"),
                   help="batch: one frame per time from START to STOP (ISO 8601) every STEP (10min, 1h, PT10M), "
                        "the Sun over the site")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="batch: worker threads of the local Dask cluster that renders the frames (default: the "
                        "machine's cores; 0: no cluster, this process renders them; resumable either way)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="batch: render the frames on the Dask cluster of this scheduler (tcp://HOST:8786)")
    p.add_argument("--flight", type=int, default=None, metavar="FRAMES",
                   help="batch: fly from 4 planet radii straight down to eye height (1.7 m) above the site in FRAMES frames")
    p.add_argument("--fisheye", default=None, help="180 deg dome master (PNG tone-mapped, or .exr linear)")
    p.add_argument("--fisheye-size", type=int, default=1024)
    p.add_argument("--fisheye-tilt", type=float, default=0.0,
                   help="dome master: its centre turned from the zenith toward --heading [deg, 0-90]")
    p.add_argument("--panorama", default=None, help="equirectangular HDR sky (OpenEXR)")
    p.add_argument("--panorama-size", type=_size, default=(2048, 1024), help="WIDTHxHEIGHT")
    p.add_argument("--sky-method", choices=("render", "numpy"), default="render",
                   help="dome master and panorama: through the renderer (a cube of faces, resampled) or the NumPy "
                        "evaluator per pixel (the check; slow)")


def _shading(args):
    """``--shading``, by default per pixel; per vertex where only whole-sky pictures are asked for, whose cube faces
    read the tables per vertex (cube_faces.render_directions), so that the scene is not rebuilt for each."""
    if args.shading:
        return args.shading
    return "pixel" if args.screenshot or args.exr else "vertex"


def wants_output(args):
    return any((args.screenshot, args.exr, args.fisheye, args.panorama))


class _Bar:
    def __init__(self, total, label):
        self.total, self.label = total, label

    def __call__(self, i):
        filled = int(round(30 * i / self.total))
        sys.stdout.write(f"\r{self.label} [{'#' * filled}{'.' * (30 - filled)}] {i}/{self.total}")
        if i == self.total:
            sys.stdout.write("\n")
        sys.stdout.flush()


def view_keywords(args) -> dict:
    """The camera ``args`` ask for: ``kind`` ("space" or "ground") and the keywords of ``Scene.view_from_space`` or
    ``Scene.view_from_ground``."""
    site = dict(latitude=args.latitude, longitude=args.longitude)
    if args.view == "space":
        return dict(kind="space", distance=args.distance, fov=args.fov or 30.0, **site)
    return dict(kind="ground", altitude=args.altitude, heading=args.heading, pitch=args.pitch, fov=args.fov or 60.0,
                **site)


def set_view(scene, view):
    """Place ``scene``'s camera as :func:`view_keywords` describes it."""
    view = dict(view)
    kind = view.pop("kind")
    (scene.view_from_space if kind == "space" else scene.view_from_ground)(**view)


#: The site the windows look at and see the sun from unless told (``app.py --site``): latitude, longitude [deg].
SITE = (30.0, 0.0)
#: The windows' camera presets (:func:`camera_preset`).
CAMERA_PRESETS = ("orbit", "limb", "aircraft", "ground")


def camera_preset(scene, name, site):
    """Look at ``site`` (latitude, longitude [deg]) from orbit, or toward the sun from 400 km (the limb), 10 km
    (an aircraft) or eye height on the ground."""
    (lat, lon), heading = site, scene.sun.azimuth
    if name == "orbit":
        scene.view_from_space(latitude=lat, longitude=lon)
    elif name == "limb":
        scene.view_from_ground(latitude=lat, longitude=lon, altitude=4e5, heading=heading, pitch=-17.0, fov=40.0)
    elif name == "aircraft":
        scene.view_from_ground(latitude=lat, longitude=lon, altitude=1e4, heading=heading, pitch=0.0, fov=60.0)
    elif name == "ground":
        scene.view_from_ground(latitude=lat, longitude=lon, altitude=EYE_HEIGHT_M, heading=heading, pitch=5.0,
                               fov=60.0)
    else:
        raise ValueError(f"camera preset: one of {', '.join(CAMERA_PRESETS)}, got {name!r}")


def _frame(scene, args):
    for path, write in ((args.screenshot, scene.screenshot), (args.exr, scene.render_hdr)):
        if path:
            Path(path).parent.mkdir(parents=True, exist_ok=True)
            write(str(path))
            print(f"wrote {path}")


def place_site_and_sun(args):
    """``--site`` into ``args.latitude`` and ``args.longitude``; ``--time`` into ``args.sun_elevation`` and
    ``args.sun_azimuth`` (the Sun in Earth's sky, planetviz/model/sun.py). At most one of ``--time``,
    ``--time-lapse`` and ``--sweep-sun``. Returns the times of ``--time-lapse`` (UTC), or None."""
    chosen = [name for name in ("time", "time_lapse", "sweep_sun") if getattr(args, name)]
    if len(chosen) > 1:
        raise ValueError(f"{' and '.join('--' + n.replace('_', '-') for n in chosen)}: choose one")
    if args.site is not None:
        from ..model.sun import parse_site
        args.latitude, args.longitude = parse_site(args.site)
    if args.time is not None:
        from ..model.sun import parse_time, sun_position
        args.sun_elevation, args.sun_azimuth = sun_position(args.latitude, args.longitude, parse_time(args.time))
    if args.time_lapse:
        from ..model.sun import time_steps
        return time_steps(*args.time_lapse)
    return None


def run_render(args) -> int:
    """Render what ``args`` asks for, off-screen: one picture, or a sequence (planetviz/app/sequence.py)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    from .sky_images import sky_images, write_sky_image
    times = place_site_and_sun(args)
    images = sky_images(args)                 # checked before anything is rendered
    if times or args.sweep_sun or args.flight:
        return _run_sequence(args, times)
    if args.workers is not None or args.scheduler is not None:
        raise ValueError("workers, scheduler: for a sequence (--sweep-sun, --time-lapse or --flight)")
    from ..render import Scene
    scene = Scene(args.atmosphere, quality=args.quality, surface=None if args.uniform_albedo else "texture",
                  exposure=args.exposure, tone_mapping=args.tone_mapping, window_size=args.size,
                  off_screen=True, method=args.method, shading=_shading(args), quick_samples=args.samples,
                  quick_terms=args.terms, quick_orders=args.quick_orders, tables=args.tables)
    try:
        set_view(scene, view_keywords(args))
        scene.set_sun(elevation=args.sun_elevation, azimuth=args.sun_azimuth, latitude=args.latitude,
                      longitude=args.longitude)
        _frame(scene, args)
        for image in images:
            write_sky_image(scene, image)
            print(f"wrote {image.path}")
    finally:
        scene.close()
    return 0


def _run_sequence(args, times):
    from ..model.presets import load_atmosphere
    from .sequence import SceneSettings, manifest_path, run_sequence, sequence_frames
    if args.workers is not None and not 0 <= args.workers <= 256:
        raise ValueError(f"workers: 0 to 256 threads, got {args.workers}")
    workers = (os.cpu_count() or 1) if args.workers is None else args.workers
    atm = load_atmosphere(args.atmosphere)
    settings = SceneSettings(atm.to_json(), quality=args.quality, surface=None if args.uniform_albedo else "texture",
                             exposure=args.exposure, tone_mapping=args.tone_mapping, size=tuple(args.size),
                             method=args.method, shading=_shading(args), quick_samples=args.samples,
                             quick_terms=args.terms, quick_orders=args.quick_orders, tables=args.tables)
    frames = sequence_frames(args, atm.bottom_radius_m, times)
    bar = _Bar(len(frames), "time-lapse" if times else "sun sweep" if args.sweep_sun else "flight")
    rendered = run_sequence(settings, frames, workers=workers or None, scheduler=args.scheduler,
                            progress=lambda done, total: bar(done))
    print(f"{len(rendered)} frames rendered, {len(frames) - len(rendered)} already there; "
          f"manifest {manifest_path(frames)}")
    return 0
