"""Frame sequences (a sun sweep, a time-lapse, a flight): every frame's camera and sun, rendered in this process or
on Dask workers, resumable, with a JSON manifest.

    planetviz render ... --sweep-sun -6 30 2 --screenshot frames/sun.png [--workers 2 | --scheduler tcp://HOST:8786]

(``planetviz render``'s sequences run on a local Dask cluster of the machine's cores by default, ``--workers 0``
in this process.)

1. :func:`sequence_frames` lists the frames: their camera, their sun and their numbered outputs.
2. :func:`run_sequence` writes the manifest (``<first output's folder>/<stem>.manifest.json``: the atmosphere's
   hash, the scene's settings, every frame's parameters; paths absolute, on a folder every worker sees), skips the
   frames whose files exist and whose parameters the previous manifest records (a re-run after an interruption
   renders only what is missing; one with other parameters renders everything), and renders the rest: one after
   another here, or on a Dask cluster (a local one of ``workers`` worker threads in this process, each with a
   scene of its own, or any cluster's scheduler at ``scheduler``; each worker keeps one scene per settings,
   loads the tables from the shared table cache and writes its frames). The local cluster's workers are
   threads, not processes: on one machine llvmpipe already draws on every core, and worker processes cost their
   start-up (Python, VTK, Dask) without drawing faster: 17% over the one-process run against 3-8% for threads
   (docs/rendering.md).
3. Each output is written to a temporary name and renamed (an interrupted frame leaves no partial file); a frame
   that fails is retried (``retries``) and then reported by number: the run raises listing every failed frame.
"""
from __future__ import annotations

import hashlib
import json
import os
import threading
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from ..quick_view.single_scattering import DEFAULT_SAMPLES
from .render_options import set_view, view_keywords
from .sky_images import sky_images, write_sky_image


@dataclass(frozen=True)
class SceneSettings:
    """What a worker needs to make the scene: the atmosphere (its standard-mode JSON, so that a worker on another
    machine needs no file) and the options of :class:`~planetviz.render.scene.Scene`."""

    atmosphere_json: str
    quality: str = "standard"
    surface: str | None = "texture"
    exposure: float = 1e-4
    tone_mapping: str = "exponential"
    size: tuple = (960, 540)
    method: str = "tables"
    shading: str = "pixel"
    quick_samples: int = DEFAULT_SAMPLES
    quick_terms: str = "physical"
    quick_orders: str = "all"
    tables: str = "4d"


@dataclass(frozen=True)
class Frame:
    """One frame: ``view`` (``kind`` "ground" or "space" and the keywords of ``Scene.view_from_ground`` or
    ``view_from_space``), ``sun`` (the keywords of ``Scene.set_sun``), its output files (.png, .exr) and its
    whole-sky pictures (:class:`~planetviz.app.sky_images.SkyImage`: dome masters, panoramas)."""

    index: int
    view: dict
    sun: dict
    outputs: tuple
    sky: tuple = ()

    @property
    def files(self):
        """Every file the frame writes."""
        return self.outputs + tuple(image.path for image in self.sky)


def numbered(path, i):
    """``path`` with the frame number: frames/sun.png -> frames/sun_0007.png."""
    p = Path(path)
    return str(p.with_name(f"{p.stem}_{i:04d}{p.suffix}"))


def sequence_frames(args, bottom_radius, times=None):
    """The frames of ``args``' sequence (``--time-lapse`` at ``times``, ``--sweep-sun`` or ``--flight``), each
    with the camera of ``args`` and the sun it asks for."""
    site = dict(latitude=args.latitude, longitude=args.longitude)
    view = view_keywords(args)
    sun = dict(elevation=args.sun_elevation, azimuth=args.sun_azimuth, **site)
    views, suns = [], []
    if times:
        from ..model.sun import sun_position
        for time in times:
            elevation, azimuth = sun_position(args.latitude, args.longitude, time)
            views.append(view)
            suns.append({**sun, "elevation": elevation, "azimuth": azimuth})
    elif args.sweep_sun:
        start, stop, step = args.sweep_sun
        if step == 0 or (stop - start) / step < 0:
            raise ValueError(f"sweep-sun: STEP must be non-zero and go from START toward STOP, got {step:g}")
        for elevation in np.arange(start, stop + 0.5 * step, step):
            views.append(view)
            suns.append({**sun, "elevation": float(elevation)})
    elif args.flight:
        from ..render.scene import flight_path
        for altitude, pitch in flight_path(bottom_radius, args.flight, level_pitch=args.pitch):
            views.append(dict(kind="ground", altitude=altitude, heading=args.heading, pitch=pitch,
                              fov=args.fov or 60.0, **site))
            suns.append(sun)
    stems = [Path(path).resolve() for path in (args.screenshot, args.exr) if path]   # workers elsewhere: absolute
    images = sky_images(args)
    return [Frame(i, v, s, tuple(numbered(path, i) for path in stems),
                  tuple(replace(image, path=numbered(Path(image.path).resolve(), i)) for image in images))
            for i, (v, s) in enumerate(zip(views, suns))]


_SCENES = {}


def _scene(settings):
    """This process's scene for ``settings`` (made once: the tables are read from the cache once per worker)."""
    key = (settings, threading.get_ident())              # one scene per thread: a threaded worker has its own
    if key not in _SCENES:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
        from ..model.atmosphere import Atmosphere
        from ..render import Scene
        _SCENES[key] = Scene(Atmosphere.from_json(settings.atmosphere_json), quality=settings.quality,
                                  surface=settings.surface, exposure=settings.exposure,
                                  tone_mapping=settings.tone_mapping, window_size=settings.size, off_screen=True,
                                  method=settings.method, shading=settings.shading,
                                  quick_samples=settings.quick_samples, quick_terms=settings.quick_terms,
                                  quick_orders=settings.quick_orders, tables=settings.tables)
    return _SCENES[key]


def close_scenes():
    """Close this process's scenes."""
    while _SCENES:
        _SCENES.popitem()[1].close()


def render_frame(settings, frame):
    """Render ``frame`` with this process's scene and write its outputs, each under a temporary name first."""
    scene = _scene(settings)
    set_view(scene, frame.view)
    scene.set_sun(**frame.sun)
    writers = [(out, scene.render_hdr if Path(out).suffix.lower() == ".exr" else scene.screenshot)
               for out in frame.outputs]
    writers += [(image.path, lambda tmp, image=image: write_sky_image(scene, image, tmp)) for image in frame.sky]
    for out, write in writers:
        path = Path(out)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.stem}.partial{path.suffix}")
        write(str(tmp))
        os.replace(tmp, path)
    return frame.index


def manifest_path(frames):
    first = Path(frames[0].files[0])
    return first.with_name(first.stem.rsplit("_", 1)[0] + ".manifest.json")


def write_manifest(path, settings, frames):
    """The sequence's JSON manifest: the atmosphere's hash, the settings and every frame's parameters."""
    record = {"atmosphere_sha256": hashlib.sha256(settings.atmosphere_json.encode()).hexdigest(),
              "settings": asdict(settings), "frames": [asdict(f) for f in frames]}
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(path).with_name(Path(path).name + ".partial")
    tmp.write_text(json.dumps(record, indent=1))
    os.replace(tmp, path)


def _as_json(value):
    return json.loads(json.dumps(value))


def finished_frames(path, settings, frames):
    """Indices of the frames already rendered as asked: their files exist and the manifest at ``path`` records
    the same atmosphere, settings and frame parameters (a sequence re-run with other parameters starts over)."""
    try:
        old = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return set()
    if not isinstance(old, dict) or old.get("settings") != _as_json(asdict(settings)):
        return set()
    recorded = {f.get("index"): f for f in old.get("frames", []) if isinstance(f, dict)}
    return {f.index for f in frames
            if recorded.get(f.index) == _as_json(asdict(f)) and all(Path(out).exists() for out in f.files)}


def run_sequence(settings, frames, workers=None, scheduler=None, retries=2, progress=None):
    """Render the frames whose outputs are missing (here, or on Dask with ``workers`` local worker threads or at the
    ``scheduler`` address); ``progress(done, total)`` after each frame. Returns the indices rendered; raises
    RuntimeError naming the frames that failed after their retries."""
    if not frames or not frames[0].files:
        raise ValueError("sequence: --screenshot, --exr, --fisheye or --panorama name the frames' files")
    finished = finished_frames(manifest_path(frames), settings, frames)
    write_manifest(manifest_path(frames), settings, frames)
    todo = [f for f in frames if f.index not in finished]
    done = len(frames) - len(todo)
    if progress:
        progress(done, len(frames))
    if workers is None and scheduler is None:
        rendered, failed = _run_here(settings, todo, retries, done, len(frames), progress)
    else:
        rendered, failed = _run_on_dask(settings, todo, workers, scheduler, retries, done, len(frames), progress)
    if failed:
        raise RuntimeError("sequence: frames " + ", ".join(f"{i} ({failed[i]})" for i in sorted(failed))
                           + f" failed after {retries} retries; the others are written")
    return sorted(rendered)


def _run_here(settings, todo, retries, done, total, progress):
    rendered, failed = [], {}
    try:
        for frame in todo:
            for _ in range(retries + 1):
                try:
                    rendered.append(render_frame(settings, frame))
                    failed.pop(frame.index, None)
                    break
                except Exception as exc:           # retried, then reported by number
                    failed[frame.index] = exc
            done += 1
            if progress:
                progress(done, total)
    finally:
        close_scenes()
    return rendered, failed


def _run_on_dask(settings, todo, workers, scheduler, retries, done, total, progress):
    import logging

    from distributed import Client, LocalCluster, as_completed
    cluster = None if scheduler else LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                                                  dashboard_address=None)
    client = Client(scheduler or cluster)
    rendered, failed = [], {}
    try:
        futures = {client.submit(render_frame, settings, frame, retries=retries, pure=False): frame.index
                   for frame in todo}
        for future in as_completed(futures):
            try:
                rendered.append(future.result())
            except Exception as exc:
                failed[futures[future]] = exc
            done += 1
            if progress:
                progress(done, total)
    finally:
        logging.getLogger("distributed").setLevel(logging.CRITICAL)     # heartbeats' noise at shutdown
        client.close()
        if cluster is not None:
            cluster.close()
            close_scenes()                    # the local cluster's workers are threads of this process
    return rendered, failed
