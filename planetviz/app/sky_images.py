"""Whole-sky pictures of a scene: dome masters (an equidistant 180 deg fisheye, tilted forward for a tilted dome)
and equirectangular panoramas, read through the renderer (a cube of faces around the camera, resampled:
planetviz/render/cube_faces.py) or the NumPy evaluator along every pixel's direction, written as PNG (tone-mapped)
or OpenEXR (linear radiance, per wavelength).

``planetviz render --fisheye dome.png [--fisheye-size 4096] [--fisheye-tilt 25] [--panorama sky.exr]`` writes them for
one picture and, with ``--sweep-sun``, ``--time-lapse`` or ``--flight``, for every frame of a sequence
(planetviz/app/sequence.py).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The projections, the ways of reading them, and the largest side and tilt a sky image may have.
PROJECTIONS = ("fisheye", "panorama")
SKY_METHODS = ("render", "numpy")
MAX_SIZE = 16384
TILT_RANGE_DEG = (0.0, 90.0)


@dataclass(frozen=True)
class SkyImage:
    """One whole-sky picture to write: ``projection`` ("fisheye" or "panorama"), its file (.png tone-mapped, .exr
    linear), its size in pixels, the dome's heading (the direction at the bottom of the image) and tilt (how far
    the dome's centre is turned from the zenith toward the heading) [deg], and how it is read (``SKY_METHODS``)."""

    path: str
    projection: str
    width: int
    height: int
    heading_deg: float = 0.0
    tilt_deg: float = 0.0
    method: str = "render"

    def __post_init__(self):
        if self.projection not in PROJECTIONS:
            raise ValueError(f"projection: one of {', '.join(PROJECTIONS)}, got {self.projection!r}")
        if self.method not in SKY_METHODS:
            raise ValueError(f"sky-method: one of {', '.join(SKY_METHODS)}, got {self.method!r}")
        for name, value in (("width", self.width), ("height", self.height)):
            if not 16 <= value <= MAX_SIZE:
                raise ValueError(f"{self.projection}-size: {name} 16 to {MAX_SIZE} pixels, got {value}")
        lo, hi = TILT_RANGE_DEG
        if not (np.isfinite(self.tilt_deg) and lo <= self.tilt_deg <= hi):
            raise ValueError(f"fisheye-tilt: {lo:g} to {hi:g} deg, got {self.tilt_deg}")

    def directions(self, camera):
        """(height, width, 3) unit view directions from ``camera`` [m, planet-centred]; NaN outside a dome's
        circle."""
        from ..tables.panorama import equirectangular_directions, fisheye_directions
        if self.projection == "fisheye":
            return fisheye_directions(camera, self.width, heading_deg=self.heading_deg, tilt_deg=self.tilt_deg)
        return equirectangular_directions(camera, self.width, self.height)

    def description(self) -> str:
        """The projection in words, for the OpenEXR header."""
        if self.projection == "panorama":
            return "equirectangular: azimuth from north through east, elevation up"
        return (f"fisheye 180 deg, equidistant, its centre {90.0 - self.tilt_deg:g} deg above the horizon at heading "
                f"{self.heading_deg:g} deg, which is at the bottom of the image")


def sky_images(args) -> tuple:
    """The :class:`SkyImage` s that ``args`` (planetviz render's options) ask for."""
    images = []
    if args.fisheye:
        images.append(SkyImage(str(args.fisheye), "fisheye", args.fisheye_size, args.fisheye_size,
                               heading_deg=args.heading, tilt_deg=args.fisheye_tilt, method=args.sky_method))
    if args.panorama:
        width, height = args.panorama_size
        images.append(SkyImage(str(args.panorama), "panorama", width, height, method=args.sky_method))
    return tuple(images)


def write_sky_image(scene, image: SkyImage, path=None):
    """Render ``image`` of ``scene``'s view (camera position, sun) and write it to ``path`` (default
    ``image.path``; the format follows its suffix)."""
    from ..model.color import display_colour, linear_srgb
    from ..model.optics.light import star_irradiance
    from ..render.cube_faces import render_directions as render_cube_directions
    from ..render.hdr import write_exr
    from ..render.surface import write_image
    from ..tables import QUALITY, TableCache, precompute
    from ..tables.panorama import render_directions
    atm, cam = scene.atmosphere, scene.camera_location
    path = str(image.path if path is None else path)
    dirs = image.directions(cam)
    if image.method == "render":
        face = max(16, (image.width if image.projection == "fisheye" else image.width // 2) // 2)
        radiance = render_cube_directions(scene, dirs, face)
    else:
        tables = scene.planet.tables if scene.planet is not None else \
            precompute(atm, QUALITY[scene.quality], cache=TableCache())        # the quick view has none
        radiance = render_directions(tables, atm, cam, dirs, scene.sun_direction)
    rgb = linear_srgb(radiance, atm)
    if path.lower().endswith(".exr"):
        write_exr(path, rgb, radiance * star_irradiance(atm.star, atm.wavelengths_nm), atm.wavelengths_nm,
                  {"atmosphere": atm.name, "camera_position_m": list(map(float, cam)),
                   "sun_direction": list(map(float, scene.sun_direction)), "projection": image.description()})
    else:
        s = scene.settings
        write_image(path, np.round(display_colour(rgb, s.exposure, s.tone_mapping) * 255).astype(np.uint8))
