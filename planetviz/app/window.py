"""The desktop window: a :class:`~planetviz.render.Scene` with PyVista widgets (``python app.py``).

Sliders change the sun, the exposure and the atmosphere (standard mode: scattering coefficients, scale heights,
the Mie phase, ozone, ground albedo; advanced mode: the physical quantities of the paper's Table 1 "(A)" rows),
each labelled with its unit. Every atmosphere change goes through :meth:`Atmosphere.from_dict`, so an invalid
value is refused with a visible message and the picture keeps its last good state; a valid one that needs new
tables shows the quick view while they are computed in the background (the status line says so).

Keys (chosen clear of VTK's and PyVista's own): F1-F5 presets (earth, mars, exo-co2-thick, exo-mdwarf,
earth-advanced); o orbit, l limb from low orbit, a aircraft, g ground at the horizon toward the sun; y fly
between orbit and the ground; x renderer (tables / quick view); h shading (tables per pixel / per vertex); k mode
(standard / advanced); t tone mapping; i quality (draft / standard / high); z screenshot (planetviz-<n>.png); F9
save the atmosphere (planetviz-atmosphere-<n>.json); F6 reload the atmosphere file the app was started with (edit it in a text
editor, press F6: an invalid file is refused with a message, the picture stays).
"""
from __future__ import annotations

import copy
import json
import time

import numpy as np

from ..model.limits import AtmosphereError
from ..render.scene import flight_path
from .parameters import STANDARD, advanced_parameters, apply_parameter, current_value, load_with_form
from .render_options import SITE, camera_preset

PRESET_KEYS = {"F1": "earth", "F2": "mars", "F3": "exo-co2-thick", "F4": "exo-mdwarf", "F5": "earth-advanced"}
QUALITIES = ("draft", "standard", "high")


class PlanetApp:
    """The window around a :class:`Scene` (``scene.show()`` runs it).

    >>> from planetviz.render import Scene
    >>> app = PlanetApp(Scene("earth", quality="draft"))   # doctest: +SKIP
    >>> app.scene.show()                                    # doctest: +SKIP
    """

    def __init__(self, scene, mode="standard", atmosphere_file=None, site=SITE):
        self.scene = scene
        self.site = site
        self.mode = mode
        self.message = ""
        self._base = scene.atmosphere.to_dict()      # what the "x" (scale) sliders scale
        self._source = self._base                     # the file's own form (advanced fields when it has them)
        self._source_base = self._source              # what the advanced "x" sliders scale
        self._file = atmosphere_file                  # the atmosphere file reloaded by F6, if any
        self._frame_ms = 0.0
        self._shots = 0
        self._status = scene.add_text("", position="lower_left", font_size=9, name="status")
        self._alert = scene.add_text("", position="upper_edge", font_size=10, color="orange", name="message")
        scene.set_sun(latitude=site[0], longitude=site[1])
        self._building = False
        self._add_sliders()
        for key, preset in PRESET_KEYS.items():
            scene.add_key_event(key, lambda p=preset: self.load_preset(p))
        for key, view in (("o", "orbit"), ("l", "limb"), ("a", "aircraft"), ("g", "ground")):
            scene.add_key_event(key, lambda v=view: self.camera_preset(v))
        scene.add_key_event("y", self.fly)
        scene.add_key_event("x", self.toggle_renderer)
        scene.add_key_event("h", self.toggle_shading)
        scene.add_key_event("k", self.toggle_mode)
        scene.add_key_event("t", self.cycle_tone_mapping)
        scene.add_key_event("i", self.cycle_quality)
        scene.add_key_event("z", self.save_screenshot)
        scene.add_key_event("F9", self.save_atmosphere)
        scene.add_key_event("F6", self.reload_file)
        self.camera_preset("orbit")

    # ----------------------------------------------------------------------------------------- widgets
    def _add_sliders(self):
        s = self.scene
        self._building = True             # PyVista calls each slider's callback once when it creates it
        s.clear_slider_widgets()
        self.sliders = {}
        style = dict(style="modern", title_height=0.018, fmt="%.3g", tube_width=0.004, slider_width=0.012)
        self.sliders["sun elevation [deg]"] = s.add_slider_widget(
            lambda v: self.set_sun(elevation=v), (-20.0, 90.0), value=s.sun.elevation, title="sun elevation [deg]",
            pointa=(0.03, 0.93), pointb=(0.30, 0.93), **style)
        self.sliders["sun azimuth [deg]"] = s.add_slider_widget(
            lambda v: self.set_sun(azimuth=v), (0.0, 360.0), value=s.sun.azimuth % 360.0, title="sun azimuth [deg]",
            pointa=(0.03, 0.83), pointb=(0.30, 0.83), **style)
        self.sliders["exposure log10 [m2/cd]"] = s.add_slider_widget(
            lambda v: self.set_exposure(10.0 ** v), (-6.0, 0.0), value=float(np.log10(s.settings.exposure)),
            title="exposure log10 [m2/cd]", pointa=(0.03, 0.73), pointb=(0.30, 0.73), **style)
        rows = STANDARD if self.mode == "standard" else self._advanced_rows()
        d = self.scene.atmosphere.to_dict() if self.mode == "standard" else self._source
        for i, row in enumerate(rows):
            y = 0.93 - 0.08 * i
            value = current_value(row, d, self._base)
            if value is None:
                continue                                # not in this atmosphere's form (e.g. advanced only)
            rng = row.slider
            self.sliders[row.label] = s.add_slider_widget(
                lambda v, row=row: self.change_parameter(row, v), rng, value=float(np.clip(value, *rng)),
                title=f"{row.label}  {rng[0]:g} to {rng[1]:g}", pointa=(0.70, y), pointb=(0.97, y), **style)
        for widget in self.sliders.values():
            widget.SetAnimationModeToOff()        # values change by dragging the handle, never by a stray click
        self._building = False

    def _advanced_rows(self):
        return advanced_parameters(self._source_base)

    # ------------------------------------------------------------------------------------------ actions
    def change_parameter(self, row, value):
        """Apply one widget's value (:class:`~planetviz.app.parameters.Parameter` ``row``) to a copy of the
        atmosphere; refuse it visibly if it is invalid."""
        if self._building:
            return None
        source = self.scene.atmosphere.to_dict() if self.mode == "standard" else self._source
        try:
            atm, d = apply_parameter(row, source, self._base, value)
        except (AtmosphereError, ValueError, KeyError, TypeError, AttributeError) as exc:
            self.show_message(f"{row.label} = {value:.4g} refused: {exc}")
            self.refresh()
            return False
        self._source = d
        self.show_message("")
        self.scene.set_atmosphere(atm)
        self.refresh()
        return True

    def load_preset(self, name):
        try:
            atm, source = load_with_form(name)
        except (AtmosphereError, ValueError, OSError) as exc:
            self.show_message(f"{name}: {exc}")
            self.refresh()
            return False
        self._base, self._source = atm.to_dict(), source
        self._source_base = copy.deepcopy(source)
        self.scene.set_atmosphere(atm)
        self._add_sliders()
        self.show_message("")
        self.refresh()
        return True

    def set_sun(self, elevation=None, azimuth=None):
        """Move the sun (degrees, seen from the window's site); an invalid angle is refused with a message and
        the sun stays where it was."""
        if self._building:
            return None
        try:
            self.scene.set_sun(elevation=elevation, azimuth=azimuth)
        except ValueError as exc:
            self.show_message(f"refused: {exc}")
            self.refresh()
            return False
        sun = self.scene.sun
        for name, value in (("sun elevation [deg]", sun.elevation), ("sun azimuth [deg]", sun.azimuth % 360.0)):
            if name in self.sliders:                  # keep the sliders in step when set from code or keys
                self.sliders[name].GetRepresentation().SetValue(value)
        self.refresh()
        return True

    def set_exposure(self, value):
        """Set the exposure [m^2/cd]; anything but a positive finite number is refused with a message."""
        if self._building:
            return None
        value = float(value)
        if not (np.isfinite(value) and value > 0):
            self.show_message(f"refused: exposure must be a positive finite number [m^2/cd], got {value!r}")
            self.refresh()
            return False
        self.scene.settings.exposure = value
        self.refresh()
        return True

    def camera_preset(self, name):
        """Look at the window's site from orbit, or from 400 km (the limb), 10 km or eye height toward the sun."""
        camera_preset(self.scene, name, self.site)
        self.refresh()

    def fly(self, frames=60):
        """Fly straight down from orbit to 1.7 m above the ground (or back up), a frame per step."""
        r = np.linalg.norm(self.scene.camera_location) - self.scene.atmosphere.bottom_radius_m
        down = r > 1e5
        path = flight_path(self.scene.atmosphere.bottom_radius_m, frames)
        for alt, pitch in path if down else path[::-1]:
            self.scene.view_from_ground(latitude=self.site[0], longitude=self.site[1], altitude=alt,
                                        heading=self.scene.sun.azimuth, pitch=pitch)
            self.refresh()

    def cycle_quality(self):
        s = self.scene
        s.set_quality(QUALITIES[(QUALITIES.index(s.quality) + 1) % len(QUALITIES)])
        self.refresh()

    def save_atmosphere(self):
        """Write the current atmosphere (its file form) to planetviz-atmosphere-<n>.json."""
        self._shots += 1
        path = f"planetviz-atmosphere-{self._shots}.json"
        with open(path, "w") as f:
            json.dump(self._source, f, indent=2)
        self.show_message(f"saved {path}")
        self.refresh()

    def reload_file(self):
        """Load the atmosphere file again (after editing it): refused with a message when it is invalid."""
        if self._file is None:
            self.show_message("no atmosphere file: start with --atmosphere FILE.json")
            self.refresh()
            return False
        try:
            atm, source = load_with_form(self._file)
        except (AtmosphereError, ValueError, OSError) as exc:
            self.show_message(f"{self._file}: {exc}")
            self.refresh()
            return False
        self._base, self._source, self._source_base = atm.to_dict(), source, copy.deepcopy(source)
        self.scene.set_atmosphere(atm)
        self._add_sliders()
        self.show_message("")
        self.refresh()
        return True

    def toggle_renderer(self):
        method = "quick" if self.scene.renderer_in_use == "tables" else "tables"
        self.scene.set_method(method)
        self.refresh()

    def toggle_shading(self):
        self.scene.set_shading("vertex" if self.scene.shading == "pixel" else "pixel")
        self.refresh()

    def toggle_mode(self):
        self.mode = "advanced" if self.mode == "standard" else "standard"
        self._add_sliders()
        self.refresh()

    def cycle_tone_mapping(self):
        order = ["exponential", "filmic", "clamp"]
        s = self.scene.settings
        s.tone_mapping = order[(order.index(s.tone_mapping) + 1) % 3]
        self.refresh()

    def save_screenshot(self):
        self._shots += 1
        path = f"planetviz-{self._shots}.png"
        self.scene.screenshot(path)
        self.show_message(f"saved {path}")

    # ------------------------------------------------------------------------------------------- status
    def show_message(self, text):
        self.message = text
        self._alert.SetText(7, text)          # 7: the upper edge of the corner annotation

    def status_text(self):
        s = self.scene
        job = s.precompute_progress
        tables = f"tables {job[0]} {100 * job[1]:.0f}%" if job else \
            (f"tables failed: {s.table_error}" if s.table_error else "tables ready")
        shown = f"{s.renderer_in_use}{' (draft)' if s.showing_draft else ''}"
        return (f"{s.atmosphere.name} | renderer: {shown} (per {s.shading}) | {tables} | "
                f"{s.quality} quality | frame {self._frame_ms:.0f} ms | {self.mode} mode | "
                f"tone mapping {s.settings.tone_mapping}")

    def refresh(self):
        """Update the status line (with the previous frame's time) and render once, timing the frame."""
        self._status.SetText(0, self.status_text())
        t0 = time.perf_counter()
        self.scene.render()
        self._frame_ms = 1e3 * (time.perf_counter() - t0)

    def poll(self, step=None):
        """Timer callback: show finished tables and the precompute progress."""
        if self.scene.precompute_progress is not None or self.scene.renderer_in_use == "quick":
            self.refresh()


def run(scene, mode="standard", atmosphere_file=None, site=SITE):
    """Open the window looking at ``site`` (latitude, longitude [deg]) with the scene's sun there (blocks until it
    is closed)."""
    app = PlanetApp(scene, mode=mode, atmosphere_file=atmosphere_file, site=site)
    scene.add_timer_event(max_steps=10 ** 9, duration=250, callback=app.poll)
    scene.show(title="planetviz")
    return app
