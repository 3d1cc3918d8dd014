"""``Scene``: a PyVista plotter showing a planet and its atmosphere, from orbit to the ground.

Positions are planet-centred, in metres; the planet's north pole is +z. Sites are given by latitude and
longitude [deg]; the sun by its elevation and azimuth (from north, through east) [deg] seen from a site.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonCore import vtkCommand

from ..model.atmosphere import Atmosphere
from ..model.geometry import EYE_HEIGHT_M, SunPlacement, local_frame, site_direction
from ..model.presets import load_atmosphere
from ..model.color import linear_srgb
from ..model.optics.light import star_irradiance
from ..quick_view.multiple_scattering import ORDERS
from ..quick_view.single_scattering import DEFAULT_SAMPLES
from ..tables.cache import TableCache, parameters_hash, stage_parameters
from ..tables.compact import TABLE_KINDS, tables_of_kind
from ..tables.precompute import QUALITY, is_cached, precompute
from .atmosphere_actor import AtmosphereActor
from .background import BACKGROUND_NICENESS, BackgroundJob
from .quick_view_actor import QuickViewActor
from .hdr import render_spectral, write_exr
from .surface import SurfaceTexture, surface_texture
from .uniforms import TONE_MAPPINGS, DisplaySettings, camera_uniforms
from .vertex_actor import VertexAtmosphereActor

#: How the table-based renderer evaluates the model: per pixel (the paper's Algorithm 1) or per vertex of the
#: adaptive direction mesh with the texture and the sun disc per pixel (interactive on a software renderer).
SHADINGS = {"pixel": AtmosphereActor, "vertex": VertexAtmosphereActor}


def _one_of(field, value, choices):
    """Raise ValueError naming ``field`` and its choices unless ``value`` is one of them."""
    if value not in choices:
        raise ValueError(f"{field}: one of {', '.join(choices)}, got {value!r}")


def is_software_renderer(gl_renderer):
    """True for an OpenGL renderer string of a CPU rasteriser (Mesa's llvmpipe, softpipe, swrast; OpenSWR)."""
    return any(name in gl_renderer.lower() for name in ("llvmpipe", "softpipe", "swrast", "swr", "software"))


def flight_path(bottom_radius, frames, level_pitch=5.0):
    """[(altitude [m], pitch [deg])] of a flight straight down from 3 planet radii to 1.7 m above the ground:
    altitudes evenly spaced in the logarithm, looking straight down from orbit and levelling out to
    ``level_pitch`` below 100 km."""
    if frames < 2:
        raise ValueError(f"flight: at least 2 frames, got {frames}")
    altitudes = np.geomspace(3.0 * bottom_radius, EYE_HEIGHT_M, frames)
    pitch = -90.0 + 90.0 * np.clip(np.log10(1e7 / altitudes) / 2.0, 0.0, 1.0)
    return [(float(a), float(min(p, level_pitch))) for a, p in zip(altitudes, pitch)]


@dataclass
class HDRImage:
    """Linear float output of :meth:`Scene.render_hdr`.

    ``radiance``: (h, w, W) per unit solar irradiance [1/sr] at ``wavelengths_nm``, as ``planetviz radiance``
    gives it; ``spectral_radiance``: the same times the star's irradiance [W m^-2 sr^-1 nm^-1];
    ``linear_srgb``: (h, w, 3), CIE luminance in cd/m^2, not tone-mapped."""

    radiance: np.ndarray
    spectral_radiance: np.ndarray
    linear_srgb: np.ndarray
    wavelengths_nm: tuple

    def save_exr(self, path, metadata=None):
        write_exr(path, self.linear_srgb, self.spectral_radiance, self.wavelengths_nm, metadata or {})


#: The sun's elevation, azimuth, and the latitude and longitude of the site they are seen from [deg], when a
#: scene starts.
SUN_DEFAULT = (30.0, 135.0, 0.0, 0.0)


class PlanetView:
    """A planet with its atmosphere on a PyVista plotter: the tables or the quick view, the sun and the camera.

    Mixed into a plotter class: :class:`Scene` (``pyvista.Plotter``, a window of its own or off-screen) and the
    Qt window's view (``pyvistaqt.QtInteractor``, planetviz/app/qt_window.py). The keywords are
    :class:`Scene`'s; the rest go to the plotter.
    """


    def __init__(self, atmosphere="earth", quality="standard", surface="texture", exposure=1e-4,
                 tone_mapping="exponential", cache=True, method="tables", shading="pixel", quick_samples=DEFAULT_SAMPLES,
                 quick_terms="physical", quick_orders="all", tables="4d", **kwargs):
        self._job = None                      # a background precompute (render() may run inside __init__)
        self.planet = None                    # the table-based actor (None while its tables are computed)
        self.quick = None                     # the quick-view actor, made on first use
        self._surface_texture = SurfaceTexture()   # the surface map on the GPU, shared by the actors
        self._auto_shading = False
        self.gl_renderer = None               # the OpenGL renderer string, known after the first frame
        super().__init__(**kwargs)
        self.ren_win.SetMultiSamples(0)
        self.set_background("black")
        self.renderer.SetNearClippingPlaneTolerance(1e-6)
        _one_of("tone_mapping", tone_mapping, TONE_MAPPINGS)
        if not (np.isfinite(exposure) and exposure > 0):
            raise ValueError(f"exposure: a positive finite number, got {exposure!r}")
        _one_of("shading", shading, (*SHADINGS, "auto"))
        _one_of("tables", tables, TABLE_KINDS)
        self._table_kind = tables
        self._tables = None                   # the 4D tables of the planet shown
        self.settings = DisplaySettings(exposure=float(exposure), tone_mapping=tone_mapping)
        self._shading = "vertex" if shading == "auto" else shading
        self._auto_shading = shading == "auto"
        self.renderer.AddObserver(vtkCommand.EndEvent, self._note_gl_renderer)
        self.renderer.AddObserver(vtkCommand.EndEvent, self._after_frame)
        _one_of("quick_orders", quick_orders, ORDERS)
        self.quick_samples, self.quick_terms, self.quick_orders = quick_samples, quick_terms, quick_orders
        self.table_error = None               # why the last background precompute failed, if it did
        self.showing_draft = False            # draft tables stand in while the final ones are computed
        self.sun = SunPlacement(*SUN_DEFAULT)
        self._sun = self.sun.direction()
        self._method = None
        self.add_planet(atmosphere, quality=quality, surface=surface, cache=cache, method=method)
        self.view_from_space()

    # --------------------------------------------------------------------------------------------- planet
    def add_planet(self, atmosphere="earth", quality="standard", surface="texture", cache=True, method="tables"):
        """Set the planet: precompute (or load) its tables and show them (``method="tables"``), or show the
        quick view (``"quick"``, no tables). Returns the actor shown."""
        atm = atmosphere if isinstance(atmosphere, Atmosphere) else load_atmosphere(atmosphere)
        _one_of("quality", quality, QUALITY)
        if method not in ("tables", "quick"):
            raise ValueError(f"method: tables or quick, got {method!r}")
        self._atmosphere, self._quality, self._cache = atm, quality, cache
        self._ground_surface = surface_texture(atm) if isinstance(surface, str) and surface == "texture" else surface
        self._drop_actors()
        if method == "tables":
            self._show_tables(precompute(atm, QUALITY[quality], cache=TableCache() if cache else None))
        else:
            self._show_quick()
        self._method = method
        return self.planet if method == "tables" else self.quick

    @property
    def quality(self):
        """The table quality: ``"draft"``, ``"standard"`` or ``"high"``."""
        return self._quality

    def set_quality(self, quality):
        """Change the table quality (new tables in the background, the quick view meanwhile)."""
        _one_of("quality", quality, QUALITY)
        self._quality = quality
        self.set_atmosphere(self._atmosphere, force=True)

    @property
    def shading(self):
        """How the tables are read: ``"pixel"`` or ``"vertex"``."""
        return self._shading

    def set_shading(self, shading):
        """Read the tables per pixel (``"pixel"``) or per vertex of the direction mesh (``"vertex"``)."""
        _one_of("shading", shading, SHADINGS)
        self._shading = shading
        self._show_again()

    @property
    def table_kind(self):
        """Which tables are drawn: ``"4d"`` or ``"compact"``."""
        return self._table_kind

    def set_table_kind(self, kind):
        """Draw the 4D tables (``"4d"``) or their compact tables (``"compact"``)."""
        _one_of("tables", kind, TABLE_KINDS)
        self._table_kind = kind
        self._show_again()

    def _show_again(self):
        """Show the planet's tables again with the current shading and table kind (if tables are shown)."""
        if self.planet is not None:
            self._drop_actors()
            self._show_tables(self._tables)

    def set_method(self, method):
        """Show the tables (``"tables"``) or the quick view (``"quick"``) of the current planet."""
        return self.add_planet(self._atmosphere, quality=self._quality, surface=self._ground_surface,
                               cache=self._cache, method=method)

    def set_atmosphere(self, atmosphere, wait=False, force=False):
        """Change the atmosphere, keeping the view. With table rendering, a change that needs new tables shows
        the quick view at once while the tables are computed in a background thread; above the draft quality the
        thread first makes draft tables (unless the cache holds the final ones), which stand in until the final
        ones are ready (:attr:`showing_draft`); the next render after each is ready shows it
        (:attr:`renderer_in_use` says which is shown). ``wait``: compute in the foreground; ``force``: new tables
        even if the parameters did not change (after a change of quality). The precompute starts when the next
        frame has been drawn (planetviz/render/background.py)."""
        atm = atmosphere if isinstance(atmosphere, Atmosphere) else load_atmosphere(atmosphere)
        old = self._atmosphere
        self._atmosphere = atm
        if self._method == "quick":
            self._drop_actors()
            self._show_quick()
            return
        sizes = QUALITY[self._quality]
        same = not force and (parameters_hash(stage_parameters(old, sizes)["multiple_scattering"])
                              == parameters_hash(stage_parameters(atm, sizes)["multiple_scattering"]))
        if same and self.planet is not None:  # e.g. only the star or the name changed: the tables stay
            self._show_again()
            return
        cache = TableCache() if self._cache else None
        if wait:
            self._drop_actors()
            self._show_tables(precompute(atm, sizes, cache=cache))
            return
        self._drop_actors()
        self._show_quick()
        self._job = _TableJob(atm, sizes, cache, preview=None if self._quality == "draft" else QUALITY["draft"])

    @property
    def renderer_in_use(self):
        """``"tables"`` or ``"quick"``: what the next frame shows."""
        return "tables" if self.planet is not None else "quick"

    @property
    def precompute_progress(self):
        """(stage, fraction) of the background precompute, or None when none runs."""
        return None if self._job is None else self._job.progress

    def render(self):
        """Render, first switching to the tables if a background precompute has finished, and the quick view to
        all orders if their table is ready (and settling ``shading="auto"`` once the OpenGL renderer is known)."""
        self._prepare_frame()
        return super().render()

    def _prepare_frame(self):
        """What :meth:`render` does before the frame: take in finished background work, settle the shading."""
        self.collect()
        if self._auto_shading and self.gl_renderer is not None:
            self._auto_shading = False
            self.set_shading("vertex" if is_software_renderer(self.gl_renderer) else "pixel")

    def _note_gl_renderer(self, caller=None, event=None):
        if self.gl_renderer is None:
            lines = [line for line in self.ren_win.ReportCapabilities().splitlines() if "renderer string" in line]
            self.gl_renderer = lines[0].split(":", 1)[1].strip() if lines else ""

    def collect(self):
        """Take in what the background work has finished, without waiting: the tables of a precompute, the quick
        view's table of the orders above the first. True when the next frame changes because of it (a window
        renders then, and otherwise leaves the CPU to the work)."""
        changed = self._collect_tables()
        if self.quick is not None:
            changed = self.quick.collect() or changed
        return changed

    def _after_frame(self, caller=None, event=None):
        """At the end of a frame: start the background work that a change asked for."""
        self._start_background()

    def _start_background(self):
        """Start the precompute and the quick view's table, where they wait."""
        if self._job is not None:
            self._job.start()
        if self.quick is not None:
            self.quick.start_job()

    def _collect_tables(self):
        """Show a finished precompute's tables, or its draft tables while it goes on; True if it did."""
        job = self._job
        if job is None:
            return False
        if not job.done:
            draft = job.take_preview()
            if draft is None or job.atmosphere is not self._atmosphere:
                return False
            self._drop_actors()
            self._show_tables(draft)
            self.showing_draft = True
            return True
        self._job = None
        if job.atmosphere is not self._atmosphere:         # superseded by a later change
            return False
        if job.error is not None:
            self.table_error = job.error                       # keep showing the quick view or the draft
            return False
        self.table_error = None
        self._drop_actors()
        self._show_tables(job.result)
        return True

    def wait_for_tables(self, timeout=None):
        """Block until the background precompute (if any) ends, then show its tables."""
        if self._job is not None:
            self._job.join(timeout)
        self._collect_tables()

    def _show_tables(self, tables):
        self._tables = tables
        self.showing_draft = False
        drawn = tables_of_kind(tables, self._atmosphere, self._table_kind)
        self.planet = SHADINGS[self._shading](self._atmosphere, drawn, self.renderer,
                                              surface=self._ground_surface, settings=self.settings,
                                              surface_texture=self._surface_texture)
        self.planet.sun_direction = self._sun
        self.add_actor(self.planet.actor, reset_camera=False, name="planet", render=False)
        self.renderer.ResetCameraClippingRange()     # the previous actor's bounds may have set it

    def _show_quick(self):
        self.quick = QuickViewActor(self._atmosphere, self.renderer, samples=self.quick_samples,
                                    terms=self.quick_terms, settings=self.settings, orders=self.quick_orders,
                                    surface=self._ground_surface, surface_texture=self._surface_texture)
        self.quick.sun_direction = self._sun
        self.add_actor(self.quick.actor, reset_camera=False, name="quick-view", render=False)

    def _drop_actors(self):
        """Take the actors out (no frame: the caller's next render draws what replaces them)."""
        self.showing_draft = False
        if self.planet is not None:
            self.remove_actor(self.planet.actor, render=False)
            self.planet.release()
            self.planet = None
        if self.quick is not None:
            self.remove_actor(self.quick.actor, render=False)
            self.quick.release()
            self.quick = None

    @property
    def atmosphere(self):
        return self._atmosphere

    @property
    def tables(self):
        """The 4D tables of the planet shown (:class:`~planetviz.tables.precompute.Tables`), None while the quick
        view is shown."""
        return self._tables if self.planet is not None else None

    @property
    def active_actor(self):
        """The actor drawing the planet now (:class:`AtmosphereActor`, :class:`VertexAtmosphereActor` or
        :class:`QuickViewActor`)."""
        return self.planet if self.planet is not None else self.quick

    # ------------------------------------------------------------------------------------------------ sun
    def set_sun(self, elevation=None, azimuth=None, latitude=None, longitude=None):
        """Put the sun at ``elevation`` and ``azimuth`` [deg, azimuth from north through east] seen from the site
        at ``latitude`` and ``longitude`` [deg]; what is left out keeps its value (:attr:`sun`). The camera
        never moves the sun.

        >>> scene.set_sun(elevation=-4)                                        # doctest: +SKIP
        >>> scene.set_sun(elevation=10, azimuth=250, latitude=45, longitude=7)  # doctest: +SKIP
        """
        changes = dict(elevation=elevation, azimuth=azimuth, latitude=latitude, longitude=longitude)
        placement = SunPlacement(**{**vars(self.sun), **{k: v for k, v in changes.items() if v is not None}})
        self._apply_sun(placement, placement.direction())

    @property
    def sun_direction(self):
        return self._sun.copy()

    @sun_direction.setter
    def sun_direction(self, value):
        """The sun's planet-centred unit direction; :attr:`sun` becomes its elevation and azimuth seen from
        the same site."""
        v = np.asarray(value, dtype=float)
        if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
            raise ValueError(f"sun_direction: a finite non-zero 3-vector, got {value!r}")
        v = v / np.linalg.norm(v)
        self._apply_sun(SunPlacement.seen_from(v, self.sun.latitude, self.sun.longitude), v)

    def _apply_sun(self, placement, direction):
        self.sun, self._sun = placement, direction
        for actor in (self.planet, self.quick):
            if actor is not None:
                actor.sun_direction = self._sun

    # --------------------------------------------------------------------------------------------- camera
    def set_view(self, position, direction, up=None, fov=60.0):
        """Camera at ``position`` [m, planet-centred] looking along ``direction``, vertical field of view
        ``fov`` [deg]; ``up`` defaults to the local vertical."""
        pos = np.asarray(position, dtype=float)
        d = np.asarray(direction, dtype=float)
        r = np.linalg.norm(pos)
        if not (np.all(np.isfinite(pos)) and r >= self.atmosphere.bottom_radius_m):
            raise ValueError(f"camera position: finite and at or above the ground "
                             f"(|position| >= {self.atmosphere.bottom_radius_m:g} m), got {position!r}")
        if not (np.all(np.isfinite(d)) and np.linalg.norm(d) > 0):
            raise ValueError(f"view direction: a finite non-zero 3-vector, got {direction!r}")
        if not (0 < fov < 180):
            raise ValueError(f"fov: (0, 180) deg, got {fov!r}")
        d = d / np.linalg.norm(d)
        up = pos / r if up is None else np.asarray(up, dtype=float)
        if abs(np.dot(up / np.linalg.norm(up), d)) > 0.999:
            up = np.cross(d, [1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.cross(d, [0.0, 1.0, 0.0])
        cam = self.renderer.GetActiveCamera()
        cam.SetPosition(*pos)
        cam.SetFocalPoint(*(pos + d * max(1.0, 1e-3 * r)))
        cam.SetViewUp(*up)
        cam.SetViewAngle(fov)
        self.renderer.camera.is_set = True          # PyVista must not reset it on the first render
        self.renderer.ResetCameraClippingRange()

    def pixel_directions(self, rows, cols):
        """Unit view directions (..., 3) through the centres of pixels (rows from the top of the image), as the
        fragment shader computes them."""
        u = camera_uniforms(self.renderer)
        x0, y0, w, h = u["viewport"][1]
        rows, cols = np.asarray(rows, dtype=float), np.asarray(cols, dtype=float)
        ndc_x = (cols + 0.5 - x0) / w * 2 - 1
        ndc_y = ((h - 1 - rows) + 0.5 - y0) / h * 2 - 1
        v = (u["camera_forward"][1] + ndc_x[..., None] * u["camera_right"][1]
             + ndc_y[..., None] * u["camera_up"][1])
        return v / np.linalg.norm(v, axis=-1, keepdims=True)

    @property
    def camera_location(self):
        """Planet-centred camera position [m] (float64)."""
        return np.array(self.renderer.GetActiveCamera().GetPosition())

    def view_from_space(self, distance=None, latitude=0.0, longitude=0.0, fov=30.0):
        """Camera at ``distance`` [m] from the planet's centre (default: 4 planet radii) above a site, looking at
        the centre, north up."""
        distance = 4.0 * self.atmosphere.bottom_radius_m if distance is None else float(distance)
        up, _, north = local_frame(latitude, longitude)
        self.set_view(up * distance, -up, up=north, fov=fov)

    def view_from_ground(self, latitude=0.0, longitude=0.0, altitude=EYE_HEIGHT_M, heading=0.0, pitch=10.0,
                         fov=60.0):
        """Camera ``altitude`` [m] above a site looking toward ``heading`` (azimuth from north, deg), ``pitch``
        [deg] above the horizontal."""
        if not (np.isfinite(altitude) and altitude >= 0):
            raise ValueError(f"altitude: >= 0 m, got {altitude!r}")
        up, _, _ = local_frame(latitude, longitude)
        self.set_view(up * (self.atmosphere.bottom_radius_m + altitude),
                      site_direction(pitch, heading, latitude, longitude), fov=fov)

    @property
    def quick_pending(self):
        """True while the quick view shows single scattering and its table of the orders above is computed."""
        return self.quick is not None and self.quick.pending

    def _complete_quick_view(self):
        """Pictures for output show the whole quick view: wait for its table of the orders above the first."""
        if self.quick is not None:
            self.quick.collect(wait=True)

    def screenshot(self, filename=None, **kwargs):
        """The current view as 8-bit sRGB (tone-mapped), rendered afresh (PyVista reuses the last frame)."""
        self._complete_quick_view()
        self.render()
        return super().screenshot(filename, **kwargs)

    # ----------------------------------------------------------------------------------------------- HDR
    def render_hdr(self, path=None):
        """Linear radiance of the current view as an :class:`HDRImage` (float32, read back from a float
        framebuffer, not tone-mapped); with ``path``, also written as OpenEXR."""
        self._collect_tables()
        self._complete_quick_view()
        atm = self.atmosphere
        radiance = render_spectral(self.active_actor, self.ren_win)
        spectral = radiance * star_irradiance(atm.star, atm.wavelengths_nm).astype(np.float32)
        rgb = linear_srgb(radiance, atm)
        hdr = HDRImage(radiance, spectral, rgb, tuple(atm.wavelengths_nm))
        if path is not None:
            cam = self.renderer.GetActiveCamera()
            hdr.save_exr(Path(path), {"atmosphere": atm.name, "camera_position_m": list(cam.GetPosition()),
                                      "sun_direction": list(map(float, self._sun)),
                                      "renderer": self.renderer_in_use, "shading": self._shading,
                                      "R,G,B": "linear sRGB, luminance in cd/m^2",
                                      "L.*": "spectral radiance, W m^-2 sr^-1 nm^-1"})
        return hdr

    def close(self, *args, **kwargs):
        if self._job is not None and self._job.started:
            self._job.join()
        self._job = None
        if self.ren_win is not None:
            for actor in (self.planet, self.quick):
                if actor is not None:
                    actor.release()
            self._surface_texture.release()
        return super().close(*args, **kwargs)


class Scene(PlanetView, pv.Plotter):
    """A planet with its atmosphere, rendered from precomputed tables (paper Sect. 5).

    Parameters
    ----------
    atmosphere : str, Path or Atmosphere
        A preset name (``"earth"``, ``"mars"``, ...), an atmosphere file or an :class:`Atmosphere`.
    quality : str
        Table quality: ``"draft"``, ``"standard"`` or ``"high"``.
    surface : str or ndarray or None
        ``"texture"``: the planet's colour map from ``assets/textures`` where there is one (else the
        atmosphere's ground albedo); ``None``: the atmosphere file's uniform ground albedo; or an (h, w, 3)
        uint8 sRGB equirectangular image.
    exposure : float
        Multiplies linear sRGB (cd/m^2) before tone mapping; 1e-4 suits daylight, twilight needs ~1e-2.
    tone_mapping : str
        ``"exponential"`` (the paper's 1 - exp(-x)), ``"filmic"`` or ``"clamp"``.
    method : str
        ``"tables"`` (precomputed multiple scattering) or ``"quick"`` (the quick view: single scattering per
        vertex, no precompute).
    shading : str
        How the tables are read: ``"pixel"`` (every pixel, the paper's Algorithm 1), ``"vertex"`` (the 4D
        tables at the vertices of an adaptive mesh of view directions, interpolated, with the lit ground and the
        sun disc per pixel: about 20x faster on a software renderer, within the interpolation error measured in
        docs/benchmarks.md) or ``"auto"`` (``"vertex"`` on a software OpenGL such as llvmpipe, else
        ``"pixel"``; decided after the first frame).
    quick_samples, quick_terms, quick_orders : int, str, str
        The quick view's points per path, terms (``"physical"`` or Keller and Bohn's ``"artistic"``) and orders
        of scattering (``"all"``: single scattering and a table of the orders above, with the sky's
        light on the ground; ``"single"``: Keller and Bohn's single scattering alone).
    tables : str
        Which tables are drawn: ``"4d"`` (the precomputed 4D tables) or ``"compact"`` (Atmosphere Plus's 3D tables
        made from them, for machines short of GPU memory: a third of the memory, without the sun-view azimuth
        and the quadratures along rays; their error in docs/benchmarks.md).

    Examples
    --------
    >>> import planetviz
    >>> scene = planetviz.Scene("earth", quality="draft", off_screen=True, window_size=(320, 240))
    >>> scene.view_from_ground(latitude=45, heading=90, pitch=5)
    >>> scene.set_sun(elevation=3, azimuth=90, latitude=45)
    >>> scene.screenshot("sunset.png")  # doctest: +SKIP
    >>> hdr = scene.render_hdr()       # linear radiance, float32
    """

    def __init__(self, *args, window_size=(960, 540), **kwargs):
        super().__init__(*args, window_size=list(window_size), **kwargs)


class _TableJob(BackgroundJob):
    """A precompute as a background job (NumPy and the disk cache only: VTK is touched by the main thread);
    ``progress``: (stage, fraction). With ``preview`` (table sizes), tables of those sizes are made first, unless
    the cache holds the final ones, and handed out once by :meth:`take_preview` while the final ones are computed
    (for Earth, draft tables in 0.6 s before standard ones in 4 s)."""

    def __init__(self, atmosphere, sizes, cache, preview=None):
        self.atmosphere = atmosphere
        self.progress = ("starting", 0.0)
        self._preview = None

        def work():
            if preview is not None and not is_cached(atmosphere, sizes, cache):
                self._preview = precompute(atmosphere, preview, cache=cache,
                                           progress=lambda stage, f: setattr(self, "progress", (f"draft {stage}", f)))
            return precompute(atmosphere, sizes, cache=cache,
                              progress=lambda stage, f: setattr(self, "progress", (stage, f)))
        super().__init__(work, niceness=BACKGROUND_NICENESS)

    def take_preview(self):
        """The preview's tables once they are ready, once; else None."""
        tables, self._preview = self._preview, None
        return tables
